"""The stepper: one time step as one fused Taichi kernel, composed from the enabled modules' hooks,
and what the step keeps on the device besides the particles (its accumulator's type, the force
pass's maxima, the batch's log of time steps and health, the paddle's series).

One time step is one kernel (a handful of parallel loops), because on the CPU each kernel
launch costs ~40 us and each parallel loop ~15 us: separate kernels for binning, sorting,
forces and integration would cost more than the physics at a few thousand particles.

Time integration is velocity Verlet (kick-drift-kick) with one force evaluation per step:
    x^{n+1} = x^n + dt v^n + dt^2/2 a^n (+ dt * XSPH^n)
    v^{n+1/2} = v^n + dt/2 a^n,  rho^{n+1/2} = rho^n + dt/2 drho^n
    forces at x^{n+1} with the predicted v^n + dt a^n and rho^n + dt drho^n
    v^{n+1} = v^{n+1/2} + dt/2 a^{n+1},  rho^{n+1} = rho^{n+1/2} + dt/2 drho^{n+1}
Second order, symplectic for the conservative part, half the force passes of predictor-corrector.

The step's loops, in order:
  1. advance: drift and half kick (fluid), prescribed motion (MOVING), boundary half kick;
     outflow, container and domain checks; cell keys and counts
  2. prefix sum over the cells (serial on the CPU; by blocks of cells on a GPU)
  3. scatter particle indices into their cells
  4. per cell: order by id, gather every member into the sorted copy, evaluation state
     (predicted velocity and density, Tait pressure, 1/rho)
  5a. where run.pair_once takes it (engine/pairs.py): each pair once, both particles' terms,
     in zones of cell rows, the even zones then the odd ones
  5. forces: each fluid particle's neighbour pass (the modules' pair hooks; with 5a, its sums),
     closing half kick, the modules' finish hooks, health, the maxima per block of particles;
     boundary particles' own pass (dynamic walls)
  6. the next time step (engine/limits.py)

The modules' hooks take the kernel view S (view.py: its store's fields S.p and S.tmp, its table's
S.prm, S.mat and S.stats, its grid, the kernel's constants), not the solver; the stepper reads the
same and keeps its own state apart.
"""

import taichi as ti

from ..hooks.health import BAD_DENSITY, BAD_LEAK, BAD_NONE, fluid_code, report
from ..particles import FLUID, MOVING, OUT, OUTFLOW
from ..terms.pressure import tait
from . import pairs
from .batch import BATCH, PFIT, series_at
from .limits import next_dt
from .pairs import PairOnce
from .state import resolve
from .table import CORE_MAXIMA
from .view import KernelView

# The base slots of a fluid particle's accumulator (the modules add theirs).
ACC_CORE = {
    "a": "vec2",
    "drho": "real",
    "vi": "vec2",
    "rhoi": "real",
    "pi": "real",
    "inv_rhoi": "real",
    "mui": "real",
    "mat": "int",
    "kind": "int",
    "m": "real",
}


@ti.data_oriented
class Stepper:
    def __init__(self, S, pair_once):
        """S: the solver, its store, table and grid built; pair_once: whether to visit each pair
        once where the modules allow it (engine/pairs.py). The kernels read S through its kernel
        view (view.py), and pass the view to the hooks."""
        self.S = KernelView(S, self)
        # the force pass's maxima: on the CPU per block of particles, reduced once on one thread
        # (no atomics in the pass; 1,024 blocks or more, so Taichi's CPU range-for deals them to
        # every thread); on a GPU per particle, by its hardware atomics
        self.maxima = dict(CORE_MAXIMA)
        for m in S.modules:
            self.maxima.update(m.maxima)
        self.MaxT = ti.types.struct(**{k: resolve(t, S.real) for k, t in self.maxima.items()})
        self.blk = max(1, S.n // 1024) if S.cpu else 1
        self.nblk = (S.n + self.blk - 1) // self.blk
        self.bmax = self.MaxT.field(shape=self.nblk if S.cpu else 1)
        # each step k of a batch writes the dt it chose into dtlog[k], the health code into
        # slot_health and the steps the batch took into slot_taken (the rest parked: a step parks
        # once the batch has reached the time it was given, or the health has gone bad); the host
        # reads the batch back in one transfer (access.py, step_ahead)
        self.slot_health, self.slot_taken = BATCH, BATCH + 1
        self.dtlog = ti.field(S.real, shape=BATCH + 2)
        self.ptau = ti.field(S.real, shape=())  # time into a batch: the paddle's series, the stop
        self.live = ti.field(ti.i32, shape=())  # 0 where the last step launched was parked
        self.pfit = ti.field(S.real, shape=PFIT)  # its series in one or two pieces (batch.py, series_fit)
        # the maxima a finish hook raises through pt (the pass itself raises amax2 and rhodev)
        self._module_max0 = {
            k: 0 if t == "int" else 0.0 for k, t in self.maxima.items() if k not in ("amax2", "rhodev")
        }
        self._module_max, self._maxima = tuple(self._module_max0), tuple(self.maxima)
        acc = dict(ACC_CORE)
        for m in S.modules:
            acc.update(m.acc)
        self.acc_types = {k: resolve(t, S.real) for k, t in acc.items()}
        self.Acc = ti.types.struct(**self.acc_types)
        # each pair once where asked (run.pair_once, runner/setup.py) and the modules allow it
        # (engine/pairs.py), unless the gather pass runs in the lanes (they beat it: the beach
        # 1.23x in the same cells); otherwise the gather pass
        self.pair_once = (
            PairOnce(self.S, self.Acc, self.acc_types)
            if pair_once and pairs.applicable(S) and S.dual is None and not S.lanes
            else None
        )
        self.once = self.pair_once is not None

    @ti.func
    def advance(self, i, dt):  # noqa: C901 (ti.static branches, one a hook: only the case's are compiled)
        """Loop 1: drift and half kick, boundaries' motion, removals and checks, the cell key."""
        S = self.S
        p = S.p
        k = p.kind[i]
        key = S.grid.ncells
        if k >= 0:
            if k == FLUID:
                drift = p.v[i]
                for m in ti.static(S.hooks["drift"]):
                    drift = m.drift(S, i, drift)
                p.x[i] = S.grid.wrap(p.x[i] + dt * drift + 0.5 * dt * dt * p.a[i])
                p.v[i] += 0.5 * dt * p.a[i]
                p.rho[i] += 0.5 * dt * p.drho[i]
            else:
                if k == MOVING:
                    if ti.static(len(S.hooks["move"]) > 0):
                        for m in ti.static(S.hooks["move"]):
                            m.move(S, i, dt)
                    else:
                        p.x[i] = S.grid.wrap(p.x[i] + dt * p.v[i])
                for m in ti.static(S.hooks["boundary_motion"]):
                    m.boundary_motion(S, i, k, dt)
                for m in ti.static(S.hooks["boundary_kick"]):
                    m.boundary_kick(S, i, dt)
            gone = False
            if ti.static(len(S.hooks["remove"]) > 0):
                if k == FLUID:
                    for m in ti.static(S.hooks["remove"]):
                        if not gone and m.remove(S, i):
                            gone = True  # parked as the module says: OUTFLOW, or SPRAY
                            p.kind[i] = ti.cast(ti.static(getattr(m, "kind_out", OUTFLOW)), p.kind.dtype)
            if ti.static(len(S.hooks["position_check"]) > 0):
                if k == FLUID and not gone:
                    for m in ti.static(S.hooks["position_check"]):
                        m.position_check(S, i)
            if not gone and S.grid.inside(p.x[i]):
                key = S.grid.key_of(p.x[i])
                if p.kind[i] == FLUID:
                    S.grid.fcnt[key] = ti.cast(1, S.grid.fdtype)
            elif not gone:
                if k == FLUID:
                    report(S.stats, BAD_LEAK, p.id[i])
                p.kind[i] = ti.cast(OUT, p.kind.dtype)
                ti.atomic_add(S.stats[None].leaked, 1)
        S.grid.key[i] = key
        ti.atomic_add(S.grid.cnt[key], 1)

    @ti.func
    def gather(self, c, dt):
        """Loop 4: cell c's particles in id order into the sorted copy, with their evaluation
        state: predicted velocity and density, Tait pressure (paper 000 eq. 11), 1/rho."""
        S = self.S
        S.grid.sort_cell(c, S.p.id)
        t = S.tmp
        for a in range(S.grid.start[c], S.grid.start[c + 1]):
            src = S.grid.order[a]
            for fp, ft in ti.static(S.pairs):
                ft[a] = fp[src]
            k = t.kind[a]
            if k == FLUID:
                t.ve[a] = t.v[a] + 0.5 * dt * t.a[a]
                t.rhoe[a] = t.rho[a] + 0.5 * dt * t.drho[a]
            elif k >= 0:
                t.ve[a] = t.v[a]
                re = t.rho[a]
                for m in ti.static(S.hooks["prepare"]):
                    re = m.prepare(S, a, re, dt)
                t.rhoe[a] = re
            mt = ti.cast(t.mat[a], ti.i32)  # a byte on the CPU; an index here
            t.p[a] = tait(t.rhoe[a], S.mat.rho0[mt], S.mat.B[mt])
            t.ir[a] = 1.0 / t.rhoe[a]
            if ti.static(self.once):
                self.pair_once.clear(a)

    @ti.func
    def fluid_pair(self, i, j, r, r2, acc: ti.template()):
        """All enabled terms for fluid particle i from neighbour j, unrolled at compile time."""
        S = self.S
        nb = self.neighbour_view(i, j, r, r2, acc)
        for m in ti.static(S.hooks["pair"]):
            m.pair(S, i, j, r, r2, nb, acc)

    @ti.func
    def neighbour_view(self, i, j, r, r2, acc: ti.template()):
        """How fluid particle i sees neighbour j: its state, the kernel gradient, v_ij."""
        S = self.S
        s = S.tmp
        nb = ti.Struct(
            kj=s.kind[j],
            rho_j=s.rhoe[j],
            ir_j=s.ir[j],
            p_j=s.p[j],
            q=0.0,
            m_j=0.0,
            vol_j=0.0,
            ie=0.0,
            gw=ti.Vector([0.0, 0.0]),
            v_ij=ti.Vector([0.0, 0.0]),
            v_visc=ti.Vector([0.0, 0.0]),
        )
        for m in ti.static(S.hooks["view"]):
            m.view(S, i, j, r, r2, nb, acc)
        nb.q = ti.sqrt(r2) * S.inv_h
        nb.ie = 1.0 / (r2 + S.eta2)  # one division per pair, shared by the terms that need it
        nb.gw = S.g_scale * S.K.fshape(nb.q) * r
        nb.m_j = s.m[j]
        nb.vol_j = nb.m_j * nb.ir_j
        nb.v_ij = acc.vi - s.ve[j]
        nb.v_visc = nb.v_ij
        return nb

    @ti.func
    def forces(self, i, dt, mx: ti.template()):  # noqa: C901 (ti.static branches, as advance)
        """Loop 5 for one particle: the neighbour pass and the closing half kick; raises the
        block's maxima mx."""
        S = self.S
        prm = S.prm[None]
        t = S.tmp
        for fp, ft in ti.static(S.pairs):
            fp[i] = ft[i]
        k = t.kind[i]
        if k == FLUID:
            mi = ti.cast(t.mat[i], ti.i32)
            acc = self.Acc(0)
            acc.vi, acc.rhoi, acc.pi, acc.inv_rhoi = t.ve[i], t.rhoe[i], t.p[i], t.ir[i]
            acc.mui, acc.mat = S.mat.mu[mi], mi
            for m in ti.static(S.hooks["init_acc"]):
                m.init_acc(S, i, acc)
            full = False
            acc_s = self.Acc(0)
            if ti.static(self.once):
                self.pair_once.load(i, acc)  # the pair passes' sums
            elif ti.static(bool(S.dual)):
                acc_s = acc  # a copy: the slots the advection-rate hooks read
                full = S.dual.sums(S, i, acc, acc_s)
            else:
                S.grid.for_neighbours(t, i, t.x[i], self.fluid_pair, acc, S.lanes)
            a = acc.a + prm.g
            for m in ti.static(S.hooks["body_force"]):
                a = m.body_force(S, i, mi, a)
            v = t.v[i] + 0.5 * dt * a
            for m in ti.static(S.hooks["relax"]):
                v = m.relax(S, i, mi, v, dt)
            rho = t.rho[i] + 0.5 * dt * acc.drho
            S.p.a[i] = a
            S.p.drho[i] = acc.drho
            S.p.v[i] = v
            S.p.rho[i] = rho
            pt = ti.Struct(a=a, v=v, rho=rho, **self._module_max0)
            for m in ti.static(S.fast["finish"]):
                m.finish(S, i, mi, acc, pt)
            if full:
                for m in ti.static(S.slow["finish"]):
                    m.finish(S, i, mi, acc_s, pt)
            else:
                for m in ti.static(S.slow["hold"]):
                    m.hold(S, i, mi, pt)
            for k in ti.static(self._module_max):
                mx[k] = ti.max(mx[k], pt[k])
            mx.amax2 = ti.max(mx.amax2, a.dot(a))
            dev = ti.abs(rho / S.mat.rho0[mi] - 1.0)
            mx.rhodev = ti.max(mx.rhodev, dev)
            code = fluid_code(a, rho, pt.v.dot(pt.v), dev, prm.c0, prm.band)
            if ti.static(S.physics.spray):
                if code == BAD_DENSITY:
                    code = BAD_NONE  # spray: the next step removes it (zones.Spray), up to its limit
            if code != BAD_NONE:
                report(S.stats, code, t.id[i])
        elif k >= 0:
            for m in ti.static(S.hooks["boundary_pass"]):
                m.boundary_pass(S, i, dt)

    @ti.func
    def force_block(self, b, dt):
        """Loop 5 over block b of particles; its maxima into bmax[b] (the CPU) or the stats."""
        S = self.S
        mx = self.MaxT(0)
        for i in range(b * self.blk, ti.min((b + 1) * self.blk, S.n)):
            self.forces(i, dt, mx)
        if ti.static(S.cpu):
            self.bmax[b] = mx
        else:
            for k in ti.static(self._maxima):
                ti.atomic_max(S.stats[None][k], mx[k])

    # ------------------------------------------------------------------ the step
    @ti.kernel
    def step(self, k: ti.i32, fit: ti.i32, pd: ti.f64, pv: ti.f64, stop: ti.f64):  # noqa: C901 (one kernel: the step's loops in order)
        """One step; writes the next step's dt into dtlog[k] and the health code into its
        slot_health (no value returned: a return waits for the device). Where the paddle module
        is on, its displacement and rate at the step's end: pd, pv as given (fit 0; the launch's
        arguments, not a launch of their own), or (fit 1) the Chebyshev series in pfit over the
        batch's span, at the time the batch's steps have taken so far (batch.py, series_fit).
        Step k > 0 of a batch parks (changes nothing) once the batch's steps have taken `stop`
        seconds or the health has gone bad: the host launches more steps than an output needs
        and reads the log once, at the output (access.py, step_ahead). Scalar arguments: a
        vector argument costs about 50 us a launch on the CPU."""
        S = self.S
        dt = S.prm[None].dt
        tau = dt  # the batch's time at this step's end
        if k > 0:
            tau += self.ptau[None]
        go = 1
        if k > 0 and (self.ptau[None] >= ti.cast(stop, S.real) or S.stats[None].bad_code != BAD_NONE):
            go = 0
        self.live[None] = go
        if go:
            self.ptau[None] = tau
            self.dtlog[self.slot_taken] = ti.cast(k + 1, S.real)
            if ti.static(S.table.has("pd")):
                if fit == 0:
                    S.prm[None].pd = ti.cast(pd, S.real)
                    S.prm[None].pv = ti.cast(pv, S.real)
                else:
                    motion = series_at(self.pfit, tau)
                    S.prm[None].pd = motion[0]
                    S.prm[None].pv = motion[1]
        ncell = S.grid.ncells
        for i in range(S.n):
            if go:
                self.advance(i, dt)
        if ti.static(S.cpu):
            ti.loop_config(serialize=True)
            for _ in range(1):
                if go:
                    S.grid.prefix()
                    if ti.static(self.once):
                        self.pair_once.zones()
        else:  # the same integers in three passes: one thread over every cell starves a GPU
            for b in range(S.grid.nscan):
                if go:
                    S.grid.block_total(b)
            ti.loop_config(serialize=True)
            for _ in range(1):
                if go:
                    S.grid.block_offsets()
            for b in range(S.grid.nscan):
                if go:
                    S.grid.block_prefix(b)
        for i in range(S.n):
            if go:
                S.grid.scatter(i)
        for c in range(ncell + 1):
            if go:
                self.gather(c, dt)
        if ti.static(self.once):
            for u in range(pairs.ZONES // 2 * pairs.LANE):  # the even zones, then the odd ones
                if go:
                    self.pair_once.phase(u, 0)
            for u in range(pairs.ZONES // 2 * pairs.LANE):
                if go:
                    self.pair_once.phase(u, 1)
        for b in range(self.nblk):
            if go:
                self.force_block(b, dt)
        # light loops on one CPU thread: a parallel loop's wake-up cost more than zeroing the cells
        # (measured: 0.12 ms a step at 8e3 cells, 4 % of a dam-break step at dx 0.015)
        ti.loop_config(serialize=S.cpu)
        for c in range(ncell + 2):
            if go:
                S.grid.fcnt[c] = ti.cast(0, S.grid.fdtype)
        ti.loop_config(serialize=True)
        for _ in range(1):  # one serial task after the parallel loops
            if go:
                for b in range(self.nblk if ti.static(S.cpu) else 0):
                    for k in ti.static(self._maxima):
                        S.stats[None][k] = ti.max(S.stats[None][k], self.bmax[b][k])
                next_dt(S)
                self.dtlog[k] = S.prm[None].dt
            self.dtlog[self.slot_health] = ti.cast(S.stats[None].bad_code, S.real)
