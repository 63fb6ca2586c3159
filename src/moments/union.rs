//! Density realizability on a union of ellipsoids (Corollary 2): π is
//! realizable in `S = ∪ⱼ Sⱼ` iff `π = Σⱼ πⱼ` with each πⱼ realizable in Sⱼ.
//! The split is found with one small SDP through [`conic`](crate::conic).

use super::ellipsoid::Ellipsoid;
use super::error::MomentsError;
use super::lmi::BodyVars;
use super::params::InertialParams;
use super::points::{PointMass, four_point_masses_in};
use crate::conic::{Problem, Settings, Status};

/// The answer of [`realize_on_union`].
#[derive(Clone, Debug, PartialEq)]
pub enum UnionRealization {
    /// A split `π = Σ πⱼ`, piece j realizable in ellipsoid j (pieces may be
    /// (near) zero when an ellipsoid holds no mass).
    Realizable(Vec<InertialParams>),
    /// No split exists: π is not density realizable in the union.
    NotRealizable,
}

/// Splits π over the ellipsoids (Corollary 2). Among all valid splits it
/// returns the one that maximises the smallest scaled margin, so each piece
/// is comfortably inside its cone whenever possible.
pub fn realize_on_union(
    pi: &InertialParams,
    parts: &[Ellipsoid],
) -> Result<UnionRealization, MomentsError> {
    if parts.is_empty() {
        return Err(MomentsError::InvalidEllipsoid(
            "an empty union of ellipsoids".into(),
        ));
    }
    if !pi.is_finite() {
        return Err(MomentsError::NonFinite("union realizability".into()));
    }
    let m = pi.mass();
    if m <= 0.0 {
        return Ok(UnionRealization::NotRealizable);
    }
    // Length scale: the largest semi-axis; entries of J scaled to ~m.
    let l = parts.iter().map(|e| e.semi_axes.max()).fold(0.0, f64::max);
    let mut p = Problem::new();
    let t = p.scalar("t");
    let bodies: Vec<BodyVars> = (0..parts.len())
        .map(|j| BodyVars::new(&mut p, &format!("piece{j}")))
        .collect();
    let d = nalgebra::DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![
        1.0 / l,
        1.0 / l,
        1.0 / l,
        1.0,
    ]));
    for (b, s) in bodies.iter().zip(parts) {
        // the pieces of π/m (well scaled whatever the mass):
        // D J D − t·I ⪰ 0 and tr(JQ) ≥ t
        let jd = b.pseudo_inertia().congruence(&d)?;
        p.add_psd(jd - crate::conic::MatExpr::scaled_identity(4, t))?;
        p.add_ge(b.trace_jq(s), t)?;
    }
    for k in 0..10 {
        let sum: crate::conic::AffExpr = bodies.iter().map(|b| &b.params()[k]).sum();
        p.add_eq(sum, pi.0[k] / m)?;
    }
    p.add_le(t, 1.0)?;
    p.maximize(t);
    let sol = p.solve(&Settings::default())?;
    match sol.status {
        s if s.is_solved() => {
            let tv = sol.value(t)?;
            let pieces: Vec<InertialParams> = bodies
                .iter()
                .map(|b| b.value(&sol).map(|q| InertialParams(q.0.map(|x| x * m))))
                .collect::<Result<_, _>>()?;
            let ok = tv >= -1e-7
                && pieces
                    .iter()
                    .zip(parts)
                    .all(|(q, s)| piece_fits(q, s, &d, m));
            Ok(if ok {
                UnionRealization::Realizable(pieces)
            } else {
                UnionRealization::NotRealizable
            })
        }
        Status::PrimalInfeasible | Status::PrimalInfeasibleInaccurate => {
            Ok(UnionRealization::NotRealizable)
        }
        status => Err(MomentsError::Solver {
            status,
            task: "splitting π over a union of ellipsoids".into(),
        }),
    }
}

/// A piece lies in its ellipsoid up to the solver's accuracy, measured
/// against the whole body: `D J D ⪰ −10⁻⁷ m I` and `tr(J Q) ≥ −10⁻⁷ m` (a
/// piece that holds almost no mass is judged by the body's mass, not by its
/// own).
fn piece_fits(q: &InertialParams, s: &Ellipsoid, d: &nalgebra::DMatrix<f64>, m: f64) -> bool {
    let j = q.pseudo_inertia();
    let jd = nalgebra::Matrix4::from_fn(|r, c| j[(r, c)] * d[(r, r)] * d[(c, c)]);
    let min_eig = nalgebra::SymmetricEigen::new(jd).eigenvalues.min();
    min_eig >= -1e-7 * m && (j * s.q_matrix()).trace() >= -1e-7 * m
}

/// Four point masses per piece of a union realization (pieces with no mass
/// are skipped). The masses lie inside their piece's ellipsoid.
pub fn point_masses_on_union(
    pi: &InertialParams,
    parts: &[Ellipsoid],
) -> Result<Vec<PointMass>, MomentsError> {
    match realize_on_union(pi, parts)? {
        UnionRealization::NotRealizable => Err(MomentsError::OutsideUnion { parts: parts.len() }),
        UnionRealization::Realizable(pieces) => {
            let mut out = Vec::new();
            for (q, s) in pieces.iter().zip(parts) {
                // a piece this light is within the union test's tolerance of
                // nothing; its own four masses could be judged outside
                if q.mass() > 1e-6 * pi.mass() {
                    out.extend(four_point_masses_in(q, s)?);
                }
            }
            Ok(out)
        }
    }
}
