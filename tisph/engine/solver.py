"""The WCSPH solver: a case's enabled modules composed over its particles. The solver holds the
parts and the run's Python API (access.py); each part keeps its own state:

  the particle store (store.py): the particles' fields, their sorted copy, the backup
  the parameter table (table.py): the runtime parameters, the material table, the statistics
  the grid (grid.py): the cells, the sort, the neighbour loops
  the stepper (stepper.py): one time step as one fused kernel, and its log on the device

Inside the step kernel the modules' hooks take the kernel view S (view.py), not the solver, and
reach the parts through it: S.p and S.tmp (the store's), S.prm, S.mat and S.stats (the table's),
S.grid.
"""

import taichi as ti

from ..hooks.health import BAD_NONE
from ..hooks.module import HOOKS
from ..runtime import blocks
from ..settings.config import Physics
from . import state as st_mod
from .access import SolverAPI
from .batch import BATCH, BATCH_CPU, READ_ELEMENTS
from .drive import CurrentAPI, DeviceDrive
from .enabled import enabled_modules
from .grid import LANE_SUPPORT, WHOLE_CELL, Grid
from .smoothing import get_kernel
from .stepper import Stepper
from .store import ParticleStore
from .table import ParamTable, Setup


@ti.data_oriented
class Solver(SolverAPI, CurrentAPI):
    def __init__(self, physics: Physics, particles, materials, domain, params: dict, outflow=(), container=None):
        """particles: ParticleSet; materials: list of dicts (rho0, B, viscosity and the modules'
        material keys); domain: ((xlo, ylo), (xhi, yhi)); params: dx, h, c0 and the modules'
        runtime parameters (missing ones take their one default, engine/table.py and the modules);
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
            big = 1e30  # float32-safe stand-in for an open side
            self.container = (
                max(x0 - tol, -big),
                max(y0 - tol, -big),
                min(x1 + tol, big),
                min(y1 + tol, big),
                min(top[0] if top else big, big),
            )
        self._build_fields(physics, domain)
        self._build_tables(params, materials)
        self.store.load(particles)
        for m in self.modules:
            m.setup(self)
        self._reset_stats()
        self.steps = 0
        self.time = 0.0
        self.rhodev_sum, self.rhodev_n, self.rhodev_p999 = 0.0, 0, 0.0  # the probe samples' (access.py)
        self._primed = False
        self._dt = None  # the next step's dt as the step kernel logged it (None: read prm)
        self.health = BAD_NONE  # the health code the last batch of steps read back
        self.health_read = False  # whether the last step_ahead read it (a single step: every 10th)

    def _build_fields(self, physics, domain):
        """The kernel's constants, the enabled modules and their hooks, the particle fields (the
        state and its sorted copy) and the cell grid."""
        self.K = get_kernel(physics.kernel)
        self.real = ti.lang.impl.get_runtime().default_fp
        self.bits = st_mod.types(self.real)["bits"]
        self.np_real = st_mod.float_type(self.real)
        # compile-time constants baked into the kernels
        self.inv_h = 1.0 / self.h
        self.w_scale = self.K.sigma / self.h**2
        self.g_scale = self.K.sigma / self.h**4
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
        support = self.K.support * self.h
        self.cpu = st_mod.on_cpu()  # the CPU-only paths below; a GPU build turns them off
        # the force pass's neighbour loops in vector lanes (grid.py): on the CPU (a GPU's threads
        # are its lanes), where every module with a neighbour task has them lane-safe, and the
        # support reaches LANE_SUPPORT spacings; their cells the whole support where it reaches
        # under WHOLE_CELL (rows of about 20-31 candidates at 2.6-3.2 dx, against 8-13 in cells of
        # half: the tunnel 1.35x, Mao's case 1.1-1.5x, paper 000's dam break 1.3-1.7x, the beach
        # 1.24-1.30x faster than the branch form with each pair once), else half of it (the default
        # scheme's 5 dx: 0.79-0.86x in cells of the whole) (docs/performance.md)
        tasks = [m for m in self.modules if m.has("pair") or m.has("view") or m.has("boundary_pass")]
        reach = support >= LANE_SUPPORT * self.dx
        self.lanes = bool(self.params.get("lanes", self.cpu and reach)) and all(m.lanes for m in tasks)
        cdiv = 1 if self.lanes and support < WHOLE_CELL * self.dx else 2
        self.grid = Grid(self.n, domain, support, physics.periodic_x, cdiv)
        self.domain = (tuple(float(v) for v in domain[0]), tuple(float(v) for v in domain[1]))
        self.lo, self.hi, self.period = self.grid.lo, self.grid.hi, self.grid.period
        self.support = self.grid.support

    def _build_tables(self, params, materials):
        """The parameter table (runtime parameters, materials, statistics), the stepper (the step
        kernel, its maxima, log and accumulator; each pair once where asked), the modules' own
        fields, then every table written at once."""
        # a held current's feedback (measure/control.py) run by the device (engine/drive.py): on a
        # GPU, where the host's reads of the mean velocity wait for it; the CPU keeps the host's
        # control, so its results stay as they were
        held = params.get("held_current")
        on_device = held is not None and bool(params.get("drive_series", not self.cpu))
        self.usum_block, nb = blocks(self.n)  # block sums of the mean velocity (drive.py)
        self.usum = ti.Vector.field(2, ti.f64, nb) if on_device or not self.cpu else None
        setup = Setup(self.dx, self.h, self.c0, materials, self.particles)
        self.table = ParamTable(self.modules, params, setup, self.real)
        self.prm, self.mat, self.stats = self.table.prm, self.table.mat, self.table.stats
        self.param_values = self.table.values
        self.cfl = self.table.setup.cfl
        self.stepper = Stepper(self, params.get("pair_once", False))
        self.pair_once = self.stepper.pair_once
        for m in self.modules:
            m.allocate(self)  # module fields that are not per particle, if any
        self.drive = DeviceDrive(self, held) if on_device else None
        self.table.write()  # every field exists now
        self.motion = params.get("motion")  # motion(t) -> (displacement, rate), for the paddle
        # a smooth paddle motion followed on the device by a series over a batch of steps
        # (batch.py, series_fit), which rounds differently from the host's motion(t) cast to f32:
        # on a GPU, where the host's value every step costs a wait for the device; on the CPU,
        # where it costs microseconds, the host's, so the CPU's results stay as they were
        self.paddle_series = bool(params.get("paddle_series", not self.cpu))
        self.read_elements = int(params.get("read_elements", READ_ELEMENTS if self.cpu else 0))
        # the run loop launches past an output and lets the steps after it park (stepper.py) where
        # a read waits for the device; on the CPU a read costs 5 us, a parked step a launch
        self.park = bool(params.get("park", not self.cpu))
        self.batch = BATCH if self.park else BATCH_CPU

    def has_stat(self, name):
        return self.table.has_stat(name)

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
