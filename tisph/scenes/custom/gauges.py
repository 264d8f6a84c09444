"""The gauges of a case file: what each reads every probe interval and what summary.json reports.

surface    eta_<label>: the free surface at x (the wave gauge of the flume), zeroed at t = 0
velocity   u_<label>, w_<label>: the water's velocity at (x, z), Shepard-interpolated
pressure   p_<label>: the water's pressure at (x, z), Shepard-interpolated (Pa)
force      F_<label>: the pressure integrated along a wall face, points a spacing apart (N per m)
discharge  V_<label>: the water beyond the vertical section at x (m3 per m); its rate is the
           discharge through the section (the overtopping of a crest, the basin behind it filling)
front      front_<label>: the leading water along a floor at z (the largest x of the water within two
           spacings above it, plus half a spacing: the dam break's surge front)
"""
import math

import numpy as np

from ...particles import FLUID, SPRAY
from ...measure.field import shepard_at, surface_heights
from ...validation import eurotop
from ...measure.records import wave_height
from ...waves.theory import wavenumber


# a point reads the water only where the water fraction sum V W is at least this (DualSPHysics'
# MeasureTool's KClimit): elsewhere it is dry (NaN; nothing in a force)
WET = 0.5


class CaseGauges:
    def __init__(self, gauges, dx, h, g, wall_side, depth_at):
        self.gauges, self.dx, self.h, self.g = gauges, dx, h, g
        self.depth = {q["label"]: depth_at(q["x"]) for q in gauges if q["type"] == "surface"}
        self.surface = [q for q in gauges if q["type"] == "surface"]
        self.points = [q for q in gauges if q["type"] in ("velocity", "pressure")]
        self.force = []
        for q in gauges:
            if q["type"] == "force":
                (x0, z0), (x1, z1) = q["line"]
                n = max(int(math.ceil(math.hypot(x1 - x0, z1 - z0) / dx)), 1)
                s = (np.arange(n) + 0.5) / n
                pts = np.column_stack([x0 + s * (x1 - x0), z0 + s * (z1 - z0)])
                # read half a smoothing length into the water, where the kernel is not cut by the wall
                pts += 0.5 * h * wall_side(pts)
                self.force.append((q, pts, math.hypot(x1 - x0, z1 - z0) / n))
        self.zero = None
        cols = []
        for q in gauges:
            lab = q["label"]
            cols += {"surface": [f"eta_{lab}"], "velocity": [f"u_{lab}", f"w_{lab}"], "pressure": [f"p_{lab}"],
                     "force": [f"F_{lab}"], "discharge": [f"V_{lab}"], "front": [f"front_{lab}"]}[q["type"]]
        self.columns = tuple(cols)

    def read(self, st):
        vals = {}
        if self.surface:
            eta = surface_heights(st, [q["x"] for q in self.surface], self.dx, self.h, floor=-1e9, mat=None)
            if self.zero is None:
                self.zero = list(eta)
            for q, e, z in zip(self.surface, eta, self.zero):
                vals[q["label"]] = [float(e - z)]
        if self.points:
            pts = [[q["x"], q["z"]] for q in self.points]
            v = shepard_at(st, pts, self.h, "v", None, WET)
            p = shepard_at(st, pts, self.h, "p", None, WET)
            for k, q in enumerate(self.points):
                vals[q["label"]] = [float(v[k, 0]), float(v[k, 1])] if q["type"] == "velocity" else [float(p[k])]
        for q, pts, ds in self.force:
            p = shepard_at(st, pts, self.h, "p", None, WET)
            vals[q["label"]] = [float(np.nansum(p) * ds)]
        fl = st["kind"] == FLUID
        for q in self.gauges:
            if q["type"] == "discharge":   # spray removed beyond x went over too: counted where it was parked
                beyond = ((st["kind"] == SPRAY) | fl) & (st["x"][:, 0] > q["x"])
                vals[q["label"]] = [float((st["m"][beyond] / st["rho"][beyond]).sum())]
            elif q["type"] == "front":
                x = st["x"][fl]
                band = x[(x[:, 1] > q["z"]) & (x[:, 1] < q["z"] + 2 * self.dx)]
                vals[q["label"]] = [float(band[:, 0].max()) + 0.5 * self.dx if len(band) else float("nan")]
        out = []
        for q in self.gauges:
            out += vals[q["label"]]
        return tuple(out)

    def metrics(self, c, period, still_level):
        """Per gauge, over t >= its from_time: wave height (surface), peaks (velocity, pressure,
        force), mean discharge and EurOtop's (discharge)."""
        self.seen = c
        t = np.asarray(c["t"])
        out = {}
        heights = {}
        for q in self.gauges:
            lab = q["label"]
            w = t >= q["from_time"]
            if w.sum() < 2:
                continue
            if q["type"] == "surface":
                e = np.asarray(c[f"eta_{lab}"])
                out[f"{lab}_eta_max"] = float(np.nanmax(e[w]))
                out[f"{lab}_eta_min"] = float(np.nanmin(e[w]))
                if period:
                    H, n = wave_height(t, e, q["from_time"], float(t[-1]), period)
                    heights[lab] = H if n else float("nan")
                    out[f"{lab}_wave_height"] = heights[lab]
                    out[f"{lab}_waves"] = int(n)
            elif q["type"] == "velocity":
                sp = np.hypot(c[f"u_{lab}"], c[f"w_{lab}"])[w]
                out[f"{lab}_speed_max"] = float(np.nanmax(sp)) if np.isfinite(sp).any() else None
            elif q["type"] in ("pressure", "force"):
                col = np.asarray(c[f"{'p' if q['type'] == 'pressure' else 'F'}_{lab}"])[w]
                if np.isfinite(col).any():
                    k = int(np.nanargmax(col))
                    out[f"{lab}_max"] = float(col[k])
                    out[f"{lab}_time_of_max"] = float(t[w][k])
                    out[f"{lab}_mean"] = float(np.nanmean(col))
            elif q["type"] == "front":
                out[f"{lab}_end"] = float(np.asarray(c[f"front_{lab}"])[-1])
            else:
                V = np.asarray(c[f"V_{lab}"])[w]
                tw = t[w]
                q_mean = float((V[-1] - V[0]) / (tw[-1] - tw[0]))
                out[f"{lab}_volume_end"] = float(V[-1])
                out[f"{lab}_mean_discharge"] = q_mean
        for q in self.gauges:
            if q["type"] == "discharge" and q["cot_slope"] > 0 and period:
                lab = q["label"]
                H = self.incident(c, q, period, heights, out)
                out[f"{lab}_freeboard"] = q["crest"] - still_level
                if math.isfinite(H) and H > 0:
                    qe, regime = eurotop.mean_discharge(H, period, q["cot_slope"], q["crest"] - still_level, self.g)
                    out[f"{lab}_eurotop_discharge"] = qe
                    out[f"{lab}_eurotop_regime"] = regime
                    out[f"{lab}_eurotop_wave_height"] = H
                    if qe > 0 and f"{lab}_mean_discharge" in out:
                        out[f"{lab}_discharge_over_eurotop"] = out[f"{lab}_mean_discharge"] / qe
        return out

    def incident(self, c, q, period, heights, out):
        """The incident wave height at the toe for EurOtop: one gauge's wave height, or with three or
        more the incident first harmonic separated from the reflected one (Mansard & Funke 1980) at
        the wavenumber of the gauges' mean still depth; out gets the reflection coefficient."""
        labs = q["toe_gauges"]
        if len(labs) == 1:
            return heights.get(labs[0], float("nan"))
        from ...measure import harmonics
        omega = 2 * math.pi / period
        g = {p["label"]: p for p in self.surface}
        k = wavenumber(omega, float(np.mean([self.depth[lab] for lab in labs])), self.g)
        t0 = max(g[lab]["from_time"] for lab in labs)
        amps = [harmonics.harmonics(c["t"], c[f"eta_{lab}"], omega, t0, float(c["t"][-1]), 1) for lab in labs]
        if any(a is None for a in amps):
            return float("nan")
        ai, ar, kr = harmonics.reflection([g[lab]["x"] for lab in labs], [a[0] for a in amps], k)
        out[f"{q['label']}_reflection_coefficient"] = kr
        return 2 * ai

    PANELS = (("surface", "eta", "surface (m)", 1.0), ("velocity", "u", "u (m/s)", 1.0),
              ("pressure", "p", "pressure (kPa)", 1e-3), ("force", "F", "force (N/m)", 1.0),
              ("discharge", "V", "beyond x (m3/m)", 1.0), ("front", "front", "front x (m)", 1.0))

    def plot(self, path):
        """gauges.png: every gauge's record, one panel per kind of gauge."""
        c = getattr(self, "seen", None)
        panels = [p for p in self.PANELS if any(q["type"] == p[0] for q in self.gauges)]
        if not panels or c is None or len(c["t"]) < 2:
            return
        from ...measure.plots import pyplot, save
        plt = pyplot()
        fig, axes = plt.subplots(len(panels), 1, figsize=(7.5, 1.7 * len(panels) + 0.6), sharex=True, squeeze=False)
        for ax, (kind, col, label, scale) in zip(axes[:, 0], panels):
            for q in self.gauges:
                if q["type"] == kind:
                    ax.plot(c["t"], scale * np.asarray(c[f"{col}_{q['label']}"]), lw=0.8, label=q["label"])
            ax.set_ylabel(label, fontsize=8)
            ax.legend(fontsize=7, ncol=4, loc="upper left")
        axes[-1, 0].set_xlabel("t (s)")
        save(fig, path)
