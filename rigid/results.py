"""The rigid-body model's results: :class:`SimulationResult` (histories, impacts, failure and
limit states, energy balance) with its :class:`Impact` and :class:`EnergyBalance` parts, and
:class:`NumericalInstabilityError`; returned and raised by :func:`rigid.simulate`
(docs/theory/rigid-body.md)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .bearing import DFPBearing
from .limit_states import deprecated_attribute

__all__ = ["EnergyBalance", "Impact", "NumericalInstabilityError", "SimulationResult"]


class NumericalInstabilityError(RuntimeError):
    """The integration went unstable (a numerical, not a physical, failure).

    ``result``: the run as far as it went (a :class:`SimulationResult` with
    ``numerical_failure`` set, e.g. the limit states reached before the instability), or None.
    """

    def __init__(self, message: str, result=None):
        super().__init__(message, result)
        self.result = result

    def __str__(self) -> str:
        return str(self.args[0])


@dataclass(frozen=True)
class Impact:
    """One rim impact: the first contact of a rim after it was free for the merge time.

    Attributes
    ----------
    time : float [s]
    rim : str
        ``"bottom -x"``, ``"bottom +x"``, ``"top -x"`` or ``"top +x"``.
    velocity : float [m/s]
        Horizontal velocity of the top plate relative to the bottom plate at first contact.
    peak_force : float [N]
        Largest total normal force on that rim during the impact.
    duration : float [s]
        Time from first contact to the last contact of the (merged) impact.
    """

    time: float
    rim: str
    velocity: float
    peak_force: float
    duration: float


@dataclass(frozen=True)
class EnergyBalance:
    """Energy histories [J] at the result's sampling; all start at zero.

    ``potential`` is gravity plus the contacts' (and yielding rims') elastic energy;
    ``friction``, ``impact`` and ``plastic`` are the energies dissipated by friction, by the
    contact dampers and by the yielding rims' plastic flow (zero with rigid rims); ``input`` is
    the work of the inertial loads −m·a_g on the bodies' motions relative to the ground.
    """

    input: np.ndarray
    kinetic: np.ndarray
    potential: np.ndarray
    friction: np.ndarray
    impact: np.ndarray
    plastic: np.ndarray

    @property
    def residual(self) -> np.ndarray:
        """input − (kinetic + potential + friction + impact + plastic) [J]; zero for exact
        integration."""
        return self.input - (self.kinetic + self.potential + self.friction + self.impact
                             + self.plastic)

    @property
    def relative_error(self) -> float:
        """Largest |residual| over the largest input energy [-]."""
        scale = np.max(np.abs(self.input))
        return float(np.max(np.abs(self.residual)) / scale) if scale > 0 else 0.0


@dataclass(frozen=True)
class SimulationResult:
    """Response of the rigid-body model. Histories are sampled at ``time``.

    Attributes
    ----------
    time : ndarray [s]
    displacement : ndarray [m]
        Horizontal displacement of the top plate relative to the bottom plate.
    top_plate_rise : ndarray [m]
        Vertical displacement of the top plate from its static position.
    slider_displacement, slider_rise : ndarray [m]
        Slider centroid horizontal position and vertical displacement from rest.
    slider_rotation : ndarray [rad]
        Counter-clockwise positive.
    velocity : ndarray [m/s]
        Horizontal velocity of the top plate relative to the bottom plate.
    base_shear : ndarray [N]
        Horizontal force of the bearing on the bottom plate, positive along +x.
    rim_force : ndarray [N]
        Sum of the normal forces on all four rims.
    energy : EnergyBalance
    impacts : tuple of Impact
    failed : bool
        Physical failure under ``limit_state``: the slider escaped over or through a
        rim or overturned (lost containment, failure under any limit state), or, with yielding
        rims, a rim reached the hinge or rupture asked for.
    failure_time : float or None [s]
    failure_mode : {"uplift", "yielding", None}
        "yielding" if a rim hinged or ruptured (the limit state) or let the slider through, or
        the centroid passed a rim after a hinge; "uplift" if the slider climbed over a rim or
        overturned (docs/theory/rigid-body.md, Eq. R63). Rigid rims fail by uplift only.
    failure_detail : str or None
    numerical_failure : bool
        The integration went unstable; the response after ``failure_time`` is missing.
    max_uplift : float [m]
        Largest separation of a slider face from its dish, both vertices clear.
    max_rotation : float [rad]
    max_penetration : float [m]
    max_rim_force : float [N]
    internal_step : float [s]
    steps : int
        Simulated time in internal (fine) steps.
    steps_taken : int
        Integration steps actually taken, fine and coarse (the cost of the run).
    bearing : DFPBearing
    rims : {"rigid", "yielding"}
    limit_state : {"hinge", "rupture", "containment"}
        The limit state that defined ``failed`` (``failure_criterion`` before: a deprecated
        alias).
    limit_states : dict
        Limit state → time [s] it was first reached, or None, as far as the run went
        (``"hinge"`` and ``"rupture"`` only with yielding rims; Eq. R62).
    rim_sets : tuple of float [m]
        Permanent outward set of each rim at the end (order of ``RIM_NAMES``; zeros with rigid
        rims).
    rim_set : ndarray [m]
        History of the largest permanent rim set.
    """

    time: np.ndarray
    displacement: np.ndarray
    top_plate_rise: np.ndarray
    slider_displacement: np.ndarray
    slider_rise: np.ndarray
    slider_rotation: np.ndarray
    velocity: np.ndarray
    base_shear: np.ndarray
    rim_force: np.ndarray
    energy: EnergyBalance
    impacts: tuple
    failed: bool
    failure_time: float | None
    failure_mode: str | None
    failure_detail: str | None
    numerical_failure: bool
    max_uplift: float
    max_rotation: float
    max_penetration: float
    max_rim_force: float
    internal_step: float
    steps: int
    steps_taken: int
    bearing: DFPBearing
    rims: str
    limit_state: str
    limit_states: dict
    rim_sets: tuple
    rim_set: np.ndarray

    failure_criterion = deprecated_attribute("failure_criterion")

    @property
    def max_impact_velocity(self) -> float:
        """Largest |velocity| over all impacts [m/s]; 0 when there was no impact."""
        return max((abs(i.velocity) for i in self.impacts), default=0.0)

    @property
    def max_displacement(self) -> float:
        """Largest |displacement| [m]."""
        return float(np.max(np.abs(self.displacement)))

    def summary(self) -> str:
        """One paragraph for the console."""
        lines = [
            f"{len(self.impacts)} rim impact(s); max impact velocity "
            f"{self.max_impact_velocity:.3f} m/s; max displacement {self.max_displacement:.3f} m; "
            f"max uplift {self.max_uplift * 1e3:.1f} mm; max slider rotation "
            f"{math.degrees(self.max_rotation):.2f}°"
        ]
        for i in self.impacts:
            lines.append(
                f"  t = {i.time:7.3f} s  {i.rim:9s}  v = {i.velocity:+.3f} m/s  "
                f"peak force {i.peak_force / 1e6:.2f} MN"
            )
        if self.failed:
            lines.append(
                f"FAILED by {self.failure_mode} at t = {self.failure_time:.3f} s: "
                f"{self.failure_detail}"
            )
        elif self.numerical_failure:
            lines.append(
                f"NUMERICAL FAILURE at t = {self.failure_time:.3f} s: {self.failure_detail}"
            )
        else:
            lines.append("no failure")
        return "\n".join(lines)
