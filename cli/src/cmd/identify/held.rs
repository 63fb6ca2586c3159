//! `--with-effects FILE`: a diagnosis' fitted effects held at their values.

use momentlmi::dynamics::{ParamChoice, RobotDescription};
use std::path::Path;

/// `--with-effects FILE`: the model file's bodies and friction (the model
/// its effects were fitted with) and its fitted effects.
pub(super) struct Held {
    model: momentlmi::dynamics::Model,
    friction: momentlmi::dynamics::Friction,
    pub(super) effects: Vec<momentlmi::dynamics::params_file::FittedEffect>,
}

impl Held {
    pub(super) fn read(robot: &RobotDescription, path: &Path) -> Result<Self, String> {
        if !path.is_file() {
            return Err(format!(
                "--with-effects {}: not a file (a diagnosis' model file, diagnose --model-out, is needed)",
                path.display()
            ));
        }
        let value = path.to_str().unwrap_or_default();
        let (model, friction, effects) = super::super::parameters_with_effects_for(
            robot,
            "--with-effects",
            Some(value),
            ParamChoice::Own,
        )?;
        if effects.is_empty() {
            return Err(format!(
                "--with-effects {}: it holds no fitted effects (bodies and friction only: give it as --prior)",
                path.display()
            ));
        }
        Ok(Self {
            model,
            friction,
            effects,
        })
    }

    /// The held effects' torques taken off `data`'s (the files of `flag`).
    pub(super) fn take_off(
        &self,
        data: &mut momentlmi::data::Dataset,
        flag: &str,
    ) -> Result<(), String> {
        let library = momentlmi::effects::Library::builtin();
        let mut fx = momentlmi::dynamics::Samples::zeros(data.len(), data.joints.len());
        momentlmi::effects::fitted::add_effects(
            &self.model,
            &self.friction,
            &self.effects,
            data,
            &library,
            &mut fx,
        )
        .map_err(|e| format!("--with-effects on the {flag} files: {e}"))?;
        let flat = data.tau.as_flat_mut();
        flat.iter_mut().zip(fx.as_flat()).for_each(|(t, x)| *t -= x);
        Ok(())
    }
}
