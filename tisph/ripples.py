"""Bed measurement: the sediment surface along x, and ripple statistics of the bed change.

Ripples are measured on the bed change z(x) = bed(x, t) - bed(x, 0) over the active zone, after
removing its linear trend (net erosion or deposition across the zone is not a ripple) and, when a
window is given, its running mean over that window (a bar or a shoreline profile change is longer
than the window and is not a ripple either: a high-pass filter, as field ripple surveys use). Zero
up-crossings split z into ripples; each ripple's length is the distance between consecutive
up-crossings and its height is crest minus trough between them (the zero-crossing method of
wave analysis, applied along x). Wiberg & Harris (1994): orbital ripples have a length of about
0.62 d0, with d0 = H / sinh(kh) the near-bed orbital diameter.
"""
import numpy as np


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
    up = np.nonzero(s[:-1] & ~s[1:])[0]          # zd goes from < 0 to >= 0 between up and up + 1
    if len(up) < 2:
        return float("nan"), float("nan"), rms
    # the crossing point, interpolated between the two samples
    xc = x[up] - zd[up] * (x[up + 1] - x[up]) / (zd[up + 1] - zd[up])
    heights = np.array([zd[a + 1:b + 1].max() - zd[a + 1:b + 1].min() for a, b in zip(up[:-1], up[1:])])
    lengths = np.diff(xc)
    keep = (lengths >= min_length) & (heights >= min_height)
    if not keep.any():
        return float("nan"), float("nan"), rms
    return float(np.mean(lengths[keep])), float(np.mean(heights[keep])), rms


def orbital_diameter(H, k, depth):
    """Near-bed orbital diameter of linear waves, d0 = H / sinh(k h)."""
    return H / np.sinh(k * depth)
