"""Benchmark: run time against error, throughput and scaling, and a PySPH comparison.

    python -m tisph.bench [--quick] [--peer pysph] [--out renders/bench] [--only CASE ...]
    python -m tisph.bench --speed [--against REV] [--repeats N] [--quick]   (tisph/bench/speed.py)
    python -m tisph.bench --shedding [--gaps G ...] [--dx DX] [--end-time T] [--config F]   (tisph/bench/shedding.py)
    python -m tisph.bench --mao-held [--times T ...] [--dx DX] [--end-time T] [--config F]   (tisph/bench/mao_held.py)
    python -m tisph.bench --validate [--quick] [--only WORD ...]   (tisph/bench/validate.py: docs/validation.md)
    python -m tisph.bench --waves [--quick] [--dx DX] [--peer-finest DP] [--dualsphysics CLONE]   (tisph/bench/peers/flume_codes.py)

Every validation case runs at a ladder of resolutions; each run records particles, steps, wall
time, Taichi compile time (the first call, separately), particle-steps/s and its error against
its reference. Writes OUT/bench.csv, OUT/bench.md (tables, observed convergence orders, the
scaling table, the specialisation ratio, a kernel profile and, with --peer, the PySPH
comparison) and OUT/bench.png (run time against error, log-log).
Timings are for this machine and this run; compare them as ratios within one run.
"""

import dataclasses
import os
import sys
import time

import numpy as np

from ..io import ensure_dir, write_csv, write_text
from ..measure.plots import pyplot, save
from ..sweep import execute
from .common import named, peers, run_case, table
from .engine_costs import engine_sections


@dataclasses.dataclass
class BenchCase:
    name: str
    scene: str  # module under tisph (scenes.x or validation.x)
    metric: str  # the error metric in summary.json
    reference: str
    ladder: tuple  # dx values, full run
    quick: tuple  # dx values, --quick
    overrides: dict = dataclasses.field(default_factory=dict)
    config: str = ""  # a case file under scenes/
    quick_overrides: dict = dataclasses.field(default_factory=dict)


# a table, one case a row: kept as written
# fmt: off
CASES = [
    BenchCase("hydrostatic tank", "scenes.tank", "pressure_error", "rho g d below the top two rows",
              (0.04, 0.02, 0.01), (0.05, 0.04, 0.025), {"run.end_time": 1.5, "geometry.depth": 0.4}),
    BenchCase("Poiseuille, Newtonian", "validation.poiseuille", "velocity_l2_error", "steady parabola",
              (0.01, 0.005, 0.0025), (0.01, 0.00667, 0.005),
              {"materials.fluid.yield_stress": 0.0, "geometry.length": 0.08}),
    BenchCase("Poiseuille, Bingham 10 Pa", "validation.poiseuille", "velocity_l2_error", "exact Bingham profile",
              (0.01, 0.005, 0.0025), (0.01, 0.00667, 0.005), {"geometry.length": 0.08}),
    BenchCase("dam break (Martin & Moyce)", "scenes.dam_break", "front_rms_error", "Martin & Moyce 1952 front",
              (0.06, 0.04, 0.03, 0.02), (0.08, 0.06, 0.04), {}),
    BenchCase("wet-bed dam break, alpha 0.4", "scenes.dam_break", "bore_speed_error", "Stoker bore speed",
              (0.025, 0.0167, 0.0125), (0.03, 0.025, 0.02), {}, config="dam_break_alpha04.toml",
              quick_overrides={"run.end_time": 1.6, "geometry.profile_times": []}),
    # H / dx = 3, 5, 8, 12; to the end of the window at three wavelengths (no reflection window)
    BenchCase("flume, piston (Biesel)", "scenes.flume", "wave_height_error", "Biesel H/S, worst of 1, 2, 3 wavelengths",
              (0.02, 0.0125, 0.0075, 0.005), (0.03, 0.025), {"run.end_time": 9.6, "geometry.array_gauges": 0}),
]
# fmt: on


def run_one(case, dx, out, quick):
    slug = "".join(c if c.isalnum() else "_" for c in case.name)[:30] + f"_dx{dx:g}"
    s, wall = run_case(case, dx, quick, os.path.join(out, "runs", slug))
    err = s["metrics"].get(case.metric, float("nan"))
    return dict(
        case=case.name,
        dx=dx,
        particles=s["particles"],
        steps=s["steps"],
        sim_time=s["sim_time"],
        wall_time_s=round(wall, 3),
        compile_time_s=round(s["compile_time_s"], 3),
        step_time_s=round(s["step_time_s"], 3),
        particle_steps_per_s=round(s["particle_steps_per_s"]),
        metric=case.metric,
        error=float(err) if err is not None else float("nan"),
        status=s["status"],
    )


def convergence_order(dxs, errs):
    """Slope of log(error) against log(dx), least squares over the finite points (NaN if < 2)."""
    d, e = np.asarray(dxs, float), np.asarray(errs, float)
    m = np.isfinite(e) & (e > 0)
    if m.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(d[m]), np.log(e[m]), 1)[0])


# ---------------------------------------------------------------------------- PySPH
def peer_pysph(out, log, venv=None):
    return peers("pysph_runs").compare(out, log, venv)


# ---------------------------------------------------------------------------- report
def plot(rows, path):
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for name in dict.fromkeys(r["case"] for r in rows):
        rr = [r for r in rows if r["case"] == name and np.isfinite(r["error"]) and r["error"] > 0]
        if not rr:
            continue
        ax.loglog([r["wall_time_s"] for r in rr], [r["error"] for r in rr], "o-", label=name)
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("error against the reference")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    ax.set_title("tisph: run time against error (each point one resolution)", fontsize=10)
    save(fig, path)


def _on_cluster(jobs, a, log):
    """The ladders' runs as Dask tasks on a.scheduler (tisph.sweep's path), rows in job order."""
    from dask.distributed import Client

    client = Client(a.scheduler)
    try:
        res = execute(
            [(f"{i:03d}", run_one, (c, dx, a.out, a.quick)) for i, (c, dx) in enumerate(jobs)], client, progress=False
        )
    finally:
        client.close()
    rows = []
    for i, (c, dx) in enumerate(jobs):
        r = res[f"{i:03d}"]
        if isinstance(r, tuple):  # the task failed
            log(f"{c.name}, dx {dx:g}: failed: {r[1]}")
            r = dict(
                case=c.name,
                dx=dx,
                particles=0,
                steps=0,
                sim_time=0.0,
                wall_time_s=float("nan"),
                compile_time_s=float("nan"),
                step_time_s=float("nan"),
                particle_steps_per_s=0,
                metric=c.metric,
                error=float("nan"),
                status="error",
            )
        rows.append(r)
    return rows


def ladder_report(a, cases, rows):
    """bench.csv, and bench.md's first sections: the runs' table and each case's observed order."""
    cols = (
        "case",
        "dx",
        "particles",
        "steps",
        "sim_time",
        "wall_time_s",
        "compile_time_s",
        "step_time_s",
        "particle_steps_per_s",
        "metric",
        "error",
        "status",
    )
    write_csv(os.path.join(a.out, "bench.csv"), cols, [tuple(r[k] for k in cols) for r in rows])
    md = [
        "# tisph benchmark",
        "",
        f"{'Quick' if a.quick else 'Full'} run, {time.strftime('%Y-%m-%d %H:%M')}, CPU backend, f32, "
        f"{os.cpu_count()} threads. Wall time includes set-up and compilation; compile is the first call.",
        "",
        "## Run time against error",
        "",
        table(
            ("case", "dx", "particles", "steps", "wall s", "compile s", "particle-steps/s", "error", "metric"),
            [
                (
                    r["case"],
                    f"{r['dx']:g}",
                    r["particles"],
                    r["steps"],
                    f"{r['wall_time_s']:.1f}",
                    f"{r['compile_time_s']:.1f}",
                    f"{r['particle_steps_per_s']:.3g}",
                    f"{r['error']:.4g}",
                    r["metric"],
                )
                for r in rows
            ],
        ),
        "",
        "Observed convergence order (slope of log error against log dx; positive means the error falls with dx):",
        "",
    ]
    orders = []
    for c in cases:
        rr = [r for r in rows if r["case"] == c.name]
        orders.append(
            (c.name, c.reference, f"{convergence_order([r['dx'] for r in rr], [r['error'] for r in rr]):.2f}")
        )
    return md + [table(("case", "reference", "order"), orders), ""]


def run(a):
    """The ladder, scaling and profile parts of `python -m tisph.bench` (options parsed by cli.py)."""
    from .. import runtime

    runtime.init("cpu", "f32")
    ensure_dir(a.out)
    log = lambda m: print(m, file=sys.stderr, flush=True)
    rows = []
    cases = named(CASES, a.only)
    if a.dry_run:
        cases = [dataclasses.replace(CASES[0], quick=CASES[0].quick[:2], quick_overrides={"run.end_time": 0.2})]
        a.quick = True
    jobs = [(c, dx) for c in cases for dx in (c.quick if a.quick else c.ladder)]
    if a.scheduler:
        rows = _on_cluster(jobs, a, log)
    else:
        rows = [run_one(c, dx, a.out, a.quick) for c, dx in jobs]
    for (c, dx), r in zip(jobs, rows):
        log(
            f"{c.name}, dx {dx:g}: {r['particles']} particles, {r['steps']} steps, {r['wall_time_s']:.1f} s "
            f"(compile {r['compile_time_s']:.1f} s), {r['particle_steps_per_s']:.3g} p-steps/s, "
            f"{c.metric} = {r['error']:.4g}"
        )
    md = ladder_report(a, cases, rows)
    try:
        plot(rows, os.path.join(a.out, "bench.png"))
        md += ["![run time against error](bench.png)", ""]
    except Exception as e:
        log(f"warning: no plot: {e}")
    if not a.no_scaling:
        md += engine_sections(a, log)
    if "pysph" in a.peer:
        md += peer_pysph(a.out, log, a.peer_venv)
    write_text(os.path.join(a.out, "bench.md"), "\n".join(md) + "\n")
    print("\n".join(md))
    return 0
