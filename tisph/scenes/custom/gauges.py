"""The gauges of a case file (tisph/measure/gauges.py: one class a type), and EurOtop's mean
overtopping beside a discharge gauge's, from the incident wave at the structure's toe."""

import math
import os

import numpy as np

from ...measure import harmonics
from ...measure.gauge_sets import GaugeSet, case_gauges
from ...runner import loop
from ...settings.config import ConfigError
from ...validation import eurotop
from ...waves.theory import wavenumber
from .layout import who


def load_cutoff(c0, height):
    """The load gauges' low-pass (Hz): half the water's lowest acoustic mode, c0 / (4 height) (a
    column of water of this height, closed at the floor and open at the surface). WCSPH's water is
    compressible at c0, and a force or a pressure read from it rings at these modes (a wall under
    standing waves: 11 N/m RMS at 17-25 Hz); at c0 = 10 sqrt(g height) the cutoff is 1.25
    sqrt(g / height), 6 Hz in 0.4 m of water, above a wave's first harmonics."""
    return c0 / (8.0 * height)


class CaseGauges(GaugeSet):
    def __init__(self, specs, dx, h, g, wall_side, depth_at, band=None, cutoff=None):
        """band: (lo, hi) in Hz of an irregular sea's spectrum (paddle.spectrum), else None;
        cutoff: the load gauges' low-pass (load_cutoff)."""
        super().__init__(case_gauges(specs, dx, h, wall_side), dx, h, cutoff)
        for gauge in self.gauges:
            gauge.irregular = band is not None  # a surface gauge's Hm0 and Tp come from spectra
        self.specs, self.g, self.band = specs, g, band
        self.depth = {q["label"]: depth_at(q["x"]) for q in specs if q["type"] == "surface"}

    def plot(self, path, title=""):
        """gauges.png, each array's incident and reflected waves under the title."""
        m = self.last_metrics
        said = [
            f"array {n}: incident H {m[f'{n}_incident_height']:.3g} m, reflected H {m[f'{n}_reflected_height']:.3g} m, "
            f"reflection coefficient {m[f'{n}_reflection_coefficient']:.2f}"
            for n in sorted({q["array"] for q in self.specs if q["array"]})
            if m.get(f"{n}_reflection_coefficient") is not None
        ]
        super().plot(path, "\n".join([title, *said]))

    def metrics(self, c, period, still_level):
        """Per gauge, over t >= its from_time: wave height and harmonics, or an irregular sea's
        Hm0 and Tp (surface), peaks (velocity, pressure, force), mean discharge and EurOtop's
        (discharge)."""
        out = super().metrics(c, period)
        if self.band and period:
            self.spectra(c, period, out)
        for name in sorted({q["array"] for q in self.specs if q["array"]} if period and not self.band else ()):
            split = self.split([q["label"] for q in self.specs if q["array"] == name], period)
            if split is not None:
                ai, ar, kr = split
                out.update(
                    {
                        f"{name}_incident_height": 2 * ai,
                        f"{name}_reflected_height": 2 * ar,
                        f"{name}_reflection_coefficient": kr,
                    }
                )
        for q in self.specs:
            if q["type"] == "discharge" and q["cot_slope"] > 0 and period:
                lab = q["label"]
                H = self.incident(q, period, out)
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
            f, S, n = harmonics.welch(c["t"], c[f"eta_{lab}"], q["from_time"], t_end, 16 * tp)
            hm0, tpk = harmonics.spectral_height_and_peak(f, S, *self.band) if n else (None, None)
            out[f"{lab}_hm0"] = float(hm0) if n else None
            out[f"{lab}_tp"] = float(tpk) if n else None
            out[f"{lab}_spectrum_segments"] = int(n)

    def incident(self, q, period, out):
        """The incident wave height at the toe for EurOtop: one gauge's wave height, or with three or
        more the incident first harmonic separated from the reflected one (split); out gets the
        reflection coefficient."""
        labs = q["toe_gauges"]
        if len(labs) == 1:
            return out.get(f"{labs[0]}_wave_height", float("nan"))
        split = self.split(labs, period)
        if split is None:
            return float("nan")
        out[f"{q['label']}_reflection_coefficient"] = split[2]
        return 2 * split[0]

    def split(self, labs, period):
        """(incident amplitude, reflected amplitude, reflection coefficient) of the first harmonic
        at the surface gauges labs (Mansard & Funke 1980) at the wavenumber of their mean still
        depth, over the whole periods from the latest from_time; None under two periods."""
        c, omega = self.seen, 2 * math.pi / period
        g = {p["label"]: p for p in self.specs if p["type"] == "surface"}
        k = wavenumber(omega, float(np.mean([self.depth[lab] for lab in labs])), self.g)
        t0 = max(g[lab]["from_time"] for lab in labs)
        amps = [harmonics.harmonics(c["t"], c[f"eta_{lab}"], omega, t0, float(c["t"][-1]), 1) for lab in labs]
        if any(a is None for a in amps):
            return None
        return harmonics.reflection([g[lab]["x"] for lab in labs], [a[0] for a in amps], k)


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
                    errors.append(
                        ConfigError(
                            f"{q['name']}.x",
                            q["x"],
                            f"with z = {q['z']:g} m, a point in the water, outside every solid",
                            f"it lies {depth:.3g} m inside {who(s)}: move it out of that "
                            f"solid, into the water beside its face",
                        )
                    )
                    break
        elif q["type"] == "force" and lay.shapes:
            (x0, z0), (x1, z1) = q["line"]
            n = max(2, int(math.ceil(math.hypot(x1 - x0, z1 - z0) / dx)) + 1)
            pts = np.column_stack([np.linspace(x0, x1, n), np.linspace(z0, z1, n)])
            far = [(float(shape.distance(pts).max()), s) for s, shape in lay.shapes]
            d, s = min(far, key=lambda e: e[0])
            if d > dx:
                errors.append(
                    ConfigError(
                        f"{q['name']}.line",
                        q["line"],
                        f"a line along a solid's face (every point within dx = {dx:g} m of it)",
                        f"it runs up to {d:.3g} m off the nearest solid's face, {who(s)}: "
                        "draw it on that face, corner to corner",
                    )
                )


def run_title(cfg, out):
    """The gauges figure's title: the run's title (the case file's name: my_bar.toml, my_bar), else
    the run's folder."""
    return f"{loop.run_title(cfg, os.path.basename(os.path.normpath(out)))}: gauges"


def observers(cfg, cg, sand, period, still):
    """What the case measures and draws: its gauges (cg), and with a sand bed the bed's probes,
    metrics and figures beside them, the bed's coupling as the run's control."""
    parts = dict(
        probe_columns=cg.columns,
        probe=cg.read,
        persist=(cg,),
        metrics=lambda c: cg.metrics(c, period, still),
        finalize=lambda out, m: cg.plot(os.path.join(out, "gauges.png"), run_title(cfg, out)),
    )
    if sand:

        def finalize(out, m):
            cg.plot(os.path.join(out, "gauges.png"), run_title(cfg, out))
            sand.finalize(out)

        parts = dict(
            probe_columns=cg.columns + ("bed_change_rms",),
            probe=lambda st: cg.read(st) + sand.probe(st),
            metrics=lambda c: dict(cg.metrics(c, period, still), **sand.metrics(c)),
            finalize=finalize,
            control=sand.coupler.update,
            control_every=cfg.sediment.update_every,
            persist=(cg, sand.coupler, sand),
            **sand.picture(),
        )
    return parts
