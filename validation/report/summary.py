"""The report's first section, "Summary": what was run, the critical SA per pressure, model
and limit state, the FE model against the rigid one in a line per limit state, which model to
trust for what, the prediction's record and the collapse margin, beside the key figure; every
sentence made from the run's numbers (nothing here goes stale when a run is repeated).

:func:`answer_rows` gives the table of answers, :func:`summary_lines` the sentences,
:func:`significant` the precision rule of small samples; :func:`write_summary` puts them in a
:class:`validation.report.html.Report`."""

from __future__ import annotations

import math

import numpy as np

from rigid import G
from rigid.limit_states import LIMIT_STATES

from .fem_tables import meets_goal

__all__ = ["FEW_RECORDS", "answer_rows", "answers", "design_period", "plot_answers",
           "significant", "summary_lines", "what_ran", "write_summary"]

#: Fewer records than this give a fragility (median, β) and a collapse margin two significant
#: digits at most, with a warning: the standard error of a lognormal median from n records is
#: β/√n, about 20 % for β = 0.6 and n = 9, so a third digit means nothing.
FEW_RECORDS = 10


def significant(value: float, n: int) -> str:
    """``value`` with 3 significant digits, or 2 when it comes from fewer than
    :data:`FEW_RECORDS` records (``n``)."""
    if value is None or not math.isfinite(value):
        return "—"
    return f"{value:.{2 if n < FEW_RECORDS else 3}g}"


def _stats(values) -> tuple[int, float | None, float | None, float | None]:
    """(failures, median, lowest, highest) of critical SAs [m/s²] in g (None: no failure)."""
    failed = [v / G for v in values if v is not None]
    if not failed:
        return 0, None, None, None
    return len(failed), float(np.median(failed)), min(failed), max(failed)


def _cell(values, n: int) -> str:
    """"0.27 (0.15–0.46) 4/4": median (range) and failures of ``n`` cases, over the certain
    answers ``values``."""
    failed, median, low, high = _stats(values)
    if not failed:
        return f"none up to the top, 0/{n}" if n else "—"
    spread = f" ({low:.2f}–{high:.2f})" if failed > 1 else ""
    return f"{median:.2f}{spread} {failed}/{n}"


def answers(results: dict, fem_rows: list | None = None) -> dict:
    """The certain critical SAs [m/s², None: no failure] by (pressure [Pa], limit state,
    model), model one of "rigid rims" (containment only), "yielding rims", "FE model"; the
    number of uncertain answers left out by the same key under ``"uncertain"``."""
    fem_rows = fem_rows or []
    out: dict = {"uncertain": {}}
    def put(key, found):
        out[key] = [a.sa for a in found if not a.uncertain]
        out["uncertain"][key] = sum(bool(a.uncertain) for a in found)

    for pressure, res in results.items():
        put((pressure, "containment", "rigid rims"), res.actual)
        for state, ladders in res.yielding.items():
            put((pressure, state, "yielding rims"), ladders)
        for state in LIMIT_STATES:
            fem = [r for r in fem_rows
                   if r["limit_state"] == state and r["pressure_mpa"] == pressure / 1e6]
            if fem:
                key = (pressure, state, "FE model")
                out[key] = [None if r["fem_sa_g"] is None else r["fem_sa_g"] * G
                            for r in fem if not r["uncertain"]]
                out["uncertain"][key] = sum(bool(r["uncertain"]) for r in fem)
    return out


def plot_answers(results: dict, fem_rows: list | None = None):
    """The key figure: the critical SA(Tb) [g] of each model under each limit state, a dot
    at the median and a bar over the records' range, one colour and marker per pressure."""
    import matplotlib.pyplot as plt

    found = answers(results, fem_rows)
    keys = [k for k in found if k != "uncertain"]
    rows = []
    for state in LIMIT_STATES:
        for model in ("rigid rims", "yielding rims", "FE model"):
            if any(k[1] == state and k[2] == model for k in keys):
                rows.append((state, model))
    pressures = list(results)
    fig, ax = plt.subplots(figsize=(4.6, 0.42 * len(rows) + 1.3))
    styles = list(zip(("tab:red", "tab:blue", "tab:green", "tab:purple"), "os^D",
                      strict=True))
    for j, pressure in enumerate(pressures):
        colour, marker = styles[j % len(styles)]
        offset = (j - (len(pressures) - 1) / 2) * 0.18
        label = f"{pressure / 1e6:g} MPa"
        for i, (state, model) in enumerate(rows):
            failed = [v / G for v in found.get((pressure, state, model), []) if v is not None]
            if not failed:
                continue
            y = i + offset
            ax.plot([min(failed), max(failed)], [y, y], "-", color=colour, lw=1.5)
            ax.plot(float(np.median(failed)), y, marker, color=colour, ms=7, label=label)
            label = None
    ax.set_yticks(range(len(rows)), [f"{m}, {s}" for s, m in rows], fontsize=8)
    ax.invert_yaxis()
    ax.set_xlim(left=0)
    ax.set_xlabel("critical SA(Tb) [g]: median (marker), range over records (bar)",
                  fontsize=8)
    ax.grid(axis="x", color="0.9")
    if ax.get_legend_handles_labels()[1]:  # none when no record failed
        ax.legend(fontsize=8, loc="lower right", title="slider pressure", title_fontsize=8)
    fig.tight_layout()
    return fig


def answer_rows(results: dict, fem_rows: list | None = None) -> list[dict]:
    """The answers by pressure and limit state: the critical SA(Tb) [g] of the rigid model
    with rigid rims (containment only), with yielding rims, and of the FE model, each
    "median (lowest–highest) failed/cases", over the answers that are not uncertain."""
    found = answers(results, fem_rows)
    rows = []
    for pressure in results:
        states = [s for s in LIMIT_STATES if any(k != "uncertain" and k[:2] == (pressure, s)
                                                 for k in found)]
        for state in states:
            row = {"pressure [MPa]": pressure / 1e6, "limit state": state}
            for model in ("rigid rims", "yielding rims", "FE model"):
                values = found.get((pressure, state, model))
                if values is None:
                    row[model] = ("cannot yield" if model == "rigid rims" else "not run")
                    continue
                row[model] = _cell(values, len(values))
                left_out = found["uncertain"].get((pressure, state, model))
                if left_out:
                    row[model] += f" ({left_out} uncertain)"
            rows.append(row)
    return rows


def _trust(stats: list[dict]) -> list[str]:
    """Which model to trust for what, from :func:`validation.report.fem_statistics`' rows:
    the rigid model with each rim model against the FE model, per limit state, by the goal
    (median within ±15 %, every case within ±35 %); a sentence per rim model."""
    out = []
    for model in ("rigid rims", "yielding rims"):
        rows = [s for s in stats if s["rigid_model"] == model and s["compared"]]
        if not rows:
            continue
        good, low, high = [], [], []
        for s in rows:
            if meets_goal(s):
                good.append(s["limit_state"])
            else:
                (high if s["median_ratio"] < 1 else low).append(s)
        figures = ", ".join(f"{s['limit_state']} {s['median_ratio']:.2f} "
                            f"({s['within_35_percent']}/{s['compared']} within ±35 %)"
                            for s in rows)
        verdicts = []
        if good:
            verdicts.append(f"trust it for the {', '.join(good)}")
        if high:
            folds = [1 / s["median_ratio"] for s in high]
            span = f"{min(folds):.2g}" + (f"–{max(folds):.2g}" if len(folds) > 1 else "")
            verdicts.append(f"it overstates the {', '.join(s['limit_state'] for s in high)} "
                            f"SA {span}-fold: do not trust it there")
        if low:
            verdicts.append(f"it is low for the {', '.join(s['limit_state'] for s in low)} "
                            "(on the safe side)")
        out.append(f"[[{model}|{model.capitalize()}]]: {figures}: {'; '.join(verdicts)}.")
    if not out:
        return []
    return ["Rigid model against the [[FE model]], median [[FE / rigid]] per limit state "
            "(goal: median within ±15 %, every case within ±35 %). " + " ".join(out)]


def summary_lines(*, table2_rows: list, fragility_rows: list,
                  fem_stats: list | None = None) -> list[str]:
    """The summary's sentences: FE against rigid and which to trust (when FE ran), the
    prediction's share within 20 % (Table 2), the collapse margin against FEMA P695."""
    lines = _trust(fem_stats or [])
    if fem_stats is None:
        lines.append("No FE runs: the rigid model's answers are not checked against the FE "
                     "model here (docs/fem_validation.md has the whole set).")
    by_criterion: dict = {}
    for row in table2_rows:
        good, n = (int(x) for x in row["all good/n"].split("/"))
        if n:
            by_criterion.setdefault(row["criterion"], []).append(
                f"{good}/{n} at {row['pressure [MPa]']:g} MPa")
    if by_criterion:
        lines.append("[[predicted SA|Predicted]] from a Ricker pulse, within 20 % of the "
                     "critical SA ([[Table 2]]): " + "; ".join(
                         f"[[criterion]] {c}: {', '.join(v)}" for c, v in by_criterion.items())
                     + ".")
    margins = []
    for f in fragility_rows:
        n = f["records"]
        verdict = "passes" if f["acmr"] >= f["acmr10"] else "fails"
        margins.append(
            f"{f['pressure_mpa']:g} MPa: median {significant(f['median_sa_g'], n)} g, "
            f"[[ACMR]] {significant(f['acmr'], n)} against {f['acmr10']:.2f}, {verdict}"
            + (f" ({n} records only: 2 digits)" if n < FEW_RECORDS else ""))
    if margins:
        lines.append("[[fragility|Fragility]] and collapse margin ([[CMR]], FEMA P695): "
                     + "; ".join(margins) + ".")
    return lines


def design_period(results: dict) -> float:
    """Tb [s] of the run's bearings (the baseline's when there are none)."""
    from rigid import DFPBearing

    for res in results.values():
        return res.bearing.design_period
    return DFPBearing().design_period


def what_ran(results: dict, motions, settings, record_set: str, fem_rows) -> str:
    """One sentence: records, bearings, models and limit states, the ladder."""
    pressures = ", ".join(f"{p / 1e6:g}" for p in results)
    variant = settings.describe().get("bearing variant")
    models = "the [[rigid model]] with [[rigid rims]] (fails by losing containment)"
    if settings.ladder_states():
        models += f" and with [[yielding rims]] ({', '.join(settings.ladder_states())})"
    if settings.fem is not None and fem_rows:
        targets = {(r["record"], r["pressure_mpa"]) for r in fem_rows}
        models += (f"; the [[FE model]] ({settings.fem.mesh} mesh) on {len(targets)} record "
                   f"× pressure case(s), [[limit state]]s {', '.join(settings.fem.limit_states)}")
    tb = design_period(results)
    return (f"{len(motions)} records ({record_set}); bearings at {pressures} MPa"
            + (f" ({variant})" if variant else "") + f"; {models}. Each record is scaled on a "
            f"[[ladder]] of SA({tb:g} s) in {settings.step / G:.2f} g steps up to "
            f"{settings.stop / G:g} g; the answer is its [[critical SA]] in g.")


def write_summary(report, results, motions, settings, record_set: str, *, table2_rows,
                  fragility_rows, fem_rows=None, fem_stats=None, figure=None,
                  caption: str = "") -> None:
    """The Summary section at the current end of ``report``: the sentence of what ran, the
    answers' table, the sentences, and ``figure`` (a PNG) beside them."""
    report.open("summary")
    report.open("summary-text")
    report.heading("Summary", id="summary")
    report.paragraph(what_ran(results, motions, settings, record_set, fem_rows))
    report.table(answer_rows(results, fem_rows),
                 caption="[[critical SA]] [g]: median (lowest–highest) failed/cases, over the "
                 "answers that are not [[uncertain]]; the FE model's over the records it ran "
                 "on")
    report.items(summary_lines(table2_rows=table2_rows,
                               fragility_rows=fragility_rows, fem_stats=fem_stats))
    report.paragraph("Details, figures and every number below; every term in the "
                     "[[#glossary|glossary]] at the end.")
    report.close()
    if figure is not None:
        report.figure(figure, caption)
    report.close()
