"""Numba core of the rigid-body DFP model (private; use :func:`rigid.simulate`).

Frame: X horizontal (direction of shaking), Z up, coordinates relative to the bottom plate,
which follows the ground; every free body carries the inertial load −m·a_g in X.
Bodies: slider (x_S, z_S, θ) and top plate with the supported mass (x_T, z_T), paper §2.
Contacts (12 slots, each with its own hysteretic friction state; docs/theory/rigid-body.md,
"Contact slots"):

* 0–3   slider vertices on the dish of their plate (bottom-left, bottom-right, top-left,
        top-right vertex), Eq. R22;
* 4–7   the same vertices against the restraining rim they face (inner face or rim top),
        Eq. R23;
* 8–11  the rims' inner corners (bottom −x, bottom +x, top −x, top +x) against the slider's
        sides and faces, so that a tilted slider cannot pass through a rim corner, Eq. R24.

Normal force: Hertz with the Jankowski nonlinear damper, F = kδ^1.5 + cδ̇ on approach and kδ^1.5
on restitution, c = 2ξ√(k√δ·m_eff) (paper Eqs. 1–4; Eqs. R15–R19). Friction: Coulomb, μF_n·Z,
with Z a hysteretic state per contact: an elastic–perfectly-plastic tangential spring of
stiffness μF_n/Y (the sharp limit of the Bouc–Wen law), updated by its exact return map
(Eqs. R27–R28).

Time stepping (docs/theory/rigid-body.md §Time steps): velocity Verlet (kick–drift–kick,
Eq. R30). The contact dampers are implicit in the kicks (backward Euler on the 5 × 5 system
M + h/2·C, Eqs. R31–R32), because c/m_s reaches 1e5–1e6 1/s when the supported mass sets c;
the friction state advances on the half-step slip. Far from the rims, with every contact near
its static load, the step is longer (Eq. R34: explicit medium steps below the stability limit
of the contact modes, Eq. R37, or coarse steps on a modified mass, Eqs. R35–R36); near and at
the rims the fine step resolves the impacts. The hot loop allocates nothing.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# parameter vector layout ------------------------------------------------------------------
P_R, P_HALF_B, P_HS, P_HALF_HE, P_RIN, P_TR, P_ZTOP = 0, 1, 2, 3, 4, 5, 6
P_K, P_XI, P_MU, P_MU_RIM, P_Y, P_MS, P_JS, P_M, P_G = 7, 8, 9, 10, 11, 12, 13, 14, 15
P_MEFF_BOT, P_MEFF_TOP, P_DMAX, P_MERGE, P_DFAR, P_DNEAR = 16, 17, 18, 19, 20, 21
# yielding rims (docs/theory/rigid-body.md, "Yielding rims"): flag, rim height, elastic
# stiffness, lever of the rim's bending, plastic sets at the hinge and at rupture, criterion;
# a law through tearing: 1 if the corner heights come from the law's table (Eq. R55b), and
# the set at which a rim is off (Eq. R64; inf: never)
P_YIELDING, P_HR, P_KEL, P_LEVER, P_UP_HINGE, P_UP_RUPTURE, P_CRITERION = (
    22, 23, 24, 25, 26, 27, 28)
P_CORNER, P_UP_OFF = 29, 30
N_PARAMS = 31
#: failure criteria (P_CRITERION): the limit state that ends a run with yielding rims
CRIT_CONTAINMENT, CRIT_HINGE, CRIT_RUPTURE = 0, 1, 2

# history channels ----------------------------------------------------------------------------
H_XT, H_ZT, H_XS, H_ZS, H_TH, H_VT, H_SHEAR, H_RIMF = 0, 1, 2, 3, 4, 5, 6, 7
H_EIN, H_EKIN, H_EPOT, H_EFRIC, H_EIMP = 8, 9, 10, 11, 12
H_EPLAS, H_SET = 13, 14  # rims' plastic work [J]; largest permanent set of a rim [m]
N_CHANNELS = 15

# summary entries -----------------------------------------------------------------------------
S_STATUS, S_FAIL_TIME, S_FAIL_CODE, S_N_EVENTS, S_MAX_UPLIFT, S_MAX_ROT = 0, 1, 2, 3, 4, 5
S_MAX_PEN, S_MAX_RIMF, S_EIN, S_EKIN, S_EPOT, S_EFRIC, S_EIMP, S_N_REC, S_STEPS = (
    6,
    7,
    8,
    9,
    10,
    11,
    12,
    13,
    14,
)
S_TAKEN = 15  # steps actually taken, fine and coarse
# yielding rims: first hinge, first rupture and loss of containment [s] (−1: not reached),
# plastic work [J], then the permanent set of each rim [m]
S_T_HINGE, S_T_RUPTURE, S_T_CONTAINMENT, S_EPLAS, S_SET = 16, 17, 18, 19, 20
N_SUMMARY = 24

# status and failure codes --------------------------------------------------------------------
STATUS_OK, STATUS_FAILED, STATUS_NUMERICAL = 0, 1, 2
FAIL_BOTTOM_RIM, FAIL_TOP_RIM, FAIL_CENTROID, FAIL_OVERTURN = 1, 2, 3, 4
# yielding rims: a hinge or a rupture (the criterion asked for), a vertex got through a bent
# bottom or top rim (Eq. R63), a torn rim came off (Eq. R64)
FAIL_HINGE, FAIL_RUPTURE, FAIL_THROUGH_BOTTOM, FAIL_THROUGH_TOP, FAIL_TORN_OFF = 5, 6, 7, 8, 9
NUM_NAN, NUM_PENETRATION, NUM_ENERGY, NUM_JUMP = 10, 11, 12, 13
#: energy residual, relative to the input energy, beyond which the run counts as unstable
#: (Eq. R46)
ENERGY_TOLERANCE = 0.05

N_SLOTS = 12
#: modified-mass factor of the coarse steps, M + β·h²·K: stable for a true contact stiffness
#: up to 4β times the one in K (Hertz stiffens as √δ, and K is taken at the step's start;
#: Eqs. R35–R36)
BETA = 1.0
# work vector of the force routine: energies, forces and flags, then the damping matrix C
A_EEL, A_CSUM, A_PFRIC, A_BFX, A_KSUM, A_C = 0, 1, 2, 3, 4, 5
#: (row, column) of each stored entry of the upper triangle of C (and of K); the unrolled
#: solve of :func:`_kick` follows this order
C_INDEX = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2), (0, 3), (0, 4), (1, 3), (1, 4),
           (2, 3), (2, 4), (3, 3), (3, 4), (4, 4))
A_K = A_C + 15  # then the contact stiffness matrix K (same layout), far from the rims
A_PLAS = A_K + 15  # then the rims' plastic work over the step [J]
N_ACC = A_PLAS + 1
N_RIMS = 4
EVENT_FIELDS = 5  # time, rim, top-plate velocity, peak rim force, duration


@njit(cache=True)
def friction_state_update(z0, slip_over_y):
    """Hysteretic friction state after a slip (in units of Y): an elastic–perfectly-plastic
    tangential spring, the η → ∞ limit of the Bouc–Wen law (Cundall & Strack 1979).

    Z = F_t/(μF_n) grows by slip/Y while sticking and saturates at ±1 while sliding; the
    update is the exact return map, stable at any step (Eq. R27).
    """
    return min(1.0, max(-1.0, z0 + slip_over_y))


@njit(cache=True)
def damper_coefficient(sqrt_delta, k, xi, meff):
    """Damping coefficient c = 2ξ√(k√δ·m_eff) [N·s/m], paper Eq. 3 (Eq. R17)."""
    return 2.0 * xi * math.sqrt(k * sqrt_delta * meff)


@njit(cache=True)
def hertz_damped_force(delta, delta_rate, k, xi, meff):
    """Normal contact force of paper Eqs. 1–3 as (elastic, damper) parts [N], for δ > 0.

    Elastic kδ^1.5 always; damper cδ̇ only on approach (δ̇ > 0), so the force is never
    tensile (Eqs. R15–R17). The kernel applies the same law with the damper implicit in time.
    """
    sd = math.sqrt(delta)
    if delta_rate > 0.0:
        return k * delta * sd, damper_coefficient(sd, k, xi, meff) * delta_rate
    return k * delta * sd, 0.0


@njit(cache=True, inline="always")
def _add_gtg(acc, base, c, g0, g1, g2, top):
    """Add c·GᵀG to the matrix kept in acc[base:] (upper triangle, order of ``C_INDEX``):
    the damping matrix (base A_C) or the stiffness matrix (A_K). G = [g0, g1, g2, −g0, −g1],
    the last two only for contacts with the top plate; with g = (n_x, n_z, r×n), G·v is
    minus the approach rate (Eq. R31). (Kept in ``acc``: a separate array made the force routine 2×
    slower.)"""
    a0 = c * g0
    a1 = c * g1
    a2 = c * g2
    acc[base] += a0 * g0
    acc[base + 1] += a0 * g1
    acc[base + 2] += a0 * g2
    acc[base + 3] += a1 * g1
    acc[base + 4] += a1 * g2
    acc[base + 5] += a2 * g2
    if top:
        acc[base + 6] -= a0 * g0
        acc[base + 7] -= a0 * g1
        acc[base + 8] -= a1 * g0
        acc[base + 9] -= a1 * g1
        acc[base + 10] -= a2 * g0
        acc[base + 11] -= a2 * g1
        acc[base + 12] += a0 * g0
        acc[base + 13] += a0 * g1
        acc[base + 14] += a1 * g1


@njit(cache=True, inline="always")
def _apply(slot, delta, nx, nz, px, pz, top, meff, mu, p, q, v, h, Z, gen, acc, stiff,
           cscale=1.0):
    """Contact force of one slot on the slider at point (px, pz) with normal (nx, nz).

    ``top`` is True when the other body is the top plate (moving with v[3], v[4]), False for
    the bottom plate (fixed in this frame). Adds the elastic and friction forces into
    ``gen``; into ``acc`` the elastic energy, the friction power, the bottom plate's Fx and,
    on approach, the damper c·GᵀG (implicit in the kicks); with ``stiff``, the contact's
    tangent stiffness (normal 1.5k√δ, and μF_n/Y along the tangent while sticking) into the
    stiffness matrix. ``cscale`` multiplies the damper (a yielding rim's series compliance,
    Eq. R60). Returns the elastic normal force. Eqs. R25–R28 of docs/theory/rigid-body.md.
    """
    rx = px - q[0]
    rz = pz - q[1]
    # relative velocity of the slider's material point with respect to the plate (Eq. R25)
    wx = v[0] - v[2] * rz - (v[3] if top else 0.0)
    wz = v[1] + v[2] * rx - (v[4] if top else 0.0)
    ddot = -(wx * nx + wz * nz)
    vt = -wx * nz + wz * nx  # tangent t = (−n_z, n_x)
    sd = math.sqrt(delta)
    f_el = p[P_K] * delta * sd  # Eq. R15 (Hertz): paper Eq. 2, the elastic part of Eq. 1
    if ddot > 0.0:  # approach: Eqs. R16–R17 (Jankowski damper), paper Eq. 1 with c from Eq. 3
        c = damper_coefficient(sd, p[P_K], p[P_XI], meff) * cscale
        _add_gtg(acc, A_C, c, nx, nz, rx * nz - rz * nx, top)
        acc[A_CSUM] += c
    # Coulomb friction on the elastic normal force (the damper's part is transient):
    # Eqs. R27–R28
    z = friction_state_update(Z[slot], vt * h / p[P_Y])
    Z[slot] = z
    if stiff:
        _add_gtg(acc, A_K, 1.5 * p[P_K] * sd, nx, nz, rx * nz - rz * nx, top)
        if abs(z) < 1.0:  # sticking: the tangential spring, t = (−n_z, n_x)
            _add_gtg(acc, A_K, mu * f_el / p[P_Y], -nz, nx, rx * nx + rz * nz, top)
        acc[A_KSUM] = 1.0
    ft = -mu * f_el * z
    fx = f_el * nx - ft * nz  # Eq. R26
    fz = f_el * nz + ft * nx
    gen[0] += fx
    gen[1] += fz
    gen[2] += rx * fz - rz * fx
    if top:
        gen[3] -= fx
        gen[4] -= fz
    else:
        acc[A_BFX] -= fx
    acc[A_EEL] += f_el * delta / 2.5  # Eq. R20
    acc[A_PFRIC] += -ft * vt  # Eq. R50
    return f_el


@njit(cache=True, inline="always")
def _corner_contact(dx, dz, c, s, hb, hs, R):
    """A rim's inner corner against the slider's section (Eq. R24): the corner at (dx, dz) [m]
    from the slider's centre, the slider turned by θ (c = cos θ, s = sin θ), its half width
    ``hb``, height ``hs`` and face radius ``R`` [m]. Returns the depth [m] of the corner below
    the nearest face of the section (flat side, spherical bottom or top; 0.0 if outside) and
    the force's direction on the slider (−the outward normal of that face, global)."""
    qx = c * dx + s * dz  # corner in the slider's body frame
    qz = -s * dx + c * dz
    dside = hb - abs(qx)
    if dside <= 0.0 or abs(qz) > hs:
        return 0.0, 0.0, 0.0
    # depth below each face of the section: side (flat), bottom and top (spherical)
    db = R - math.sqrt(qx * qx + (qz + hs / 2 - R) ** 2)
    dt_ = R - math.sqrt(qx * qx + (qz - hs / 2 + R) ** 2)
    if db <= 0.0 or dt_ <= 0.0:
        return 0.0, 0.0, 0.0
    if dside <= db and dside <= dt_:
        delta, nbx, nbz = dside, (1.0 if qx > 0 else -1.0), 0.0
    elif db <= dt_:
        ln = math.sqrt(qx * qx + (qz + hs / 2 - R) ** 2)
        delta, nbx, nbz = db, qx / ln, (qz + hs / 2 - R) / ln
    else:
        ln = math.sqrt(qx * qx + (qz - hs / 2 + R) ** 2)
        delta, nbx, nbz = dt_, qx / ln, (qz - hs / 2 + R) / ln
    # outward body normal to global; the force on the slider points inward (−n_out)
    return delta, -(c * nbx - s * nbz), -(s * nbx + c * nbz)


@njit(cache=True)
def forces(p, q, v, Z, h, gen, acc, rimf, sep, vert, stiff, rim_set, law, buf, count):
    """Generalized contact forces at configuration q with velocities v.

    Advances the friction states Z over a slip of v_t·h (h = 0 leaves them). Fills:
    gen[5] slider Fx, Fz, moment and top-plate Fx, Fz [N, N·m]; acc as in :func:`_apply`;
    rimf[4] total normal force on each rim [N]; sep[2] the smaller vertex separation from the
    bottom and from the top dish [m]. With ``stiff`` the contacts' tangent stiffness matrix
    goes into acc[A_K:] (see :func:`_kick`). With yielding rims (p[P_YIELDING]) the rim
    contacts go through :func:`_yielding_rims`, which advances the rims' permanent sets
    ``rim_set`` when h > 0 (backbone ``law``; ``buf`` and ``count`` its work space).
    Returns the largest penetration [m].
    """
    yielding = p[P_YIELDING] != 0.0
    for i in range(5):
        gen[i] = 0.0
    for i in range(N_ACC):
        acc[i] = 0.0
    for i in range(N_RIMS):
        rimf[i] = 0.0
    R = p[P_R]
    hb = p[P_HALF_B]
    hs = p[P_HS]
    hhe = p[P_HALF_HE]
    rin = p[P_RIN]
    tr = p[P_TR]
    ztop = p[P_ZTOP]
    xs, zs, th, xt, zt = q[0], q[1], q[2], q[3], q[4]
    c = math.cos(th)
    s = math.sin(th)
    ctz = zt + hs - R  # centre of the top dish (x_T, ctz); bottom dish centre (0, R)
    dmax = 0.0
    sep[0] = 1e9
    sep[1] = 1e9
    off_bottom = False
    off_top = False
    for j in range(4):
        bx = hb if (j % 2 == 1) else -hb
        bz = hhe if j >= 2 else -hhe
        px = xs + c * bx - s * bz
        pz = zs + s * bx + c * bz
        vert[j, 0] = px
        vert[j, 1] = pz
        is_top = j >= 2
        if is_top:
            cx, cz, meff = xt, ctz, p[P_MEFF_TOP]
        else:
            cx, cz, meff = 0.0, R, p[P_MEFF_BOT]
        # vertex on the dish (slot j, Eq. R22); the dish continues under the rim root
        dx = cx - px
        dz = cz - pz
        d = math.sqrt(dx * dx + dz * dz)
        delta = d - R
        vert[j, 2] = delta
        xl = px - cx
        if abs(xl) <= rin + tr:
            sep[1 if is_top else 0] = min(sep[1 if is_top else 0], -delta)
            if delta > 0.0:
                dmax = max(dmax, delta)
                _apply(j, delta, dx / d, dz / d, px, pz, is_top, meff, p[P_MU], p, q, v, h, Z,
                       gen, acc, stiff)
            else:
                Z[j] = 0.0
        else:
            Z[j] = 0.0
            if is_top:
                off_top = True
            else:
                off_bottom = True
        if yielding:  # the rims are done below
            continue
        # vertex against the rim it faces (slot 4 + j, Eq. R23): inner face or rim top/bottom
        # face
        side = 1.0 if xl >= 0.0 else -1.0
        u = side * xl - rin
        if is_top:
            w = pz - (zt + hs - ztop)
        else:
            w = ztop - pz
        rim = (2 if is_top else 0) + (1 if side > 0 else 0)
        if u > 0.0 and u < tr and w > 0.0:
            if u <= w:
                delta, nx, nz = u, -side, 0.0
            else:
                delta, nx, nz = w, 0.0, (-1.0 if is_top else 1.0)
            dmax = max(dmax, delta)
            rimf[rim] += _apply(4 + j, delta, nx, nz, px, pz, is_top, meff, p[P_MU_RIM], p, q, v,
                                h, Z, gen, acc, stiff)
        else:
            Z[4 + j] = 0.0
    if off_bottom:
        sep[0] = 1e9
    if off_top:
        sep[1] = 1e9
    if yielding:
        return max(dmax, _yielding_rims(p, q, v, Z, h, gen, acc, rimf, vert, stiff, rim_set,
                                        law, buf, count))
    # rim corners against the slider's section (slots 8–11, Eq. R24)
    for r in range(N_RIMS):
        is_top = r >= 2
        side = 1.0 if (r % 2 == 1) else -1.0
        if is_top:
            kx, kz = xt + side * rin, zt + hs - ztop
        else:
            kx, kz = side * rin, ztop
        delta, nx, nz = _corner_contact(kx - xs, kz - zs, c, s, hb, hs, R)
        if delta <= 0.0:
            Z[8 + r] = 0.0
            continue
        meff = p[P_MEFF_TOP] if is_top else p[P_MEFF_BOT]
        dmax = max(dmax, delta)
        rimf[r] += _apply(8 + r, delta, nx, nz, kx, kz, is_top, meff, p[P_MU_RIM], p, q, v, h,
                          Z, gen, acc, stiff)
    return dmax


# yielding rims (docs/theory/rigid-body.md, "Yielding rims", Eqs. R55–R63) -------------------
#: fields of a rim contact in the work buffer: slot, overlap, normal (x, z), point (x, z),
#: share: the part of the normal across the rim, the overlap a unit outward deflection of
#: the rim closes (Eq. R58)
B_SLOT, B_GAP, B_NX, B_NZ, B_PX, B_PZ, B_SHARE = 0, 1, 2, 3, 4, 5, 6
B_FIELDS = 7
#: contacts one rim can carry at once: two vertices and its corner
B_CONTACTS = 3


@njit(cache=True)
def backbone_force(law, up):
    """Rim force on the backbone at plastic set ``up`` [m]: linear between the rows of
    ``law`` (plastic set [m], force [N], corner height [m]), flat past the last row (Eq.
    R56)."""
    return _law_at(law, up, 1)


@njit(cache=True)
def _law_at(law, up, column):
    """Column ``column`` of the law's table at plastic set ``up`` [m]: linear between its
    rows, flat past either end."""
    n = law.shape[0]
    if up <= law[0, 0]:
        return law[0, column]
    for i in range(1, n):
        if up <= law[i, 0]:
            return law[i - 1, column] + (law[i, column] - law[i - 1, column]) * (
                up - law[i - 1, 0]) / (law[i, 0] - law[i - 1, 0])
    return law[n - 1, column]


@njit(cache=True)
def backbone_slope(law, up):
    """dF/du_p of the backbone at ``up`` [N/m] (0 past its last row)."""
    n = law.shape[0]
    for i in range(1, n):
        if up < law[i, 0]:
            return (law[i, 1] - law[i - 1, 1]) / (law[i, 0] - law[i - 1, 0])
    return 0.0


@njit(cache=True)
def _rim_load(buf, n, k, w):
    """Force across a rim that has deflected by w [m], Σ k·(g_i − w·s_i)^1.5·s_i over its
    contacts (overlap g_i, share s_i), and its derivative in w (Eq. R58)."""
    f = 0.0
    df = 0.0
    for i in range(n):
        s = buf[i, B_SHARE]
        d = buf[i, B_GAP] - w * s
        if s > 0.0 and d > 0.0:
            sd = math.sqrt(d)
            f += k * d * sd * s
            df -= 1.5 * k * sd * s * s
    return f, df


@njit(cache=True)
def rim_response(buf, n, k, k_el, law, up0):
    """Deflection w [m], force F [N] and plastic increment Δu_p [m] of one rim pressed by the
    ``n`` contacts in ``buf`` (overlaps measured against the rim at its set ``up0``), each a
    Hertz spring in series with the rim: elastic k_el up to the backbone force, then plastic
    flow along the backbone ``law`` (Eqs. R57–R59). Both equations are monotone in the
    unknown, so their roots are unique: Newton from w = 0 for the elastic trial (the residual
    is convex and decreasing, so the iterates rise to the root without overshoot), bisection
    for the plastic increment (the backbone is piecewise linear)."""
    w = 0.0
    for _ in range(100):  # elastic trial, Eq. R57
        f, df = _rim_load(buf, n, k, w)
        step = (f - k_el * w) / (k_el - df)
        w += step
        if step <= 1e-14 + 1e-12 * w:
            break
    force = k_el * w
    if force <= backbone_force(law, up0):
        return w, force, 0.0
    # plastic increment, Eq. R59: r(Δ) = load at w = F_b/k_el + Δ, minus F_b(u0 + Δ), is
    # decreasing; r(0) > 0 and r(hi) < 0 at the largest overlap. Regula falsi with the
    # Illinois modification keeps the bracket and converges superlinearly
    lo, r_lo = 0.0, force - backbone_force(law, up0)
    hi = 0.0
    for i in range(n):
        if buf[i, B_SHARE] > 0.0:
            hi = max(hi, buf[i, B_GAP] / buf[i, B_SHARE])
    r_hi = -backbone_force(law, up0 + hi)
    side = 0
    d = hi
    for _ in range(100):
        d = (lo * r_hi - hi * r_lo) / (r_hi - r_lo)
        fb = backbone_force(law, up0 + d)
        f, _ = _rim_load(buf, n, k, fb / k_el + d)
        r = f - fb
        if r > 0.0:
            lo, r_lo = d, r
            if side == 1:
                r_hi *= 0.5
            side = 1
        else:
            hi, r_hi = d, r
            if side == -1:
                r_lo *= 0.5
            side = -1
        if hi - lo <= 1e-15 + 1e-12 * hi or abs(r) <= 1e-12 * fb:
            break
    fb = backbone_force(law, up0 + d)
    return fb / k_el + d, fb, d


@njit(cache=True)
def rim_geometry(p, q, r, up, law):
    """A rim bent outward by its plastic set ``up`` [m] (Eq. R55): its inner face moved
    outward by u_p, and lowered to the height h_r·cos φ it keeps when it turns by φ about its
    root, sin φ = u_p/L (L = p[P_LEVER], at most a right angle); with a law through tearing
    (p[P_CORNER]) the height is the corner's in the push at that set instead (Eq. R55b, the
    law's third column). Returns the face's x, the root's z and the face's height towards
    the free end (upward for bottom rims, downward for top rims) [m]. Rims 0–3 as
    RIM_NAMES; top rims relative to the top plate."""
    side = 1.0 if r % 2 == 1 else -1.0
    if p[P_CORNER] > 0.0:
        height = _law_at(law, up, 2)
    else:
        sphi = min(1.0, up / p[P_LEVER])
        height = p[P_HR] * math.sqrt(1.0 - sphi * sphi)
    if r >= 2:
        return q[3] + side * (p[P_RIN] + up), q[4] + p[P_HS] - p[P_ZTOP] + p[P_HR], height
    return side * (p[P_RIN] + up), p[P_ZTOP] - p[P_HR], height


@njit(cache=True)
def _yielding_rims(p, q, v, Z, h, gen, acc, rimf, vert, stiff, rim_set, law, buf, count):
    """Contact forces of the four yielding rims (slots 4–11 as for rigid rims; Eqs. R55–R61):
    gathers each rim's contacts against its bent geometry, solves the rim in series with them
    (:func:`rim_response`), applies the Hertz forces that remain with the damper scaled by
    the series compliance, adds the rims' elastic energy to acc[A_EEL] and, when h > 0,
    advances their sets and puts the plastic work in acc[A_PLAS]. Returns the largest
    overlap [m]."""
    dmax = 0.0
    xs, zs, th = q[0], q[1], q[2]
    # no rim within reach of the slider (the sets only move faces outward): nothing to do
    reach = math.sqrt(p[P_HALF_B] ** 2 + 0.25 * p[P_HS] ** 2)
    if abs(xs) + reach < p[P_RIN] and abs(xs - q[3]) + reach < p[P_RIN]:
        for slot in range(4, N_SLOTS):
            Z[slot] = 0.0
        return 0.0
    for r in range(N_RIMS):
        count[r] = 0
    c = math.cos(th)
    s = math.sin(th)
    tr = p[P_TR]
    for j in range(4):  # vertices against the rim they face (slots 4–7, Eq. R23 bent)
        is_top = j >= 2
        sz = -1.0 if is_top else 1.0
        px, pz = vert[j, 0], vert[j, 1]
        side = 1.0 if px - (q[3] if is_top else 0.0) >= 0.0 else -1.0
        r = (2 if is_top else 0) + (1 if side > 0 else 0)
        xf, z0, height = rim_geometry(p, q, r, rim_set[r], law)
        u = side * (px - xf)  # depth past the inner face
        w = height - sz * (pz - z0)  # depth below the free end
        if u > 0.0 and u < tr and w > 0.0:
            b = buf[r, count[r]]
            b[B_SLOT], b[B_PX], b[B_PZ] = 4 + j, px, pz
            if u <= w:  # the inner face: across the rim
                b[B_GAP], b[B_NX], b[B_NZ], b[B_SHARE] = u, -side, 0.0, 1.0
            else:  # the free end: along the rim
                b[B_GAP], b[B_NX], b[B_NZ], b[B_SHARE] = w, 0.0, sz, 0.0
            count[r] += 1
        else:
            Z[4 + j] = 0.0
    hb = p[P_HALF_B]
    hs = p[P_HS]
    R = p[P_R]
    for r in range(N_RIMS):  # corners against the slider's section (slots 8–11, Eq. R24)
        side = 1.0 if r % 2 == 1 else -1.0
        xf, z0, height = rim_geometry(p, q, r, rim_set[r], law)
        kx, kz = xf, z0 + (-height if r >= 2 else height)
        delta, nx, nz = _corner_contact(kx - xs, kz - zs, c, s, hb, hs, R)
        if delta <= 0.0:
            Z[8 + r] = 0.0
            continue
        b = buf[r, count[r]]
        b[B_SLOT], b[B_GAP], b[B_NX], b[B_NZ], b[B_PX], b[B_PZ] = 8 + r, delta, nx, nz, kx, kz
        b[B_SHARE] = max(0.0, -side * nx)
        count[r] += 1
    k = p[P_K]
    k_el = p[P_KEL]
    for r in range(N_RIMS):
        n = count[r]
        if n == 0:
            continue
        is_top = r >= 2
        up0 = rim_set[r]
        w, force, d = rim_response(buf[r], n, k, k_el, law, up0)
        k_rim = k_el  # the rim's tangent in series with each contact (Eq. R60)
        if d > 0.0:
            slope = backbone_slope(law, up0 + d)
            k_rim = k_el * slope / (k_el + slope) if slope > 0.0 else 0.0
        meff = p[P_MEFF_TOP] if is_top else p[P_MEFF_BOT]
        sz = -1.0 if is_top else 1.0
        end_load = 0.0  # the contact forces along the rim, against its free end [N]
        for i in range(n):
            b = buf[r, i]
            slot = int(b[B_SLOT])
            dmax = max(dmax, b[B_GAP])
            delta = b[B_GAP] - w * b[B_SHARE]
            if delta <= 0.0:
                Z[slot] = 0.0
                continue
            kh = 1.5 * k * math.sqrt(delta) * b[B_SHARE] ** 2
            scale = k_rim / (k_rim + kh) if kh > 0.0 else 1.0
            f = _apply(slot, delta, b[B_NX], b[B_NZ], b[B_PX], b[B_PZ], is_top, meff,
                       p[P_MU_RIM], p, q, v, h, Z, gen, acc, stiff, scale * scale)
            rimf[r] += f
            end_load += f * sz * b[B_NZ]
        acc[A_EEL] += 0.5 * force * force / k_el
        if h > 0.0 and d > 0.0:
            # plastic work: the force across the rim over the set, and the load on its end
            # over the drop of the end that the set brings (Eq. R61)
            drop = rim_geometry(p, q, r, up0, law)[2] - rim_geometry(p, q, r, up0 + d, law)[2]
            acc[A_PLAS] += 0.5 * (backbone_force(law, up0) + force) * d + end_load * drop
            rim_set[r] = up0 + d
    return dmax


@njit(cache=True)
def _containment_yielding(p, q, vert, rim_set, law):
    """Loss of containment with bent rims (0: none), Eq. R63: a vertex beyond the bent inner
    corner of the rim it faces, horizontally outside and vertically past it — over the rim
    (FAIL_BOTTOM_RIM/FAIL_TOP_RIM) if it is also past the corner's unbent height, through it
    (FAIL_THROUGH_BOTTOM/TOP) if not; the centroid past an unbent inner face; overturning."""
    for j in range(4):
        is_top = j >= 2
        px, pz = vert[j, 0], vert[j, 1]
        side = 1.0 if px - (q[3] if is_top else 0.0) >= 0.0 else -1.0
        r = (2 if is_top else 0) + (1 if side > 0 else 0)
        kx, z0, height = rim_geometry(p, q, r, rim_set[r], law)
        kz = z0 + (-height if is_top else height)
        if side * (px - kx) <= 0.0:
            continue
        if not is_top and pz > kz:
            return FAIL_BOTTOM_RIM if pz > p[P_ZTOP] else FAIL_THROUGH_BOTTOM
        if is_top and pz < kz:
            unbent = q[4] + p[P_HS] - p[P_ZTOP]
            return FAIL_TOP_RIM if pz < unbent else FAIL_THROUGH_TOP
    if abs(q[0]) > p[P_RIN] or abs(q[0] - q[3]) > p[P_RIN]:
        return FAIL_CENTROID
    if abs(q[2]) > 0.25 * math.pi:
        return FAIL_OVERTURN
    return 0


@njit(cache=True)
def _step_jump(p, v, hs):
    """Largest distance [m] any point of the slider or the top plate moved in the last step
    of length hs [s] (translations, and the rotation times the slider's half-diagonal)."""
    arm = math.hypot(p[P_HALF_B], 0.5 * p[P_HS])
    jump = abs(v[2]) * hs * arm
    for i in (0, 1, 3, 4):
        jump = max(jump, abs(v[i]) * hs)
    return jump


@njit(cache=True)
def _failure(p, q, vert):
    """Physical failure code (0: none): the slider has escaped over a rim or overturned.

    Only bottom vertices are tested against bottom rims and top vertices against top rims
    (a tilted slider's upper corners legitimately overhang the bottom rim; Eqs. R42–R45 of
    docs/theory/rigid-body.md).
    """
    xs, xt, zt = q[0], q[3], q[4]
    rin = p[P_RIN]
    ztop = p[P_ZTOP]
    for j in range(2):
        if abs(vert[j, 0]) > rin and vert[j, 1] > ztop:
            return FAIL_BOTTOM_RIM
    for j in range(2, 4):
        if abs(vert[j, 0] - xt) > rin and vert[j, 1] < zt + p[P_HS] - ztop:
            return FAIL_TOP_RIM
    if abs(xs) > rin or abs(xs - xt) > rin:
        return FAIL_CENTROID
    if abs(q[2]) > 0.25 * math.pi:
        return FAIL_OVERTURN
    return 0


@njit(cache=True)
def _kick(p, v, gen, ag, acc, hk):
    """Half kick of velocity Verlet over hk, with the contact dampers backward-Euler:
    (M + hk·C) v⁺ = M v + hk·F (Eq. R32). Implicit damping keeps the step free of the
    damper's limit (c/m_s reaches 1e5–1e6 1/s when the supported mass sets c).

    On coarse steps (acc[A_KSUM] set) the mass is modified by the contacts' tangent stiffness:
    (M + β·h²K + hk·C)(v⁺ − v) = hk·(F − C·v), h = 2hk (Eq. R35). For a linear system this is
    central differences on the mass M + β·h²K, stable at any step for β ≥ 1/4 (the Newmark
    average-acceleration equivalence, Eq. R36); it slows only the stiff contact modes, whose
    directions K spans, and leaves the sliding motion alone. Returns the energy the dampers
    dissipated, hk·v⁺ᵀCv⁺ [J] (Eq. R33)."""
    ms, js, mt = p[P_MS], p[P_JS], p[P_M]
    f0 = gen[0] - ms * ag
    f1 = gen[1] - ms * p[P_G]
    f3 = gen[3] - mt * ag
    f4 = gen[4] - mt * p[P_G]
    if acc[A_CSUM] == 0.0 and acc[A_KSUM] == 0.0:  # no contact approaching
        v[0] += hk * f0 / ms
        v[1] += hk * f1 / ms
        v[2] += hk * gen[2] / js
        v[3] += hk * f3 / mt
        v[4] += hk * f4 / mt
        return 0.0
    # M + hk·C (C's upper triangle in the order of C_INDEX), solved by an unrolled Cholesky
    # factorisation L·Lᵀ in scalars: a 5 × 5 system in registers beats loops (BENCHMARKS.md,
    # "Rigid model")
    c = acc
    a00 = ms + hk * c[A_C]
    a01 = hk * c[A_C + 1]
    a02 = hk * c[A_C + 2]
    a11 = ms + hk * c[A_C + 3]
    a12 = hk * c[A_C + 4]
    a22 = js + hk * c[A_C + 5]
    a03 = hk * c[A_C + 6]
    a04 = hk * c[A_C + 7]
    a13 = hk * c[A_C + 8]
    a14 = hk * c[A_C + 9]
    a23 = hk * c[A_C + 10]
    a24 = hk * c[A_C + 11]
    a33 = mt + hk * c[A_C + 12]
    a34 = hk * c[A_C + 13]
    a44 = mt + hk * c[A_C + 14]
    b0 = ms * v[0] + hk * f0
    b1 = ms * v[1] + hk * f1
    b2 = js * v[2] + hk * gen[2]
    b3 = mt * v[3] + hk * f3
    b4 = mt * v[4] + hk * f4
    if acc[A_KSUM] != 0.0:  # modified mass M + hk²K: add hk²K to the matrix and hk²K·v to b
        k = acc
        h2 = 4.0 * BETA * hk * hk  # β·h² of the whole step
        v0, v1, v2, v3, v4 = v[0], v[1], v[2], v[3], v[4]
        a00 += h2 * k[A_K]
        a01 += h2 * k[A_K + 1]
        a02 += h2 * k[A_K + 2]
        a11 += h2 * k[A_K + 3]
        a12 += h2 * k[A_K + 4]
        a22 += h2 * k[A_K + 5]
        a03 += h2 * k[A_K + 6]
        a04 += h2 * k[A_K + 7]
        a13 += h2 * k[A_K + 8]
        a14 += h2 * k[A_K + 9]
        a23 += h2 * k[A_K + 10]
        a24 += h2 * k[A_K + 11]
        a33 += h2 * k[A_K + 12]
        a34 += h2 * k[A_K + 13]
        a44 += h2 * k[A_K + 14]
        b0 += h2 * (k[A_K] * v0 + k[A_K + 1] * v1 + k[A_K + 2] * v2 + k[A_K + 6] * v3
                    + k[A_K + 7] * v4)
        b1 += h2 * (k[A_K + 1] * v0 + k[A_K + 3] * v1 + k[A_K + 4] * v2 + k[A_K + 8] * v3
                    + k[A_K + 9] * v4)
        b2 += h2 * (k[A_K + 2] * v0 + k[A_K + 4] * v1 + k[A_K + 5] * v2 + k[A_K + 10] * v3
                    + k[A_K + 11] * v4)
        b3 += h2 * (k[A_K + 6] * v0 + k[A_K + 8] * v1 + k[A_K + 10] * v2 + k[A_K + 12] * v3
                    + k[A_K + 13] * v4)
        b4 += h2 * (k[A_K + 7] * v0 + k[A_K + 9] * v1 + k[A_K + 11] * v2 + k[A_K + 13] * v3
                    + k[A_K + 14] * v4)
    l00 = math.sqrt(a00)
    l10 = a01 / l00
    l20 = a02 / l00
    l30 = a03 / l00
    l40 = a04 / l00
    l11 = math.sqrt(a11 - l10 * l10)
    l21 = (a12 - l20 * l10) / l11
    l31 = (a13 - l30 * l10) / l11
    l41 = (a14 - l40 * l10) / l11
    l22 = math.sqrt(a22 - l20 * l20 - l21 * l21)
    l32 = (a23 - l30 * l20 - l31 * l21) / l22
    l42 = (a24 - l40 * l20 - l41 * l21) / l22
    l33 = math.sqrt(a33 - l30 * l30 - l31 * l31 - l32 * l32)
    l43 = (a34 - l40 * l30 - l41 * l31 - l42 * l32) / l33
    l44 = math.sqrt(a44 - l40 * l40 - l41 * l41 - l42 * l42 - l43 * l43)
    y0 = b0 / l00  # forward, L y = b
    y1 = (b1 - l10 * y0) / l11
    y2 = (b2 - l20 * y0 - l21 * y1) / l22
    y3 = (b3 - l30 * y0 - l31 * y1 - l32 * y2) / l33
    y4 = (b4 - l40 * y0 - l41 * y1 - l42 * y2 - l43 * y3) / l44
    x4 = y4 / l44  # backward, Lᵀ v⁺ = y
    x3 = (y3 - l43 * x4) / l33
    x2 = (y2 - l32 * x3 - l42 * x4) / l22
    x1 = (y1 - l21 * x2 - l31 * x3 - l41 * x4) / l11
    x0 = (y0 - l10 * x1 - l20 * x2 - l30 * x3 - l40 * x4) / l00
    v[0] = x0
    v[1] = x1
    v[2] = x2
    v[3] = x3
    v[4] = x4
    dissipated = (c[A_C] * x0 * x0 + 2.0 * c[A_C + 1] * x0 * x1 + 2.0 * c[A_C + 2] * x0 * x2
                  + c[A_C + 3] * x1 * x1 + 2.0 * c[A_C + 4] * x1 * x2 + c[A_C + 5] * x2 * x2
                  + 2.0 * (c[A_C + 6] * x0 * x3 + c[A_C + 7] * x0 * x4 + c[A_C + 8] * x1 * x3
                           + c[A_C + 9] * x1 * x4 + c[A_C + 10] * x2 * x3 + c[A_C + 11] * x2 * x4
                           + c[A_C + 13] * x3 * x4)
                  + c[A_C + 12] * x3 * x3 + c[A_C + 14] * x4 * x4)
    return hk * dissipated


@njit(cache=True)
def _step_level(p, q, v, vert, dmax, rim_contact, h_medium, h_coarse):
    """Which step is safe after this one: 0 fine, 1 medium (explicit), 2 coarse (modified
    mass); Eq. R34 of docs/theory/rigid-body.md. Medium needs no rim contact, the dish
    contacts below twice their static penetration and every vertex farther from its rims than
    it travels in four medium steps.
    Coarse needs the same for four coarse steps, and every vertex either seated (δ_s/4 … 2δ_s,
    so that the stiffness in the modified mass, taken at the step's start, is at least a
    quarter of the true one; see ``BETA``) or off its dish by more than it can close in two
    coarse steps (so that no contact starts within a step that treats it explicitly)."""
    if rim_contact or dmax > p[P_DFAR]:
        return 0
    speed = abs(v[0]) + abs(v[1]) + abs(v[2]) * (p[P_HALF_B] + p[P_HALF_HE])
    room = p[P_RIN] - 0.005
    level = 2
    for j in range(4):
        x = abs(vert[j, 0] - q[3] if j >= 2 else vert[j, 0])
        travel = 4.0 * (speed + (abs(v[3]) if j >= 2 else 0.0))
        if x > room - travel * h_medium:
            return 0
        if x > room - travel * h_coarse:
            level = 1
        d = vert[j, 2]
        if level == 2 and d < p[P_DNEAR]:
            closing = speed + (abs(v[3]) + abs(v[4]) if j >= 2 else 0.0)
            if -d < 2.0 * h_coarse * closing + 1e-6:
                level = 1
    return level


@njit(cache=True)
def _kinetic(p, v):
    """Kinetic energy of the slider and the top plate [J] (Eq. R48)."""
    ms, js, mt = p[P_MS], p[P_JS], p[P_M]
    return 0.5 * (ms * (v[0] ** 2 + v[1] ** 2) + js * v[2] ** 2 + mt * (v[3] ** 2 + v[4] ** 2))


@njit(cache=True)
def _gravity(p, q, zs0, zt0):
    """Gravity's potential energy [J] from the start (the gravity terms of Eq. R49)."""
    ms, mt, g = p[P_MS], p[P_M], p[P_G]
    return ms * g * (q[1] - zs0) + mt * g * (q[4] - zt0)


@njit(cache=True)
def _record(hist, n, p, q, v, zs0, zt0, e_pot, shear, rimf, rim_set, e_in, e_fric, e_imp,
            e_plas):
    """Write history row ``n`` (the channels H_*) and return the kinetic energy [J]."""
    e_kin = _kinetic(p, v)
    hist[n, H_XT] = q[3]
    hist[n, H_ZT] = q[4] - zt0
    hist[n, H_XS] = q[0]
    hist[n, H_ZS] = q[1] - zs0
    hist[n, H_TH] = q[2]
    hist[n, H_VT] = v[3]
    hist[n, H_SHEAR] = shear
    hist[n, H_RIMF] = rimf[0] + rimf[1] + rimf[2] + rimf[3]
    hist[n, H_EIN] = e_in
    hist[n, H_EKIN] = e_kin
    hist[n, H_EPOT] = e_pot
    hist[n, H_EFRIC] = e_fric
    hist[n, H_EIMP] = e_imp
    hist[n, H_EPLAS] = e_plas
    hist[n, H_SET] = max(max(rim_set[0], rim_set[1]), max(rim_set[2], rim_set[3]))
    return e_kin


@njit(cache=True)
def _track_impacts(p, t, v, rimf, in_contact, last_contact, open_event, events, n_events,
                   max_rimf):
    """Rim impact events after a step ending at ``t`` [s]: a contact that begins more than
    P_MERGE after the rim's last one opens an event (Eq. R52, its velocity the top plate's,
    Eq. R53), a continuing one raises its peak force and duration. Return the number of
    events, whether any rim is touched, and the largest rim force so far [N]."""
    rim_contact = False
    for r in range(N_RIMS):
        f = rimf[r]
        if f > 0.0:
            rim_contact = True
            if not in_contact[r]:
                in_contact[r] = True
                if t - last_contact[r] > p[P_MERGE] and n_events < events.shape[0]:
                    events[n_events, 0] = t
                    events[n_events, 1] = r
                    events[n_events, 2] = v[3]
                    events[n_events, 3] = 0.0
                    events[n_events, 4] = 0.0
                    open_event[r] = n_events
                    n_events += 1
            e = open_event[r]
            if e >= 0:
                events[e, 3] = max(events[e, 3], f)
                events[e, 4] = t - events[e, 0]
            last_contact[r] = t
            max_rimf = max(max_rimf, f)
        else:
            in_contact[r] = False
    return n_events, rim_contact, max_rimf


@njit(cache=True)
def _numerical_failure(p, q, v, dmax, hs):
    """The code of a numerical failure after a step of ``hs`` [s] (docs/theory/rigid-body.md,
    "Failure"): a coordinate not finite, a penetration past P_DMAX, a jump of a quarter of
    it in one step; 0 if none."""
    for i in range(5):
        if not math.isfinite(q[i]) or not math.isfinite(v[i]):
            return NUM_NAN
    if dmax > p[P_DMAX]:
        return NUM_PENETRATION
    if _step_jump(p, v, hs) > 0.25 * p[P_DMAX]:
        return NUM_JUMP
    return 0


@njit(cache=True)
def _yielding_limit_states(p, q, vert, rim_set, law, t, t_hinge, t_rupture, t_lost, lost):
    """The yielding rims' limit states reached by time ``t`` [s] (Eqs. R62–R64): the first
    hinge and rupture of a rim's plastic set, and the loss of containment (a torn rim off, or
    the slider past a rim); return the updated (t_hinge, t_rupture, t_lost, lost)."""
    most = max(max(rim_set[0], rim_set[1]), max(rim_set[2], rim_set[3]))
    if t_hinge < 0.0 and most >= p[P_UP_HINGE]:
        t_hinge = t
    if t_rupture < 0.0 and most >= p[P_UP_RUPTURE]:
        t_rupture = t
    beyond = abs(q[2]) > 0.25 * math.pi  # a vertex past an unbent face, or tipped
    for j in range(4):
        beyond = beyond or abs(vert[j, 0] - (q[3] if j >= 2 else 0.0)) > p[P_RIN]
    if t_lost < 0.0 and most >= p[P_UP_OFF]:  # a torn rim came off (Eq. R64)
        lost, t_lost = FAIL_TORN_OFF, t
    if t_lost < 0.0 and beyond:  # containment can only be lost then (Eq. R63)
        lost = _containment_yielding(p, q, vert, rim_set, law)
        if lost != 0:
            t_lost = t
    return t_hinge, t_rupture, t_lost, lost


@njit(cache=True)
def _fine_steps(level, medium, coarse, room):
    """Fine steps in the next step at step level ``level`` (0 near a rim, 1 medium, 2 coarse:
    :func:`_step_level`), no more than ``room`` (the fine steps left to the next input
    sample)."""
    if level == 2 and coarse <= room:
        return coarse
    if level >= 1 and medium <= room:
        return medium
    return 1


@njit(cache=True)
def _ground_at(ag_in, n_sub, k):
    """Ground acceleration [m/s²] at fine step ``k``: linear between the input's samples
    (every ``n_sub`` fine steps), zero after its end."""
    k_in = k // n_sub
    frac = (k % n_sub) / n_sub
    if k_in < ag_in.shape[0] - 1:
        return ag_in[k_in] + frac * (ag_in[k_in + 1] - ag_in[k_in])
    if k_in == ag_in.shape[0] - 1 and frac == 0.0:
        return ag_in[k_in]
    return 0.0


@njit(cache=True)
def _yielding_failure(criterion, t_hinge, t_rupture, t_lost, lost):
    """The failure code of yielding rims under ``criterion`` (Eq. R62): the loss of
    containment whatever the criterion, else the hinge or the rupture it asks for; 0 if
    none yet."""
    if t_lost >= 0.0:
        return lost
    if criterion == CRIT_HINGE and t_hinge >= 0.0:
        return FAIL_HINGE
    if criterion == CRIT_RUPTURE and t_rupture >= 0.0:
        return FAIL_RUPTURE
    return 0


@njit(cache=True)
def _check_failure(p, q, v, vert, dmax, hs, t, yielding, criterion, stop_at_failure, rim_set,
                   law, status, fail_code, fail_time, t_hinge, t_rupture, t_lost, lost):
    """After a step ending at t [s]: numerical failure (docs/theory/rigid-body.md, "Failure"),
    then physical failure (Eqs. R42–R45) or, with yielding rims, the limit states recorded as
    far as the run goes and the chosen one's failure. Returns the updated (status, fail_code,
    fail_time, t_hinge, t_rupture, t_lost, lost)."""
    numerical = _numerical_failure(p, q, v, dmax, hs)
    if numerical != 0:
        status, fail_code, fail_time = STATUS_NUMERICAL, numerical, t
    elif fail_code == 0 and not yielding:
        code = _failure(p, q, vert)
        if code != 0:
            fail_code, fail_time = code, t
            if stop_at_failure:
                status = STATUS_FAILED
    elif yielding:
        t_hinge, t_rupture, t_lost, lost = _yielding_limit_states(
            p, q, vert, rim_set, law, t, t_hinge, t_rupture, t_lost, lost)
        if fail_code == 0:
            code = _yielding_failure(criterion, t_hinge, t_rupture, t_lost, lost)
            if code != 0:
                fail_code, fail_time = code, t
                if stop_at_failure:
                    status = STATUS_FAILED
    return status, fail_code, fail_time, t_hinge, t_rupture, t_lost, lost


@njit(cache=True)
def _summarize(summary, status, fail_time, fail_code, n_events, max_uplift, max_rot, max_pen,
               max_rimf, e_in, e_kin, e_pot, e_fric, e_imp, e_plas, n_rec, step, taken,
               t_hinge, t_rupture, t_lost, rim_set):
    """Write a run's end state into ``summary`` (N_SUMMARY, slots S_*): status and failure,
    impacts, extremes, the energies of Eqs. R46–R51 [J], counts, the limit-state times [s] and
    the rims' plastic sets [m]."""
    summary[S_STATUS] = status
    summary[S_FAIL_TIME] = fail_time
    summary[S_FAIL_CODE] = fail_code
    summary[S_N_EVENTS] = n_events
    summary[S_MAX_UPLIFT] = max_uplift
    summary[S_MAX_ROT] = max_rot
    summary[S_MAX_PEN] = max_pen
    summary[S_MAX_RIMF] = max_rimf
    summary[S_EIN] = e_in
    summary[S_EKIN] = e_kin
    summary[S_EPOT] = e_pot
    summary[S_EFRIC] = e_fric
    summary[S_EIMP] = e_imp
    summary[S_N_REC] = n_rec
    summary[S_STEPS] = step
    summary[S_TAKEN] = taken
    summary[S_T_HINGE] = t_hinge
    summary[S_T_RUPTURE] = t_rupture
    summary[S_T_CONTAINMENT] = t_lost
    summary[S_EPLAS] = e_plas
    for r in range(N_RIMS):
        summary[S_SET + r] = rim_set[r]


@njit(cache=True)
def integrate(p, q0, ag_in, n_sub, h, n_steps, medium, coarse, quiet_energy, stop_at_failure,
              hist, events, summary, law):
    """Advance the model over ``n_steps`` fine steps of size h.

    ``ag_in`` is sampled every ``n_sub`` fine steps and interpolated linearly in between
    (zero after its end). Away from the rims (see :func:`_step_level`) the kernel takes
    ``medium`` fine steps at once (plain velocity Verlet, below the stability limit of the
    contact modes) or, with every contact settled, ``coarse`` fine steps with the contact
    stiffness in a modified mass (see :func:`_kick`); never across a sample time. After the
    input has ended, the
    run stops once the mechanical energy is below ``quiet_energy`` [J] (0: never), when no
    rim can be reached any more (Eq. R41). Energies: Eqs. R46–R51; impacts and uplift:
    Eqs. R52–R54. Histories are written at the input's sampling into ``hist``
    (n_rec × N_CHANNELS), rim impact events into ``events`` (max_events × EVENT_FIELDS);
    ``summary`` (N_SUMMARY) gets the rest. ``law``: the yielding rims' backbone (rows of
    plastic set [m], force [N]; unused with rigid rims).
    """
    q = q0.copy()
    v = np.zeros(5)
    Z = np.zeros(N_SLOTS)
    gen = np.zeros(5)
    acc = np.zeros(N_ACC)
    rimf = np.zeros(N_RIMS)
    sep = np.zeros(2)
    vert = np.zeros((4, 3))
    in_contact = np.zeros(N_RIMS, dtype=np.bool_)
    last_contact = np.full(N_RIMS, -1e9)
    open_event = np.full(N_RIMS, -1)
    rim_set = np.zeros(N_RIMS)
    buf = np.zeros((N_RIMS, B_CONTACTS, B_FIELDS))
    count = np.zeros(N_RIMS, dtype=np.int64)
    yielding = p[P_YIELDING] != 0.0
    criterion = int(p[P_CRITERION])
    t_hinge = -1.0
    t_rupture = -1.0
    t_lost = -1.0
    lost = 0
    e_plas = 0.0
    n_in = ag_in.shape[0]
    input_steps = (n_in - 1) * n_sub
    mt, g = p[P_M], p[P_G]

    dmax = forces(p, q, v, Z, 0.0, gen, acc, rimf, sep, vert, False, rim_set, law, buf, count)
    e_el0 = acc[A_EEL]
    zs0, zt0 = q0[1], q0[4]
    e_in = 0.0
    e_scale = mt * g * 1e-3  # floor: the work of lifting the supported mass by 1 mm
    e_fric = 0.0
    e_imp = 0.0
    max_uplift = 0.0
    max_rot = 0.0
    max_pen = dmax
    max_rimf = 0.0
    n_events = 0
    n_rec = 0
    status = STATUS_OK
    fail_code = 0
    fail_time = -1.0
    ag_old = ag_in[0]
    shear = acc[A_BFX]
    level = 0
    step = 0
    taken = 0
    while True:
        t = step * h
        if step % n_sub == 0 and n_rec < hist.shape[0]:
            e_grav = _gravity(p, q, zs0, zt0)
            e_pot = e_grav + acc[A_EEL] - e_el0
            e_kin = _record(hist, n_rec, p, q, v, zs0, zt0, e_pot, shear, rimf, rim_set, e_in,
                            e_fric, e_imp, e_plas)
            n_rec += 1
            # an explicit scheme past its stability limit creates energy: report, not hide
            # (Eq. R46)
            e_scale = max(e_scale, abs(e_in))
            residual = e_in - (e_kin + e_pot + e_fric + e_imp + e_plas)
            if status == STATUS_OK and abs(residual) > ENERGY_TOLERANCE * e_scale:
                status, fail_code, fail_time = STATUS_NUMERICAL, NUM_ENERGY, t
            if step >= input_steps and e_kin + e_grav < quiet_energy and fail_code == 0:
                break
        if step >= n_steps or status != STATUS_OK:
            break
        m = _fine_steps(level, medium, coarse, min(n_sub - step % n_sub, n_steps - step))
        implicit = m == coarse and coarse > medium
        hs = m * h
        if not implicit:  # plain velocity Verlet: drop a coarse step's stiffness
            acc[A_KSUM] = 0.0
        elif acc[A_KSUM] == 0.0:  # first coarse step: its first kick needs the stiffness too
            forces(p, q, v, Z, 0.0, gen, acc, rimf, sep, vert, True, rim_set, law, buf, count)
        ag_new = _ground_at(ag_in, n_sub, step + m)  # at the end of the step
        # kick – drift (Eq. R30)
        e_imp += _kick(p, v, gen, ag_old, acc, 0.5 * hs)
        for i in range(5):
            q[i] += hs * v[i]
        # input work of the inertial loads over the step, half-step velocities (Eq. R47)
        e_in -= 0.5 * (ag_old + ag_new) * (p[P_MS] * v[0] + mt * v[3]) * hs
        dmax = forces(p, q, v, Z, hs, gen, acc, rimf, sep, vert, implicit, rim_set, law, buf,
                      count)
        e_fric += acc[A_PFRIC] * hs
        e_plas += acc[A_PLAS]
        shear = acc[A_BFX]
        # kick
        e_imp += _kick(p, v, gen, ag_new, acc, 0.5 * hs)
        ag_old = ag_new
        step += m
        taken += 1
        t = step * h
        # outputs
        max_pen = max(max_pen, dmax)
        max_rot = max(max_rot, abs(q[2]))
        for k in range(2):
            if sep[k] < 1e8:  # both vertices over the plate
                max_uplift = max(max_uplift, sep[k])
        n_events, rim_contact, max_rimf = _track_impacts(
            p, t, v, rimf, in_contact, last_contact, open_event, events, n_events, max_rimf)
        level = _step_level(p, q, v, vert, dmax, rim_contact, medium * h, coarse * h)
        status, fail_code, fail_time, t_hinge, t_rupture, t_lost, lost = _check_failure(
            p, q, v, vert, dmax, hs, t, yielding, criterion, stop_at_failure, rim_set, law,
            status, fail_code, fail_time, t_hinge, t_rupture, t_lost, lost)
    if status == STATUS_OK and fail_code != 0:
        status = STATUS_FAILED
    _summarize(summary, status, fail_time, fail_code, n_events, max_uplift, max_rot, max_pen,
               max_rimf, e_in, _kinetic(p, v), _gravity(p, q, zs0, zt0) + acc[A_EEL] - e_el0,
               e_fric, e_imp, e_plas, n_rec, step, taken, t_hinge, t_rupture, t_lost, rim_set)
