"""The ``dfp`` console command. Arguments in g, seconds and MPa, checked against the
plausibility limits of docs/limits.md before anything runs.

Every error reaches the user as one line on standard error naming what was wrong, with an
exit status: 0 done; 1 no trustworthy answer (numerical instability, an answer that depends
on numerical rungs) or a problem of the machine (a file that cannot be written, a full disk,
a damaged store that cannot be rebuilt, out of memory, an output folder in use); 2 bad input
(arguments, record files, manifests); 3 an internal error (a bug: please report it; ``--debug``
shows the traceback); 4 the Dask cluster cannot go on (its scheduler unreachable or lost, no
worker within ``--worker-wait``, a task that kills its workers: the results stored so far are
kept, rerun to resume); 130 interrupted (Ctrl-C); 143 terminated (SIGTERM). An interrupted or
terminated run stops its worker processes (on a cluster: cancels its tasks, which stop on the
workers) and keeps every result stored so far.

This module parses the arguments and turns errors into that one line (:func:`main`); the
commands themselves are in :mod:`validation.commands`.
"""

from __future__ import annotations

import argparse
import errno
import logging
import re
import signal
import sys
import warnings

from rigid.limit_states import LIMIT_STATES, RIM_MODELS
from rigid.limits import (
    RECORD_DT_RANGE,
    RICKER_AMPLITUDE_MAX,
    RICKER_PERIOD_RANGE,
)
from rigid.motions import ALL_WEIGHTINGS, FEMA_P695_SETS, KINDS, MAX_PULSE_PERIOD, WEIGHTINGS
from rigid.rims import RIM_LAW_MODELS
from rigid.units import G

from .arguments import PRESSURE, STOP, number, positive
from .commands import (  # the commands, and what their help texts quote
    FULL_FEM_STEP,
    LADDER_TOP,
    QUICK_FEM_RECORDS,
    QUICK_FEM_STEP,
    QUICK_RECORDS,
    CommandError,
    MachineError,
    NoAnswerError,
    bearing,
    critical,
    did_you_mean,
    pulses,
    simulate,
    validate,
)

#: Most local worker processes (more only thrash a machine).
MAX_WORKERS = 256
#: Longest error message printed [characters].
MAX_MESSAGE = 400

EXIT_FAILED, EXIT_USAGE, EXIT_BUG, EXIT_CLUSTER = 1, 2, 3, 4
EXIT_INTERRUPTED, EXIT_TERMINATED = 130, 143
#: Default longest wait for a Dask worker [s] (``dfp validate --worker-wait``).
WORKER_WAIT = 60.0


class Terminated(KeyboardInterrupt):
    """SIGTERM, handled like Ctrl-C (workers terminated, results so far kept)."""


def one_line(text, limit: int = MAX_MESSAGE) -> str:
    """``text`` on one line (whitespace runs collapsed), at most ``limit`` characters."""
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _bearing_args(p, pressures=False):
    """``--bearing FILE`` and the options of the common fields (:mod:`validation.bearing_file`;
    an option wins over the file). ``pressures``: ``--pressure`` takes several (validate)."""
    from rigid.bearing import DFPBearing

    from .bearing_file import OPTIONS, option_range

    p.add_argument("--bearing", metavar="FILE",
                   help="the bearing: a TOML file with any DFPBearing field in the units of "
                   "docs/bearing.md (dfp bearing --template writes one); the options below "
                   "override it")
    if pressures:
        p.add_argument("--pressure", type=PRESSURE, nargs="+",
                       help="slider pressures [MPa], 1-200 (default: the file's, else 60 10)")
    else:
        p.add_argument("--pressure", type=PRESSURE,
                       help="slider pressure [MPa], 1-200 (paper: 60 heavy, 10 light; default: "
                       "the file's, else 10)")
    helps = {"radius": "radius of each sliding surface [m]",
             "friction": "friction coefficient of the sliding surfaces [-]",
             "slider_diameter": "slider diameter [m]",
             "displacement_capacity": "the bearing's displacement capacity [m], twice the "
             "travel on one surface",
             "rim_thickness": "the rims' thickness [mm]", "rim_height": "the rims' height [mm]",
             "yield_stress": "rim steel yield stress [MPa]",
             "ultimate_stress": "rim steel ultimate stress [MPa]"}
    baseline = DFPBearing()
    for option, text in helps.items():
        low, high, unit, low_open = option_range(option)
        name, _, factor = OPTIONS[option]
        p.add_argument("--" + option.replace("_", "-"),
                       type=number(float, low, high, f" {unit}" if unit else "",
                                    low_open=low_open),
                       help=f"{text}, {low:g}-{high:g} (default "
                       f"{getattr(baseline, name) / factor:g})")


def _rim_args(p):
    p.add_argument("--rims", choices=RIM_MODELS, default="rigid",
                   help="rim model: rigid (the paper's, default) or yielding (elastoplastic "
                   "rims derived from the FE companion's rim push)")
    p.add_argument("--limit-state", choices=LIMIT_STATES,
                   help="what counts as failure with yielding rims: a rim's hinge (default), "
                   "its rupture, or the loss of containment (rigid rims: containment only)")


def _record_args(p, required):
    p.add_argument("--record", required=required,
                   help="record file (PEER AT2, K-NET, JMA CSV or plain text)")
    p.add_argument("--dt", type=number(float, *RECORD_DT_RANGE, " s",
                                        "accelerographs sample at 10-10,000 Hz"),
                   help="time step [s] of a plain text record, 1e-4 to 0.1")
    p.add_argument("--units", help="units of a plain text record (g, m/s2, gal, ...)")


_INVALID_CHOICE = re.compile(r"invalid choice: '?(?P<word>[^' ]*)'? "
                             r"\(choose from (?P<choices>.*)\)")


class _Parser(argparse.ArgumentParser):
    """argparse with its errors on one line (no usage block), and the nearest subcommand,
    choice or option suggested for a mistyped one (argparse suggests none before Python 3.14)."""

    #: The subcommands' parsers, by name (set on the top parser by :func:`build_parser`).
    commands: dict | None = None

    def parse_args(self, args=None, namespace=None):
        known, extra = self.parse_known_args(args, namespace)
        if extra:
            sub = (self.commands or {}).get(getattr(known, "command", None), self)
            options = [o for a in sub._actions for o in a.option_strings]
            hints = "".join(did_you_mean(w.split("=")[0], options) for w in extra
                            if w.startswith("--"))
            self.error(f"unrecognized arguments: {' '.join(extra)}{hints}")
        return known

    def error(self, message):
        m = _INVALID_CHOICE.search(message)
        if m:
            choices = [c.strip(" '") for c in m["choices"].split(",")]
            message += did_you_mean(m["word"], choices)
        self.exit(EXIT_USAGE, f"{self.prog}: error: {one_line(message)} (see {self.prog} "
                  "--help)\n")


def _debug_arg(p, default):
    p.add_argument("--debug", action="store_true", default=default,
                   help="show the traceback of an error (for bug reports)")


def build_parser() -> argparse.ArgumentParser:
    """The ``dfp`` command's parser: one subcommand each (simulate and its alias demo,
    pulses, critical-sa, validate, bearing), each calling its command (:mod:`validation.commands`,
    looked up here at call time)."""
    parser = _Parser(
        prog="dfp",
        description="Failure of double friction pendulum bearings under pulse-like motions "
        "(Bao & Becker 2016, reproduced and extended).",
    )
    _debug_arg(parser, False)
    sub = parser.add_subparsers(dest="command", required=True)
    _simulate_parsers(sub)
    _pulses_parser(sub)
    _critical_parser(sub)
    _validate_parser(sub)
    _bearing_parser(sub)
    for p in sub.choices.values():  # --debug after the command too
        _debug_arg(p, argparse.SUPPRESS)
    parser.commands = dict(sub.choices)
    return parser


def _simulate_parsers(sub):
    """``simulate`` and its alias ``demo``: a Ricker pulse or a record, one rigid run."""
    for name, helptext in (("simulate", "the rigid model on a Ricker pulse or a record"),
                           ("demo", "the same as simulate (by default the light bearing on a "
                            "0.8 g, 3 s Ricker pulse)")):
        p = sub.add_parser(name, help=helptext, description=simulate.__doc__)
        _bearing_args(p)
        p.add_argument("--amplitude", default=0.8,
                       type=number(float, 0, RICKER_AMPLITUDE_MAX / G, " g",
                                    "the largest recorded ground motions reach about 4 g",
                                    low_open=True),
                       help="pulse amplitude Ap [g], up to 10 (default 0.8)")
        p.add_argument("--period", default=3.0,
                       type=number(float, *RICKER_PERIOD_RANGE, " s",
                                    "from a 20 Hz pulse to beyond the longest velocity pulses"),
                       help="pulse period Tp [s], 0.05-20 (default 3)")
        p.add_argument("--kind", choices=KINDS, default="symmetric", help="Ricker pulse shape")
        _record_args(p, required=False)
        p.add_argument("--scale", type=positive(float), default=1.0,
                       help="scale factor of the record (default 1; the scaled peak must stay "
                       "within 10 g)")
        _rim_args(p)
        p.add_argument("--out", default="dfp-simulate", help="output folder")
        p.set_defaults(func=simulate)


def _pulses_parser(sub):
    """``pulses``: the best Ricker pulses of a record."""
    p = sub.add_parser("pulses", help="best Ricker pulses of a record (criteria 1-4)",
                       description=pulses.__doc__)
    _record_args(p, required=True)
    _pulse_args(p)
    p.add_argument("--out", default="dfp-pulses", help="output folder")
    p.set_defaults(func=pulses)


def _pulse_args(p):
    """The pulse extraction's options (paper §4.1)."""
    p.add_argument("--weighting", choices=(ALL_WEIGHTINGS, *WEIGHTINGS), default=ALL_WEIGHTINGS,
                   help="wavelet weighting w(s): 'all' pools the candidates of the three, as "
                   "the paper does (default); 1/sqrt(s) alone is the one unbiased on a pure pulse")
    p.add_argument("--max-period", type=positive(float), default=MAX_PULSE_PERIOD,
                   help=f"longest pulse period searched [s] (default {MAX_PULSE_PERIOD:g}, the "
                   "paper's limit)")


def _critical_parser(sub):
    """``critical-sa``: the ladder and its prediction for one record."""
    p = sub.add_parser("critical-sa", help="critical SA(4.5 s) of a record and its prediction",
                       description=critical.__doc__)
    _bearing_args(p)
    _record_args(p, required=True)
    p.add_argument("--stop", type=STOP, default=LADDER_TOP,
                   help=f"highest SA(4.5 s) of the ladder [g], up to 5 (default {LADDER_TOP:g}, "
                   "as every dfp command)")
    p.add_argument("--search", choices=("fast", "full"), default="full", help="ladder search")
    p.add_argument("--after-failure", type=number(int, 0, 1000), default=10,
                   help="rungs run above the first failure, to show resurrections (default 10)")
    p.add_argument("--criterion", type=int, choices=(1, 2, 3, 4), default=4,
                   help="pulse selection criterion of the prediction (default 4)")
    _pulse_args(p)
    _rim_args(p)
    p.set_defaults(func=critical)


def _bearing_parser(sub):
    """``bearing``: a bearing file's template, or a bearing checked and described."""
    p = sub.add_parser("bearing", help="write a bearing file's template, or check a bearing "
                       "and show its parameters and derived quantities",
                       description=bearing.__doc__)
    p.add_argument("--template", nargs="?", const="bearing.toml", metavar="FILE",
                   help="write a commented bearing file with every field at the baseline's "
                   "value to FILE (default bearing.toml; - for standard output); an existing "
                   "file is kept")
    _bearing_args(p)
    p.set_defaults(func=bearing)


def _validate_parser(sub):
    """``validate``: a record set, both models, the report."""
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
                   "(about 2 minutes on 2 cores)")
    p.add_argument("--records", type=positive(int), help="use only the first N components")
    _bearing_args(p, pressures=True)
    p.add_argument("--criteria", type=int, nargs="+", choices=[1, 2, 3, 4],
                   help="pulse selection criteria (default all; --quick: 3 and 4, the paper's)")
    p.add_argument("--stop", type=STOP, default=LADDER_TOP,
                   help=f"highest SA(4.5 s) of the ladder [g], up to 5 (default {LADDER_TOP:g}, "
                   "as every dfp command)")
    p.add_argument("--search", choices=("fast", "full"), default="fast",
                   help="ladder search (default fast: 0.1 g steps, then 0.01 g)")
    p.add_argument("--fem", action=argparse.BooleanOptionalAction, default=True,
                   help="FE critical SA around the rigid one (default on; seconds to minutes "
                   "per FE run; about 2 runs per record and limit state when started from the "
                   "yielding rims, about 8 from rigid rims)")
    p.add_argument("--fem-mesh", choices=("coarse", "default"), default="coarse",
                   help="FE mesh: coarse (905 dofs, default) or default (4301 dofs, ~10x "
                   "slower)")
    p.add_argument("--fem-step", type=number(float, 0, 0.1, " s", low_open=True),
                   help=f"FE time step [s] while sliding (default {FULL_FEM_STEP:g}; --quick: "
                   f"{QUICK_FEM_STEP:g})")
    p.add_argument("--fem-records", type=positive(int),
                   help=f"FE runs for the N shortest records only (default all; --quick: "
                   f"{QUICK_FEM_RECORDS})")
    p.add_argument("--fem-pressure", type=PRESSURE, nargs="+",
                   help="pressures [MPa] with FE runs (default all; --quick: the first)")
    p.add_argument("--fem-fracture", choices=("steep", "median", "mild"),
                   help="FE rims that tear: ductile damage with a critical strain that falls "
                   "with the stress triaxiality (the three constants' sets; default none: the "
                   "steel never tears; docs/theory/finite-elements.md, 'Rim fracture')")
    p.add_argument("--fem-edge-radius", type=number(float, 0, None, " mm"), default=0.0,
                   help="FE slider's rounded edges, radius [mm], below half the height of its "
                   "flat sides (default 0: sharp, the rigid model's; docs/fe-companion.md, "
                   "'Rounded slider edges')")
    p.add_argument("--fem-crush", type=number(float, 0, 0.99, low_open=True), metavar="J_C",
                   help="with --fem-fracture: also crush the rims' elements whose det F falls "
                   "below J_C (in (0, 1); 0.1 in the thick rims' studies), and let the faces "
                   "that eroded elements uncover carry contact, in the FE runs and in the "
                   "slider's push for the law (default none; docs/theory/finite-elements.md, "
                   "Eqs. F67b, F68c)")
    p.add_argument("--limit-state", nargs="+", choices=LIMIT_STATES, default=["hinge"],
                   help="FE limit states searched, each its own FE critical SA sharing the "
                   "same runs (default hinge; docs/theory/finite-elements.md, 'Limit states')")
    p.add_argument("--rims", nargs="+", choices=RIM_MODELS,
                   default=["rigid", "yielding"],
                   help="rim models of the rigid model's ladders (default both; rigid rims, "
                   "the paper's model, always run); with yielding rims one ladder per limit "
                   "state, where the FE searches then start")
    p.add_argument("--fem-kinematics", choices=("finite", "small"), default="finite",
                   help="FE kinematics: finite deformation (default) or small strain")
    p.add_argument("--rim-model", choices=RIM_LAW_MODELS, default=RIM_LAW_MODELS[0],
                   help="the rims' strength: the plane-strain rim times the depth πb/4 "
                   "(default), or the 3-D push of the rim as a ring (the yielding rims' law, "
                   "and the FE rims' effective depth at the one limit state searched; the "
                   "first use of a rim geometry runs a 3-D push, a few minutes)")
    p.add_argument("--rim-fracture", choices=("steep", "median", "mild"),
                   help="the yielding rims' law through tearing: the plane-strain push goes "
                   "on with the ductile damage of that set until the rim is off, and a rim "
                   "that comes off loses containment (default: --fem-fracture's set with FE "
                   "runs and the plane-strain rim model, else none; "
                   "docs/theory/rigid-body.md, 'Rims that tear')")
    p.add_argument("--rim-punch", choices=("face", "slider"), default="face",
                   help="what pushes the plane-strain rim for the law through tearing: a "
                   "uniform displacement of its inner face (default) or the slider itself on "
                   "its pendulum path, with --fem-edge-radius's edges (default 20 mm), which "
                   "tears a thick rim that the face push does not (docs/fe-companion.md, "
                   "'The rim pushed by the slider')")
    p.add_argument("--out", default="dfp-validation", help="output folder")
    p.add_argument("--scheduler", help="address of a Dask scheduler (default: local processes);"
                   " the results come back here, the workers need no view of --out")
    p.add_argument("--worker-wait", type=number(float, 0, 86400, " s"), default=WORKER_WAIT,
                   help="with --scheduler: longest wait [s] for a Dask worker, at the start "
                   f"and whenever all have left (default {WORKER_WAIT:g})")
    p.add_argument("--workers", type=number(int, 1, MAX_WORKERS),
                   help=f"local worker processes (1-{MAX_WORKERS})")
    p.add_argument("--no-progress", dest="progress", action="store_false",
                   help="no progress bars")
    p.add_argument("--replay", action="store_true",
                   help="compute nothing: rewrite the report of --out from its store alone; "
                   "an error names the results missing there (a changed input or model code)")
    p.add_argument("--rekey-from", metavar="REVISION",
                   help="carry the results stored in --out by the code of a git REVISION "
                   "over to today's keys, after rerunning the shortest two of each kind with "
                   "today's code and finding them equal, floats to 1e-6 (for a change of code "
                   "that leaves the physics alone); needs a git checkout")
    p.add_argument("--keep-stored-laws", action="store_true",
                   help="with --rekey-from: carry the store's rim laws over even where "
                   "today's push differs (a push through tearing is not repeatable across "
                   "machines); the differences are printed")
    p.set_defaults(func=validate)


def _describe(exc: BaseException) -> tuple[str, int]:
    """The one-line message and the exit status of an exception."""
    import sqlite3

    from rigid import NumericalInstabilityError
    from rigid.tasks import ClusterError, FolderBusyError, StoreError

    if isinstance(exc, ClusterError):
        return f"error: {exc}", EXIT_CLUSTER
    full = isinstance(exc, OSError) and exc.errno == errno.ENOSPC
    if full and not isinstance(exc, StoreError):  # a store's message names it and says so
        where = f" writing {exc.filename}" if exc.filename else ""
        return (f"error: the disk is full{where} ({exc.strerror or exc}); the results stored "
                "so far are kept: free some space and rerun to resume", EXIT_FAILED)
    if isinstance(exc, (CommandError, ValueError)):  # RecordFormatError is a ValueError
        return f"error: {exc}", EXIT_USAGE
    if isinstance(exc, MachineError):
        return f"error: {exc}", EXIT_FAILED
    if isinstance(exc, NoAnswerError):
        return f"no answer: {exc}", EXIT_FAILED
    if isinstance(exc, NumericalInstabilityError):
        return f"no answer: numerical instability, not a physical failure: {exc}", EXIT_FAILED
    if isinstance(exc, (FolderBusyError, StoreError)):
        return f"error: {exc}", EXIT_FAILED
    if isinstance(exc, OSError):
        if exc.filename is not None and exc.strerror:
            return f"error: {exc.filename}: {exc.strerror}", EXIT_FAILED
        return f"error: {exc}", EXIT_FAILED
    if isinstance(exc, sqlite3.Error):
        return f"error: result store: {exc}", EXIT_FAILED
    if isinstance(exc, MemoryError):
        return ("error: out of memory (the inputs are within docs/limits.md; please report "
                "it)", EXIT_FAILED)
    if isinstance(exc, ModuleNotFoundError):
        return (f"error: {exc}; install the optional dependencies: pip install "
                "'dfp-failure[all]'", EXIT_FAILED)
    return (f"internal error (please report, with the output of --debug): "
            f"{type(exc).__name__}: {exc}", EXIT_BUG)


def _quiet_dask():
    """Silence Dask's loggers in this process (a lost scheduler logs tracebacks of its own;
    ``dfp`` says it in one line; ``--debug`` keeps them); return what restores them."""
    try:
        import distributed  # noqa: F401 - sets up its loggers, which are then turned down
    except ImportError:  # --scheduler without dask: the run says so
        return lambda: None
    names = [n for n in list(logging.root.manager.loggerDict)
             if n == "distributed" or n.startswith("distributed.")]
    levels = {n: logging.getLogger(n).level for n in names}
    for name in names:
        logging.getLogger(name).setLevel(logging.CRITICAL + 1)

    def restore():
        for name, level in levels.items():
            logging.getLogger(name).setLevel(level)

    return restore


def _terminate(signum, frame):
    raise Terminated()


def main(argv=None) -> int:
    """Run the ``dfp`` command with ``argv`` (default ``sys.argv[1:]``); return the exit
    status (see the module docstring)."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse: --help (0) or a usage error (2), already printed
        return exc.code if isinstance(exc.code, int) else EXIT_USAGE
    prefix = f"dfp {args.command}"

    def show(message, category, filename, lineno, file=None, line=None):
        print(f"{prefix}: warning: {one_line(message)}", file=sys.stderr)

    quiet = _quiet_dask() if getattr(args, "scheduler", None) and not args.debug else None
    previous = None
    try:
        previous = signal.signal(signal.SIGTERM, _terminate)
    except ValueError:  # not the main thread: leave SIGTERM alone
        pass
    try:
        with warnings.catch_warnings():
            warnings.showwarning = show
            return args.func(args)
    except Terminated:
        print(f"{prefix}: terminated (SIGTERM); workers stopped, results so far kept",
              file=sys.stderr)
        return EXIT_TERMINATED
    except KeyboardInterrupt:
        print(f"{prefix}: interrupted; workers stopped, results so far kept", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception as exc:
        message, status = _describe(exc)
        if args.debug:
            import traceback

            traceback.print_exc()
        print(f"{prefix}: {one_line(message)}", file=sys.stderr)
        return status
    finally:
        if quiet is not None:
            quiet()
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
        lock = getattr(args, "_lock", None)
        if lock is not None:
            lock.release()


if __name__ == "__main__":
    sys.exit(main())
