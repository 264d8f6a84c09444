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
