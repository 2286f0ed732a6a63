"""Input validation shared by the whole package.

Every public entry point checks its arguments here, so that a bad input always
gives a ``ValueError`` that names the parameter and says what is allowed.
"""
from __future__ import annotations

import math
from numbers import Real

import numpy as np


def real(name: str, value, *, low=None, high=None, low_open=False, high_open=False) -> float:
    """A finite real number, optionally within [low, high] (or open ends)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (Real, np.floating, np.integer)):
        raise ValueError(f"{name} must be a real number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value!r}")
    if low is not None and (value < low or (low_open and value == low)):
        bound = f"> {low:g}" if low_open else f">= {low:g}"
        raise ValueError(f"{name} must be {bound}, got {value!r}")
    if high is not None and (value > high or (high_open and value == high)):
        bound = f"< {high:g}" if high_open else f"<= {high:g}"
        raise ValueError(f"{name} must be {bound}, got {value!r}")
    return value


def positive(name: str, value) -> float:
    """A finite real number > 0."""
    return real(name, value, low=0.0, low_open=True)


def integer(name: str, value, *, low=None, high=None) -> int:
    """An int within [low, high]."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    value = int(value)
    if (low is not None and value < low) or (high is not None and value > high):
        raise ValueError(f"{name} must be an integer in [{low}, {high}], got {value}")
    return value


def array(name: str, value, shape: tuple, *, batch: bool = False) -> np.ndarray:
    """A finite float array of the given trailing shape (with any leading dims if batch)."""
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an array of numbers with shape {_fmt(shape)}, got {value!r}") from None
    ok = arr.shape[arr.ndim - len(shape):] == shape if batch else arr.shape == shape
    if not ok or (batch and arr.ndim > len(shape) + 1):
        want = f"{_fmt(shape)} or (N, {_fmt(shape)[1:-1]})" if batch else _fmt(shape)
        raise ValueError(f"{name} must have shape {want}, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must contain only finite numbers (no NaN or inf), got {arr.tolist()}")
    return arr


def vector3(name: str, value) -> np.ndarray:
    """A finite 3-vector."""
    return array(name, value, (3,))


def choice(name: str, value, allowed) -> str:
    """One of a fixed set of strings."""
    if value not in allowed:
        raise ValueError(f"{name} must be one of {sorted(allowed)}, got {value!r}")
    return value


def _fmt(shape: tuple) -> str:
    return "(" + ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"
