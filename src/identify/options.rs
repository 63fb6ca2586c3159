//! The identification's options: the constraint [`Level`] (the paper's,
//! from [`crate::moments`]), the [`Regularizer`], [`IdentifyOptions`], the
//! solver's default tolerances and the tolerance results are checked with.

use super::error::IdentifyError;
use crate::conic::Settings;
use crate::dynamics::RobotDescription;
use crate::moments::Ellipsoid;
pub use crate::moments::Level;
use serde::Serialize;

/// Tolerance with which identified bodies are checked (an interior-point
/// solution on the boundary of a cone sits within ~1e-9 of it).
pub const CHECK_TOL: f64 = 1e-7;

/// How the prior π̂ enters the objective, with the weight w_π.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "snake_case")]
pub enum Regularizer {
    /// `w ‖π − π̂‖²` over every body's ten parameters (units mixed: kg,
    /// kg·m, kg·m²; w in N²·m² per unit²).
    #[default]
    Euclidean,
    /// `w Σ_b d(J_b ‖ Ĵ_b)`, `d(J ‖ Ĵ) = −log det(Ĵ⁻¹J) + tr(Ĵ⁻¹J) − 4`:
    /// dimensionless and frame invariant (w in N²·m²); keeps every J ≻ 0
    /// and needs every prior body strictly consistent.
    Entropic,
    /// `w Σ_b ½ tr(Ĵ_b⁻¹ΔJ_b Ĵ_b⁻¹ΔJ_b)`, `ΔJ = J(π) − J(π̂)`: the entropic
    /// divergence's second-order term at the prior (the constant-pullback
    /// distance of Lee, Wensing & Park 2020, "Geometric robot dynamic
    /// identification"). Dimensionless and frame invariant like the
    /// entropic one, holding a body's spread in proportion to the prior's
    /// own (where the Euclidean prior barely sees a second moment of
    /// 1e-2 kg·m²), but quadratic: it costs what the Euclidean prior costs
    /// and its weight is chosen with the friction law from the same Gram
    /// matrices. Needs every prior body strictly consistent.
    Pullback,
}

impl Regularizer {
    /// From the CLI name.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "euclidean" => Some(Self::Euclidean),
            "entropic" => Some(Self::Entropic),
            "pullback" => Some(Self::Pullback),
            _ => None,
        }
    }

    /// The regulariser when neither it nor the weight is given, the weight
    /// chosen from the data with the friction law, at constraint `level`
    /// (every body's): entropic when the level constrains (not
    /// [`Level::None`]: the divergence is itself a barrier at `J ≻ 0`, so
    /// it would constrain an unconstrained fit) and every body of `prior`
    /// (10 values each) is strictly consistent (`J(π̂) ≻ 0`, by its Cholesky
    /// factorisation), else Euclidean. No body identified under the
    /// barrier collapses to a point, rod or plate; its weight is chosen on
    /// its second-order term at the prior (the [`Self::Pullback`]
    /// quadratic) from the same Gram matrices as the law.
    pub fn for_chosen_weight(prior: &[f64], level: Level) -> Self {
        if level == Level::None {
            return Self::Euclidean;
        }
        let strictly = |p: &[f64]| {
            let pi = crate::moments::InertialParams(std::array::from_fn(|k| p[k]));
            pi.pseudo_inertia().cholesky().is_some()
        };
        let all = !prior.is_empty() && prior.chunks_exact(10).all(strictly);
        match all && prior.len().is_multiple_of(10) {
            true => Self::Entropic,
            false => Self::Euclidean,
        }
    }

    /// The CLI name.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Euclidean => "euclidean",
            Self::Entropic => "entropic",
            Self::Pullback => "pullback",
        }
    }
}

/// Options of [`super::solve_identification`], validated at construction; what
/// depends on the model (the prior's and the ellipsoids' lengths) is checked
/// against it when solving.
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifyOptions {
    pub(crate) level: Level,
    pub(crate) weight: f64,
    pub(crate) mass_weight: MassWeight,
    pub(crate) prior: Vec<f64>,
    pub(crate) regularizer: Regularizer,
    pub(crate) ellipsoids: Option<Vec<Ellipsoid>>,
    pub(crate) com_lmi: bool,
    pub(crate) eps: f64,
    pub(crate) settings: Settings,
}

/// The extra weight `w_m Σ_b (m_b − m̂_b)²` toward the prior's masses: the
/// caller's, else the robot's (its sidecar's `[identify] prior_mass_weight`),
/// settled when the problem is solved from the prior then set.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct MassWeight {
    /// Set by the caller (`prior_mass_weight`): used as it is.
    pub(crate) explicit: Option<f64>,
    /// The robot's: used with the Euclidean prior on only (with the entropic
    /// one it moved the Panda's lightest link further from the truth, see
    /// docs/identification.md; the pullback prior holds masses in
    /// proportion to the prior's like the entropic one).
    pub(crate) robot: Option<f64>,
}

impl MassWeight {
    /// The weight in effect with prior weight `weight` and `regularizer`.
    pub(crate) fn resolve(&self, weight: f64, regularizer: Regularizer) -> f64 {
        self.explicit.unwrap_or_else(|| match self.robot {
            Some(w) if weight > 0.0 && regularizer == Regularizer::Euclidean => w,
            _ => 0.0,
        })
    }
}

/// The solver settings of the constrained levels: tolerances 1e-9, at most
/// 300 iterations.
pub fn default_settings() -> Settings {
    Settings::default()
        .tol_gap_abs(1e-9)
        .tol_gap_rel(1e-9)
        .tol_feas(1e-9)
        .max_iter(300)
}

impl IdentifyOptions {
    /// `level` for every body, no regularisation, no ellipsoids, no CoM
    /// LMI, `⪰ 0` LMIs.
    pub fn new(level: Level) -> Self {
        Self {
            level,
            weight: 0.0,
            mass_weight: MassWeight::default(),
            prior: vec![],
            regularizer: Regularizer::Euclidean,
            ellipsoids: None,
            com_lmi: false,
            eps: 0.0,
            settings: default_settings(),
        }
    }

    /// A robot's set-up: its CAD prior with weight `weight` (and the masses'
    /// extra weight its sidecar sets, used with the Euclidean prior on unless
    /// [`Self::with_prior_mass_weight`] sets one), and its bounding
    /// ellipsoids when every body has exactly one (required, and an error
    /// naming the body otherwise, for [`Level::Ellipsoid`]). A robot whose
    /// sidecar sets identification facts (per-body levels, a total mass,
    /// equal bodies) is refused: these options cannot express them, use
    /// [`super::Identification::for_robot`].
    pub fn for_robot(
        robot: &RobotDescription,
        level: Level,
        weight: f64,
    ) -> Result<Self, IdentifyError> {
        let f = &robot.identification;
        let set: Vec<&str> = [
            ("per-body levels", f.levels.iter().any(Option::is_some)),
            ("total_mass", f.total_mass.is_some()),
            ("equal", !f.equal.is_empty()),
        ]
        .into_iter()
        .filter_map(|(name, on)| on.then_some(name))
        .collect();
        if !set.is_empty() {
            return Err(IdentifyError::RobotFacts {
                robot: robot.origin(),
                facts: set,
            });
        }
        let mut opts = Self::new(level).with_prior(weight, robot.prior_vector())?;
        opts.mass_weight.robot = f.prior_mass_weight;
        match robot.single_ellipsoids() {
            Ok(e) => Ok(opts.with_ellipsoids(e)),
            Err(e) if level == Level::Ellipsoid => Err(e.into()),
            Err(_) => Ok(opts),
        }
    }

    /// Regularisation `w R(π, π̂)` toward `prior` (10 per body, links then
    /// rotors; R the [`Regularizer`], Euclidean by default); `w` ≥ 0 and
    /// finite (0: off), the prior finite.
    pub fn with_prior(mut self, weight: f64, prior: Vec<f64>) -> Result<Self, IdentifyError> {
        nonnegative("weight", weight)?;
        if let Some(k) = prior.iter().position(|x| !x.is_finite()) {
            return Err(IdentifyError::PriorNotFinite {
                index: k,
                value: prior[k],
            });
        }
        self.weight = weight;
        self.prior = prior;
        Ok(self)
    }

    /// The extra weight `w_m Σ_b (m_b − m̂_b)²` toward the prior's masses
    /// ([`super::Identification::prior_mass_weight`]); ≥ 0 and finite
    /// (0, the default: off).
    pub fn with_prior_mass_weight(mut self, mass_weight: f64) -> Result<Self, IdentifyError> {
        self.mass_weight.explicit = Some(nonnegative("prior_mass_weight", mass_weight)?);
        Ok(self)
    }

    /// How the prior enters the objective (default Euclidean).
    pub fn with_regularizer(mut self, r: Regularizer) -> Self {
        self.regularizer = r;
        self
    }

    /// One bounding ellipsoid per body (the ellipsoid level and the CoM LMI).
    pub fn with_ellipsoids(mut self, ellipsoids: Vec<Ellipsoid>) -> Self {
        self.ellipsoids = Some(ellipsoids);
        self
    }

    /// Adds the CoM-in-ellipsoid LMI (22) (needs ellipsoids).
    pub fn with_com_lmi(mut self, on: bool) -> Self {
        self.com_lmi = on;
        self
    }

    /// Margin ε of the strict LMIs `⪰ εI` (≥ 0, finite).
    pub fn with_eps(mut self, eps: f64) -> Result<Self, IdentifyError> {
        self.eps = nonnegative("eps", eps)?;
        Ok(self)
    }

    /// The solver settings of the constrained levels (default
    /// [`default_settings`]); validated here.
    pub fn with_settings(mut self, settings: Settings) -> Result<Self, IdentifyError> {
        settings.validate()?;
        self.settings = settings;
        Ok(self)
    }

    /// The constraint level.
    pub fn level(&self) -> Level {
        self.level
    }

    /// The regularisation weight.
    pub fn weight(&self) -> f64 {
        self.weight
    }

    /// The prior (10 per body).
    pub fn prior(&self) -> &[f64] {
        &self.prior
    }

    /// The masses' extra weight in effect: the one set, else the robot's with
    /// the Euclidean prior on, else 0.
    pub fn prior_mass_weight(&self) -> f64 {
        self.mass_weight.resolve(self.weight, self.regularizer)
    }

    /// The regulariser.
    pub fn regularizer(&self) -> Regularizer {
        self.regularizer
    }

    /// The ellipsoids, if given.
    pub fn ellipsoids(&self) -> Option<&[Ellipsoid]> {
        self.ellipsoids.as_deref()
    }
}

/// `value` if it is ≥ 0 and finite, else the option error naming `option`.
pub(crate) fn nonnegative(option: &'static str, value: f64) -> Result<f64, IdentifyError> {
    if value >= 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(IdentifyError::Negative { option, value })
    }
}
