"""--ripples: the oscillating tunnel over a range of orbital diameters, periods and mobility
numbers, every parameter at its default, through the Dask sweep (tisph.sweep): the ripple length
over d0 and the steepness against Wiberg & Harris (1994)'s orbital ripples (0.62 d0, steepness
0.17; the band 0.5-0.75 d0, 0.10-0.20), and above mobility 240 no ripples (sheet flow, van der A et
al. 2013). The default tunnel (d0 = 0.3 m, T = 2 s) is the case the lee-zone constants were chosen
on; it is run from seeded ripples of 0.3 d0 and 1.5 d0 and at dx / 1.5 too, and two other cases
are run from ripples seeded at 1.5 d0 (SEEDED_CHECKS). Every other case is a check the constants
were not chosen on.

Each case's periodic length holds at least 6.5 predicted ripples, its dx gives the predicted
ripple 18.6 spacings (as in the default tunnel; 5 mm to 2 cm), its water is at least half d0 deep,
its random bed is the tunnel's (RMS 1 % of d0), and it runs 200 periods of bed change (wave periods x
morfac) at morfac 10, or at the lower morfac that keeps the bed turning over no faster in each wave
period than in the default tunnel (tunnel.morfac_limit). Writes OUT/ripples.md, ripples.csv, ripples.png (length
and steepness against d0 with the bands) and growth.png (the length against bed periods).
"""

import json
import math
import os
import sys
import time

import numpy as np

from .. import sweep
from ..io import ensure_dir, write_csv, write_text
from ..ripples import ORBITAL_BAND as BAND
from ..ripples import wiberg_harris
from ..runner import resolve
from ..scenes import tunnel
from .ripple_report import growth, in_band, plot, report

GRAIN = 0.0003  # d50 (m): the tunnel's default
S_GRAIN = 2.65  # quartz
BED_PERIODS = 200  # periods of bed change (wave periods x morfac) per case
SEEDED_BED_PERIODS = 300  # a seeded bed must change its length first, then hold it
MIN_RIPPLES = 6.5  # predicted ripples in the periodic length
CALIBRATION = (0.3, 2.0)
RIPPLE_DX = 18.6  # predicted ripple length over dx in every case (the default tunnel's)
MORFAC = 10.0  # the default tunnel's, where the bed turns over no faster than there
# (d0 m, T s): mobility 20-170 with ripples, and two above 240 (sheet flow)
SWEEP = [
    (0.15, 1.5),
    (0.2, 2.0),
    (0.3, 3.0),
    (0.45, 3.5),
    (0.3, 2.0),
    (0.6, 3.5),
    (0.5, 2.5),
    (0.4, 1.75),
    (0.4, 1.5),
    (0.5, 1.75),
    (0.6, 1.6),
    (0.55, 1.4),
]
# seeded at 1.5 d0 as well: a smaller period (morfac 4.2) and a larger d0 than the calibration's
SEEDED_CHECKS = [(0.4, 1.5), (0.5, 2.5)]


def mobility(d0, T, d50=GRAIN, s=S_GRAIN, g=9.81):
    """psi = (A omega)^2 / ((s - 1) g d50), A = d0 / 2."""
    return (math.pi * d0 / T) ** 2 / ((s - 1.0) * g * d50)


def periodic_length(d0, dx):
    """At least MIN_RIPPLES predicted ripples, a whole number of dx, and at least 0.6 m."""
    lam = wiberg_harris(d0, GRAIN)[0]
    return round(round(max(MIN_RIPPLES * lam, 0.6) / dx) * dx, 6)


def resolved_dx(d0):
    """dx that gives the predicted ripple as many spacings as the default tunnel's (0.186 m at
    1 cm: 18.6), between 5 mm and 2 cm: every length the model takes in dx (the reference and
    outer heights, the saturation length, the seed's smoothing) then scales with the ripple."""
    return min(max(round(wiberg_harris(d0, GRAIN)[0] / RIPPLE_DX, 4), 0.005), 0.02)


def water_depth(d0):
    """The water over the bed: at least 0.15 m and half the orbital diameter (about five predicted
    ripple heights), so that grown ripples do not fill the layer: in 0.15 m of water, ripples of
    d0 = 0.4-0.5 m (8-10 cm high) squeezed the flow over their crests and compressed it (99.9th
    percentile density error 9-15 %, one run unstable)."""
    return round(max(0.15, 0.5 * d0), 3)


def tunnel_bed(d0, T):
    """(morfac, random bed's RMS) of the tunnel at d0, T: the default tunnel's morfac, or less where
    the bed would turn over faster in each wave period than in the default tunnel
    (tunnel.morfac_limit), to a tenth; and its own random bed (tunnel.seed_rms), given as a number
    so a case's inputs say it."""
    cfg = resolve(tunnel, None, {"geometry.orbital_diameter": d0, "geometry.period": T})
    return min(MORFAC, math.floor(tunnel.morfac_limit(cfg) * 10) / 10), tunnel.seed_rms(cfg)


def seeded(base, f, d0, T, morfac):
    """A case started from ripples f d0 long and half Wiberg & Harris's steepness high (0.085 f d0),
    run SEEDED_BED_PERIODS, over sand deep enough for the seed (tunnel: sand_depth - 2 dx)."""
    height = 0.17 * f * d0 * 0.5
    sand = max(0.08, math.ceil((height + 2 * base["numerics.dx"]) * 100) / 100)
    return dict(
        base,
        **{
            "geometry.seed_ripple_length": f * d0,
            "geometry.seed_ripple_height": height,
            "geometry.sand_depth": sand,
            "run.end_time": round(SEEDED_BED_PERIODS * T / morfac, 2),
        },
    )


def cases(quick=False):
    """[(label, kind, overrides)] of the sweep: kind 'calibration', 'check', 'sheet', 'seeded',
    'resolution'."""
    out = []
    for d0, T in SWEEP:
        kind = "calibration" if (d0, T) == CALIBRATION else "sheet" if mobility(d0, T) > 240 else "check"
        dx, (m, rms) = resolved_dx(d0), tunnel_bed(d0, T)
        out.append(
            (
                f"d0 {d0:g} T {T:g}",
                kind,
                {
                    "geometry.orbital_diameter": d0,
                    "geometry.period": T,
                    "geometry.length": periodic_length(d0, dx),
                    "geometry.water_depth": water_depth(d0),
                    "sediment.seed_rms": rms,
                    "sediment.morfac": m,
                    "run.end_time": round(BED_PERIODS * T / m, 2),
                    "numerics.dx": dx,
                },
            )
        )
    d0, T = CALIBRATION
    dx, (_, rms) = resolved_dx(d0), tunnel_bed(d0, T)
    base = {
        "geometry.orbital_diameter": d0,
        "geometry.period": T,
        "geometry.length": periodic_length(d0, dx),
        "geometry.water_depth": water_depth(d0),
        "sediment.seed_rms": rms,
        "sediment.morfac": MORFAC,
        "run.end_time": round(BED_PERIODS * T / MORFAC, 2),
        "numerics.dx": dx,
    }
    for f in (0.3, 1.5):
        out.append((f"seeded {f:g} d0", "seeded", seeded(base, f, d0, T, MORFAC)))
    for d0_, T_ in SEEDED_CHECKS:  # ripples too long split where the throw was not chosen
        case = next(ov for lab, _, ov in out if lab == f"d0 {d0_:g} T {T_:g}")
        out.append(
            (f"seeded 1.5 d0 at d0 {d0_:g} T {T_:g}", "seeded", seeded(case, 1.5, d0_, T_, case["sediment.morfac"]))
        )
    # dx against dx / 1.5 in twice the length (13 predicted ripples, so one ripple is 8 % of the
    # count), both on the gather pass so the two differ only in dx
    twice = dict(base, **{"geometry.length": 2 * base["geometry.length"], "run.pair_once": "off"})
    out.append(("twice the length, dx", "resolution", twice))
    out.append(("twice the length, dx / 1.5", "resolution", dict(twice, **{"numerics.dx": round(dx / 1.5, 6)})))
    if quick:  # exercise every path in seconds
        out = [
            (lab, kind, dict(ov, **{"run.end_time": 0.2, "geometry.length": 0.3, "numerics.dx": 0.015}))
            for lab, kind, ov in out[:1] + out[-1:]
        ]
    return out


def held_bed_periods(t, lam, T, morfac=10.0, d0=None):
    """Bed periods (wave periods x morfac) to the run's end since the ripple count last changed:
    how long the final length has held; with d0, for a bed that ends in the band, since its length
    was last outside the band (a small ripple counted in one sample and not the next moves the
    count between two lengths in the band). 0 without a series."""
    if len(t) < 2:
        return 0.0
    lam = np.where(np.isfinite(lam), lam, -1.0)
    if d0 is not None and BAND[0] <= lam[-1] / d0 <= BAND[1]:
        changed = np.nonzero((lam[:-1] / d0 < BAND[0]) | (lam[:-1] / d0 > BAND[1]))[0]
    else:
        changed = np.nonzero(lam[1:] != lam[:-1])[0]
    since = t[changed[-1] + 1] if len(changed) else t[0]
    return float((t[-1] - since) / T * morfac)


def num(v):
    """A summary's number, NaN for a null (a metric the run could not measure)."""
    return float("nan") if v is None else float(v)


def rows_from(out, plan):
    rows = []
    for (cid, _, ov), (label, kind, _) in plan:
        try:
            with open(os.path.join(out, cid, "summary.json")) as f:
                s = json.load(f)
        except (OSError, ValueError):
            s = {"status": "missing", "metrics": {}}
        m = s.get("metrics", {})
        d0, T = ov["geometry.orbital_diameter"], ov["geometry.period"]
        lam, h = m.get("ripple_length"), m.get("ripple_height")
        lam = float(lam) if lam is not None else float("nan")
        count = int(m.get("ripple_count") or 0)
        steep = (
            (float(h) / lam)
            if (h is not None and count > 0 and lam > 0)
            else float(m.get("bed_change_rms") or 0.0) * 2.83 / ov["geometry.length"]
        )
        rows.append(
            dict(
                label=label,
                kind=kind,
                d0=d0,
                T=T,
                psi=mobility(d0, T),
                dx=ov["numerics.dx"],
                morfac=ov["sediment.morfac"],
                length=ov["geometry.length"],
                lam_d0=lam / d0,
                steepness=steep,
                count=count,
                rho_max=num(s.get("max_density_error")),
                rho_mean=num(s.get("mean_density_error")),
                near_bed=num(m.get("near_bed_velocity_ratio")),
                particles=s.get("particles", 0),
                steps=s.get("steps", 0),
                wall=num(s.get("wall_time_s")),
                status=s.get("status"),
                dir=os.path.join(out, cid),
            )
        )
        t, lam_t = growth(os.path.join(out, cid, "probes.csv"))
        rows[-1]["held"] = held_bed_periods(t, lam_t, T, ov["sediment.morfac"], d0)
        rows[-1]["in_band"] = in_band(rows[-1])
    return rows


def main(a):
    out = os.path.abspath(os.path.join(a.out, "ripples"))
    ensure_dir(out)
    plan_cases = cases(quick=a.quick or a.dry_run)
    keys = sorted({k for _, _, ov in plan_cases for k in ov})
    defaults = {
        "geometry.seed_ripple_length": 0.0,
        "geometry.seed_ripple_height": 0.0,
        "run.pair_once": "auto",
        "geometry.sand_depth": tunnel.SCENE.DEFAULTS["geometry"]["sand_depth"],
    }
    sets = [(k, [ov.get(k, defaults.get(k)) for _, _, ov in plan_cases]) for k in keys]
    argv = ["tunnel", "--zip", "--out", out, "--resume"] + sum(
        [["--set", f"{k}=" + ",".join(repr(v) for v in vals)] for k, vals in sets], []
    )
    if a.scheduler:
        argv += ["--scheduler", a.scheduler]
    t0 = time.perf_counter()
    code = sweep.main(argv)
    wall = time.perf_counter() - t0
    planned = sweep.plan(
        tunnel,
        None,
        sweep.parse_sets([f"{k}=" + ",".join(repr(v) for v in vals) for k, vals in sets]),
        True,
        out,
        {"output.render": False},
    )
    rows = rows_from(out, list(zip(planned, plan_cases)))
    cols = [k for k in rows[0] if k != "dir"]
    write_csv(os.path.join(out, "ripples.csv"), cols, [tuple(r[k] for k in cols) for r in rows])
    try:
        plot(rows, os.path.join(out, "ripples.png"), os.path.join(out, "growth.png"))
    except Exception as e:  # the table stands without the figure
        print(f"warning: no ripple figure: {e}", file=sys.stderr)
    md = report(rows, wall)
    write_text(os.path.join(out, "ripples.md"), md)
    print(md)
    return code
