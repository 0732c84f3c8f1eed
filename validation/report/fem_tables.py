"""The FE part of a validation report's data: one row per FE critical-SA search
(:func:`fem_rows`), the statistics of FE against rigid critical SA per limit state and the
verdicts on the project's claims (:func:`fem_statistics`, :func:`claim_verdicts`), one row per
FE run (:func:`fem_run_rows`) and the FE-against-rigid figure (:func:`plot_fem_vs_rigid`).
Used by :func:`validation.report.write_report` and the FE validation studies."""

from __future__ import annotations

import numpy as np

from rigid import G
from rigid.limit_states import LIMIT_STATES
from validation.fem_search import verdict_of

__all__ = ["claim_verdicts", "fem_rows", "fem_run_rows", "fem_statistics", "meets_goal",
           "plot_fem_vs_rigid", "within_band"]


def fem_rows(fem: dict) -> list[dict]:
    """One row per FE search: record, pressure_mpa, the limit state, rigid and FE critical SA
    [g], their ratio, the FE failure mode and time [s], the highest surviving SA below it [g],
    runs (numerical ones, and whether the answer depends on them), CPU [min]."""
    rows = []
    for pressure, found in fem.items():
        for r in found:
            ratio = (r.sa / r.rigid_sa) if (r.sa is not None and r.rigid_sa is not None) \
                else None
            y_ratio = (r.sa / r.yielding_sa) if (r.sa is not None and r.yielding_sa
                                                 is not None) else None
            rows.append({
                "record": r.name, "pressure_mpa": pressure / 1e6,
                "limit_state": r.limit_state,
                "rigid_sa_g": None if r.rigid_sa is None else r.rigid_sa / G,
                "fem_sa_g": None if r.sa is None else r.sa / G,
                "fem_over_rigid": ratio,
                "yielding_sa_g": None if r.yielding_sa is None else r.yielding_sa / G,
                "fem_over_yielding": y_ratio,
                "fem_failure_mode": r.failure_mode or "none",
                "fem_failure_time_s": r.failure_time,
                "survived_below_g": None if r.survived_below is None else r.survived_below / G,
                "fem_runs": r.runs, "numerical_runs": r.numerical_runs,
                "uncertain": r.uncertain, "cpu_min": r.cpu_seconds / 60,
            })
    return rows


def within_band(ratios, band: float):
    """True where a ratio lies within ±``band`` of 1 (``band`` as a fraction: 0.2 for ±20 %).

    Critical SAs are rungs of 0.01 g, so ratios fall exactly on a band's edge (0.18 g against
    0.15 g); the edge counts as inside, with a 1e-9 allowance for rounding, which would
    otherwise put a rung stored as 0.18000000000000002 g over 0.15 g (1.2000000000000002)
    outside."""
    return np.abs(np.asarray(ratios, dtype=float) - 1) <= band + 1e-9


def fem_statistics(rows: list[dict]) -> list[dict]:
    """Paper Fig. 4 in numbers: per FE limit state and rim model of the rigid model, over the
    searches with both answers and no uncertainty, the median FE / rigid ratio, its
    dispersion (standard deviation of its logarithm) and how many lie within ±20 % and ±35 %
    (the ±15 % median and ±35 % per-record goal of docs/fem_validation.md). The yielding-rim
    row is left out when the run made no yielding-rim ladders, kept (with no case compared)
    when every search was uncertain."""
    out = []
    for state in LIMIT_STATES:
        for model, key in (("rigid rims", "fem_over_rigid"),
                           ("yielding rims", "fem_over_yielding")):
            of_state = [r for r in rows if r["limit_state"] == state]
            ratios = np.array([r[key] for r in of_state
                               if r.get(key) is not None and not r["uncertain"]], dtype=float)
            if not of_state or (model == "yielding rims" and all(
                    r.get("yielding_sa_g") is None and r.get(key) is None for r in of_state)):
                continue
            searched = len(of_state)
            out.append({
                "limit_state": state, "rigid_model": model, "cases": searched,
                "compared": int(ratios.size),
                "median_ratio": float(np.median(ratios)) if ratios.size else None,
                "dispersion": float(np.std(np.log(ratios))) if ratios.size > 1 else None,
                "within_20_percent": int(np.sum(within_band(ratios, 0.2))),
                "within_35_percent": int(np.sum(within_band(ratios, 0.35))),
            })
    return out


def meets_goal(stat: dict) -> bool:
    """Whether a row of :func:`fem_statistics` meets the goal of docs/fem_validation.md: the
    median FE / rigid within ±15 % and every compared case within ±35 % (False with no case
    compared)."""
    return bool(stat["compared"] and within_band(stat["median_ratio"], 0.15)
                and stat["within_35_percent"] == stat["compared"])


def claim_verdicts(stats: list[dict]) -> list[str]:
    """One sentence per row of :func:`fem_statistics`: does the rigid model agree with the FE
    model by the goal of docs/fem_validation.md (median FE / rigid within ±15 % and every
    compared case within ±35 %)? Cases without both answers are named, not judged."""
    out = []
    for s in stats:
        head = f"{s['limit_state']}, {s['rigid_model']}: "
        if not s["compared"]:
            out.append(head + f"no case with both answers among {s['cases']}.")
            continue
        holds = meets_goal(s)
        missing = s["cases"] - s["compared"]
        out.append(
            head + f"median FE / rigid {s['median_ratio']:.2f}, {s['within_20_percent']} of "
            f"{s['compared']} within ±20 % and {s['within_35_percent']} within ±35 %"
            + (f" ({missing} of {s['cases']} cases without both answers)" if missing else "")
            + (": agrees by the goal." if holds else ": does not agree by the goal."))
    return out


def fem_run_rows(fem: dict) -> list[dict]:
    """Every FE run, in the order each search made them (a run shared by the searches of
    several limit states is listed under each, with that limit state's verdict: ``failed``
    True, False or "numerical", and the mode and time [s] of that failure), with the times
    [s] it reached each limit state and, for a run that ended numerically, why
    (``numerical_detail``)."""
    rows = []
    for pressure, found in fem.items():
        for r in found:
            for k, p in enumerate(r.probes):
                times = p.get("limit_states") or {}
                mode, time = verdict_of(p, r.limit_state) if p["failed"] else (None, None)
                rows.append({
                    "record": r.name, "pressure_mpa": pressure / 1e6,
                    "limit_state": r.limit_state, "run": k + 1,
                    "sa_g": p["sa"] / G, "scale": p["scale"],
                    "failed": "numerical" if p["failed"] is None else bool(p["failed"]),
                    "failure_mode": mode or "none",
                    **{f"{state}_s": times.get(state) for state in LIMIT_STATES},
                    "failure_time_s": time,
                    "numerical_failure": bool(p.get("numerical_failure", False)),
                    "numerical_detail": (p.get("detail") if p.get("numerical_failure")
                                         else None),
                    "start_s": p.get("start"), "strong_end_s": p.get("strong_end"),
                    "end_s": p.get("end"), "quiet": bool(p.get("quiet", True)),
                    "energy_end_over_reach": (p["energy_end"] / p["reach_energy"]
                                              if p.get("reach_energy") else None),
                    "steps": p.get("steps"), "newton_iterations": p.get("newton_iterations"),
                    "dofs": p.get("dofs"),
                    "max_plastic_strain": p.get("max_plastic_strain"),
                    "max_rim_force_mn": (p["max_rim_force"] / 1e6
                                         if p.get("max_rim_force") is not None else None),
                    "cpu_s": p.get("cpu_seconds"),
                })
    return rows


_MODES = {"yielding": ("^", "FE: rim yielding"), "uplift": ("o", "FE: uplift"),
          "none": ("v", "no FE failure (at the top)"),
          "uncertain": ("D", "FE uncertain: lower bound")}


def plot_fem_vs_rigid(rows: list[dict], stop: float):
    """Paper Fig. 4: FE against rigid critical SA(Tb) [g] per record, one panel per limit
    state, 1:1 line and ±20 % band, FE failure mode by marker, pressure by colour; a search
    without failure sits at ``stop`` [g] with a hollow marker, an uncertain one (a numerical
    run at or below its answer) at its highest surviving SA, a lower bound, with a hollow
    diamond (and a plus against yielding rims)."""
    import matplotlib.pyplot as plt

    states = [s for s in LIMIT_STATES if any(r["limit_state"] == s for r in rows)]
    fig, axes = plt.subplots(1, len(states), figsize=(4.4 * len(states), 4.6), squeeze=False)
    for ax, state in zip(axes[0], states, strict=True):
        _fem_vs_rigid_panel(ax, [r for r in rows if r["limit_state"] == state], stop)
        ax.set_title(f"FE limit state: {state}", fontsize=10)
    fig.tight_layout()
    return fig


def _fem_vs_rigid_panel(ax, rows, stop):
    colours = dict(zip(sorted({r["pressure_mpa"] for r in rows}, reverse=True),
                       ("tab:red", "tab:blue", "tab:green", "tab:purple"), strict=False))
    values = [stop if v is None else v for r in rows
              for v in (r["rigid_sa_g"], r["fem_sa_g"], r.get("yielding_sa_g"))]
    top = 1.1 * max([*values, 0.1])
    ax.plot([0, top], [0, top], "k-", lw=1, label="1:1")
    ax.fill_between([0, top], [0, 0.8 * top], [0, 1.2 * top], color="0.9", lw=0,
                    label="±20 %")
    seen = set()
    for r in rows:
        uncertain = bool(r.get("uncertain"))
        mode = ("uncertain" if uncertain else
                r["fem_failure_mode"] if r["fem_sa_g"] is not None else "none")
        marker, text = _MODES.get(mode, ("s", mode))
        x = r["rigid_sa_g"] if r["rigid_sa_g"] is not None else stop
        y = (r.get("survived_below_g") if uncertain
             else r["fem_sa_g"] if r["fem_sa_g"] is not None else stop)
        if y is None:  # uncertain from the lowest rung: nothing to show
            continue
        colour = colours.get(r["pressure_mpa"], "k")
        label = f"{r['pressure_mpa']:g} MPa, against rigid rims ({text})"
        hollow = mode in ("none", "uncertain") or r["rigid_sa_g"] is None
        ax.plot(x, y, marker, color=colour, ms=8 if marker != "D" else 6,
                mfc="none" if hollow else colour, label=None if label in seen else label)
        seen.add(label)
        if r.get("yielding_sa_g") is not None:  # the same FE answer against yielding rims
            label = (f"{r['pressure_mpa']:g} MPa, against yielding rims"
                     + (" (FE lower bound)" if uncertain else ""))
            ax.plot(r["yielding_sa_g"], y, "+" if uncertain else "x", color=colour, ms=8,
                    label=None if label in seen else label)
            seen.add(label)
    ax.set_xlim(0, top)
    ax.set_ylim(0, top)
    ax.set_aspect("equal")
    ax.set_xlabel("rigid model critical SA(Tb) [g]")
    ax.set_ylabel("FE model critical SA(Tb) [g]")
    ax.legend(fontsize=7, loc="upper left")
