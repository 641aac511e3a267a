"""Command line of the joint identification: ``fricdamp identify SIGNALS --rig RIG.toml``.

::

    fricdamp identify signals.csv --rig rig.toml --out DIR [--frequency 30] [--periods 20]
                      [--kinematics paper|exact] [--format auto|csv|uff]

Runs paper 002's post-processing (:func:`fricdamp.analysis.identify.identify_joint`) on measured
accelerations -- a CSV table (time + channels, units in the header) or a Universal File
(dataset 58) -- and writes ``summary.json`` (dissipated energy, rotation and torque amplitudes,
paper 002's damping ratio), ``loop.csv`` (one period of the loop, averaged over the periods
analysed) and ``loop.png`` into ``DIR``.

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

    [processing]                   # optional (the command-line options override it)
    frequency_hz = 30.0            # default: estimated from the signals
    periods = 20                   # last whole periods analysed; default all
    kinematics = "paper"           # or "exact"
    gravity_sensing = false        # with "exact": sensors read g sin(theta)
    filter = "harmonic"            # or "highpass"
    # n_harmonics = 20
    # f_low_hz = 15.0

Exit codes: 0 success, 2 invalid input (one line on stderr naming the key or file and what
is allowed), 1 internal error.
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

__all__ = ["ChannelsSection", "ProcessingSection", "RigFile", "RigSection", "add_subparsers",
           "handle_identify", "load_rig_file", "main"]

EXIT_OK, EXIT_FAILURE, EXIT_INVALID = 0, 1, 2

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


class ChannelsSection(Section):
    """``[channels]``: column names of the accelerometers and an optional common unit."""

    A: str = "A"
    B: str = "B"
    C: str = "C"
    unit: str | None = None


class ProcessingSection(Section):
    """``[processing]``: options of :func:`fricdamp.analysis.identify.identify_joint`."""

    frequency_hz: Positive | None = None
    periods: Annotated[int, Field(ge=1)] | None = None
    kinematics: Literal["paper", "exact"] = "paper"
    gravity_sensing: bool = False
    filter: Literal["harmonic", "highpass"] = "harmonic"
    n_harmonics: Annotated[int, Field(ge=1)] | None = None
    f_low_hz: Positive | None = None


class RigFile(Section):
    """A rig file: ``[rig]``, optional ``[channels]`` and ``[processing]``."""

    rig: RigSection
    channels: ChannelsSection = ChannelsSection()
    processing: ProcessingSection = ProcessingSection()


def load_rig_file(path):
    """Read and validate a rig TOML file; return ``(RigFile, JointRigGeometry)``.

    Raises
    ------
    CaseError
        Missing file, TOML syntax error, unknown key, wrong type or a value out of range
        (naming the table and the key), or a geometry the identification cannot use.
    """
    import tomllib

    from fricdamp.analysis.identify import JointRigGeometry

    p = Path(path)
    if not p.is_file():
        raise CaseError(f"rig file {str(p)!r} does not exist")
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8"))
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
    return spec, geom


def read_signals(path, fmt: str = "auto"):
    """Read a CSV or UFF signal file (``fmt`` "auto" decides by the extension)."""
    p = Path(path)
    if fmt == "auto":
        fmt = "uff" if p.suffix.lower() in (".uff", ".unv", ".uf", ".bunv") else "csv"
    if fmt == "uff":
        from fricdamp.analysis.uff import read_signals_uff

        return read_signals_uff(p)
    from fricdamp.analysis.signals import read_signals_csv

    return read_signals_csv(p)


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
                    "FFT integration over whole periods, joint torque, loop area and damping "
                    "ratio. Writes summary.json, loop.csv and loop.png.")
    s.add_argument("signals", help="signal file: CSV (time + channels) or UFF (.uff/.unv)")
    s.add_argument("--rig", required=True, metavar="RIG.toml",
                   help="rig geometry, channel names and processing options (TOML)")
    s.add_argument("--out", metavar="DIR", help="output folder (default: "
                   "./fricdamp-out/identify-<signals file stem>)")
    s.add_argument("--frequency", type=float, metavar="HZ",
                   help="excitation frequency (default: [processing] or estimated)")
    s.add_argument("--periods", type=int, metavar="N",
                   help="last whole periods analysed (default: [processing] or all)")
    s.add_argument("--kinematics", choices=("paper", "exact"),
                   help="linear kinematics of the paper, or exact (default: [processing])")
    s.add_argument("--format", choices=("auto", "csv", "uff"), default="auto",
                   help="signal file format (default: by extension)")
    s.add_argument("--traceback", action="store_true",
                   help="show the Python traceback of internal errors")
    s.add_argument("-v", "--verbose", action="store_true", help="log what happens")
    s.set_defaults(func=handle_identify, handler=handle_identify)


def _out(msg: str) -> None:
    print(msg, flush=True)


def _err(msg: str) -> None:
    print(f"fricdamp: error: {msg}", file=sys.stderr)


def handle_identify(args) -> int:
    """``fricdamp identify``: run the pipeline, write the outputs; return the exit code."""
    import numpy as np

    from fricdamp.analysis.identify import identify_from_table
    from fricdamp.iofiles import save_figure, write_json, write_text

    spec, geom = load_rig_file(args.rig)
    proc = spec.processing.model_dump()
    if args.frequency is not None:
        if not args.frequency > 0:
            raise CaseError(f"--frequency must be > 0 Hz, got {args.frequency:g}")
        proc["frequency_hz"] = args.frequency
    if args.periods is not None:
        if args.periods < 1:
            raise CaseError(f"--periods must be an integer >= 1, got {args.periods}")
        proc["periods"] = args.periods
    if args.kinematics is not None:
        proc["kinematics"] = args.kinematics
    table = read_signals(args.signals, args.format)
    ch = spec.channels
    t0 = time.perf_counter()
    ident = identify_from_table(table, geom, channels={"A": ch.A, "B": ch.B, "C": ch.C},
                                units=ch.unit, **proc)
    elapsed = time.perf_counter() - t0

    out = Path(args.out) if args.out else Path("fricdamp-out") / \
        f"identify-{Path(args.signals).stem}"
    out.mkdir(parents=True, exist_ok=True)
    summary = {"fricdamp_version": __version__, "signals": str(args.signals),
               "rig": str(args.rig), "identification": ident.to_dict(),
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
    d = ident.to_dict()
    _out(f"fricdamp {__version__}: identified {Path(args.signals).name} "
         f"({ident.n_periods} periods at {ident.frequency_hz:.5g} Hz, {d['kinematics']} "
         "kinematics)")
    _out(f"dissipated energy {d['dissipated_energy_J']:.4g} J per cycle, rotation amplitude "
         f"{d['rotation_amplitude_rad']:.4g} rad, torque amplitude "
         f"{d['torque_amplitude_Nm']:.4g} N m, damping ratio (002) {d['damping_ratio']:.4g}")
    _out(f"wrote summary.json, loop.csv and loop.png to {out}")
    return EXIT_OK


def main(argv: list[str] | None = None) -> int:
    """Run ``identify`` without the main ``fricdamp`` parser (tests, scripts).

    ``python -m fricdamp.cli_identify identify SIGNALS --rig RIG.toml --out DIR``
    """
    from fricdamp.cli import main_for

    return main_for(add_subparsers, argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
