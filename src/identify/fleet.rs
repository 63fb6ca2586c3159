//! Reduced data of parts of a data set added, and stored as bytes: the
//! fleet path. The reduction is a sum over samples, so files reduced apart
//! (on other threads, processes or machines) and added give the sums of
//! the whole, and one SDP is solved on them
//! ([`Identification::fit_streamed`](super::Identification::fit_streamed)).
//!
//! The bytes (little-endian): the magic `MLMIRED\0`, the format version
//! (u32), the robot's [`signature`] (u32 length, UTF-8), the samples (u64),
//! p (u64), the number of per-joint matrices kept (u64), then the lower
//! triangles, row by row, of the (p + 1)² Gram matrix and of each joint's
//! (f64). Reading checks each, and that the robot is the same.

use super::error::IdentifyError;
use super::reduce::Reduced;
use crate::dynamics::Model;
use faer::Mat;

const MAGIC: &[u8; 8] = b"MLMIRED\0";
/// The most samples sums may hold (10¹⁵: a thousand robots for thirty
/// years at 1 kHz), so that counts never overflow.
pub const MAX_SAMPLES: usize = 1_000_000_000_000_000;

/// The first entry of `g` that is not finite.
fn not_finite(g: &Mat<f64>) -> Option<(usize, usize)> {
    (0..g.ncols())
        .flat_map(|j| (0..g.nrows()).map(move |i| (i, j)))
        .find(|&(i, j)| !g[(i, j)].is_finite())
}

/// The version of the bytes [`Reduced::to_bytes`] writes.
pub const REDUCED_FORMAT_VERSION: u32 = 1;

/// What a reduction's sums depend on, by name: the joints, the bodies,
/// the friction terms and the Stribeck velocity (not the kinematics, which
/// the names are taken to stand for).
pub fn signature(model: &Model) -> String {
    let terms: Vec<&str> = model.friction_terms().iter().map(|t| t.name()).collect();
    format!(
        "joints {}; bodies {}; friction {}; stribeck {:e}; columns {}",
        model.joint_names().join(","),
        model.body_names().join(","),
        terms.join(","),
        model.stribeck_velocity(),
        model.regressor_columns()
    )
}

impl Reduced {
    /// The sums of `other` (samples of the same robot reduced apart)
    /// added; the per-joint matrices are kept only if both have them. An
    /// error if the sums stop being finite or the count passes [`MAX_SAMPLES`].
    pub fn merge(mut self, other: &Reduced) -> Result<Self, IdentifyError> {
        if other.p != self.p {
            let message = format!("{} regressor columns added to {}", other.p, self.p);
            return Err(IdentifyError::Stored(message));
        }
        let samples = (self.samples.checked_add(other.samples))
            .filter(|&k| k <= MAX_SAMPLES)
            .ok_or_else(|| {
                IdentifyError::Stored(format!("more than {MAX_SAMPLES} samples in all"))
            })?;
        self.gram += &other.gram;
        if let Some((i, j)) = not_finite(&self.gram) {
            let m =
                format!("entry ({i}, {j}) of the sums is not finite: the samples are too large");
            return Err(IdentifyError::Stored(m));
        }
        if self.joint_grams.len() == other.joint_grams.len() {
            let pairs = self.joint_grams.iter_mut().zip(&other.joint_grams);
            pairs.for_each(|(a, b)| *a += b);
        } else {
            self.joint_grams.clear();
        }
        self.samples = samples;
        self.reduce_time_s += other.reduce_time_s;
        // the rows kept for a load term are one part's: not the sum's
        self.load_rows = None;
        Ok(self)
    }

    /// The bytes of these sums, for `model` (see the module).
    pub fn to_bytes(&self, model: &Model) -> Vec<u8> {
        let sig = signature(model);
        let mut out = Vec::with_capacity(64 + sig.len() + 8 * self.gram.nrows().pow(2));
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&REDUCED_FORMAT_VERSION.to_le_bytes());
        out.extend_from_slice(&(sig.len() as u32).to_le_bytes());
        out.extend_from_slice(sig.as_bytes());
        for k in [self.samples, self.p, self.joint_grams.len()] {
            out.extend_from_slice(&(k as u64).to_le_bytes());
        }
        for g in std::iter::once(&self.gram).chain(&self.joint_grams) {
            for i in 0..g.nrows() {
                (0..=i).for_each(|j| out.extend_from_slice(&g[(i, j)].to_le_bytes()));
            }
        }
        out
    }

    /// The sums [`to_bytes`](Self::to_bytes) wrote, for `model`: an error
    /// naming what does not fit (not these bytes, another version or
    /// robot, cut short or too long, a value that is not finite).
    pub fn from_bytes(model: &Model, bytes: &[u8]) -> Result<Self, IdentifyError> {
        let bad = |m: String| IdentifyError::Stored(m);
        let mut r = Bytes(bytes);
        if r.take(8)? != MAGIC {
            return Err(bad("not momentlmi's reduced data (no MLMIRED mark)".into()));
        }
        let version = u32::from_le_bytes(r.array()?);
        if version != REDUCED_FORMAT_VERSION {
            let m = format!("format version {version}; this build reads {REDUCED_FORMAT_VERSION}");
            return Err(bad(m));
        }
        let len = u32::from_le_bytes(r.array()?) as usize;
        let sig = String::from_utf8_lossy(r.take(len)?).into_owned();
        if sig != signature(model) {
            let m = format!("of another robot ({sig}; this one: {})", signature(model));
            return Err(bad(m));
        }
        let [samples, p, joints] = [(); 3].map(|_| r.u64());
        let (samples, p, joints) = (samples?, p?, joints?);
        let joints_ok = joints == 0 || joints == model.dof();
        if p != model.regressor_columns() || !joints_ok || samples == 0 || samples > MAX_SAMPLES {
            let m = format!("{samples} samples, {p} columns, {joints} joints' matrices");
            return Err(bad(format!("{m}: not this robot's sums")));
        }
        let gram = r.lower(p + 1)?;
        let joint_grams = (0..joints)
            .map(|_| r.lower(p + 1))
            .collect::<Result<_, _>>()?;
        if !r.0.is_empty() {
            return Err(bad(format!("{} bytes past the end", r.0.len())));
        }
        let mut red = Reduced::from_gram(gram, samples)?;
        red.joint_grams = joint_grams;
        Ok(red)
    }
}

/// Bytes read from the front.
struct Bytes<'a>(&'a [u8]);

impl<'a> Bytes<'a> {
    fn take(&mut self, k: usize) -> Result<&'a [u8], IdentifyError> {
        if self.0.len() < k {
            return Err(IdentifyError::Stored("cut short".into()));
        }
        let (head, rest) = self.0.split_at(k);
        self.0 = rest;
        Ok(head)
    }

    fn array<const K: usize>(&mut self) -> Result<[u8; K], IdentifyError> {
        let mut a = [0; K];
        a.copy_from_slice(self.take(K)?);
        Ok(a)
    }

    fn u64(&mut self) -> Result<usize, IdentifyError> {
        let k = u64::from_le_bytes(self.array()?);
        usize::try_from(k).map_err(|_| IdentifyError::Stored(format!("a count of {k}")))
    }

    /// A symmetric matrix of side `n` from its lower triangle; an entry
    /// that is not finite is an error.
    fn lower(&mut self, n: usize) -> Result<Mat<f64>, IdentifyError> {
        let mut g = Mat::zeros(n, n);
        for i in 0..n {
            for j in 0..=i {
                let v = f64::from_le_bytes(self.array()?);
                if !v.is_finite() {
                    let m = format!("entry ({i}, {j}) is not finite");
                    return Err(IdentifyError::Stored(m));
                }
                (g[(i, j)], g[(j, i)]) = (v, v);
            }
        }
        Ok(g)
    }
}

#[cfg(test)]
mod tests {
    use crate::dynamics::robots::load_robot;
    use crate::identify::{Reduced, StreamReducer};

    /// The leg's samples reduced in four parts and added equal one
    /// reduction of all (to 1e-12 relative); the bytes give the same sums
    /// back, and bytes that are cut, altered or of another robot are
    /// errors that say so.
    #[test]
    fn parts_added_equal_the_whole_and_bytes_round_trip() {
        let leg = load_robot("cheetah3-leg", None).unwrap();
        let model = &leg.model;
        let n = model.dof();
        let state = |s: usize, k: f64| -> Vec<f64> {
            (0..n)
                .map(|j| (0.37 * s as f64 * k + j as f64).sin())
                .collect()
        };
        let reduce = |from: usize, to: usize| {
            let mut r = StreamReducer::starting_at(model, 64, from);
            for s in from..to {
                let (q, qd, qdd) = (state(s, 1.0), state(s, 1.3), state(s, 1.7));
                r.push(&q, &qd, &qdd, &state(s, 0.9)).unwrap();
            }
            r.finish().unwrap()
        };
        let whole = reduce(0, 1000);
        let parts = [(0, 130), (130, 500), (500, 501), (501, 1000)];
        let mut sum: Option<Reduced> = None;
        for (a, b) in parts {
            let part = reduce(a, b);
            sum = Some(match sum {
                None => part,
                Some(s) => s.merge(&part).unwrap(),
            });
        }
        let sum = sum.unwrap();
        assert_eq!(sum.samples, 1000);
        let scale = whole.gram.norm_max();
        assert!((&sum.gram - &whole.gram).norm_max() < 1e-12 * scale);
        assert_eq!(sum.joint_grams.len(), n);
        let bytes = sum.to_bytes(model);
        let back = Reduced::from_bytes(model, &bytes).unwrap();
        assert_eq!((back.gram, back.samples), (sum.gram.clone(), 1000));
        assert_eq!(back.joint_grams, sum.joint_grams);
        let err = |b: &[u8]| Reduced::from_bytes(model, b).unwrap_err().to_string();
        assert!(err(&bytes[..bytes.len() - 3]).contains("cut short"));
        assert!(err(&[&bytes[..], &[0]].concat()).contains("past the end"));
        assert!(err(b"PK\x03\x04 not these").contains("no MLMIRED mark"));
        let mut v2 = bytes.clone();
        v2[8] = 2;
        assert!(err(&v2).contains("format version 2"));
        // a part of the joints' matrices, or a count past the limit, is refused
        let n_at = 8 + 4 + 4 + super::signature(model).len() + 16;
        let mut one = bytes.clone();
        one[n_at..n_at + 8].copy_from_slice(&1u64.to_le_bytes());
        assert!(err(&one).contains("not this robot's sums"));
        let mut many = bytes.clone();
        many[n_at - 16..n_at - 8].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(err(&many).contains("not this robot's sums"));
        let mut nan = bytes.clone();
        let end = nan.len();
        nan[end - 8..].copy_from_slice(&f64::NAN.to_le_bytes());
        assert!(err(&nan).contains("is not finite"));
        let other = model.clone().with_friction_terms(&[]);
        let e = Reduced::from_bytes(&other, &bytes).unwrap_err().to_string();
        assert!(e.contains("of another robot"), "{e}");
    }
}
