"""A case's gauges together: GaugeSet (their probe columns, one read a probe, their metrics and
gauges.png), WaveGauges (the built-in scenes' wave gauges) and case_gauges (a case file's
[[gauge]] entries as gauges). The gauge types are in gauges.py."""

from __future__ import annotations

import warnings
from collections.abc import Iterable

import numpy as np

from .gauges import GAUGE_TYPES, Gauge, LoadGauge, Site, SurfaceGauge
from .plots import gauge_panels
from .records import arrival_time, crossing_period_and_level, height_at


class GaugeSet:
    """A case's gauges: their columns in order, one read a probe (each type in one batch), their
    metrics, and gauges.png (a panel a gauge); cutoff: the load gauges' low-pass (Hz) or None."""

    def __init__(self, gauges: Iterable[Gauge], dx: float, h: float, cutoff: float | None = None) -> None:
        self.gauges, self.site = list(gauges), Site(dx, h)
        for g in self.gauges:
            if isinstance(g, LoadGauge):
                g.cutoff = cutoff
        self.columns = tuple(c for g in self.gauges for c in g.columns)
        self.seen = None
        self.last_metrics = {}

    def by_type(self):
        """[(type, its gauges)] in GAUGE_TYPES' order, each type once."""
        types = [cls for cls in GAUGE_TYPES.values() if any(type(g) is cls for g in self.gauges)]
        return [(cls, [g for g in self.gauges if type(g) is cls]) for cls in types]

    def read(self, st: dict) -> tuple[float, ...]:
        vals = {}
        for cls, mine in self.by_type():
            vals.update(zip(map(id, mine), cls.read_all(mine, st, self.site)))
        return tuple(x for g in self.gauges for x in vals[id(g)])

    def metrics(self, c: dict, period: float | None) -> dict:
        """Each gauge's metrics over t >= its from_time (none where under two readings)."""
        self.seen = c
        t = np.asarray(c["t"])
        out = self.last_metrics = {}
        for g in self.gauges:
            w = t >= g.from_time
            if w.sum() >= 2:
                out.update(g.metrics(c, t, w, period))
        return out

    def plot(self, path: str, title: str = "") -> None:
        """gauges.png: one panel a gauge (five surface gauges in one panel hid each other), the
        gauges of a type on one vertical scale so their records compare at a glance; the panel
        names the gauge, where it stands and, for a surface gauge, its wave height and harmonics;
        a load gauge's low-passed record over its raw one."""
        shown = [g for cls, mine in self.by_type() for g in mine]
        if shown and self.seen is not None and len(self.seen["t"]) >= 2:
            gauge_panels(shown, self.seen, self.last_metrics, path, title)


class WaveGauges(GaugeSet):
    """The built-in scenes' wave gauges at x (m from the paddle's mean position): surface gauges
    of the water (material 0) from the floor up, less the still-water level, and the wave
    heights, periods and mean levels once the ramped waves have reached each."""

    def __init__(self, xs, dx, h, level, columns=None, dry_from=float("inf")):
        """dry_from: where the bed stands above the still water (a beach's shoreline): a gauge
        there reads no wave height (None in the metrics) and is warned about."""
        self.xs = [float(x) for x in xs]
        self.dry = [x for x in self.xs if x >= dry_from]
        if self.dry:
            warnings.warn(
                f"gauges at x = {', '.join(f'{x:g}' for x in self.dry)} m stand on dry land (the "
                f"still-water shoreline is at x = {dry_from:.3g} m): their wave heights are reported "
                "as null"
            )
        cols = tuple(columns or (f"eta_x{x:.2f}" for x in self.xs))
        super().__init__(
            [
                SurfaceGauge(col, x, floor=0.0, mat=0, level=level, column=col, still_start=True)
                for x, col in zip(self.xs, cols)
            ],
            dx,
            h,
        )

    @property
    def zero(self):  # each gauge's first reading (the lattice's offset under the still water)
        return [g.zero for g in self.gauges if g.zero is not None]

    def metrics(self, c, p, cg):
        """gauges_x and the mean wave height at each over whole periods once the ramped waves
        have reached it at the group velocity cg (at the paddle's depth: on a slope, where waves
        slow, an early bound) and to the end of the run."""
        out = dict(
            gauges_x=list(self.xs),
            gauges_on_dry_land=list(self.dry),
            wave_height_at_gauges=[],
            wave_period_at_gauges=[],
            mean_level_at_gauges=[],
        )
        for x, col in zip(self.xs, self.columns):
            wet = x not in self.dry and len(c["t"])
            T, level = (
                crossing_period_and_level(c["t"], c[col], arrival_time(p, x, cg), float(c["t"][-1]))
                if wet
                else (None, None)
            )
            out["wave_height_at_gauges"].append(height_at(c, col, x, p, cg)[0] if wet else None)
            out["wave_period_at_gauges"].append(T)
            out["mean_level_at_gauges"].append(level)
        return out


def case_gauges(specs, dx, h, side):
    """The gauges of a case file's [[gauge]] tables (checked by tisph/scenes/custom/elements.py);
    side(points): unit vectors from wall points towards the water, for force gauges."""
    return [GAUGE_TYPES[q["type"]].from_spec(q, dx, h, side) for q in specs]
