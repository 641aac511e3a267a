"""The damping gap of paper 003's beam wheel: what moves zeta(2ND) and zeta(6ND), by how much.

:func:`damping_gap_study` evaluates the damping ratio of the resonant travelling wave at one
amplitude (default 0.5 mm of the contact node, the largest FEM amplitude of 003 Fig. 19)
for the baseline wheel and for controlled changes of one ingredient at a time:

* ``penalty x10`` / ``penalty x0.1``: normal and tangential penalties scaled, the offset
  changed so that the prestress of the wheel at rest stays 2.4 N (003's contact stiffness
  was "automatically calculated" by ANSYS from the local stiffness: unknown);
* ``k_t = 0.1 k_n``: a softer tangential penalty only;
* ``mu = 0.4`` / ``mu = 0.2``: constant friction coefficients instead of 003 (2) (mu_s, and
  mu_d alone: the limits of mu(v));
* ``prestress x2``: offset doubled (4.8 N), the penalty kept;
* ``modal forcing``: the load ``M phi`` of the open-contact ND mode instead of point forces
  at the tie-boss (the "forcing shape");
* ``at rest``: the wheel at rest instead of speed-locked at the critical speed;
* ``tip amplitude``: the same curve read at 0.5 mm of the blade *tip* instead of the
  contact node (the amplitude definition: where the rig's displacement is taken);
* ``standing wave``: the rig's kind of load, a standing ND pattern on the assembled wheel
  (:func:`fricdamp.models.tieboss_wheel.forced.standing_wave_peaks`, full-wheel HB, at rest).

Each entry interpolates (log-log) the resonance-peak ratios of a few load levels
(:func:`fricdamp.models.tieboss_wheel.forced.damping_vs_amplitude`) at the amplitude.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from fricdamp.models.tieboss_wheel.forced import damping_vs_amplitude
from fricdamp.models.tieboss_wheel.model import TiebossSector, build_wheel, prestress_normal_force

__all__ = ["damping_gap_study", "offset_for_prestress"]

#: Load levels [N] bracketing 0.2-1 mm for the baseline wheel (travelling wave, tie-boss).
BASE_FORCES = {2: (0.7, 0.9, 1.2, 1.6), 6: (1.5, 1.8, 2.3, 3.0)}


def offset_for_prestress(sector: TiebossSector, target_N: float = 2.4, *,
                         n_modes: int = 4) -> float:
    """Offset [m] giving ``target_N`` of prestress at rest for the sector's penalties: the
    wheel's normal force is ``g0 / (1 / k_n + c)``, c the structure's compliance; c from one
    static solution, then one secant correction (friction makes it mildly nonlinear)."""
    p = sector.parameters
    g = [p.contact_offset_m]
    n = []
    for _ in range(3):
        q = p.with_(contact_offset_m=g[-1])
        n.append(prestress_normal_force(build_wheel(replace(sector, parameters=q),
                                                    n_modes=n_modes)))
        if abs(n[-1] / target_N - 1) < 1e-3:
            break
        g.append(g[-1] * target_N / n[-1])
    return float(g[-1])


def _zeta_at(entry: dict, amplitude: float, scale: float = 1.0):
    A = np.asarray(entry["amplitude_m"]) * scale
    z = np.asarray(entry["damping_ratio"])
    if A.size < 2:
        return None, False
    inside = bool(A[0] <= amplitude <= A[-1])
    c = np.polyfit(np.log(A), np.log(z), 1) if not inside else None
    val = np.exp(np.interp(np.log(amplitude), np.log(A), np.log(z))) if inside else \
        np.exp(np.polyval(c, np.log(amplitude)))
    return float(val), inside


def damping_gap_study(sector: TiebossSector, *, amplitude_m: float = 5e-4, nds=(2, 6),
                      orders=(1, 3), pulses: int = 8, n_modes: int = 4, harmonics: int = 5,
                      samples: int = 120, variants=None) -> list[dict]:
    """Damping ratio at ``amplitude_m`` per ND for the baseline and each variant.

    Returns
    -------
    list of dict
        ``variant``, ``description``, ``zeta`` {"2": ..., "6": ...}, ``change``
        (relative to the baseline), ``interpolated`` (False: extrapolated from the
        log-log fit of the load levels), ``parameters`` changed.
    """
    from fricdamp.contact.element3d import Contact3D
    from fricdamp.structure.cyclic import nodal_diameter_modes

    p = sector.parameters
    kn = p.normal_stiffness_N_per_m

    def with_params(**kw):
        return replace(sector, parameters=p.with_(**kw))

    def penalty(f):
        s = with_params(normal_stiffness_N_per_m=kn * f, tangential_stiffness_N_per_m=kn * f)
        return with_params(normal_stiffness_N_per_m=kn * f, tangential_stiffness_N_per_m=kn * f,
                           contact_offset_m=offset_for_prestress(s, p.contact_preload_N,
                                                                 n_modes=n_modes))

    def const_mu(mu):
        return Contact3D(kn, p.tangential_stiffness, mu, offset=p.contact_offset_m,
                         n_contacts=1)

    all_variants = {
        "baseline": ("003's law and prestress, k_t = k_n calibrated for 2.4 N, point forces "
                     "at the tie-boss, speed-locked, contact-node amplitude", {}),
        "penalty x10": ("k_n = k_t x 10, offset reset for 2.4 N", {"sector": lambda: penalty(
            10.0)}),
        "penalty x0.1": ("k_n = k_t x 0.1, offset reset for 2.4 N", {"sector": lambda: penalty(
            0.1)}),
        "k_t = 0.1 k_n": ("softer tangential penalty only (prestress unchanged)",
                          {"sector": lambda: with_params(tangential_stiffness_N_per_m=0.1 * kn),
                           "force_scale": 1.0}),
        "mu = 0.4": ("constant mu = mu_s (no drop with the sliding speed)",
                     {"law": lambda: const_mu(0.4)}),
        "mu = 0.2": ("constant mu = mu_d", {"law": lambda: const_mu(0.2),
                                            "force_scale": 0.5}),
        "prestress x2": ("offset doubled (4.8 N), penalty kept",
                         {"sector": lambda: with_params(contact_offset_m=2 * p.contact_offset_m),
                          "force_scale": 2.0}),
        "modal forcing": ("load M phi of the open-contact mode instead of tie-boss points",
                          {"modal": True}),
        "at rest": ("wheel at rest (no stress stiffening / spin softening)", {"rest": True}),
        "tip amplitude": ("the baseline read at 0.5 mm of the blade tip", {"tip": True}),
        "standing wave": ("the rig's kind of load: F cos(2 pi nd j / N) per blade, full-wheel "
                          "HB at rest, H = 3, antinode amplitude", {"standing": True}),
    }
    names = list(all_variants) if variants is None else ["baseline", *[
        v for v in variants if v != "baseline"]]
    rows = []
    base = {}
    cache = {}
    for name in names:
        desc, opt = all_variants[name]
        sec = opt["sector"]() if "sector" in opt else sector
        law = opt["law"]() if "law" in opt else None
        fs = opt.get("force_scale", 1.0)
        zetas, inside = {}, {}
        for nd, o in zip(nds, orders, strict=True):
            forces = [fs * f for f in BASE_FORCES.get(nd, (1.0, 1.5, 2.0, 3.0))]
            key = ("tip" if opt.get("tip") else name, nd)
            if opt.get("standing"):
                from fricdamp.models.tieboss_wheel.forced import standing_wave_peaks

                band = {2: (43.0, 46.5), 6: (47.5, 50.5)}.get(nd, (40.0, 52.0))
                e = standing_wave_peaks(sec, nd, forces, n_modes=n_modes,
                                        frequency_range_hz=band)
                z, ok = _zeta_at(e, amplitude_m)
            elif opt.get("tip"):
                e = cache[("baseline", nd)]
                ratio = np.nanmean([r for r in e["tip_ratio"] if r is not None])
                z, ok = _zeta_at(e, amplitude_m, scale=ratio)
            else:
                kw = {}
                if law is not None:
                    kw["law"] = law
                if opt.get("modal"):
                    w = build_wheel(sec, n_modes=n_modes)
                    cyc = w.cyclic
                    ndh = (-nd) % cyc.n_sectors
                    phi = nodal_diameter_modes(cyc, ndh, 1).shapes[:, 0]
                    f = np.asarray(cyc.M @ phi).ravel()
                    # same generalised force on the mode as the tie-boss baseline
                    tb = np.zeros(cyc.n_dof, complex)
                    tb[np.asarray(cyc.named_dofs["tieboss"])] = sec.flexural_direction
                    f = f * abs(np.vdot(phi, tb)) / abs(np.vdot(phi, f))
                    kw["force_vector"] = f
                e = damping_vs_amplitude(sec, nd, forces, order=None if opt.get("rest") else o,
                                         pulses=pulses, n_modes=n_modes, harmonics=harmonics,
                                         samples=samples, **kw)
                cache[key] = e
                z, ok = _zeta_at(e, amplitude_m)
            zetas[str(nd)], inside[str(nd)] = z, ok
        if name == "baseline":
            base = zetas
        rows.append({"variant": name, "description": desc, "zeta": zetas,
                     "change": {k: (v / base[k] - 1.0) if v is not None and base.get(k)
                                else None for k, v in zetas.items()},
                     "interpolated": inside})
    return rows
