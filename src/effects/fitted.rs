//! A model file's fitted effects ([`FittedEffect`]): recorded from an
//! accepted hypothesis, and built again on other data to predict with them
//! ([`Effect::replay`]) — the torque of the file's bodies and friction plus
//! each effect's columns times its coefficients. A column is named by its
//! joint and its place among that joint's columns (`hip#0`, `hip#1`), or
//! `all#k` for the k-th column spanning several joints, so that a ripple
//! recorded on two joints finds its columns on data where the hypothesis
//! proposes it on three.

use super::context::Context;
use super::effect::Effect;
use super::error::EffectError;
use super::hypothesis::Columns;
use super::library::Library;
use crate::data::Dataset;
use crate::dynamics::params_file::FittedEffect;
use crate::dynamics::predict::predict_torques;
use crate::dynamics::{Friction, Model, Samples};

/// The joint every nonzero value of a sample-major column lies in (`n`
/// joints), if one.
pub fn joint_of(col: &[f64], n: usize) -> Option<usize> {
    let mut rows = col.iter().enumerate().filter(|(_, x)| **x != 0.0);
    let j = rows.next()?.0 % n;
    rows.all(|(i, _)| i % n == j).then_some(j)
}

/// The names of columns lying in the joints `col_joints` (`None`: several).
pub fn column_names(col_joints: &[Option<usize>], joints: &[String]) -> Vec<String> {
    let mut seen = vec![0usize; joints.len()];
    let mut spanning = 0;
    (col_joints.iter())
        .map(|j| match j {
            Some(j) => {
                seen[*j] += 1;
                format!("{}#{}", joints[*j], seen[*j] - 1)
            }
            None => {
                spanning += 1;
                format!("all#{}", spanning - 1)
            }
        })
        .collect()
}

/// The record of `effect`'s variant `columns` (its columns in the joints
/// `col_joints`) with coefficients `beta`; columns with a zero coefficient
/// (a joint the effect was not kept on) are left out.
pub fn record(
    effect: &dyn Effect,
    columns: &Columns,
    col_joints: &[Option<usize>],
    beta: &[f64],
    joints: &[String],
) -> FittedEffect {
    let names = column_names(col_joints, joints);
    let (columns_kept, coefficients) = (names.into_iter().zip(beta))
        .filter(|(_, b)| **b != 0.0)
        .map(|(n, b)| (n, *b))
        .unzip();
    FittedEffect {
        effect: effect.name().to_string(),
        key: columns.key.iter().cloned().collect(),
        columns: columns_kept,
        coefficients,
    }
}

/// The torques of `model` + `friction` at `data`'s states with the fitted
/// `effects` (of `library`) added ([`add_effects`]).
pub fn predict_with(
    model: &Model,
    friction: &Friction,
    effects: &[FittedEffect],
    data: &Dataset,
    library: &Library,
) -> Result<Samples, EffectError> {
    let mut tau = predict_torques(model, friction, &data.q, &data.qd, &data.qdd)?;
    add_effects(model, friction, effects, data, library, &mut tau)?;
    Ok(tau)
}

/// Adds to `tau` (a row per sample of `data`) the torques of the fitted
/// `effects` (of `library`) on `model` + `friction`: each effect's columns
/// built again on `data` ([`Effect::replay`]), matched to the record by
/// name. An unknown effect, a column the data do not give, or a record
/// whose lengths differ is an error naming the effect.
pub fn add_effects(
    model: &Model,
    friction: &Friction,
    effects: &[FittedEffect],
    data: &Dataset,
    library: &Library,
    tau: &mut Samples,
) -> Result<(), EffectError> {
    if effects.is_empty() {
        return Ok(());
    }
    let zeros = vec![0.0; data.len() * model.dof()];
    let cx = Context::new(model, friction, data, &zeros, data.len());
    let flat = tau.as_flat_mut();
    for fe in effects {
        for (col, b) in replayed(fe, &cx, library)?
            .into_iter()
            .zip(&fe.coefficients)
        {
            flat.iter_mut().zip(&col).for_each(|(t, x)| *t += b * x);
        }
    }
    Ok(())
}

/// The columns of the record `fe` on the data of `cx`, in the record's
/// order.
pub fn replayed(
    fe: &FittedEffect,
    cx: &Context,
    library: &Library,
) -> Result<Vec<Vec<f64>>, EffectError> {
    let bad = |why: String| EffectError::NotReplayable {
        effect: fe.effect.clone(),
        key: why,
    };
    if fe.columns.len() != fe.coefficients.len() || !fe.coefficients.iter().all(|b| b.is_finite()) {
        return Err(bad(format!(
            "{} columns and {} coefficients, all finite expected",
            fe.columns.len(),
            fe.coefficients.len()
        )));
    }
    let effect = library.get(&fe.effect)?;
    let key: Vec<(String, f64)> = fe.key.iter().map(|(k, v)| (k.clone(), *v)).collect();
    let mut v = effect.replay(cx, &key)?;
    let col_joints: Vec<Option<usize>> = match v.joints.len() == v.cols.len() {
        true => v.joints.clone(),
        false => v.cols.iter().map(|c| joint_of(c, cx.joints())).collect(),
    };
    let names = column_names(&col_joints, &cx.data.joints);
    (fe.columns.iter())
        .map(|c| match names.iter().position(|x| x == c) {
            Some(a) => Ok(std::mem::take(&mut v.cols[a])),
            None => Err(bad(format!(
                "column '{c}' (the data give {})",
                names.join(", ")
            ))),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::column_names;

    #[test]
    fn columns_are_named_by_joint_and_place() {
        let joints = vec!["a".to_string(), "b".to_string()];
        let names = column_names(&[Some(1), None, Some(1), Some(0), None], &joints);
        assert_eq!(names, ["b#0", "all#0", "b#1", "a#0", "all#1"]);
    }
}
