"""A particle field interpolated onto a panel's pixels with the SPH kernel, for frames drawn as
continuous fields (tisph/viz/render.py) rather than discs."""

import numpy as np

from ..kernels import CubicSpline2D as K

SHEPARD_CUT = 0.35  # the water ends where the kernel sum falls under this: 0.5 a free surface's
# half spacing out, a lone droplet 0.45 at its centre (it stays drawn)


def kernel_image(x, f, origin, scale, dx, W, H, ey=1.0):
    """f at the points x interpolated onto a W x H image (pixels of 1 / scale m from origin, of
    1 / (ey scale) m upwards: heights exaggerated ey times) with the cubic spline at h = dx,
    normalised by the kernel sum (each point's volume dx^2); returns (values, inside) with rows
    top to bottom, inside where the sum reaches SHEPARD_CUT. Summed on a grid of about a third of
    the support a cell, every cell offset at once, then bilinear onto the pixels (a zoom's kernel
    spans many)."""
    g = max(1, int(round(K.support * dx * scale / 3)))  # px a grid cell
    cell = g / scale
    gw, gh = -(-W // g), -(-H // g)
    px, py = (x[:, 0] - origin[0]) / cell - 0.5, ey * (x[:, 1] - origin[1]) / cell - 0.5
    rc = int(np.ceil(K.support * dx / cell))
    ry = int(np.ceil(ey * K.support * dx / cell))
    near = (px > -rc - 1) & (px < gw + rc) & (py > -ry - 1) & (py < gh + ry)
    px, py, f = px[near], py[near], f[near]
    oy, ox = (o.ravel() for o in np.mgrid[-ry : ry + 2, -rc : rc + 2])
    ix = np.floor(px).astype(int)[:, None] + ox[None, :]
    iy = np.floor(py).astype(int)[:, None] + oy[None, :]
    q = np.hypot(ix - px[:, None], (iy - py[:, None]) / ey) * (cell / dx)
    ok = (q < K.support) & (ix >= 0) & (ix < gw) & (iy >= 0) & (iy < gh)
    w, idx = K.sigma * K.shape_np(q[ok]), (iy * gw + ix)[ok]  # sigma / h^2 times V = dx^2
    den = np.bincount(idx, weights=w, minlength=gw * gh).reshape(gh, gw)
    num = np.bincount(idx, weights=w * np.broadcast_to(f[:, None], ok.shape)[ok], minlength=gw * gh).reshape(gh, gw)
    if g > 1:
        den, num = (_bilinear(_bilinear(a, H, g, 0), W, g, 1) for a in (den, num))
    with np.errstate(invalid="ignore", divide="ignore"):
        val = np.where(den > 0, num / den, 0.0)
    return val[::-1], (den >= SHEPARD_CUT)[::-1]


def _bilinear(a, n, g, axis):
    """a, sampled at the centres of cells g pixels wide along axis, at the centres of n pixels
    (held at the end values beyond the first and last centre)."""
    m = a.shape[axis]
    if m == 1:
        return np.repeat(a, n, axis)
    c = np.clip((np.arange(n) + 0.5) / g - 0.5, 0, m - 1)
    i = np.minimum(np.floor(c).astype(int), m - 2)
    t = (c - i)[:, None] if axis == 0 else (c - i)[None, :]
    return np.take(a, i, axis) * (1 - t) + np.take(a, i + 1, axis) * t
