"""Still water in a closed tank, optionally over a sediment layer: the hydrostatic check every SPH
code must pass, and (with sediment) the two-phase check of a stable density jump.

Starts from the hydrostatic density of each layer, settles, and reports the pressure against
the hydrostatic profile row by row, the peak speed against sqrt(g H), the density error, any
particle that left the tank and, with sediment, how far the interface moved and whether the
pressure is continuous across it.
"""

import math
import sys
from functools import partial

import numpy as np

from ..case import Scene, make_case, resolves
from ..constants import G
from ..particles import (
    FLUID,
    WALL,
    ParticleSet,
    block,
    box_walls,
    density_from_pressure,
    layered_pressure,
    surface_above,
    tait_B,
)
from ..runner import common_params, run_scene, sound_speed
from ..settings.config import ConfigError, physics_from_config
from ..settings.schema import NON_NEGATIVE, POSITIVE, K
from ..settings.schemes import numerics


def layer_pressure_errors(x, p, dx, rho0, g=G, skip_top=2, expected=None):
    """Per particle row: (depth, mean p / p_hydrostatic - 1), top `skip_top` rows left out.

    Rows are binned from the floor at spacing dx; depth is measured from the actual free surface
    (top row + dx/2), so a uniform settling of the column does not count as a pressure error.
    expected(depth) gives the hydrostatic pressure (default rho0 g depth).
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
        ref = expected(d) if expected else rho0 * g * d
        out.append((d, p[m].mean() / ref - 1.0))
    return np.array(out).reshape(-1, 2)


def final_metrics(st, dx, W, H, hs, rw, rs, vref, sed0):
    """The tank at its end: the pressure of each layer against rho g d, the largest speed and
    density error, particles outside, and over a sediment layer its interface's displacement and
    pressure jump."""
    fl = st["kind"] == FLUID
    x, p, mat = st["x"][fl], st["p"][fl], st["mat"][fl]
    errs = layer_pressure_errors(x, p, dx, rw, expected=lambda d: layered_pressure(H - d, hs, H, rw, rs))
    v = st["v"][fl]
    rho0 = np.where(mat == 0, rw, rs)
    below_floor = int(np.sum(x[:, 1] < 0.0))
    outside = int(np.sum((x[:, 0] < 0) | (x[:, 0] > W))) + below_floor
    out = dict(
        pressure_error=float(np.abs(errs[:, 1]).max()) if len(errs) else float("nan"),
        speed_ratio=float(np.sqrt((v * v).sum(1)).max() / vref),
        density_error=float(np.abs(st["rho"][fl] / rho0 - 1.0).max()),
        crossed_wall=outside,
        layers_checked=int(len(errs)),
    )
    if hs > 0:
        # interface: the top row of sediment, per column, against its start
        ids_top = sed0["top_ids"]
        y_now = st["x"][ids_top, 1]
        out["interface_displacement"] = float(np.abs(y_now - sed0["top_y"]).max())
        out["interface_displacement_over_dx"] = out["interface_displacement"] / dx
        # pressure continuity: the jump between the last sediment row and the first water row
        # against the hydrostatic jump over the same distance
        s_top = (mat == 1) & (np.abs(x[:, 1] - (hs - 0.5 * dx)) < 0.5 * dx)
        w_bot = (mat == 0) & (np.abs(x[:, 1] - (hs + 0.5 * dx)) < 0.5 * dx)
        if s_top.any() and w_bot.any():
            ys, yw = x[s_top, 1].mean(), x[w_bot, 1].mean()
            jump = p[s_top].mean() - p[w_bot].mean()
            expect = layered_pressure(ys, hs, H, rw, rs) - layered_pressure(yw, hs, H, rw, rs)
            out["interface_pressure_jump_error"] = float(abs(jump - expect) / layered_pressure(hs, hs, H, rw, rs))
    return out


class Tank(Scene):
    """Still water in a closed tank, over a sediment layer or not: the hydrostatic check."""

    NAME = "tank"

    SCHEMA = {
        "run": {"end_time": 2.0},
        "numerics": numerics("default", dx=0.02),
        "geometry": {
            "width": K(0.5, "the tank's inside width", "m", range=POSITIVE),
            "depth": K(0.5, "still water", "m", range=POSITIVE),
            "tank_height": K(0.7, "the walls' height", "m", range=POSITIVE),
            "sediment_depth": K(0.0, "> 0: a sediment layer at the bottom, water above it", range=NON_NEGATIVE),
        },
        "materials": {
            "water": {"rho0": 1000.0, "viscosity": 1.0e-3},
            # saturated sand as a Bingham fluid (paper 000 section 5: 1950 kg/m3, mu_B = 0.1 Pa s)
            "sediment": {
                "rho0": 1950.0,
                "viscosity": 0.1,
                "rheology": "bingham",
                "yield_stress": 200.0,
                "regularisation": 100.0,
                "mu_max": 0.0,
            },
        },
        "output": {"frame_interval": 0.1, "probe_interval": 0.01, "render": False},
    }

    def check(self, cfg):
        g, dx = cfg.geometry, cfg.numerics.dx
        if g.depth > g.tank_height:
            raise ConfigError("geometry.depth", g.depth, f"at most geometry.tank_height = {g.tank_height}")
        resolves(min(g.width, g.depth), 4, "the water", dx)
        if g.sediment_depth > 0 and not (2 * dx <= g.sediment_depth <= g.depth - 2 * dx):
            raise ConfigError(
                "geometry.sediment_depth",
                g.sediment_depth,
                f"0 (none) or between 2 dx and geometry.depth - 2 dx ({2 * dx:g} to {g.depth - 2 * dx:g} m)",
            )

    def build(self, cfg):
        geo, num = cfg.geometry, cfg.numerics
        dx, W, H, Ht, hs = num.dx, geo.width, geo.depth, geo.tank_height, geo.sediment_depth
        mats = cfg.materials
        rw, rs = mats.water["rho0"], mats.sediment["rho0"]
        c0, u_max = sound_speed(cfg, math.sqrt(2 * G * H))
        ps = ParticleSet()
        used = ["water"] + (["sediment"] if hs > 0 else [])
        water = block(0.0, hs, W, H, dx)
        ps.add(
            water, FLUID, 0, density_from_pressure(layered_pressure(water[:, 1], hs, H, rw, rs), rw, c0), rw * dx * dx
        )
        if hs > 0:
            sed = block(0.0, 0.0, W, hs, dx)
            ps.add(
                sed, FLUID, 1, density_from_pressure(layered_pressure(sed[:, 1], hs, H, rw, rs), rs, c0), rs * dx * dx
            )
        walls = box_walls(0.0, 0.0, W, Ht, dx, num.wall_layers)
        h = num.h_factor * dx
        top = surface_above(walls[:, 0], np.vstack([water] + ([sed] if hs > 0 else [])), dx, 2 * h)
        pw = np.where(top > walls[:, 1], layered_pressure(np.minimum(walls[:, 1], H), hs, H, rw, rs), 0.0)
        pw = np.where(np.isfinite(top), pw, 0.0)
        ps.add(walls, WALL, 0, density_from_pressure(pw, rw, c0), rw * dx * dx)
        pad = num.wall_layers * dx + 4 * h
        domain = ((-pad, -pad), (W + pad, 2.0 * Ht + pad))  # open top: room for spray to fall back
        materials = []
        for name in ("water", "sediment"):
            m = dict(mats[name])
            materials.append(dict(m, name=name, B=tait_B(m["rho0"], c0)))
        vref = math.sqrt(G * H)
        sed0 = {}

        def probe(st):
            fl = st["kind"] == FLUID
            v = st["v"][fl]
            return (float(np.sqrt((v * v).sum(1)).max() / vref),)

        if hs > 0:
            idx = np.nonzero((ps.kind == FLUID) & (ps.mat == 1))[0]
            ys = ps.x[idx, 1]
            top_ids = idx[ys > ys.max() - 0.5 * dx]
            sed0["top_ids"], sed0["top_y"] = top_ids, ps.x[top_ids, 1].copy()

        def metrics(cols):
            return dict(peak_speed_ratio_max=float(np.max(cols["speed_ratio"])))

        margin = num.wall_layers * dx + dx
        return make_case(
            name=self.NAME,
            particles=ps,
            materials=materials,
            domain=domain,
            params=common_params(cfg, c0, G, depth=H),
            physics=physics_from_config(cfg, materials_used=used),
            view=((-margin, -margin), (W + margin, Ht + margin)),
            u_max=u_max,
            probe_columns=("speed_ratio",),
            probe=probe,
            metrics=metrics,
            final_metrics=partial(final_metrics, dx=dx, W=W, H=H, hs=hs, rw=rw, rs=rs, vref=vref, sed0=sed0),
            container=(0.0, 0.0, W, float("inf"), Ht),
        )


SCENE = Tank()
main = partial(run_scene, SCENE)


if __name__ == "__main__":
    sys.exit(main())
