"""Dam break on a dry bed: a water column collapses in a closed tank.

Default: the Martin & Moyce (1952) / Koshizuka & Oka (1996) case in the geometry of PySPH's
dam_break_2d (column 1 m wide, 2 m high, at the left of a 4 m x 4 m tank), dx = 0.03 m, to
T = t sqrt(2 g / a) = 3.5. The surge front is compared with Martin & Moyce's measurements.
"""
import math
import sys

import numpy as np

from ..config import ConfigError, physics_from_config
from ..particles import ParticleSet, block, box_walls, hydrostatic_density, surface_above, tait_B, FLUID, WALL
from ..runner import Case, common_params, run_scene, sound_speed
from ..validation import martin_moyce

NAME = "dam_break"
G = 9.81

DEFAULTS = {
    "run": {"end_time": 0.7902},  # T = t sqrt(2 g / a) = 3.5 for a = 1 m
    "numerics": {"dx": 0.03, "h_factor": 1.3, "artificial_viscosity": 0.1,
                 "density_diffusion": "fourtakas", "delta": 0.1},
    "geometry": {
        "tank_width": 4.0,
        "tank_height": 4.0,
        "column_width": 1.0,   # a
        "column_height": 2.0,  # n^2 a with n^2 = 2
    },
    "materials": {"water": {"rho0": 1000.0, "viscosity": 1.0e-3}},
    "output": {"frame_interval": 0.02, "probe_interval": 0.005},
}

RANGES = {f"geometry.{k}": (0.0, None, False, True) for k in DEFAULTS["geometry"]}


def check(cfg):
    g, dx = cfg["geometry"], cfg["numerics"]["dx"]
    if g["column_width"] > g["tank_width"]:
        raise ConfigError("geometry.column_width", g["column_width"],
                          f"at most geometry.tank_width = {g['tank_width']}")
    if g["column_height"] > g["tank_height"]:
        raise ConfigError("geometry.column_height", g["column_height"],
                          f"at most geometry.tank_height = {g['tank_height']}")
    smallest = min(g["column_width"], g["column_height"])
    if smallest / dx < 4:
        raise ConfigError("numerics.dx", dx, f"at most {smallest / 4:.4g} m (4 particles across the column)")


def build(cfg):
    geo, num = cfg["geometry"], cfg["numerics"]
    dx, a, H = num["dx"], geo["column_width"], geo["column_height"]
    W, Ht = geo["tank_width"], geo["tank_height"]
    water = cfg["materials"]["water"]
    rho0 = water["rho0"]
    c0, u_max = sound_speed(cfg, math.sqrt(2 * G * H))
    B = tait_B(rho0, c0)

    ps = ParticleSet()
    fluid = block(0.0, 0.0, a, H, dx)
    ps.add(fluid, FLUID, 0, hydrostatic_density(H - fluid[:, 1], rho0, c0, G), rho0 * dx * dx)
    walls = box_walls(0.0, 0.0, W, Ht, dx, num["wall_layers"])
    wall_m = rho0 * dx * dx
    h = num["h_factor"] * dx
    top = surface_above(walls[:, 0], fluid, dx, 2 * h)
    ps.add(walls, WALL, 0, hydrostatic_density(top - walls[:, 1], rho0, c0, G), wall_m)

    pad = 3 * num["wall_layers"] * dx + 4 * h
    domain = ((-pad, -pad), (W + pad, Ht + pad))
    params = common_params(cfg, c0, G, depth=H)
    materials = [dict(name="water", rho0=rho0, viscosity=water["viscosity"], B=B)]

    band = 2.0 * dx  # the front is measured along the floor, within two particle rows of it

    def probe(st):
        fl = st["kind"] == FLUID
        x = st["x"][fl]
        floor = x[x[:, 1] < band]
        front = floor[:, 0].max() + 0.5 * dx if len(floor) else float("nan")
        wall = x[x[:, 0] < 2.0 * dx]
        col_h = wall[:, 1].max() + 0.5 * dx if len(wall) else 0.0
        return front, col_h

    def metrics(cols):
        rms, npts = martin_moyce.front_rms_error(cols["t"], cols["front_x"], a, G)
        return dict(front_rms_error=rms, front_points=npts,
                    front_x_end=float(cols["front_x"][-1]), column_h_end=float(cols["column_h"][-1]))

    margin = num["wall_layers"] * dx + dx
    view = ((-margin, -margin), (W + margin, min(Ht, max(H, 0.6 * Ht)) + margin))
    return Case(name=NAME, particles=ps, materials=materials, domain=domain, params=params,
                physics=physics_from_config(cfg), view=view, u_max=u_max,
                probe_columns=("front_x", "column_h"), probe=probe, metrics=metrics,
                container=(0.0, 0.0, W, float("inf")))


def main(argv=None):
    return run_scene(sys.modules[__name__], argv)


if __name__ == "__main__":
    sys.exit(main())
