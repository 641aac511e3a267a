"""How far a joint identification can be trusted (:mod:`fricdamp.signals.identify`).

Paper 002's three-accelerometer method measures the joint rotation as the small difference
of two beam rotations and the joint torque as the small remainder of beam 2's inertial
torques (002 (8)). In micro-slip the difference is ~0.2 % of the beams' rotation, so errors
of the accelerometers that the paper does not discuss (noise, sensitivity, phase, sensor
position) are amplified ~500-fold into the loop. Three diagnostics say whether a result can
be used:

* **block scatter**: the record's steady part is cut into separate blocks of 3 periods,
  each identified on its own; the relative standard deviation of their energies exposes
  noise and non-stationarity (the per-period spread after the harmonic filter cannot: the
  filter makes every period alike);
* **conditioning**: the joint's relative rotation over the larger beam rotation
  (fundamentals), and the joint torque over the largest inertial term of 002 (8); a
  relative error ``e`` of the accelerations becomes ~``e / ratio`` in the loop;
* **Monte Carlo**: ``samples`` copies of the record with perturbed sensor positions
  (normal, ``position_std_m``), sensitivities (``1 + N(0, sensitivity_std)``), channel
  delays (``N(0, delay_std_s)``) and, by default, fresh noise at the record's own noise
  level (estimated from the spectrum between the harmonics), run through the pipeline; the
  95 % interval of E_d and xi holds both the basic bootstrap interval
  ``[x - q97.5(dx), x - q2.5(dx)]`` and the percentile interval ``[x + q2.5(dx), x +
  q97.5(dx)]`` of the deviations ``dx`` from the unperturbed run (:func:`basic_interval`).

The result is **unreliable** when E_d <= 0, when its 95 % interval includes 0 or is wider
than ``max_relative_width`` times E_d, or when the block scatter exceeds
``max_block_scatter`` (docs/identify.md gives the defaults and why).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from fricdamp.errors import ModelError, check_positive
from fricdamp.signals._identify_core import first_harmonic, process_window
from fricdamp.signals._identify_window import whole_periods

__all__ = ["MeasurementUncertainty", "TrustReport", "TrustThresholds"]


@dataclass(frozen=True)
class MeasurementUncertainty:
    """Standard uncertainties (one sigma) of the measurement chain, for the Monte Carlo.

    Parameters
    ----------
    position_std_m : float, optional
        Of each accelerometer's position along its beam (d1, d2, d4) [m], >= 0; default
        0.5 mm (a sensor's seismic centre is known to about that).
    sensitivity_std : float, optional
        Relative, of each channel's sensitivity [-], >= 0; default 0.005 (0.5 %, a good
        back-to-back calibration; datasheet values are 2-5 %).
    delay_std_s : float, optional
        Of each channel's time delay (phase mismatch) [s], >= 0; default 1e-6 (simultaneous
        sampling; 1 us is 0.011 degrees at 30 Hz).
    noise : bool, optional
        Add fresh noise at the record's own level to each copy; default True.
    samples : int, optional
        Monte Carlo copies, >= 20; default 1000 (the 95 % quantiles to ~3 %).
    seed : int or None, optional
        Seed of the draws; default 0 (reproducible).
    """

    position_std_m: float = 0.5e-3
    sensitivity_std: float = 0.005
    delay_std_s: float = 1e-6
    noise: bool = True
    samples: int = 1000
    seed: int | None = 0

    def __post_init__(self):
        for name, unit in (("position_std_m", "m"), ("sensitivity_std", ""),
                           ("delay_std_s", "s")):
            object.__setattr__(self, name, float(check_positive(
                name, getattr(self, name), unit=unit, allow_zero=True)))
        if int(self.samples) != self.samples or self.samples < 20:
            raise ModelError(f"samples must be an integer >= 20, got {self.samples!r}")
        object.__setattr__(self, "samples", int(self.samples))


@dataclass(frozen=True)
class TrustThresholds:
    """When an identification is flagged unreliable (module docstring).

    Parameters
    ----------
    max_relative_width : float, optional
        Largest width ``(hi - lo) / E_d`` of the 95 % interval of E_d, > 0; default 0.2
        (E_d known to about +-10 %).
    max_block_scatter : float, optional
        Largest relative standard deviation of the block energies, > 0; default 0.1.
    block_periods : int, optional
        Periods per block, >= 1; default 3.
    min_blocks : int, optional
        Blocks below which the scatter is only a warning, >= 2; default 5.
    min_conditioning : float, optional
        Joint/beam rotation ratio below which a warning is given, >= 0; default 0.01.
    max_torque_discrepancy : float, optional
        With a force channel: largest RMS difference of the torque from the shaker force
        and the torque of 002 (8), relative to the torque's RMS, > 0; default 0.02
        (:mod:`fricdamp.signals._identify_force`).
    max_energy_imbalance : float, optional
        With a force channel: largest ``|W_in - E_rig - E_d|`` relative to the shaker's
        work per cycle W_in, > 0; default 0.02.
    """

    max_relative_width: float = 0.2
    max_block_scatter: float = 0.1
    block_periods: int = 3
    min_blocks: int = 5
    min_conditioning: float = 0.01
    max_torque_discrepancy: float = 0.02
    max_energy_imbalance: float = 0.02

    def __post_init__(self):
        for name in ("max_relative_width", "max_block_scatter", "max_torque_discrepancy",
                     "max_energy_imbalance"):
            object.__setattr__(self, name, float(check_positive(name, getattr(self, name))))
        object.__setattr__(self, "min_conditioning", float(check_positive(
            "min_conditioning", self.min_conditioning, allow_zero=True)))
        for name, low in (("block_periods", 1), ("min_blocks", 2)):
            v = getattr(self, name)
            if int(v) != v or v < low:
                raise ModelError(f"{name} must be an integer >= {low}, got {v!r}")
            object.__setattr__(self, name, int(v))


@dataclass(frozen=True)
class TrustReport:
    """The verdict on one identification.

    Attributes
    ----------
    status : {"ok", "unreliable"}
    warnings : tuple of str
        Every finding, reasons for "unreliable" first.
    energy_interval, damping_ratio_interval, damping_ratio_energy_interval : (float, float)
        95 % intervals of E_d [J], of paper 002's xi and of the energy-based xi [-].
    relative_width : float
        ``(hi - lo) / |E_d|`` of the energy interval.
    contributions : dict
        Relative half-width of the 95 % interval of E_d from each source alone
        (``noise``, ``position``, ``sensitivity``, ``delay``).
    block_energies : ndarray, shape (n_blocks,)
        E_d of each block [J], latest block first.
    block_scatter : float or None
        Their relative standard deviation (None with fewer than 2 blocks).
    conditioning : dict
        ``joint_to_beam_rotation``, ``torque_to_inertial_torque``, ``amplification``.
    noise_std : ndarray, shape (3,)
        Noise level estimated on A, B, C [m/s^2].
    uncertainty : MeasurementUncertainty
    thresholds : TrustThresholds
    """

    status: str
    warnings: tuple
    energy_interval: tuple
    damping_ratio_interval: tuple
    damping_ratio_energy_interval: tuple
    relative_width: float
    contributions: dict
    block_energies: np.ndarray
    block_scatter: float | None
    conditioning: dict
    noise_std: np.ndarray
    uncertainty: MeasurementUncertainty = field(default_factory=MeasurementUncertainty)
    thresholds: TrustThresholds = field(default_factory=TrustThresholds)

    @property
    def reliable(self) -> bool:
        return self.status == "ok"

    def to_dict(self) -> dict:
        """JSON-able: ``confidence_95``, ``block_scatter``, ``conditioning``, ``warnings``..."""
        return {
            "status": self.status,
            "confidence_95": {
                "dissipated_energy_J": [float(x) for x in self.energy_interval],
                "damping_ratio": [float(x) for x in self.damping_ratio_interval],
                "damping_ratio_energy": [float(x) for x in self.damping_ratio_energy_interval],
            },
            "confidence_relative_width": float(self.relative_width),
            "confidence_contributions": {k: float(v) for k, v in self.contributions.items()},
            "block_scatter": None if self.block_scatter is None else float(self.block_scatter),
            "block_energies_J": [float(x) for x in self.block_energies],
            "block_periods": int(self.thresholds.block_periods),
            "conditioning": {k: float(v) for k, v in self.conditioning.items()},
            "noise_std_m_per_s2": [float(x) for x in self.noise_std],
            "uncertainty": asdict(self.uncertainty),
            "thresholds": asdict(self.thresholds),
            "warnings": list(self.warnings),
        }


# ============================================================================ pieces
def noise_level(Gw, n_periods: int) -> np.ndarray:
    """White-noise standard deviation of each column of a window of whole periods.

    From the bins between the harmonics: for white noise of variance s^2 each rfft bin has
    ``|X|^2 ~ n s^2 Exp(1)``, whose median is ``n s^2 ln 2`` (the median ignores the few
    bins that hold a transient or a suspension mode).
    """
    n = Gw.shape[0]
    X = np.fft.rfft(Gw - Gw.mean(axis=0), axis=0)
    bins = np.arange(X.shape[0])
    between = (bins % n_periods != 0) & (bins > 0)
    if n % 2 == 0:
        between[-1] = False
    if not np.any(between):
        return np.zeros(Gw.shape[1])
    power = np.abs(X[between]) ** 2
    return np.sqrt(np.median(power, axis=0) / (n * math.log(2.0)))


#: at most this many blocks, spread evenly over a long record (the statistic needs no more)
MAX_BLOCKS = 24


def block_energies(t, G, dt, frequency, geometry, options, block_periods: int) -> np.ndarray:
    """E_d of separate blocks of ``block_periods`` whole periods, from the record's end.

    Every block of the steady record up to :data:`MAX_BLOCKS`; a longer record gives that
    many blocks spread evenly over it (latest first).
    """
    per = 1.0 / (frequency * dt)
    n = t.size
    n_blocks = int(np.floor(n / per + 1e-9)) // block_periods
    picks = range(n_blocks)
    if n_blocks > MAX_BLOCKS:
        picks = np.unique(np.round(np.linspace(0, n_blocks - 1, MAX_BLOCKS)).astype(int))
    out = []
    for b in picks:
        end = n - int(round(b * block_periods * per))
        if end < block_periods * per:
            break
        _, Gb, nb, _, dtb = whole_periods(t[:end], G[:end], dt, frequency, block_periods)
        out.append(float(process_window(Gb, dtb, nb, geometry, **options).energy))
    return np.asarray(out)


def conditioning(loop, geometry, n_periods: int) -> dict:
    """Joint/beam rotation and joint/inertial torque ratios of a processed window."""
    rot = first_harmonic(loop.rotation, n_periods)
    beams = max(first_harmonic(loop.theta1, n_periods), first_harmonic(loop.theta2, n_periods))
    m2, d3, d5 = geometry.beam2_mass, geometry.joint_arm1, geometry.joint_arm2
    terms = [(geometry.beam2_inertia + m2 * d5 * d5) * loop.acc[:, 1],
             m2 * d5 * loop.acc[:, 2], m2 * d3 * d5 * loop.acc[:, 0]]
    inertial = max(first_harmonic(x, n_periods) for x in terms)
    tq = first_harmonic(loop.torque, n_periods)
    ratio = float(rot / beams) if beams > 0 else 0.0
    return {"joint_to_beam_rotation": ratio,
            "torque_to_inertial_torque": float(tq / inertial) if inertial > 0 else 0.0,
            "amplification": float(1.0 / ratio) if ratio > 0 else float("inf")}


def _one_period(Gw, n_periods: int, n_harmonics):
    """Harmonic coefficients of the synchronous-average period, for synthesis on s samples."""
    n = Gw.shape[0]
    s = int(math.ceil(n / n_periods - 1e-9))
    H = np.fft.rfft(Gw, axis=0)[::n_periods]
    k_max = min(H.shape[0], (s + 1) // 2)
    if n % 2 == 0 and (n // 2) % n_periods == 0:
        k_max = min(k_max, n // 2 // n_periods)  # the window's Nyquist bin carries no phase
    if n_harmonics is not None:
        k_max = min(k_max, int(n_harmonics) + 1)
    C = np.zeros((s // 2 + 1, Gw.shape[1]), dtype=complex)
    C[1:k_max] = H[1:k_max] * (s / n)
    return C, s, k_max


def monte_carlo(Gw, n_periods: int, frequency: float, geometry, options: dict,
                unc: MeasurementUncertainty, noise_std, *, sources=("noise", "position",
                                                                     "sensitivity", "delay"),
                samples: int | None = None, seed=None):
    """Perturbed copies of the synchronous-average period through the pipeline.

    Returns ``(energy, xi, xi_energy)`` deviations from the unperturbed copy, each (samples,).
    """
    rng = np.random.default_rng(unc.seed if seed is None else seed)
    m = unc.samples if samples is None else int(samples)
    C, s, k_max = _one_period(Gw, n_periods, options.get("n_harmonics"))
    dt1 = 1.0 / (frequency * s)
    # one fixed-point pass of the exact kinematics: the draws' deviations are first order
    opts = dict(options, filter="harmonic", iterations=1)
    opts.pop("n_harmonics", None)
    opts.pop("f_low", None)
    k = np.arange(C.shape[0])

    def run(g, positions):
        loop = process_window(g, dt1, 1, geometry, positions=positions, **opts)
        th = 0.5 * np.ptp(loop.rotation, axis=0)
        mm = 0.5 * np.ptp(loop.torque, axis=0)
        th1 = first_harmonic(loop.rotation, 1)
        m1 = first_harmonic(loop.torque, 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            return loop.energy, loop.energy / (np.pi * th * mm), loop.energy / (np.pi * th1
                                                                                  * m1)

    base = [np.asarray(x).reshape(()) for x in run(np.fft.irfft(C, n=s, axis=0)[:, :, None],
                                                   None)]
    d0 = np.array([geometry.sensor_a, geometry.sensor_b, geometry.sensor_c])
    outs = [[], [], []]
    chunk = 250
    for start in range(0, m, chunk):
        mc = min(chunk, m - start)
        fac = np.ones((C.shape[0], 3, mc), dtype=complex)
        if "sensitivity" in sources and unc.sensitivity_std > 0:
            fac *= 1.0 + unc.sensitivity_std * rng.standard_normal((1, 3, mc))
        if "delay" in sources and unc.delay_std_s > 0:
            tau = unc.delay_std_s * rng.standard_normal((1, 3, mc))
            fac *= np.exp(-2j * np.pi * frequency * k[:, None, None] * tau)
        Cm = C[:, :, None] * fac
        if "noise" in sources and unc.noise:
            sd = s * np.asarray(noise_std)[None, :, None] / math.sqrt(2.0 * Gw.shape[0])
            z = rng.standard_normal((k_max - 1, 3, mc)) + 1j * rng.standard_normal(
                (k_max - 1, 3, mc))
            Cm[1:k_max] += sd * z
        if "position" in sources and unc.position_std_m > 0:
            pos = d0[:, None] + unc.position_std_m * rng.standard_normal((3, mc))
            positions = (pos[0], pos[1], pos[2])
        else:
            positions = None
        res = run(np.fft.irfft(Cm, n=s, axis=0), positions)
        for lst, x, b in zip(outs, res, base, strict=True):
            lst.append(np.asarray(x) - b)
    return tuple(np.concatenate(x) for x in outs)


def basic_interval(value: float, deviations) -> tuple[float, float]:
    """95 % interval from the draws' deviations ``d`` (NaN draws dropped).

    The union of the basic bootstrap interval ``[x - q97.5(d), x - q2.5(d)]`` (right when
    the record carries errors like the draws') and the percentile interval
    ``[x + q2.5(d), x + q97.5(d)]`` (right when it carries none): the two coincide for
    symmetric deviations (E_d), and the union stays honest for one-signed ones (peak-to-peak
    amplitudes only grow with perturbations, so paper 002's xi only falls).
    """
    d = np.asarray(deviations, dtype=float)
    d = d[np.isfinite(d)]
    if d.size == 0:
        return (float("nan"), float("nan"))
    lo, hi = np.percentile(d, [2.5, 97.5])
    return (float(value + min(lo, -hi)), float(value + max(hi, -lo)))


def assess(*, energy: float, damping_ratio: float, damping_ratio_energy: float, Gw,
           n_periods: int, frequency: float, loop, geometry, options: dict, t_steady,
           G_steady, dt: float, unc: MeasurementUncertainty, thr: TrustThresholds,
           notes=()) -> TrustReport:
    """Run the three diagnostics and give the verdict (module docstring)."""
    noise = noise_level(Gw, n_periods)
    dE, dxi, dxe = monte_carlo(Gw, n_periods, frequency, geometry, options, unc, noise)
    e_int = basic_interval(energy, dE)
    x_int = basic_interval(damping_ratio, dxi)
    xe_int = basic_interval(damping_ratio_energy, dxe)
    scale = abs(energy) if energy != 0 else float("inf")
    width = (e_int[1] - e_int[0]) / scale if np.all(np.isfinite(e_int)) else float("inf")
    contributions = {}
    for j, src in enumerate(("noise", "position", "sensitivity", "delay")):
        d, _, _ = monte_carlo(Gw, n_periods, frequency, geometry, options, unc, noise,
                              sources=(src,), samples=max(20, unc.samples // 5),
                              seed=None if unc.seed is None else unc.seed + 1 + j)
        lo, hi = basic_interval(energy, d)
        contributions[src] = 0.5 * (hi - lo) / scale if np.isfinite(hi - lo) else float("inf")
    blocks = block_energies(t_steady, G_steady, dt, frequency, geometry, options,
                            thr.block_periods)
    scatter = None
    if blocks.size >= 2:
        mean = float(np.mean(blocks))
        scatter = float(np.std(blocks, ddof=1) / abs(mean)) if mean != 0 else float("inf")
    cond = conditioning(loop, geometry, n_periods)

    reasons, notes = [], list(notes)
    if not energy > 0:
        reasons.append(f"the loop area E_d = {energy:.3g} J is not positive: the loop runs "
                       "the wrong way or is noise (check channel assignment and signs)")
    if not e_int[0] > 0:
        reasons.append(f"the 95 % interval of E_d [{e_int[0]:.3g}, {e_int[1]:.3g}] J "
                       "includes zero")
    if width > thr.max_relative_width:
        worst = max(contributions, key=contributions.get)
        reasons.append(f"the 95 % interval of E_d is {100 * width:.3g} % of E_d wide (limit "
                       f"{100 * thr.max_relative_width:g} %); largest source: {worst} "
                       f"(+-{100 * contributions[worst]:.3g} % alone)")
    if scatter is not None and scatter > thr.max_block_scatter:
        msg = (f"the energies of {blocks.size} separate blocks of {thr.block_periods} "
               f"periods scatter by {100 * scatter:.3g} % (limit "
               f"{100 * thr.max_block_scatter:g} %): noise or a non-steady record")
        (reasons if blocks.size >= thr.min_blocks else notes).append(msg)
    if blocks.size < thr.min_blocks:
        notes.append(f"only {blocks.size} block(s) of {thr.block_periods} periods in the "
                     f"steady record ({thr.min_blocks} needed for the block scatter test): "
                     "record longer signals")
    if cond["joint_to_beam_rotation"] < thr.min_conditioning:
        notes.append(f"ill-conditioned: the joint rotation is "
                     f"{100 * cond['joint_to_beam_rotation']:.3g} % of the beams' rotation, "
                     f"so accelerometer errors are amplified ~{cond['amplification']:.3g}x "
                     "in the loop")
    return TrustReport(status="unreliable" if reasons else "ok",
                       warnings=tuple(reasons + notes), energy_interval=e_int,
                       damping_ratio_interval=x_int, damping_ratio_energy_interval=xe_int,
                       relative_width=float(width), contributions=contributions,
                       block_energies=blocks, block_scatter=scatter, conditioning=cond,
                       noise_std=noise, uncertainty=unc, thresholds=thr)
