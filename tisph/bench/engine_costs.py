"""What the engine costs beside the ladder's runs (`python -m tisph.bench` without
--no-scaling): particle-steps/s and memory against size (the hydrostatic tank), what compiling
only the physics a scene uses saves (the dam break with unused terms at zero strength), and
Taichi's kernel profile of a dam-break step."""

import dataclasses
import math
import os
import subprocess
import sys
import time

from ..io import write_csv
from ..runner import Log, build_case, resolve
from ..scenes import dam_break
from .common import ROOT, table, this_tree_env
from .speed import measure


# ---------------------------------------------------------------------------- scaling
def scaling(sizes, steps=100):
    """Particle-steps/s and memory of the hydrostatic tank at about the given particle counts,
    each in a fresh process (tisph/bench/speed.py's measurement). The RSS cost of a particle is the
    slope of peak RSS against particle count between consecutive sizes (the Taichi runtime's own
    footprint cancels)."""
    rows = []
    for n in sizes:
        side = math.sqrt(n) * 0.01
        m = measure(
            ROOT,
            "tank",
            {"numerics.dx": 0.01, "geometry.width": side, "geometry.depth": side, "geometry.tank_height": side * 1.05},
            steps,
        )
        row = dict(
            particles=m["particles"],
            steps=steps,
            seconds=round(m["seconds"], 3),
            particle_steps_per_s=round(m["pps"]),
            field_bytes_per_particle=round(m["field_bytes"], 1),
            peak_rss_mb=round(m["peak_rss_mb"], 1),
        )
        if rows:
            p = rows[-1]
            row["rss_bytes_per_particle"] = round(
                (row["peak_rss_mb"] - p["peak_rss_mb"]) * 2**20 / (row["particles"] - p["particles"]), 1
            )
        else:
            row["rss_bytes_per_particle"] = float("nan")
        rows.append(row)
    return rows


def specialisation(quick, steps=None):
    """The dam break as shipped against the same case compiled with the rheology, laminar
    viscosity, XSPH and no-slip terms switched on at zero strength."""
    from ..engine.solver import Solver

    cfg = resolve(dam_break, overrides={"numerics.dx": 0.03, "output.quiet": True})
    case = build_case(dam_break, cfg, Log(os.devnull, True))
    out = {}
    steps = steps or (300 if quick else 1500)
    for label, phys in (
        ("as shipped", case.physics),
        (
            "rheology + laminar + XSPH + no-slip + SPS + drag + DEM at zero strength",
            dataclasses.replace(
                case.physics,
                rheology=True,
                laminar_viscosity=True,
                xsph=True,
                noslip=True,
                sps=True,
                drag=True,
                dem=True,
            ),
        ),
    ):
        mats = [dict(m, viscosity=0.0) for m in case.materials]
        s = Solver(phys, case.particles, mats, case.domain, dict(case.params, xsph=0.0))
        s.prime()
        for _ in range(20):
            s.step()
        t0 = time.perf_counter()
        for _ in range(steps):
            s.step()
        s.dt
        out[label] = s.n * steps / (time.perf_counter() - t0)
    return out


PROFILE_SNIPPET = r"""
import os, sys, io, contextlib
os.environ["ENABLE_TAICHI_HEADER_PRINT"] = "0"
import taichi as ti
ti.init(arch=ti.cpu, kernel_profiler=True, default_fp=ti.f32, log_level=ti.WARN)
from tisph.runner import build_case, Log, resolve
from tisph.scenes import dam_break
from tisph.engine.solver import Solver
cfg = resolve(dam_break, overrides={"numerics.dx": 0.03, "output.quiet": True})
case = build_case(dam_break, cfg, Log(os.devnull, True))
s = Solver(case.physics, case.particles, case.materials, case.domain, case.params)
s.prime()
for _ in range(50):
    s.step()
ti.profiler.clear_kernel_profiler_info()
for _ in range(500):
    s.step()
s.dt
buf = io.StringIO()
with contextlib.redirect_stdout(buf):
    ti.profiler.print_kernel_profiler_info("count")
print(buf.getvalue())
"""


def kernel_profile():
    env = this_tree_env()
    try:
        r = subprocess.run(
            [sys.executable, "-c", PROFILE_SNIPPET], capture_output=True, text=True, env=env, timeout=600
        )
        return (r.stdout or r.stderr).strip()
    except Exception as e:  # the profile is informative; the bench goes on without it
        return f"(kernel profile failed: {e})"


def engine_sections(a, log):
    """Scaling, specialisation and the kernel profile, as markdown lines."""
    sizes = (2e3,) if a.dry_run else (1e4, 4e4) if a.quick else (1e4, 4e4, 1.6e5, 6.4e5)
    sc = scaling([int(n) for n in sizes], steps=5 if a.dry_run else 50 if a.quick else 100)
    for r in sc:
        log(f"scaling: {r}")
    md = [
        "## Scaling (hydrostatic tank, dx 0.01, fixed steps)",
        "",
        table(
            (
                "particles",
                "steps",
                "s",
                "particle-steps/s",
                "field bytes/particle",
                "peak RSS MB",
                "RSS bytes/particle (slope)",
            ),
            [
                (
                    r["particles"],
                    r["steps"],
                    r["seconds"],
                    f"{r['particle_steps_per_s']:.3g}",
                    r["field_bytes_per_particle"],
                    r["peak_rss_mb"],
                    r["rss_bytes_per_particle"],
                )
                for r in sc
            ],
        ),
        "",
    ]
    write_csv(os.path.join(a.out, "scaling.csv"), tuple(sc[0]), [tuple(r.values()) for r in sc])
    sp = specialisation(a.quick, 20 if a.dry_run else None)
    (k0, v0), (k1, v1) = sp.items()
    log(f"specialisation: {sp}")
    md += [
        "## Specialisation (dam break, dx 0.03)",
        "",
        table(
            ("build", "particle-steps/s", "ratio"),
            [(k0, f"{v0:.3g}", "1"), (k1, f"{v1:.3g}", f"{v0 / v1:.2f}x slower")],
        ),
        "",
        "Zero strength: no viscosity, XSPH epsilon 0, drag coefficient 0, no material with DEM "
        "contacts; the terms are compiled and evaluated, their effect is nil.",
        "",
    ]
    prof = "(skipped in a dry run)" if a.dry_run else kernel_profile()
    md += [
        "## Kernel profile (dam break dx 0.03, 500 steps, Taichi kernel profiler)",
        "",
        "```",
        prof,
        "```",
        "",
        "One time step is one fused kernel (`_step`); the profiler lists its parallel loops: "
        "kernel_1 drift and cell keys, kernel_2 the serial prefix sum, kernel_3 the scatter, kernel_4 "
        "the per-cell sort and gather, kernel_5 the force pass, kernel_6/7 the time-step reduction.",
        "",
    ]
    return md
