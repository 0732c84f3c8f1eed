"""The three regions of an impact region spectrum (paper §3.2, Fig. 8) as arrays: boundaries read
from a grid, columns that are not monotonic in amplitude, and the region of any pulse (Tp, Ap)
from a spectrum's boundaries (the look-up of paper §4.2); docs/theory/impact-spectra.md,
Eqs. I8–I10."""

from __future__ import annotations

import numpy as np

from ..units import G
from .sweep import FAILURE, IMPACT, NO_IMPACT, NUMERICAL

__all__ = ["grid_boundaries", "nonmonotonic_periods", "region_at"]


def nonmonotonic_periods(region) -> tuple[np.ndarray, np.ndarray]:
    """Columns whose regions are not monotonic in amplitude (Eq. I9).

    Parameters
    ----------
    region : array_like of int, shape (n_amplitudes, n_periods)
        Region codes with amplitudes ascending along axis 0; -1 (numerical failure) cells are
        ignored.

    Returns
    -------
    failure_below_nonfailure : ndarray of bool, shape (n_periods,)
        Some failure cell lies below a cell without failure.
    impact_below_no_impact : ndarray of bool, shape (n_periods,)
        Some cell with an impact lies below a cell without impact.
    """
    r = np.asarray(region)
    if r.ndim != 2:
        raise ValueError("region must be two-dimensional (amplitude, period)")
    valid = r >= 0
    failed = np.maximum.accumulate((r == FAILURE) & valid, axis=0)
    hit = np.maximum.accumulate((r >= IMPACT) & valid, axis=0)
    fail_flag = np.any(failed & valid & (r != FAILURE), axis=0)
    impact_flag = np.any(hit & valid & (r == NO_IMPACT), axis=0)
    return fail_flag, impact_flag


def grid_boundaries(region, amplitudes) -> tuple[np.ndarray, np.ndarray]:
    """Region boundaries read from a grid [m/s²], one per period column (Eq. I8).

    The boundary of region k is placed midway between the first cell (lowest amplitude) whose
    region is ≥ k and the cell below it (Ap = 0, no motion, below the first row), i.e. the
    true boundary is within half an amplitude step of it when the column is monotonic. NaN if
    the region is not reached on the grid. In a non-monotonic column this is the lowest
    transition (conservative); see :func:`nonmonotonic_periods`.

    Returns
    -------
    impact_boundary, failure_boundary : ndarray [m/s²]
    """
    r = np.asarray(region)
    a = np.concatenate([[0.0], np.asarray(amplitudes, dtype=float)])
    out = []
    for k in (IMPACT, FAILURE):
        reached = (r >= k) | (r == NUMERICAL) if k == FAILURE else (r >= k)
        first = np.argmax(reached, axis=0)
        b = 0.5 * (a[first] + a[first + 1])
        b[~np.any(reached, axis=0)] = np.nan
        out.append(b)
    return out[0], out[1]


def region_at(spectrum, period, amplitude):
    """Region (0, 1, 2) of a pulse (Tp, Ap) from a spectrum's boundaries.

    Rule (documented interpolation, Eq. I10): the boundaries ``impact_boundary`` and
    ``failure_boundary`` of the two grid periods that bracket Tp are interpolated linearly in
    Tb/Tp (the paper's abscissa); the pulse is in region 2 if Ap ≥ the failure boundary, else
    in region 1 if Ap ≥ the impact boundary, else 0. A boundary that is NaN (not reached up to
    the spectrum's highest amplitude) counts as +∞, so an interpolation with it is +∞.
    Works with the grids of :func:`impact_region_spectrum` (boundaries midway between cells)
    and the bisected boundaries of :func:`region_boundaries`.

    Parameters
    ----------
    spectrum : xarray.Dataset
        With ``impact_boundary`` and ``failure_boundary`` [m/s²] along ``period``, and the
        attribute ``amplitude_max`` [m/s²].
    period : float or array_like [s]
    amplitude : float or array_like [m/s²]

    Returns
    -------
    int or ndarray of int

    Raises
    ------
    ValueError
        Tp outside the spectrum's periods, or Ap above ``amplitude_max`` where the region is
        not known there (no failure boundary at or below it).
    """
    periods = np.asarray(spectrum["period"].values, dtype=float)
    tb = float(spectrum.attrs["design_period"])
    tp, ap = np.broadcast_arrays(np.asarray(period, dtype=float),
                                 np.asarray(amplitude, dtype=float))
    if np.any(~np.isfinite(tp)) or np.any(tp < periods.min() * (1 - 1e-12)) or np.any(
        tp > periods.max() * (1 + 1e-12)
    ):
        raise ValueError(
            f"period outside the spectrum's range [{periods.min():.4g}, {periods.max():.4g}] s"
        )
    x_grid = tb / periods
    order = np.argsort(x_grid)
    x = tb / tp
    bounds = []
    for name in ("impact_boundary", "failure_boundary"):
        b = np.asarray(spectrum[name].values, dtype=float)[order]
        b = np.where(np.isnan(b), np.inf, b)
        xs = x_grid[order]
        j = np.clip(np.searchsorted(xs, x), 1, len(xs) - 1) if len(xs) > 1 else np.zeros_like(x)
        if len(xs) == 1:
            bounds.append(np.full_like(x, b[0]))
            continue
        x0, x1, b0, b1 = xs[j - 1], xs[j], b[j - 1], b[j]
        w = np.clip((x - x0) / (x1 - x0), 0.0, 1.0)
        with np.errstate(invalid="ignore"):
            bi = np.where(np.isinf(b0) | np.isinf(b1), np.inf, b0 + w * (b1 - b0))
        bi = np.where(w == 0.0, b0, np.where(w == 1.0, b1, bi))  # at a grid period: its own
        bounds.append(bi)
    impact_b, failure_b = bounds
    top = float(spectrum.attrs["amplitude_max"])
    unknown = (ap > top * (1 + 1e-12)) & ~(failure_b <= top)
    if np.any(unknown):
        raise ValueError(
            f"amplitude above the spectrum's highest amplitude ({top / G:.3f} g) where the "
            "failure boundary is not known"
        )
    region = np.where(ap >= failure_b, FAILURE, np.where(ap >= impact_b, IMPACT, NO_IMPACT))
    return int(region) if region.ndim == 0 else region.astype(int)
