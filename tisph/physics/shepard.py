"""Shepard density filter, paper 002 eqs. 13-15, every numerics.shepard_every steps."""

import taichi as ti

from ..hooks.module import Module
from ..particles import FLUID


@ti.data_oriented
class Shepard(Module):
    """rho_i = sum m_j W / sum V_j W over fluid neighbours, fluid particles only; a kernel of its
    own after the step (it needs every particle's new density)."""

    name = "shepard"
    on = {"shepard": True}

    def setup(self, S):
        self.S = S
        self.every = int(S.params.get("shepard_every", 0))

    def after_step(self, S):
        if self.every > 0 and S.steps % self.every == 0:
            self._filter()

    @ti.kernel
    def _filter(self):
        S = self.S
        for i in range(S.n):
            if S.stepper.live[None] and S.p.kind[i] == FLUID:  # not after a parked step
                acc = ti.Struct(num=0.0, den=0.0)  # the self term comes with the neighbours
                S.grid.for_neighbours(S.p, i, S.p.x[i], self.shepard_pair, acc)
                S.tmp.rho[i] = acc.num / acc.den
        for i in range(S.n):
            if S.stepper.live[None] and S.p.kind[i] == FLUID:
                S.p.rho[i] = S.tmp.rho[i]

    @ti.func
    def shepard_pair(self, i, j, r, r2, acc: ti.template()):
        S = self.S
        if S.p.kind[j] == FLUID:
            w = S.w_scale * S.K.shape(ti.sqrt(r2) * S.inv_h)
            acc.num += S.p.m[j] * w
            acc.den += S.p.m[j] / S.p.rho[j] * w
