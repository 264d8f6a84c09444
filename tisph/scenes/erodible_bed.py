"""Dam break over an erodible bed (paper 000 section 4.3, Tables 3-4, Figs. 12-16).

A sediment layer 0.1 m thick covers a 2.5 m flume; a water column 1 m wide stands on it at the
left behind a gate removed at t = 0. Sediment: Bingham, tau_B = 0.447 Pa, mu_B = 0.04 Pa s,
1940 kg/m3; water 1000 kg/m3, 0.001 Pa s.

Table 3 gives a water height of 0.05 m and a particle spacing of 0.05 m, which cannot both hold
(one particle across the water; its "time step 0.00003 m" is a unit typo for s). The experiment
it cites (Spinewine & Zech 2007) stood 0.35 m of water on the bed. Default here: 0.1 m of water
at dx = 0.01 m, 10 particles across the water and the sediment; scenes/erodible_bed_deep.toml
has the experiment's 0.35 m.

Outputs besides the usual: probes.csv `t, front_x, eroded_area`; profiles/ with the free
surface and the bed (sediment surface) at t = 0.25, 0.5, 0.75 s as CSV and one PNG; metrics
bed_drop_at_gate (m) and front_x at 0.75 s and eroded_area (m^2) at the end.
"""

import math
import os
import sys
from functools import partial

import numpy as np

from ..case import Scene, make_case, resolves
from ..constants import G
from ..io import write_csv
from ..measure.field import surface_heights
from ..measure.plots import pyplot, save
from ..particles import FLUID, WALL, ParticleSet, block, density_from_pressure, tait_B
from ..runner import common_params, run_scene, sound_speed
from ..settings.config import ConfigError, physics_from_config
from ..settings.schema import POSITIVE, K
from ..settings.schemes import numerics
from ..viz.render import SAND

PROFILE_TIMES = (0.25, 0.5, 0.75)


def _plot_profiles(path, profiles, stations, bed_initial):
    """Bed and free surface at the profile times, over the initial bed."""
    plt = pyplot()
    fig, axes = plt.subplots(len(profiles), 1, figsize=(8, 2.0 * len(profiles) + 0.6), sharex=True, squeeze=False)
    for ax, (t, b, top) in zip(axes[:, 0], profiles):
        ax.fill_between(stations, 0, b, color=SAND, lw=0)
        ax.plot(stations, top, color="tab:blue", lw=1.0, label="free surface")
        ax.plot(stations, bed_initial, "k--", lw=0.7, label="initial bed")
        ax.set_title(f"t = {t:.2f} s", fontsize=9, loc="left")
        ax.set_ylabel("y (m)")
    axes[0, 0].legend(fontsize=7)
    axes[-1, 0].set_xlabel("x (m)")
    save(fig, path)


def bed_metrics(c, profiles, bed0, gate):
    """The surge front and the eroded area at the end; the bed's drop at the gate and the front at
    0.75 s (the paper's figure's time)."""
    out = dict(front_x=float(c["front_x"][-1]), eroded_area=float(c["eroded_area"][-1]))
    for t, b, top in profiles:
        if abs(t - 0.75) < 1e-6:
            out["bed_drop_at_gate"] = float(bed0["b"][gate] - b[gate])
            k = np.argmin(np.abs(c["t"] - t))
            out["front_x_at_0.75s"] = float(c["front_x"][k])
    return out


def write_profiles(out, metrics, profiles, stations, bed0):
    """The bed and the free surface at each profile time: profiles/profile_t*.csv and profiles.png."""
    if not profiles:
        return
    d = os.path.join(out, "profiles")
    os.makedirs(d, exist_ok=True)
    for t, b, top in profiles:
        write_csv(os.path.join(d, f"profile_t{t:.2f}.csv"), ("x", "bed", "free_surface"), list(zip(stations, b, top)))
    _plot_profiles(os.path.join(d, "profiles.png"), profiles, stations, bed0["b"])


class ErodibleBed(Scene):
    """Dam break over an erodible bed (paper 000 section 4.3, Tables 3-4, Figs. 12-16)."""

    NAME = "erodible_bed"

    # where the scene departs from its scheme (tisph/settings/schemes.py), and why
    DEPARTS = {
        "xsph": "Table 3's XSPH factor, 0.07",
        "h_factor": "h = 1.3 dx and alpha 0.1 hold the sand's Bingham impact at the gate (the dam break's "
        "stable set before the one scheme)",
        "artificial_viscosity": "as h_factor",
    }

    SCHEMA = {
        "run": {"end_time": 0.75},
        "numerics": numerics(
            "paper000", dx=0.01, h_factor=1.3, artificial_viscosity=0.1, xsph=0.07
        ),  # Table 3's XSPH factor (its "m" is a unit typo)
        "geometry": {
            "flume_length": K(2.5, "the channel", "m", range=POSITIVE),
            "sediment_depth": K(0.1, "the Bingham bed over its floor", "m", range=POSITIVE),
            "water_width": K(1.0, "the water column behind the gate", "m", range=POSITIVE),
            "water_height": K(0.1, "the water column's height above the bed", "m", range=POSITIVE),
            "wall_height": K(0.5, "the walls' height", "m", range=POSITIVE),
        },
        "materials": {
            "water": {"rho0": 1000.0, "viscosity": 1.0e-3},
            "sediment": {
                "rho0": 1940.0,
                "viscosity": 0.04,
                "rheology": "bingham",
                "yield_stress": 0.447,
                "regularisation": 100.0,
                "mu_max": 0.0,
                "unyielded": "rest",
            },
        },
        "output": {"frame_interval": 0.01, "probe_interval": 0.01, "width": 1280},
    }

    def check(self, cfg):
        g, dx = cfg.geometry, cfg.numerics.dx
        for k in ("water_height", "sediment_depth"):
            resolves(g[k], 4, f"geometry.{k}", dx)
        if g.water_width >= g.flume_length:
            raise ConfigError("geometry.water_width", g.water_width, f"below geometry.flume_length = {g.flume_length}")
        if g.water_height + g.sediment_depth >= g.wall_height:
            raise ConfigError(
                "geometry.wall_height",
                g.wall_height,
                f"above sediment_depth + water_height = {g.water_height + g.sediment_depth:g} m",
            )

    def build(self, cfg):
        geo, num = cfg.geometry, cfg.numerics
        dx, Lf, hs, a = num.dx, geo.flume_length, geo.sediment_depth, geo.water_width
        hw, Hw = geo.water_height, geo.wall_height
        mats = cfg.materials
        rw, rs = mats.water["rho0"], mats.sediment["rho0"]
        c0, u_max = sound_speed(cfg, 2.0 * math.sqrt(G * hw))  # Ritter's front speed
        L = num.wall_layers
        T = L * dx
        h = num.h_factor * dx
        ps = ParticleSet()
        water = block(0.0, hs, a, hs + hw, dx)
        sed = block(0.0, 0.0, Lf, hs, dx)

        def p_sed(x, y):
            top = np.where(x < a, rw * G * hw, 0.0)
            return top + rs * G * (hs - y)

        ps.add(water, FLUID, 0, density_from_pressure(rw * G * (hs + hw - water[:, 1]), rw, c0), rw * dx * dx)
        ps.add(sed, FLUID, 1, density_from_pressure(p_sed(sed[:, 0], sed[:, 1]), rs, c0), rs * dx * dx)
        walls = np.vstack([block(-T, -T, Lf + T, 0.0, dx), block(-T, 0.0, 0.0, Hw, dx), block(Lf, 0.0, Lf + T, Hw, dx)])
        wp = np.where(
            walls[:, 1] < hs,
            p_sed(np.clip(walls[:, 0], 0, Lf), np.maximum(walls[:, 1], 0.0)),
            np.where(walls[:, 0] < a, rw * G * np.maximum(hs + hw - walls[:, 1], 0.0), 0.0),
        )
        ps.add(walls, WALL, 0, density_from_pressure(wp, rw, c0), rw * dx * dx)
        materials = [dict(dict(mats[n]), name=n, B=tait_B(mats[n]["rho0"], c0)) for n in ("water", "sediment")]
        pad = 3 * T + 4 * h
        domain = ((-pad, -pad), (Lf + pad, 2 * Hw + pad))

        stations = np.arange(0.5 * dx, Lf, dx)
        bed0 = {}
        profiles = []

        def bed(st):
            return surface_heights(st, stations, dx, h, mat=1)

        def front(st):
            fl = (st["kind"] == FLUID) & (st["mat"] == 0)
            return float(st["x"][fl, 0].max() + 0.5 * dx) if fl.any() else float("nan")

        def probe(st):
            b = bed(st)
            if "b" not in bed0:
                bed0["b"] = b
            eroded = float(np.sum(np.maximum(bed0["b"] - b, 0.0)) * dx)
            return front(st), eroded

        def on_profile(st, t):
            # the free surface: the top of the fluid, water or sediment
            profiles.append((t, bed(st), surface_heights(st, stations, dx, h, mat=None)))

        gate = int(np.argmin(np.abs(stations - a)))

        margin = T + dx
        return make_case(
            name=self.NAME,
            particles=ps,
            materials=materials,
            domain=domain,
            params=common_params(cfg, c0, G, depth=hs + hw),
            physics=physics_from_config(cfg),
            view=((-margin, -margin), (Lf + margin, min(Hw, 2.2 * (hs + hw)) + margin)),
            u_max=u_max,
            probe_columns=("front_x", "eroded_area"),
            probe=probe,
            metrics=partial(bed_metrics, profiles=profiles, bed0=bed0, gate=gate),
            finalize=partial(write_profiles, profiles=profiles, stations=stations, bed0=bed0),
            events=[(t, on_profile) for t in PROFILE_TIMES],
            container=(0.0, 0.0, Lf, float("inf"), Hw),
            render_modes=("flat", "speed"),
            mat_colors=(None, SAND),
            persist=(bed0, profiles),
        )


SCENE = ErodibleBed()
main = partial(run_scene, SCENE)


if __name__ == "__main__":
    sys.exit(main())
