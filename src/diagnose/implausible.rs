//! When a fitted candidate is physically doubtful: the doubt its search
//! found, a grid point at an open edge of its grid, or the effect's own
//! rule ([`crate::effects::Effect::doubt`]).

use super::candidate::Candidate;

/// Why the fit of `c`'s variant `at` (coefficients `beta`, one per column
/// of the variant) is physically doubtful, if it is.
pub fn implausible(c: &Candidate, at: usize, beta: &[f64], names: &[String]) -> Option<String> {
    let chosen = &c.variants[at];
    if let Some(why) = &chosen.columns.doubt {
        return Some(why.clone());
    }
    let last = c.variants.len() - 1;
    let edge = (at == last && c.open_high) || (at == 0 && c.open_low);
    if c.variants.len() > 2 && edge {
        return Some(format!(
            "its nonlinear parameter ({}) is at the edge of the grid searched; the true value may lie beyond it",
            chosen.columns.detail
        ));
    }
    c.effect.doubt(&chosen.columns, beta, names)
}

#[cfg(test)]
mod tests {
    use super::implausible;
    use crate::diagnose::candidate::Candidate;
    use crate::diagnose::folds::Folds;
    use crate::diagnose::store::Store;
    use crate::effects::{Columns, Hypothesis, Library};

    /// A fit at an open edge of its grid, or an encoder offset beyond a
    /// calibration error, is flagged; one inside its grid is not.
    #[test]
    fn implausible_fits_are_flagged() {
        let folds = Folds {
            ranges: vec![0..2, 2..4],
            fit: 1,
            by_file: false,
        };
        let mut store = Store::new(vec![0.0; 4], 1, &folds);
        let lib = Library::builtin();
        let mut candidate = |name: &str, h: Hypothesis| {
            Candidate::new(lib.get(name).unwrap().clone(), h, &mut store).unwrap()
        };
        let col = |detail: &str| Columns::variant(detail, vec![vec![1.0; 4]], 1);
        let grid = || Hypothesis::grid(["1", "2", "3"].map(col).to_vec());
        let names = vec!["knee".to_string()];
        let delay = candidate("time_delay", grid());
        assert!(implausible(&delay, 1, &[1.0], &names).is_none());
        assert!(implausible(&delay, 0, &[1.0], &names).is_none());
        let edge = implausible(&delay, 2, &[1.0], &names).unwrap();
        assert!(edge.contains("(3)") && edge.contains("edge"), "{edge}");
        let low = candidate("stribeck", grid().open_below());
        assert!(implausible(&low, 0, &[1.0], &names).is_some());
        let off = candidate("joint_offset", Hypothesis::linear(vec![vec![1.0; 4]]));
        assert!(implausible(&off, 0, &[0.05], &names).is_none());
        let far = implausible(&off, 0, &[-0.4], &names).unwrap();
        assert!(far.contains("'knee'") && far.contains("-0.400"), "{far}");
        let mut soft = col("K = (3)");
        soft.doubt = Some("stiffness 3 N·m/rad".into());
        let soft = candidate("elasticity", Hypothesis::single(soft));
        let why = implausible(&soft, 0, &[1.0], &names).unwrap();
        assert!(why.contains("stiffness 3"), "{why}");
    }
}
