"""python -m tisph.bench --validate [--quick] [--only WORD ...] [--jobs N] [--docs DIR] [--out DIR]

Runs every validation case and writes the validation page, DOCS/validation.md, with a small
figure per case in DOCS/validation/ and the run time against error figure, and fills the table
between the validation markers of the README. Each case runs at its reported resolution and, for
the cost figure, at one or two coarser ones; --quick runs coarse, short versions of every case
(for a test: the page, its rows and its figures, not the figures' values). The runs go N at a
time, each in a process of its own on cores / N CPU threads (runner/pool.py; default one a core),
the longest first by the stored results.
"""

import dataclasses
import importlib
import json
import os
import sys
import time

import numpy as np

from ..io import ensure_dir, write_text
from .common import ROOT, named, run_case
from .validation_cases import CASES, CASES_BY_NAME
from .validation_page import (
    cost_figure,
    figure,
    fill_readme,
    fmt,
    intervals,
    machine,
    page,
    readme_table,
    slug,
)


def run_one(case, dx, out, quick, resume=False):
    d = os.path.join(out, slug(case.name), f"dx{dx:g}")
    s = finished(d) if resume else None
    resumed = bool(s)
    if resumed:
        wall = s["wall_time_s"]
    else:
        s, wall = run_case(case, dx, quick, d)
    m = s["metrics"]
    v = m.get(case.metric)
    v = float("nan") if v is None else float(v)
    err = float("nan") if not case.has_reference else v / case.reference_value - 1.0 if case.reference_value else v
    also = {k: m.get(k, s.get(k)) for k in case.also}
    if s["status"] != "ok":
        also["run"] = f"{s['status']} at t = {s['sim_time']:.3g} s"
    return dict(
        case=case.name,
        dx=dx,
        particles=s["particles"],
        steps=s["steps"],
        wall=wall,
        pps=s["particle_steps_per_s"],
        value=v,
        error=err,
        density=s.get("max_density_error"),
        also=also,
        dir=d,
        status=s["status"],
        date=time.strftime("%Y-%m-%d", time.gmtime()),
        resumed=resumed,
    )


def _resolved(case):
    from ..runner import resolve

    return resolve(
        importlib.import_module(f"tisph.{case.scene}"),
        os.path.join(ROOT, "scenes", case.config) if case.config else None,
        dict(case.overrides),
    )


def seeds_for(case):
    """The seeds of the case's ensemble (its bed's, or its start's where the bed is not random:
    runner/ensemble.py), its own (the reported run's) first."""
    from ..runner.ensemble import seeds_of

    return seeds_of(_resolved(case), case.seeds) if case.seeds > 1 else []


def finished(d):
    """The summary of a run that ended well in folder d (--resume takes it as run), or None."""
    try:
        with open(os.path.join(d, "summary.json")) as f:
            s = json.load(f)
    except (OSError, ValueError):
        return None
    return s if s.get("status") == "ok" and "wall_time_s" in s else None


def run_task(name, dx, seed, out, quick, resume=False):
    """One run of the table (in a worker process where --jobs runs several): the case NAME at dx,
    with the ensemble's seed (runner/ensemble.py's seed_key) unless None."""
    from ..runner.ensemble import seed_key

    case = CASES_BY_NAME[name]
    if seed is None:
        return run_one(case, dx, out, quick, resume)
    key, also = seed_key(_resolved(case))
    return run_one(
        dataclasses.replace(case, overrides=dict(case.overrides, **also, **{key: seed})),
        dx,
        os.path.join(out, f"seed{seed}"),
        quick,
        resume,
    )


def failed_row(case, dx, e):
    return dict(
        case=case.name,
        dx=dx,
        particles=0,
        steps=0,
        wall=float("nan"),
        pps=float("nan"),
        value=float("nan"),
        error=float("nan"),
        density=None,
        also={"run": f"failed: {e}"},
        dir="",
        status="error",
        date=time.strftime("%Y-%m-%d", time.gmtime()),
    )


def ensemble(case, row, seeds, seed_rows):
    """The reported row with its seeds' runs: its value and error become the ensemble's mean, its
    `ensemble` each seed's value and the spread."""
    from ..measure.spread import spread
    from ..runner.ensemble import seed_key

    values = [row["value"]] + [seed_rows[s]["value"] if seed_rows[s]["status"] == "ok" else None for s in seeds[1:]]
    ens = dict(spread(values), seeds=list(seeds), key=seed_key(_resolved(case))[0])
    row["ensemble"] = ens
    if ens["mean"] is not None:
        row["value"] = ens["mean"]
        row["error"] = ens["mean"] / case.reference_value - 1.0 if case.reference_value else ens["mean"]


def load_results(path):
    """{case name: (rows, figure)} of an earlier run, or {}."""
    try:
        with open(path) as f:
            return {k: (v["rows"], v["figure"]) for k, v in json.load(f).items()}
    except (OSError, ValueError, KeyError):
        return {}


def save_results(path, results):
    def clean(r):
        return {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in r.items() if k != "dir"}

    write_text(
        path,
        json.dumps(
            {k: {"rows": [clean(r) for r in rows], "figure": fig} for k, (rows, fig) in results.items()}, indent=1
        )
        + "\n",
    )


def estimate(stored, name, dx, key="wall", unknown=float("inf")):
    """A run's wall time (or another key) in the stored results, or `unknown`: to start the
    longest first, and to run the large ones alone on every core."""
    rows = [r for r in stored.get(name, ((), None))[0] if r.get("dx") == dx and _num(r.get(key)) == r.get(key)]
    return rows[0][key] if rows else unknown


def plan_tasks(cases, ladders, seeds, out, quick, resume, stored):
    """Every run of the table: each case at each spacing of its ladder, then its further seeds; the
    longest first by the stored results."""
    tasks = [
        ((c.name, dx, None), run_task, (c.name, dx, None, out, quick, resume)) for c in cases for dx in ladders[c.name]
    ]
    tasks += [
        ((c.name, ladders[c.name][-1], s), run_task, (c.name, ladders[c.name][-1], s, out, quick, resume))
        for c in cases
        for s in seeds[c.name][1:]
    ]
    return sorted(tasks, key=lambda t: -estimate(stored, t[0][0], t[0][1]))


def main(a):
    from ..runner.pool import run_all, stages

    # only a full run without --out refreshes the tree's docs/ and README; any other writes under --out
    tree = not (a.quick or getattr(a, "out_given", False))
    out = a.out
    docs = a.docs or (os.path.join(ROOT, "docs") if tree else out)
    ensure_dir(os.path.join(docs, "validation"))
    store = os.path.join(docs, "validation", "results.json")
    log = lambda m: print(m, file=sys.stderr, flush=True)
    cases = named(CASES, a.only)
    # the last run's rows: their wall times and sizes order and place this run's (the tree's where --out has none)
    stored = load_results(store) or load_results(os.path.join(ROOT, "docs", "validation", "results.json"))
    # --only re-runs those cases and keeps the others' rows from the last run (the same kind of run)
    results = {
        k: v
        for k, v in (stored if a.only else {}).items()
        if k in CASES_BY_NAME and all(bool(r.get("quick")) == bool(a.quick) for r in v[0])
    }
    ladders = {c.name: (c.quick,) if a.quick else c.ladder for c in cases}
    seeds = {c.name: seeds_for(c) if not a.quick else [] for c in cases}
    resume = getattr(a, "resume", False)
    tasks = plan_tasks(cases, ladders, seeds, out, a.quick, resume, stored)
    sizes = [estimate(stored, t[0][0], t[0][1], "particles", 0) for t in tasks]
    plan = stages(tasks, sizes, getattr(a, "jobs", 0))
    started, mach, t0 = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), machine(), time.perf_counter()
    for part, jobs, threads in plan:
        log(f"{len(part)} runs, {jobs} at a time on {threads} CPU thread{'s' if threads > 1 else ''} each")
    got = {c.name: {} for c in cases}
    way = {t[0]: (jobs, threads) for part, jobs, threads in plan for t in part}

    def done(key, r, e):
        name, dx, seed = key
        c = CASES_BY_NAME[name]
        if e is not None:
            log(f"{name}, dx {dx:g}: failed: {e}")
            r = failed_row(c, dx, e)
        r.update(quick=bool(a.quick), jobs=way[key][0], threads=way[key][1])
        got[name][(dx, seed)] = r
        log(
            f"{name}, dx {dx:g}"
            + (f", sediment.seed {seed}" if seed is not None else "")
            + f": {r['particles']} particles, {r['steps']} steps, {r['wall']:.1f} s, {c.metric} = "
            f"{fmt(r['value'], 4)}, error {fmt(r['error'])}"
        )
        if len(got[name]) == len(ladders[name]) + max(0, len(seeds[name]) - 1):
            finish(c, got[name])

    def finish(c, runs):
        rows = [runs[(dx, None)] for dx in ladders[c.name]]
        if len(seeds[c.name]) > 1 and rows[-1]["status"] == "ok":
            ensemble(c, rows[-1], seeds[c.name], {s: runs[(rows[-1]["dx"], s)] for s in seeds[c.name][1:]})
        for k, r in enumerate(rows):
            r["last"] = k == len(rows) - 1
        fig = figure(c, rows[-1], docs) if rows[-1]["dir"] else None
        results[c.name] = (rows, fig)
        save_results(store, results)

    for part, jobs, threads in plan:
        run_all(part, jobs, threads, done)
    rows = [
        dict(r, error=_num(r["error"]), value=_num(r["value"]), wall=_num(r["wall"]), pps=_num(r["pps"]))
        for c in CASES
        if c.name in results
        for r in results[c.name][0]
    ]
    figs = {k: v[1] for k, v in results.items()}
    cost_figure(rows, os.path.join(docs, "validation", "cost.png"), intervals(rows))
    ran = dict(
        minutes=(time.perf_counter() - t0) / 60,
        runs=len(tasks),
        ways=[(len(p), j, n) for p, j, n in plan],
        resumed=sum(bool(r.get("resumed")) for runs in got.values() for r in runs.values()),
    )
    write_text(os.path.join(docs, "validation.md"), page(rows, a.quick, started, ran, mach, figs))
    readme = a.readme if a.readme is not None else (os.path.join(ROOT, "README.md") if tree and not a.docs else "")
    if readme and all(c.name in results for c in CASES):
        fill_readme(readme, readme_table(rows))
    log(f"wrote {os.path.join(docs, 'validation.md')}")
    return 0


def _num(v):
    return float("nan") if v is None else v
