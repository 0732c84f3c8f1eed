"""The commands of ``dfp`` (simulate, pulses, critical, validate): each takes the parsed
arguments (:func:`validation.cli.build_parser`) and returns an exit status; errors are raised as
:class:`CommandError` (bad input), :class:`NoAnswerError` (no trustworthy answer) or
:class:`MachineError` (a read-only or full output folder) and turned into one line by
:func:`validation.cli.main`."""

from __future__ import annotations

import dataclasses
import errno
import math
import os
import warnings
from pathlib import Path

from rigid.bearing import DFPBearing
from rigid.limit_states import check_limit_state
from rigid.limits import MAX_RECORD_ACCELERATION
from rigid.motions import FEMA_P695_SETS
from rigid.units import G

__all__ = ["CommandError", "MachineError", "NoAnswerError", "bearing", "critical", "pulses",
           "simulate", "validate"]

#: Records of the quick run: the first components of the first FEMA P695 records of the set.
QUICK_RECORDS = 4
#: FE critical SA in the quick run: this many records (the shortest), at the first pressure.
QUICK_FEM_RECORDS = 1
#: Top of the SA(4.5 s) ladder of every dfp command [g]: every record of the FEMA P695
#: studies fails the bearing below it (docs/critical_sa.md). The library's own default
#: (rigid.critical_sa) is 3 g.
LADDER_TOP = 1.5
#: FE time step [s] while sliding freely: the quick run's, and the full run's (fem.simulate's
#: default).
QUICK_FEM_STEP, FULL_FEM_STEP = 0.01, 0.005


class CommandError(Exception):
    """A user-facing error: printed as one line, exit status 2."""


class NoAnswerError(Exception):
    """The computation ran but gives no trustworthy answer: printed as one line, exit 1."""


class MachineError(Exception):
    """A problem of the machine, not of the input (a read-only or full output folder):
    printed as one line, exit 1."""


def did_you_mean(word: str, choices) -> str:
    """`` (did you mean X?)`` for the choice nearest ``word`` (:func:`difflib.get_close_matches`),
    or "" when none is near."""
    import difflib

    near = difflib.get_close_matches(word, list(choices), n=1, cutoff=0.6)
    return f" (did you mean {near[0]}?)" if near else ""


def _output_folder(path: str) -> Path:
    """The output folder as an absolute path (workers on a cluster have other working
    folders), created and checked writable."""
    folder = Path(os.path.abspath(path))
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / ".write-test"
        probe.write_text("")
        probe.unlink()
    except OSError as exc:
        message = f"cannot write to output folder {folder}: {exc.strerror}"
        if exc.errno in (errno.EROFS, errno.EACCES, errno.EPERM, errno.ENOSPC, errno.EDQUOT):
            raise MachineError(message) from None
        raise CommandError(message) from None  # a file in the way, a name too long, …
    return folder


def _locked_output_folder(args) -> Path:
    """The output folder, created, writable and locked for this run (released at exit)."""
    from rigid.tasks import FolderLock

    folder = _output_folder(args.out)
    args._lock = FolderLock(folder).acquire()
    return folder


#: Pressure [Pa] of the single-bearing commands when neither the file nor --pressure gives one.
DEFAULT_PRESSURE = 10e6


def _bearing(args):
    """The bearing of a single-bearing command: ``--bearing FILE`` and the options
    (:mod:`validation.bearing_file`), pressure :data:`DEFAULT_PRESSURE` unless given."""
    from .bearing_file import bearing_from, overrides

    fields = overrides(args)
    fields.setdefault("pressure", DEFAULT_PRESSURE)
    return bearing_from(fields)


def _bearing_line(bearing, rims: dict) -> str:
    """The bearing as the commands print it first: pressure, mass, capacity, period, and
    the rims (size; model and limit state from ``rims``, :func:`_rim_options`)."""
    return (f"DFP bearing, {bearing.pressure / 1e6:g} MPa (supported mass "
            f"{bearing.supported_mass / 1e3:.1f} t, capacity ±{bearing.displacement_capacity:.2f}"
            f" m, period {bearing.period:.2f} s); rims {bearing.rim_thickness * 1e3:g} × "
            f"{bearing.rim_height * 1e3:g} mm (thickness × height), {rims['rims']}, failure = "
            f"{rims['limit_state']}")


def _ladder_line(args, bearing) -> str:
    """The ladder as the commands print it: SA(Tb), step, top (said to differ from
    :data:`LADDER_TOP` when it does) and search."""
    top = f"{args.stop:g} g" + (f" (not the default {LADDER_TOP:g} g)"
                                if args.stop != LADDER_TOP else "")
    return (f"ladder: SA({bearing.design_period:g} s) in 0.01 g steps up to {top}, "
            f"{args.search} search")


def bearing(args) -> int:
    """Write a commented bearing file (--template), or check a bearing (--bearing FILE and
    the options) and print its parameters, in the file's units, and derived quantities."""
    from .bearing_file import template

    if args.template is not None:
        text = template()
        if args.template == "-":
            print(text, end="")
            return 0
        path = Path(args.template)
        if path.exists():
            raise CommandError(f"{path} exists; choose another name or remove it")
        try:
            path.write_text(text, encoding="utf-8")
        except OSError as exc:
            raise CommandError(f"cannot write {path}: {exc.strerror}") from None
        print(f"bearing template: {path} (edit it, then pass it as --bearing {path})")
        return 0
    from .report.write import bearing_rows

    b = _bearing(args)
    for row in bearing_rows(b):
        unit = "" if row["unit"] in ("", "-") else f" {row['unit']}"
        base = f"  (baseline {row['baseline']})" if row["baseline"] else ""
        print(f"{row['parameter']:24s} {row['value']}{unit}{base}")
    return 0


def _record(args):
    from rigid import read_record

    if not Path(args.record).exists():
        raise CommandError(f"record file {args.record} does not exist")
    return read_record(args.record, dt=args.dt, units=args.units)


def _no_answer(kind: str, error) -> NoAnswerError:
    return NoAnswerError(f"numerical instability, not a physical failure: {error} ({kind})")


def simulate(args) -> int:
    """Run the rigid model on a Ricker pulse or a record; print impacts and failure; plot."""
    from rigid import NumericalInstabilityError, ricker_record
    from rigid import simulate as run
    from rigid.plots import plot_response

    bearing = _bearing(args)
    out = _locked_output_folder(args)
    if args.record:  # read and checked before anything is printed
        motion = _record(args)
        if motion.pga * args.scale > MAX_RECORD_ACCELERATION:
            raise CommandError(f"--scale {args.scale:g} takes the peak acceleration of "
                               f"{motion.name} to {motion.pga * args.scale / G:.3g} g, beyond "
                               f"the {MAX_RECORD_ACCELERATION / G:g} g of any recorded ground "
                               "motion (docs/limits.md)")
        dt, acceleration = motion.dt, args.scale * motion.acceleration
        title = f"{bearing.pressure / 1e6:g} MPa, {motion.name} × {args.scale:g}"
    else:
        dt = 0.005
        _, acceleration = ricker_record(args.amplitude * G, args.period, args.kind, dt=dt)
        title = (f"{bearing.pressure / 1e6:g} MPa, {args.kind} Ricker Ap = {args.amplitude:g} g, "
                 f"Tp = {args.period:g} s")
    rims = _rim_options(args, bearing)
    print(_bearing_line(bearing, rims))
    print(title)
    try:
        result = run(bearing, acceleration, dt, **rims)
    except NumericalInstabilityError as exc:
        raise _no_answer("the rigid model's integration stayed unstable; the run gives no "
                         "verdict", exc) from None
    print(result.summary())
    path = plot_response(result, out / "response.png", title=title)
    print(f"plot: {path}")
    return 0


def pulses(args) -> int:
    """Extract the best Ricker pulse of a record by each criterion of paper §4.1; plot."""
    from rigid import best_pulse
    from rigid.motions.plots import plot_record_pulses

    out = _locked_output_folder(args)
    motion = _record(args)
    found = []
    print(f"{motion.name}: dt = {motion.dt:g} s, {motion.acceleration.size} samples")
    print(f"weighting {args.weighting}, pulse periods up to {args.max_period:g} s")
    print("criterion  kind           w(s)       Tp [s]   Ap [g]   t0 [s]   e_a     e_v")
    for criterion in (1, 2, 3, 4):
        p = best_pulse(motion, criterion=criterion, weighting=args.weighting,
                       max_period=args.max_period)
        found.append(p)
        print(f"{criterion:9d}  {p.kind:13s} {p.weighting:9s} {p.period:7.3f} "
              f"{p.amplitude / G:8.3f} {p.time:8.2f} {_index(p.e_a)} {_index(p.e_v)}")
    path = plot_record_pulses(motion, found, out / "pulses.png", title=motion.name)
    print(f"plot: {path}")
    return 0


def _index(value) -> str:
    """A match index for the pulse table: 3 decimals, or a dash when undefined."""
    return f"{value:7.3f}" if math.isfinite(value) else f"{'—':>7s}"


def critical(args) -> int:
    """Critical SA(4.5 s) of a record by the 0.01 g ladder, and its pulse prediction.

    Exit status 1 (after the two lines) when either answer depends on rungs whose
    integration stayed unstable (numerical: neither failures nor survivals)."""
    from rigid import critical_sa, predict_critical_sa

    bearing = _bearing(args)
    motion = _record(args)
    rims = _rim_options(args, bearing)
    print(_bearing_line(bearing, rims))
    print(_ladder_line(args, bearing))
    actual = critical_sa(bearing, motion, stop=args.stop * G, search=args.search,
                         after_failure=args.after_failure, **rims)
    print(actual.summary())
    predicted = predict_critical_sa(bearing, motion, criterion=args.criterion,
                                    stop=args.stop * G, search=args.search,
                                    weighting=args.weighting, max_period=args.max_period, **rims)
    print(predicted.summary())
    uncertain = [what for what, r in (("critical SA", actual), ("prediction", predicted))
                 if r.uncertain]
    if uncertain:
        n = len(actual.numerical_failures) + len(predicted.numerical_failures)
        raise NoAnswerError(f"the {' and the '.join(uncertain)} depend on {n} numerical "
                            "rung(s) (integration unstable, outcome unknown): no verdict")
    return 0


def _motions(args):
    from rigid import fema_p695, read_manifest

    if args.manifest:
        motions = read_manifest(args.manifest)
        label = f"manifest {args.manifest}"
    else:
        if args.set not in FEMA_P695_SETS:
            raise CommandError(f"unknown record set {args.set!r}"
                               f"{did_you_mean(args.set, FEMA_P695_SETS)}; choose from "
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


def _check_edge_radius(bearing: DFPBearing, radius: float) -> None:
    """A one-line error unless the slider of ``bearing`` can have edges of ``radius`` [m]."""
    from fem.contact.slider import SliderShape

    try:
        SliderShape.from_bearing(bearing, radius)
    except ValueError as exc:
        raise CommandError(f"--fem-edge-radius {radius * 1e3:g}: {exc}") from None


def _rim_punch_edges(args, rim_fracture) -> float | None:
    """With ``--rim-punch slider``: the pushing slider's edge radius [m] (``--fem-edge-radius``,
    else 20 mm); None with the face push."""
    if args.rim_punch == "face":
        return None
    if rim_fracture is None or args.rim_model != "plane-strain":
        raise CommandError("--rim-punch slider gives the plane-strain law through tearing: it "
                           "needs --rim-fracture (or --fem-fracture) and --rim-model "
                           "plane-strain")
    from fem.slider_push import EDGE_RADIUS

    return args.fem_edge_radius / 1e3 if args.fem_edge_radius else EDGE_RADIUS


def _crush(args, slider_edges) -> float | None:
    """The law's crushing J_c: ``--fem-crush``'s when the slider pushes the rim for the law
    (``--rim-punch slider``), which then crushes as the FE runs do; else None."""
    return args.fem_crush if slider_edges is not None else None


def validate(args) -> int:
    """Critical SA by time history and its pulse-based prediction over a record set; report."""
    import time

    from rigid.tasks import MissingResultsError
    from validation.fem_search import FESettings
    from validation.report import write_report
    from validation.run import Settings, run_validation

    from .bearing_file import bearing_from, describe_variant, overrides

    fields = overrides(args)
    pressure = fields.pop("pressure", None)
    if args.pressure is None:  # the file's pressure, else the paper's two
        args.pressure = [pressure / 1e6] if pressure is not None else [60.0, 10.0]
    baseline = DFPBearing()
    fields = {k: v for k, v in fields.items() if v != getattr(baseline, k)}
    for p in args.pressure:  # a variant that is no bearing fails here, in one line
        variant = bearing_from(fields, pressure=p * 1e6)
        if args.fem and args.fem_edge_radius:
            _check_edge_radius(variant, args.fem_edge_radius / 1e3)
    out = _locked_output_folder(args)
    motions, label = _motions(args)
    criteria = args.criteria or ((3, 4) if args.quick else (1, 2, 3, 4))
    fem_pressures = args.fem_pressure or (args.pressure[:1] if args.quick else args.pressure)
    unknown = [p for p in fem_pressures if p not in args.pressure]
    if args.fem and unknown:
        raise CommandError(f"--fem-pressure {unknown[0]:g} is not one of --pressure "
                           f"{' '.join(f'{p:g}' for p in args.pressure)}")
    if args.fem_crush is not None and not (args.fem and args.fem_fracture):
        raise CommandError("--fem-crush goes with FE runs and --fem-fracture (the rims' "
                           "crushed elements let go as torn ones do)")
    fem = None
    if args.fem:
        step = args.fem_step or (QUICK_FEM_STEP if args.quick else FULL_FEM_STEP)
        fem = FESettings(mesh=args.fem_mesh, max_step=step, impact_step=min(5e-4, step),
                         kinematics=args.fem_kinematics,
                         limit_states=tuple(dict.fromkeys(args.limit_state)),
                         fracture=args.fem_fracture, edge_radius=args.fem_edge_radius / 1e3,
                         crush_jacobian=args.fem_crush)
    bearing = tuple(fields.items())
    if args.rim_model == "ring" and fem is not None and len(fem.limit_states) != 1:
        raise CommandError("--rim-model ring gives the FE rims the ring's effective depth at "
                           "the limit state searched: give one --limit-state per run")
    if args.keep_stored_laws and not args.rekey_from:
        raise CommandError("--keep-stored-laws goes with --rekey-from")
    if args.rim_fracture and args.rim_model == "ring":
        raise CommandError("--rim-fracture: the law through tearing comes from the "
                           "plane-strain push; it cannot go with --rim-model ring")
    rim_fracture = args.rim_fracture or (
        args.fem_fracture if fem is not None and args.rim_model == "plane-strain" else None)
    slider_edges = _rim_punch_edges(args, rim_fracture)
    crush = _crush(args, slider_edges)
    _store_rim_laws(args, out, bearing, rim_fracture, slider_edges, fem is not None, crush)
    if args.rim_model == "ring" and fem is not None:
        fem = dataclasses.replace(fem, rim_depth=_ring_depth(bearing, fem.limit_states))
    settings = Settings(
        pressures=tuple(p * 1e6 for p in args.pressure), criteria=tuple(criteria),
        stop=args.stop * G, search=args.search, fem=fem,
        fem_pressures=tuple(p * 1e6 for p in fem_pressures),
        fem_records=args.fem_records or (QUICK_FEM_RECORDS if args.quick else None),
        rims=tuple(dict.fromkeys(["rigid", *args.rims])),
        yielding_states=None if args.fem else tuple(dict.fromkeys(args.limit_state)),
        bearing=bearing, rim_model=args.rim_model, rim_fracture=rim_fracture,
        **({} if slider_edges is None
           else {"rim_punch": "slider", "rim_edge_radius": slider_edges,
                 "rim_crush": crush}),
    )
    if not args.replay:
        with open(out / "progress.log", "a") as fh:  # a first line at once (#32): rims' law
            fh.write(f"{time.strftime('%Y-%m-%d %H:%M:%S')}: dfp validate: {len(motions)} "
                     "records; preparing the tasks (the yielding rims' law: FE pushes, cached)\n")
    variant = f"; bearing: {describe_variant(fields)}" if fields else ""
    top = f"; ladder top {args.stop:g} g" if args.stop != LADDER_TOP else ""
    print(f"validation: {len(motions)} records ({label}), pressures "
          f"{', '.join(f'{p:g}' for p in args.pressure)} MPa{variant}{top} -> {out}")
    start = time.perf_counter()
    progress = None if args.progress else False
    if args.rekey_from:
        _rekey(args.rekey_from, motions, settings, out)
    try:
        results, fem_results = run_validation(motions, settings, out, scheduler=args.scheduler,
                                              workers=args.workers, progress=progress,
                                              worker_wait=args.worker_wait, replay=args.replay)
    except MissingResultsError as exc:
        raise CommandError(f"--replay: {exc}") from None
    _print_summary(results, fem_results, settings)
    path = write_report(results, motions, settings, out, elapsed=time.perf_counter() - start,
                        title="DFP bearing failure: validation run", record_set=label,
                        fem=fem_results)
    print(f"report: {path}")
    return 0


def _store_rim_laws(args, out: Path, bearing: tuple, rim_fracture, slider_edges,
                    with_fem: bool, crush: float | None = None) -> None:
    """The rim laws the run uses, pushed (or carried over with ``--rekey-from``) and kept in
    its store, so that the run replays elsewhere (:mod:`validation.stored_rim_laws`)."""
    laws = ([args.rim_model] if "yielding" in args.rims else []) + (
        ["ring", "plane-strain"] if args.rim_model == "ring" and with_fem else [])
    if not laws:
        return
    from rigid.tasks import MissingResultsError, ResultStore
    from rigid.tasks.rekey import RekeyError

    from .stored_rim_laws import carry_rim_laws, keep_rim_laws

    pushed = DFPBearing(**dict(bearing))
    which = {"fracture": rim_fracture if "yielding" in args.rims else None,
             "edge_radius": slider_edges, "crush_jacobian": crush}
    try:
        with ResultStore(out / "results.sqlite") as store:
            if args.rekey_from:
                for line in carry_rim_laws(store, pushed, laws, args.rekey_from,
                                           keep_differing=args.keep_stored_laws, **which):
                    print(f"--rekey-from {args.rekey_from}: {line}")
            keep_rim_laws(store, pushed, laws, replay=args.replay, **which)
    except MissingResultsError as exc:
        raise CommandError(str(exc)) from None
    except RekeyError as exc:
        raise CommandError(f"--rekey-from {args.rekey_from}: {exc}") from None


def _print_summary(results: dict, fem_results: dict, settings) -> None:
    """The console's lines on a finished validation: per pressure, how many records fail
    below the ladder's top (a warning for uncertain ones), and each FE search's answer."""
    for pressure, res in results.items():
        failed = sum(a.sa is not None for a in res.actual)
        numerical = [a for a in res.actual if a.numerical_failures]
        uncertain = [a.name for a in res.actual if a.uncertain]
        line = (f"  {pressure / 1e6:g} MPa: {failed}/{len(res.actual)} records fail below "
                f"{settings.stop / G:g} g")
        if numerical:
            line += (f"; {len(numerical)} with numerical rungs (neither failures nor "
                     f"survivals), {len(uncertain)} of them uncertain")
        print(line)
        if uncertain:
            warnings.warn(f"at {pressure / 1e6:g} MPa the critical SA of "
                          f"{len(uncertain)} record(s) depends on numerical rungs: "
                          f"{', '.join(uncertain[:5])}{' …' if len(uncertain) > 5 else ''} "
                          "(flagged in the report)", stacklevel=1)
    for pressure, found in fem_results.items():
        for r in found:
            sa = ("no failure" if r.sa is None else
                  f"{r.sa / G:.2f} g ({r.failure_mode or 'the run there ended numerically'})")
            rigid_sa = "none" if r.rigid_sa is None else f"{r.rigid_sa / G:.2f} g"
            flag = f", {r.numerical_runs} numerical" if r.numerical_runs else ""
            flag += ", UNCERTAIN" if r.uncertain else ""
            print(f"  FE {pressure / 1e6:g} MPa {r.name} ({r.limit_state}): critical SA {sa}; "
                  f"rigid {rigid_sa}; {r.runs} FE runs{flag}")


def _rekey(revision: str, motions, settings, out: Path) -> None:
    """``--rekey-from``: the results that ``revision``'s code stored in ``out`` under its
    keys, carried over to today's once a rerun of the shortest of each kind gives the same
    result (:func:`rigid.tasks.rekey.rekey`); an unfinished run's as far as it went."""
    from rigid.tasks import ResultStore
    from rigid.tasks.rekey import RekeyError, rekey
    from validation.run import run_validation

    def replay(seen):
        run_validation(motions, settings, out, progress=False, replay=True, seen=seen)

    try:
        with ResultStore(out / "results.sqlite") as store:
            carried = rekey(store, replay, revision)
    except RekeyError as exc:
        raise CommandError(f"--rekey-from {revision}: {exc}") from None
    print(f"--rekey-from {revision}: {carried.describe()}")


def _ring_depth(bearing, limit_states) -> float:
    """The FE rims' depth under ``--rim-model ring``: the ring's effective depth at the one
    limit state searched, the one of ``limit_states`` (:func:`fem.effective_rim_depth`; it
    differs between limit states)."""
    from fem import effective_rim_depth

    try:
        return effective_rim_depth(DFPBearing(**dict(bearing)), limit_states[0])
    except ValueError as exc:
        raise CommandError(str(exc)) from None


def _rim_options(args, bearing) -> dict:
    """The rim model, limit state and (yielding rims) rim law of :func:`rigid.simulate` from
    the arguments; the law from the FE companion's rim push (:func:`fem.rim_law`, cached)."""
    if args.rims == "rigid" and args.limit_state not in (None, "containment"):
        raise CommandError(f"--limit-state {args.limit_state} needs --rims yielding (rigid "
                           "rims cannot yield)")
    limit_state = check_limit_state(args.limit_state, rims=args.rims)
    options = {"rims": args.rims, "limit_state": limit_state}
    if args.rims == "yielding":
        from fem import rim_law

        options["rim_law"] = rim_law(bearing)
    return options
