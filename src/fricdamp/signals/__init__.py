"""Post-processing: hysteresis loops and energy, damping identification, signals."""

from fricdamp.signals.damping import (
    coulomb_equivalent_ratio,
    energy_damping_ratio,
    equivalent_viscous_damping,
    log_decrement_from_zeta,
    loss_factor,
    paper002_damping_ratio,
    paper002_supplied_energy,
    zeta_from_log_decrement,
)
from fricdamp.signals.decay import (
    CoulombFit,
    DecayResult,
    Envelope,
    Peaks,
    ViscousFit,
    coulomb_envelope_fit,
    decay_damping,
    envelope_hilbert,
    envelope_peaks,
    find_peaks,
    log_decrement,
    viscous_envelope_fit,
)
from fricdamp.signals.energy import (
    dissipated_energy_per_cycle,
    hysteresis_loop,
    loop_area,
    peak_strain_energy,
    steady_cycle,
)
from fricdamp.signals.identify import (
    JointIdentification,
    JointRigGeometry,
    identify_from_table,
    identify_joint,
    joint_torque,
)
from fricdamp.signals.records import SignalTable, fft_integrate, read_signals_csv
from fricdamp.signals.uff import read_signals_uff

__all__ = [
    "JointIdentification",
    "JointRigGeometry",
    "identify_from_table",
    "identify_joint",
    "joint_torque",
    "read_signals_uff",
    "CoulombFit",
    "DecayResult",
    "Envelope",
    "Peaks",
    "SignalTable",
    "ViscousFit",
    "coulomb_envelope_fit",
    "coulomb_equivalent_ratio",
    "decay_damping",
    "dissipated_energy_per_cycle",
    "energy_damping_ratio",
    "envelope_hilbert",
    "envelope_peaks",
    "equivalent_viscous_damping",
    "fft_integrate",
    "find_peaks",
    "hysteresis_loop",
    "log_decrement",
    "log_decrement_from_zeta",
    "loop_area",
    "loss_factor",
    "paper002_damping_ratio",
    "paper002_supplied_energy",
    "peak_strain_energy",
    "read_signals_csv",
    "steady_cycle",
    "viscous_envelope_fit",
    "zeta_from_log_decrement",
]
