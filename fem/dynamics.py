r"""Implicit HHT-α time integration with Newton iterations and automatic step control.

The equations of motion in the frame of the ground, for the reduced unknowns ``a`` of
:class:`fem.system.Reduction`, are M ä + f_int(a) = f_ext(t) = g − M r a_g(t), with a lumped M,
g the weights and r the horizontal influence vector (docs/theory/finite-elements.md, Eq. F23).
Each step solves the HHT-α equilibrium (Hilber, Hughes & Taylor 1977) with the Newmark updates
(Eqs. F24–F26) by Newton's method on d_{n+1} (Eq. F27), starting from the predictor
d_n + Δt v_n + Δt² a_n/2 (Eq. F28, which follows the slider's curved path to third order) with
the tangent M/(βΔt²) + (1 + α) K_t; the linear solves use :class:`fem.linear.TangentSolver`,
and a line search's accepted evaluation serves as the next iteration's.

Step control (docs/theory/finite-elements.md, "Time steps"): a step whose Newton iteration
does not converge is retried with half the step (down to ``min_step``; below it, with rounded
slider edges, once a run from ``impact_step`` with the friction history carried across the
edges, Eq. F16a); a step that opens or
closes a rim contact while longer than ``impact_step`` is retried at ``impact_step``, which is
kept while any rim contact is active; a step that changes the energy-balance residual by more than
``energy_tol`` is redone at half the size; afterwards the step doubles back to ``max_step``.

Energy per unit depth is recorded every step (Eqs. F29–F31): the input work, kinetic energy,
material work split into elastic strain energy and plastic dissipation, the penalty springs'
energy and the friction work; their residual is HHT's algorithmic dissipation plus the
trapezoidal error of the work sums. With a :class:`fem.fracture.RimFracture`, the elements it
tears let go between steps, and the strain and penalty energy they release is booked as
``fracture`` (Eq. F69).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .linear import TangentSolver
from .system import State


@dataclass(frozen=True)
class HHTParameters:
    """HHT-α constants (docs/theory/finite-elements.md, Eq. F26).

    Parameters
    ----------
    alpha : float [-]
        −1/3 ≤ α ≤ 0; 0 is Newmark's average acceleration. The default −0.3 damps the
        slider's stiff penalty-contact modes that spoil Newton's predictor, chosen by a
        measured comparison (docs/theory/finite-elements.md, "Why α = −0.3").
    """

    alpha: float = -0.3

    def __post_init__(self):
        if not -1.0 / 3.0 <= self.alpha <= 0.0:
            raise ValueError(f"HHT alpha must lie in [-1/3, 0], got {self.alpha!r}")

    @property
    def beta(self) -> float:
        """β = (1 − α)²/4."""
        return (1.0 - self.alpha) ** 2 / 4.0

    @property
    def gamma(self) -> float:
        """γ = ½ − α."""
        return 0.5 - self.alpha

    @property
    def spectral_radius(self) -> float:
        """High-frequency spectral radius ρ∞ = (1 + α)/(1 − α)."""
        return (1.0 + self.alpha) / (1.0 - self.alpha)


@dataclass
class StepControl:
    """Time-step limits [s] and Newton settings.

    Parameters
    ----------
    max_step : float [s]
        Step while sliding freely.
    impact_step : float [s]
        Largest step while a rim contact is active, and when one opens or closes.
    min_step : float [s]
        Below this a non-converging step ends the run (numerical failure).
    rtol : float [-]
        Newton converges when ‖residual‖ ≤ rtol·‖g‖ (g the weights).
    max_iter : int
        Newton iterations before a cutback.
    energy_tol : float [J/m]
        Largest change of the energy-balance residual in one step: a step that exceeds it is
        redone at half the size, down to ``impact_step / 8`` (below that it is accepted).
        Penalty contacts that open and close within one step (a light slider rattling between
        airborne plates) make or destroy energy; this catches them. Default: no limit
        (docs/theory/finite-elements.md §Time steps).
    hold : int
        Accepted steps after a step Newton could not do during which the step does not grow;
        every further such step doubles the hold (up to 64 × ``hold``), and a step that grows
        and converges resets it. 0 (default): the step doubles back at once.
    """

    max_step: float = 5e-3
    impact_step: float = 5e-4
    min_step: float = 1e-6
    rtol: float = 1e-6
    max_iter: int = 12
    energy_tol: float = math.inf
    hold: int = 0


@dataclass
class Energy:
    """Energy histories per unit depth [J/m], zero at the start of the dynamic phase."""

    input: list = field(default_factory=list)
    kinetic: list = field(default_factory=list)
    strain: list = field(default_factory=list)
    plastic: list = field(default_factory=list)
    contact: list = field(default_factory=list)  # penalty springs
    friction: list = field(default_factory=list)
    fracture: list = field(default_factory=list)  # released by torn elements (Eq. F69)
    loose_kinetic: list = field(default_factory=list)  # part of kinetic (Eq. F69b)

    def arrays(self) -> dict:
        """The histories as numpy arrays, plus ``residual`` = input − all the others
        (``loose_kinetic`` is part of ``kinetic``, not another term)."""
        out = {k: np.asarray(v) for k, v in self.__dict__.items()}
        out["residual"] = out["input"] - (
            out["kinetic"] + out["strain"] + out["plastic"] + out["contact"] + out["friction"]
            + out["fracture"]
        )
        return out


@dataclass
class Released:
    """Energy per unit depth [J/m] released by torn elements as they let go (Eq. F69): their
    strain energy and the penalty energy of the contacts they carried."""

    strain: float = 0.0
    penalty: float = 0.0

    @property
    def total(self) -> float:
        return self.strain + self.penalty


class StepFailure(RuntimeError):
    """Newton did not converge even at the smallest step."""


@dataclass(frozen=True)
class StepResult:
    """One converged HHT-α step (:meth:`Integrator.step`).

    Attributes
    ----------
    d, v, acc : ndarray [m, m/s, m/s²]
        Reduced displacement, velocity and acceleration at the end of the step.
    state : fem.system.State
        The trial history (material and contact) the step converged with.
    evaluation : object
        The system's evaluation at ``d`` (forces, contact, stresses).
    f_int, f_ext : ndarray [N/m]
        Reduced internal and external forces at the end of the step.
    iterations : int
        Newton iterations the step took.
    """

    d: np.ndarray
    v: np.ndarray
    acc: np.ndarray
    state: State
    evaluation: object
    f_int: np.ndarray
    f_ext: np.ndarray
    iterations: int


@dataclass(frozen=True)
class RunResult:
    """The outcome of :meth:`Integrator.run`.

    Attributes
    ----------
    time : ndarray [s]
        The accepted steps' times, from the start.
    energy : dict of ndarray [J/m]
        :meth:`Energy.arrays` at ``time``.
    stopped : bool
        The observer stopped the run.
    failed_numerically : bool
        Newton did not converge even at the smallest step.
    message : str
        Why the run failed numerically ("" otherwise).
    d, v : ndarray [m, m/s]
        Final reduced displacement and velocity.
    state : fem.system.State
        Final committed history.
    friction_carried_from : float or None [s]
        When the fallback of Eq. F16a was taken (None: never).
    """

    time: np.ndarray
    energy: dict
    stopped: bool
    failed_numerically: bool
    message: str
    d: np.ndarray
    v: np.ndarray
    state: State
    friction_carried_from: float | None = None


@dataclass
class Integrator:
    """HHT-α integration of a :class:`fem.dfp.DFPSystem`-like problem.

    Parameters
    ----------
    model : fem.dfp.DFPSystem
        Provides ``system``, ``reduction``, ``mass``, ``gravity``, ``influence``.
    ground_acceleration : callable
        t [s] → a_g [m/s²].
    hht : HHTParameters
    control : StepControl
    rim_mask : ndarray of bool, optional
        Slave nodes that belong to a rim (for the impact step control).
    fracture : fem.fracture.RimFracture, optional
        Updated after every accepted step; the elements it tears let go (Eq. F68).
    """

    model: object
    ground_acceleration: object
    hht: HHTParameters = field(default_factory=HHTParameters)
    control: StepControl = field(default_factory=StepControl)
    rim_mask: np.ndarray | None = None
    fracture: object = None

    def __post_init__(self):
        m = self.model
        self.system = m.system
        self.red = m.reduction
        self.M = np.asarray(m.mass, dtype=float)
        self.g = np.asarray(m.gravity, dtype=float)
        self.r = np.asarray(m.influence, dtype=float)
        self.scale = float(np.linalg.norm(self.g))
        self.newton_iterations = 0
        self.rejected = 0
        self.steps = 0
        self.solver = TangentSolver(self.system, self.red, self.M)
        self.loose = np.zeros(self.M.size, dtype=bool)  # reduced dofs of loose material
        self.friction_carried_from = None  # time [s] of the fallback of Eq. F16a, if taken

    def external(self, t: float) -> np.ndarray:
        """f_ext(t) = g − M r a_g(t), reduced [N/m]."""
        return self.g - self.M * self.r * float(self.ground_acceleration(t))

    # -- static gravity step -------------------------------------------------------------
    def gravity_step(self):
        """Static equilibrium under the weights with the ground at rest.

        Returns
        -------
        a, state, evaluation
            Reduced displacement, committed history, and the evaluation at equilibrium.
        """
        from .system import solve_static

        counts = np.asarray(self.red.P.sum(axis=0)).ravel()
        f_full = self.red.P @ (self.g / np.maximum(counts, 1))
        res = solve_static(
            self.system, self.red, np.zeros(self.system.size), self.system.initial_state(),
            f_full,
        )
        if not res.converged:
            raise StepFailure(f"gravity step did not converge: {res.residuals}")
        a = (self.red.PT @ res.displacement) / np.maximum(counts, 1)
        self.newton_iterations += res.iterations
        return a, res.state, res.evaluation

    # -- one HHT step ----------------------------------------------------------------------
    def step(self, t, h, d, v, acc, state: State, f_int_n, f_ext_n):
        """Attempt one HHT-α step of size h from the converged (d, v, acc, state) at t.

        Returns
        -------
        StepResult or None
            None if Newton did not converge.
        """
        al, be, ga = self.hht.alpha, self.hht.beta, self.hht.gamma  # Eq. F26
        f_ext = self.external(t + h)
        rhs_const = (1 + al) * f_ext - al * f_ext_n + al * f_int_n
        base = d + h * v + h * h * (0.5 - be) * acc
        x = d + h * v + 0.5 * h * h * acc  # predictor: a_{n+1} = a_n (Eq. F28)
        c0 = 1.0 / (be * h * h)
        tol = self.control.rtol * self.scale
        ev = None
        for it in range(self.control.max_iter + 1):
            if ev is None:
                ev = self.system.evaluate(self.red.expand(x), state)
            f_int = self.red.reduce(ev.internal_force)
            a_new = c0 * (x - base)
            res = rhs_const - self.M * a_new - (1 + al) * f_int  # Eqs. F24 and F27
            norm = float(np.linalg.norm(res))
            if not math.isfinite(norm):
                return None
            if norm <= tol:
                self.newton_iterations += it
                v_new = v + h * ((1 - ga) * acc + ga * a_new)  # Eq. F25
                return StepResult(
                    d=x, v=v_new, acc=a_new, state=State(ev.material.state, ev.contact.state),
                    evaluation=ev, f_int=f_int, f_ext=f_ext, iterations=it,
                )
            if it == self.control.max_iter:
                break
            dx = self.solver.solve(ev, c0, 1 + al, res)
            x, ev = self._line_search(x, dx, state, rhs_const, base, c0, norm)
        self.newton_iterations += self.control.max_iter
        return None

    def _line_search(self, x, dx, state, rhs_const, base, c0, norm, halvings=4):
        """Backtracking: halve the Newton correction while it raises the residual norm (guards
        semi-smooth Newton against active-set ping-pong; docs/theory/finite-elements.md,
        Eq. F27); the last trial is kept.
        Returns the new iterate and its evaluation (None if it was not evaluated)."""
        al = self.hht.alpha
        s = 1.0
        for _ in range(halvings):
            trial = x + s * dx
            ev = self.system.evaluate(self.red.expand(trial), state)
            res = rhs_const - self.M * c0 * (trial - base) - (1 + al) * self.red.reduce(
                ev.internal_force
            )
            r = float(np.linalg.norm(res))
            if math.isfinite(r) and r < norm:
                return trial, ev
            s *= 0.5
        return x + s * dx, None

    def run(self, t_end: float, observer=None, t_start: float = 0.0):
        """Integrate from the gravity equilibrium at rest to ``t_end``.

        Parameters
        ----------
        t_end : float [s]
        observer : callable, optional
            ``observer(t, d_full, evaluation, state) → bool``, called after the gravity step
            (t = t_start) and after every accepted step; returning True stops the run.
        t_start : float [s]

        Returns
        -------
        RunResult
        """
        ctl = self.control
        d, state, ev = self.gravity_step()
        v = np.zeros_like(d)
        f_int = self.red.reduce(ev.internal_force)
        f_mat = self.red.reduce(ev.material_force)
        f_ext = self.external(t_start)
        # Initial acceleration from equilibrium: M a0 = f_ext − f_int (ground load at t_start).
        acc = (f_ext - f_int) / self.M
        energy = Energy()
        w_ext = w_mat = w_fric = 0.0
        ekin = residual = 0.0
        strain0 = self.system.strain_energy(ev)
        cont0 = ev.contact.normal_energy
        self.released = Released()
        times = [t_start]
        self._record(energy, w_ext, ekin, w_mat, w_fric, ev, strain0, cont0, v)
        stopped = False
        failed = False
        message = ""
        if observer is not None and observer(t_start, self.red.expand(d), ev, state):
            stopped = True
        t = t_start
        h = ctl.max_step
        rim_active = False
        held, backoff = 0, ctl.hold  # steps left without growth, the next hold's length
        grew = False  # the step attempted is longer than the last accepted one
        while not stopped and t < t_end - 1e-12:
            h = min(h, t_end - t)
            out = self.step(t, h, d, v, acc, state, f_int, f_ext)
            if out is not None and self.rim_mask is not None and h > ctl.impact_step * 1.0001:
                now_active = bool(out.evaluation.contact.active[self.rim_mask].any())
                if now_active != rim_active:
                    out = None  # a rim contact opens or closes: redo at the impact step
                    self.rejected += 1
                    h, grew = ctl.impact_step, False
                    continue
            if out is None:
                self.rejected += 1
                self.solver.thaw()  # Newton failed: fresh frozen tangents (Eq. F35a)
                if ctl.hold:  # hold the step that converges (§Time steps)
                    held, backoff = backoff, min(2 * backoff, 64 * ctl.hold)
                grew = False
                h *= 0.5
                if h < ctl.min_step and self._carry_across_edges(t):
                    h = ctl.impact_step  # the fallback of Eq. F16a: retry the step
                    continue
                if h < ctl.min_step:
                    failed = True
                    message = f"Newton did not converge at t = {t:.5f} s even with Δt = {h:.2e} s"
                    if self.friction_carried_from is not None:
                        message += (" and the friction carried across the slider's edges from"
                                    f" t = {self.friction_carried_from:.5f} s (Eq. F16a)")
                    break
                continue
            dd = out.d - d
            f_mat_new = self.red.reduce(out.evaluation.material_force)
            con = out.evaluation.contact
            w_ext_new = w_ext + 0.5 * float((f_ext + out.f_ext) @ dd)
            w_mat_new = w_mat + 0.5 * float((f_mat + f_mat_new) @ dd)
            w_fric_new = w_fric + float(-(con.tangential * con.slip).sum())
            ekin_new = 0.5 * float(self.M @ (out.v * out.v))
            # residual = input − kinetic − (strain + plastic) − contact − friction (Eqs.
            # F29–F31)
            residual_new = (w_ext_new - ekin_new - w_mat_new - (con.normal_energy - cont0)
                            - w_fric_new - self.released.penalty)
            if abs(residual_new - residual) > ctl.energy_tol and h > ctl.impact_step / 8:
                self.rejected += 1
                h, grew = 0.5 * h, False
                continue
            w_ext, w_mat, w_fric, ekin, residual = (w_ext_new, w_mat_new, w_fric_new,
                                                    ekin_new, residual_new)
            d, v, acc, state = out.d, out.v, out.acc, out.state
            f_int, f_ext, f_mat, ev = out.f_int, out.f_ext, f_mat_new, out.evaluation
            t += h
            self.steps += 1
            times.append(t)
            if self.fracture is not None:
                ev, f_int, f_mat = self._tear(t, d, ev, state, f_int, f_mat)
            self._record(energy, w_ext, ekin, w_mat, w_fric, ev, strain0, cont0, v)
            if self.rim_mask is not None:
                rim_active = bool(ev.contact.active[self.rim_mask].any())
            if observer is not None and observer(t, self.red.expand(d), ev, state):
                stopped = True
                break
            limit = ctl.impact_step if rim_active else ctl.max_step
            if grew:
                backoff = ctl.hold
            if out.iterations > ctl.max_iter // 2:  # hard step: be careful with the next
                h, grew = max(0.5 * h, ctl.min_step), False
            elif held:
                held -= 1
                h, grew = min(h, limit), False
            else:
                h, grew = min(2.0 * h, limit), 2.0 * h <= limit
        return RunResult(
            time=np.asarray(times), energy=energy.arrays(), stopped=stopped,
            failed_numerically=failed, message=message, d=d, v=v, state=state,
            friction_carried_from=self.friction_carried_from,
        )

    def _carry_across_edges(self, t: float) -> bool:
        """The fallback of a step that failed at its smallest size: from ``t`` [s] on, the
        friction history carries across the slider's rounded edges (Eq. F16a), once a run and
        only where the edges are rounded. True if it was turned on now."""
        sysm = self.system
        if sysm.carry_across_edges or sysm.shape.edge_radius <= 0.0:
            return False
        sysm.carry_across_edges = True
        self.friction_carried_from = t
        return True

    def _tear(self, t, d, ev, state, f_int, f_mat):
        """After an accepted step: update the fracture; if elements let go further (Eq. F68),
        re-evaluate at the same configuration, book what they released (Eq. F69), and return
        the new evaluation and reduced internal and material forces."""
        sysm = self.system
        if not self.fracture.update(t, state.material.eq_plastic_strain, ev.material.stress,
                                    ev.material.jacobian):
            return ev, f_int, f_mat
        strain, penalty = sysm.strain_energy(ev), ev.contact.normal_energy
        sysm.erode(self.fracture.retained, self.red.expand(d))
        ev = sysm.evaluate(self.red.expand(d), state)
        self.released.strain += strain - sysm.strain_energy(ev)
        self.released.penalty += penalty - ev.contact.normal_energy
        self.solver.thaw()  # the frozen tangents of Eq. F35a may have let go
        full = np.zeros(sysm.size)
        full[sysm.loose_dofs] = 1.0
        self.loose = self.red.reduce(full) > 0.0
        return ev, self.red.reduce(ev.internal_force), self.red.reduce(ev.material_force)

    def _record(self, energy, w_ext, ekin, w_mat, w_fric, ev, strain0, cont0, v):
        strain = self.system.strain_energy(ev) - strain0
        contact = ev.contact.normal_energy - cont0
        energy.input.append(w_ext)
        energy.kinetic.append(ekin)
        energy.strain.append(strain)
        energy.plastic.append(w_mat - strain - self.released.strain)
        energy.contact.append(contact)
        energy.friction.append(w_fric)
        energy.fracture.append(self.released.total)
        loose = self.loose
        energy.loose_kinetic.append(0.5 * float(self.M[loose] @ (v[loose] * v[loose])))
