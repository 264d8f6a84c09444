"""Paddle motions for wave makers: piston or flap (hinged at the bottom), a ramped sine or a
(t, displacement) CSV series; paddle.absorb wraps either in active absorption (tisph/awas.py).

A motion is a callable m(t) -> (displacement, rate): metres and m/s for a piston, radians and
rad/s for a flap (the solver rotates the paddle about its hinge). For a flap the stroke S is the
horizontal excursion at the still-water level, as in Biesel's transfer function.
"""
import math

import numpy as np

from .config import ConfigError
from .constants import G
from .awas import absorbing, check_absorb
from .particles import block
from .probes.gauges import surface_heights


class Motion:
    def __init__(self, kind, stroke=0.0, period=1.0, ramp_periods=2.0, lever=1.0, series=None, second=(),
                 duration=0.0):
        """kind: piston | flap; stroke S (m, peak to peak); period T (s); ramp over
        ramp_periods periods (0: none); lever: hinge to still-water level (flap); series:
        (t, X) arrays of surface displacement in metres instead of the sinusoid; second: the
        (sin, cos) amplitudes (m) of the second-order stroke at 2 omega (second_order_stroke);
        duration: the paddle ramps down over the same ramp before this time and stands still
        after it (0: never)."""
        self.kind = kind
        self.duration = float(duration)
        self.second = tuple(float(b) for b in second) if second else ()
        self.S, self.T = float(stroke), float(period)
        self.omega = 2 * math.pi / self.T if self.T > 0 else 0.0
        self.t_ramp = float(ramp_periods) * self.T
        self.lever = float(lever)
        self.series = None
        if series is not None:
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
            return (0.5 * (1 - math.cos(math.pi * t / self.t_ramp)),
                    0.5 * math.pi / self.t_ramp * math.sin(math.pi * t / self.t_ramp))
        return 1.0, 0.0

    def made(self, t):
        """X(t) and X'(t) before the ramp down."""
        if self.series is not None:
            ts, xs, vs = self.series
            return float(np.interp(t, ts, xs)), float(np.interp(t, ts, vs))
        a, w = 0.5 * self.S, self.omega
        r, dr = self.ramp(t)
        X = r * a * math.sin(w * t)
        V = dr * a * math.sin(w * t) + r * a * w * math.cos(w * t)
        if self.second:   # second order in the amplitude, so its ramp is r^2
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
    from .config import check_file
    check_file("paddle.series", path, "CSV file with columns t, displacement")
    try:
        data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except (OSError, ValueError) as e:
        raise ConfigError("paddle.series", path, "a readable CSV file with columns t, displacement", str(e)) from None
    if data.shape[1] < 2 or len(data) < 2 or np.any(np.diff(data[:, 0]) <= 0) or not np.all(np.isfinite(data)):
        raise ConfigError("paddle.series", path, "at least two rows of finite (t, displacement) with t increasing")
    return data[:, 0], data[:, 1]


def wavenumber(omega, depth, g=9.81):
    """k from the linear dispersion relation omega^2 = g k tanh(k h) (Newton, from Eckart's guess)."""
    k0 = omega * omega / g
    k = k0 / math.sqrt(math.tanh(k0 * depth)) if k0 * depth > 0 else k0
    for _ in range(50):
        th = math.tanh(k * depth)
        f = g * k * th - omega * omega
        df = g * th + g * k * depth * (1 - th * th)
        dk = f / df
        k -= dk
        if abs(dk) < 1e-12 * k:
            break
    return k


def biesel_piston(kh):
    """Piston wave maker, H/S = 2 (cosh 2kh - 1) / (sinh 2kh + 2kh) (Biesel 1951; Dean & Dalrymple).
    Past kh = 20 the deep-water value 2 to round-off (and no overflow)."""
    kh = min(kh, 20.0)
    return 2 * (math.cosh(2 * kh) - 1) / (math.sinh(2 * kh) + 2 * kh)


def biesel_flap(kh):
    """Flap hinged at the bed, H/S = (4 sinh kh / kh) (kh sinh kh - cosh kh + 1) / (sinh 2kh + 2kh).
    Past kh = 20 its deep-water form 2 (1 - 1/kh) (exact to e^-2kh; no overflow)."""
    if kh > 20.0:
        return 2.0 * (1.0 - 1.0 / kh)
    return 4 * math.sinh(kh) / kh * (kh * math.sinh(kh) - math.cosh(kh) + 1) / (math.sinh(2 * kh) + 2 * kh)


def group_velocity(omega, k, depth):
    c = omega / k
    kh = min(k * depth, 20.0)    # deep water past it (and no overflow)
    return 0.5 * c * (1 + 2 * kh / math.sinh(2 * kh))


def wave_height(t, eta, t0, t1, period):
    """Mean trough-to-crest height over whole periods in [t0, t1]: max - min in each period window."""
    t, eta = np.asarray(t, float), np.asarray(eta, float)
    hs = []
    a = t0
    while a + period <= t1 + 1e-9:
        m = (t >= a) & (t < a + period) & np.isfinite(eta)
        if m.sum() >= 4:
            hs.append(float(eta[m].max() - eta[m].min()))
        a += period
    return (float(np.mean(hs)) if hs else float("nan")), len(hs)


def crossing_period_and_level(t, eta, t0, t1):
    """(mean zero up-crossing period about the window's mean, that mean level) of eta over
    [t0, t1]: what a gauge's record says of the waves' period and of the set-up or set-down.
    A crossing counts once the record has dipped a tenth of its range below the mean since the
    last one.
    NaN where the window holds under two up-crossings."""
    t, eta = np.asarray(t, float), np.asarray(eta, float)
    m = (t >= t0) & (t <= t1) & np.isfinite(eta)
    if m.sum() < 4:
        return float("nan"), float("nan")
    tt, e = t[m], eta[m]
    level = float(e.mean())
    d = e - level
    # a crossing counts once the record has been below -b since the last one: a shoaling wave's
    # secondary crests (its harmonics) near the mean are not waves of their own
    b = 0.1 * float(d.max() - d.min())
    up, low = [], False
    for i in range(len(d) - 1):
        low = low or d[i] < -b
        if low and d[i] < 0 <= d[i + 1]:
            up.append(i)
            low = False
    up = np.array(up, int)
    if len(up) < 2:
        return float("nan"), level
    tc = tt[up] - d[up] * (tt[up + 1] - tt[up]) / (d[up + 1] - d[up])
    if len(tc) < 2:
        return float("nan"), level
    whole = (tt >= tc[0]) & (tt < tc[-1])          # the level over whole waves only
    return float(np.mean(np.diff(tc))), float(e[whole].mean())


def wave_period(p):
    """The paddle table's period: the peak period with a spectrum."""
    return p["tp"] if p.get("spectrum") else p["period"]


def arrival_time(p, x, cg):
    """When the fully ramped waves of paddle table p have reached x at group velocity cg, plus
    one period (the peak period with a spectrum): the start of a wave-height window there."""
    T = wave_period(p)
    return p["ramp_periods"] * T + x / cg + T


def height_at(c, column, x, p, cg):
    """(mean wave height, periods) of probe column c[column] at x, from the ramped waves' arrival
    to the end of the run."""
    return wave_height(c["t"], c[column], arrival_time(p, x, cg), float(c["t"][-1]), p["period"])


class Gauges:
    """Wave gauges at x (m from the paddle's mean position): the free surface minus the still-water
    level, zeroed at the first reading (the still water of t = 0), as a laboratory gauge is: the
    SPH surface of a particle lattice reads about dx/2 under the water's mass level."""

    def __init__(self, xs, dx, h, level, columns=None, dry_from=float("inf")):
        """dry_from: where the bed stands above the still water (a beach's shoreline): a gauge
        there reads no wave height (None in the metrics) and is warned about."""
        self.xs = [float(x) for x in xs]
        self.dry = [x for x in self.xs if x >= dry_from]
        if self.dry:
            import warnings
            warnings.warn(f"gauges at x = {', '.join(f'{x:g}' for x in self.dry)} m stand on dry land (the "
                          f"still-water shoreline is at x = {dry_from:.3g} m): their wave heights are reported "
                          "as null")
        self.dx, self.h, self.level = dx, h, level
        self.columns = tuple(columns or (f"eta_x{x:.2f}" for x in self.xs))
        self.zero = []

    def read(self, st):
        eta = [float(z) - self.level for z in surface_heights(st, self.xs, self.dx, self.h)]
        if not self.zero:
            self.zero = list(eta)
        return tuple(e - z for e, z in zip(eta, self.zero))

    def metrics(self, c, p, cg):
        """gauges_x and the mean wave height at each over whole periods once the ramped waves
        have reached it at the group velocity cg (at the paddle's depth: on a slope, where waves
        slow, an early bound) and to the end of the run."""
        out = dict(gauges_x=list(self.xs), gauges_on_dry_land=list(self.dry),
                   wave_height_at_gauges=[], wave_period_at_gauges=[], mean_level_at_gauges=[])
        for x, col in zip(self.xs, self.columns):
            wet = x not in self.dry and len(c["t"])
            T, level = (crossing_period_and_level(c["t"], c[col], arrival_time(p, x, cg), float(c["t"][-1]))
                        if wet else (None, None))
            out["wave_height_at_gauges"].append(height_at(c, col, x, p, cg)[0] if wet else None)
            out["wave_period_at_gauges"].append(T)
            out["mean_level_at_gauges"].append(level)
        return out


# ---------- the [paddle] table every wave scene shares (flume, beach, custom): its defaults, ranges
# and checks, the paddle's particles and motion, and the linear wave it makes.
PADDLE_DEFAULTS = {
    "type": "piston",       # piston (translates) | flap (hinged at the floor)
    "stroke": 0.04,         # m: the full stroke (peak to peak, not the amplitude): piston travel, or the flap's at the still-water level
    "wave_height": 0.0,     # m: the wave height wanted; > 0: the stroke from Biesel's first-order transfer (give one of the two)
    "period": 0.8,          # s
    "ramp_periods": 2.0,    # periods over which the stroke ramps up (no start-up transient)
    "series": "",           # CSV of t, displacement (m or rad): a measured paddle signal instead of a sine
    "order": 1,             # 1: a sine; 2: with the second-order stroke that cancels the free second harmonic
    "absorb": False,        # active absorption: the paddle corrects its motion from the surface it sees (tisph/awas.py)
    "duration": 0.0,        # s: the paddle ramps down (over ramp_periods) to stand still at this time; 0: it runs to the end
}
PADDLE_RANGES = {"paddle.stroke": (0.0, None, False, True), "paddle.wave_height": (0.0, None, True, True),
                 "paddle.period": (0.0, None, False, True),
                 "paddle.ramp_periods": (0.0, None, True, True), "paddle.order": (1, 2, True, True),
                 "paddle.duration": (0.0, None, True, True)}


def check_paddle(cfg, depth, length, default_stroke=None):
    """The paddle's keys against the depth and dx; with paddle.wave_height the stroke is set from it
    (Biesel's first-order H / S for the paddle type and kh), and a stroke given beside it is refused."""
    p, dx = cfg["paddle"], cfg["numerics"]["dx"]
    check_absorb(p)
    H = p.get("wave_height", 0.0)
    if H > 0:
        if p.get("spectrum") or p["series"]:
            key = "paddle.spectrum" if p.get("spectrum") else "paddle.series"
            raise ConfigError("paddle.wave_height", H, f"0 with {key} (irregular waves are asked for by paddle.hs, a "
                              "series by its own displacements)")
        S = H / linear_wave(cfg, depth)[4]
        if default_stroke is not None and not (math.isclose(p["stroke"], default_stroke) or math.isclose(p["stroke"], S)):
            raise ConfigError("paddle.stroke", p["stroke"], f"left out with paddle.wave_height = {H:g} (give one of "
                              f"the two: that height needs a stroke of {S:.4g} m by Biesel)")
        if S > depth:
            raise ConfigError("paddle.wave_height", H, f"a height whose stroke is at most the depth ({depth:g} m): "
                              f"Biesel gives a stroke of {S:.4g} m for it")
        p["stroke"] = S
    ramp = p["ramp_periods"] * wave_period(p)
    if 0 < p.get("duration", 0.0) < 2 * ramp:
        raise ConfigError("paddle.duration", p["duration"], f"0 or at least twice the ramp ({2 * ramp:g} s: "
                          "paddle.ramp_periods periods up and as many down)")
    if p.get("spectrum"):
        from .irregular import check_irregular
        check_irregular(cfg, depth)
        return
    # a shallow-water piston moves the whole column: a stroke beyond the depth makes a bore, not a wave
    from .plausible import check_regular_waves, unit_guess
    if p["stroke"] > depth:
        raise ConfigError("paddle.stroke", p["stroke"], f"at most the depth at the paddle ({depth:g} m){unit_guess(cfg)}")
    if not p["series"] and p["stroke"] < dx:
        raise ConfigError("paddle.stroke", p["stroke"], f"at least dx = {dx:g} m (the paddle must move a particle spacing)")
    if p["series"]:
        if p["order"] == 2:
            raise ConfigError("paddle.order", 2, "1 with a series (the second-order stroke is for regular waves)")
        read_series(p["series"])
    else:
        omega, k, _, _, ratio = linear_wave(cfg, depth)
        check_regular_waves(cfg, "paddle.wave_height" if H > 0 else "paddle.stroke", ratio * p["stroke"], k, depth)
        k2h = wavenumber(2 * omega, depth, G) * depth if p["order"] == 2 else 0.0
        if k2h > 100:   # cosh k2 (z + h) spans e^100 over the depth: the integrals lose it
            raise ConfigError("paddle.order", 2, f"1 for this wave: its second harmonic is in deep water (k2 h = "
                              f"{k2h:.0f}, at most 100), where the second-order stroke is not computed")


def paddle(cfg, depth, height, floor_y=0.0):
    """The paddle's particles (wall_layers columns left of x = 0 from the floor to `height`), its
    motion and the solver parameters it needs. depth: still water over the hinge."""
    p, num = cfg["paddle"], cfg["numerics"]
    dx, L = num["dx"], num["wall_layers"]
    pts = block(-L * dx, floor_y, 0.0, height, dx)
    series = read_series(p["series"]) if p["series"] else None
    if p.get("spectrum"):
        from .irregular import irregular_series
        series = irregular_series(p, depth, cfg["run"]["end_time"])
    second = ()
    if p["order"] == 2:
        from .second_order import second_order_stroke   # it reads wavenumber from here
        second = second_order_stroke(p["type"], p["stroke"], 2 * math.pi / p["period"], depth)
    # a series or a spectrum ramps down over ramp_periods of its own (peak) period
    motion = Motion(p["type"], p["stroke"], wave_period(p), p["ramp_periods"], lever=depth, series=series,
                    duration=p.get("duration", 0.0),
                    second=second)
    reach = 0.5 * (p["stroke"] if series is None else 2 * float(np.abs(series[1]).max()))
    if p.get("absorb"):   # the correction may take the piston as far again as its stroke
        motion, reach = absorbing(motion, cfg, depth, floor_y + depth), 2 * reach
    return pts, motion, dict(motion=motion, pivot=(0.0, floor_y)), reach


def linear_wave(cfg, depth):
    """(omega, k, wavelength, group velocity, Biesel H/S) of the configured paddle (at the peak
    period with a spectrum)."""
    p = cfg["paddle"]
    omega = 2 * math.pi / wave_period(p)
    k = wavenumber(omega, depth, G)
    hs = biesel_piston(k * depth) if p["type"] == "piston" else biesel_flap(k * depth)
    return omega, k, 2 * math.pi / k, group_velocity(omega, k, depth), hs
