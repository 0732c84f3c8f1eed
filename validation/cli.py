"""The ``dfp`` console command. Arguments in g and seconds; errors in one line, no traceback."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

KINDS = ("symmetric", "antisymmetric")
SETS = ("nearfield_pulse", "nearfield_no_pulse", "farfield", "nearfield")


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


def demo(args) -> int:
    """Run one Ricker pulse through the rigid model, print impacts and failure, plot."""
    import dataclasses

    from rigid import DFPBearing, G, ricker_record, simulate
    from rigid.plots import plot_response

    out = _output_folder(args.out)
    bearing = dataclasses.replace(DFPBearing(), pressure=args.pressure * 1e6)
    dt = 0.005
    _, acceleration = ricker_record(args.amplitude * G, args.period, args.kind, dt=dt)
    result = simulate(bearing, acceleration, dt)
    print(f"DFP bearing, {args.pressure:g} MPa (supported mass "
          f"{bearing.supported_mass / 1e3:.1f} t, capacity ±{bearing.displacement_capacity:.2f} m,"
          f" period {bearing.period:.2f} s)")
    print(f"{args.kind} Ricker pulse, Ap = {args.amplitude:g} g, Tp = {args.period:g} s")
    print(result.summary())
    title = (f"{args.pressure:g} MPa, {args.kind} Ricker Ap = {args.amplitude:g} g, "
             f"Tp = {args.period:g} s")
    path = plot_response(result, out / "demo_response.png", title=title)
    print(f"plot: {path}")
    return 0


def _motions(args):
    from rigid import fema_p695, read_manifest

    if args.manifest:
        motions = read_manifest(args.manifest)
        label = f"manifest {args.manifest}"
    else:
        if args.set not in SETS:
            raise CommandError(f"unknown record set {args.set!r}; choose from {', '.join(SETS)}")
        motions = fema_p695(args.set)
        label = f"FEMA P695 {args.set}"
    if args.quick and args.records is None:
        from validation.pipeline import QUICK_RECORDS

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
    from validation.pipeline import Settings, run_rigid
    from validation.summary import write_report

    out = _output_folder(args.out)
    motions, label = _motions(args)
    settings = Settings(pressures=tuple(p * 1e6 for p in args.pressure),
                        criteria=tuple(args.criteria), stop=args.stop * G, search=args.search)
    print(f"validation: {len(motions)} records ({label}), pressures "
          f"{', '.join(f'{p:g}' for p in args.pressure)} MPa -> {out}")
    start = time.perf_counter()
    results = run_rigid(motions, settings, out, scheduler=args.scheduler, workers=args.workers,
                        progress=None if args.progress else False)
    path = write_report(results, motions, settings, out, elapsed=time.perf_counter() - start,
                        title="DFP bearing failure: validation run", record_set=label)
    for pressure, res in results.items():
        failed = sum(a.sa is not None for a in res.actual)
        print(f"  {pressure / 1e6:g} MPa: {failed}/{len(res.actual)} records fail below "
              f"{settings.stop / G:g} g")
    print(f"report: {path}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="dfp",
        description="Failure of double friction pendulum bearings under pulse-like motions "
        "(Bao & Becker 2016, reproduced and extended).",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("demo", help="one Ricker pulse through the rigid model, with a plot",
                       description=demo.__doc__)
    p.add_argument("--pressure", type=_positive(float), default=10.0,
                   help="slider pressure [MPa] (paper: 60 heavy, 10 light; default 10)")
    p.add_argument("--amplitude", type=_positive(float), default=0.8,
                   help="pulse amplitude Ap [g] (default 0.8)")
    p.add_argument("--period", type=_positive(float), default=3.0,
                   help="pulse period Tp [s] (default 3)")
    p.add_argument("--kind", choices=KINDS, default="symmetric", help="Ricker pulse shape")
    p.add_argument("--out", default="dfp-demo", help="output folder (default ./dfp-demo)")
    p.set_defaults(func=demo)

    p = sub.add_parser("validate", help="critical SA and its prediction over a record set",
                       description=validate.__doc__)
    source = p.add_mutually_exclusive_group()
    source.add_argument("--set", default="nearfield_pulse",
                        help=f"FEMA P695 record set: {', '.join(SETS)} (default nearfield_pulse)")
    source.add_argument("--manifest", help="user record set: a TOML or CSV manifest")
    p.add_argument("--quick", action="store_true",
                   help=f"a short run: the first component of the first "
                   f"{4} records (about 10 minutes here)")
    p.add_argument("--records", type=_positive(int), help="use only the first N components")
    p.add_argument("--pressure", type=_positive(float), nargs="+", default=[60.0, 10.0],
                   help="slider pressures [MPa] (default 60 10)")
    p.add_argument("--criteria", type=int, nargs="+", default=[1, 2, 3, 4],
                   choices=[1, 2, 3, 4], help="pulse selection criteria (default all)")
    p.add_argument("--stop", type=_positive(float), default=1.5,
                   help="highest SA(4.5 s) of the ladder [g] (default 1.5)")
    p.add_argument("--search", choices=("fast", "full"), default="fast",
                   help="ladder search (default fast: 0.1 g steps, then 0.01 g)")
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
