"""Outflow through a submerged hatch (paper 000 section 4.1, Table 1, Fig. 3).

A reservoir 0.15 m long holds water 0.15 m deep; a hatch 0.035 m high at the bottom of its right
wall opens abruptly at t = 0 and the water runs out over a floor into an open region, where it
leaves the simulation through an outflow boundary. The orifice variant (scenes/orifice.toml,
Fig. 4) raises the opening: 0.055 m high with its bottom 0.045 m above the floor.

The discharge coefficient is the measured discharge over a sqrt(2 g dh) in the quasi-steady stage
(dh: head over the opening's centre). A sharp-edged opening gives about 0.6; the 2D contraction
limit of a slot is pi / (pi + 2) = 0.611.
"""

import math
import os
import sys
from functools import partial

import numpy as np

from ..case import Scene, make_case, resolves
from ..constants import G
from ..particles import FLUID, WALL, ParticleSet, block, hydrostatic_density, tait_B, wall_density
from ..profiles import plot_profiles, surface_profile, write_profile
from ..runner import common_params, run_scene, sound_speed
from ..settings.config import ConfigError, physics_from_config
from ..settings.schema import NON_NEGATIVE, POSITIVE, K
from ..settings.schemes import numerics


def discharge_coefficient(t, level, a, b, L, window, g=G):
    """Cd over the window from the reservoir level: Q = -L dh/dt from a quadratic fit of h(t)."""
    t, level = np.asarray(t), np.asarray(level)
    m = (t >= window[0]) & (t <= window[1])
    if m.sum() < 5:
        return float("nan"), float("nan")
    c = np.polyfit(t[m], level[m], 2)
    q = -L * np.polyval(np.polyder(c), t[m])
    head = np.polyval(c, t[m]) - (b + 0.5 * a)
    ok = head > 0
    if not ok.any():
        return float("nan"), float("nan")
    cd = q[ok] / (a * np.sqrt(2 * g * head[ok]))
    return float(np.mean(cd)), float(np.mean(q[ok]))


def hatch_metrics(cols, a, b, L, window):
    """The discharge coefficient against Kirchhoff's contraction, from the reservoir's level."""
    cd, q = discharge_coefficient(cols["t"], cols["reservoir_level"], a, b, L, window)
    return dict(
        discharge_coefficient=cd,
        mean_discharge=q,
        contraction_limit=math.pi / (math.pi + 2),
        reservoir_level_end=float(cols["reservoir_level"][-1]),
    )


def write_surfaces(out, metrics, surfaces, name):
    """The free surface at each still time: profiles/surface_t*.csv and surface.png."""
    os.makedirs(os.path.join(out, "profiles"), exist_ok=True)
    for t, xs, ys in surfaces:
        write_profile(os.path.join(out, "profiles", f"surface_t{t:.3f}.csv"), xs, ys, names=("x", "y_surface"))
    if surfaces:
        plot_profiles(
            os.path.join(out, "profiles", "surface.png"),
            [(f"t = {t:.3f} s", xs, ys, None, None) for t, xs, ys in surfaces],
            "x (m)",
            "free surface (m)",
            f"{name}: free surface",
        )


class Hatch(Scene):
    """Outflow through a submerged hatch (paper 000 section 4.1, Table 1, Fig. 3)."""

    NAME = "hatch"

    SCHEMA = {
        "run": {"end_time": 0.3},
        # Paper Table 1: 900 water particles at 0.005 m (30 x 30); h = 1.5 dx as in its Table 2.
        "numerics": numerics("default", dx=0.005),
        "geometry": {
            "reservoir_length": K(0.15, "the reservoir behind the gate", "m", range=POSITIVE),
            "water_depth": K(0.15, "the water in it at the start", "m", range=POSITIVE),
            "wall_height": K(0.2, "the walls' height", "m", range=POSITIVE),
            "opening_bottom": K(0.0, "hatch: at the floor; orifice: 0.045", range=NON_NEGATIVE),
            "opening_height": K(0.035, "hatch: 0.035; orifice: 0.055", range=POSITIVE),
            "downstream_length": K(0.15, "floor beyond the gate, then the outflow boundary", range=POSITIVE),
            "cd_window": K([0.05, 0.25], "quasi-steady stage for the discharge coefficient", "s"),
            "still_times": K([0.0, 0.04, 0.1, 0.14], "the paper's Fig. 3 times"),
        },
        "materials": {"water": {"rho0": 1000.0, "viscosity": 1.0e-3}},
        "output": {"frame_interval": 0.005, "probe_interval": 0.0025, "width": 560},
    }

    def check(self, cfg):
        g, dx = cfg.geometry, cfg.numerics.dx
        top = g.opening_bottom + g.opening_height
        if top >= g.wall_height:
            raise ConfigError(
                "geometry.opening_height",
                g.opening_height,
                f"an opening whose top ({top:g} m) stays below geometry.wall_height = {g.wall_height}",
            )
        if g.water_depth > g.wall_height:
            raise ConfigError("geometry.water_depth", g.water_depth, f"at most geometry.wall_height = {g.wall_height}")
        if g.water_depth <= top:
            raise ConfigError("geometry.water_depth", g.water_depth, f"above the opening's top ({top:g} m)")
        resolves(g.opening_height, 4, "the opening", dx)
        w = g.cd_window
        if len(w) != 2 or not (0 <= w[0] < w[1]):
            raise ConfigError("geometry.cd_window", w, "[start, end] in seconds with 0 <= start < end")

    def build(self, cfg):
        geo, num = cfg.geometry, cfg.numerics
        dx, L, H = num.dx, geo.reservoir_length, geo.water_depth
        Wh, b, a = geo.wall_height, geo.opening_bottom, geo.opening_height
        Ld = geo.downstream_length
        layers = num.wall_layers
        T = layers * dx
        water = cfg.materials.water
        rho0 = water.rho0
        c0, u_max = sound_speed(cfg, math.sqrt(2 * G * H))

        ps = ParticleSet()
        fluid = block(0.0, 0.0, L, H, dx)
        ps.add(fluid, FLUID, 0, hydrostatic_density(H - fluid[:, 1], rho0, c0, G), rho0 * dx * dx)
        x_end = L + T + Ld
        parts = [
            block(-T, -T, x_end, 0.0, dx),  # floor, under the reservoir and downstream
            block(-T, 0.0, 0.0, Wh, dx),  # left wall
            block(L, b + a, L + T, Wh, dx),
        ]  # the gate, above the opening
        if b > 0:
            parts.append(block(L, 0.0, L + T, b, dx))  # below an orifice
        walls = np.vstack([p for p in parts if len(p)])
        h = num.h_factor * dx
        ps.add(walls, WALL, 0, wall_density(walls, fluid, dx, h, rho0, c0, G), rho0 * dx * dx)

        pad = T + 4 * h
        domain = ((-pad, -pad - 0.1), (x_end + pad + 0.05, Wh + pad))
        outflow = [
            (x_end, -1.0, x_end + 1.0, Wh + 1.0),  # off the end of the floor
            (-1.0, -1.0, x_end + 1.0, -T - 2 * dx),
        ]  # (and anything that falls below it)
        materials = [dict(name="water", rho0=rho0, viscosity=water.viscosity, B=tait_B(rho0, c0))]
        surfaces = []

        def probe(st):
            fl = st["kind"] == FLUID
            x = st["x"][fl]
            vol = st["m"][fl] / st["rho"][fl]
            level = float(vol[x[:, 0] < L].sum() / L)
            prev, t = probe.prev, st["t"]
            q = (prev[1] - level) * L / (t - prev[0]) if prev and t > prev[0] else 0.0
            probe.prev = (t, level)
            out_m = float(st["m"][st["kind"] == -2].sum())
            return level, q, out_m

        probe.prev = None

        def surface_event(state, t):
            xs, ys = surface_profile(state, -T, x_end, 2 * dx, dx)
            surfaces.append((t, xs, ys))

        margin = T + dx
        case = make_case(
            name=self.NAME,
            particles=ps,
            materials=materials,
            domain=domain,
            params=common_params(cfg, c0, G, depth=H),
            physics=physics_from_config(cfg),
            view=((-margin, -margin), (x_end + margin, Wh + margin)),
            u_max=u_max,
            probe_columns=("reservoir_level", "discharge", "outflow_mass"),
            probe=probe,
            metrics=partial(hatch_metrics, a=a, b=b, L=L, window=geo.cd_window),
            outflow=tuple(outflow),
            stills=tuple(geo.still_times),
            events=[(t, surface_event) for t in geo.still_times],
            finalize=partial(write_surfaces, surfaces=surfaces, name=self.NAME),
            container=(0.0, 0.0, x_end, float("inf")),
            persist=(surfaces,),
        )
        return case


SCENE = Hatch()
main = partial(run_scene, SCENE)


if __name__ == "__main__":
    sys.exit(main())
