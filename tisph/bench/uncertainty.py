"""Each validation case's error with its numerical uncertainty: the grid convergence index of its
reported run where it ran three spacings (Celik et al. 2008, measure/gci.py), the standard
error over its seeds where the metric is chaotic (a ripple field, measure/spread.py), or the
reason there is none."""

import math

from ..measure.gci import verdict


def _finite(v):
    return isinstance(v, (int, float)) and math.isfinite(v)


def interval(case, rows):
    """(half-width on the error or None, what it is or why there is none) for a case's rows,
    coarse to fine."""
    if not case.has_reference:
        return None, "no reference value"
    scale = 1.0 / case.reference_value if case.reference_value else 1.0
    last = rows[-1]
    ens = last.get("ensemble")
    if ens and ens.get("stderr") is not None:
        half = abs(ens["stderr"] * scale)
        vals = ", ".join(f"{v:.3g}" for v in ens["values"] if v is not None)
        what = "of the bed" if ens.get("key", "sediment.seed") == "sediment.seed" else "of a perturbed start"
        return half, f"+- {half:.2g}: the standard error over {ens['n']} seeds {what} ({case.metric}: {vals})"
    rungs = [r for r in rows if _finite(r.get("value"))]
    if len(rungs) >= 3:
        f1, f2, f3 = (r["value"] for r in rungs[:-4:-1])
        d1, d2, d3 = (r["dx"] for r in rungs[:-4:-1])
        m = verdict(case.metric, f1, f2, f3, d2 / d1, d3 / d2)
        if m["gci_fine"] is not None and m["order"] is not None:
            half = m["gci_fine"] * abs(f1) * scale
            return half, f"+- {half:.2g}: GCI {m['gci_fine']:.2%} of the value (observed order {m['order']:.2f})"
        return None, f"no GCI over three spacings: {m['reason'].split(':')[0]}"
    if len(rungs) == 2:
        return None, "two spacings: no order to observe (a GCI needs three)"
    return None, "one spacing: no GCI" + (f"; one run: its spread in {case.spread}" if case.spread else "")
