"""Bed measurement: the sediment surface along x, and ripple statistics of the bed change.

Ripples are measured on the bed change z(x) = bed(x, t) - bed(x, 0) over the active zone, after
removing its linear trend (net erosion or deposition across the zone is not a ripple) and, when a
window is given, its running mean over that window (a bar or a shoreline profile change is longer
than the window and is not a ripple either: a high-pass filter, as field ripple surveys use). Zero
up-crossings split z into ripples; each ripple's length is the distance between consecutive
up-crossings and its height is crest minus trough between them (the zero-crossing method of
wave analysis, applied along x).

The reference is the equilibrium ripple predictor of Wiberg & Harris (1994, J. Geophys. Res.
99(C1), 775-789) from the near-bed orbital diameter d0 (linear waves: d0 = H / sinh(kh)) and the
grain diameter D: orbital ripples 0.62 d0 long and 0.17 of that high, anorbital ripples 535 D
long, suborbital ripples in between.
"""

import math
import warnings

import numpy as np

# What counts as a ripple on a particle bed, in particle spacings: at least 3 long, and at least
# half a spacing high. Lower bumps are rearrangements within the top particle row: a resting
# bed reads as bumps up to 0.17 dx high (bed gauge flicker, tunnel default run) and a Bingham bed
# of 0.5 Pa wandering under the oscillation as bumps of 0.33 dx.
MIN_LENGTH_DX = 3.0
MIN_HEIGHT_DX = 0.5
# the band of orbital ripples around Wiberg & Harris (1994): length over d0, and height over length
ORBITAL_BAND = (0.5, 0.75)
STEEPNESS_BAND = (0.10, 0.20)
# a ripple the bed model resolves: its predicted length at least this many spacings. Measured on the
# default tunnel: 0.58 d0 at 18.6 and at 28 spacings a ripple, 1.0 d0 at 12.4 (docs/sediment.md)
RESOLVED_DX = 18.0


def unresolved(metrics, predicted, dx, keys=("ripple_length_over_prediction", "ripple_steepness")):
    """Null the ripple metrics of a bed whose predicted ripple spans under RESOLVED_DX spacings (its
    length is then set by the grid as much as by the waves: 1.0 d0 at 12.4 spacings against 0.58 d0
    at 18.6 in the default tunnel), and say why in metrics["ripple_metrics_note"]."""
    if 0 < predicted < RESOLVED_DX * dx:
        for k in keys:
            metrics[k] = None
        metrics["ripple_metrics_note"] = (
            f"the predicted ripple, {predicted:.3g} m, spans {predicted / dx:.1f} dx: under "
            f"{RESOLVED_DX:g} dx its length is set by the grid as much as by the waves, so "
            f"no ripple statistics (numerics.dx at most {predicted / RESOLVED_DX:.3g} m)"
        )
    return metrics


def floor2(x):
    """x rounded down to two significant digits (a spacing that resolves at least what x does)."""
    e = math.floor(math.log10(x)) - 1
    return round(math.floor(x / 10.0**e + 1e-9) * 10.0**e, 12)


def derive_resolution(cfg, given, lam, d0, where="", limit=None, cap=None):
    """A ripple scene's dx and morfac where the user left them unset: dx puts the predicted ripple
    lam (Wiberg & Harris for d0) over RESOLVED_DX spacings; morfac is the largest, to a tenth, at
    which the bed turns over no faster per wave period than in the calibration tunnel (limit,
    tisph/sediment/morfac.py; None: keep morfac), at most cap. A resolving step: returns the
    values ({dotted key: value}) and run.log's lines."""
    notes, changes = [], {}
    if "numerics.dx" not in given:
        changes["numerics.dx"] = dx = floor2(lam / RESOLVED_DX)
        notes.append(
            f"numerics.dx = {dx:g} m: the predicted ripple{where} ({lam:.3g} m, Wiberg & Harris for d0 = "
            f"{d0:.3g} m) over {RESOLVED_DX:g} spacings (set numerics.dx to choose)"
        )
    if limit is not None and "sediment.morfac" not in given:
        m = max(1.0, min(cap or math.inf, math.floor(limit * 10 + 1e-6) / 10))
        changes["sediment.morfac"] = m
        notes.append(
            f"sediment.morfac = {m:g}: the bed{where} turns over no faster per wave period than in the "
            f"calibration tunnel ({f'at most {cap:g}; ' if cap else ''}set sediment.morfac to choose)"
        )
    return changes, notes


def warn_unresolved(length, dx, where):
    """A warning (captured into summary.json and printed at the start) when the predicted ripple
    is shorter than RESOLVED_DX spacings."""
    if 0 < length < RESOLVED_DX * dx:
        warnings.warn(
            f"the predicted ripple {where} is {length:.3g} m, {length / dx:.1f} dx: the bed model "
            f"resolves ripples of at least {RESOLVED_DX:g} dx, so its ripple length here is set by the grid "
            f"as much as by the waves; numerics.dx at most {length / RESOLVED_DX:.3g} m resolves it"
        )


def high_pass(x, z, window):
    """z minus its running mean over `window` (same units as x; x evenly spaced), ends reflected."""
    n = max(1, int(round(window / (x[1] - x[0]))))
    if n < 2 or n >= len(z):
        return z
    pad = np.pad(z, n, mode="reflect")
    smooth = np.convolve(pad, np.ones(n) / n, mode="same")[n:-n]
    return z - smooth


def ripple_stats(x, z, window=None, min_length=0.0, min_height=0.0):
    """(mean ripple length, mean ripple height, rms of z) of bed change z sampled at x (ascending).

    window: bedforms longer than this are filtered out first (None: only the linear trend goes).
    Ripples shorter than min_length or lower than min_height are not counted (the bed gauge's
    noise). Length and height are NaN when no ripple is left."""
    x, z = np.asarray(x, float), np.asarray(z, float)
    ok = np.isfinite(z)
    x, z = x[ok], z[ok]
    if len(x) < 4:
        return float("nan"), float("nan"), float("nan")
    rms = float(np.sqrt(np.mean(z * z)))
    zd = z - np.polyval(np.polyfit(x, z, 1), x)
    if window:
        zd = high_pass(x, zd, window)
    s = np.signbit(zd)
    up = np.nonzero(s[:-1] & ~s[1:])[0]  # zd goes from < 0 to >= 0 between up and up + 1
    if len(up) < 2:
        return float("nan"), float("nan"), rms
    # the crossing point, interpolated between the two samples
    xc = x[up] - zd[up] * (x[up + 1] - x[up]) / (zd[up + 1] - zd[up])
    heights = np.array([zd[a + 1 : b + 1].max() - zd[a + 1 : b + 1].min() for a, b in zip(up[:-1], up[1:])])
    lengths = np.diff(xc)
    keep = (lengths >= min_length) & (heights >= min_height)
    if not keep.any():
        return float("nan"), float("nan"), rms
    return float(np.mean(lengths[keep])), float(np.mean(heights[keep])), rms


def last_finite(columns, keys):
    """{key: the last finite value of columns[key]} (NaN if none): a probe's final statistic when
    the last samples found no ripple."""
    out = {}
    for key in keys:
        v = np.asarray(columns[key], float)
        v = v[np.isfinite(v)]
        out[key] = float(v[-1]) if len(v) else float("nan")
    return out


def orbital_diameter(H, k, depth):
    """Near-bed orbital diameter of linear waves, d0 = H / sinh(k h)."""
    return H / np.sinh(k * depth)


def wiberg_harris(d0, grain_diameter):
    """Equilibrium wave-ripple (length, height, regime) of Wiberg & Harris (1994).

    Orbital: length 0.62 d0, height 0.17 length. Anorbital: length 535 D, height from the
    steepness law height/length = exp(-0.095 ln(d0/height)^2 + 0.442 ln(d0/height) - 2.28),
    solved for height. The regime follows from d0 / anorbital height: under 20 orbital, over 100
    anorbital, and between them suborbital, whose length is interpolated between the two in log
    space and whose height follows from the same steepness law. d0 and D in m; d0 = 0 gives
    (0, 0, "no motion")."""
    D = float(grain_diameter)
    d0 = float(d0)
    if not (D > 0):
        raise ValueError(f"grain_diameter = {grain_diameter!r}: must be a positive length in m")
    if not (d0 > 0):
        return 0.0, 0.0, "no motion"

    def height_for(length):
        # With y = ln(d0 / height) the steepness law is the quadratic
        # 0.095 y^2 - 1.442 y + 2.28 + ln(d0 / length) = 0; its smaller root is the branch on
        # which steepness falls as d0 / height grows (y > 2.33). No root (d0 > 24 lengths): the
        # flattest ripple the law allows, at its vertex.
        c = 2.28 + math.log(d0 / length)
        y = (1.442 - math.sqrt(max(1.442**2 - 4 * 0.095 * c, 0.0))) / 0.19
        return d0 * math.exp(-y)

    l_orb = 0.62 * d0
    l_ano = 535.0 * D
    h_ano = height_for(l_ano)
    ratio = d0 / h_ano
    if ratio < 20.0:
        return l_orb, 0.17 * l_orb, "orbital"
    if ratio > 100.0:
        return l_ano, h_ano, "anorbital"
    w = (math.log(ratio) - math.log(100.0)) / (math.log(20.0) - math.log(100.0))
    l_sub = math.exp(w * (math.log(l_orb) - math.log(l_ano)) + math.log(l_ano))
    return l_sub, height_for(l_sub), "suborbital"


def ripple_band(z, dx):
    """The hysteresis band of periodic_ripples: half the bed's RMS about its mean (a sine's crest
    to trough is 2.8 RMS, so a bump under a fifth of the ripples' height is not counted), and at
    least a tenth of a spacing."""
    z = np.asarray(z, float)
    return max(0.1 * dx, 0.5 * float(np.std(z)))


def periodic_ripples(z, length, band):
    """(count, mean height) of the ripples on a periodic bed z (evenly spaced over `length`): each
    ripple is one rise of z - mean from below -band/2 to above +band/2 (a crossing with hysteresis,
    so a wiggle smaller than `band` in a trough is not a ripple), counted round the period; the
    mean length is length / count. Counting round the period keeps the ripple that straddles the
    seam, which the zero up-crossings of ripple_stats drop. (0, NaN) without a ripple."""
    zd = np.asarray(z, float) - float(np.mean(z))
    if len(zd) < 4:
        return 0, float("nan")
    zd = np.roll(zd, -int(np.argmin(zd)))  # start in the deepest trough: below -band/2 if any ripple is
    lo, hi = -0.5 * band, 0.5 * band
    state, starts = "low", []
    for i, v in enumerate(zd):
        if state == "low" and v > hi:
            state = "high"
            starts.append(i)
        elif state == "high" and v < lo:
            state = "low"
    if not starts or zd[0] >= lo:
        return 0, float("nan")
    bounds = starts + [len(zd) + starts[0]]
    zz = np.concatenate([zd, zd])
    heights = [zz[a:b].max() - zz[a:b].min() for a, b in zip(bounds[:-1], bounds[1:])]
    return len(starts), float(np.mean(heights))
