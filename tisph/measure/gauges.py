"""Gauges: one class a type, each saying the probes.csv columns it writes, what it reads from the
particles each probe, and the metrics its record gives. A case's gauges are a GaugeSet; the
built-in scenes' wave gauges (WaveGauges) are surface gauges with the wave windows' metrics.

surface    eta_<label>: the free surface at x (the wave gauge of the flume), zeroed at t = 0
velocity   u_<label>, w_<label>: the water's velocity at (x, z), Shepard-interpolated
pressure   p_<label>: the water's pressure at (x, z), Shepard-interpolated (Pa)
force      F_<label>: the pressure integrated along a wall face, points a spacing apart (N per m)
discharge  V_<label>: the water beyond the vertical section at x (m3 per m); its rate is the
           discharge through the section (the overtopping of a crest, the basin behind it filling)
front      front_<label>: the leading water along a floor at z (the largest x of the water within two
           spacings above it, plus half a spacing: the dam break's surge front)

A new type is one subclass here (type, needs, prefixes, read or read_all, metrics, panel) in
GAUGE_TYPES; the [[gauge]] keys it needs are checked in tisph/scenes/custom/elements.py. A case's
gauges together are a GaugeSet (gauge_sets.py).
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from ..particles import FLUID, SPRAY
from .field import lattice_offset, particle_surface, shepard_at, surface_heights
from .harmonics import harmonic_amplitudes
from .records import free_oscillation, low_pass, wave_height

# a point reads the water only where the water fraction sum V W is at least this (DualSPHysics'
# MeasureTool's KClimit): elsewhere it is dry (NaN; nothing in a force)
WET = 0.5


class Gauge:
    """The interface. type: the [[gauge]] type; needs: the [[gauge]] keys it must be given, each
    with what it means; from_spec: one from a checked [[gauge]] table; columns: its probes.csv
    columns; read_all: one pass for every gauge of the type (read together, as one batch);
    metrics: summary.json's entries from its record; panel: gauges.png's (axis label, scale) of its
    first column."""

    type = ""
    needs = {}
    prefixes = ()
    panel = None
    cutoff = None  # a load gauge's low-pass (Hz): GaugeSet sets it from the case's sound speed

    def filtered(self, c: dict):
        """Its first column low-passed at cutoff (a load gauge's), or None."""
        return None

    @classmethod
    def from_spec(cls, q: dict, dx: float, h: float, side) -> Gauge:
        """A gauge from a case file's checked [[gauge]] table q (side: see ForceGauge)."""
        return cls(q["label"], *(q[k] for k in cls.needs), from_time=q["from_time"])

    def __init__(self, label: str, from_time: float = 0.0) -> None:
        self.label, self.from_time = label, float(from_time)

    @property
    def columns(self) -> tuple[str, ...]:
        return tuple(f"{p}_{self.label}" for p in self.prefixes)

    @classmethod
    def read_all(cls, gauges: list[Gauge], st: dict, site: Site) -> list[list[float]]:
        """[values of each gauge] from the particle state st (site: dx, h)."""
        return [g.read(st, site) for g in gauges]

    def read(self, st: dict, site: Site) -> list[float]:
        raise NotImplementedError

    def describe(self, m: dict) -> str:
        """The gauge's panel label in gauges.png: its label, where it stands, and for a surface
        gauge its wave height and first harmonics (from the metrics m)."""
        where = ", ".join(f"{k} = {getattr(self, k):g} m" for k in ("x", "z") if hasattr(self, k))
        text, H = self.label + (f" ({where})" if where else ""), m.get(f"{self.label}_wave_height")
        if H is not None and math.isfinite(H):
            text += f": H = {H:.3g} m"
        h = [v for v in (m.get(f"{self.label}_harmonic_{k}") for k in (1, 2, 3)) if v is not None]
        if h:  # in the panel's unit (kPa for pressure), named in its axis label "... (unit)"
            text += (
                "; harmonics "
                + ", ".join(f"{self.panel[1] * v:.2g}" for v in h)
                + " "
                + self.panel[0][:-1].split("(")[-1]
            )
        return text

    def metrics(self, c: dict, t: np.ndarray, w: np.ndarray, period: float | None) -> dict:
        """summary.json's entries over the window w (t >= from_time) of the record c."""
        return {}


class Site:
    """What every gauge reads by: the spacing dx, the smoothing length h."""

    def __init__(self, dx: float, h: float) -> None:
        self.dx, self.h = dx, h


class SurfaceGauge(Gauge):
    """The free surface at x above the still-water level `level`. The SPH surface reads under the
    water's own, by an offset taken at the first reading. A scene whose water starts still at
    `level` (the flume, the beach) zeroes the gauge there, as a laboratory gauge is zeroed in
    still water (`still_start`). A case file's water may start tilted or moving: its offset is
    taken against the particles' own surface at x (the top particle within half a spacing, plus
    half a spacing), so the record starts at the water's level; a gauge dry at the start takes
    a deep still surface's offset on the lattice (field.lattice_offset). floor and mat: where the
    surface search starts and which material counts as water (None: every fluid)."""

    type = "surface"
    needs = {"x": "a number (m): a surface gauge's position"}
    prefixes = ("eta",)
    panel = ("surface (m)", 1.0)
    irregular = False  # an irregular sea (a case's paddle.spectrum): its spectrum's metrics instead

    def __init__(self, label, x, from_time=0.0, floor=-1e9, mat=None, level=0.0, column=None, still_start=False):
        super().__init__(label, from_time)
        self.still_start = still_start
        self.x, self.floor, self.mat, self.level = float(x), floor, mat, level
        self.column = column
        self.zero = None

    @property
    def columns(self):
        return (self.column,) if self.column else super().columns

    @classmethod
    def read_all(cls, gauges, st, site):
        out = []  # one surface search for each run of gauges alike in floor and material
        for (floor, mat), run in itertools.groupby(gauges, key=lambda g: (g.floor, g.mat)):
            run = list(run)
            for g, z in zip(run, surface_heights(st, [g.x for g in run], site.dx, site.h, floor=floor, mat=mat)):
                if z <= floor:  # no water over the gauge (dry land, a drained basin): no reading
                    out.append([float("nan")])
                    continue
                if g.zero is None and g.still_start:
                    g.zero = float(z) - g.level
                elif g.zero is None:
                    top = particle_surface(st, g.x, site.dx, mat)
                    g.zero = float(z) - top if top is not None else lattice_offset(site.dx, site.h)
                out.append([float(z) - g.level - g.zero])
        return out

    def metrics(self, c, t, w, period):
        e = np.asarray(c[self.columns[0]], float)
        wet = e[w][np.isfinite(e[w])]  # a dry gauge's readings are NaN
        out = {
            f"{self.label}_eta_max": float(wet.max()) if wet.size else float("nan"),
            f"{self.label}_eta_min": float(wet.min()) if wet.size else float("nan"),
        }
        if self.irregular:  # its spectrum's Hm0 and Tp instead (CaseGauges.spectra)
            return out
        if period:
            H, n = wave_height(t, e, self.from_time, float(t[-1]), period)
            out[f"{self.label}_wave_height"] = H if n else float("nan")
            out[f"{self.label}_waves"] = int(n)
            out.update(harmonic_amplitudes(self.label, t, e, period, self.from_time))
        else:  # no wave maker: the water's own oscillation (sloshing, a seiche)
            T, loss, se, n = free_oscillation(np.asarray(t)[w], e[w])
            if n:
                out.update(
                    {
                        f"{self.label}_period": T,
                        f"{self.label}_loss_per_period": loss,
                        f"{self.label}_loss_stderr": se,
                        f"{self.label}_cycles": n,
                    }
                )
        return out


class _PointGauge(Gauge):
    """A Shepard-interpolated field of the water at (x, z); NaN where the point is dry."""

    field = ""

    def __init__(self, label, x, z, from_time=0.0):
        super().__init__(label, from_time)
        self.x, self.z = float(x), float(z)

    @classmethod
    def read_all(cls, gauges, st, site):
        vals = shepard_at(st, [[g.x, g.z] for g in gauges], site.h, cls.field, None, WET)
        return [g.values(v) for g, v in zip(gauges, vals)]


class VelocityGauge(_PointGauge):
    type = "velocity"
    needs = {"x": "a number (m): a velocity gauge's position", "z": "a number (m): a velocity gauge's height"}
    prefixes = ("u", "w")
    panel = ("u (m/s)", 1.0)
    field = "v"

    @staticmethod
    def values(v):
        return [float(v[0]), float(v[1])]

    def metrics(self, c, t, w, period):
        sp = np.hypot(*(np.asarray(c[col]) for col in self.columns))[w]
        return {f"{self.label}_speed_max": float(np.nanmax(sp)) if np.isfinite(sp).any() else None}


def _peaks(label, col, t, w):
    """The largest value, when, and the mean over the window; null where the record has none (a
    point that stayed dry): the keys are there, and the run's warning names them."""
    col = np.asarray(col)[w]
    if not np.isfinite(col).any():
        return {f"{label}_{k}": None for k in ("max", "time_of_max", "mean")}
    k = int(np.nanargmax(col))
    return {
        f"{label}_max": float(col[k]),
        f"{label}_time_of_max": float(t[w][k]),
        f"{label}_mean": float(np.nanmean(col)),
    }


def _load_metrics(g, col, t, w, period):
    """A load's peaks, with a wave maker its harmonics; with a cutoff, the extremes of the record
    low-passed there (records.low_pass: WCSPH's water rings at its acoustic modes, which a raw peak
    carries) 1/cutoff from its ends, where a zero-phase filter is less sure. Raw peaks stay."""
    label = g.label
    out = _peaks(label, col, t, w)
    if period:
        out.update(harmonic_amplitudes(label, t, col, period, g.from_time))
    if g.cutoff:
        tw, y = t[w], low_pass(t[w], g.as_load(np.asarray(col)[w]), g.cutoff)
        inner = (tw - tw[0] > 1.0 / g.cutoff) & (tw[-1] - tw > 1.0 / g.cutoff) & (y is not None)
        k = int(np.argmax(np.where(inner, y, -np.inf))) if inner.any() else None
        out.update(
            {
                f"{label}_filtered_max": None if k is None else float(y[k]),
                f"{label}_filtered_time_of_max": None if k is None else float(tw[k]),
                f"{label}_filtered_min": None if k is None else float(y[inner].min()),
                f"{label}_filter_hz": float(g.cutoff),
            }
        )
    return out


class LoadGauge(Gauge):
    """A pressure or a force: its record low-passed for gauges.png and the filtered extremes."""

    def filtered(self, c):
        return low_pass(c["t"], self.as_load(np.asarray(c[self.columns[0]])), self.cutoff) if self.cutoff else None

    @staticmethod
    def as_load(col):
        """The record the filter takes: a point dry at times (no water in its kernel: NaN) reads the
        atmosphere's gauge pressure, 0 Pa, there, as a gauge above the water does; a record dry
        throughout stays NaN and gives nulls."""
        col = np.asarray(col, float)
        return np.where(np.isfinite(col), col, 0.0) if np.isfinite(col).any() else col

    def metrics(self, c, t, w, period):
        return _load_metrics(self, c[self.columns[0]], t, w, period)


class PressureGauge(_PointGauge, LoadGauge):
    type = "pressure"
    needs = {"x": "a number (m): a pressure gauge's position", "z": "a number (m): a pressure gauge's height"}
    prefixes = ("p",)
    panel = ("pressure (kPa)", 1e-3)
    field = "p"

    @staticmethod
    def values(p):
        return [float(p)]


class ForceGauge(LoadGauge):
    """The pressure integrated along a wall face: points a spacing apart, read half a smoothing
    length into the water (towards `side`, unit vectors), where the kernel is not cut by the wall."""

    type = "force"
    needs = {"line": "two points [[x0, z0], [x1, z1]] along the wall face"}
    prefixes = ("F",)
    panel = ("force (N/m)", 1.0)

    @classmethod
    def from_spec(cls, q, dx, h, side):
        return cls(q["label"], q["line"], dx, h, side, q["from_time"])

    def __init__(self, label, line, dx, h, side, from_time=0.0):
        super().__init__(label, from_time)
        (x0, z0), (x1, z1) = line
        n = max(int(math.ceil(math.hypot(x1 - x0, z1 - z0) / dx)), 1)
        s = (np.arange(n) + 0.5) / n
        pts = np.column_stack([x0 + s * (x1 - x0), z0 + s * (z1 - z0)])
        self.points = pts + 0.5 * h * side(pts)
        self.ds = math.hypot(x1 - x0, z1 - z0) / n

    def read(self, st, site):
        p = shepard_at(st, self.points, site.h, "p", None, WET)
        return [float(np.nansum(p) * self.ds)]


class DischargeGauge(Gauge):
    """The water beyond the vertical section at x; spray removed beyond x went over too, counted
    where it was parked."""

    type = "discharge"
    needs = {"x": "a number (m): a discharge gauge's position"}
    prefixes = ("V",)
    panel = ("beyond x (m3/m)", 1.0)

    def __init__(self, label, x, from_time=0.0):
        super().__init__(label, from_time)
        self.x = float(x)

    def read(self, st, site):
        beyond = ((st["kind"] == SPRAY) | (st["kind"] == FLUID)) & (st["x"][:, 0] > self.x)
        return [float((st["m"][beyond] / st["rho"][beyond]).sum())]

    def metrics(self, c, t, w, period):
        V, tw = np.asarray(c[self.columns[0]])[w], t[w]
        return {
            f"{self.label}_volume_end": float(V[-1]),
            f"{self.label}_mean_discharge": float((V[-1] - V[0]) / (tw[-1] - tw[0])),
        }


class FrontGauge(Gauge):
    """The leading water along the floor at z: the largest x of the water within two spacings
    above it, plus half a spacing."""

    type = "front"
    needs = {"z": "a number (m): the floor level a front gauge follows the water along"}
    prefixes = ("front",)
    panel = ("front x (m)", 1.0)

    def __init__(self, label, z, from_time=0.0):
        super().__init__(label, from_time)
        self.z = float(z)

    def read(self, st, site):
        x = st["x"][st["kind"] == FLUID]
        band = x[(x[:, 1] > self.z) & (x[:, 1] < self.z + 2 * site.dx)]
        return [float(band[:, 0].max()) + 0.5 * site.dx if len(band) else float("nan")]

    def metrics(self, c, t, w, period):
        return {f"{self.label}_end": float(np.asarray(c[self.columns[0]])[-1])}


GAUGE_TYPES = {
    cls.type: cls for cls in (SurfaceGauge, VelocityGauge, PressureGauge, ForceGauge, DischargeGauge, FrontGauge)
}
