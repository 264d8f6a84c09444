"""python -m tisph.bench --convergence [--quick] [--only breakwater|seawall]

An example case's result at three resolutions with the default numerics, its observed order of
convergence and Roache's grid convergence index (Roache 1994, J. Fluids Eng. 116:405; the
procedure of Celik et al. 2008, J. Fluids Eng. 130:078001): the breakwater's mean overtopping
discharge at about 4, 6 and 9 spacings over the incident wave height, and the seawall's peak
force. Writes OUT/convergence/convergence.md and convergence.csv.
"""

import math
import os
import time

from ..io import ensure_dir, write_csv, write_text
from ..measure.gci import gci
from .common import ROOT, table

# (case file, {metric: what it is}, dx coarse to fine: refinement ratios of about 1.5)
CASES = (
    (
        "breakwater",
        {
            "overtopping_mean_discharge": "mean overtopping discharge q (m3/s per m)",
            "overtopping_discharge_over_eurotop": "q over EurOtop's for the run's own freeboard and "
            "incident wave (the lattice's water level moves with dx)",
        },
        (0.015, 0.01, 0.0067),
    ),
    (
        "seawall",
        {
            "wall_force_max": "peak force on the wall (N/m)",
            "wall_force_mean": "mean force on the wall over the run (N/m)",
        },
        (0.02, 0.0133, 0.0089),
    ),
)


def report(name, metrics, dxs, vals, runs):
    """The case's section: its runs' table, and each metric's observed order and GCI (or why none)."""
    r21, r32 = dxs[1] / dxs[2], dxs[0] / dxs[1]
    md = [
        f"## {name}",
        "",
        table(
            ("dx (m)", "particles", "steps", "wall s")
            + tuple(metrics)
            + ("largest density error", "99.9th percentile"),
            [
                (f"{x[0]:g}", x[1], x[2], x[3])
                + tuple(f"{vals[m][k]:.4g}" for m in metrics)
                + (f"{x[4]:.1%}", f"{x[5]:.1%}")
                for k, x in enumerate(runs)
            ],
        ),
        "",
    ]
    for m, what in metrics.items():
        f3, f2, f1 = vals[m]
        p, ext, g21, g32 = gci(f1, f2, f3, r21, r32)
        md += [
            f"{what}: refinement ratios {r21:.2f} and {r32:.2f}; the two finest differ by "
            f"{abs(f1 / f2 - 1):.1%}; "
            + (
                f"observed order {p:.2f}, Richardson's estimate {ext:.4g}, GCI {g21:.1%} on the finest grid "
                f"and {g32:.1%} on the middle one (GCI32 / (r21^p GCI21) = {g32 / (g21 * r21**p):.2f}, 1 in "
                "the asymptotic range)."
                if math.isfinite(p)
                else "the differences change sign (or vanish): no observed order, no GCI (Celik et al.)."
            ),
            "",
        ]
    return md


def main(a):
    import tisph

    out = ensure_dir(os.path.join(a.out, "convergence"))
    rows, md = [], ["# Convergence of the example cases", ""]
    for name, metrics, dxs in CASES:
        if a.only and not any(w.lower() in name for w in a.only):
            continue
        if a.quick:
            dxs = tuple(3 * d for d in dxs)
        vals = {m: [] for m in metrics}
        runs = []
        for dx in dxs:
            case = tisph.Case.from_toml(os.path.join(ROOT, "scenes", f"{name}.toml"))
            case.set("numerics.dx", dx)
            if a.quick:
                case.set("run.end_time", 2.0)
            t0 = time.time()
            r = tisph.run(case, out=os.path.join(out, f"{name}_dx{dx:g}"), render=False, progress=False)
            wall = time.time() - t0
            s = r.summary
            for m in metrics:
                v = s["metrics"].get(m)
                vals[m].append(float("nan") if v is None else float(v))
            runs.append(
                (
                    dx,
                    s["particles"],
                    s["steps"],
                    round(wall, 1),
                    s["max_density_error"],
                    s["density_error_p999"],
                    s["status"],
                )
            )
            rows += [(name, m, dx, vals[m][-1]) + runs[-1][1:] for m in metrics]
            print(
                f"{name} dx {dx:g}: {s['particles']} particles, {s['steps']} steps, {wall:.0f} s, "
                + ", ".join(f"{m} = {vals[m][-1]:.4g}" for m in metrics),
                flush=True,
            )
        md += report(name, metrics, dxs, vals, runs)
    write_csv(
        os.path.join(out, "convergence.csv"),
        (
            "case",
            "metric",
            "dx",
            "value",
            "particles",
            "steps",
            "wall_s",
            "max_density_error",
            "density_error_p999",
            "status",
        ),
        rows,
    )
    write_text(os.path.join(out, "convergence.md"), "\n".join(md) + "\n")
    print("\n".join(md))
    return 0
