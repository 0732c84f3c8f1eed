"""Plots of impact spectra in the style of Bao & Becker (2016) Figs. 6–8, and design charts.

matplotlib is imported on use with the Agg backend; every function writes a PNG and returns
its path. Accelerations are shown in g (the only place g appears), velocities in m/s.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..units import G

#: Colours of the three regions (0 no impact, 1 impact without failure, 2 failure).
REGION_COLOURS = ("#d9ead3", "#fce5b6", "#f4b6b6")
REGION_LABELS = ("no impact", "impact without failure", "impact with failure")


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, plt, path) -> Path:
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _region_bands(ax, x, region):
    """Shade the Tb/Tp axis by region, each sample owning the half-intervals around it."""
    order = np.argsort(x)
    x, region = np.asarray(x)[order], np.asarray(region)[order]
    edges = np.concatenate([[x[0]], 0.5 * (x[1:] + x[:-1]), [x[-1]]])
    for i, r in enumerate(region):
        if r >= 0:
            ax.axvspan(edges[i], edges[i + 1], color=REGION_COLOURS[r], lw=0, zorder=0)


def _legend_patches():
    from matplotlib.patches import Patch

    return [Patch(color=c, label=lab) for c, lab in zip(REGION_COLOURS, REGION_LABELS,
                                                        strict=True)]


def plot_impact_velocity_spectrum(ds, path, title: str | None = None) -> Path:
    """Paper Fig. 6: every impact (dots), the maximum (line), failures (crosses), regions.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`rigid.impact_velocity_spectrum`.
    path : str or Path
        Output PNG.
    title : str, optional
    """
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 4.2), constrained_layout=True)
    x = ds["frequency_ratio"].values
    _region_bands(ax, x, ds["region"].values)
    v = np.abs(ds["impact_velocity"].values)
    xs = np.broadcast_to(x[:, None], v.shape)
    ok = np.isfinite(v)
    ax.plot(xs[ok], v[ok], ".", ms=3, color="0.25", label="impact")
    order = np.argsort(x)
    ax.plot(x[order], ds["max_impact_velocity"].values[order], "-", color="C0", lw=1.3,
            label="maximum")
    failed = ds["failed"].values.astype(bool)
    ax.plot(x[failed], ds["max_impact_velocity"].values[failed], "x", color="C3", ms=7,
            mew=1.8, label="failure (uplift)")
    ax.set(xlabel="Tb/Tp [-]", ylabel="impact velocity [m/s]", xlim=(x.min(), x.max()))
    ax.set_ylim(bottom=0)
    ax.legend(handles=ax.get_legend_handles_labels()[0] + _legend_patches(), fontsize=8,
              loc="upper right")
    ax.set_title(title or f"{ds.attrs['kind']} Ricker, Ap = {ds.attrs['amplitude'] / G:.2f} g, "
                 f"p = {ds.attrs['bearing_pressure'] / 1e6:.0f} MPa")
    return _save(fig, plt, path)


def plot_max_impact_velocity_spectra(ds, path, amplitudes=None, title: str | None = None):
    """Paper Fig. 7: maximum impact velocity against Tb/Tp, one line per amplitude.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`rigid.impact_region_spectrum` (or ``max_impact_velocity_spectra``).
    path : str or Path
    amplitudes : array_like [m/s²], optional
        Rows to draw (nearest grid amplitudes); default six spread over the grid.
    """
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 4.2), constrained_layout=True)
    amps = ds["amplitude"].values
    if amplitudes is None:
        amplitudes = amps[np.unique(np.linspace(0, len(amps) - 1, 6).round().astype(int))]
    x = ds["frequency_ratio"].values
    order = np.argsort(x)
    for j, a in enumerate(amplitudes):
        row = ds.sel(amplitude=a, method="nearest")
        v = row["max_impact_velocity"].values[order]
        ax.plot(x[order], v, "-", color=f"C{j % 10}", lw=1.2,
                label=f"Ap = {float(row['amplitude']) / G:.2f} g")
        f = row["region"].values[order] == 2
        ax.plot(x[order][f], v[f], "x", color=f"C{j % 10}", ms=6, mew=1.5)
    ax.plot([], [], "x", color="0.3", label="failure")
    ax.set(xlabel="Tb/Tp [-]", ylabel="maximum impact velocity [m/s]")
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=8)
    ax.set_title(title or f"{ds.attrs['kind']} Ricker, p = "
                 f"{ds.attrs['bearing_pressure'] / 1e6:.0f} MPa")
    return _save(fig, plt, path)


def plot_impact_region_spectrum(ds, path, boundaries=None, title: str | None = None) -> Path:
    """Paper Fig. 8: the three regions over (Tb/Tp, Ap), non-monotonic periods marked.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`rigid.impact_region_spectrum`.
    path : str or Path
    boundaries : xarray.Dataset, optional
        From :func:`rigid.region_boundaries`: drawn as lines over the grid.
    """
    from matplotlib.colors import BoundaryNorm, ListedColormap

    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 4.8), constrained_layout=True)
    x = ds["frequency_ratio"].values
    order = np.argsort(x)
    amps = ds["amplitude"].values / G
    region = ds["region"].values[:, order].astype(float)
    region[region < 0] = np.nan
    cmap = ListedColormap(REGION_COLOURS)
    cmap = cmap.with_extremes(bad="k")
    ax.pcolormesh(x[order], amps, region, cmap=cmap, norm=BoundaryNorm([-0.5, 0.5, 1.5, 2.5], 3),
                  shading="nearest")
    handles = _legend_patches()
    flags = ds["nonmonotonic_failure"].values | ds["nonmonotonic_impact"].values
    if np.any(flags):
        (h,) = ax.plot(x[flags], np.full(flags.sum(), amps.max()), "v", color="k", ms=5,
                       clip_on=False, label="non-monotonic in Ap")
        handles.append(h)
    if boundaries is not None:
        xb = boundaries["frequency_ratio"].values
        ob = np.argsort(xb)
        for name, style in (("impact_boundary", "--"), ("failure_boundary", "-")):
            (h,) = ax.plot(xb[ob], boundaries[name].values[ob] / G, style, color="k", lw=1.2,
                           label=f"{name.split('_')[0]} boundary (bisection)")
            handles.append(h)
    ax.set(xlabel="Tb/Tp [-]", ylabel="Ap [g]", xlim=(x.min(), x.max()),
           ylim=(0, amps.max()))
    ax.legend(handles=handles, fontsize=8, loc="upper right")
    ax.set_title(title or f"impact region spectrum, {ds.attrs['kind']} Ricker, p = "
                 f"{ds.attrs['bearing_pressure'] / 1e6:.0f} MPa")
    return _save(fig, plt, path)


def plot_region_boundaries(boundaries, path, title: str | None = None) -> Path:
    """The bisected boundaries alone: lines with their ± tolerance and flagged periods."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 4.2), constrained_layout=True)
    x = boundaries["frequency_ratio"].values
    o = np.argsort(x)
    for name, colour in (("impact", "C1"), ("failure", "C3")):
        b = boundaries[f"{name}_boundary"].values[o] / G
        ax.plot(x[o], b, "-", color=colour, lw=1.3, label=f"{name} boundary")
        ax.fill_between(x[o], boundaries[f"{name}_lower"].values[o] / G,
                        boundaries[f"{name}_upper"].values[o] / G, color=colour, alpha=0.3,
                        lw=0)
        flag = boundaries[f"nonmonotonic_{name}"].values[o]
        if np.any(flag):
            ax.plot(x[o][flag], b[flag], "o", mfc="none", color=colour,
                    label=f"{name}: non-monotonic")
    ax.set(xlabel="Tb/Tp [-]", ylabel="Ap [g]")
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=8)
    ax.set_title(title or f"region boundaries, {boundaries.attrs['kind']} Ricker, p = "
                 f"{boundaries.attrs['bearing_pressure'] / 1e6:.0f} MPa")
    return _save(fig, plt, path)


def plot_design_chart(chart, path, title: str | None = None) -> Path:
    """Dimensionless boundaries Ap·Tp²/d_cap against Tb/Tp, one line per bearing."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True, sharey=True)
    x = chart["frequency_ratio"].values
    mus = sorted(set(chart["friction"].values.tolist()))
    caps = sorted(set(chart["capacity"].values.tolist()))
    styles = ["-", "--", ":", "-."]
    for ax, name in zip(axes, ("impact", "failure"), strict=True):
        for c in range(chart.sizes["case"]):
            mu = float(chart["friction"][c])
            cap = float(chart["capacity"][c])
            ax.plot(x, chart[f"{name}_pi"].values[c], styles[caps.index(cap) % 4],
                    color=f"C{mus.index(mu)}", lw=1.2,
                    label=f"μ = {mu:g}, d_cap = {2 * cap:.2f} m")
        ax.set(xlabel="Tb/Tp [-]", title=f"{name} boundary", yscale="log")
        ax.grid(True, which="both", lw=0.3)
    axes[0].set_ylabel("Ap·Tp²/d_cap [-]")
    axes[0].legend(fontsize=7)
    fig.suptitle(title or f"design chart, {chart.attrs['kind']} Ricker pulses")
    return _save(fig, plt, path)
