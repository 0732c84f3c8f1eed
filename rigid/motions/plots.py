"""Plot a record with its extracted Ricker pulses (like Figures 9–10 of Bao & Becker 2016).

matplotlib is imported inside the function (Agg backend), so ``import rigid`` stays light.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..units import G
from .record import cumulative_integral

__all__ = ["plot_record_pulses"]


def plot_record_pulses(motion, pulses, path, title: str | None = None, dpi: int = 150):
    """Write a PNG of a record's acceleration and velocity with pulses overlaid.

    Parameters
    ----------
    motion : GroundMotion
        The record.
    pulses : Pulse or sequence of Pulse
        Pulses to overlay; their velocities are integrated from the record's first sample
        with the same trapezoidal rule as the record's (as in e_v, paper Eq. 9).
    path : str or Path
        Output PNG file.
    title : str, optional
        Figure title; default the motion's name.
    dpi : int
        Resolution [dots per inch].

    Returns
    -------
    Path
        The file written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if not isinstance(pulses, (list, tuple)):
        pulses = [pulses]
    t = motion.time
    fig, (ax_a, ax_v) = plt.subplots(2, 1, sharex=True, figsize=(8.0, 5.5))
    ax_a.plot(t, motion.acceleration / G, color="0.55", lw=0.7, label="record")
    ax_v.plot(t, motion.velocity(), color="0.55", lw=0.7, label="record")
    for p in pulses:
        a_p = np.asarray(p.acceleration(t))
        label = (
            f"{p.kind[:4]}. ({p.source[:3]}., w={p.weighting}): Tp={p.period:.2f} s, "
            f"Ap={p.amplitude / G:+.3f} g, e_a={p.e_a:.2f}, e_v={p.e_v:.2f}"
        )
        ax_a.plot(t, a_p / G, lw=1.3, label=label)
        ax_v.plot(t, cumulative_integral(a_p, motion.dt), lw=1.3)
    ax_a.set_ylabel("acceleration [g]")
    ax_v.set_ylabel("velocity [m/s]")
    ax_v.set_xlabel("time [s]")
    ax_a.legend(fontsize=7, loc="upper right")
    ax_a.set_title(title if title is not None else motion.name)
    for ax in (ax_a, ax_v):
        ax.grid(True, lw=0.3)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path
