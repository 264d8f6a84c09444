"""The gauges of a case file (tisph/measure/gauges.py: one class a type), and EurOtop's mean
overtopping beside a discharge gauge's, from the incident wave at the structure's toe."""
import math

import numpy as np

from ...config import ConfigError
from .layout import who
from ...measure import harmonics
from ...measure.gauges import GaugeSet, case_gauges
from ...validation import eurotop
from ...waves.theory import wavenumber


class CaseGauges(GaugeSet):
    def __init__(self, specs, dx, h, g, wall_side, depth_at, band=None):
        """band: (lo, hi) in Hz of an irregular sea's spectrum (paddle.spectrum), else None."""
        super().__init__(case_gauges(specs, dx, h, wall_side), dx, h)
        self.specs, self.g, self.band = specs, g, band
        self.depth = {q["label"]: depth_at(q["x"]) for q in specs if q["type"] == "surface"}

    def metrics(self, c, period, still_level):
        """Per gauge, over t >= its from_time: wave height and harmonics, or an irregular sea's
        Hm0 and Tp (surface), peaks (velocity, pressure, force), mean discharge and EurOtop's
        (discharge)."""
        out = super().metrics(c, period)
        if self.band and period:
            self.spectra(c, period, out)
        for q in self.specs:
            if q["type"] == "discharge" and q["cot_slope"] > 0 and period:
                lab = q["label"]
                H = self.incident(c, q, period, out)
                out[f"{lab}_freeboard"] = q["crest"] - still_level
                if math.isfinite(H) and H > 0:
                    qe, regime = eurotop.mean_discharge(H, period, q["cot_slope"], q["crest"] - still_level, self.g)
                    out[f"{lab}_eurotop_discharge"] = qe
                    out[f"{lab}_eurotop_regime"] = regime
                    out[f"{lab}_eurotop_wave_height"] = H
                    if qe > 0 and f"{lab}_mean_discharge" in out:
                        out[f"{lab}_discharge_over_eurotop"] = out[f"{lab}_mean_discharge"] / qe
        return out

    def spectra(self, c, tp, out):
        """An irregular sea at each surface gauge: Hm0 and the peak period from its spectrum
        (Welch, segments of 16 peak periods over the record from from_time, as the flume's), in
        place of the regular wave's height and harmonics, which mean nothing there."""
        t_end = float(np.asarray(c["t"])[-1])
        for q in self.specs:
            if q["type"] != "surface":
                continue
            lab = q["label"]
            for k in ("wave_height", "waves", "harmonic_1", "harmonic_2", "harmonic_3"):
                out.pop(f"{lab}_{k}", None)
            f, S, n = harmonics.welch(c["t"], c[f"eta_{lab}"], q["from_time"], t_end, 16 * tp)
            hm0, tpk = harmonics.spectral_height_and_peak(f, S, *self.band) if n else (None, None)
            out[f"{lab}_hm0"] = float(hm0) if n else None
            out[f"{lab}_tp"] = float(tpk) if n else None
            out[f"{lab}_spectrum_segments"] = int(n)

    def incident(self, c, q, period, out):
        """The incident wave height at the toe for EurOtop: one gauge's wave height, or with three or
        more the incident first harmonic separated from the reflected one (Mansard & Funke 1980) at
        the wavenumber of the gauges' mean still depth; out gets the reflection coefficient."""
        labs = q["toe_gauges"]
        if len(labs) == 1:
            return out.get(f"{labs[0]}_wave_height", float("nan"))
        omega = 2 * math.pi / period
        g = {p["label"]: p for p in self.specs if p["type"] == "surface"}
        k = wavenumber(omega, float(np.mean([self.depth[lab] for lab in labs])), self.g)
        t0 = max(g[lab]["from_time"] for lab in labs)
        amps = [harmonics.harmonics(c["t"], c[f"eta_{lab}"], omega, t0, float(c["t"][-1]), 1) for lab in labs]
        if any(a is None for a in amps):
            return float("nan")
        ai, ar, kr = harmonics.reflection([g[lab]["x"] for lab in labs], [a[0] for a in amps], k)
        out[f"{q['label']}_reflection_coefficient"] = kr
        return 2 * ai


def check_sites(gauges, lay, errors):
    """Each gauge against the geometry, before anything runs (each a ConfigError in `errors`):
    a velocity or pressure point inside a solid (it would read nothing all run), and a force
    line that is not on a solid's face (within a spacing of it: the force is the pressure on a
    face, read half a smoothing length into the water). A point above the water at the start is
    left alone: run-up or a rising tide may reach it, and its record says when it was wet."""
    dx = lay.dx
    for q in gauges:
        if q["type"] in ("velocity", "pressure"):
            pt = np.array([[q["x"], q["z"]]])
            for s, shape in lay.shapes:
                if s["shape"] != "line" and shape.inside(pt)[0]:
                    depth = float(shape.distance(pt)[0])
                    errors.append(ConfigError(f"{q['name']}.x", q["x"],
                                              f"with z = {q['z']:g} m, a point in the water, outside every solid",
                                              f"it lies {depth:.3g} m inside {who(s)}: move it out of that "
                                              f"solid, into the water beside its face"))
                    break
        elif q["type"] == "force" and lay.shapes:
            (x0, z0), (x1, z1) = q["line"]
            n = max(2, int(math.ceil(math.hypot(x1 - x0, z1 - z0) / dx)) + 1)
            pts = np.column_stack([np.linspace(x0, x1, n), np.linspace(z0, z1, n)])
            far = [(float(shape.distance(pts).max()), s) for s, shape in lay.shapes]
            d, s = min(far, key=lambda e: e[0])
            if d > dx:
                errors.append(ConfigError(f"{q['name']}.line", q["line"], "a line along a solid's face (every point "
                                          f"within dx = {dx:g} m of it)",
                                          f"it runs up to {d:.3g} m off the nearest solid's face, {who(s)}: "
                                          "draw it on that face, corner to corner"))
