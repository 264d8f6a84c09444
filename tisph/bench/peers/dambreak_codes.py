"""Three codes side by side on the dam break: tisph, PySPH 1.0b2 and DualSPHysics 5.0 (CPU), each
from the command line in a fresh process on two threads, back to back, at dp 0.03 to 0.7 s and
dp 0.015 to 0.3 s: particles, steps, wall time, particle-steps/s of the time loop, the front's
RMS error against Martin & Moyce (1952), and each code's settings. With --peer-ladder, every code
at dp 0.06 to 0.015, all to 0.7 s: each code's error against its wall time (a figure) and how
long tisph takes to reach each peer run's error.

    python -m tisph.bench --speed --peer pysph,dualsphysics [--dualsphysics CLONE] [--peer-ladder]

Each code runs its own recommended settings (PySPH's stock dam_break_2d, DualSPHysics' example
CaseDambreakVal2D, tisph's dam_break scene); the front is read from each one's particles the
same way (pysph_runs.py, dualsphysics.py).
"""

import os

import numpy as np

from ...io import read_csv
from ...measure.plots import pyplot, save
from ...runner import resolve
from ...scenes import dam_break
from ...validation import martin_moyce
from ..common import cache_dir
from . import dualsphysics, pysph_runs

RUNS = ((0.03, 0.7), (0.015, 0.3))
LADDER = tuple((dp, 0.7) for dp in (0.06, 0.04, 0.03, 0.02, 0.015))
# the converged front is compared while it is at most this far along the 4 m tank (a = 1 m), half
# a column before the far wall, where the front stops being a surge over a dry floor
CONVERGED_UP_TO = 3.5


def run_tisph(out, dx, tf):
    s, wall, d = pysph_runs.run_tisph_dam_break(out, dx, tf)
    num = resolve(dam_break, overrides={"numerics.dx": dx}).numerics
    settings = (
        f"{num.kernel}, h = {s['h'] / dx:.2f} dp, velocity Verlet with CFL {num.cfl:g}, "
        f"c0 {s['c0']:.1f} m/s, "
        f"modules: {', '.join(s['modules'])}"
    )
    _, probes = read_csv(os.path.join(d, "probes.csv"))
    return dict(
        particles=s["particles"],
        steps=s["steps"],
        wall_s=wall,
        loop_s=s["wall_time_s"],
        rms=s["metrics"]["front_rms_error"],
        t=np.array(probes["t"]),
        front=np.array(probes["front_x"]),
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
        t=p["t"],
        front=p["front"],
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
        t=d["t"],
        front=d["front"],
        settings=d["settings"],
    )


def _ready(peers, pysph_venv, dsph_source, notes, log):
    """The peers that can run here: {name: (kind, handle)}; why the others cannot, in notes."""
    cache = cache_dir()
    ready = {}
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
    return ready


def _measure(out, log, ready, runs, notes, settings):
    """Every code at every (dp, end time), back to back: one row a run."""
    rows = []
    for dx, tf in runs:
        results = [("tisph", lambda: run_tisph(out, dx, tf))]
        for name, (kind, handle) in ready.items():
            run = run_pysph if kind == "pysph" else run_dualsphysics
            results.append((name, lambda h=handle, run=run: run(h, out, dx, tf)))
        for name, fn in results:
            try:
                r = fn()
            except Exception as e:
                log(f"{name} at dp {dx:g} failed: {e}")
                notes.append(f"{name} at dp {dx:g}: not run ({str(e).splitlines()[0][:200]})")
                continue
            r = dict(r, code=name, dx=dx, tf=tf)
            r["pps"] = r["particles"] * r["steps"] / r["loop_s"] if r["loop_s"] > 0 else float("nan")
            log(
                f"dp {dx:g} to {tf:g} s, {name}: {r['particles']} particles, {r['steps']} steps, "
                f"{r['wall_s']:.1f} s ({r['loop_s']:.1f} s loop), {r['pps']:.3g} particle-steps/s, "
                f"front RMS {r['rms']:.3f}"
            )
            settings[name] = r.pop("settings")
            rows.append(r)
    return rows


def converged(rows):
    """Each run's front against the converged one: the mean front of the codes' runs at the finest
    dp two or more codes reached, RMS of the difference over x / a while that front is at most
    CONVERGED_UP_TO. Sets row["conv"]; returns (the reference runs, their own RMS half-difference)
    or None where no two codes share a dp."""
    shared = [dx for dx in {r["dx"] for r in rows} if sum(r["dx"] == dx for r in rows) >= 2]
    if not shared:
        return None
    finest = [r for r in rows if r["dx"] == min(shared)]
    t = np.linspace(0.0, min(min(r["t"].max() for r in rows), min(r["tf"] for r in rows)), 141)
    fronts = np.array([np.interp(t, r["t"], r["front"]) for r in finest])
    ref = fronts.mean(axis=0)
    keep = ref <= CONVERGED_UP_TO
    for r in rows:
        r["conv"] = float(np.sqrt(np.mean((np.interp(t, r["t"], r["front"])[keep] - ref[keep]) ** 2)))
    spread = float(np.sqrt(np.mean((fronts[:, keep] - ref[keep]) ** 2)))
    return finest, spread


def time_to_error(rows, key="rms"):
    """For each peer run, tisph's quickest run (process wall time) whose error (row[key]) is at
    most the peer's: (peer row, tisph row or None)."""
    ours = [r for r in rows if r["code"] == "tisph"]
    pairs = []
    for r in rows:
        if r["code"] == "tisph":
            continue
        good = [o for o in ours if o[key] <= r[key]]
        pairs.append((r, min(good, key=lambda o: o["wall_s"]) if good else None))
    return pairs


def _time_to_error_md(rows, key="rms", what="front RMS against Martin & Moyce"):
    md = [
        f"### Time to the same error: {what}",
        "",
        "For each peer run, tisph's quickest run with an error at most the peer's.",
        "",
        "| peer run | its error | its wall s (loop s) | tisph's quickest run as good | tisph wall s (loop s) | "
        "peer wall / tisph wall | peer loop / tisph loop |",
        "|---|---|---|---|---|---|---|",
    ]
    for r, o in time_to_error(rows, key):
        head = f"| {r['code']}, dp {r['dx']:g} | {r[key]:.3f} | {r['wall_s']:.1f} ({r['loop_s']:.1f}) |"
        if o is None:
            md.append(head + " none of tisph's runs | - | - | - |")
        else:
            md.append(
                head + f" dp {o['dx']:g}: {o[key]:.3f} | {o['wall_s']:.1f} ({o['loop_s']:.1f}) | "
                f"{r['wall_s'] / o['wall_s']:.1f} | {r['loop_s'] / o['loop_s']:.1f} |"
            )
    return md + [""]


def figure(rows, path):
    """Each code's front error against its process wall time, one curve a code over its dp: against
    Martin & Moyce, and (where converged() set it) against the converged front."""
    plt = pyplot()
    panels = [("rms", "front RMS error against Martin & Moyce (x / a)")]
    if all("conv" in r for r in rows):
        panels.append(("conv", "front RMS against the converged front (x / a)"))
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 4.0), squeeze=False)
    for ax, (key, label) in zip(axes[0], panels):
        for k, code in enumerate(dict.fromkeys(r["code"] for r in rows)):
            rr = sorted((r for r in rows if r["code"] == code), key=lambda r: -r["dx"])
            ax.loglog([r["wall_s"] for r in rr], [r[key] for r in rr], "-o", color=f"C{k}", label=code, ms=5)
            for r in rr:
                ax.annotate(
                    f"{r['dx']:g}", (r["wall_s"], r[key]), fontsize=7, xytext=(3, 3), textcoords="offset points"
                )
        ax.set_xlabel("wall time of the process (s), two threads", fontsize=8)
        ax.set_ylabel(label, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3, which="both")
    axes[0][0].legend(fontsize=8)
    fig.suptitle(f"Dam break to {rows[0]['tf']:g} s, each code at its own settings (labels: dp in m)", fontsize=9)
    save(fig, path)


def compare(out, log, peers, pysph_venv=None, dsph_source=None, runs=RUNS):
    """The Markdown section: every code at every (dp, end time), back to back; with a ladder of
    three or more spacings, the time to the same error and OUT/dambreak_codes.png."""
    notes, settings = [], {}
    ready = _ready(peers, pysph_venv, dsph_source, notes, log)
    rows = _measure(out, log, ready, runs, notes, settings)
    ladder = len({r["dx"] for r in rows}) >= 3 and any(r["code"] != "tisph" for r in rows)
    ref = converged(rows) if ladder else None
    md = [
        "## Three codes on the dam break",
        "",
        "| dp | to t (s) | code | particles | steps | wall s (process) | time loop s | particle-steps/s (loop) | "
        "front RMS vs Martin & Moyce |" + (" front RMS vs the converged front |" if ref else ""),
        "|---|---|---|---|---|---|---|---|---|" + ("---|" if ref else ""),
    ]
    md += [
        f"| {r['dx']:g} | {r['tf']:g} | {r['code']} | {r['particles']} | {r['steps']} | {r['wall_s']:.1f} | "
        f"{r['loop_s']:.1f} | {r['pps']:.3g} | {r['rms']:.3f} |" + (f" {r['conv']:.4f} |" if ref else "")
        for r in rows
    ]
    md += [""] + [f"- {k}: {v}." for k, v in settings.items()] + [""] + notes + [""]
    if ladder:
        md += _time_to_error_md(rows)
    if ref:
        finest, spread = ref
        md += _time_to_error_md(rows, "conv", "the converged front")
        md += [
            f"The converged front: the mean of {', '.join(r['code'] for r in finest)} at dp {finest[0]['dx']:g}, "
            f"while it is at most {CONVERGED_UP_TO:g} a along the floor; those runs lie {spread:.4f} a from it "
            "(RMS), the reference's own uncertainty.",
            "",
        ]
    if ladder:
        figure(rows, os.path.join(out, "dambreak_codes.png"))
        md += ["![front error against wall time](dambreak_codes.png)", ""]
    return md
