"""Active wave absorption at a piston or flap paddle (paddle.absorb): the paddle corrects its motion
from the surface elevation it sees, so waves coming back from the far end leave through it instead of
reflecting and building a seiche (DualSPHysics' AWAS, Altomare et al. 2017; Schaffer & Klopman
2000).

Every control interval the free surface is read at a gauge that moves with the paddle, a smoothing
length in front of its face (the theory wants the elevation at the paddle); what differs from the wave the paddle is making there (linear theory: the
progressive wave of Biesel's height, eta_T = H/2 r(t) cos(omega t - k x_g)) is a wave arriving from
the flume, eta_R (less its running mean over a period: a set-down or the crests' asymmetry is not a
wave). The paddle adds the velocity of that wave, U_c = -G eta_R, with the gain
G = omega / F(kh) that turns a wave elevation into the paddle velocity that makes it (F: Biesel's
H/S, the piston's or the flap's; G = sqrt(g/h) for a piston in shallow water). A flap takes the
correction as a displacement and velocity at the still-water level, where its stroke is defined,
and turns them into its angle about the hinge (Motion.at_level), as its own stroke is. eta_R is
taken as it was x_g / c ago (c = omega / k): the returning wave passes the gauge that long before
it reaches the face the theory is written for.
Without that delay (19 degrees of phase at T = 0.8 s, dx = 0.02) a closed flume kept twice the
wave after the returning train had met the paddle (docs/waves.md). Its displacement is integrated,
and pulled back towards the paddle's mean position over DRIFT_PERIODS periods so that the paddle
does not wander.

With a spectrum (paddle.spectrum) the target is the components' linear waves summed at the gauge
(tisph.waves.irregular.irregular_elevation), and the gain and the delay are the peak period's: one
number for the band, as DualSPHysics' long-wave gain is (for the flume's 0.9 s sea over 0.25 m,
omega / F is 5.3 1/s at the peak, 6.0 at half its frequency and 7.0 at twice it).
"""

import dataclasses
import math

import numpy as np

from ..measure.field import surface_at
from ..settings.config import ConfigError
from .irregular import irregular_elevation
from .theory import linear_wave

DRIFT_PERIODS = 5.0  # the correction's displacement relaxes to zero over this many wave periods


@dataclasses.dataclass(frozen=True)
class Aim:
    """The wave the paddle makes, as the absorption compares with it: Biesel's height, the
    wavenumber and depth, the gain omega / F(kh); series: (t, eta) at the gauge for irregular
    waves (the height is then unused)."""

    height: float
    k: float
    depth: float
    gain: float
    series: tuple = None


@dataclasses.dataclass(frozen=True)
class Sensor:
    """The gauge that moves with the paddle: its distance in front of the paddle's mean position
    x_paddle, the still-water level it reads from, the spacing and the smoothing length."""

    x: float
    x_paddle: float
    level: float
    dx: float
    h: float


class AbsorbingMotion:
    """A paddle's Motion plus the absorbing correction; callable as the Motion is (t -> X, V for a
    piston, angle and its rate for a flap)."""

    smooth = False  # each call integrates the correction: the solver calls it once a step

    def __init__(self, motion, aim, sensor):
        self.target_series = aim.series
        self.motion, self.H, self.k, self.depth, self.gain = motion, float(aim.height), aim.k, aim.depth, aim.gain
        self.x_gauge, self.x_abs, self.level = sensor.x, sensor.x_paddle + sensor.x, sensor.level
        self.dx, self.h = sensor.dx, sensor.h
        self.xc = self.uc = 0.0  # the correction's displacement and velocity
        self.mean = 0.0  # the running mean of eta - eta_T over a period: a mean level is not a wave
        self.t_last = 0.0
        self.zero = None  # the gauge's reading at rest (the SPH surface sits about dx/2 low)
        self.history = []  # (t, eta measured, eta target, correction velocity)
        self.recent = []  # (t, eta_R less its mean) over the last x_g / c and a little more

    def __getattr__(self, name):  # the wrapped Motion's period, stroke, ramp
        if name == "motion":
            raise AttributeError(name)
        return getattr(self.motion, name)

    def target(self, t):
        """The elevation at the gauge of the wave the paddle makes (linear, ramped as the stroke)."""
        m = self.motion
        if self.target_series is not None:
            return float(np.interp(t, *self.target_series)) * m.envelope(t)[0]
        return 0.5 * self.H * m.ramp(t)[0] * m.envelope(t)[0] * math.cos(m.omega * t - self.k * self.x_gauge)

    def __call__(self, t):
        dt = max(t - self.t_last, 0.0)
        self.t_last = t
        self.xc += dt * (self.uc - self.xc / (DRIFT_PERIODS * self.motion.T))
        X, V = self.motion.surface(t)
        return self.motion.at_level(X + self.xc, V + self.uc)

    def face(self, t):
        """The paddle's displacement at the still-water level, correction included."""
        return self.motion.surface(t)[0] + self.xc

    def control(self, solver):
        """Read the gauge and set the correction velocity (every control interval)."""
        st = solver.state(("x", "kind", "rho", "m", "mat"))
        eta = (
            surface_at(st, self.x_abs + self.face(solver.time), self.dx, self.h, floor=self.level - self.depth, mat=0)
            - self.level
        )
        if self.zero is None:
            self.zero = eta
        eta -= self.zero
        t = solver.time
        eta_r = eta - self.target(t)
        dt = t - self.history[-1][0] if self.history else 0.0
        self.mean += min(dt / self.motion.T, 1.0) * (eta_r - self.mean)
        self.recent.append((t, eta_r - self.mean))
        self.uc = -self.gain * self.delayed(t - self.x_gauge * self.k / self.motion.omega)
        self.history.append((t, eta, self.target(t), self.uc))

    def delayed(self, tq):
        """eta_R less its mean at time tq, interpolated in the recent readings (the oldest one
        before the first reading); readings older than tq's bracket are dropped."""
        r = self.recent
        while len(r) > 2 and r[1][0] <= tq:
            r.pop(0)
        if tq <= r[0][0]:
            return r[0][1]
        (t0, a), (t1, b) = r[0], r[1] if len(r) > 1 else r[0]
        return b if t1 <= t0 else a + (b - a) * min((tq - t0) / (t1 - t0), 1.0)


def absorbing(motion, cfg, depth, still_level, x_paddle=0.0):
    """Wrap a paddle's Motion for paddle.absorb: the gauge moves with the paddle, a smoothing length
    in front of its face (the paddle's mean position is x_paddle)."""
    p, dx = cfg.paddle, cfg.numerics.dx
    h = cfg.numerics.h_factor * dx
    omega, k, _, _, F = linear_wave(cfg, depth)  # the paddle's transfer; the peak's
    target = None
    if p.get("spectrum"):
        target = irregular_elevation(p, depth, cfg.run.end_time, h)
    return AbsorbingMotion(
        motion, Aim(F * p.stroke, k, depth, omega / F, target), Sensor(h, x_paddle, still_level, dx, h)
    )


def check_absorb(p):
    """paddle.absorb: a piston's or a flap's first-order waves, regular or from a spectrum (the target
    is their linear wave)."""
    if not p.get("absorb"):
        return
    for key, bad, what in (("series", p["series"], "no series"), ("order", p["order"] != 1, "order 1")):
        if bad:
            raise ConfigError(
                "paddle.absorb",
                True,
                f"false with paddle.{key} = {p[key]!r}",
                f"active absorption here is for {what}: its target is the linear wave of a paddle's first-order stroke",
            )


def with_control(motion, control=None):
    """The control hook a scene passes to make_case: the absorbing paddle's, then the scene's own."""
    mine = getattr(motion, "control", None)
    if mine is None or control is None:
        return mine or control

    def both(solver):
        mine(solver)
        control(solver)

    return both
