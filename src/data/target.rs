//! What an output path names, and so how it is written: a regular file (or
//! a new one) is staged beside its real location and renamed into place; a
//! character device, a FIFO or standard output is written in place, whole,
//! when the command commits; a folder, a block device or a socket is
//! refused by name.

use super::error::DataError;
use std::path::{Path, PathBuf};

/// The names of standard output: `-`, and the system's paths to it.
pub const STDOUT_NAMES: [&str; 4] = ["-", "/dev/stdout", "/dev/fd/1", "/proc/self/fd/1"];

/// Symbolic links followed before giving up (the system's own limit).
const MAX_LINKS: usize = 40;

/// How an output path is written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Target {
    /// A regular file, existing or not, at this path (symbolic links
    /// resolved: the link stays and the file it names is replaced).
    File(PathBuf),
    /// The process's standard output.
    Stdout,
    /// A character device or a FIFO, opened for writing (never replaced).
    Stream(PathBuf),
}

impl Target {
    /// What `path` names now ([module docs](self)).
    pub fn of(path: &Path) -> Result<Self, DataError> {
        let refuse = |message: &str| DataError::Output {
            path: path.display().to_string(),
            message: message.into(),
        };
        let resolved = resolve_links(path)?;
        if resolved.iter().any(|p| is_stdout_name(p)) {
            return Ok(Self::Stdout);
        }
        let last = resolved
            .last()
            .cloned()
            .unwrap_or_else(|| path.to_path_buf());
        let meta = match std::fs::metadata(&last) {
            Ok(m) => m,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Self::File(last)),
            Err(source) => {
                return Err(DataError::Io {
                    path: path.display().to_string(),
                    source,
                });
            }
        };
        let kind = meta.file_type();
        if kind.is_file() {
            return Ok(Self::File(last));
        }
        if kind.is_dir() {
            return Err(refuse("is a folder; an output file cannot replace it"));
        }
        special(&kind, &last).map_err(|m| refuse(&m))
    }

    /// Whether the output is a regular file (renamed into place).
    pub fn is_file(&self) -> bool {
        matches!(self, Self::File(_))
    }
}

/// A path that is standard output by name.
fn is_stdout_name(p: &Path) -> bool {
    STDOUT_NAMES.iter().any(|n| p == Path::new(n))
}

/// `path` and every path its symbolic links lead to, in order (a relative
/// link read from the link's folder); stops at the first that is not a
/// link, or at a name of standard output (which the system resolves per
/// process).
fn resolve_links(path: &Path) -> Result<Vec<PathBuf>, DataError> {
    let mut chain = vec![path.to_path_buf()];
    for _ in 0..MAX_LINKS {
        let p = chain.last().expect("one at least");
        if is_stdout_name(p) {
            return Ok(chain);
        }
        let Ok(meta) = std::fs::symlink_metadata(p) else {
            return Ok(chain); // does not exist (yet)
        };
        if !meta.file_type().is_symlink() {
            return Ok(chain);
        }
        let to = std::fs::read_link(p).map_err(|source| DataError::Io {
            path: p.display().to_string(),
            source,
        })?;
        let next = match p.parent() {
            Some(dir) if to.is_relative() => dir.join(to),
            _ => to,
        };
        chain.push(next);
    }
    Err(DataError::Output {
        path: path.display().to_string(),
        message: format!("more than {MAX_LINKS} symbolic links to follow"),
    })
}

/// A special file as a target, or why it is refused.
#[cfg(unix)]
fn special(kind: &std::fs::FileType, path: &Path) -> Result<Target, String> {
    use std::os::unix::fs::FileTypeExt;
    if kind.is_char_device() || kind.is_fifo() {
        Ok(Target::Stream(path.to_path_buf()))
    } else if kind.is_block_device() {
        Err("is a block device (a disk or a partition); refusing to write to it".into())
    } else if kind.is_socket() {
        Err(
            "is a socket; an output is a file, a FIFO, a character device or - (standard output)"
                .into(),
        )
    } else {
        Err("is neither a file nor a device this command can write to".into())
    }
}

#[cfg(not(unix))]
fn special(_: &std::fs::FileType, _: &Path) -> Result<Target, String> {
    Err("is neither a file nor a device this command can write to".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_links_and_standard_output_are_told_apart() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let new = d.join("new.csv");
        assert_eq!(Target::of(&new).unwrap(), Target::File(new.clone()));
        std::fs::write(&new, "x").unwrap();
        assert_eq!(Target::of(&new).unwrap(), Target::File(new.clone()));
        for name in STDOUT_NAMES {
            assert_eq!(Target::of(Path::new(name)).unwrap(), Target::Stdout);
        }
        let e = Target::of(d).unwrap_err().to_string();
        assert!(e.contains("is a folder"), "{e}");
        #[cfg(unix)]
        {
            let sub = d.join("sub");
            std::fs::create_dir(&sub).unwrap();
            // a relative link into another folder, and a dangling one
            std::os::unix::fs::symlink("../new.csv", sub.join("link.csv")).unwrap();
            assert_eq!(
                Target::of(&sub.join("link.csv")).unwrap(),
                Target::File(sub.join("../new.csv"))
            );
            std::os::unix::fs::symlink(d.join("later.csv"), d.join("dangling")).unwrap();
            assert_eq!(
                Target::of(&d.join("dangling")).unwrap(),
                Target::File(d.join("later.csv"))
            );
            std::os::unix::fs::symlink("/dev/stdout", d.join("out")).unwrap();
            assert_eq!(Target::of(&d.join("out")).unwrap(), Target::Stdout);
            assert_eq!(
                Target::of(Path::new("/dev/null")).unwrap(),
                Target::Stream("/dev/null".into())
            );
            std::os::unix::fs::symlink(d.join("loop"), d.join("loop")).unwrap();
            let e = Target::of(&d.join("loop")).unwrap_err().to_string();
            assert!(e.contains("symbolic links"), "{e}");
        }
    }
}
