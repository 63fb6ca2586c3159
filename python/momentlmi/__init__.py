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
(:attr:`Robot.joint_names`), or pandas DataFrames whose columns are found by name
(``<joint>`` or ``q_<joint>`` …), never by position. A bad argument raises a
``ValueError`` (a wrong value) or ``TypeError`` (a wrong kind) whose message starts
with its name; the library's errors raise :class:`MomentlmiError` (subclasses per
kind) with the command line's messages; each warning of a report is issued as a
:class:`MomentlmiWarning`. :class:`Robot`, :class:`Reducer` and
:class:`IdentifyResult` pickle (multiprocessing, Dask). The rules: docs/python.md.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
import warnings
from typing import Iterable, Optional, Sequence, Tuple, Union

import numpy as np

from . import _args, _native
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

__version__: str = _native.__version__

__all__ = [
    "__version__",
    "CHECK_TOL",
    "REDUCED_FORMAT_VERSION",
    "DataError",
    "IdentifyError",
    "IdentifyResult",
    "InertiaError",
    "ModelError",
    "MomentlmiError",
    "MomentlmiWarning",
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


_floats = _args.floats


class MomentlmiWarning(UserWarning):
    """A warning of a report (``identify``, ``Reducer.solve``, ``diagnose``,
    ``check_urdf``), in the command line's words; ``.kind`` names it (the report's
    ``kind``, or ``status``, ``inconsistent_bodies``, ``degenerate_body``,
    ``identifiability``)."""

    kind: str = "warning"


def _warn(notes, stacklevel: int = 3) -> None:
    """Each `(kind, message)` issued as a :class:`MomentlmiWarning`."""
    for kind, message in notes:
        w = MomentlmiWarning(message)
        w.kind = kind
        warnings.warn(w, stacklevel=stacklevel)


def _text(x, name: str) -> str:
    """A string argument (an option's name): a TypeError if it is none."""
    if not isinstance(x, str):
        raise TypeError(f"{name}: {x!r} is not a string")
    return x


# -- one body ---------------------------------------------------------------


def pseudo_inertia(pi) -> np.ndarray:
    """J(π), the 4×4 pseudo-inertia [[Σ, h], [hᵀ, m]] (Σ = ½ tr(Ī)·1 − Ī)."""
    return _native.pseudo_inertia(_floats(pi, "pi"))


def check_consistency(pi, tol: float = CHECK_TOL) -> dict:
    """The consistency report: ``verdict``, margins, ``consistent`` (J(π) ⪰ 0 within `tol`)."""
    return json.loads(_native.consistency(_floats(pi, "pi"), _args.number(tol, "tol", finite=False)))


def is_consistent(pi, tol: float = CHECK_TOL) -> bool:
    """Whether π is physically consistent (J(π) positive semidefinite within `tol`)."""
    return bool(check_consistency(pi, tol)["consistent"])


def realizability(pi, center, semi_axes, rotation=None, tol: float = CHECK_TOL) -> dict:
    """The realizability report of π in the ellipsoid of `center` (m), `semi_axes` (m)
    and `rotation` (3×3, its axes as columns; default: the body frame's)."""
    rot = np.eye(3) if rotation is None else rotation
    args = [_floats(a, n) for a, n in ((pi, "pi"), (center, "center"), (semi_axes, "semi_axes"), (rot, "rotation"))]
    return json.loads(_native.realizability(*args, _args.number(tol, "tol", finite=False)))


def realizable_in(pi, center, semi_axes, rotation=None, tol: float = CHECK_TOL) -> bool:
    """Whether π is density realizable in the ellipsoid (Theorem 4: consistent and tr(J Q) ≥ 0)."""
    return bool(realizability(pi, center, semi_axes, rotation, tol)["realizable"])


def four_point_masses(pi) -> Tuple[np.ndarray, np.ndarray]:
    """Four point masses with the parameters π of a consistent body: masses (4,) kg and
    positions (4, 3) m in the body frame."""
    return _native.point_masses(_floats(pi, "pi"))


def nearest_consistent(pi, eps: float = 1e-6, keep_mass: bool = True) -> Tuple[np.ndarray, float]:
    """The nearest consistent π′ (J(π′) ⪰ ε·scale) and its distance (docs/math.md's metric)."""
    return _native.nearest(_floats(pi, "pi"), _args.number(eps, "eps"), bool(keep_mass))


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
    sc = _args.optional_path(sidecar, "sidecar")
    text, notes = _native.check_urdf(_args.path(path, "path"), sc, _args.paths(package_paths, "package_paths"))
    _warn([("check", n) for n in notes])
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
    sc = _args.optional_path(sidecar, "sidecar")
    text, repaired = _native.repair_urdf_text(_args.path(path, "path"), _text(target, "target"),
                                              _args.number(margin, "margin"), sc,
                                              _args.paths(package_paths, "package_paths"))
    if out is not None:
        _write_whole(_args.path(out, "out"), text)
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
    volumes. ``Robot.builtin("cheetah3-leg")`` or ``Robot.from_urdf(path, sidecar=...)``;
    wherever a robot is expected, a built-in robot's name or a URDF's path will do.

    A Robot pickles as what it was loaded from (the built-in's name, or the URDF's,
    the sidecar's and the package paths' absolute paths) and is loaded again when
    unpickled: the files must be readable there and unchanged (an error if its joints,
    bodies, friction terms or parameters differ)."""

    def __init__(self, native: "_native.Robot"):
        self._r = native

    @staticmethod
    def builtin(name: str) -> "Robot":
        """A built-in robot by name (``cheetah3-leg``); another name is a ValueError."""
        return Robot(_native.Robot.builtin(_text(name, "name")))

    @staticmethod
    def from_urdf(path: PathLike, sidecar: Optional[PathLike] = None,
                  package_paths: Optional[Sequence[PathLike]] = None,
                  floating_base: bool = False) -> "Robot":
        """A URDF robot; `sidecar` is its TOML (rotors, friction, bounding volumes, data
        mapping), `package_paths` the folders where ``package://`` meshes are found;
        `floating_base`: its root link is free (a legged robot's base; the sidecar's
        ``[floating_base]`` table says so too), as ``--floating-base``."""
        sc = _args.optional_path(sidecar, "sidecar")
        if not isinstance(floating_base, bool):
            raise TypeError(f"floating_base: {floating_base!r} is not True or False")
        absolute = lambda p: None if p is None else os.path.abspath(p)
        pkgs = [absolute(p) for p in _args.paths(package_paths, "package_paths")]
        return Robot(_native.Robot.from_urdf(absolute(_args.path(path, "path")), absolute(sc), pkgs,
                                             floating_base))

    def __reduce__(self):
        spec, sidecar, pkgs = self._r.load_args
        return (_robot_again, (spec, sidecar and os.fspath(sidecar), [os.fspath(p) for p in pkgs],
                               self._r.signature, self.params(), self._r.floating_asked))

    @property
    def floating_base(self) -> bool:
        """Whether the robot's root link is free (a floating base)."""
        return self._r.floating_base

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

    def _states(self, q, v, a) -> tuple:
        """q, v, a as (N, n) arrays; DataFrames by column name (q_, qd_, qdd_ or none)."""
        j = self.joint_names
        return (_args.samples(q, "q", j, "q"), _args.samples(v, "v", j, "qd"),
                _args.samples(a, "a", j, "qdd"))

    def rnea(self, q, v, a) -> np.ndarray:
        """Joint torques (N·m) of the rigid bodies and rotors, no friction, (N, n), at
        positions q (rad), velocities v (rad/s), accelerations a (rad/s²), each (N, n)."""
        return self._r.rnea(*self._states(q, v, a))

    def regressor(self, q, v, a) -> np.ndarray:
        """The regressor Y, (N, n, p), with τ = Y θ (θ: 10 per body, then friction;
        :attr:`parameter_names`)."""
        return self._r.regressor(*self._states(q, v, a))

    def predict(self, params, q, v, a) -> np.ndarray:
        """Joint torques (N·m), (N, n), of the model with identified parameters: `params`
        an :func:`identify` result, a dict, the JSON text of one (``to_json()``) or a
        parameter file's path; links, rotors and every friction term, as ``momentlmi
        predict --params FILE`` predicts them."""
        text = _args.params_text(params, "params")
        states = self._states(q, v, a)
        if text is None:
            return self._r.predict(os.fspath(params), *states, from_file=True)
        return self._r.predict(text, *states)

    def __repr__(self) -> str:
        return repr(self._r)


def _robot_again(spec: str, sidecar, package_paths: list, signature: str, params,
                 floating_base: bool = False) -> Robot:
    """A pickled :class:`Robot` loaded again, and checked to be the one pickled."""
    r = Robot(_native.Robot.from_urdf(spec, sidecar, package_paths, floating_base))
    if r._r.signature != signature or not np.array_equal(r.params(), params):
        raise MomentlmiError(f"unpickling a Robot: '{spec}' is not the robot that was pickled "
                             f"(its files changed: {r._r.signature}; pickled: {signature})")
    return r


def _fixed(r: Robot, what: str) -> Robot:
    """`r`, unless its base floats: `what` takes a fixed-base robot for now (a
    ValueError before its other arguments are read)."""
    if r.floating_base:
        raise ValueError(f"{what}: '{r._r.load_args[0]}' has a floating base, and this is for a "
                         "fixed-base robot for now (a floating base's logs go to identify; "
                         "docs/floating-base.md)")
    return r


def _robot(x, name: str = "robot") -> Robot:
    """A :class:`Robot`, or one loaded from a built-in robot's name or a URDF's path."""
    if isinstance(x, Robot):
        return x
    if isinstance(x, str):
        try:
            return Robot.builtin(x)
        except ValueError as e:
            if not os.path.isfile(x):
                why = str(e).split(": ", 1)[-1]
                raise ValueError(f"{name}: {why}, and no file '{x}' (a Robot, a built-in's name or a URDF's path)") from None
    if isinstance(x, (str, os.PathLike)):
        return Robot.from_urdf(x)
    raise TypeError(f"{name}: a Robot, a built-in robot's name or a URDF's path, not {type(x).__name__}")


@contextlib.contextmanager
def _params_file(x, name: str):
    """A parameter choice as the library takes it: None, ``cad``, ``true`` or a file's
    path; a result, a dict or JSON text written to a temporary ``<name>.json``."""
    if x is None or (isinstance(x, str) and x in ("cad", "true")):
        yield x
        return
    text = _args.params_text(x, name)
    if text is None:
        yield os.fspath(x)
        return
    with tempfile.TemporaryDirectory(prefix="momentlmi-") as folder:
        path = os.path.join(folder, f"{name}.json")
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        yield path


def simulate(robot: Robot, seconds: float, effects: Union[str, Sequence[str]] = (),
             params: Union[str, Sequence[str], dict] = (), seed: int = 1,
             noise: Optional[float] = None) -> dict:
    """`seconds` of the robot's excitation, as ``momentlmi simulate`` writes it for the
    same arguments: a dict of arrays ``t`` (N,), ``q``, ``qd``, ``qdd``, ``tau`` (N, n,
    SI units) and ``joints``. `effects` are unmodelled effects by name (a list or a
    comma-separated string: ``"backlash,ripple"``), `params` their ``NAME=VALUE``
    overrides (a list, a comma-separated string or a dict), `noise` the torque noise σ
    (N·m; 0: exact samples), `seed` an integer ≥ 0.

    A floating-base robot is hung from a harness (a load cell at its base) as
    ``momentlmi simulate`` does it: the dict holds the log's columns, named as its CSV's
    (``t``, ``base_x`` …, ``q_<joint>`` …, ``force_<link>_x`` …), which :func:`identify`
    takes as a log; `effects` among ``joint_friction``, ``wrench_offset``, ``payload``
    (fixed sizes, no `params`)."""
    r = _robot(robot)
    if isinstance(params, dict):
        params = [f"{k}={v}" for k, v in params.items()]
    return _native.simulate(r._r, _args.number(seconds, "seconds"), _args.names(effects, "effects"),
                            _args.names(params, "params"), _args.count(seed, "seed"),
                            None if noise is None else _args.number(noise, "noise"))


_KEYS = {"q": "q", "qd": "qd", "qdd": "qdd", "tau": "tau"}


def _segment(d, joints: list, name: str) -> tuple:
    """One segment (a dict of arrays, or a DataFrame with the CSV's column names) as
    (t, q, qd, qdd, tau) arrays, those not given None; labelled columns by name."""
    if _args.is_frame(d):  # a pandas DataFrame: t, q_<joint>, qd_<joint> …
        cols = [str(c) for c in d.columns]
        if "t" not in cols:
            raise ValueError(f"{name}: no column 't'")
        arrays = {"t": _args.times(d["t"], f"{name}: t")}
        for p in _KEYS:
            have = [f"{p}_{j}" for j in joints if f"{p}_{j}" in cols]
            arrays[p] = _args.samples(d, f"{name}: {p}", joints, p) if have else None
    elif isinstance(d, dict):
        unknown = set(d) - {"t", "q", "qd", "qdd", "tau", "joints"}
        if unknown:
            raise ValueError(f"{name}: unknown keys {sorted(unknown)} (t, q, qd, qdd, tau)")
        order = _joint_order(d.get("joints"), joints, name)
        arrays = {"t": None if d.get("t") is None else _args.times(d["t"], f"{name}: t")}
        for p in _KEYS:
            x = d.get(p)
            if x is None:
                arrays[p] = None
            elif _args.is_frame(x) or _args.is_series(x):  # by its names, not `joints`
                arrays[p] = _args.samples(x, f"{name}: {p}", joints, p)
            else:
                a = _floats(x, f"{name}: {p}")
                arrays[p] = a if order is None or a.ndim == 0 or a.shape[-1] != len(order) else a[..., order]
    else:
        raise TypeError(f"{name}: a dict of arrays or a DataFrame, not {type(d).__name__}")
    for k in ("t", "q"):
        if arrays[k] is None:
            raise ValueError(f"{name}: no {k}")
    return tuple(arrays[k] for k in ("t", "q", "qd", "qdd", "tau"))


def _joint_order(given, joints: list, name: str):
    """The columns' order into the robot's, from a segment's ``joints`` (None: as they are)."""
    if given is None or list(given) == list(joints):
        return None
    given = list(given)
    if sorted(given) != sorted(joints):
        raise ValueError(f"{name}: joints {given} are not the robot's {list(joints)}")
    return [given.index(j) for j in joints]


def _segments(data, joints: list, name: str) -> list:
    if data is None:
        return []
    many = isinstance(data, (list, tuple))
    return [_segment(d, joints, f"{name}[{k}]" if many else name) for k, d in enumerate(data if many else [data])]


class IdentifyResult(dict):
    """An identification's report, as ``momentlmi identify --json`` writes it: a dict
    (``bodies``, ``friction``, ``training_rms``, ``validation_rms``, ``status`` …) with
    the parameters as arrays and the command line's file text. Pickles as its text;
    ``repr`` is one line (robot, level, status, RMS, base parameters)."""

    def __init__(self, text: str):
        super().__init__(json.loads(text))
        self._text = text

    def __reduce__(self):
        return (IdentifyResult, (self._text,))

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

    def __repr__(self) -> str:
        rms = lambda k: "None" if self.get(k) is None else np.array2string(np.round(self[k], 4), separator=", ")
        ident = self.get("identifiability") or {}
        return (f"IdentifyResult(robot={self.get('robot')!r}, constraints={self.get('constraints')!r}, "
                f"status={self.get('status')!r}, weight={self.get('weight')}, bodies={len(self.get('bodies', []))}, "
                f"training_rms={rms('training_rms')}, validation_rms={rms('validation_rms')}, "
                f"base_parameters='{ident.get('rank')} of {ident.get('columns')}')")

    __str__ = __repr__


def _weight(weight) -> Optional[str]:
    """`weight` as the extension takes it: None, ``auto`` or a number's text."""
    if weight is None or (isinstance(weight, str) and weight == "auto"):
        return weight
    if isinstance(weight, str):
        raise ValueError(f"weight: '{weight}' is not a number or 'auto'")
    return repr(_args.number(weight, "weight", nonnegative=True))


def _friction(friction) -> Optional[str]:
    """`friction` as the extension takes it: None, ``auto`` or a comma-separated list
    (an empty list: ``none``)."""
    if friction is None or (isinstance(friction, str) and friction.strip() == "auto"):
        return friction
    terms = _args.names(friction, "friction")
    return ",".join(terms) if terms else "none"


def identify(robot: Robot, data, constraints: str = "ellipsoid", prior="cad",
             weight: Union[None, float, str] = None, regularizer: Optional[str] = None, validate=None,
             cutoff_hz: Optional[float] = None, velocity: str = "differentiate",
             friction: Union[None, str, Sequence[str]] = None,
             bounds: Union[None, float, str] = None, rows: Optional[str] = None) -> IdentifyResult:
    """The identification of `robot` from `data`, as ``momentlmi identify --json``
    reports it (``bodies`` with each body's ``params``, ``training_rms``,
    ``validation_rms`` …); every warning the command line prints beside it is issued as
    a :class:`MomentlmiWarning`.

    `robot` a :class:`Robot` (or a built-in's name, a URDF's path). `data` (and
    `validate`, held out) is a segment or a list of segments, each a dict
    of arrays ``t`` (N,), ``q``, and ``qd``, ``qdd``, ``tau`` (N, n) where recorded, or
    a pandas DataFrame with the CSV's column names (``t``, ``q_<joint>`` …). A segment
    with ``qdd`` is taken as it is; one without is filtered and differentiated as a raw
    log file (`cutoff_hz`: a frequency > 0, always checked; None chooses it; `velocity`:
    differentiate or file).
    `constraints`: none, semi, consistent or ellipsoid; `prior`: cad, true, or a
    parameter file (a result, a dict, JSON text or a path); `weight`: a number or
    ``"auto"`` (cross-validation; None, the default: auto when the friction law is
    chosen, else 1e-6);
    `regularizer`: euclidean, entropic or pullback (None, the default: entropic when the
    weight is chosen and every prior body is strictly consistent, else euclidean — as
    ``--regularizer``); `friction`: the friction terms identified (a list or a
    comma-separated string: ``"viscous,coulomb,offset,load,stribeck"``); ``"auto"``:
    chosen by cross-validation on the training data, with the weight when it is ``"auto"``,
    the table in ``result["model_selection"]``; None, the default: auto, with viscous +
    Coulomb kept (a ``law_not_chosen`` warning) when the data are too short to choose —
    as ``momentlmi identify`` without ``--friction``); `bounds`: each
    parameter's range over the constrained models whose residual is at most (1 + bounds)
    × the estimate's (``"auto"``: the 95 % confidence region; None: not computed), in
    ``result["bounds"]``. ``result["identifiability"]`` has the rank, the base
    parameters with their standard deviations and the parameters that enter no torque.

    A floating-base `robot` (``Robot.from_urdf(..., floating_base=True)``) is identified
    as ``momentlmi identify --floating-base --json`` does it: each log of `data` and
    `validate` a file (CSV or ``.npz``, docs/floating-base.md) or its columns (a
    DataFrame, or a dict of 1-D arrays, named as the CSV's: ``t``, ``base_x`` …,
    ``q_<joint>`` …, ``force_<link>_x`` …); `rows` ``"base"``, ``"joints"`` or ``"all"``
    (None: every row when the logs have joint torques, else the base's); `weight` a
    number (None: 1e-6), `friction` a list (None: the robot's own terms); `cutoff_hz`,
    `velocity`, `bounds` and the ``"auto"`` choices are not taken for a floating base yet."""
    r = _robot(robot)
    if r.floating_base:
        given = {"cutoff_hz": cutoff_hz is not None, "velocity": velocity != "differentiate",
                 "bounds": bounds is not None, "weight='auto'": weight == "auto",
                 "friction='auto'": friction == "auto"}
        return _identify_logs(r, data, validate, constraints, prior, weight, regularizer, friction,
                              rows, [k for k, v in given.items() if v])
    if rows is not None:
        raise ValueError(f"rows: '{r._r.load_args[0]}' is loaded with a fixed base, which has only joint "
                         "rows (rows is for a floating base: Robot.from_urdf(path, sidecar=...) with its "
                         "[floating_base] table, or floating_base=True)")
    joints = r.joint_names
    if bounds is not None and not (isinstance(bounds, str) and bounds == "auto"):
        if isinstance(bounds, str):
            raise ValueError(f"bounds: '{bounds}' is not a number >= 0 or 'auto'")
        bounds = repr(_args.number(bounds, "bounds", nonnegative=True))
    cut = None if cutoff_hz is None else _args.number(cutoff_hz, "cutoff_hz", positive=True)
    segs = (_segments(data, joints, "data"), _segments(validate, joints, "validate"))
    options = (_text(constraints, "constraints"),)
    reg = None if regularizer is None else _text(regularizer, "regularizer")
    with _params_file(prior, "prior") as p:
        text, notes = _native.identify(r._r, *segs, *options, p, _weight(weight), reg, cut,
                                       _text(velocity, "velocity"), _friction(friction), bounds)
    _warn(notes)
    return IdentifyResult(text)


def _floating_log(d, name: str):
    """A floating-base log as the extension takes it: a path, or (names, 1-D arrays)."""
    if isinstance(d, (str, os.PathLike)):
        return os.fspath(d)
    if _args.is_frame(d):
        items = [(str(c), d[c]) for c in d.columns]
    elif isinstance(d, dict):
        items = [(str(k), v) for k, v in d.items()]
    else:
        raise TypeError(f"{name}: a file's path, a DataFrame or a dict of columns, not {type(d).__name__}")
    fixed = {"q", "qd", "qdd", "tau", "joints"} & {k for k, _ in items}
    if fixed:
        raise ValueError(f"{name}: a fixed-base log ({', '.join(sorted(fixed))}); a floating base's log "
                         "has the CSV's columns: t, base_x …, q_<joint> …, force_<link>_x … "
                         "(docs/floating-base.md)")
    columns = [_args.times(v, f"{name}: {k}") for k, v in items]
    for (k, _), c in zip(items, columns):
        if c.ndim != 1:
            raise ValueError(f"{name}: column '{k}' has shape {c.shape}, not (N,)")
    return ([k for k, _ in items], columns)


def _identify_logs(r: Robot, data, validate, constraints, prior, weight, regularizer, friction,
                   rows, refused: list) -> IdentifyResult:
    """:func:`identify` of a floating-base robot."""
    if refused:
        raise ValueError(f"{refused[0]} is not available for a floating base yet "
                         "(docs/floating-base.md, \"Not yet built\")")
    logs = lambda x, name: [] if x is None else [
        _floating_log(d, f"{name}[{k}]" if isinstance(x, (list, tuple)) else name)
        for k, d in enumerate(x if isinstance(x, (list, tuple)) else [x])]
    w = None if weight is None else _args.number(weight, "weight", nonnegative=True)
    reg = None if regularizer is None else _text(regularizer, "regularizer")
    fr = None if friction is None else _friction(friction)
    rw = None if rows is None else _text(rows, "rows")
    with _params_file(prior, "prior") as p:
        text, notes = _native.identify_logs(r._r, logs(data, "data"), logs(validate, "validate"),
                                            _text(constraints, "constraints"), p or "cad", w, reg, fr, rw)
    _warn(notes, stacklevel=4)
    return IdentifyResult(text)


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
    n = _args.number
    text, (t, q, qd, qdd) = _native.excite(_fixed(_robot(robot), "excite")._r, n(seconds, "seconds"), criterion,
                                           _args.count(harmonics, "harmonics"), n(base_hz, "base_hz"),
                                           _args.count(seeds, "seeds"), _args.count(seed, "seed"),
                                           _args.count(pool, "pool"), n(rate_hz, "rate_hz"))
    report = json.loads(text)
    report["samples"] = {"t": t, "q": q, "qd": qd, "qdd": qdd}
    return report


def diagnose(robot: Robot, data, nominal=None, repeats=None, nominal_data=None) -> dict:
    """Where `data` depart from the `nominal` model (None: the robot's own parameters;
    ``"cad"``, ``"true"`` or a parameter file: a result, a dict, JSON text or a path),
    which unmodelled effects explain the gap and how far it shrinks on held-out data,
    as ``momentlmi diagnose --json`` reports it; its warnings are issued as
    :class:`MomentlmiWarning`s. `data` as for :func:`identify`; `repeats`, two runs of
    one trajectory, give the noise floor (needed when the torques were low-pass
    filtered); `nominal_data`, the data the nominal was identified on (as `data`), have
    its bodies refit with the friction law so that what they could not determine is not
    named an effect (``--nominal-data``)."""
    r = _fixed(_robot(robot), "diagnose")
    joints = r.joint_names
    reps = _segments(repeats, joints, "repeats")
    own = _segments(nominal_data, joints, "nominal_data")
    with _params_file(nominal, "nominal") as nom:
        report = json.loads(_native.diagnosis(r._r, _segments(data, joints, "data"), nom, reps, own))
    _warn([(w.get("kind", "diagnose"), w.get("message", str(w))) for w in report.get("warnings", [])])
    return report


# -- the fleet path ---------------------------------------------------------


class Reducer:
    """Samples of one robot reduced to fixed-size sums (the Gram matrix of [Y τ]): add
    samples with :meth:`update`, other reducers' sums with :meth:`merge` (from other
    processes or machines: :meth:`to_bytes` / :meth:`from_bytes`), then :meth:`solve`
    one SDP. The sums of the parts are the sums of the whole. Pickles as its robot and
    its sums' bytes."""

    def __init__(self, robot: Robot, _native_reducer=None):
        self.robot = _robot(robot)
        self._r = _native_reducer if _native_reducer is not None else _native.Reducer(self.robot._r)

    def __reduce__(self):
        return (_reducer_again, (self.robot, self.to_bytes() if self.samples else None))

    @property
    def samples(self) -> int:
        """The samples reduced so far."""
        return self._r.samples

    def update(self, q, v, a, tau) -> "Reducer":
        """Adds samples: q (rad), v (rad/s), a (rad/s²), τ (N·m), each (N, n) (DataFrames
        by column name: ``<joint>`` or ``q_``, ``qd_``, ``qdd_``, ``tau_<joint>``)."""
        q, v, a = self.robot._states(q, v, a)
        self._r.update(q, v, a, _args.samples(tau, "tau", self.robot.joint_names, "tau"))
        return self

    def gram(self) -> np.ndarray:
        """The Gram matrix [Y τ]ᵀ[Y τ] of the samples so far, (p + 1) × (p + 1)."""
        return self._r.gram()

    def merge(self, other: "Reducer") -> "Reducer":
        """Adds the sums of `other` (the same robot's)."""
        if not isinstance(other, Reducer):
            raise TypeError(f"other: a Reducer, not {type(other).__name__}")
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
        if not isinstance(data, (bytes, bytearray, memoryview)):
            raise TypeError(f"data: bytes (Reducer.to_bytes()), not {type(data).__name__}")
        r = _robot(robot)
        return Reducer(r, _native.Reducer.from_bytes(r._r, bytes(data)))

    def solve(self, constraints: str = "ellipsoid", weight: float = 1e-6,
              regularizer: str = "euclidean") -> IdentifyResult:
        """The identification on the sums, as ``momentlmi identify --json`` reports it
        (:class:`IdentifyResult`; its warnings issued as :class:`MomentlmiWarning`s):
        `constraints` none, semi, consistent or ellipsoid; toward the robot's prior with
        `weight`, a number ≥ 0 (``"auto"`` is refused: choosing it cross-validates on
        samples, which the sums no longer hold — :func:`identify` does it)."""
        if isinstance(weight, str):
            raise ValueError(f"weight: {weight!r}: Reducer.solve takes a number >= 0; choosing the weight "
                             f"('auto') cross-validates on the samples, which the sums do not keep "
                             f"(identify(robot, data, weight='auto') does it)")
        w = _args.number(weight, "weight", nonnegative=True)
        text, notes = self._r.solve(_text(constraints, "constraints"), w, _text(regularizer, "regularizer"))
        _warn(notes)
        return IdentifyResult(text)


def _reducer_again(robot: Robot, data: Optional[bytes]) -> Reducer:
    """A pickled :class:`Reducer` made again from its robot and its sums."""
    return Reducer(robot) if data is None else Reducer.from_bytes(robot, data)
