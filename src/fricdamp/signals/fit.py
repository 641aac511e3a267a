"""Fit a joint model to measured hysteresis loops and/or dissipated energy against amplitude.

"Identification" in paper 002 means finding the parameters of a joint model from its loops.
Three models (all :class:`~fricdamp.contact.base.ContactLaw`, so a fitted law goes straight
into any solver):

``"jenkins"``
    :class:`~fricdamp.contact.jenkins.Jenkins`: ``stiffness`` and ``slip_force``.
``"iwan"``
    :class:`~fricdamp.contact.iwan.Iwan`: Segalman's ``stiffness`` K_T, ``slip_force``
    F_S, ``chi`` and ``beta``.
``"rough"``
    Paper 002's rough rotational joint (:class:`~fricdamp.contact.rough.RoughRotationalJoint`,
    Greenwood-Williamson summits with Cattaneo-Mindlin loops, 002 (11)-(25)), for rotation
    and torque loops, at a known preload and contact geometry.

Reparameterisation of the rough joint
-------------------------------------
Its statistical parameters enter the loops only through three combinations. Every summit
slips fully at ``delta_s = 3 mu N C / (16 a) = mu E* C (z - d) / 4`` (Hertz ``N``, ``a``), which
does not depend on the summit radius R; the preload fixes the separation ``h = d / sigma``
through ``P = (4/3) eta A E* sqrt(R) sigma^(3/2) F_3/2(h)``; the initial stiffness is
``K0 = (8/C) sum(A_cell r^2) eta sqrt(R sigma) F_1/2(h)``. So the summit density eta and
radius R appear only as the product ``eta sqrt(R)`` -- they are not separately identifiable
(the Jacobian in (mu, sigma, eta, R) is singular, see :attr:`FitResult.conditioning`) --
and the fit uses ``mu`` (set by the slip moment ``mu P <r>``), ``K0`` (the slope of the loops'
ends) and ``sigma`` (the spread of the slip displacements: the shape of the micro- to
macro-slip transition). ``eta sqrt(R)``, ``h`` and eta for the assumed R follow.

Objective and confidence intervals
----------------------------------
Loops: each loop is driven twice through the model from the virgin state (the first pass
sets the Masing memory) and the second pass is compared with the measurement, both without
their mean force (an offset is not the joint's); residuals are divided by the loop's force
amplitude so that small and large loops count alike. Energy: ``(E_model(A) - E) / E`` at
each amplitude, the model's symmetric cycle from the virgin state. ``least_squares``
(trust-region reflective) on log parameters (chi and beta linear, bounded), from several
starts. The 95 % intervals come from the Jacobian at the optimum: covariance
``s^2 (J^T J)^-1`` with the residual variance ``s^2``, inflated for the correlation of
successive residuals within a loop (AR(1): effective sample size ``n (1 - r) / (1 + r)``,
``r`` their lag-one correlation), Student's t quantile.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from fricdamp.contact.base import ContactLaw
from fricdamp.errors import ConvergenceError, ModelError, as_finite_array
from fricdamp.results import ResultMixin
from fricdamp.signals.energy import loop_area
from fricdamp.signals.records import Loop, read_fit_input

log = logging.getLogger(__name__)

__all__ = ["MODELS", "FitResult", "Loop", "fit_joint", "read_fit_input", "rough_joint"]

MODELS = ("jenkins", "iwan", "rough")

# ============================================================================ models
_ROUGH_DEFAULTS = {"preload_N": 100.0, "contact_width_m": 0.028, "contact_height_m": 0.018,
                   "summit_radius_m": 50e-6, "youngs_modulus_Pa": 210e9, "poisson_ratio": 0.3,
                   "joint_cells": (14, 9), "height_classes": 24}


class _RoughBuilder:
    """Paper 002's rough joint from (mu, K0, sigma) at a fixed preload and geometry."""

    def __init__(self, fixed: Mapping):
        from fricdamp.contact.mindlin import (
            effective_modulus,
            shear_modulus,
            tangential_compliance,
        )

        unknown = set(fixed) - set(_ROUGH_DEFAULTS)
        if unknown:
            raise ModelError(f"unknown fixed parameter(s) of the rough model {sorted(unknown)}; "
                             f"known: {sorted(_ROUGH_DEFAULTS)}")
        c = dict(_ROUGH_DEFAULTS, **fixed)
        for key in ("preload_N", "contact_width_m", "contact_height_m", "summit_radius_m",
                    "youngs_modulus_Pa"):
            v = float(as_finite_array(key, c[key], ndim=0))
            if v <= 0:
                raise ModelError(f"{key} must be > 0, got {c[key]!r}")
            c[key] = v
        nu = float(as_finite_array("poisson_ratio", c["poisson_ratio"], ndim=0))
        if not 0.0 <= nu < 0.5:
            raise ModelError(f"poisson_ratio must lie in [0, 0.5), got {nu!r}")
        cells = np.asarray(c["joint_cells"])
        if cells.shape != (2,) or np.any(cells < 1) or np.any(cells != np.round(cells)):
            raise ModelError(f"joint_cells must be two integers >= 1, got {c['joint_cells']!r}")
        self.fixed = c
        E = c["youngs_modulus_Pa"]
        g = shear_modulus(E, nu)
        self.E_star = float(effective_modulus(E, nu, E, nu))
        self.compliance = float(tangential_compliance(g, nu, g, nu))
        w, hgt = c["contact_width_m"], c["contact_height_m"]
        nx, ny = int(cells[0]), int(cells[1])
        xc = -0.5 * w + (np.arange(nx) + 0.5) * w / nx
        yc = -0.5 * hgt + (np.arange(ny) + 0.5) * hgt / ny
        r = np.hypot(*np.meshgrid(xc, yc, indexing="ij")).ravel()
        self.area = w * hgt
        self.cell_area = self.area / r.size
        self.sum_r2 = float(np.sum(r * r)) * self.cell_area
        self.mean_r = float(np.mean(r))

    def slip_moment(self, mu):
        return mu * self.fixed["preload_N"] * self.mean_r

    def separation(self, k0, sigma) -> float:
        """h = d / sigma with F_1/2(h) / F_3/2(h) = K0 C E* sigma A / (6 P sum A_cell r^2)."""
        from scipy.optimize import brentq

        from fricdamp.contact.rough import gw_integral

        target = (k0 * self.compliance * self.E_star * sigma * self.area
                  / (6.0 * self.fixed["preload_N"] * self.sum_r2))

        def g(h):
            return math.log(gw_integral(0.5, h) / gw_integral(1.5, h)) - math.log(target)

        lo, hi = -40.0, 30.0
        if not g(lo) < 0 < g(hi):
            raise ModelError(f"initial stiffness {k0:.4g} N m/rad and summit_std {sigma:.4g} m "
                             "cannot be reached by a Greenwood-Williamson contact at this "
                             "preload (the separation leaves [-40, 30] summit_std)")
        return float(brentq(g, lo, hi, xtol=1e-12))

    def stiffness_for(self, h, sigma) -> float:
        """K0 [N m/rad] of the joint whose separation is ``h`` summit_std at ``sigma``."""
        from fricdamp.contact.rough import gw_integral

        ratio = gw_integral(0.5, h) / gw_integral(1.5, h)
        return (ratio * 6.0 * self.fixed["preload_N"] * self.sum_r2
                / (self.compliance * self.E_star * sigma * self.area))

    def eta_sqrt_r(self, sigma, h) -> float:
        from fricdamp.contact.rough import gw_integral

        return self.fixed["preload_N"] / (4.0 / 3.0 * self.E_star * sigma ** 1.5 * self.area
                                          * gw_integral(1.5, h))

    def joint(self, mu, k0, sigma):
        from fricdamp.contact.rough import RoughRotationalJoint

        h = self.separation(k0, sigma)
        rad = self.fixed["summit_radius_m"]
        return self.raw_joint(mu, sigma, self.eta_sqrt_r(sigma, h) / math.sqrt(rad), rad,
                              RoughRotationalJoint)

    def raw_joint(self, mu, sigma, eta, radius, cls=None):
        if cls is None:
            from fricdamp.contact.rough import RoughRotationalJoint as cls
        c = self.fixed
        return cls(summit_density=eta, summit_radius=radius, summit_std=sigma,
                   E_star=self.E_star, compliance=self.compliance, mu=mu,
                   preload=c["preload_N"], width=c["contact_width_m"],
                   height=c["contact_height_m"], n_cells=tuple(int(v) for v in c["joint_cells"]),
                   n_heights=int(c["height_classes"]))


def rough_joint(mu, initial_stiffness, summit_std, **fixed):
    """Paper 002's rough joint with a given slip coefficient, initial stiffness and sigma.

    Parameters
    ----------
    mu : float
        Friction coefficient [-], > 0.
    initial_stiffness : float
        K0, tangent rotational stiffness of the virgin joint [N m/rad], > 0.
    summit_std : float
        sigma, standard deviation of the summit heights [m], > 0.
    **fixed
        ``preload_N`` (100), ``contact_width_m`` (0.028), ``contact_height_m`` (0.018),
        ``summit_radius_m`` (50e-6, only ``eta sqrt(R)`` matters), ``youngs_modulus_Pa``
        (210e9), ``poisson_ratio`` (0.3), ``joint_cells`` ((14, 9)), ``height_classes`` (24).

    Returns
    -------
    RoughRotationalJoint
        With the summit density that gives ``initial_stiffness`` (module docstring).
    """
    for name, v in (("mu", mu), ("initial_stiffness", initial_stiffness),
                    ("summit_std", summit_std)):
        if not float(as_finite_array(name, v, ndim=0)) > 0:
            raise ModelError(f"{name} must be > 0, got {v!r}")
    return _RoughBuilder(fixed).joint(float(mu), float(initial_stiffness), float(summit_std))


@dataclass
class _Spec:
    """A model: parameter names, transforms, bounds, law and energy from theta."""

    name: str
    names: list
    log: list
    bounds: tuple
    law: object          # theta -> ContactLaw
    energy: object       # (theta, amplitudes) -> energies
    starts: list = field(default_factory=list)
    derived: object = None   # theta -> dict of derived quantities


def _symmetric_energy(law, amplitudes, n=400):
    out = []
    ph = 2 * np.pi * np.arange(n) / n
    for a in amplitudes:
        cyc = a * np.cos(ph)
        u = np.concatenate((a * np.sin(np.linspace(0, 0.5 * np.pi, 60)), cyc))
        f, _ = law.march(u[:, None, None])
        out.append(loop_area(cyc, f[-n:, 0, 0]))
    return np.asarray(out)


def _guess(loops, energy):
    """(stiffness, slip force) first guesses from the data."""
    if loops:
        f_max = max(lp.force_amplitude for lp in loops)
        k_rev = []
        for lp in loops:
            x, f = lp.displacement, lp.force
            i = int(np.argmax(x))
            xs, fs = np.roll(x, -i), np.roll(f, -i)
            sel = np.flatnonzero(xs < xs[0] - 0.2 * lp.amplitude)
            m = int(sel[0]) if sel.size else xs.size // 4
            m = max(m, 3)
            k_rev.append(float(np.polyfit(xs[:m], fs[:m], 1)[0]))
        k_rev = [k for k in k_rev if k > 0] or [max(lp.force_amplitude / lp.amplitude
                                                    for lp in loops)]
        return float(np.median(k_rev)), f_max
    a, e, _ = energy
    # gross slip: E ~ 4 F A at the largest amplitude; stiffness from the smallest amplitudes
    f_max = float(e[-1] / (4 * a[-1]))
    return 10.0 * f_max / float(a[0]), f_max


def _make_spec(model, rotational, loops, energy, fixed, initial):
    from fricdamp.contact.iwan import Iwan
    from fricdamp.contact.jenkins import Jenkins

    k_unit, f_name = ("Nm_per_rad", "slip_moment_Nm") if rotational else ("N_per_m",
                                                                         "slip_force_N")
    k0, f0 = _guess(loops, energy)
    if model == "jenkins":
        names = [f"stiffness_{k_unit}", f_name]

        def law(th):
            return Jenkins(math.exp(th[0]), math.exp(th[1]))

        def energy_fn(th, a):
            k, fs = math.exp(th[0]), math.exp(th[1])
            return 4.0 * fs * np.maximum(a - fs / k, 0.0)

        starts = [[math.log(k0), math.log(f0)], [math.log(2 * k0), math.log(f0)]]
        return _Spec(model, names, [True, True], ([-np.inf] * 2, [np.inf] * 2), law,
                     energy_fn, starts)
    if model == "iwan":
        names = [f"stiffness_{k_unit}", f_name, "chi", "beta"]

        def law(th):
            return Iwan(math.exp(th[0]), math.exp(th[1]), th[2], th[3])

        def energy_fn(th, a):
            return law(th).discrete_energy(a)[:, 0]

        starts = [[math.log(k0), math.log(f0), chi, beta] for chi in (-0.6, -0.2)
                  for beta in (0.2, 1.5)]
        return _Spec(model, names, [True, True, False, False],
                     ([-np.inf, -np.inf, -0.99, 0.0], [np.inf, np.inf, 1.0, 100.0]), law,
                     energy_fn, starts)
    if model == "rough":
        if not rotational:
            raise ModelError("the rough model is paper 002's rotational joint: give rotation "
                             "[rad] and torque [N m] loops (or amplitudes in rad)")
        b = _RoughBuilder(fixed)
        names = ["mu", "initial_stiffness_Nm_per_rad", "summit_std_m"]

        def law(th):
            return b.joint(math.exp(th[0]), math.exp(th[1]), math.exp(th[2]))

        def energy_fn(th, a):
            return _symmetric_energy(law(th), a)

        def derived(th):
            mu, kk, sg = (math.exp(v) for v in th)
            h = b.separation(kk, sg)
            lam = b.eta_sqrt_r(sg, h)
            return {"eta_sqrt_R_per_m1p5": lam,
                    "summit_density_per_m2": lam / math.sqrt(b.fixed["summit_radius_m"]),
                    "separation_over_std": h, "slip_moment_Nm": b.slip_moment(mu)}

        mu0 = f0 / (b.fixed["preload_N"] * b.mean_r)
        # converges to the same optimum from sigma = 0.1 .. 3 um (tests/unit/test_fit.py);
        # a stiffness read from the loops is kept when it means a separation of 0-6 sigma,
        # otherwise (loops in gross slip hide it) the start is h = 3 (a typical GW contact)
        s0 = 0.45e-6
        if not b.stiffness_for(6.0, s0) >= k0 >= b.stiffness_for(0.0, s0):
            k0 = b.stiffness_for(3.0, s0)
        starts = [[math.log(mu0), math.log(k0), math.log(s0)]]
        spec = _Spec(model, names, [True, True, True], ([-np.inf] * 3, [np.inf] * 3), law,
                     energy_fn, starts, derived)
        spec.builder = b
        return spec
    raise ModelError(f"model must be one of {MODELS}, got {model!r}")


# ============================================================================ result
#: Unit of a parameter from its name's suffix (longest first); dimensionless otherwise.
_PARAM_UNITS = (("_Nm_per_rad", "N m/rad"), ("_N_per_m", "N/m"), ("_per_m1p5", "1/m^1.5"),
                ("_per_m2", "1/m^2"), ("_Nm", "N m"), ("_Pa", "Pa"), ("_N", "N"),
                ("_m", "m"), ("_rad", "rad"))


def _param_unit(name: str) -> str:
    for suffix, unit in _PARAM_UNITS:
        if name.endswith(suffix):
            return unit
    return "1"


@dataclass(frozen=True, repr=False)
class FitResult(ResultMixin):
    """A fitted joint model.

    Attributes
    ----------
    model : str
        "jenkins", "iwan" or "rough".
    parameters : dict
        Fitted values, named with their units as in case files (e.g.
        ``stiffness_N_per_m``, ``slip_force_N``; ``..._Nm_per_rad``, ``slip_moment_Nm`` for
        rotation).
    confidence_95 : dict
        ``name -> (lo, hi)`` 95 % intervals of the parameters.
    derived : dict
        Quantities that follow from the parameters (rough model: ``eta_sqrt_R_per_m1p5``,
        ``summit_density_per_m2`` for the assumed radius, ``separation_over_std``,
        ``slip_moment_Nm``), with ``derived_confidence_95``.
    derived_confidence_95 : dict
    residual : dict
        ``rms_relative`` (all residuals), ``per_loop`` (RMS of each loop relative to its force
        amplitude), ``energy_relative`` (model/measured - 1 per amplitude or loop),
        ``lag1_correlation``, ``effective_sample_fraction``.
    conditioning : dict
        ``fitted_parameters``, ``fitted_condition_number`` (column-scaled Jacobian),
        ``correlation`` (of the fitted parameters); rough model also
        ``raw_parameters`` (mu, sigma, eta, R) and their ``raw_condition_number`` (eta and R
        only enter as eta sqrt(R): singular).
    law : ContactLaw
        The fitted law.
    loops : tuple of Loop
    predicted : tuple of ndarray
        Model force of each loop (second pass), shape of the loop.
    energy_data : tuple or None
        ``(amplitude, energy)`` fitted, if any.
    status : str
        "ok" or "unreliable" (see ``warnings``).
    warnings : tuple of str
    success : bool
    message : str
    nfev : int
    """

    model: str
    parameters: dict
    confidence_95: dict
    derived: dict
    derived_confidence_95: dict
    residual: dict
    conditioning: dict
    law: ContactLaw
    loops: tuple
    predicted: tuple
    energy_data: tuple | None
    status: str
    warnings: tuple
    success: bool
    message: str
    nfev: int
    rotational: bool = False

    def to_dict(self) -> dict:
        """JSON-able: ``parameters``, ``confidence_95``, ``residual``, ... (units in keys)."""
        def clean(v):
            if isinstance(v, dict):
                return {k: clean(x) for k, x in v.items()}
            if isinstance(v, (list, tuple, np.ndarray)):
                return [clean(x) for x in v]
            if isinstance(v, (np.floating, float)):
                return float(v)
            if isinstance(v, (np.integer, int)) and not isinstance(v, bool):
                return int(v)
            return v

        return clean({"model": self.model, "parameters": self.parameters,
                      "confidence_95": self.confidence_95, "derived": self.derived,
                      "derived_confidence_95": self.derived_confidence_95,
                      "residual": self.residual, "conditioning": self.conditioning,
                      "status": self.status, "warnings": list(self.warnings),
                      "success": self.success, "message": self.message, "nfev": self.nfev,
                      "n_loops": len(self.loops), "rotational": self.rotational})

    def __repr__(self) -> str:
        from fricdamp.results import summary_repr

        head = summary_repr(self, skip=("confidence_95", "derived", "derived_confidence_95",
                                        "residual", "conditioning", "parameters", "message"))
        lines = [head[:-1] + ","] if head.endswith(")") else [head]
        for k, v in self.parameters.items():
            lo, hi = self.confidence_95.get(k, (float("nan"), float("nan")))
            lines.append(f"    {k}={float(v):.6g} (95 %: {float(lo):.4g} to {float(hi):.4g}),")
        lines[-1] = lines[-1].rstrip(",") + ")"
        return "\n".join(lines)

    def _judge(self):
        from fricdamp.results import status_verdict

        est = {"rms_relative": self.residual.get("rms_relative")}
        reasons = tuple(self.warnings) if self.status != "ok" else ()
        if self.status != "ok" and not reasons:
            reasons = (f"the fit is {self.status}",)
        return status_verdict(self.success, self.message, est, reasons=reasons)

    def to_xarray(self):
        """``xarray.Dataset``: each fitted and derived parameter as a scalar variable named as
        in ``parameters`` (unit from the name's suffix), its 95 % interval as ``<name>_lo``
        and ``<name>_hi``; the loops' samples along ``sample`` (``displacement``, ``force``,
        ``predicted_force``, ``loop``) and the fitted energies along ``amplitude_point``."""
        import xarray as xr

        data = {}
        for values, ci in ((self.parameters, self.confidence_95),
                           (self.derived, self.derived_confidence_95)):
            for k, v in values.items():
                if not isinstance(v, (int, float, np.integer, np.floating)):
                    continue
                u = {"units": _param_unit(k)}
                data[k] = ((), float(v), u)
                if k in ci:
                    lo, hi = ci[k]
                    data[f"{k}_lo"] = ((), float(lo), u)
                    data[f"{k}_hi"] = ((), float(hi), u)
        xu, fu = ("rad", "N m") if self.rotational else ("m", "N")
        if self.loops:
            data["displacement"] = ("sample", np.concatenate(
                [lp.displacement for lp in self.loops]), {"units": xu})
            data["force"] = ("sample", np.concatenate([lp.force for lp in self.loops]),
                             {"units": fu})
            data["predicted_force"] = ("sample", np.concatenate(
                [np.asarray(p, float) for p in self.predicted]), {"units": fu})
            data["loop"] = ("sample", np.concatenate(
                [np.full(lp.force.size, i, np.int32) for i, lp in enumerate(self.loops)]))
        if self.energy_data is not None:
            a, e = self.energy_data
            data["energy_amplitude"] = ("amplitude_point", np.asarray(a, float),
                                        {"units": xu})
            data["energy"] = ("amplitude_point", np.asarray(e, float), {"units": "J"})
            data["predicted_energy"] = ("amplitude_point", np.asarray(
                _model_energy(self, np.asarray(a, float)), float), {"units": "J"})
        rms = self.residual.get("rms_relative")
        return xr.Dataset(data, attrs={
            "model": self.model, "status": self.status, "success": int(self.success),
            "message": self.message, "warnings": "\n".join(self.warnings),
            "rotational": int(self.rotational), "nfev": int(self.nfev),
            "rms_relative": float(rms) if rms is not None else float("nan")})

    def plot(self, fig=None):
        """Measured and fitted loops (and energies); returns the figure."""
        import matplotlib.pyplot as plt

        panels = (1 if self.loops else 0) + (1 if self.energy_data is not None else 0)
        if fig is None:
            fig = plt.figure(figsize=(5.8 * panels, 4.4))
        axes = fig.subplots(1, panels, squeeze=False)[0]
        scale, xl = (1e3, "rotation [mrad]") if self.rotational else (1e6, "displacement [um]")
        fl = "torque [N m]" if self.rotational else "force [N]"
        k = 0
        if self.loops:
            ax = axes[k]
            k += 1
            for i, (lp, fm) in enumerate(zip(self.loops, self.predicted, strict=True)):
                c = f"C{i % 10}"
                x = np.append(lp.displacement, lp.displacement[0]) * scale
                ax.plot(x, np.append(lp.force, lp.force[0]) - lp.force.mean(), ".", ms=2,
                        color=c, alpha=0.5)
                ax.plot(x, np.append(fm, fm[0]) - fm.mean(), "-", color=c, lw=1.2)
            ax.set_xlabel(xl)
            ax.set_ylabel(fl)
            ax.set_title(f"{self.model}: measured (dots), fitted (lines)")
            ax.grid(alpha=0.3)
        if self.energy_data is not None:
            ax = axes[k]
            a, e = self.energy_data
            ax.loglog(a * scale, e, "ko", ms=4, label="measured")
            aa = np.geomspace(a.min() / 2, a.max() * 2, 60)
            ax.loglog(aa * scale, _model_energy(self, aa), "-", label=self.model)
            ax.set_xlabel(xl.replace("rotation", "rotation amplitude").replace(
                "displacement", "amplitude"))
            ax.set_ylabel("dissipated energy per cycle [J]")
            ax.grid(alpha=0.3, which="both")
            ax.legend(fontsize="small")
        fig.tight_layout()
        return fig


def _model_energy(result: FitResult, amplitudes):
    law = result.law
    if hasattr(law, "discrete_energy"):
        return law.discrete_energy(amplitudes)[:, 0]
    if result.model == "jenkins":
        k, fs = float(law.stiffness[0]), float(law.slip_force[0])
        return 4.0 * fs * np.maximum(np.asarray(amplitudes) - fs / k, 0.0)
    return _symmetric_energy(law, amplitudes)


# ============================================================================ fitting
def _loop_force(law, x):
    """Steady force along one period ``x`` (whole periods) from the virgin state.

    The law is first taken to the extreme of ``x`` reached earlier in the period, then to the
    later one, then along the rest of the period: for laws with Masing's wipe-out memory
    (Jenkins, Iwan, Cattaneo-Mindlin) that is the state the whole period leaves behind, so
    the second pass is the periodic loop (half the work of marching the period twice).
    """
    i_max, i_min = int(np.argmax(x)), int(np.argmin(x))
    last, other = (i_max, i_min) if i_max > i_min else (i_min, i_max)
    prefix = np.concatenate(([x[other], x[last]], x[last + 1:]))
    f, _ = law.march(np.concatenate((prefix, x))[:, None, None])
    return f[prefix.size:, 0, 0]


def _condition(J):
    norms = np.linalg.norm(J, axis=0)
    norms[norms == 0] = 1.0
    s = np.linalg.svd(J / norms, compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else float("inf")


def fit_joint(loops: Sequence[Loop] = (), *, energy=None, model: str = "jenkins",
              target: str | None = None, initial: Mapping | None = None,
              fixed: Mapping | None = None, max_relative_half_width: float = 0.5,
              max_rms_residual: float = 0.2, min_samples_informing: float = 20.0
              ) -> FitResult:
    """Fit a joint model to loops and/or energy against amplitude.

    Parameters
    ----------
    loops : sequence of Loop
        Measured loops (whole periods), all translational or all rotational.
    energy : tuple, optional
        ``(amplitude, energy)`` arrays (n,) [m or rad], [J], > 0, or ``(amplitude, energy,
        rotational)``.
    model : {"jenkins", "iwan", "rough"}
        See the module docstring.
    target : {"loops", "energy", "both"}, optional
        What the residuals compare; default "loops" when loops are given, else "energy".
        "energy" with loops uses their areas and amplitudes; "both" adds those energy
        residuals, each weighted like one loop.
    initial : mapping, optional
        Starting values by parameter name (overrides the automatic guesses).
    fixed : mapping, optional
        Rough model: ``preload_N``, ``contact_width_m``, ``contact_height_m``,
        ``summit_radius_m``, ``youngs_modulus_Pa``, ``poisson_ratio``, ``joint_cells``,
        ``height_classes`` (defaults: paper 002's joint, :func:`rough_joint`).
    max_relative_half_width : float, optional
        A parameter (other than chi and beta) whose 95 % interval is wider than +- this
        fraction makes the fit "unreliable"; default 0.5.
    max_rms_residual : float, optional
        RMS relative residual above which the fit is "unreliable"; default 0.2.
    min_samples_informing : float, optional
        A parameter whose sensitivity is carried by fewer samples than this (participation
        ratio ``(sum |J_i|)^2 / sum J_i^2`` of its Jacobian column) makes the fit
        "unreliable": its interval then rests on a handful of points and model errors
        there go unseen; default 20.

    Returns
    -------
    FitResult

    Raises
    ------
    ModelError
        No data, mixed rotational/translational loops, an unknown model, target or
        parameter name, a fixed parameter out of range.
    ConvergenceError
        When no start gives a finite residual.
    """
    from scipy.optimize import least_squares
    from scipy.stats import t as student

    loops = tuple(loops)
    if model not in MODELS:
        raise ModelError(f"model must be one of {MODELS}, got {model!r}")
    rot_flags = {lp.rotational for lp in loops}
    if len(rot_flags) > 1:
        raise ModelError("the loops mix rotation/torque and displacement/force")
    e_data = None
    rotational = rot_flags.pop() if rot_flags else False
    if energy is not None:
        a = as_finite_array("energy amplitude", energy[0], ndim=1)
        e = as_finite_array("energy", energy[1], ndim=1)
        if a.size != e.size or a.size < 2 or np.any(a <= 0) or np.any(e <= 0):
            raise ModelError("energy must be (amplitude, energy) arrays of equal length >= 2, "
                             "all > 0")
        order = np.argsort(a)
        e_data = (a[order], e[order])
        if len(energy) > 2 and not loops:
            rotational = bool(energy[2])
    if target is None:
        target = "loops" if loops else "energy"
    if target not in ("loops", "energy", "both"):
        raise ModelError(f"target must be 'loops', 'energy' or 'both', got {target!r}")
    if target in ("loops", "both") and not loops:
        raise ModelError(f"target {target!r} needs loops")
    if target in ("energy", "both") and e_data is None:
        if not loops:
            raise ModelError("give loops or an energy table to fit")
        a = np.array([lp.amplitude for lp in loops])
        e = np.array([lp.energy for lp in loops])
        keep = e > 0
        if keep.sum() < 2:
            raise ModelError("fitting energies needs at least 2 loops with a positive area")
        order = np.argsort(a[keep])
        e_data = (a[keep][order], e[keep][order])
    spec = _make_spec(model, rotational, loops,
                      (e_data[0], e_data[1], rotational) if e_data is not None else None,
                      dict(fixed or {}), initial)
    if initial:
        unknown = set(initial) - set(spec.names)
        if unknown:
            raise ModelError(f"initial: unknown parameter(s) {sorted(unknown)}; the "
                             f"{model} model has {spec.names}")
        x0 = list(spec.starts[0])
        for i, name in enumerate(spec.names):
            if name in initial:
                v = float(initial[name])
                if spec.log[i] and not v > 0:
                    raise ModelError(f"initial {name} must be > 0, got {v!r}")
                x0[i] = math.log(v) if spec.log[i] else v
        spec.starts = [x0]

    scales = [lp.force_amplitude for lp in loops]
    f_meas = [lp.force - lp.force.mean() for lp in loops]
    n_mean = float(np.mean([lp.displacement.size for lp in loops])) if loops else 1.0
    use_loops = target in ("loops", "both")
    use_energy = target in ("energy", "both")
    w_energy = math.sqrt(n_mean) if target == "both" else 1.0

    def residual(th, parts=False, on=(use_loops, use_energy)):
        law = spec.law(th)
        out = []
        if on[0]:
            for lp, fm, sc in zip(loops, f_meas, scales, strict=True):
                fp = _loop_force(law, lp.displacement)
                out.append(((fp - fp.mean()) - fm) / sc)
        if on[1]:
            em = spec.energy(th, e_data[0])
            out.append(w_energy * (em / e_data[1] - 1.0))
        return out if parts else np.concatenate(out)

    n_loop_rows = sum(lp.displacement.size for lp in loops)

    def solve(starts, on):
        n_res = (n_loop_rows if on[0] else 0) + (e_data[0].size if on[1] else 0)

        def safe(th):
            try:
                r = residual(th, on=on)
            except (ModelError, FloatingPointError, ValueError):
                return np.full(n_res, 1e3)
            return np.where(np.isfinite(r), r, 1e3)

        lo, hi = spec.bounds
        best = None
        for x0 in starts:
            x0 = np.clip(np.asarray(x0, float), np.asarray(lo) + 1e-9, np.asarray(hi) - 1e-9)
            try:
                res = least_squares(safe, x0, bounds=spec.bounds, x_scale="jac", xtol=1e-10,
                                    ftol=1e-12, gtol=1e-10, max_nfev=300 * len(x0),
                                    diff_step=1e-6)
            except (ValueError, np.linalg.LinAlgError) as exc:  # pragma: no cover
                log.info("start %s failed: %s", x0, exc)
                continue
            if best is None or res.cost < best.cost:
                best = res
        if best is None or not np.all(np.isfinite(best.fun)) or np.all(best.fun == 1e3):
            raise ConvergenceError(f"fitting the {model} model failed from every start "
                                   f"({len(starts)}): no parameters reproduce the data's scale")
        return best

    if target == "both":  # the loops first, then loops and energies from there
        best = solve([solve(spec.starts, (True, False)).x], (True, True))
    else:
        best = solve(spec.starts, (use_loops, use_energy))
    th = best.x
    J = best.jac
    r = best.fun
    n, p = r.size, th.size
    dof = max(n - p, 1)
    s2 = float(r @ r) / dof
    # lag-one correlation of residuals within loops -> effective sample size
    parts = residual(th, parts=True)
    loop_parts = parts[:len(loops)] if use_loops else []
    num = sum(float(np.dot(q[:-1], q[1:])) for q in loop_parts)
    den = sum(float(np.dot(q, q)) for q in loop_parts)
    rho = min(max(num / den, 0.0), 0.99) if den > 0 else 0.0
    eff = (1.0 - rho) / (1.0 + rho)
    cov = s2 * np.linalg.pinv(J.T @ J) / eff
    tq = float(student.ppf(0.975, max(int(dof * eff), 1)))
    se = np.sqrt(np.maximum(np.diag(cov), 0.0))
    params, ci = {}, {}
    warnings = []
    for i, name in enumerate(spec.names):
        if spec.log[i]:
            val = math.exp(th[i])
            with np.errstate(over="ignore"):
                lo_i, hi_i = (float(np.exp(th[i] - tq * se[i])),
                              float(np.exp(th[i] + tq * se[i])))
            half = 0.5 * (hi_i - lo_i) / val
            if half > max_relative_half_width:
                warnings.append(f"{name} is poorly determined: 95 % interval [{lo_i:.4g}, "
                                f"{hi_i:.4g}] (+-{100 * half:.3g} %)")
        else:
            val = float(th[i])
            lo_i, hi_i = val - tq * se[i], val + tq * se[i]
        params[name], ci[name] = val, (lo_i, hi_i)
    derived, dci = {}, {}
    edge = False  # the optimum at the edge of the model's range (finite differences fail)
    if spec.derived is not None:
        derived = spec.derived(th)
        step = 1e-5
        try:
            grads = []
            for i in range(p):
                d = np.zeros(p)
                d[i] = step
                up, dn = spec.derived(th + d), spec.derived(th - d)
                grads.append({k: (up[k] - dn[k]) / (2 * step) for k in derived})
            for k, v in derived.items():
                g = np.array([gr[k] for gr in grads])
                sd = math.sqrt(max(float(g @ cov @ g), 0.0))
                dci[k] = (v - tq * sd, v + tq * sd)
        except ModelError:
            edge = True
            dci = {k: (float("nan"), float("nan")) for k in derived}
    corr = cov / np.outer(se, se) if np.all(se > 0) else np.full_like(cov, np.nan)
    # participation of each parameter's sensitivity: in loop samples (energies alone: in
    # amplitudes, where the limit is a tenth of min_samples_informing)
    absj = np.abs(J[:n_loop_rows] if use_loops else J)
    with np.errstate(invalid="ignore", divide="ignore"):
        support = np.sum(absj, axis=0) ** 2 / np.sum(absj * absj, axis=0)
    min_support = min_samples_informing if use_loops else 0.1 * min_samples_informing
    cond = {"fitted_parameters": list(spec.names),
            "fitted_condition_number": _condition(J),
            "correlation": corr.tolist(),
            "samples_informing": {k: float(v) for k, v in zip(spec.names, support,
                                                               strict=True)}}
    if model == "rough":
        try:
            cond.update(_raw_conditioning(spec, th, loops, f_meas, scales, use_loops,
                                          use_energy, e_data, w_energy))
        except ModelError:
            edge = True
    if edge:
        warnings.insert(0, "the optimum lies at the edge of the model's range (a separation "
                           "beyond [-40, 30] summit_std nearby): the data do not hold the "
                           "parameters; no intervals")
        ci = {k: (float("nan"), float("nan")) for k in ci}
    law = spec.law(th)
    predicted = tuple(_loop_force(law, lp.displacement) for lp in loops)
    per_loop = [float(np.sqrt(np.mean(q * q))) for q in loop_parts]
    rms = float(np.sqrt(np.mean(r * r)))
    resid = {"rms_relative": rms, "per_loop": per_loop,
             "lag1_correlation": rho, "effective_sample_fraction": eff,
             "n_residuals": int(n)}
    if e_data is not None:
        resid["energy_relative"] = (spec.energy(th, e_data[0]) / e_data[1] - 1.0).tolist()
        resid["energy_amplitudes"] = e_data[0].tolist()
    if loops:
        resid["loop_energy_relative"] = [
            float(loop_area(lp.displacement, fp) / lp.energy - 1.0) if lp.energy > 0 else
            float("nan") for lp, fp in zip(loops, predicted, strict=True)]
    if rms > max_rms_residual:
        warnings.insert(0, f"the model misses the data: RMS residual {100 * rms:.3g} % of the "
                           f"force amplitude (limit {100 * max_rms_residual:g} %)")
    lo_b, hi_b = spec.bounds
    for i, name in enumerate(spec.names):
        if not spec.log[i] and (th[i] <= lo_b[i] + 1e-6 or th[i] >= hi_b[i] - 1e-6):
            warnings.append(f"{name} = {th[i]:.4g} sits on its bound [{lo_b[i]:g}, "
                            f"{hi_b[i]:g}]: the data ask for a limit of the model (e.g. "
                            "beta at its upper bound: a Jenkins element)")
    for name, v in cond["samples_informing"].items():
        if not v >= min_support:
            warnings.append(f"{name} rests on ~{v:.3g} samples (participation of its "
                            f"sensitivity; limit {min_support:g}): the data barely "
                            "resolve what sets it (e.g. the stick phase at the reversals "
                            "of gross-slip loops); add smaller loops or sample faster")
    if cond["fitted_condition_number"] > 1e6:
        warnings.append(f"ill-conditioned fit (condition number "
                        f"{cond['fitted_condition_number']:.3g}): the data do not separate "
                        "the parameters; add loops spanning micro- to macro-slip")
    return FitResult(model=model, parameters=params, confidence_95=ci, derived=derived,
                     derived_confidence_95=dci, residual=resid, conditioning=cond, law=law,
                     loops=loops, predicted=predicted,
                     energy_data=e_data if use_energy else None,
                     status="unreliable" if warnings else "ok", warnings=tuple(warnings),
                     success=bool(best.success), message=str(best.message),
                     nfev=int(best.nfev), rotational=rotational)


def _raw_conditioning(spec, th, loops, f_meas, scales, use_loops, use_energy, e_data, w_e):
    """Condition number of the rough model's Jacobian in (mu, sigma, eta, R) (log)."""
    b = spec.builder
    joint = spec.law(th)
    raw = np.log([math.exp(th[0]), joint.gw.summit_std, joint.gw.summit_density,
                  joint.gw.summit_radius])

    def res(z):
        law = b.raw_joint(*np.exp(z))
        out = []
        if use_loops:
            for lp, fm, s in zip(loops, f_meas, scales, strict=True):
                fp = _loop_force(law, lp.displacement)
                out.append(((fp - fp.mean()) - fm) / s)
        if use_energy:
            out.append(w_e * (_symmetric_energy(law, e_data[0]) / e_data[1] - 1.0))
        return np.concatenate(out)

    step = 1e-5
    cols = []
    for i in range(4):
        d = np.zeros(4)
        d[i] = step
        cols.append((res(raw + d) - res(raw - d)) / (2 * step))
    J = np.column_stack(cols)
    return {"raw_parameters": ["mu", "summit_std_m", "summit_density_per_m2",
                               "summit_radius_m"],
            "raw_condition_number": _condition(J),
            "note": "eta and R enter only as eta sqrt(R) (Hertz loads at a preload-fixed "
                    "separation; slip displacements mu E* C (z - d) / 4 do not depend on R): "
                    "the fit uses mu, the initial stiffness and sigma instead"}
