"""What an FE run records after every accepted step (:func:`fem.simulate`): the histories
(:class:`History`), snapshots, the limit states and the verdict (:class:`Verdict`), kept by
the :class:`Observer` that :meth:`fem.dynamics.Integrator.run` calls; and which rim each
contact node belongs to (:func:`rim_of_nodes`)."""

from __future__ import annotations

from dataclasses import dataclass, field, fields

import numpy as np

from .limit_states import LimitStates

__all__ = ["PLASTIC_STRAIN_LIMIT", "History", "Observer", "Verdict", "rim_of_nodes"]

#: Equivalent plastic strain of a rim, averaged over a gauge of its thickness (Eq. F52), beyond
#: which a run has left the model's range (a true strain of 5 stretches a fibre 150-fold; 25
#: times the rupture strain): it ends as numerical. The gauge average, because the local strain
#: at the rim root's re-entrant corner grows with mesh refinement (docs/results/rupture_mesh.csv).
PLASTIC_STRAIN_LIMIT = 5.0


def rim_of_nodes(model) -> np.ndarray:
    """The rim (index in :data:`RIMS`) of every contact slave node on a rim's inner face or
    top, or inside a rim (Eq. F68c), -1 for the others: for the rim forces and the impact
    step control."""
    mesh, nodes = model.mesh, model.system.nodes
    rim_of = np.full(len(nodes), -1)
    side = mesh.p[0, nodes.nodes] > 0
    for plate, base in (("bottom", 0), ("top", 2)):
        faces = [mesh.facets[:, mesh.boundaries[f"{plate}_{k}"]].ravel()
                 for k in ("rim_inner", "rim_top")]
        inside = mesh.t[:, mesh.subdomains[f"{plate}_rim"]].ravel()
        on_rim = np.isin(nodes.nodes, np.concatenate([*faces, inside]))
        rim_of[on_rim & ~side] = base
        rim_of[on_rim & side] = base + 1
    return rim_of


@dataclass
class History:
    """The histories recorded after every accepted step (lists, then arrays; SI, forces per
    bearing, i.e. times the depth): time ``t``, top plate ``x`` and rise ``z``, slider ``xs``,
    rise ``zs`` and rotation ``th``, base ``shear``, ``dish`` forces (bottom, top), ``rim``
    forces (:data:`RIMS` order), the rims' root plastic strain ``root_p``, yielded fraction
    ``root_frac`` and gauge-averaged (``regular``) plastic strain, and with fracture the
    rims' largest element ``damage`` (Eq. F67)."""

    t: list = field(default_factory=list)
    x: list = field(default_factory=list)
    z: list = field(default_factory=list)
    xs: list = field(default_factory=list)
    zs: list = field(default_factory=list)
    th: list = field(default_factory=list)
    shear: list = field(default_factory=list)
    dish: list = field(default_factory=list)
    rim: list = field(default_factory=list)
    root_p: list = field(default_factory=list)
    root_frac: list = field(default_factory=list)
    regular: list = field(default_factory=list)
    damage: list = field(default_factory=list)

    def arrays(self) -> History:
        """The same histories as numpy arrays."""
        return History(**{f.name: np.asarray(getattr(self, f.name)) for f in fields(self)})


@dataclass
class Verdict:
    """What the run came to: the limit state's ``time`` [s], failure ``mode`` and ``detail``
    once reached, or ``numerical`` (why the run left the model's range)."""

    time: float | None = None
    mode: str | None = None
    detail: str | None = None
    numerical: str | None = None

    @property
    def reached(self) -> bool:
        """A verdict was given (failure or numerical)."""
        return self.time is not None or self.numerical is not None


@dataclass
class Observer:
    """Called by :meth:`fem.dynamics.Integrator.run` after every accepted step: records the
    histories, keeps snapshots, watches the limit states (:class:`fem.limit_states.LimitStates`)
    and stops the run at failure (with ``stop_at_failure``) or when a rim's gauge-averaged
    plastic strain passes :data:`PLASTIC_STRAIN_LIMIT` (numerical)."""

    model: object
    rim_of: np.ndarray
    watch: LimitStates
    limit_state: str
    stop_at_failure: bool
    snapshot_every: int
    first_step: float
    top_rows: np.ndarray
    top_z_rows: np.ndarray
    history: History = field(default_factory=History)
    snapshots: list = field(default_factory=list)
    verdict: Verdict = field(default_factory=Verdict)
    z_top0: float | None = None

    def __call__(self, t, d, ev, state) -> bool:
        sysm, nodes, depth = self.model.system, self.model.system.nodes, self.model.depth
        hist, rim_of = self.history, self.rim_of
        rim_mask = rim_of >= 0
        pose = sysm.slider_pose(d)
        con = ev.contact
        p = state.material.eq_plastic_strain
        hist.t.append(t)
        hist.x.append(float(d[self.top_rows].mean()))
        zt = float(d[self.top_z_rows].mean())
        if self.z_top0 is None:
            self.z_top0 = zt
        hist.z.append(zt - self.z_top0)
        hist.xs.append(pose[0])
        hist.zs.append(pose[1] - sysm.pose[1])
        hist.th.append(pose[2])
        bottom = nodes.plate == 0
        hist.shear.append(float(con.node_force[0, bottom].sum()) * depth)
        hist.dish.append(
            [float(con.normal[(nodes.plate == k) & ~rim_mask].sum()) * depth for k in (0, 1)]
        )
        hist.rim.append([float(con.normal[rim_of == k].sum()) * depth for k in range(4)])
        root_p, frac, regular = self.watch.update(t, d, pose, p)
        hist.root_p.append(root_p)
        hist.root_frac.append(frac)
        hist.regular.append(regular)
        if self.watch.fracture is not None:
            hist.damage.append(list(self.watch.fracture.rim_damage))
        if self.snapshot_every and (len(hist.t) - 1) % self.snapshot_every == 0:
            self.snapshots.append((t, d.copy(), p.copy(), ev.material.stress.copy()))
        return self._judge(t, regular)

    def _judge(self, t, regular) -> bool:
        """Update the verdict after a step; True stops the run."""
        verdict = self.verdict
        if max(regular) > PLASTIC_STRAIN_LIMIT:
            if verdict.numerical is None:
                verdict.numerical = (f"a rim's gauge-averaged plastic strain reached "
                                     f"{max(regular):.3g} at t = {t:.4f} s, beyond the model's "
                                     "range")
            return True
        if not verdict.reached:
            failed, when, mode, detail = self.watch.verdict(self.limit_state)
            if failed:
                if when <= self.first_step and abs(self.history.x[-1]) < 1e-3:
                    verdict.numerical = (f"failure at the first step ({detail}) without "
                                         "motion: a numerical, not a physical, failure")
                    return True
                verdict.time, verdict.mode, verdict.detail = when, mode, detail
                if self.stop_at_failure:
                    return True
        return False
