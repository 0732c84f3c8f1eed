"""Critical SA(Tb) predicted from a record's Ricker pulse: the pulse scales with the record up
the same ladder as the time-history search, and the first rung whose pulse lies in the failure
region (found by simulating the pulse, or read from an impact region spectrum) is the
prediction (paper §4.2, Fig. 11; docs/theory/collapse.md, Eq. C5).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bearing import DFPBearing
from ..limit_states import check_limit_state, deprecated_attribute, renamed_limit_state
from ..units import G

__all__ = ["PredictedSA", "PredictionRung", "predict_critical_sa", "pulse_region"]

_SEARCHES = ("full", "fast", "bisect")


@dataclass(frozen=True)
class PredictionRung:
    """One rung of the predicted ladder.

    Attributes
    ----------
    index : int
    sa : float [m/s²]
        SA(Tb) of the scaled record.
    scale : float [-]
    amplitude : float [m/s²]
        |Ap| of the scaled pulse.
    region : int
        0 no impact, 1 impact without failure, 2 failure (-1: the pulse's simulation was
        numerically unstable).
    """

    index: int
    sa: float
    scale: float
    amplitude: float
    region: int


@dataclass(frozen=True)
class PredictedSA:
    """Critical SA(Tb) predicted from a Ricker pulse.

    Attributes
    ----------
    sa : float or None [m/s²]
        SA(Tb) of the first rung whose pulse is in the failure region; None up to ``stop``.
    scale : float or None [-]
    pulse : rigid.Pulse
        The pulse of the unscaled record (``pulse.scaled(scale)`` is the critical one).
    criterion : int or None
        Paper §4.1 criterion that chose it (None for a given pulse).
    name : str
    record_sa : float [m/s²]
        SA(Tb) of the unscaled record.
    period : float [s]
        Tb.
    start, step, stop : float [m/s²]
    search : {"full", "fast"}
    rungs : tuple of PredictionRung
    """

    sa: float | None
    scale: float | None
    pulse: object
    criterion: int | None
    name: str
    record_sa: float
    period: float
    start: float
    step: float
    stop: float
    search: str
    rungs: tuple

    @property
    def frequency_ratio(self) -> float:
        """Tb/Tp [-], the abscissa of the impact region spectrum."""
        return self.period / self.pulse.period

    @property
    def critical_amplitude(self) -> float | None:
        """|Ap| of the pulse at the predicted critical rung [m/s²]."""
        return None if self.scale is None else abs(self.pulse.amplitude) * self.scale

    @property
    def numerical_failures(self) -> tuple:
        """Rungs whose pulse simulation stayed unstable (region -1: outcome unknown)."""
        return tuple(r for r in self.rungs if r.region == -1)

    @property
    def uncertain(self) -> bool:
        """The prediction depends on numerical rungs: one lies below the predicted rung, or
        none is in the failure region and some were numerical."""
        return any(r.region == -1 and (self.sa is None or r.sa < self.sa) for r in self.rungs)

    def summary(self) -> str:
        """One line for the console (SA in g)."""
        crit = (f"no failure predicted up to {self.stop / G:.2f} g" if self.sa is None
                else f"predicted SA {self.sa / G:.2f} g")
        p = self.pulse
        extra = ""
        numerical = self.numerical_failures
        if numerical:
            extra = (f"; {len(numerical)} numerical rung(s) (outcome unknown) at "
                     + ", ".join(f"{r.sa / G:.2f}" for r in numerical) + " g")
        if self.uncertain:
            extra += "; UNCERTAIN: the prediction depends on numerical rungs"
        return (f"{self.name}: {crit} (criterion {self.criterion}, w = {p.weighting}, "
                f"{p.kind} Tp = {p.period:.3f} s, Ap = {abs(p.amplitude) / G:.3f} g "
                f"unscaled){extra}")


class pulse_region:  # a callable class, named and used like a function
    """Region of a Ricker pulse found by simulating it: ``pulse_region(bearing, kind)(Tp, Ap)``.

    The pulse (paper Eq. 5 or 6) is sampled over t0 ± 3·Tp (both kinds are negligible beyond:
    docs/theory/ground-motions.md, note to Eq. M8) and followed by ``free`` seconds of rest;
    the run stops once no rim can be reached. Results are memoised per (Tp, Ap); the region is
    that of docs/theory/impact-spectra.md, Eq. I3.

    Parameters
    ----------
    bearing : DFPBearing
    kind : {"symmetric", "antisymmetric"}
    dt : float [s]
        Sampling of the pulse (accuracy does not depend on it; ``rigid.simulate``).
    free : float [s]
        Longest time simulated after the pulse.
    max_step : float [s], optional
        Largest internal step of :func:`rigid.simulate` (default its own).
    rims, limit_state, rim_law
        The rim model, the limit state of the failure region and the yielding rims' law
        (:func:`rigid.simulate`; ``failure_criterion``: the deprecated name of
        ``limit_state``).
    """

    failure_criterion = deprecated_attribute("failure_criterion")

    @renamed_limit_state()
    def __init__(self, bearing: DFPBearing, kind: str, dt: float = 0.005, free: float = 20.0,
                 max_step: float | None = None, rims: str = "rigid",
                 limit_state: str | None = None, rim_law=None):
        from ..motions.pulses import KINDS

        if kind not in KINDS:
            raise ValueError(f"kind must be 'symmetric' or 'antisymmetric', got {kind!r}")
        self.bearing, self.kind, self.dt, self.free = bearing, kind, float(dt), float(free)
        self.max_step = max_step
        self.rims, self.limit_state = rims, check_limit_state(limit_state, rims=rims)
        if rims == "yielding":
            from ..rims import resolve_rim_law

            rim_law = resolve_rim_law(bearing, rim_law, stacklevel=3)
        self.rim_law = rim_law
        self._memo: dict = {}

    def __call__(self, period: float, amplitude: float) -> int:
        from ..model import DEFAULT_MAX_STEP, NumericalInstabilityError, simulate
        from ..motions.pulses import ricker

        key = (float(period), abs(float(amplitude)))
        if key not in self._memo:
            tp, ap = key
            n = round(6.0 * tp / self.dt) + 1
            a = ricker(np.arange(n) * self.dt, ap, tp, self.kind, t0=3.0 * tp)  # Eqs. 5-6
            try:
                r = simulate(self.bearing, a, self.dt, duration=(n - 1) * self.dt + self.free,
                             max_step=self.max_step or DEFAULT_MAX_STEP, record_every=n,
                             on_instability="refine", stop_when_quiet=True, rims=self.rims,
                             limit_state=self.limit_state, rim_law=self.rim_law)
                self._memo[key] = 2 if r.failed else (1 if r.impacts else 0)
            except NumericalInstabilityError:
                self._memo[key] = -1
        return self._memo[key]


def _resolve_region(region, bearing, kind, rims="rigid", limit_state=None, rim_law=None):
    if region is None:
        return pulse_region(bearing, kind, rims=rims, limit_state=limit_state, rim_law=rim_law)
    if isinstance(region, dict):
        if kind not in region:
            raise ValueError(f"the region mapping has no entry for a {kind} pulse")
        region = region[kind]
    if hasattr(region, "data_vars") and "failure_boundary" in region.data_vars:
        from ..impact import region_at  # an impact region spectrum (xarray.Dataset)

        spectrum = region
        return lambda tp, ap: int(region_at(spectrum, tp, ap))
    if not callable(region):
        raise TypeError("region must be None, a callable (period, amplitude) -> 0/1/2, "
                        "an impact region spectrum, or a mapping of those by pulse kind")
    return region


@renamed_limit_state()
def predict_critical_sa(
    bearing: DFPBearing,
    motion,
    pulse=None,
    criterion: int = 4,
    *,
    step: float = 0.01 * G,
    start: float | None = None,
    stop: float = 3.0 * G,
    region=None,
    search: str = "full",
    coarse: int = 10,
    weighting: str = "all",
    max_period: float = 7.5,
    period: float | None = None,
    damping: float = 0.05,
    dt: float | None = None,
    rims: str = "rigid",
    limit_state: str | None = None,
    rim_law=None,
) -> PredictedSA:
    """Predicted critical SA(Tb): the first ladder rung whose scaled pulse is in region 2
    (Eq. C5).

    Parameters
    ----------
    bearing : DFPBearing
    motion : GroundMotion or array_like [m/s²]
        The record (an array needs ``dt``).
    pulse : rigid.Pulse, optional
        The record's pulse; default :func:`rigid.best_pulse` with ``criterion``.
    criterion : {1, 2, 3, 4}
        Paper §4.1 selection criterion (ignored when ``pulse`` is given).
    step, start, stop : float [m/s²]
        The ladder of SA(Tb), as in :func:`rigid.critical_sa` (default 0.01 g steps from
        0.01 g to 3 g).
    region : callable, mapping, xarray.Dataset or None
        Where (Tp, Ap) falls (module docstring); default :class:`pulse_region` (simulation).
    search : {"full", "fast", "bisect"}
        ``"full"``: every rung from the bottom. ``"fast"``: every ``coarse``-th rung up to the
        first in region 2, then the fine rungs of every coarse interval with an impact
        (region ≥ 1) at either end, lowest first (no failure without an impact).
        ``"bisect"``: bisection over the rungs, which assumes that the failure region lies
        above one boundary amplitude at this Tp, as an impact region spectrum draws it
        (paper Fig. 8); about log2(rungs) region evaluations.
    coarse : int
        Rungs per coarse step of the fast search.
    weighting : {"all", "1/sqrt(s)", "1/s", "1"}
        w(s) of the pulse extraction (paper Eq. 7); ``"all"``, the paper's procedure, pools
        the candidates of the three (:func:`rigid.best_pulse`).
    max_period : float [s]
        Longest pulse period searched (the paper's 7.5 s).
    period : float [s], optional
        Tb; default ``bearing.design_period``.
    damping : float [-]
        Damping of the scaling spectrum.
    dt : float [s], optional
        Time step when ``motion`` is an array.
    rims, limit_state : str
        Rim model and limit state of the default region (:class:`pulse_region`; ignored
        when ``region`` is given; ``failure_criterion``: the deprecated name of
        ``limit_state``).
    rim_law : rigid.rims.RimLaw, optional
        The yielding rims' law of the default region (``fem.rim_law(bearing)``).

    Returns
    -------
    PredictedSA
    """
    from .ladder import as_record, check_ladder, record_ladder

    start = check_ladder(bearing, search, _SEARCHES, step, coarse, start, stop)
    period = bearing.design_period if period is None else float(period)
    acc, dt, name = as_record(motion, dt)
    if pulse is None:
        from ..motions.pulse_extraction import best_pulse

        pulse = best_pulse(acc, criterion=criterion, weighting=weighting, dt=dt,
                           max_period=max_period)
        used = criterion
    else:
        used = None
    record_sa, n_rungs = record_ladder(acc, dt, period, damping, name, start, step, stop)
    where = _resolve_region(region, bearing, pulse.kind, rims, limit_state, rim_law)
    ap0 = abs(float(pulse.amplitude))
    done: dict[int, PredictionRung] = {}

    def rung(j: int) -> PredictionRung:
        if j not in done:
            sa = start + j * step
            k = sa / record_sa  # Eq. C2; the pulse scales with the record (Eq. C5)
            done[j] = PredictionRung(j, sa, k, ap0 * k, int(where(pulse.period, ap0 * k)))
        return done[j]

    first = _first_in_failure_region(lambda j: rung(j).region, n_rungs, search, coarse)
    return PredictedSA(
        sa=None if first is None else done[first].sa,
        scale=None if first is None else done[first].scale,
        pulse=pulse,
        criterion=used,
        name=name,
        record_sa=record_sa,
        period=period,
        start=start,
        step=float(step),
        stop=float(start + (n_rungs - 1) * step),
        search=search,
        rungs=tuple(done[j] for j in sorted(done)),
    )


def _first_in_failure_region(region, n_rungs: int, search: str, coarse: int) -> int | None:
    """The lowest rung whose scaled pulse is in the failure region (``region(j)`` = 2; Eq.
    C5), or None, by ``search``: "full" every rung from the bottom; "bisect" assumes one
    boundary; "fast" every ``coarse``-th rung, then the rungs of each coarse interval with an
    end in the impact region or above (a failure needs an impact first; paper §3.2)."""
    from .search import coarse_scan

    if search == "full":
        return next((j for j in range(n_rungs) if region(j) == 2), None)
    if search == "bisect":
        if region(n_rungs - 1) != 2:
            return None
        lo, hi = -1, n_rungs - 1  # rung lo is below the boundary (or none), hi above
        while hi - lo > 1:
            mid = (lo + hi) // 2
            lo, hi = (lo, mid) if region(mid) == 2 else (mid, hi)
        return hi
    ends, first = coarse_scan(lambda j: region(j) == 2, n_rungs, coarse)
    if first is not None:
        for lo, hi in zip([-1, *ends[:-1]], ends, strict=True):
            if lo >= first:
                break
            if hi == ends[-1] or region(hi) != 0 or (lo >= 0 and region(lo) != 0):
                hit = next((j for j in range(lo + 1, hi) if region(j) == 2), None)
                if hit is not None:
                    return hit
    return first
