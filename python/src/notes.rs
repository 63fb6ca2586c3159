//! The warnings of an identification, as the command line prints them
//! beside its report: the report's own (`warnings`, each by its `kind`),
//! a solver status other than `solved`, the bodies that are not physically
//! consistent or identified as point masses, rods or plates, and the
//! directions the data (not the robot's structure) leave unexcited. Each is
//! a `(kind, message)`; the package issues each as a `MomentlmiWarning`.

use momentlmi::identify::{Identifiability, IdentifyResult, IdentifyWarning};

/// A warning: its kind (the report's `kind`, or the binding's own) and its
/// message (the command line's words).
pub(crate) type Note = (String, String);

/// Every warning of the identification `r`, in the command line's order.
pub(crate) fn of_identification(r: &IdentifyResult) -> Vec<Note> {
    let mut out: Vec<Note> = r
        .warnings
        .iter()
        .map(|w| (kind(w), w.to_string()))
        .collect();
    if r.status != "solved" && !out.iter().any(|(k, _)| k == "inaccurate") {
        let m = format!("the solver's status is '{}', not 'solved'", r.status);
        out.push(("status".into(), m));
    }
    if !r.all_bodies_consistent {
        let m = format!(
            "not physically consistent (J(π) is not positive semidefinite): {}; constraints=\"consistent\" or above makes every body physical",
            r.inconsistent_bodies.join(", ")
        );
        out.push(("inconsistent_bodies".into(), m));
    }
    for b in &r.bodies {
        if let Some(d) = &b.degenerate {
            let [x, y, z] = d.semi_axes;
            let m = format!(
                "body '{}' is identified as a {} (spread {x:.1e}, {y:.1e}, {z:.1e} m against {:.3} m): {}",
                b.name,
                d.shape.as_str(),
                d.length,
                d.advice
            );
            out.push(("degenerate_body".into(), m));
        }
    }
    out.extend(unexcited(&r.identifiability).map(|m| ("identifiability".into(), m)));
    out
}

/// A report warning's `kind`, as its JSON names it.
fn kind(w: &IdentifyWarning) -> String {
    let v = serde_json::to_value(w).ok();
    let k = v.as_ref().and_then(|v| v.get("kind")?.as_str());
    k.unwrap_or("identify").to_string()
}

/// The directions the data do not excite, when the data could have
/// excited more (the command line's warning); `None` when every direction
/// is seen, or when the robot's structure allows no more (its note: a fact
/// of the robot, in the report's `identifiability` alone).
fn unexcited(id: &Identifiability) -> Option<String> {
    let all_seen = id.rank == id.columns && id.unidentifiable.is_empty();
    if all_seen || id.structural_rank == Some(id.rank) {
        return None;
    }
    Some(format!(
        "{}; the directions in result[\"identifiability\"][\"directions\"]",
        id.summary()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unexcited_directions_warn_only_below_the_structural_rank() {
        let mut id = Identifiability {
            rank: 30,
            columns: 66,
            structural_rank: Some(38),
            unidentifiable: vec!["abad.m".into()],
            ..Identifiability::default()
        };
        let w = unexcited(&id).expect("30 of the 38 the structure allows: a warning");
        assert!(w.starts_with("30 of 66 parameter directions"), "{w}");
        id.rank = 38;
        assert_eq!(unexcited(&id), None);
        id.structural_rank = None;
        assert!(unexcited(&id).is_some());
    }

    #[test]
    fn a_report_warning_keeps_its_kind() {
        let w = IdentifyWarning::Inaccurate { iterations: 7 };
        assert_eq!(kind(&w), "inaccurate");
        assert!(w.to_string().contains("7 iterations"));
    }
}
