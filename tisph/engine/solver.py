"""The WCSPH solver: composes the enabled modules into one fused Taichi kernel per time step.

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
  2. prefix sum over the cells (serial)
  3. scatter particle indices into their cells
  4. per cell: order by id, gather every member into the sorted copy, evaluation state
     (predicted velocity and density, Tait pressure, 1/rho)
  5a. where run.pair_once takes it (engine/pairs.py): each pair once, both particles' terms,
     in zones of cell rows, the even zones then the odd ones
  5. forces: each fluid particle's neighbour pass (the modules' pair hooks; with 5a, its sums),
     closing half kick, the modules' finish hooks, health, the maxima per block of particles;
     boundary particles' own pass (dynamic walls)
  6. the next time step (engine/limits.py)
"""
import taichi as ti

from ..hooks.health import BAD_DENSITY, BAD_LEAK, BAD_NONE, fluid_code, report
from ..hooks.module import HOOKS
from ..particles import FLUID, MOVING, OUT, OUTFLOW
from ..settings.config import Physics
from ..terms.pressure import tait
from . import pairs
from . import state as st_mod
from .access import SolverAPI
from .batch import BATCH, CHEB, READ_ELEMENTS, chebyshev
from .grid import Grid
from .kernels import get_kernel
from .limits import next_dt
from .pairs import PairOnce
from .registry import enabled_modules
from .store import ParticleStore

# The base slots of a fluid particle's accumulator (the modules add theirs).
ACC_CORE = {"a": "vec2", "drho": "real", "vi": "vec2", "rhoi": "real", "pi": "real", "inv_rhoi": "real",
            "mui": "real", "mat": "int", "kind": "int", "m": "real"}


@ti.data_oriented
class Solver(SolverAPI):
    def __init__(self, physics: Physics, particles, materials, domain, params: dict, outflow=(),
                 container=None):
        """particles: ParticleSet; materials: list of dicts (rho0, B, viscosity and the modules'
        material keys); domain: ((xlo, ylo), (xhi, yhi)); params: dx, h, c0 and the modules'
        runtime parameters (missing ones take their one default, engine/state.py and the modules);
        outflow: boxes (x0, y0, x1, y1) fluid leaves through; container: (x0, y0, x1, y1[, top])."""
        self.physics = physics
        self.n = len(particles)
        if self.n == 0:
            raise ValueError("no particles to simulate")
        self.particles, self.materials, self.params = particles, materials, params
        self.dx, self.h, self.c0 = float(params["dx"]), float(params["h"]), float(params["c0"])
        self.outflow = tuple(tuple(float(v) for v in z) for z in outflow)
        self.container = None
        if container is not None:
            x0, y0, x1, y1, *top = (float(v) for v in container)
            tol = 0.5 * self.dx
            big = 1e30   # float32-safe stand-in for an open side
            self.container = (max(x0 - tol, -big), max(y0 - tol, -big), min(x1 + tol, big),
                              min(y1 + tol, big), min(top[0] if top else big, big))
        self._build_fields(physics, domain)
        self._build_tables(params, materials)
        self.store.load(particles)
        for m in self.modules:
            m.setup(self)
        self._reset_stats()
        self.steps = 0
        self.time = 0.0
        self.rhodev_sum, self.rhodev_n, self.rhodev_p999 = 0.0, 0, 0.0   # the probe samples' (access.py)
        self._primed = False
        self._dt = None          # the next step's dt as the step kernel logged it (None: read prm)
        self.health = BAD_NONE   # the health code the last batch of steps read back
        self.health_read = False   # whether the last step_ahead read it (a single step: every 10th)

    def _build_fields(self, physics, domain):
        """The kernel's constants, the enabled modules and their hooks, the particle fields (the
        state and its sorted copy) and the cell grid."""
        self.K = get_kernel(physics.kernel)
        self.real = ti.lang.impl.get_runtime().default_fp
        self.np_real = st_mod.float_type(self.real)
        # compile-time constants baked into the kernels
        self.inv_h = 1.0 / self.h
        self.w_scale = self.K.sigma / self.h ** 2
        self.g_scale = self.K.sigma / self.h ** 4
        self.eta2 = 0.01 * self.h * self.h
        self.modules = enabled_modules(self)
        self.hooks = {k: [m for m in self.modules if m.has(k)] for k in HOOKS}
        # dual time stepping (physics/dual.py): the advection-rate modules' pair and finish hooks
        # sum into a second accumulator on the steps that evaluate them; their sums are held
        self.dual = self.module("dual_criteria")
        self.slow = {k: [m for m in v if self.dual and m.rate == "advection"] for k, v in self.hooks.items()}
        self.fast = {k: [m for m in v if m not in self.slow[k]] for k, v in self.hooks.items()}
        members = st_mod.core_members(self.real)
        for m in self.modules:
            members.update(m.fields(self.real))
        # the particles' fields are the store's (engine/store.py); the step kernel and the
        # modules' hooks reach them as p (the state) and tmp (the sorted copy)
        self.store = ParticleStore(members, st_mod.eval_members(self.real), self.n, self.np_real)
        self.members, self.p, self.tmp, self.pairs = self.store.members, self.store.p, self.store.tmp, self.store.pairs
        self.grid = Grid(self.n, domain, self.K.support * self.h, physics.periodic_x)
        self.domain = (tuple(float(v) for v in domain[0]), tuple(float(v) for v in domain[1]))
        self.lo, self.hi, self.period = self.grid.lo, self.grid.hi, self.grid.period
        self.support = self.grid.support

    def _build_tables(self, params, materials):
        """The runtime parameters and material table, the step's maxima and logs, the
        accumulator's type, the pair-once pass, the modules' own fields."""
        self.param_decl, self.param_values = st_mod.param_struct(self, self.modules, params, self.dx)
        self.cfl = float(self.param_values["cfl"])   # the viscosity cap reads it (materials below)
        mat_writes = st_mod.material_table(self, self.modules, materials)
        self.stat_decl = st_mod.stats_struct(self, self.modules)
        # the force pass's maxima: on the CPU per block of particles, reduced once on one thread
        # (no atomics in the pass; 1,024 blocks or more, so Taichi's CPU range-for deals them to
        # every thread); on a GPU per particle, by its hardware atomics
        self.maxima = dict(st_mod.CORE_MAXIMA)
        for m in self.modules:
            self.maxima.update(m.maxima)
        self.MaxT = ti.types.struct(**{k: st_mod.resolve(t, self.real) for k, t in self.maxima.items()})
        self.cpu = st_mod.on_cpu()   # the CPU-only paths below; a GPU build turns them off
        self.blk = max(1, self.n // 1024) if self.cpu else 1
        self.nblk = (self.n + self.blk - 1) // self.blk
        self.bmax = self.MaxT.field(shape=self.nblk if self.cpu else 1)
        # each step k of a batch writes the dt it chose into dtlog[k], and the health code into
        # the last slot: the host reads the batch back in one transfer (access.py, step_ahead)
        self.batch = BATCH
        self.dtlog = ti.field(self.real, shape=BATCH + 1)
        self.ptau = ti.field(self.real, shape=())   # time into a batch, for the paddle's series
        self.pfit = ti.field(self.real, shape=2 * CHEB + 3)   # its displacement's, its rate's, the span
        # the maxima a finish hook raises through pt (the pass itself raises amax2 and rhodev)
        self._module_max0 = {k: 0 if t == "int" else 0.0 for k, t in self.maxima.items()
                             if k not in ("amax2", "rhodev")}
        self._module_max, self._maxima = tuple(self._module_max0), tuple(self.maxima)
        acc = dict(ACC_CORE)
        for m in self.modules:
            acc.update(m.acc)
        self.acc_types = {k: st_mod.resolve(t, self.real) for k, t in acc.items()}
        self.Acc = ti.types.struct(**self.acc_types)
        # each pair once where asked (run.pair_once, runner/setup.py) and the modules allow it
        # (engine/pairs.py); otherwise the gather pass
        self.pair_once = (PairOnce(self) if params.get("pair_once", False) and pairs.applicable(self)
                          and self.dual is None else None)
        self.once = self.pair_once is not None
        for m in self.modules:
            m.allocate(self)          # module fields that are not per particle, if any
        st_mod.write_tables(self, mat_writes, self.param_values)   # every field exists now
        self.motion = params.get("motion")   # motion(t) -> (displacement, rate), for the paddle
        # a smooth paddle motion followed on the device by a series over a batch of steps
        # (batch.py, paddle_fit), which rounds differently from the host's motion(t) cast to f32:
        # on a GPU, where the host's value every step costs a wait for the device; on the CPU,
        # where it costs microseconds, the host's, so the CPU's results stay as they were
        self.paddle_series = bool(params.get("paddle_series", not self.cpu))
        self.read_elements = int(params.get("read_elements", READ_ELEMENTS if self.cpu else 0))

    def has_stat(self, name):
        return name in self.stat_decl

    def module(self, name):
        """The enabled module of that name, or None."""
        return next((m for m in self.modules if m.name == name), None)

    def _reset_stats(self):
        s = self.stats[None]
        s.amax2 = 0.0
        s.mumax = 0.0
        s.bad_code = 0
        s.bad_idx = 2**31 - 1
        s.rhodev = 0.0

    # ------------------------------------------------------------------ loop bodies
    @ti.func
    def advance(self, i, dt):  # noqa: C901 (ti.static branches, one a hook: only the case's are compiled)
        """Loop 1: drift and half kick, boundaries' motion, removals and checks, the cell key."""
        p = self.p
        k = p.kind[i]
        key = self.grid.ncells
        if k >= 0:
            if k == FLUID:
                drift = p.v[i]
                for m in ti.static(self.hooks["drift"]):
                    drift = m.drift(self, i, drift)
                p.x[i] = self.grid.wrap(p.x[i] + dt * drift + 0.5 * dt * dt * p.a[i])
                p.v[i] += 0.5 * dt * p.a[i]
                p.rho[i] += 0.5 * dt * p.drho[i]
            else:
                if k == MOVING:
                    if ti.static(len(self.hooks["move"]) > 0):
                        for m in ti.static(self.hooks["move"]):
                            m.move(self, i, dt)
                    else:
                        p.x[i] = self.grid.wrap(p.x[i] + dt * p.v[i])
                for m in ti.static(self.hooks["boundary_motion"]):
                    m.boundary_motion(self, i, k, dt)
                for m in ti.static(self.hooks["boundary_kick"]):
                    m.boundary_kick(self, i, dt)
            gone = False
            if ti.static(len(self.hooks["remove"]) > 0):
                if k == FLUID:
                    for m in ti.static(self.hooks["remove"]):
                        if not gone and m.remove(self, i):
                            gone = True   # parked as the module says: OUTFLOW, or SPRAY
                            p.kind[i] = ti.cast(ti.static(getattr(m, "kind_out", OUTFLOW)), p.kind.dtype)
            if ti.static(len(self.hooks["position_check"]) > 0):
                if k == FLUID and not gone:
                    for m in ti.static(self.hooks["position_check"]):
                        m.position_check(self, i)
            if not gone and self.grid.inside(p.x[i]):
                key = self.grid.key_of(p.x[i])
                if p.kind[i] == FLUID:
                    self.grid.fcnt[key] = ti.cast(1, self.grid.fdtype)
            elif not gone:
                if k == FLUID:
                    report(self.stats, BAD_LEAK, p.id[i])
                p.kind[i] = ti.cast(OUT, p.kind.dtype)
                ti.atomic_add(self.stats[None].leaked, 1)
        self.grid.key[i] = key
        ti.atomic_add(self.grid.cnt[key], 1)

    @ti.func
    def gather(self, c, dt):
        """Loop 4: cell c's particles in id order into the sorted copy, with their evaluation
        state: predicted velocity and density, Tait pressure (paper 000 eq. 11), 1/rho."""
        self.grid.sort_cell(c, self.p.id)
        t = self.tmp
        for a in range(self.grid.start[c], self.grid.start[c + 1]):
            src = self.grid.order[a]
            for fp, ft in ti.static(self.pairs):
                ft[a] = fp[src]
            k = t.kind[a]
            if k == FLUID:
                t.ve[a] = t.v[a] + 0.5 * dt * t.a[a]
                t.rhoe[a] = t.rho[a] + 0.5 * dt * t.drho[a]
            elif k >= 0:
                t.ve[a] = t.v[a]
                re = t.rho[a]
                for m in ti.static(self.hooks["prepare"]):
                    re = m.prepare(self, a, re, dt)
                t.rhoe[a] = re
            mt = ti.cast(t.mat[a], ti.i32)       # a byte on the CPU; an index here
            t.p[a] = tait(t.rhoe[a], self.mat_rho0[mt], self.mat_B[mt])
            t.ir[a] = 1.0 / t.rhoe[a]
            if ti.static(self.once):
                self.pair_once.clear(a)

    @ti.func
    def fluid_pair(self, i, j, r, r2, acc: ti.template()):
        """All enabled terms for fluid particle i from neighbour j, unrolled at compile time."""
        nb = self.neighbour_view(i, j, r, r2, acc)
        for m in ti.static(self.hooks["pair"]):
            m.pair(self, i, j, r, r2, nb, acc)

    @ti.func
    def neighbour_view(self, i, j, r, r2, acc: ti.template()):
        """How fluid particle i sees neighbour j: its state, the kernel gradient, v_ij."""
        s = self.tmp
        nb = ti.Struct(kj=s.kind[j], rho_j=s.rhoe[j], ir_j=s.ir[j], p_j=s.p[j], q=0.0, m_j=0.0, vol_j=0.0, ie=0.0,
                       gw=ti.Vector([0.0, 0.0]), v_ij=ti.Vector([0.0, 0.0]), v_visc=ti.Vector([0.0, 0.0]))
        for m in ti.static(self.hooks["view"]):
            m.view(self, i, j, r, r2, nb, acc)
        nb.q = ti.sqrt(r2) * self.inv_h
        nb.ie = 1.0 / (r2 + self.eta2)    # one division per pair, shared by the terms that need it
        nb.gw = self.g_scale * self.K.fshape(nb.q) * r
        nb.m_j = s.m[j]
        nb.vol_j = nb.m_j * nb.ir_j
        nb.v_ij = acc.vi - s.ve[j]
        nb.v_visc = nb.v_ij
        return nb

    @ti.func
    def forces(self, i, dt, mx: ti.template()):  # noqa: C901 (ti.static branches, as advance)
        """Loop 5 for one particle: the neighbour pass and the closing half kick; raises the
        block's maxima mx."""
        prm = self.prm[None]
        t = self.tmp
        for fp, ft in ti.static(self.pairs):
            fp[i] = ft[i]
        k = t.kind[i]
        if k == FLUID:
            mi = ti.cast(t.mat[i], ti.i32)
            acc = self.Acc(0)
            acc.vi, acc.rhoi, acc.pi, acc.inv_rhoi = t.ve[i], t.rhoe[i], t.p[i], t.ir[i]
            acc.mui, acc.mat = self.mat_mu[mi], mi
            for m in ti.static(self.hooks["init_acc"]):
                m.init_acc(self, i, acc)
            full = False
            acc_s = self.Acc(0)
            if ti.static(self.once):
                self.pair_once.load(i, acc)         # the pair passes' sums
            elif ti.static(bool(self.dual)):
                acc_s = acc   # a copy: the slots the advection-rate hooks read
                full = self.dual.sums(self, i, acc, acc_s)
            else:
                self.grid.for_neighbours(t, i, t.x[i], self.fluid_pair, acc)
            a = acc.a + prm.g
            for m in ti.static(self.hooks["body_force"]):
                a = m.body_force(self, i, mi, a)
            v = t.v[i] + 0.5 * dt * a
            for m in ti.static(self.hooks["relax"]):
                v = m.relax(self, i, mi, v, dt)
            rho = t.rho[i] + 0.5 * dt * acc.drho
            self.p.a[i] = a
            self.p.drho[i] = acc.drho
            self.p.v[i] = v
            self.p.rho[i] = rho
            pt = ti.Struct(a=a, v=v, rho=rho, **self._module_max0)
            for m in ti.static(self.fast["finish"]):
                m.finish(self, i, mi, acc, pt)
            if full:
                for m in ti.static(self.slow["finish"]):
                    m.finish(self, i, mi, acc_s, pt)
            else:
                for m in ti.static(self.slow["hold"]):
                    m.hold(self, i, mi, pt)
            for k in ti.static(self._module_max):
                mx[k] = ti.max(mx[k], pt[k])
            mx.amax2 = ti.max(mx.amax2, a.dot(a))
            dev = ti.abs(rho / self.mat_rho0[mi] - 1.0)
            mx.rhodev = ti.max(mx.rhodev, dev)
            code = fluid_code(a, rho, pt.v.dot(pt.v), dev, prm.c0, prm.band)
            if ti.static(self.physics.spray):
                if code == BAD_DENSITY:
                    code = BAD_NONE       # spray: the next step removes it (zones.Spray), up to its limit
            if code != BAD_NONE:
                report(self.stats, code, t.id[i])
        elif k >= 0:
            for m in ti.static(self.hooks["boundary_pass"]):
                m.boundary_pass(self, i, dt)

    # ------------------------------------------------------------------ the step
    @ti.kernel
    def _step(self, k: ti.i32, fit: ti.i32, pd: ti.f64, pv: ti.f64):  # noqa: C901 (one kernel: the step's loops in order)
        """One step; writes the next step's dt into dtlog[k] and the health code into the log's
        last slot (no value returned: a return waits for the device). Where the paddle module
        is on, its displacement and rate at the step's end: pd, pv as given (fit 0; the launch's
        arguments, not a launch of their own), or (fit 1) the Chebyshev series in pfit over the
        batch's span, at the time the batch's steps have taken so far (batch.py, paddle_fit).
        Four scalar arguments: a vector argument costs about 50 us a launch on the CPU."""
        dt = self.prm[None].dt
        if ti.static("pd" in self.param_decl):
            if fit == 0:
                self.prm[None].pd = ti.cast(pd, self.real)
                self.prm[None].pv = ti.cast(pv, self.real)
            else:
                tau = dt
                if k > 0:
                    tau += self.ptau[None]
                self.ptau[None] = tau
                x = 2.0 * tau / self.pfit[2 * CHEB + 2] - 1.0
                self.prm[None].pd = chebyshev(self.pfit, 0, x)
                self.prm[None].pv = chebyshev(self.pfit, CHEB + 1, x)
        ncell = self.grid.ncells
        for i in range(self.n):
            self.advance(i, dt)
        ti.loop_config(serialize=True)
        for _ in range(1):
            self.grid.prefix()
            if ti.static(self.once):
                self.pair_once.zones()
        for i in range(self.n):
            self.grid.scatter(i)
        for c in range(ncell + 1):
            self.gather(c, dt)
        if ti.static(self.once):
            for u in range(pairs.ZONES // 2 * pairs.LANE):   # the even zones, then the odd ones
                self.pair_once.phase(u, 0)
            for u in range(pairs.ZONES // 2 * pairs.LANE):
                self.pair_once.phase(u, 1)
        for b in range(self.nblk):
            mx = self.MaxT(0)
            for i in range(b * self.blk, ti.min((b + 1) * self.blk, self.n)):
                self.forces(i, dt, mx)
            if ti.static(self.cpu):
                self.bmax[b] = mx
            else:
                for k in ti.static(self._maxima):
                    ti.atomic_max(self.stats[None][k], mx[k])
        # light loops on one CPU thread: a parallel loop's wake-up cost more than zeroing the cells
        # (measured: 0.12 ms a step at 8e3 cells, 4 % of a dam-break step at dx 0.015)
        ti.loop_config(serialize=self.cpu)
        for c in range(ncell + 2):
            self.grid.fcnt[c] = ti.cast(0, self.grid.fdtype)
        ti.loop_config(serialize=True)
        for _ in range(1):   # one serial task after the parallel loops
            for b in range(self.nblk if ti.static(self.cpu) else 0):
                for k in ti.static(self._maxima):
                    self.stats[None][k] = ti.max(self.stats[None][k], self.bmax[b][k])
            next_dt(self)
            self.dtlog[k] = self.prm[None].dt
            self.dtlog[BATCH] = ti.cast(self.stats[None].bad_code, self.real)
