//! Solver settings: a builder with defaults, validated once.

use super::error::ConicError;

/// How a weighted sum of squares `Σ wᵢ (aᵢ·x + bᵢ)²` in the objective reaches
/// the solver. Both forms first reduce the stacked rows to their Gram matrix
/// or triangular factor, so their size does not depend on the number of rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LeastSquaresForm {
    /// As Clarabel's quadratic term: `P = 2 AᵀWA`, `q += 2 AᵀWb`.
    #[default]
    Quadratic,
    /// As an epigraph: minimise `t` with `‖R [x; 1]‖² ≤ t` written as the
    /// second-order cone `‖(2 R [x; 1], t − 1)‖ ≤ t + 1`, R from a QR
    /// factorisation of the stacked rows.
    SecondOrderCone,
}

/// Which sparse LDLᵀ factorisation Clarabel uses for its KKT systems.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum KktSolver {
    /// faer's supernodal LDLᵀ (dense kernels on supernodes): much faster on
    /// the dense blocks that PSD cones put into the KKT matrix.
    #[default]
    Faer,
    /// QDLDL, Clarabel's default simplicial LDLᵀ: fine for LPs, QPs and
    /// small PSD cones.
    Qdldl,
}

/// Whether Clarabel's chordal decomposition of sparse PSD cones is used.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Decomposition {
    /// Decompose; then check the result against the original, undecomposed
    /// problem (primal and dual cone membership with the dual PSD-completed,
    /// stationarity, duality gap, all relative to the data's scale) and
    /// solve again without decomposition when the check fails. Clarabel 0.11
    /// can end "solved" at a wrong optimum (SDPLIB control1: 18.0568 instead
    /// of 17.7846; docs/benchmarks.md).
    #[default]
    Verified,
    /// Decompose and return Clarabel's result unchecked.
    Unchecked,
    /// Never decompose.
    Off,
}

/// KKT systems smaller than this (variables + constraints) are factorised
/// on one thread; larger ones on as many as Clarabel chooses.
pub const SERIAL_KKT_DIM: usize = 1000;

/// Settings of the conic layer and of Clarabel.
///
/// ```
/// use momentlmi::conic::Settings;
/// let s = Settings::default().max_iter(300).tol_gap_rel(1e-10).verbose(false);
/// assert!(s.validate().is_ok());
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    pub(crate) max_iter: u32,
    pub(crate) time_limit: f64,
    pub(crate) verbose: bool,
    pub(crate) tol_gap_abs: f64,
    pub(crate) tol_gap_rel: f64,
    pub(crate) tol_feas: f64,
    pub(crate) tol_infeas_abs: f64,
    pub(crate) tol_infeas_rel: f64,
    pub(crate) tol_ktratio: f64,
    pub(crate) equilibrate: bool,
    pub(crate) presolve: bool,
    pub(crate) decomposition: Decomposition,
    pub(crate) decomposition_check_tol: f64,
    pub(crate) no_fallback: Option<String>,
    pub(crate) least_squares: LeastSquaresForm,
    pub(crate) kkt_solver: KktSolver,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            max_iter: 200,
            time_limit: f64::INFINITY,
            verbose: false,
            tol_gap_abs: 1e-8,
            tol_gap_rel: 1e-8,
            tol_feas: 1e-8,
            tol_infeas_abs: 1e-8,
            tol_infeas_rel: 1e-8,
            tol_ktratio: 1e-6,
            equilibrate: true,
            presolve: true,
            decomposition: Decomposition::Verified,
            decomposition_check_tol: 1e-5,
            no_fallback: None,
            least_squares: LeastSquaresForm::Quadratic,
            kkt_solver: KktSolver::Faer,
        }
    }
}

macro_rules! setter {
    ($($(#[$doc:meta])+ $name:ident : $t:ty),* $(,)?) => {$(
        $(#[$doc])+
        pub fn $name(mut self, v: $t) -> Self {
            self.$name = v;
            self
        }
    )*};
}

impl Settings {
    setter! {
        /// Maximum interior-point iterations (default 200).
        max_iter: u32,
        /// Wall-clock limit in seconds (default ∞).
        time_limit: f64,
        /// Print Clarabel's iteration log to stdout (default off).
        verbose: bool,
        /// Absolute duality-gap tolerance (default 1e-8).
        tol_gap_abs: f64,
        /// Relative duality-gap tolerance (default 1e-8).
        tol_gap_rel: f64,
        /// Primal/dual feasibility tolerance, relative (default 1e-8).
        tol_feas: f64,
        /// Absolute infeasibility-certificate tolerance (default 1e-8).
        tol_infeas_abs: f64,
        /// Relative infeasibility-certificate tolerance (default 1e-8).
        tol_infeas_rel: f64,
        /// κ/τ ratio tolerance for infeasibility detection (default 1e-6).
        tol_ktratio: f64,
        /// Ruiz equilibration of the data (default on).
        equilibrate: bool,
        /// Clarabel's presolve, dropping redundant rows (default on).
        presolve: bool,
        /// Clarabel's chordal decomposition of sparse PSD cones (default
        /// [`Decomposition::Verified`]).
        decomposition: Decomposition,
        /// Largest relative residual the check of a decomposed result
        /// accepts (default 1e-5; see [`Decomposition::Verified`]).
        decomposition_check_tol: f64,
        /// How least-squares terms reach the solver (default quadratic).
        least_squares: LeastSquaresForm,
        /// Sparse LDLᵀ used for the KKT systems (default faer's supernodal).
        kkt_solver: KktSolver,
    }

    /// Forbids solving again without decomposition when a decomposed result
    /// fails its check ([`Decomposition::Verified`]): the solve then ends in
    /// [`ConicError::DecompositionRejected`] carrying `why`. For callers that
    /// cannot afford the undecomposed solve's memory (the SDPA reader when
    /// its memory limit admits only the decomposed solve). By default the
    /// fall-back is allowed.
    pub fn forbid_decomposition_fallback(mut self, why: impl Into<String>) -> Self {
        self.no_fallback = Some(why.into());
        self
    }

    /// The least-squares form chosen.
    pub fn least_squares_form(&self) -> LeastSquaresForm {
        self.least_squares
    }

    /// Checks every field once: tolerances positive and finite, a positive
    /// iteration limit and a positive time limit.
    pub fn validate(&self) -> Result<(), ConicError> {
        let tols = [
            ("tol_gap_abs", self.tol_gap_abs),
            ("tol_gap_rel", self.tol_gap_rel),
            ("tol_feas", self.tol_feas),
            ("tol_infeas_abs", self.tol_infeas_abs),
            ("tol_infeas_rel", self.tol_infeas_rel),
            ("tol_ktratio", self.tol_ktratio),
            ("decomposition_check_tol", self.decomposition_check_tol),
        ];
        for (name, v) in tols {
            if !(v.is_finite() && v > 0.0) {
                return Err(ConicError::InvalidSetting {
                    name,
                    reason: format!("must be positive and finite, got {v}"),
                });
            }
        }
        if self.max_iter == 0 {
            return Err(ConicError::InvalidSetting {
                name: "max_iter",
                reason: "must be at least 1".into(),
            });
        }
        if self.time_limit.is_nan() || self.time_limit <= 0.0 {
            return Err(ConicError::InvalidSetting {
                name: "time_limit",
                reason: format!("must be positive (seconds), got {}", self.time_limit),
            });
        }
        Ok(())
    }

    /// Clarabel's settings, with the decomposition on or off, for a KKT
    /// system of dimension `kkt` (variables + constraints): below
    /// [`SERIAL_KKT_DIM`] the factorisation runs on one thread (for a small
    /// system, waking a second costs more than it saves).
    pub(crate) fn to_clarabel(
        &self,
        decompose: bool,
        kkt: usize,
    ) -> clarabel::solver::DefaultSettings<f64> {
        clarabel::solver::DefaultSettings {
            max_iter: self.max_iter,
            time_limit: self.time_limit,
            verbose: self.verbose,
            tol_gap_abs: self.tol_gap_abs,
            tol_gap_rel: self.tol_gap_rel,
            tol_feas: self.tol_feas,
            tol_infeas_abs: self.tol_infeas_abs,
            tol_infeas_rel: self.tol_infeas_rel,
            tol_ktratio: self.tol_ktratio,
            equilibrate_enable: self.equilibrate,
            presolve_enable: self.presolve,
            chordal_decomposition_enable: decompose,
            chordal_decomposition_complete_dual: true,
            direct_solve_method: match self.kkt_solver {
                KktSolver::Faer => "faer".to_string(),
                KktSolver::Qdldl => "qdldl".to_string(),
            },
            max_threads: if kkt < SERIAL_KKT_DIM { 1 } else { 0 },
            ..Default::default()
        }
    }
}
