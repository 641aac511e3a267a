"""The rig's electromagnet excitation of paper 003 and which nodal diameter each order excites.

003 sections 2.1 and 2.3: eight electromagnets EM1..EM8 around the wheel, wired in four
pairs (EM1, EM5), (EM2, EM6), (EM3, EM7), (EM4, EM8) -- opposite magnets, 180 degrees
apart -- fire pulses *synchronised with the rotation*: "the excitation comes when blade L1
passes EM1 in case 15 and L1 passes EM5 in case 51". With both cases of every pair the
wheel receives ``p = 2 x 4 = 8`` pulses per revolution and the critical speeds follow
003 (1), ``s = 60 f_R / (p o)``: the blades are excited at the frequencies ``p o n / 60``.

Which nodal diameter (ND) does order ``o`` excite? Two rules, derived here and both
computed by :func:`engine_order_content` (a 2D discrete Fourier transform of the force
on every blade over one revolution, so neither is assumed):

* **Stationary pattern** (magnets always on, or pulses not locked to the rotor): the force
  on blade j is a function of its angular position only, ``f_j(t) = G(Omega t + j alpha)``
  with ``alpha = 2 pi / N``. Expanding ``G`` in harmonics ``n`` of the revolution,
  ``f_j = sum_n G_n exp(i n (Omega t + j alpha))``: harmonic ``n`` is a travelling wave of
  ND ``k = -n (mod N)``, folded to ``k = +-n (mod N)`` in 0..N/2 -- the classical
  interference (ZZENF) rule. For 8 equally spaced magnets only ``n = 8 o`` survives:
  o = 1 -> 8ND, o = 2 -> 14ND, o = 3 -> 24 = 30 - 6 -> 6ND (backward).
* **Rotor-synchronous pulses** (the rig): the pulse of pair m fires when blade L1 (blade 0)
  stands in front of magnet m (or m + 4). Magnets at ``i 45`` degrees and blades every 12
  degrees line up only for blades 0 and 15 (``12 j = 45 l (mod 360)`` needs ``j = 15 l / 4``),
  so every pulse pulls blade 0 and blade 15 (plus their neighbours as far as the field and
  the pulse length reach): the load is *fixed to the rotor*, ``f_j(t) = S_j s(t)``, with
  ``s`` of period ``T_rev / 8``. Its content separates: time harmonics ``n = 8 o`` only,
  and for every one of them the ND content of the pattern ``S`` -- a standing wave
  (forward and backward components equal) of every **even** ND (``S`` has the symmetry
  ``j -> j + 15``), weighted by the spatial window of the field. No ND is tied to o: the
  resonating ND at a critical speed is the even ND whose frequency meets ``p o n / 60``,
  which is how 003 identifies it ("by association with the eigenfrequencies of Table 1").

Table 2's pairs follow the second rule: o = 1 meets the 2ND branch at 334 rpm
(``8 x 334 / 60 = 44.53 Hz``, the lowest even-ND crossing of the line o = 1), o = 3 the
6ND branch at 123 rpm (49.2 Hz); the stationary rule would give 8ND for o = 1 (at about
49.5 Hz, i.e. near 371 rpm). :func:`engine_order_map` lists, per order, the excited NDs, the
speeds where the line crosses their branches and the ND whose crossing is nearest the
measured critical speed.

Pulse shape (003 Fig. 7, bottom: the recorded electromagnet forces are short unipolar
pulses): modelled as a half-sine of ``pulse_width_deg`` of rotation (default 10 degrees,
about one blade pitch) and a magnetic field that pulls a blade with a Gaussian weight of
its angular distance to the magnet (``field_width_deg``, default 4 degrees, standard
deviation). Both are documented assumptions: the paper gives neither.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fricdamp.errors import ModelError

__all__ = ["ElectromagnetRig", "engine_order_content", "engine_order_map",
           "stationary_alias_nd"]


@dataclass(frozen=True)
class ElectromagnetRig:
    """The excitation of 003's rig (module docstring).

    Attributes
    ----------
    n_blades : int
        N (003: 30).
    n_magnets : int
        Magnets, equally spaced (003: 8), magnet i at ``360 i / n_magnets`` degrees.
    pairs : tuple of (int, int)
        Wired pairs (003: (0, 4), (1, 5), (2, 6), (3, 7), 0-based).
    both_cases : bool
        Each pair fires when blade 0 passes either of its magnets (cases "15" and "51":
        ``p = 2 x pairs``); False: only the first (``p = pairs``).
    synchronous : bool
        Pulses triggered by blade 0's passage (the rig); False: magnets always on
        (stationary pattern).
    pulse_width_deg : float
        Duration of a half-sine pulse in degrees of rotation.
    field_width_deg : float
        Standard deviation of the Gaussian pull of a magnet on a blade [deg].
    force_N : float
        Peak pull on a blade aligned with a firing magnet [N].
    """

    n_blades: int = 30
    n_magnets: int = 8
    pairs: tuple = ((0, 4), (1, 5), (2, 6), (3, 7))
    both_cases: bool = True
    synchronous: bool = True
    pulse_width_deg: float = 10.0
    field_width_deg: float = 4.0
    force_N: float = 1.0

    def __post_init__(self):
        if int(self.n_blades) != self.n_blades or self.n_blades < 3:
            raise ModelError(f"n_blades must be an integer >= 3, got {self.n_blades!r}")
        if int(self.n_magnets) != self.n_magnets or self.n_magnets < 1:
            raise ModelError(f"n_magnets must be an integer >= 1, got {self.n_magnets!r}")
        for a, b in self.pairs:
            if not (0 <= a < self.n_magnets and 0 <= b < self.n_magnets):
                raise ModelError(f"pairs hold magnets 0..{self.n_magnets - 1}, got "
                                 f"{self.pairs!r}")
        for nm in ("pulse_width_deg", "field_width_deg"):
            v = getattr(self, nm)
            if not (np.isfinite(v) and 0 < v < 360):
                raise ModelError(f"{nm} must lie in (0, 360) deg, got {v!r}")

    @property
    def pulses_per_rev(self) -> int:
        """p: pulses per revolution (003 (1): 8)."""
        return len(self.pairs) * (2 if self.both_cases else 1)

    def forces(self, samples: int = 720) -> np.ndarray:
        """Pull on every blade over one revolution, shape (samples, n_blades) [N].

        Blade j sits at ``theta_j = theta + j alpha`` at rotor angle ``theta`` (sample
        ``theta = 2 pi s / samples``); magnet i at ``beta_i``. Synchronous: pair (a, b)
        fires half-sine pulses starting when blade 0 reaches ``beta_a`` (and ``beta_b``
        with ``both_cases``), both magnets of the pair on; stationary: every magnet on.
        """
        N = int(self.n_blades)
        th = 2 * np.pi * np.arange(samples) / samples
        beta = 2 * np.pi * np.arange(self.n_magnets) / self.n_magnets
        alpha = 2 * np.pi / N
        sig = np.deg2rad(self.field_width_deg)
        width = np.deg2rad(self.pulse_width_deg)
        # current of each magnet vs rotor angle
        cur = np.zeros((samples, self.n_magnets))
        if self.synchronous:
            for a, b in self.pairs:
                for trig in ((beta[a], beta[b]) if self.both_cases else (beta[a],)):
                    ph = np.mod(th - trig + width / 2, 2 * np.pi)
                    on = ph < width
                    pulse = np.where(on, np.sin(np.pi * ph / width), 0.0)
                    cur[:, a] += pulse
                    cur[:, b] += pulse
        else:
            cur[:] = 1.0
        pos = th[:, None] + alpha * np.arange(N)[None, :]                 # (S, N)
        dist = np.angle(np.exp(1j * (pos[:, :, None] - beta[None, None, :])))
        g = np.exp(-0.5 * (dist / sig) ** 2)                               # (S, N, m)
        return self.force_N * np.einsum("snm,sm->sn", g, cur)


def engine_order_content(forces: np.ndarray) -> np.ndarray:
    """Travelling-wave content ``c[n, k]`` [N] of a blade-force field over one revolution.

    ``forces`` (samples, N): ``f_j(theta)``. Returns the complex amplitudes (samples, N)
    with ``f_j(theta) = sum_{n,k} c[n, k] exp(i (n theta - 2 pi k j / N))`` -- harmonic n
    of the revolution, forward wave of k nodal diameters in the convention of
    :func:`fricdamp.solvers.hb.engine_order_load` (k > N/2: backward wave of N - k).
    """
    f = np.asarray(forces, float)
    S, N = f.shape
    # time: exp(-i n theta) -> numpy fft over axis 0; space: exp(+i 2 pi k j / N) -> ifft
    return np.fft.ifft(np.fft.fft(f, axis=0) / S, axis=1)


def stationary_alias_nd(harmonic: int, n_blades: int) -> int:
    """ND excited by revolution harmonic ``n`` of a stationary pattern: ``|n| mod N``
    folded to 0..N/2 (the ZZENF rule)."""
    k = int(harmonic) % int(n_blades)
    return min(k, int(n_blades) - k)


def engine_order_map(rig: ElectromagnetRig | None = None, *, orders=(1, 2, 3),
                     branch_hz=None, measured_rpm=None, rel_threshold: float = 0.05,
                     samples: int = 1440) -> list[dict]:
    """Orders of the rig's pulses, the NDs they excite and where they resonate.

    Parameters
    ----------
    rig : ElectromagnetRig, optional
        Default: 003's rig (8 magnets, 4 opposite pairs, both cases, synchronous).
    orders : sequence of int
        Orders o (revolution harmonic ``n = p o``).
    branch_hz : callable (nd, rpm) -> Hz, optional
        Frequency of the first family by ND at a speed (e.g. from
        :func:`fricdamp.models.tieboss_wheel.studies.campbell_by_nd`); gives the crossing
        speeds ``60 f / (p o)`` per excited ND (solved by fixed point).
    measured_rpm : dict o -> rpm, optional
        Measured critical speeds (003 Table 2: {1: 334, 3: 123}); the entry's ``nd`` is
        then the excited ND whose crossing is nearest.
    rel_threshold : float
        NDs whose content is below this fraction of the largest at that harmonic are not
        counted as excited.

    Returns
    -------
    list of dict
        Per order: ``order``, ``harmonic`` (p o), ``nd`` (selected ND: nearest crossing to
        the measured speed if given, else the largest content), ``rule``,
        ``excited_nds``, ``nd_content_N`` (per excited ND, the larger of the forward and
        backward components), ``forward_backward_ratio`` (per excited ND, 1 for a standing
        wave), ``stationary_rule_nd``,
        ``crossing_rpm`` (per excited ND, if ``branch_hz``), ``order_force_N`` (the
        largest component at that harmonic).
    """
    rig = ElectromagnetRig() if rig is None else rig
    N = int(rig.n_blades)
    p = rig.pulses_per_rev if rig.synchronous else rig.n_magnets
    c = engine_order_content(rig.forces(samples))
    out = []
    for o in orders:
        n = p * int(o)
        if n >= samples // 2:
            raise ModelError(f"order {o}: harmonic {n} beyond the sampling ({samples})")
        row = np.abs(c[n])                                  # forward k at +n
        amp = {k: float(max(row[k], row[(N - k) % N])) for k in range(N // 2 + 1)}
        top = max(amp.values())
        excited = [k for k, a in amp.items() if top > 0 and a >= rel_threshold * top]
        # forward / backward components of each excited ND (1: a standing wave)
        fb = {str(k): float(row[k] / row[(N - k) % N]) if row[(N - k) % N] > 0 else np.inf
              for k in excited if 0 < k < N - k}
        entry = {"order": int(o), "harmonic": n, "pulses": p, "excited_nds": excited,
                 "nd_content_N": {str(k): amp[k] for k in excited},
                 "forward_backward_ratio": fb, "order_force_N": float(top),
                 "stationary_rule_nd": stationary_alias_nd(n, N)}
        if rig.synchronous:
            entry["rule"] = ("rotor-synchronous pulses: force fixed to the blades passing the "
                             "firing magnets (blades 0 and 15), time harmonics n = p o only, "
                             "every even ND as a standing wave; the resonating ND is the one "
                             "whose branch meets f = p o n / 60")
        else:
            entry["rule"] = ("stationary pattern: revolution harmonic n excites ND k = +-n "
                             "(mod N)")
        nd_sel = max(excited, key=lambda k: amp[k]) if excited else None
        if branch_hz is not None and excited:
            cross = {}
            for k in excited:
                rpm = 300.0
                for _ in range(30):
                    rpm_new = 60.0 * branch_hz(k, rpm) / n
                    if abs(rpm_new - rpm) < 1e-6:
                        break
                    rpm = rpm_new
                cross[str(k)] = float(rpm_new)
            entry["crossing_rpm"] = cross
            if measured_rpm and int(o) in measured_rpm:
                m = float(measured_rpm[int(o)])
                nd_sel = int(min(excited, key=lambda k: abs(cross[str(k)] - m)))
                entry["measured_rpm"] = m
        entry["nd"] = None if nd_sel is None else int(nd_sel)
        out.append(entry)
    return out
