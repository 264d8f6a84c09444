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
import platform
import shutil
import sys
import time

import numpy as np

from ..io import ensure_dir, read_csv, write_text
from ..measure.plots import pyplot, save
from .common import ROOT, run_case, table
from .uncertainty import interval
from .validation_cases import CASES, CASES_BY_NAME

README_START, README_END = "<!-- validation:start -->", "<!-- validation:end -->"


def slug(name):
    words = "".join(c if c.isalnum() else " " for c in name.lower()).split()
    return "_".join(words)[:40].strip("_")


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


def seeds_for(case):
    """The seeds of the case's bed for its ensemble, its own (the reported run's) first."""
    from ..runner import resolve
    from ..runner.ensemble import seeds_of

    if case.seeds <= 1:
        return []
    cfg = resolve(
        importlib.import_module(f"tisph.{case.scene}"),
        os.path.join(ROOT, "scenes", case.config) if case.config else None,
        dict(case.overrides),
    )
    return seeds_of(cfg, case.seeds)


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
    with sediment.seed = seed unless None."""
    case = CASES_BY_NAME[name]
    if seed is None:
        return run_one(case, dx, out, quick, resume)
    return run_one(
        dataclasses.replace(case, overrides=dict(case.overrides, **{"sediment.seed": seed})),
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

    values = [row["value"]] + [seed_rows[s]["value"] if seed_rows[s]["status"] == "ok" else None for s in seeds[1:]]
    ens = dict(spread(values), seeds=list(seeds))
    row["ensemble"] = ens
    if ens["mean"] is not None:
        row["value"] = ens["mean"]
        row["error"] = ens["mean"] / case.reference_value - 1.0 if case.reference_value else ens["mean"]


def figure(case, row, dest, width=480):
    """The case's figure, scaled to `width` px, as DEST/validation/<slug>.png (or None)."""
    from PIL import Image

    path = os.path.join(dest, "validation", slug(case.name) + ".png")
    src = os.path.join(row["dir"], case.figure) if case.figure else None
    tmp = path + ".part.png"
    if src and os.path.exists(src):
        shutil.copyfile(src, tmp)
    elif case.probes and os.path.exists(os.path.join(row["dir"], "probes.csv")):
        _, cols = read_csv(os.path.join(row["dir"], "probes.csv"))
        plt = pyplot()
        fig, ax = plt.subplots(figsize=(5, 3))
        for c in case.probes:
            ax.plot(cols["t"], cols[c], label=c)
        ax.set_xlabel("t (s)")
        ax.legend(fontsize=8)
        ax.set_title(f"{case.name}, dx {row['dx']:g} m", fontsize=9)
        ax.grid(alpha=0.3)
        save(fig, tmp)
    else:
        return None
    im = Image.open(tmp)
    if im.width > 2.5 * im.height:  # a wide figure keeps its text legible at 800 px
        width = max(width, 800)
    if im.width > width:
        im = im.resize((width, round(im.height * width / im.width)), Image.LANCZOS)
    im.convert("RGB").save(tmp, format="PNG", optimize=True)
    os.replace(tmp, path)
    return os.path.relpath(path, dest)


def intervals(rows):
    """{case: (half-width on the error or None, what it is)} of the rows' cases (bench/uncertainty.py)."""
    return {
        c.name: interval(c, [r for r in rows if r["case"] == c.name])
        for c in CASES
        if any(r["case"] == c.name for r in rows)
    }


def cost_figure(rows, path, unc):
    """Run time against |error|, each case at its resolutions (log-log); the reported run's
    uncertainty (unc: intervals) as an error bar where it has one."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9.5, 4.5))
    colours, markers = plt.get_cmap("tab20").colors, "osD^vP*Xh<>p"
    for k, name in enumerate(dict.fromkeys(r["case"] for r in rows)):
        rr = [r for r in rows if r["case"] == name and np.isfinite(r["error"]) and r["error"] != 0]
        if rr:
            colour = colours[(2 * k) % 20 + (k // 10) % 2]
            ax.loglog(
                [r["wall"] for r in rr],
                [abs(r["error"]) for r in rr],
                "-",
                marker=markers[k % len(markers)],
                color=colour,
                label=name,
            )
            half, e = unc.get(name, (None, ""))[0], abs(rr[-1]["error"])
            if half and rr[-1]["last"]:
                lo = min(half, 0.9 * e)  # a log axis: the bar stops above zero
                ax.errorbar([rr[-1]["wall"]], [e], yerr=[[lo], [half]], color=colour, capsize=3, lw=1)
    ax.set_xlabel(f"wall time (s): {how_run(rows)}", fontsize=8)
    ax.set_ylabel("|error| against the reference")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))  # beside: over the curves it hid points
    ax.set_title("Run time against error: each point one resolution; bars: the reported run's uncertainty", fontsize=9)
    save(fig, path)


def _fmt(v, digits=3):
    if v is None or (isinstance(v, float) and not np.isfinite(v)):
        return "-"
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_fmt(x, digits) for x in v) + "]"
    return str(v)


def machine():
    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    return (
        f"{platform.system()} {platform.machine()}, {os.cpu_count()} CPU threads, Python "
        f"{platform.python_version()}; load average at the start {load[0]:.2f}"
    )


def how_run(rows):
    """How the rows' runs shared the machine, in words."""
    ways = sorted({(r.get("jobs", 1), r.get("threads")) for r in rows})
    said = [
        f"{j} runs side by side on {t} CPU thread{'s' if t > 1 else ''} each"
        if j > 1
        else f"one run at a time on {t or 'all the'} CPU threads"
        for j, t in ways
    ]
    return " or ".join(said)


def page(rows, quick, started, ran, mach, figs):
    best = [r for r in rows if r["last"]]
    unc = intervals(rows)
    md = [
        "# Validation",
        "",
        "Generated by `python -m tisph.bench --validate" + (" --quick" if quick else "") + "` on "
        f"{started} ({mach}): {ran['runs']} runs in {ran['minutes']:.1f} minutes, "
        + ", then ".join(
            (
                f"{n} one at a time on {t} CPU threads"
                if j == 1
                else f"{n} side by side, {j} at a time on {t} CPU thread{'s' if t > 1 else ''} each"
            )
            for n, j, t in ran["ways"]
        )
        + " (`--jobs`)"
        + (f"; {ran['resumed']} of them taken from an earlier run (`--resume`)" if ran.get("resumed") else "")
        + ". Each case's section gives "
        "the date it ran (`--only` re-runs some cases and keeps the others). Do not edit: run the command again.",
        "",
    ]
    if quick:
        md += [
            "**A quick run**: coarse and short versions of every case, to exercise the page; its errors "
            "say nothing about the solver.",
            "",
        ]
    md += [
        "Each case's error at its reported resolution (the default case file's). Wall time is the whole "
        f"run (set-up, compile, stepping, outputs) on the CPU backend, {how_run(rows)}; particle-steps/s is the "
        "stepping rate. The errors are signed where the sign says something (a ripple longer than predicted "
        "is positive).",
        "",
        table(
            (
                "case",
                "reference",
                "error",
                "uncertainty",
                "value",
                "dx (m)",
                "particles",
                "steps",
                "wall s",
                "largest density error",
                "more",
            ),
            [
                (
                    r["case"],
                    CASES_BY_NAME[r["case"]].reference,
                    f"{_fmt(r['error'])} ({CASES_BY_NAME[r['case']].error})",
                    unc[r["case"]][1],
                    _fmt(r["value"], 4),
                    f"{r['dx']:g}",
                    r["particles"],
                    r["steps"],
                    f"{r['wall']:.0f}",
                    _fmt(r["density"]),
                    "; ".join(f"{k} {_fmt(v)}" for k, v in r["also"].items()),
                )
                for r in best
            ],
        ),
        "",
        "The uncertainty is the numerical one: the grid convergence index of the reported run where "
        "the case ran three spacings (Celik et al. 2008, safety factor 1.25), the standard error of the "
        "mean where a chaotic metric is the mean over seeds of the random bed, or why there is none; "
        "`tisph run CASE --convergence` and `--seeds N` give them for any case.",
        "",
        "## Run time against error",
        "",
        "![run time against error](validation/cost.png)",
        "",
        table(
            ("case", "dx (m)", "particles", "steps", "wall s", "particle-steps/s", "error"),
            [
                (
                    r["case"],
                    f"{r['dx']:g}",
                    r["particles"],
                    r["steps"],
                    f"{r['wall']:.1f}",
                    f"{r['pps']:.3g}",
                    _fmt(r["error"]),
                )
                for r in rows
            ],
        ),
        "",
        "## The cases",
        "",
    ]
    for r in best:
        c = CASES_BY_NAME[r["case"]]
        md += [
            f"### {c.name}",
            "",
            f"`python -m tisph.{c.scene}"
            + (f" --config scenes/{c.config}" if c.config else "")
            + (f" --dx {r['dx']:g}" if not quick else "")
            + "`"
            + (f"; overrides {c.overrides}" if c.overrides else ""),
            "",
            f"Reference: {c.reference}. Error: {c.error} = {_fmt(r['error'])} at dx {r['dx']:g} m "
            f"({r['particles']} particles, {r['steps']} steps, {r['wall']:.0f} s; run {r.get('date', '')})."
            + (f" {c.note}" if c.note else ""),
            "",
        ]
        if figs.get(c.name):
            md += [f"![{c.name}]({figs[c.name]})", ""]
    return "\n".join(md) + "\n"


def readme_table(rows):
    best = [r for r in rows if r["last"]]
    return table(
        ("case", "error", "dx (m)", "particles", "wall s"),
        [
            (
                r["case"],
                f"{_fmt(r['error'])} ({CASES_BY_NAME[r['case']].error})",
                f"{r['dx']:g}",
                r["particles"],
                f"{r['wall']:.0f}",
            )
            for r in best
        ],
    )


def fill_readme(path, text):
    with open(path, encoding="utf-8") as f:
        src = f.read()
    i, j = src.index(README_START) + len(README_START), src.index(README_END)
    write_text(path, src[:i] + "\n" + text + "\n" + src[j:])


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


def main(a):
    from ..runner.pool import run_all, stages

    # only a full run without --out refreshes the tree's docs/ and README; any other writes under --out
    tree = not (a.quick or getattr(a, "out_given", False))
    out = a.out
    docs = a.docs or (os.path.join(ROOT, "docs") if tree else out)
    ensure_dir(os.path.join(docs, "validation"))
    store = os.path.join(docs, "validation", "results.json")
    log = lambda m: print(m, file=sys.stderr, flush=True)
    cases = [c for c in CASES if not a.only or any(w.lower() in c.name.lower() for w in a.only)]
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
    tasks = [
        ((c.name, dx, None), run_task, (c.name, dx, None, out, a.quick, resume))
        for c in cases
        for dx in ladders[c.name]
    ]
    tasks += [
        ((c.name, ladders[c.name][-1], s), run_task, (c.name, ladders[c.name][-1], s, out, a.quick, resume))
        for c in cases
        for s in seeds[c.name][1:]
    ]
    tasks.sort(key=lambda t: -estimate(stored, t[0][0], t[0][1]))
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
            f"{_fmt(r['value'], 4)}, error {_fmt(r['error'])}"
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
