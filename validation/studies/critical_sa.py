"""Critical SA study on a FEMA P695 set: actual vs predicted, Table 2, Figs. 11-12, fragility, CMR.

For each bearing pressure: the actual critical SA(4.5 s) of every component (rigid model,
0.01 g ladder; :func:`rigid.critical_sas`, parallel, cached), the same with yielding rims up
to the first rim hinge (the second "actual"), the best Ricker pulse of each criterion under
each pulse extraction (the paper's pooled weightings, and each single weighting) and its
predicted critical SA (:func:`rigid.predict_critical_sa`, region by simulating the pulse at
its own Tp), then writes to ``--out``:

- ``critical_sa_<set>_<MPa>.csv``   the per-record table of the paper's procedure (pulse,
  e_a, e_v, actual with rigid and yielding rims, predicted, error) and
  ``ladders_<set>_<MPa>.csv`` every rung run (resurrections marked);
- ``predictions_<set>.csv``         every record × pressure × extraction × actual;
- ``table2_<set>.csv``              share of predictions within 20 % (paper Table 2) per
  pressure, extraction, criterion and actual, with the median error and the records left out;
- ``fig11_<set>_<MPa>.png``, ``fig12_<set>_<MPa>.png``, ``fragility_<set>_<MPa>.png``;
- ``collapse_margin_<set>.txt``     lognormal fit, CMR/ACMR (per-record and set scaling);
- ``fast_vs_full_<set>_<MPa>_<N>.csv`` with ``--check-full N``: fast and full ladders
  compared on the N records of lowest critical SA per pressure (the shortest full ladders);
  ``--check-only`` skips everything else.

Run (about 20 min per pressure on 2 busy cores with the fast search)::

    python -m validation.studies.critical_sa --set nearfield_pulse --pressures 60e6 10e6 \
        --search fast --processes 2

or on record files (e.g. ``--files RSN1120_KOBE_TAK090.AT2 --tag takatori``).
"""

from __future__ import annotations

import argparse
import hashlib
import math
import os
import pickle
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

import rigid
from rigid.collapse.comparison import comparison_rows, ladder_rows, table2, write_csv
from rigid.collapse.fragility import collapse_margin, fit_lognormal
from rigid.collapse.predict import predict_critical_sa, pulse_region
from rigid.collapse.record_set import critical_sas, pool_context
from rigid.motions import ALL_WEIGHTINGS, WEIGHTINGS
from rigid.tasks import Task, cache_root, code_hash, run_tasks

from . import RESULTS

G = rigid.G


def _predict_record(motion, bearings, criteria, weightings, search, cache_dir):
    """All predictions of one record: {(pressure, weighting, criterion): PredictedSA} (cached
    per bearing). A pulse found by several (weighting, criterion) pairs is predicted once."""
    pulses = None
    out = {}
    for b in bearings:
        key = hashlib.sha256(np.ascontiguousarray(motion.acceleration).tobytes())
        key.update(repr((motion.dt, [b], criteria, weightings, search,
                         code_hash("rigid", "motions", "collapse"), "predict-2")).encode())
        path = None if cache_dir is None else Path(cache_dir) / f"pred-{key.hexdigest()}.pkl"
        if path is not None and path.exists():
            out.update(pickle.loads(path.read_bytes()))
            continue
        if pulses is None:
            pulses = {(w, c): rigid.best_pulse(motion, criterion=c, weighting=w)
                      for w in weightings for c in criteria}
        mine, regions, done = {}, {}, {}
        for (w, c), pulse in pulses.items():
            if pulse not in done:
                kind = pulse.kind
                regions.setdefault(kind, pulse_region(b, kind))  # shared by pulses of a kind
                done[pulse] = predict_critical_sa(b, motion, pulse, region=regions[kind],
                                                  search=search)
            mine[(b.pressure, w, c)] = replace(done[pulse], criterion=c)
        if path is not None:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(pickle.dumps(mine))
        out.update(mine)
    return out


def predictions(motions, bearings, criteria, weightings, search, processes, cache_dir):
    """:func:`_predict_record` of every record, in record order, through
    :func:`rigid.tasks.run_tasks` (forkserver, else spawn, as :func:`rigid.critical_sas`;
    ``processes=1`` runs them in this process)."""
    tasks = [Task(str(i), "predictions", _predict_record,
                  {"motion": m, "bearings": bearings, "criteria": criteria,
                   "weightings": weightings, "search": search, "cache_dir": cache_dir})
             for i, m in enumerate(motions)]
    results = run_tasks(tasks, None, workers=max(1, processes), progress=True,
                        description="predictions", unit="record",
                        start_method=pool_context().get_start_method())
    return [results[t.key] for t in tasks]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--set", default="nearfield_pulse")
    ap.add_argument("--pressures", type=float, nargs="+", default=[60e6, 10e6])
    ap.add_argument("--files", nargs="+", help="record files instead of --set (any format "
                    "rigid.read_record reads; the study's tag is --tag)")
    ap.add_argument("--tag", help="name of the outputs with --files")
    ap.add_argument("--criteria", type=int, nargs="+", default=[3, 4])
    ap.add_argument("--weightings", nargs="+", default=[ALL_WEIGHTINGS, *WEIGHTINGS],
                    help="pulse extractions compared: 'all' (the paper's pooled procedure, the "
                    "one of critical_sa_*.csv and the figures) and single weightings")
    ap.add_argument("--no-yielding", action="store_true",
                    help="skip the yielding-rim critical SA (hinge), the second 'actual'")
    ap.add_argument("--search", choices=("full", "fast"), default="fast")
    ap.add_argument("--predict-search", choices=("full", "fast", "bisect"), default="fast",
                    help="search of the predicted ladder (bisect assumes one failure boundary "
                         "per Tp, which pulses with failure lobes break)")
    ap.add_argument("--after-failure", type=int, default=3)
    ap.add_argument("--processes", type=int, default=os.cpu_count())
    ap.add_argument("--records", type=int, default=None, help="only the first N components")
    ap.add_argument("--check-full", type=int, default=0,
                    help="compare fast and full ladders on the N records with the lowest "
                         "critical SA (the cheapest full ladders), per pressure")
    ap.add_argument("--check-only", action="store_true",
                    help="only the fast/full comparison (no tables, figures or predictions)")
    ap.add_argument("--cache", default=str(cache_root() / "ladders"))
    ap.add_argument("--out", default=str(RESULTS))
    ap.add_argument("--sdc", default="dmax", help="SDC for S_MT and the SSF")
    args = ap.parse_args()

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.files:
        motions = [rigid.read_record(f) for f in args.files]
        tag = args.tag or "records"
    else:
        motions = rigid.fema_p695(args.set)[: args.records]
        tag = args.set
    bearings = [rigid.DFPBearing(pressure=p) for p in args.pressures]
    t0 = time.perf_counter()

    actual = {}
    for b in bearings:
        t = time.perf_counter()
        actual[b.pressure] = critical_sas(b, motions, processes=args.processes, cache=args.cache,
                                          search=args.search, after_failure=args.after_failure)
        cpu = sum(r.cpu_seconds for r in actual[b.pressure])
        print(f"{b.pressure / 1e6:g} MPa: actual critical SA of {len(motions)} records in "
              f"{time.perf_counter() - t:.0f} s ({args.search} search; simulation CPU "
              f"{cpu:.0f} s for the rungs not in the cache)", flush=True)

    yielding = {} if args.no_yielding or args.check_only else _yielding(args, motions, bearings)
    if not args.check_only:
        _study(args, motions, bearings, actual, yielding, out, tag)
    if args.check_full:
        _check_full(args, motions, bearings, actual, out, tag)
    print(f"total {time.perf_counter() - t0:.0f} s; outputs in {out}")


def _yielding(args, motions, bearings):
    """The yielding-rim critical SA at the first rim hinge, per pressure: the second "actual"
    (docs/critical_sa.md, "The paper's prediction as written")."""
    from fem import rim_law

    out = {}
    for b in bearings:
        t = time.perf_counter()
        out[b.pressure] = critical_sas(b, motions, processes=args.processes, cache=args.cache,
                                       search=args.search, after_failure=args.after_failure,
                                       rims="yielding", limit_state="hinge",
                                       rim_law=rim_law(b))
        print(f"{b.pressure / 1e6:g} MPa: yielding-rim critical SA (hinge) in "
              f"{time.perf_counter() - t:.0f} s", flush=True)
    return out


def _study(args, motions, bearings, actual, yielding, out, tag):
    t = time.perf_counter()
    preds = predictions(motions, bearings, args.criteria, args.weightings,
                        args.predict_search, args.processes, args.cache)
    print(f"predictions in {time.perf_counter() - t:.0f} s", flush=True)

    t2_rows, long_rows, cm_lines = [], [], []
    for b in bearings:
        mpa = f"{b.pressure / 1e6:g}MPa"
        act = actual[b.pressure]
        actuals = {"rigid rims": act}
        if b.pressure in yielding:
            actuals["yielding rims (hinge)"] = yielding[b.pressure]
        for w in args.weightings:
            by_c = {c: [p[(b.pressure, w, c)] for p in preds] for c in args.criteria}
            for label, reference in actuals.items():
                rows = comparison_rows(reference, by_c)
                long_rows += [{"pressure_MPa": b.pressure / 1e6, "weighting": w,
                               "actual": label, **r} for r in rows]
                t2_rows += _table2_rows(rows, b, w, label, args.criteria)
            if w == args.weightings[0]:
                rows = comparison_rows(act, by_c)
                if b.pressure in yielding:
                    for r, y in zip(rows, yielding[b.pressure], strict=True):
                        r["actual_yielding_sa_g"] = np.nan if y.sa is None else y.sa / G
                write_csv(rows, out / f"critical_sa_{tag}_{mpa}.csv")
                _figures(rows, act, by_c, out, tag, mpa, args.criteria)
        write_csv(ladder_rows(act), out / f"ladders_{tag}_{mpa}.csv")
        resurrected = [a.name for a in act if a.resurrected]
        cm_lines.append(f"== {mpa}: {len(act)} records, {sum(a.sa is None for a in act)} "
                        f"without failure up to {act[0].stop / G:.2f} g; resurrections "
                        f"(within {args.after_failure} rungs above): {resurrected or 'none'}")
        if args.files:  # a check on a few records: no fragility
            cm_lines.append("")
            continue
        fit = fit_lognormal(act)
        cm_lines.append(f"lognormal fit: median {fit.median / G:.3f} g, β = {fit.beta:.3f}")
        nm = [m.metadata["normalization_factor"] for m in motions]
        cm = collapse_margin(act, period=b.design_period, sdc=args.sdc,
                             record_set="nearfield" if "near" in tag else "farfield",
                             normalization=nm)
        cm_lines += [cm.summary(), ""]
    write_csv(t2_rows, out / f"table2_{tag}.csv")
    write_csv(long_rows, out / f"predictions_{tag}.csv")
    (out / f"collapse_margin_{tag}.txt").write_text("\n".join(cm_lines) + "\n")
    print("\n".join(cm_lines))


def _table2_rows(rows, bearing, weighting, actual, criteria):
    """Paper Table 2 (Eq. C6) of one pulse extraction against one actual, per criterion, with
    the median error and the records left out (no actual failure, or uncertain)."""
    out = []
    for c in criteria:
        t2 = table2(rows, c)
        errors = [r[f"error_{c}"] for r in rows if not math.isnan(r["actual_sa_g"])
                  and not r.get("uncertain", False)]
        left_out = [r["record"].split()[-1] for r in rows if math.isnan(r["actual_sa_g"])
                    or r.get("uncertain", False)]
        missing = [r["record"].split()[-1] for r in rows if not math.isnan(r["actual_sa_g"])
                   and math.isnan(r[f"error_{c}"])]
        out.append({"pressure_MPa": bearing.pressure / 1e6, "weighting": weighting,
                    "criterion": c, "actual": actual,
                    **{f"{k}_good": v[0] for k, v in t2.items()},
                    **{f"{k}_n": v[1] for k, v in t2.items()},
                    "median_error": float(np.nanmedian(errors)) if errors else math.nan,
                    "no_prediction": " ".join(missing), "left_out": " ".join(left_out)})
        print(f"{bearing.pressure / 1e6:g} MPa, w = {weighting}, criterion {c}, against "
              f"{actual}: within 20 % " + ", ".join(f"{k} {v[0]}/{v[1]}" for k, v in t2.items())
              + f"; median error {out[-1]['median_error']:+.0%}", flush=True)
    return out


def _check_full(args, motions, bearings, actual, out, tag):
    rows = []
    for b in bearings:
        act = actual[b.pressure]
        order = sorted(range(len(act)), key=lambda i: np.inf if act[i].sa is None
                       else act[i].sa)[: args.check_full]
        fulls = critical_sas(b, [motions[i] for i in order], processes=args.processes,
                             cache=args.cache, search="full")
        for i, full in zip(order, fulls, strict=True):
            a = act[i]
            rows.append({"pressure_MPa": b.pressure / 1e6, "record": a.name,
                         "fast_sa_g": np.nan if a.sa is None else a.sa / G,
                         "full_sa_g": np.nan if full.sa is None else full.sa / G,
                         "fast_rungs": len(a.rungs), "full_rungs": len(full.rungs),
                         "same": a.sa == full.sa})
            print(f"{b.pressure / 1e6:g} MPa {a.name}: fast {rows[-1]['fast_sa_g']:.2f} g, "
                  f"full {rows[-1]['full_sa_g']:.2f} g", flush=True)
    mpa = "_".join(f"{b.pressure / 1e6:g}" for b in bearings)
    write_csv(rows, out / f"fast_vs_full_{tag}_{mpa}MPa_{args.check_full}.csv")


def _figures(rows, act, by_c, out, tag, mpa, criteria):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rigid.collapse.plots import plot_comparison, plot_fragility, plot_prediction

    fig, axes = plt.subplots(1, len(criteria), figsize=(4.5 * len(criteria), 4.5),
                             constrained_layout=True)
    for ax, c in zip(np.atleast_1d(axes), criteria, strict=True):
        plot_comparison(rows, c, ax=ax)
    fig.suptitle(f"{tag}, {mpa}", fontsize=9)
    fig.savefig(out / f"fig12_{tag}_{mpa}.png", dpi=110)
    plt.close(fig)
    c = criteria[-1]
    i = next((k for k, p in enumerate(by_c[c]) if p.sa is not None and act[k].sa is not None), 0)
    fig = plot_prediction(by_c[c][i], actual=act[i])
    fig.savefig(out / f"fig11_{tag}_{mpa}.png", dpi=110)
    plt.close(fig)
    if sum(a.sa is not None for a in act) >= 2:  # a lognormal needs two failures
        fig = plot_fragility(fit_lognormal(act), [a.sa for a in act], label=f"{tag}, {mpa}")
        fig.savefig(out / f"fragility_{tag}_{mpa}.png", dpi=110)
        plt.close(fig)


if __name__ == "__main__":
    main()
