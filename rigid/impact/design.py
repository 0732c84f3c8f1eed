"""Dimensionless design charts (beyond the paper: the "generalized graphs" of its abstract): the
region boundaries of several bearings as Ap·Tp²/d_cap against Tb/Tp."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..bearing import DFPBearing
from ..units import G
from .boundaries import boundaries_many, bracket_midpoint
from .spectra import PERIOD_MAX, check_sweep
from .sweep import SweepSettings

__all__ = ["design_chart"]


def design_chart(
    bearings: Sequence[DFPBearing],
    kind: str,
    ratios=None,
    *,
    amplitude_max: float = 1.0 * G,
    tolerance: float = 0.005 * G,
    scan_step: float | None = 0.05 * G,
    failure: bool = True,
    settings: SweepSettings | None = None,
    workers: int | None = None,
    progress: bool | None = None,
    cache=True,
):
    """Region boundaries of several bearings in dimensionless form.

    Dimensional analysis (docs/theory/impact-spectra.md, Eq. I14) of a pendulum of period Tb
    under a pulse (Tp, Ap) with a stop at the displacement capacity d_cap: without friction
    the displacement scales with Ap·Tp², so impact occurs when Π = Ap·Tp²/d_cap exceeds a
    function of Tb/Tp only; friction adds the group μg/Ap, the rims' geometry and the mass
    the rest. The chart shows how far the boundaries of different μ and capacities collapse
    on Π(Tb/Tp).

    Parameters
    ----------
    bearings : sequence of DFPBearing
        The cases (e.g. several ``friction`` and ``capacity`` values).
    kind : {"symmetric", "antisymmetric"}
    ratios : array_like [-], optional
        Tb/Tp values; default 40 from Tb/7.5 s to 6.
    amplitude_max, tolerance, scan_step, failure, settings, workers, progress, cache
        As in :func:`region_boundaries`.

    Returns
    -------
    xarray.Dataset
        Dimensions ``case`` and ``frequency_ratio``; ``impact_pi`` and ``failure_pi``
        (Ap·Tp²/d_cap [-]) and the boundaries ``impact_boundary``, ``failure_boundary``
        [m/s²]; per case coordinates ``friction``, ``capacity`` (per surface [m]),
        ``displacement_capacity`` [m], ``pressure`` [Pa].
    """
    import xarray as xr

    if not bearings:
        raise ValueError("design_chart needs at least one bearing")
    tb = {b.design_period for b in bearings}
    if len(tb) != 1:
        raise ValueError("all bearings must share the design period Tb")
    tb = tb.pop()
    if ratios is None:
        ratios = np.linspace(tb / PERIOD_MAX, 6.0, 40)
    ratios = np.sort(np.asarray(ratios, dtype=float))
    periods = np.sort(tb / ratios)
    for b in bearings:
        check_sweep(b, kind, periods)
    settings = SweepSettings() if settings is None else settings
    rows, _stats = boundaries_many([(b, kind, periods) for b in bearings], settings,
                                    amplitude_max, tolerance, scan_step, workers, progress,
                                    cache, failure)
    order = np.argsort(tb / periods)  # rows follow ascending period; chart ascending ratio
    ib = np.array([[bracket_midpoint(r["impact"]) for r in case] for case in rows])[:, order]
    fb = np.array([[bracket_midpoint(r["failure"]) for r in case] for case in rows])[:, order]
    tp = periods[order]
    dcap = np.array([b.displacement_capacity for b in bearings])
    pi_scale = tp[None, :] ** 2 / dcap[:, None]
    dims = ("case", "frequency_ratio")
    return xr.Dataset(
        {
            "impact_pi": (dims, ib * pi_scale, {"units": "1", "long_name": "Ap·Tp²/d_cap"}),
            "failure_pi": (dims, fb * pi_scale, {"units": "1", "long_name": "Ap·Tp²/d_cap"}),
            "impact_boundary": (dims, ib, {"units": "m/s2"}),
            "failure_boundary": (dims, fb, {"units": "m/s2"}),
        },
        coords={
            "frequency_ratio": ("frequency_ratio", tb / tp, {"units": "1", "long_name": "Tb/Tp"}),
            "period": ("frequency_ratio", tp, {"units": "s"}),
            "friction": ("case", [b.friction for b in bearings], {"units": "1"}),
            "capacity": ("case", [b.capacity for b in bearings], {"units": "m"}),
            "displacement_capacity": ("case", dcap, {"units": "m"}),
            "pressure": ("case", [b.pressure for b in bearings], {"units": "Pa"}),
        },
        attrs={"kind": kind, "design_period": tb, "amplitude_max": float(amplitude_max),
               "tolerance": float(tolerance), "tolerance_units": "m/s2"},
    )
