//! The regressor's column layout, by name: what identification needs to
//! know of a robot to name and constrain its parameters, whether its
//! [`Model`](super::Model) has a fixed or a free-flying root.

use super::friction::FrictionTerm;

/// Columns `[10 per body | per friction term, one per joint]`, rows per
/// sample `rows`.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamLayout {
    /// The bodies, in column order (a free-flyer's base first, then links,
    /// then rotors).
    pub bodies: Vec<String>,
    /// The joints the friction columns are of.
    pub joints: Vec<String>,
    /// The friction terms, in column order.
    pub terms: Vec<FrictionTerm>,
    /// Rows of the regressor per sample (n for a fixed base; 6, n or 6 + n
    /// for a free-flyer, as its rows are chosen).
    pub rows: usize,
    /// The first of them among the sample's rows (0, or 6 for a
    /// free-flyer's joint rows).
    pub first_row: usize,
}

impl ParamLayout {
    /// The rows of each sample this layout's problem fits.
    pub fn row_range(&self) -> std::ops::Range<usize> {
        self.first_row..self.first_row + self.rows
    }

    /// Number of bodies.
    pub fn num_bodies(&self) -> usize {
        self.bodies.len()
    }

    /// Number of regressor columns.
    pub fn columns(&self) -> usize {
        10 * self.bodies.len() + self.terms.len() * self.joints.len()
    }

    /// The first friction column of term `k`.
    pub fn friction_start(&self, k: usize) -> usize {
        10 * self.bodies.len() + k * self.joints.len()
    }

    /// Parameter names: `<body>.<m|hx|…>`, then `<term>.<joint>` for each
    /// friction term (`viscous.<joint>`, `coulomb.<joint>`, …).
    pub fn parameter_names(&self) -> Vec<String> {
        const P: [&str; 10] = [
            "m", "hx", "hy", "hz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz",
        ];
        let mut v: Vec<String> = (self.bodies.iter())
            .flat_map(|b| P.iter().map(move |p| format!("{b}.{p}")))
            .collect();
        for t in &self.terms {
            v.extend(self.joints.iter().map(|j| format!("{}.{j}", t.name())));
        }
        v
    }
}
