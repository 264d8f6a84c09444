"""The paddle's motion: a ramped sine (with the second-order stroke at 2 omega where asked) or a
(t, displacement) CSV series, for a piston or a flap hinged at the bottom.

A motion is a callable m(t) -> (displacement, rate): metres and m/s for a piston, radians and
rad/s for a flap (the solver rotates the paddle about its hinge). For a flap the stroke S is the
horizontal excursion at the still-water level, as in Biesel's transfer function.
"""

import math
from typing import NamedTuple

import numpy as np

from ..settings.config import ConfigError, check_file


class Components(NamedTuple):
    """A displacement sum X_i sin(2 pi f_i t + phase_i) (a spectrum's, waves/irregular.py)."""

    f: np.ndarray
    X: np.ndarray
    phase: np.ndarray


class Motion:
    def __init__(self, kind, stroke=0.0, period=1.0, ramp_periods=2.0, lever=1.0, series=None, second=(), duration=0.0):
        """kind: piston | flap; stroke S (m, peak to peak); period T (s); ramp over
        ramp_periods periods (0: none); lever: hinge to still-water level (flap); series:
        (t, X) arrays of surface displacement in metres instead of the sinusoid, or Components
        summed at each time under the ramp; second: the (sin, cos) amplitudes (m) of the
        second-order stroke at 2 omega (second_order_stroke); duration: the paddle ramps down
        over the same ramp before this time and stands still after it (0: never)."""
        self.kind = kind
        self.duration = float(duration)
        self.second = tuple(float(b) for b in second) if second else ()
        self.S, self.T = float(stroke), float(period)
        self.omega = 2 * math.pi / self.T if self.T > 0 else 0.0
        self.t_ramp = float(ramp_periods) * self.T
        self.lever = float(lever)
        self.series = None
        self.components = series if isinstance(series, Components) else None
        # a smooth function of time alone: the solver may follow it by a series over a batch of
        # steps (engine/access.py, series_fit); a measured series is piecewise linear
        self.smooth = series is None or self.components is not None
        if series is not None and self.components is None:
            t, x = (np.asarray(a, float) for a in series)
            self.series = (t, x, np.gradient(x, t) if len(t) > 1 else np.zeros_like(x))

    def envelope(self, t):
        """(e, e'): 1 until the ramp down before `duration`, 0 after it (half-cosine between)."""
        if self.duration <= 0 or t <= self.duration - self.t_ramp:
            return 1.0, 0.0
        if t >= self.duration:
            return 0.0, 0.0
        a = math.pi * (self.duration - t) / self.t_ramp
        return 0.5 * (1 - math.cos(a)), -0.5 * math.pi / self.t_ramp * math.sin(a)

    @property
    def breaks(self):
        """The times where the motion has a kink: the ramp's end, the ramp down's start and end."""
        b = (self.t_ramp,) if self.t_ramp > 0 else ()
        if self.duration > 0:
            b += (self.duration - self.t_ramp, self.duration)
        return b

    def surface(self, t):
        """Horizontal displacement X(t) at the still-water level and its rate X'(t)."""
        e, de = self.envelope(t)
        if e == 0.0:
            return 0.0, 0.0
        X, V = self.made(t)
        return e * X, e * V + de * X

    def ramp(self, t):
        """(r, r'): the half-cosine ramp up over t_ramp: amplitude and its rate start at zero."""
        if t < self.t_ramp:
            return (
                0.5 * (1 - math.cos(math.pi * t / self.t_ramp)),
                0.5 * math.pi / self.t_ramp * math.sin(math.pi * t / self.t_ramp),
            )
        return 1.0, 0.0

    def made(self, t):
        """X(t) and X'(t) before the ramp down."""
        if self.series is not None:
            ts, xs, vs = self.series
            return float(np.interp(t, ts, xs)), float(np.interp(t, ts, vs))
        r, dr = self.ramp(t)
        if self.components is not None:
            f, A, phase = self.components
            w = 2 * math.pi * f
            arg = w * t + phase
            s = float(A @ np.sin(arg))
            return r * s, dr * s + r * float((A * w) @ np.cos(arg))
        a, w = 0.5 * self.S, self.omega
        X = r * a * math.sin(w * t)
        V = dr * a * math.sin(w * t) + r * a * w * math.cos(w * t)
        if self.second:  # second order in the amplitude, so its ramp is r^2
            bs, bc = self.second
            x2 = bs * math.sin(2 * w * t) + bc * math.cos(2 * w * t)
            X += r * r * x2
            V += 2 * r * dr * x2 + r * r * 2 * w * (bs * math.cos(2 * w * t) - bc * math.sin(2 * w * t))
        return X, V

    def __call__(self, t):
        return self.at_level(*self.surface(t))

    def at_level(self, X, V):
        """The solver's motion for a displacement X and rate V at the still-water level: a
        piston's own, a flap's angle about its hinge and its rate."""
        if self.kind == "flap":
            L = self.lever
            return math.atan2(X, L), V * L / (L * L + X * X)
        return X, V


def read_series(path):
    """A paddle time series: CSV with a header row and columns t (s), displacement (m)."""
    check_file("paddle.series", path, "CSV file with columns t, displacement")
    try:
        data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except (OSError, ValueError) as e:
        raise ConfigError("paddle.series", path, "a readable CSV file with columns t, displacement", str(e)) from None
    if data.shape[1] < 2 or len(data) < 2 or np.any(np.diff(data[:, 0]) <= 0) or not np.all(np.isfinite(data)):
        raise ConfigError("paddle.series", path, "at least two rows of finite (t, displacement) with t increasing")
    return data[:, 0], data[:, 1]
