"""Linear modal analysis, Campbell diagrams and critical speeds.

**Normal modes** (``kind="undamped"``): ``(K - w^2 M) phi = 0`` with M, K symmetric, solved
densely (LAPACK) for small systems and by ARPACK shift-invert on a sparse LU factorisation
of ``K - sigma M`` for large ones (a few thousand DOFs in well under a second). The
damping matrix does not enter; the modal damping ratios reported are the diagonal
projections ``zeta_k = phi_k^T D phi_k / (2 w_k phi_k^T M phi_k)`` (exact for proportional
damping).

**Complex modes** (``kind="damped"``; chosen automatically when D has a skew-symmetric
(gyroscopic) part or K is not symmetric): the first-order form with ``z = [q; q']``::

    A z' + B z = 0,   A = [[D, M], [M, 0]],   B = [[K, 0], [0, -M]]

whose eigenvalues ``lam`` come in complex-conjugate pairs. The pairs nearest the shift
``s = 2 pi i sigma`` are found with ``(B + s A)^{-1} A`` (eigenvalue ``-1/(lam - s)``), and
one of each pair (``Im lam >= 0``) is kept: frequency ``|Im lam| / 2 pi`` [Hz] (damped),
damping ratio ``-Re lam / |lam|``.

**Campbell diagram**: modes at each spin speed of a system with rotation terms
(:class:`~fricdamp.structure.system.RotationTerms`), followed across speeds by the modal
assurance criterion (MAC) with an optimal one-to-one assignment, so branches keep their
identity through crossings.

**Critical speeds** of paper 003 (1): a wheel passing ``p`` excitation pulses per
revolution, excited in the harmonic order ``o`` of that pulse train, resonates at
``s = 60 f_R / (p o)`` [rpm] (excitation frequency ``p o s / 60`` equal to the resonance
``f_R``). Check against paper 003 Table 2: ``p = 8``, ``o = 1``, ``f_R = 44.53 Hz`` gives
334 rpm; ``o = 3``, ``f_R = 49.20 Hz`` gives 123 rpm.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fricdamp.errors import ConvergenceError, ModelError
from fricdamp.results import ResultMixin
from fricdamp.structure.eigen import DENSE_MAX, _factor, eigenpairs
from fricdamp.structure.system import MechanicalSystem

KINDS = ("auto", "undamped", "damped")

#: Modes computed by :func:`modes` when ``n_modes`` is not given (fewer if the system has
#: fewer DOFs): the lowest ten cover the first families of a blade or a bladed sector, and
#: cost little more than one with shift-invert.
DEFAULT_N_MODES = 10


def _asym(A) -> float:
    scale = float(abs(A).max()) if A.shape[0] else 0.0
    if scale == 0.0:
        return 0.0
    return float(abs(A - A.T).max()) / scale


def _is_zero(A) -> bool:
    return (A.nnz == 0 or abs(A).max() == 0) if sp.issparse(A) else not np.any(A)


def mac(a, b) -> np.ndarray:
    """Modal assurance criterion between the columns of ``a`` and ``b``.

    ``MAC_ij = |a_i^H b_j|^2 / ((a_i^H a_i)(b_j^H b_j))``, in [0, 1] (complex shapes allowed).

    Parameters
    ----------
    a : ndarray, shape (n, k)
    b : ndarray, shape (n, m)

    Returns
    -------
    ndarray, shape (k, m)
    """
    a = np.atleast_2d(np.asarray(a).T).T
    b = np.atleast_2d(np.asarray(b).T).T
    if a.shape[0] != b.shape[0]:
        raise ModelError(f"shapes must have the same number of DOFs, got {a.shape[0]} and "
                         f"{b.shape[0]}")
    num = np.abs(a.conj().T @ b) ** 2
    den = np.outer(np.real(np.sum(a.conj() * a, 0)), np.real(np.sum(b.conj() * b, 0)))
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(den > 0, num / np.where(den > 0, den, 1.0), 0.0)
    return out


@dataclass(frozen=True, repr=False)
class ModalResult(ResultMixin):
    """Modes of a linear system from :func:`modes`.

    Attributes
    ----------
    frequencies : ndarray, shape (n_modes,)
        Eigenfrequencies [Hz], ascending (damped frequencies ``|Im lam|/2 pi`` for complex
        modes; 0 for divergent or rigid-body modes).
    shapes : ndarray, shape (n_dof, n_modes)
        Mode shapes (real for normal modes, complex for damped/gyroscopic ones), normalised
        as asked (``"mass"``: ``phi^H M phi = 1``; ``"max"``: largest component 1).
    modal_masses : ndarray, shape (n_modes,)
        ``phi^H M phi`` [kg for the ``"max"`` normalisation].
    eigenvalues : ndarray of complex, shape (n_modes,)
        ``lam`` [rad/s] with ``q = phi exp(lam t)`` (``i w`` for undamped modes).
    damping_ratios : ndarray, shape (n_modes,)
        Modal damping ratios [-] (see the module docstring).
    kind : str
        ``"undamped"`` or ``"damped"``.
    dof_names : tuple of str
    """

    frequencies: np.ndarray
    shapes: np.ndarray
    modal_masses: np.ndarray
    eigenvalues: np.ndarray
    damping_ratios: np.ndarray
    kind: str
    dof_names: tuple[str, ...] = ()
    meta: dict = field(default_factory=dict, compare=False)

    @property
    def n_modes(self) -> int:
        return self.frequencies.size

    @property
    def omega(self) -> np.ndarray:
        """Angular frequencies [rad/s] (kept for compatibility; ``omega_rad_s``)."""
        return 2 * np.pi * self.frequencies

    @property
    def omega_rad_s(self) -> np.ndarray:
        """Angular frequencies [rad/s], shape (n_modes,)."""
        return 2 * np.pi * self.frequencies

    @property
    def frequencies_hz(self) -> np.ndarray:
        """Eigenfrequencies [Hz] (the same as ``frequencies``), shape (n_modes,)."""
        return self.frequencies

    def _judge(self):
        """``ok`` (a linear eigensolution has no error estimate to judge), ``unreliable`` if
        a frequency is not finite; the lowest frequency and the number of modes recorded."""
        from fricdamp.results import status_verdict

        finite = bool(np.all(np.isfinite(self.frequencies)))
        return status_verdict(True, "", {"n_modes": self.n_modes, "lowest_frequency_hz":
                                         float(self.frequencies[0]) if self.n_modes else None},
                              reasons=() if finite else ("a frequency is not finite",))

    def mac(self, other: ModalResult | np.ndarray | None = None) -> np.ndarray:
        """MAC matrix against another result's shapes (or against itself)."""
        b = self.shapes if other is None else (
            other.shapes if isinstance(other, ModalResult) else other)
        return mac(self.shapes, b)

    def to_xarray(self):
        """``xarray.Dataset`` with coordinates ``mode`` and ``dof``."""
        import xarray as xr

        mode = np.arange(1, self.n_modes + 1)
        dof = list(self.dof_names) if self.dof_names else np.arange(self.shapes.shape[0])
        ds = xr.Dataset(
            {
                "frequency": ("mode", self.frequencies, {"units": "Hz"}),
                "modal_mass": ("mode", self.modal_masses,
                               {"units": "kg" if self.meta.get("normalize") == "max" else "1"}),
                "damping_ratio": ("mode", self.damping_ratios, {"units": "1"}),
                "eigenvalue_real": ("mode", self.eigenvalues.real, {"units": "rad/s"}),
                "eigenvalue_imag": ("mode", self.eigenvalues.imag, {"units": "rad/s"}),
                "shape_real": (("dof", "mode"), np.real(self.shapes), {"units": "1"}),
                "shape_imag": (("dof", "mode"), np.imag(self.shapes), {"units": "1"}),
            },
            coords={"mode": mode, "dof": dof},
            attrs={"kind": self.kind},
        )
        return ds

    def plot(self, modes=None, ax=None):
        """Bar plot of the (real parts of the) mode shapes; returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(layout="constrained")
        sel = range(min(self.n_modes, 4)) if modes is None else modes
        x = np.arange(self.shapes.shape[0])
        for k in sel:
            ax.plot(x, np.real(self.shapes[:, k]), marker="o",
                    label=f"mode {k + 1}: {self.frequencies[k]:.4g} Hz")
        ax.set_xlabel("DOF")
        ax.set_ylabel("mode shape (real part)")
        ax.legend()
        return ax


def _check_int(name: str, value, low: int, high: int | None = None) -> int:
    if isinstance(value, bool) or int(value) != value or value < low or (
            high is not None and value > high):
        rng = f"[{low}, {high}]" if high is not None else f">= {low}"
        raise ModelError(f"{name} must be an integer in {rng}, got {value!r}")
    return int(value)


def _stuck_contact_stiffness(system: MechanicalSystem):
    n = system.n_dof
    Kc = sp.csr_matrix((n, n))
    for c in system.contacts:
        st = c.law.initial_state()
        z = np.zeros((c.n_contacts, c.n_dir))
        kt = c.law.step(st, z, z).stiffness
        blk = sp.block_diag(list(kt), format="csr")
        P = sp.csr_matrix(c.projection)
        Kc = Kc + P.T @ blk @ P
    return Kc


def _normalise(X, M, how: str):
    if how == "mass":
        mm = np.real(np.einsum("ij,ij->j", X.conj(), np.asarray(M @ X)))
        X = X / np.sqrt(mm)
    elif how == "max":
        idx = np.argmax(np.abs(X), axis=0)
        X = X / X[idx, np.arange(X.shape[1])]
    if np.iscomplexobj(X) and how == "mass":  # make the largest component real positive
        idx = np.argmax(np.abs(X), axis=0)
        ph = X[idx, np.arange(X.shape[1])]
        X = X * (np.abs(ph) / ph)
    mm = np.real(np.einsum("ij,ij->j", X.conj(), np.asarray(M @ X)))
    return X, mm


def _complex_modes(M, D, K, n_modes: int, sigma_hz: float, method: str):
    n = M.shape[0]
    sparse_in = sp.issparse(M) or sp.issparse(K) or sp.issparse(D)
    use_dense = method == "dense" or (method == "auto" and (n <= DENSE_MAX // 2
                                                            or 2 * n_modes >= n))
    if 2 * n_modes + 2 >= 2 * n - 1:
        use_dense = True
    s = 2j * np.pi * sigma_hz
    if use_dense:
        Md, Dd, Kd = (A.toarray() if sp.issparse(A) else np.asarray(A) for A in (M, D, K))
        Z = np.zeros((n, n))
        A = np.block([[Dd, Md], [Md, Z]])
        B = np.block([[Kd, Z], [Z, -Md]])
        lam, V = sla.eig(-B, A, check_finite=False)
        ok = np.isfinite(lam)
        lam, V = lam[ok], V[:, ok]
    else:
        if sparse_in:
            Ms, Ds, Ks = (sp.csc_matrix(A) for A in (M, D, K))
            A = sp.bmat([[Ds, Ms], [Ms, None]], format="csc")
            B = sp.bmat([[Ks, None], [None, -Ms]], format="csc")
        else:
            Md, Dd, Kd = (np.asarray(A) for A in (M, D, K))
            Z = np.zeros((n, n))
            A = np.block([[Dd, Md], [Md, Z]])
            B = np.block([[Kd, Z], [Z, -Md]])
        scale = float(abs(K.diagonal()).mean() / abs(M.diagonal()).mean())
        shift = s
        solve = _factor(B + shift * A, sparse=sp.issparse(A))
        bump = 1e-3 * np.sqrt(max(scale, 1e-300))
        tries = 0
        while solve is None:
            tries += 1
            if tries > 6:
                raise ModelError("cannot factorise the first-order pencil near the shift: "
                                 "K is singular; check boundary conditions")
            shift = s - bump
            bump *= 10
            solve = _factor(B + shift * A, sparse=sp.issparse(A))
        dtype = complex
        op = spla.LinearOperator((2 * n, 2 * n), matvec=lambda x: solve((A @ x).astype(dtype)),
                                 dtype=dtype)
        k = min(2 * n_modes + 2, 2 * n - 2)
        rng = np.random.default_rng(12345)
        v0 = rng.standard_normal(2 * n).astype(complex)
        try:
            nu, V = spla.eigs(op, k=k, which="LM", v0=v0, ncv=min(2 * n, max(2 * k + 1, 24)))
        except spla.ArpackNoConvergence as exc:  # pragma: no cover - rare
            raise ConvergenceError(f"ARPACK did not converge for the complex modes: {exc}. "
                                   "Try method='dense' or another sigma") from exc
        lam = shift - 1.0 / nu
    # one of each conjugate pair: Im >= 0 (real eigenvalues kept once each)
    tol = 1e-9 * max(float(np.abs(lam).max(initial=0.0)), 1e-300)
    keep = lam.imag >= -tol
    lam, V = lam[keep], V[:, keep]
    # for Im ~ 0 pairs with a conjugate duplicate, drop duplicates
    order = np.argsort(np.abs(lam - s), kind="stable")
    lam, V = lam[order], V[:, order]
    if lam.size < n_modes:
        raise ConvergenceError(f"found only {lam.size} complex modes, asked for {n_modes}; "
                               "try method='dense'")
    lam, V = lam[:n_modes], V[:, :n_modes]
    order = np.argsort(np.abs(lam.imag) + 1e-12 * np.abs(lam), kind="stable")
    return lam[order], V[:n][:, order]


def modes(system: MechanicalSystem, n_modes: int | None = None, *, sigma: float = 0.0,
          kind: str = "auto", speed: float | None = None, normalize: str = "mass",
          contacts: str = "open", method: str = "auto") -> ModalResult:
    """Linear modes of ``system``.

    Parameters
    ----------
    system : MechanicalSystem
        Linear structure (dense or sparse matrices).
    n_modes : int, optional
        Number of modes, ``1 <= n_modes <= n_dof``; default ``min(10, n_dof)``
        (:data:`DEFAULT_N_MODES`).
    sigma : float
        Frequency [Hz] around which the modes are sought (0: the lowest modes). A system
        with rigid-body modes is handled (the shift is nudged so K - sigma M factorises).
    kind : {"auto", "undamped", "damped"}
        ``undamped``: real normal modes of (K, M). ``damped``: complex modes of the
        first-order form (gyroscopic, non-proportional damping, non-symmetric K).
        ``auto``: damped if D has a skew-symmetric part or K is not symmetric.
    speed : float, optional
        Spin speed [rad/s] at which to evaluate the rotation terms (``system.at_speed``).
    normalize : {"mass", "max"}
        ``phi^H M phi = 1`` or largest component equal to 1.
    contacts : {"open", "stuck"}
        ``open``: contacts ignored (the 003 open-contact model). ``stuck``: each contact's
        tangent at zero relative displacement from its virgin state is added to K.
    method : {"auto", "dense", "sparse"}
        Dense LAPACK or ARPACK shift-invert (auto: dense up to 400 DOFs).

    Returns
    -------
    ModalResult

    Raises
    ------
    ModelError
        Bad arguments.

    Examples
    --------
    >>> import numpy as np
    >>> from fricdamp.structure import chain
    >>> res = modes(chain([1.0], [4 * np.pi**2]), 1)
    >>> float(np.round(res.frequencies[0], 12))
    1.0
    """
    if not isinstance(system, MechanicalSystem):
        raise ModelError(f"system must be a MechanicalSystem, got {type(system).__name__}")
    n = system.n_dof
    if n_modes is None:
        n_modes = min(DEFAULT_N_MODES, n)
    n_modes = _check_int("n_modes", n_modes, 1, n)
    if not np.isfinite(sigma) or sigma < 0:
        raise ModelError(f"sigma must be a frequency >= 0 Hz, got {sigma!r}")
    if kind not in KINDS:
        raise ModelError(f"kind must be one of {KINDS}, got {kind!r}")
    if normalize not in ("mass", "max"):
        raise ModelError(f"normalize must be 'mass' or 'max', got {normalize!r}")
    if contacts not in ("open", "stuck"):
        raise ModelError(f"contacts must be 'open' or 'stuck', got {contacts!r}")
    if speed is not None:
        if not np.isfinite(speed):
            raise ModelError(f"speed must be a finite spin speed in rad/s, got {speed!r}")
        system = system.at_speed(float(speed))
    M, D, K = system.M, system.D, system.K
    if contacts == "stuck" and system.contacts:
        Kc = _stuck_contact_stiffness(system)
        K = (sp.csr_matrix(K) + Kc) if sp.issparse(K) else K + Kc.toarray()
    if kind == "auto":
        kind = "damped" if (_asym(D) > 1e-12 or _asym(K) > 1e-10) else "undamped"
    if kind == "undamped":
        if _asym(K) > 1e-8:
            raise ModelError("K is not symmetric: use kind='damped' (first-order complex "
                             "modes)")
        lam2, X = eigenpairs(K, M, n_modes, shift=(2 * np.pi * sigma) ** 2, method=method)
        w = np.sqrt(np.maximum(lam2, 0.0))
        eig = np.where(lam2 >= 0, 1j * w, np.sqrt(np.maximum(-lam2, 0.0)) + 0j)
        X, mm = _normalise(X, M, normalize)
        dd = np.real(np.einsum("ij,ij->j", X.conj(), np.asarray(D @ X)))
        with np.errstate(divide="ignore", invalid="ignore"):
            zeta = np.where(w > 0, dd / (2 * np.where(w > 0, w, 1.0) * mm), 0.0)
        freqs = w / (2 * np.pi)
    else:
        from threadpoolctl import threadpool_limits

        with threadpool_limits(limits=1, user_api="blas"):  # see eigenpairs: ~40x faster
            lam, X = _complex_modes(M, D, K, n_modes, sigma, method)
        X, mm = _normalise(X, M, normalize)
        eig = lam
        freqs = np.abs(lam.imag) / (2 * np.pi)
        absl = np.abs(lam)
        with np.errstate(divide="ignore", invalid="ignore"):
            zeta = np.where(absl > 0, -lam.real / np.where(absl > 0, absl, 1.0), 0.0)
    return ModalResult(frequencies=freqs, shapes=X, modal_masses=mm, eigenvalues=eig,
                       damping_ratios=zeta, kind=kind, dof_names=system.names,
                       meta={"sigma_hz": sigma, "normalize": normalize, "spin_speed_rad_s":
                             system.meta.get("spin_speed_rad_s")})


def whirl_direction(shapes, x_dof: int, y_dof: int) -> np.ndarray:
    """Whirl direction of complex modes from two orthogonal DOFs ``x`` and ``y``.

    With ``q = Re(phi exp(i w t))``, ``w > 0``, the orbit of ``(q_x, q_y)`` turns
    counter-clockwise (positive about z = x cross y) when ``Im(conj(phi_x) phi_y) < 0``.

    Returns
    -------
    ndarray of int, shape (n_modes,)
        +1 counter-clockwise (forward whirl for a positive spin about z), -1 clockwise
        (backward), 0 for a straight-line (real) orbit.
    """
    X = np.atleast_2d(np.asarray(shapes).T).T
    s = -np.imag(np.conj(X[x_dof]) * X[y_dof])
    scale = np.abs(X[x_dof]) * np.abs(X[y_dof])
    out = np.sign(s).astype(int)
    out[np.abs(s) <= 1e-9 * np.maximum(scale, 1e-300)] = 0
    return out


# --------------------------------------------------------------------------- Campbell
@dataclass(frozen=True)
class Crossing:
    """Intersection of a Campbell branch with an excitation line ``f = p o Omega / 2 pi``."""

    order: int
    mode: int
    speed_rad_s: float
    frequency_hz: float

    @property
    def rpm(self) -> float:
        return self.speed_rad_s * 30.0 / np.pi


@dataclass(frozen=True, repr=False)
class CampbellResult(ResultMixin):
    """Modes of a rotating system across spin speeds, tracked by MAC.

    Attributes
    ----------
    speeds : ndarray, shape (n_speeds,)
        Spin speeds [rad/s].
    frequencies : ndarray, shape (n_speeds, n_modes)
        Branch frequencies [Hz]; column k is one mode followed across speeds.
    damping_ratios : ndarray, shape (n_speeds, n_modes)
    eigenvalues : ndarray of complex, shape (n_speeds, n_modes)
    tracking_mac : ndarray, shape (n_speeds, n_modes)
        MAC of each branch with itself at the previous speed (1 at the first speed); low
        values flag ambiguous tracking (e.g. splitting of a double mode).
    shapes : ndarray, shape (n_speeds, n_dof, n_modes) or None
        Mode shapes when asked for (``keep_shapes=True``).
    """

    speeds: np.ndarray
    frequencies: np.ndarray
    damping_ratios: np.ndarray
    eigenvalues: np.ndarray
    tracking_mac: np.ndarray
    shapes: np.ndarray | None = None

    @property
    def rpm(self) -> np.ndarray:
        """Spin speeds [rpm]."""
        return self.speeds * 30.0 / np.pi

    @property
    def speeds_rad_s(self) -> np.ndarray:
        """Spin speeds [rad/s] (the same as ``speeds``)."""
        return self.speeds

    def _judge(self):
        """``ok``; the lowest tracking MAC is recorded (low values flag an ambiguous
        assignment, e.g. a double mode splitting: refine the speed grid there)."""
        from fricdamp.results import status_verdict

        mac_min = float(np.min(self.tracking_mac)) if self.tracking_mac.size else None
        return status_verdict(True, "", {"min_tracking_mac": mac_min})

    def crossings(self, orders, pulses: int = 1) -> list[Crossing]:
        """Crossings of the branches with excitation lines ``f = pulses * o * Omega / 2 pi``.

        Linear interpolation between the computed speeds (refine the speed grid near a
        crossing for accuracy). ``orders`` are the engine orders ``o`` (or pulse-train
        harmonic orders, 003 (1)).
        """
        p = _check_int("pulses", pulses, 1)
        out = []
        for o in np.atleast_1d(orders):
            o = _check_int("orders", o, 1)
            line = p * o * self.speeds / (2 * np.pi)
            for k in range(self.frequencies.shape[1]):
                g = self.frequencies[:, k] - line
                for i in range(len(g) - 1):
                    if g[i] == 0 or g[i] * g[i + 1] < 0:
                        t = 0.0 if g[i] == 0 else g[i] / (g[i] - g[i + 1])
                        w = self.speeds[i] + t * (self.speeds[i + 1] - self.speeds[i])
                        f = self.frequencies[i, k] + t * (self.frequencies[i + 1, k]
                                                          - self.frequencies[i, k])
                        out.append(Crossing(order=o, mode=k, speed_rad_s=float(w),
                                            frequency_hz=float(f)))
                if g[-1] == 0:
                    out.append(Crossing(order=o, mode=k, speed_rad_s=float(self.speeds[-1]),
                                        frequency_hz=float(self.frequencies[-1, k])))
        return out

    def to_xarray(self):
        """``xarray.Dataset`` with coordinates ``speed`` [rad/s] and ``mode``."""
        import xarray as xr

        mode = np.arange(1, self.frequencies.shape[1] + 1)
        return xr.Dataset(
            {
                "frequency": (("speed", "mode"), self.frequencies, {"units": "Hz"}),
                "damping_ratio": (("speed", "mode"), self.damping_ratios, {"units": "1"}),
                "tracking_mac": (("speed", "mode"), self.tracking_mac, {"units": "1"}),
                "rpm": ("speed", self.rpm, {"units": "rpm"}),
            },
            coords={"speed": ("speed", self.speeds, {"units": "rad/s"}), "mode": mode},
        )

    def plot(self, orders=(), pulses: int = 1, ax=None):
        """Campbell diagram (frequency vs rpm) with excitation lines; returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(layout="constrained")
        for k in range(self.frequencies.shape[1]):
            ax.plot(self.rpm, self.frequencies[:, k], label=f"mode {k + 1}")
        for o in np.atleast_1d(orders):
            ax.plot(self.rpm, pulses * o * self.speeds / (2 * np.pi), "k--", lw=0.8)
        ax.set_xlabel("speed [rpm]")
        ax.set_ylabel("frequency [Hz]")
        ax.set_ylim(bottom=0)
        return ax


def campbell(system: MechanicalSystem, speeds_rad_s, n_modes: int, *, sigma: float = 0.0,
             kind: str = "auto", extra_modes: int = 4, keep_shapes: bool = False,
             method: str = "auto") -> CampbellResult:
    """Campbell diagram: modes of ``system`` at each spin speed, tracked by MAC.

    Parameters
    ----------
    system : MechanicalSystem
        System with :class:`~fricdamp.structure.system.RotationTerms` (gyroscopic matrix,
        spin softening, stress stiffening); without them the diagram is flat.
    speeds_rad_s : array_like, shape (n_speeds,)
        Spin speeds [rad/s], in the order the branches are followed (monotone, finely
        enough spaced that shapes change little between neighbours).
    n_modes : int
        Number of branches followed.
    sigma : float
        Frequency [Hz] around which modes are sought.
    kind : {"auto", "undamped", "damped"}
        As in :func:`modes`; ``auto`` uses complex modes at every speed when the system has
        a gyroscopic matrix.
    extra_modes : int
        Candidates computed beyond ``n_modes`` at each speed, so a branch leaving the lowest
        ``n_modes`` is still found.
    keep_shapes : bool
        Store the tracked shapes in the result.

    Returns
    -------
    CampbellResult

    Notes
    -----
    At each speed the candidate modes are assigned one-to-one to the branches by
    minimising ``sum (1 - MAC) + 1e-3 |f - f_prev| / f_ref`` (Hungarian algorithm); the
    frequency term only breaks ties (e.g. a double mode splitting).
    """
    from scipy.optimize import linear_sum_assignment

    if not isinstance(system, MechanicalSystem):
        raise ModelError(f"system must be a MechanicalSystem, got {type(system).__name__}")
    speeds = np.asarray(speeds_rad_s, float).reshape(-1)
    if speeds.size == 0 or not np.all(np.isfinite(speeds)):
        raise ModelError("speeds_rad_s must be a non-empty finite sequence of spin speeds "
                         "[rad/s]")
    n = system.n_dof
    n_modes = _check_int("n_modes", n_modes, 1, n)
    extra = _check_int("extra_modes", extra_modes, 0)
    n_cand = min(n, n_modes + extra)
    if kind not in KINDS:
        raise ModelError(f"kind must be one of {KINDS}, got {kind!r}")
    if kind == "auto":
        gyro = system.rotation is not None and system.rotation.gyroscopic is not None
        kind = "damped" if gyro or _asym(system.D) > 1e-12 else "undamped"
    ns = speeds.size
    F = np.zeros((ns, n_modes))
    Z = np.zeros((ns, n_modes))
    L = np.zeros((ns, n_modes), complex)
    T = np.ones((ns, n_modes))
    S = np.zeros((ns, n, n_modes), complex) if keep_shapes else None
    prev_shapes = prev_f = None
    for i, w in enumerate(speeds):
        res = modes(system, n_cand, sigma=sigma, kind=kind, speed=float(w), method=method)
        if prev_shapes is None:
            sel = np.arange(n_modes)
        else:
            Mac = mac(prev_shapes, res.shapes)
            fref = max(float(np.max(prev_f)), 1e-300)
            cost = (1.0 - Mac) + 1e-3 * np.abs(res.frequencies[None, :] - prev_f[:, None]) / fref
            rows, cols = linear_sum_assignment(cost)
            sel = cols[np.argsort(rows)]
            T[i] = Mac[np.arange(n_modes), sel]
        F[i] = res.frequencies[sel]
        Z[i] = res.damping_ratios[sel]
        L[i] = res.eigenvalues[sel]
        prev_shapes = res.shapes[:, sel]
        prev_f = F[i]
        if S is not None:
            S[i] = prev_shapes
    return CampbellResult(speeds=speeds, frequencies=F, damping_ratios=Z, eigenvalues=L,
                          tracking_mac=T, shapes=S)


def critical_speeds(frequencies_hz, orders, pulses=1) -> np.ndarray:
    """Critical speeds [rpm] ``s = 60 f_R / (p o)`` of paper 003 (1).

    Parameters
    ----------
    frequencies_hz : array_like
        Resonance frequencies ``f_R`` [Hz], >= 0.
    orders : array_like of int
        Order numbers ``o`` >= 1 (harmonic of the pulse train / engine order).
    pulses : array_like of int
        Pulses per revolution ``p`` >= 1 (003: eight electromagnet pulses, ``p = 8``).

    Returns
    -------
    ndarray
        Speeds [rpm], broadcast over the three arguments.

    Examples
    --------
    >>> float(np.round(critical_speeds(44.53, 1, 8), 2))  # 003 Table 2, test 1: 334 rpm
    333.98
    """
    f = np.asarray(frequencies_hz, float)
    if not np.all(np.isfinite(f)) or np.any(f < 0):
        raise ModelError(f"frequencies_hz must be finite and >= 0 Hz, got {frequencies_hz!r}")
    o = np.asarray(orders)
    p = np.asarray(pulses)
    for name, a in (("orders", o), ("pulses", p)):
        af = np.asarray(a, float)
        if not np.all(np.isfinite(af)) or np.any(af < 1) or np.any(af != np.round(af)):
            raise ModelError(f"{name} must be integers >= 1, got {a.tolist()!r}")
    return 60.0 * f / (p.astype(float) * o.astype(float))


__all__ = [
    "CampbellResult",
    "Crossing",
    "ModalResult",
    "campbell",
    "critical_speeds",
    "mac",
    "modes",
    "whirl_direction",
]
