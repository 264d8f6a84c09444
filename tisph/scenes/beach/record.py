"""The beach's bed record: the sand surface at stations every dx, the near-bed orbital velocity
above them, the ripples of the bed change and Wiberg & Harris's prediction from the measured
motion (the Bingham sand beach of paper 000 section 4.4; the bed-load beach's is bedload.py)."""

import os

import numpy as np

from ...io import write_csv, write_station_rows
from ...measure.field import surface_at, surface_heights
from ...measure.gauge_sets import WaveGauges
from ...measure.plots import pyplot, save
from ...measure.records import arrival_time, height_at
from ...particles import FLUID
from ...ripples import MIN_HEIGHT_DX, MIN_LENGTH_DX, last_finite, orbital_diameter, ripple_stats, wiberg_harris

# Bedforms longer than this many wavelengths (bars, the shoreline's retreat) are filtered out before
# the ripples are counted; shorter than 3 dx or lower than dx / 2 is not a ripple (tisph/ripples.py).
RIPPLE_WINDOW = 0.25
# the times of the stills the beach writes (s)
STILLS = (0.0, 0.7, 2.0, 4.0, 8.0, 12.0, 16.0)


class BedRecord:
    """The sand surface at stations every dx, the near-bed orbital velocity above them, the
    ripple statistics of the bed change, and the Wiberg & Harris prediction from the measured
    motion. The active zone for ripples: one wavelength before the toe to just past the
    still-water shoreline."""

    def __init__(self, cfg, h, wave):
        geo, num, self.p = cfg.geometry, cfg.numerics, cfg.paddle
        self.cfg, self.h, self.dx = cfg, h, num.dx
        self.omega, self.k, self.wavelength, self.cg, self.H_biesel = wave
        self.d, self.toe, self.grain = geo.depth, geo.toe_x, geo.grain_diameter
        self.yw = geo.sand_thickness + geo.depth
        Lf = geo.length
        self.stations = np.arange(0.5, Lf - 0.25, self.dx)
        shore = self.toe + self.d * geo.slope
        self.active = (self.stations >= max(0.5, self.toe - 0.5 * self.wavelength)) & (self.stations <= shore + 0.2)
        self.rows, self.bed0, self.u_near, self.pred_rows = [], None, [], None
        self.gauges = WaveGauges(geo.gauges_x, self.dx, h, self.yw, dry_from=shore)

    def probe(self, st):
        dx, h, stations, active = self.dx, self.h, self.stations, self.active
        b = surface_heights(st, stations, dx, h, mat=1)
        if self.bed0 is None:
            self.bed0 = b
        self.rows.append((st["t"],) + tuple(b))
        self.u_near.append(near_bed_velocity(st, stations, b, dx))
        z = b - self.bed0
        lam, hr, rms = ripple_stats(
            stations[active],
            z[active],
            window=RIPPLE_WINDOW * self.wavelength,
            min_length=MIN_LENGTH_DX * dx,
            min_height=MIN_HEIGHT_DX * dx,
        )
        eta = surface_at(st, self.toe, dx, h, mat=0) - self.yw
        return (lam, hr, rms, eta) + self.gauges.read(st)

    def metrics(self, c):
        p, stations, active, d, k = self.p, self.stations, self.active, self.d, self.k
        out = dict(
            kh_paddle=k * d,
            wavelength=self.wavelength,
            biesel_wave_height=self.H_biesel,
            active_zone=[float(stations[active][0]), float(stations[active][-1])],
        )
        out.update(last_finite(c, ("ripple_length", "ripple_height", "bed_change_rms")))
        # wave height at the toe after the ramp (incident plus what the beach reflects)
        t0 = arrival_time(p, self.toe, self.cg)
        H, n = height_at(c, "eta_toe", self.toe, p, self.cg)
        out["wave_height_at_toe"] = H
        out["periods_measured_at_toe"] = n
        out.update(self.gauges.metrics(c, p, self.cg))
        if n:
            d0 = float(orbital_diameter(H, k, d))
            out["orbital_diameter_d0"] = d0
            out["ripple_length_over_d0"] = out["ripple_length"] / d0
            out["wiberg_harris_ratio"] = 0.62
        pred = self.ripple_prediction(c["t"], t0) or {}
        row = pred.get(int(np.argmin(np.abs(stations - self.toe))))
        if row:
            out["near_bed_orbital_diameter_toe"] = row[3]
            out["predicted_ripple_length_toe"] = row[4]
            out["predicted_ripple_height_toe"] = row[5]
            out["predicted_ripple_regime_toe"] = row[6]
            # 8 particles along a ripple (about 1.4 across its height at orbital steepness 0.17)
            out["dx_to_resolve_ripples_toe"] = row[4] / 8.0
            out["ripple_length_over_prediction"] = out["ripple_length"] / row[4] if row[4] > 0 else float("nan")
        return out

    def ripple_prediction(self, t, t0):
        """Wiberg & Harris ripples at each active station from the simulated near-bed orbital
        velocity: amplitude (max - min) / 2 of the water velocity 1-2 dx above the bed over whole
        periods after t0, so d0 = 2 amplitude / omega. None before a whole period has passed
        (the velocity record is in the checkpoint: a restart continues it)."""
        period = self.p["period"]
        t = np.asarray(t, float)
        n_per = int((t[-1] - t0) // period) if len(t) else 0
        if n_per < 1 or len(self.u_near) != len(t):
            return None
        U = np.array(self.u_near)
        win = t >= t[-1] - n_per * period
        rows = []
        for kx in np.nonzero(self.active)[0]:
            u = U[win, kx]
            u = u[np.isfinite(u)]
            if len(u) < 4:
                continue
            amp = 0.5 * float(u.max() - u.min())
            d0x = 2.0 * amp / self.omega
            lam, hgt, regime = wiberg_harris(d0x, self.grain)
            rows.append((float(self.stations[kx]), float(self.bed0[kx]), amp, d0x, lam, hgt, regime))
        self.pred_rows = rows
        return {int(np.argmin(np.abs(self.stations - r[0]))): r for r in rows}

    def finalize(self, out, metrics):
        if not self.rows:
            return
        write_station_rows(os.path.join(out, "bed_profile.csv"), self.stations, self.rows)
        if self.pred_rows:
            write_csv(
                os.path.join(out, "ripple_prediction.csv"),
                (
                    "x",
                    "bed_initial",
                    "near_bed_velocity_amplitude",
                    "orbital_diameter_d0",
                    "wiberg_harris_length",
                    "wiberg_harris_height",
                    "regime",
                ),
                self.pred_rows,
            )
        self.plot(os.path.join(out, "bed_profile.png"))

    def plot(self, path):
        plt = pyplot()
        stations, active, dx = self.stations, self.active, self.dx
        arr = np.array(self.rows)
        rows = self.pred_rows
        fig, axes = plt.subplots(3 if rows else 2, 1, figsize=(9, 7.5 if rows else 5.5), sharex=True)
        a1, a2 = axes[0], axes[1]
        times = [t for t in STILLS if t <= arr[-1, 0] + 1e-9] or [arr[-1, 0]]
        for t in times:
            r = arr[np.argmin(np.abs(arr[:, 0] - t))]
            a1.plot(stations, r[1:], lw=0.9, label=f"t = {r[0]:.1f} s")
            a2.plot(stations, r[1:] - arr[0, 1:], lw=0.9)
        a1.axhline(self.yw, color="tab:blue", lw=0.6, ls="--", label="still water")
        a1.set_ylabel("sand surface (m)")
        a1.legend(fontsize=7, ncol=3)
        a2.axvspan(stations[active][0], stations[active][-1], color="0.93")
        a2.set_ylabel("bed change (m)")
        if rows:
            # what ripples the measured near-bed motion would make, against the particle size
            a3 = axes[2]
            xr = [r[0] for r in rows]
            a3.plot(xr, [100 * r[4] for r in rows], label="Wiberg & Harris ripple length")
            a3.plot(xr, [100 * r[5] for r in rows], label="ripple height")
            a3.axhline(100 * dx, color="k", lw=0.8, ls="--", label="dx")
            a3.axhline(800 * dx, color="k", lw=0.8, ls=":", label="8 dx (resolved length)")
            a3.set_ylabel("cm")
            a3.legend(fontsize=7, ncol=4, loc="upper left")
        axes[-1].set_xlabel("x (m)")
        fig.suptitle(
            f"beach, tau_B = {self.cfg.materials.sand.yield_stress:g} Pa: bed profile over time (grey: active zone)",
            fontsize=10,
        )
        save(fig, path)


def near_bed_velocity(st, stations, bed, dx):
    """Mean horizontal velocity of the water between 1 and 2 spacings above the bed at each
    station (NaN where there is none): the near-bed orbital velocity, outside the one-particle
    layer the bed's no-slip slows."""
    w = (st["kind"] == FLUID) & (st["mat"] == 0)
    x, u = st["x"][w], st["v"][w, 0]
    col = np.rint((x[:, 0] - stations[0]) / dx).astype(int)
    ok = (col >= 0) & (col < len(stations))
    col, x, u = col[ok], x[ok], u[ok]
    z = x[:, 1] - bed[col]
    band = (z >= dx) & (z < 2 * dx)
    n = np.bincount(col[band], minlength=len(stations))
    su = np.bincount(col[band], weights=u[band], minlength=len(stations))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n > 0, su / np.maximum(n, 1), np.nan)
