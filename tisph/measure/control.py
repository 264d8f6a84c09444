"""Feedback control of a periodic current through its driving pressure gradient."""


class PIDrive:
    """Proportional-integral feedback: drive = feedforward + e / Tc + (integral of e) / Tc^2, with
    e the target minus the measured velocity; Tc sets the response time. Written into the solver
    with set_drive (the Drive module's runtime parameter)."""

    def __init__(self, Tc, start=0.0):
        self.Tc = Tc
        self.integral = 0.0
        self.t = 0.0
        self.value = start

    def update(self, solver, error, feedforward):
        self.integral += error * (solver.time - self.t)
        self.t = solver.time
        self.value = feedforward + error / self.Tc + self.integral / self.Tc**2
        solver.set_drive(self.value)
        return self.value


class HeldCurrent:
    """A current held toward law(t) = (target velocity, feedforward drive) by PI feedback (self.ctl,
    a PIDrive) on the mean x-velocity of the water of material `mat` above y = `above`, every
    `every` steps. The host runs it (update, as a case's control) on the CPU; on a GPU the solver
    runs the same arithmetic on the device (engine/drive.py: a case gives it as the solver's
    held_current parameter), the law followed over each batch of steps by a series (its kinks in
    `breaks`), so the steps between outputs read nothing back. A subclass sets ctl and law."""

    mat, above, every, breaks = 0, -1e30, 10, ()
    ctl: PIDrive

    def law(self, t):
        raise NotImplementedError

    def update(self, s):
        u_t, feedforward = self.law(s.time)
        self.ctl.update(s, u_t - s.mean_velocity(self.mat, above=self.above), feedforward)
