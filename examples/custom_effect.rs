//! Your own effect, outside the crate: a torque `k sin(2 q)` on one joint,
//! standing in for a spring or a cable the CAD lacks. It is one type
//! implementing `momentlmi::effects::Effect` — its parameter, how the
//! simulator's true robot has it, and its regressor column for the
//! diagnosis — added to the built-in library. The program simulates a
//! robot with it, identifies a nominal model on other data (without it, as
//! the CAD would be), diagnoses, and prints the verdict; then the same
//! without the effect, where the diagnosis must not accept it.
//!
//! Run: `cargo run --release --example custom_effect`

use momentlmi::diagnose::{DiagnoseOptions, Diagnosis, diagnose};
use momentlmi::dynamics::RobotDescription;
use momentlmi::dynamics::robots::load_robot;
use momentlmi::effects::{
    Context, Effect, EffectError, Hypothesis, Library, Memory, ParamSpec, Range, Shape, Values,
};
use momentlmi::identify::{IdentifyOptions, Level, identify};
use momentlmi::sim::{Effects, SimConfig, Truth};

/// A torque `k sin(2 q)` on the joint named `joint`.
pub struct CableSpring {
    /// The joint it acts on.
    pub joint: &'static str,
}

/// Its one parameter: the amplitude k.
const K: ParamSpec = ParamSpec::new(
    "cable_k",
    "N·m",
    0.6,
    Range::Any,
    "Amplitude k of the cable's torque k sin(2q).",
);

impl CableSpring {
    /// The joint's index in `names`, or the effect's own error.
    fn index(&self, names: &[&str]) -> Result<usize, EffectError> {
        names
            .iter()
            .position(|n| *n == self.joint)
            .ok_or_else(|| EffectError::Own {
                effect: "cable_spring",
                source: format!("the robot has no joint '{}'", self.joint).into(),
            })
    }
}

impl Effect for CableSpring {
    fn name(&self) -> &'static str {
        "cable_spring"
    }

    fn summary(&self) -> &'static str {
        "A cable or spring the CAD lacks: k sin(2q) on one joint"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![K]
    }

    /// The true robot has the torque on its joint.
    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        let j = self.index(&truth.robot().model.joint_names())?;
        let k = p.get(K.name)?;
        truth.add_torque(move |s| {
            if s.joint == j {
                k * (2.0 * s.q).sin()
            } else {
                0.0
            }
        });
        Ok(())
    }

    fn memory(&self, shape: &Shape) -> Memory {
        Memory::columns(shape, 1)
    }

    /// One column: sin(2 q) in the joint's rows; its coefficient is k.
    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let j = self.index(&cx.model.joint_names())?;
        let n = cx.joints();
        let mut col = vec![0.0; cx.samples() * n];
        for (k, q) in cx.data.q.iter().enumerate() {
            col[k * n + j] = (2.0 * q[j]).sin();
        }
        Ok(Hypothesis::linear(vec![col]))
    }

    fn detail(&self, _: &momentlmi::effects::Columns, beta: &[f64]) -> String {
        format!("k = {:.3} N·m on joint '{}'", beta[0], self.joint)
    }
}

/// The diagnosis of 15 s of `robot` with the cable on `joint` (or without,
/// `present = false`), against a nominal model identified on 20 s of other
/// data without it.
pub fn run(
    robot: &RobotDescription,
    joint: &'static str,
    base: &str,
    present: bool,
) -> Result<Diagnosis, Box<dyn std::error::Error>> {
    let library = Library::builtin().with(CableSpring { joint })?;
    let sim = |effects: &str, seconds, seed| {
        let fx = Effects::parse(effects, &[])?;
        let cfg = SimConfig::for_robot(robot, seconds, fx, seed);
        Ok::<_, Box<dyn std::error::Error>>(library.simulate(robot, &cfg, |_, _| {})?)
    };
    let train = sim(base, 20.0, 101)?;
    let opts = IdentifyOptions::for_robot(robot, Level::Ellipsoid, 1e-6)?;
    let (model, friction) =
        identify(&robot.model, &train, None, &opts)?.applied_to(&robot.model)?;
    let effects = if present {
        format!("{base},cable_spring")
    } else {
        base.to_string()
    };
    let data = sim(&effects, 15.0, 7)?;
    let dopts = DiagnoseOptions::default().with_library(library);
    Ok(diagnose(&model, &friction, &data, &dopts)?)
}

/// One line: what was accepted, and the cable's fit if it was.
pub fn verdict(d: &Diagnosis) -> String {
    let cable = d
        .ranked_effects
        .iter()
        .find(|e| e.effect == "cable_spring" && e.accepted);
    match cable {
        Some(e) => format!(
            "cable_spring accepted in round {}: {}; accepted: {}",
            e.round,
            e.detail,
            d.accepted.join(", ")
        ),
        None => format!(
            "cable_spring not accepted; accepted: {}",
            if d.accepted.is_empty() {
                "none".to_string()
            } else {
                d.accepted.join(", ")
            }
        ),
    }
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let leg = load_robot("cheetah3-leg", None)?;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/panda");
    let urdf = dir.join("panda.urdf");
    let arm = load_robot(
        urdf.to_str().ok_or("a UTF-8 path")?,
        Some(&dir.join("panda.toml")),
    )?;
    let cases = [
        (&leg, "hip", "rotor_inertia,coulomb,viscous"),
        (&arm, "panda_joint4", "coulomb,viscous"),
    ];
    for (robot, joint, base) in cases {
        for present in [true, false] {
            let d = run(robot, joint, base, present)?;
            println!(
                "{} with{} a cable on '{joint}' (k = {} N·m): {}",
                robot.model.name,
                if present { "" } else { "out" },
                K.nominal,
                verdict(&d)
            );
        }
    }
    Ok(())
}
