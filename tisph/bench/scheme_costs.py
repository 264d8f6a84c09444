"""Run time against error by scheme: four validation cases (the dam break against Martin &
Moyce, Stoker's wet dam break at alpha 0.4, the piston flume against Biesel, the sloshing tank
against linear theory), each at two or three spacings under each of the numerics schemes below,
so that the default is where a user gets the most accuracy a minute.

    python -m tisph.bench --schemes [--quick] [--jobs N] [--out DIR]

Writes OUT/schemes.md (every run: dx, particles, steps, wall time, error), OUT/schemes.json and
OUT/schemes.png (each case's |error| against wall time, one curve a scheme). The runs go N at
a time (runner/pool.py), so each run's wall time is the time it took beside the others.
"""

import dataclasses
import json
import os
import sys
import time

import numpy as np

from ..io import ensure_dir, write_text
from ..measure.plots import pyplot, save
from .common import table
from .validate import run_one
from .validation_cases import CASES_BY_NAME

# name: the [numerics] keys a run sets over the case's own
SCHEMES = {
    "default (Wendland h = 2.5 dx, dual stepping)": {},
    "default at h = 2 dx": {"numerics.h_factor": 2.0},
    "default, every term every step": {"numerics.time_stepping": "single"},
    "paper000 (cubic h = 1.5 dx, dynamic walls, XSPH)": {"numerics.scheme": "paper000"},
    "paper002 (Wendland h = 1.3 dx, dynamic walls)": {"numerics.scheme": "paper002"},
}
# case: the spacings (coarse to fine); the validation's case, its metric and reference
LADDERS = {
    "Dam break (Martin & Moyce)": (0.06, 0.04, 0.03),
    "Dam break on a wet bed, alpha 0.4 (Stoker)": (0.025, 0.01875, 0.0125),
    "Wave flume, piston (Biesel)": (0.028125, 0.01875),
    "Sloshing, first mode (linear theory)": (0.0225, 0.015),
}


def run_task(case_name, scheme, dx, out, quick):
    """One run (in a worker process): the validation case under the scheme's keys."""
    c = CASES_BY_NAME[case_name]
    c = dataclasses.replace(c, overrides=dict(c.overrides, **SCHEMES[scheme]))
    return run_one(c, dx, os.path.join(out, str(list(SCHEMES).index(scheme))), quick)


def figure(rows, path):
    plt = pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(9, 6.5))
    for ax, name in zip(axes.flat, LADDERS):
        for k, s in enumerate(SCHEMES):
            rr = [
                r
                for r in rows
                if r["case"] == name and r["scheme"] == s and np.isfinite(r["error"] or np.nan) and r["error"] != 0
            ]
            if rr:
                ax.loglog(
                    [r["wall"] for r in rr],
                    [abs(r["error"]) for r in rr],
                    "-o",
                    ms=4,
                    color=f"C{k}",
                    label=s,
                    lw=2.2 if k == 0 else 1.2,
                )
        ax.set_title(f"{name}: {CASES_BY_NAME[name].error}", fontsize=8)
        ax.set_xlabel("wall time (s)", fontsize=8)
        ax.set_ylabel("|error|", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3, which="both")
    axes.flat[0].legend(fontsize=6.5, loc="best")
    fig.suptitle("Run time against error by scheme: each point one spacing, the finer to the right", fontsize=10)
    fig.tight_layout()
    save(fig, path)


def main(a):
    from ..runner.pool import plan, run_all

    out = ensure_dir(os.path.join(a.out, "schemes"))
    log = lambda m: print(m, file=sys.stderr, flush=True)
    tasks = [
        ((c, s, dx), run_task, (c, s, dx, out, a.quick))
        for c, ladder in LADDERS.items()
        for s in SCHEMES
        for dx in ((CASES_BY_NAME[c].quick,) if a.quick else ladder)
    ]
    tasks.sort(key=lambda t: t[0][2])  # the finest (the longest) first
    jobs, threads = plan(getattr(a, "jobs", 0), len(tasks))
    log(f"{len(tasks)} runs, {jobs} at a time on {threads} CPU thread{'s' if threads > 1 else ''} each")
    rows = []

    def done(key, r, e):
        c, s, dx = key
        if e is not None:
            log(f"{c}, {s}, dx {dx:g}: failed: {e}")
            return
        rows.append(dict(r, scheme=s, threads=threads, jobs=jobs))
        log(
            f"{c}, {s}, dx {dx:g}: {r['particles']} particles, {r['steps']} steps, {r['wall']:.1f} s, "
            f"error {r['error']:.4g}"
        )

    t0 = time.perf_counter()
    run_all(tasks, jobs, threads, done)
    rows.sort(key=lambda r: (list(LADDERS).index(r["case"]), list(SCHEMES).index(r["scheme"]), -r["dx"]))
    clean = [
        {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in r.items() if k != "dir"}
        for r in rows
    ]
    write_text(os.path.join(out, "schemes.json"), json.dumps(clean, indent=1) + "\n")
    figure(rows, os.path.join(out, "schemes.png"))
    md = [
        "# Run time against error by scheme",
        "",
        f"{len(tasks)} runs in {(time.perf_counter() - t0) / 60:.1f} minutes, {jobs} at a time on {threads} CPU "
        f"thread{'s' if threads > 1 else ''} each" + (" (--quick: coarse, short runs)" if a.quick else "") + ".",
        "",
        table(
            ("case", "scheme", "dx (m)", "particles", "steps", "wall s", "error", "status"),
            [
                (
                    r["case"],
                    r["scheme"],
                    f"{r['dx']:g}",
                    r["particles"],
                    r["steps"],
                    f"{r['wall']:.1f}",
                    f"{r['error']:.4g}",
                    r["status"],
                )
                for r in rows
            ],
        ),
        "",
        "![run time against error](schemes.png)",
    ]
    write_text(os.path.join(out, "schemes.md"), "\n".join(md) + "\n")
    log(f"wrote {os.path.join(out, 'schemes.md')}")
    return 0
