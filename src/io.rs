//! Reading a file no further than a limit, for every reader of the crate.

use std::io::Read;
use std::path::Path;

/// Why [`read_capped`] read nothing.
pub(crate) enum Capped {
    /// The OS refused.
    Io(std::io::Error),
    /// The file is larger than the limit: its size, or (a device or pipe
    /// that does not say its size) the bytes read before stopping.
    TooLarge(u64),
}

/// The bytes of the file at `path` if it holds at most `max` bytes: a file
/// that says it is larger is refused before it is read, and no more than
/// `max + 1` bytes are ever read (a device or pipe has no size to check).
pub(crate) fn read_capped(path: &Path, max: u64) -> Result<Vec<u8>, Capped> {
    let file = std::fs::File::open(path).map_err(Capped::Io)?;
    let size = file.metadata().map_err(Capped::Io)?.len();
    if size > max {
        return Err(Capped::TooLarge(size));
    }
    let mut bytes = Vec::with_capacity(size as usize);
    file.take(max.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(Capped::Io)?;
    if bytes.len() as u64 > max {
        return Err(Capped::TooLarge(bytes.len() as u64));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::{Capped, read_capped};

    /// The largest limit reads the whole file (`max + 1` once wrapped to
    /// 0 and read nothing: `sdpa --max-memory-gib 1e20` saw an empty file).
    #[test]
    fn any_limit_reads_a_file_within_it() {
        let p = std::env::temp_dir().join(format!("momentlmi-capped-{}", std::process::id()));
        std::fs::write(&p, b"12345").unwrap();
        for max in [5, 6, u64::MAX - 1, u64::MAX] {
            assert_eq!(
                read_capped(&p, max).ok().as_deref(),
                Some(&b"12345"[..]),
                "{max}"
            );
        }
        assert!(matches!(read_capped(&p, 4), Err(Capped::TooLarge(5))));
        let _ = std::fs::remove_file(&p);
    }
}
