"""The ``dfp`` console command. Arguments in g and seconds; errors in one line, no traceback."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from rigid.motions import FEMA_P695_SETS, KINDS, WEIGHTINGS

#: Records of the quick run: the first components of the first FEMA P695 records of the set.
QUICK_RECORDS = 4
#: FE critical SA in the quick run: this many records (the shortest), at the first pressure.
QUICK_FEM_RECORDS = 1
#: FE time step [s] while sliding freely: the quick run's, and the full run's (fem.simulate's
#: default).
QUICK_FEM_STEP, FULL_FEM_STEP = 0.01, 0.005


class CommandError(Exception):
    """A user-facing error: printed as one line, exit status 2."""


def _positive(kind):
    def parse(text):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
        if not value > 0:
            raise argparse.ArgumentTypeError(f"must be positive, got {text}")
        return value

    return parse


def _output_folder(path: str) -> Path:
    folder = Path(path)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / ".write-test"
        probe.write_text("")
        probe.unlink()
    except OSError as exc:
        raise CommandError(f"cannot write to output folder {folder}: {exc.strerror}") from None
    return folder


def _bearing(args):
    import dataclasses

    from rigid import DFPBearing

    return dataclasses.replace(DFPBearing(), pressure=args.pressure * 1e6)


def _record(args):
    from rigid import read_record

    if not Path(args.record).exists():
        raise CommandError(f"record file {args.record} does not exist")
    return read_record(args.record, dt=args.dt, units=args.units)


def simulate(args) -> int:
    """Run the rigid model on a Ricker pulse or a record; print impacts and failure; plot."""
    from rigid import G, ricker_record
    from rigid import simulate as run
    from rigid.plots import plot_response

    out = _output_folder(args.out)
    bearing = _bearing(args)
    print(f"DFP bearing, {args.pressure:g} MPa (supported mass "
          f"{bearing.supported_mass / 1e3:.1f} t, capacity ±{bearing.displacement_capacity:.2f} m,"
          f" period {bearing.period:.2f} s)")
    if args.record:
        motion = _record(args)
        dt, acceleration = motion.dt, args.scale * motion.acceleration
        title = f"{args.pressure:g} MPa, {motion.name} × {args.scale:g}"
    else:
        dt = 0.005
        _, acceleration = ricker_record(args.amplitude * G, args.period, args.kind, dt=dt)
        title = (f"{args.pressure:g} MPa, {args.kind} Ricker Ap = {args.amplitude:g} g, "
                 f"Tp = {args.period:g} s")
    print(title)
    result = run(bearing, acceleration, dt)
    print(result.summary())
    path = plot_response(result, out / "response.png", title=title)
    print(f"plot: {path}")
    return 0


def pulses(args) -> int:
    """Extract the best Ricker pulse of a record by each criterion of paper §4.1; plot."""
    from rigid import G, best_pulse
    from rigid.motions.plots import plot_record_pulses

    out = _output_folder(args.out)
    motion = _record(args)
    found = []
    print(f"{motion.name}: dt = {motion.dt:g} s, {motion.acceleration.size} samples")
    print("criterion  kind           Tp [s]   Ap [g]   t0 [s]   e_a     e_v")
    for criterion in (1, 2, 3, 4):
        p = best_pulse(motion, criterion=criterion, weighting=args.weighting)
        found.append(p)
        print(f"{criterion:9d}  {p.kind:13s} {p.period:7.3f} {p.amplitude / G:8.3f} "
              f"{p.time:8.2f} {p.e_a:7.3f} {p.e_v:7.3f}")
    path = plot_record_pulses(motion, found, out / "pulses.png", title=motion.name)
    print(f"plot: {path}")
    return 0


def critical(args) -> int:
    """Critical SA(4.5 s) of a record by the 0.01 g ladder, and its pulse prediction."""
    from rigid import G, critical_sa, predict_critical_sa

    bearing = _bearing(args)
    motion = _record(args)
    actual = critical_sa(bearing, motion, stop=args.stop * G, search=args.search,
                         after_failure=args.after_failure)
    print(actual.summary())
    predicted = predict_critical_sa(bearing, motion, criterion=args.criterion,
                                    stop=args.stop * G, search=args.search)
    print(predicted.summary())
    return 0


def _motions(args):
    from rigid import fema_p695, read_manifest

    if args.manifest:
        motions = read_manifest(args.manifest)
        label = f"manifest {args.manifest}"
    else:
        if args.set not in FEMA_P695_SETS:
            raise CommandError(f"unknown record set {args.set!r}; choose from "
                               f"{', '.join(FEMA_P695_SETS)}")
        motions = fema_p695(args.set)
        label = f"FEMA P695 {args.set}"
    if args.quick and args.records is None:
        motions = motions[: 2 * QUICK_RECORDS : 2]  # first component of the first records
    elif args.records is not None:
        motions = motions[: args.records]
    if not motions:
        raise CommandError("the record set is empty")
    return motions, label


def validate(args) -> int:
    """Critical SA by time history and its pulse-based prediction over a record set; report."""
    import time

    from rigid import G
    from validation.fem_search import FESettings
    from validation.report import write_report
    from validation.run import Settings, run_validation

    out = _output_folder(args.out)
    motions, label = _motions(args)
    criteria = args.criteria or ((3, 4) if args.quick else (1, 2, 3, 4))
    fem_pressures = args.fem_pressure or (args.pressure[:1] if args.quick else args.pressure)
    unknown = [p for p in fem_pressures if p not in args.pressure]
    if args.fem and unknown:
        raise CommandError(f"--fem-pressure {unknown[0]:g} is not one of --pressure "
                           f"{' '.join(f'{p:g}' for p in args.pressure)}")
    fem = None
    if args.fem:
        step = args.fem_step or (QUICK_FEM_STEP if args.quick else FULL_FEM_STEP)
        fem = FESettings(mesh=args.fem_mesh, max_step=step, impact_step=min(5e-4, step))
    settings = Settings(
        pressures=tuple(p * 1e6 for p in args.pressure), criteria=tuple(criteria),
        stop=args.stop * G, search=args.search, fem=fem,
        fem_pressures=tuple(p * 1e6 for p in fem_pressures),
        fem_records=args.fem_records or (QUICK_FEM_RECORDS if args.quick else None),
    )
    print(f"validation: {len(motions)} records ({label}), pressures "
          f"{', '.join(f'{p:g}' for p in args.pressure)} MPa -> {out}")
    start = time.perf_counter()
    progress = None if args.progress else False
    results, fem_results = run_validation(motions, settings, out, scheduler=args.scheduler,
                                          workers=args.workers, progress=progress)
    for pressure, res in results.items():
        failed = sum(a.sa is not None for a in res.actual)
        print(f"  {pressure / 1e6:g} MPa: {failed}/{len(res.actual)} records fail below "
              f"{settings.stop / G:g} g")
    for pressure, found in fem_results.items():
        for r in found:
            sa = "no failure" if r.sa is None else f"{r.sa / G:.2f} g ({r.failure_mode})"
            rigid_sa = "none" if r.rigid_sa is None else f"{r.rigid_sa / G:.2f} g"
            print(f"  FE {pressure / 1e6:g} MPa {r.name}: critical SA {sa}; rigid {rigid_sa}; "
                  f"{r.runs} FE runs")
    path = write_report(results, motions, settings, out, elapsed=time.perf_counter() - start,
                        title="DFP bearing failure: validation run", record_set=label,
                        fem=fem_results)
    print(f"report: {path}")
    return 0


def _bearing_args(p):
    p.add_argument("--pressure", type=_positive(float), default=10.0,
                   help="slider pressure [MPa] (paper: 60 heavy, 10 light; default 10)")


def _record_args(p, required):
    p.add_argument("--record", required=required,
                   help="record file (PEER AT2, K-NET, JMA CSV or plain text)")
    p.add_argument("--dt", type=_positive(float), help="time step [s] of a plain text record")
    p.add_argument("--units", help="units of a plain text record (g, m/s2, gal, ...)")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="dfp",
        description="Failure of double friction pendulum bearings under pulse-like motions "
        "(Bao & Becker 2016, reproduced and extended).",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    for name, helptext in (("simulate", "the rigid model on a Ricker pulse or a record"),
                           ("demo", "the same as simulate (the first example of the README)")):
        p = sub.add_parser(name, help=helptext, description=simulate.__doc__)
        _bearing_args(p)
        p.add_argument("--amplitude", type=_positive(float), default=0.8,
                       help="pulse amplitude Ap [g] (default 0.8)")
        p.add_argument("--period", type=_positive(float), default=3.0,
                       help="pulse period Tp [s] (default 3)")
        p.add_argument("--kind", choices=KINDS, default="symmetric", help="Ricker pulse shape")
        _record_args(p, required=False)
        p.add_argument("--scale", type=_positive(float), default=1.0,
                       help="scale factor of the record (default 1)")
        p.add_argument("--out", default="dfp-simulate", help="output folder")
        p.set_defaults(func=simulate)

    p = sub.add_parser("pulses", help="best Ricker pulses of a record (criteria 1-4)",
                       description=pulses.__doc__)
    _record_args(p, required=True)
    p.add_argument("--weighting", choices=WEIGHTINGS, default=WEIGHTINGS[0],
                   help="wavelet weighting w(s) (default 1/sqrt(s), the unbiased one)")
    p.add_argument("--out", default="dfp-pulses", help="output folder")
    p.set_defaults(func=pulses)

    p = sub.add_parser("critical-sa", help="critical SA(4.5 s) of a record and its prediction",
                       description=critical.__doc__)
    _bearing_args(p)
    _record_args(p, required=True)
    p.add_argument("--stop", type=_positive(float), default=2.0,
                   help="highest SA(4.5 s) of the ladder [g] (default 2)")
    p.add_argument("--search", choices=("fast", "full"), default="full", help="ladder search")
    p.add_argument("--after-failure", type=int, default=10,
                   help="rungs run above the first failure, to show resurrections (default 10)")
    p.add_argument("--criterion", type=int, choices=(1, 2, 3, 4), default=4,
                   help="pulse selection criterion of the prediction (default 4)")
    p.set_defaults(func=critical)

    p = sub.add_parser("validate", help="critical SA and its prediction over a record set",
                       description=validate.__doc__)
    source = p.add_mutually_exclusive_group()
    source.add_argument("--set", default="nearfield_pulse",
                        help=f"FEMA P695 record set: {', '.join(FEMA_P695_SETS)} (default "
                        "nearfield_pulse)")
    source.add_argument("--manifest", help="user record set: a TOML or CSV manifest")
    p.add_argument("--quick", action="store_true",
                   help=f"a short run: the first component of the first {QUICK_RECORDS} "
                   "records, criteria 3 and 4, FE critical SA for the shortest record at the "
                   f"first pressure on the coarse mesh with {QUICK_FEM_STEP:g} s steps "
                   "(about 10 minutes on 2 cores)")
    p.add_argument("--records", type=_positive(int), help="use only the first N components")
    p.add_argument("--pressure", type=_positive(float), nargs="+", default=[60.0, 10.0],
                   help="slider pressures [MPa] (default 60 10)")
    p.add_argument("--criteria", type=int, nargs="+", choices=[1, 2, 3, 4],
                   help="pulse selection criteria (default all; --quick: 3 and 4, the paper's)")
    p.add_argument("--stop", type=_positive(float), default=1.5,
                   help="highest SA(4.5 s) of the ladder [g] (default 1.5)")
    p.add_argument("--search", choices=("fast", "full"), default="fast",
                   help="ladder search (default fast: 0.1 g steps, then 0.01 g)")
    p.add_argument("--fem", action=argparse.BooleanOptionalAction, default=True,
                   help="FE critical SA around the rigid one (default on; costly: minutes "
                   "per FE run, about 8 runs per record)")
    p.add_argument("--fem-mesh", choices=("coarse", "default"), default="coarse",
                   help="FE mesh: coarse (905 dofs, default) or default (4301 dofs, ~10x "
                   "slower)")
    p.add_argument("--fem-step", type=_positive(float),
                   help=f"FE time step [s] while sliding (default {FULL_FEM_STEP:g}; --quick: "
                   f"{QUICK_FEM_STEP:g})")
    p.add_argument("--fem-records", type=_positive(int),
                   help=f"FE runs for the N shortest records only (default all; --quick: "
                   f"{QUICK_FEM_RECORDS})")
    p.add_argument("--fem-pressure", type=_positive(float), nargs="+",
                   help="pressures [MPa] with FE runs (default all; --quick: the first)")
    p.add_argument("--out", default="dfp-validation", help="output folder")
    p.add_argument("--scheduler", help="address of a Dask scheduler (default: local processes)")
    p.add_argument("--workers", type=_positive(int), help="local worker processes")
    p.add_argument("--no-progress", dest="progress", action="store_false",
                   help="no progress bars")
    p.set_defaults(func=validate)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except (CommandError, ValueError, OSError) as exc:
        print(f"dfp {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"dfp {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
