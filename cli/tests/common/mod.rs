//! What the CLI tests share: the binary and a scratch folder per test.

#![allow(dead_code)] // each test file uses its own part

use std::path::PathBuf;
use std::process::Command;

/// The `momentlmi` binary under test.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_momentlmi"))
}

/// A scratch folder, emptied when made and removed when dropped.
pub struct TempDir(pub PathBuf);

impl TempDir {
    /// `momentlmi-<tag>-<pid>` in the system's temporary folder.
    pub fn new(tag: &str) -> Self {
        let d = std::env::temp_dir().join(format!("momentlmi-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        Self(d)
    }

    /// Writes `text` to `name` in the folder; returns its path.
    pub fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    /// The names in the folder, sorted.
    pub fn names(&self) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(&self.0)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs the binary with `args` and returns its stdout, failing the test
/// with its stderr if it does not exit 0.
pub fn ok(args: &[&str]) -> Vec<u8> {
    let o = bin().args(args).output().unwrap();
    assert!(
        o.status.success(),
        "momentlmi {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&o.stderr)
    );
    o.stdout
}
