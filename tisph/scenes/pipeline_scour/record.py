"""What the pipeline scene measures and writes, for both sand models: the drive's control, the
scour depth under the pipe, the transport through the section under it, the bed shear, the bed
profiles (scour_profile.csv/png), the velocity profiles and the streamline stills."""

import os

import numpy as np

from ...constants import KAPPA, G
from ...io import write_csv, write_station_rows
from ...measure.control import HeldCurrent, PIDrive
from ...measure.field import surface_heights
from ...measure.plots import pyplot, save
from ...particles import FLUID
from ...profiles import streamlines_png
from ...sediment.transport import transport_scale


def water_velocity(st):
    """The mean x-velocity of the water (material 0) particles."""
    w = (st["kind"] == FLUID) & (st["mat"] == 0)
    return float(st["v"][w, 0].mean())


class ScourRecord(HeldCurrent):
    """The drive's control (the water's mean velocity held at U), the bed under and around the
    pipe, the transport through the section under it, the bed shear, and the velocity profiles
    of the second half of the run."""

    def __init__(self, cfg, g):
        self.cfg, self.g = cfg, g
        # driving: a body force g_x = u*^2 / h (uniform channel flow) plus feedback on the mean velocity
        self.g0 = g.ustar**2 / g.hw
        self.ctl = PIDrive(0.5, start=self.g0)
        self.stations = np.arange(0.5 * g.dx, g.Lx, g.dx)
        self.under = np.abs(self.stations - g.xc) < 0.5 * g.D
        self.rows, self.bed0 = [], None
        self.offsets = cfg.geometry.profile_offsets
        self.prof = {o: [] for o in self.offsets}

    def law(self, t):
        """The mean velocity held, and the uniform channel's body force, the feedforward."""
        return self.g.U, self.g0

    def probe(self, st):
        g, dx, stations = self.g, self.g.dx, self.stations
        fl = st["kind"] == FLUID
        sedm = fl & (st["mat"] == 1)
        wat = fl & (st["mat"] == 0)
        u_mean = water_velocity(st)
        if g.hs <= 0:
            return float("nan"), float("nan"), float("nan"), u_mean, self.ctl.value
        b = surface_heights(st, stations, dx, g.h, mat=1)
        if self.bed0 is None:
            self.bed0 = b
        self.rows.append((st["t"],) + tuple(b))
        # scour depth: below the undisturbed bed as first measured (the median level, away from the dip)
        depth = float(np.median(self.bed0) - b[self.under].min()) / g.D
        # sediment flux through the section under the pipe: sum of V u_x over a band dx wide
        band = sedm & (np.abs(st["x"][:, 0] - g.xc) < 0.5 * dx)
        q = float((st["m"][band] / st["rho"][band] * st["v"][band, 0]).sum() / dx)
        phi = q / transport_scale(g.d50, g.rs / g.rw)
        # bed shear stress from the log law through the water velocity 1.5 dx above the bed
        tau = 0.0
        xw_, vw_ = st["x"][wat], st["v"][wat]
        col = np.clip(((xw_[:, 0]) / dx).astype(int), 0, len(stations) - 1)
        zrel = xw_[:, 1] - b[col]
        near = (zrel > dx) & (zrel < 2 * dx)
        if near.any():
            z = zrel[near]
            u = np.abs(vw_[near, 0])
            tau = float((g.rw * (KAPPA * u / np.log(z / g.z0)) ** 2).max())
        return depth, phi, tau, u_mean, self.ctl.value

    def on_profile_sample(self, st, t):
        g = self.g
        wat = (st["kind"] == FLUID) & (st["mat"] == 0)
        for o in self.offsets:
            xo = (g.xc + o * g.D) % g.Lx
            m = wat & (np.abs(st["x"][:, 0] - xo) < g.dx)
            self.prof[o].append((st["x"][m, 1], st["v"][m, 0]))

    def metrics(self, c):
        g = self.g
        out = dict(
            friction_velocity=g.ustar,
            shields_parameter=g.ustar**2 / ((g.rs / g.rw - 1) * G * g.d50),
            mean_velocity_end=float(c["u_mean"][-1]),
            body_force_end=float(c["body_force"][-1]),
            pipe_reynolds=g.U * g.D / 1e-6,
        )
        if g.hs > 0:
            d = c["scour_depth_over_D"]
            out["scour_depth_over_D"] = float(d[-1])
            # the scour the flow added to the initial dip: S/D, smoothed over 0.5 s (a particle
            # row is 0.1 D and the bed gauge flickers by about half of that)
            t = c["t"]
            w = max(1, int(round(0.5 / max(t[1] - t[0], 1e-9)))) if len(t) > 1 else 1
            if len(d) < w:  # a run shorter than the window: no smoothing
                w = 1
            ds = np.convolve(d, np.ones(w) / w, mode="valid")
            out["initial_scour_depth_over_D"] = float(d[0])
            out["scour_depth_over_D_smoothed"] = float(ds[-1])
            grown = ds[-1] - d[0]
            k = np.nonzero(ds - d[0] >= 0.5 * grown)[0]
            # time (end of the 0.5 s window) when half the added depth was first reached
            out["time_to_half_depth"] = float(t[k[0] + w - 1]) if grown > 0 and len(k) else float("nan")
            out["max_transport_rate_phi"] = float(np.nanmax(c["transport_rate_phi"]))
            out["max_bed_shear_end"] = float(c["max_bed_shear"][-1])
        return out

    def finalize(self, out, metrics):
        if self.rows:
            write_station_rows(os.path.join(out, "scour_profile.csv"), self.stations, self.rows)
            self.plot_scour(os.path.join(out, "scour_profile.png"))
        if any(self.prof.values()):
            self.velocity_profiles(out)

    def plot_scour(self, path):
        g, plt = self.g, pyplot()
        arr = np.array(self.rows)
        fig, ax = plt.subplots(figsize=(8, 3))
        for t in np.linspace(arr[0, 0], arr[-1, 0], 5):
            r = arr[np.argmin(np.abs(arr[:, 0] - t))]
            ax.plot((self.stations - g.xc) / g.D, (r[1:] - g.hs) / g.D, lw=0.9, label=f"t = {r[0]:.1f} s")
        ax.add_patch(plt.Circle((0, (g.yc - g.hs) / g.D), 0.5, color="0.5"))
        ax.set_aspect("equal")
        ax.set_xlabel("x / D")
        ax.set_ylabel("bed / D")
        ax.legend(fontsize=7)
        save(fig, path)

    def velocity_profiles(self, out):
        g, plt, offsets = self.g, pyplot(), self.offsets
        rows = []
        fig, axes = plt.subplots(1, len(offsets), figsize=(3 * len(offsets), 3.5), sharey=True, squeeze=False)
        for ax, o in zip(axes[0], offsets):
            ys = np.concatenate([p[0] for p in self.prof[o]])
            us = np.concatenate([p[1] for p in self.prof[o]])
            edges = np.arange(0.0, g.ytop + g.dx, g.dx)
            n, _ = np.histogram(ys, edges)
            su, _ = np.histogram(ys, edges, weights=us)
            with np.errstate(invalid="ignore"):
                um = su / n
            yc_ = 0.5 * (edges[1:] + edges[:-1])
            for y, u in zip(yc_, um):
                rows.append((o, y, u))
            ax.plot(um / g.U, (yc_ - (g.hs if g.hs > 0 else 0.0)) / g.D, "o-", ms=2)
            ax.set_title(f"x - x_pipe = {o:g} D", fontsize=9)
            ax.set_xlabel("time-averaged u / U")
        axes[0, 0].set_ylabel("y / D above the bed")
        save(fig, os.path.join(out, "velocity_profiles.png"))
        write_csv(os.path.join(out, "velocity_profiles.csv"), ("x_offset_over_D", "y", "u_mean"), rows)


def streamlines_event(g):
    Lx, ytop, dx, xc, yc, R = g.Lx, g.ytop, g.dx, g.xc, g.yc, g.R

    def cb(st, t):
        d = os.path.join(st["out"], "stills")
        os.makedirs(d, exist_ok=True)
        streamlines_png(
            os.path.join(d, f"streamlines_t{t:.3f}.png"),
            st,
            (0.0, Lx),
            (0.0, ytop),
            dx,
            f"streamlines of the water velocity, t = {t:.2f} s",
            (8, 8 * ytop / Lx + 0.6),
            circle=(xc, yc, R),
        )

    return cb
