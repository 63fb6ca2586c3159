//! The real-data confusion table of docs/diagnosis.md: known effects added
//! to the KUKA LWR4+'s measured torques of run 3 (`robots/kuka-lwr4`), one
//! case per effect and joint, each diagnosed against the model identified
//! on runs 1–2 at the options docs/real-robot.md recommends, with runs
//! 1–2's repeatability as the noise floor. The untouched run 3 is the
//! null row. Strict scoring: a case is found when the diagnosis accepts
//! the injected effect itself (or one the report names as the same
//! hypothesis; a tie does not count) on the injected joint — or, for a
//! term the nominal friction law already has (offset, Coulomb, viscous,
//! load friction), when the law's refit moves that coefficient by the
//! injected amount (within 20 %, beyond its interval) more than it does on
//! the untouched run. What else it accepts that the untouched run does not
//! show (significant there in no round) is listed.
//!
//! Run: `cargo run --release --example confusion_real` (`-- NAME`: only
//! the cases of effect NAME; `DROP=a,b`: without those candidates, to see
//! what absorbs what; `NOMINAL_OWN=1`: the nominal holds runs 1–2's own
//! effects, `NOMINAL_DATA=1`: runs 1–2 given as its data, see [`Nominal`];
//! `VERBOSE=1`: every accepted effect's variant, joints, fold gains and
//! sizes on stderr, `VERBOSE=NAME` also NAME's reports in every round,
//! `VERBOSE=law` the law's refit coefficients).

use momentlmi::data::{Dataset, Mapping, ReadOptions, read_logs, rms_per_joint};
use momentlmi::diagnose::floor::{NoiseFloor, repeat_floor};
use momentlmi::diagnose::{DiagnoseOptions, Diagnosis, diagnose, diagnose_with};
use momentlmi::dynamics::predict::predict_torques;
use momentlmi::dynamics::robots::load_robot;
use momentlmi::dynamics::{Friction, FrictionTerm, Model, RobotDescription, Samples, sign};
use momentlmi::effects::Library;
use momentlmi::effects::fitted::add_effects;
use momentlmi::identify::{Identification, Level, Regularizer};
use momentlmi::moments::InertialParams;
use nalgebra::Matrix3;
use std::error::Error;
use std::path::Path;

/// An effect added to measured data, at a realistic size.
#[derive(Clone, Copy, Debug)]
enum Injection {
    /// Torque-sensor gain error (relative).
    Gain(f64),
    /// Torque-sensor offset (N·m).
    Offset(f64),
    /// Extra Coulomb friction (N·m).
    Coulomb(f64),
    /// Extra viscous friction (N·m·s/rad).
    Viscous(f64),
    /// Torque measured this late (s).
    Delay(f64),
    /// Encoder zero offset (rad), through the nominal model's dynamics.
    Encoder(f64),
    /// A point mass (kg) at the tool point, through the nominal dynamics.
    Payload(f64),
    /// Ripple `A sin(p q + 1)`: (A N·m, p per joint turn).
    Ripple(f64, f64),
    /// Load-dependent friction μ |τ̂| sign q̇.
    Load(f64),
}

impl Injection {
    /// The built-in effect that stands for it.
    fn effect(self) -> &'static str {
        match self {
            Self::Gain(_) => "torque_gain",
            Self::Offset(_) => "offset",
            Self::Coulomb(_) => "coulomb",
            Self::Viscous(_) => "viscous",
            Self::Delay(_) => "time_delay",
            Self::Encoder(_) => "joint_offset",
            Self::Payload(_) => "payload",
            Self::Ripple(..) => "ripple",
            Self::Load(_) => "load_friction",
        }
    }

    /// The injected size in the unit the diagnosis reports it in (gain %,
    /// delay ms, offset and friction N·m or N·m·s/rad, encoder offset rad,
    /// ripple amplitude N·m, load μ, payload kg).
    fn value(self) -> f64 {
        match self {
            Self::Gain(g) => 100.0 * g,
            Self::Delay(d) => 1e3 * d,
            Self::Offset(x) | Self::Coulomb(x) | Self::Viscous(x) | Self::Encoder(x) => x,
            Self::Payload(m) | Self::Load(m) => m,
            Self::Ripple(a, _) => a,
        }
    }

    fn size(self) -> String {
        match self {
            Self::Gain(g) => format!("{:+.0} %", 100.0 * g),
            Self::Offset(c) | Self::Coulomb(c) => format!("{c} N·m"),
            Self::Viscous(b) => format!("{b} N·m·s/rad"),
            Self::Delay(d) => format!("{:.0} ms", 1e3 * d),
            Self::Encoder(d) => format!("{:.1}°", d.to_degrees()),
            Self::Payload(m) => format!("{m} kg"),
            Self::Ripple(a, p) => format!("{a} N·m, {p}/turn"),
            Self::Load(mu) => format!("μ = {mu}"),
        }
    }
}

/// The nominal model's torques at `d`'s states, with `q` shifted on joint
/// `j` by `dq` and the model's bodies `model`.
fn nominal(model: &Model, f: &Friction, d: &Dataset, (j, dq): (usize, f64)) -> Vec<Vec<f64>> {
    let mut q = d.q.clone();
    q.iter_mut().for_each(|r| r[j] += dq);
    let tau = predict_torques(model, f, &q, &d.qd, &d.qdd).expect("the nominal model predicts");
    tau.iter().map(<[f64]>::to_vec).collect()
}

/// `d` with `inj` added to joint `j` (the payload: at the tool).
fn inject(inj: Injection, j: usize, d: &Dataset, (model, f): (&Model, &Friction)) -> Dataset {
    let mut out = d.clone();
    let base = nominal(model, f, d, (j, 0.0));
    let add = |out: &mut Dataset, g: &dyn Fn(usize, usize) -> f64, all: bool| {
        for k in 0..d.len() {
            for i in 0..d.joints.len() {
                if all || i == j {
                    out.tau[k][i] += g(k, i);
                }
            }
        }
    };
    match inj {
        Injection::Gain(e) => add(&mut out, &|k, i| e * d.tau[k][i], false),
        Injection::Offset(c) => add(&mut out, &|_, _| c, false),
        Injection::Coulomb(c) => add(&mut out, &|k, i| c * sign(d.qd[k][i]), false),
        Injection::Viscous(b) => add(&mut out, &|k, i| b * d.qd[k][i], false),
        Injection::Delay(s) => {
            let dt = (d.t[d.len() - 1] - d.t[0]) / (d.len() - 1) as f64;
            let lag = (s / dt).round() as usize;
            add(
                &mut out,
                &|k, i| d.tau[k.saturating_sub(lag)][i] - d.tau[k][i],
                false,
            );
        }
        Injection::Encoder(delta) => {
            let moved = nominal(model, f, d, (j, delta));
            add(&mut out, &|k, i| moved[k][i] - base[k][i], true);
        }
        Injection::Payload(m) => {
            let tool = model.tool.expect("the KUKA has a tool point");
            let mut heavy = model.clone();
            let mut p = heavy.params();
            let b = 10 * tool.body;
            let point = InertialParams::from_mass_com_inertia(m, tool.point, Matrix3::zeros());
            (0..10).for_each(|c| p[b + c] += point.as_array()[c]);
            heavy
                .set_params(&p)
                .expect("a payload keeps the model valid");
            let loaded = nominal(&heavy, f, d, (j, 0.0));
            add(&mut out, &|k, i| loaded[k][i] - base[k][i], true);
        }
        Injection::Ripple(a, p) => add(&mut out, &|k, i| a * (p * d.q[k][i] + 1.0).sin(), false),
        Injection::Load(mu) => {
            let rigid = nominal(model, &Friction::zeros(d.joints.len()), d, (j, 0.0));
            add(
                &mut out,
                &|k, i| mu * rigid[k][i].abs() * sign(d.qd[k][i]),
                false,
            )
        }
    }
    out
}

/// One case of the table.
pub struct Row {
    /// The effect and its size.
    pub case: String,
    /// The built-in effect that stands for it.
    pub effect: &'static str,
    /// The injected joint (the payload: the joint it moves most).
    pub joint: String,
    /// RMS of what was injected there, and the noise floor there (N·m).
    pub size: (f64, f64),
    /// Accepted effects (with the same hypothesis and ties).
    pub accepted: String,
    /// Found: the injected effect accepted on its joint (not through a
    /// tie), or — a term of the nominal friction law — its refit
    /// coefficient there moved from the untouched run's by more than its
    /// interval, by the injected amount within 20 %.
    pub found: bool,
    /// How: `"accepted"` or `"law refit"`.
    pub how: &'static str,
    /// The fitted size (the unit of [`Injection::value`]) less the untouched
    /// run's fit of the same effect there, and the injected size.
    pub fitted: Option<(f64, f64)>,
    /// Accepted effects the null row does not accept and the injected one
    /// does not cover.
    pub beyond: String,
}

/// The effects added, each with the joints it is added on: additive ones
/// on a shoulder, an elbow and a wrist joint; those that scale with the
/// joint's torque (a gain, a delay, an encoder offset through gravity, load
/// friction) on the two joints that carry the arm (the others' torques,
/// 0.6–2 N·m RMS, make them smaller than the repeatability there at any
/// realistic size); the payload at the tool.
fn cases(tool_body: usize) -> Vec<(Injection, usize)> {
    let additive = [1usize, 3, 5];
    let loaded = [1usize, 3];
    let cases: [(Injection, &[usize]); 8] = [
        (Injection::Gain(0.05), &loaded),
        (Injection::Offset(0.3), &additive),
        (Injection::Coulomb(0.3), &additive),
        (Injection::Viscous(0.3), &additive),
        (Injection::Delay(0.02), &loaded),
        (Injection::Encoder(2f64.to_radians()), &loaded),
        (Injection::Ripple(0.3, 6.0), &additive),
        (Injection::Load(0.05), &loaded),
    ];
    let mut list: Vec<(Injection, usize)> = cases
        .iter()
        .flat_map(|&(c, joints)| joints.iter().map(move |&j| (c, j)))
        .collect();
    list.push((Injection::Payload(1.0), tool_body));
    list
}

/// The KUKA at the recommended options: its description, runs 1–2 (train)
/// and run 3.
fn kuka() -> Result<(RobotDescription, Dataset, Dataset), Box<dyn Error>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/kuka-lwr4");
    let urdf = dir.join("kuka_lwr4.urdf");
    let mut robot = load_robot(
        urdf.to_str().ok_or("a UTF-8 path")?,
        Some(&dir.join("kuka_lwr4.toml")),
    )?;
    robot.model = robot.model.clone().with_friction_terms(&[
        FrictionTerm::Viscous,
        FrictionTerm::Coulomb,
        FrictionTerm::Offset,
        FrictionTerm::Load,
        FrictionTerm::Stribeck,
    ]);
    let names = robot.model.joint_names();
    let mapping = robot
        .data_mapping
        .as_ref()
        .map(|p| Mapping::read(p))
        .transpose()?;
    let opts = ReadOptions {
        mapping,
        mapping_is_default: true,
        ..ReadOptions::default()
    };
    let run = |k: usize| dir.join(format!("data/measurements_{k}.npz"));
    let train = read_logs(&[&run(1), &run(2)], &names, &opts)?.data;
    let val = read_logs(&[&run(3)], &names, &opts)?.data;
    Ok((robot, train, val))
}

/// The KUKA, its nominal model and friction (identified on runs 1–2 at the
/// recommended options), the repeatability floor of runs 1–2, and run 3.
#[allow(clippy::type_complexity)]
pub fn setup() -> Result<
    (
        RobotDescription,
        Model,
        Friction,
        NoiseFloor,
        Dataset,
        Dataset,
    ),
    Box<dyn Error>,
> {
    let (robot, train, val) = kuka()?;
    let (model, friction) = identified(&robot, &train)?;
    let segs: Vec<Dataset> = train
        .segment_ranges()
        .into_iter()
        .map(|r| train.slice(r))
        .collect();
    let floor = repeat_floor(&segs[0], &segs[1], ["run 1", "run 2"])?;
    Ok((robot, model, friction, floor, val, train))
}

/// What the diagnosis knows of the nominal model besides its parameters.
#[derive(Clone, Copy, Debug, Default)]
pub struct Nominal {
    /// The effects runs 1–2 show against their own model are part of it:
    /// runs 1–2 are diagnosed first (their bodies held), the effects that
    /// diagnosis accepts (a body change aside) are held and runs 1–2 are
    /// identified again with them taken off (as `identify --with-effects`
    /// does): that model with those effects is the nominal
    /// (`NOMINAL_OWN=1`).
    pub own_effects: bool,
    /// The data it was identified on (runs 1–2) are given
    /// (`DiagnoseOptions::with_nominal_data`, `--nominal-data`): its bodies
    /// are refit with the law on those data and the fitting part
    /// (`NOMINAL_DATA=1`).
    pub own_data: bool,
}

/// The KUKA's model identified on `data` at the recommended options
/// (ellipsoid level, entropic prior weight 10⁻²).
fn identified(
    robot: &RobotDescription,
    data: &Dataset,
) -> Result<(Model, Friction), Box<dyn Error>> {
    let id = Identification::for_robot(robot, Level::Ellipsoid, 1e-2)?
        .regularizer(Regularizer::Entropic);
    Ok(id.identify(data, None)?.applied_to(&robot.model)?)
}

/// The null row's diagnosis and the cases whose effect name contains
/// `only`, diagnosed without the candidates `drop`, against the nominal
/// model with what `nominal` says it knows.
pub fn run(
    only: &str,
    drop: &[&str],
    nominal: Nominal,
) -> Result<(Diagnosis, Vec<Row>), Box<dyn Error>> {
    let (robot, model, friction, floor, val, train) = setup()?;
    let mut lib = Library::empty();
    for e in Library::builtin()
        .effects()
        .iter()
        .filter(|e| !drop.contains(&e.name()))
    {
        lib.push(e.clone())?;
    }
    let mut dopts = DiagnoseOptions::default()
        .with_noise_floor(floor)
        .with_library(lib);
    let (model, friction, effects) = match nominal.own_effects {
        true => {
            // runs 1–2 against the model identified on them (their bodies
            // held: given as its own data they would be fitted in every fold)
            let own = diagnose(&model, &friction, &train, &dopts)?;
            if std::env::var_os("VERBOSE").is_some() {
                show("runs 1–2 against their own model", &own);
            }
            // the effects it accepted held, runs 1–2 identified again (as
            // `identify --with-effects` does): their torques taken off
            let mut m = model.clone();
            let f = own.model.apply(&mut m, "runs 1–2's diagnosis")?;
            let effects = own.model.effects.clone();
            let mut fx = Samples::zeros(train.len(), train.joints.len());
            add_effects(&m, &f, &effects, &train, &Library::builtin(), &mut fx)?;
            let mut held = train.clone();
            (held.tau.as_flat_mut().iter_mut().zip(fx.as_flat())).for_each(|(t, x)| *t -= x);
            let (m, f) = identified(&robot, &held)?;
            (m, f, effects)
        }
        false => (model, friction, vec![]),
    };
    if nominal.own_data {
        dopts = dopts.with_nominal_data(train.clone());
    }
    let diagnose =
        |d: &Dataset, o: &DiagnoseOptions| diagnose_with((&model, &friction, &effects), d, o);
    let null = diagnose(&val, &dopts)?;
    if std::env::var_os("VERBOSE").is_some() {
        show("the untouched run", &null);
    }
    let n = val.joints.len();
    let mut rows = vec![];
    let tool = robot.model.tool.ok_or("the KUKA has no tool point")?;
    for (inj, j) in cases(tool.body)
        .into_iter()
        .filter(|(c, _)| c.effect().contains(only))
    {
        let d = inject(inj, j, &val, (&model, &friction));
        let diff: Vec<f64> = (d.tau.iter().flatten().zip(val.tau.iter().flatten()))
            .map(|(a, b)| a - b)
            .collect();
        let size = rms_per_joint(&diff, n);
        let j = match inj {
            Injection::Payload(_) => (0..n)
                .max_by(|&a, &b| size[a].total_cmp(&size[b]))
                .unwrap_or(0),
            _ => j,
        };
        let dg = diagnose(&d, &dopts)?;
        if std::env::var_os("VERBOSE").is_some() {
            show(
                &format!("{} {} on {}", inj.effect(), inj.size(), val.joints[j]),
                &dg,
            );
        }
        let joint = val.joints[j].clone();
        let (found, how, fitted) = match law_term(inj.effect()) {
            Some(term) => {
                let (case, half) = refit_of(&dg, term, &joint);
                let change = case - refit_of(&null, term, &joint).0;
                let right = (change - inj.value()).abs() <= 0.2 * inj.value().abs();
                (
                    change.abs() > half && right,
                    "law refit",
                    Some((change, inj.value())),
                )
            }
            None => {
                let e = dg
                    .ranked_effects
                    .iter()
                    .find(|e| e.accepted && names(e, inj.effect()));
                let on = e.is_some_and(|e| {
                    matches!(inj, Injection::Payload(_)) || e.joints.contains(&joint)
                });
                // the untouched run's own fit of the effect there (not accepted),
                // at the same nonlinear parameter (period, delay), taken off
                let variant = e.map(|e| e.detail.clone()).unwrap_or_default();
                let own = (null.ranked_effects.iter())
                    .find(|n| names(n, inj.effect()) && n.round == 1 && n.detail == variant);
                let own = own.and_then(|e| fitted_size(e, inj, &joint)).unwrap_or(0.0);
                let fitted = e
                    .and_then(|e| fitted_size(e, inj, &joint))
                    .map(|v| (v - own, inj.value()));
                (on, "accepted", fitted)
            }
        };
        rows.push(Row {
            case: format!("{} {}", inj.effect(), inj.size()),
            effect: inj.effect(),
            size: (size[j], dg.noise_floor[j]),
            accepted: accepted(&dg),
            found,
            how,
            fitted,
            beyond: beyond(&dg, &null, inj.effect()),
            joint,
        });
    }
    Ok((null, rows))
}

#[allow(dead_code)] // tests/examples.rs calls `run`
fn main() -> Result<(), Box<dyn Error>> {
    let only = std::env::args().nth(1).unwrap_or_default();
    let drop = std::env::var("DROP").unwrap_or_default();
    let drop: Vec<&str> = drop.split(',').filter(|s| !s.is_empty()).collect();
    let nominal = Nominal {
        own_effects: std::env::var_os("NOMINAL_OWN").is_some(),
        own_data: std::env::var_os("NOMINAL_DATA").is_some(),
    };
    let (null, rows) = run(&only, &drop, nominal)?;
    println!(
        "| injected | joint | injected RMS there (N·m) | floor there | accepted (tied with) | found | fitted / injected | accepted beyond the null row |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    println!(
        "| none (null row) | — | — | — | {} | — | — | — |",
        accepted(&null)
    );
    for r in &rows {
        let fitted = r.fitted.map_or("—".into(), |(f, i)| {
            format!("{f:.3} / {i:.3} ({:+.0} %)", 100.0 * (f / i - 1.0))
        });
        println!(
            "| {} | {} | {:.3} | {:.3} | {} | {} | {fitted} | {} |",
            r.case,
            r.joint,
            r.size.0,
            r.size.1,
            r.accepted,
            if r.found {
                format!("yes ({})", r.how)
            } else {
                "**no**".into()
            },
            r.beyond
        );
    }
    let found = rows.iter().filter(|r| r.found).count();
    let accepted = rows
        .iter()
        .filter(|r| r.found && r.how == "accepted")
        .count();
    println!(
        "\nfound {found} of {} ({accepted} accepted as effects)",
        rows.len()
    );
    println!("null row re-estimates: {}", reestimated(&null));
    Ok(())
}

/// `VERBOSE`: each accepted (or removed) effect's variant, joints, fold
/// gains, sizes and rule; `VERBOSE=NAME` also NAME's report in every round,
/// `VERBOSE=law` the law's refit coefficients.
fn show(case: &str, d: &Diagnosis) {
    eprintln!("{case}:");
    let also = std::env::var("VERBOSE").unwrap_or_default();
    for r in d.friction_refit.iter().filter(|_| also == "law") {
        eprintln!(
            "  law {} {:.4} [{:.4}, {:.4}]",
            r.name, r.value, r.low, r.high
        );
    }
    for e in
        (d.ranked_effects.iter()).filter(|e| e.accepted || e.effect == also || e.removed.is_some())
    {
        let sizes: Vec<String> = (e.sizes.iter())
            .map(|s| {
                format!(
                    "{} {:.4} [{:.4}, {:.4}] {}",
                    s.name, s.value, s.low, s.high, s.unit
                )
            })
            .collect();
        let rule = e.rule.chars().take(200).collect::<String>();
        let gains: Vec<String> = e.fold_gains.iter().map(|g| format!("{g:.4}")).collect();
        eprintln!(
            "  r{} {} ({}) on {:?} folds [{}]: {} [{rule}]",
            e.round,
            e.effect,
            e.detail,
            e.joints,
            gains.join(" "),
            sizes.join("; ")
        );
    }
}

/// Accepted effects, with what is the same hypothesis and ties.
fn accepted(d: &Diagnosis) -> String {
    let a: Vec<String> = d
        .ranked_effects
        .iter()
        .filter(|e| e.accepted)
        .map(|e| format!("{}{}", e.label(), e.ties()))
        .collect();
    if a.is_empty() {
        "—".into()
    } else {
        a.join("; ")
    }
}

/// The friction-law term an effect is (`None`: not a term of the
/// recommended law, which has viscous, Coulomb, offset, load and Stribeck
/// friction).
fn law_term(effect: &str) -> Option<&'static str> {
    match effect {
        "coulomb" => Some("coulomb"),
        "viscous" => Some("viscous"),
        "offset" => Some("offset"),
        "load_friction" => Some("load"),
        _ => None,
    }
}

/// The refit coefficient of `term` on `joint` and its interval's
/// half-width.
fn refit_of(d: &Diagnosis, term: &str, joint: &str) -> (f64, f64) {
    let name = format!("{term} friction, {joint}");
    (d.friction_refit.iter())
        .find(|r| r.name == name)
        .map_or((f64::NAN, f64::INFINITY), |r| {
            (r.value, 0.5 * (r.high - r.low))
        })
}

/// Whether report `e` is `effect` or the same hypothesis.
fn names(e: &momentlmi::diagnose::EffectReport, effect: &str) -> bool {
    e.effect == effect || e.same_as.iter().any(|a| a == effect)
}

/// The fitted size of an accepted report that stands for `inj` on `joint`.
fn fitted_size(e: &momentlmi::diagnose::EffectReport, inj: Injection, joint: &str) -> Option<f64> {
    let want = match inj {
        Injection::Payload(_) => "payload mass".to_string(),
        _ => format!(", {joint}"),
    };
    e.sizes
        .iter()
        .find(|s| s.name.contains(&want) || s.name.ends_with(&want))
        .map(|s| s.value)
}

/// The untouched run's moved law coefficients, in words.
fn reestimated(d: &Diagnosis) -> String {
    let r: Vec<String> = d.reestimated.iter().map(|r| r.refit.words()).collect();
    if r.is_empty() {
        "—".into()
    } else {
        r.join("; ")
    }
}

/// Whether the untouched run already shows `effect`: a report of it (or of
/// one the same hypothesis) the rule accepts in some round, accepted or
/// not.
fn shown(null: &Diagnosis, effect: &str) -> bool {
    null.ranked_effects
        .iter()
        .any(|n| names(n, effect) && !n.rule.starts_with("not"))
}

/// Accepted effects that the untouched run does not show ([`shown`]) and
/// that are not (tied with) the injected one.
fn beyond(d: &Diagnosis, null: &Diagnosis, effect: &str) -> String {
    let extra: Vec<String> = d
        .ranked_effects
        .iter()
        .filter(|e| e.accepted && !e.covers(effect) && !shown(null, &e.effect))
        .map(|e| e.label())
        .collect();
    if extra.is_empty() {
        "—".into()
    } else {
        extra.join(", ")
    }
}
