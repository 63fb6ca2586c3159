//! What an accepted effect reports of its fit: named sizes with units
//! (a gain in %, a delay in ms, a payload's mass in kg), each a function
//! of the fitted coefficients — so that the diagnosis can give each an
//! interval from the coefficients' replicates.

use crate::dynamics::Model;
use serde::Serialize;

/// One size of a fitted effect.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Size {
    /// What it is, with the joint or body it belongs to
    /// (`"gain error, lwr_1_joint"`).
    pub name: String,
    /// Its unit (`"%"`, `"ms"`, `"kg"`, `"N·m"`).
    pub unit: String,
    /// Its value.
    pub value: f64,
}

impl Size {
    /// A size.
    pub fn new(name: impl Into<String>, unit: impl Into<String>, value: f64) -> Self {
        Self {
            name: name.into(),
            unit: unit.into(),
            value,
        }
    }
}

/// What sizes are computed from besides the coefficients.
pub struct SizeContext<'a> {
    /// The model (its joints, bodies and tool point).
    pub model: &'a Model,
    /// The joint of each column of the variant, when it lies in one.
    pub col_joints: &'a [Option<usize>],
}

impl SizeContext<'_> {
    /// The name of joint `i`.
    pub fn joint(&self, i: usize) -> &str {
        self.model.joints.get(i).map_or("?", |j| j.name.as_str())
    }

    /// One size per column with a joint and a coefficient that is not zero
    /// (a joint the effect was not kept on has zeros): `name, <joint>` in
    /// `unit`, the coefficient times `scale`.
    pub fn per_joint(&self, beta: &[f64], name: &str, unit: &str, scale: f64) -> Vec<Size> {
        (beta.iter().zip(self.col_joints))
            .filter(|(b, _)| **b != 0.0)
            .filter_map(|(b, j)| {
                j.map(|j| Size::new(format!("{name}, {}", self.joint(j)), unit, b * scale))
            })
            .collect()
    }

    /// Per joint whose columns are a sine and a cosine with coefficients
    /// that are not both zero: the amplitude `√(a² + b²)` in `unit`.
    pub fn amplitudes(&self, beta: &[f64], name: &str, unit: &str) -> Vec<Size> {
        let mut joints: Vec<usize> = self.col_joints.iter().flatten().copied().collect();
        joints.dedup();
        joints.sort_unstable();
        joints.dedup();
        joints
            .into_iter()
            .filter_map(|j| {
                let mine: Vec<f64> = (beta.iter().zip(self.col_joints))
                    .filter(|(_, c)| **c == Some(j))
                    .map(|(b, _)| *b)
                    .collect();
                (mine.len() == 2 && mine.iter().any(|b| *b != 0.0)).then(|| {
                    Size::new(
                        format!("{name}, {}", self.joint(j)),
                        unit,
                        mine[0].hypot(mine[1]),
                    )
                })
            })
            .collect()
    }
}
