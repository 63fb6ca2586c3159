//! Outputs written whole or not at all, and the JSON record beside a CSV.

use super::dataset::Dataset;
use super::error::DataError;
use super::target::Target;
use crate::tempfiles::TempFile;
use serde::Serialize;
use std::io::{Seek, Write};
use std::path::{Path, PathBuf};

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> DataError + '_ {
    move |source| DataError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// One staged output: a named temporary file beside a regular target, or
/// an unnamed one (nothing on disk to leave behind) for standard output
/// (`to: None`), a character device or a FIFO.
enum Entry {
    File {
        temp: TempFile,
        to: PathBuf,
    },
    Stream {
        temp: std::fs::File,
        to: Option<PathBuf>,
    },
}

/// Outputs staged in temporary files and put in place together by
/// [`Staged::commit`]. A regular file (or a new one; through symbolic
/// links, which stay) is staged beside its target and renamed onto it: a
/// reader sees the old files or the whole new set. Standard output (`-`,
/// `/dev/stdout`), a character device or a FIFO is written in place, whole,
/// before the renames; a folder, a block device or a socket is refused by
/// name ([`Target`]). A command that fails before committing leaves
/// nothing (the temporary files are removed when the `Staged` is dropped,
/// and by [`crate::tempfiles::remove_all`] on a signal). Commits into the
/// same folders are serialised by a lock on each folder, so two runs that
/// write the same set leave one run's set whole. No temporary name can be
/// an input or a file the user keeps.
#[derive(Default)]
pub struct Staged {
    files: Vec<(Entry, PathBuf)>,
    inputs: Vec<PathBuf>,
}

impl Staged {
    /// Nothing staged.
    pub fn new() -> Self {
        Self::default()
    }

    /// Nothing staged yet, and none of `inputs` (the files the command
    /// reads) may be staged as an output.
    pub fn protecting(inputs: impl IntoIterator<Item = impl AsRef<Path>>) -> Self {
        Self {
            files: vec![],
            inputs: (inputs.into_iter())
                .map(|p| p.as_ref().to_path_buf())
                .collect(),
        }
    }

    /// What `path` would be written as, or why it is refused: one of the
    /// protected inputs, already staged, a folder, a block device or a
    /// socket ([`Target::of`]). Call it before the work to fail early.
    pub fn claim(&self, path: &Path) -> Result<Target, DataError> {
        let refuse = |message: String| DataError::Output {
            path: path.display().to_string(),
            message,
        };
        let target = Target::of(path)?;
        if let Some(i) = self.inputs.iter().find(|i| same_target(i, &target)) {
            return Err(refuse(format!(
                "is also an input of this command ({}); choose another output name",
                i.display()
            )));
        }
        if self.files.iter().any(|(e, _)| e.target() == target) {
            let what = match target {
                Target::Stdout => "standard output already takes another output of this command",
                _ => "written twice by the same command",
            };
            return Err(refuse(what.into()));
        }
        Ok(target)
    }

    /// Whether an output staged so far goes to standard output (a command
    /// then prints its summary elsewhere).
    pub fn writes_stdout(&self) -> bool {
        self.files.iter().any(|(e, _)| e.target() == Target::Stdout)
    }

    /// Stages `text` for `path` (see [`Staged::add`]).
    pub fn add_text(&mut self, path: &Path, text: &str) -> Result<(), DataError> {
        self.add(path, text.as_bytes())
    }

    /// Stages `bytes` for `path`; a path [`Staged::claim`] refuses is
    /// refused.
    pub fn add(&mut self, path: &Path, bytes: &[u8]) -> Result<(), DataError> {
        let entry = match self.claim(path)? {
            Target::File(to) => stage_file(&to, bytes),
            Target::Stdout => stage_stream(None, bytes),
            Target::Stream(to) => stage_stream(Some(to), bytes),
        }
        .map_err(io(path))?;
        self.files.push((entry, path.to_path_buf()));
        Ok(())
    }

    /// Puts every staged output in place: the streams written first (a
    /// stream that cannot take them, `/dev/full` or a closed pipe, fails the
    /// commit before any file is renamed: the files stay as they were), then
    /// the regular files renamed together (their folders locked meanwhile);
    /// returns their paths as given.
    pub fn commit(self) -> Result<Vec<PathBuf>, DataError> {
        let mut renames = vec![];
        let mut streams = vec![];
        let mut done = Vec::with_capacity(self.files.len());
        for (entry, named) in self.files {
            match entry {
                Entry::File { temp, to } => renames.push((temp, to)),
                Entry::Stream { temp, to } => streams.push((temp, to, named.clone())),
            }
            done.push(named);
        }
        for (temp, to, named) in streams {
            write_stream(temp, to.as_deref()).map_err(io(&named))?;
        }
        let _locks = lock_folders(renames.iter().map(|(_, to)| to.as_path()))?;
        crate::tempfiles::persist_all(renames).map_err(|(to, e)| io(&to)(e))?;
        Ok(done)
    }
}

impl Entry {
    fn target(&self) -> Target {
        match self {
            Entry::File { to, .. } => Target::File(to.clone()),
            Entry::Stream { to: None, .. } => Target::Stdout,
            Entry::Stream { to: Some(p), .. } => Target::Stream(p.clone()),
        }
    }
}

/// `bytes` in a new temporary file beside `to`, with `to`'s permissions
/// (an existing file's, else rw-r--r--; a temporary file is private).
fn stage_file(to: &Path, bytes: &[u8]) -> std::io::Result<Entry> {
    let dir = match to.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut temp = TempFile::new_in(dir, ".momentlmi-")?;
    temp.write_all(bytes)?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(to).map_or(0o644, |m| m.permissions().mode());
        temp.as_file()
            .set_permissions(std::fs::Permissions::from_mode(mode))?;
    }
    Ok(Entry::File {
        temp,
        to: to.to_path_buf(),
    })
}

/// `bytes` in an unnamed temporary file, for standard output (`to: None`)
/// or the device or FIFO `to`.
fn stage_stream(to: Option<PathBuf>, bytes: &[u8]) -> std::io::Result<Entry> {
    let mut temp = tempfile::tempfile()?;
    temp.write_all(bytes)?;
    Ok(Entry::Stream { temp, to })
}

/// Exclusive locks on the folders of `targets` (each once, in one order,
/// so that two commits cannot wait on each other), held while the guards
/// live. A file system without locks is not an error.
fn lock_folders<'a>(
    targets: impl Iterator<Item = &'a Path>,
) -> Result<Vec<std::fs::File>, DataError> {
    let mut dirs: Vec<PathBuf> = targets
        .map(|t| match t.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        })
        .map(|d| d.canonicalize().unwrap_or_else(|_| d.to_path_buf()))
        .collect();
    dirs.sort();
    dirs.dedup();
    let mut locks = Vec::with_capacity(dirs.len());
    for d in dirs {
        let Ok(f) = std::fs::File::open(&d) else {
            continue; // a folder that cannot be opened is not lockable; the rename says more
        };
        match f.lock() {
            Ok(()) => locks.push(f),
            Err(e) if e.kind() == std::io::ErrorKind::Unsupported => {}
            Err(e) => return Err(io(&d)(e)),
        }
    }
    Ok(locks)
}

/// The staged bytes in `temp` written to standard output (`to: None`) or
/// to the device or FIFO `to` (opened for writing, never created or
/// replaced).
fn write_stream(mut temp: std::fs::File, to: Option<&Path>) -> std::io::Result<()> {
    temp.rewind()?;
    let mut out: Box<dyn Write> = match to {
        None => Box::new(std::io::stdout().lock()),
        Some(p) => Box::new(std::fs::OpenOptions::new().write(true).open(p)?),
    };
    std::io::copy(&mut temp, &mut out)?;
    out.flush()
}

/// Whether the output `target` is the file `input` (standard output is
/// never an input).
fn same_target(input: &Path, target: &Target) -> bool {
    match target {
        Target::Stdout => false,
        Target::File(p) | Target::Stream(p) => same_file(input, p),
    }
}

/// Whether two paths name the same file: by identity when both are regular
/// files (the same device and inode on Unix, so a hard link or another spelling is
/// caught), else by canonical path, else textually after canonicalising the
/// directory.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b))
        && x.is_file()
        && y.is_file()
    {
        use std::os::unix::fs::MetadataExt;
        return (x.dev(), x.ino()) == (y.dev(), y.ino());
    }
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
    if !staged.claim(csv)?.is_file() {
        return Err(DataError::Output {
            path: csv.display().to_string(),
            message: "a data file is written with its JSON record beside it, so it must be a regular file (not standard output, a device or a FIFO)".into(),
        });
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs::TryLockError;

    /// A commit holds its outputs' folders: while one holds them, another
    /// (any process: a lock belongs to its open folder) cannot take them,
    /// and can once it is done. Commits of the same set are thus one after
    /// the other, each set renamed whole.
    #[test]
    fn a_commit_holds_its_folders_until_done() {
        let (one, two) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
        let targets = [
            one.path().join("a.csv"),
            two.path().join("b.csv"),
            one.path().join("c.json"),
        ];
        let held = lock_folders(targets.iter().map(PathBuf::as_path)).unwrap();
        assert_eq!(held.len(), 2, "each folder once");
        for d in [one.path(), two.path()] {
            let other = std::fs::File::open(d).unwrap();
            assert!(matches!(other.try_lock(), Err(TryLockError::WouldBlock)));
        }
        drop(held);
        for d in [one.path(), two.path()] {
            std::fs::File::open(d).unwrap().try_lock().unwrap();
        }
    }

    /// A set committed while a signal handler may run: the files are
    /// renamed under the temporary-file registry's lock, so the handler
    /// sees them all staged or all in place; nothing is left registered.
    #[test]
    fn a_commit_leaves_nothing_registered() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = Staged::new();
        s.add_text(&dir.path().join("a.csv"), "1").unwrap();
        s.add_text(&dir.path().join("a.json"), "1").unwrap();
        let staged: Vec<PathBuf> = crate::tempfiles::registered()
            .into_iter()
            .filter(|p| p.starts_with(dir.path()))
            .collect();
        assert_eq!(staged.len(), 2);
        s.commit().unwrap();
        assert!(
            crate::tempfiles::registered()
                .iter()
                .all(|p| !p.starts_with(dir.path()))
        );
        assert!(staged.iter().all(|p| !p.exists()));
    }
}
