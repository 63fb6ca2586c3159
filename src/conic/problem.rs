//! The problem builder: variables, constraints, objective.

use super::error::ConicError;
use super::expr::{AffExpr, Var};
use super::matexpr::MatExpr;
use std::sync::atomic::{AtomicU32, Ordering};

/// Problem identities: 1, 2, ….
static NEXT_PROBLEM: AtomicU32 = AtomicU32::new(1);

fn new_id() -> u32 {
    NEXT_PROBLEM.fetch_add(1, Ordering::Relaxed)
}

/// Who owns which handles: a problem's own identity, and for a clone, the
/// identities it was cloned from with the number of variables and
/// constraints each had then (those handles are valid in the clone too;
/// handles either side creates later are not valid in the other).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Lineage {
    pub id: u32,
    /// `(ancestor id, its variables, its constraints)` at the clone.
    pub ancestors: Vec<(u32, usize, usize)>,
}

impl Lineage {
    /// Whether variable `v` is one of this problem's first `nvars`.
    pub fn owns_var(&self, v: Var, nvars: usize) -> bool {
        (v.problem == self.id && v.index() < nvars)
            || self
                .ancestors
                .iter()
                .any(|&(a, n, _)| a == v.problem && v.index() < n)
    }

    /// Whether constraint `c` is one of this problem's first `ncons`.
    pub fn owns_constraint(&self, c: ConstraintId, ncons: usize) -> bool {
        (c.problem == self.id && c.index < ncons)
            || self
                .ancestors
                .iter()
                .any(|&(a, _, n)| a == c.problem && c.index < n)
    }

    /// Whether `v` is this problem's but newer than `nvars`.
    pub fn is_newer_var(&self, v: Var, nvars: usize) -> bool {
        v.problem == self.id && v.index() >= nvars
    }
}

/// The cone a constraint's affine rows `s(x)` must lie in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConeKind {
    /// `s = 0` (equalities).
    Zero,
    /// `s ≥ 0` elementwise.
    Nonnegative,
    /// `s₀ ≥ ‖s₁..‖₂`.
    SecondOrder,
    /// `svec(S) ⪰ 0` for an `n × n` S: the rows are its upper triangle,
    /// column by column, off-diagonals scaled by √2 (Clarabel's
    /// `PSDTriangleConeT`).
    Psd {
        /// Side of the matrix.
        n: usize,
    },
    /// The exponential cone `K_exp = cl{(x, y, z) : y > 0, y·e^{x/y} ≤ z}`
    /// (three rows `x, y, z`; Clarabel's `ExponentialConeT`). Its dual is
    /// `K_exp* = cl{(u, v, w) : u < 0, −u·e^{v/u} ≤ e·w}`.
    Exponential,
}

/// Handle of a constraint of one problem, for its dual and name; using it
/// with another problem or its solution is an error, never an alias.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ConstraintId {
    pub(crate) problem: u32,
    pub(crate) index: usize,
}

/// A symmetric matrix variable, stored as its upper triangle
/// (`n(n+1)/2` scalar variables).
#[derive(Clone, Debug, PartialEq)]
pub struct SymVar {
    n: usize,
    /// Upper triangle, column by column: (0,0), (0,1), (1,1), (0,2), …
    vars: Vec<Var>,
}

impl SymVar {
    /// Side n.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The scalar variable at `(i, j)` (either triangle); `None` out of range.
    pub fn var(&self, i: usize, j: usize) -> Option<Var> {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        (j < self.n).then(|| self.vars[j * (j + 1) / 2 + i])
    }

    /// The full symmetric matrix as an expression.
    pub fn expr(&self) -> MatExpr {
        MatExpr::from_fn(self.n, self.n, |i, j| {
            let (i, j) = if i <= j { (i, j) } else { (j, i) };
            AffExpr::from(self.vars[j * (j + 1) / 2 + i])
        })
    }
}

impl SymVar {
    /// `tr X`.
    pub fn trace(&self) -> AffExpr {
        (0..self.n).map(|i| self[(i, i)]).sum()
    }

    /// The diagonal `[X₀₀, X₁₁, …]`.
    pub fn diagonal(&self) -> Vec<AffExpr> {
        (0..self.n).map(|i| AffExpr::from(self[(i, i)])).collect()
    }

    /// `Σᵢⱼ Xᵢⱼ` (off-diagonals counted twice).
    pub fn sum(&self) -> AffExpr {
        self.expr().sum()
    }
}

impl std::ops::Index<(usize, usize)> for SymVar {
    type Output = Var;
    /// The variable at `(i, j)` (either triangle); panics out of range
    /// ([`SymVar::var`] returns `None`).
    fn index(&self, (i, j): (usize, usize)) -> &Var {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        assert!(
            j < self.n,
            "SymVar index ({i}, {j}) out of range for {0}×{0}",
            self.n
        );
        &self.vars[j * (j + 1) / 2 + i]
    }
}

impl From<&SymVar> for MatExpr {
    fn from(s: &SymVar) -> MatExpr {
        s.expr()
    }
}

#[derive(Clone, Debug)]
pub(crate) struct ConstraintData {
    pub name: String,
    pub kind: ConeKind,
    /// The rows are `rhs − lhs` (an `add_le`).
    pub flipped: bool,
    /// The cone's rows `s(x)`, affine in x.
    pub rows: Vec<AffExpr>,
}

/// Direction of optimisation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sense {
    /// Minimise.
    Minimize,
    /// Maximise (solved as the minimisation of the negated objective).
    Maximize,
}

/// A conic optimisation problem
///
/// ```text
/// minimise    cᵀx + c₀ + Σₖ wₖ (aₖᵀx + bₖ)²
/// subject to  sᵢ(x) ∈ Kᵢ   (each constraint an affine map into a cone)
/// ```
///
/// with Kᵢ the zero cone (equalities), the nonnegative orthant, a
/// second-order cone, a PSD cone or the exponential cone. It compiles to Clarabel's
/// `min ½xᵀPx + qᵀx s.t. Ax + s = b, s ∈ K`.
///
/// ```
/// use momentlmi::conic::{Problem, Settings, Status};
/// let mut p = Problem::new();
/// let x = p.scalar("x");
/// let y = p.scalar("y");
/// p.add_ge(x + y, 1.0).unwrap();
/// p.add_square(1.0, x - 2.0 * y);
/// p.minimize(x + 0.0);
/// let sol = p.solve(&Settings::default()).unwrap();
/// assert_eq!(sol.status, Status::Solved);
/// assert!((sol.value(x).unwrap() - 0.0).abs() < 1e-6 || sol.primal_objective < 1.0);
/// ```
#[derive(Debug)]
pub struct Problem {
    /// Identity of this problem and of those it was cloned from.
    pub(crate) lineage: Lineage,
    pub(crate) nvars: usize,
    pub(crate) var_names: Vec<String>,
    pub(crate) constraints: Vec<ConstraintData>,
    pub(crate) linear: AffExpr,
    pub(crate) squares: Vec<(f64, AffExpr)>,
    pub(crate) sense: Sense,
}

impl Clone for Problem {
    /// A new problem with the same variables, constraints and objective:
    /// handles created before the clone work in both, handles either
    /// creates afterwards only in their own.
    fn clone(&self) -> Self {
        let mut ancestors = self.lineage.ancestors.clone();
        ancestors.push((self.lineage.id, self.nvars, self.constraints.len()));
        Self {
            lineage: Lineage {
                id: new_id(),
                ancestors,
            },
            nvars: self.nvars,
            var_names: self.var_names.clone(),
            constraints: self.constraints.clone(),
            linear: self.linear.clone(),
            squares: self.squares.clone(),
            sense: self.sense,
        }
    }
}

impl Default for Problem {
    fn default() -> Self {
        Self::new()
    }
}

impl Problem {
    /// An empty problem (minimise 0).
    pub fn new() -> Self {
        Self {
            lineage: Lineage {
                id: new_id(),
                ancestors: vec![],
            },
            nvars: 0,
            var_names: Vec::new(),
            constraints: Vec::new(),
            linear: AffExpr::zero(),
            squares: Vec::new(),
            sense: Sense::Minimize,
        }
    }

    /// Number of scalar variables.
    pub fn num_vars(&self) -> usize {
        self.nvars
    }

    /// Number of constraints.
    pub fn num_constraints(&self) -> usize {
        self.constraints.len()
    }

    /// Name of a scalar variable (`None` for another problem's).
    pub fn var_name(&self, v: Var) -> Option<&str> {
        if !self.lineage.owns_var(v, self.nvars) {
            return None;
        }
        self.var_names.get(v.index()).map(String::as_str)
    }

    /// A new free scalar variable.
    pub fn scalar(&mut self, name: &str) -> Var {
        self.var_names.push(name.to_string());
        self.nvars += 1;
        Var {
            problem: self.lineage.id,
            index: u32::try_from(self.nvars - 1).expect("at most 2³² variables"),
        }
    }

    /// `n` new free scalar variables `name[0]..name[n-1]`.
    pub fn vector(&mut self, name: &str, n: usize) -> Vec<Var> {
        (0..n)
            .map(|i| self.scalar(&format!("{name}[{i}]")))
            .collect()
    }

    /// A new free symmetric `n × n` matrix variable.
    pub fn symmetric(&mut self, name: &str, n: usize) -> SymVar {
        let mut vars = Vec::with_capacity(n * (n + 1) / 2);
        for j in 0..n {
            for i in 0..=j {
                vars.push(self.scalar(&format!("{name}[{i},{j}]")));
            }
        }
        SymVar { n, vars }
    }

    /// Whether `e`'s variables are this problem's.
    pub(crate) fn owns(&self, e: &AffExpr) -> bool {
        e.vars().all(|v| self.lineage.owns_var(v, self.nvars))
    }

    fn check_expr(&self, e: &AffExpr, what: &str) -> Result<(), ConicError> {
        if !self.owns(e) {
            return Err(ConicError::ForeignHandle {
                what: format!("a variable in {what}"),
            });
        }
        if !e.is_finite() {
            return Err(ConicError::NonFinite {
                what: what.to_string(),
            });
        }
        Ok(())
    }

    fn push(
        &mut self,
        kind: ConeKind,
        rows: Vec<AffExpr>,
        label: &str,
    ) -> Result<ConstraintId, ConicError> {
        let name = format!("constraint #{} ({label})", self.constraints.len());
        // checked after merging repeated terms: two finite coefficients of
        // one variable can sum to infinity
        let rows: Vec<AffExpr> = rows
            .into_iter()
            .map(|mut e| {
                e.compact();
                e
            })
            .collect();
        for (r, e) in rows.iter().enumerate() {
            self.check_expr(e, &format!("{name}, row {r}"))?;
        }
        self.constraints.push(ConstraintData {
            name,
            kind,
            flipped: false,
            rows,
        });
        Ok(ConstraintId {
            problem: self.lineage.id,
            index: self.constraints.len() - 1,
        })
    }

    /// This problem's constraint `id`, or [`ConicError::ForeignHandle`].
    fn constraint(&self, id: ConstraintId) -> Result<&ConstraintData, ConicError> {
        if self.lineage.owns_constraint(id, self.constraints.len()) {
            Ok(&self.constraints[id.index])
        } else {
            Err(ConicError::ForeignHandle {
                what: format!("constraint handle #{}", id.index),
            })
        }
    }

    /// Names a constraint (used in error messages and reports).
    pub fn set_name(&mut self, id: ConstraintId, name: &str) -> Result<(), ConicError> {
        self.constraint(id)?;
        self.constraints[id.index].name = name.to_string();
        Ok(())
    }

    /// Name of a constraint.
    pub fn constraint_name(&self, id: ConstraintId) -> Result<&str, ConicError> {
        Ok(self.constraint(id)?.name.as_str())
    }

    /// Cone of a constraint.
    pub fn constraint_kind(&self, id: ConstraintId) -> Result<ConeKind, ConicError> {
        Ok(self.constraint(id)?.kind)
    }

    /// `lhs = rhs`. Dual z: `∇f = Σ z ∇(lhs − rhs)`.
    pub fn add_eq(
        &mut self,
        lhs: impl Into<AffExpr>,
        rhs: impl Into<AffExpr>,
    ) -> Result<ConstraintId, ConicError> {
        self.push(ConeKind::Zero, vec![lhs.into() - rhs.into()], "=")
    }

    /// `lhs ≤ rhs`, as `rhs − lhs ≥ 0`; its dual is ≥ 0.
    pub fn add_le(
        &mut self,
        lhs: impl Into<AffExpr>,
        rhs: impl Into<AffExpr>,
    ) -> Result<ConstraintId, ConicError> {
        let id = self.push(ConeKind::Nonnegative, vec![rhs.into() - lhs.into()], "≤")?;
        self.constraints[id.index].flipped = true;
        Ok(id)
    }

    /// `lhs ≥ rhs`, as `lhs − rhs ≥ 0`; its dual is ≥ 0.
    pub fn add_ge(
        &mut self,
        lhs: impl Into<AffExpr>,
        rhs: impl Into<AffExpr>,
    ) -> Result<ConstraintId, ConicError> {
        self.push(ConeKind::Nonnegative, vec![lhs.into() - rhs.into()], "≥")
    }

    /// Every expression `= 0` (one constraint, one dual entry each).
    pub fn add_zeros(
        &mut self,
        exprs: impl IntoIterator<Item = AffExpr>,
    ) -> Result<ConstraintId, ConicError> {
        self.push(ConeKind::Zero, exprs.into_iter().collect(), "= 0")
    }

    /// Every expression `≥ 0`.
    pub fn add_nonneg(
        &mut self,
        exprs: impl IntoIterator<Item = AffExpr>,
    ) -> Result<ConstraintId, ConicError> {
        self.push(ConeKind::Nonnegative, exprs.into_iter().collect(), "≥ 0")
    }

    /// `‖x‖₂ ≤ t`.
    pub fn add_soc(
        &mut self,
        t: impl Into<AffExpr>,
        x: Vec<AffExpr>,
    ) -> Result<ConstraintId, ConicError> {
        let mut rows = vec![t.into()];
        rows.extend(x);
        self.push(ConeKind::SecondOrder, rows, "SOC")
    }

    /// `(x, y, z) ∈ K_exp`, i.e. `y·e^{x/y} ≤ z` with `y > 0` (or, in the
    /// closure, `x ≤ 0, y = 0, z ≥ 0`). Its dual is a 3-vector in
    /// `K_exp* = cl{(u, v, w) : u < 0, −u·e^{v/u} ≤ e·w}`. The atoms built on
    /// it (`log`, `log det`, relative entropy) are in this layer's
    /// [`Problem::add_log_ge`], [`Problem::add_logdet_ge`] and
    /// [`Problem::add_rel_entropy_le`].
    pub fn add_exp_cone(
        &mut self,
        x: impl Into<AffExpr>,
        y: impl Into<AffExpr>,
        z: impl Into<AffExpr>,
    ) -> Result<ConstraintId, ConicError> {
        let rows = vec![x.into(), y.into(), z.into()];
        self.push(ConeKind::Exponential, rows, "exp cone")
    }

    /// `M ⪰ 0` for a symmetric `n × n` expression (a `&MatExpr`, a
    /// `MatExpr` or a `&SymVar`). Its dual is a symmetric PSD matrix Z with
    /// `∇f = Σ ⟨Z, ∇M⟩`.
    pub fn add_psd(&mut self, m: impl Into<MatExpr>) -> Result<ConstraintId, ConicError> {
        self.add_psd_eps(m, 0.0)
    }

    /// `A ⪰ B` (as `A − B ⪰ 0`).
    pub fn add_psd_ge(
        &mut self,
        a: impl Into<MatExpr>,
        b: impl Into<MatExpr>,
    ) -> Result<ConstraintId, ConicError> {
        let d = a.into().try_sub(&b.into())?;
        self.add_psd(d)
    }

    /// `A ⪯ B` (as `B − A ⪰ 0`).
    pub fn add_psd_le(
        &mut self,
        a: impl Into<MatExpr>,
        b: impl Into<MatExpr>,
    ) -> Result<ConstraintId, ConicError> {
        self.add_psd_ge(b, a)
    }

    /// `M ⪰ εI` for any finite ε: with ε > 0 the usual stand-in for a strict
    /// LMI `M ≻ 0` (and `P ⪰ I` is `add_psd_eps(&p, 1.0)`).
    pub fn add_psd_eps(
        &mut self,
        m: impl Into<MatExpr>,
        eps: f64,
    ) -> Result<ConstraintId, ConicError> {
        let m = &m.into();
        let label = if eps == 0.0 {
            "⪰ 0".to_string()
        } else {
            format!("⪰ {eps:e}·I")
        };
        let what = format!("constraint #{} ({label})", self.constraints.len());
        if m.nrows() != m.ncols() {
            return Err(ConicError::DimensionMismatch {
                what,
                expected: "a square matrix".into(),
                found: format!("{}×{}", m.nrows(), m.ncols()),
            });
        }
        if !eps.is_finite() {
            return Err(ConicError::NonFinite {
                what: format!("{what}: ε"),
            });
        }
        if !m.is_finite() {
            return Err(ConicError::NonFinite { what });
        }
        let scale = m
            .entries()
            .iter()
            .flat_map(|e| e.terms.iter().map(|t| t.1.abs()).chain([e.constant.abs()]))
            .fold(1.0f64, f64::max);
        if let Some((row, col)) = m.symmetry_defect(1e-12 * scale) {
            return Err(ConicError::NotSymmetric {
                constraint: what,
                row,
                col,
            });
        }
        let n = m.nrows();
        let mut rows = Vec::with_capacity(n * (n + 1) / 2);
        let s2 = std::f64::consts::SQRT_2;
        for j in 0..n {
            for i in 0..=j {
                let mut e = m.at(i, j).clone();
                if i == j {
                    e.constant -= eps;
                } else {
                    // average the two triangles, then √2-scale
                    e.axpy(1.0, m.at(j, i));
                    e.scale(0.5 * s2);
                }
                rows.push(e);
            }
        }
        self.push(ConeKind::Psd { n }, rows, &label)
    }

    /// `A = B` entry by entry (one constraint, one dual per entry, column-major).
    pub fn add_eq_mat(
        &mut self,
        a: impl Into<MatExpr>,
        b: impl Into<MatExpr>,
    ) -> Result<ConstraintId, ConicError> {
        let (a, b) = (a.into(), b.into());
        let d = a.try_sub(&b)?;
        self.push(ConeKind::Zero, d.entries().to_vec(), "matrix =")
    }

    /// Sets the objective to minimise `e` (replacing any linear objective;
    /// squares added with [`Problem::add_square`] are kept).
    pub fn minimize(&mut self, e: impl Into<AffExpr>) {
        self.linear = e.into();
        self.sense = Sense::Minimize;
    }

    /// Sets the objective to maximise `e`. Not allowed together with squares
    /// (a maximised convex quadratic is not convex): compile reports it.
    pub fn maximize(&mut self, e: impl Into<AffExpr>) {
        self.linear = e.into();
        self.sense = Sense::Maximize;
    }

    /// Adds `weight · e²` to a minimised objective.
    pub fn add_square(&mut self, weight: f64, e: impl Into<AffExpr>) {
        self.squares.push((weight, e.into()));
    }

    /// Adds `weight · Σ eᵢ²`.
    pub fn add_squares(&mut self, weight: f64, exprs: impl IntoIterator<Item = AffExpr>) {
        self.squares.extend(exprs.into_iter().map(|e| (weight, e)));
    }

    /// Adds `weight · ‖M‖²_F = weight · Σᵢⱼ Mᵢⱼ²` (e.g. `M = X − C` for the
    /// nearest X to C in the Frobenius norm).
    pub fn add_frobenius(&mut self, weight: f64, m: impl Into<MatExpr>) {
        self.add_squares(weight, m.into().entries().iter().cloned());
    }

    /// Objective value at x (in the user's sense).
    pub fn objective_at(&self, x: &[f64]) -> f64 {
        self.linear.eval(x)
            + self
                .squares
                .iter()
                .map(|(w, e)| w * e.eval(x).powi(2))
                .sum::<f64>()
    }
}
