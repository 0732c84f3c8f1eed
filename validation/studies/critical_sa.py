"""Critical SA study on a FEMA P695 set: actual vs predicted, Table 2, Figs. 11-12, fragility, CMR.

For each bearing pressure: the actual critical SA(4.5 s) of every component (rigid model,
0.01 g ladder; :func:`rigid.critical_sas`, parallel, cached), the best Ricker pulse of each
criterion and the predicted critical SA (:func:`rigid.predict_critical_sa`, region by
simulating the pulse at its own Tp), then writes to ``--out``:

- ``critical_sa_<set>_<MPa>.csv``   the per-record table (pulse, e_a, e_v, actual, predicted,
  error) and ``ladders_<set>_<MPa>.csv`` every rung run (resurrections marked);
- ``table2_<set>.csv``              share of predictions within 20 % (paper Table 2);
- ``fig11_<set>_<MPa>.png``, ``fig12_<set>_<MPa>.png``, ``fragility_<set>_<MPa>.png``;
- ``collapse_margin_<set>.txt``     lognormal fit, CMR/ACMR (per-record and set scaling);
- ``fast_vs_full_<set>_<MPa>_<N>.csv`` with ``--check-full N``: fast and full ladders
  compared on the N records of lowest critical SA per pressure (the shortest full ladders);
  ``--check-only`` skips everything else.

Run (about 20 min per pressure on 2 busy cores with the fast search)::

    python -m validation.studies.critical_sa --set nearfield_pulse --pressures 60e6 10e6 \
        --search fast --processes 2
"""

from __future__ import annotations

import argparse
import hashlib
import os
import pickle
import time
from pathlib import Path

import numpy as np

import rigid
from rigid.collapse.comparison import comparison_rows, ladder_rows, table2, write_csv
from rigid.collapse.fragility import collapse_margin, fit_lognormal
from rigid.collapse.predict import predict_critical_sa, pulse_region
from rigid.collapse.record_set import critical_sas, pool_context
from rigid.tasks import Task, cache_root, code_hash, run_tasks

from . import RESULTS

G = rigid.G


def _predict_record(motion, bearings, criteria, search, cache_dir):
    """All predictions of one record: {(pressure, criterion): PredictedSA} (cached per bearing)."""
    pulses = None
    out = {}
    for b in bearings:
        key = hashlib.sha256(np.ascontiguousarray(motion.acceleration).tobytes())
        key.update(repr((motion.dt, [b], criteria, search,
                         code_hash("rigid", "motions", "collapse"), "predict-1")).encode())
        path = None if cache_dir is None else Path(cache_dir) / f"pred-{key.hexdigest()}.pkl"
        if path is not None and path.exists():
            out.update(pickle.loads(path.read_bytes()))
            continue
        if pulses is None:
            pulses = {c: rigid.best_pulse(motion, criterion=c) for c in criteria}
        mine, regions = {}, {}
        for c in criteria:
            kind = pulses[c].kind
            regions.setdefault(kind, pulse_region(b, kind))  # shared by criteria: same kind
            pred = predict_critical_sa(b, motion, pulses[c], region=regions[kind],
                                       search=search)
            mine[(b.pressure, c)] = _with_criterion(pred, c)
        if path is not None:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(pickle.dumps(mine))
        out.update(mine)
    return out


def _with_criterion(pred, c):
    from dataclasses import replace

    return replace(pred, criterion=c)


def predictions(motions, bearings, criteria, search, processes, cache_dir):
    """:func:`_predict_record` of every record, in record order, through
    :func:`rigid.tasks.run_tasks` (forkserver, else spawn, as :func:`rigid.critical_sas`;
    ``processes=1`` runs them in this process)."""
    tasks = [Task(str(i), "predictions", _predict_record,
                  {"motion": m, "bearings": bearings, "criteria": criteria, "search": search,
                   "cache_dir": cache_dir}) for i, m in enumerate(motions)]
    results = run_tasks(tasks, None, workers=max(1, processes), progress=True,
                        description="predictions", unit="record",
                        start_method=pool_context().get_start_method())
    return [results[t.key] for t in tasks]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--set", default="nearfield_pulse")
    ap.add_argument("--pressures", type=float, nargs="+", default=[60e6, 10e6])
    ap.add_argument("--criteria", type=int, nargs="+", default=[3, 4])
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
    motions = rigid.fema_p695(args.set)[: args.records]
    bearings = [rigid.DFPBearing(pressure=p) for p in args.pressures]
    tag = args.set
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

    if not args.check_only:
        _study(args, motions, bearings, actual, out, tag)
    if args.check_full:
        _check_full(args, motions, bearings, actual, out, tag)
    print(f"total {time.perf_counter() - t0:.0f} s; outputs in {out}")


def _study(args, motions, bearings, actual, out, tag):
    t = time.perf_counter()
    preds = predictions(motions, bearings, args.criteria, args.predict_search, args.processes,
                        args.cache)
    print(f"predictions in {time.perf_counter() - t:.0f} s", flush=True)

    t2_rows, cm_lines = [], []
    for b in bearings:
        mpa = f"{b.pressure / 1e6:g}MPa"
        act = actual[b.pressure]
        by_c = {c: [p[(b.pressure, c)] for p in preds] for c in args.criteria}
        rows = comparison_rows(act, by_c)
        write_csv(rows, out / f"critical_sa_{tag}_{mpa}.csv")
        write_csv(ladder_rows(act), out / f"ladders_{tag}_{mpa}.csv")
        for c in args.criteria:
            t2 = table2(rows, c)
            t2_rows.append({"pressure_MPa": b.pressure / 1e6, "criterion": c,
                            **{f"{k}_good": v[0] for k, v in t2.items()},
                            **{f"{k}_n": v[1] for k, v in t2.items()}})
            print(f"{mpa} criterion {c}: within 20 % " + ", ".join(
                f"{k} {v[0]}/{v[1]}" for k, v in t2.items()), flush=True)
        _figures(rows, act, by_c, out, tag, mpa, args.criteria)
        resurrected = [a.name for a in act if a.resurrected]
        cm_lines.append(f"== {mpa}: {len(act)} records, {sum(a.sa is None for a in act)} "
                        f"without failure up to {act[0].stop / G:.2f} g; resurrections "
                        f"(within {args.after_failure} rungs above): {resurrected or 'none'}")
        nm = [m.metadata["normalization_factor"] for m in motions]
        fit = fit_lognormal(act)
        cm = collapse_margin(act, period=b.design_period, sdc=args.sdc,
                             record_set="nearfield" if "near" in tag else "farfield",
                             normalization=nm)
        cm_lines += [f"lognormal fit: median {fit.median / G:.3f} g, β = {fit.beta:.3f}",
                     cm.summary(), ""]
    write_csv(t2_rows, out / f"table2_{tag}.csv")
    (out / f"collapse_margin_{tag}.txt").write_text("\n".join(cm_lines) + "\n")
    print("\n".join(cm_lines))



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
    fig = plot_fragility(fit_lognormal(act), [a.sa for a in act], label=f"{tag}, {mpa}")
    fig.savefig(out / f"fragility_{tag}_{mpa}.png", dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
