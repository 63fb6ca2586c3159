//! A floating-base robot standing on force plates: the feet stay where the
//! stance posture put them while the base sways and tilts along a smooth
//! random motion (positions, roll, pitch and yaw each a Fourier series);
//! the joints follow by inverse kinematics, and each foot's plate measures
//! its point force (world axes; the moment about the foot is zero, its
//! columns carry the plate's moment noise). The forces are the base rows'
//! required wrench split among the feet by least norm (each inside its
//! friction cone, else an error), and the joint torques are the joint
//! rows less the feet's share: `τ = g_joints − J_jointsᵀ f`. The joint
//! velocities and accelerations are the least-norm solutions of the feet's
//! velocity and acceleration constraints: the time derivatives of the
//! inverse kinematics' path when each leg has as many joints as its foot
//! has coordinates (three, as Solo12's).
//! Noise as for [`simulate_suspended`](super::floating::simulate_suspended).

use super::error::SimError;
use super::floating::{FloatingEffects, FloatingNoise, add_noise, channels, coefficients};
use crate::data::Dataset;
use crate::dynamics::{ContactWrench, Data, Model, WrenchFrame};
use nalgebra::{DMatrix, DVector, Matrix3, UnitQuaternion, Vector3};
use rand::SeedableRng;
use rand::rngs::StdRng;

/// The stance, the motion's amplitudes, the log's rate and length.
#[derive(Clone, Debug, PartialEq)]
pub struct StandingConfig {
    /// The contact frames (feet), each on its own force plate.
    pub feet: Vec<String>,
    /// Joint positions (n) of the stance: the feet are placed where this
    /// posture puts them, the base level above the lowest foot.
    pub posture: Vec<f64>,
    /// Seconds of log.
    pub seconds: f64,
    /// Samples per second.
    pub rate: f64,
    /// Random seed of the motion and the noise.
    pub seed: u64,
    /// Base displacement amplitude per harmonic (m).
    pub sway: f64,
    /// Base roll, pitch and yaw amplitude per harmonic (rad).
    pub tilt: f64,
    /// Friction coefficient of the plates: every foot's tangential force
    /// is at most this times its normal force.
    pub friction: f64,
    /// Sensor noise (the plates' as the load cell's).
    pub noise: FloatingNoise,
    /// Effects the nominal model lacks (a wrench offset on every plate).
    pub effects: FloatingEffects,
}

impl StandingConfig {
    /// Defaults: 20 s at 200 Hz, 1 cm sway and 0.04 rad tilt per harmonic,
    /// μ = 0.8.
    pub fn new(feet: Vec<String>, posture: Vec<f64>) -> Self {
        Self {
            feet,
            posture,
            seconds: 20.0,
            rate: 200.0,
            seed: 1,
            sway: 0.01,
            tilt: 0.04,
            friction: 0.8,
            noise: FloatingNoise::default(),
            effects: FloatingEffects::default(),
        }
    }
}

/// The base's pose and motion (world position and its rates, orientation,
/// body angular velocity and its rate) at one time.
struct BaseMotion {
    p: [Vector3<f64>; 3],
    rot: UnitQuaternion<f64>,
    omega: Vector3<f64>,
    omega_dot: Vector3<f64>,
}

/// Position offsets (x, y, z) then roll, pitch, yaw, each `[x, ẋ, ẍ]`,
/// to the base motion: `R = Rz(ψ) Ry(θ) Rx(φ)`, ω in base axes.
fn base_motion(origin: Vector3<f64>, c: &[[f64; 3]]) -> BaseMotion {
    let p = [0, 1, 2].map(|d| Vector3::new(c[0][d], c[1][d], c[2][d]));
    let ([f, fd, fdd], [th, thd, thdd], [ps, psd, psdd]) = (c[3], c[4], c[5]);
    let (sf, cf, st, ct) = (f.sin(), f.cos(), th.sin(), th.cos());
    let omega = Vector3::new(
        fd - psd * st,
        thd * cf + psd * ct * sf,
        -thd * sf + psd * ct * cf,
    );
    let omega_dot = Vector3::new(
        fdd - psdd * st - psd * thd * ct,
        thdd * cf - thd * fd * sf + psdd * ct * sf - psd * thd * st * sf + psd * fd * ct * cf,
        -thdd * sf - thd * fd * cf + psdd * ct * cf - psd * thd * st * cf - psd * fd * ct * sf,
    );
    BaseMotion {
        p: [origin + p[0], p[1], p[2]],
        rot: UnitQuaternion::from_euler_angles(f, th, ps),
        omega,
        omega_dot,
    }
}

/// The stance's fixed parts: the feet's frame indices and world
/// positions, the base's rest position, the motion's coefficients.
struct Stance<'a> {
    ff: &'a Model,
    cfg: &'a StandingConfig,
    frames: Vec<usize>,
    feet: Vec<Vector3<f64>>,
    origin: Vector3<f64>,
    coef: Vec<[Vec<f64>; 2]>,
}

impl<'a> Stance<'a> {
    fn new(ff: &'a Model, cfg: &'a StandingConfig, rng: &mut StdRng) -> Result<Self, SimError> {
        let frames = (cfg.feet.iter())
            .map(|f| ff.frame_index(f))
            .collect::<Result<Vec<_>, _>>()?;
        let mut data = Data::new(ff);
        let rest = ff.frames_in_base(&mut data, &cfg.posture, &frames)?;
        let lowest = rest.iter().map(|f| f.z).fold(f64::INFINITY, f64::min);
        let origin = Vector3::new(0.0, 0.0, -lowest);
        let mut coef = coefficients(rng, 6, 1.0);
        for (i, c) in coef.iter_mut().enumerate() {
            let scale = if i < 3 { cfg.sway } else { cfg.tilt };
            c.iter_mut().flatten().for_each(|x| *x *= scale);
        }
        let feet = rest.iter().map(|f| origin + f).collect();
        Ok(Self {
            ff,
            cfg,
            frames,
            feet,
            origin,
            coef,
        })
    }
}

/// Central-difference step of the kinematics' Jacobian (rad).
const JACOBIAN_STEP: f64 = 1e-6;
/// Step of the second difference giving `J̇ q̇` (rad along q̇'s direction).
const BIAS_STEP: f64 = 1e-4;
/// Newton iterations of the inverse kinematics.
const IK_ITERATIONS: usize = 30;
/// The kinematics' failure.
const SINGULAR: &str = "the feet's Jacobian is singular: a leg straight, or the feet not moved independently by the joints";

impl Stance<'_> {
    fn fail(&self, time: f64, problem: String) -> SimError {
        SimError::Stance { time, problem }
    }

    /// The feet in base coordinates, stacked (3 per foot).
    fn fk(&self, data: &mut Data, q: &[f64]) -> Result<DVector<f64>, SimError> {
        let f = self.ff.frames_in_base(data, q, &self.frames)?;
        Ok(DVector::from_iterator(
            3 * f.len(),
            f.iter().flat_map(|v| [v.x, v.y, v.z]),
        ))
    }

    /// The feet's Jacobian (3 per foot × n) by central differences.
    fn jacobian(&self, data: &mut Data, q: &[f64]) -> Result<DMatrix<f64>, SimError> {
        let n = q.len();
        let mut j = DMatrix::zeros(3 * self.frames.len(), n);
        let mut x = q.to_vec();
        for c in 0..n {
            x[c] = q[c] + JACOBIAN_STEP;
            let plus = self.fk(data, &x)?;
            x[c] = q[c] - JACOBIAN_STEP;
            let minus = self.fk(data, &x)?;
            x[c] = q[c];
            j.set_column(c, &((plus - minus) / (2.0 * JACOBIAN_STEP)));
        }
        Ok(j)
    }

    /// Least-norm `J x = b`; an error naming `what` if J loses rank.
    fn solve(
        &self,
        j: &DMatrix<f64>,
        b: &DVector<f64>,
        (time, what): (f64, &str),
    ) -> Result<DVector<f64>, SimError> {
        let svd = j.clone().svd(true, true);
        let (max, min) = (svd.singular_values.max(), svd.singular_values.min());
        if !(min > 1e-6 * max) {
            let ratio = min / max;
            let feet = &self.cfg.feet;
            return Err(self.fail(
                time,
                format!("{what} (feet {feet:?}; σ_min/σ_max = {ratio:.1e})"),
            ));
        }
        svd.solve(b, 0.0)
            .map_err(|e| self.fail(time, e.to_string()))
    }

    /// The joint positions putting the feet at `target` (base coordinates),
    /// by Newton's method from `q`.
    fn inverse_kinematics(
        &self,
        data: &mut Data,
        mut q: Vec<f64>,
        target: &DVector<f64>,
        time: f64,
    ) -> Result<Vec<f64>, SimError> {
        for _ in 0..IK_ITERATIONS {
            let r = self.fk(data, &q)? - target;
            if r.amax() < 1e-12 {
                return Ok(q);
            }
            let step = self.solve(&self.jacobian(data, &q)?, &r, (time, SINGULAR))?;
            q.iter_mut().zip(step.iter()).for_each(|(x, s)| *x -= s);
        }
        Err(self.fail(
            time,
            format!(
                "a foot of {:?} is out of reach (inverse kinematics did not converge)",
                self.cfg.feet
            ),
        ))
    }
}

impl Stance<'_> {
    /// The free-flyer's `q`, `v`, `a` at `time`, the feet fixed; `prev`:
    /// the joint positions the inverse kinematics starts from.
    fn state(&self, data: &mut Data, prev: Vec<f64>, time: f64) -> Result<[Vec<f64>; 3], SimError> {
        let m = base_motion(self.origin, &channels(&self.coef, time));
        let rt: Matrix3<f64> = m.rot.to_rotation_matrix().matrix().transpose();
        let v_b = rt * m.p[1];
        let vdot_b = rt * m.p[2] - m.omega.cross(&v_b);
        let k = 3 * self.feet.len();
        let [mut f, mut fd, mut fdd] = [0; 3].map(|_| DVector::zeros(k));
        for (i, c) in self.feet.iter().enumerate() {
            let fi = rt * (c - m.p[0]);
            let fdi = -m.omega.cross(&fi) - v_b;
            let fddi = -m.omega_dot.cross(&fi) - m.omega.cross(&fdi) - vdot_b;
            f.rows_mut(3 * i, 3).copy_from(&fi);
            fd.rows_mut(3 * i, 3).copy_from(&fdi);
            fdd.rows_mut(3 * i, 3).copy_from(&fddi);
        }
        let qj = self.inverse_kinematics(data, prev, &f, time)?;
        let j = self.jacobian(data, &qj)?;
        let qd = self.solve(&j, &fd, (time, SINGULAR))?;
        let bias = self.bias(data, &qj, &qd)?;
        let qdd = self.solve(&j, &(fdd - bias), (time, SINGULAR))?;
        let c = m.rot.coords;
        let p = m.p[0];
        let q = [p.x, p.y, p.z, c.x, c.y, c.z, c.w].into_iter().chain(qj);
        let v = v_b.iter().chain(m.omega.iter()).chain(qd.iter()).copied();
        let a = (vdot_b.iter().chain(m.omega_dot.iter()).chain(qdd.iter())).copied();
        Ok([q.collect(), v.collect(), a.collect()])
    }

    /// `J̇ q̇` of the feet: the second difference of the kinematics along q̇.
    fn bias(
        &self,
        data: &mut Data,
        q: &[f64],
        qd: &DVector<f64>,
    ) -> Result<DVector<f64>, SimError> {
        let speed = qd.amax();
        if speed == 0.0 {
            return Ok(DVector::zeros(3 * self.feet.len()));
        }
        let h = BIAS_STEP / speed;
        let at = |s: f64| -> Vec<f64> { q.iter().zip(qd.iter()).map(|(x, d)| x + s * d).collect() };
        let (plus, mid, minus) = (
            self.fk(data, &at(h))?,
            self.fk(data, q)?,
            self.fk(data, &at(-h))?,
        );
        Ok((plus - 2.0 * mid + minus) / (h * h))
    }

    /// The feet's forces (world axes) balancing the base rows of the
    /// generalized force `g` with least norm, each checked against its
    /// friction cone, and the joint torques left.
    fn forces(
        &self,
        data: &mut Data,
        q: &[f64],
        g: &DVector<f64>,
        time: f64,
    ) -> Result<(DVector<f64>, Vec<f64>), SimError> {
        let (k, nv) = (3 * self.frames.len(), self.ff.nv());
        let mut map = DMatrix::zeros(nv, k);
        for (c, &frame) in (0..k).zip(self.frames.iter().flat_map(|f| [f; 3])) {
            let mut wrench = [0.0; 6];
            wrench[c % 3] = 1.0;
            let unit = ContactWrench {
                frame,
                wrench,
                expressed: WrenchFrame::WorldAligned,
            };
            map.set_column(c, &self.ff.contact_force(data, q, &[unit])?);
        }
        let base = map.rows(0, 6).into_owned();
        let g_base = g.rows(0, 6).into_owned();
        const UNBALANCED: &str =
            "the feet cannot balance the base's wrench: fewer than three, or in a line";
        let f = self.solve(&base, &g_base, (time, UNBALANCED))?;
        // least squares: exact only when the feet span every wrench
        let miss = (&base * &f - &g_base).amax();
        if !(miss <= 1e-9 * (1.0 + g_base.amax())) {
            return Err(self.fail(time, format!("{UNBALANCED} (off by {miss:.2e})")));
        }
        self.check_cone(&f, time)?;
        let tau = g.rows(6, nv - 6) - map.rows(6, nv - 6) * &f;
        Ok((f, tau.iter().copied().collect()))
    }

    /// Every foot's force pushes (`f_z > 0`) and sticks (`|f_t| ≤ μ f_z`).
    fn check_cone(&self, f: &DVector<f64>, time: f64) -> Result<(), SimError> {
        let mu = self.cfg.friction;
        for (i, foot) in self.cfg.feet.iter().enumerate() {
            let (t, n) = (f[3 * i].hypot(f[3 * i + 1]), f[3 * i + 2]);
            if !(n > 0.0 && t <= mu * n) {
                return Err(self.fail(time, format!(
                    "foot '{foot}' would need a force of {:.3} N tangential, {:.3} N normal: outside its friction cone (μ = {mu}); less sway or tilt",
                    t, n)));
            }
        }
        Ok(())
    }
}

/// A log of the robot `ff` (the nominal model; the truth is it with
/// `cfg.effects`) standing on force plates (module doc), with noise.
pub fn simulate_standing(ff: &Model, cfg: &StandingConfig) -> Result<Dataset, SimError> {
    check(cfg)?;
    check_stance(ff, cfg)?;
    let truth = cfg.effects.truth(ff)?;
    let ff = &truth;
    let mut rng = StdRng::seed_from_u64(cfg.seed);
    let stance = Stance::new(ff, cfg, &mut rng)?;
    let samples = (cfg.seconds * cfg.rate).round() as usize;
    let mut data = Data::new(ff);
    let feet: Vec<(String, WrenchFrame)> = (cfg.feet.iter())
        .map(|frame| (frame.clone(), WrenchFrame::WorldAligned))
        .collect();
    let mut log = Dataset::for_model(ff, &feet);
    let mut prev = cfg.posture.clone();
    for k in 0..samples {
        let time = k as f64 / cfg.rate;
        let [q, v, a] = stance.state(&mut data, prev, time)?;
        let g = crate::dynamics::rnea(ff, &mut data, &q, &v, &a)?.clone();
        let (f, tau) = stance.forces(&mut data, &q, &g, time)?;
        for (i, c) in log.contacts.iter_mut().enumerate() {
            c.wrench
                .extend([f[3 * i], f[3 * i + 1], f[3 * i + 2], 0.0, 0.0, 0.0]);
        }
        log.push_state(time, (&q, &v, &a), Some(&tau));
        prev = q[7..].to_vec();
    }
    cfg.effects.apply(&mut log);
    add_noise(&mut log, &cfg.noise, &mut rng)?;
    Ok(log)
}

/// The stance: feet named once each (not the base), a finite posture of
/// the robot's joints.
fn check_stance(ff: &Model, cfg: &StandingConfig) -> Result<(), SimError> {
    let fail = |problem: String| Err(SimError::Stance { time: 0.0, problem });
    if cfg.posture.len() != ff.dof() || cfg.posture.iter().any(|x| !x.is_finite()) {
        let (found, n) = (cfg.posture.len(), ff.dof());
        return fail(format!(
            "the posture has {found} joint positions, not {n} finite ones"
        ));
    }
    if cfg.feet.len() < 3 {
        let n = cfg.feet.len();
        return fail(format!(
            "{n} feet: point feet balance the base's six wrench components only three or more at a time"
        ));
    }
    for (i, foot) in cfg.feet.iter().enumerate() {
        if cfg.feet[..i].contains(foot) {
            return fail(format!("foot '{foot}' is named twice"));
        }
        let frame = ff.frame_index(foot)?;
        if ff.frames[frame].body.is_none() {
            return fail(format!(
                "foot '{foot}' is on the base: a foot must be moved by joints"
            ));
        }
    }
    Ok(())
}

/// The configuration's numbers are in range.
fn check(cfg: &StandingConfig) -> Result<(), SimError> {
    let samples = cfg.seconds * cfg.rate;
    let bad = |setting, value, requirement| {
        Err(SimError::Setting {
            setting,
            value,
            requirement,
        })
    };
    if !(cfg.rate > 0.0 && (10.0..=1e7).contains(&samples)) {
        return bad(
            "seconds × rate",
            samples,
            "between 10 and 1e7 samples at a positive rate",
        );
    }
    for (setting, value) in [("sway", cfg.sway), ("tilt", cfg.tilt)] {
        if !(value.is_finite() && value >= 0.0) {
            return bad(setting, value, "finite and ≥ 0");
        }
    }
    if !(cfg.friction.is_finite() && cfg.friction > 0.0) {
        return bad("friction", cfg.friction, "a finite coefficient > 0");
    }
    Ok(())
}
