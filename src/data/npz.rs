//! NumPy logs: `.npz` archives (arrays named by a [`Mapping`]) and `.npy`
//! arrays (one 2-D array laid out as the CSV format's columns), read with
//! `npyz` (arrays of float64, float32, int64 or int32, C or Fortran order)
//! and `zip`.

use super::error::DataError;
use super::mapping::{Kind, Mapping};
use super::raw::{MAX_ABS_TIME, MAX_ABS_VALUE, MAX_ROWS, RawLog, check_value, joint_positions};
use crate::dynamics::Samples;
use std::io::Read;
use std::path::Path;

/// The most values one array may hold (an array is read whole).
pub const MAX_ARRAY_VALUES: u64 = 400_000_000;

/// One array: its shape and values, in C order.
struct Array {
    shape: Vec<u64>,
    values: Vec<f64>,
}

/// The shape an archive member must have, checked on its header before a
/// value is decompressed.
#[derive(Clone, Copy)]
enum Want {
    /// One value per sample: `[n]` or `[n, 1]`, n at most `rows` (or
    /// exactly `rows` when `exact`).
    Vector { rows: usize, exact: bool },
    /// `[rows, cols]`.
    Matrix { rows: usize, cols: usize },
    /// `[n, c]`, n at most [`MAX_ROWS`] and c at most `cols`.
    Table { cols: usize },
}

impl Want {
    /// One value per sample, at most [`MAX_ROWS`] (time stamps).
    const AT_MOST_ROWS: Want = Want::Vector {
        rows: MAX_ROWS,
        exact: false,
    };

    /// `[rows, cols]`.
    fn matrix(rows: usize, cols: usize) -> Want {
        Want::Matrix { rows, cols }
    }

    /// Why `shape` is not the one wanted, if it is not.
    fn refuses(self, shape: &[u64]) -> Option<String> {
        match (self, shape) {
            (Want::Vector { rows, exact }, [n] | [n, 1]) => {
                let n = usize::try_from(*n).unwrap_or(usize::MAX);
                match (exact, n == rows, n <= rows) {
                    (true, false, _) => Some(format!("{n} values for {rows} time stamps")),
                    (false, _, false) => Some(format!(
                        "shape {shape:?}: expected one value per sample, at most {MAX_ROWS}"
                    )),
                    _ => None,
                }
            }
            (Want::Vector { .. }, s) => Some(format!(
                "shape {s:?}: expected one value per sample, at most {MAX_ROWS}"
            )),
            (Want::Matrix { rows, cols }, [r, c]) if *r == rows as u64 && *c == cols as u64 => None,
            (Want::Table { cols }, [n, c]) if *n <= MAX_ROWS as u64 && *c <= cols as u64 => None,
            (Want::Table { cols }, s) => Some(format!(
                "shape {s:?}: expected [n, c] with n at most {MAX_ROWS} samples and c at most {cols} columns"
            )),
            (Want::Matrix { rows, cols }, s) => Some(format!(
                "shape {s:?}: expected [{rows}, {cols}] (one row per time stamp, one column per joint of the mapping's order)"
            )),
        }
    }
}

impl Array {
    /// Reads a `.npy` stream of `bytes` bytes whose header must declare the
    /// shape `want` (checked before a value is read); `name` names it in
    /// errors.
    fn read(
        r: impl Read,
        bytes: u64,
        (path, name): (&str, &str),
        want: Want,
    ) -> Result<Self, DataError> {
        let bad = |message: String| DataError::Array {
            path: path.into(),
            array: name.into(),
            message,
        };
        let npy = npyz::NpyFile::new(r).map_err(|e| bad(format!("not a NumPy array: {e}")))?;
        let shape = npy.shape().to_vec();
        if let Some(why) = want.refuses(&shape) {
            return Err(bad(why));
        }
        let n = npy.len();
        if n > MAX_ARRAY_VALUES {
            return Err(bad(format!("{n} values; at most {MAX_ARRAY_VALUES}")));
        }
        let width = match npy.dtype() {
            npyz::DType::Plain(t) => t.size_field() as u64,
            d => return Err(bad(format!("dtype {} is not a number", d.descr()))),
        };
        if n.saturating_mul(width) > bytes {
            return Err(bad(format!(
                "truncated: shape {shape:?} needs {} bytes, the archive holds {bytes}",
                n * width
            )));
        }
        let fortran = npy.order() == npyz::Order::Fortran;
        let values = numbers(npy).map_err(|m| bad(m))?;
        let values = if fortran && shape.len() == 2 {
            transpose(&values, shape[0] as usize, shape[1] as usize)
        } else {
            values
        };
        Ok(Self { shape, values })
    }
}

/// The array's values as f64 (from f8, f4, i8 or i4).
fn numbers<R: Read>(npy: npyz::NpyFile<R>) -> Result<Vec<f64>, String> {
    // room made once for all a log usually has (a hostile header claiming
    // more grows the vector only as values really come)
    let n = (npy.len() as usize).min(1 << 22);
    if let npyz::DType::Plain(t) = npy.dtype() {
        use npyz::{Endianness, TypeChar};
        if (t.type_char(), t.size_field(), t.endianness())
            == (TypeChar::Float, 8, Endianness::Little)
        {
            return little_f64(npy.len(), n, npy.into_inner());
        }
    }
    let all = |it: &mut dyn Iterator<Item = std::io::Result<f64>>| {
        let mut v = Vec::with_capacity(n);
        for x in it {
            v.push(x.map_err(|e| format!("truncated or unreadable: {e}"))?);
        }
        Ok(v)
    };
    let npy = match npy.try_data::<f64>() {
        Ok(r) => return all(&mut r.into_iter()),
        Err(n) => n,
    };
    let npy = match npy.try_data::<f32>() {
        Ok(r) => return all(&mut r.into_iter().map(|x| x.map(f64::from))),
        Err(n) => n,
    };
    let npy = match npy.try_data::<i64>() {
        Ok(r) => return all(&mut r.into_iter().map(|x| x.map(|v| v as f64))),
        Err(n) => n,
    };
    match npy.try_data::<i32>() {
        Ok(r) => all(&mut r.into_iter().map(|x| x.map(f64::from))),
        Err(n) => Err(format!(
            "dtype {} is not float64, float32, int64 or int32",
            n.dtype().descr()
        )),
    }
}

/// `len` little-endian float64 values read in bulk (the common case: what
/// NumPy writes on every usual machine), `room` of them allocated at first.
fn little_f64(len: u64, room: usize, mut r: impl Read) -> Result<Vec<f64>, String> {
    let mut bytes = Vec::with_capacity(room * 8);
    (&mut r)
        .take(len.saturating_mul(8))
        .read_to_end(&mut bytes)
        .map_err(|e| format!("truncated or unreadable: {e}"))?;
    if (bytes.len() as u64) < len.saturating_mul(8) {
        return Err(format!(
            "truncated or unreadable: {} of {len} values",
            bytes.len() / 8
        ));
    }
    // the end must follow the values: an archive member then has its
    // checksum checked, and one that inflates beyond its declared size
    // (a zip bomb) is refused, not cut at the values it declared
    match r.read(&mut [0u8; 1]) {
        Ok(0) => {}
        Ok(_) => return Err("data after the array's values (a corrupt or hostile member)".into()),
        Err(e) => return Err(format!("corrupt: {e}")),
    }
    Ok(bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect())
}

/// Column-major `v` (`rows × cols`) in row-major order.
fn transpose(v: &[f64], rows: usize, cols: usize) -> Vec<f64> {
    (0..rows * cols)
        .map(|k| v[(k % cols) * rows + k / cols])
        .collect()
}

/// Reads an `.npz` archive through `mapping` (`None`: the default names
/// `t`, `q`, `qd`, `qdd`, `tau`, of which only `t`, `q` are required; those
/// too when `only_default` says the mapping is just the robot's default and
/// the archive has `t` and not the mapping's time array) for the robot's
/// `joints`.
pub fn read_npz(
    path: &Path,
    mapping: Option<&Mapping>,
    only_default: bool,
    joints: &[&str],
) -> Result<RawLog, DataError> {
    let p = path.display().to_string();
    let (mut zip, names) = open_archive(path, &p)?;
    super::csv::refuse_base_columns(&names, &p)?;
    let default = default_names();
    let has = |n: &str| names.iter().any(|x| x == n);
    let mapping = match mapping {
        Some(m) if !(only_default && has("t") && !has(m.time_name())) => m,
        _ => &default,
    };
    let by_default = std::ptr::eq(mapping, &default);
    let mut get = |name: &str, want: Want| -> Result<Array, DataError> {
        let mut f = zip
            .by_name(&format!("{name}.npy"))
            .map_err(|_| DataError::Array {
                path: p.clone(),
                array: name.into(),
                message: no_such_array(&names, by_default),
            })?;
        let size = f.size();
        // large reads: the archive's checksum and inflate run on whole blocks,
        // not on each number npyz asks for
        let r = std::io::BufReader::with_capacity((size as usize).clamp(8 << 10, 1 << 20), &mut f);
        Array::read(r, size, (&p, name), want)
    };
    let t = get(mapping.time_name(), Want::AT_MOST_ROWS)?;
    let scale = mapping.time_scale().unwrap_or(1.0);
    let rows = vector(&t, &p, mapping.time_name())?;
    let t: Vec<f64> = rows
        .iter()
        .enumerate()
        .map(|(r, v)| check_value(v * scale, MAX_ABS_TIME, &p, mapping.time_name(), r + 1))
        .collect::<Result<_, _>>()?;
    let order = mapping.joint_order(joints);
    let mut log = RawLog {
        path: p.clone(),
        t,
        ..RawLog::default()
    };
    for k in Kind::ALL {
        let Some(qm) = mapping.quantity(k) else {
            continue;
        };
        let label = qm.source.clone().unwrap_or_else(|| k.prefix().into());
        if by_default && k != Kind::Q && !names.contains(&label) {
            continue; // the defaults beyond t and q are optional
        }
        let pos = joint_positions(joints, &order, &p, &label)?;
        let scale = qm.scale().unwrap_or(1.0);
        let m = match qm.per_joint(&order) {
            Some(names) => per_joint_arrays(&mut get, &names, log.len(), &p)?,
            None => {
                let name = qm.source.clone().unwrap_or_default();
                let a = get(&name, Want::matrix(log.len(), order.len()))?;
                matrix(a, log.len(), order.len(), &p, &name)?
            }
        };
        let v = rows_of(&m, order.len(), &pos, scale, &p, &label)?;
        match k {
            Kind::Q => log.q = v,
            Kind::Qd => log.qd = Some(v),
            Kind::Qdd => log.qdd = Some(v),
            Kind::Tau => log.tau = Some(v),
        }
    }
    Ok(log)
}

/// Every array of an `.npz` archive as one column (a 1-D array, or n × 1)
/// of one value per time stamp, named by the array (`t` first when there
/// is one): a table saved as `numpy.savez(path, **columns)`. At most
/// `max_columns` arrays and `max_values` values in all (the rows of the
/// first times the arrays, checked before the others are read); each
/// checked on its header (one value per row of the first, at most
/// [`MAX_ROWS`]) before a value is decompressed.
pub fn read_npz_columns(
    path: &Path,
    max_columns: usize,
    max_values: u64,
) -> Result<(Vec<String>, Vec<Vec<f64>>), DataError> {
    let p = path.display().to_string();
    let (mut zip, mut names) = open_archive(path, &p)?;
    if names.len() > max_columns {
        return Err(DataError::Array {
            path: p,
            array: "(archive)".into(),
            message: format!("{} arrays; at most {max_columns}", names.len()),
        });
    }
    if let Some(k) = names.iter().position(|n| n == "t") {
        names[..=k].rotate_right(1);
    }
    let mut columns: Vec<Vec<f64>> = Vec::with_capacity(names.len());
    for name in &names {
        let want = match columns.first() {
            None => Want::AT_MOST_ROWS,
            Some(c) => Want::Vector {
                rows: c.len(),
                exact: true,
            },
        };
        let mut f = zip
            .by_name(&format!("{name}.npy"))
            .map_err(|e| DataError::Array {
                path: p.clone(),
                array: name.clone(),
                message: e.to_string(),
            })?;
        let size = f.size();
        let r = std::io::BufReader::with_capacity((size as usize).clamp(8 << 10, 1 << 20), &mut f);
        let a = Array::read(r, size, (&p, name), want)?;
        columns.push(vector(&a, &p, name)?);
        let total = (columns[0].len() as u64).saturating_mul(names.len() as u64);
        if total > max_values {
            return Err(DataError::Array {
                path: p,
                array: "(archive)".into(),
                message: format!(
                    "{} arrays of {} values: more than the {max_values} values allowed in memory",
                    names.len(),
                    columns[0].len()
                ),
            });
        }
    }
    Ok((names, columns))
}

type Archive = zip::ZipArchive<std::io::BufReader<std::fs::File>>;

/// The archive at `path` (`p` names it) and its arrays' names.
fn open_archive(path: &Path, p: &str) -> Result<(Archive, Vec<String>), DataError> {
    let file = std::fs::File::open(path).map_err(|source| DataError::Io {
        path: p.into(),
        source,
    })?;
    let zip =
        zip::ZipArchive::new(std::io::BufReader::new(file)).map_err(|e| DataError::Array {
            path: p.into(),
            array: "(archive)".into(),
            message: format!("not a NumPy .npz archive (a zip file): {e}"),
        })?;
    if let Some(listed) = listed_members(path)
        && listed != zip.len() as u64
    {
        return Err(DataError::Array {
            path: p.into(),
            array: "(archive)".into(),
            message: format!(
                "lists {listed} members under {} names: a name given twice (which array is meant?)",
                zip.len()
            ),
        });
    }
    let names = (zip.file_names())
        .filter_map(Result::ok)
        .map(|n| n.trim_end_matches(".npy").to_string())
        .collect();
    Ok((zip, names))
}

/// The number of members the zip file's end record says it holds (the
/// reader keeps one member per name), when the record is found within the
/// file's last 64 KiB and is not a ZIP64 one.
fn listed_members(path: &Path) -> Option<u64> {
    use std::io::{Seek, SeekFrom};
    let mut f = std::fs::File::open(path).ok()?;
    let len = f.metadata().ok()?.len();
    let tail = len.min(22 + 0xFFFF);
    f.seek(SeekFrom::Start(len - tail)).ok()?;
    let mut buf = Vec::with_capacity(tail as usize);
    f.take(tail).read_to_end(&mut buf).ok()?;
    let at = buf.windows(4).rposition(|w| w == b"PK\x05\x06")?;
    let count = u16::from_le_bytes(buf.get(at + 10..at + 12)?.try_into().ok()?);
    (count != 0xFFFF).then_some(u64::from(count))
}

/// What a missing array's error says: the arrays there are, and, when no
/// mapping was given, where mappings are described.
fn no_such_array(names: &[String], by_default: bool) -> String {
    let hint = if by_default {
        "; no mapping was given, and a column mapping names other arrays (docs/inputs.md, \"Column mappings\")"
    } else {
        ""
    };
    format!(
        "no such array (the archive has: {}){hint}",
        names.join(", ")
    )
}

/// An archive's default names: arrays `t`, `q`, `qd`, `qdd`, `tau`
/// (n × joints, the robot's order).
fn default_names() -> Mapping {
    let mut m = Mapping::csv_default();
    for (q, name) in [
        (&mut m.q, "q"),
        (&mut m.qd, "qd"),
        (&mut m.qdd, "qdd"),
        (&mut m.tau, "tau"),
    ] {
        if let Some(q) = q {
            q.source = Some(name.into());
        }
    }
    m
}

/// A 1-D array (or n × 1).
fn vector(a: &Array, path: &str, name: &str) -> Result<Vec<f64>, DataError> {
    match a.shape.as_slice() {
        [n] | [n, 1] if (*n as usize) <= MAX_ROWS => Ok(a.values.clone()),
        s => Err(DataError::Array {
            path: path.into(),
            array: name.into(),
            message: format!("shape {s:?}: expected one value per sample, at most {MAX_ROWS}"),
        }),
    }
}

/// An `n × cols` array, row-major.
fn matrix(a: Array, n: usize, cols: usize, path: &str, name: &str) -> Result<Vec<f64>, DataError> {
    match a.shape.as_slice() {
        [r, c] if *r as usize == n && *c as usize == cols => Ok(a.values),
        s => Err(DataError::Array {
            path: path.into(),
            array: name.into(),
            message: format!(
                "shape {s:?}: expected [{n}, {cols}] (one row per time stamp, one column per joint of the mapping's order)"
            ),
        }),
    }
}

/// One 1-D array per joint, interleaved into an `n × joints` matrix.
fn per_joint_arrays(
    get: &mut impl FnMut(&str, Want) -> Result<Array, DataError>,
    names: &[String],
    n: usize,
    path: &str,
) -> Result<Vec<f64>, DataError> {
    let cols = names.len();
    let mut m = vec![0.0; n * cols];
    for (j, name) in names.iter().enumerate() {
        let v = vector(
            &get(
                name,
                Want::Vector {
                    rows: n,
                    exact: true,
                },
            )?,
            path,
            name,
        )?;
        if v.len() != n {
            return Err(DataError::Array {
                path: path.into(),
                array: name.clone(),
                message: format!("{} values for {n} time stamps", v.len()),
            });
        }
        v.iter().enumerate().for_each(|(r, x)| m[r * cols + j] = *x);
    }
    Ok(m)
}

/// Per sample, the robot's joints' values (columns `pos` of the row-major
/// `m`, `cols` wide), scaled and checked.
fn rows_of(
    m: &[f64],
    cols: usize,
    pos: &[usize],
    scale: f64,
    path: &str,
    name: &str,
) -> Result<Samples, DataError> {
    let mut out = Samples::with_capacity(pos.len(), m.len() / cols.max(1));
    for (r, row) in m.chunks_exact(cols.max(1)).enumerate() {
        out.try_push_with(|j| check_value(row[pos[j]] * scale, MAX_ABS_VALUE, path, name, r + 1))?;
    }
    Ok(out)
}

/// Reads a `.npy` file: one 2-D array whose columns are the CSV format's
/// `t, q_*, qd_*, [qdd_*,] tau_*` for the robot's `joints` in order (the
/// column count says whether q̈ is there), or `t, q_*, qd_*` without τ.
pub fn read_npy(path: &Path, joints: &[&str]) -> Result<RawLog, DataError> {
    let p = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|source| DataError::Io {
        path: p.clone(),
        source,
    })?;
    let size = file.metadata().map(|m| m.len()).unwrap_or(0);
    let j = joints.len();
    let want = Want::Table { cols: 1 + 4 * j };
    let a = Array::read(std::io::BufReader::new(file), size, (&p, "(array)"), want)?;
    let blocks = match a.shape.as_slice() {
        [_, c] if (*c as usize) > 0 && (*c as usize - 1) % j.max(1) == 0 => {
            (*c as usize - 1) / j.max(1)
        }
        _ => 0,
    };
    if !(2..=4).contains(&blocks) {
        return Err(DataError::Array {
            path: p,
            array: "(array)".into(),
            message: format!(
                "shape {:?}: expected [n, 1 + k·{j}] with k = 2 (q, q̇), 3 (q, q̇, τ) or 4 (q, q̇, q̈, τ) for the joints {}",
                a.shape,
                joints.join(", ")
            ),
        });
    }
    let c = 1 + blocks * j;
    let col = |b: usize| -> Result<Samples, DataError> {
        let pos: Vec<usize> = (0..j).map(|k| 1 + b * j + k).collect();
        rows_of(&a.values, c, &pos, 1.0, &p, "(array)")
    };
    let t = a
        .values
        .chunks_exact(c)
        .enumerate()
        .map(|(r, row)| check_value(row[0], MAX_ABS_TIME, &p, "(array)", r + 1))
        .collect::<Result<_, _>>()?;
    Ok(RawLog {
        path: p.clone(),
        t,
        q: col(0)?,
        qd: Some(col(1)?),
        qdd: if blocks == 4 { Some(col(2)?) } else { None },
        tau: if blocks >= 3 {
            Some(col(blocks - 1)?)
        } else {
            None
        },
        warnings: vec![],
    })
}
