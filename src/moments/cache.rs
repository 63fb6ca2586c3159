//! Solved bounding ellipsoids kept on disk, keyed by the content of what
//! was solved: a mesh's minimum-volume ellipsoid (its distinct vertices and
//! scale) and a body's covering ellipsoid (its parts). A URDF whose meshes
//! have been seen once costs a file read per shape afterwards instead of a
//! conic solve.
//!
//! A key is the SHA-256 of a tag naming the computation and its version
//! ([`CACHE_VERSION`]) and the exact bits of its inputs, so a changed mesh,
//! scale, tolerance or algorithm is a different key; nothing is ever
//! invalidated in place. An entry is one file `<key>.ell` of 160 bytes: a
//! magic, the ellipsoid's 15 numbers (centre, semi-axes, rotation by
//! columns, little-endian `f64` bits) and the SHA-256 of the key and those
//! numbers, so a truncated or altered entry is a miss (and is rewritten),
//! never a wrong ellipsoid. Entries are written to a temporary file
//! ([`crate::tempfiles`]) and renamed into place: concurrent runs read
//! whole entries or none.

use super::ellipsoid::Ellipsoid;
use nalgebra::{Matrix3, Vector3};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// Part of every key: bump it when an algorithm behind a cached result
/// changes what it returns.
pub const CACHE_VERSION: u32 = 1;

const MAGIC: &[u8; 8] = b"MLMIELL1";
const ENTRY_BYTES: usize = 8 + 15 * 8 + 32;

/// The key of one cached computation: the SHA-256 of its tag and inputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CacheKey([u8; 32]);

impl CacheKey {
    /// The key of computation `tag` (e.g. `"mesh-mvee tol=1e-7"`) on
    /// `inputs` (their exact bits).
    pub fn new(tag: &str, inputs: impl IntoIterator<Item = f64>) -> Self {
        let mut h = Sha256::new();
        h.update(CACHE_VERSION.to_le_bytes());
        h.update((tag.len() as u64).to_le_bytes());
        h.update(tag.as_bytes());
        for x in inputs {
            h.update(x.to_bits().to_le_bytes());
        }
        Self(h.finalize().into())
    }

    /// The key of computation `tag` on the ellipsoids `parts` (each one's
    /// centre, semi-axes and rotation).
    pub fn of_ellipsoids(tag: &str, parts: &[Ellipsoid]) -> Self {
        Self::new(tag, parts.iter().flat_map(numbers))
    }

    /// The key in hexadecimal (the entry's file stem).
    pub fn hex(&self) -> String {
        self.0.iter().map(|b| format!("{b:02x}")).collect()
    }

    /// The key whose [`Self::hex`] is `hex` (an entry's file stem), if it
    /// is 64 hexadecimal digits.
    pub fn from_hex(hex: &str) -> Option<Self> {
        let digits = hex.as_bytes();
        if digits.len() != 64 || !digits.iter().all(u8::is_ascii_hexdigit) {
            return None;
        }
        let mut key = [0u8; 32];
        for (k, pair) in key.iter_mut().zip(digits.chunks_exact(2)) {
            let text = std::str::from_utf8(pair).ok()?;
            *k = u8::from_str_radix(text, 16).ok()?;
        }
        Some(Self(key))
    }
}

/// A folder of solved ellipsoids ([module docs](self)).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SolveCache {
    dir: PathBuf,
}

impl SolveCache {
    /// The cache the command line uses: the folder `MOMENTLMI_CACHE_DIR`
    /// names (empty or `off`: none), else `$XDG_CACHE_HOME/momentlmi`, else
    /// `$HOME/.cache/momentlmi`.
    pub fn from_env() -> Option<Self> {
        let var = |k: &str| std::env::var_os(k).filter(|v| !v.is_empty());
        if let Some(dir) = std::env::var_os("MOMENTLMI_CACHE_DIR") {
            return (!dir.is_empty() && dir != "off").then(|| Self::new(dir));
        }
        let base = var("XDG_CACHE_HOME")
            .map(PathBuf::from)
            .or_else(|| var("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
        Some(Self::new(base.join("momentlmi")))
    }

    /// The cache in folder `dir` (made when the first entry is written).
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        Self { dir: dir.into() }
    }

    /// The cache's folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn path(&self, key: &CacheKey) -> PathBuf {
        self.dir.join(format!("{}.ell", key.hex()))
    }

    /// The ellipsoid stored under `key`, if a whole, intact entry is there.
    pub fn get(&self, key: &CacheKey) -> Option<Ellipsoid> {
        let bytes = std::fs::read(self.path(key)).ok()?;
        decode(key, &bytes)
    }

    /// Stores `e` under `key` (written whole, then renamed into place).
    pub fn put(&self, key: &CacheKey, e: &Ellipsoid) -> std::io::Result<()> {
        use std::io::Write;
        if self.dir.exists() && !self.dir.is_dir() {
            let kind = std::io::ErrorKind::NotADirectory;
            return Err(std::io::Error::new(kind, "not a folder"));
        }
        std::fs::create_dir_all(&self.dir)?;
        let mut tmp = crate::tempfiles::TempFile::new_in(&self.dir, ".momentlmi-cache-")?;
        tmp.write_all(&encode(key, e))?;
        tmp.persist(&self.path(key))
    }

    /// The ellipsoid under `key`, else `solve`'s, stored for next time.
    /// A failed store is returned beside the result (the result stands).
    pub fn get_or_solve<E>(
        &self,
        key: &CacheKey,
        solve: impl FnOnce() -> Result<Ellipsoid, E>,
    ) -> Result<(Ellipsoid, Option<std::io::Error>), E> {
        if let Some(e) = self.get(key) {
            return Ok((e, None));
        }
        let e = solve()?;
        Ok((e, self.put(key, &e).err()))
    }
}

fn numbers(e: &Ellipsoid) -> impl Iterator<Item = f64> + '_ {
    (e.center.iter())
        .chain(e.semi_axes.iter())
        .chain(e.rotation.iter())
        .copied()
}

fn checksum(key: &CacheKey, payload: &[u8]) -> [u8; 32] {
    let mut h = Sha256::new();
    h.update(key.0);
    h.update(payload);
    h.finalize().into()
}

fn encode(key: &CacheKey, e: &Ellipsoid) -> Vec<u8> {
    let mut out = MAGIC.to_vec();
    out.extend(numbers(e).flat_map(|x| x.to_le_bytes()));
    let sum = checksum(key, &out[MAGIC.len()..]);
    out.extend(sum);
    out
}

fn decode(key: &CacheKey, bytes: &[u8]) -> Option<Ellipsoid> {
    if bytes.len() != ENTRY_BYTES || &bytes[..MAGIC.len()] != MAGIC {
        return None;
    }
    let (payload, sum) = bytes[MAGIC.len()..].split_at(15 * 8);
    if checksum(key, payload) != sum {
        return None;
    }
    let x: Vec<f64> = payload
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect();
    Ellipsoid::with_rotation(
        Vector3::from_column_slice(&x[0..3]),
        Vector3::from_column_slice(&x[3..6]),
        Matrix3::from_column_slice(&x[6..15]),
    )
    .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Ellipsoid {
        let r = super::super::ellipsoid::rpy_rotation([0.3, -0.2, 1.1]);
        Ellipsoid::with_rotation(
            Vector3::new(0.1, -0.2, 0.3),
            Vector3::new(0.4, 0.05, 0.2),
            r,
        )
        .unwrap()
    }

    #[test]
    fn an_entry_round_trips_bit_for_bit() {
        let dir = tempfile::tempdir().unwrap();
        let cache = SolveCache::new(dir.path().join("sub"));
        let key = CacheKey::new("test", [1.0, 2.0]);
        assert_eq!(cache.get(&key), None);
        cache.put(&key, &sample()).unwrap();
        assert_eq!(cache.get(&key), Some(sample()));
        // no temporary file left beside the entry
        let names: Vec<_> = std::fs::read_dir(cache.dir()).unwrap().collect();
        assert_eq!(names.len(), 1);
    }

    #[test]
    fn keys_differ_with_tag_inputs_and_their_bits() {
        let k = CacheKey::new("a", [1.0, 2.0]);
        assert_ne!(k, CacheKey::new("b", [1.0, 2.0]));
        assert_ne!(k, CacheKey::new("a", [1.0, 2.0, 0.0]));
        assert_ne!(CacheKey::new("a", [0.0]), CacheKey::new("a", [-0.0]));
        assert_eq!(k, CacheKey::new("a", [1.0, 2.0]));
        assert_eq!(CacheKey::from_hex(&k.hex()), Some(k));
        assert_eq!(CacheKey::from_hex(&k.hex()[1..]), None);
        assert_eq!(CacheKey::from_hex(&format!("{}g", &k.hex()[1..])), None);
        assert_eq!(CacheKey::from_hex(&format!("+{}", &k.hex()[1..])), None);
    }

    #[test]
    fn a_damaged_or_foreign_entry_is_a_miss() {
        let dir = tempfile::tempdir().unwrap();
        let cache = SolveCache::new(dir.path());
        let (k1, k2) = (CacheKey::new("a", [1.0]), CacheKey::new("a", [2.0]));
        cache.put(&k1, &sample()).unwrap();
        let good = std::fs::read(cache.path(&k1)).unwrap();
        // another key's entry copied under this key
        std::fs::write(cache.path(&k2), &good).unwrap();
        assert_eq!(cache.get(&k2), None);
        // one bit flipped in the numbers
        let mut bad = good.clone();
        bad[20] ^= 1;
        std::fs::write(cache.path(&k1), &bad).unwrap();
        assert_eq!(cache.get(&k1), None);
        // truncated
        std::fs::write(cache.path(&k1), &good[..100]).unwrap();
        assert_eq!(cache.get(&k1), None);
        // get_or_solve rewrites it
        let (e, err) = cache.get_or_solve(&k1, || Ok::<_, ()>(sample())).unwrap();
        assert!(err.is_none());
        assert_eq!(e, sample());
        assert_eq!(std::fs::read(cache.path(&k1)).unwrap(), good);
    }

    #[test]
    fn an_unwritable_cache_returns_the_solve_and_the_error() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a-file");
        std::fs::write(&file, b"x").unwrap();
        let cache = SolveCache::new(&file); // a file where the folder should be
        let (e, err) = cache
            .get_or_solve(&CacheKey::new("a", [1.0]), || Ok::<_, ()>(sample()))
            .unwrap();
        assert_eq!(e, sample());
        assert!(err.unwrap().to_string().contains("not a folder"));
    }
}
