"""Sand beach in front of a wave maker: a piston paddle at the left makes waves that shoal and
break on a sloping sand beach and reshape the bed.

Default (scenes/beach.toml): the sand is the morphodynamic bed below particle scale
(sediment.model = "bedload", tisph/sediment, tisph/scenes/beach/bedload.py) under SPH water, and
ripples form on it. Why this geometry: Wiberg & Harris (1994) orbital ripples are 0.62 d0 long,
and in shallow water a piston moves the whole column, so the near-bed orbital diameter d0 is
about the stroke, which is at most the depth: a ripple is about half the depth long, and the bed
model resolves it over 18 dx, so the water is about 40 particles deep. Still water 0.3 m deep
over 0.1 m of sand, flat to x = 1 m and then 1:10 to the end wall at 5.3 m (the crest 0.13 m up); T =
2.5 s (kh = 0.45), stroke 0.28 m, Biesel H = 0.127 m, d0 = 0.27 m at the toe, 0.3 mm quartz sand.
dx and morfac follow from the wave where a case leaves them unset (derive): dx puts the ripple
predicted at the toe over 18 spacings (0.0093 m), morfac turns the bed over no faster a wave
period than in the default tunnel (20.2: 16 s of flow move the bed as 323 s would, 129 wave
periods). The lee vortex (sediment.lee_vortex, separation_*) is what grows ripples from the
random bed it starts with (RMS 1 % of the toe's linear-wave d0: geometry.roughness);
docs/sediment.md says what it does and what is measured.

The paper's case (paper 000 section 5, Table 5, Figs. 17-28), scenes/beach_bingham_tau200.toml
and beach_bingham_tau1000.toml: the sand as Bingham particles, 1950 kg/m3, mu_B = 0.1 Pa s,
tau_B = 200 or 1000 Pa, dx = 0.04 m as in Table 5; still water 0.4 m over 0.12 m of sand rising
at 1:6 from x = 3 m on a rigid ramp (the paper gives no geometry; chosen for plunging breakers),
T = 1.6 s, stroke 0.16 m. The table's time step (2e-5 s) is what an explicit step with the full
Bingham viscosity needs; here the effective viscosity is capped where its explicit viscous step
would fall below the acoustic one, and sand below the yield stress is held at rest
(materials.sand.unyielded = "rest"). That bed changes, but makes no ripples.

Outputs besides the usual: bed_profile.csv (the bed along x at every probe), probes.csv with the
ripple statistics, bed_profile.png, ripple_prediction.csv (the Wiberg & Harris ripple for the
near-bed orbital motion measured along the beach) and stills at t = 0, 0.7, 2, 4, 8, 12, 16 s (the
Bingham beach adds streamline panels, stills/streamlines_t*.png).
"""

import math
import os
from functools import partial

import numpy as np

from ...case import Scene, make_case, resolves
from ...constants import G
from ...particles import FLUID, MOVING, WALL, ParticleSet, block, density_from_pressure, layered_pressure, tait_B
from ...profiles import streamlines_png
from ...runner import common_params, run_scene, sound_speed
from ...sediment import keys as sediment_keys
from ...settings.config import ConfigError, physics_from_config
from ...settings.materials import BINGHAM_SAND, WATER
from ...settings.schema import POSITIVE, K, with_defaults
from ...settings.schemes import numerics
from ...viz.render import SAND
from ...waves.absorb import with_control
from ...waves.paddle import PADDLE, check_paddle, paddle, stroke_step
from ...waves.theory import linear_wave
from .bedload import build_bedload, derive_bedload, paddle_depth
from .record import STILLS, BedRecord, near_bed_velocity  # noqa: F401  (near_bed_velocity: the beach's API)


def _particles(cfg, c0):
    """Water over a sand layer on the floor and a 1:slope ramp, walls, and the paddle; each
    particle at the hydrostatic density of the layers above it."""
    geo, num = cfg.geometry, cfg.numerics
    dx, Lf, d, ts = num.dx, geo.length, geo.depth, geo.sand_thickness
    toe, sl, Hw = geo.toe_x, geo.slope, geo.wall_height
    yw = ts + d
    rw, rs = cfg.materials.water.rho0, cfg.materials.sand.rho0
    L = num.wall_layers
    T = L * dx

    def ramp(x):
        return np.maximum(0.0, (np.asarray(x, float) - toe) / sl)

    # The slope is built from rows of particles parallel to it (a lattice cut by a 1:6 line
    # would leave a staircase that reads as ripples and whose corners slump).
    ca, sa = sl / math.hypot(sl, 1.0), 1.0 / math.hypot(sl, 1.0)
    s_len = (Lf - toe) / ca

    def slope_rows(offsets):
        s_ = np.arange(0.5 * dx, s_len, dx)
        pts = [np.column_stack([toe + s_ * ca - o * sa, s_ * sa + o * ca]) for o in offsets]
        pts = np.vstack(pts)
        return pts[pts[:, 0] < Lf - 0.5 * dx]

    def far_from(a, b, r):
        """Points of a farther than r from every point of b (only near the toe do they meet)."""
        keep = np.ones(len(a), bool)
        near_a = np.nonzero(np.abs(a[:, 0] - toe) < 4 * dx)[0]
        nb = b[np.abs(b[:, 0] - toe) < 5 * dx]
        if len(near_a) and len(nb):
            d2 = ((a[near_a, None, :] - nb[None, :, :]) ** 2).sum(-1).min(1)
            keep[near_a] = d2 >= r * r
        return a[keep]

    nlay = int(round(ts / dx))
    flat_sand = block(0.0, 0.0, toe, ts, dx)
    slope_sand = far_from(slope_rows([(k + 0.5) * dx for k in range(nlay)]), flat_sand, 0.7 * dx)
    xs = np.vstack([flat_sand, slope_sand])
    ramp_wall = slope_rows([-(k + 0.5) * dx for k in range(L)])
    ramp_wall = ramp_wall[ramp_wall[:, 1] > 0.25 * dx]  # the floor lies below y = 0
    lattice = block(0.0, 0.0, Lf, Hw, dx)
    # water: the lattice above the sand, at least half a spacing clear of its surface
    dist = np.where(lattice[:, 0] < toe, lattice[:, 1] - ts, ((lattice[:, 1] - ts) - (lattice[:, 0] - toe) / sl) * ca)
    xw = lattice[(dist >= 0.5 * dx) & (lattice[:, 1] < yw)]
    xw = far_from(xw, xs, 0.7 * dx)

    def pressure(y, ytop_sand):
        return layered_pressure(y, ytop_sand, yw, rw, rs, G)

    ps = ParticleSet()
    ps.add(xw, FLUID, 0, density_from_pressure(pressure(xw[:, 1], ramp(xw[:, 0]) + ts), rw, c0), rw * dx * dx)
    ps.add(xs, FLUID, 1, density_from_pressure(pressure(xs[:, 1], ramp(xs[:, 0]) + ts), rs, c0), rs * dx * dx)
    pad_pts, motion, extra, reach = paddle(cfg, yw, Hw)
    x_left = -reach - 2 * T
    walls = np.vstack([block(x_left, -T, Lf + T, 0.0, dx), block(Lf, 0.0, Lf + T, Hw, dx), ramp_wall])
    ytop = np.maximum(ramp(walls[:, 0]), 0.0) + ts
    wall_p = pressure(np.maximum(walls[:, 1], 0.0), ytop)
    ps.add(walls, WALL, 0, density_from_pressure(wall_p, rw, c0), rw * dx * dx)
    pp = pressure(pad_pts[:, 1], np.full(len(pad_pts), ts))
    ps.add(pad_pts, MOVING, 0, density_from_pressure(pp, rw, c0), rw * dx * dx)
    return ps, extra, reach, x_left


def _streamlines_event(yw, Lf, dx):
    """A callback drawing streamlines of the water velocity over the sand (offscreen) into
    OUT/stills/streamlines_t*.png."""

    def cb(st, t):
        d = os.path.join(st["out"], "stills")
        os.makedirs(d, exist_ok=True)
        streamlines_png(
            os.path.join(d, f"streamlines_t{t:.3f}.png"),
            st,
            (0.0, Lf),
            (0.0, yw + 0.3),
            dx,
            f"water velocity streamlines, t = {t:.1f} s",
            (12, 2.4),
            density=(4, 1),
        )

    return cb


class Beach(Scene):
    """Sand beach in front of a wave maker: waves shoal and break on it and reshape the bed."""

    NAME = "beach"
    # where the scene departs from its scheme (tisph/settings/schemes.py), and why: breaking waves (below)
    DEPARTS = {
        "artificial_viscosity": "breaking waves compress the water without it (below)",
        "artificial_viscosity_surface": "droplets and the swash's film ring without it (below)",
        "laminar_viscosity": "alpha's viscosity is 500 times the water's; the bed was calibrated so",
    }

    SCHEMA = {
        "run": {"end_time": 16.0},
        # the tunnel's numerics (the bed scheme) but for breaking waves: without artificial
        # viscosity the breakers compress the water (99.9th percentile of the density error 3.5 %, 1.1 %
        # with alpha 0.01); the bed's outer scaling takes away the slower near-bed flow alpha's Stokes
        # layer makes. At the free surface, 0.1: droplets torn off a breaker and the swash's thin film
        # ring under the Tait tension (largest density error 20-25 % at 0.01, 7.7 % at 0.05, 2.1 % at
        # 0.1; a constant alpha of 0.03 holds them but takes 13-18 % off the breaking height;
        # docs/waves.md). The Bingham beaches set their own alpha.
        # A breaker may throw a droplet out of the density band: removed and counted as spray (at most
        # 0.2 % of the water), not a stop. dx: the derived value at these defaults (derive, below).
        "numerics": numerics(
            "bed",
            dx=0.0093,
            artificial_viscosity=0.01,
            artificial_viscosity_surface=0.1,
            laminar_viscosity=False,
            spray_limit=0.002,
        ),
        "geometry": {
            "length": K(
                5.3,
                "paddle (x = 0) to the end wall: the crest 0.13 m above still water, over Hunt's run-up of the default wave (0.105 m)",
                "m",
                range=POSITIVE,
            ),
            "depth": K(0.3, "still water over the flat sand", "m", range=POSITIVE),
            "sand_thickness": K(
                0.1, "the sand's level above the floor (m): the flat bed, and under the ramp", range=POSITIVE
            ),
            "toe_x": K(1.0, "where the beach starts to rise", "m", range=POSITIVE),
            "slope": K(10.0, "1 : slope (horizontal run per unit rise)", range=(1.0, None, True, True)),
            "wall_height": K(0.6, "the side walls' height above the floor", "m", range=POSITIVE),
            "grain_diameter": K(
                0.0003,
                "d50: the bed load's grain, and the Wiberg & Harris ripple prediction; a medium sand",
                "m",
                range=POSITIVE,
            ),
            "gauges_x": K(
                [0.8, 2.0, 3.0, 3.6],
                "wave gauges (m from the paddle's mean position): probes.csv eta_x..., and the wave height at each in summary.json (wave_height_at_gauges)",
            ),
            "roughness": K(
                0.01,
                "the bed-load bed's random RMS over the linear-wave d0 at the toe where sediment.seed_rms = 0 (2.7 mm at the default), as the tunnel's (docs/sediment.md)",
                range=(0.0, 0.1, True, True),
            ),
        },
        "paddle": with_defaults(PADDLE, stroke=0.28, period=2.5, ramp_periods=1.0),
        "materials": {"water": dict(WATER), "sand": dict(BINGHAM_SAND)},
        # sediment.model = "bedload": the bed below particle scale (tisph/sediment, scenes/beach.toml);
        # "particles": the paper's Bingham sand (scenes/beach_bingham_tau200.toml)
        # the tunnel's bed parameters, the outer scaling included: the beach's near-wall layer is as thick
        # (at 1.5 dx the velocity amplitude is half of that 6 dx up) and the flow above it carries the
        # waves' flux at 0.89-1.02 of (H / 2) sqrt(g h) up the slope (docs/sediment.md)
        "sediment": with_defaults(sediment_keys.SEDIMENT, **sediment_keys.WAVE_RIPPLES, morfac=20.2),
        "output": {"frame_interval": 0.04, "probe_interval": 0.04, "width": 1280},
    }

    def derive(self, cfg, given):
        """The resolving steps: the stroke a wave height asks for, then the bed-load beach's dx and
        morfac from its wave where the user left them unset (bedload.derive_bedload). Returns the
        values and run.log's lines."""
        changes, notes = stroke_step(cfg, paddle_depth(cfg), self.DEFAULTS["paddle"]["stroke"])
        if cfg.sediment.model == "bedload":
            more, said = derive_bedload(cfg.replace(changes), given)
            changes, notes = dict(changes, **more), notes + said
        return changes, notes

    def check(self, cfg):
        g, dx = cfg.geometry, cfg.numerics.dx
        resolves(g.sand_thickness, 3, "the sand", dx, "geometry.sand_thickness", g.sand_thickness)
        resolves(g.depth, 6, "the water depth", dx)
        top = g.sand_thickness + g.depth
        if top + 0.1 >= g.wall_height:
            raise ConfigError(
                "geometry.wall_height", g.wall_height, f"above the water surface + 0.1 m ({top + 0.1:g} m)"
            )
        shore = g.toe_x + g.depth * g.slope
        if shore >= g.length - 0.2:
            raise ConfigError(
                "geometry.length",
                g.length,
                f"longer than the shoreline position + 0.2 m ({shore + 0.2:.3g} m) for this toe_x and slope",
            )
        if not isinstance(g.gauges_x, list) or any(
            isinstance(x, bool) or not isinstance(x, (int, float)) or not 0 < x < g.length for x in g.gauges_x
        ):
            raise ConfigError("geometry.gauges_x", g.gauges_x, f"a list of positions in m, each in (0, {g.length:g})")
        if g.toe_x < 1.0:
            raise ConfigError("geometry.toe_x", g.toe_x, "at least 1 m (room for the waves to form)")
        check_paddle(cfg, paddle_depth(cfg), g.length, default_stroke=self.DEFAULTS["paddle"]["stroke"])

    def build(self, cfg):
        if cfg.sediment.model == "bedload":
            return build_bedload(cfg, self.NAME, STILLS)
        geo, num, p = cfg.geometry, cfg.numerics, cfg.paddle
        dx, Lf, d, ts, Hw = num.dx, geo.length, geo.depth, geo.sand_thickness, geo.wall_height
        yw = ts + d  # still-water level
        omega, k, wavelength, cg, hs_ratio = linear_wave(cfg, d)
        H_biesel = hs_ratio * p.stroke
        c0, u_max = sound_speed(cfg, math.sqrt(G * (d + H_biesel)))  # bore speed of the broken wave
        T = num.wall_layers * dx
        h = num.h_factor * dx
        ps, extra, reach, x_left = _particles(cfg, c0)
        materials = [
            dict(dict(cfg.materials[n]), name=n, B=tait_B(cfg.materials[n]["rho0"], c0)) for n in ("water", "sand")
        ]
        pad = 3 * T + 4 * h
        domain = ((x_left - pad, -pad), (Lf + pad, 2 * Hw + pad))
        params = common_params(cfg, c0, G, depth=yw)
        params.update(extra)
        bed = BedRecord(cfg, h, (omega, k, wavelength, cg, H_biesel))
        events = []
        if cfg.output.render:
            events = [(t, _streamlines_event(yw, Lf, dx)) for t in STILLS]
        margin = T + dx
        return make_case(
            name=self.NAME,
            particles=ps,
            materials=materials,
            domain=domain,
            params=params,
            physics=physics_from_config(cfg, paddle=p.type),
            view=((x_left - margin, -margin), (Lf + margin, min(Hw, yw + 0.35) + margin)),
            u_max=u_max,
            probe_columns=("ripple_length", "ripple_height", "bed_change_rms", "eta_toe") + bed.gauges.columns,
            probe=bed.probe,
            metrics=bed.metrics,
            finalize=bed.finalize,
            events=events,
            stills=STILLS,
            container=(-reach - dx, 0.0, Lf, float("inf"), Hw),
            render_modes=("phase",),
            mat_colors=(None, SAND),
            control=with_control(extra["motion"]),
            persist=(bed,) + ((extra["motion"],) if p.absorb else ()),
        )


SCENE = Beach()
main = partial(run_scene, SCENE)
