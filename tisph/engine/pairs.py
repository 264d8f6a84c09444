"""Each pair once, on the CPU: the force pass visits every pair of neighbours once and gives
both particles their terms, in an order that does not depend on the threads.

The gather pass (stepper.forces) visits every pair twice, once from each side: half of its
candidate scan and of its kernel evaluations (|r|, W', 1/(r^2 + eta^2)) are repeats. Here each
particle scans the forward half of its stencil only (its own cell row after itself, and the two
rows above) and computes the pair's kernel once. A fluid-fluid pair's terms for both particles
come from the modules' pair2 hooks, which share the two sides' arithmetic (one
(p_i + p_j) / (rho_i rho_j), one v_ij . grad W); a fluid-boundary pair's from the pair hooks,
called with the roles swapped where the boundary particle holds the pair (-r, -grad W, -v_ij:
exact negations). The terms equal the gather pass's to rounding.

Writing to j from many threads would race. The cell rows are cut into ZONES zones of at least
two rows (balanced by particle count); a particle's forward half reaches at most two rows up,
into the next zone only, so the even zones run in parallel first, then the odd ones, each zone
in sorted order on one thread. The zones are a fixed number, so the sums' order, and with it
every bit of a run, is the same on any number of threads: restarts stay bit for bit.

It applies where every module with a pair hook has pair2 (Module.pair_once) and none changes how
i sees j (view hooks): continuity, pressure, artificial and laminar viscosity and density
diffusion (but the renormalised one) with dynamic or extrapolated walls; the no-slip walls, the
velocity gradient, the SPS stress and the k and omega equations (not the rheology, drag, DEM or
suspended sand). Other cases (the flume's renormalised diffusion), and any GPU, keep the gather
pass; run.pair_once chooses (by default, runs long enough to repay its longer compile,
runner/setup.py). Where the gather pass runs in the CPU's vector lanes (engine/grid.py), which
beat this pass, it is not taken (engine/stepper.py).
"""

import numpy as np
import taichi as ti

from ..particles import FLUID

ZONES = 16  # 8 a phase: the rows are cut the same way whatever the thread count
LANE = 512  # Taichi's CPU range-for deals each thread max(ceil(N / T), 512) iterations in one
# piece: a loop of (zones a phase) x 512 iterations, one zone at every 512th,
# runs the zones on all threads (a loop under 1,024 iterations runs on one)


def deal(per_phase, threads):
    """The zone (of a phase's per_phase) that each LANE of the phase's loop takes, so that thread t's
    contiguous piece of the loop holds zones t, t + threads, ...: the zones round the threads."""
    if threads > per_phase or per_phase % threads:
        return list(range(per_phase))
    piece = per_phase // threads
    return [(q % piece) * threads + q // piece for q in range(per_phase)]


def applicable(S):
    """Whether the solver's modules allow each pair once (and it runs on the CPU)."""
    if not S.cpu or S.hooks["view"]:
        return False
    return all(getattr(m, "pair_once", None) is not None and m.has("pair2") for m in S.hooks["pair"])


def sum_slots(S):
    """{slot: 'sum' | 'max'}: the accumulator slots that pairs add to, kept per particle."""
    slots = {"a": "sum", "drho": "sum"}
    for m in S.hooks["pair"]:
        slots.update(m.pair_once)
    return slots


@ti.data_oriented
class PairOnce:
    def __init__(self, S, Acc, acc_types):
        """S: the kernel view (view.py); Acc, acc_types: the stepper's accumulator type and its slots' types."""
        self.S, self.Acc = S, Acc
        self.slots = sum_slots(S)
        self.names = tuple(self.slots)
        self.SumT = ti.types.struct(**{k: acc_types[k] for k in self.names})
        self.sums = self.SumT.field(shape=S.n)
        self.zr = ti.field(ti.i32, ZONES + 1)  # each zone's first cell row
        # which of a phase's zones each LANE of its loop takes: Taichi deals each thread one
        # contiguous piece of the loop, and a shallow domain's water fills only the first few
        # zones, so in row order one thread would get them all; dealt round the threads instead.
        # Each zone still runs in sorted order on one thread: the sums' order does not change.
        threads = max(1, int(ti.lang.impl.current_cfg().cpu_max_num_threads))
        self.slot = ti.field(ti.i32, ZONES // 2)
        self.slot.from_numpy(np.array(deal(ZONES // 2, threads), dtype=np.int32))

    @ti.func
    def zones(self):
        """Cut the rows into zones of at least two rows, about n / ZONES particles each (one task,
        after the prefix sum)."""
        g = self.S.grid
        n_in = g.start[g.ncells]
        self.zr[0] = 0
        z = 1
        for row in range(g.ny):
            if z < ZONES and row >= self.zr[z - 1] + g.cdiv and g.start[row * g.nx] * ZONES >= z * n_in:
                self.zr[z] = row
                z += 1
        for k in range(z, ZONES + 1):
            self.zr[k] = g.ny

    @ti.func
    def clear(self, a):
        self.sums[a] = self.SumT(0)

    @ti.func
    def phase(self, u, ph):
        """Iteration u of a phase's loop: zone 2 (u / LANE) + ph, in sorted order, at u % LANE == 0."""
        if u % LANE == 0:
            g = self.S.grid
            z = 2 * self.slot[u // LANE] + ph
            i0 = g.start[self.zr[z] * g.nx]
            i1 = g.start[self.zr[z + 1] * g.nx]
            for i in range(i0, i1):
                self.visit(i)

    @ti.func
    def own(self, i, acc: ti.template(), ve, rhoe, ir, p, mi):
        """Particle i's own values in an accumulator, as the gather pass sets them."""
        S = self.S
        acc.vi, acc.rhoi, acc.pi, acc.inv_rhoi = ve, rhoe, p, ir
        acc.mui, acc.mat = S.mat.mu[mi], mi
        for m in ti.static(S.hooks["init_acc"]):
            m.init_acc(S, i, acc)

    @ti.func
    def visit(self, i):
        S = self.S
        t = S.tmp
        k = t.kind[i]
        acc = self.Acc(0)
        self.own(i, acc, t.ve[i], t.rhoe[i], t.ir[i], t.p[i], ti.cast(t.mat[i], ti.i32))
        acc.kind = ti.cast(k, ti.i32)
        acc.m = t.m[i]
        if k == FLUID:
            for s in ti.static(self.names):
                acc[s] = self.sums[i][s]
            S.grid.for_forward(t, i, t.x[i], self.pair, acc)
            for s in ti.static(self.names):
                self.sums[i][s] = acc[s]
        elif k >= 0:
            if S.grid.fluid_near(t.x[i]):
                S.grid.for_forward(t, i, t.x[i], self.bound_pair, acc)

    @ti.func
    def kernel(self, r, r2):
        """The pair's q = |r| / h, 1 / (r^2 + eta^2) and grad W, once for both sides."""
        S = self.S
        q = ti.sqrt(r2) * S.inv_h
        return q, 1.0 / (r2 + S.eta2), S.g_scale * S.K.fshape(q) * r

    @ti.func
    def add_to(self, j, part: ti.template()):
        """Fluid j's share of a pair into its sums (no other thread writes j: the zones)."""
        for sl in ti.static(self.names):
            if ti.static(self.slots[sl] == "max"):
                self.sums[j][sl] = ti.max(self.sums[j][sl], part[sl])
            else:
                self.sums[j][sl] += part[sl]

    @ti.func
    def pair(self, i, j, r, r2, acc: ti.template()):
        """The pair (i, j) of a fluid i, j in i's forward half: with a fluid j, both particles'
        terms at once (the modules' pair2, which share the arithmetic of the two sides); with a
        boundary j, i's terms."""
        S = self.S
        s = S.tmp
        kj = ti.cast(s.kind[j], ti.i32)
        q, ie, gw = self.kernel(r, r2)
        m_j, ir_j = s.m[j], s.ir[j]
        v_ij = acc.vi - s.ve[j]
        nb = ti.Struct(
            kj=kj,
            rho_j=s.rhoe[j],
            ir_j=ir_j,
            p_j=s.p[j],
            q=q,
            m_j=m_j,
            vol_j=m_j * ir_j,
            m_i=acc.m,
            vol_i=acc.m * acc.inv_rhoi,
            ie=ie,
            gw=gw,
            v_ij=v_ij,
            v_visc=v_ij,
        )
        if kj == FLUID:
            sj = self.SumT(0)
            for m in ti.static(S.hooks["pair"]):
                m.pair2(S, i, j, r, r2, nb, acc, sj)
            self.add_to(j, sj)
        else:
            for m in ti.static(S.hooks["pair"]):
                m.pair(S, i, j, r, r2, nb, acc)

    @ti.func
    def bound_pair(self, i, j, r, r2, acc: ti.template()):
        """The pair (i, j) of a boundary particle i: fluid j's terms from i, the hooks called with
        the roles swapped (-r, -grad W, -v_ij: exact negations, so the terms are the ones j's own
        gather would compute)."""
        S = self.S
        s = S.tmp
        if s.kind[j] == FLUID:
            q, ie, gw = self.kernel(r, r2)
            ve_j = s.ve[j]
            v_ij = acc.vi - ve_j
            accj = self.Acc(0)
            self.own(j, accj, ve_j, s.rhoe[j], s.ir[j], s.p[j], ti.cast(s.mat[j], ti.i32))
            nbi = ti.Struct(
                kj=acc.kind,
                rho_j=acc.rhoi,
                ir_j=acc.inv_rhoi,
                p_j=acc.pi,
                q=q,
                m_j=acc.m,
                vol_j=acc.m * acc.inv_rhoi,
                ie=ie,
                gw=-gw,
                v_ij=-v_ij,
                v_visc=-v_ij,
            )
            for m in ti.static(S.hooks["pair"]):
                m.pair(S, j, i, -r, r2, nbi, accj)
            self.add_to(j, accj)

    @ti.func
    def load(self, i, acc: ti.template()):
        """Fluid particle i's finished sums into its accumulator (the closing pass)."""
        for s in ti.static(self.names):
            acc[s] = self.sums[i][s]
