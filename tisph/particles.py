"""Particle kinds and NumPy builders for initial particle sets (blocks, tank walls)."""

from __future__ import annotations

import os

import numpy as np

from .settings.config import ConfigError

FLUID, WALL, MOVING, BED = 0, 1, 2, 3  # BED: boundary particles of a morphodynamic bed (they follow z_b)
# parked: left the domain (a leak), left through an open boundary, or torn off as spray and removed
OUT, OUTFLOW, SPRAY = -1, -2, -3
KIND_NAMES = {
    FLUID: "fluid",
    WALL: "fixed boundary",
    MOVING: "moving boundary",
    BED: "sand bed",
    OUT: "leaked",
    OUTFLOW: "outflow",
    SPRAY: "spray",
}


class ParticleSet:
    """Host-side particle arrays a scene builds; the solver copies them into Taichi fields."""

    def __init__(self):
        self.x = np.zeros((0, 2))
        self.v = np.zeros((0, 2))
        self.rho = np.zeros(0)
        self.m = np.zeros(0)
        self.kind = np.zeros(0, dtype=np.int32)
        self.mat = np.zeros(0, dtype=np.int32)
        self.wall_normal = np.zeros((0, 2))  # wall particles: unit normal into the fluid
        self.wall_dist = np.zeros(0)  # and distance behind the wall surface (no-slip)
        self.bed_station = np.zeros(0, dtype=np.int32)  # BED particles: their bed station (else -1)

    def add(self, x, kind, mat, rho, m, v=None, normal=None, wall_dist=None, station=None):
        x = np.asarray(x, dtype=float).reshape(-1, 2)
        n = len(x)
        st = np.full(n, -1, np.int32) if station is None else np.broadcast_to(np.asarray(station, np.int32), (n,))
        self.bed_station = np.concatenate([self.bed_station, st])
        nrm = np.zeros((n, 2)) if normal is None else np.broadcast_to(np.asarray(normal, float), (n, 2))
        wd = np.zeros(n) if wall_dist is None else np.broadcast_to(np.asarray(wall_dist, float), (n,))
        self.wall_normal = np.vstack([self.wall_normal, nrm])
        self.wall_dist = np.concatenate([self.wall_dist, wd])
        self.x = np.vstack([self.x, x])
        self.v = np.vstack([self.v, np.zeros((n, 2)) if v is None else np.broadcast_to(np.asarray(v, float), (n, 2))])
        self.rho = np.concatenate([self.rho, np.broadcast_to(np.asarray(rho, float), (n,))])
        self.m = np.concatenate([self.m, np.broadcast_to(np.asarray(m, float), (n,))])
        self.kind = np.concatenate([self.kind, np.full(n, kind, np.int32)])
        self.mat = np.concatenate([self.mat, np.full(n, mat, np.int32)])
        return slice(len(self.x) - n, len(self.x))

    def __len__(self):
        return len(self.x)

    def count(self, kind):
        return int(np.sum(self.kind == kind))


# Memory a run takes per particle: measured 11 GB resident for 22 million particles (dam break,
# dx 3e-4), i.e. about 500 bytes: the solver's fields (particles, sorted copy, backup) and the
# builders' arrays. Building a lattice takes about 64 bytes a point (coordinates and masks).
RUN_BYTES_PER_PARTICLE = 500
BUILD_BYTES_PER_POINT = 64


def available_memory():
    """Bytes this machine can still give (MemAvailable), or None if unknown."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def _gb(b):
    return f"{b / 1e12:.3g} TB" if b >= 1e12 else f"{b / 1e9:.3g} GB"


def check_fits(count, per, dx, what, unit="particles"):
    """Refuse (exit 2, on numerics.dx) a case whose `count` items at `per` bytes each cannot fit."""
    avail = available_memory()
    if avail is not None and count * per > avail:
        raise ConfigError(
            "numerics.dx",
            dx,
            "a spacing whose particles fit in this machine's memory",
            f"{what} of {count:.3g} {unit} needs about {_gb(count * per)} "
            f"({per} bytes each); {_gb(avail)} is available",
        )


def block(x0, y0, x1, y1, dx):
    """Cell-centred lattice filling [x0, x1] x [y0, y1]: points at (i + 1/2) dx from the corner."""
    nx = int(round((x1 - x0) / dx))
    ny = int(round((y1 - y0) / dx))
    check_fits(max(nx, 0) * max(ny, 0), BUILD_BYTES_PER_POINT, dx, "a lattice", "points")
    if nx < 1 or ny < 1:
        return np.zeros((0, 2))
    gx, gy = np.meshgrid(x0 + (np.arange(nx) + 0.5) * dx, y0 + (np.arange(ny) + 0.5) * dx, indexing="ij")
    return np.column_stack([gx.ravel(), gy.ravel()])


def box_walls(x0, y0, x1, y1, dx, layers=3, top=False):
    """Walls around the box [x0, x1] x [y0, y1] (left, right, bottom, and top if asked).

    `layers` rows of particles at spacing dx, the first half a spacing outside the box, so the
    fluid lattice continues into the wall and the wall fills the kernel support (DualSPHysics'
    DBC layout). The same layout serves the repulsive walls: a fluid particle next to the wall
    then sits at the repulsive force's zero, r0 = dx (paper 000 eq. 6).
    """
    L = layers
    pts = block(x0 - L * dx, y0 - L * dx, x1 + L * dx, y1 + (L * dx if top else 0.0), dx)
    inside = (pts[:, 0] > x0) & (pts[:, 0] < x1) & (pts[:, 1] > y0)
    if top:
        inside &= pts[:, 1] < y1
    return pts[~inside]


def tait_B(rho0, c0, gamma=7.0):
    """Tait stiffness B = c0^2 rho0 / gamma (paper 000 eqs. 11-12)."""
    return c0 * c0 * rho0 / gamma


def hydrostatic_density(depth, rho0, c0, g, gamma=7.0):
    """Density that gives p = rho0 g depth through the Tait equation, so a column starts at rest."""
    B = tait_B(rho0, c0, gamma)
    return rho0 * (1.0 + rho0 * g * np.maximum(depth, 0.0) / B) ** (1.0 / gamma)


def density_from_pressure(p, rho0, c0, gamma=7.0):
    """Inverse Tait: the density of a material at pressure p."""
    return rho0 * (1.0 + np.asarray(p, float) / tait_B(rho0, c0, gamma)) ** (1.0 / gamma)


def layered_pressure(y, y_bed, y_top, rho_w, rho_s, g=9.81):
    """Hydrostatic pressure at height y under water (surface y_top) over a sediment layer (surface
    y_bed): the water column above max(y, y_bed) plus the sediment column above y."""
    y, y_bed = np.asarray(y, float), np.asarray(y_bed, float)
    return rho_w * g * np.maximum(y_top - np.maximum(y, y_bed), 0.0) + rho_s * g * np.maximum(y_bed - y, 0.0)


def wall_density(walls, fluid_x, dx, h, rho0, c0, g):
    """Hydrostatic start for wall particles: the density of the water column standing above them
    (within a kernel support), rest density where no water is near."""
    top = surface_above(walls[:, 0], fluid_x, dx, 2 * h)
    return hydrostatic_density(top - walls[:, 1], rho0, c0, g)


def surface_above(xq, fluid_x, dx, reach):
    """Free-surface height above each query x: the top of the fluid columns within `reach`.

    Returns -inf where no fluid is near. Used to give boundary particles a hydrostatic start.
    """
    if len(fluid_x) == 0:
        return np.full(len(xq), -np.inf)
    xs, ys = fluid_x[:, 0], fluid_x[:, 1] + 0.5 * dx
    order = np.argsort(xs)
    xs, ys = xs[order], ys[order]
    out = np.full(len(xq), -np.inf)
    lo = np.searchsorted(xs, xq - reach, side="left")
    hi = np.searchsorted(xs, xq + reach, side="right")
    # running max over sorted x using a sparse-table-free loop over unique windows
    for k in range(len(xq)):
        if hi[k] > lo[k]:
            out[k] = ys[lo[k] : hi[k]].max()
    return out
