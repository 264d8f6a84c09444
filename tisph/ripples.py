"""Bed measurement: the sediment surface along x, and ripple statistics of the bed change.

Ripples are measured on the bed change z(x) = bed(x, t) - bed(x, 0) over the active zone, after
removing its linear trend (net erosion or deposition across the zone is not a ripple). Zero
up-crossings split z into ripples; each ripple's length is the distance between consecutive
up-crossings and its height is crest minus trough between them (the zero-crossing method of
wave analysis, applied along x). Wiberg & Harris (1994): orbital ripples have a length of about
0.62 d0, with d0 = H / sinh(kh) the near-bed orbital diameter.
"""
import numpy as np


def ripple_stats(x, z):
    """(mean ripple length, mean ripple height, rms of z) of bed change z sampled at x (ascending).

    Length and height are NaN when fewer than two up-crossings (one whole ripple) are found."""
    x, z = np.asarray(x, float), np.asarray(z, float)
    ok = np.isfinite(z)
    x, z = x[ok], z[ok]
    if len(x) < 4:
        return float("nan"), float("nan"), float("nan")
    rms = float(np.sqrt(np.mean(z * z)))
    zd = z - np.polyval(np.polyfit(x, z, 1), x)
    s = np.signbit(zd)
    up = np.nonzero(s[:-1] & ~s[1:])[0]          # zd goes from < 0 to >= 0 between up and up + 1
    if len(up) < 2:
        return float("nan"), float("nan"), rms
    # the crossing point, interpolated between the two samples
    xc = x[up] - zd[up] * (x[up + 1] - x[up]) / (zd[up + 1] - zd[up])
    lengths, heights = [], []
    for a, b in zip(up[:-1], up[1:]):
        seg = zd[a + 1:b + 1]
        heights.append(float(seg.max() - seg.min()))
    lengths = np.diff(xc)
    return float(np.mean(lengths)), float(np.mean(heights)), rms


def orbital_diameter(H, k, depth):
    """Near-bed orbital diameter of linear waves, d0 = H / sinh(k h)."""
    return H / np.sinh(k * depth)
