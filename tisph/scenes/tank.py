"""Still water in a closed tank: the hydrostatic check every SPH code must pass.

Starts from the hydrostatic density, settles, and reports the pressure against rho g d layer by
layer, the peak speed against sqrt(g H), the density error and any particle that left the tank.
"""
import math
import sys

import numpy as np

from ..config import ConfigError, physics_from_config
from ..particles import ParticleSet, block, box_walls, hydrostatic_density, surface_above, tait_B, FLUID, WALL
from ..runner import Case, common_params, run_scene, sound_speed

NAME = "tank"
G = 9.81

DEFAULTS = {
    "run": {"end_time": 2.0},
    "numerics": {"dx": 0.02, "h_factor": 1.3, "artificial_viscosity": 0.1,
                 "density_diffusion": "fourtakas", "delta": 0.1},
    "geometry": {"width": 0.5, "depth": 0.5, "tank_height": 0.7},
    "materials": {"water": {"rho0": 1000.0, "viscosity": 1.0e-3}},
    "output": {"frame_interval": 0.1, "probe_interval": 0.01, "render": False},
}
RANGES = {f"geometry.{k}": (0.0, None, False, True) for k in DEFAULTS["geometry"]}


def check(cfg):
    g, dx = cfg["geometry"], cfg["numerics"]["dx"]
    if g["depth"] > g["tank_height"]:
        raise ConfigError("geometry.depth", g["depth"], f"at most geometry.tank_height = {g['tank_height']}")
    if min(g["width"], g["depth"]) / dx < 4:
        raise ConfigError("numerics.dx", dx, f"at most {min(g['width'], g['depth']) / 4:.4g} m "
                          "(4 particles across the water)")


def layer_pressure_errors(x, p, dx, rho0, g=G, skip_top=2):
    """Per particle row: (depth, mean p / (rho0 g depth) - 1), top `skip_top` rows left out.

    Rows are binned from the floor at spacing dx; depth is measured from the actual free surface
    (top row + dx/2), so a uniform settling of the column does not count as a pressure error.
    """
    rows = np.floor(x[:, 1] / dx + 1e-6).astype(int)
    top = rows.max()
    ysurf = x[rows == top, 1].mean() + 0.5 * dx
    out = []
    for r in range(rows.min(), top - skip_top + 1):
        m = rows == r
        if m.sum() < 2:
            continue
        d = ysurf - x[m, 1].mean()
        out.append((d, p[m].mean() / (rho0 * g * d) - 1.0))
    return np.array(out).reshape(-1, 2)


def build(cfg):
    geo, num = cfg["geometry"], cfg["numerics"]
    dx, W, H, Ht = num["dx"], geo["width"], geo["depth"], geo["tank_height"]
    water = cfg["materials"]["water"]
    rho0 = water["rho0"]
    c0, u_max = sound_speed(cfg, math.sqrt(2 * G * H))
    ps = ParticleSet()
    fluid = block(0.0, 0.0, W, H, dx)
    ps.add(fluid, FLUID, 0, hydrostatic_density(H - fluid[:, 1], rho0, c0, G), rho0 * dx * dx)
    walls = box_walls(0.0, 0.0, W, Ht, dx, num["wall_layers"])
    h = num["h_factor"] * dx
    top = surface_above(walls[:, 0], fluid, dx, 2 * h)
    ps.add(walls, WALL, 0, hydrostatic_density(top - walls[:, 1], rho0, c0, G), rho0 * dx * dx)
    pad = num["wall_layers"] * dx + 4 * h
    domain = ((-pad, -pad), (W + pad, Ht + pad))
    materials = [dict(name="water", rho0=rho0, viscosity=water["viscosity"], B=tait_B(rho0, c0))]
    vref = math.sqrt(G * H)

    def probe(st):
        fl = st["kind"] == FLUID
        v = st["v"][fl]
        return (float(np.sqrt((v * v).sum(1)).max() / vref),)

    def final_metrics(st):
        fl = st["kind"] == FLUID
        errs = layer_pressure_errors(st["x"][fl], st["p"][fl], dx, rho0)
        v = st["v"][fl]
        rho_h = hydrostatic_density(errs[:, 0], rho0, c0, G) if len(errs) else np.array([rho0])
        below_floor = int(np.sum(st["x"][fl, 1] < 0.0))
        outside = int(np.sum((st["x"][fl, 0] < 0) | (st["x"][fl, 0] > W))) + below_floor
        return dict(pressure_error=float(np.abs(errs[:, 1]).max()) if len(errs) else float("nan"),
                    speed_ratio=float(np.sqrt((v * v).sum(1)).max() / vref),
                    density_error=float(np.abs(st["rho"][fl] / rho0 - 1.0).max()),
                    crossed_wall=outside, layers_checked=int(len(errs)))

    def metrics(cols):
        return dict(peak_speed_ratio_max=float(np.max(cols["speed_ratio"])))

    margin = num["wall_layers"] * dx + dx
    return Case(name=NAME, particles=ps, materials=materials, domain=domain,
                params=common_params(cfg, c0, G, depth=H), physics=physics_from_config(cfg),
                view=((-margin, -margin), (W + margin, Ht + margin)), u_max=u_max,
                probe_columns=("speed_ratio",), probe=probe, metrics=metrics, final_metrics=final_metrics,
                container=(0.0, 0.0, W, float("inf")))


def main(argv=None):
    return run_scene(sys.modules[__name__], argv)


if __name__ == "__main__":
    sys.exit(main())
