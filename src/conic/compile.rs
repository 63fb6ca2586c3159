//! Compilation of a [`Problem`] to Clarabel's standard form, and back.
//!
//! Stage 1 (rows + cones): every constraint is an affine map `s(x)` into its
//! cone; row r with `s_r = aᵣ·x + cᵣ` becomes `Aᵣ = −aᵣ, bᵣ = cᵣ`, so that
//! `A x + s = b`. Stage 2 (objective): squares are reduced once (Gram matrix
//! or QR factor) so the size does not grow with the number of rows. The
//! inverse map takes Clarabel's (x, z) back to user variables and to one dual
//! per constraint, in the same row order.

use super::error::ConicError;
use super::expr::AffExpr;
use super::problem::{ConeKind, Problem, Sense};
use super::settings::{LeastSquaresForm, Settings};
use super::solution::Solution;
use super::status::Status;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use std::time::Instant;

/// A problem in Clarabel's form `min ½xᵀPx + qᵀx + c₀ s.t. Ax + s = b, s ∈ K`,
/// with the maps back to the user's problem.
pub struct Compiled {
    /// Upper triangle of P (`n × n`).
    pub p: CscMatrix<f64>,
    /// Linear cost (`n`).
    pub q: Vec<f64>,
    /// Constraint matrix (`m × n`).
    pub a: CscMatrix<f64>,
    /// Right-hand side (`m`).
    pub b: Vec<f64>,
    /// Cones, in row order.
    pub cones: Vec<SupportedConeT<f64>>,
    /// Constant added to the objective.
    pub obj_const: f64,
    /// Number of user variables (the first entries of x).
    pub n_user: usize,
    /// First row of each user constraint, plus the end.
    pub(crate) offsets: Vec<usize>,
    pub(crate) kinds: Vec<ConeKind>,
    pub(crate) names: Vec<String>,
    pub(crate) flipped: Vec<bool>,
    pub(crate) lineage: super::problem::Lineage,
    pub(crate) sense: Sense,
    pub(crate) settings: Settings,
    compile_time: f64,
}

struct Triplets {
    rows: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
}

impl Triplets {
    fn new() -> Self {
        Self {
            rows: Vec::new(),
            cols: Vec::new(),
            vals: Vec::new(),
        }
    }
    fn push(&mut self, r: usize, c: usize, v: f64) {
        if v != 0.0 {
            self.rows.push(r);
            self.cols.push(c);
            self.vals.push(v);
        }
    }
    /// CSC with duplicates summed.
    fn into_csc(self, m: usize, n: usize) -> CscMatrix<f64> {
        let mut idx: Vec<usize> = (0..self.vals.len()).collect();
        idx.sort_by_key(|&k| (self.cols[k], self.rows[k]));
        let mut colptr = vec![0usize; n + 1];
        let mut rowval = Vec::with_capacity(idx.len());
        let mut nzval: Vec<f64> = Vec::with_capacity(idx.len());
        let mut last: Option<(usize, usize)> = None;
        for k in idx {
            let (r, c) = (self.rows[k], self.cols[k]);
            if last == Some((r, c)) {
                *nzval.last_mut().unwrap_or(&mut 0.0) += self.vals[k];
            } else {
                rowval.push(r);
                nzval.push(self.vals[k]);
                colptr[c + 1] += 1;
                last = Some((r, c));
            }
        }
        for c in 0..n {
            colptr[c + 1] += colptr[c];
        }
        CscMatrix::new(m, n, colptr, rowval, nzval)
    }
}

/// Stage 1's output: the constraint rows `A x + s = b` (A transposed into
/// triplets), each constraint's first row, and the cones.
struct Rows {
    at: Triplets,
    b: Vec<f64>,
    offsets: Vec<usize>,
    cones: Vec<SupportedConeT<f64>>,
}

/// Stage 2's output: the variables (the user's, and a squares' epigraph in
/// the second-order-cone form), `q`, the constant and `P`'s triplets.
struct Objective {
    n: usize,
    q: Vec<f64>,
    obj_const: f64,
    pt: Triplets,
}

impl Problem {
    /// Compiles to Clarabel's form: the checks, then stage 1 (constraint
    /// rows and cones), then stage 2 (the objective).
    pub fn compile(&self, settings: &Settings) -> Result<Compiled, ConicError> {
        let t0 = Instant::now();
        settings.validate()?;
        self.check_objective()?;
        let mut rows = self.constraint_rows();
        let obj = self.objective(settings, &mut rows);
        let m = rows.b.len();
        Ok(Compiled {
            p: obj.pt.into_csc(obj.n, obj.n),
            q: obj.q,
            a: rows.at.into_csc(m, obj.n),
            b: rows.b,
            cones: rows.cones,
            obj_const: obj.obj_const,
            n_user: self.nvars,
            offsets: rows.offsets,
            kinds: self.constraints.iter().map(|c| c.kind).collect(),
            names: self.constraints.iter().map(|c| c.name.clone()).collect(),
            flipped: self.constraints.iter().map(|c| c.flipped).collect(),
            lineage: self.lineage.clone(),
            sense: self.sense,
            settings: settings.clone(),
            compile_time: t0.elapsed().as_secs_f64(),
        })
    }

    /// A problem with variables, a convex objective with this problem's
    /// variables, finite numbers and non-negative weights.
    fn check_objective(&self) -> Result<(), ConicError> {
        if self.nvars == 0 {
            return Err(ConicError::EmptyProblem);
        }
        if self.sense == Sense::Maximize && !self.squares.is_empty() {
            return Err(ConicError::Unsupported(
                "maximising an objective with squares (not convex); minimise its negation".into(),
            ));
        }
        let check = |e: &AffExpr, what: String| -> Result<(), ConicError> {
            if !self.owns(e) {
                return Err(ConicError::ForeignHandle {
                    what: format!("a variable in {what}"),
                });
            }
            if !e.is_finite() {
                return Err(ConicError::NonFinite { what });
            }
            Ok(())
        };
        check(&self.linear, "the objective".into())?;
        for (k, (w, e)) in self.squares.iter().enumerate() {
            if !(w.is_finite() && *w >= 0.0) {
                return Err(ConicError::NegativeWeight {
                    square: k,
                    weight: *w,
                });
            }
            check(e, format!("square #{k} of the objective"))?;
        }
        Ok(())
    }

    /// Stage 1: every constraint's rows `s_r = a_r·x + c_r` as `A_r = −a_r`,
    /// `b_r = c_r`, and its cone (runs of zero or non-negative cones merged).
    fn constraint_rows(&self) -> Rows {
        let mut rows = Rows {
            at: Triplets::new(),
            b: Vec::new(),
            offsets: Vec::with_capacity(self.constraints.len() + 1),
            cones: Vec::new(),
        };
        for c in &self.constraints {
            rows.offsets.push(rows.b.len());
            for e in &c.rows {
                let r = rows.b.len();
                for &(v, a) in &e.terms {
                    rows.at.push(r, v.index(), -a);
                }
                rows.b.push(e.constant);
            }
            let k = c.rows.len();
            let cone = match c.kind {
                ConeKind::Zero => SupportedConeT::ZeroConeT(k),
                ConeKind::Nonnegative => SupportedConeT::NonnegativeConeT(k),
                ConeKind::SecondOrder => SupportedConeT::SecondOrderConeT(k),
                ConeKind::Psd { n } => SupportedConeT::PSDTriangleConeT(n),
                ConeKind::Exponential => SupportedConeT::ExponentialConeT(),
            };
            match (rows.cones.last_mut(), &cone) {
                (Some(SupportedConeT::ZeroConeT(a)), SupportedConeT::ZeroConeT(k)) => *a += k,
                (
                    Some(SupportedConeT::NonnegativeConeT(a)),
                    SupportedConeT::NonnegativeConeT(k),
                ) => *a += k,
                _ if k == 0 => {}
                _ => rows.cones.push(cone),
            }
        }
        rows.offsets.push(rows.b.len());
        rows
    }

    /// Stage 2: the linear objective (negated to maximise), and the squares
    /// reduced once, to the Gram matrix or to one second-order cone (whose
    /// rows join `rows`).
    fn objective(&self, settings: &Settings, rows: &mut Rows) -> Objective {
        let sign = match self.sense {
            Sense::Minimize => 1.0,
            Sense::Maximize => -1.0,
        };
        let mut obj = Objective {
            n: self.nvars,
            q: vec![0.0; self.nvars],
            obj_const: sign * self.linear.constant,
            pt: Triplets::new(),
        };
        for &(v, a) in &self.linear.terms {
            obj.q[v.index()] += sign * a;
        }
        if !self.squares.is_empty() {
            let (cols, d) = stack_squares(&self.squares, self.nvars);
            match settings.least_squares {
                LeastSquaresForm::Quadratic => gram_form(&cols, &d, &mut obj),
                LeastSquaresForm::SecondOrderCone => soc_form(&cols, &d, &mut obj, rows),
            }
        }
        obj
    }

    /// Compiles and solves.
    pub fn solve(&self, settings: &Settings) -> Result<Solution, ConicError> {
        self.compile(settings)?.solve()
    }
}

/// The squares `‖D [x; 1]‖²` as `xᵀ P x / 2 + qᵀx + c` with `P = 2 GᵀG`'s
/// pattern over `cols`, `G = DᵀD` (one matrix product).
fn gram_form(cols: &[usize], d: &faer::Mat<f64>, obj: &mut Objective) {
    let k = cols.len();
    let mut g = faer::Mat::<f64>::zeros(k + 1, k + 1);
    faer::linalg::matmul::matmul(
        g.as_mut(),
        faer::Accum::Replace,
        d.transpose(),
        d.as_ref(),
        1.0,
        faer::Par::Seq,
    );
    for jj in 0..k {
        for ii in 0..=jj {
            obj.pt.push(
                cols[ii].min(cols[jj]),
                cols[ii].max(cols[jj]),
                2.0 * g[(ii, jj)],
            );
        }
        obj.q[cols[jj]] += 2.0 * g[(jj, k)];
    }
    obj.obj_const += g[(k, k)];
}

/// The squares as a variable t ≥ ‖R [x; 1]‖² (R the thin QR factor of D),
/// minimised: rows `t + 1, t − 1, 2 R [x; 1]` in one second-order cone.
fn soc_form(cols: &[usize], d: &faer::Mat<f64>, obj: &mut Objective, rows: &mut Rows) {
    let k = cols.len();
    let r = if d.nrows() > d.ncols() {
        d.qr().thin_R().to_owned()
    } else {
        d.clone()
    };
    let t = obj.n;
    obj.n += 1;
    obj.q.push(1.0);
    let r0 = rows.b.len();
    rows.at.push(r0, t, -1.0);
    rows.b.push(1.0);
    rows.at.push(r0 + 1, t, -1.0);
    rows.b.push(-1.0);
    for i in 0..r.nrows() {
        let row = rows.b.len();
        for jj in 0..k {
            rows.at.push(row, cols[jj], -2.0 * r[(i, jj)]);
        }
        rows.b.push(2.0 * r[(i, k)]);
    }
    rows.cones
        .push(SupportedConeT::SecondOrderConeT(2 + r.nrows()));
}

/// Stacks `√w (a·x + b)` rows densely over the variables they use:
/// returns the used variable indices and the `rows × (k + 1)` matrix whose
/// last column holds the constants.
fn stack_squares(squares: &[(f64, AffExpr)], nvars: usize) -> (Vec<usize>, faer::Mat<f64>) {
    const UNUSED: usize = usize::MAX;
    let mut col_of = vec![UNUSED; nvars];
    let mut cols = Vec::new();
    for (_, e) in squares {
        for &(v, _) in &e.terms {
            let i = v.index();
            if col_of[i] == UNUSED {
                col_of[i] = cols.len();
                cols.push(i);
            }
        }
    }
    let k = cols.len();
    let mut d = faer::Mat::<f64>::zeros(squares.len(), k + 1);
    for (r, (w, e)) in squares.iter().enumerate() {
        let sw = w.sqrt();
        for &(v, a) in &e.terms {
            let i = v.index();
            d[(r, col_of[i])] += sw * a;
        }
        d[(r, k)] = sw * e.constant;
    }
    (cols, d)
}

/// What a caught solver panic said.
fn panic_text(p: &Box<dyn std::any::Any + Send>) -> String {
    let what = p
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown".into());
    format!("Clarabel failed on this problem's numbers ({what}); check its scale")
}

impl Compiled {
    /// Seconds spent compiling.
    pub fn compile_time(&self) -> f64 {
        self.compile_time
    }

    /// Number of rows of A (the cone dimension).
    pub fn num_rows(&self) -> usize {
        self.b.len()
    }

    /// Solves with Clarabel and maps the result back, with the chordal
    /// decomposition as [`Settings`] asks (checked and, if the check fails,
    /// solved again without it; [`Solution::decomposition`] says which).
    pub fn solve(&self) -> Result<Solution, ConicError> {
        use super::settings::Decomposition;
        use super::solution::DecompositionOutcome as Outcome;
        let mode = self.settings.decomposition;
        if mode == Decomposition::Off {
            return Ok(self.to_solution(self.run(false)?, Outcome::Off));
        }
        let mut first = self.run(true)?;
        if !first.decomposed {
            return Ok(self.to_solution(first, Outcome::Off));
        }
        if mode == Decomposition::Unchecked {
            return Ok(self.to_solution(first, Outcome::Unchecked));
        }
        let t0 = Instant::now();
        let s = &first.solver.solution;
        let verdict = self.verify(s.status, &s.x, &s.z);
        first.extra_solve = t0.elapsed().as_secs_f64();
        match (verdict, &self.settings.no_fallback) {
            (Ok(()), _) => Ok(self.to_solution(first, Outcome::Used)),
            // a run that claims nothing (an iteration or time limit) is
            // returned as it is: its status says it is no answer
            (Err(_), Some(_)) if !claims_an_answer(first.solver.solution.status) => {
                Ok(self.to_solution(first, Outcome::Unchecked))
            }
            (Err(reason), Some(why)) => Err(ConicError::DecompositionRejected {
                reason,
                why: why.clone(),
            }),
            (Err(reason), None) => {
                let mut again = self.run(false)?;
                again.setup += first.setup;
                again.extra_solve = first.solve + first.extra_solve;
                Ok(self.to_solution(again, Outcome::FellBack(reason)))
            }
        }
    }

    /// One Clarabel run, decomposing or not.
    fn run(&self, decompose: bool) -> Result<Run, ConicError> {
        #[cfg(feature = "faer-lapack")]
        crate::faer_lapack::ensure_linked();
        let t0 = Instant::now();
        // Clarabel panics on some numerically hopeless data (an SVD that
        // does not converge in its equilibration, say); that is the
        // problem's failure, not the process's
        let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let mut solver = DefaultSolver::new(
                &self.p,
                &self.q,
                &self.a,
                &self.b,
                &self.cones,
                self.settings.to_clarabel(decompose, self.a.n + self.a.m),
            )
            .map_err(|e| ConicError::Solver(e.to_string()))?;
            let setup = t0.elapsed().as_secs_f64();
            let t1 = Instant::now();
            solver.solve();
            Ok((solver, setup, t1.elapsed().as_secs_f64()))
        }));
        let (solver, setup, solve) = run.map_err(|p| ConicError::Solver(panic_text(&p)))??;
        // a decomposition adds PSD cones (one per clique)
        let psd = |c: &[SupportedConeT<f64>]| {
            c.iter()
                .filter(|c| matches!(c, SupportedConeT::PSDTriangleConeT(_)))
                .count()
        };
        let decomposed = psd(&solver.data.cones) > psd(&self.cones);
        Ok(Run {
            solver,
            setup,
            solve,
            extra_solve: 0.0,
            decomposed,
        })
    }

    fn to_solution(
        &self,
        run: Run,
        decomposition: super::solution::DecompositionOutcome,
    ) -> Solution {
        let s = &run.solver.solution;
        let status = match s.status {
            SolverStatus::Solved => Status::Solved,
            SolverStatus::AlmostSolved => Status::SolvedInaccurately,
            SolverStatus::PrimalInfeasible => Status::PrimalInfeasible,
            SolverStatus::AlmostPrimalInfeasible => Status::PrimalInfeasibleInaccurate,
            SolverStatus::DualInfeasible => Status::DualInfeasible,
            SolverStatus::AlmostDualInfeasible => Status::DualInfeasibleInaccurate,
            SolverStatus::MaxIterations => Status::IterationLimit,
            SolverStatus::MaxTime => Status::TimeLimit,
            SolverStatus::NumericalError => Status::NumericalError,
            SolverStatus::InsufficientProgress => Status::InsufficientProgress,
            SolverStatus::Unsolved | SolverStatus::CallbackTerminated => Status::NotSolved,
        };
        let sign = if self.sense == Sense::Maximize {
            -1.0
        } else {
            1.0
        };
        let duals = self
            .offsets
            .windows(2)
            .map(|w| s.z[w[0]..w[1]].to_vec())
            .collect();
        Solution {
            status,
            primal_objective: sign * (s.obj_val + self.obj_const),
            dual_objective: sign * (s.obj_val_dual + self.obj_const),
            x: s.x[..self.n_user].to_vec(),
            raw_duals: duals,
            kinds: self.kinds.clone(),
            names: self.names.clone(),
            flipped: self.flipped.clone(),
            lineage: self.lineage.clone(),
            sense: self.sense,
            iterations: s.iterations,
            primal_residual: s.r_prim,
            dual_residual: s.r_dual,
            setup_time_s: self.compile_time + run.setup,
            solve_time_s: run.solve + run.extra_solve,
            decomposition,
        }
    }
}

/// Whether a status claims an optimum or an infeasibility certificate (what
/// the check of a decomposed result can confirm or refute).
fn claims_an_answer(s: SolverStatus) -> bool {
    matches!(
        s,
        SolverStatus::Solved
            | SolverStatus::AlmostSolved
            | SolverStatus::PrimalInfeasible
            | SolverStatus::AlmostPrimalInfeasible
            | SolverStatus::DualInfeasible
            | SolverStatus::AlmostDualInfeasible
    )
}

/// A finished Clarabel run.
struct Run {
    solver: DefaultSolver<f64>,
    /// Clarabel's setup (its `solve_time` counts it too, so this layer
    /// times setup and solve itself), seconds.
    setup: f64,
    /// The interior-point solve, seconds.
    solve: f64,
    /// Time that counts as solving besides `solve`: the check of this
    /// decomposed run, or a failed decomposed solve and its check before
    /// this one, seconds.
    extra_solve: f64,
    decomposed: bool,
}
