"""Size checks before allocating: refuse a run that would need more memory than the machine has.

A time step of 1e-12 s over one second, or ``harmonics = 10**9``, would otherwise end in a
``MemoryError`` (or the machine swapping) deep inside numpy. These functions estimate the
memory of the arrays a solver allocates from its arguments alone and raise a
:class:`~fricdamp.errors.CheckError` (a ModelError: exit code 2 on the command line) naming
the parameter that drives the size, the estimate and what the machine has.

The estimates count the arrays that grow with the parameter (saved histories, harmonic bases,
dense Jacobians) at 8 bytes per number; they are lower bounds of the real use, so a run that
passes may still be large, but one that fails certainly does not fit.
"""

from __future__ import annotations

import math
import os

from fricdamp.errors import CheckError, ModelError

__all__ = ["available_memory", "check_harmonics_memory", "check_time_memory", "format_bytes"]

#: Share of the available memory one run may plan to use.
MEMORY_SHARE = 0.8


def available_memory() -> int:
    """Bytes of memory available to a new allocation (``MemAvailable`` on Linux, else the
    physical memory); the environment variable ``FRICDAMP_MAX_MEMORY`` (bytes) caps it."""
    avail = None
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    avail = int(line.split()[1]) * 1024
                    break
    except (OSError, ValueError, IndexError):
        avail = None
    if avail is None:
        try:
            avail = os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
        except (ValueError, OSError, AttributeError):
            avail = 8 * 2**30
    cap = os.environ.get("FRICDAMP_MAX_MEMORY")
    if cap:
        try:
            avail = min(avail, int(float(cap)))
        except ValueError:
            pass
    return int(avail)


def format_bytes(n: float) -> str:
    """``7.3 TiB``, ``512 MiB``, ..."""
    for unit, size in (("PiB", 2**50), ("TiB", 2**40), ("GiB", 2**30), ("MiB", 2**20),
                       ("KiB", 2**10)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{n:.0f} B"


def _refuse(param: str, value, need: float, what: str, advice: str) -> None:
    have = available_memory()
    if need > MEMORY_SHARE * have:
        raise CheckError(f"{param} = {value!r} would need about {format_bytes(need)} for "
                         f"{what}; the machine has {format_bytes(have)} available: {advice}")


def check_time_memory(duration: float, dt: float, n_dof: int, n_contact_rows: int = 0, *,
                      save_every: int = 1, param: str = "dt", value=None) -> int:
    """Refuse a constant-step integration whose saved history does not fit in memory.

    Parameters
    ----------
    duration, dt : float
        Integrated time span and time step [s] (both > 0, finite).
    n_dof : int
        DOFs (q, v, a are saved: 3 n_dof numbers per saved step).
    n_contact_rows : int
        Contact directions summed over the contacts (displacement and force saved).
    save_every : int
        Every k-th step is saved.
    param, value : str, optional
        Name and value of the parameter that sets the step, for the message (default ``dt``
        and ``dt``; e.g. ``steps_per_period`` and its value).

    Returns
    -------
    int
        The number of steps.

    Raises
    ------
    CheckError
        Naming ``param``, the memory estimate and the available memory.
    """
    for name, v in (("duration", duration), (param, dt)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ModelError(f"{name} must be a finite number > 0 s, got {v!r}")
    n_steps = math.ceil(duration / dt - 1e-9)
    n_save = n_steps // max(int(save_every), 1) + 1
    per_sample = 8 * (3 * n_dof + 2 * n_contact_rows + 8)
    more = "reduce" if param == "steps_per_period" else "increase"
    _refuse(param, dt if value is None else value, n_save * per_sample,
            f"{n_save:.3g} saved steps of {n_dof} DOF{'s' if n_dof != 1 else ''}",
            f"{more} {param} or save fewer steps (save_every), or shorten the run")
    return n_steps


def check_harmonics_memory(harmonics: int, samples: int | None, n_dof: int,
                           n_contact_rows: int = 0, *, param: str = "harmonics") -> None:
    """Refuse a harmonic-balance size whose bases and Jacobian do not fit in memory.

    Counted: the AFT bases (two ``samples x (2H + 1)`` matrices), the contact signals on the
    grid (``samples x n_contact_rows``, four of them) and one dense Jacobian of the condensed
    unknowns ``(n_contact_rows (2H + 1))^2`` (or of all DOFs without contacts). ``samples``
    defaults to the power of two >= 16 H as in :func:`fricdamp.solvers.hb.harmonic_balance`.

    Raises
    ------
    ModelError
        ``harmonics`` not an integer >= 1.
    CheckError
        Naming ``harmonics`` (or ``samples`` when it is the larger factor).
    """
    if isinstance(harmonics, bool) or not isinstance(harmonics, int) or harmonics < 1:
        raise ModelError(f"harmonics must be an integer >= 1, got {harmonics!r}")
    H = int(harmonics)
    nh = 2 * H + 1
    if samples is None:
        n_t = 2 ** math.ceil(math.log2(max(16 * H, 8)))
        name, value = param, harmonics
    else:
        if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
            raise ModelError(f"samples must be an integer >= 2H + 1, got {samples!r}")
        n_t = int(samples)
        name, value = ("samples", samples) if n_t > 16 * H else (param, harmonics)
    rows = n_contact_rows if n_contact_rows else n_dof
    need = 8.0 * (2 * n_t * nh + 4 * n_t * max(n_contact_rows, 1) + (rows * nh) ** 2)
    _refuse(name, value, need, f"harmonic balance with H = {H} and {n_t} AFT samples",
            "reduce harmonics (H = 7 to 21 resolves friction loops to ~1 %) or samples")
