"""Shapes of a case in metres (polylines, polygons, circles, boxes) and how they become particles.

Every particle sits on one lattice, cell-centred at ((i + 1/2) dx, (j + 1/2) dx) from the origin
(the lattice the built-in scenes use), so water and wall particles never overlap and a wall drawn
along x = 0 puts its layers exactly where the dam break's blocks put them. A solid's wall
particles are the lattice points on its solid side within `layers` spacings of its surface
(DualSPHysics' GenCase fills a drawn shape on its lattice the same way).
"""

import math

import numpy as np

from .particles import BUILD_BYTES_PER_POINT, check_fits

CHUNK = 4096  # points per block in the point-to-segment distances (memory: CHUNK x segments)


def _as_points(pts):
    a = np.asarray(pts, float).reshape(-1, 2)
    return a


def segment_distance(p, a, b):
    """(distance, parameter t in [0, 1], unclamped t) of each point p (N, 2) to each segment a-b (M, 2):
    arrays (N, M)."""
    d = b - a
    L2 = np.maximum((d * d).sum(1), 1e-300)
    rel = p[:, None, :] - a[None, :, :]
    tu = (rel * d[None]).sum(2) / L2
    t = np.clip(tu, 0.0, 1.0)
    q = rel - t[..., None] * d[None]
    return np.sqrt((q * q).sum(2)), t, tu


def crossings(pts, closed):
    """Pairs (i, j) of segments that cross (not neighbours sharing a vertex): a shape drawn over itself."""
    p = _as_points(pts)
    a = p if closed else p[:-1]
    b = np.roll(p, -1, axis=0) if closed else p[1:]
    n = len(a)
    if n < 3:
        return []

    def orient(o, u, v):
        return (u[..., 0] - o[..., 0]) * (v[..., 1] - o[..., 1]) - (u[..., 1] - o[..., 1]) * (v[..., 0] - o[..., 0])

    A, B = a[:, None], b[:, None]
    C, D = a[None, :], b[None, :]
    d1, d2 = orient(C, D, A), orient(C, D, B)
    d3, d4 = orient(A, B, C), orient(A, B, D)
    cross = (d1 * d2 < 0) & (d3 * d4 < 0)
    i, j = np.nonzero(np.triu(cross, 2))
    keep = ~(closed & (i == 0) & (j == n - 1))
    return list(zip(i[keep].tolist(), j[keep].tolist()))


def in_polygon(pts, poly):
    """Even-odd rule: which points lie inside the closed polygon."""
    x, y = pts[:, 0], pts[:, 1]
    inside = np.zeros(len(pts), bool)
    px, py = poly[:, 0], poly[:, 1]
    qx, qy = np.roll(px, -1), np.roll(py, -1)
    for k in range(len(poly)):
        up = (py[k] > y) != (qy[k] > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = px[k] + (y - py[k]) * (qx[k] - px[k]) / (qy[k] - py[k])
        inside ^= up & (x < xc)
    return inside


class Polygon:
    """A closed polygon; the solid is its inside."""

    def __init__(self, pts, label=""):
        self.pts, self.label = _as_points(pts), label
        if len(self.pts) > 1 and np.allclose(self.pts[0], self.pts[-1]):
            self.pts = self.pts[:-1]

    def segments(self):
        return self.pts, np.roll(self.pts, -1, axis=0)

    def inside(self, p):
        return in_polygon(p, self.pts)

    def distance(self, p):
        a, b = self.segments()
        out = np.empty(len(p))
        for s in range(0, len(p), CHUNK):
            out[s : s + CHUNK] = segment_distance(p[s : s + CHUNK], a, b)[0].min(1)
        return out

    def band(self, p, thickness):
        """Lattice points of the wall: inside, within `thickness` of the surface."""
        ins = self.inside(p)
        out = np.zeros(len(p), bool)
        out[ins] = self.distance(p[ins]) < thickness
        return out

    def bounds(self):
        return self.pts.min(0), self.pts.max(0)


class Circle(Polygon):
    """A circle (xc, zc, r); the solid is its inside (a pipe)."""

    def __init__(self, xc, zc, r, label=""):
        self.c, self.r, self.label = np.array([xc, zc], float), float(r), label
        n = max(64, int(2 * math.pi * r / 1e-3) // 8)
        th = np.linspace(0, 2 * math.pi, n, endpoint=False)
        self.pts = self.c + self.r * np.column_stack([np.cos(th), np.sin(th)])

    def inside(self, p):
        return np.hypot(*(p - self.c).T) < self.r

    def distance(self, p):
        return np.abs(np.hypot(*(p - self.c).T) - self.r)


class Polyline:
    """An open polyline; the solid is on its right as one walks along it, so the water is on the
    left (a tank drawn from the top of its left wall down, along the floor and up the right wall;
    a bathymetry drawn from left to right). Its first and last segments continue as rays, so the
    sides are defined everywhere; the wall layers stop square at its ends."""

    def __init__(self, pts, label=""):
        self.pts, self.label = _as_points(pts), label

    def segments(self):
        return self.pts[:-1], self.pts[1:]

    def _nearest(self, p):
        a, b = self.segments()
        d, t, tu = np.empty((len(p),)), np.empty((len(p),)), np.empty((len(p),))
        seg = np.empty(len(p), int)
        for s in range(0, len(p), CHUNK):
            dd, tt, uu = segment_distance(p[s : s + CHUNK], a, b)
            # the end segments extend as rays: their distance is to the line beyond the end
            last = len(a) - 1
            for k, off in ((0, uu[:, 0] < 0), (last, uu[:, last] > 1)):
                if off.any():
                    rel = p[s : s + CHUNK][off] - a[k]
                    dk = b[k] - a[k]
                    q = rel - uu[off, k][:, None] * dk
                    dd[off, k] = np.hypot(q[:, 0], q[:, 1])
                    tt[off, k] = uu[off, k]
            j = dd.argmin(1)
            r = np.arange(len(j))
            d[s : s + CHUNK], t[s : s + CHUNK], tu[s : s + CHUNK], seg[s : s + CHUNK] = dd[r, j], tt[r, j], uu[r, j], j
        return d, t, tu, seg

    def _right_normals(self):
        a, b = self.segments()
        d = b - a
        d = d / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-300)[:, None]
        return np.column_stack([d[:, 1], -d[:, 0]])

    def inside(self, p):
        """The solid side: right of the nearest segment; at a vertex, of the two segments' mean normal."""
        a, b = self.segments()
        n = self._right_normals()
        _, t, _, seg = self._nearest(p)
        normal = n[seg].copy()
        m = len(a)
        at_end = (t >= 1.0) & (seg < m - 1)
        at_start = (t <= 0.0) & (seg > 0)
        normal[at_end] += n[seg[at_end] + 1]
        normal[at_start] += n[seg[at_start] - 1]
        base = np.where(t[:, None] >= 1.0, b[seg], a[seg])
        base = np.where(((t > 0) & (t < 1))[:, None], a[seg], base)
        return ((p - base) * normal).sum(1) > 0

    def distance(self, p):
        return self._nearest(p)[0]

    def offset(self, thickness):
        """The line moved `thickness` to its solid side, mitred at the joints."""
        n = self._right_normals()
        off = np.empty_like(self.pts)
        off[0], off[-1] = n[0], n[-1]
        for k in range(1, len(self.pts) - 1):
            s = n[k - 1] + n[k]
            c = 1.0 + float(n[k - 1] @ n[k])
            off[k] = s / c if c > 0.25 else s / max(np.hypot(*s), 1e-300)  # very sharp joints: no long spike
        return self.pts + thickness * off

    def band(self, p, thickness):
        """Lattice points of the wall: on the solid side, inside the mitred strip `thickness` wide."""
        strip = np.vstack([self.pts, self.offset(thickness)[::-1]])
        ins = self.inside(p)
        out = np.zeros(len(p), bool)
        out[ins] = in_polygon(p[ins], strip)
        # where the strip folds over itself (a concave joint with short segments), the distance decides
        d, t, tu, seg = self._nearest(p[ins])
        m = len(self.pts) - 1
        within = (d < thickness) & ~((seg == 0) & (tu < 0)) & ~((seg == m - 1) & (tu > 1))
        out[ins] |= within
        return out

    def bounds(self):
        return self.pts.min(0), self.pts.max(0)


def lattice(x0, x1, z0, z1, dx):
    """The lattice points in [x0, x1] x [z0, z1], cell-centred on the global lattice."""
    i0, i1 = math.ceil(x0 / dx - 0.5 - 1e-9), math.floor(x1 / dx - 0.5 + 1e-9)
    j0, j1 = math.ceil(z0 / dx - 0.5 - 1e-9), math.floor(z1 / dx - 0.5 + 1e-9)
    nx, nz = max(i1 - i0 + 1, 0), max(j1 - j0 + 1, 0)
    check_fits(nx * nz, BUILD_BYTES_PER_POINT, dx, "the case's lattice", "points")
    gx, gz = np.meshgrid((np.arange(i0, i1 + 1) + 0.5) * dx, (np.arange(j0, j1 + 1) + 0.5) * dx, indexing="ij")
    return np.column_stack([gx.ravel(), gz.ravel()])


def inscribed(shape_inside, pts, dist):
    """Twice the largest distance from a lattice point inside to the surface: the thickness of a
    shape's thickest part (0 if no lattice point falls inside)."""
    if not shape_inside.any():
        return 0.0
    return 2.0 * float(dist[shape_inside].max())


def read_profile(path):
    """(x, z) points of a CSV profile: two numeric columns, header and # comment lines allowed before
    the first row, sorted by x."""
    rows = []
    with open(path, encoding="utf-8-sig") as f:
        for n, line in enumerate(f, 1):
            cells = [c.strip() for c in line.replace(";", ",").split(",") if c.strip()]
            if not cells or cells[0].startswith("#"):
                continue
            try:
                rows.append([float(cells[0]), float(cells[1])])
            except (ValueError, IndexError):
                if rows:
                    raise ValueError(f"line {n}: {line.strip()!r} is not two numbers x, z") from None
    pts = np.array(rows, float).reshape(-1, 2)
    if len(pts) < 2:
        raise ValueError("fewer than two (x, z) points")
    if not np.isfinite(pts).all():
        raise ValueError("a value that is not a finite number")
    order = np.argsort(pts[:, 0], kind="stable")
    pts = pts[order]
    if (np.diff(pts[:, 0]) == 0).any():
        raise ValueError(f"two points at the same x = {pts[1:, 0][np.diff(pts[:, 0]) == 0][0]:g} m (a profile is z(x))")
    return pts
