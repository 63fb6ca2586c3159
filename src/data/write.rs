//! Outputs written whole or not at all, and the JSON record beside a CSV.

use super::dataset::Dataset;
use super::error::DataError;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The temporary name `text` is written under before the rename: hidden,
/// beside `path`, and unique to this process, so that it is neither the
/// input nor a file the user keeps.
fn temporary(path: &Path) -> PathBuf {
    let name = path.file_name().and_then(|f| f.to_str()).unwrap_or("out");
    path.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> DataError + '_ {
    move |source| DataError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// Writes `text` to `path` via a temporary file and a rename: a reader sees
/// the old file or the whole new one, never a part.
pub fn write_whole(path: &Path, text: &str) -> Result<(), DataError> {
    let tmp = temporary(path);
    std::fs::write(&tmp, text)
        .and_then(|_| std::fs::rename(&tmp, path))
        .map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            io(path)(e)
        })
}

/// The record written beside a data file `x.csv`: `x.json`.
pub fn record_path(csv: &Path) -> PathBuf {
    csv.with_extension("json")
}

/// Writes a data set as CSV and, beside it ([`record_path`]), a JSON record
/// of how it was made: both are written to temporary files first and
/// renamed only when both are complete. A data path whose record would be
/// itself (`x.json`) is refused. Returns the record's path.
pub fn write_with_record(
    data: &Dataset,
    csv: &Path,
    record: &impl Serialize,
) -> Result<PathBuf, DataError> {
    let rec = record_path(csv);
    if rec == csv {
        return Err(DataError::Output {
            path: csv.display().to_string(),
            message: "the data file and its JSON record would be the same file; use a .csv name"
                .into(),
        });
    }
    let text = serde_json::to_string_pretty(record).map_err(|source| DataError::Json {
        path: rec.display().to_string(),
        source,
    })?;
    let (tmp_csv, tmp_rec) = (temporary(csv), temporary(&rec));
    let cleanup = || {
        let _ = std::fs::remove_file(&tmp_csv);
        let _ = std::fs::remove_file(&tmp_rec);
    };
    let staged = std::fs::write(&tmp_csv, data.to_csv())
        .map_err(io(csv))
        .and_then(|_| std::fs::write(&tmp_rec, &text).map_err(io(&rec)));
    let done = staged
        .and_then(|_| std::fs::rename(&tmp_csv, csv).map_err(io(csv)))
        .and_then(|_| std::fs::rename(&tmp_rec, &rec).map_err(io(&rec)));
    if done.is_err() {
        cleanup();
    }
    done.map(|_| rec)
}
