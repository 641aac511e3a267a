"""Signal processing for measured and simulated records: FFT integration, time bases, CSV
import of signals, tables and hysteresis loops.

Paper 002 (section 3.4, Fig. 7, appendix B) builds its torque-rotation loops from three
accelerometers: the kinematic relations (B.1)-(B.10) turn the tangential accelerations into
``theta_1''``, ``theta_2''`` and ``x_1''``, and a Fourier transform / inverse transform
integrates them twice into rotations and displacement. :func:`fft_integrate` is that
integration step; the kinematic relations belong to the model of the test structure.
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fricdamp.errors import ModelError, as_finite_array

__all__ = ["Loop", "SignalTable", "fft_integrate", "read_fit_input", "read_signals_csv",
           "read_table_csv", "uniform_time"]


def fft_integrate(x, dt: float, order: int = 1, *, f_low: float | None = None,
                  axis: int = 0) -> np.ndarray:
    """Integrate a sampled signal ``order`` times in the frequency domain (FFT / IFFT).

    Each Fourier component ``X(f)`` (f > 0) is divided by ``(i 2 pi f)^order``; the mean
    (f = 0) and every component below ``f_low`` are set to zero, so the result is the
    zero-mean periodic part of the integral (constants and linear drifts of integration are
    not recoverable from an acceleration and are dropped on purpose: sensor offsets would
    otherwise grow into parabolic drifts). For an odd ``order`` and an even number of
    samples the Nyquist component is dropped (its integral is zero at the samples).

    The result is exact (to round-off) for a band-limited signal holding an integer number
    of periods of each component: cut measured records to whole periods of the excitation
    first (:func:`fricdamp.signals.energy.steady_cycle`), otherwise leakage from the
    discontinuity between the ends of the record spreads over the low frequencies, which
    ``f_low`` then removes (the high-pass of the paper 002 algorithm, Fig. 7).

    Parameters
    ----------
    x : array_like, shape (n, ...)
        Uniformly sampled signal (e.g. acceleration [m/s^2] or [rad/s^2]), time along
        ``axis``.
    dt : float
        Sampling interval [s], > 0.
    order : {1, 2}, optional
        1: acceleration -> velocity; 2: acceleration -> displacement. Default 1.
    f_low : float, optional
        High-pass cut-off [Hz]: components with ``f < f_low`` are removed; in [0, 1/(2 dt)).
        Default None (only the mean is removed).
    axis : int, optional
        Time axis; default 0.

    Returns
    -------
    ndarray, same shape as x
        The integrated signal (velocity [m/s] or displacement [m] for an acceleration in
        [m/s^2]), zero mean.

    Raises
    ------
    ModelError
        Non-finite x, fewer than 4 samples, dt <= 0, order not in {1, 2}, f_low out of range.

    References
    ----------
    Paper 002, section 3.4 and Fig. 7 (FFT/IFFT integration of the accelerometer signals).

    Examples
    --------
    >>> import numpy as np
    >>> dt = 1e-3
    >>> t = dt * np.arange(1000)
    >>> a = -(2 * np.pi * 5) ** 2 * np.sin(2 * np.pi * 5 * t)   # 5 Hz, 5 whole periods
    >>> bool(np.allclose(fft_integrate(a, dt, order=2), np.sin(2 * np.pi * 5 * t)))
    True
    """
    x = as_finite_array("x", x)
    if x.ndim == 0:
        raise ModelError("x must be an array of samples, got a scalar")
    dt = float(as_finite_array("dt", dt))
    if dt <= 0:
        raise ModelError(f"dt must be > 0 s, got {dt!r}")
    if order not in (1, 2):
        raise ModelError(f"order must be 1 (velocity) or 2 (displacement), got {order!r}")
    if int(axis) != axis or not -x.ndim <= axis < x.ndim:
        raise ModelError(f"axis must be an integer in [{-x.ndim}, {x.ndim}) for x of shape "
                         f"{x.shape}, got {axis!r}")
    axis = int(axis) % x.ndim
    n = x.shape[axis]
    if n < 4:
        raise ModelError(f"x needs at least 4 samples along axis {axis}, got {n}")
    nyquist = 0.5 / dt
    if f_low is not None:
        f_low = float(as_finite_array("f_low", f_low))
        if not 0.0 <= f_low < nyquist:
            raise ModelError(f"f_low must lie in [0, {nyquist:g}) Hz (below Nyquist), got "
                             f"{f_low!r}")
    spec = np.fft.rfft(x, axis=axis)
    freq = np.fft.rfftfreq(n, dt)
    keep = freq > 0.0
    if f_low is not None:
        keep &= freq >= f_low
    if order % 2 == 1 and n % 2 == 0:
        keep[-1] = False
    factor = np.zeros(freq.size, dtype=complex)
    factor[keep] = (1.0 / (2j * np.pi * freq[keep])) ** order
    shape = [1] * x.ndim
    shape[axis] = freq.size
    return np.fft.irfft(spec * factor.reshape(shape), n=n, axis=axis)


# ---------------------------------------------------------------------------------------------
# time bases
# ---------------------------------------------------------------------------------------------

#: time stamps may deviate from the uniform grid by less than this fraction of a step
#: (rounding when written with few decimals); more means missing or repeated samples
_JITTER_LIMIT = 0.5
#: ... and the median deviation over each twentieth of the record by less than this, or a
#: tenth of the largest deviation (a persistent offset is a gap in the record, not rounding)
_OFFSET_LIMIT = 0.01
#: a rate within this relative distance of a whole number of hertz is that whole number
_RATE_SNAP = 1e-5


def uniform_time(time, *, name: str = "time") -> tuple[np.ndarray, float, bool]:
    """Rebuild a near-uniform time base as an exactly uniform one (rounded time stamps).

    Lab software often writes time columns with a fixed number of decimals (5120 Hz with 7
    decimals is ``0.0001953`` per step, 2.6e-4 of a step off), which breaks the whole-period
    arithmetic of FFT integration. The rule, the same as the UFF reader's
    (:func:`fricdamp.signals.uff.read_signals_uff`):

    * the grid is the least-squares line ``t0 + k dt`` through the stamps;
    * every stamp must lie within half a step of it (otherwise a sample is missing or
      repeated), and the median deviation over each twentieth of the record within 1 % of a
      step or a tenth of the largest deviation (otherwise the record has a gap or a jump:
      rounding does not shift whole blocks);
    * a rate ``1/dt`` within 1e-5 of a whole number of hertz is taken as that number
      (acquisition rates are whole numbers);
    * the time stamps are then replaced by ``t0 + k dt``.

    Parameters
    ----------
    time : array_like, shape (n,)
        Time stamps [s], strictly increasing, n >= 2.
    name : str, optional
        Name used in error messages.

    Returns
    -------
    t : ndarray, shape (n,)
        Uniform time base [s].
    dt : float
        Its step [s].
    snapped : bool
        True when the stamps were changed by more than round-off (1e-9 of a step).

    Raises
    ------
    ModelError
        Non-increasing or non-uniform stamps (naming the sample and the step).

    Examples
    --------
    >>> t = np.round(np.arange(6) / 5120.0, 7)          # written with 7 decimals
    >>> t2, dt, snapped = uniform_time(t)
    >>> round(1 / dt, 6), snapped
    (5120.0, True)
    """
    t = as_finite_array(name, time, ndim=1)
    if t.size < 2:
        raise ModelError(f"{name} needs at least 2 samples, got {t.size}")
    steps = np.diff(t)
    if np.any(steps <= 0):
        i = int(np.flatnonzero(steps <= 0)[0])
        raise ModelError(f"{name} must be strictly increasing: sample {i + 1} is "
                         f"{t[i + 1]!r} s after {t[i]!r} s")
    n = t.size
    k = np.arange(n, dtype=float)
    kc = k - 0.5 * (n - 1)
    dt = float(np.dot(kc, t - t.mean()) / np.dot(kc, kc)) if n > 2 else float(steps[0])
    n_chunks = min(20, max(1, n // 8))

    def fit(step):
        grid = float(np.mean(t - k * step)) + k * step
        dev = (t - grid) / step
        offset = max(abs(float(np.median(c))) for c in np.array_split(dev, n_chunks))
        jitter = float(np.max(np.abs(dev)))
        return grid, dev, (jitter <= _JITTER_LIMIT
                           and offset <= max(_OFFSET_LIMIT, 0.1 * jitter))

    rate = 1.0 / dt
    grid, dev, ok = fit(dt)
    if abs(rate - round(rate)) <= _RATE_SNAP * rate and round(rate) > 0:
        whole = fit(1.0 / float(round(rate)))
        if whole[2]:  # the whole-hertz rate, unless it drifts off the stamps
            dt = 1.0 / float(round(rate))
            grid, dev, ok = whole
    if not ok:
        i = int(np.argmax(np.abs(steps - dt)))
        raise ModelError(f"{name}: the samples must be uniformly spaced (FFT integration): "
                         f"the step at sample {i} is {steps[i]:.6g} s, the mean step "
                         f"{dt:.6g} s (a gap or a repeated sample); resample the record or "
                         "give the sample rate")
    snapped = bool(np.max(np.abs(dev)) > 1e-9)
    return (grid if snapped else t), dt, snapped


# ---------------------------------------------------------------------------------------------
# CSV
# ---------------------------------------------------------------------------------------------

class SignalTable(dict):
    """Columns of a signal file: a ``dict`` name -> ndarray (n,), with units and source.

    Always holds the key ``"time"`` (seconds). ``units`` maps each name to its unit string
    ('' when the file gives none); ``path`` is the file read; ``time_column`` the name of the
    column the time came from.
    """

    def __init__(self, data, *, units, path, time_column):
        super().__init__(data)
        self.units: dict[str, str] = dict(units)
        self.path: str = str(path)
        self.time_column: str = time_column


_TIME_NAMES = {"time", "t", "zeit", "temps", "tiempo", "tempo", "times", "time_s", "t_s"}
_TIME_SCALE = {"s": 1.0, "sec": 1.0, "secs": 1.0, "second": 1.0, "seconds": 1.0, "": 1.0,
               "ms": 1e-3, "msec": 1e-3, "us": 1e-6, "µs": 1e-6, "μs": 1e-6, "ns": 1e-9,
               "min": 60.0}
_DECIMAL_COMMA = re.compile(r"^[+-]?\d*,\d+(?:[eE][+-]?\d+)?$")
_UNIT_RE = re.compile(r"^\s*(.*?)\s*(?:\[([^\]]*)\]|\(([^)]*)\))\s*$")


def _split_name_unit(header: str) -> tuple[str, str]:
    m = _UNIT_RE.match(header)
    if m and m.group(1):
        return m.group(1).strip(), (m.group(2) if m.group(2) is not None else m.group(3)).strip()
    return header.strip(), ""


def _is_number(text: str, decimal: str) -> bool:
    s = text.strip()
    if decimal == ",":
        s = s.replace(",", ".")
    try:
        float(s)
    except ValueError:
        return False
    return True


def _split(line: str, delimiter: str | None) -> list[str]:
    if delimiter is None:
        return line.split()
    return next(csv.reader([line], delimiter=delimiter))


def read_signals_csv(path, *, time_column: str | int | None = None,
                     delimiter: str | None = None, decimal: str | None = None,
                     skip_rows: int = 0, time_scale: float | None = None,
                     time_unit: str | None = None,
                     sample_rate: float | None = None) -> SignalTable:
    """Read a table of sampled signals (CSV, semicolon or tab separated, decimal comma).

    Format: optional comment lines (``#``, ``%``, ``//``) and ``skip_rows`` metadata lines,
    then a header row of column names, each optionally with a unit as ``name [unit]`` or
    ``name (unit)``, then optionally a row of units (a row with no number in it), then the
    numeric rows. The delimiter is detected (``;``, tab, ``,``, else white space) unless
    given, and a decimal comma is detected when the delimiter is not a comma. An empty
    trailing column (a delimiter at every line end) is ignored.

    The time column is ``time_column`` (name or 0-based index), else the first column whose
    name is a usual time name (time, t, zeit, temps, ...), else the first column. It is
    returned under the key ``"time"`` in seconds: a unit of ms, us or min is converted
    (``time_unit`` or ``time_scale`` override the header), and it must be strictly
    increasing. A first column that is a **sample index** (named sample, index, n, no, #,
    ... or holding consecutive integers without a unit) is never read as seconds: give
    ``sample_rate`` (the time is then ``k / sample_rate``, and the index and any time
    column are left out of the channels), or name the time column.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    time_column : str or int, optional
        Time column name (without unit) or index.
    delimiter : str, optional
        Field delimiter; detected when omitted.
    decimal : {".", ","}, optional
        Decimal separator; detected when omitted.
    skip_rows : int, optional
        Raw lines to skip before looking for the header (metadata blocks); default 0.
    time_scale : float, optional
        Factor turning the time column into seconds (overrides its unit), > 0.
    time_unit : str, optional
        Unit of the time column (s, ms, us, ns, min), overriding the header's.
    sample_rate : float, optional
        Sampling rate [Hz], > 0: the time is rebuilt as ``k / sample_rate`` (k = 0, 1, ...)
        whatever the file's time or index column says.

    Returns
    -------
    SignalTable
        dict name -> ndarray (n_samples,) with ``"time"`` [s] and every other column, plus
        ``.units``, ``.path``, ``.time_column``.

    Raises
    ------
    ModelError
        Naming the file (and the column and line) when the file is missing or empty, a cell
        is not a number, a row has the wrong number of fields, the time column is unknown,
        not strictly increasing or a sample index (without ``sample_rate``).
    """
    p = Path(path)
    names, units, data, body = _parse_csv(p, delimiter, decimal, skip_rows)

    if sample_rate is not None:
        return _table_at_rate(p, data, names, units, time_column, sample_rate)
    if time_column is None:
        tname = next((nm for nm in names if nm.lower() in _TIME_NAMES), names[0])
        if tname.lower() not in _TIME_NAMES and _is_index(tname, units[0], data[tname]):
            raise ModelError(f"{str(p)!r}: column {tname!r} is a sample index, not a time: "
                             "give the sample rate (sample_rate, --sample-rate) or name the "
                             "time column (time_column, --time-column)")
    elif isinstance(time_column, (int, np.integer)):
        if not 0 <= time_column < len(names):
            raise ModelError(f"{str(p)!r}: time_column index {time_column} out of range "
                             f"[0, {len(names)})")
        tname = names[int(time_column)]
    else:
        if time_column not in data:
            raise ModelError(f"{str(p)!r}: no column named {time_column!r}; columns are "
                             f"{names}")
        tname = time_column
    tunit = units[names.index(tname)] if time_unit is None else str(time_unit)
    if time_scale is None:
        key = tunit.strip().lower()
        if key not in _TIME_SCALE:
            raise ModelError(f"{str(p)!r}: time column {tname!r} has unit {tunit!r}; known "
                             f"units are s, ms, us, ns, min (or pass time_unit, time_scale "
                             "or the sample rate)")
        time_scale = _TIME_SCALE[key]
    time_scale = float(as_finite_array("time_scale", time_scale))
    if time_scale <= 0:
        raise ModelError(f"time_scale must be > 0, got {time_scale!r}")
    tvals = data.pop(tname) * time_scale
    dt = np.diff(tvals)
    if np.any(dt <= 0):
        i = int(np.flatnonzero(dt <= 0)[0])
        raise ModelError(f"{str(p)!r}, column {tname!r}: time must be strictly increasing, "
                         f"but line {body[i + 1][0]} has {tvals[i + 1]!r} after {tvals[i]!r}")
    if "time" in data:
        raise ModelError(f"{str(p)!r}: column 'time' is not the time column {tname!r}; "
                         "rename it or pass time_column='time'")
    out = {"time": tvals, **data}
    unit_map = {"time": "s"}
    unit_map.update({nm: units[j] for j, nm in enumerate(names) if nm != tname})
    return SignalTable(out, units=unit_map, path=p, time_column=tname)


_INDEX_NAMES = {"sample", "samples", "index", "idx", "n", "no", "no.", "nr", "#", "count",
                "point", "points", "sample number", "sample_number", "sample no", "sample_no",
                "sample index", "sample_index"}


def _is_index(name: str, unit: str, values: np.ndarray) -> bool:
    """A column of sample numbers: an index name, or consecutive integers without a unit."""
    if name.strip().lower() in _INDEX_NAMES:
        return True
    if unit.strip() or values.size < 2:
        return False
    return bool(np.all(values == np.round(values)) and np.all(np.diff(values) == 1.0))


def _table_at_rate(p: Path, data: dict, names: list, units: list, time_column,
                   sample_rate) -> SignalTable:
    """The table with ``time = k / sample_rate``; index and time columns left out."""
    rate = float(as_finite_array("sample_rate", sample_rate, ndim=0))
    if rate <= 0:
        raise ModelError(f"sample_rate must be > 0 Hz, got {sample_rate!r}")
    drop = set()
    if time_column is not None:
        if isinstance(time_column, (int, np.integer)):
            if not 0 <= time_column < len(names):
                raise ModelError(f"{str(p)!r}: time_column index {time_column} out of range "
                                 f"[0, {len(names)})")
            drop.add(names[int(time_column)])
        elif time_column not in data:
            raise ModelError(f"{str(p)!r}: no column named {time_column!r}; columns are "
                             f"{names}")
        else:
            drop.add(time_column)
    drop.update(nm for nm in names if nm.lower() in _TIME_NAMES)
    if _is_index(names[0], units[0], data[names[0]]):
        drop.add(names[0])
    if "time" in data and "time" not in drop:  # pragma: no cover - 'time' is a time name
        drop.add("time")
    n = next(iter(data.values())).size
    out = {"time": np.arange(n) / rate}
    unit_map = {"time": "s"}
    for j, nm in enumerate(names):
        if nm not in drop:
            out[nm] = data[nm]
            unit_map[nm] = units[j]
    if len(out) == 1:
        raise ModelError(f"{str(p)!r}: no signal columns left besides time and index")
    return SignalTable(out, units=unit_map, path=p, time_column=f"<{rate:g} Hz>")


def _parse_csv(path, delimiter, decimal, skip_rows):
    """Columns of a delimited text table: ``(names, units, data, body lines)``."""
    from fricdamp.iofiles import require_regular_file

    p = Path(path)
    require_regular_file(p, what="signal file", error=ModelError)
    raw = p.read_bytes()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    if int(skip_rows) != skip_rows or skip_rows < 0:
        raise ModelError(f"skip_rows must be an integer >= 0, got {skip_rows!r}")
    lines = [(i + 1, ln) for i, ln in enumerate(text.splitlines())]
    lines = lines[int(skip_rows):]
    lines = [(no, ln) for no, ln in lines
             if ln.strip() and not ln.lstrip().startswith(("#", "%", "//"))]
    if len(lines) < 2:
        raise ModelError(f"{str(p)!r}: needs a header row and at least one row of numbers")
    head_no, head = lines[0]
    first = lines[1][1]

    if delimiter is None:
        for cand in (";", "\t", ","):
            n_h = len(_split(head, cand))
            if n_h > 1 and n_h in (len(_split(first, cand)), len(_split(first, cand)) - 1):
                delimiter = cand
                break
        else:
            delimiter = None if len(head.split()) > 1 else ","
    if decimal is None:
        decimal = "."
        if delimiter != ",":
            sample = [f.strip() for _, ln in lines[1:6] for f in _split(ln, delimiter)]
            if any(_DECIMAL_COMMA.match(f) for f in sample):
                decimal = ","
    if decimal not in (".", ","):
        raise ModelError(f"decimal must be '.' or ',', got {decimal!r}")
    if decimal == delimiter:
        raise ModelError(f"{str(p)!r}: decimal separator and delimiter are both {decimal!r}")

    names_raw = [h.strip() for h in _split(head, delimiter)]
    if names_raw and names_raw[-1] == "" and len(names_raw) > 1:
        names_raw = names_raw[:-1]
    ncol = len(names_raw)
    parsed = [_split_name_unit(h) for h in names_raw]
    names = [nm if nm else f"column_{j}" for j, (nm, _) in enumerate(parsed)]
    units = [u for _, u in parsed]
    if len(set(names)) != len(names):
        dup = sorted({nm for nm in names if names.count(nm) > 1})
        raise ModelError(f"{str(p)!r}: duplicate column name(s) {dup}")

    body = lines[1:]
    first_fields = [s.strip() for s in _split(body[0][1], delimiter)][:ncol]
    if first_fields and not any(_is_number(s, decimal) for s in first_fields):
        for j, u in enumerate(first_fields):  # a row of units
            if u and not units[j]:
                units[j] = u.strip("[]()")
        body = body[1:]
    if not body:
        raise ModelError(f"{str(p)!r}: no rows of numbers after the header")

    cells = []
    for no, ln in body:
        fields = [s.strip() for s in _split(ln, delimiter)]
        if len(fields) == ncol + 1 and fields[-1] == "":
            fields = fields[:-1]
        if len(fields) != ncol:
            raise ModelError(f"{str(p)!r}, line {no}: {len(fields)} fields, expected {ncol} "
                             f"(columns {names}); delimiter {delimiter!r}")
        cells.append(fields)
    table = np.array(cells, dtype=object)
    data: dict[str, np.ndarray] = {}
    for j, name in enumerate(names):
        col = table[:, j].astype(str)
        if decimal == ",":
            col = np.char.replace(col, ",", ".")
        try:
            values = col.astype(float)
        except ValueError:
            bad = next(i for i, s in enumerate(col) if not _is_number(s, "."))
            raise ModelError(f"{str(p)!r}, line {body[bad][0]}, column {name!r}: "
                             f"{table[bad, j]!r} is not a number") from None
        if not np.all(np.isfinite(values)):
            bad = int(np.flatnonzero(~np.isfinite(values))[0])
            raise ModelError(f"{str(p)!r}, line {body[bad][0]}, column {name!r}: "
                             f"non-finite value {table[bad, j]!r}")
        data[name] = values
    return names, units, data, body


def read_table_csv(path, *, delimiter: str | None = None, decimal: str | None = None,
                   skip_rows: int = 0) -> SignalTable:
    """Every column of a delimited text table, without choosing a time column.

    The format rules of :func:`read_signals_csv` (comments, ``skip_rows``, units in the
    header or in a row of units, delimiter and decimal comma detected). Used for tables that
    are not time series (hysteresis loops, energy against amplitude).

    Returns
    -------
    SignalTable
        name -> ndarray (n_rows,), with ``.units``; ``.time_column`` is ''.

    Raises
    ------
    ModelError
        As :func:`read_signals_csv` (missing file, bad cells, ragged rows).
    """
    p = Path(path)
    names, units, data, _ = _parse_csv(p, delimiter, decimal, skip_rows)
    return SignalTable(data, units=dict(zip(names, units, strict=True)), path=p,
                       time_column="")


# ---------------------------------------------------------------------------------------------
# hysteresis loops and energy tables (the input of fricdamp.signals.fit)
# ---------------------------------------------------------------------------------------------
# units understood in loop files, to SI
_LENGTH = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6, "nm": 1e-9}
_ANGLE = {"rad": 1.0, "mrad": 1e-3, "urad": 1e-6, "µrad": 1e-6, "μrad": 1e-6,
          "deg": math.pi / 180.0, "°": math.pi / 180.0}
_FORCE = {"n": 1.0, "kn": 1e3, "mn": 1e-3}
_MOMENT = {"nm": 1.0, "n m": 1.0, "n*m": 1.0, "n.m": 1.0, "n·m": 1.0, "nmm": 1e-3,
           "n mm": 1e-3, "n*mm": 1e-3, "mnm": 1e-3, "mn m": 1e-3, "knm": 1e3, "kn m": 1e3}
_ENERGY = {"j": 1.0, "mj": 1e-3, "uj": 1e-6, "µj": 1e-6, "μj": 1e-6, "nj": 1e-9}
_X_NAMES = ("displacement", "disp", "slip", "rotation", "rot", "theta", "angle", "x", "u")
_F_NAMES = ("force", "load", "torque", "moment", "f", "m")


@dataclass(frozen=True)
class Loop:
    """One measured hysteresis loop (whole periods, not closed).

    Attributes
    ----------
    displacement : ndarray, shape (n,)
        Relative displacement [m] or rotation [rad].
    force : ndarray, shape (n,)
        Force [N] or moment [N m] the joint resists it with.
    rotational : bool
        True for rotation/torque.
    source : str
    """

    displacement: np.ndarray
    force: np.ndarray
    rotational: bool = False
    source: str = ""

    def __post_init__(self):
        x = as_finite_array("displacement", self.displacement, ndim=1)
        f = as_finite_array("force", self.force, ndim=1)
        if x.size != f.size or x.size < 8:
            raise ModelError(f"a loop needs displacement and force of equal length >= 8, got "
                             f"{x.size} and {f.size} ({self.source or 'arrays'})")
        if np.ptp(x) <= 0:
            raise ModelError(f"the loop's displacement does not vary ({self.source or 'arrays'})")
        object.__setattr__(self, "displacement", x)
        object.__setattr__(self, "force", f)

    @property
    def amplitude(self) -> float:
        """Half the peak-to-peak displacement [m] or rotation [rad]."""
        return 0.5 * float(np.ptp(self.displacement))

    @property
    def force_amplitude(self) -> float:
        """Half the peak-to-peak force [N] or moment [N m]."""
        return 0.5 * float(np.ptp(self.force))

    @property
    def energy(self) -> float:
        """Loop area [J] (trapezoidal, closed) of the samples held."""
        from fricdamp.signals.energy import loop_area

        return loop_area(self.displacement, self.force)


def _unit_key(u: str) -> str:
    return u.strip().lower().replace("²", "^2")


def _classify(name: str, unit: str):
    """('x' | 'f' | 'e' | 'a' | None, rotational or None, factor) of a column."""
    n, u = name.strip().lower(), _unit_key(unit)
    if "energy" in n or u in _ENERGY:
        return "e", None, _ENERGY.get(u, 1.0)
    if "amplitude" in n:
        if u in _ANGLE:
            return "a", True, _ANGLE[u]
        return "a", (True if "rot" in n or "theta" in n else False if u in _LENGTH else None), \
            _LENGTH.get(u, 1.0)
    if u in _MOMENT or any(k in n for k in ("torque", "moment")):
        return "f", True, _MOMENT.get(u, 1.0)
    if u in _ANGLE or any(k in n for k in ("rotation", "theta", "angle")):
        return "x", True, _ANGLE.get(u, 1.0)
    if u in _FORCE or n in _F_NAMES or "force" in n or "load" in n:
        return "f", False, _FORCE.get(u, 1.0)
    if u in _LENGTH or n in _X_NAMES or "displacement" in n or "slip" in n:
        return "x", False, _LENGTH.get(u, 1.0)
    return None, None, 1.0


def read_fit_input(path):
    """Loops or an energy table from a CSV file or a ``fricdamp identify`` output folder.

    The input of :func:`fricdamp.signals.fit.fit_joint` (``fricdamp fit LOOPS``).

    A CSV holds either one loop -- a displacement (``displacement [m]``, ``[mm]``, ``[um]``) or
    rotation (``rotation [rad]``, ``[mrad]``, ``[deg]``) column and a force (``force [N]``) or
    torque (``torque [N m]``) column, any time or phase column being ignored; the samples
    should span whole periods -- or dissipated energy against amplitude (``amplitude [rad]``
    or ``[m]``, ``energy [J]``). A folder written by ``fricdamp identify`` gives its
    ``loop.csv`` (one period of rotation and torque).

    Returns
    -------
    list of Loop, or (amplitude, energy, rotational)
        The loop(s), or the energy table as arrays (n,), (n,) and a flag.

    Raises
    ------
    ModelError
        A missing file, no recognisable columns (listing them), bad units.
    """
    p = Path(path)
    if p.is_dir():
        if not (p / "loop.csv").is_file():
            raise ModelError(f"{str(p)!r} is a folder without loop.csv (expected the output "
                             "folder of fricdamp identify)")
        p = p / "loop.csv"
    from fricdamp.iofiles import require_regular_file

    require_regular_file(p, what="loop file", error=ModelError)
    tab = read_table_csv(p)
    roles = {}
    for name in tab:
        role, rot, factor = _classify(name, tab.units.get(name, ""))
        if role is not None and role not in roles:
            roles[role] = (name, rot, factor)
    cols = [f"{k} [{tab.units.get(k, '')}]" for k in tab]
    if "a" in roles and "e" in roles:
        (na, rot, fa), (ne, _, fe) = roles["a"], roles["e"]
        a = np.asarray(tab[na]) * fa
        e = np.asarray(tab[ne]) * fe
        if np.any(a <= 0) or np.any(e <= 0):
            raise ModelError(f"{str(p)!r}: amplitudes and energies must be > 0")
        return a, e, bool(rot)
    if "x" not in roles or "f" not in roles:
        raise ModelError(f"{str(p)!r}: needs a displacement or rotation column and a force or "
                         f"torque column (or amplitude and energy); columns: {cols}")
    (nx, rx, fx), (nf, rf, ff) = roles["x"], roles["f"]
    if rx is not None and rf is not None and rx != rf:
        raise ModelError(f"{str(p)!r}: column {nx!r} and column {nf!r} do not match (a rotation "
                         "goes with a torque, a displacement with a force)")
    rot = bool(rx if rx is not None else rf)
    return [Loop(np.asarray(tab[nx]) * fx, np.asarray(tab[nf]) * ff, rotational=rot,
                 source=str(p))]
