"""Command line of the joint identification: ``fricdamp identify SIGNALS --rig RIG.toml``.

::

    fricdamp identify signals.csv --rig rig.toml --out DIR [--frequency 30] [--periods 20]
                      [--kinematics paper|exact] [--format auto|csv|uff]
                      [--sample-rate HZ] [--skip-rows N] [--time-column NAME]
                      [--time-unit ms] [--sensitivity A=10.35,B=10.79,C=10.29]
                      [--skip-periods auto|N] [--no-diagnostics]

Runs paper 002's post-processing (:func:`fricdamp.signals.identify.identify_joint`) on measured
accelerations -- a CSV table (time + channels, units in the header) or a Universal File
(dataset 58) -- and writes ``identification.json`` (dissipated energy, damping ratios, their
95 % confidence intervals, block scatter, conditioning, status and warnings),
``summary.json`` (the same and the inputs), ``loop.csv`` (one period of the loop, averaged over
the periods analysed) and ``loop.png`` into ``DIR``. The page
"Identify a joint from accelerations" of the fricdamp documentation explains every key.

The rig file (TOML, unknown keys rejected)::

    [rig]                          # paper 002 Fig. 6, eqs (7), (10); positions along the beams
    beam1_length_m = 0.200         # l1
    beam2_length_m = 0.200         # l2
    joint_offset_m = 0.009         # h: joint axis from the end of each beam
    beam2_mass_kg = 0.4396         # m2
    sensor_mass_kg = 0.00994       # m_c (one accelerometer)
    sensor_a_m = -0.090            # d1: A on beam 1, from G1 towards the joint
    sensor_b_m = 0.0               # d2: B on beam 1
    sensor_c_m = 0.090             # d4: C on beam 2, from G2 away from the joint
    # beam2_inertia_kg_m2 = 1.55e-3   optional: overrides I2 = m2 l2^2/12 + m_c d4^2
    # gravity_m_per_s2 = 9.81         optional

    [channels]                     # optional: the columns of A, B, C (default "A", "B", "C")
    A = "acc_A"
    B = "acc_B"
    C = "acc_C"
    # unit = "g"                   optional: unit of the three channels (overrides the file)
    # sensitivity_mV_per_g = {A = 10.35, B = 10.79, C = 10.29}   voltage channels (mV or V)
    # force = "force"              optional: the shaker's force column (needs [shaker])
    # force_unit = "N"             N, kN, mN, lbf, kgf, or mV/V with force_sensitivity_mV_per_N
    # force_sensitivity_mV_per_N = 100.0

    [shaker]                       # optional: beam 1 and its suspension; with a force column
    beam1_mass_kg = 0.4396         # m1 (with its sensors' mass in I1 below)
    shaker_arm_m = -0.100          # d_F: D on beam 1, from G1 towards the joint
    # beam1_inertia_kg_m2 = 1.55e-3     optional: overrides I1 = m1 l1^2/12 + m_c (d1^2 + d2^2)
    # suspension_stiffness_N_per_m = 0.0            k_x (the rig's known suspension of G1)
    # suspension_damping_N_s_per_m = 0.0            c_x
    # suspension_torsional_stiffness_N_m_per_rad = 0.0   k_t
    # suspension_torsional_damping_N_m_s_per_rad = 0.0   c_t

    [input]                        # optional: how to read a CSV (command-line options override)
    # sample_rate_hz = 5120.0      time = k / rate (files with a sample index or no time)
    # skip_rows = 0                metadata lines before the header
    # time_column = "Time"         name (or 0-based index) of the time column
    # time_unit = "ms"             s, ms, us, ns or min (overrides the header)

    [processing]                   # optional (the command-line options override it)
    frequency_hz = 30.0            # default: estimated from the signals
    periods = 20                   # last whole periods analysed; default all after the
                                   # start-up transient
    skip_periods = "auto"          # start-up transient: "auto" (default) or a number
    kinematics = "paper"           # or "exact"
    gravity_sensing = false        # with "exact": sensors read g sin(theta)
    filter = "harmonic"            # or "highpass"
    # n_harmonics = 20
    # f_low_hz = 15.0

    [trust]                        # optional: the diagnostics (defaults shown)
    # diagnostics = true
    # position_std_m = 0.5e-3      sensor positions, one sigma
    # sensitivity_std = 0.005      relative, one sigma
    # delay_std_s = 1e-6           channel delays, one sigma
    # noise = true                 fresh noise at the record's level in each draw
    # samples = 1000               Monte Carlo draws
    # seed = 0
    # max_relative_width = 0.2     flag when the 95 % interval of E_d is wider than this x E_d
    # max_block_scatter = 0.1      ... or the block energies scatter more than this
    # block_periods = 3
    # min_blocks = 5
    # min_conditioning = 0.01      warn when joint/beam rotation is below this
    # max_torque_discrepancy = 0.02  with a force channel: torque from the force vs 002 (8)
    # max_energy_imbalance = 0.02    ... and |W_in - E_rig - E_d| / W_in

Exit codes: 0 success; 3 identified but **unreliable** (the outputs are written; the
warnings say why: 95 % interval of the energy wider than the limit or including zero,
block scatter above the limit, negative loop, with a force channel the two torques or the
energy balance disagreeing beyond their limits); 2 invalid input (one line on stderr naming
the key or file and what is allowed); 1 internal error.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Annotated, Literal

from pydantic import Field

from fricdamp._version import __version__
from fricdamp.case import Section, validate_section
from fricdamp.errors import CaseError, ModelError

__all__ = ["ChannelsSection", "InputSection", "ProcessingSection", "RigFile", "RigSection",
           "ShakerSection", "TrustSection", "add_subparsers", "driven_beam", "handle_identify",
           "load_rig_file", "main"]

EXIT_OK, EXIT_FAILURE, EXIT_INVALID, EXIT_UNRELIABLE = 0, 1, 2, 3

Positive = Annotated[float, Field(gt=0)]
NonNegative = Annotated[float, Field(ge=0)]


class RigSection(Section):
    """``[rig]``: what the identification needs to know about the test structure."""

    beam1_length_m: Positive
    beam2_length_m: Positive
    joint_offset_m: NonNegative
    beam2_mass_kg: Positive
    sensor_mass_kg: NonNegative
    sensor_a_m: float
    sensor_b_m: float
    sensor_c_m: float
    beam2_inertia_kg_m2: Positive | None = None
    gravity_m_per_s2: NonNegative = 9.81


class SensitivitySection(Section):
    """``sensitivity_mV_per_g``: per accelerometer [mV/g], for voltage channels."""

    A: Positive | None = None
    B: Positive | None = None
    C: Positive | None = None


class ChannelsSection(Section):
    """``[channels]``: column names of the accelerometers, a common unit, sensitivities."""

    A: str = "A"
    B: str = "B"
    C: str = "C"
    unit: str | None = None
    sensitivity_mV_per_g: SensitivitySection | None = None
    force: str | None = None
    force_unit: str | None = None
    force_sensitivity_mV_per_N: Positive | None = None


class ShakerSection(Section):
    """``[shaker]``: beam 1, the shaker's position and the suspension (force channel)."""

    beam1_mass_kg: Positive
    shaker_arm_m: float
    beam1_inertia_kg_m2: Positive | None = None
    suspension_stiffness_N_per_m: NonNegative = 0.0
    suspension_damping_N_s_per_m: NonNegative = 0.0
    suspension_torsional_stiffness_N_m_per_rad: NonNegative = 0.0
    suspension_torsional_damping_N_m_s_per_rad: NonNegative = 0.0


class InputSection(Section):
    """``[input]``: how to read a CSV file."""

    sample_rate_hz: Positive | None = None
    skip_rows: Annotated[int, Field(ge=0)] = 0
    time_column: str | Annotated[int, Field(ge=0)] | None = None
    time_unit: Literal["s", "ms", "us", "ns", "min"] | None = None


class ProcessingSection(Section):
    """``[processing]``: options of :func:`fricdamp.signals.identify.identify_joint`."""

    frequency_hz: Positive | None = None
    periods: Annotated[int, Field(ge=1)] | None = None
    kinematics: Literal["paper", "exact"] = "paper"
    gravity_sensing: bool = False
    filter: Literal["harmonic", "highpass"] = "harmonic"
    n_harmonics: Annotated[int, Field(ge=1)] | None = None
    f_low_hz: Positive | None = None
    skip_periods: Literal["auto"] | Annotated[int, Field(ge=0)] = "auto"


class TrustSection(Section):
    """``[trust]``: the diagnostics (defaults: those of the library's dataclasses)."""

    diagnostics: bool = True
    position_std_m: NonNegative | None = None
    sensitivity_std: NonNegative | None = None
    delay_std_s: NonNegative | None = None
    noise: bool | None = None
    samples: Annotated[int, Field(ge=20)] | None = None
    seed: Annotated[int, Field(ge=0)] | None = None
    max_relative_width: Positive | None = None
    max_block_scatter: Positive | None = None
    block_periods: Annotated[int, Field(ge=1)] | None = None
    min_blocks: Annotated[int, Field(ge=2)] | None = None
    min_conditioning: NonNegative | None = None
    max_torque_discrepancy: Positive | None = None
    max_energy_imbalance: Positive | None = None

    def objects(self):
        """``(MeasurementUncertainty, TrustThresholds)`` with the keys given."""
        from fricdamp.signals.identify import MeasurementUncertainty, TrustThresholds

        given = {k: v for k, v in self.model_dump().items() if v is not None}
        unc = {k: given[k] for k in ("position_std_m", "sensitivity_std", "delay_std_s",
                                     "noise", "samples", "seed") if k in given}
        thr = {k: given[k] for k in ("max_relative_width", "max_block_scatter",
                                     "block_periods", "min_blocks", "min_conditioning",
                                     "max_torque_discrepancy", "max_energy_imbalance")
               if k in given}
        return MeasurementUncertainty(**unc), TrustThresholds(**thr)


class RigFile(Section):
    """A rig file: ``[rig]``, optional ``[channels]``, ``[shaker]``, ``[input]``,
    ``[processing]``, ``[trust]``."""

    rig: RigSection
    channels: ChannelsSection = ChannelsSection()
    shaker: ShakerSection | None = None
    input: InputSection = InputSection()
    processing: ProcessingSection = ProcessingSection()
    trust: TrustSection = TrustSection()


def load_rig_file(path):
    """Read and validate a rig TOML file; return ``(RigFile, JointRigGeometry)``.

    Raises
    ------
    CaseError
        Missing file, TOML syntax error, unknown key, wrong type or a value out of range
        (naming the table and the key), or a geometry the identification cannot use.
    """
    import tomllib

    from fricdamp.iofiles import read_regular_file
    from fricdamp.signals.identify import JointRigGeometry

    p = Path(path)
    try:
        data = tomllib.loads(read_regular_file(p, what="rig file").decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise CaseError(f"{str(p)!r} is not valid TOML: {exc}") from None
    spec = validate_section(RigFile, data, "")
    r = spec.rig
    for name, length in (("beam1_length_m", r.beam1_length_m),
                         ("beam2_length_m", r.beam2_length_m)):
        if r.joint_offset_m >= 0.5 * length:
            raise CaseError(f"{p.name}: [rig] joint_offset_m must be < {name} / 2 = "
                            f"{0.5 * length:g} m, got {r.joint_offset_m:g}")
    for name, value, length in (("sensor_a_m", r.sensor_a_m, r.beam1_length_m),
                                ("sensor_b_m", r.sensor_b_m, r.beam1_length_m),
                                ("sensor_c_m", r.sensor_c_m, r.beam2_length_m)):
        if abs(value) > 0.5 * length:
            raise CaseError(f"{p.name}: [rig] {name} must lie on its beam, in "
                            f"[{-0.5 * length:g}, {0.5 * length:g}] m, got {value:g}")
    inertia = r.beam2_inertia_kg_m2
    if inertia is None:
        inertia = r.beam2_mass_kg * r.beam2_length_m ** 2 / 12.0 \
            + r.sensor_mass_kg * r.sensor_c_m ** 2  # 002 (10)
    try:
        geom = JointRigGeometry(
            sensor_a=r.sensor_a_m, sensor_b=r.sensor_b_m,
            joint_arm1=0.5 * r.beam1_length_m - r.joint_offset_m, sensor_c=r.sensor_c_m,
            joint_arm2=0.5 * r.beam2_length_m - r.joint_offset_m, beam2_mass=r.beam2_mass_kg,
            beam2_inertia=inertia, gravity=r.gravity_m_per_s2)
    except ModelError as exc:
        raise CaseError(f"{p.name}: [rig] {exc}") from None
    if spec.channels.force is not None and spec.shaker is None:
        raise CaseError(f"{p.name}: [channels] force = {spec.channels.force!r} needs a "
                        "[shaker] table (beam1_mass_kg, shaker_arm_m, suspension) for the "
                        "torque from the force and the energy balance")
    try:
        driven_beam(spec)
    except ModelError as exc:
        raise CaseError(f"{p.name}: [shaker] {exc}") from None
    except CaseError as exc:
        raise CaseError(f"{p.name}: {exc}") from None
    return spec, geom


def driven_beam(spec):
    """The :class:`~fricdamp.signals.identify.DrivenBeam` of a rig file's ``[shaker]``
    (None without one); I1 defaults to ``m1 l1^2/12 + m_c (d1^2 + d2^2)``, 002 (9)."""
    from fricdamp.signals.identify import DrivenBeam

    sh, r = spec.shaker, spec.rig
    if sh is None:
        return None
    if abs(sh.shaker_arm_m) > 0.5 * r.beam1_length_m:
        raise CaseError(f"[shaker] shaker_arm_m must lie on beam 1, in "
                        f"[{-0.5 * r.beam1_length_m:g}, {0.5 * r.beam1_length_m:g}] m, got "
                        f"{sh.shaker_arm_m:g}")
    inertia = sh.beam1_inertia_kg_m2
    if inertia is None:
        inertia = sh.beam1_mass_kg * r.beam1_length_m ** 2 / 12.0 + r.sensor_mass_kg * (
            r.sensor_a_m ** 2 + r.sensor_b_m ** 2)  # 002 (9)
    return DrivenBeam(sh.beam1_mass_kg, inertia, sh.shaker_arm_m,
                      sh.suspension_stiffness_N_per_m, sh.suspension_damping_N_s_per_m,
                      sh.suspension_torsional_stiffness_N_m_per_rad,
                      sh.suspension_torsional_damping_N_m_s_per_rad)


def read_signals(path, fmt: str = "auto", **csv_options):
    """Read a CSV or UFF signal file (``fmt`` "auto" decides by the extension).

    ``csv_options`` (``sample_rate``, ``skip_rows``, ``time_column``, ``time_unit``) go to
    :func:`fricdamp.signals.records.read_signals_csv`; a UFF file carries its own time base,
    so they are refused for it.
    """
    p = Path(path)
    if fmt == "auto":
        fmt = "uff" if p.suffix.lower() in (".uff", ".unv", ".uf", ".bunv") else "csv"
    given = {k: v for k, v in csv_options.items() if v not in (None, 0)}
    if fmt == "uff":
        from fricdamp.signals.uff import read_signals_uff

        if given:
            raise CaseError(f"{p.name} is a Universal File: {', '.join(sorted(given))} apply "
                            "to CSV files only (a UFF dataset 58 carries its time base)")
        return read_signals_uff(p)
    from fricdamp.signals.records import read_signals_csv

    return read_signals_csv(p, **{k: v for k, v in csv_options.items() if v is not None})


def add_subparsers(subparsers) -> None:
    """Add the ``identify`` command to an argparse subparsers object.

    Sets ``func`` (and ``handler``) to :func:`handle_identify`, which takes the parsed
    arguments and returns the exit code.
    """
    s = subparsers.add_parser(
        "identify", help="torque-rotation loop of a joint from three accelerometers "
                         "(paper 002)",
        description="Run paper 002's post-processing on measured accelerations (CSV with "
                    "units in the header, or Universal File dataset 58): kinematics, "
                    "FFT integration over whole periods after the start-up transient, joint "
                    "torque, loop area and damping ratios, with diagnostics (block scatter, "
                    "conditioning, 95 % confidence intervals from a Monte Carlo of sensor "
                    "positions, sensitivities, delays and noise). Writes identification.json, "
                    "summary.json, loop.csv and loop.png.",
        epilog="Exit codes: 0 identified; 3 identified but unreliable (outputs written, the "
               "warnings say why); 2 invalid input; 1 internal error. Keys: the page "
               "\"Identify a joint from accelerations\" of the fricdamp documentation.")
    s.add_argument("signals", help="signal file: CSV (time + channels) or UFF (.uff/.unv)")
    s.add_argument("--rig", required=True, metavar="RIG.toml",
                   help="rig geometry, channel names and processing options (TOML)")
    s.add_argument("--out", metavar="DIR", help="output folder (default: "
                   "./fricdamp-out/identify-<signals file stem>)")
    s.add_argument("--frequency", type=float, metavar="HZ",
                   help="excitation frequency (default: [processing] or estimated)")
    s.add_argument("--periods", type=int, metavar="N",
                   help="last whole periods analysed (default: [processing] or all after the "
                        "start-up transient)")
    s.add_argument("--skip-periods", metavar="auto|N",
                   help="leading periods dropped as start-up transient (default: "
                        "[processing] or auto-detected)")
    s.add_argument("--kinematics", choices=("paper", "exact"),
                   help="linear kinematics of the paper, or exact (default: [processing])")
    s.add_argument("--format", choices=("auto", "csv", "uff"), default="auto",
                   help="signal file format (default: by extension)")
    s.add_argument("--sample-rate", type=float, metavar="HZ",
                   help="CSV: sampling rate; the time is k / rate (for files with a sample "
                        "index or without time)")
    s.add_argument("--skip-rows", type=int, metavar="N",
                   help="CSV: metadata lines before the header (default: [input] or 0)")
    s.add_argument("--time-column", metavar="NAME|INDEX",
                   help="CSV: the time column (default: by name, else the first column)")
    s.add_argument("--time-unit", choices=("s", "ms", "us", "ns", "min"),
                   help="CSV: unit of the time column (overrides the header)")
    s.add_argument("--sensitivity", metavar="A=S,B=S,C=S",
                   help="sensitivities [mV/g] of voltage channels (mV or V), e.g. "
                        "A=10.35,B=10.79,C=10.29")
    s.add_argument("--position-std", type=float, metavar="M",
                   help="uncertainty (one sigma) of the sensor positions (default 0.5e-3 m)")
    s.add_argument("--sensitivity-std", type=float, metavar="FRACTION",
                   help="relative uncertainty of the sensitivities (default 0.005)")
    s.add_argument("--delay-std", type=float, metavar="S",
                   help="uncertainty of the channel delays (default 1e-6 s)")
    s.add_argument("--no-diagnostics", action="store_true",
                   help="skip the diagnostics (no confidence intervals, never exit 3)")
    s.add_argument("--traceback", action="store_true",
                   help="show the Python traceback of internal errors")
    s.add_argument("-v", "--verbose", action="store_true", help="log what happens")
    s.set_defaults(func=handle_identify, handler=handle_identify)


def _out(msg: str) -> None:
    print(msg, flush=True)


def _err(msg: str) -> None:
    print(f"fricdamp: error: {msg}", file=sys.stderr)


def _warn(msg: str) -> None:
    print(f"fricdamp: warning: {msg}", file=sys.stderr)


def _sensitivities(text: str) -> dict:
    """``"A=10.35,B=10.79"`` -> ``{"A": 10.35, "B": 10.79}`` (CaseError naming the option)."""
    out = {}
    for part in filter(None, (p.strip() for p in text.split(","))):
        role, sep, value = part.partition("=")
        role = role.strip().upper()
        try:
            val = float(value)
        except ValueError:
            val = float("nan")
        if not sep or role not in ("A", "B", "C") or not val > 0 or val == float("inf"):
            raise CaseError(f"--sensitivity must be like A=10.35,B=10.79,C=10.29 (mV/g > 0 "
                            f"for A, B, C), got {text!r}")
        out[role] = val
    return out


def _options(args, spec):
    """Processing, reading and diagnostic options: the rig file, overridden by the flags."""
    from dataclasses import replace

    proc = spec.processing.model_dump()
    if args.frequency is not None:
        if not args.frequency > 0:
            raise CaseError(f"--frequency must be > 0 Hz, got {args.frequency:g}")
        proc["frequency_hz"] = args.frequency
    if args.periods is not None:
        if args.periods < 1:
            raise CaseError(f"--periods must be an integer >= 1, got {args.periods}")
        proc["periods"] = args.periods
    if args.skip_periods is not None:
        text = args.skip_periods.strip().lower()
        if text != "auto" and not (text.isdigit()):
            raise CaseError(f"--skip-periods must be 'auto' or an integer >= 0, got "
                            f"{args.skip_periods!r}")
        proc["skip_periods"] = "auto" if text == "auto" else int(text)
    if args.kinematics is not None:
        proc["kinematics"] = args.kinematics
    inp = spec.input
    csv = {"sample_rate": inp.sample_rate_hz, "skip_rows": inp.skip_rows,
           "time_column": inp.time_column, "time_unit": inp.time_unit}
    if args.sample_rate is not None:
        if not args.sample_rate > 0:
            raise CaseError(f"--sample-rate must be > 0 Hz, got {args.sample_rate:g}")
        csv["sample_rate"] = args.sample_rate
    if args.skip_rows is not None:
        if args.skip_rows < 0:
            raise CaseError(f"--skip-rows must be an integer >= 0, got {args.skip_rows}")
        csv["skip_rows"] = args.skip_rows
    if args.time_column is not None:
        tc = args.time_column
        csv["time_column"] = int(tc) if tc.isdigit() else tc
    if args.time_unit is not None:
        csv["time_unit"] = args.time_unit
    sens = {}
    if spec.channels.sensitivity_mV_per_g is not None:
        sens = {k: v for k, v in spec.channels.sensitivity_mV_per_g.model_dump().items()
                if v is not None}
    if args.sensitivity is not None:
        sens.update(_sensitivities(args.sensitivity))
    unc, thr = spec.trust.objects()
    for flag, key in (("position_std", "position_std_m"), ("sensitivity_std",
                                                            "sensitivity_std"),
                      ("delay_std", "delay_std_s")):
        value = getattr(args, flag)
        if value is not None:
            if not value >= 0 or value == float("inf"):
                raise CaseError(f"--{flag.replace('_', '-')} must be >= 0, got {value:g}")
            unc = replace(unc, **{key: value})
    proc.update(diagnostics=spec.trust.diagnostics and not args.no_diagnostics,
                uncertainty=unc, thresholds=thr)
    return proc, csv, sens


def handle_identify(args) -> int:
    """``fricdamp identify``: run the pipeline, write the outputs; return the exit code."""
    from fricdamp.iofiles import OutputLock, prepare_output_folder

    spec, geom = load_rig_file(args.rig)
    proc, csv, sens = _options(args, spec)
    table = read_signals(args.signals, args.format, **csv)
    out = Path(args.out) if args.out else Path("fricdamp-out") / \
        f"identify-{Path(args.signals).stem}"
    # the folder is created, write-tested and locked before anything is computed
    prepare_output_folder(out)
    with OutputLock(out, "identify"):
        return _identify(args, spec, geom, proc, sens, table, out)


def _verdict(ident, d: dict):
    """The identification's :class:`~fricdamp.verdict.Verdict`: ``unreliable`` with its
    warnings as reasons, else ``ok`` (also without diagnostics when no check found
    anything); estimates: the diagnostics' numbers."""
    from fricdamp.verdict import OK, UNRELIABLE, Verdict

    keys = ("dissipated_energy_J", "confidence_relative_width", "block_scatter",
            "cycle_energy_relative_spread", "filtered_fraction")
    est = {k: d[k] for k in keys if isinstance(d.get(k), (int, float))}
    est["diagnostics"] = ident.trust is not None
    if ident.force_check is not None:
        est["torque_from_force_rms_difference"] = d["torque_from_force"][
            "torque_relative_rms_difference"]
        est["energy_balance_residual"] = d["energy_balance"]["residual_relative_to_input"]
    if ident.status == "unreliable":
        return Verdict(UNRELIABLE, tuple(ident.warnings), est)
    return Verdict(OK, (), est)


def _identify(args, spec, geom, proc, sens, table, out: Path) -> int:
    import numpy as np

    from fricdamp.cli._common import say_verdict
    from fricdamp.iofiles import save_figure, write_json, write_text
    from fricdamp.signals.identify import identify_from_table
    from fricdamp.verdict import exit_code, verdict_block

    ch = spec.channels
    beam = driven_beam(spec)
    roles = {"A": ch.A, "B": ch.B, "C": ch.C}
    if beam is not None:
        roles["force"] = ch.force or "force"
    t0 = time.perf_counter()
    ident = identify_from_table(table, geom, channels=roles, units=ch.unit,
                                sensitivity_mV_per_g=sens or None, driven_beam=beam,
                                force_unit=ch.force_unit,
                                force_sensitivity_mV_per_N=ch.force_sensitivity_mV_per_N,
                                **proc)
    elapsed = time.perf_counter() - t0
    d = ident.to_dict()
    verdict = verdict_block({"identification": _verdict(ident, d)})
    code = exit_code(verdict["overall"])
    head = {"fricdamp_version": __version__, "signals": str(args.signals),
            "rig": str(args.rig), "exit_code": code}
    write_json(out / "identification.json", {**head, **d})
    summary = {"verdict": verdict, **head, "identification": d,
               "geometry": {"d1_m": geom.sensor_a, "d2_m": geom.sensor_b,
                            "d3_m": geom.joint_arm1, "d4_m": geom.sensor_c,
                            "d5_m": geom.joint_arm2, "m2_kg": geom.beam2_mass,
                            "I2_kg_m2": geom.beam2_inertia, "g_m_per_s2": geom.gravity},
               "runtime_s": elapsed}
    write_json(out / "summary.json", summary)
    r, f = ident.cycle()
    phase = np.arange(r.size) / r.size
    lines = ["phase [-],rotation [rad],torque [N m]"]
    lines += [f"{a:.6f},{b:.9e},{c:.9e}" for a, b, c in zip(phase, r, f, strict=True)]
    write_text(out / "loop.csv", "\n".join(lines) + "\n")
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    ident.plot(ax)
    ax.set_title(f"{Path(args.signals).name}: {ident.n_periods} periods at "
                 f"{ident.frequency_hz:.4g} Hz")
    fig.tight_layout()
    save_figure(fig, out / "loop.png")
    plt.close(fig)
    _out(f"fricdamp {__version__}: identified {Path(args.signals).name} "
         f"({ident.n_periods} periods at {ident.frequency_hz:.5g} Hz after "
         f"{ident.skipped_periods} start-up periods, {d['kinematics']} kinematics)")
    _out(f"dissipated energy {d['dissipated_energy_J']:.4g} J per cycle, rotation amplitude "
         f"{d['rotation_amplitude_rad']:.4g} rad, torque amplitude "
         f"{d['torque_amplitude_Nm']:.4g} N m, damping ratio (002) {d['damping_ratio']:.4g}, "
         f"energy-based {d['damping_ratio_energy']:.4g}")
    if ident.trust is not None:
        lo, hi = ident.trust.energy_interval
        bs = ident.trust.block_scatter
        _out(f"95 % interval of the energy [{lo:.4g}, {hi:.4g}] J; block scatter "
             f"{'n/a' if bs is None else f'{bs:.3g}'}; joint/beam rotation "
             f"{d['conditioning']['joint_to_beam_rotation']:.3g}; status {ident.status}")
    if ident.force_check is not None:
        fb = d["energy_balance"]
        _out(f"torque from the shaker force: {100 * ident.force_check.torque_discrepancy:.3g}"
             f" % RMS from 002 (8); energy balance: input {fb['input_work_J']:.4g} J, rig "
             f"{fb['rig_dissipation_J']:.4g} J, joint {fb['joint_dissipation_J']:.4g} J, "
             f"residual {100 * fb['residual_relative_to_input']:.3g} % of the input")
    said_last = 1 if verdict["overall"] != "ok" else 0   # the verdict's reason, said last
    for w in ident.warnings[said_last:]:
        _warn(w)
    _out(f"wrote identification.json, summary.json, loop.csv and loop.png to {out}")
    return say_verdict(verdict)


def main(argv: list[str] | None = None) -> int:
    """Run ``identify`` without the main ``fricdamp`` parser (tests, scripts).

    ``python -m fricdamp.cli.identify identify SIGNALS --rig RIG.toml --out DIR``
    """
    from fricdamp.cli.app import main_for

    return main_for(add_subparsers, argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
