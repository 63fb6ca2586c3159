"""momentlmi: physically consistent inertial parameter identification of robots.

The Python face of the momentlmi crate (Wensing, Kim, Slotine 2017): a rigid body's
ten inertial parameters π = [m, hx, hy, hz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz] (about the
body frame's origin, SI units) are physically consistent iff the 4×4 pseudo-inertia
J(π) is positive definite; a body inside an ellipsoid is density realizable in it iff
also tr(J Q) ≥ 0.

- One body: :func:`pseudo_inertia`, :func:`is_consistent`, :func:`realizable_in`,
  :func:`four_point_masses`, :func:`nearest_consistent`, and Pinocchio's order
  (:func:`from_pinocchio`, :func:`to_pinocchio`).
- A URDF: :func:`check_urdf` (``momentlmi check --json``'s verdicts and margins),
  :func:`repair_urdf`.
- A robot: :class:`Robot` (``Robot.builtin("cheetah3-leg")``, ``Robot.from_urdf``):
  inverse dynamics and the regressor over many samples at once.
- Data too large for one machine: :class:`Reducer` reduces samples into fixed-size
  sums that add across processes and machines (``to_bytes`` / ``from_bytes``), and
  solves one SDP on them.

Arrays are NumPy arrays of samples, shape (N, n) in the robot's joint order
(:attr:`Robot.joint_names`). A wrong shape or a value that is not finite raises
``ValueError`` naming the argument; the library's errors raise
:class:`MomentlmiError` (subclasses per kind) with the command line's messages.
"""

from __future__ import annotations

import json
import os
import tempfile
import warnings
from typing import Iterable, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._native import (
    CHECK_TOL,
    REDUCED_FORMAT_VERSION,
    DataError,
    IdentifyError,
    InertiaError,
    ModelError,
    MomentlmiError,
    UrdfError,
)

__all__ = [
    "CHECK_TOL",
    "REDUCED_FORMAT_VERSION",
    "DataError",
    "IdentifyError",
    "IdentifyResult",
    "InertiaError",
    "ModelError",
    "MomentlmiError",
    "UrdfError",
    "Reducer",
    "Robot",
    "check_consistency",
    "check_urdf",
    "check_urdf_report",
    "diagnose",
    "excite",
    "four_point_masses",
    "identify",
    "from_pinocchio",
    "is_consistent",
    "nearest_consistent",
    "pseudo_inertia",
    "realizability",
    "realizable_in",
    "repair_urdf",
    "simulate",
    "to_pinocchio",
]

PathLike = Union[str, "os.PathLike[str]"]


def _floats(x, name: str) -> np.ndarray:
    """`x` as a C-contiguous float64 array; a ValueError naming `name` if it is not numbers."""
    try:
        return np.ascontiguousarray(np.asarray(x, dtype=np.float64))
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name}: not an array of numbers ({e})") from None


def _paths(paths: Optional[Iterable[PathLike]]) -> list:
    return [os.fspath(p) for p in (paths or [])]


# -- one body ---------------------------------------------------------------


def pseudo_inertia(pi) -> np.ndarray:
    """J(π), the 4×4 pseudo-inertia [[Σ, h], [hᵀ, m]] (Σ = ½ tr(Ī)·1 − Ī)."""
    return _native.pseudo_inertia(_floats(pi, "pi"))


def check_consistency(pi, tol: float = CHECK_TOL) -> dict:
    """The consistency report: ``verdict``, margins, ``consistent`` (J(π) ⪰ 0 within `tol`)."""
    return json.loads(_native.consistency(_floats(pi, "pi"), float(tol)))


def is_consistent(pi, tol: float = CHECK_TOL) -> bool:
    """Whether π is physically consistent (J(π) positive semidefinite within `tol`)."""
    return bool(check_consistency(pi, tol)["consistent"])


def realizability(pi, center, semi_axes, rotation=None, tol: float = CHECK_TOL) -> dict:
    """The realizability report of π in the ellipsoid of `center` (m), `semi_axes` (m)
    and `rotation` (3×3, its axes as columns; default: the body frame's)."""
    rot = np.eye(3) if rotation is None else rotation
    args = [_floats(a, n) for a, n in ((pi, "pi"), (center, "center"), (semi_axes, "semi_axes"), (rot, "rotation"))]
    return json.loads(_native.realizability(*args, float(tol)))


def realizable_in(pi, center, semi_axes, rotation=None, tol: float = CHECK_TOL) -> bool:
    """Whether π is density realizable in the ellipsoid (Theorem 4: consistent and tr(J Q) ≥ 0)."""
    return bool(realizability(pi, center, semi_axes, rotation, tol)["realizable"])


def four_point_masses(pi) -> Tuple[np.ndarray, np.ndarray]:
    """Four point masses with the parameters π of a consistent body: masses (4,) kg and
    positions (4, 3) m in the body frame."""
    return _native.point_masses(_floats(pi, "pi"))


def nearest_consistent(pi, eps: float = 1e-6, keep_mass: bool = True) -> Tuple[np.ndarray, float]:
    """The nearest consistent π′ (J(π′) ⪰ ε·scale) and its distance (docs/math.md's metric)."""
    return _native.nearest(_floats(pi, "pi"), float(eps), bool(keep_mass))


def from_pinocchio(p) -> np.ndarray:
    """π from Pinocchio's ``Inertia.toDynamicParameters()`` order
    [m, mcx, mcy, mcz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz] (inertia about the frame's origin)."""
    return _native.from_pinocchio(_floats(p, "p"))


def to_pinocchio(pi) -> np.ndarray:
    """π in Pinocchio's order (``pinocchio.Inertia.FromDynamicParameters`` takes it)."""
    return _native.to_pinocchio(_floats(pi, "pi"))


# -- a URDF -----------------------------------------------------------------


def check_urdf_report(path: PathLike, sidecar: Optional[PathLike] = None,
                      package_paths: Optional[Sequence[PathLike]] = None) -> dict:
    """``momentlmi check --json``'s whole report of the URDF at `path`: ``robot``,
    ``links`` (one dict per link with an inertial), ``consistent``, ``warnings`` …
    The report's warnings are also issued as Python warnings."""
    sc = None if sidecar is None else os.fspath(sidecar)
    text, notes = _native.check_urdf(os.fspath(path), sc, _paths(package_paths))
    for n in notes:
        warnings.warn(n, stacklevel=2)
    return json.loads(text)


def check_urdf(path: PathLike, package_paths: Optional[Sequence[PathLike]] = None,
               sidecar: Optional[PathLike] = None) -> list:
    """Each link's verdict and margins, as ``momentlmi check --json`` gives them: a list
    of dicts (``name``, ``mass``, ``com``, ``principal_moments``, ``consistent``,
    ``realizable_in_geometry``, margins …)."""
    return check_urdf_report(path, sidecar, package_paths)["links"]


def repair_urdf(path: PathLike, out: Optional[PathLike] = None, target: str = "consistent",
                margin: float = 1e-6, sidecar: Optional[PathLike] = None,
                package_paths: Optional[Sequence[PathLike]] = None) -> Tuple[str, list]:
    """The URDF with its inconsistent inertials repaired (``target="geometry"``: also
    those not realizable in their geometry), as ``momentlmi check --repair`` writes it,
    and the names of the links repaired. With `out`, also written there, whole or not
    at all."""
    sc = None if sidecar is None else os.fspath(sidecar)
    text, repaired = _native.repair_urdf_text(os.fspath(path), target, float(margin), sc, _paths(package_paths))
    if out is not None:
        _write_whole(os.fspath(out), text)
    return text, repaired


def _write_whole(path: str, text: str) -> None:
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".momentlmi-")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


# -- a robot ----------------------------------------------------------------


class Robot:
    """A robot: its model (links, geared rotors, friction terms), prior and bounding
    volumes. ``Robot.builtin("cheetah3-leg")`` or ``Robot.from_urdf(path, sidecar=...)``."""

    def __init__(self, native: "_native.Robot"):
        self._r = native

    @staticmethod
    def builtin(name: str) -> "Robot":
        """A built-in robot by name (``cheetah3-leg``)."""
        return Robot(_native.Robot.builtin(name))

    @staticmethod
    def from_urdf(path: PathLike, sidecar: Optional[PathLike] = None,
                  package_paths: Optional[Sequence[PathLike]] = None) -> "Robot":
        """A URDF robot; `sidecar` is its TOML (rotors, friction, bounding volumes, data
        mapping), `package_paths` the folders where ``package://`` meshes are found."""
        sc = None if sidecar is None else os.fspath(sidecar)
        return Robot(_native.Robot.from_urdf(os.fspath(path), sc, _paths(package_paths)))

    @property
    def joint_names(self) -> list:
        """The joints, in the order of every array's columns."""
        return self._r.joint_names

    @property
    def body_names(self) -> list:
        """The bodies (links, then rotors), in the order of the parameters."""
        return self._r.body_names

    @property
    def parameter_names(self) -> list:
        """The regressor's columns: 10 per body (``abad.m``, ``abad.hx`` …), then friction."""
        return self._r.parameter_names

    @property
    def dof(self) -> int:
        """The number of joints n."""
        return self._r.dof

    def params(self) -> np.ndarray:
        """The model's inertial parameters, (bodies, 10), the paper's order."""
        return self._r.params()

    def rnea(self, q, v, a) -> np.ndarray:
        """Joint torques (N·m) of the rigid bodies and rotors, no friction, (N, n), at
        positions q (rad), velocities v (rad/s), accelerations a (rad/s²), each (N, n)."""
        return self._r.rnea(_floats(q, "q"), _floats(v, "v"), _floats(a, "a"))

    def regressor(self, q, v, a) -> np.ndarray:
        """The regressor Y, (N, n, p), with τ = Y θ (θ: 10 per body, then friction;
        :attr:`parameter_names`)."""
        return self._r.regressor(_floats(q, "q"), _floats(v, "v"), _floats(a, "a"))

    def predict(self, params, q, v, a) -> np.ndarray:
        """Joint torques (N·m), (N, n), of the model with identified parameters: `params`
        an :func:`identify` report (a dict) or a parameter file's path; links, rotors and
        every friction term, as ``momentlmi predict --params FILE`` predicts them."""
        if isinstance(params, IdentifyResult):
            text = params.to_json()
        elif isinstance(params, dict):
            text = json.dumps(params)
        else:
            with open(os.fspath(params), encoding="utf-8") as f:
                text = f.read()
        return self._r.predict(text, _floats(q, "q"), _floats(v, "v"), _floats(a, "a"))

    def __repr__(self) -> str:
        return repr(self._r)


def simulate(robot: Robot, seconds: float, effects: Sequence[str] = (), params: Sequence[str] = (),
             seed: int = 1, noise: Optional[float] = None) -> dict:
    """`seconds` of the robot's excitation, as ``momentlmi simulate`` writes it for the
    same arguments: a dict of arrays ``t`` (N,), ``q``, ``qd``, ``qdd``, ``tau`` (N, n,
    SI units) and ``joints``. `effects` are unmodelled effects by name (``backlash``,
    ``ripple`` …), `params` their ``NAME=VALUE`` overrides, `noise` the torque noise σ
    (N·m; 0: exact samples)."""
    return _native.simulate(robot._r, float(seconds), list(effects), list(params), int(seed),
                            None if noise is None else float(noise))


def _segment(d, joints: list, name: str) -> tuple:
    """One segment (a dict of arrays, or a DataFrame with the CSV's column names) as
    (t, q, qd, qdd, tau) arrays, those not given None."""
    if hasattr(d, "columns"):  # a pandas DataFrame: t, q_<joint>, qd_<joint> …
        cols = set(map(str, d.columns))

        def get(p):
            names = [f"{p}_{j}" for j in joints]
            have = [n for n in names if n in cols]
            if have and len(have) < len(names):
                missing = [n for n in names if n not in cols]
                raise ValueError(f"{name}: columns {', '.join(missing)} missing (it has {', '.join(have)})")
            return _floats(d[names].to_numpy(), f"{name}: {p}") if have else None

        if "t" not in cols:
            raise ValueError(f"{name}: no column 't'")
        arrays = {"t": _floats(d["t"].to_numpy(), f"{name}: t"), **{p: get(p) for p in ("q", "qd", "qdd", "tau")}}
    elif isinstance(d, dict):
        unknown = set(d) - {"t", "q", "qd", "qdd", "tau", "joints"}
        if unknown:
            raise ValueError(f"{name}: unknown keys {sorted(unknown)} (t, q, qd, qdd, tau)")
        arrays = {k: None if d.get(k) is None else _floats(d[k], f"{name}: {k}") for k in ("t", "q", "qd", "qdd", "tau")}
        if d.get("joints") is not None and list(d["joints"]) != list(joints):
            given = list(d["joints"])
            if sorted(given) != sorted(joints):
                raise ValueError(f"{name}: joints {given} are not the robot's {list(joints)}")
            order = [given.index(j) for j in joints]  # the columns into the robot's order
            arrays = {k: (v if k == "t" or v is None else v[..., order]) for k, v in arrays.items()}
    else:
        raise ValueError(f"{name}: a dict of arrays or a DataFrame, not {type(d).__name__}")
    for k in ("t", "q"):
        if arrays[k] is None:
            raise ValueError(f"{name}: no {k}")
    return tuple(arrays[k] for k in ("t", "q", "qd", "qdd", "tau"))


def _segments(data, joints: list, name: str) -> list:
    if data is None:
        return []
    many = isinstance(data, (list, tuple))
    return [_segment(d, joints, f"{name}[{k}]" if many else name) for k, d in enumerate(data if many else [data])]


class IdentifyResult(dict):
    """An identification's report, as ``momentlmi identify --json`` writes it: a dict
    (``bodies``, ``friction``, ``training_rms``, ``validation_rms``, ``status`` …) with
    the parameters as arrays and the command line's file text."""

    def __init__(self, text: str):
        super().__init__(json.loads(text))
        self._text = text

    @property
    def params(self) -> np.ndarray:
        """Each body's identified π, (bodies, 10), the paper's order, in ``body_names``' order."""
        return np.array([b["params"] for b in self["bodies"]])

    @property
    def body_names(self) -> list:
        return [b["name"] for b in self["bodies"]]

    def to_json(self) -> str:
        """The report as the command line writes it (``identify --json > model.json``): a
        parameter file ``--params`` / ``--prior`` / ``--nominal`` and :meth:`Robot.predict` take."""
        return self._text


def identify(robot: Robot, data, constraints: str = "ellipsoid", prior: str = "cad",
             weight: Union[None, float, str] = None, regularizer: Optional[str] = None, validate=None,
             cutoff_hz: Optional[float] = None, velocity: str = "differentiate",
             friction: Optional[str] = None,
             bounds: Union[None, float, str] = None) -> IdentifyResult:
    """The identification of `robot` from `data`, as ``momentlmi identify --json``
    reports it (``bodies`` with each body's ``params``, ``training_rms``,
    ``validation_rms`` …).

    `data` (and `validate`, held out) is a segment or a list of segments, each a dict
    of arrays ``t`` (N,), ``q``, and ``qd``, ``qdd``, ``tau`` (N, n) where recorded, or
    a pandas DataFrame with the CSV's column names (``t``, ``q_<joint>`` …). A segment
    with ``qdd`` is taken as it is; one without is filtered and differentiated as a raw
    log file (`cutoff_hz`: None chooses it; `velocity`: differentiate or file).
    `constraints`: none, semi, consistent or ellipsoid; `prior`: cad, true or a
    parameter file; `weight`: a number or ``"auto"`` (cross-validation; None, the
    default: auto when the friction law is chosen, else 1e-6);
    `regularizer`: euclidean, entropic or pullback (None, the default: entropic when the
    weight is chosen and every prior body is strictly consistent, else euclidean — as
    ``--regularizer``); `friction`: the friction terms identified
    (``"viscous,coulomb,offset,load,stribeck"``); ``"auto"``: chosen by cross-validation
    on the training data, with the weight when it is ``"auto"``,
    the table in ``result["model_selection"]``; None, the default: auto, with viscous +
    Coulomb kept (a ``law_not_chosen`` warning) when the data are too short to choose —
    as ``momentlmi identify`` without ``--friction``); `bounds`: each
    parameter's range over the constrained models whose residual is at most (1 + bounds)
    × the estimate's (``"auto"``: the 95 % confidence region; None: not computed), in
    ``result["bounds"]``. ``result["identifiability"]`` has the rank, the base
    parameters with their standard deviations and the parameters that enter no torque."""
    joints = robot.joint_names
    if bounds is not None and not (bounds == "auto" or (not isinstance(bounds, str) and float(bounds) >= 0)):
        raise ValueError(f"bounds: {bounds!r} is not a number >= 0 or 'auto'")
    b = None if bounds is None else ("auto" if bounds == "auto" else repr(float(bounds)))
    if weight is None or isinstance(weight, str):
        if weight not in (None, "auto"):
            raise ValueError(f"weight: '{weight}' is not a number or 'auto'")
        w = weight
    else:
        w = repr(float(weight))
    return IdentifyResult(_native.identify(robot._r, _segments(data, joints, "data"), _segments(validate, joints, "validate"),
                                           constraints, os.fspath(prior), w, regularizer,
                                           None if cutoff_hz is None else float(cutoff_hz), velocity, friction, b))


def excite(robot: Robot, seconds: float = 10.0, criterion: str = "d", harmonics: int = 5,
           base_hz: float = 0.2, seeds: int = 8, seed: int = 1, pool: int = 0,
           rate_hz: float = 1000.0) -> dict:
    """A designed excitation of `robot`, as ``momentlmi excite --json`` reports it: a
    periodic Fourier series per joint within the joints' limits, optimised for
    `criterion` (``"d"`` log det, ``"e"`` smallest eigenvalue, ``"cond"`` condition
    number) of the base parameters' information; `pool` random candidates give the
    convex design's bound. The report's ``"samples"`` holds ``t`` (N,), ``q``, ``qd``,
    ``qdd`` (N, n) at `rate_hz`, ready for :func:`simulate`'s robot or a controller."""
    if criterion not in ("d", "e", "cond"):
        raise ValueError(f"criterion: '{criterion}' is not one of d, e, cond")
    text, (t, q, qd, qdd) = _native.excite(robot._r, float(seconds), criterion, int(harmonics),
                                           float(base_hz), int(seeds), int(seed), int(pool),
                                           float(rate_hz))
    report = json.loads(text)
    report["samples"] = {"t": t, "q": q, "qd": qd, "qdd": qdd}
    return report


def diagnose(robot: Robot, data, nominal: Optional[str] = None, repeats=None, nominal_data=None) -> dict:
    """Where `data` depart from the `nominal` model (None: the robot's own parameters;
    ``"cad"``, ``"true"`` or a parameter file), which unmodelled effects explain the
    gap and how far it shrinks on held-out data, as ``momentlmi diagnose --json``
    reports it. `data` as for :func:`identify`; `repeats`, two runs of one trajectory,
    give the noise floor (needed when the torques were low-pass filtered);
    `nominal_data`, the data the nominal was identified on (as `data`), have its
    bodies refit with the friction law so that what they could not determine is not
    named an effect (``--nominal-data``)."""
    joints = robot.joint_names
    reps = _segments(repeats, joints, "repeats")
    own = _segments(nominal_data, joints, "nominal_data")
    nom = None if nominal is None else os.fspath(nominal)
    return json.loads(_native.diagnosis(robot._r, _segments(data, joints, "data"), nom, reps, own))


# -- the fleet path ---------------------------------------------------------


class Reducer:
    """Samples of one robot reduced to fixed-size sums (the Gram matrix of [Y τ]): add
    samples with :meth:`update`, other reducers' sums with :meth:`merge` (from other
    processes or machines: :meth:`to_bytes` / :meth:`from_bytes`), then :meth:`solve`
    one SDP. The sums of the parts are the sums of the whole."""

    def __init__(self, robot: Robot, _native_reducer=None):
        self.robot = robot
        self._r = _native_reducer if _native_reducer is not None else _native.Reducer(robot._r)

    @property
    def samples(self) -> int:
        """The samples reduced so far."""
        return self._r.samples

    def update(self, q, v, a, tau) -> "Reducer":
        """Adds samples: q (rad), v (rad/s), a (rad/s²), τ (N·m), each (N, n)."""
        self._r.update(_floats(q, "q"), _floats(v, "v"), _floats(a, "a"), _floats(tau, "tau"))
        return self

    def gram(self) -> np.ndarray:
        """The Gram matrix [Y τ]ᵀ[Y τ] of the samples so far, (p + 1) × (p + 1)."""
        return self._r.gram()

    def merge(self, other: "Reducer") -> "Reducer":
        """Adds the sums of `other` (the same robot's)."""
        if other is self or other._r is self._r:
            raise ValueError("other: a reducer cannot be merged into itself (its samples would count twice)")
        self._r.merge(other._r)
        return self

    def to_bytes(self) -> bytes:
        """The sums, versioned (:data:`REDUCED_FORMAT_VERSION`) and tied to the robot."""
        return self._r.to_bytes()

    @staticmethod
    def from_bytes(robot: Robot, data: bytes) -> "Reducer":
        """The reducer whose sums `data` holds; an error if they are not this robot's."""
        return Reducer(robot, _native.Reducer.from_bytes(robot._r, bytes(data)))

    def solve(self, constraints: str = "ellipsoid", weight: float = 1e-6,
              regularizer: str = "euclidean") -> IdentifyResult:
        """The identification on the sums, as ``momentlmi identify --json`` reports it
        (:class:`IdentifyResult`): `constraints` none, semi, consistent or ellipsoid;
        toward the robot's prior with `weight`."""
        return IdentifyResult(self._r.solve(constraints, float(weight), regularizer))
