//! The text report of `identify`.

use momentlmi::dynamics::FrictionTerm;
use momentlmi::identify::IdentifyResult;

/// How a choice's cross-validation split the training data, in words.
pub(super) fn folds_text(folds: momentlmi::identify::choose_weight::Folds, k: usize) -> String {
    match folds {
        momentlmi::identify::choose_weight::Folds::Segments => {
            format!(
                "{k} motions held out in turn: files or pieces between gaps, each with its repeats"
            )
        }
        momentlmi::identify::choose_weight::Folds::Time => {
            format!("{k} blocks in time held out in turn, the same block of every file")
        }
    }
}

/// The curve `--weight auto` chose from.
pub(super) fn print_weight_choice(c: &momentlmi::identify::WeightChoice) {
    let folds = folds_text(c.folds, c.k);
    println!(
        "weight chosen by cross-validation ({folds}; the strongest prior within the noise of the lowest): mean held-out RMS per weight"
    );
    for (w, m) in c.weights.iter().zip(&c.mean_rms) {
        let mark = match (*w == c.chosen, *w == c.lowest) {
            (true, _) => "  ← chosen",
            (false, true) => "  (lowest)",
            _ => "",
        };
        println!("  {w:>7.0e}  {m:.4} N·m{mark}");
    }
    if !c.fold_notes.is_empty() {
        println!(
            "  ({} notes from the folds' fits, in the JSON's weight_choice.fold_notes; first: {})",
            c.fold_notes.len(),
            c.fold_notes[0]
        );
    }
}

pub(super) fn print_friction_choice(c: &momentlmi::identify::friction_choice::FrictionChoice) {
    let folds = folds_text(c.folds, c.k);
    let weighed = c.weight_chosen();
    println!(
        "friction law{} chosen by cross-validation ({folds}; links and law refit by least squares{}): mean held-out RMS",
        if weighed { " and prior weight" } else { "" },
        if weighed {
            "; each law at its best weight"
        } else {
            ""
        },
    );
    // one row per law: the chosen entry in its law's row, else its best weight
    let same = |i: usize, j: usize| {
        c.laws[i].terms == c.laws[j].terms
            && c.laws[i].stribeck_velocity == c.laws[j].stribeck_velocity
    };
    let mut rows: Vec<usize> = vec![];
    for i in 0..c.laws.len() {
        match rows.iter_mut().find(|r| same(**r, i)) {
            Some(r) if *r == c.chosen => {}
            Some(r) if i == c.chosen || c.laws[i].mean_rms < c.laws[*r].mean_rms => *r = i,
            Some(_) => {}
            None => rows.push(i),
        }
    }
    rows.sort_by(|&a, &b| c.laws[a].mean_rms.total_cmp(&c.laws[b].mean_rms));
    let name = |l: &momentlmi::identify::friction_choice::LawScore| {
        let vs = l.stribeck_velocity.map(|v| format!(" (v_s {v})"));
        format!("{}{}", l.terms.join(", "), vs.unwrap_or_default())
    };
    let width = rows.iter().map(|&i| name(&c.laws[i]).chars().count()).max();
    for i in rows {
        let l = &c.laws[i];
        let w = if weighed {
            format!("  weight {:<8.2e}", l.weight)
        } else {
            String::new()
        };
        let mark = match (i == c.chosen, i == c.best) {
            (true, _) => "  ← chosen",
            (false, true) => "  (lowest)",
            _ => "",
        };
        println!(
            "  {:<width$}{w} {:.4} N·m{mark}",
            name(l),
            l.mean_rms,
            width = width.unwrap_or(0) + 1
        );
    }
    println!("  chosen: {}", c.rule);
}

/// A short human report.
pub fn print_report(r: &IdentifyResult) {
    println!(
        "{} — constraints: {}, {} prior with weight {:e}{}, {} training samples, rank {}/{}",
        r.robot,
        r.constraints.as_str(),
        r.regularizer.as_str(),
        r.weight,
        if r.prior_mass_weight > 0.0 {
            format!(" (masses {:e})", r.prior_mass_weight)
        } else {
            String::new()
        },
        r.training_samples,
        r.identifiability.rank,
        r.identifiability.columns
    );
    if let Some(c) = &r.model_selection {
        print_friction_choice(c);
    }
    if let Some(c) = &r.weight_choice {
        print_weight_choice(c);
    }
    print_bodies(r);
    print_friction(r);
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.4}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    if let Some(s) = &r.joint_noise {
        println!("joint noise σ̂  {} N·m (weights ∝ 1/σ̂²)", list(s));
    }
    println!("training RMS   {} N·m", list(&r.training_rms));
    if let Some(v) = &r.validation_rms {
        println!(
            "validation RMS {} N·m ({} samples)",
            list(v),
            r.validation_samples
        );
    }
    println!(
        "status {}, {} iterations, constraints satisfied: {}",
        r.status, r.iterations, r.constraints_satisfied
    );
    print_base_parameters(&r.identifiability);
    if let Some(b) = &r.bounds {
        print_bounds(b);
    }
    print_timings(&r.timings);
}

/// One line of the stages' times (ms).
pub(super) fn print_timings(t: &momentlmi::identify::Timings) {
    let ms = |s: f64| format!("{:.1}", 1e3 * s);
    let read = if t.streamed {
        format!("read {} (streamed, beside the reduction)", ms(t.read_s))
    } else {
        format!("read {}, filter {}", ms(t.read_s), ms(t.filter_s))
    };
    println!(
        "time [ms]      {read}, regressor + reduction {}, solve {}, check {}, validate {}, total {}",
        ms(t.reduce_s),
        ms(t.solve_s),
        ms(t.check_s),
        ms(t.validate_s),
        ms(t.total_s)
    );
}

/// The base parameters: value ± standard deviation, best determined first.
pub(super) fn print_base_parameters(id: &momentlmi::identify::Identifiability) {
    println!(
        "base parameters ({} of {} columns; condition number {:.3e}; σ from the residual):",
        id.rank, id.columns, id.condition_number
    );
    for b in &id.base_parameters {
        let sd = b.std_dev.map_or_else(|| "-".into(), |s| format!("{s:.3e}"));
        // relative only where the value stands out of its σ
        let rel = (b.std_dev)
            .filter(|s| *s < b.value.abs())
            .map_or_else(String::new, |s| {
                format!(" ({:.1} %)", 100.0 * s / b.value.abs())
            });
        println!("  {:>12.5e} ± {sd}{rel:<10}  {}", b.value, b.combination);
    }
}

/// Whether a missing end is unbounded (else its solve failed: the note).
pub(super) fn solved_end(p: &momentlmi::identify::ParamRange) -> bool {
    p.note.as_deref().is_none_or(|n| n.starts_with("unbounded"))
}

/// Each parameter's range over the models that fit almost as well.
pub(super) fn print_bounds(b: &momentlmi::identify::ParameterBounds) {
    println!(
        "parameter ranges over the constrained models with residual ≤ (1 + {:.3e}) × {:.4e}:",
        b.delta, b.residual
    );
    println!(
        "  {:<24} {:>12} {:>12} {:>12} {:>12}  pinned by",
        "parameter", "estimate", "prior", "min", "max"
    );
    let v = |x: Option<f64>, none: &str| x.map_or_else(|| none.to_string(), |x| format!("{x:.5e}"));
    for p in &b.ranges {
        println!(
            "  {:<24} {:>12.5e} {:>12} {:>12} {:>12}  {}{}",
            p.name,
            p.estimate,
            v(p.prior, "-"),
            v(p.min, if solved_end(p) { "-∞" } else { "?" }),
            v(p.max, if solved_end(p) { "+∞" } else { "?" }),
            match p.pinned_by {
                momentlmi::identify::PinnedBy::Data => "data",
                momentlmi::identify::PinnedBy::Physics => "physics",
                momentlmi::identify::PinnedBy::Unknown => "unknown",
            },
            p.note
                .as_ref()
                .map_or_else(String::new, |n| format!(" ({n})"))
        );
    }
}

/// The bodies' table: mass, CoM, principal moments, consistency, distance
/// from the prior.
fn print_bodies(r: &IdentifyResult) {
    println!(
        "{:<12} {:>9} {:>28} {:>34} {:>11} {:>11}",
        "body", "mass", "CoM [m]", "principal moments [kg·m²]", "consistent", "d(J‖Ĵ)"
    );
    for b in &r.bodies {
        let com = b.com.map_or_else(
            || format!("{:>28}", "- (no positive mass)"),
            |c| format!("({:>8.4}, {:>8.4}, {:>8.4})", c[0], c[1], c[2]),
        );
        let div = b
            .divergence_from_prior
            .map_or_else(|| "-".to_string(), |d| format!("{d:.3e}"));
        println!(
            "{:<12} {:>9.4} {com} ({:>10.3e}, {:>10.3e}, {:>10.3e}) {:>11} {div:>11}",
            b.name,
            b.mass,
            b.principal_moments[0],
            b.principal_moments[1],
            b.principal_moments[2],
            if b.consistent { "yes" } else { "NO" }
        );
    }
}

/// The joints and each friction term identified (viscous and Coulomb
/// always, the others when non-zero).
fn print_friction(r: &IdentifyResult) {
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.4}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let joints = r.joints.join(", ");
    println!("joints         {joints}");
    println!("viscous        {} N·m·s/rad", list(&r.friction.viscous));
    println!("Coulomb        {} N·m", list(&r.friction.coulomb));
    // the terms beyond the default, when identified (non-zero)
    for t in &FrictionTerm::ALL[2..] {
        let c = r.friction.coefficients(*t);
        if c.iter().any(|&c| c != 0.0) {
            let vs = (*t == FrictionTerm::Stribeck)
                .then(|| format!(" (v_s {} rad/s)", r.friction.stribeck_velocity()))
                .unwrap_or_default();
            println!("{:<15}{} {}{vs}", t.name(), list(c), t.unit());
        }
    }
}
