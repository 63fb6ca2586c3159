//! `offset`: a constant torque `c` on every joint (a sensor bias, an
//! unmodelled spring's preload).

use crate::dynamics::FrictionTerm;
use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, ParamSpec, Range, Size, SizeContext, Values,
};
use crate::sim::Truth;

/// A constant torque offset.
pub struct Offset;

const OFFSET: ParamSpec = ParamSpec::new(
    "offset",
    "N·m",
    0.5,
    Range::Any,
    "Torque offset, every joint.",
);

impl Effect for Offset {
    fn name(&self) -> &'static str {
        "offset"
    }

    fn motion(&self) -> &'static str {
        "motion in both directions at the same speeds"
    }

    fn law_term(&self) -> Option<FrictionTerm> {
        Some(FrictionTerm::Offset)
    }

    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        super::friction::term_sizes(beta, cx, FrictionTerm::Offset, "torque offset")
    }

    fn summary(&self) -> &'static str {
        "A constant torque offset (sensor bias, an unmodelled spring preload)"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![OFFSET]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        let c = p.get(OFFSET.name)?;
        truth.add_torque(move |_| c);
        Ok(())
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        Ok(Hypothesis::per_joint(cx.per_joint(|_, _| 1.0)))
    }
}
