//! The CSV form of a floating-base robot's [`Dataset`] (docs/inputs.md,
//! "Floating-base logs"):
//!
//! - `t`; the base pose `base_x, base_y, base_z` (world, m) and
//!   `base_qx, base_qy, base_qz, base_qw` (base → world); its twist
//!   `base_vx, base_vy, base_vz, base_wx, base_wy, base_wz` and the twist's
//!   derivative `base_dvx, …, base_dwz` (base coordinates, SI);
//! - per joint `q_<j>, qd_<j>, qdd_<j>` and, when measured, `tau_<j>`;
//! - per contact frame (a URDF link) `force_<frame>_<x|y|z>` and optionally
//!   `moment_<frame>_<x|y|z>` (N, N·m about the frame origin) in the
//!   frame's own axes, or `world_force_…`, `world_moment_…` in world-aligned
//!   axes at the frame origin (a force plate's).
//!
//! Any column order; every other column is an error naming it. The same
//! columns as the arrays of a NumPy `.npz` archive (one 1-D array per
//! column, [`read_floating_npz`]); [`Dataset::to_csv`] writes it.

use super::Dataset;
use super::base::{AXES, BASE_Q, BASE_V, prefix_of};
use super::csv::MAX_COLUMNS;
use super::error::DataError;
use super::raw::{MAX_ROWS, limit, not_after, refusal};
use crate::dynamics::{Model, WrenchFrame};
use std::collections::HashMap;

/// What a column holds: (array, width, index) or a contact's entry.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Slot {
    Q(usize),
    V(usize),
    A(usize),
    Tau(usize),
    T,
    /// Contact c's wrench entry (0..3 force, 3..6 moment).
    Wrench(usize, usize),
}

/// Every column's slot and the contacts found;
/// an unknown, repeated or missing column is an error naming it.
fn slots(
    ff: &Model,
    header: &[String],
    path: &str,
) -> Result<(Vec<Slot>, Vec<(String, WrenchFrame)>), DataError> {
    let joints = ff.joint_names();
    let mut known: HashMap<String, Slot> = HashMap::new();
    known.insert("t".into(), Slot::T);
    for (i, c) in BASE_Q.iter().enumerate() {
        known.insert(format!("base_{c}"), Slot::Q(i));
    }
    for (i, c) in BASE_V.iter().enumerate() {
        known.insert(format!("base_{c}"), Slot::V(i));
        known.insert(format!("base_d{c}"), Slot::A(i));
    }
    for (i, j) in joints.iter().enumerate() {
        known.insert(format!("q_{j}"), Slot::Q(7 + i));
        known.insert(format!("qd_{j}"), Slot::V(6 + i));
        known.insert(format!("qdd_{j}"), Slot::A(6 + i));
        known.insert(format!("tau_{j}"), Slot::Tau(i));
    }
    let mut contacts: Vec<(String, WrenchFrame)> = Vec::new();
    let mut out = Vec::with_capacity(header.len());
    for name in header {
        let slot = match known.get(name) {
            Some(s) => *s,
            None => {
                let value = |message| DataError::Value {
                    path: path.into(),
                    row: 0,
                    column: name.clone(),
                    message,
                };
                match contact_slot(ff, name, &mut contacts).map_err(value)? {
                    Some(s) => s,
                    None => {
                        return Err(value(
                            "not a column of a floating-base log (docs/inputs.md)".into(),
                        ));
                    }
                }
            }
        };
        if out.contains(&slot) {
            return Err(DataError::Value {
                path: path.into(),
                row: 0,
                column: name.clone(),
                message: "given twice".into(),
            });
        }
        out.push(slot);
    }
    let has_tau = out.iter().any(|s| matches!(s, Slot::Tau(_)));
    let mut need: Vec<(Slot, String)> = vec![(Slot::T, "t".into())];
    for (name, slot) in &known {
        let required = !matches!(slot, Slot::T | Slot::Tau(_)) || has_tau;
        if required && !matches!(slot, Slot::T) {
            need.push((*slot, name.clone()));
        }
    }
    need.sort_by(|a, b| a.1.cmp(&b.1));
    if let Some((_, missing)) = need.iter().find(|(s, _)| !out.contains(s)) {
        return Err(DataError::MissingColumn {
            path: path.into(),
            column: missing.clone(),
            header: header.join(","),
        });
    }
    Ok((out, contacts))
}

/// A `[world_]force_<frame>_<axis>` or `[world_]moment_…` column's slot;
/// `None` for a name of another form, an error for a frame the robot does
/// not have.
fn contact_slot(
    ff: &Model,
    name: &str,
    contacts: &mut Vec<(String, WrenchFrame)>,
) -> Result<Option<Slot>, String> {
    let Some((expressed, offset, axis, frame)) = contact_column(name) else {
        return Ok(None);
    };
    ff.frame_index(frame).map_err(|e| e.to_string())?;
    let c = match contacts
        .iter()
        .position(|(f, e)| f == frame && *e == expressed)
    {
        Some(c) => c,
        None => {
            contacts.push((frame.to_string(), expressed));
            contacts.len() - 1
        }
    };
    Ok(Some(Slot::Wrench(c, offset + axis)))
}

/// A contact column's parts: how it is expressed, 0 (force) or 3
/// (moment), the axis and the frame's name.
fn contact_column(name: &str) -> Option<(WrenchFrame, usize, usize, &str)> {
    let (expressed, rest) = match name.strip_prefix("world_") {
        Some(r) => (WrenchFrame::WorldAligned, r),
        None => (WrenchFrame::Local, name),
    };
    let (offset, rest) = if let Some(r) = rest.strip_prefix("force_") {
        (0, r)
    } else {
        (3, rest.strip_prefix("moment_")?)
    };
    let axis = AXES.iter().position(|a| rest.ends_with(&format!("_{a}")))?;
    let frame = &rest[..rest.len() - 2];
    (!frame.is_empty()).then_some((expressed, offset, axis, frame))
}

/// Reads the CSV text of a floating-base log of the robot `ff`; `path`
/// names it in errors (row numbers 1-based, data rows). A contact without
/// moment columns has zero moment (a point contact); a contact with some
/// but not all three force columns is an error.
pub fn floating_from_csv(ff: &Model, text: &str, path: &str) -> Result<Dataset, DataError> {
    floating_from_reader(ff, text.as_bytes(), path)
}

/// Reads a floating-base log's CSV file (streamed, within the readers' row limit),
/// as [`floating_from_csv`].
pub fn read_floating_csv(ff: &Model, path: &std::path::Path) -> Result<Dataset, DataError> {
    let name = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|source| DataError::Io {
        path: name.clone(),
        source,
    })?;
    floating_from_reader(ff, std::io::BufReader::new(file), &name)
}

/// Reads a floating-base log from a NumPy `.npz` archive: one 1-D array
/// per column, named as the CSV's columns (module docs), checked as the
/// CSV is (rows numbered from 1); at most `max_values` numbers in all
/// (checked before the archive's arrays past the first are read).
pub fn read_floating_npz(
    ff: &Model,
    path: &std::path::Path,
    max_values: u64,
) -> Result<Dataset, DataError> {
    let name = path.display().to_string();
    let (header, columns) = super::npz::read_npz_columns(path, MAX_COLUMNS, max_values)?;
    floating_from_columns(ff, &header, &columns, &name)
}

/// A floating-base log from named columns of equal length (`header[i]`
/// names `columns[i]`, as the CSV's columns), checked as the CSV is (rows
/// numbered from 1); `name` names the log in errors.
pub fn floating_from_columns<C: AsRef<[f64]>>(
    ff: &Model,
    header: &[String],
    columns: &[C],
    name: &str,
) -> Result<Dataset, DataError> {
    let rows = columns.first().map_or(0, |c| c.as_ref().len());
    let array = |array: &str, message: String| DataError::Array {
        path: name.into(),
        array: array.into(),
        message,
    };
    if header.len() != columns.len() || header.len() > MAX_COLUMNS {
        let (h, c) = (header.len(), columns.len());
        return Err(array(
            "(columns)",
            format!("{h} names for {c} columns (at most {MAX_COLUMNS})"),
        ));
    }
    if let Some(i) = columns.iter().position(|c| c.as_ref().len() != rows) {
        let found = columns[i].as_ref().len();
        return Err(array(
            &header[i],
            format!("{found} values; the first column has {rows}"),
        ));
    }
    let (slots, contacts) = slots(ff, header, name)?;
    check_forces(&slots, &contacts, name)?;
    let mut log = new_log(ff, &contacts)?;
    let mut values = vec![0.0; columns.len()];
    for r in 0..rows {
        values
            .iter_mut()
            .zip(columns)
            .for_each(|(v, c)| *v = c.as_ref()[r]);
        push_values(&mut log, ff, &slots, &values, (name, r + 1), header)?;
    }
    Ok(log)
}

/// An empty log of the free flyer `ff` with the `contacts`.
fn new_log(ff: &Model, contacts: &[(String, WrenchFrame)]) -> Result<Dataset, DataError> {
    ff.need_free_flyer("a floating-base log")
        .map_err(|e| DataError::Log {
            message: e.to_string(),
        })?;
    Ok(Dataset::for_model(ff, contacts))
}

/// [`floating_from_csv`] from any reader.
fn floating_from_reader(
    ff: &Model,
    reader: impl std::io::Read,
    path: &str,
) -> Result<Dataset, DataError> {
    let mut rdr = ::csv::ReaderBuilder::new()
        .trim(::csv::Trim::All)
        .from_reader(super::csv::LineLimit::new(reader));
    let row_err = |row, message: String| DataError::Row {
        path: path.into(),
        row,
        message,
    };
    let header: Vec<String> = (rdr.headers().map_err(|e| row_err(0, e.to_string()))?)
        .iter()
        .map(str::to_string)
        .collect();
    if header.len() > MAX_COLUMNS {
        return Err(row_err(
            0,
            format!("{} columns; at most {MAX_COLUMNS}", header.len()),
        ));
    }
    let (slots, contacts) = slots(ff, &header, path)?;
    check_forces(&slots, &contacts, path)?;
    let mut log = new_log(ff, &contacts)?;
    for (r, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| row_err(r + 1, e.to_string()))?;
        if r >= MAX_ROWS {
            return Err(row_err(r + 1, format!("more than {MAX_ROWS} rows")));
        }
        push_row(&mut log, ff, &slots, &rec, (path, r + 1), &header)?;
    }
    Ok(log)
}

/// Every contact has its three force columns.
fn check_forces(
    slots: &[Slot],
    contacts: &[(String, WrenchFrame)],
    path: &str,
) -> Result<(), DataError> {
    for (c, (frame, e)) in contacts.iter().enumerate() {
        let has_moment = (3..6).any(|i| slots.contains(&Slot::Wrench(c, i)));
        for (i, a) in AXES.iter().enumerate() {
            // every force axis; the moment's all or none (a point contact)
            for (kind, offset, needed) in [("force", 0, true), ("moment", 3, has_moment)] {
                if needed && !slots.contains(&Slot::Wrench(c, offset + i)) {
                    return Err(DataError::MissingColumn {
                        path: path.into(),
                        column: format!("{}{kind}_{frame}_{a}", prefix_of(*e)),
                        header: format!("the other {kind} columns of that contact"),
                    });
                }
            }
        }
    }
    Ok(())
}

fn push_row(
    log: &mut Dataset,
    ff: &Model,
    slots: &[Slot],
    rec: &::csv::StringRecord,
    (path, row): (&str, usize),
    header: &[String],
) -> Result<(), DataError> {
    if rec.len() != slots.len() {
        return Err(DataError::Row {
            path: path.into(),
            row,
            message: format!("{} fields, the header has {}", rec.len(), slots.len()),
        });
    }
    let values = (rec.iter().zip(header))
        .map(|(field, name)| {
            field.parse().map_err(|_| DataError::Value {
                path: path.into(),
                row,
                column: name.clone(),
                message: format!("'{field}' is not a number"),
            })
        })
        .collect::<Result<Vec<f64>, _>>()?;
    push_values(log, ff, slots, &values, (path, row), header)
}

/// One row's values (one per slot) into `log`, each within the readers'
/// limits, the time after the last row's.
fn push_values(
    log: &mut Dataset,
    ff: &Model,
    slots: &[Slot],
    values: &[f64],
    (path, row): (&str, usize),
    header: &[String],
) -> Result<(), DataError> {
    let (nq, nv, n) = (ff.nq(), ff.nv(), ff.dof());
    let (mut q, mut v, mut a, mut tau) =
        (vec![0.0; nq], vec![0.0; nv], vec![0.0; nv], vec![0.0; n]);
    let mut wrench = vec![[0.0; 6]; log.contacts.len()];
    let mut time = 0.0;
    for ((&x, slot), name) in values.iter().zip(slots).zip(header) {
        let bad = |message| DataError::Value {
            path: path.into(),
            row,
            column: name.clone(),
            message,
        };
        if let Some(why) = refusal(x, limit(*slot == Slot::T)) {
            return Err(bad(why));
        }
        if let (Slot::T, Some(&last)) = (slot, log.t.last())
            && x <= last
        {
            return Err(bad(not_after(x, last, "row")));
        }
        match *slot {
            Slot::T => time = x,
            Slot::Q(i) => q[i] = x,
            Slot::V(i) => v[i] = x,
            Slot::A(i) => a[i] = x,
            Slot::Tau(i) => tau[i] = x,
            Slot::Wrench(c, i) => wrench[c][i] = x,
        }
    }
    let has_tau = slots.iter().any(|s| matches!(s, Slot::Tau(_)));
    log.push_state(time, (&q, &v, &a), has_tau.then_some(&tau[..]));
    for (c, w) in log.contacts.iter_mut().zip(wrench) {
        c.wrench.extend(w);
    }
    Ok(())
}
