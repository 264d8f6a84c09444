"""Numerical gauges: the free surface (or a sediment surface) along x from the particles."""

import functools

import numpy as np

from ..kernels import CubicSpline2D as K
from ..particles import FLUID


def _water(st, mat):
    """The fluid particles of material `mat` (None: every fluid)."""
    fl = st["kind"] == FLUID
    if mat is not None and st.get("mat") is not None:
        fl &= st["mat"] == mat
    return fl


def _near_columns(st, mat, xs, reach, field="v"):
    """The particles of material `mat` (None: every fluid), sorted by x, as (x, st[field],
    volume), and for each position in xs the index range [lo, hi) of those within `reach` of it in x."""
    fl = _water(st, mat)
    order = np.argsort(st["x"][fl][:, 0])
    x = st["x"][fl][order]
    v = np.asarray(st[field])[fl][order] if field in st else None
    vol = (st["m"][fl] / st["rho"][fl])[order]
    xs = np.asarray(xs, float)
    return x, v, vol, np.searchsorted(x[:, 0], xs - reach), np.searchsorted(x[:, 0], xs + reach)


def surface_heights(st, xs, dx, h, floor=0.0, mat=0):
    """Free-surface height at each x in xs, as a numerical wave gauge does it (DualSPHysics'
    approach): the highest point on the vertical line where the SPH-interpolated fraction of
    material `mat`, sum_j V_j W(x - x_j), is still at least 1/2 (linearly interpolated between
    samples a quarter spacing apart). Counting particles in a column instead steps by dx/2 and
    reads a wave three particles high with +-15 % noise."""
    x, _, vol, lo, hi = _near_columns(st, mat, xs, K.support * h)
    out = np.full(len(xs), float(floor))
    step = 0.25 * dx
    for k, xg in enumerate(xs):
        if hi[k] <= lo[k]:
            continue
        xn, vn = x[lo[k] : hi[k]], vol[lo[k] : hi[k]]
        ys = np.arange(max(floor, xn[:, 1].min() - dx), xn[:, 1].max() + 2 * h, step)
        r = np.hypot(xn[None, :, 0] - xg, xn[None, :, 1] - ys[:, None]) / h
        frac = (K.sigma / h**2 * K.shape_np(r) * vn[None, :]).sum(1)
        wet = np.nonzero(frac >= 0.5)[0]
        if len(wet):
            i = wet[-1]
            out[k] = ys[i]
            if i + 1 < len(ys):  # where the fraction crosses 1/2 between two samples
                out[k] += step * (frac[i] - 0.5) / max(frac[i] - frac[i + 1], 1e-12)
    return out


@functools.cache
def lattice_offset(dx, h):
    """What surface_heights reads above still water on the particle lattice, whose surface (the
    water's mass level) is half a spacing above its top row's centres: the gauge subtracts it, so
    it reads the water's level, whatever the surface at the start (a tilted one included)."""
    n = int(np.ceil(K.support * h / dx)) + 2
    X, Y = np.meshgrid(np.arange(-n, n + 1) * dx, (np.arange(-2 * n, 0) + 0.5) * dx)
    st = {
        "x": np.c_[X.ravel(), Y.ravel()],
        "kind": np.full(X.size, FLUID),
        "m": np.full(X.size, dx * dx),
        "rho": np.ones(X.size),
    }
    return float(surface_heights(st, [0.0], dx, h, floor=-1e9, mat=None)[0])


def particle_surface(st, xg, dx, mat=0):
    """The water's own surface over x at a lattice start: the top particle of material `mat`
    (None: every fluid) within half a spacing of x, plus half a spacing; None where dry."""
    near = _water(st, mat) & (np.abs(st["x"][:, 0] - xg) <= 0.5 * dx + 1e-9)
    return float(st["x"][near, 1].max()) + 0.5 * dx if near.any() else None


def surface_at(st, xg, dx, h, floor=0.0, mat=0):
    """surface_heights at a single x."""
    return float(surface_heights(st, [xg], dx, h, floor, mat)[0])


def velocity_at(st, points, h, mat=0):
    """SPH velocity of material `mat` at the given points, Shepard-normalised (sum V_j u_j W /
    sum V_j W, so a point near the bed or the surface is not biased low); NaN where no water is
    within the kernel."""
    return shepard_at(st, points, h, "v", mat)


def shepard_at(st, points, h, name, mat=0, min_fraction=0.0):
    """Shepard-normalised SPH interpolation of st[name] (a scalar or a 2-vector per particle) of
    material `mat` at the given points: sum V_j f_j W / sum V_j W (DualSPHysics' MeasureTool does
    the same); NaN where no water is within the kernel, or where the water fraction sum V_j W is
    under min_fraction (MeasureTool's KClimit, 0.5: a point in the air near one droplet reads
    nothing, not the droplet's value). All points at once: every (point, particle) pair in each
    point's column."""
    pts = np.asarray(points, float).reshape(-1, 2)
    x, f, vol, lo, hi = _near_columns(st, mat, pts[:, 0], K.support * h, field=name)
    f = f.reshape(len(x), -1)
    out = np.full((len(pts), f.shape[1]), np.nan)
    counts = np.maximum(hi - lo, 0)
    if counts.sum() == 0:
        return out if f.shape[1] > 1 else out[:, 0]
    k = np.repeat(np.arange(len(pts)), counts)
    first = np.cumsum(counts) - counts
    j = np.repeat(lo, counts) + (np.arange(counts.sum()) - np.repeat(first, counts))
    w = K.shape_np(np.hypot(x[j, 0] - pts[k, 0], x[j, 1] - pts[k, 1]) / h) * vol[j]
    sw = np.bincount(k, w, minlength=len(pts))
    ok = sw > max(min_fraction * h * h / K.sigma, 0.0)  # sum V W with W's normalisation sigma / h^2 left out
    for c in range(f.shape[1]):
        out[ok, c] = np.bincount(k, w * f[j, c], minlength=len(pts))[ok] / sw[ok]
    return out if f.shape[1] > 1 else out[:, 0]
