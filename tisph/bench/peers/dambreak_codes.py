"""Three codes side by side on the dam break: tisph, PySPH 1.0b2 and DualSPHysics 5.0 (CPU), each
from the command line in a fresh process on two threads, back to back, at dp 0.03 to 0.7 s and
dp 0.015 to 0.3 s: particles, steps, wall time, particle-steps/s of the time loop, the front's
RMS error against Martin & Moyce (1952), and each code's settings.

    python -m tisph.bench --speed --peer pysph,dualsphysics [--dualsphysics CLONE]

Each code runs its own recommended settings (PySPH's stock dam_break_2d, DualSPHysics' example
CaseDambreakVal2D, tisph's dam_break scene); the front is read from each one's particles the
same way (pysph_runs.py, dualsphysics.py).
"""

import os

from ...runner import resolve
from ...scenes import dam_break
from ...validation import martin_moyce
from ..common import cache_dir
from . import dualsphysics, pysph_runs

RUNS = ((0.03, 0.7), (0.015, 0.3))


def run_tisph(out, dx, tf):
    s, wall = pysph_runs.run_tisph_dam_break(out, dx, tf)
    num = resolve(dam_break, overrides={"numerics.dx": dx}).numerics
    settings = (
        f"{num.kernel}, h = {s['h'] / dx:.2f} dp, velocity Verlet with CFL {num.cfl:g}, "
        f"c0 {s['c0']:.1f} m/s, "
        f"modules: {', '.join(s['modules'])}"
    )
    return dict(
        particles=s["particles"],
        steps=s["steps"],
        wall_s=wall,
        loop_s=s["wall_time_s"],
        rms=s["metrics"]["front_rms_error"],
        settings=settings,
    )


def run_pysph(py, out, dx, tf):
    p = pysph_runs.run_pysph(py, out, dx, tf)
    rms, _ = martin_moyce.front_rms_error(p["t"], p["front"], 1.0)
    return dict(
        particles=p["particles"],
        steps=p["steps"],
        wall_s=p["wall_time_s"],
        loop_s=p["run_s"],
        rms=rms,
        settings="stock dam_break_2d: WCSPH scheme, Wendland quintic, h = 1.3 dp (its hdx), PEC integrator, "
        "c0 = 10 sqrt(2 g H), alpha 0.1, 2 OpenMP threads"
        + ("" if dx == pysph_runs.DX else "; h and m set for this dp by a subclass"),
    )


def run_dualsphysics(root, out, dx, tf):
    d = dualsphysics.run(root, out, dx, tf)
    rms, _ = martin_moyce.front_rms_error(d["t"], d["front"], 1.0)
    return dict(
        particles=d["particles"],
        steps=d["steps"],
        wall_s=d["wall_s"],
        loop_s=d["loop_s"],
        rms=rms,
        settings=d["settings"],
    )


def compare(out, log, peers, pysph_venv=None, dsph_source=None, runs=RUNS):
    """The Markdown section: every code at every (dp, end time), back to back."""
    cache = cache_dir()
    ready, notes = {}, []
    if "pysph" in peers:
        try:
            ready["PySPH 1.0b2"] = (
                "pysph",
                pysph_runs.ensure_pysph(pysph_venv or os.path.join(cache, "pysph-venv"), log),
            )
        except Exception as e:  # no network, no compiler: the bench goes on without it
            notes.append(f"PySPH not run: {e}")
    if "dualsphysics" in peers:
        try:
            ready["DualSPHysics 5.0 CPU"] = ("dualsphysics", dualsphysics.ensure(cache, dsph_source, log))
        except dualsphysics.NotAvailable as e:
            notes.append(f"DualSPHysics not run: {e}")
    md = [
        "## Three codes on the dam break",
        "",
        "| dp | to t (s) | code | particles | steps | wall s (process) | time loop s | particle-steps/s (loop) | "
        "front RMS vs Martin & Moyce |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    settings = {}
    for dx, tf in runs:
        results = [("tisph", lambda: run_tisph(out, dx, tf))]
        for name, (kind, handle) in ready.items():
            if kind == "pysph":
                results.append((name, lambda h=handle: run_pysph(h, out, dx, tf)))
            else:
                results.append((name, lambda h=handle: run_dualsphysics(h, out, dx, tf)))
        for name, fn in results:
            try:
                r = fn()
            except Exception as e:
                log(f"{name} at dp {dx:g} failed: {e}")
                notes.append(f"{name} at dp {dx:g}: not run ({str(e).splitlines()[0][:200]})")
                continue
            pps = r["particles"] * r["steps"] / r["loop_s"] if r["loop_s"] > 0 else float("nan")
            log(
                f"dp {dx:g} to {tf:g} s, {name}: {r['particles']} particles, {r['steps']} steps, "
                f"{r['wall_s']:.1f} s ({r['loop_s']:.1f} s loop), {pps:.3g} particle-steps/s, front RMS {r['rms']:.3f}"
            )
            md.append(
                f"| {dx:g} | {tf:g} | {name} | {r['particles']} | {r['steps']} | {r['wall_s']:.1f} | "
                f"{r['loop_s']:.1f} | {pps:.3g} | {r['rms']:.3f} |"
            )
            settings[name] = r["settings"]
    md += [""] + [f"- {k}: {v}." for k, v in settings.items()] + [""] + notes + [""]
    return md
