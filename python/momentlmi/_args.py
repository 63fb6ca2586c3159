"""Arguments checked and converted before they reach the extension.

Every rule of docs/python.md ("Arguments") is here: a bad argument is a
``ValueError`` (a wrong value) or a ``TypeError`` (a wrong kind) whose message
starts with the argument's name.

- Arrays of samples (q, v, a, τ): array-likes, or pandas DataFrames whose columns
  are found by name (``<joint>`` or the CSV's ``<prefix>_<joint>``), never by
  position; a Series is one sample, found by its index's names.
- Arrays with no names (π, a centre, …): array-likes; a pandas object is refused
  (its labels cannot name the values here).
- Lists of names: a list (tuple …) of strings or one comma-separated string.
- Parameters (a parameter file): an identification's result, a dict, JSON text or
  a file's path.
- Numbers and counts: real numbers (not strings), counts integers ≥ their least.
"""

from __future__ import annotations

import json
import numbers
import os
from typing import Optional

import numpy as np

#: The largest seed, count … the extension takes (an unsigned 64-bit integer).
MAX_COUNT = 2**64 - 1


def is_frame(x) -> bool:
    """Whether `x` is a pandas DataFrame (by its shape, not by importing pandas)."""
    return hasattr(x, "columns") and hasattr(x, "to_numpy") and hasattr(x, "index")


def is_series(x) -> bool:
    """Whether `x` is a pandas Series (one-dimensional, labelled)."""
    return (not is_frame(x) and hasattr(x, "index") and hasattr(x, "to_numpy")
            and getattr(x, "ndim", None) == 1)


def floats(x, name: str) -> np.ndarray:
    """`x` as a C-contiguous float64 array: a pandas object is refused (a TypeError:
    its labels cannot say which value is which here), something that is not numbers is
    a ValueError naming `name`."""
    if is_frame(x) or is_series(x):
        raise TypeError(f"{name}: a pandas {type(x).__name__} has labels that cannot name these "
                        f"values; pass an array (.to_numpy()) in the documented order")
    return _array(x, name)


def times(x, name: str) -> np.ndarray:
    """Time stamps (N,): an array-like or a pandas Series (its values)."""
    if is_series(x):
        x = x.to_numpy()
    return floats(x, name)


def _array(x, name: str) -> np.ndarray:
    try:
        return np.ascontiguousarray(np.asarray(x, dtype=np.float64))
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name}: not an array of numbers ({e})") from None


def samples(x, name: str, joints: list, prefix: str) -> np.ndarray:
    """Samples (N, n) in the robot's joint order: an array-like as it is; a DataFrame's
    columns (a Series' index) found by name, ``<joint>`` or ``<prefix>_<joint>``."""
    if is_frame(x):
        labels = [str(c) for c in x.columns]
        cols = _by_name(labels, name, joints, prefix)
        return _array(x.to_numpy()[:, cols], name)
    if is_series(x):
        labels = [str(c) for c in x.index]
        cols = _by_name(labels, name, joints, prefix)
        return _array(x.to_numpy()[cols], name)
    return _array(x, name)


def _by_name(labels: list, name: str, joints: list, prefix: str) -> list:
    """The positions of the robot's joints among `labels`, by name."""
    schemes = [[f"{prefix}_{j}" for j in joints], list(joints)]
    complete = [s for s in schemes if all(c in labels for c in s)]
    if len(complete) == 2:
        raise ValueError(f"{name}: both {prefix}_<joint> and <joint> columns ({', '.join(joints)}): "
                         f"which to take is ambiguous; select one set")
    if not complete:
        best = max(schemes, key=lambda s: sum(c in labels for c in s))
        missing = [c for c in best if c not in labels]
        raise ValueError(f"{name}: labelled columns are matched by name ({prefix}_<joint> or <joint> "
                         f"for each of {', '.join(joints)}); missing {', '.join(missing)} "
                         f"(it has {', '.join(labels[:12])}{' …' if len(labels) > 12 else ''})")
    want = complete[0]
    for c in want:
        if labels.count(c) > 1:
            raise ValueError(f"{name}: column '{c}' appears {labels.count(c)} times")
    return [labels.index(c) for c in want]


def number(x, name: str, *, positive: bool = False, nonnegative: bool = False,
           finite: bool = True) -> float:
    """A real number (not a string, not a bool): a TypeError if it is none, a
    ValueError if it is not finite or out of range."""
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Real):
        raise TypeError(f"{name}: {x!r} is not a number")
    v = float(x)
    if finite and not np.isfinite(v):
        raise ValueError(f"{name}: {v} is not finite")
    if positive and not v > 0:
        raise ValueError(f"{name}: {v} is not > 0")
    if nonnegative and not v >= 0:
        raise ValueError(f"{name}: {v} is not >= 0")
    return v


def count(x, name: str, least: int = 0) -> int:
    """An integer in [least, 2⁶⁴ − 1] (a float with no fraction is not taken)."""
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Integral):
        raise TypeError(f"{name}: {x!r} is not an integer")
    v = int(x)
    if not least <= v <= MAX_COUNT:
        raise ValueError(f"{name}: {v} is not an integer in [{least}, 2**64 - 1]")
    return v


def names(x, name: str) -> list:
    """A list of names: a comma-separated string (``"viscous,coulomb"``) or a list
    (tuple, …) of strings; empty items are dropped."""
    if x is None:
        return []
    if isinstance(x, str):
        items = x.split(",")
    elif isinstance(x, (bytes, bytearray)) or not hasattr(x, "__iter__"):
        raise TypeError(f"{name}: a comma-separated string or a list of strings, not {type(x).__name__}")
    else:
        items = list(x)
        bad = [i for i in items if not isinstance(i, str)]
        if bad:
            raise TypeError(f"{name}: {bad[0]!r} is not a string")
    return [i.strip() for i in items if i.strip()]


def path(x, name: str) -> str:
    """A file's path: a string or an ``os.PathLike``."""
    if isinstance(x, (str, os.PathLike)):
        return os.fspath(x)
    raise TypeError(f"{name}: a path (str or os.PathLike), not {type(x).__name__}")


def optional_path(x, name: str) -> Optional[str]:
    return None if x is None else path(x, name)


def paths(x, name: str) -> list:
    """Paths: one path, or a list (tuple, …) of them."""
    if x is None:
        return []
    if isinstance(x, (str, os.PathLike)):
        return [os.fspath(x)]
    if not hasattr(x, "__iter__"):
        raise TypeError(f"{name}: a path or a list of paths, not {type(x).__name__}")
    return [path(p, f"{name}[{k}]") for k, p in enumerate(x)]


def is_json_text(x) -> bool:
    """Whether the string `x` is JSON text (an object), not a path."""
    return isinstance(x, str) and x.lstrip().startswith("{")


def params_text(x, name: str) -> Optional[str]:
    """A parameter file's text from an identification's result, a dict or JSON text;
    None for a path (the library reads it: its errors name `name`)."""
    if hasattr(x, "to_json") and callable(x.to_json) and isinstance(x, dict):
        return x.to_json()
    if isinstance(x, dict):
        return json.dumps(x)
    if is_json_text(x):
        return x
    if isinstance(x, (str, os.PathLike)):
        return None
    raise TypeError(f"{name}: an identify result, a dict, JSON text or a file's path, not {type(x).__name__}")
