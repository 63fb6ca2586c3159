//! Outputs written whole or not at all, and the JSON record beside a CSV.

use super::dataset::Dataset;
use super::error::DataError;
use serde::Serialize;
use std::path::{Path, PathBuf};

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> DataError + '_ {
    move |source| DataError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// Outputs staged in uniquely named temporary files beside their targets
/// and renamed into place together by [`Staged::commit`]: a reader sees the
/// old files or the whole new set, and a command that fails before
/// committing leaves nothing (the temporary files are removed when the
/// `Staged` is dropped). No temporary name can be an input or a file the
/// user keeps.
#[derive(Default)]
pub struct Staged {
    files: Vec<(tempfile::NamedTempFile, PathBuf)>,
    inputs: Vec<PathBuf>,
}

impl Staged {
    /// Nothing staged.
    pub fn new() -> Self {
        Self::default()
    }

    /// Nothing staged yet, and none of `inputs` (the files the command
    /// reads) may be staged as an output.
    pub fn protecting<'a>(inputs: impl IntoIterator<Item = &'a Path>) -> Self {
        Self {
            files: vec![],
            inputs: inputs.into_iter().map(Path::to_path_buf).collect(),
        }
    }

    /// Refuses `path` as an output if it is one of the protected inputs or
    /// already staged; call it before the work to fail early.
    pub fn claim(&self, path: &Path) -> Result<(), DataError> {
        let refuse = |message: String| {
            Err(DataError::Output {
                path: path.display().to_string(),
                message,
            })
        };
        if let Some(i) = self.inputs.iter().find(|i| same_file(i, path)) {
            return refuse(format!(
                "is also an input of this command ({}); choose another output name",
                i.display()
            ));
        }
        if self.files.iter().any(|(_, p)| same_file(p, path)) {
            return refuse("written twice by the same command".into());
        }
        if path.is_dir() {
            return refuse("is a folder; an output file cannot replace it".into());
        }
        Ok(())
    }

    /// Stages `text` for `path` (see [`Staged::add`]).
    pub fn add_text(&mut self, path: &Path, text: &str) -> Result<(), DataError> {
        self.add(path, text.as_bytes())
    }

    /// Stages `bytes` for `path`; a path staged twice or protected as an
    /// input is refused.
    pub fn add(&mut self, path: &Path, bytes: &[u8]) -> Result<(), DataError> {
        self.claim(path)?;
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let mut f = tempfile::Builder::new()
            .prefix(".momentlmi-")
            .suffix(".tmp")
            .tempfile_in(dir)
            .map_err(io(path))?;
        std::io::Write::write_all(&mut f, bytes).map_err(io(path))?;
        // a temporary file is private (0600); the output gets the usual
        // permissions (an existing file's, else rw-r--r--)
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(path).map_or(0o644, |m| m.permissions().mode());
            f.as_file()
                .set_permissions(std::fs::Permissions::from_mode(mode))
                .map_err(io(path))?;
        }
        self.files.push((f, path.to_path_buf()));
        Ok(())
    }

    /// Renames every staged file into place; returns their paths.
    pub fn commit(self) -> Result<Vec<PathBuf>, DataError> {
        let mut done = Vec::with_capacity(self.files.len());
        for (f, path) in self.files {
            f.persist(&path).map_err(|e| io(&path)(e.error))?;
            done.push(path);
        }
        Ok(done)
    }
}

/// Whether two paths name the same file (by canonical path when both exist,
/// else textually after canonicalising the directory).
pub fn same_file(a: &Path, b: &Path) -> bool {
    let canon = |p: &Path| -> PathBuf {
        if let Ok(c) = p.canonicalize() {
            return c;
        }
        match (p.parent(), p.file_name()) {
            (Some(d), Some(n)) => {
                let d = if d.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    d
                };
                d.canonicalize()
                    .map_or_else(|_| p.to_path_buf(), |c| c.join(n))
            }
            _ => p.to_path_buf(),
        }
    };
    canon(a) == canon(b)
}

/// Writes `text` to `path` via a temporary file and a rename: a reader sees
/// the old file or the whole new one, never a part.
pub fn write_whole(path: &Path, text: &str) -> Result<(), DataError> {
    let mut s = Staged::new();
    s.add(path, text.as_bytes())?;
    s.commit().map(|_| ())
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
    let mut staged = Staged::new();
    let rec = stage_with_record(&mut staged, data, csv, record)?;
    staged.commit()?;
    Ok(rec)
}

/// [`write_with_record`] into `staged`, for commands that write more files
/// and commit them together. Returns the record's path.
pub fn stage_with_record(
    staged: &mut Staged,
    data: &Dataset,
    csv: &Path,
    record: &impl Serialize,
) -> Result<PathBuf, DataError> {
    let rec = record_path(csv);
    if same_file(&rec, csv) {
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
    staged.claim(&rec)?;
    staged.add(csv, data.to_csv().as_bytes())?;
    staged.add(&rec, text.as_bytes())?;
    Ok(rec)
}
