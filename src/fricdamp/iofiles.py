"""Atomic file writing: JSON with numpy support, netCDF / ``.npz`` results, PNG figures.

Every writer here writes to a temporary file in the destination folder and then renames it
over the destination with :func:`os.replace` (atomic on POSIX and Windows), so a reader never
sees a half-written result: either the old file or the complete new one. If writing fails,
the temporary file is removed and the destination is left untouched.

Results files hold one :class:`xarray.Dataset`. netCDF is written with ``engine="scipy"``
(netCDF-3, no extra dependency); ``.npz`` is the fallback for users without netCDF tools.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import tempfile
from collections.abc import Iterator, Mapping
from dataclasses import asdict, is_dataclass
from pathlib import Path

import numpy as np

__all__ = [
    "OutputLock",
    "atomic_path",
    "prepare_output_folder",
    "read_regular_file",
    "combine_results",
    "read_results",
    "save_figure",
    "to_jsonable",
    "write_json",
    "write_results",
    "write_text",
]

#: Suffixes accepted by :func:`write_results`.
RESULT_FORMATS = {".nc": "netcdf", ".npz": "npz"}


def _os_reason(exc: OSError) -> str:
    import errno

    if exc.errno == errno.ENOSPC:
        return "the disk is full"
    if exc.errno == errno.EDQUOT:
        return "the disk quota is exceeded"
    if exc.errno in (errno.EACCES, errno.EPERM):
        return "permission denied"
    if exc.errno == errno.EROFS:
        return "the file system is read-only"
    return exc.strerror or type(exc).__name__


def output_error(path, exc: OSError, action: str = "cannot write"):
    """An :class:`~fricdamp.errors.OutputError` naming ``path`` and the reason (one line)."""
    from fricdamp.errors import OutputError

    return OutputError(f"{action} {os.fspath(path)!r}: {_os_reason(exc)}")


def prepare_output_folder(out_dir: str | os.PathLike) -> Path:
    """Create ``out_dir`` (with parents) and check a file can be written there, before any
    computation starts.

    Raises
    ------
    OutputError
        Naming the folder (or the file in the way) and the reason: not a folder, permission
        denied, read-only or full file system.
    """
    from fricdamp.errors import OutputError

    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise OutputError(f"the output folder {str(out_dir)!r} is a file; choose another --out")
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise output_error(out_dir, exc, "cannot create the output folder") from None
    probe = out_dir / f".fricdamp-write-test-{os.getpid()}"
    try:
        with open(probe, "wb") as fh:
            fh.write(b"x" * 4096)
            fh.flush()
            os.fsync(fh.fileno())
    except OSError as exc:
        raise output_error(out_dir, exc, "cannot write into the output folder") from None
    finally:
        with contextlib.suppress(OSError):
            probe.unlink()
    return out_dir


class OutputLock:
    """``out_dir/.fricdamp.lock`` held while a run or study writes into ``out_dir``.

    Created with ``O_EXCL`` and holding the process id; a lock left by a process that no
    longer runs (killed) is taken over. Use as a context manager.

    Raises
    ------
    OutputError
        If another running fricdamp process holds the folder.
    """

    NAME = ".fricdamp.lock"

    def __init__(self, out_dir: str | os.PathLike, what: str = "run"):
        self.path = Path(out_dir) / self.NAME
        self.what = what
        self._held = False

    @staticmethod
    def _alive(pid: int) -> bool:
        if pid <= 0:
            return False
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return False
        except PermissionError:
            return True
        return True

    def acquire(self) -> OutputLock:
        from fricdamp.errors import OutputError

        for _ in range(2):
            try:
                fd = os.open(self.path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                try:
                    text = self.path.read_text(encoding="utf-8").split()
                    pid = int(text[0]) if text else -1
                except (OSError, ValueError):
                    pid = -1
                if pid != os.getpid() and self._alive(pid):
                    raise OutputError(
                        f"another fricdamp {text[1] if len(text) > 1 else 'run'} (process "
                        f"{pid}) is writing into {str(self.path.parent)!r} (lock file "
                        f"{self.path.name}); wait for it to finish or choose another folder"
                    ) from None
                with contextlib.suppress(FileNotFoundError):
                    self.path.unlink()   # stale: its process is gone
                continue
            except OSError as exc:
                raise output_error(self.path, exc) from None
            with os.fdopen(fd, "w") as fh:
                fh.write(f"{os.getpid()} {self.what}\n")
            self._held = True
            return self
        raise OutputError(f"cannot take the lock {str(self.path)!r}")

    def release(self) -> None:
        if self._held:
            with contextlib.suppress(OSError):
                self.path.unlink()
            self._held = False

    def __enter__(self) -> OutputLock:
        return self.acquire()

    def __exit__(self, *exc) -> None:
        self.release()


#: Largest case or table file read (bytes): a case file is a few kB.
MAX_TEXT_FILE_BYTES = 16 * 2**20


def require_regular_file(path: str | os.PathLike, *, what: str = "file",
                         error: type[Exception] | None = None) -> os.stat_result:
    """The ``os.stat`` of ``path``, which must exist and be a regular file.

    A missing path "does not exist"; a folder "is a folder, not a file"; a device or pipe
    (``/dev/zero``, ``/dev/stdin``) "is not a regular file" (reading it would never end).
    Raises ``error`` (default :class:`~fricdamp.errors.CaseError`) naming ``what`` and the
    path.
    """
    import stat

    if error is None:
        from fricdamp.errors import CaseError as error
    p = Path(path)
    try:
        st = os.stat(p)
    except FileNotFoundError:
        raise error(f"{what} {str(p)!r} does not exist") from None
    except OSError as exc:
        raise error(f"cannot read {what} {str(p)!r}: {_os_reason(exc)}") from None
    if stat.S_ISDIR(st.st_mode):
        raise error(f"{what} {str(p)!r} is a folder, not a file")
    if not stat.S_ISREG(st.st_mode):
        raise error(f"{what} {str(p)!r} is not a regular file (a device or pipe); give "
                    "the path of a file")
    return st


def read_regular_file(path: str | os.PathLike, *, what: str = "file",
                      max_bytes: int = MAX_TEXT_FILE_BYTES) -> bytes:
    """The bytes of ``path``, which must be a regular file of at most ``max_bytes``.

    Devices, pipes and folders are refused (``/dev/zero`` would never end), and so is a
    file larger than the cap. Raises :class:`~fricdamp.errors.CaseError` naming the path.
    """
    from fricdamp.errors import CaseError

    p = Path(path)
    st = require_regular_file(p, what=what, error=CaseError)
    if st.st_size > max_bytes:
        raise CaseError(f"{what} {str(p)!r} is {st.st_size / 2**20:.1f} MiB; a {what} may be "
                        f"at most {max_bytes / 2**20:.0f} MiB")
    try:
        with open(p, "rb") as fh:
            data = fh.read(max_bytes + 1)
    except OSError as exc:
        raise CaseError(f"cannot read {what} {str(p)!r}: {_os_reason(exc)}") from None
    if len(data) > max_bytes:
        raise CaseError(f"{what} {str(p)!r} is larger than {max_bytes / 2**20:.0f} MiB")
    return data


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; rename it over ``path`` on success.

    Parameters
    ----------
    path : path-like
        Final destination. Its folder must exist.

    Yields
    ------
    Path
        A fresh temporary file in the same folder (same file system, so the rename is atomic).
        Write the complete content to it; it replaces ``path`` when the block exits normally
        and is deleted when the block raises.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> with atomic_path(d / "x.txt") as tmp:
    ...     _ = tmp.write_text("done")
    >>> (d / "x.txt").read_text()
    'done'
    """
    path = Path(path)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        yield tmp
        # mkstemp creates files readable by the owner only; give results the usual mode
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
        raise


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically; return the path."""
    path = Path(path)
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        fh.write(text)
        fh.flush()
        os.fsync(fh.fileno())
    return path


def to_jsonable(obj):
    """Convert ``obj`` to plain JSON types.

    numpy scalars and arrays become Python numbers and (nested) lists, paths become strings,
    dataclasses and mappings become dicts (keys as strings), tuples and sets become lists.
    Non-finite floats (NaN, inf) become ``None`` (JSON has no NaN; ``null`` means "not
    available"). Complex numbers become ``{"real": ..., "imag": ...}``.
    """
    if obj is None or isinstance(obj, (bool, str)):
        return obj
    if isinstance(obj, (int, np.integer)) and not isinstance(obj, np.bool_):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, (float, np.floating)):
        x = float(obj)
        return x if math.isfinite(x) else None
    if isinstance(obj, (complex, np.complexfloating)):
        return {"real": to_jsonable(obj.real), "imag": to_jsonable(obj.imag)}
    if isinstance(obj, np.ndarray):
        return [to_jsonable(x) for x in obj.tolist()] if obj.ndim else to_jsonable(obj.item())
    if isinstance(obj, os.PathLike):
        return os.fspath(obj)
    if is_dataclass(obj) and not isinstance(obj, type):
        return to_jsonable(asdict(obj))
    if isinstance(obj, Mapping):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, set, frozenset)):
        return [to_jsonable(x) for x in obj]
    if hasattr(obj, "model_dump"):  # pydantic models
        return to_jsonable(obj.model_dump())
    raise TypeError(f"cannot convert {type(obj).__name__} to JSON: {obj!r}")


def write_json(path: str | os.PathLike, obj, *, indent: int = 2) -> Path:
    """Write ``obj`` as JSON (through :func:`to_jsonable`) atomically; return the path."""
    text = json.dumps(to_jsonable(obj), indent=indent, allow_nan=False, ensure_ascii=False)
    return write_text(path, text + "\n")


def save_figure(fig, path: str | os.PathLike, *, dpi: int = 120) -> Path:
    """Save a matplotlib figure as PNG atomically; return the path."""
    path = Path(path)
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fig.savefig(fh, format="png", dpi=dpi)
    return path


# --------------------------------------------------------------------------- results files
def _sanitize_attrs(attrs: Mapping) -> dict:
    """netCDF-3 attributes must be strings, numbers or 1-D numeric arrays."""
    out = {}
    for k, v in attrs.items():
        if isinstance(v, (str, int, float, np.integer, np.floating)) and not isinstance(
                v, (bool, np.bool_)):
            out[str(k)] = v
        elif isinstance(v, (bool, np.bool_)):
            out[str(k)] = int(v)
        elif isinstance(v, (list, tuple, np.ndarray)) and np.asarray(v).dtype.kind in "iuf":
            out[str(k)] = np.asarray(v)
        else:
            out[str(k)] = json.dumps(to_jsonable(v)) if not isinstance(v, str) else v
    return out


def _netcdf3_ready(ds):
    """Copy of ``ds`` that the scipy (netCDF-3) backend can write.

    Complex variables are split into ``<name>_real`` / ``<name>_imag``, 64-bit integers become
    32-bit (netCDF-3 has no int64; values out of range raise), booleans become int8 and
    attributes are made netCDF-safe.
    """
    import xarray as xr

    new_vars = {}
    for name, var in ds.data_vars.items():
        var = var.variable
        if np.iscomplexobj(var.values):
            new_vars[f"{name}_real"] = xr.Variable(var.dims, var.values.real, var.attrs)
            new_vars[f"{name}_imag"] = xr.Variable(var.dims, var.values.imag, var.attrs)
        else:
            new_vars[name] = var
    out = xr.Dataset(new_vars, coords=ds.coords)
    for name in list(out.variables):
        v = out[name].variable
        vals = v.values
        if vals.dtype.kind in "iu" and vals.dtype.itemsize > 4:
            if vals.size and (vals.max() > np.iinfo(np.int32).max
                              or vals.min() < np.iinfo(np.int32).min):
                raise ValueError(f"variable {name!r} does not fit in netCDF-3 int32")
            vals = vals.astype(np.int32)
        elif vals.dtype.kind == "b":
            vals = vals.astype(np.int8)
        elif vals.dtype.kind == "O":
            vals = vals.astype(str)
        attrs = _sanitize_attrs(v.attrs)
        out[name] = xr.Variable(v.dims, vals, attrs)
    out.attrs = _sanitize_attrs(ds.attrs)
    return out


def write_results(path: str | os.PathLike, ds) -> Path:
    """Write a Dataset atomically as netCDF-3 (``.nc``, scipy engine) or ``.npz``.

    Parameters
    ----------
    path : path-like
        Destination; the suffix chooses the format (``.nc`` or ``.npz``).
    ds : xarray.Dataset
        The results. For ``.npz`` every variable and coordinate is stored under its own name,
        with its dimension names in ``<name>__dims`` and the attributes as JSON in
        ``__attrs__``, so :func:`read_results` rebuilds the Dataset.
    """
    path = Path(path)
    fmt = RESULT_FORMATS.get(path.suffix)
    if fmt is None:
        raise ValueError(f"results file must end in one of {sorted(RESULT_FORMATS)}, got {path}")
    if fmt == "netcdf":
        ds3 = _netcdf3_ready(ds)
        with atomic_path(path) as tmp:
            ds3.to_netcdf(tmp, engine="scipy", format="NETCDF3_64BIT")
        return path
    arrays = {}
    for name, var in ds.variables.items():
        arrays[str(name)] = np.asarray(var.values)
        arrays[f"{name}__dims"] = np.array(var.dims, dtype=str)
    attrs = {"dataset": to_jsonable(dict(ds.attrs)),
             "variables": {str(n): to_jsonable(dict(v.attrs)) for n, v in ds.variables.items()},
             "coords": [str(c) for c in ds.coords]}
    arrays["__attrs__"] = np.array(json.dumps(attrs))
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        np.savez_compressed(fh, **arrays)
    return path


def read_results(path: str | os.PathLike):
    """Read a results file written by :func:`write_results` back into an xarray Dataset."""
    import xarray as xr

    path = Path(path)
    if path.suffix == ".nc":
        with xr.open_dataset(path, engine="scipy") as ds:
            return ds.load()
    with np.load(path) as z:
        meta = json.loads(str(z["__attrs__"]))
        names = [k for k in z.files if not k.endswith("__dims") and k != "__attrs__"]
        variables = {n: xr.Variable(tuple(z[f"{n}__dims"].tolist()), z[n],
                                    meta["variables"].get(n, {})) for n in names}
    coords = {n: v for n, v in variables.items() if n in meta["coords"]}
    data = {n: v for n, v in variables.items() if n not in meta["coords"]}
    return xr.Dataset(data, coords=coords, attrs=meta["dataset"])


def combine_results(results: Mapping[str, Mapping[str, object]], *, attrs=None):
    """Merge per-analysis arrays into one Dataset with prefixed names.

    Parameters
    ----------
    results : mapping analysis name -> mapping entry name -> DataArray or Dataset
        The ``arrays`` of each analysis output.
    attrs : mapping, optional
        Global attributes of the merged Dataset.

    Returns
    -------
    xarray.Dataset
        A DataArray ``arr`` of analysis ``a`` becomes variable ``a__arr``; each variable ``v``
        of a Dataset entry becomes ``a__v``. Dimensions and coordinates are prefixed with
        ``a__`` too (``free_decay__time``). When two entries of one analysis share a dimension
        name with different sizes or coordinate values, the later entry's dimensions are
        prefixed ``a__entry__`` instead, so nothing is silently aligned or overwritten.
    """
    import xarray as xr

    merged = xr.Dataset(attrs=dict(attrs or {}))
    for analysis, entries in results.items():
        for entry, obj in entries.items():
            if isinstance(obj, xr.DataArray):
                ds = obj.to_dataset(name=entry)
            elif isinstance(obj, xr.Dataset):
                ds = obj
            else:
                raise TypeError(f"{analysis}.{entry}: arrays must be xarray DataArray or "
                                f"Dataset, got {type(obj).__name__}")
            for prefix in (f"{analysis}__", f"{analysis}__{entry}__"):
                renamed = _prefixed(ds, prefix, var_prefix=f"{analysis}__")
                if _compatible(merged, renamed):
                    break
            else:  # pragma: no cover - the entry prefix is unique by construction
                raise ValueError(f"cannot merge results {analysis}.{entry}")
            clash = set(renamed.data_vars) & set(merged.data_vars)
            if clash:
                raise ValueError(f"results of {analysis!r} define {sorted(clash)} twice")
            merged = xr.merge([merged, renamed], compat="no_conflicts", join="exact",
                              combine_attrs="override")
    return merged


def _prefixed(ds, dim_prefix: str, *, var_prefix: str):
    names = {d: f"{dim_prefix}{d}" for d in ds.dims}
    coord_names = {c: f"{dim_prefix}{c}" for c in ds.coords if c not in names}
    vars_ = {v: f"{var_prefix}{v}" for v in ds.data_vars}
    return ds.rename({**names, **coord_names, **vars_})


def _compatible(merged, ds) -> bool:
    for d, size in ds.sizes.items():
        if d in merged.sizes and merged.sizes[d] != size:
            return False
    for c in ds.coords:
        if c in merged.coords and not merged[c].equals(ds[c]):
            return False
    return True
