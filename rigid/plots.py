"""Plots of a rigid-model response (matplotlib, imported on use, Agg backend, PNG)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .model import SimulationResult


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_response(result: SimulationResult, path, title: str | None = None) -> Path:
    """Displacement history, force–displacement loop and energy balance, to a PNG file.

    Parameters
    ----------
    result : SimulationResult
    path : str or Path
        Output file (.png).
    title : str, optional

    Returns
    -------
    Path of the written file.
    """
    plt = _pyplot()
    b = result.bearing
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2), constrained_layout=True)
    ax = axes[0]
    ax.plot(result.time, result.displacement, lw=1.2, label="top plate rel. to bottom")
    for sign in (1, -1):
        ax.axhline(sign * b.displacement_capacity, color="0.4", ls="--", lw=0.8)
    for i in result.impacts:
        ax.plot(i.time, np.interp(i.time, result.time, result.displacement), "o", ms=5,
                mfc="none", color="C3")
    if result.failed:
        ax.axvline(result.failure_time, color="C3", lw=1.0)
        ax.text(result.failure_time, 0, "  failure (uplift)", color="C3", va="bottom")
    ax.set(xlabel="time [s]", ylabel="displacement [m]",
           title="displacement (dashed: capacity; o: rim impacts)")
    ax = axes[1]
    ax.plot(result.displacement, result.base_shear / b.weight, lw=1.0)
    u = np.linspace(-b.displacement_capacity, b.displacement_capacity, 3)
    for sign in (1, -1):
        ax.plot(u, u / b.effective_radius + sign * b.friction, color="0.5", ls=":", lw=1.0)
    ax.set(xlabel="displacement [m]", ylabel="base shear / W [-]",
           title="force–displacement (dotted: u/R_eff ± μ)")
    ax.set_ylim(-0.5, 0.5)
    ax = axes[2]
    e = result.energy
    for series, label in ((e.input, "input"), (e.kinetic, "kinetic"), (e.potential, "potential"),
                          (e.friction, "friction"), (e.impact, "impact damping"),
                          (e.residual, "residual")):
        ax.plot(result.time, series / 1e3, lw=1.0, label=label)
    ax.set(xlabel="time [s]", ylabel="energy [kJ]", title="energy balance")
    ax.legend(fontsize=8)
    if title:
        fig.suptitle(title)
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
