"""Figures of the critical-SA study: paper Figs. 11 and 12 and the fragility curve.

matplotlib is imported inside the functions with the Agg backend (files, no display).
Axes in g (plots are an edge of the program).
"""

from __future__ import annotations

import math

import numpy as np

from ..units import G

__all__ = ["plot_comparison", "plot_fragility", "plot_prediction"]

_REGION_STYLE = {0: ("no impact", "tab:green", "o"), 1: ("impact, no failure", "tab:orange", "o"),
                 2: ("impact with failure", "tab:red", "x"), -1: ("numerical", "k", "s")}


def _axes(ax, size=(5.0, 4.0)):
    if ax is not None:
        return ax.figure, ax
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=size, constrained_layout=True)
    return fig, ax


def plot_prediction(pred, spectrum=None, actual=None, ax=None):
    """Paper Fig. 11: the scaled pulse's (Tb/Tp, Ap) at every rung, coloured by region.

    Parameters
    ----------
    pred : PredictedSA
    spectrum : xarray.Dataset, optional
        Impact region spectrum of the pulse's kind; its impact and failure boundaries are drawn.
    actual : CriticalSA, optional
        The time-history result, quoted in the title.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib Figure
    """
    fig, ax = _axes(ax)
    x = pred.frequency_ratio
    if spectrum is not None:
        fr = np.asarray(spectrum["frequency_ratio"].values, dtype=float)
        order = np.argsort(fr)
        for name, style in (("impact_boundary", "--"), ("failure_boundary", "-")):
            ax.plot(fr[order], np.asarray(spectrum[name].values)[order] / G, "k" + style, lw=1,
                    label=name.replace("_", " "))
    for reg, (label, color, marker) in _REGION_STYLE.items():
        amps = [r.amplitude / G for r in pred.rungs if r.region == reg]
        if amps:
            ax.plot([x] * len(amps), amps, marker, color=color, ls="none", ms=4, label=label)
    if pred.sa is not None:
        ax.annotate(f"SA = {pred.sa / G:.2f} g", (x, pred.critical_amplitude / G),
                    xytext=(8, 0), textcoords="offset points", va="center", fontsize=8)
    ax.set_xlim(0.0, max(6.0, 1.2 * x))  # the paper's abscissa range (Tp ≥ 0.75 s)
    ax.set_xlabel("Tb / Tp")
    ax.set_ylabel("pulse amplitude Ap [g]")
    title = f"{pred.name}: {pred.pulse.kind}, Tp = {pred.pulse.period:.2f} s"
    if actual is not None:
        act = "none" if actual.sa is None else f"{actual.sa / G:.2f} g"
        title += f"\npredicted {_fmt(pred.sa)}, actual {act}"
    ax.set_title(title, fontsize=8)
    ax.legend(fontsize=7, loc="best")
    return fig


def _fmt(sa):
    return "none" if sa is None else f"{sa / G:.2f} g"


def plot_comparison(rows, criterion: int, tolerance: float = 0.2, split: float = 0.5, ax=None):
    """Paper Fig. 12: predicted against actual critical SA [g], with the ±20 % band.

    Parameters
    ----------
    rows : list of dict
        From :func:`rigid.collapse.comparison_rows`.
    criterion : int
    tolerance : float [-]
    split : float [s]
        Long-period pulses (Tp > split) are filled, short ones hollow.

    Returns
    -------
    matplotlib Figure
    """
    fig, ax = _axes(ax, (4.5, 4.5))
    act = np.array([r["actual_sa_g"] for r in rows], dtype=float)
    pre = np.array([r[f"predicted_sa_g_{criterion}"] for r in rows], dtype=float)
    tp = np.array([r[f"tp_{criterion}"] for r in rows], dtype=float)
    ok = np.isfinite(act) & np.isfinite(pre)
    top = 1.1 * max(np.nanmax(act[ok]) if ok.any() else 1.0, np.nanmax(pre[ok]) if ok.any()
                    else 1.0)
    line = np.array([0.0, top])
    ax.plot(line, line, "k-", lw=1, label="predicted = actual")
    ax.fill_between(line, line * (1 - tolerance), line * (1 + tolerance), color="0.9",
                    label=f"±{tolerance:.0%}")
    long = ok & (tp > split)
    short = ok & (tp <= split)
    ax.plot(act[long], pre[long], "o", color="tab:blue", label=f"Tp > {split} s")
    ax.plot(act[short], pre[short], "o", mfc="none", color="tab:blue", label=f"Tp ≤ {split} s")
    missing = int(np.sum(np.isfinite(act) & ~np.isfinite(pre)))
    ax.set_xlim(0, top)
    ax.set_ylim(0, top)
    ax.set_aspect("equal")
    ax.set_xlabel("actual critical SA(Tb) [g]")
    ax.set_ylabel("predicted critical SA(Tb) [g]")
    ax.set_title(f"criterion {criterion}" + (f" ({missing} without prediction)" if missing
                                                else ""), fontsize=9)
    ax.legend(fontsize=7, loc="upper left")
    return fig


def plot_fragility(fit, values, label: str = "", ax=None):
    """Empirical distribution of critical SA and the fitted lognormal fragility curve.

    Parameters
    ----------
    fit : LognormalFit
    values : sequence of float [m/s²] or None
        Per-record critical SA (None: no failure, drawn at the top of the plot range).
    label : str
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib Figure
    """
    fig, ax = _axes(ax)
    vals = np.sort([v for v in values if v is not None]) / G
    n = len(values)
    top = max(vals.max() if vals.size else 1.0, fit.median / G * math.exp(2.5 * fit.beta))
    sa = np.linspace(1e-3, top, 300)
    ax.plot(sa, fit.probability(sa * G), "-", label=f"lognormal: median {fit.median / G:.2f} g, "
            f"β = {fit.beta:.2f}")
    ax.step(vals, (np.arange(vals.size) + 1) / n, where="post", color="k", lw=1,
            label=f"records ({vals.size} of {n} failed)")
    ax.set_xlabel("SA(Tb) [g]")
    ax.set_ylabel("probability of failure")
    ax.set_ylim(0, 1)
    ax.set_xlim(0, top)
    ax.set_title(label, fontsize=9)
    ax.legend(fontsize=7, loc="lower right")
    return fig
