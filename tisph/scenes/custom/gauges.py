"""The gauges of a case file (tisph/measure/gauges.py: one class a type), and EurOtop's mean
overtopping beside a discharge gauge's, from the incident wave at the structure's toe."""
import math

import numpy as np

from ...measure import harmonics
from ...measure.gauges import GaugeSet, case_gauges
from ...validation import eurotop
from ...waves.theory import wavenumber


class CaseGauges(GaugeSet):
    def __init__(self, specs, dx, h, g, wall_side, depth_at):
        super().__init__(case_gauges(specs, dx, h, wall_side), dx, h)
        self.specs, self.g = specs, g
        self.depth = {q["label"]: depth_at(q["x"]) for q in specs if q["type"] == "surface"}

    def metrics(self, c, period, still_level):
        """Per gauge, over t >= its from_time: wave height (surface), peaks (velocity, pressure,
        force), mean discharge and EurOtop's (discharge)."""
        out = super().metrics(c, period)
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
