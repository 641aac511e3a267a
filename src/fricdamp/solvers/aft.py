"""Alternating frequency-time (AFT) evaluation of contact forces for harmonic balance.

A periodic signal of fundamental angular frequency Omega is represented by the real
coefficients ``c = [c0, a1, b1, a2, b2, ..., aH, bH]`` (``n_coeff = 2H + 1``)::

    x(tau) = c0 + sum_k a_k cos(k tau) + b_k sin(k tau),     tau = Omega t.

The AFT step samples the contact displacements at ``N`` equally spaced instants of one
period (inverse DFT), marches each contact law over the period until its hysteretic state
is periodic (:meth:`fricdamp.contact.base.ContactLaw.periodic_response`) and projects the
force samples back onto the harmonics (DFT). The Jacobian follows from the law's exact
sensitivity of the periodic force samples to the displacement coefficients, projected by
the same DFT, so it is the exact derivative of the discrete residual. All contacts of a
contact element go through one call (vectorised; no per-contact Python loop); a law with a
compiled AFT step (:meth:`fricdamp.contact.base.ContactLaw.harmonic_response`, e.g. Jenkins)
does the synthesis, the march and both projections in that call.

With ``N > 2H`` the trapezoidal rule is exact for trigonometric polynomials of degree < N,
which makes the discrete work identities used by :func:`cycle_work` exact.

References
----------
Cameron & Griffin (1989), J. Appl. Mech. 56, 149-154 (the AFT method).
Krack & Gross (2019), *Harmonic Balance for Nonlinear Vibration Problems*, Springer, ch. 2-3.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from fricdamp.errors import ModelError
from fricdamp.structure.system import ContactElement

__all__ = ["HarmonicBasis", "AFTResult", "aft", "cycle_work", "harmonic_numbers"]


def harmonic_numbers(harmonics: int) -> np.ndarray:
    """Harmonic index of each real coefficient: ``[0, 1, 1, 2, 2, ..., H, H]``."""
    return np.concatenate([[0], np.repeat(np.arange(1, harmonics + 1), 2)]).astype(int)


@dataclass(frozen=True, eq=False)
class HarmonicBasis:
    """Sampling and projection matrices of the real harmonic representation.

    Attributes
    ----------
    harmonics : int
        Highest harmonic H.
    samples : int
        Time samples N per period (N >= 2H + 1).
    tau : ndarray, shape (N,)
        Sample phases ``2 pi n / N`` [rad].
    synthesis : ndarray, shape (N, 2H+1)
        Inverse DFT: ``x(tau_n) = synthesis @ c``.
    derivative : ndarray, shape (N, 2H+1)
        ``dx/dtau (tau_n) = derivative @ c``; the velocity is Omega times this.
    analysis : ndarray, shape (2H+1, N)
        DFT: ``c = analysis @ x(tau_n)`` for a trigonometric polynomial of degree H.
    d_dtau : ndarray, shape (2H+1, 2H+1)
        Coefficients of dx/dtau from those of x.
    """

    harmonics: int
    samples: int
    tau: np.ndarray
    synthesis: np.ndarray
    derivative: np.ndarray
    analysis: np.ndarray
    d_dtau: np.ndarray

    @classmethod
    def create(cls, harmonics: int, samples: int | None = None) -> HarmonicBasis:
        """Basis for ``harmonics`` H >= 1 and ``samples`` N >= 2H + 1 (default below).

        The default N is the power of two >= 16 H (128 for H = 7), enough to resolve the
        stick-slip transitions of a Jenkins element to well under 1 % of the force.
        """
        if int(harmonics) != harmonics or harmonics < 1:
            raise ModelError(f"harmonics must be an integer >= 1, got {harmonics!r}")
        H = int(harmonics)
        if samples is None:
            samples = int(2 ** np.ceil(np.log2(max(16 * H, 16))))
        if int(samples) != samples or samples < 2 * H + 1:
            raise ModelError(f"samples must be an integer >= 2 * harmonics + 1 = {2 * H + 1} "
                             f"(Nyquist), got {samples!r}")
        N = int(samples)
        cached = _BASES.get((H, N))
        if cached is not None:      # immutable (read-only arrays): shared by every analysis
            return cached
        tau = 2.0 * np.pi * np.arange(N) / N
        k = np.arange(1, H + 1)
        kt = np.outer(tau, k)
        syn = np.empty((N, 2 * H + 1))
        der = np.empty((N, 2 * H + 1))
        syn[:, 0] = 1.0
        der[:, 0] = 0.0
        syn[:, 1::2] = np.cos(kt)
        syn[:, 2::2] = np.sin(kt)
        der[:, 1::2] = -k * np.sin(kt)
        der[:, 2::2] = k * np.cos(kt)
        ana = np.ascontiguousarray(syn.T) * (2.0 / N)
        ana[0] = 1.0 / N
        dd = np.zeros((2 * H + 1, 2 * H + 1))
        dd[1::2, 2::2] = np.diag(k)    # a'_k = k b_k
        dd[2::2, 1::2] = -np.diag(k)   # b'_k = -k a_k
        for a in (tau, syn, der, ana, dd):
            a.setflags(write=False)
        basis = cls(H, N, tau, syn, der, ana, dd)
        if len(_BASES) < 64:
            _BASES[(H, N)] = basis
        return basis

    @property
    def n_coeff(self) -> int:
        """Number of real coefficients per signal, 2H + 1."""
        return 2 * self.harmonics + 1

    @property
    def harmonic_number(self) -> np.ndarray:
        """Harmonic index of each coefficient, shape (2H+1,)."""
        return harmonic_numbers(self.harmonics)

    def to_time(self, coeffs: np.ndarray, n_samples: int | None = None) -> np.ndarray:
        """Time samples of signals ``coeffs`` (..., 2H+1) -> (n_samples, ...) over one period.

        ``n_samples`` defaults to N; a finer grid is synthesised exactly (band-limited).
        """
        c = np.asarray(coeffs, dtype=float)
        if n_samples is None or n_samples == self.samples:
            S = self.synthesis
        else:
            S = _synthesis(self.harmonics, int(n_samples))
        out = S @ c.reshape(-1, self.n_coeff).T
        return out.reshape((S.shape[0],) + c.shape[:-1])


#: Bases by (H, N): the prefix sums and caches keyed on their arrays then hit by identity.
_BASES: dict[tuple[int, int], HarmonicBasis] = {}


def _synthesis(H: int, N: int) -> np.ndarray:
    tau = 2.0 * np.pi * np.arange(N) / N
    kt = np.outer(tau, np.arange(1, H + 1))
    S = np.empty((N, 2 * H + 1))
    S[:, 0] = 1.0
    S[:, 1::2] = np.cos(kt)
    S[:, 2::2] = np.sin(kt)
    return S


@dataclass(frozen=True, eq=False)
class AFTResult:
    """Harmonic contact forces from one AFT evaluation.

    Rows are the local contact directions of all contact elements stacked in order
    (element e, contact c, direction d), ``n_rows = sum_e n_contacts_e * n_dir_e``.

    Attributes
    ----------
    force : ndarray, shape (n_rows, 2H+1)
        Harmonic coefficients of the contact forces [N].
    jacobian : list of ndarray, each shape (n_contacts_e, n_dir_e (2H+1), n_dir_e (2H+1))
        Per element, the blocks d force / d displacement coefficients of each contact
        (row and column index ``d * (2H+1) + h``); None if not requested.
    d_omega : ndarray or None, shape (n_rows, 2H+1)
        d force / d Omega at fixed displacement coefficients (non-zero only for
        velocity-dependent laws); None if every law is rate independent.
    u_time, f_time : ndarray, shape (N, n_rows)
        Displacement and force samples over the periodic period.
    converged : bool
        Every law reached a periodic state.
    periods : int
        Largest number of periods marched.
    """

    force: np.ndarray
    jacobian: list[np.ndarray] | None
    d_omega: np.ndarray | None
    u_time: np.ndarray
    f_time: np.ndarray
    converged: bool
    periods: int


def element_rows(contacts: Sequence[ContactElement]) -> list[slice]:
    """Row slice of each contact element in the stacked relative-displacement vector."""
    out, r = [], 0
    for c in contacts:
        n = c.n_contacts * c.n_dir
        out.append(slice(r, r + n))
        r += n
    return out


def aft(contacts: Sequence[ContactElement], u_coeffs: np.ndarray, omega: float,
        basis: HarmonicBasis, *, jacobian: bool = True, states=None,
        max_periods: int = 50) -> AFTResult:
    """Harmonic contact forces and their Jacobian by the AFT method.

    Parameters
    ----------
    contacts : sequence of ContactElement
        The system's contact elements.
    u_coeffs : ndarray, shape (n_rows, 2H+1)
        Harmonic coefficients of the local relative displacements [m] of all contact rows.
    omega : float
        Fundamental angular frequency [rad/s] (enters through the velocities only).
    basis : HarmonicBasis
    jacobian : bool
        Also return the exact (or, for laws without a specialised method, finite
        difference) Jacobian blocks.
    states : sequence of ndarray, optional
        Start state of each element's periodic march (virgin states by default).
    max_periods : int
        Largest number of periods marched to reach a periodic state.

    Returns
    -------
    AFTResult
    """
    u_coeffs = np.asarray(u_coeffs, dtype=float)
    n_h = basis.n_coeff
    N = basis.samples
    n_rows = u_coeffs.shape[0]
    u_time = np.empty((N, n_rows))
    f_time = np.empty((N, n_rows))
    force = np.empty((n_rows, n_h))
    blocks = [] if jacobian else None
    d_omega = None
    conv, periods = True, 0
    for e, (c, rows) in enumerate(zip(contacts, element_rows(contacts), strict=True)):
        nc, nd = c.n_contacts, c.n_dir
        law = c.law
        st = None if states is None else states[e]
        if not law.velocity_dependent:
            # a law with a compiled AFT step (synthesis, march, projections in one call)
            hr = law.harmonic_response(u_coeffs[rows].reshape(nc, nd, n_h), basis.synthesis,
                                       basis.analysis, jacobian=jacobian, state=st,
                                       max_periods=max_periods)
            if hr is not None:
                u_time[:, rows] = hr.u_time.reshape(N, nc * nd)
                f_time[:, rows] = hr.force_time.reshape(N, nc * nd)
                force[rows] = hr.force.reshape(nc * nd, n_h)
                conv = conv and hr.converged
                periods = max(periods, hr.periods)
                if jacobian:
                    blocks.append(hr.jacobian)
                continue
        u_rows = basis.synthesis @ u_coeffs[rows].T                # (N, nc * nd)
        u_time[:, rows] = u_rows
        u3 = u_rows.reshape(N, nc, nd)
        v3 = None
        vb = None
        if law.velocity_dependent:
            v3 = (omega * (basis.derivative @ u_coeffs[rows].T)).reshape(N, nc, nd)
            vb = omega * basis.derivative
        res = law.periodic_response(u3, v3, basis=basis.synthesis if jacobian else None,
                                    velocity_basis=vb, state=st, max_periods=max_periods)
        f_time[:, rows] = res.force.reshape(N, nc * nd)
        force[rows] = (basis.analysis @ f_time[:, rows]).T
        conv = conv and res.converged
        periods = max(periods, res.periods)
        if jacobian:
            jt = res.jacobian                                   # (N, nc, nd, nd, n_h)
            J = (basis.analysis @ jt.reshape(N, -1)).reshape(n_h, nc, nd, nd, n_h)
            blocks.append(np.ascontiguousarray(
                J.transpose(1, 2, 0, 3, 4).reshape(nc, nd * n_h, nd * n_h)))
        if law.velocity_dependent and omega > 0:
            # d f / d Omega at fixed coefficients: v = Omega * (dx/dtau) scales with Omega
            delta = 1e-7
            rp = law.periodic_response(u3, v3 * (1.0 + delta), state=st,
                                       max_periods=max_periods)
            df = (rp.force - res.force).reshape(N, nc * nd) / (delta * omega)
            if d_omega is None:
                d_omega = np.zeros((n_rows, n_h))
            d_omega[rows] = (basis.analysis @ df).T
    return AFTResult(force, blocks, d_omega, u_time, f_time, conv, periods)


def cycle_work(x_coeffs: np.ndarray, f_coeffs: np.ndarray) -> np.ndarray:
    """Work ``oint f dx`` [J] over one period of signals given by their coefficients.

    ``W = pi sum_k k (A_k b_k - B_k a_k)`` with ``x = sum a_k cos + b_k sin`` and
    ``f = sum A_k cos + B_k sin``; it equals the trapezoidal sum over the N AFT samples
    exactly (N > 2H), i.e. the loop area of the sampled periodic force.

    Parameters
    ----------
    x_coeffs, f_coeffs : ndarray, shape (..., 2H+1)

    Returns
    -------
    ndarray, shape (...)
    """
    x = np.asarray(x_coeffs, dtype=float)
    f = np.asarray(f_coeffs, dtype=float)
    H = (x.shape[-1] - 1) // 2
    k = np.arange(1, H + 1)
    return np.pi * np.sum(k * (f[..., 1::2] * x[..., 2::2] - f[..., 2::2] * x[..., 1::2]),
                          axis=-1)
