"""The bed-load bed's initial state: the random bed, the water over it and its BED particles
(the tunnel, the beach, the pipeline and custom cases build theirs from these)."""

import numpy as np

from ..particles import BED, BUILD_BYTES_PER_POINT, check_fits
from .bed import Bed, Sand


def random_bed_rms(sed, roughness, d0):
    """The random bed's RMS (m): sediment.seed_rms, or roughness x d0 where it is 0 (rounded to a
    nanometre: the same RMS typed as a number gives the same bed). Where a random bed's ripples end
    depends on its roughness over d0 (docs/sediment.md), so the tunnel and the beach scale it."""
    return sed["seed_rms"] or round(roughness * d0, 9)


def initial_bed(stations, z, sed, dx, periodic, top=None):
    """The initial bed: z plus a random perturbation of RMS seed_rms, smoothed over 2 dx (a white
    perturbation at one station would be a 1-dx spike) and rescaled to that RMS, then relaxed to
    the angle of repose (Bed.avalanche), as sand rests: a 3 mm bed at dx = 6.7 mm had 20 of its 363
    faces steeper, and the first bed update slid them down at 0.45 m/s into the water above
    (largest density error 4.9 %). top: the level of the water the scene lays over it afterwards
    (water_columns), whose particles must fit before the relaxation, a Python loop that would run
    for hours on a bed too fine, is started."""
    z = np.array(z, float)
    count = len(z) if top is None else int(np.sum(np.maximum(np.ceil((top - z) / dx), 0))) + len(z)
    check_fits(count, BUILD_BYTES_PER_POINT, dx, "the water over the bed", "points")
    if sed["seed_rms"] > 0:
        rng = np.random.default_rng(int(sed["seed"]))
        e = rng.standard_normal(len(stations))
        k = np.array([0.25, 0.5, 0.25])
        for _ in range(2):
            e = k[0] * np.roll(e, 1) + k[1] * e + k[2] * np.roll(e, -1)
        e -= e.mean()
        z += sed["seed_rms"] * e / np.sqrt(np.mean(e * e))
        bed = Bed(
            np.asarray(stations, float),
            z,
            Sand(3e-4, repose_deg=sed["repose_angle"]),  # the grain:
            periodic=periodic,
        )  # unused here
        bed.avalanche()
        z = bed.z
    return z


def above_bed(points, stations, z, dx):
    """(Which points lie at least dx/2 above the bed z, each point's station): the lattice points
    a scene keeps as water over a bed whose stations lie dx apart from x = dx/2."""
    col = np.clip((points[:, 0] / dx).astype(int), 0, len(stations) - 1)
    return points[:, 1] >= z[col] + 0.5 * dx, col


def add_bed_particles(ps, stations, zb, dx, layers, rho_w, density):
    """BED particles: at each station a column `layers` deep under z_b, spaced dx; density(y)
    gives their rest-state density (hydrostatic). Their wall normal is up and their distance
    behind the surface (k + 1/2) dx, for a no-slip wall (NoSlip, paper 002 eq. 39)."""
    for k in range(layers):
        y = zb - (k + 0.5) * dx
        pts = np.column_stack([stations, y])
        ps.add(
            pts,
            BED,
            0,
            density(y),
            rho_w * dx * dx,
            station=np.arange(len(stations)),
            normal=(0.0, 1.0),
            wall_dist=(k + 0.5) * dx,
        )


def water_columns(x, zb, dx, top):
    """Water particles in columns at x over a bed at zb (its level under each column): from dx/2
    above the bed, dx apart, below top. A lattice cut by a rough bed leaves the lowest particle
    dx/2 to 3 dx/2 above it, a gap each column falls through in the first 0.1 s; the pressure wave
    of that fall set the tunnel's largest density error (2.9 % over a 3 mm random bed at
    c0 = 12.1 m/s, against 0.95 % over a flat one). Here the top is ragged by up to dx instead,
    at the free surface where nothing falls onto it."""
    x, zb = np.asarray(x, float), np.asarray(zb, float)
    n = np.maximum(np.ceil((top - zb - 0.5 * dx) / dx - 1e-9), 0).astype(int)
    col = np.repeat(np.arange(len(x)), n)
    k = np.arange(len(col)) - np.repeat(np.cumsum(n) - n, n)
    return np.column_stack([x[col], zb[col] + (k + 0.5) * dx])


def drop_onto_bed(y, zb, dx):
    """How far to lower lattice points at heights y, each over a bed at zb, so that each column's
    lowest lies dx/2 above the bed (as water_columns places them), for a lattice shared with walls."""
    off = np.mod(y - zb - 0.5 * dx, dx)
    return np.where(off > (1.0 - 1e-6) * dx, 0.0, off)
