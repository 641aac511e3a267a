"""Project exceptions and parameter checks.

Every message names the parameter, the value received and the allowed range, so a user
never has to read a traceback from deep inside numpy to find out what is wrong.
"""

from __future__ import annotations

import numpy as np


class FricdampError(Exception):
    """Base class of every error raised on purpose by fricdamp."""


class ModelError(FricdampError, ValueError):
    """A model or parameter is invalid (negative mass, mu < 0, singular mass matrix, ...)."""


class ConvergenceError(FricdampError, RuntimeError):
    """A nonlinear solver did not converge; the message says where and what to try."""


class CaseError(FricdampError, ValueError):
    """A case file is invalid (typo'd key, wrong type, value out of range)."""


def _short(value) -> str:
    """``repr`` of a value, cut to 60 characters (an array can be millions of numbers)."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def as_finite_array(name: str, value, *, ndim: int | None = None) -> np.ndarray:
    """Return ``value`` as a float array, raising ModelError if it holds NaN or inf.

    The message names the first bad entry by its 1-based position (as the product counts)."""
    if isinstance(value, (str, bytes)):
        raise ModelError(f"{name} must be numeric, got {_short(value)}")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ModelError(f"{name} must be numeric, got {_short(value)}") from exc
    if ndim is not None and arr.ndim != ndim:
        raise ModelError(f"{name} must have {ndim} dimension(s), got shape {arr.shape}")
    finite = np.isfinite(arr)
    if not np.all(finite):
        if arr.ndim == 0:
            raise ModelError(f"{name} must be finite (no NaN or inf), got {_short(value)}")
        where = tuple(int(i) + 1 for i in np.argwhere(~finite)[0])
        pos = where[0] if len(where) == 1 else where
        raise ModelError(f"{name} must be finite (no NaN or inf): entry {pos} (counting from "
                         f"1) is {arr[tuple(i - 1 for i in where)]}")
    return arr


def check_positive(name: str, value, *, unit: str = "", allow_zero: bool = False) -> np.ndarray:
    """Check ``value`` (scalar or array) is finite and > 0 (>= 0 with ``allow_zero``)."""
    arr = as_finite_array(name, value)
    bad = arr < 0 if allow_zero else arr <= 0
    if np.any(bad):
        rng = ">= 0" if allow_zero else "> 0"
        u = f" {unit}" if unit else ""
        raise ModelError(f"{name} must be {rng}{u}, got {value!r}")
    return arr


def check_range(name: str, value, low: float, high: float, *, unit: str = "",
                low_open: bool = False, high_open: bool = False) -> np.ndarray:
    """Check ``low <= value <= high`` (with open ends if asked); raise ModelError otherwise."""
    arr = as_finite_array(name, value)
    lo_bad = arr <= low if low_open else arr < low
    hi_bad = arr >= high if high_open else arr > high
    if np.any(lo_bad | hi_bad):
        lb = "(" if low_open else "["
        hb = ")" if high_open else "]"
        u = f" {unit}" if unit else ""
        raise ModelError(f"{name} must lie in {lb}{low}, {high}{hb}{u}, got {value!r}")
    return arr


class OutputError(FricdampError, OSError):
    """A result could not be written (folder not writable, disk full, another run holds the
    folder); the message names the file. Exit code 1 on the command line."""


class CheckError(ModelError):
    """A run would need more memory or time than is sensible (the message names the parameter
    that drives the size, the estimate and the limit)."""
