"""The pipeline scene's geometry, shared by its two sand models: the pipe, the log-law current
and the initial bed (paper 002 section 4.2; Mao 1986)."""

import math
import types

import numpy as np

from ...constants import KAPPA, G
from ...particles import WALL
from ...validation import mao

NAME = "pipeline_scour"


def profile_time(geo):
    """Mao's time (s) of the measured bed the run starts from (geometry.initial_profile), or None."""
    p = geo["initial_profile"]
    return None if p == "none" else float(p[len("mao_") : -1])


def has_bedload(cfg):
    """Whether the sand is the bed-load bed (a rigid bed, sand_depth = 0, has no sand model)."""
    return cfg.sediment.model == "bedload" and cfg.geometry.sand_depth > 0


def log_law(z, ustar, z0):
    """u(z) = (u*/kappa) ln(z/z0) above the bed (paper 002 eq. 32, kappa = 0.42), 0 below z0."""
    z = np.maximum(np.asarray(z, float), z0)
    return ustar / KAPPA * np.log(z / z0)


def friction_velocity(U, depth, z0):
    """u* whose log-law profile has depth-mean U: U = (u*/kappa) (ln(h/z0) - 1)."""
    return KAPPA * U / (math.log(depth / z0) - 1.0)


def ring(cx, cy, radius, dx):
    n = max(8, int(round(2 * math.pi * radius / dx)))
    a = np.arange(n) * 2 * math.pi / n
    return np.column_stack([cx + radius * np.cos(a), cy + radius * np.sin(a)]), np.column_stack([np.cos(a), np.sin(a)])


def geometry(cfg):
    """The case's derived quantities: pipe centre, water top, friction velocity and roughness."""
    geo, num = cfg.geometry, cfg.numerics
    g = types.SimpleNamespace(
        dx=num.dx,
        D=geo.pipe_diameter,
        hw=geo.water_depth,
        hs=geo.sand_depth,
        Lx=geo.length,
        U=geo.mean_velocity,
        d50=geo.grain_diameter,
        L=num.wall_layers,
        h=num.h_factor * num.dx,
        geo=geo,
    )
    mats = cfg.materials
    g.rw, g.rs = mats.water["rho0"], mats.sand["rho0"]
    if has_bedload(cfg):  # the bed's grains, not the two-phase model's bulk sand
        g.rs = cfg.sediment.grain_density
    g.R = 0.5 * g.D
    g.xc = 0.5 * g.Lx
    g.yc = g.hs + geo.gap + g.R
    g.ytop = g.hs + g.hw
    if geo.shields > 0:
        g.ustar = math.sqrt(geo.shields * (g.rs / g.rw - 1) * G * g.d50)
        g.z0 = g.hw * math.exp(-(KAPPA * g.U / g.ustar + 1.0))
    else:
        g.z0 = 2.5 * g.d50 / 30.0  # Nikuradse roughness 2.5 d50
        g.ustar = friction_velocity(g.U, g.hw, g.z0)
    return g


def initial_bed(g, x):
    """The initial sand surface: flat, with a small dip under the pipe; or Mao's measured bed
    (geometry.initial_profile)."""
    x = np.asarray(x, float)
    D, xc = g.D, g.xc
    if g.geo["initial_profile"] != "none":
        return g.hs + mao.profile_bed(profile_time(g.geo), x - xc, D)
    dip = g.geo["perturbation"] * np.where(np.abs(x - xc) < D, 0.5 * (1 + np.cos(np.pi * (x - xc) / D)), 0.0)
    return g.hs - dip


def add_pipe(ps, g, density):
    """The pipe: wall_layers rings of wall particles inside its surface, normals outward, with
    their distance behind the surface for the no-slip ghost velocity (paper 002 eq. 39)."""
    for k in range(g.L):
        r_k = g.R - (k + 0.5) * g.dx
        if r_k <= 0:
            break
        pts, nrm = ring(g.xc, g.yc, r_k, g.dx)
        ps.add(pts, WALL, 0, density(pts[:, 1]), g.rw * g.dx * g.dx, normal=nrm, wall_dist=g.R - r_k)
