//! Every named temporary file the crate writes (staged outputs beside their
//! targets, cache entries before their rename), registered while it exists,
//! so that a process interrupted by a signal can remove them all
//! ([`remove_all`]) before it exits: a program's signal handler calls it
//! (the `momentlmi` CLI does on SIGINT and SIGTERM; the library installs no
//! handler).
//!
//! A [`TempFile`] is created, renamed into place ([`TempFile::persist`]) and
//! dropped (deleted) under the registry's lock, so [`remove_all`] sees each
//! file either registered or gone, never in between.

use std::collections::HashSet;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

static LIVE: Mutex<Option<HashSet<PathBuf>>> = Mutex::new(None);

fn live() -> MutexGuard<'static, Option<HashSet<PathBuf>>> {
    // a thread that panicked while holding the lock left the set whole
    LIVE.lock().unwrap_or_else(|e| e.into_inner())
}

/// A named temporary file, registered from its creation until it is
/// renamed into place or deleted.
pub struct TempFile {
    file: Option<tempfile::NamedTempFile>,
}

impl TempFile {
    /// A new file `PREFIX*.tmp` in `dir` (e.g. prefix `.momentlmi-`).
    pub fn new_in(dir: &Path, prefix: &str) -> io::Result<Self> {
        let mut set = live();
        let file = tempfile::Builder::new()
            .prefix(prefix)
            .suffix(".tmp")
            .tempfile_in(dir)?;
        set.get_or_insert_with(HashSet::new)
            .insert(file.path().to_path_buf());
        Ok(Self { file: Some(file) })
    }

    /// The open file.
    pub fn as_file(&self) -> &std::fs::File {
        self.inner().as_file()
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        self.inner().path()
    }

    fn inner(&self) -> &tempfile::NamedTempFile {
        self.file
            .as_ref()
            .expect("present until persisted or dropped")
    }

    /// Renames the file to `target` (replacing it) and unregisters it
    /// ([`persist_all`] of one).
    pub fn persist(self, target: &Path) -> io::Result<()> {
        persist_all(vec![(self, target.to_path_buf())]).map_err(|(_, e)| e)
    }
}

impl io::Write for TempFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.file.as_mut().expect("present").write(buf)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.file.as_mut().expect("present").flush()
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if let Some(file) = self.file.take() {
            let mut set = live();
            unregister(&mut set, file.path());
            let _ = file.close(); // removed while the lock is held
        }
    }
}

fn unregister(set: &mut Option<HashSet<PathBuf>>, path: &Path) {
    if let Some(s) = set.as_mut() {
        s.remove(path);
    }
}

/// Renames each file onto its target, in order, all under the registry's
/// lock: a signal handler sees the whole set renamed or none of it. On a
/// failure, the files before it are in place, it and the rest are deleted,
/// and its target and error are returned.
pub fn persist_all(files: Vec<(TempFile, PathBuf)>) -> Result<(), (PathBuf, io::Error)> {
    let mut set = live();
    let mut rest = files.into_iter();
    for (mut temp, target) in rest.by_ref() {
        let file = temp
            .file
            .take()
            .expect("present until persisted or dropped");
        let path = file.path().to_path_buf();
        match file.persist(&target) {
            Ok(_) => unregister(&mut set, &path),
            Err(e) => {
                unregister(&mut set, &path);
                let _ = e.file.close();
                for (mut t, _) in rest {
                    if let Some(f) = t.file.take() {
                        unregister(&mut set, f.path());
                        let _ = f.close();
                    }
                }
                return Err((target, e.error));
            }
        }
    }
    Ok(())
}

/// Removes every registered temporary file; returns how many were removed.
/// For a signal handler about to exit the process: the lock is left held
/// (no file can be created or renamed afterwards).
pub fn remove_all() -> usize {
    let mut set = live();
    let paths = set.take().unwrap_or_default();
    let removed = paths
        .iter()
        .filter(|p| std::fs::remove_file(p).is_ok())
        .count();
    std::mem::forget(set);
    removed
}

/// The registered temporary files now (for tests and diagnostics).
pub fn registered() -> Vec<PathBuf> {
    live()
        .as_ref()
        .map_or(vec![], |s| s.iter().cloned().collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn files_are_registered_until_persisted_or_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let mut a = TempFile::new_in(dir.path(), ".t-").unwrap();
        let b = TempFile::new_in(dir.path(), ".t-").unwrap();
        let (pa, pb) = (a.path().to_path_buf(), b.path().to_path_buf());
        assert!(registered().contains(&pa) && registered().contains(&pb));
        a.write_all(b"hello").unwrap();
        let target = dir.path().join("out.txt");
        a.persist(&target).unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"hello");
        assert!(!registered().contains(&pa));
        drop(b);
        assert!(!registered().contains(&pb) && !pb.exists());
        // a failed rename keeps the file registered until it is dropped
        let c = TempFile::new_in(dir.path(), ".t-").unwrap();
        let pc = c.path().to_path_buf();
        assert!(c.persist(&dir.path().join("no/such/folder/x")).is_err());
        assert!(!registered().contains(&pc) && !pc.exists());
    }
}
