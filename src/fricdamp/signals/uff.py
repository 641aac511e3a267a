"""Time series from Universal File Format files (dataset 58), as test labs export them.

Modal-test and data-acquisition software (Simcenter Testlab, m+p, B&K Pulse/BK Connect, ME'scope,
Dewesoft, ...) export measured channels as UFF dataset 58 ("function at nodal DOF"), ASCII or
binary (58b). This module reads them with the ``pyuff`` library (imported when called) and
returns a :class:`~fricdamp.signals.records.SignalTable`, the same table the CSV reader gives,
so :func:`fricdamp.signals.identify.identify_from_table` accepts either.

What is read: every dataset 58 holding a real, evenly or unevenly spaced **time response**
(function type 1, or type 0 "general" with a time abscissa, specific data type 17). Frequency
functions (FRFs, spectra) and other datasets are skipped. All channels must share one time base.

Channel names: the dataset's first ID line (``id1``) when the channels' ID lines are non-empty
and distinct, else ``node<N><dir>`` from the response node and direction (``node3+X``).
Units: the ordinate's unit label when the file gives one; otherwise, for accelerations
(specific data type 12) in a file with a units dataset 164, the SI unit scaled by the file's
length factor (dataset 164: a value in SI is the file's value divided by the factor, e.g.
1000 for millimetres); otherwise none (give the unit when running the identification).
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from fricdamp.errors import ModelError
from fricdamp.signals.records import SignalTable

log = logging.getLogger(__name__)

__all__ = ["read_signals_uff"]

_DIRECTIONS = {0: "", 1: "+X", 2: "+Y", 3: "+Z", 4: "+RX", 5: "+RY", 6: "+RZ",
               -1: "-X", -2: "-Y", -3: "-Z", -4: "-RX", -5: "-RY", -6: "-RZ"}
_TIME_UNITS = {"s": 1.0, "sec": 1.0, "second": 1.0, "seconds": 1.0, "": 1.0, "none": 1.0,
               "ms": 1e-3, "msec": 1e-3, "us": 1e-6, "µs": 1e-6}
#: UFF specific data types (record 8/9, field 1) that are time abscissae / accelerations
_TIME_TYPE, _ACCELERATION_TYPE = 17, 12


def _label(value) -> str:
    s = "" if value is None else str(value).strip()
    return "" if s.upper() == "NONE" else s


def read_signals_uff(path, *, time_tolerance: float = 1e-9,
                     snap_rate: bool = True) -> SignalTable:
    """Read the time-series channels (dataset 58) of a Universal File Format file.

    The header of dataset 58 stores the time increment with 6 significant digits (format
    E13.5), so ``1/6000 s`` comes back as ``1.66667e-4 s``: 2e-6 off, enough to make the
    record's periods a non-integer number of samples. With ``snap_rate`` (default) an evenly
    spaced abscissa whose rate ``1/increment`` is within 1e-5 of a whole number of hertz
    (data-acquisition rates are) is rebuilt from that rate.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.uff`` / ``.unv`` file, ASCII or binary.
    time_tolerance : float, optional
        Relative tolerance on the agreement of the channels' time bases; default 1e-9.
    snap_rate : bool, optional
        Rebuild a truncated sampling rate (see above); default True.

    Returns
    -------
    SignalTable
        ``"time"`` [s] and one column per channel; ``.units`` (name -> unit label, '' if
        unknown), ``.path``, ``.time_column`` and ``.channel_info`` (name -> dict with the
        response node, direction, entity name and the ID lines).

    Raises
    ------
    ModelError
        When the file is missing or unreadable, holds no time-series dataset 58, or its
        channels have different time bases or lengths (naming them).

    Examples
    --------
    Write one channel with pyuff and read it back::

        import numpy as np, pyuff
        t = np.arange(1000) / 1000.0
        ds = pyuff.prepare_58(func_type=1, rsp_node=1, rsp_dir=1, ref_node=0, ref_dir=0,
                              id1="acc_A", data=np.sin(60 * t), x=t, abscissa_spacing=1,
                              abscissa_spec_data_type=17, ordinate_spec_data_type=12,
                              orddenom_spec_data_type=0, ordinate_axis_units_lab="m/s^2")
        pyuff.UFF("rig.uff").write_sets(ds, mode="overwrite")
        read_signals_uff("rig.uff")["acc_A"]
    """
    from fricdamp.iofiles import require_regular_file

    p = Path(path)
    require_regular_file(p, what="UFF file", error=ModelError)
    try:
        import pyuff
    except ImportError as exc:  # pragma: no cover - pyuff is a dependency
        raise ModelError("reading UFF files needs the 'pyuff' package (pip install "
                         "pyuff>=2.4)") from exc
    try:
        uff = pyuff.UFF(str(p))
        types = [int(x) for x in np.atleast_1d(uff.get_set_types())]
        sets = uff.read_sets() if types else []
    except Exception as exc:  # pyuff raises bare Exceptions on malformed files
        raise ModelError(f"{str(p)!r} is not a readable Universal File: {exc}") from None
    if isinstance(sets, dict):
        sets = [sets]
    length_factor = None
    for ds in sets:
        if int(ds.get("type", 0)) == 164:
            length_factor = float(ds.get("length", 1.0) or 1.0)

    series, skipped = [], []
    for i, ds in enumerate(sets):
        if int(ds.get("type", 0)) != 58:
            continue
        ftype = int(ds.get("func_type", 0))
        xtype = int(ds.get("abscissa_spec_data_type", 0))
        data = np.asarray(ds.get("data"))
        if (ftype == 1 or (ftype == 0 and xtype == _TIME_TYPE)) and not np.iscomplexobj(data):
            series.append(ds)
        else:
            skipped.append(f"#{i + 1} (function type {ftype})")
    if not series:
        raise ModelError(f"{str(p)!r} holds no time series (dataset 58 of function type 1); "
                         f"found dataset types {sorted(set(types))}"
                         + (f", skipped {', '.join(skipped)}" if skipped else ""))
    if skipped:
        log.info("%s: skipped datasets that are not time series: %s", p, ", ".join(skipped))

    ids = [_label(ds.get("id1")) for ds in series]
    use_ids = all(ids) and len(set(ids)) == len(ids)
    names, info = [], {}
    for ds, ident in zip(series, ids, strict=True):
        node, direction = int(ds.get("rsp_node", 0)), int(ds.get("rsp_dir", 0))
        name = ident if use_ids else f"node{node}{_DIRECTIONS.get(direction, str(direction))}"
        if name in info:
            raise ModelError(f"{str(p)!r}: two channels are both named {name!r} (same ID line "
                             "or same node and direction)")
        names.append(name)
        info[name] = {"node": node, "direction": direction,
                      "entity": _label(ds.get("rsp_ent_name")),
                      "id": [_label(ds.get(f"id{k}")) for k in range(1, 6)],
                      "ordinate_type": int(ds.get("ordinate_spec_data_type", 0))}

    # the common time base
    t0 = np.asarray(series[0]["x"], dtype=float)
    tunit = _label(series[0].get("abscissa_axis_units_lab")).lower()
    if tunit not in _TIME_UNITS:
        raise ModelError(f"{str(p)!r}, channel {names[0]!r}: time unit {tunit!r} is not "
                         f"understood (known: s, ms, us)")
    for ds, name in zip(series[1:], names[1:], strict=True):
        x = np.asarray(ds["x"], dtype=float)
        if x.shape != t0.shape:
            raise ModelError(f"{str(p)!r}: channel {name!r} has {x.size} samples, channel "
                             f"{names[0]!r} has {t0.size}; all channels must share one time "
                             "base")
        span = max(float(np.ptp(t0)), 1e-300)
        if np.max(np.abs(x - t0)) > time_tolerance * span:
            raise ModelError(f"{str(p)!r}: channel {name!r} is not sampled at the times of "
                             f"channel {names[0]!r}; all channels must share one time base")
    t = t0 * _TIME_UNITS[tunit]
    if t.size < 2 or np.any(np.diff(t) <= 0):
        raise ModelError(f"{str(p)!r}: the time abscissa must be strictly increasing")
    if snap_rate and int(series[0].get("abscissa_spacing", 0)) == 1:
        rate = (t.size - 1) / (t[-1] - t[0])
        if abs(rate - round(rate)) <= 1e-5 * rate and round(rate) > 0:
            t = t[0] + np.arange(t.size) / float(round(rate))

    data, units = {"time": t}, {"time": "s"}
    for ds, name in zip(series, names, strict=True):
        y = np.asarray(ds["data"], dtype=float)
        if not np.all(np.isfinite(y)):
            raise ModelError(f"{str(p)!r}: channel {name!r} holds non-finite values")
        unit = _label(ds.get("ordinate_axis_units_lab"))
        if not unit and int(ds.get("ordinate_spec_data_type", 0)) == _ACCELERATION_TYPE \
                and length_factor is not None:
            y = y / length_factor  # 164: SI = file value / factor
            unit = "m/s^2"
        data[name] = y
        units[name] = unit
    table = SignalTable(data, units=units, path=p, time_column="time")
    table.channel_info = info
    return table
