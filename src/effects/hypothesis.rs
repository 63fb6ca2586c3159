//! What an effect proposes to a diagnosis: its regressor columns, as one
//! variant or a grid of variants over a nonlinear parameter, and what they
//! cost in memory.

/// One variant of a hypothesis: extra regressor columns over every sample
/// and joint, `cols[c][k·n + i]` for column c, sample k, joint i (the
/// residual's layout), fitted as `r ≈ Σ_c β_c cols[c]` on the training part.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Columns {
    /// The variant's nonlinear parameter, for reports (`"period 6 per motor
    /// turn"`; empty for a linear hypothesis).
    pub detail: String,
    /// The columns, column-major.
    pub cols: Vec<Vec<f64>>,
    /// An inertial correction: the nominal parameters of the corrected
    /// bodies, 10 columns each in the paper's order, first; the fit keeps
    /// `J(π + β) ⪰ 0` for each.
    pub bodies: Vec<[f64; 10]>,
    /// The coefficients must be ≥ 0 (a mass).
    pub nonneg: bool,
    /// The model bodies (their indices) each block of 10 columns corrects,
    /// in order, when the fitted coefficients are changes of their
    /// inertial parameters (a payload's: the body that carries it): a model
    /// file adds them there.
    pub into_bodies: Vec<usize>,
    /// Nonlinear parameters chosen before the linear fit (a delay, a grid
    /// point, a stiffness per joint, …); they count in the fit's ΔBIC.
    pub nonlinear: usize,
    /// Why the nonlinear parameters found are physically doubtful, if they
    /// are (when they were searched, not gridded).
    pub doubt: Option<String>,
    /// The variant's nonlinear parameters by name, with SI values
    /// (`[("delay_s", 0.025)]`): what a model file records so that the
    /// effect's columns can be built again on other data
    /// ([`crate::effects::Effect::replay`]); empty for a linear hypothesis.
    pub key: Vec<(String, f64)>,
    /// The joint each column lies in by construction (`None`: several),
    /// one per column; empty: read off the values (a column that is zero
    /// on some data has no joint there, so an effect whose columns are one
    /// joint's each says which).
    pub joints: Vec<Option<usize>>,
}

impl Columns {
    /// Plain linear columns.
    pub fn linear(cols: Vec<Vec<f64>>) -> Self {
        Self {
            cols,
            ..Self::default()
        }
    }

    /// One point of a grid over `nonlinear` nonlinear parameters.
    pub fn variant(detail: impl Into<String>, cols: Vec<Vec<f64>>, nonlinear: usize) -> Self {
        Self {
            detail: detail.into(),
            cols,
            nonlinear,
            ..Self::default()
        }
    }

    /// The same with each column's joint stated (one per column).
    pub fn in_joints(mut self, joints: impl IntoIterator<Item = usize>) -> Self {
        self.joints = joints.into_iter().map(Some).collect();
        self
    }

    /// The same with its nonlinear parameter recorded as `name = value`.
    pub fn keyed(mut self, name: &str, value: f64) -> Self {
        self.key.push((name.to_string(), value));
        self
    }

    /// The recorded value of the nonlinear parameter `name`.
    pub fn key_value(&self, name: &str) -> Option<f64> {
        self.key.iter().find(|(k, _)| k == name).map(|(_, v)| *v)
    }
}

/// An effect's hypothesis: its variants (the diagnosis fits each on the
/// training part and keeps the best), and which edges of a grid can hide a
/// value beyond them (a fit at such an edge is reported as doubtful).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Hypothesis {
    /// The variants, in grid order (none: nothing to propose on this model).
    pub variants: Vec<Columns>,
    /// The true value may lie below the grid's first point.
    pub open_low: bool,
    /// The true value may lie above the grid's last point.
    pub open_high: bool,
}

impl Hypothesis {
    /// One variant.
    pub fn single(c: Columns) -> Self {
        Self {
            variants: vec![c],
            ..Self::default()
        }
    }

    /// Linear columns.
    pub fn linear(cols: Vec<Vec<f64>>) -> Self {
        Self::single(Columns::linear(cols))
    }

    /// Linear columns, the i-th in joint i's rows.
    pub fn per_joint(cols: Vec<Vec<f64>>) -> Self {
        let n = cols.len();
        Self::single(Columns::linear(cols).in_joints(0..n))
    }

    /// A grid of variants whose top can hide a larger value (the longest
    /// delay, the finest period); [`Self::open_below`] for one whose bottom
    /// can too.
    pub fn grid(variants: Vec<Columns>) -> Self {
        Self {
            variants,
            open_low: false,
            open_high: true,
        }
    }

    /// The grid's bottom can hide a smaller value too.
    pub fn open_below(mut self) -> Self {
        self.open_low = true;
        self
    }

    /// Nothing to propose.
    pub fn none() -> Self {
        Self::default()
    }
}

/// The size of a diagnosis, for memory estimates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shape {
    /// Joints n.
    pub joints: usize,
    /// Bodies (links and rotors).
    pub bodies: usize,
    /// Samples.
    pub samples: usize,
}

impl Shape {
    /// Bytes of `count` columns over every sample and joint, twice (the
    /// columns and a fitted copy).
    pub fn columns(&self, count: usize) -> u64 {
        8 * 2 * self.samples as u64 * self.joints as u64 * count as u64
    }
}

/// What an effect's hypothesis holds in memory while a diagnosis runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Memory {
    /// Its own bytes.
    pub bytes: u64,
    /// Essential, or part of an optional group.
    pub part: Part,
}

/// Whether a hypothesis must fit in the memory limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// The diagnosis is refused if the essential hypotheses do not fit.
    Essential,
    /// Left out, with a warning, when it does not fit; the hypotheses of
    /// one group go together (in the library's order of groups), their
    /// `shared` bytes counted once.
    Optional {
        /// The group (`"inertial"`, `"compliance"`).
        group: &'static str,
        /// Bytes the group's hypotheses share (a linearisation).
        shared: u64,
    },
}

impl Memory {
    /// `count` essential columns.
    pub fn columns(shape: &Shape, count: usize) -> Self {
        Self {
            bytes: shape.columns(count),
            part: Part::Essential,
        }
    }

    /// `count` columns of the optional group `group` (sharing `shared`
    /// bytes with its other members).
    pub fn optional(shape: &Shape, count: usize, group: &'static str, shared: u64) -> Self {
        Self {
            bytes: shape.columns(count),
            part: Part::Optional { group, shared },
        }
    }
}
