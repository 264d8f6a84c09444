"""The beach over the morphodynamic bed (sediment.model = "bedload", the default): SPH water over
a height field z_b(x) whose boundary particles follow it (tisph/sediment), in front of the paddle.

The bed starts at sand_thickness above the floor, flat to toe_x, then rising at 1:slope past the
shoreline to the end wall; the first RIGID metres in front of the paddle are a rigid floor at
that level (the paddle's own start-up flow is not a wave's). Both ends of the bed are closed, so
its sand volume is conserved. The near-bed orbital amplitude A that Swart's friction factor and
the lee vortex need is measured at every station from the near-bed velocity (it grows as the
waves shoal), and so is the Wiberg & Harris (1994) ripple the measured d0 = 2 A predicts.
"""

import math
import os

import numpy as np

from ...case import make_case
from ...constants import G
from ...io import write_csv, write_station_rows
from ...measure.field import surface_at
from ...measure.gauge_sets import WaveGauges
from ...measure.plots import pyplot, save
from ...measure.records import height_at
from ...particles import BED, FLUID, MOVING, WALL, ParticleSet, block, density_from_pressure, tait_B
from ...ripples import (
    MIN_LENGTH_DX,
    RESOLVED_DX,
    derive_resolution,
    last_finite,
    orbital_diameter,
    ripple_stats,
    unresolved,
    warn_unresolved,
    wiberg_harris,
)
from ...runner import common_params, sound_speed
from ...sediment import coupling, initial
from ...sediment.morfac import bed_turnover, morfac_limit, warn_fast_bed
from ...settings.config import physics_from_config
from ...settings.plausible import warn_waves
from ...waves.absorb import with_control
from ...waves.paddle import paddle
from ...waves.theory import linear_wave
from .shoaling import Shoaling, crest_height, run_up, warn_run_up

RIGID = 0.5  # m of rigid floor in front of the paddle
RIPPLE_WINDOW = 0.6  # m: bedforms longer than this (the profile's bar and shoreline) are not ripples


def bed_profile(geo, x):
    """The initial bed level: flat at sand_thickness, then 1:slope from toe_x."""
    return geo["sand_thickness"] + np.maximum(0.0, (np.asarray(x, float) - geo["toe_x"]) / geo["slope"])


def paddle_depth(cfg):
    """The water depth at the paddle: the bed-load bed's paddle stands on the bed, the Bingham
    bed's on the floor under the sand."""
    g = cfg.geometry
    return g.depth + (0.0 if cfg.sediment.model == "bedload" else g.sand_thickness)


def toe_wave(cfg):
    """(omega, k, Biesel H, d0) of the linear wave over the flat bed in front of the toe."""
    d, p = cfg.geometry.depth, cfg.paddle
    omega, k, _, _, hs_ratio = linear_wave(cfg, d)
    H = p.wave_height if p.wave_height > 0 else hs_ratio * p.stroke
    return omega, k, H, orbital_diameter(H, k, d)


def derive_bedload(cfg, given):
    """dx and morfac from the wave where the user left them unset, as the tunnel's: dx resolves the
    ripple Wiberg & Harris predict for the toe's linear-wave d0 over RESOLVED_DX spacings, and
    morfac turns the bed there over no faster per wave period than in the calibration tunnel.
    Returns the values and run.log's lines."""
    geo, sed = cfg.geometry, cfg.sediment
    if cfg.paddle.series:
        return {}, []  # a measured signal: no wave to derive them from
    omega, _, H, d0 = toe_wave(cfg)
    if not (H > 0 and d0 > 0):
        return {}, []
    rw = cfg.materials.water.rho0
    turn = bed_turnover(d0, 2.0 * math.pi / omega, geo.grain_diameter, sed.grain_density / rw, sed)
    return derive_resolution(
        cfg, given, wiberg_harris(d0, geo.grain_diameter)[0], d0, " at the toe", limit=morfac_limit(sed, turn)
    )


def _bedload_particles(cfg, stations, z, c0):
    """The bed-load beach's particles: the water over the bed z at the stations, the rigid floor
    to the paddle and the end wall, the paddle's, and the bed's BED columns. Returns (particles,
    the paddle's motion, its parameters, how far behind x = 0 it reaches, the lowest the bed may
    erode to)."""
    geo, num = cfg.geometry, cfg.numerics
    dx, Lf, d, ts, Hw = num.dx, geo.length, geo.depth, geo.sand_thickness, geo.wall_height
    yw, rw = ts + d, cfg.materials.water.rho0
    L = num.wall_layers
    T = L * dx

    def density(y):
        return density_from_pressure(rw * G * np.maximum(yw - y, 0.0), rw, c0)

    ps = ParticleSet()
    cols = (np.arange(int(round(Lf / dx))) + 0.5) * dx
    xw = initial.water_columns(cols, np.interp(cols, stations, z, left=ts), dx, yw)
    ps.add(xw, FLUID, 0, density(xw[:, 1]), rw * dx * dx)
    pad_pts, motion, extra, reach = paddle(cfg, d, Hw, floor_y=ts)
    x_left = -reach - 2 * T
    floor = float(z.min()) - 0.1  # the bed may erode 0.1 m below its lowest point
    # Where the rigid floor meets the bed, the bed's first column and the floor's last two reach
    # down to the bed's floor: sand piled against the rigid floor (or scoured beside it) leaves
    # a face higher than the column's own layers, and water found its way under the bed there
    # (at dx 0.0062, a 2.6 cm pile).
    walls = np.vstack(
        [
            block(x_left, ts - T, RIGID, ts, dx),
            block(RIGID - 2 * dx, floor - T, RIGID, ts - T, dx),
            block(Lf, floor - T, Lf + T, Hw, dx),
        ]
    )
    ps.add(walls, WALL, 0, density(walls[:, 1]), rw * dx * dx)
    ps.add(pad_pts, MOVING, 0, density(pad_pts[:, 1]), rw * dx * dx)
    initial.add_bed_particles(ps, stations, z, dx, L, rw, density)
    depth = (np.arange(L, int(np.ceil((z[0] - floor) / dx)) + L) + 0.5) * dx  # below the first column's L
    y = z[0] - depth
    ps.add(
        np.column_stack([np.full(len(y), stations[0]), y]),
        BED,
        0,
        density(y),
        rw * dx * dx,
        station=np.zeros(len(y), int),
        normal=(0.0, 1.0),
        wall_dist=depth,
    )
    return ps, motion, extra, reach, floor


def build_bedload(cfg, name, stills):
    geo, num, p, sed = cfg.geometry, cfg.numerics, cfg.paddle, cfg.sediment
    dx, Lf, d, ts, Hw = num.dx, geo.length, geo.depth, geo.sand_thickness, geo.wall_height
    yw = ts + d
    rw = cfg.materials.water.rho0
    omega, k, wavelength, cg, hs_ratio = linear_wave(cfg, d)
    H_biesel = hs_ratio * p.stroke
    d0_toe = orbital_diameter(H_biesel, k, d)
    lam_toe, ripple_h_toe, _ = wiberg_harris(d0_toe, geo.grain_diameter)
    warn_unresolved(lam_toe, dx, "at the toe (Wiberg & Harris for the linear-wave d0)")
    T_wave = 2.0 * math.pi / omega
    warn_fast_bed(
        sed,
        bed_turnover(d0_toe, T_wave, geo.grain_diameter, sed["grain_density"] / rw, sed),
        f"at the toe's linear-wave d0 of {d0_toe:.3g} m",
    )
    warn_waves(cfg, H_biesel, k, d, linear_metric=False)
    c0, u_max = sound_speed(cfg, math.sqrt(G * (d + H_biesel)))
    L, h = num.wall_layers, num.h_factor * dx
    T = L * dx
    stations = RIGID + (np.arange(int(round((Lf - RIGID) / dx))) + 0.5) * dx
    sed = dict(sed, seed_rms=initial.random_bed_rms(sed, geo.roughness, d0_toe))
    z = initial.initial_bed(stations, bed_profile(geo, stations), sed, dx, periodic=False, top=yw)

    ps, motion, extra, reach, floor = _bedload_particles(cfg, stations, z, c0)
    x_left = -reach - 2 * T

    params = common_params(cfg, c0, G, depth=yw)
    params.update(extra)
    params["bed_stations"] = len(stations)
    pad = 3 * T + 4 * h
    domain = ((x_left - pad, floor - T - pad), (Lf + T + pad, 2 * Hw + pad))
    physics = physics_from_config(cfg, paddle=p.type, materials_used=["water"], moving_bed=True)
    bed = coupling.BedCoupler(
        sed,
        coupling.sand_of(sed, geo.grain_diameter, sed["grain_density"], rw),
        coupling.Stations(stations, z, dx, h, periodic=False),
        coupling.Drive(amplitude=None, omega=omega, still_level=yw),
    )
    rec = BeachBed(cfg, bed, stations, omega, k, wavelength, cg, H_biesel)
    # the frame: the whole beach from the paddle, where the bed changes, to the swash; under it a
    # metre of the ripple zone (from half a metre past the toe) at true scale (output.zoom)
    view = ((0.0, ts - 0.05), (Lf, min(Hw, yw + 0.1)))
    # tall enough for a shoaled crest (up to about a wave height above still water near breaking)
    zx = geo.toe_x + 0.5
    zoom = ((zx, float(bed_profile(geo, zx)) - 0.04), (zx + 1.0, yw + max(0.06, H_biesel)))
    # colour top: three times the near-bed orbital speed at the paddle (linear waves), not the
    # bore speed that bounds the sound speed: the shoaling waves are what the frame shows
    u_col = 3.0 * 0.5 * H_biesel * omega / math.sinh(k * d)
    return make_case(
        name=name,
        particles=ps,
        materials=[dict(cfg.materials.water, name="water", B=tait_B(rw, c0))],
        domain=domain,
        params=params,
        physics=physics,
        view=view,
        zoom=zoom,
        u_max=u_max,
        marks=[(x, f"g{i + 1}") for i, x in enumerate(geo.gauges_x)],
        speed_scale=u_col,
        probe_columns=BeachBed.COLUMNS + rec.gauges.columns,
        probe=rec.probe,
        metrics=rec.metrics,
        finalize=rec.finalize,
        stills=stills,
        container=(-reach - dx, floor - T, Lf, float("inf"), Hw),
        control=with_control(motion, bed.update),
        control_every=sed["update_every"],
        persist=(bed, rec) + ((motion,) if p.absorb else ()),
        **bed.picture(left=ts, ripple_height=ripple_h_toe),
    )


class BeachBed:
    """Probes, metrics and plots of the bed-load beach: ripples on the bed change (high-passed
    over RIPPLE_WINDOW) over the zone where the measured near-bed motion predicts ripples of at
    least MIN_LENGTH_DX spacings, against Wiberg & Harris there."""

    COLUMNS = (
        "ripple_length",
        "ripple_height",
        "ripple_count",
        "bed_change_rms",
        "eta_toe",
        "predicted_ripple_length",
        "max_bed_shear",
        "run_up",
    )

    def __init__(self, cfg, bed, stations, omega, k, wavelength, cg, H_biesel):
        self.cfg, self.bed, self.stations = cfg, bed, stations
        self.dx = cfg.numerics.dx
        self.omega, self.k, self.wavelength, self.cg, self.H_biesel = omega, k, wavelength, cg, H_biesel
        geo = cfg.geometry
        self.yw = geo.sand_thickness + geo.depth
        self.toe, self.grain = geo.toe_x, geo.grain_diameter
        self.rows, self.zone = [], None
        self.lengths = (float("nan"), float("nan"))  # the last probe's measured and predicted means
        self.gauges = WaveGauges(
            geo.gauges_x, self.dx, cfg.numerics.h_factor * self.dx, self.yw, dry_from=geo.toe_x + geo.depth * geo.slope
        )
        self.shore = geo.toe_x + geo.depth * geo.slope
        self.hunt = warn_run_up(geo, H_biesel, omega, k)  # warns where the crest is under it
        self.shoal = Shoaling(
            geo, lambda x: self.yw - float(bed_profile(geo, x)), self.yw, self.dx, cfg.numerics.h_factor * self.dx
        )

    def predicted(self):
        """Wiberg & Harris length at every station for the measured d0 = 2 A (0 where dry)."""
        lam = np.zeros(len(self.stations))
        for i, a in enumerate(self.bed.amplitude):
            if a > 0:
                lam[i] = wiberg_harris(2.0 * a, self.grain)[0]
        return lam

    def ripple_zone(self, lam):
        """Stations 2 dx or more under still water where the measured motion predicts ripples at
        least MIN_LENGTH_DX spacings long."""
        wet = self.bed.bed.z < self.yw - 2 * self.dx
        return wet & (lam >= MIN_LENGTH_DX * self.dx)

    def probe(self, st):
        zb = self.bed.bed.z
        self.rows.append((st["t"],) + tuple(zb))
        lam_p = self.predicted()
        zone = self.ripple_zone(lam_p)
        lam = hr = float("nan")
        count = 0
        if zone.sum() > 8:
            x = self.stations[zone]
            dz = (zb - self.bed.z0)[zone]
            lam, hr, _ = ripple_stats(
                x, dz, window=RIPPLE_WINDOW, min_length=MIN_LENGTH_DX * self.dx, min_height=0.1 * self.dx
            )
            count = int(round((x[-1] - x[0]) / lam)) if np.isfinite(lam) and lam > 0 else 0
            self.zone = zone
        rms = float(np.sqrt(np.mean((zb - self.bed.z0) ** 2)))
        eta = surface_at(st, self.toe, self.dx, self.cfg.numerics.h_factor * self.dx, mat=0) - self.yw
        lp = float(lam_p[zone].mean()) if zone.any() else float("nan")
        self.lengths = (lam, lp)
        self.shoal.read(st)
        ru = run_up(st, self.stations, zb, self.shore, self.yw, self.dx)
        return (lam, hr, count, rms, eta, lp, float(np.abs(self.bed.tau).max()), ru) + self.gauges.read(st)

    def metrics(self, c):
        p, sed = self.cfg.paddle, self.cfg.sediment
        out = dict(
            kh_paddle=self.k * self.cfg.geometry.depth,
            wavelength=self.wavelength,
            biesel_wave_height=self.H_biesel,
            sediment_model="bedload",
            morfac=sed["morfac"],
            theta_cr=self.bed.bed.theta_cr,
            sand_volume_error=self.bed.volume_error(),
        )
        out.update(last_finite(c, ("ripple_length", "ripple_height", "bed_change_rms", "predicted_ripple_length")))
        out["ripple_count"] = int(c["ripple_count"][-1]) if len(c["ripple_count"]) else 0
        lam, lp = out["ripple_length"], out["predicted_ripple_length"]
        out["ripple_length_over_prediction"] = lam / lp if lp > 0 else float("nan")
        out["ripple_steepness"] = out["ripple_height"] / lam if lam > 0 else float("nan")
        if self.zone is not None:
            out["ripple_zone"] = [float(self.stations[self.zone][0]), float(self.stations[self.zone][-1])]
        geo = self.cfg.geometry
        out["run_up_max"] = float(np.max(c["run_up"])) if len(c["run_up"]) else float("nan")
        out["run_up_hunt"] = self.hunt
        out["crest_above_still_water"] = top = crest_height(geo)
        # the swash reached the end wall: wet within two stations of it
        out["swash_at_end_wall"] = bool(out["run_up_max"] >= top - 2.5 * self.dx / geo.slope)
        H, n = height_at(c, "eta_toe", self.toe, p, self.cg)
        out["wave_height_at_toe"] = H
        out["periods_measured_at_toe"] = n
        out.update(self.gauges.metrics(c, p, self.cg))
        out.update(
            self.shoal.measure(p, self.cg, self.omega, lambda x: float(np.interp(x, self.stations, self.bed.amplitude)))
        )
        return unresolved(out, lp, self.dx)

    def finalize(self, out, metrics):
        if not self.rows:
            return
        write_station_rows(os.path.join(out, "bed_profile.csv"), self.stations, self.rows)
        lam = self.predicted()
        write_csv(
            os.path.join(out, "ripple_prediction.csv"),
            ("x", "bed_initial", "orbital_amplitude", "orbital_diameter_d0", "wiberg_harris_length"),
            [
                (float(x), float(z0), float(a), float(2 * a), float(lp))
                for x, z0, a, lp in zip(self.stations, self.bed.z0, self.bed.amplitude, lam)
            ],
        )
        self.plot(os.path.join(out, "bed_profile.png"), lam)
        self.shoal.plot(os.path.join(out, "shoaling.png"), pyplot, save)

    def plot(self, path, lam):
        plt = pyplot()
        arr = np.array(self.rows)
        x = self.stations
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 5.5), sharex=True)
        for t in np.linspace(arr[0, 0], arr[-1, 0], 5)[1:]:
            r = arr[np.argmin(np.abs(arr[:, 0] - t))]
            a1.plot(x, 1e3 * (r[1:] - self.bed.z0), lw=0.8, label=f"t = {r[0]:.1f} s")
        if self.zone is not None:
            a1.axvspan(x[self.zone][0], x[self.zone][-1], color="0.93", label="ripple zone")
        a1.set_ylabel("bed change (mm)")
        a1.legend(fontsize=7, ncol=5, loc="lower left")
        a2.plot(x, 100 * lam, label="Wiberg & Harris length (measured d0)")
        lengths = self.lengths
        if self.zone is not None and np.isfinite(lengths[0]):
            x0, x1 = x[self.zone][0], x[self.zone][-1]
            a2.hlines(
                100 * lengths[1],
                x0,
                x1,
                color="C0",
                lw=2.0,
                ls="--",
                label=f"its mean over the ripple zone, {100 * lengths[1]:.1f} cm",
            )
            a2.hlines(
                100 * lengths[0],
                x0,
                x1,
                color="C3",
                lw=2.0,
                label=f"the ripples' mean length there, {100 * lengths[0]:.1f} cm",
            )
        a2.axhline(100 * RESOLVED_DX * self.dx, color="k", lw=0.8, ls=":", label=f"{RESOLVED_DX:g} dx (resolved)")
        a2.set_ylabel("ripple length (cm)")
        a2.set_xlabel("x (m)")
        a2.legend(fontsize=7, loc="lower left", ncol=2)
        fig.suptitle(f"beach over a bed-load sand bed (morfac {self.cfg.sediment.morfac:g})", fontsize=10)
        save(fig, path)
