"""MechanicalSystem: ``M q'' + D q' + K q + sum_c P_c^T f_c(P_c q, P_c q') = F_static + F(t)``.

Matrices may be dense numpy arrays or scipy sparse matrices (n x n). Contact elements map
the DOFs to local relative displacements through constant projection matrices and carry a
contact law (:mod:`fricdamp.contact`). Rotation terms are functions of the spin speed and
are turned into a plain system at one speed with :meth:`MechanicalSystem.at_speed`.
Everything a solver needs is derivable from this object; solvers do not know which paper a
model comes from.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fricdamp.contact.base import ContactLaw
from fricdamp.errors import ModelError

Matrix = np.ndarray | sp.spmatrix | sp.sparray


def _as_matrix(name: str, A, n: int | None) -> Matrix:
    if sp.issparse(A):
        A = sp.csr_matrix(A, dtype=float)
        data = A.data
    else:
        try:
            A = np.array(A, dtype=float)
        except (TypeError, ValueError) as exc:
            raise ModelError(f"{name} must be a numeric matrix") from exc
        if A.ndim == 0:
            A = A.reshape(1, 1)
        data = A
    if A.ndim != 2 or A.shape[0] != A.shape[1]:
        raise ModelError(f"{name} must be a square matrix, got shape {A.shape}")
    if n is not None and A.shape[0] != n:
        raise ModelError(f"{name} must be {n} x {n} like the mass matrix, got {A.shape}")
    if not np.all(np.isfinite(data)):
        raise ModelError(f"{name} must be finite (no NaN or inf)")
    return A


def _asymmetry(A: Matrix) -> float:
    scale = abs(A).max() if A.shape[0] else 0.0
    if scale == 0:
        return 0.0
    return float(abs(A - A.T).max() / scale)


def _check_mass(M: Matrix) -> None:
    if _asymmetry(M) > 1e-10:
        raise ModelError("mass matrix M must be symmetric (|M - M^T| / |M| <= 1e-10)")
    diag = M.diagonal()
    if np.any(diag <= 0):
        i = int(np.argmin(diag))
        raise ModelError(
            f"mass matrix M must be positive definite: its diagonal entry at DOF {i + 1} "
            f"(counting from 1) is {diag[i]:g} kg (every DOF needs mass > 0)"
        )
    from threadpoolctl import threadpool_limits

    if sp.issparse(M):
        # LU without row pivoting in symmetric mode: for a symmetric matrix the pivots are
        # those of LDL^T, all > 0 iff M is positive definite.
        try:
            lu = spla.splu(sp.csc_matrix(M), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                           options={"SymmetricMode": True})
            pivots = lu.U.diagonal()
        except RuntimeError:
            pivots = np.array([0.0])
        if not np.all(pivots > 0):
            raise ModelError("mass matrix M must be positive definite (it is singular or "
                             f"indefinite: smallest pivot {pivots.min():.3g})")
        return
    with threadpool_limits(limits=1, user_api="blas"):
        try:
            np.linalg.cholesky(M)
        except np.linalg.LinAlgError:
            lam = np.linalg.eigvalsh(M)
            raise ModelError(
                "mass matrix M must be positive definite (it is singular or indefinite: "
                f"smallest eigenvalue {lam[0]:.3g})"
            ) from None


def _matrix_kind(A) -> str:
    return f"sparse (nnz {A.nnz})" if sp.issparse(A) else "dense"


@dataclass(frozen=True, repr=False)
class ContactElement:
    """Contacts sharing one law, attached to the structure through a projection.

    Parameters
    ----------
    law : ContactLaw
        The law with ``n_contacts`` contacts of ``n_dir`` directions each.
    projection : array_like or sparse, shape (n_contacts * n_dir, n_dof)
        ``u = (projection @ q).reshape(n_contacts, n_dir)``: row ``c * n_dir + d`` gives the
        relative displacement of contact c in local direction d (for a 3D element
        d = 0 normal, 1 and 2 tangential).
    name : str
        Label used in results and plots.
    """

    law: ContactLaw
    projection: Matrix
    name: str = "contact"

    def __post_init__(self):
        if not isinstance(self.law, ContactLaw):
            raise ModelError(f"contact {self.name!r}: law must be a ContactLaw, got {self.law!r}")
        P = self.projection
        P = sp.csr_matrix(P, dtype=float) if sp.issparse(P) else np.atleast_2d(
            np.asarray(P, dtype=float))
        rows = self.law.n_contacts * self.law.n_dir
        if P.shape[0] != rows:
            raise ModelError(
                f"contact {self.name!r}: projection must have n_contacts * n_dir = {rows} rows, "
                f"got shape {P.shape}"
            )
        object.__setattr__(self, "projection", P)

    def __repr__(self) -> str:
        return (f"ContactElement({self.name!r}: {type(self.law).__name__}, "
                f"{self.n_contacts} contact(s) x {self.n_dir} direction(s), projection "
                f"{self.projection.shape[0]} x {self.projection.shape[1]} "
                f"{_matrix_kind(self.projection)})")

    @property
    def n_contacts(self) -> int:
        return self.law.n_contacts

    @property
    def n_dir(self) -> int:
        return self.law.n_dir

    def relative(self, q: np.ndarray) -> np.ndarray:
        """Local relative displacements (or velocities), shape (n_contacts, n_dir)."""
        return np.asarray(self.projection @ q).reshape(self.n_contacts, self.n_dir)

    def to_dofs(self, force: np.ndarray) -> np.ndarray:
        """Generalised force ``P^T f`` on the DOFs, shape (n_dof,)."""
        return np.asarray(self.projection.T @ np.asarray(force).reshape(-1)).ravel()


@dataclass(frozen=True, repr=False)
class HarmonicLoad:
    """Harmonic load ``F(t) = Re(amplitude * exp(i * harmonic * omega * t))`` [N].

    ``amplitude`` is complex (n_dof,): real part the cosine, minus the imaginary part the sine
    component. For a travelling wave on a cyclic assembly give the phases in ``amplitude``.
    ``omega`` [rad/s] is needed in the time domain only: harmonic balance
    (``frequency_response``, ``harmonic_balance``) replaces it by the solver's frequency, so
    it may be left out there (None); evaluating a load without it raises a ModelError.
    """

    amplitude: np.ndarray
    omega: float | None = None
    harmonic: int = 1

    def __post_init__(self):
        a = np.asarray(self.amplitude, dtype=complex).ravel()
        if not np.all(np.isfinite(a)):
            raise ModelError("HarmonicLoad.amplitude must be finite")
        if self.omega is not None:
            if not np.isfinite(self.omega) or self.omega < 0:
                raise ModelError(f"HarmonicLoad.omega must be >= 0 rad/s, got {self.omega!r}")
            object.__setattr__(self, "omega", float(self.omega))
        if int(self.harmonic) != self.harmonic or self.harmonic < 0:
            raise ModelError(f"HarmonicLoad.harmonic must be an integer >= 0, got {self.harmonic}")
        object.__setattr__(self, "amplitude", a)

    def __call__(self, t: float) -> np.ndarray:
        if self.omega is None:
            raise ModelError("HarmonicLoad.omega is not set: give its frequency in rad/s "
                             "(HarmonicLoad(amplitude, omega) or load.with_omega(omega)) for "
                             "a time-domain run; harmonic balance does not need it")
        return np.real(self.amplitude * np.exp(1j * self.harmonic * self.omega * t))

    def __repr__(self) -> str:
        w = "None" if self.omega is None else f"{self.omega:.6g}"
        return (f"HarmonicLoad(n_dof={self.amplitude.size}, max |amplitude|="
                f"{float(np.max(np.abs(self.amplitude), initial=0.0)):.4g} N, omega={w} rad/s, "
                f"harmonic={self.harmonic})")

    def with_omega(self, omega: float) -> HarmonicLoad:
        return replace(self, omega=omega)


@dataclass(frozen=True, repr=False)
class TimeLoad:
    """Arbitrary load ``F(t) = shape * func(t)`` [N]: ``shape`` (n_dof,), ``func`` scalar."""

    shape: np.ndarray
    func: Callable[[float], float]

    def __repr__(self) -> str:
        name = getattr(self.func, "__name__", type(self.func).__name__)
        return (f"TimeLoad(n_dof={self.shape.size}, max |shape|="
                f"{float(np.max(np.abs(self.shape), initial=0.0)):.4g} N, func={name})")

    def __post_init__(self):
        object.__setattr__(self, "shape", np.asarray(self.shape, dtype=float).ravel())

    def __call__(self, t: float) -> np.ndarray:
        return self.shape * float(self.func(t))


@dataclass(frozen=True)
class RotationTerms:
    """Speed-dependent terms of a rotating structure at spin speed Omega [rad/s].

    ``D(Omega) = D + Omega * gyroscopic``,
    ``K(Omega) = K + Omega**2 * (stress_stiffening - spin_softening)``,
    ``F_static(Omega) = F_static + Omega**2 * centrifugal_load``.
    Any term may be None. Matrices are n x n, the load (n_dof,).
    """

    gyroscopic: Matrix | None = None
    spin_softening: Matrix | None = None
    stress_stiffening: Matrix | None = None
    centrifugal_load: np.ndarray | None = None


@dataclass(frozen=True, repr=False)
class MechanicalSystem:
    """Linear structure with friction contacts.

    Parameters
    ----------
    M, D, K : array_like or sparse, shape (n_dof, n_dof)
        Mass [kg], viscous damping [N s/m] and stiffness [N/m] matrices (in the DOFs' own
        units). M must be symmetric positive definite. ``D`` defaults to zero.
    contacts : sequence of ContactElement
        Friction/contact elements.
    static_load : array_like, shape (n_dof,), optional
        Constant load [N] (preload, centrifugal force, ...).
    loads : sequence of HarmonicLoad or TimeLoad
        Time-dependent excitation; summed.
    rotation : RotationTerms, optional
        Speed-dependent terms; use :meth:`at_speed` to evaluate them.
    dof_names : sequence of str, optional
        Labels of the DOFs for results and plots.
    """

    M: Matrix
    K: Matrix
    D: Matrix | None = None
    contacts: tuple[ContactElement, ...] = ()
    static_load: np.ndarray | None = None
    loads: tuple[HarmonicLoad | TimeLoad, ...] = ()
    rotation: RotationTerms | None = None
    dof_names: tuple[str, ...] | None = None
    name: str = "system"
    meta: dict = field(default_factory=dict, compare=False)

    def __post_init__(self):
        M = _as_matrix("M", self.M, None)
        n = M.shape[0]
        if n == 0:
            raise ModelError("the system must have at least one DOF (M is 0 x 0)")
        _check_mass(M)
        K = _as_matrix("K", self.K, n)
        D = _as_matrix("D", self.D, n) if self.D is not None else (
            sp.csr_matrix((n, n)) if sp.issparse(M) else np.zeros((n, n)))
        object.__setattr__(self, "M", M)
        object.__setattr__(self, "K", K)
        object.__setattr__(self, "D", D)
        contacts = tuple(self.contacts)
        for c in contacts:
            if not isinstance(c, ContactElement):
                raise ModelError(f"contacts must be ContactElement objects, got {c!r}")
            if c.projection.shape[1] != n:
                raise ModelError(
                    f"contact {c.name!r}: projection has {c.projection.shape[1]} columns, the "
                    f"system has {n} DOFs"
                )
        object.__setattr__(self, "contacts", contacts)
        f0 = np.zeros(n) if self.static_load is None else np.asarray(self.static_load, float)
        if f0.shape != (n,) or not np.all(np.isfinite(f0)):
            raise ModelError(f"static_load must be a finite vector of length {n}")
        object.__setattr__(self, "static_load", f0)
        loads = tuple(self.loads)
        for ld in loads:
            size = ld.amplitude.size if isinstance(ld, HarmonicLoad) else ld.shape.size
            if size != n:
                raise ModelError(f"load {ld!r} has {size} entries, the system has {n} DOFs")
        object.__setattr__(self, "loads", loads)
        if self.dof_names is not None:
            names = tuple(str(s) for s in self.dof_names)
            if len(names) != n:
                raise ModelError(f"dof_names has {len(names)} names for {n} DOFs")
            object.__setattr__(self, "dof_names", names)

    def __repr__(self) -> str:
        names = self.names
        shown = ", ".join(names[:4]) + (", ..." if len(names) > 4 else "")
        lines = [f"MechanicalSystem {self.name!r}: {self.n_dof} DOFs ({shown}); M, D, K "
                 f"{_matrix_kind(self.K)}"]
        if self.contacts:
            lines.append("  contacts: " + "; ".join(
                f"{c.name} ({type(c.law).__name__}, {c.n_contacts} x {c.n_dir})"
                for c in self.contacts[:4]) + ("; ..." if len(self.contacts) > 4 else ""))
        if self.loads:
            n_h = sum(isinstance(ld, HarmonicLoad) for ld in self.loads)
            lines.append(f"  loads: {n_h} harmonic, {len(self.loads) - n_h} time")
        if np.any(self.static_load):
            lines.append(f"  static load: max |F| = {np.max(np.abs(self.static_load)):.4g} N")
        if self.rotation is not None:
            terms = [k for k in ("gyroscopic", "spin_softening", "stress_stiffening",
                                 "centrifugal_load") if getattr(self.rotation, k) is not None]
            lines.append("  rotation terms: " + (", ".join(terms) or "none"))
        return "\n".join(lines)

    # ----------------------------------------------------------------- properties
    @property
    def n_dof(self) -> int:
        return self.M.shape[0]

    @property
    def is_sparse(self) -> bool:
        return sp.issparse(self.M)

    @property
    def names(self) -> tuple[str, ...]:
        return self.dof_names or tuple(f"q{i + 1}" for i in range(self.n_dof))

    # ----------------------------------------------------------------- evaluation
    def external_force(self, t: float) -> np.ndarray:
        """Static plus time-dependent load at time t [s], shape (n_dof,)."""
        f = self.static_load.copy()
        for ld in self.loads:
            f += ld(t)
        return f

    def contact_force(self, q: np.ndarray, states: Sequence[np.ndarray],
                      v: np.ndarray | None = None) -> np.ndarray:
        """Generalised contact force ``sum P^T f`` at q for given states (not committed)."""
        out = np.zeros(self.n_dof)
        for c, st in zip(self.contacts, states, strict=True):
            vv = None if v is None else c.relative(v)
            out += c.to_dofs(c.law.step(st, c.relative(q), vv).force)
        return out

    def kinetic_energy(self, v: np.ndarray) -> float:
        return 0.5 * float(v @ (self.M @ v))

    def strain_energy(self, q: np.ndarray) -> float:
        """Strain energy of the linear part ``q^T K q / 2`` [J] (K symmetrised)."""
        return 0.5 * float(q @ (self.K @ q))

    def dense(self) -> MechanicalSystem:
        """Copy with dense matrices."""
        def d(A):
            return A.toarray() if sp.issparse(A) else A
        return replace(self, M=d(self.M), D=d(self.D), K=d(self.K))

    # ----------------------------------------------------------------- copies
    def with_contacts(self, *contacts: ContactElement) -> MechanicalSystem:
        return replace(self, contacts=tuple(contacts))

    def with_loads(self, *loads) -> MechanicalSystem:
        return replace(self, loads=tuple(loads))

    def with_static_load(self, static_load) -> MechanicalSystem:
        return replace(self, static_load=np.asarray(static_load, float))

    def at_speed(self, omega: float) -> MechanicalSystem:
        """The system at spin speed ``omega`` [rad/s] with rotation terms evaluated."""
        if self.rotation is None:
            return self
        r = self.rotation
        D, K, f0 = self.D, self.K, self.static_load
        if r.gyroscopic is not None:
            D = D + omega * _as_matrix("gyroscopic", r.gyroscopic, self.n_dof)
        if r.stress_stiffening is not None:
            K = K + omega**2 * _as_matrix("stress_stiffening", r.stress_stiffening, self.n_dof)
        if r.spin_softening is not None:
            K = K - omega**2 * _as_matrix("spin_softening", r.spin_softening, self.n_dof)
        if r.centrifugal_load is not None:
            f0 = f0 + omega**2 * np.asarray(r.centrifugal_load, float)
        return replace(self, D=D, K=K, static_load=f0, rotation=None,
                       meta={**self.meta, "spin_speed_rad_s": omega})

    def initial_states(self) -> list[np.ndarray]:
        """Virgin states of all contact elements."""
        return [c.law.initial_state() for c in self.contacts]
