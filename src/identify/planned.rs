//! An identification of whole training data with what its caller left open
//! chosen from that data, in the one order `momentlmi identify` and the
//! Python binding both run: the friction law (with the prior's weight when
//! that is open too), the identification set up for the model with that law
//! ([`Setup`], the caller's options), the weight alone when the law was
//! given, the reduction (made from the law's choice pass), the fit (with the
//! caller's own work on the other core) and each parameter's range.

use super::friction_choice::{FrictionChoice, LawChoice};
use super::{Identification, IdentifyError, IdentifyResult, Margin, Reduced, WEIGHT_GRID};
use crate::data::Dataset;
use crate::dynamics::RobotDescription;

/// The training data as the caller has them.
#[derive(Clone, Copy, Debug)]
pub enum Training<'a> {
    /// Every sample (what a choice from the data needs).
    Samples(&'a Dataset),
    /// Reduced while read ([`reduce_logs`](super::reduce_logs)): the law
    /// and the weight must be given ([`IdentifyError::ChoiceNeedsSamples`]).
    Reduced(&'a Reduced),
}

/// How the friction law is had.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LawPlan {
    /// The model's own law.
    Own,
    /// Chosen from the data; data too short to choose are an error.
    Choose,
    /// Chosen from the data, or, with data too short to choose, the model's
    /// own law kept at the identification's weight with a warning
    /// ([`IdentifyWarning::LawNotChosen`](super::IdentifyWarning)).
    ChooseOrKeep,
}

impl LawPlan {
    /// The plan the options ask for: `auto` a law chosen from the data
    /// (else the model's own); `asked` the law or the weight named by the
    /// caller (then data too short to choose are an error, else the
    /// model's law is kept with a warning).
    pub fn for_options(auto: bool, asked: bool) -> Self {
        match (auto, asked) {
            (false, _) => LawPlan::Own,
            (true, true) => LawPlan::Choose,
            (true, false) => LawPlan::ChooseOrKeep,
        }
    }
}

/// What [`identify_planned`] chooses and computes.
#[derive(Clone, Copy, Debug)]
pub struct Plan {
    /// How the friction law is had.
    pub law: LawPlan,
    /// The prior's weight; `None`: chosen from the data (with the law when
    /// it is chosen, else by [`Identification::choose_weight`] over
    /// [`WEIGHT_GRID`]).
    pub weight: Option<f64>,
    /// Each parameter's range with this residual margin; `None`: no ranges.
    pub bounds: Option<Margin>,
}

/// The step of [`identify_planned`] that failed, for the caller to name
/// the option it concerns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// Choosing the friction law, or applying it to the model.
    Law,
    /// Choosing or setting the prior's weight.
    Weight,
    /// Reducing the training data.
    Reduce,
    /// The fit.
    Fit,
    /// The parameters' ranges.
    Bounds,
}

/// A failed step and why.
#[derive(Debug)]
pub struct Failed {
    /// Which step.
    pub step: Step,
    /// Why.
    pub source: IdentifyError,
}

/// The caller's options as an identification of a model: its prior,
/// levels, regulariser, constraints, memory limit.
pub trait Setup {
    /// The caller's error, which a failed step converts into.
    type Error: From<Failed>;

    /// The identification of `robot` (the model with the law in use) at
    /// `weight` (the grid's first when the weight is chosen from the data:
    /// the choice then sets it).
    fn identification<'r>(
        &self,
        robot: &'r RobotDescription,
        weight: f64,
    ) -> Result<Identification<'r>, Self::Error>;
}

/// What [`identify_planned`] found: the result (its law and weight choices
/// in `model_selection` and `weight_choice`) and the robot with the law
/// chosen (the given one when the law was not).
#[derive(Debug)]
pub struct Planned {
    /// The identification.
    pub result: IdentifyResult,
    /// The robot whose model the result belongs to.
    pub robot: RobotDescription,
}

/// Runs `plan` on the whole training data `train` for `robot` with the
/// caller's `setup`; `beside` runs on another thread while the fit is
/// solved, and its value is returned whatever the fit's outcome (the
/// command line reads its held-out files there, and shows their error
/// first); `None` when a step before the fit failed (it is not run).
pub fn identify_planned<S: Setup, T: Send>(
    setup: &S,
    robot: &RobotDescription,
    train: Training,
    plan: &Plan,
    beside: impl FnOnce() -> T + Send,
) -> (Result<Planned, S::Error>, Option<T>) {
    let first = plan.weight.unwrap_or(WEIGHT_GRID[0]);
    let law = (|| {
        let id = setup.identification(robot, first)?;
        chosen_law(&id, train, plan)
    })();
    let (selection, kept) = match law {
        Ok(l) => l,
        Err(e) => return (Err(e), None),
    };
    let chosen = match with_law(robot, selection.as_ref()) {
        Ok(r) => r,
        Err(e) => return (Err(e.into()), None),
    };
    let mut id = match weighted(setup, &chosen, first, selection.as_ref()) {
        Ok(id) => id,
        Err(e) => return (Err(e), None),
    };
    let (fitted, side) = fit(&mut id, train, plan, (selection, kept.is_some()), beside);
    drop(id);
    let result = fitted.map(|mut r| {
        r.warnings.extend(kept);
        Planned {
            result: r,
            robot: chosen,
        }
    });
    (result.map_err(S::Error::from), side)
}

/// The law chosen (or `None`: the model's own) and the warning when it
/// was kept for want of data.
fn chosen_law<E: From<Failed>>(
    id: &Identification,
    train: Training,
    plan: &Plan,
) -> Result<(Option<FrictionChoice>, Option<super::IdentifyWarning>), E> {
    let weights = id.model_weights(plan.weight.is_none());
    let failed = |source| Failed {
        step: Step::Law,
        source,
    };
    let train = match (train, plan.law) {
        (_, LawPlan::Own) => return Ok((None, None)),
        (Training::Samples(d), _) => d,
        (Training::Reduced(_), _) => return Err(failed(IdentifyError::ChoiceNeedsSamples).into()),
    };
    Ok(match plan.law {
        LawPlan::Own => (None, None),
        LawPlan::Choose => (Some(id.choose_model(train, weights).map_err(failed)?), None),
        LawPlan::ChooseOrKeep => match id.choose_model_or_keep(train, weights).map_err(failed)? {
            LawChoice::Chosen(c) => (Some(c), None),
            LawChoice::Kept(w) => (None, Some(w)),
        },
    })
}

/// `robot` with the law `c` chose (itself when none was).
fn with_law(
    robot: &RobotDescription,
    c: Option<&FrictionChoice>,
) -> Result<RobotDescription, Failed> {
    let mut r = robot.clone();
    if let Some(c) = c {
        r.model = c.apply(r.model).map_err(|e| Failed {
            step: Step::Law,
            source: IdentifyError::Dynamics(e),
        })?;
    }
    Ok(r)
}

/// The identification of the robot with its law, at the weight chosen with
/// the law when it was.
fn weighted<'r, S: Setup>(
    setup: &S,
    robot: &'r RobotDescription,
    first: f64,
    selection: Option<&FrictionChoice>,
) -> Result<Identification<'r>, S::Error> {
    let id = setup.identification(robot, first)?;
    match selection.filter(|c| c.weight_chosen()) {
        Some(c) => Ok(id.with_weight(c.weight()).map_err(|source| Failed {
            step: Step::Weight,
            source,
        })?),
        None => Ok(id),
    }
}

/// The weight's own choice (when it is open and the law did not set it),
/// the reduction, the fit beside `beside`, and the ranges.
fn fit<T: Send>(
    id: &mut Identification,
    train: Training,
    plan: &Plan,
    (mut selection, kept): (Option<FrictionChoice>, bool),
    beside: impl FnOnce() -> T + Send,
) -> (Result<IdentifyResult, Failed>, Option<T>) {
    let at = |step| move |source| Failed { step, source };
    let open = plan.weight.is_none() && selection.as_ref().is_none_or(|c| !c.weight_chosen());
    // (a law kept for want of data keeps the weight it was given)
    let choice = match (open && !kept, train) {
        (false, _) => None,
        (true, Training::Reduced(_)) => {
            return (
                Err(at(Step::Weight)(IdentifyError::ChoiceNeedsSamples)),
                None,
            );
        }
        (true, Training::Samples(d)) => {
            match id.choose_weight(d, &WEIGHT_GRID).map_err(at(Step::Weight)) {
                Ok(c) => Some(c),
                Err(e) => return (Err(e), None),
            }
        }
    };
    let red = match train {
        Training::Samples(d) => id.reduce_chosen(d, selection.as_mut()),
        Training::Reduced(r) => Ok(r.clone()),
    };
    let red = match red {
        Ok(r) => r,
        Err(e) => return (Err(at(Step::Reduce)(e)), None),
    };
    let (fitted, side) = std::thread::scope(|s| {
        let side = s.spawn(beside);
        let fitted = match train {
            Training::Samples(d) => id.fit_reduced(d, &red),
            Training::Reduced(_) => id.fit_streamed(&red),
        };
        (fitted.map_err(at(Step::Fit)), side.join())
    });
    let side = match side {
        Ok(v) => v,
        Err(p) => std::panic::resume_unwind(p),
    };
    let result = fitted.and_then(|mut r| {
        if let Some(m) = plan.bounds {
            let rows = red.samples * id.model().dof();
            let delta = m
                .delta(r.identifiability.rank, rows)
                .map_err(at(Step::Bounds))?;
            let b = id.parameter_bounds(&red, &r.theta, &r.identifiability, delta);
            r.bounds = Some(b.map_err(at(Step::Bounds))?);
        }
        r.weight_choice = choice;
        r.model_selection = selection;
        Ok(r)
    });
    (result, Some(side))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{Friction, Samples, random_states};
    use crate::identify::Level;

    /// The consistent level at the weight asked, nothing else.
    struct Consistent;

    impl Setup for Consistent {
        type Error = Failed;

        fn identification<'r>(
            &self,
            robot: &'r RobotDescription,
            weight: f64,
        ) -> Result<Identification<'r>, Failed> {
            Identification::for_robot(robot, Level::Consistent, weight).map_err(|source| Failed {
                step: Step::Fit,
                source,
            })
        }
    }

    /// The leg and 600 random states with its rigid torques.
    fn leg() -> (RobotDescription, Dataset) {
        let robot = crate::dynamics::robots::load_robot("cheetah3-leg", None).unwrap();
        let model = &robot.model;
        let (n, m) = (model.dof(), 600);
        let [q, qd, qdd] = random_states(model, m, 5).map(|v| Samples::from_flat(n, v).unwrap());
        let none = Friction::zeros(n);
        let tau = crate::dynamics::predict::predict_torques(model, &none, &q, &qd, &qdd).unwrap();
        let d = Dataset {
            joints: model.joint_names().iter().map(|j| j.to_string()).collect(),
            t: (0..m).map(|s| s as f64 * 1e-3).collect(),
            q,
            qd,
            qdd,
            tau,
            segments: vec![0],
            base: None,
            contacts: vec![],
        };
        (robot, d)
    }

    /// With the law and the weight given, the sequence is the plain
    /// identification (no choice made), and `beside` ran.
    #[test]
    fn a_given_law_and_weight_is_the_plain_identification() {
        let (robot, d) = leg();
        let plan = Plan {
            law: LawPlan::Own,
            weight: Some(1e-6),
            bounds: None,
        };
        let (got, side) = identify_planned(&Consistent, &robot, Training::Samples(&d), &plan, || 7);
        let got = got.unwrap();
        assert_eq!(side, Some(7));
        let want = Identification::for_robot(&robot, Level::Consistent, 1e-6)
            .and_then(|id| id.identify(&d, None))
            .unwrap();
        assert_eq!(got.result.theta.len(), want.theta.len());
        for (a, b) in got.result.theta.iter().zip(&want.theta) {
            assert!((a - b).abs() <= 1e-9 * (1.0 + b.abs()), "{a} vs {b}");
        }
        assert!(got.result.model_selection.is_none() && got.result.weight_choice.is_none());
    }

    /// A choice asked of a reduction without its samples fails at its own
    /// step, before the fit (`beside` not run).
    #[test]
    fn a_choice_without_samples_is_refused_before_the_fit() {
        let (robot, d) = leg();
        let red = Identification::for_robot(&robot, Level::Consistent, 1e-6)
            .and_then(|id| id.reduce(&d))
            .unwrap();
        for (law, weight, step) in [
            (LawPlan::Choose, Some(1e-6), Step::Law),
            (LawPlan::Own, None, Step::Weight),
        ] {
            let plan = Plan {
                law,
                weight,
                bounds: None,
            };
            let (got, side) =
                identify_planned(&Consistent, &robot, Training::Reduced(&red), &plan, || ());
            let e = got.unwrap_err();
            assert_eq!(e.step, step);
            assert!(
                matches!(e.source, IdentifyError::ChoiceNeedsSamples),
                "{e:?}"
            );
            assert!(side.is_none());
        }
    }
}
