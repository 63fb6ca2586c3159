//! The sidecar written beside an exported URDF: the robot's own sidecar
//! (its text kept where not changed) with the identified rotors and
//! friction, and the prior it was identified against.

use super::checks::has_friction;
use super::error::ExportError;
use crate::dynamics::{Friction, FrictionTerm, Model};
use crate::moments::InertialParams;
use toml_edit::{Array, ArrayOfTables, DocumentMut, Item, Table, value};

/// The sidecar text for a URDF written by [`super::urdf_with_params`]:
/// `given` (the sidecar's text and path, if the robot had one) with
/// - each `[[rotor]]`'s inertia replaced by the identified `params` (its
///   `mass`, `com`, `inertia` keys removed);
/// - each moving joint's `[[joint]]` friction set to the identified law
///   (when friction was identified): `viscous`, `coulomb`, and each other
///   term with a non-zero coefficient (`offset`, `asymmetric`, `load`,
///   `stribeck`, with the root's `stribeck_velocity`), the others removed;
/// - each body's `[[body]]` `prior` set to `prior` (the prior of the
///   identification: the written URDF's inertials are the identified ones,
///   so a body without a stated prior would otherwise take those as its
///   prior) unless the sidecar states one;
/// - `[data] mapping` made an absolute path (it was relative to `given`'s);
///
/// everything else kept. `prior` is per body, links then rotors.
pub fn sidecar_with_params(
    given: Option<(&str, &str)>,
    model: &Model,
    friction: &Friction,
    prior: &[InertialParams],
) -> Result<String, ExportError> {
    let (text, path) = given.unwrap_or(("", "sidecar"));
    let mut doc: DocumentMut = text.parse().map_err(|e| ExportError::Sidecar {
        path: path.into(),
        message: format!("{e}"),
    })?;
    let bad = |message: String| ExportError::Sidecar {
        path: path.into(),
        message,
    };
    for r in &model.rotors {
        let joint = &model.joints[r.joint].name;
        let t = entry(&mut doc, "rotor", "joint", joint).map_err(bad)?;
        for k in ["mass", "com", "inertia"] {
            t.remove(k);
        }
        // the rotor's kinematics, as the model has them (exact for any source)
        let (roll, pitch, yaw) =
            nalgebra::Rotation3::from_matrix_unchecked(r.x_tree.e.transpose()).euler_angles();
        t["name"] = value(r.name.as_str());
        t["gear_ratio"] = value(r.gear_ratio);
        t["xyz"] = value(numbers(r.x_tree.r.as_slice()));
        t["rpy"] = value(numbers(&[roll, pitch, yaw]));
        t["axis"] = value(numbers(r.axis.as_slice()));
        t["params"] = value(numbers(&r.inertia.0));
    }
    if has_friction(friction) {
        write_friction(&mut doc, model, friction).map_err(bad)?;
    }
    for (name, p) in model.body_names().iter().zip(prior) {
        let t = entry(&mut doc, "body", "name", name).map_err(bad)?;
        if !t.contains_key("prior") {
            let mut spec = toml_edit::InlineTable::new();
            spec.insert("params", numbers(&p.0).into());
            t["prior"] = value(spec);
        }
    }
    absolute_mapping(&mut doc, path);
    let head = "# Written by momentlmi beside the URDF it identified: the rotors' params and the\n# joints' friction (every term of the law) are the identified ones; each body's prior\n# is the one it was identified against (the URDF now holds the identified inertials).\n";
    Ok(format!("{head}{doc}"))
}

/// Every moving joint's friction coefficients of `friction`: viscous and
/// Coulomb always, each other term when any joint's is non-zero (else its
/// key removed), and the Stribeck velocity with a Stribeck term.
fn write_friction(doc: &mut DocumentMut, model: &Model, friction: &Friction) -> Result<(), String> {
    let on = |t: FrictionTerm| friction.coefficients(t).iter().any(|&c| c != 0.0);
    for (j, joint) in model.joints.iter().enumerate() {
        let t = entry(doc, "joint", "name", &joint.name)?;
        for term in FrictionTerm::ALL {
            match FrictionTerm::DEFAULT.contains(&term) || on(term) {
                true => t[term.name()] = value(friction.coefficients(term)[j]),
                false => drop(t.remove(term.name())),
            }
        }
    }
    match on(FrictionTerm::Stribeck) {
        true => doc["stribeck_velocity"] = value(friction.stribeck_velocity()),
        false => drop(doc.remove("stribeck_velocity")),
    }
    Ok(())
}

/// `[data] mapping` (a path relative to the sidecar read from `path`)
/// made absolute, so that the sidecar written elsewhere still finds it.
fn absolute_mapping(doc: &mut DocumentMut, path: &str) {
    let dir = std::path::Path::new(path).parent();
    let Some(m) = doc.get_mut("data").and_then(|d| d.get_mut("mapping")) else {
        return;
    };
    if let (Some(rel), Some(dir)) = (m.as_str(), dir) {
        let full = dir.join(rel);
        let full = std::fs::canonicalize(&full).unwrap_or(full);
        *m = value(full.display().to_string());
    }
}

/// The `[[kind]]` table whose `key` is `name`, appended if there is none.
fn entry<'d>(
    doc: &'d mut DocumentMut,
    kind: &str,
    key: &str,
    name: &str,
) -> Result<&'d mut Table, String> {
    let item = doc
        .entry(kind)
        .or_insert(Item::ArrayOfTables(ArrayOfTables::new()));
    let Some(tables) = item.as_array_of_tables_mut() else {
        return Err(format!("'{kind}' is not an array of tables ([[{kind}]])"));
    };
    let found = tables
        .iter()
        .position(|t| t.get(key).and_then(Item::as_str) == Some(name));
    let k = match found {
        Some(k) => k,
        None => {
            let mut t = Table::new();
            t[key] = value(name);
            tables.push(t);
            tables.len() - 1
        }
    };
    Ok(tables.get_mut(k).expect("the table found or pushed"))
}

/// Numbers as a TOML array (Rust's shortest round-trip form).
fn numbers(x: &[f64]) -> Array {
    x.iter().copied().collect()
}
