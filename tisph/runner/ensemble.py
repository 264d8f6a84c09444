"""`tisph run CASE --seeds N`: the case with N random seeds, and each metric of summary.json as its
mean, standard deviation and standard error over the runs (measure/spread.py). A case with a
random initial bed takes its bed's seeds (sediment.seed, then the next N - 1 integers); any other
case takes the perturbation's (run.seed, then the next N - 1): the further runs start with each
fluid particle (water, or a sand phase) moved by up to run.perturbation dx (PERTURBATION where the case sets none), the
size of noise round-off makes, so the spread is how far the case's own chaos carries it.

Writes seeds/ensemble.md, ensemble.csv and ensemble.png in the run's folder (each further seed's
own run under seeds/seed<N>/), and `ensemble` in summary.json."""

import importlib
import os
import time

from ..io import ensure_dir, write_csv, write_text
from ..measure.spread import ensemble_metrics
from ..settings.config import ConfigError
from .convergence import QUIET, add_to_summary, fmt, panels
from .pool import run_all, stages
from .start import simulate

MAX_SEEDS = 100


PERTURBATION = 1e-3  # of dx: 2.5e-6 m at Mao's spacing, some 40 f32 units of a position


def check_seeds(cfg, n):
    """--seeds N: a whole number from 2 to MAX_SEEDS."""
    if not isinstance(n, int) or isinstance(n, bool) or not 2 <= n <= MAX_SEEDS:
        raise ConfigError("--seeds", n, f"a whole number of runs from 2 to {MAX_SEEDS}")


def random_bed(cfg):
    """Whether the case starts from a random bed that sediment.seed draws (sediment/initial.py)."""
    sed = cfg.get("sediment", {})
    return (
        sed.get("model") == "bedload"
        and "seed" in sed
        and (sed.get("seed_rms", 0.0) > 0.0 or cfg.get("geometry", {}).get("roughness", 0.0) > 0.0)
    )


def seed_key(cfg):
    """(the key an ensemble varies, {what the further runs also set}): the bed's seed, or the
    start's perturbation."""
    if random_bed(cfg):
        return "sediment.seed", {}
    return "run.seed", {"run.perturbation": cfg.run.perturbation or PERTURBATION}


def seeds_of(cfg, n):
    key = seed_key(cfg)[0]
    s0 = int(cfg.sediment.seed if key == "sediment.seed" else cfg.run.seed)
    return [s0 + k for k in range(n)]


def seed_run(module, config, overrides, out):
    """One further seed's run (in a worker process where several run at once)."""
    return simulate(importlib.import_module(module), overrides=overrides, config=config, out=out)


def study(scene, config, overrides, cfg, summary, out, n, log=print, jobs=0):
    """Run the further seeds, `jobs` at a time in worker processes of their own (0: one a core;
    one at a time on every core for a run of pool.WIDE particles or more; runner/pool.py), write the table, the figure and summary.json's `ensemble`; returns that
    entry. A seed that ends unstable is listed with its status and left out of the statistics."""
    seeds = seeds_of(cfg, n)
    key, also = seed_key(cfg)
    done = {seeds[0]: summary}
    tasks = []
    for s in seeds[1:]:
        sub = os.path.join(out, "seeds", f"seed{s}")
        ov = dict(overrides or {}, **QUIET, **also, **{key: s, "output.dir": sub})
        tasks.append((s, seed_run, (scene.module, config, ov, sub)))
    # the first run's size says whether the others go side by side or one at a time on every core
    ((tasks, jobs, threads),) = stages(tasks, [summary["particles"]] * len(tasks), jobs)
    log(
        f"seeds: {len(tasks)} more runs, {jobs} at a time on {threads} CPU thread{'s' if threads > 1 else ''} "
        f"each, in {os.path.join(out, 'seeds')}"
    )

    def finished(s, r, e):
        if e is not None:
            raise e
        log(f"seeds: {key} = {s}: {r['status']}")
        done[s] = r

    t0 = time.perf_counter()
    run_all(tasks, jobs, threads, finished)
    runs = [(s, done[s]) for s in seeds]
    ok = [r for r in runs if r[1]["status"] == "ok"]
    entry = {
        "key": key,
        "perturbation": also.get("run.perturbation"),
        "seeds": seeds,
        "status": {str(s): r["status"] for s, r in runs},
        "metrics": ensemble_metrics([r[1].get("metrics") for r in ok]),
        "seeds_ok": [r[0] for r in ok],
        "jobs": jobs,
        "threads": threads,
        "cost_over_run": (time.perf_counter() - t0) / max(summary["wall_time_s"], 1e-9),
    }
    folder = ensure_dir(os.path.join(out, "seeds"))
    write_text(os.path.join(folder, "ensemble.md"), report(entry))
    write_csv(
        os.path.join(folder, "ensemble.csv"),
        ("metric", "n", "mean", "std", "stderr", *(f"seed{s}" for s in entry["seeds_ok"])),
        [(k, m["n"], m["mean"], m["std"], m["stderr"], *m["values"]) for k, m in entry["metrics"].items()],
    )
    if varying(entry):
        figure(entry, os.path.join(folder, "ensemble.png"))
    return add_to_summary(out, "ensemble", entry)


def report(entry):
    ok, seeds = entry["seeds_ok"], entry["seeds"]
    bad = [f"{s} ({entry['status'][str(s)]})" for s in seeds if s not in ok]
    lines = [
        "# Ensemble",
        "",
        f"The case with {entry.get('key', 'sediment.seed')} = {', '.join(str(s) for s in seeds)}"
        + (
            f" (the further runs with run.perturbation = {entry['perturbation']:g}: each fluid particle moved at "
            "the start by up to that fraction of dx)"
            if entry.get("perturbation")
            else ""
        )
        + ": each metric's mean, standard "
        f"deviation (n - 1) and standard error of the mean over the {len(ok)} runs that finished. The further "
        f"runs, {entry.get('jobs', 1)} at a time, took {entry['cost_over_run']:.2f} of the first run's wall time."
        + (f" Left out: {', '.join(bad)}." if bad else ""),
        "",
        "| metric | n | mean | std | standard error | " + " | ".join(f"seed {s}" for s in ok) + " |",
        "|---|---|---|---|---|" + "---|" * len(ok),
    ]
    moved = varying(entry)
    lines[2] += f" {len(moved)} of the {len(entry['metrics'])} metrics moved between the seeds" + (
        " (ensemble.png)." if moved else "."
    )
    for k, m in entry["metrics"].items():
        lines.append(
            f"| {k} | {m['n']} | {fmt(m['mean'])} | {fmt(m['std'])} | {fmt(m['stderr'])} | "
            + " | ".join(fmt(v) for v in m["values"])
            + " |"
        )
    return "\n".join(lines) + "\n"


def varying(entry):
    """The metrics whose value moved between the seeds (the others are the case's inputs or
    deterministic: the table lists them)."""
    # a spread under 1e-12 of the mean is the mean's own rounding (an input the same in every run)
    return [k for k, m in entry["metrics"].items() if m["std"] and m["std"] > 1e-12 * abs(m["mean"])]


def figure(entry, path):
    """Each metric that moved: its value by seed, its mean and the band of one standard error."""
    seeds = entry["seeds_ok"]

    def draw(ax, k):
        m = entry["metrics"][k]
        pts = [(s, v) for s, v in zip(seeds, m["values"]) if v is not None]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o", color="C0", ms=4)
        if m["mean"] is not None:
            ax.axhline(m["mean"], color="C3", lw=1)
            if m["stderr"] is not None:
                ax.axhspan(m["mean"] - m["stderr"], m["mean"] + m["stderr"], color="C3", alpha=0.15, lw=0)
        se = f" +- {m['stderr']:.3g}" if m["stderr"] is not None else ""
        ax.set_title(f"{k}\n{fmt(m['mean'], '.3g')}{se}", fontsize=7)
        ax.set_xticks(seeds)

    panels(varying(entry)[:16], path, draw, entry.get("key", "sediment.seed"))
