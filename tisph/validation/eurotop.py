"""Mean wave overtopping of a smooth impermeable slope: EurOtop (2018), the mean-value approach.

q / sqrt(g Hm0^3) = 0.023 / sqrt(tan a) gb xi exp(-(2.7 Rc / (xi Hm0 gb gf gbeta gv))^1.3)   (eq. 5.10)
with the maximum for non-breaking waves
q / sqrt(g Hm0^3) = 0.09 exp(-(1.5 Rc / (Hm0 gf gbeta g*))^1.3)                              (eq. 5.11)
xi = xi_m-1,0 = tan a / sqrt(Hm0 / L_m-1,0), L_m-1,0 = g T_m-1,0^2 / (2 pi); the influence factors
(berm gb, roughness gf, obliquity gbeta, wall gv, g*) are 1 for a smooth plain slope under normal
attack. The formulas are fitted to irregular waves; fed a regular wave's H and T they give the
order of the discharge, not a prediction to a few per cent (their own scatter is a factor of about
two either way at one standard deviation, EurOtop 2018 section 5.3).
"""

import math


def mean_discharge(hm0, period, cot_slope, freeboard, g=9.81, roughness=1.0):
    """(q in m3/s per m, which formula governs: 'breaking' eq. 5.10 or 'non-breaking' eq. 5.11)."""
    tan_a = 1.0 / cot_slope
    L = g * period * period / (2 * math.pi)
    xi = tan_a / math.sqrt(hm0 / L)
    scale = math.sqrt(g * hm0**3)
    rc = max(freeboard, 0.0)
    breaking = 0.023 / math.sqrt(tan_a) * xi * math.exp(-((2.7 * rc / (xi * hm0 * roughness)) ** 1.3))
    top = 0.09 * math.exp(-((1.5 * rc / (hm0 * roughness)) ** 1.3))
    return (breaking * scale, "breaking") if breaking <= top else (top * scale, "non-breaking")
