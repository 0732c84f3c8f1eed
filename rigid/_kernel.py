"""Numba core of the rigid-body DFP model (private; use :func:`rigid.simulate`).

Frame: X horizontal (direction of shaking), Z up, coordinates relative to the bottom plate,
which follows the ground; every free body carries the inertial load −m·a_g in X.
Bodies: slider (x_S, z_S, θ) and top plate with the supported mass (x_T, z_T), paper §2.
Contacts (12 slots, each with its own hysteretic friction state):

* 0–3   slider vertices on the dish of their plate (bottom-left, bottom-right, top-left,
        top-right vertex), reference rigid_model.md §6.3;
* 4–7   the same vertices against the restraining rim they face (inner face or rim top);
* 8–11  the rims' inner corners (bottom −x, bottom +x, top −x, top +x) against the slider's
        sides and faces, so that a tilted slider cannot pass through a rim corner.

Normal force: Hertz with the Jankowski nonlinear damper, F = kδ^1.5 + cδ̇ on approach and kδ^1.5
on restitution, c = 2ξ√(k√δ·m_eff) (paper Eqs. 1–4). Friction: Coulomb, μF_n·Z, with Z a
hysteretic state per contact: an elastic–perfectly-plastic tangential spring of stiffness
μF_n/Y (the sharp limit of the Bouc–Wen law), updated by its exact return map.

Time stepping: velocity Verlet (kick–drift–kick). The contact dampers are implicit in the
kicks (backward Euler on the 5 × 5 system M + h/2·C), because c/m_s reaches 1e5–1e6 1/s when
the supported mass sets c; the friction state advances on the half-step slip. Far from the
rims, with every contact near its static load, the step is a few times longer (the stiffest
mode there, slider rocking on its vertices at ~1.7e4 rad/s at 60 MPa, allows 1.1e-4 s); near
and at the rims the fine step resolves the impacts. The hot loop allocates nothing.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# parameter vector layout ------------------------------------------------------------------
P_R, P_HALF_B, P_HS, P_HALF_HE, P_RIN, P_TR, P_ZTOP = 0, 1, 2, 3, 4, 5, 6
P_K, P_XI, P_MU, P_MU_RIM, P_Y, P_MS, P_JS, P_M, P_G = 7, 8, 9, 10, 11, 12, 13, 14, 15
P_MEFF_BOT, P_MEFF_TOP, P_DMAX, P_MERGE, P_DFAR = 16, 17, 18, 19, 20
N_PARAMS = 21

# history channels ----------------------------------------------------------------------------
H_XT, H_ZT, H_XS, H_ZS, H_TH, H_VT, H_SHEAR, H_RIMF = 0, 1, 2, 3, 4, 5, 6, 7
H_EIN, H_EKIN, H_EPOT, H_EFRIC, H_EIMP = 8, 9, 10, 11, 12
N_CHANNELS = 13

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
N_SUMMARY = 15

# status and failure codes --------------------------------------------------------------------
STATUS_OK, STATUS_FAILED, STATUS_NUMERICAL = 0, 1, 2
FAIL_BOTTOM_RIM, FAIL_TOP_RIM, FAIL_CENTROID, FAIL_OVERTURN = 1, 2, 3, 4
NUM_NAN, NUM_PENETRATION, NUM_ENERGY = 10, 11, 12
#: energy residual, relative to the input energy, beyond which the run counts as unstable
ENERGY_TOLERANCE = 0.05

N_SLOTS = 12
# work vector of the force routine: energies and forces, then the damping matrix C
A_EEL, A_CSUM, A_PFRIC, A_BFX, A_C = 0, 1, 2, 3, 5
#: (row, column) of each stored entry of the upper triangle of C
C_INDEX = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2), (0, 3), (0, 4), (1, 3), (1, 4),
           (2, 3), (2, 4), (3, 3), (3, 4), (4, 4))
N_ACC = A_C + 15
N_RIMS = 4
EVENT_FIELDS = 5  # time, rim, top-plate velocity, peak rim force, duration


@njit(cache=True)
def friction_state_update(z0, slip_over_y):
    """Hysteretic friction state after a slip (in units of Y): an elastic–perfectly-plastic
    tangential spring, the η → ∞ limit of the Bouc–Wen law (Cundall & Strack 1979).

    Z = F_t/(μF_n) grows by slip/Y while sticking and saturates at ±1 while sliding; the
    update is the exact return map, stable at any step.
    """
    return min(1.0, max(-1.0, z0 + slip_over_y))


@njit(cache=True)
def damper_coefficient(sqrt_delta, k, xi, meff):
    """Damping coefficient c = 2ξ√(k√δ·m_eff) [N·s/m], paper Eq. 3."""
    return 2.0 * xi * math.sqrt(k * sqrt_delta * meff)


@njit(cache=True)
def hertz_damped_force(delta, delta_rate, k, xi, meff):
    """Normal contact force of paper Eqs. 1–3 as (elastic, damper) parts [N], for δ > 0.

    Elastic kδ^1.5 always; damper cδ̇ only on approach (δ̇ > 0), so the force is never
    tensile. The kernel applies the same law with the damper implicit in time.
    """
    sd = math.sqrt(delta)
    if delta_rate > 0.0:
        return k * delta * sd, damper_coefficient(sd, k, xi, meff) * delta_rate
    return k * delta * sd, 0.0


@njit(cache=True, inline="always")
def _add_damper(acc, c, g0, g1, g2, top):
    """Add c·GᵀG to the damping matrix kept in acc[A_C:] (upper triangle, order of
    ``C_INDEX``); G = [n_x, n_z, r×n, −n_x, −n_z], the last two only for contacts with the
    top plate, so that G·v is minus the approach rate. (Kept in ``acc``: a separate array
    made the force routine 2× slower.)"""
    a0 = c * g0
    a1 = c * g1
    a2 = c * g2
    acc[A_C] += a0 * g0
    acc[A_C + 1] += a0 * g1
    acc[A_C + 2] += a0 * g2
    acc[A_C + 3] += a1 * g1
    acc[A_C + 4] += a1 * g2
    acc[A_C + 5] += a2 * g2
    if top:
        acc[A_C + 6] -= a0 * g0
        acc[A_C + 7] -= a0 * g1
        acc[A_C + 8] -= a1 * g0
        acc[A_C + 9] -= a1 * g1
        acc[A_C + 10] -= a2 * g0
        acc[A_C + 11] -= a2 * g1
        acc[A_C + 12] += a0 * g0
        acc[A_C + 13] += a0 * g1
        acc[A_C + 14] += a1 * g1


@njit(cache=True, inline="always")
def _apply(slot, delta, nx, nz, px, pz, top, meff, mu, p, q, v, h, Z, gen, acc):
    """Contact force of one slot on the slider at point (px, pz) with normal (nx, nz).

    ``top`` is True when the other body is the top plate (moving with v[3], v[4]), False for
    the bottom plate (fixed in this frame). Adds the elastic and friction forces into
    ``gen``; into ``acc`` the elastic energy, the friction power, the bottom plate's Fx and,
    on approach, the damper c·GᵀG (implicit in the kicks). Returns the elastic normal force.
    """
    rx = px - q[0]
    rz = pz - q[1]
    # relative velocity of the slider's material point with respect to the plate
    wx = v[0] - v[2] * rz - (v[3] if top else 0.0)
    wz = v[1] + v[2] * rx - (v[4] if top else 0.0)
    ddot = -(wx * nx + wz * nz)
    vt = -wx * nz + wz * nx  # tangent t = (−n_z, n_x)
    sd = math.sqrt(delta)
    f_el = p[P_K] * delta * sd  # paper Eq. 2 (and the elastic part of Eq. 1)
    if ddot > 0.0:  # approach: the damper of Eq. 1 with c from Eq. 3
        c = damper_coefficient(sd, p[P_K], p[P_XI], meff)
        _add_damper(acc, c, nx, nz, rx * nz - rz * nx, top)
        acc[A_CSUM] += c
    # Coulomb friction on the elastic normal force (the damper's part is transient)
    z = friction_state_update(Z[slot], vt * h / p[P_Y])
    Z[slot] = z
    ft = -mu * f_el * z
    fx = f_el * nx - ft * nz
    fz = f_el * nz + ft * nx
    gen[0] += fx
    gen[1] += fz
    gen[2] += rx * fz - rz * fx
    if top:
        gen[3] -= fx
        gen[4] -= fz
    else:
        acc[A_BFX] -= fx
    acc[A_EEL] += f_el * delta / 2.5
    acc[A_PFRIC] += -ft * vt
    return f_el


@njit(cache=True)
def forces(p, q, v, Z, h, gen, acc, rimf, sep, vert):
    """Generalized contact forces at configuration q with velocities v.

    Advances the friction states Z over a slip of v_t·h (h = 0 leaves them). Fills:
    gen[5] slider Fx, Fz, moment and top-plate Fx, Fz [N, N·m]; acc as in :func:`_apply`;
    rimf[4] total normal force on each rim [N]; sep[2] the smaller vertex separation from the
    bottom and from the top dish [m]. Returns the largest penetration [m].
    """
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
        # vertex on the dish (slot j); the dish continues under the rim root
        dx = cx - px
        dz = cz - pz
        d = math.sqrt(dx * dx + dz * dz)
        delta = d - R
        xl = px - cx
        if abs(xl) <= rin + tr:
            sep[1 if is_top else 0] = min(sep[1 if is_top else 0], -delta)
            if delta > 0.0:
                dmax = max(dmax, delta)
                _apply(j, delta, dx / d, dz / d, px, pz, is_top, meff, p[P_MU], p, q, v, h, Z,
                       gen, acc)
            else:
                Z[j] = 0.0
        else:
            Z[j] = 0.0
            if is_top:
                off_top = True
            else:
                off_bottom = True
        # vertex against the rim it faces (slot 4 + j): inner face or rim top/bottom face
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
                                h, Z, gen, acc)
        else:
            Z[4 + j] = 0.0
    if off_bottom:
        sep[0] = 1e9
    if off_top:
        sep[1] = 1e9
    # rim corners against the slider's section (slots 8–11)
    for r in range(N_RIMS):
        is_top = r >= 2
        side = 1.0 if (r % 2 == 1) else -1.0
        if is_top:
            kx, kz = xt + side * rin, zt + hs - ztop
        else:
            kx, kz = side * rin, ztop
        dx = kx - xs
        dz = kz - zs
        qx = c * dx + s * dz  # corner in the slider's body frame
        qz = -s * dx + c * dz
        dside = hb - abs(qx)
        if dside <= 0.0 or abs(qx) > hb or abs(qz) > hs:
            Z[8 + r] = 0.0
            continue
        # depth below each face of the section: side (flat), bottom and top (spherical)
        db = R - math.sqrt(qx * qx + (qz + hs / 2 - R) ** 2)
        dt_ = R - math.sqrt(qx * qx + (qz - hs / 2 + R) ** 2)
        if db <= 0.0 or dt_ <= 0.0:
            Z[8 + r] = 0.0
            continue
        if dside <= db and dside <= dt_:
            delta, nbx, nbz = dside, (1.0 if qx > 0 else -1.0), 0.0
        elif db <= dt_:
            ln = math.sqrt(qx * qx + (qz + hs / 2 - R) ** 2)
            delta, nbx, nbz = db, qx / ln, (qz + hs / 2 - R) / ln
        else:
            ln = math.sqrt(qx * qx + (qz - hs / 2 + R) ** 2)
            delta, nbx, nbz = dt_, qx / ln, (qz - hs / 2 + R) / ln
        # outward body normal to global; the force on the slider points inward (−n_out)
        nx = -(c * nbx - s * nbz)
        nz = -(s * nbx + c * nbz)
        meff = p[P_MEFF_TOP] if is_top else p[P_MEFF_BOT]
        dmax = max(dmax, delta)
        rimf[r] += _apply(8 + r, delta, nx, nz, kx, kz, is_top, meff, p[P_MU_RIM], p, q, v, h,
                          Z, gen, acc)
    return dmax


@njit(cache=True)
def _failure(p, q, vert):
    """Physical failure code (0: none): the slider has escaped over a rim or overturned.

    Only bottom vertices are tested against bottom rims and top vertices against top rims
    (a tilted slider's upper corners legitimately overhang the bottom rim; reference §9).
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
def _kick(p, v, gen, ag, acc, hk, work):
    """Half kick of velocity Verlet over hk, with the contact dampers backward-Euler:
    (M + hk·C) v⁺ = M v + hk·F. Implicit damping keeps the step free of the damper's limit
    (c/m_s reaches 1e5–1e6 1/s when the supported mass sets c). Returns the energy the
    dampers dissipated, hk·v⁺ᵀCv⁺ [J]."""
    ms, js, mt = p[P_MS], p[P_JS], p[P_M]
    f0 = gen[0] - ms * ag
    f1 = gen[1] - ms * p[P_G]
    f3 = gen[3] - mt * ag
    f4 = gen[4] - mt * p[P_G]
    if acc[A_CSUM] == 0.0:  # no contact approaching
        v[0] += hk * f0 / ms
        v[1] += hk * f1 / ms
        v[2] += hk * gen[2] / js
        v[3] += hk * f3 / mt
        v[4] += hk * f4 / mt
        return 0.0
    # M + hk·C from the upper triangle of C, Cholesky factor in the lower triangle of work
    for k in range(15):
        i, j = C_INDEX[k]
        work[j, i] = hk * acc[A_C + k]
    work[0, 0] += ms
    work[1, 1] += ms
    work[2, 2] += js
    work[3, 3] += mt
    work[4, 4] += mt
    work[0, 5] = ms * v[0] + hk * f0
    work[1, 5] = ms * v[1] + hk * f1
    work[2, 5] = js * v[2] + hk * gen[2]
    work[3, 5] = mt * v[3] + hk * f3
    work[4, 5] = mt * v[4] + hk * f4
    for j in range(5):
        d = work[j, j]
        for k in range(j):
            d -= work[j, k] * work[j, k]
        d = math.sqrt(d)
        work[j, j] = d
        for i in range(j + 1, 5):
            s = work[i, j]
            for k in range(j):
                s -= work[i, k] * work[j, k]
            work[i, j] = s / d
    for i in range(5):  # forward, L y = b
        s = work[i, 5]
        for k in range(i):
            s -= work[i, k] * work[k, 5]
        work[i, 5] = s / work[i, i]
    for i in range(4, -1, -1):  # backward, Lᵀ x = y
        s = work[i, 5]
        for k in range(i + 1, 5):
            s -= work[k, i] * v[k]
        v[i] = s / work[i, i]
    dissipated = 0.0
    for k in range(15):
        i, j = C_INDEX[k]
        dissipated += (1.0 if i == j else 2.0) * acc[A_C + k] * v[i] * v[j]
    return hk * dissipated


@njit(cache=True)
def _far_from_rims(p, q, v, vert, dmax, rim_contact, h_coarse):
    """True where the coarse step is safe: no rim contact, contacts near their static
    penetration, and every vertex farther from its rims than it can travel in a few steps."""
    if rim_contact or dmax > p[P_DFAR]:
        return False
    reach = p[P_RIN] - 0.005 - 4.0 * h_coarse * (abs(v[0]) + abs(v[3]) + abs(v[2]) * p[P_HALF_B])
    for j in range(4):
        x = vert[j, 0] - q[3] if j >= 2 else vert[j, 0]
        if abs(x) > reach:
            return False
    return True


@njit(cache=True)
def integrate(p, q0, ag_in, n_sub, h, n_steps, coarse, quiet_energy, stop_at_failure,
              hist, events, summary):
    """Advance the model over ``n_steps`` fine steps of size h.

    ``ag_in`` is sampled every ``n_sub`` fine steps and interpolated linearly in between
    (zero after its end). Away from the rims (see :func:`_far_from_rims`) the kernel takes
    ``coarse`` fine steps at once, never across a sample time. After the input has ended, the
    run stops once the mechanical energy is below ``quiet_energy`` [J] (0: never), when no
    rim can be reached any more. Histories are written at the input's sampling into ``hist``
    (n_rec × N_CHANNELS), rim impact events into ``events`` (max_events × EVENT_FIELDS);
    ``summary`` (N_SUMMARY) gets the rest.
    """
    q = q0.copy()
    v = np.zeros(5)
    Z = np.zeros(N_SLOTS)
    gen = np.zeros(5)
    acc = np.zeros(N_ACC)
    rimf = np.zeros(N_RIMS)
    sep = np.zeros(2)
    vert = np.zeros((4, 2))
    work = np.zeros((5, 6))
    in_contact = np.zeros(N_RIMS, dtype=np.bool_)
    last_contact = np.full(N_RIMS, -1e9)
    open_event = np.full(N_RIMS, -1)
    n_in = ag_in.shape[0]
    input_steps = (n_in - 1) * n_sub
    max_events = events.shape[0]
    ms, js, mt, g = p[P_MS], p[P_JS], p[P_M], p[P_G]

    dmax = forces(p, q, v, Z, 0.0, gen, acc, rimf, sep, vert)
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
    far = False
    step = 0
    while True:
        t = step * h
        if step % n_sub == 0 and n_rec < hist.shape[0]:
            e_kin = 0.5 * (ms * (v[0] ** 2 + v[1] ** 2) + js * v[2] ** 2
                           + mt * (v[3] ** 2 + v[4] ** 2))
            e_grav = ms * g * (q[1] - zs0) + mt * g * (q[4] - zt0)
            e_pot = e_grav + acc[A_EEL] - e_el0
            hist[n_rec, H_XT] = q[3]
            hist[n_rec, H_ZT] = q[4] - zt0
            hist[n_rec, H_XS] = q[0]
            hist[n_rec, H_ZS] = q[1] - zs0
            hist[n_rec, H_TH] = q[2]
            hist[n_rec, H_VT] = v[3]
            hist[n_rec, H_SHEAR] = shear
            hist[n_rec, H_RIMF] = rimf[0] + rimf[1] + rimf[2] + rimf[3]
            hist[n_rec, H_EIN] = e_in
            hist[n_rec, H_EKIN] = e_kin
            hist[n_rec, H_EPOT] = e_pot
            hist[n_rec, H_EFRIC] = e_fric
            hist[n_rec, H_EIMP] = e_imp
            n_rec += 1
            # an explicit scheme past its stability limit creates energy: report, not hide
            e_scale = max(e_scale, abs(e_in))
            residual = e_in - (e_kin + e_pot + e_fric + e_imp)
            if status == STATUS_OK and abs(residual) > ENERGY_TOLERANCE * e_scale:
                status, fail_code, fail_time = STATUS_NUMERICAL, NUM_ENERGY, t
            if step >= input_steps and e_kin + e_grav < quiet_energy and fail_code == 0:
                break
        if step >= n_steps or status != STATUS_OK:
            break
        m = 1
        if far and coarse > 1 and step % n_sub + coarse <= n_sub and step + coarse <= n_steps:
            m = coarse
        hs = m * h
        # ground acceleration at the end of the step, linear between input samples
        k_in = (step + m) // n_sub
        frac = ((step + m) % n_sub) / n_sub
        ag_new = 0.0
        if k_in < n_in - 1:
            ag_new = ag_in[k_in] + frac * (ag_in[k_in + 1] - ag_in[k_in])
        elif k_in == n_in - 1 and frac == 0.0:
            ag_new = ag_in[k_in]
        # kick – drift
        e_imp += _kick(p, v, gen, ag_old, acc, 0.5 * hs, work)
        for i in range(5):
            q[i] += hs * v[i]
        # input work of the inertial loads over the step, half-step velocities
        e_in -= 0.5 * (ag_old + ag_new) * (ms * v[0] + mt * v[3]) * hs
        dmax = forces(p, q, v, Z, hs, gen, acc, rimf, sep, vert)
        e_fric += acc[A_PFRIC] * hs
        shear = acc[A_BFX]
        # kick
        e_imp += _kick(p, v, gen, ag_new, acc, 0.5 * hs, work)
        ag_old = ag_new
        step += m
        t = step * h
        # outputs
        max_pen = max(max_pen, dmax)
        max_rot = max(max_rot, abs(q[2]))
        for k in range(2):
            if sep[k] < 1e8:  # both vertices over the plate
                max_uplift = max(max_uplift, sep[k])
        rim_contact = False
        for r in range(N_RIMS):
            f = rimf[r]
            if f > 0.0:
                rim_contact = True
                if not in_contact[r]:
                    in_contact[r] = True
                    if t - last_contact[r] > p[P_MERGE] and n_events < max_events:
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
        far = _far_from_rims(p, q, v, vert, dmax, rim_contact, coarse * h)
        # numerical and physical failure
        bad = False
        for i in range(5):
            if not math.isfinite(q[i]) or not math.isfinite(v[i]):
                bad = True
        if bad:
            status, fail_code, fail_time = STATUS_NUMERICAL, NUM_NAN, t
        elif dmax > p[P_DMAX]:
            status, fail_code, fail_time = STATUS_NUMERICAL, NUM_PENETRATION, t
        elif fail_code == 0:
            code = _failure(p, q, vert)
            if code != 0:
                fail_code, fail_time = code, t
                if stop_at_failure:
                    status = STATUS_FAILED
    if status == STATUS_OK and fail_code != 0:
        status = STATUS_FAILED
    e_kin = 0.5 * (ms * (v[0] ** 2 + v[1] ** 2) + js * v[2] ** 2 + mt * (v[3] ** 2 + v[4] ** 2))
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
    summary[S_EPOT] = ms * g * (q[1] - zs0) + mt * g * (q[4] - zt0) + acc[A_EEL] - e_el0
    summary[S_EFRIC] = e_fric
    summary[S_EIMP] = e_imp
    summary[S_N_REC] = n_rec
    summary[S_STEPS] = step
