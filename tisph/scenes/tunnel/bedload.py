"""The tunnel over the bed-load bed (sediment.model = "bedload"): water only, over BED particles that
follow the bed level z_b, which the bed load moves (tisph/sediment)."""

import os
import warnings

import numpy as np

from ...case import make_case
from ...constants import G
from ...io import write_station_rows
from ...measure.ripple_plots import plot_bed, plot_growth
from ...particles import FLUID, ParticleSet, density_from_pressure, tait_B
from ...ripples import last_finite, ripple_band, unresolved, warn_unresolved, wiberg_harris
from ...ripples import periodic_ripples as ripples_counted
from ...runner import common_params, sound_speed
from ...sediment import coupling, initial
from ...sediment.morfac import warn_fast_bed
from ...settings.config import physics_from_config
from .drive import BED_PERIODS, CREST_SPEED, TunnelDrive, seed_count, seed_rms, turnover_periods


def _warn_short(end_time, period, morfac):
    bed_periods = end_time / period * morfac
    if bed_periods < 0.99 * BED_PERIODS:  # a rounded end time is not short
        warnings.warn(
            f"run.end_time = {end_time:g} s is {bed_periods:.0f} periods of bed change "
            f"(wave periods x morfac {morfac:g}): ripples take about 100 to reach their length and "
            f"a run should show 100 more that it holds; run.end_time = "
            f"{BED_PERIODS * period / morfac:g} s gives {BED_PERIODS}"
        )


def _ripples_round(zb, Lx, dx):
    """(mean length, mean height) of the ripples counted round the periodic bed."""
    n, hr = ripples_counted(zb, Lx, ripple_band(zb, dx))
    return (Lx / n, hr) if n else (float("nan"), float("nan"))


class TunnelRecord:
    """What the tunnel over a bed-load bed measures: the bed at every probe, the ripples of its
    change against Wiberg & Harris's (predicted: their length, height and regime for d0), the
    near-bed flow the bed reads, and the bed's figures."""

    def __init__(self, cfg, drive, bed, stations, predicted, turnover, limit):
        self.geo, self.sed, self.dx = cfg.geometry, cfg.sediment, cfg.numerics.dx
        self.rw = cfg.materials.water.rho0
        self.drive, self.bed, self.stations = drive, bed, stations
        self.lam_wh, self.eta_wh, self.regime = predicted
        self.turnover, self.limit = turnover, limit
        self.rows, self.seen = [], {}  # the bed at every probe; the probe columns, for the growth plot

    def probe(self, st):
        zb, drive = self.bed.bed.z, self.drive
        self.rows.append((st["t"],) + tuple(zb))
        lam, hr = _ripples_round(zb, self.geo.length, self.dx)
        rms = float(np.sqrt(np.mean((zb - self.bed.z0) ** 2)))
        return (
            lam,
            hr,
            rms,
            drive.u_free(st),
            drive.target(st["t"]),
            float(np.abs(self.bed.tau).max()),
            float(np.mean(self.bed.u)),
            float(np.mean(self.bed.u_eff)),
        )

    def metrics(self, c):
        self.seen.update(c)
        geo, sed, Um, lam_wh = self.geo, self.sed, self.drive.Um, self.lam_wh
        out = dict(
            velocity_amplitude=Um,
            predicted_ripple_length=lam_wh,
            predicted_ripple_height=self.eta_wh,
            predicted_regime=self.regime,
            morfac=sed["morfac"],
            sediment_model="bedload",
            theta_cr=self.bed.bed.theta_cr,
            sand_volume_error=self.bed.volume_error(),
            mobility_number=Um**2 / ((sed["grain_density"] / self.rw - 1) * G * geo.grain_diameter),
            bed_turnover_periods=self.turnover,
            morfac_limit=self.limit,
        )
        out.update(last_finite(c, ("ripple_length", "ripple_height", "bed_change_rms")))
        lam = out["ripple_length"]
        # exact: lam = Lx / count
        out["ripple_count"] = int(round(geo.length / lam)) if np.isfinite(lam) and lam > 0 else 0
        out["ripple_length_over_d0"] = lam / geo.orbital_diameter
        out["ripple_steepness"] = out["ripple_height"] / lam if lam > 0 else float("nan")
        out["ripple_length_over_prediction"] = lam / lam_wh if lam_wh > 0 else float("nan")
        out["near_bed_velocity_ratio"] = near_bed_ratio(c["t"], c["u_near_bed"], Um, self.drive.period)
        out["effective_velocity_ratio"] = near_bed_ratio(c["t"], c["u_bed_effective"], Um, self.drive.period)
        return unresolved(
            out, lam_wh, self.dx, ("ripple_length_over_d0", "ripple_length_over_prediction", "ripple_steepness")
        )

    def finalize(self, out, metrics):
        if self.rows:
            geo, st, rows = self.geo, self.stations, self.rows
            write_station_rows(os.path.join(out, "bed_profile.csv"), st, rows)
            plot_bed(
                os.path.join(out, "bed_profile.png"),
                np.array(rows),
                st,
                geo,
                self.dx,
                self.lam_wh,
                self.eta_wh,
                level=geo.sand_depth,
            )
            plot_growth(os.path.join(out, "ripple_growth.png"), self.seen, geo, self.sed["morfac"])


def build_bedload(cfg, name):
    """The tunnel over a morphodynamic bed: water only, over BED particles that follow z_b."""
    geo, num, sed = cfg.geometry, cfg.numerics, cfg.sediment
    dx, Lx, hw, hs = num.dx, geo.length, geo.water_depth, geo.sand_depth
    d0 = geo.orbital_diameter
    drive = TunnelDrive(geo)
    Um = drive.Um
    rw = cfg.materials.water.rho0
    c0, u_max = sound_speed(cfg, CREST_SPEED * Um, hw, G)
    L, h = num.wall_layers, num.h_factor * dx
    ytop = hs + hw
    lam_wh, eta_wh, regime = wiberg_harris(d0, geo.grain_diameter)
    warn_unresolved(lam_wh, dx, "(Wiberg & Harris for d0)")
    _warn_short(cfg.run.end_time, geo.period, sed["morfac"])
    turnover = turnover_periods(cfg)
    limit = warn_fast_bed(sed, turnover, f"at d0 = {d0:g} m")
    n_seed = seed_count(geo, lam_wh)
    stations = (np.arange(int(round(Lx / dx))) + 0.5) * dx
    z = hs + 0.5 * geo.seed_ripple_height * np.sin(2 * np.pi * n_seed * stations / Lx)
    sed = dict(sed, seed_rms=seed_rms(cfg))
    z = initial.initial_bed(stations, z, sed, dx, periodic=True, top=ytop)
    ps = _bedload_particles(cfg, stations, z, c0)
    params = common_params(cfg, c0, G, depth=ytop)
    params["bed_stations"] = len(stations)
    domain = ((0.0, float(z.min()) - (L + 2) * dx - 4 * h), (Lx, 2.0 * ytop + 4 * h))
    physics = physics_from_config(cfg, periodic_x=True, materials_used=["water"], moving_bed=True)
    bed = coupling.BedCoupler(
        sed,
        coupling.sand_of(sed, geo.grain_diameter, sed["grain_density"], rw),
        coupling.Stations(stations, z, dx, h, periodic=True),
        coupling.Drive(amplitude=0.5 * d0, omega=drive.omega, still_level=ytop),
    )
    rec = TunnelRecord(cfg, drive, bed, stations, (lam_wh, eta_wh, regime), turnover, limit)

    def control(s):
        drive.update(s)
        bed.update(s)

    return make_case(
        name=name,
        particles=ps,
        materials=[dict(cfg.materials.water, name="water", B=tait_B(rw, c0))],
        domain=domain,
        params=params,
        physics=physics,
        view=((0.0, hs - 0.1), (Lx, ytop + 2 * dx)),
        u_max=u_max,
        probe_columns=(
            "ripple_length",
            "ripple_height",
            "bed_change_rms",
            "u_free",
            "u_target",
            "max_bed_shear",
            "u_near_bed",
            "u_bed_effective",
        ),
        probe=rec.probe,
        metrics=rec.metrics,
        finalize=rec.finalize,
        container=(-1e9, float(z.min()) - L * dx, 1e9, float("inf")),
        control=control,
        control_every=sed["update_every"],
        persist=(drive.ctl, bed, rec.rows),
        **bed.picture(ripple_height=eta_wh),
    )


def near_bed_ratio(t, u, Um, period):
    """The amplitude of a near-bed velocity series u(t) (averaged along the bed) over U_m, in the
    last two periods: what the bed reads of the free stream (1: all of it; a numerical boundary
    layer thicker than the reference height reads less). NaN before three periods."""
    t, u = np.asarray(t, float), np.asarray(u, float)
    if len(t) < 4 or t[-1] < 3.0 * period:
        return float("nan")
    last = t >= t[-1] - 2.0 * period
    return float(0.5 * (u[last].max() - u[last].min()) / Um)


def _bedload_particles(cfg, stations, z, c0):
    """Water in columns from dx/2 above the bed z and the bed's BED particle columns."""
    geo, num = cfg.geometry, cfg.numerics
    dx, L = num.dx, num.wall_layers
    ytop = geo.sand_depth + geo.water_depth
    rw = cfg.materials.water.rho0
    xw = initial.water_columns(stations, z, dx, ytop)

    def density(y):
        return density_from_pressure(rw * G * (ytop - np.minimum(y, ytop)), rw, c0)

    ps = ParticleSet()
    ps.add(xw, FLUID, 0, density(xw[:, 1]), rw * dx * dx)
    initial.add_bed_particles(ps, stations, z, dx, L, rw, density)
    return ps
