"""The [paddle] table every wave scene shares (flume, beach, custom): its keys, their checks,
the stroke a wave height asks for, and the paddle's particles and motion (regular, from a
series, irregular from a spectrum, second order, absorbing)."""

import math

import numpy as np

from ..constants import G
from ..measure.records import wave_period
from ..particles import block
from ..settings.config import ConfigError
from ..settings.plausible import check_regular_waves, height_guess, unit_guess
from ..settings.schema import K, choices, ranges, values
from .absorb import absorbing, check_absorb
from .irregular import check_irregular, irregular_components, irregular_series
from .motion import Motion, read_series
from .second_order import second_order_stroke
from .theory import linear_wave, wavenumber

PADDLE = {
    "type": K("piston", 'piston (translates) | flap (hinged at the floor)', choices=("piston", "flap")),
    "stroke": K(
        0.04,
        "the full stroke (peak to peak, not the amplitude): piston travel, or the flap's at the still-water level",
        'm',
        range=(0.0, None, False, True),
    ),
    "wave_height": K(
        0.0,
        "the wave height wanted; > 0: the stroke from Biesel's first-order transfer (give one of the two)",
        'm',
        range=(0.0, None, True, True),
    ),
    "period": K(0.8, "the wave period", "s", range=(0.0, None, False, True)),
    "ramp_periods": K(
        2.0, 'periods over which the stroke ramps up (no start-up transient)', range=(0.0, None, True, True)
    ),
    "series": K("", 'CSV of t, displacement (m or rad): a measured paddle signal instead of a sine'),
    "order": K(
        1, '1: a sine; 2: with the second-order stroke that cancels the free second harmonic', range=(1, 2, True, True)
    ),
    "absorb": K(
        False, 'active absorption: the paddle corrects its motion from the surface it sees (tisph/waves/absorb.py)'
    ),
    "duration": K(
        0.0,
        'the paddle ramps down (over ramp_periods) to stand still at this time; 0: it runs to the end',
        's',
        range=(0.0, None, True, True),
    ),
}
PADDLE_DEFAULTS = values(PADDLE)
PADDLE_RANGES = ranges(PADDLE, "paddle")
PADDLE_CHOICES = choices(PADDLE, "paddle")


def stroke_for(cfg, depth, default_stroke=None):
    """The full stroke the paddle runs: paddle.stroke, or with paddle.wave_height > 0 the stroke
    Biesel's first-order H / S gives for the paddle type and kh (a stroke given beside it, other
    than the scene's default, is refused)."""
    p = cfg.paddle
    H = p.get("wave_height", 0.0)
    if H <= 0:
        return p.stroke
    if p.get("spectrum") or p.series:
        key = "paddle.spectrum" if p.get("spectrum") else "paddle.series"
        raise ConfigError(
            "paddle.wave_height",
            H,
            f"0 with {key} (irregular waves are asked for by paddle.hs, a series by its own displacements)",
        )
    S = H / linear_wave(cfg, depth)[4]
    if default_stroke is not None and not (math.isclose(p.stroke, default_stroke) or math.isclose(p.stroke, S)):
        raise ConfigError(
            "paddle.stroke",
            p.stroke,
            f"left out with paddle.wave_height = {H:g} (give one of "
            f"the two: that height needs a stroke of {S:.4g} m by Biesel)",
        )
    if depth < S:
        raise ConfigError(
            "paddle.wave_height",
            H,
            f"a height whose stroke is at most the depth ({depth:g} m): "
            f"Biesel gives a stroke of {S:.4g} m for it{height_guess(H, depth)}",
        )
    return S


def stroke_step(cfg, depth, default_stroke=None):
    """A resolving step: the stroke a wave height asks for (stroke_for) as paddle.stroke, with
    run.log's line on where it came from; nothing where the stroke was given."""
    p = cfg.paddle
    if p.get("wave_height", 0.0) <= 0:
        return {}, []
    S = stroke_for(cfg, depth, default_stroke)
    return {"paddle.stroke": S}, [
        f"paddle.stroke = {S:.6g} m: resolved from paddle.wave_height = "
        f"{p.wave_height:g} m by Biesel's first-order transfer for a {p.type}"
    ]


def check_paddle(cfg, depth, length, default_stroke=None):
    """The paddle's keys against the depth and dx, for the stroke it will run (stroke_for), which
    it returns (the resolved stroke: stroke_step wrote it)."""
    p, dx = cfg.paddle, cfg.numerics.dx
    check_absorb(p)
    H = p.get("wave_height", 0.0)
    stroke = stroke_for(cfg, depth, default_stroke)
    ramp = p.ramp_periods * wave_period(p)
    if 0 < p.get("duration", 0.0) < 2 * ramp:
        raise ConfigError(
            "paddle.duration",
            p.duration,
            f"0 or at least twice the ramp ({2 * ramp:g} s: paddle.ramp_periods periods up and as many down)",
        )
    if p.get("spectrum"):
        check_irregular(cfg, depth)
        return stroke
    # a shallow-water piston moves the whole column: a stroke beyond the depth makes a bore, not a wave
    if stroke > depth:
        raise ConfigError("paddle.stroke", stroke, f"at most the depth at the paddle ({depth:g} m){unit_guess(cfg)}")
    if not p.series and stroke < dx:
        if H > 0:  # the user asked for a height: name it, and the stroke it asks for
            raise ConfigError(
                "paddle.wave_height",
                H,
                f"a height whose stroke is at least dx = {dx:g} m (Biesel "
                f"gives {stroke:.3g} m for it; the paddle must move a particle spacing): a higher "
                "wave, or a smaller numerics.dx",
            )
        raise ConfigError("paddle.stroke", stroke, f"at least dx = {dx:g} m (the paddle must move a particle spacing)")
    if p.series:
        if p.order == 2:
            raise ConfigError("paddle.order", 2, "1 with a series (the second-order stroke is for regular waves)")
        read_series(p.series)
    else:
        omega, k, _, _, ratio = linear_wave(cfg, depth)
        check_regular_waves(cfg, "paddle.wave_height" if H > 0 else "paddle.stroke", ratio * stroke, k, depth)
        k2h = wavenumber(2 * omega, depth, G) * depth if p.order == 2 else 0.0
        if k2h > 100:  # cosh k2 (z + h) spans e^100 over the depth: the integrals lose it
            raise ConfigError(
                "paddle.order",
                2,
                f"1 for this wave: its second harmonic is in deep water (k2 h = "
                f"{k2h:.0f}, at most 100), where the second-order stroke is not computed",
            )
    return stroke


def paddle(cfg, depth, height, floor_y=0.0):
    """The paddle's particles (wall_layers columns left of x = 0 from the floor to `height`), its
    motion and the solver parameters it needs. depth: still water over the hinge."""
    p, num = cfg.paddle, cfg.numerics
    dx, L = num.dx, num.wall_layers
    pts = block(-L * dx, floor_y, 0.0, height, dx)
    series = read_series(p.series) if p.series else None
    if p.get("spectrum"):  # the components, summed at each time
        series = irregular_components(p, depth, cfg.run.end_time)
    second = ()
    if p.order == 2:
        second = second_order_stroke(p.type, p.stroke, 2 * math.pi / p.period, depth)
    # a series or a spectrum ramps down over ramp_periods of its own (peak) period
    motion = Motion(
        p.type,
        p.stroke,
        wave_period(p),
        p.ramp_periods,
        lever=depth,
        series=series,
        duration=p.get("duration", 0.0),
        second=second,
    )
    sampled = irregular_series(p, depth, cfg.run.end_time) if p.get("spectrum") else series
    reach = 0.5 * (p.stroke if sampled is None else 2 * float(np.abs(sampled[1]).max()))
    if p.get("absorb"):  # the correction may take the piston as far again as its stroke
        motion, reach = absorbing(motion, cfg, depth, floor_y + depth), 2 * reach
    return pts, motion, dict(motion=motion, pivot=(0.0, floor_y)), reach
