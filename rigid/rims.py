"""The yielding rims' law as data: :class:`RimLaw`, the force–deflection curve of a rim, built
by :func:`rim_law_from_push` (numpy only) from static pushes of the rim, and where it is
cached per rim geometry and steel (docs/theory/rigid-body.md, "Yielding rims", Eqs.
R55–R63).

The pushes are run by the FE companion: ``fem.rim_law(bearing)`` computes (or reads from the
cache) the law, which is handed to :func:`rigid.simulate` as ``rim_law=``. The rigid model
never imports ``fem`` (docs/architecture.md); :func:`resolve_rim_law` keeps, for one release
and with a DeprecationWarning, the old behaviour of a yielding run without a law.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .bearing import DFPBearing
from .tasks.store import KEYED_WHEN_SET

__all__ = ["RIM_LAW_MODELS", "RimLaw", "load_rim_law", "resolve_rim_law", "rim_law",
           "rim_law_cache_file", "rim_law_from_push", "rim_law_through_tearing",
           "save_rim_law"]

#: The models a law can come from (``fem.rim_law(bearing, model=…)``): pushes of the
#: plane-strain rim times the depth πb/4 (Eqs. F1–F3), or the 3-D push of the rim as a ring
#: by the slider (Eqs. F54–F58).
RIM_LAW_MODELS = ("plane-strain", "ring")

#: The push (fem.rim_pushover, run by fem.rim_law): to 1.5 mm in 60 increments of 0.025 mm,
#: which resolve the bend from the elastic line to the hinge (about 0.1–0.6 mm for the
#: baseline rim; a stiffer rim that has not hinged by then is pushed twice as far, in
#: increments of the same size, until it has), then to half the rim height in the default 40
#: increments.
FINE_PUSH = (1.5e-3, 60)
#: Elastic push [m]: a tenth of a millimetre, in two increments, with elastic steel.
ELASTIC_PUSH = 1e-4
#: Lever of the rim's bending as a fraction of its height (Eq. R55): the centre of the
#: pushed upper half of the inner face, 3/4 of the height above the root.
LEVER_FRACTION = 0.75
#: Past the push the backbone keeps the root moment of its last row while the lever
#: shortens as the rim turns (Eq. R56b), up to this cos φ (φ = 60°), and is flat beyond:
#: the constant-moment force grows without bound as the lever vanishes, and run to cos φ =
#: 0.1 its stiff end broke the energy balance of the explicit geometry update (up to 5.9 %
#: of the input on ten pulses, one run numerical, against at most 0.7 % with 0.5;
#: docs/theory/rigid-body.md, "Yielding rims").
LAST_COS = 0.5
#: The push through tearing (fem.rim_pushover with fracture and erosion, run by
#: fem.rim_law(bearing, fracture=…)): increments of at most 0.25 mm, a torn element let go
#: over 10 of them (Eq. F68), as far as the rim's thickness plus its height (the 40 mm rim
#: is off near 38 mm) or until the rim is off (Eq. R64).
TEARING_PUSH = (2.5e-4, 10)


@dataclass(frozen=True)
class RimLaw:
    """Lateral force–deflection law of one rim (Eqs. R56–R57).

    Attributes
    ----------
    stiffness : float [N/m]
        Elastic stiffness k_el (the elastic push).
    plastic_set : ndarray [m]
        Backbone abscissae: the permanent set u_p = δ − F/k_el of each push increment, from 0.
    force : ndarray [N]
        Backbone: the force at each set (non-decreasing; flat past the last row).
    first_yield_force : float [N]
        The backbone's start: where the push leaves the elastic line (u_p = 0).
    hinge_displacement, hinge_force : float [m, N]
        The push's hinge (the whole root section plastic, Eq. F36); inf if the rim does not
        hinge within the push to half its height (a squat rim whose inner face the slider
        crushes instead).
    hinge_set : float [m]
        u_p at the hinge: the hinge limit state of the rigid model (Eq. R62); inf without a
        hinge.
    rupture_displacement : float [m]
        δ at which the push's gauge-averaged plastic strain reaches the rupture strain
        (Eqs. F51–F52), inf if it never does within the push.
    rupture_set : float [m]
        u_p there: the rupture limit state's proxy (Eq. R62).
    lever : float [m]
        Lever L of the rim's bending: a set u_p turns the rim by sin φ = u_p/L, which lowers
        its free end (Eq. R55).
    push_displacement, push_force : ndarray [m, N]
        The push curve the law was derived from (for the static check and the figures).
    corner_height : ndarray [m]
        A law through tearing (:func:`rim_law_through_tearing`): the height of the rim's
        inner top corner above its root at each backbone row, measured in the push (Eq.
        R55b); empty for a law without it, whose rim turns about its root (Eq. R55).
    tear_set : float [m]
        A law through tearing: u_p at the push's first torn element; inf otherwise.
    off_set : float [m]
        A law through tearing: u_p at which the rim is off, its push force below 2 % of its
        peak (Eq. R64) or, after a push that stopped short, the rim thickness (Eq. R64b);
        inf otherwise.
    """

    stiffness: float
    plastic_set: np.ndarray
    force: np.ndarray
    first_yield_force: float
    hinge_displacement: float
    hinge_force: float
    hinge_set: float
    rupture_displacement: float
    rupture_set: float
    lever: float
    push_displacement: np.ndarray
    push_force: np.ndarray
    # a law through tearing's own (keyed only when set: the keys of runs with other laws
    # stay as they were)
    corner_height: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(0),
                                                  metadata=KEYED_WHEN_SET)
    tear_set: float = dataclasses.field(default=math.inf, metadata=KEYED_WHEN_SET)
    off_set: float = dataclasses.field(default=math.inf, metadata=KEYED_WHEN_SET)

    @property
    def table(self) -> np.ndarray:
        """The backbone as the kernel reads it: rows of (u_p [m], F [N], corner height [m];
        the heights 0 where the law has none)."""
        heights = (self.corner_height if self.corner_height.size
                   else np.zeros_like(self.plastic_set))
        return np.ascontiguousarray(np.column_stack([self.plastic_set, self.force, heights]))

    def backbone(self, plastic_set) -> np.ndarray:
        """Backbone force [N] at plastic sets [m] (linear between rows, flat past the end)."""
        return np.interp(plastic_set, self.plastic_set, self.force)


def rim_law_from_push(bearing: DFPBearing, stiffness: float, fine, full) -> RimLaw:
    """Build the law from an elastic stiffness [N/m] and two pushes of the rim
    (:class:`fem.pushover.Pushover`): ``fine`` to the hinge and a little beyond, ``full`` to
    half the rim height (Eq. R56)."""
    # a squat rim may never hinge at its root (Eq. F36) before half its height: the slider
    # crushes its inner face instead; its hinge limit state is then never reached
    hinged = fine if fine.hinge_displacement is not None else full
    keep = full.displacement > fine.displacement[-1] * (1 + 1e-9)
    d = np.concatenate([fine.displacement, full.displacement[keep]])
    f = np.concatenate([fine.force, full.force[keep]])
    up = d - f / stiffness
    # the backbone starts where the push leaves the elastic line (u_p crosses 0 upward)
    first = int(np.flatnonzero(up > 0)[0])
    f0 = np.interp(0.0, up[first - 1:first + 1], f[first - 1:first + 1])
    sets = np.concatenate([[0.0], up[first:]])
    forces = np.maximum.accumulate(np.concatenate([[f0], f[first:]]))  # flat past the peak
    sets = np.maximum.accumulate(sets)
    keep = np.concatenate([[True], np.diff(sets) > 0])
    sets, forces = _beyond_push(sets[keep], forces[keep], LEVER_FRACTION * bearing.rim_height)
    keep = slice(None)
    if hinged.hinge_displacement is None:
        hinge_d = hinge_f = hinge_set = math.inf
    else:
        hinge_d, hinge_f = float(hinged.hinge_displacement), float(hinged.hinge_force)
        hinge_set = hinge_d - hinge_f / stiffness
    avg = full.averaged_plastic_strain
    if avg.max() >= bearing.rupture_strain:
        k = int(np.flatnonzero(avg >= bearing.rupture_strain)[0])
        rupture_d = float(np.interp(bearing.rupture_strain, avg[k - 1:k + 1],
                                    full.displacement[k - 1:k + 1]))
        rupture_set = rupture_d - float(np.interp(rupture_d, d, f)) / stiffness
    else:
        rupture_d = rupture_set = math.inf
    return RimLaw(
        stiffness=float(stiffness), plastic_set=sets[keep], force=forces[keep],
        first_yield_force=float(f0), hinge_displacement=hinge_d, hinge_force=hinge_f,
        hinge_set=float(hinge_set),
        rupture_displacement=rupture_d, rupture_set=float(rupture_set),
        lever=LEVER_FRACTION * bearing.rim_height, push_displacement=d, push_force=f,
    )


def rim_law_through_tearing(bearing: DFPBearing, stiffness: float, fine, torn) -> RimLaw:
    """Build the law through tearing (Eqs. R55b, R56c, R64) from an elastic stiffness [N/m],
    the ``fine`` push to the hinge (as :func:`rim_law_from_push`) and a push with fracture
    and erosion, ``torn`` (:class:`fem.pushover.Pushover` with ``fracture`` and
    ``erosion_steps``), to the rim's coming off or as far as Newton goes.

    The backbone is made non-decreasing up to the push's first torn element and follows the
    push's falling force past it; each row carries the height of the rim's inner top corner
    above its root there; the first tear is the rupture (as Eq. F67 makes it in the FE
    model), and the last row is where the rim is off: the push's own if it ended so (Eq.
    R64), else a row added at u_p = t_r to a push that stopped short, of zero force if the
    rim had torn and of the last force if not (Eq. R64b); a push that went on past u_p = t_r
    is cut there (Eq. R64c)."""
    root = bearing.dish_depth(bearing.rim_radius)
    keep = torn.displacement > fine.displacement[-1] * (1 + 1e-9)
    d = np.concatenate([fine.displacement, torn.displacement[keep]])
    f = np.concatenate([fine.force, torn.force[keep]])
    h = np.concatenate([fine.corner[:, 1], torn.corner[keep, 1]]) - root
    up = d - f / stiffness
    first = int(np.flatnonzero(up > 0)[0])
    at_zero = slice(first - 1, first + 1)  # where the push leaves the elastic line
    f0 = float(np.interp(0.0, up[at_zero], f[at_zero]))
    sets = np.maximum.accumulate(np.concatenate([[0.0], up[first:]]))
    forces = np.concatenate([[f0], f[first:]])
    heights = np.concatenate([[np.interp(0.0, up[at_zero], h[at_zero])], h[first:]])
    tear_d = torn.fracture_displacement
    whole = np.concatenate([[True], d[first:] < (math.inf if tear_d is None else tear_d)])
    forces[whole] = np.maximum.accumulate(forces[whole])  # a prefix: flat past the peak
    keep = np.concatenate([[True], np.diff(sets) > 0])
    sets, forces, heights = sets[keep], forces[keep], heights[keep]
    off_set = float(sets[-1])
    if sets[-1] > bearing.rim_thickness:
        # Eq. R64c: a push that went on past u_p = t_r (the slider ploughing through a
        # crushed rim) is cut there: the rim's inner face is at the plate's outer edge, and
        # the rim is off its plate
        off_set = bearing.rim_thickness
        within = sets < off_set
        forces = np.append(forces[within], np.interp(off_set, sets, forces))
        heights = np.append(heights[within], np.interp(off_set, sets, heights))
        sets = np.append(sets[within], off_set)
    elif not torn.separated and sets[-1] < bearing.rim_thickness:
        # Eq. R64b: a push that Newton stopped short goes on to where the rim's inner face
        # reaches the plate's outer edge (u_p = t_r), where the rim is off its plate: a torn
        # rim's force falls linearly to zero there, an untorn one keeps its last force
        off_set = bearing.rim_thickness
        sets = np.append(sets, off_set)
        forces = np.append(forces, 0.0 if tear_d is not None else forces[-1])
        heights = np.append(heights, heights[-1])
    law = rim_law_from_push(bearing, stiffness, fine, torn)
    if tear_d is None:
        tear_set = rupture_d = rupture_set = math.inf
    else:
        rupture_d = float(tear_d)
        tear_set = rupture_set = rupture_d - float(torn.fracture_force) / stiffness
    return dataclasses.replace(
        law, plastic_set=sets, force=forces, corner_height=heights,
        rupture_displacement=rupture_d, rupture_set=float(rupture_set),
        tear_set=float(tear_set), off_set=off_set,
        push_displacement=d, push_force=f)


def _beyond_push(sets, forces, lever):
    """The backbone past the push's last row (Eq. R56b): the rim's root moment stays that of
    the last row while the lever over which the slider pushes it, L·cos φ with
    sin φ = u_p/L, shortens, so F = F_end·cos φ_end/cos φ, down to cos φ = LAST_COS."""
    s_end = min(sets[-1] / lever, 1.0)
    c_end = math.sqrt(1.0 - s_end**2)
    cos = np.linspace(c_end, LAST_COS, 41)[1:]
    return (np.concatenate([sets, lever * np.sqrt(1.0 - cos**2)]),
            np.concatenate([forces, forces[-1] * c_end / cos]))


def rim_law_cache_file(bearing: DFPBearing, model: str = "plane-strain",
                       fracture: str | None = None, *,
                       edge_radius: float | None = None,
                       crush_jacobian: float | None = None) -> Path:
    """Where the law of a bearing's rims is cached: ``rim-laws/<key>.npz`` in the library's
    cache folder (:func:`rigid.tasks.cache_root`), keyed by the model it comes from
    (:data:`RIM_LAW_MODELS`), the rim geometry and steel (every field of the bearing but the
    pressure), the push settings above, the fracture criterion of a law through tearing and
    the edge radius [m] of the slider that pushed it (``fem.rim_law(..., punch="slider")``)
    and the push's crushing J_c (``crush_jacobian``), each keyed only when set, and the code
    of the pushing model and of this module (``code_hash("fem", "rim-law")`` or
    ``code_hash("fem-ring", "rim-law")``)."""
    from .tasks import cache_root, task_key

    if model not in RIM_LAW_MODELS:
        raise ValueError(f"model must be one of {', '.join(RIM_LAW_MODELS)}, got {model!r}")
    if fracture is not None and model != "plane-strain":
        raise ValueError("a law through tearing comes from the plane-strain push only")
    if edge_radius is not None and fracture is None:
        raise ValueError("a law from the slider's push is a law through tearing: give fracture")
    # the bottom plate and its steel: everything but the load on it
    inputs = {k: v for k, v in dataclasses.asdict(bearing).items() if k != "pressure"}
    code = ("fem", "rim-law") if model == "plane-strain" else ("fem-ring", "rim-law")
    tearing = {} if fracture is None else {"fracture": fracture, "tearing": TEARING_PUSH}
    if edge_radius is not None:
        tearing["punch"] = {"slider": "pendulum path", "edge_radius": float(edge_radius)}
    if crush_jacobian is not None:
        if fracture is None:
            raise ValueError("crushing goes with a law through tearing: give fracture")
        tearing["crush_jacobian"] = float(crush_jacobian)
    key = task_key("rim-law", code, model=model, bearing=inputs, fine=FINE_PUSH,
                   elastic=ELASTIC_PUSH, lever=LEVER_FRACTION, last_cos=LAST_COS, **tearing)
    return cache_root() / "rim-laws" / f"{key}.npz"


def load_rim_law(path: Path) -> RimLaw:
    """A law saved by :func:`save_rim_law` (an ``.npz`` file of its fields)."""
    with np.load(path) as data:
        fields = {f.name: data[f.name] for f in dataclasses.fields(RimLaw) if f.name in data}
    return RimLaw(**{k: (v if v.ndim else float(v)) for k, v in fields.items()})


def save_rim_law(law: RimLaw, path: Path) -> None:
    """Write ``law`` to ``path`` (``.npz``), atomically (a reader never sees half a file)."""
    from .tasks import atomic_path

    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as f:
            np.savez(f, **dataclasses.asdict(law))


def resolve_rim_law(bearing: DFPBearing, law: RimLaw | None, *, stacklevel: int = 2) -> RimLaw:
    """The law a yielding-rim run uses: ``law`` when given (a :class:`RimLaw`), else, for one
    release and with a DeprecationWarning, ``fem.rim_law(bearing)``: the one place the rigid
    package reaches into ``fem`` (lazily, on this deprecated path only; docs/architecture.md).
    Without ``fem`` installed, a RuntimeError says how to get the law."""
    if law is not None:
        if not isinstance(law, RimLaw):
            raise TypeError(f"rim_law must be a rigid.rims.RimLaw, got {type(law).__name__}")
        return law
    warnings.warn("rims='yielding' without rim_law= is deprecated: compute the law with "
                  "fem.rim_law(bearing) and pass it as rim_law=", DeprecationWarning,
                  stacklevel=stacklevel + 1)
    try:
        from fem.rim_laws import rim_law as fe_rim_law  # deprecated path (see above)
    except ImportError as exc:
        raise RuntimeError("rims='yielding' needs the rims' law: compute it with "
                           "fem.rim_law(bearing) (the fem extra) and pass it as rim_law=; "
                           f"fem could not be imported ({exc})") from None
    return fe_rim_law(bearing)


def rim_law(bearing: DFPBearing, *, cache: bool = True) -> RimLaw:
    """Deprecated alias of ``fem.rim_law`` (the law is computed by the FE companion; this
    alias imports it on call, with a DeprecationWarning, for one release)."""
    warnings.warn("rigid.rim_law / rigid.rims.rim_law moved to fem.rim_law", DeprecationWarning,
                  stacklevel=2)
    from fem.rim_laws import rim_law as fe_rim_law  # deprecated path (see resolve_rim_law)

    return fe_rim_law(bearing, cache=cache)
