//! # `moments`: physical consistency of inertial parameters as moment conditions
//!
//! Implements Sections IV–V of Wensing, Kim & Slotine, "Linear Matrix
//! Inequalities for Physically Consistent Inertial Parameter Identification:
//! A Statistical Perspective on the Mass Distribution" (RA-L 2017):
//!
//! - [`InertialParams`]: π ∈ ℝ¹⁰ in the paper's order and its conversions
//!   (mass/CoM/inertia, spatial inertia, pseudo-inertia J, Σ, Σ_C, covariance
//!   ellipsoid, Pinocchio / spatial_v2 / URDF orders);
//! - [`check_consistency`] / [`check_realizable`]: reports with margins for
//!   Theorem 1 (I ≻ 0), Theorem 3 (J ≻ 0, the triangle inequalities) and
//!   Theorem 4 (tr(JQ) ≥ 0 in an ellipsoid), and the CoM LMI (22);
//! - [`Ellipsoid`]: centre/semi-axes/rotation, its 4×4 Q, bounding ellipsoids
//!   of primitives and the minimum-volume ellipsoid of a point cloud;
//! - [`realize_on_union`]: Corollary 2, solved with [`conic`](crate::conic);
//! - [`four_point_masses`] / [`four_point_masses_in`]: four point masses with
//!   the same moments;
//! - [`degenerate_shape`]: whether a body has collapsed to a point mass, a
//!   rod or a plate against a length;
//! - [`Level`]: a body's constraint level (none, semi, consistent,
//!   ellipsoid);
//! - [`lmi`]: the LMIs as [`conic`](crate::conic) expressions;
//! - [`nearest_consistent`]: repair of an inconsistent π;
//! - [`entropic_divergence`]: the log-det Bregman divergence `d(J ‖ Ĵ)`
//!   between two bodies, its gradient, and [`add_entropic_divergence`] to
//!   write it into a `conic` problem;
//! - [`urdf_check`]: the URDF inertia checker behind `momentlmi check`;
//! - [`geometry`]: a URDF link's geometry — meshes, the bounding ellipsoids
//!   of its shapes, points on them (for plots).

pub mod cache;
mod check;
mod cover;
mod divergence;
mod ellipsoid;
mod error;
pub mod geometry;
mod level;
pub mod lmi;
pub mod mvee;
mod nearest;
mod params;
mod points;
mod shape;
mod union;
pub mod urdf_check;

pub use check::{
    ConsistencyReport, DEFAULT_TOL, RealizabilityReport, Verdict, check_consistency,
    check_realizable,
};
pub use divergence::{
    EntropicTerm, add_entropic_divergence, entropic_divergence, entropic_gradient,
};
pub use ellipsoid::{Ellipsoid, rpy_rotation};
pub use error::MomentsError;
pub use level::{Level, UnknownLevel};
pub use nearest::{Nearest, NearestOptions, nearest_consistent};
pub use params::{
    CovarianceEllipsoid, InertialParams, MAX_ABS_PARAM, MassComInertia, ParamFault, skew,
};
pub use points::{PointMass, four_point_masses, four_point_masses_in, pseudo_inertia_of};
pub use shape::{DEGENERATE_TOL, DegenerateShape, degenerate_shape};
pub use union::{UnionRealization, point_masses_on_union, realize_on_union};
