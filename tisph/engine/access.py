"""The solver's Python API for the run loop: stepping, runtime inputs, state, checkpoints,
the backup of the last healthy state. A mixin of engine.solver.Solver."""

import numpy as np
import taichi as ti

from ..hooks.health import BAD_NONE
from ..io import OPTIONAL
from ..particles import FLUID, SPRAY
from .batch import STOP_SHORT, fit_steps
from .smoothing import CubicSpline2D


class SolverAPI:
    @property
    def optional_members(self):
        """The members of io.OPTIONAL this case carries (the suspended sand c)."""
        return tuple(k for k in OPTIONAL if k in self.members)

    @property
    def snapshot_members(self):
        """What a snapshot holds: the state, and the optional members this case carries."""
        return ("x", "v", "rho", "p", "m", "kind", "mat", "id") + self.optional_members

    # ------------------------------------------------------------------ stepping
    def prime(self):
        """Bin the particles and evaluate forces at t = 0 (a zero-length step) to get a^0, dt^0."""
        self.table.set_dt(0.0)
        self.stepper.step(0, 0, 0.0, 0.0, 0.0)  # the paddle at rest where it starts
        self._dt = float(self.stepper.dtlog[0])
        self._primed = True

    def step(self):
        """Advance one time step; returns the dt taken."""
        dt = self.dt
        self.step_ahead(1)
        return dt

    @property
    def moves_paddle(self):
        return self.motion is not None and self.table.has("pd")

    @property
    def steps_ahead_allowed(self):
        """Whether steps may run without the host between them: not where the paddle's motion
        is more than a smooth function of time (a measured series, or the active absorption,
        which integrates its correction step by step), which needs each step's time; nor on
        the CPU, where the host gives the paddle every step (self.paddle_series)."""
        return not self.moves_paddle or (self.paddle_series and bool(getattr(self.motion, "smooth", False)))

    @property
    def dt_bound(self):
        """No step is longer than this: the acoustic limit cfl h / c0, the user's cap dt_max and
        the laminar viscous limit (engine/limits.py; the viscous signal, the force and the other
        limits only shorten a step), with f32's rounding."""
        v = self.param_values
        bound = min(float(v["cfl"]) * self.h / self.c0, float(v["dt_max"]))
        if self.physics.laminar_viscosity and "dt_visc" in v:
            bound = min(bound, float(v["dt_visc"]))
        return bound * (1.0 + 1e-5)

    def step_ahead(self, n=1, until=None):
        """Advance n steps (1 to self.batch) with one read of the device at the end: each
        step's dt stays on the device until then (the step kernel takes the dt the one before
        chose). Given `until` (seconds from now), the steps after the one that reaches it park
        (stepper.py, step): the host may launch more than it needs. A step after the health has
        gone bad parks too. Time, the step count and the health code (self.health) are current
        on return. A paddle follows a Chebyshev series of its motion over the batch
        (batch.series_fit); where it cannot (steps_ahead_allowed) n must be 1, and where the
        series does not hold fewer steps are taken (batch.fit_steps). A held current run by the device (drive.py)
        follows its law's series likewise, its control launched after each control step.
        Returns the steps taken."""
        if not self._primed:
            self.prime()
        self.dt  # the step's dt, read once after a restart
        if not 1 <= n <= self.batch:
            raise ValueError(f"step_ahead takes 1 to {self.batch} steps, not {n}")
        if n > 1 and not self.steps_ahead_allowed:
            raise ValueError("a paddle moved from the host steps one at a time")
        fit = None
        if n > 1 and self.moves_paddle:  # where no series holds, this step alone, its paddle from the host
            n, fit = fit_steps(self.motion, self.time, n, self.dt_bound)
        drive = self.drive
        if drive is not None and (self.steps + n) // drive.every > self.steps // drive.every:
            n = drive.plan(self.time, n, self.dt_bound, self._dt)  # a control step in the batch
        if fit is None:  # the kernel moves the paddle to t + dt
            args = (0,) + self._paddle_at(self.time + self._dt)
        else:
            self.stepper.pfit.from_numpy(np.array(fit, dtype=self.np_real))
            args = (1, 0.0, 0.0)
        # the device's f32 sum of the batch's steps may run ahead of the host's f64 one: it stops
        # a little short, so no step runs past the one that reaches `until` (a step short costs
        # one more batch)
        args += (STOP_SHORT * until if until is not None else 1e30,)
        step = self.stepper.step
        for k in range(n):
            step(k, *args)
            self.steps += 1
            for m in self.hooks["after_step"]:
                m.after_step(self)  # a parked step's after_step parks too (shepard.py)
            if drive is not None and self.steps % drive.every == 0:
                drive.control()  # a parked step's parks too
        log = self._read_log(n, until is not None)
        self.steps += len(log) - n
        for dt in log:  # the dt each step took, summed in step order
            self.time += self._dt
            self._dt = float(dt)
        return len(log)  # fewer than asked where the paddle's series did not hold, or steps parked

    def _read_log(self, n, parking):
        """The dt of each step the batch of n took, and the health code: element by element on
        the CPU for a short batch (5 us a read), else in one transfer."""
        log, taken = self.stepper.dtlog, self.stepper.slot_taken
        if n <= self.read_elements:
            self.health_read = False
            if n > 1 or parking or self.steps % 10 == 0:  # a single step: the health every 10 steps
                self.read_health()
            # every step taken unless some parked: a read saved
            return [log[k] for k in range(int(log[taken]) if parking or self.health else n)]
        log = log.to_numpy()  # the batch's one transfer, the health and the steps taken with it
        self.health_read = True
        self.health = int(log[self.stepper.slot_health])
        return log[: int(log[taken])]

    def read_health(self):
        """The health code as the last step left it (one read of the device)."""
        self.health = int(self.stepper.dtlog[self.stepper.slot_health])
        self.health_read = True
        return self.health

    def _paddle_at(self, t):
        """The paddle's displacement and rate at t for the step kernel (zeros where the host moves
        none; step_ahead takes one step at a time where it does)."""
        if self.moves_paddle:
            d, r = self.motion(t)
            return float(d), float(r)
        return 0.0, 0.0

    # ------------------------------------------------------------------ runtime inputs
    def set_drive(self, gx, gy=0.0):
        """The driving pressure gradient / rho_water of a periodic current (m/s2)."""
        if not self.physics.periodic_x:
            raise ValueError("set_drive needs a periodic case (the Drive module is off)")
        self.table.set_drive(float(gx), float(gy))

    def set_bed(self, dz, w):
        """The morphodynamic bed's displacement z_b - z_b0 and speed dz_b/dt per station."""
        m = self.module("moving_bed")
        if m is None:
            raise ValueError("set_bed needs physics.moving_bed (the MovingBed module is off)")
        m.set(dz, w)

    # ------------------------------------------------------------------ reading
    @property
    def dt(self):
        """The next step's dt (f32-rounded as the step kernel returns it)."""
        if self._dt is None:
            self._dt = float(np.float32(self.prm[None].dt))
        return self._dt

    def check(self):
        """None if the state is healthy, else (code, id of the first particle that went bad)."""
        st = self.stats[None]
        if st.bad_code != BAD_NONE:
            return int(st.bad_code), int(st.bad_idx)
        return None

    @property
    def max_density_error(self):
        """Largest |rho/rho0 - 1| of any fluid particle at any step so far."""
        return float(self.stats[None].rhodev)

    def sample_density_error(self, st):
        """Add one sample of the mean |rho/rho0 - 1| over the fluid particles of a state read
        (the outputs' probe samples); mean_density_error is their average over the run, and
        rhodev_p999 the largest 99.9th percentile of a sample (the 10th-largest value where a case
        has under 10,000 fluid particles, none under 100): the bulk's worst, which a breaking wave's impact on a few
        particles (the largest error, max_density_error) does not set."""
        fl = st["kind"] == FLUID
        if fl.any():
            rho0 = self.mat.rho0.to_numpy()[st["mat"][fl]]
            dev = np.abs(st["rho"][fl] / rho0 - 1.0)
            self.rhodev_sum += float(np.mean(dev))
            self.rhodev_n += 1
            if len(dev) >= 100:  # a bulk to speak of; the 10th-largest under 1e4 particles
                q = 100.0 * (1.0 - max(1e-3, 10.0 / len(dev)))
                self.rhodev_p999 = max(self.rhodev_p999, float(np.percentile(dev, q)))

    @property
    def mean_density_error(self):
        """Mean |rho/rho0 - 1| over the fluid particles, averaged over the probe samples so far."""
        return self.rhodev_sum / self.rhodev_n if self.rhodev_n else float("nan")

    @property
    def leaked(self):
        return int(self.stats[None].leaked)

    def state(self, names=("x", "v", "rho", "p", "kind", "mat", "m")):
        """Particle arrays ordered by particle id (the order the scene built them in)."""
        return self.store.by_id(names)

    def sample_velocity(self, points, mat=0, tke=False):
        """SPH velocity of fluid material `mat` at each point (n, 2), Shepard-normalised with the
        cubic spline of support 2h: sum V_j u_j W / sum V_j W; NaN where no such particle is
        within 2h. The engine's cells and the current state, no copy of it to the host
        (measure/field.velocity_at does the same from a state read: 30x slower at 2.8e4
        particles); in a periodic case the images across the seam count too. tke: also the k
        equation's k at each point, interpolated alike in the same pass; returns (u, k)."""
        if tke and "kt" not in self.members:
            raise ValueError("sampling k needs the k equation's kt (numerics.turbulence = 'k_equation')")
        if not self._primed:
            self.prime()
        pts = np.ascontiguousarray(np.asarray(points, np.float64).reshape(-1, 2))
        out = np.zeros((len(pts), 4), np.float64)
        if len(pts):
            self._sample(pts, out, int(mat), bool(tke))
        ok = out[:, 2] > 0
        u = np.full((len(pts), 2), np.nan)
        u[ok] = out[ok, :2] / out[ok, 2:3]
        if not tke:
            return u
        k = np.full(len(pts), np.nan)
        k[ok] = out[ok, 3] / out[ok, 2]
        return u, k

    def sample_tke(self, points, mat=0):
        """The k equation's turbulent kinetic energy at each point, as sample_velocity(tke=True)."""
        return self.sample_velocity(points, mat, tke=True)[1]

    def field_bytes(self):
        """Bytes the particle and grid fields take on the device (from their shapes and types)."""
        return self.store.nbytes() + self.grid.nbytes()

    def neighbour_stats(self, lanes=False):
        """Per particle id: how many neighbours the cell grid finds, and the sum of their ids; with
        lanes, as the force pass's vector lanes visit them (grid.py)."""
        if not self._primed:
            self.prime()
        cnt = np.zeros(self.n, np.int32)
        ids = np.zeros(self.n, np.int32)
        self._neighbour_stats(cnt, ids, bool(lanes))
        return cnt, ids

    # ------------------------------------------------------------------ checkpoints and backup
    def raw_state(self):
        """Everything needed to continue bit for bit: every member in the current sorted order."""
        d = self.store.arrays()
        for m in self.modules:  # a module's runtime fields (the moving bed's displacement)
            for k, f in getattr(m, "state_fields", {}).items():
                d[f"module.{m.name}.{k}"] = f.to_numpy()
        st = self.stats[None]
        scal = dict(
            time=self.time,
            steps=self.steps,
            dt=self.table.get("dt"),
            leaked=int(st.leaked),
            n=self.n,
            primed=int(self._primed),
            rhodev=float(st.rhodev),
            rhodev_sum=self.rhodev_sum,
            rhodev_n=self.rhodev_n,
            rhodev_p999=self.rhodev_p999,
            params=self.table.snapshot(),
        )
        return d, scal

    def load_raw_state(self, arrays, scalars):
        if int(scalars["n"]) != self.n:
            raise ValueError(f"checkpoint holds {int(scalars['n'])} particles, this case builds {self.n}")
        self.store.write(arrays)
        for m in self.modules:
            for k, f in getattr(m, "state_fields", {}).items():
                if f"module.{m.name}.{k}" in arrays:
                    f.from_numpy(arrays[f"module.{m.name}.{k}"])
        if "params" in scalars:  # the runtime inputs as they were (drive, paddle), not their defaults
            self.table.restore(scalars["params"])
        self.time = float(scalars["time"])
        self.steps = int(scalars["steps"])
        self.table.set_dt(float(scalars["dt"]))
        self._dt = None
        self.stats[None].leaked = int(scalars["leaked"])
        if self.physics.spray:  # the spray removed so far counts towards its cap
            self.stats[None].spray = int(np.sum(np.asarray(arrays["kind"]) == SPRAY))
        self.stats[None].rhodev = float(scalars.get("rhodev", 0.0))
        self.rhodev_sum = float(scalars.get("rhodev_sum", 0.0))
        self.rhodev_n = int(scalars.get("rhodev_n", 0))
        self.rhodev_p999 = float(scalars.get("rhodev_p999", 0.0))
        self._primed = bool(int(scalars["primed"]))

    def enable_backup(self):
        """Keep a device-side copy of the last healthy state (for the final snapshot of a run
        that goes unstable); costs one copy of the particle fields per backup() call."""
        if self.store.bak is None:
            self.store.enable_backup()
            self.bak_time, self.bak_steps = self.time, self.steps

    def backup(self):
        self.store.backup()
        self.bak_time, self.bak_steps = self.time, self.steps

    def backup_state(self, names):
        """The backed-up state, ordered by particle id."""
        return self.store.by_id(names, self.store.bak)

    # ------------------------------------------------------------------ kernels of the API
    @ti.kernel
    def _neighbour_stats(self, cnt: ti.types.ndarray(), idsum: ti.types.ndarray(), lanes: ti.template()):
        for i in range(self.n):
            if self.p.kind[i] >= 0:
                acc = ti.Struct(n=0, ids=0)
                self.grid.for_neighbours(self.p, i, self.p.x[i], self.count_pair, acc, lanes)
                cnt[self.p.id[i]] = acc.n
                idsum[self.p.id[i]] = acc.ids

    @ti.kernel
    def _sample(
        self,
        pts: ti.types.ndarray(dtype=ti.f64, ndim=2),
        out: ti.types.ndarray(dtype=ti.f64, ndim=2),
        mat: ti.i32,
        with_k: ti.template(),
    ):
        for k in range(pts.shape[0]):
            acc = ti.Struct(u=ti.Vector([0.0, 0.0], ti.f64), w=ti.f64(0.0), k=ti.f64(0.0), mat=mat)
            xk = ti.Vector([pts[k, 0], pts[k, 1]], self.real)
            if ti.static(with_k):
                self.grid.for_neighbours(self.p, k, xk, self.sample_pair_k, acc)
            else:
                self.grid.for_neighbours(self.p, k, xk, self.sample_pair, acc)
            out[k, 0] = acc.u[0]
            out[k, 1] = acc.u[1]
            out[k, 2] = acc.w
            out[k, 3] = acc.k

    @ti.func
    def sample_pair(self, k, j, r, r2, acc: ti.template()) -> ti.f64:
        """Adds particle j's Shepard weight V_j W and weighted velocity to acc (0: not fluid of
        material acc.mat); returns the weight."""
        w = ti.f64(0.0)
        if self.p.kind[j] == FLUID and ti.cast(self.p.mat[j], ti.i32) == acc.mat:
            w = ti.cast(CubicSpline2D.shape(ti.sqrt(r2) * self.inv_h) * self.p.m[j] / self.p.rho[j], ti.f64)
            acc.w += w
            acc.u += w * ti.cast(self.p.v[j], ti.f64)
        return w

    @ti.func
    def sample_pair_k(self, k, j, r, r2, acc: ti.template()):
        w = self.sample_pair(k, j, r, r2, acc)
        acc.k += w * ti.cast(self.p.kt[j], ti.f64)

    @ti.func
    def count_pair(self, i, j, r, r2, acc: ti.template()):
        if j != i and r2 < self.support * self.support:  # the lanes visit every candidate of a row
            acc.n += 1
            acc.ids += self.p.id[j]
