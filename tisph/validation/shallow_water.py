"""Exact shallow-water solutions of the dam break (1D Riemann problem on a flat, frictionless bed).

Ritter (1892), dry bed: for -c0 t <= x <= 2 c0 t, h = (2 c0 - x/t)^2 / (9 g), c0 = sqrt(g h0).
Stoker (1957), wet bed of depth hd: a rarefaction into a middle state (h_m, u_m = 2 (c0 - c_m)),
c_m = sqrt(g h_m), then a bore moving at s into the still water. Mass across the bore gives
    s = h_m u_m / (h_m - hd) = 2 c_m^2 (c0 - c_m) / (c_m^2 - g hd),
and momentum (the hydraulic-jump relation for a bore into still water) closes the system:
    h_m / hd = (sqrt(1 + 8 s^2 / (g hd)) - 1) / 2.
x is measured from the dam, positive downstream.
"""

import math

import numpy as np

from ..constants import G


def stoker_state(h0, hd, g=G):
    """(h_m, u_m, s): middle depth, middle velocity, bore speed. hd = 0 gives Ritter's limit."""
    c0 = math.sqrt(g * h0)
    if hd <= 0:
        return 0.0, 2 * c0, 2 * c0
    if hd >= h0:
        raise ValueError("downstream depth must be below the upstream depth")
    cd = math.sqrt(g * hd)

    def residual(cm):
        s = 2 * cm * cm * (c0 - cm) / (cm * cm - cd * cd)
        hm = cm * cm / g
        return hm / hd - 0.5 * (math.sqrt(1 + 8 * s * s / (g * hd)) - 1)

    lo, hi = cd * (1 + 1e-12), c0 * (1 - 1e-12)
    flo = residual(lo)
    for _ in range(200):  # bisection: the residual changes sign once on (cd, c0)
        mid = 0.5 * (lo + hi)
        fm = residual(mid)
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
    cm = 0.5 * (lo + hi)
    hm = cm * cm / g
    um = 2 * (c0 - cm)
    s = 2 * cm * cm * (c0 - cm) / (cm * cm - cd * cd)
    return hm, um, s


def rankine_hugoniot_residuals(h0, hd, g=G):
    """Relative mass and momentum imbalance across the Stoker bore (both ~0 for the solution)."""
    hm, um, s = stoker_state(h0, hd, g)
    mass = s * (hm - hd) - hm * um
    mom = s * (hm * um) - (hm * um * um + 0.5 * g * (hm * hm - hd * hd))
    return abs(mass) / (hm * um), abs(mom) / (hm * um * um)


def depth(x, t, h0, hd, g=G):
    """Exact depth h(x, t); x from the dam, t > 0."""
    x = np.asarray(x, float)
    c0 = math.sqrt(g * h0)
    hm, um, s = stoker_state(h0, hd, g)
    h = np.full_like(x, hd)
    h[x <= -c0 * t] = h0
    if hd <= 0:
        fan = (x > -c0 * t) & (x < 2 * c0 * t)
        h[fan] = (2 * c0 - x[fan] / t) ** 2 / (9 * g)
        return h
    cm = math.sqrt(g * hm)
    xa = (um - cm) * t  # tail of the rarefaction
    fan = (x > -c0 * t) & (x <= xa)
    h[fan] = (2 * c0 - x[fan] / t) ** 2 / (9 * g)
    h[(x > xa) & (x < s * t)] = hm
    return h
