"""Parameter grids of a study and the overriding of case-file keys by study parameters.

A grid axis is written ``name=start:stop:num`` (``num`` values from ``start`` to ``stop``,
both included, evenly spaced as :func:`numpy.linspace`) or ``name=v1,v2,v3`` (the listed
values, in the given order) or ``name=v`` (one value). In a case file the same axis is a key of
the ``[sweep.grid]`` table whose value is that string, a list of numbers, one number or a table
``{start = .., stop = .., num = ..}``. A grid is the Cartesian product of its axes, in the order
they were given (the first axis varies slowest).

Parameter names are identifiers, or dotted paths into a case (``model.damper_mass_kg``,
``contacts.1.mu``, ``contacts.left.mu``; list entries are numbered from 1, as everywhere in
case files). :func:`resolve_parameter` finds where a name lives in a case dict, and
:func:`apply_overrides` returns a copy of the case with the grid point's values written in; the
copy is then validated again by the case schema, so a value out of range is reported as in a
case file.

Every problem (empty range, repeated value, non-numeric value, unknown or ambiguous name) is a
:class:`~fricdamp.errors.CaseError` that names the parameter and says what is allowed.
"""

from __future__ import annotations

import copy
import difflib
import itertools
import math
import re
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from fricdamp.errors import CaseError

__all__ = [
    "Grid",
    "apply_overrides",
    "check_bounds",
    "leaf_paths",
    "parse_axis",
    "parse_bounds",
    "resolve_parameter",
]

_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\.([A-Za-z_][A-Za-z0-9_]*|[0-9]+))*$")
_SYNTAX = "NAME=START:STOP:NUM, NAME=V1,V2,... or NAME=V"

#: Largest grid accepted (points); a typo in NUM should not start a ten-million-point study.
MAX_POINTS = 1_000_000


# ------------------------------------------------------------------------------ numbers
def _number(text: str, name: str, what: str = "value") -> float:
    token = text.strip()
    try:
        value = float(token)
    except ValueError:
        raise CaseError(f"grid {what} {token!r} of parameter {name!r} is not a number "
                        f"(expected {_SYNTAX})") from None
    if not math.isfinite(value):
        raise CaseError(f"grid {what} of parameter {name!r} must be finite, got {token!r}")
    return value


def _as_number(value, name: str, what: str = "value") -> float | int:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise CaseError(f"grid {what} of parameter {name!r} must be a number, got {value!r} "
                        f"({type(value).__name__})")
    if not math.isfinite(float(value)):
        raise CaseError(f"grid {what} of parameter {name!r} must be finite, got {value!r}")
    return int(value) if isinstance(value, (int, np.integer)) else float(value)


def _check_name(name: str) -> str:
    if not isinstance(name, str) or not _NAME.match(name):
        raise CaseError(f"grid parameter name {name!r} is not valid: use a key of the case such "
                        "as gamma_deg, or a dotted path such as model.gamma_deg or contacts.1.mu")
    return name


def _linspace(name: str, start: float, stop: float, num) -> np.ndarray:
    if isinstance(num, float) and num.is_integer():
        num = int(num)
    if isinstance(num, bool) or not isinstance(num, (int, np.integer)):
        raise CaseError(f"grid parameter {name!r}: the number of values NUM must be an integer "
                        f">= 1, got {num!r}")
    if num < 1:
        raise CaseError(f"grid parameter {name!r}: empty range ({num} values from {start:g} to "
                        f"{stop:g}); NUM must be >= 1")
    if num > 1 and start == stop:
        raise CaseError(f"grid parameter {name!r}: empty range (start = stop = {start:g} with "
                        f"{num} values); give different START and STOP, or NUM = 1")
    if num == 1 and start != stop:
        raise CaseError(f"grid parameter {name!r}: one value (NUM = 1) between {start:g} and "
                        f"{stop:g} is ambiguous; write {name}={start:g}")
    if num > MAX_POINTS:
        raise CaseError(f"grid parameter {name!r}: NUM = {num} is more than {MAX_POINTS} values")
    return np.linspace(start, stop, int(num))


def _values(name: str, values: Sequence) -> np.ndarray:
    if len(values) == 0:
        raise CaseError(f"grid parameter {name!r} has no values (empty list)")
    nums = [_as_number(v, name) for v in values]
    arr = np.asarray(nums, dtype=np.int64 if all(isinstance(v, int) for v in nums) else float)
    if np.unique(arr).size != arr.size:
        seen, dup = set(), None
        for v in nums:
            if v in seen:
                dup = v
                break
            seen.add(v)
        raise CaseError(f"grid parameter {name!r} lists the value {dup!r} twice; each grid "
                        "value must be different")
    return arr


# --------------------------------------------------------------------------------- axes
def parse_axis(spec: str) -> tuple[str, np.ndarray]:
    """Parse one command-line grid axis.

    Parameters
    ----------
    spec : str
        ``"name=start:stop:num"``, ``"name=v1,v2,v3"`` or ``"name=v"``.

    Returns
    -------
    name : str
    values : numpy.ndarray, shape (n,)
        float values (int64 when every listed value is an integer literal).

    Raises
    ------
    CaseError
        Missing ``=``, bad name, non-numeric value, empty range, repeated value.

    Examples
    --------
    >>> parse_axis("gamma_deg=40:70:4")
    ('gamma_deg', array([40., 50., 60., 70.]))
    >>> parse_axis("harmonics=1,3,5")
    ('harmonics', array([1, 3, 5]))
    """
    if not isinstance(spec, str) or "=" not in spec:
        raise CaseError(f"grid {spec!r} must be written {_SYNTAX}")
    name, _, text = spec.partition("=")
    name = _check_name(name.strip())
    text = text.strip()
    if not text:
        raise CaseError(f"grid parameter {name!r} has no values (expected {_SYNTAX})")
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise CaseError(f"grid parameter {name!r}: range {text!r} must be START:STOP:NUM "
                            "(three numbers separated by ':')")
        start = _number(parts[0], name, "START")
        stop = _number(parts[1], name, "STOP")
        num_text = parts[2].strip()
        if not re.fullmatch(r"[+-]?[0-9]+", num_text):
            raise CaseError(f"grid parameter {name!r}: the number of values NUM must be an "
                            f"integer >= 1, got {num_text!r}")
        return name, _linspace(name, start, stop, int(num_text))
    items = text.split(",")
    if any(not item.strip() for item in items):
        raise CaseError(f"grid parameter {name!r}: empty entry in the list {text!r}")
    nums = []
    for item in items:
        token = item.strip()
        nums.append(int(token) if re.fullmatch(r"[+-]?[0-9]+", token)
                    else _number(token, name))
    return name, _values(name, nums)


def _axis_from_value(name: str, value) -> np.ndarray:
    """Axis from a case-file value: string, list, number or {start, stop, num} table."""
    if isinstance(value, str):
        return parse_axis(f"{name}={value}")[1]
    if isinstance(value, Mapping):
        keys = set(value)
        if keys == {"values"}:
            return _axis_from_value(name, value["values"])
        if keys != {"start", "stop", "num"}:
            raise CaseError(f"grid parameter {name!r}: a table must have exactly the keys "
                            f"start, stop, num (or values), got {sorted(keys)}")
        start = float(_as_number(value["start"], name, "start"))
        stop = float(_as_number(value["stop"], name, "stop"))
        return _linspace(name, start, stop, value["num"])
    if isinstance(value, (list, tuple, np.ndarray)):
        return _values(name, list(value))
    return _values(name, [value])


_RANGE_KEYS = {"start", "stop", "num", "values"}


def _flat_items(mapping: Mapping, prefix: str):
    """(dotted name, value) pairs: TOML reads ``contacts.1.mu = ..`` as nested tables."""
    for k, v in mapping.items():
        name = f"{prefix}{k}"
        if isinstance(v, Mapping) and v and not set(v) & _RANGE_KEYS:
            yield from _flat_items(v, f"{name}.")
        else:
            yield name, v


@dataclass(frozen=True)
class Grid:
    """A Cartesian grid of named parameters.

    Attributes
    ----------
    axes : tuple of (str, numpy.ndarray)
        Parameter name and its values (shape ``(n_i,)``), in order; the first axis varies
        slowest in :meth:`points`.
    """

    axes: tuple[tuple[str, np.ndarray], ...]

    def __post_init__(self):
        if not self.axes:
            raise CaseError("the grid is empty: give at least one parameter "
                            f"({_SYNTAX})")
        names = [n for n, _ in self.axes]
        for n in names:
            _check_name(n)
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise CaseError(f"grid parameter {dup[0]!r} is given twice")
        if self.size > MAX_POINTS:
            raise CaseError(f"the grid has {self.size} points, more than {MAX_POINTS}")

    # -- construction
    @classmethod
    def parse(cls, specs: Iterable[str]) -> Grid:
        """Grid from command-line specs (``["m=1:2:3", "g=40,50"]``)."""
        if isinstance(specs, str):
            specs = [specs]
        return cls(tuple(parse_axis(s) for s in specs))

    @classmethod
    def from_mapping(cls, mapping: Mapping) -> Grid:
        """Grid from a mapping name -> values (a ``[sweep.grid]`` table, or a dict in Python).

        Each value is a grid string (``"0.5e-3:3e-3:11"``), a sequence of numbers, one number
        or a table ``{start, stop, num}``. Nested tables (TOML's reading of an unquoted
        dotted key ``contacts.1.mu = [..]``) give dotted names.
        """
        if not isinstance(mapping, Mapping):
            raise CaseError(f"the grid must be a table of parameter = values, got {mapping!r}")
        return cls(tuple((_check_name(k), _axis_from_value(k, v))
                         for k, v in _flat_items(mapping, "")))

    @classmethod
    def coerce(cls, grid) -> Grid:
        """Accept a Grid, a mapping or a sequence of spec strings."""
        if isinstance(grid, Grid):
            return grid
        if isinstance(grid, Mapping):
            return cls.from_mapping(grid)
        if isinstance(grid, (str, list, tuple)):
            return cls.parse(grid)
        raise CaseError(f"a grid must be a mapping name -> values or a list of "
                        f"'{_SYNTAX}' strings, got {type(grid).__name__}")

    # -- shape
    @property
    def names(self) -> tuple[str, ...]:
        """Parameter names, in axis order."""
        return tuple(n for n, _ in self.axes)

    @property
    def shape(self) -> tuple[int, ...]:
        """Number of values of each axis."""
        return tuple(len(v) for _, v in self.axes)

    @property
    def size(self) -> int:
        """Number of grid points."""
        return math.prod(self.shape)

    def __getitem__(self, name: str) -> np.ndarray:
        for n, v in self.axes:
            if n == name:
                return v
        raise KeyError(name)

    def points(self) -> Iterator[dict[str, float | int]]:
        """Grid points as ``{name: value}`` (Python numbers), first axis slowest (C order)."""
        names = self.names
        for combo in itertools.product(*(v.tolist() for _, v in self.axes)):
            yield dict(zip(names, combo, strict=True))

    def check_names(self, allowed: Iterable[str], *, what: str = "the function") -> None:
        """Raise CaseError naming the first parameter not in ``allowed`` (with a suggestion)."""
        allowed = list(allowed)
        for name in self.names:
            if name not in allowed:
                raise CaseError(f"unknown grid parameter {name!r}: {what} takes "
                                f"{', '.join(allowed) or 'no parameters'}"
                                f"{_did_you_mean(name, allowed)}")

    def describe(self) -> str:
        """One line per axis: ``name: n values from a to b``."""
        lines = []
        for n, v in self.axes:
            if len(v) == 1:
                lines.append(f"{n}: {v[0]:g}")
            else:
                lines.append(f"{n}: {len(v)} values from {v[0]:g} to {v[-1]:g}")
        return "\n".join(lines)


# ------------------------------------------------------------------------------- bounds
def parse_bounds(specs: Iterable[str] | str | Mapping) -> dict[str, tuple[float, float]]:
    """Bounds of an optimisation: ``"a=lo:hi,b=lo:hi"`` (or a list of such, or a mapping).

    Returns
    -------
    dict name -> (low, high)
        In the order given.

    Raises
    ------
    CaseError
        Bad syntax, non-numeric bound, ``low >= high``, a name given twice.
    """
    out: dict[str, tuple[float, float]] = {}
    if isinstance(specs, Mapping):
        items = []
        for name, value in specs.items():
            if isinstance(value, str):
                items.append(f"{name}={value}")
            elif isinstance(value, (list, tuple)) and len(value) == 2:
                lo, hi = (_as_number(v, str(name), "bound") for v in value)
                items.append(f"{name}={lo!r}:{hi!r}")
            else:
                raise CaseError(f"bounds of parameter {name!r} must be [low, high] or "
                                f"'low:high', got {value!r}")
    else:
        if isinstance(specs, str):
            specs = [specs]
        items = [item for spec in specs for item in str(spec).split(",") if item.strip()]
    if not items:
        raise CaseError("no parameters to optimise over: give NAME=LOW:HIGH,...")
    for item in items:
        if "=" not in item:
            raise CaseError(f"bounds {item!r} must be written NAME=LOW:HIGH")
        name, _, text = item.partition("=")
        name = _check_name(name.strip())
        parts = text.split(":")
        if len(parts) != 2:
            raise CaseError(f"bounds of parameter {name!r} must be LOW:HIGH, got {text!r}")
        lo = _number(parts[0], name, "LOW")
        hi = _number(parts[1], name, "HIGH")
        if not lo < hi:
            raise CaseError(f"bounds of parameter {name!r}: LOW ({lo:g}) must be smaller than "
                            f"HIGH ({hi:g})")
        if name in out:
            raise CaseError(f"parameter {name!r} is given twice")
        out[name] = (lo, hi)
    return out


def check_bounds(bounds: Mapping[str, tuple[float, float]]) -> dict[str, tuple[float, float]]:
    """Validate a mapping name -> (low, high) given in Python; return it as floats."""
    return parse_bounds(dict(bounds))


# ---------------------------------------------------------------------------- overrides
def _did_you_mean(word: str, choices: Iterable[str]) -> str:
    choices = list(choices)
    close = difflib.get_close_matches(word, choices, n=1, cutoff=0.6)
    if not close and "." in word:
        close = difflib.get_close_matches(word.rsplit(".", 1)[-1], choices, n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def leaf_paths(case: Mapping, *, skip: Iterable[str] = ("sweep", "optimize")) -> list[tuple]:
    """Paths (tuples of keys and 0-based list indices) of every number in a case dict.

    Top-level tables named in ``skip`` (the study's own settings) are left out.
    """
    skip = set(skip)
    out: list[tuple] = []

    def walk(node, path):
        if isinstance(node, Mapping):
            for k, v in node.items():
                if not path and k in skip:
                    continue
                walk(v, (*path, k))
        elif isinstance(node, list):
            for i, v in enumerate(node):
                walk(v, (*path, i))
        elif _is_number(node):
            out.append(path)

    walk(case, ())
    return out


def _non_number_paths(case: Mapping, key: str) -> list[tuple[tuple, object]]:
    """(path, value) of tables and lists stored under ``key`` anywhere in the case."""
    found = []

    def walk(node, path):
        if isinstance(node, Mapping):
            for k, v in node.items():
                if not path and k in ("sweep", "optimize"):
                    continue
                if k == key and isinstance(v, (Mapping, list)):
                    found.append(((*path, k), v))
                walk(v, (*path, k))
        elif isinstance(node, list):
            for i, v in enumerate(node):
                walk(v, (*path, i))

    walk(case, ())
    return found


def _dotted(path: tuple) -> str:
    return ".".join(str(p + 1) if isinstance(p, int) else str(p) for p in path)


def resolve_parameter(case: Mapping, name: str) -> tuple:
    """Where parameter ``name`` lives in ``case``: a path of keys and 0-based list indices.

    A plain name (``gamma_deg``) must be the key of exactly one number in the case. A dotted
    name is a path from the top: table keys, list entries numbered from 1, or a list entry
    named by its ``name`` key (``contacts.left.mu``); its last key may be absent from the
    table (a schema default), the case schema then decides whether the key exists. A dotted
    name whose first part is not a top-level key is the end of exactly one full path
    (``initial_displacement_m.1`` for ``analysis.free_decay.initial_displacement_m.1``).

    Raises
    ------
    CaseError
        Unknown name (with the closest existing one), a name found in several places (listing
        the dotted paths to use), or a path that reaches a table or list instead of a number.
    """
    _check_name(name)
    leaves = leaf_paths(case)
    dotted = [_dotted(p) for p in leaves]
    if "." not in name:
        hits = [p for p in leaves if p and p[-1] == name]
        if len(hits) == 1:
            return hits[0]
        if len(hits) > 1:
            raise CaseError(f"grid parameter {name!r} is ambiguous: the case has it at "
                            f"{', '.join(_dotted(p) for p in hits)}; use one of these paths")
        other = _non_number_paths(case, name)
        if other:
            path, node = other[0]
            kind = "a table" if isinstance(node, Mapping) else "a list"
            raise CaseError(f"grid parameter {name!r} names {kind}, not a number ("
                            f"{_dotted(path)}); give the path of one number (for lists, add "
                            f"the entry number: {_dotted(path)}.1)")
        keys = sorted({p[-1] for p in leaves if p and isinstance(p[-1], str)})
        shown = ", ".join(dotted[:30]) + (" ..." if len(dotted) > 30 else "")
        raise CaseError(f"unknown grid parameter {name!r}: the case has no number with that "
                        f"key{_did_you_mean(name, keys)}; numbers in the case: "
                        f"{shown or 'none'}")
    parts = name.split(".")
    if parts[0] not in case:  # a path inside some table: match the end of the full paths
        hits = [p for p, d in zip(leaves, dotted, strict=True) if d.endswith("." + name)]
        if len(hits) == 1:
            return hits[0]
        if len(hits) > 1:
            raise CaseError(f"grid parameter {name!r} is ambiguous: the case has it at "
                            f"{', '.join(_dotted(p) for p in hits)}; use one of these paths")
    node, path = case, []
    for depth, part in enumerate(parts):
        last = depth == len(parts) - 1
        where = _dotted(tuple(path)) or "the case"
        if isinstance(node, Mapping):
            if part not in node and not last:
                raise CaseError(f"unknown grid parameter {name!r}: {where} has no table "
                                f"{part!r}{_did_you_mean(name, dotted)}")
            if part not in node:  # a key left at its schema default
                path.append(part)
                return tuple(path)
            path.append(part)
            node = node[part]
        elif isinstance(node, list):
            if part.isdigit():
                i = int(part) - 1
                if not 0 <= i < len(node):
                    raise CaseError(f"grid parameter {name!r}: {where} has {len(node)} "
                                    f"entries, numbered from 1; got {part}")
            else:
                named = [i for i, v in enumerate(node)
                         if isinstance(v, Mapping) and v.get("name") == part]
                if len(named) != 1:
                    raise CaseError(f"grid parameter {name!r}: {where} has "
                                    f"{'no' if not named else 'several'} entries named "
                                    f"{part!r}; number entries from 1 ({where}.1)")
                i = named[0]
            path.append(i)
            node = node[i]
        else:
            raise CaseError(f"grid parameter {name!r}: {where} is a number, not a table")
    if not _is_number(node):
        kind = "a table" if isinstance(node, Mapping) else (
            "a list" if isinstance(node, list) else f"{type(node).__name__} {node!r}")
        raise CaseError(f"grid parameter {name!r} names {kind}, not a number; give the path "
                        f"of one number (for lists, add the entry number: {name}.1)")
    return tuple(path)


def apply_overrides(case: Mapping, params: Mapping[str, float | int]) -> dict:
    """Copy of ``case`` with each parameter's value written at its place.

    Parameters
    ----------
    case : mapping
        The case as read from TOML (not modified).
    params : mapping name -> number
        Parameter names as accepted by :func:`resolve_parameter`.

    Returns
    -------
    dict
        A deep copy. A value replacing an integer is written as an integer when it is integral
        (case schemas are strict about integers), otherwise as a float, so the schema reports
        ``periods = 2.5`` as it would in a case file.
    """
    out = copy.deepcopy(dict(case))
    for name, value in params.items():
        path = resolve_parameter(out, name)
        node = out
        for key in path[:-1]:
            node = node[key]
        old = node.get(path[-1]) if isinstance(node, Mapping) else node[path[-1]]
        new = value.item() if isinstance(value, np.generic) else value
        if isinstance(old, int) and not isinstance(old, bool) and float(new).is_integer():
            new = int(new)
        elif old is not None or not isinstance(new, int):
            new = float(new)
        node[path[-1]] = new
    return out
