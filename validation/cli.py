"""The ``dfp`` console command. Arguments in g and seconds; errors in one line, no traceback."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

KINDS = ("symmetric", "antisymmetric")


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
