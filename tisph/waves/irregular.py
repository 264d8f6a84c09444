"""Irregular waves from a spectrum (paddle.spectrum = "jonswap" | "pm"): the paddle's signal and
its checks, the flume's only (the beach's ripples read one period)."""

import functools
import math

import numpy as np

from ..constants import G
from ..settings.config import ConfigError
from ..settings.schema import K, choices, ranges, values
from .motion import Components
from .theory import biesel_flap, biesel_piston, wavenumber

IRREGULAR = {
    "spectrum": K(
        "", '"": regular waves (stroke, period) | jonswap | pm (Pierson-Moskowitz)', choices=('', 'jonswap', 'pm')
    ),
    "hs": K(0.0, "the spectrum's target significant height Hm0 = 4 sqrt(m0)", 'm', range=(0.0, None, True, True)),
    "tp": K(0.0, "the spectrum's peak period", 's', range=(0.0, None, True, True)),
    "gamma": K(3.3, 'JONSWAP peak enhancement (pm: 1)', range=(1.0, 20.0, True, True)),
    "seed": K(1, "the random phases' seed", range=(0, None, True, True)),
    "band": K([0.5, 2.0], 'the frequencies sent and measured, as multiples of the peak frequency'),
}
IRREGULAR_DEFAULTS = values(IRREGULAR)
IRREGULAR_RANGES = ranges(IRREGULAR, "paddle")
IRREGULAR_CHOICES = choices(IRREGULAR, "paddle")


def spectrum(f, hs, tp, gamma):
    """JONSWAP spectral density (m2/Hz) with sigma 0.07 below the peak and 0.09 above (Hasselmann
    et al. 1973), gamma = 1 for Pierson-Moskowitz, scaled so that 4 sqrt(m0) = hs over f."""
    f = np.asarray(f, float)
    fp = 1.0 / tp
    sig = np.where(f <= fp, 0.07, 0.09)
    S = f**-5.0 * np.exp(-1.25 * (fp / f) ** 4) * gamma ** np.exp(-((f - fp) ** 2) / (2 * sig * sig * fp * fp))
    m0 = float(((S[1:] + S[:-1]) * np.diff(f)).sum() / 2) if len(f) > 1 else float(S.sum())
    return S * (hs / 4.0) ** 2 / m0


def irregular_series(p, depth, t_end, g=G):
    """(t, X): the paddle's displacement at the still-water level for p's spectrum: components
    df apart (df = 1 / the longer of the run and 100 peak periods, so the signal does not repeat
    within the run), each with the amplitude sqrt(2 S df) (deterministic amplitudes, random phases
    from the seed) divided by the paddle's first-order transfer at its frequency (Biesel), ramped
    up over ramp_periods peak periods. Kept for the last few tables (the checks and the paddle
    ask for the same one); the arrays are read-only."""
    return _irregular_series(*_key(p, depth, t_end, g))


def irregular_elevation(p, depth, t_end, x, g=G):
    """(t, eta): the first-order surface elevation those components make at x (m in front of the
    paddle's mean position): each a cos(omega t + phase - k x) under the same ramp (for a piston's
    displacement X sin(omega t + phase), as Biesel's regular wave; the active absorber's target)."""
    return _irregular_series(*_key(p, depth, t_end, g), x_at=float(x))


def _key(p, depth, t_end, g):
    return (
        p["type"],
        p["spectrum"],
        float(p["hs"]),
        float(p["tp"]),
        float(p["gamma"]),
        int(p["seed"]),
        tuple(float(b) for b in p["band"]),
        float(p["ramp_periods"]),
        float(depth),
        float(t_end),
        g,
    )


def irregular_components(p, depth, t_end, g=G):
    """The components irregular_series sums, X_i sin(2 pi f_i t + phase_i) before the ramp
    (read-only arrays). The paddle sums them at each time it is asked for, a smooth function of
    time that a GPU follows over a batch of steps (engine/batch.py, series_fit)."""
    f, _, _, X, phase = _components(*_key(p, depth, t_end, g))
    return Components(f, X, phase)


@functools.lru_cache(maxsize=4)
def _components(kind, name, hs, tp, gamma, seed, band, ramp_periods, depth, t_end, g):
    fp = 1.0 / tp
    lo, hi = (b * fp for b in band)
    t_rep = max(t_end, 100.0 * tp)
    n = max(int(math.ceil((hi - lo) * t_rep)), 8)
    f = lo + (np.arange(n) + 0.5) * (hi - lo) / n
    a = np.sqrt(2 * spectrum(f, hs, tp, 1.0 if name == "pm" else gamma) * (hi - lo) / n)
    transfer = biesel_piston if kind == "piston" else biesel_flap
    kh = np.array([wavenumber(2 * math.pi * v, depth, g) * depth for v in f])
    X = a / np.array([transfer(v) for v in kh])
    phase = np.random.default_rng(seed).uniform(0, 2 * math.pi, n)
    for v in (f, a, kh, X, phase):
        v.setflags(write=False)
    return f, a, kh, X, phase


@functools.lru_cache(maxsize=4)
def _irregular_series(kind, name, hs, tp, gamma, seed, band, ramp_periods, depth, t_end, g, x_at=None):
    f, a, kh, X, phase = _components(kind, name, hs, tp, gamma, seed, band, ramp_periods, depth, t_end, g)
    n = len(f)
    t = np.arange(0.0, t_end + 2 * tp, tp / 50.0)
    x = np.zeros_like(t)
    for i in range(0, n, 64):  # in blocks: n x len(t) at once can be large
        w = 2 * math.pi * f[i : i + 64, None] * t[None, :] + phase[i : i + 64, None]
        if x_at is None:
            x += (X[i : i + 64, None] * np.sin(w)).sum(0)
        else:
            x += (a[i : i + 64, None] * np.cos(w - kh[i : i + 64, None] / depth * x_at)).sum(0)
    t_ramp = ramp_periods * tp
    if t_ramp > 0:
        x *= np.where(t < t_ramp, 0.5 * (1 - np.cos(math.pi * np.minimum(t, t_ramp) / t_ramp)), 1.0)
    t.setflags(write=False)
    x.setflags(write=False)
    return t, x


def check_irregular(cfg, depth):
    p, dx = cfg.paddle, cfg.numerics.dx
    if not p.spectrum:
        return
    h = cfg.numerics.h_factor * dx
    for key in ("hs", "tp"):
        if p[key] <= 0:
            raise ConfigError(f"paddle.{key}", p[key], f"> 0 with paddle.spectrum = {p.spectrum!r}")
    b = p.band
    if (
        not isinstance(b, list)
        or len(b) != 2
        or any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in b)
        or not 0 < b[0] < 1 < b[1]
    ):
        raise ConfigError("paddle.band", b, "[lo, hi] multiples of the peak frequency, 0 < lo < 1 < hi")
    if p.series or p.order == 2:
        key = "paddle.series" if p.series else "paddle.order"
        raise ConfigError(
            key,
            p.series or 2,
            f"{'' if p.series else '1'} with a spectrum (a spectrum makes its own first-order paddle signal)".lstrip(),
        )
    if p.hs < 2 * dx:
        raise ConfigError(
            "paddle.hs", p.hs, f"at least 2 dx = {2 * dx:g} m (a wave under two particle spacings high is not resolved)"
        )
    shortest = 2 * math.pi / wavenumber(2 * math.pi * b[1] / p.tp, depth, G)
    if shortest < 8 * h:
        raise ConfigError(
            "paddle.band",
            b,
            f"a highest frequency whose wavelength is at least 8 h = {8 * h:.3g} m, "
            f"which the kernel does not smooth away (at {b[1]:g} fp = {b[1] / p.tp:.3g} Hz the wave is "
            f"{shortest:.3g} m long; lower the band's top or dx)",
        )
    t, x = irregular_series(p, depth, cfg.run.end_time)
    if np.abs(x).max() > 0.5 * depth:
        raise ConfigError(
            "paddle.hs",
            p.hs,
            f"a spectrum the paddle can make: it would travel {np.abs(x).max():.3g} m "
            f"from its mean position, more than half the depth ({0.5 * depth:g} m)",
        )
