"""Wave gauges: the free surface at fixed x each probe, and the heights, periods and mean levels
their records give."""
import warnings

from .field import surface_heights
from .records import arrival_time, crossing_period_and_level, height_at


class Gauges:
    """Wave gauges at x (m from the paddle's mean position): the free surface minus the still-water
    level, zeroed at the first reading (the still water of t = 0), as a laboratory gauge is: the
    SPH surface of a particle lattice reads about dx/2 under the water's mass level."""

    def __init__(self, xs, dx, h, level, columns=None, dry_from=float("inf")):
        """dry_from: where the bed stands above the still water (a beach's shoreline): a gauge
        there reads no wave height (None in the metrics) and is warned about."""
        self.xs = [float(x) for x in xs]
        self.dry = [x for x in self.xs if x >= dry_from]
        if self.dry:
            warnings.warn(f"gauges at x = {', '.join(f'{x:g}' for x in self.dry)} m stand on dry land (the "
                          f"still-water shoreline is at x = {dry_from:.3g} m): their wave heights are reported "
                          "as null")
        self.dx, self.h, self.level = dx, h, level
        self.columns = tuple(columns or (f"eta_x{x:.2f}" for x in self.xs))
        self.zero = []

    def read(self, st):
        eta = [float(z) - self.level for z in surface_heights(st, self.xs, self.dx, self.h)]
        if not self.zero:
            self.zero = list(eta)
        return tuple(e - z for e, z in zip(eta, self.zero))

    def metrics(self, c, p, cg):
        """gauges_x and the mean wave height at each over whole periods once the ramped waves
        have reached it at the group velocity cg (at the paddle's depth: on a slope, where waves
        slow, an early bound) and to the end of the run."""
        out = dict(gauges_x=list(self.xs), gauges_on_dry_land=list(self.dry),
                   wave_height_at_gauges=[], wave_period_at_gauges=[], mean_level_at_gauges=[])
        for x, col in zip(self.xs, self.columns):
            wet = x not in self.dry and len(c["t"])
            T, level = (crossing_period_and_level(c["t"], c[col], arrival_time(p, x, cg), float(c["t"][-1]))
                        if wet else (None, None))
            out["wave_height_at_gauges"].append(height_at(c, col, x, p, cg)[0] if wet else None)
            out["wave_period_at_gauges"].append(T)
            out["mean_level_at_gauges"].append(level)
        return out
