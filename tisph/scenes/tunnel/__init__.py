"""Oscillating water tunnel over a sand bed: the laboratory set-up for wave ripples, where the
beach's ripple question can be asked at a resolution that resolves them.

The near-bed motion under waves is, to first order, a uniform oscillation U(t) = U_m sin(wt) of
orbital diameter d0 = 2 U_m / w; a tunnel reproduces it with an oscillating pressure gradient.
Here the domain is periodic in x, the water has a free surface, and the pressure gradient is the
solver's drive dU/dt (sand feels rho_w / rho_s of it, as of any pressure gradient), ramped in over
the first period as U_m sin^2(pi t / 2T) sin(wt) so no mean current starts. The bed is the
bed-load bed below particle scale (sediment.model = "bedload", tisph/sediment): ripples grow from
a random bed of 1 % of d0 through the lee vortex and its throw (docs/sediment.md);
sediment.model = "particles" makes it the beach's Bingham sand (paper 000 section 5,
scenes/tunnel_bingham.toml). The measured ripples are compared with the equilibrium predictor of
Wiberg & Harris (1994) for the imposed d0 and the grain diameter.

Defaults: d0 = 0.3 m, T = 2 s (U_m = 0.47 m/s), a 0.15 m water layer over 0.08 m of sand,
1.2 m long, dx = 1 cm, so the predicted orbital ripple (0.19 m long, 3 cm high) spans 19
particles; 40 s (20 periods, 200 periods of bed change at morfac 10), about 2 minutes on two
cores. geometry.seed_ripple_height > 0 starts the bed rippled (at the predicted length, or
geometry.seed_ripple_length), to ask whether the bed keeps them, merges or splits them.
"""

import os
from functools import partial

import numpy as np

from ...case import Scene, make_case, resolves
from ...constants import G
from ...io import write_station_rows
from ...measure.field import surface_heights
from ...measure.ripple_plots import plot_bed
from ...particles import FLUID, WALL, ParticleSet, block, density_from_pressure, layered_pressure, tait_B
from ...ripples import MIN_HEIGHT_DX, MIN_LENGTH_DX, derive_resolution, last_finite, ripple_stats, wiberg_harris
from ...runner import common_params, run_scene, sound_speed
from ...sediment import keys as sediment_keys
from ...sediment.morfac import CALIBRATION
from ...settings.config import ConfigError, physics_from_config
from ...settings.materials import BINGHAM_SAND, WATER
from ...settings.schema import NON_NEGATIVE, POSITIVE, K, with_defaults
from ...settings.schemes import numerics
from ...viz.render import SAND
from .bedload import build_bedload, near_bed_ratio  # noqa: F401  (near_bed_ratio: the tests read it here)
from .drive import (  # noqa: F401
    BED_PERIODS,
    CREST_SPEED,
    TunnelDrive,
    free_stream,
    morfac_limit,
    seed_count,
    seed_rms,
    turnover_periods,
)


def _particles(cfg, c0, a_seed, n_seed):
    """Water over a sand layer (seeded with n_seed ripples of amplitude a_seed) on a floor."""
    geo, num = cfg.geometry, cfg.numerics
    dx, Lx, hw, hs = num.dx, geo.length, geo.water_depth, geo.sand_depth
    rw, rs = cfg.materials.water.rho0, cfg.materials.sand.rho0
    L = num.wall_layers
    ytop = hs + hw

    def bed_level(x):
        return hs + a_seed * np.sin(2 * np.pi * n_seed * np.asarray(x, float) / Lx)

    lattice = block(0.0, 0.0, Lx, ytop + a_seed, dx)
    sand = lattice[:, 1] < bed_level(lattice[:, 0])
    lattice = lattice[sand | (lattice[:, 1] < ytop)]  # water keeps its level over a seeded bed
    sand = lattice[:, 1] < bed_level(lattice[:, 0])

    def pressure(y, yb=hs):
        return layered_pressure(y, yb, ytop, rw, rs, G)

    ps = ParticleSet()
    xw, xs = lattice[~sand], lattice[sand]
    ps.add(xw, FLUID, 0, density_from_pressure(pressure(xw[:, 1], bed_level(xw[:, 0])), rw, c0), rw * dx * dx)
    ps.add(xs, FLUID, 1, density_from_pressure(pressure(xs[:, 1], bed_level(xs[:, 0])), rs, c0), rs * dx * dx)
    floor = block(0.0, -L * dx, Lx, 0.0, dx)
    ps.add(floor, WALL, 0, density_from_pressure(pressure(floor[:, 1]), rw, c0), rw * dx * dx)
    return ps


def particle_bed_metrics(c, Um, predicted, dx, Tp):
    """The particle-sand tunnel: the free stream against its target after the ramp (Tp), and the
    ripples of the bed change against Wiberg & Harris's (predicted: length, height, regime)."""
    lam_wh, eta_wh, regime = predicted
    out = dict(
        velocity_amplitude=Um,
        predicted_ripple_length=lam_wh,
        predicted_ripple_height=eta_wh,
        predicted_regime=regime,
        predicted_ripple_length_in_dx=lam_wh / dx,
    )
    t = c["t"]
    after = t >= Tp  # the ramp is over
    if after.sum() > 4:
        err = c["u_free"][after] - c["u_target"][after]
        out["free_stream_error"] = float(np.sqrt(np.mean(err**2)) / Um)  # rms, relative to U_m
    out.update(last_finite(c, ("ripple_length", "ripple_height", "bed_change_rms")))
    out["ripple_length_over_prediction"] = out["ripple_length"] / lam_wh if lam_wh > 0 else float("nan")
    out["bed_change_rms_over_dx"] = out["bed_change_rms"] / dx
    return out


class Tunnel(Scene):
    """Oscillating water tunnel over a sand bed: the laboratory set-up for wave ripples."""

    NAME = "tunnel"

    SCHEMA = {
        "run": {"end_time": 40.0},
        "numerics": numerics("bed", dx=0.01),
        "geometry": {
            "length": K(1.2, "periodic length", "m", range=POSITIVE),
            "water_depth": K(0.15, "water above the bed", "m", range=POSITIVE),
            "sand_depth": K(0.08, "sand layer on the rigid floor", "m", range=POSITIVE),
            "orbital_diameter": K(CALIBRATION["orbital_diameter"], "d0 = 2 U_m / omega", "m", range=POSITIVE),
            "period": K(CALIBRATION["period"], "T", "s", range=POSITIVE),
            "grain_diameter": K(
                CALIBRATION["grain_diameter"], "for the Wiberg & Harris prediction", "m", range=POSITIVE
            ),
            "seed_ripple_height": K(
                0.0,
                "> 0: the bed starts rippled, crest to trough this high (m), at the predicted length rounded to fit the periodic length: does the bed keep, grow or lose them?",
                range=NON_NEGATIVE,
            ),
            "seed_ripple_length": K(
                0.0, "m; 0: the predicted length (rounded to fit the periodic length)", range=NON_NEGATIVE
            ),
            "roughness": K(
                0.01,
                "the random bed's RMS roughness over d0 where sediment.seed_rms = 0 (3 mm at the default d0): where the ripples end depends on it (docs/sediment.md), so it follows d0; 0 and seed_rms = 0: a flat bed",
                range=(0.0, 0.1, True, True),
            ),
        },
        "materials": {"water": dict(WATER), "sand": dict(BINGHAM_SAND)},  # the beach's water and sand
        # the bed below particle scale (tisph/sediment), the wave-ripple set; seed_rms: geometry.roughness
        "sediment": with_defaults(sediment_keys.SEDIMENT, **sediment_keys.WAVE_RIPPLES, morfac=CALIBRATION["morfac"]),
        "output": {"frame_interval": 0.05, "probe_interval": 0.05, "width": 960},
    }

    def derive(self, cfg, given):
        """dx and morfac from the physics where the user left them at their defaults: dx resolves the
        predicted ripple (Wiberg & Harris for d0 and d50) over RESOLVED_DX spacings, and morfac turns
        the bed over no faster than in the calibration tunnel (tisph/sediment/morfac.py), at most its
        10. The calibration tunnel itself keeps dx 0.01 and morfac 10. Returns run.log's lines."""
        g = cfg.geometry
        limit = morfac_limit(cfg) if cfg.sediment.model == "bedload" else None
        return derive_resolution(
            cfg,
            given,
            wiberg_harris(g.orbital_diameter, g.grain_diameter)[0],
            g.orbital_diameter,
            limit=limit,
            cap=CALIBRATION["morfac"],
        )

    def check(self, cfg):
        g, dx = cfg.geometry, cfg.numerics.dx
        resolves(g.sand_depth, 4, "the sand", dx, "geometry.sand_depth", g.sand_depth)
        resolves(g.water_depth, 6, "the water", dx, "geometry.water_depth", g.water_depth)
        resolves(g.length, 20, "the tunnel", dx, "geometry.length", g.length)
        if g.seed_ripple_height > g.sand_depth - 2 * dx:
            raise ConfigError(
                "geometry.seed_ripple_height",
                g.seed_ripple_height,
                f"at most sand_depth - 2 dx ({g.sand_depth - 2 * dx:.3g} m)",
            )

    def build(self, cfg):
        if cfg.sediment.model == "bedload":
            return build_bedload(cfg, self.NAME)
        geo, num = cfg.geometry, cfg.numerics
        dx, Lx, hw, hs = num.dx, geo.length, geo.water_depth, geo.sand_depth
        Tp = geo.period
        drive = TunnelDrive(geo)
        Um = drive.Um
        mats = cfg.materials
        c0, u_max = sound_speed(cfg, CREST_SPEED * Um, hw + hs, G)
        L = num.wall_layers
        h = num.h_factor * dx
        ytop = hs + hw
        lam_wh, eta_wh, regime = wiberg_harris(geo.orbital_diameter, geo.grain_diameter)
        n_seed = seed_count(geo, lam_wh)
        a_seed = 0.5 * geo.seed_ripple_height

        ps = _particles(cfg, c0, a_seed, n_seed)
        materials = [dict(dict(mats[n]), name=n, B=tait_B(mats[n]["rho0"], c0)) for n in ("water", "sand")]
        params = common_params(cfg, c0, G, depth=ytop)
        params["held_current"] = drive  # the drive's feedback: the device's on a GPU (engine/drive.py)
        pad = 4 * h
        domain = ((0.0, -L * dx - pad), (Lx, 2.0 * ytop + pad))
        physics = physics_from_config(cfg, periodic_x=True)

        stations = np.arange(0.5 * dx, Lx, dx)
        bed_rows, bed0 = [], {}

        def probe(st):
            b = surface_heights(st, stations, dx, h, mat=1)
            if "b" not in bed0:
                bed0["b"] = b
            bed_rows.append((st["t"],) + tuple(b))
            # ripples on the bed change; on a seeded bed, on the bed itself (its seeded ripples included)
            z = b - (hs if a_seed > 0 else bed0["b"])
            lam, hr, _ = ripple_stats(
                stations, z, window=0.5 * Lx, min_length=MIN_LENGTH_DX * dx, min_height=MIN_HEIGHT_DX * dx
            )
            rms = float(np.sqrt(np.mean((b - bed0["b"]) ** 2)))
            return lam, hr, rms, drive.u_free(st), drive.target(st["t"])

        def finalize(out, metrics):
            if not bed_rows:
                return
            write_station_rows(os.path.join(out, "bed_profile.csv"), stations, bed_rows)
            plot_bed(os.path.join(out, "bed_profile.png"), np.array(bed_rows), stations, geo, dx, lam_wh, eta_wh)

        return make_case(
            name=self.NAME,
            particles=ps,
            materials=materials,
            domain=domain,
            params=params,
            physics=physics,
            view=((0.0, -L * dx), (Lx, ytop + 2 * dx)),
            u_max=u_max,
            probe_columns=("ripple_length", "ripple_height", "bed_change_rms", "u_free", "u_target"),
            probe=probe,
            metrics=partial(particle_bed_metrics, Um=Um, predicted=(lam_wh, eta_wh, regime), dx=dx, Tp=Tp),
            finalize=finalize,
            container=(-1e9, -0.5 * dx, 1e9, float("inf")),
            render_modes=("phase",),
            mat_colors=(None, SAND),
            control=drive.update,
            control_every=drive.every,
            persist=(drive.ctl, bed_rows, bed0),
        )


SCENE = Tunnel()
main = partial(run_scene, SCENE)
