"""A case file's particles: the solids' wall layers, the water regions and the paddle on one
lattice, with the geometry checks (a shape drawn over itself, a feature thinner than two spacings,
water not held, a paddle without water or floor) raised as ConfigErrors naming the entry."""

import math
import warnings

import numpy as np

from ...geometry import Circle, Polygon, Polyline, crossings, in_polygon, lattice
from ...settings.config import ConfigError

AIR, WATER, SOLID, OUTSIDE = 0, 1, 2, 3


def shape_of(s):
    k = s["shape"]
    if k == "line":
        return Polyline(s["line"], s["label"])
    if k == "polygon":
        return Polygon(s["polygon"], s["label"])
    if k == "box":
        x0, x1, z0, z1 = s["box"]
        return Polygon([[x0, z0], [x1, z0], [x1, z1], [x0, z1]], s["label"])
    return Circle(*s["circle"], label=s["label"])


def who(item):
    return f"{item['name']}" + (f" ('{item['label']}')" if item.get("label") else "")


class Layout:
    """Lattice points sorted into walls and water, with what the checks and the build need."""

    def __init__(self, box, solids, waters, dx, layers, errors):
        self.box, self.dx, self.T = box, dx, layers * dx
        x0, x1, z0, z1 = box
        pad = self.T + dx
        self.pts = lattice(x0 - pad, x1 + pad, z0 - pad, z1 + pad, dx)
        p = self.pts
        self.in_box = (p[:, 0] > x0) & (p[:, 0] < x1) & (p[:, 1] > z0) & (p[:, 1] < z1)
        self.wall = np.zeros(len(p), bool)
        self.solid = np.zeros(len(p), bool)
        self.shapes = []
        for s in solids:
            if "shape" not in s:
                continue
            shape = shape_of(s)
            pts = s.get(s["shape"])
            if s["shape"] in ("line", "polygon"):
                bad = crossings(pts, s["shape"] == "polygon")
                if bad:
                    i, j = bad[0]
                    errors.append(
                        ConfigError(
                            f"{s['name']}.{s['shape']}",
                            f"segments {i} and {j} cross",
                            "a shape that does not cross itself",
                        )
                    )
                    continue
            lo, hi = shape.bounds()
            if hi[0] < x0 or lo[0] > x1 or hi[1] < z0 or lo[1] > z1:
                errors.append(
                    ConfigError(
                        s["name"],
                        f"bounds x {lo[0]:g}..{hi[0]:g}, z {lo[1]:g}..{hi[1]:g} m",
                        f"a solid inside domain.box = {list(box)}",
                    )
                )
                continue
            inside = shape.inside(p)
            if s["shape"] != "line":
                thick = 2.0 * float(shape.distance(p[inside]).max()) if inside.any() else 0.0
                if thick < 2 * dx:
                    errors.append(
                        ConfigError(
                            s["name"],
                            f"{thick:.3g} m thick" if thick else "no lattice point inside",
                            f"a solid at least two particle spacings thick (2 dx = {2 * dx:g} m)",
                            "draw it thicker or lower numerics.dx",
                        )
                    )
                    continue
            self.solid |= inside
            self.wall |= shape.band(p, self.T)
            self.shapes.append((s, shape))
        self.water = np.zeros(len(p), bool)
        self.velocity = np.zeros((len(p), 2))
        self.region = np.full(len(p), -1)
        for w in waters:
            self._fill(w, errors)

    def solid_region(self, p):
        """Points inside the solids as drawn (a polygon or circle whole, a line's wall band): the
        frames fill it in place of its particles, so a slope is drawn as the line it is."""
        p = np.asarray(p, float).reshape(-1, 2)
        out = np.zeros(len(p), bool)
        for s, shape in self.shapes:
            out |= shape.band(p, self.T) if s["shape"] == "line" else shape.inside(p)
        return out

    def _fill(self, w, errors):
        p, dx = self.pts, self.dx
        if w["polygon"]:
            poly = np.asarray(w["polygon"])
            if crossings(w["polygon"], True):
                errors.append(
                    ConfigError(f"{w['name']}.polygon", "crosses itself", "a polygon that does not cross itself")
                )
                return
            x0, x1, z0, z1 = self.box
            out = poly[((poly < [x0 - 0.5 * dx, z0 - 0.5 * dx]) | (poly > [x1 + 0.5 * dx, z1 + 0.5 * dx])).any(1)]
            if len(out):  # said first: past the box, it is also in the walls that close the box
                errors.append(
                    ConfigError(
                        f"{w['name']}.polygon",
                        w["polygon"],
                        f"corners inside domain.box = [{x0:g}, {x1:g}, {z0:g}, {z1:g}]",
                        f"({out[0][0]:g}, {out[0][1]:g}) m lies outside it",
                    )
                )
                return
            sel = in_polygon(p, poly)
            over = sel & self.solid
            if over.any():
                q = p[over][0]
                errors.append(
                    ConfigError(
                        f"{w['name']}.polygon",
                        w["polygon"],
                        "a region clear of the solids",
                        f"{int(over.sum())} of its particles would overlap a solid, the first at "
                        f"({q[0]:.4g}, {q[1]:.4g}) m; a level fill stops at the solids by itself",
                    )
                )
                return
        else:
            sel = (p[:, 1] < w["level"]) & ~self.solid & self.in_box  # a level fills the domain, no further
            if w["x"]:
                sel &= (p[:, 0] > w["x"][0]) & (p[:, 0] < w["x"][1])
        sel &= ~self.wall
        outside = sel & ~self.in_box
        if outside.any():
            q = p[outside][0]
            errors.append(
                ConfigError(
                    who(w),
                    f"water at ({q[0]:.4g}, {q[1]:.4g}) m",
                    f"water inside domain.box = {list(self.box)}",
                    "the region reaches past the domain",
                )
            )
            return
        if not sel.any():
            errors.append(
                ConfigError(
                    who(w),
                    "no particle",
                    f"a region with water in it (at least one lattice point at dx = {dx:g} m clear of the solids)",
                )
            )
            return
        # thinner than two spacings: no column or no row of the region holds two particles
        ij = np.round(p[sel] / dx - 0.5).astype(int)
        cols = np.unique(ij[:, 0], return_counts=True)[1].max()
        rows = np.unique(ij[:, 1], return_counts=True)[1].max()
        if min(cols, rows) < 2:
            errors.append(
                ConfigError(
                    who(w),
                    f"{min(cols, rows)} particle {'row' if cols < 2 else 'column'}",
                    f"a region at least two particle spacings thick (2 dx = {2 * dx:g} m)",
                )
            )
            return
        self.water |= sel
        self.velocity[sel] = w["velocity"]
        self.region[sel] = w["index"]

    def unheld(self, outflow, paddle_x=None):
        """The first water point with a lattice neighbour outside the box that is not a wall (the water
        would run out of the domain), unless it lies in an outflow box or behind the paddle's face
        at paddle_x (the paddle holds it; its own room is checked with it); None if all are held."""
        p, dx = self.pts, self.dx
        key = {tuple(k): n for n, k in enumerate(np.round(p / dx - 0.5).astype(int))}
        ij = np.round(p[self.water] / dx - 0.5).astype(int)
        for q, (i, j) in zip(p[self.water], ij):
            for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                n = key.get((i + di, j + dj))
                if n is not None and (self.in_box[n] or self.wall[n]):
                    continue
                nb = q + dx * np.array([di, dj])
                if paddle_x is not None and nb[0] <= paddle_x:
                    continue
                if any(b[0] <= nb[0] <= b[1] and b[2] <= nb[1] <= b[3] for b in outflow):
                    continue
                return q, (di, dj)
        return None

    def column(self, x):
        """(floor, level) of the water in the lattice column just right of x: its lowest and highest
        particle, half a spacing out; None if there is no water there."""
        dx = self.dx
        xc = (math.floor(x / dx - 0.5 + 1e-9) + 1.5) * dx  # the first column centre past x
        sel = self.water & (np.abs(self.pts[:, 0] - xc) < 0.25 * dx)
        if not sel.any():
            return None
        z = self.pts[sel, 1]
        return float(z.min()) - 0.5 * dx, float(z.max()) + 0.5 * dx

    def warn_levels(self, waters, stroke_note=""):
        """A [[water]] level the lattice cannot hold as written: a level fills whole rows of
        particles, so the still water stands at the top of the last row (0.39 m for level = 0.40
        at dx = 0.03); said at the start, with the level the run uses and a dx that keeps the
        written one. stroke_note: the paddle's stroke for the level used, where Biesel set it."""
        dx, z0 = self.dx, self.box[2]
        for w in waters:
            mine = self.region == w["index"]
            if w["polygon"] or not mine.any():
                continue
            top = float(self.pts[mine, 1].max()) + 0.5 * dx
            if abs(top - w["level"]) <= 1e-6 * max(1.0, abs(w["level"])):
                continue
            rows = math.ceil((w["level"] - z0) / dx - 1e-9)
            warnings.warn(
                f"{who(w)}.level = {w['level']:g} m fills whole rows of particles up to {top:.4g} m at "
                f"numerics.dx = {dx:g} m: the run's still water stands at {top:.4g} m{stroke_note}; "
                f"numerics.dx = {(w['level'] - z0) / rows:.4g} m ({rows} rows above domain.box's floor) "
                "keeps the level as written"
            )
