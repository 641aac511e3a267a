"""One result API: what every user-facing result of fricdamp offers.

Every result type returned by a solver or an identification (``TimeResult``,
``EventResult``, ``FrequencyResponse``, ``NonlinearModes``, ``ModalResult``, ``DecayResult``,
...) is a frozen dataclass with the same five members:

``.plot(...)``
    Draws the result with matplotlib (imported only then) and returns the axes it drew on (an
    ``Axes`` or an array of them; ``figure_of`` gives the figure).
``.to_xarray()``
    An ``xarray.Dataset`` whose variables carry a ``units`` attribute (``"1"`` for
    dimensionless ratios); frequencies are in Hz (``frequency`` / ``frequency_hz``), angular
    frequencies only under names ending in ``_rad_s`` or with ``units = "rad/s"``.
``.save(path)``
    Writes ``to_xarray()`` atomically as netCDF-3 (``.nc``) or a NumPy archive (``.npz``);
    :func:`load` reads it back as the same Dataset.
``.verdict``
    A :class:`fricdamp.verdict.Verdict`: ``ok``, ``unreliable`` (with the reasons and what to
    do) or ``failed``, with the error estimates it was judged on.
``repr(result)``
    One readable paragraph: scalars and short strings by value, arrays by shape and dtype
    (never an array dump).

Frequencies for users are in Hz everywhere: a result whose historical field holds an angular
frequency without ``_rad_s`` in its name (``FrequencyResponse.omega``,
``NonlinearModes.frequency``) also has ``frequency_hz`` and a ``..._rad_s`` twin; the old
name keeps working.

:class:`ResultMixin` gives ``save``, the readable ``repr`` and a default ``verdict`` (from
``success``/``status``/``message``) to the dataclasses that mix it in (declare them with
``repr=False`` so that the dataclass does not write its own ``__repr__``).
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Mapping

import numpy as np

__all__ = ["ResultMixin", "figure_of", "load", "save_dataset", "status_verdict",
           "summary_repr"]

#: Longest string shown whole by :func:`summary_repr`.
_MAX_STR = 60


def _short(value) -> str | None:
    """A short text for one field value; None to leave the field out."""
    if value is None:
        return None
    if hasattr(value, "nnz") and hasattr(value, "shape"):      # scipy.sparse
        return f"<sparse {value.dtype} {value.shape}, nnz={value.nnz}>"
    if isinstance(value, np.ndarray):
        if value.size == 1 and value.ndim == 0:
            return repr(value.item())
        return f"<{value.dtype} {value.shape}>" if value.size else f"<empty {value.shape}>"
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.6g}"
    if isinstance(value, complex):
        return f"{value:.4g}"
    if isinstance(value, str):
        s = value if len(value) <= _MAX_STR else value[: _MAX_STR - 3] + "..."
        return repr(s)
    if isinstance(value, Mapping):
        keys = list(value)
        if not keys:
            return None
        shown = ", ".join(str(k) for k in keys[:6]) + (", ..." if len(keys) > 6 else "")
        return f"{{{shown}}}"
    if isinstance(value, (tuple, list)):
        if not value:
            return None
        if all(isinstance(v, str) for v in value):
            s = ", ".join(value[:4]) + (", ..." if len(value) > 4 else "")
            return f"({s})" if len(s) <= _MAX_STR else f"<{len(value)} names>"
        if all(isinstance(v, (int, float, np.integer, np.floating)) for v in value) and \
                len(value) <= 6:
            return "(" + ", ".join(_short(v) for v in value) + ")"
        kinds = {type(v).__name__ for v in value}
        return f"<{len(value)} x {kinds.pop() if len(kinds) == 1 else 'objects'}>"
    if dataclasses.is_dataclass(value) or hasattr(value, "__dict__"):
        return f"<{type(value).__name__}>"
    text = repr(value)
    return text if len(text) <= _MAX_STR else f"<{type(value).__name__}>"


def summary_repr(obj, *, skip=("meta", "system")) -> str:
    """``Name(field=value, ...)`` of a dataclass with arrays as ``<dtype (shape)>``.

    Fields that are None, empty or named in ``skip`` are left out; the text never holds an
    array's values, so it stays a few lines long for any size of result.
    """
    parts = []
    for f in dataclasses.fields(obj):
        if f.name in skip or not f.repr:
            continue
        text = _short(getattr(obj, f.name, None))
        if text is not None:
            parts.append(f"{f.name}={text}")
    lines, line = [], f"{type(obj).__name__}("
    for p in parts:
        if len(line) + len(p) + 2 > 96 and line.strip():
            lines.append(line.rstrip())
            line = "    "
        line += p + ", "
    lines.append(line.rstrip(", ") + ")")
    return "\n".join(lines)


def status_verdict(success: bool, message: str = "", estimates: Mapping | None = None, *,
                   reasons=()):
    """Verdict from a success flag and error estimates (judged against
    :data:`fricdamp.verdict.THRESHOLDS`): ``failed`` with ``message`` when not ``success``."""
    from fricdamp.verdict import judge

    return judge(dict(estimates or {}), reasons=reasons,
                 failed=None if success else (message or "the solver did not finish"))


def save_dataset(ds, path) -> None:
    """Write ``ds`` atomically as netCDF-3 (``.nc``; complex variables split into
    ``_real``/``_imag``, booleans as int8, see :func:`fricdamp.iofiles.write_results`) or as
    a NumPy archive (``.npz``: every variable under its own name, its dimensions in
    ``<name>__dims``, the attributes as JSON in ``__attrs__``). :func:`load` reads both."""
    from fricdamp.iofiles import write_results

    write_results(path, ds)


def plot_histories(t, q, outputs=None, ax=None):
    """Displacement histories ``q[:, i]`` [m] over ``t`` [s], drawn in mm for the outputs
    ``i`` (indices, default all); returns the axes (shared by the transient results)."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
    for i in (range(q.shape[1]) if outputs is None else outputs):
        ax.plot(t, 1e3 * q[:, i], lw=1, label=f"output {i}")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("displacement [mm]")
    ax.legend(loc="upper right", fontsize="small")
    ax.grid(alpha=0.3)
    return ax


def load(path):
    """Read a result saved by ``.save(path)`` back as an ``xarray.Dataset``."""
    from fricdamp.iofiles import read_results

    return read_results(path)


def figure_of(drawn):
    """The matplotlib figure of what a ``.plot()`` returned (an Axes, an array or sequence of
    Axes, or a Figure)."""
    from matplotlib.figure import Figure

    if isinstance(drawn, Figure):
        return drawn
    if isinstance(drawn, np.ndarray):
        drawn = drawn.ravel()[0]
    elif isinstance(drawn, (list, tuple)):
        drawn = drawn[0]
    return drawn.figure


class ResultMixin:
    """``save``, a readable ``repr`` and a default ``verdict`` for a result dataclass.

    The class must define ``to_xarray()``; a class with its own error estimates overrides
    :meth:`_judge` (called once, on first access of ``verdict``; the verdict is then kept).
    """

    __slots__ = ()

    def save(self, path: str | os.PathLike) -> None:
        """Save ``to_xarray()`` to ``path``: netCDF-3 for ``.nc``, NumPy archive for ``.npz``;
        written atomically (an interrupted write leaves no partial file). Read it back with
        :func:`fricdamp.results.load`."""
        save_dataset(self.to_xarray(), path)

    @property
    def verdict(self):
        """:class:`fricdamp.verdict.Verdict` of the result, judged on first access."""
        cached = self.__dict__.get("_verdict")
        if cached is None:
            cached = self._judge()
            object.__setattr__(self, "_verdict", cached)   # frozen: the cache bypasses it
        return cached

    def _judge(self):
        success = bool(getattr(self, "success", True))
        message = str(getattr(self, "message", ""))
        est = {}
        ebe = getattr(self, "energy_balance_error", None)
        if ebe is not None:
            arr = np.asarray(ebe, dtype=float)
            if arr.size and np.any(np.isfinite(arr)):
                est["energy_balance_error"] = float(np.nanmax(arr))
        energy = getattr(self, "energy", None)
        if isinstance(energy, Mapping) and {"kinetic", "strain", "contact_stored",
                                            "contact_dissipation", "viscous_dissipation",
                                            "input_work"} <= set(energy):
            from fricdamp.verdict import _dissipation_estimate

            est["negative_dissipation"] = _dissipation_estimate(energy)
        return status_verdict(success, message, est)

    def __repr__(self) -> str:
        return summary_repr(self)
