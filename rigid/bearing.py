"""The double friction pendulum bearing: one source of truth for geometry, mass and contact.

Both models (``rigid`` and ``fem``) build from a :class:`DFPBearing`. Values fixed by
Bao & Becker (2016) are marked *paper*; the others are *assumed* because the paper's
Figure 1 (the Japanese design values) is not available. The derived geometry and masses, the
baseline's values and the suggested sensitivity ranges are in docs/theory/rigid-body.md
(Eqs. R1–R14).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from .units import G

__all__ = ["DFPBearing", "G", "jankowski_damping_ratio"]


def jankowski_damping_ratio(restitution: float) -> float:
    """Impact damping ratio ξ of the Jankowski (2006) contact law.

    Parameters
    ----------
    restitution : float [-]
        Coefficient of restitution e, 0 < e ≤ 1.

    Returns
    -------
    float [-]
        ξ = 9√5 (1 − e²) / (2 e (e (9π − 16) + 16)), paper Eq. 4 (Eq. R18).
    """
    e = restitution
    return 9.0 * math.sqrt(5.0) * (1.0 - e * e) / (2.0 * e * (e * (9.0 * math.pi - 16.0) + 16.0))


@dataclass(frozen=True)
class DFPBearing:
    """A double friction pendulum bearing with equal surfaces, in the plane of motion.

    All parameters are SI. Change one with ``dataclasses.replace(bearing, friction=0.03)``.

    Parameters
    ----------
    pressure : float [Pa]
        Average pressure of the supported load on the slider's area. *Paper*: 60 MPa for the
        heavy case (rim yielding governs in FE) and 10 MPa for the light case (uplift).
        Sets the supported mass M = p·π b²/4 / g.
    radius : float [m]
        Radius of curvature of each concave sliding surface (R1 = R2). *Paper*: 2.5 m.
        Taken as the surface radius, so the rigid model's period is 2π√((2R − h)/g) = 4.40 s.
    friction : float [-]
        Coulomb friction coefficient of both sliding surfaces. *Paper*: 0.05.
    slider_diameter : float [m]
        Diameter b of the slider. *Assumed* 0.40 m (typical high-pressure slider).
    slider_height : float [m]
        Height h of the slider on its axis, face to face. *Assumed* 0.20 m.
    capacity : float [m]
        Travel of the slider's centroid on one surface until its leading vertex touches the
        rim. *Assumed* 0.30 m, so the bearing's total capacity is 0.60 m.
    rim_height : float [m]
        Height of the restraining rim above the dish at its inner face. *Assumed* 0.035 m.
    rim_thickness : float [m]
        Radial thickness of the rim. *Assumed* 0.040 m.
    contact_stiffness : float [N/m^1.5]
        Hertz stiffness k of every contact, paper Eqs. 1–2. *Assumed* 1e11 (static vertex
        penetration ≈ 1.1 mm at 60 MPa).
    restitution : float [-]
        Coefficient of restitution e of the contact damper, paper Eq. 4. *Paper*: 0.65.
    impact_mass : {"supported", "slider"}
        The colliding masses m1·m2/(m1 + m2) of paper Eq. 3, not given in the paper (Eq. R19
        of docs/theory/rigid-body.md gives the reasons).
        *Assumed* ``"supported"``: the slider carries the supported mass into the bottom
        plate (m_eff = M + m_s) and the top plate hits the slider backed by the ground
        (m_eff = M), so a rim impact of the superstructure rebounds with e. ``"slider"``:
        the literal pairs slider–plate, m_s and m_s·M/(m_s + M); the superstructure's
        impacts are then almost elastic whatever e is (sensitivity option).
    rim_friction : float [-]
        Friction coefficient between the slider's sides and the rims. *Assumed* 0.05.
    friction_yield_slip : float [m]
        Elastic slip Y of the hysteretic friction state before sliding starts; the
        pre-sliding stiffness of each contact is μN/Y. *Assumed* 1e-4 m.
    design_period : float [s]
        Period Tb at which records are scaled, SA(Tb). *Paper*: 4.5 s.
    steel_density : float [kg/m³]
        Density of the slider. *Assumed* 7850.
    youngs_modulus : float [Pa]
        Steel Young's modulus for the FE model. *Assumed* 200 GPa.
    poisson_ratio : float [-]
        Steel Poisson's ratio for the FE model. *Assumed* 0.3.
    yield_stress : float [Pa]
        Rim steel yield stress. *Paper*: 345 MPa.
    ultimate_stress : float [Pa]
        Rim steel ultimate stress, after which hardening stops. *Paper*: 450 MPa.
    hardening_ratio : float [-]
        Post-yield to elastic stiffness ratio E_t/E. *Paper*: 0.01.
    plate_thickness : float [m]
        Plate thickness under the dish apex, FE model only. *Assumed* 0.06 m.
    rupture_strain : float [-]
        Equivalent (logarithmic) plastic strain at which the rim steel ruptures, averaged over
        a gauge of the rim's thickness (the FE model's "rupture" limit state). Default
        ln(1 + 0.21) = 0.19: the minimum elongation at fracture of ASTM A572 Grade 50 (the
        paper's 345/450 MPa steel), 21 % in a 50 mm gauge; EN 10025-2 S355 gives 22 %
        (docs/theory/finite-elements.md, "Limit states").
    """

    pressure: float = 60e6
    radius: float = 2.5
    friction: float = 0.05
    slider_diameter: float = 0.40
    slider_height: float = 0.20
    capacity: float = 0.30
    rim_height: float = 0.035
    rim_thickness: float = 0.040
    contact_stiffness: float = 1e11
    restitution: float = 0.65
    impact_mass: str = "supported"
    rim_friction: float = 0.05
    friction_yield_slip: float = 1e-4
    design_period: float = 4.5
    steel_density: float = 7850.0
    youngs_modulus: float = 200e9
    poisson_ratio: float = 0.3
    yield_stress: float = 345e6
    ultimate_stress: float = 450e6
    hardening_ratio: float = 0.01
    plate_thickness: float = 0.06
    rupture_strain: float = 0.1906

    def __post_init__(self):
        positive = (
            "pressure radius slider_diameter slider_height capacity rim_height rim_thickness "
            "contact_stiffness friction_yield_slip design_period steel_density youngs_modulus "
            "yield_stress ultimate_stress plate_thickness rupture_strain"
        ).split()
        if self.impact_mass not in ("supported", "slider"):
            raise ValueError(
                f"DFPBearing.impact_mass must be 'supported' or 'slider', got {self.impact_mass!r}"
            )
        for f in fields(self):
            if f.name == "impact_mass":
                continue
            value = getattr(self, f.name)
            if not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ValueError(f"DFPBearing.{f.name} must be a finite number, got {value!r}")
            if f.name in positive and value <= 0:
                raise ValueError(f"DFPBearing.{f.name} must be positive, got {value!r}")
        if not 0 <= self.friction < 1:
            raise ValueError(f"DFPBearing.friction must lie in [0, 1), got {self.friction!r}")
        if not 0 <= self.rim_friction < 1:
            raise ValueError(
                f"DFPBearing.rim_friction must lie in [0, 1), got {self.rim_friction!r}"
            )
        if not 0 < self.restitution <= 1:
            raise ValueError(f"DFPBearing.restitution must lie in (0, 1], got {self.restitution!r}")
        if not 0 < self.hardening_ratio < 1:
            raise ValueError(
                f"DFPBearing.hardening_ratio must lie in (0, 1), got {self.hardening_ratio!r}"
            )
        if not 0 < self.poisson_ratio < 0.5:
            raise ValueError(
                f"DFPBearing.poisson_ratio must lie in (0, 0.5), got {self.poisson_ratio!r}"
            )
        if self.ultimate_stress < self.yield_stress:
            raise ValueError("DFPBearing.ultimate_stress must not be below yield_stress")
        if self.slider_diameter >= self.radius:
            raise ValueError("DFPBearing.slider_diameter must be smaller than the radius")
        if self.slider_height <= 2 * self.face_sag:
            raise ValueError(
                "DFPBearing.slider_height leaves no side face: it must exceed twice the face sag "
                f"({2 * self.face_sag:.4g} m)"
            )
        if self.capacity >= 0.5 * (self.radius - self.slider_height / 2):
            raise ValueError("DFPBearing.capacity is too large for the radius (tilt above 30°)")
        if self.rim_clearance <= 0:
            raise ValueError(
                "DFPBearing.rim_height leaves no clearance between the two plates' rims "
                f"(clearance {self.rim_clearance * 1e3:.1f} mm); lower rim_height or capacity"
            )

    # -- loads and masses ---------------------------------------------------------------
    @property
    def slider_area(self) -> float:
        """Slider bearing area π b²/4 [m²]."""
        return math.pi * self.slider_diameter**2 / 4

    @property
    def weight(self) -> float:
        """Supported vertical load W = p·A [N] (Eq. R13)."""
        return self.pressure * self.slider_area

    @property
    def supported_mass(self) -> float:
        """Mass M of the top plate and superstructure, W/g [kg]."""
        return self.weight / G

    @property
    def slider_mass(self) -> float:
        """Slider mass, a steel cylinder of diameter b and height h [kg] (Eq. R14)."""
        return self.steel_density * self.slider_area * self.slider_height

    @property
    def slider_inertia(self) -> float:
        """Slider moment of inertia about a horizontal diameter, m(3r² + h²)/12 [kg·m²]."""
        r = self.slider_diameter / 2
        return self.slider_mass * (3 * r * r + self.slider_height**2) / 12

    # -- geometry -----------------------------------------------------------------------
    @property
    def face_sag(self) -> float:
        """Bulge of a spherical slider face over its chord b, R − √(R² − b²/4) [m] (Eq. R1)."""
        return self.radius - math.sqrt(self.radius**2 - self.slider_diameter**2 / 4)

    @property
    def edge_height(self) -> float:
        """Height of the slider's side face, vertex to vertex, h − 2·sag [m]."""
        return self.slider_height - 2 * self.face_sag

    @property
    def effective_radius(self) -> float:
        """Sum of the two pendulum lengths, 2R − h [m]."""
        return 2 * self.radius - self.slider_height

    @property
    def period(self) -> float:
        """Small-amplitude sliding period of the rigid model, 2π√((2R − h)/g) [s] (Eq. R11)."""
        return 2 * math.pi * math.sqrt(self.effective_radius / G)

    @property
    def capacity_tilt(self) -> float:
        """Slider rotation when the centroid reaches the capacity, asin(d/(R − h/2)) [rad]
        (Eq. R5)."""
        return math.asin(self.capacity / (self.radius - self.slider_height / 2))

    @property
    def rim_radius(self) -> float:
        """Horizontal distance from the dish axis to the rim's inner face [m].

        The leading bottom vertex touches it when the centroid has travelled ``capacity``:
        r_in = (b/2) cos φ + (R − sag) sin φ (docs/theory/rigid-body.md, Eq. R6).
        """
        phi = self.capacity_tilt
        half_b = 0.5 * self.slider_diameter
        return half_b * math.cos(phi) + (self.radius - self.face_sag) * math.sin(phi)

    def dish_depth(self, r: float) -> float:
        """Height of the dish surface above its apex at horizontal distance r [m]."""
        return self.radius - math.sqrt(self.radius**2 - r * r)

    @property
    def rim_top(self) -> float:
        """Height of the rim's top above the dish apex [m]."""
        return self.dish_depth(self.rim_radius) + self.rim_height

    @property
    def rim_clearance(self) -> float:
        """Vertical gap between the two plates' rims at rest, h − 2·z(r_in) − 2·h_r [m]
        (Eq. R9)."""
        return self.slider_height - 2 * self.rim_top

    @property
    def displacement_capacity(self) -> float:
        """Top-plate displacement relative to the bottom plate at first rim contact, 2d [m]."""
        return 2 * self.capacity

    @property
    def plate_radius(self) -> float:
        """Outer radius of each plate, r_in + rim thickness [m]."""
        return self.rim_radius + self.rim_thickness

    # -- contact --------------------------------------------------------------------------
    @property
    def damping_ratio(self) -> float:
        """Jankowski impact damping ratio ξ(e), paper Eq. 4 [-] (Eq. R18)."""
        return jankowski_damping_ratio(self.restitution)

    @property
    def static_penetration(self) -> float:
        """Static penetration of each top vertex under gravity, (W/(2k))^(2/3) [m]."""
        return (self.weight / (2 * self.contact_stiffness)) ** (2.0 / 3.0)

    def describe(self) -> str:
        """A multi-line summary of the parameters and derived quantities, for reports."""
        lines = [f"{f.name} = {getattr(self, f.name)!r}" for f in fields(self)]
        derived = {
            "weight [N]": self.weight,
            "supported_mass [kg]": self.supported_mass,
            "slider_mass [kg]": self.slider_mass,
            "slider_inertia [kg m2]": self.slider_inertia,
            "rim_radius [m]": self.rim_radius,
            "rim_clearance [m]": self.rim_clearance,
            "displacement_capacity [m]": self.displacement_capacity,
            "period [s]": self.period,
            "damping_ratio [-]": self.damping_ratio,
            "static_penetration [m]": self.static_penetration,
        }
        lines += [f"{k} = {v:.6g}" for k, v in derived.items()]
        return "\n".join(lines)
