"""A periodic current's mean velocity (CurrentAPI, a mixin of engine.solver.Solver), and a held
current's feedback run by the device (DeviceDrive; measure/control.py, HeldCurrent): the tunnel's
and the pipeline's drive on a GPU, where the host's control every 10 steps read the water's mean
velocity back (a wait for the device) and cut every batch of steps at the control step.

The host fits the current's law over each batch as it fits a paddle's motion (batch.series_fit,
uploaded with the batch), and after each control step the solver launches control(): the mean
velocity summed by blocks in one order (_block_u, as the host's mean_velocity sums it on a GPU),
the law at the step's time and PIDrive.update's arithmetic in f64, the drive written into the
parameter table. The controller's state (integral, time of the last update, value) stays on
the device; the host reads it into the case's PIDrive only where something is written (a probe, a
checkpoint: sync) and writes it back on a restart (load).

Its results differ from the host's in the last digits (the law's series, the step's time as the
batch's f32 sum), so the CPU keeps the host's control unless a run asks for this (the solver's
drive_series parameter: the traffic count, the tests)."""

import numpy as np
import taichi as ti

from ..particles import FLUID
from .batch import PFIT, constant_fit, fit_steps, series_at, series_fit

INTEGRAL, T, VALUE = 0, 1, 2


class CurrentAPI:
    def mean_velocity(self, mat=0, above=-1e30):
        """Mean x-velocity of the fluid particles of material `mat` higher than y = above (NaN if
        there are none), summed on the device in one order."""
        su, n = self._sum_u(int(mat), float(above))
        return float(su) / n if n else float("nan")

    def sync_drive(self):
        """A held current run by the device (DeviceDrive): its controller's state into the
        case's PIDrive, before anything reads it (a probe, a checkpoint); nothing elsewhere."""
        if self.drive is not None:
            self.drive.sync()

    def load_drive(self):
        """The case's PIDrive onto the device, where it runs the drive (a restart)."""
        if self.drive is not None:
            self.drive.load()

    @ti.kernel
    def _sum_u(self, mat: ti.i32, above: ti.f64) -> ti.types.vector(2, ti.f64):
        """(sum of u, count) over the selected particles, in one order whatever the threads, so
        the drive's feedback restarts bit for bit: serially on the CPU; on a GPU, where one thread
        over every particle costs milliseconds, by blocks of particles (runtime.blocks), then over
        the blocks' sums."""
        s = ti.f64(0.0)
        n = ti.f64(0.0)
        if ti.static(self.cpu):
            ti.loop_config(serialize=True)
            for i in range(self.n):
                if self._drives(i, mat, above):
                    s += ti.cast(self.p.v[i][0], ti.f64)
                    n += 1.0
        else:
            for b in range(self.usum.shape[0]):
                self.usum[b] = self._block_u(b, mat, above)
            ti.loop_config(serialize=True)
            for _ in range(1):
                su = self._usum_total()
                s, n = su[0], su[1]
        return ti.Vector([s, n])

    @ti.func
    def _block_u(self, b, mat, above):
        """(sum of u, count) over block b of the particles (runtime.blocks) that _drives selects."""
        acc = ti.Vector([0.0, 0.0], ti.f64)
        for i in range(b * self.usum_block, ti.min((b + 1) * self.usum_block, self.n)):
            if self._drives(i, mat, above):
                acc += ti.Vector([ti.cast(self.p.v[i][0], ti.f64), 1.0], ti.f64)
        return acc

    @ti.func
    def _usum_total(self):
        """The blocks' (sum of u, count) summed in block order (one thread)."""
        su = ti.Vector([0.0, 0.0], ti.f64)
        for b in range(self.usum.shape[0]):
            su += self.usum[b]
        return su

    @ti.func
    def _drives(self, i, mat, above):
        return self.p.kind[i] == FLUID and ti.cast(self.p.mat[i], ti.i32) == mat and self.p.x[i][1] > above


@ti.data_oriented
class DeviceDrive:
    def __init__(self, solver, held):
        """solver: its parameter table, stepper and block sums (usum) built; held: the case's
        HeldCurrent."""
        self.S, self.held = solver, held
        self.mat, self.above, self.Tc = int(held.mat), float(held.above), float(held.ctl.Tc)
        self.every = int(held.every)
        self.state = ti.field(ti.f64, 3)  # INTEGRAL, T, VALUE
        self.fit = ti.field(ti.f64, PFIT + 1)  # the law's series over the batch, then its start time
        self.stale = False  # whether the device's state is ahead of the host's PIDrive
        self.load()

    def load(self):
        """The case's PIDrive onto the device (the start, a restart)."""
        c = self.held.ctl
        self.state.from_numpy(np.array([c.integral, c.t, c.value], np.float64))
        self.stale = False

    def sync(self):
        """The device's state into the case's PIDrive, where a control step ran since the last."""
        if self.stale:
            c = self.held.ctl
            c.integral, c.t, c.value = (float(v) for v in self.state.to_numpy())
            self.stale = False

    def plan(self, t0, n, step_bound, dt):
        """Upload the law's series over a batch of n steps from t0 (step_bound: the longest a step
        can be); returns n, or fewer where no series holds over n (batch.fit_steps; over one step,
        whose dt is known, a series or the law's value at its end)."""
        held = self.held
        n, fit = fit_steps(held.law, t0, n, step_bound, held.breaks)
        if fit is None:
            fit = series_fit(held.law, t0, dt, held.breaks) or constant_fit(held.law(t0 + dt), dt)
        self.fit.from_numpy(np.array(fit + (t0,), np.float64))
        return n

    def control(self):
        """The control after a control step; the host's PIDrive is behind the device's from here."""
        self._control()
        self.stale = True

    @ti.kernel
    def _control(self):
        """After a control step (a parked step's launch changes nothing): the selected water's
        mean x-velocity, e = target - mean at the step's time t, integral += e (t - t_last),
        drive = feedforward + e / Tc + integral / Tc^2 (measure/control.py, PIDrive)."""
        S = self.S
        for b in range(S.usum.shape[0]):
            if S.stepper.live[None]:
                S.usum[b] = S._block_u(b, self.mat, self.above)
        ti.loop_config(serialize=True)
        for _ in range(1):
            if S.stepper.live[None]:
                su = S._usum_total()
                if su[1] > 0:
                    tau = ti.cast(S.stepper.ptau[None], ti.f64)
                    law = series_at(self.fit, tau)
                    e = law[0] - su[0] / su[1]
                    t = self.fit[PFIT] + tau
                    self.state[INTEGRAL] += e * (t - self.state[T])
                    self.state[T] = t
                    value = law[1] + e / self.Tc + self.state[INTEGRAL] / self.Tc**2
                    self.state[VALUE] = value
                    S.prm[None].drive = ti.Vector([ti.cast(value, S.real), 0.0])
