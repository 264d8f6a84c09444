"""A result's numerical uncertainty from three spacings: the observed order of convergence, the
Richardson estimate of the zero-spacing value and Roache's grid convergence index (Roache 1994,
J. Fluids Eng. 116:405), by the procedure of Celik et al. (2008, J. Fluids Eng. 130:078001)."""

import math

# metric names that are the largest value of a record: an impact's peak, which need not converge
PEAK_WORDS = ("_max", "peak", "time_of_max")


def gci(f1, f2, f3, r21, r32):
    """Observed order p, the Richardson estimate of the zero-spacing value, and the fine and the
    middle grid's GCI (safety factor 1.25) from f1 (fine), f2, f3 (coarse), the spacings' ratios
    r21 = dx2 / dx1 and r32 = dx3 / dx2 (Celik et al. 2008, eqs. 3-6: p by fixed-point iteration
    where the ratios differ). p is nan where the differences change sign (oscillatory
    convergence) or vanish: then no GCI."""
    e21, e32 = f2 - f1, f3 - f2
    if e21 == 0 or e32 == 0 or e21 * e32 < 0:
        return float("nan"), float("nan"), float("nan"), float("nan")
    p = math.log(abs(e32 / e21)) / math.log(r21)
    for _ in range(100):
        q = math.log((r21**p - 1.0) / (r32**p - 1.0)) if p > 0 else 0.0
        p_new = abs(math.log(abs(e32 / e21)) + q) / math.log(r21)
        if abs(p_new - p) < 1e-10:
            break
        p = p_new
    ext = (r21**p * f1 - f2) / (r21**p - 1.0)
    gci21 = 1.25 * abs(e21 / f1) / (r21**p - 1.0)
    gci32 = 1.25 * abs(e32 / f2) / (r32**p - 1.0)
    return p, ext, gci21, gci32


def verdict(name, f1, f2, f3, r21, r32):
    """One metric's entry: its three values (fine first), the observed order, the Richardson
    estimate and the fine grid's GCI where the three are in the asymptotic range; otherwise
    the reason there is none: the same on the three grids, oscillatory (the changes alternate
    in sign) or not converging yet (the change does not shrink as the spacing does: an observed
    order of zero or less, for any two ratios)."""
    out = {"values": [f1, f2, f3], "order": None, "richardson": None, "gci_fine": None, "reason": ""}
    e21, e32 = f2 - f1, f3 - f2
    if e21 == 0 and e32 == 0:
        out.update(gci_fine=0.0, richardson=f1, reason="the same on the three spacings")
    elif e21 * e32 < 0:
        out["reason"] = "oscillatory: the changes alternate in sign, so no order or GCI"
    elif abs(e32 / e21) <= math.log(r32) / math.log(r21):
        # f = f0 + C dx^p gives e32 / e21 = r21^p (r32^p - 1) / (r21^p - 1), which falls to
        # ln r32 / ln r21 as p falls to 0 (to 1 where the ratios are equal): at or under it, p <= 0
        out["reason"] = (
            "not converging yet: the change does not shrink as the spacing does (no asymptotic range), "
            "so no order or GCI"
        )
    elif f1 == 0:
        out["reason"] = "zero on the finest spacing: no relative GCI"
    else:
        p, ext, g21, _ = gci(f1, f2, f3, r21, r32)
        out.update(order=p, richardson=ext, gci_fine=g21)
    if any(w in name for w in PEAK_WORDS):
        out["note"] = "a peak: an impact's largest value need not converge (its mean usually does)"
    return out
