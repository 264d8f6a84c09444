"""Dual-criteria time stepping (Zhang, Rezavand & Hu 2020, J. Comput. Phys. 404): the terms
that change at the flow's own pace (modules whose `rate` is "advection": the water's viscosity,
the density diffusion and, where no rheology reads it, the velocity gradient with the turbulence
it drives) are evaluated at the advection criterion dt_ad = advection_cfl h / |v|_max
(theirs, 0.25) and held over the acoustic steps inside it, which evaluate the pressure, the
continuity, the walls and the artificial viscosity (acoustic damping: its coefficient is c0's).
The step kernel splits the sums (engine/stepper.py, forces); on the steps between, a held module's
`hold` hook does what it must every step (the k equation's step with its held production)."""

import taichi as ti

from ..hooks.module import Module, Param
from ..settings.engine_keys import KEYED


@ti.data_oriented
class DualCriteria(Module):
    name = "dual_criteria"
    on = {"time_stepping": "dual"}
    params = {
        "advection_cfl": KEYED["numerics.advection_cfl"],
        "acoustic_steps": KEYED["numerics.acoustic_steps"],
        "since": Param(0.0, "s", (0.0, None), "how long the advection terms' last evaluation has acted (the kernel's)"),
        "sub": Param(0.0, "-", (0.0, None), "acoustic steps since then (the kernel's)"),
        "full": Param(1.0, "-", (0.0, 1.0), "1: this step evaluates the advection terms (the kernel's)"),
        "dt_vis": Param(1e30, "s", (0.0, None), "this step's viscous limit (the kernel's)"),
    }
    maxima = {"vmax2": "real"}

    def fields(self, real):
        # the advection terms' acceleration and density rate, held between their evaluations
        return {"a_adv": ti.types.vector(2, real), "drho_adv": real}

    def setup(self, S):
        self.S = S.stepper.S  # the kernel view its sums pass to the hooks (engine/view.py)

    @ti.func
    def sums(self, S, i, acc: ti.template(), acc_s: ti.template()):
        """Fluid particle i's neighbour pass: the acoustic-rate terms into acc; on a step that
        evaluates them, the advection-rate ones into acc_s (a copy of acc with its sums zeroed),
        kept in a_adv, drho_adv; otherwise those held. Adds them to acc's; returns whether it
        evaluated them."""
        full = S.prm[None].full > 0.5
        acc_s.a = ti.Vector([0.0, 0.0])
        acc_s.drho = 0.0
        t = S.tmp
        # two loops, not one with the test inside: each stays in the CPU's vector lanes (S.lanes)
        if full:
            S.grid.for_neighbours(t, i, t.x[i], self.pair_task, (acc, acc_s, True), S.lanes)
        else:
            S.grid.for_neighbours(t, i, t.x[i], self.pair_task, (acc, acc_s, False), S.lanes)
        a_adv, drho_adv = t.a_adv[i], t.drho_adv[i]
        if full:
            a_adv, drho_adv = acc_s.a, acc_s.drho
            S.p.a_adv[i] = a_adv
            S.p.drho_adv[i] = drho_adv
        acc.a += a_adv
        acc.drho += drho_adv
        return full

    @ti.func
    def pair_task(self, i, j, r, r2, accs: ti.template()):
        """accs = (acc, acc_s, full), indexed, not unpacked: a name bound in Taichi scope is a copy;
        full a Python bool, so the advection terms are compiled into one of the two loops only."""
        S = self.S
        nb = S.stepper.neighbour_view(i, j, r, r2, accs[0])
        for m in ti.static(S.fast["pair"]):
            m.pair(S, i, j, r, r2, nb, accs[0])
        if ti.static(accs[2]):
            for m in ti.static(S.slow["pair"]):
                m.pair(S, i, j, r, r2, nb, accs[1])

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        pt.vmax2 = ti.max(pt.vmax2, pt.v.dot(pt.v))

    @ti.func
    def dt_limit(self, S, dt_new):
        """Whether the next step evaluates the advection terms: when the terms held since the last
        evaluation would be older than dt_ad or than the explicit viscous limit 0.125 h^2 / nu (a
        held viscous term is an explicit step as long as it is held: a Bingham sand's effective
        viscosity, whose limit sets the step, is evaluated every step), or after acoustic_steps."""
        prm = S.prm[None]
        since = prm.since + prm.dt  # how long the last evaluation has acted, its own step included
        sub = prm.sub + 1.0
        if prm.full > 0.5:
            since = prm.dt
            sub = 0.0
        vmax2 = S.stats[None].vmax2
        full = 0.0
        held = since + dt_new
        if sub + 1.0 >= prm.acoustic_steps or held > prm.dt_vis or vmax2 * held**2 > (prm.advection_cfl * S.h) ** 2:
            full = 1.0
        S.prm[None].since = since
        S.prm[None].sub = sub
        S.prm[None].full = full
        S.stats[None].vmax2 = 0.0
        return dt_new
