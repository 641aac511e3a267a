"""The Newmark / HHT-alpha step shared by every transient solver of fricdamp.

One scheme, three strategies that differ only in how they solve the linear part of a step:

* ``direct`` (:func:`fricdamp.solvers.timestep.simulate`): any contact law, any damping, time-
  dependent loads; the effective stiffness ``S`` factorised once, Python time loop;
* ``modal`` (:func:`fricdamp.solvers.fast_transient.integrate_contact3d`, or ``simulate(...,
  strategy="modal")``): Contact3D laws and damping diagonal in the undamped modes, ``S``
  diagonal in modal coordinates, the whole loop compiled;
* ``reduced`` (:func:`fricdamp.solvers.modal_transient.integrate_modal`): the same modal form
  on a truncated (possibly cyclic) basis with thousands of contact rows, adaptive
  step bisection and an active-set Newton.

The discrete equations (Hilber, Hughes & Taylor 1977), ``alpha`` in [-1/3, 0],
``beta = (1 - alpha)^2 / 4``, ``gamma = 1/2 - alpha`` (``alpha = 0``: Newmark's average
acceleration)::

    M a1 + (1 + alpha) [D v1 + K q1 + g(q1)] - alpha [D v0 + K q0 + g(q0)]
        = (1 + alpha) F(t1) - alpha F(t0)
    a1 = c0 (q1 - q0) - c2 v0 - c3 a0,        v1 = v0 + h ((1 - gamma) a0 + gamma a1)

with ``c0 = 1/(beta h^2)``, ``c1 = gamma/(beta h)``, ``c2 = 1/(beta h)``,
``c3 = 1/(2 beta) - 1``, ``c4 = 1 - gamma/beta``, ``c5 = h (1 - gamma/(2 beta))``; the second
relation written for the velocity reads ``v1 = c1 (q1 - q0) + c4 v0 + c5 a0``, so the
effective stiffness of ``q1`` is ``S = c0 M + (1 + alpha)(c1 D + K)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fricdamp.errors import ModelError

__all__ = ["NewmarkScheme", "STRATEGIES"]

STRATEGIES = ("direct", "modal", "auto")


@dataclass(frozen=True)
class NewmarkScheme:
    """Coefficients of one Newmark/HHT step of size ``h``.

    Parameters
    ----------
    h : float
        Time step [s], > 0.
    alpha : float
        HHT parameter in [-1/3, 0]; 0 is Newmark's average acceleration.

    Examples
    --------
    >>> s = NewmarkScheme(1e-3)
    >>> s.beta, s.gamma, s.c0 == 4e6
    (0.25, 0.5, True)
    """

    h: float
    alpha: float = 0.0

    def __post_init__(self):
        if not (np.isfinite(self.h) and self.h > 0):
            raise ModelError(f"dt must be a finite time step > 0 s, got {self.h!r}")
        if not (-1.0 / 3.0 <= self.alpha <= 0.0):
            raise ModelError(f"alpha must lie in [-1/3, 0] for HHT-alpha, got {self.alpha!r}")
        object.__setattr__(self, "h", float(self.h))
        object.__setattr__(self, "alpha", float(self.alpha))

    @property
    def beta(self) -> float:
        return (1.0 - self.alpha) ** 2 / 4.0

    @property
    def gamma(self) -> float:
        return 0.5 - self.alpha

    @property
    def ap(self) -> float:
        """``1 + alpha``: weight of the new state in the HHT balance."""
        return 1.0 + self.alpha

    @property
    def c0(self) -> float:
        return 1.0 / (self.beta * self.h * self.h)

    @property
    def c1(self) -> float:
        return self.gamma / (self.beta * self.h)

    @property
    def c2(self) -> float:
        return 1.0 / (self.beta * self.h)

    @property
    def c3(self) -> float:
        return 1.0 / (2.0 * self.beta) - 1.0

    @property
    def c4(self) -> float:
        return 1.0 - self.gamma / self.beta

    @property
    def c5(self) -> float:
        return self.h * (1.0 - self.gamma / (2.0 * self.beta))

    @property
    def c(self) -> tuple[float, float, float, float, float, float]:
        """``(c0, c1, c2, c3, c4, c5)``."""
        return self.c0, self.c1, self.c2, self.c3, self.c4, self.c5

    @property
    def method(self) -> str:
        """Label stored with results: ``"newmark"`` or ``"hht(alpha=...)"``."""
        return "newmark" if self.alpha == 0 else f"hht(alpha={self.alpha:g})"

    def coefficients(self, t0: float = 0.0) -> np.ndarray:
        """``[h, alpha, gamma, c0, c1, c2, c3, c4, c5, t0]`` for compiled kernels."""
        return np.array([self.h, self.alpha, self.gamma, *self.c, float(t0)])

    def effective(self, mass, damping, stiffness):
        """``S = c0 M + (1 + alpha)(c1 D + K)`` for matrices (dense or sparse) or modal
        diagonals (arrays)."""
        return self.c0 * mass + self.ap * (self.c1 * damping + stiffness)

    def modal_inverse(self, damping, omega2) -> np.ndarray:
        """``1 / S`` of mass-normalised modes (unit mass, modal damping ``damping``
        [1/s], squared circular frequencies ``omega2`` [1/s^2])."""
        return 1.0 / (self.c0 + self.ap * (self.c1 * np.asarray(damping)
                                           + np.asarray(omega2)))

    def acceleration(self, dq, v0, a0):
        """``a1`` from the displacement increment ``dq = q1 - q0``."""
        return self.c0 * dq - self.c2 * v0 - self.c3 * a0

    def velocity(self, v0, a0, a1):
        """``v1 = v0 + h ((1 - gamma) a0 + gamma a1)``."""
        return v0 + self.h * ((1.0 - self.gamma) * a0 + self.gamma * a1)

    def velocity_of(self, dq, v0, a0):
        """``v1 = c1 dq + c4 v0 + c5 a0`` (the same velocity, written for ``q1``: what the
        Newton iteration on the contacts uses for rate-dependent friction)."""
        return self.c1 * dq + self.c4 * v0 + self.c5 * a0

    def period_error(self, omega: float) -> float:
        """Relative period elongation ``T_h / T - 1`` of an undamped mode of circular
        frequency ``omega`` [rad/s] under Newmark's average acceleration (alpha = 0):
        the discrete frequency obeys ``tan(omega_h h / 2) = omega h / 2``, so
        ``T_h / T = x / arctan(x)`` with ``x = omega h / 2``, about ``(omega h)^2 / 12`` for
        small steps. HHT-alpha adds numerical damping and the same phase error to leading
        order."""
        from fricdamp.verdict import newmark_period_error

        return float(newmark_period_error(float(omega) * self.h))
