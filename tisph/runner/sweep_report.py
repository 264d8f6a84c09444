"""A sweep's tables and figure (`tisph sweep`, tisph/sweep.py): OUT/sweep.csv, sweep.md and
sweep.png (each metric against the swept values), and with --seeds OUT/ensemble.csv and .md
(each combination's spread over its seeds)."""

import math
import os
import sys

from ..io import write_csv, write_text
from ..measure.plots import pyplot, save


# ---------------------------------------------------------------- the table
def flat_metrics(summary):
    out = {}
    for k, v in (summary or {}).get("metrics", {}).items():
        if isinstance(v, bool):
            out[k] = int(v)
        elif isinstance(v, (int, float, str)):
            out[k] = v
    return out


def table(cases, results):
    keys = list(cases[0][1]) if cases else []
    metric_names = []
    for cid, _, _ in cases:
        for k in flat_metrics(results.get(cid, (None, None, None))[2]):
            if k not in metric_names:
                metric_names.append(k)
    cols = ["case"] + keys + ["status", "message", "wall_time_s", "particle_steps_per_s"] + metric_names
    rows = []
    for cid, values, _ in cases:
        status, msg, s = results.get(cid, ("not run", "", None))
        m = flat_metrics(s)
        rows.append(
            [cid]
            + [values[k] for k in keys]
            + [
                status,
                (msg or "").replace("\n", " ")[:300],
                (s or {}).get("wall_time_s", ""),
                (s or {}).get("particle_steps_per_s", ""),
            ]
            + [m.get(k, "") for k in metric_names]
        )
    return cols, rows, keys, metric_names


def write_tables(out, cases, results, scene_name, wall):
    cols, rows, keys, metric_names = table(cases, results)
    write_csv(os.path.join(out, "sweep.csv"), cols, rows)

    def fmt(v):
        return f"{v:.4g}" if isinstance(v, float) and math.isfinite(v) else str(v)

    md = [
        f"# Sweep of {scene_name}",
        "",
        f"{len(cases)} cases, {wall:.1f} s wall time.",
        "",
        "| " + " | ".join(cols) + " |",
        "|" + "---|" * len(cols),
    ]
    md += ["| " + " | ".join(fmt(v) for v in r) + " |" for r in rows]
    write_text(os.path.join(out, "sweep.md"), "\n".join(md) + "\n")
    try:
        plot(os.path.join(out, "sweep.png"), rows, cols, keys, metric_names)
    except Exception as e:  # a failed plot must not lose the table
        print(f"warning: no sweep.png: {e}", file=sys.stderr)


def plot(path, rows, cols, keys, metric_names):
    """Each numeric metric against the first swept key, one line per value of the others."""
    num = [
        m
        for m in metric_names
        if all(isinstance(r[cols.index(m)], (int, float)) or r[cols.index(m)] == "" for r in rows)
        and any(isinstance(r[cols.index(m)], (int, float)) for r in rows)
    ][:12]
    if not num or not keys:
        return
    keys = [k for k in keys if len({str(r[cols.index(k)]) for r in rows}) > 1] or keys[:1]
    plt = pyplot()
    n = len(num)
    ncol = min(3, n)
    nrow = math.ceil(n / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.2 * ncol, 3.2 * nrow), squeeze=False)
    k0 = keys[0]
    groups = {}
    for r in rows:
        rest = tuple((k, r[cols.index(k)]) for k in keys[1:])
        groups.setdefault(rest, []).append(r)
    for ax, m in zip(axes.ravel(), num):
        for rest, rr in groups.items():
            pts = [(r[cols.index(k0)], r[cols.index(m)]) for r in rr if isinstance(r[cols.index(m)], (int, float))]
            if not pts:
                continue
            try:
                pts.sort()
            except TypeError:
                pass
            xs = list(range(len(pts))) if not all(isinstance(p[0], (int, float)) for p in pts) else [p[0] for p in pts]
            ax.plot(
                xs, [p[1] for p in pts], "o-", ms=4, label=", ".join(f"{k.split('.')[-1]}={v}" for k, v in rest) or None
            )
        ax.set_xlabel(k0)
        ax.set_title(m, fontsize=9)
        if len(groups) > 1:
            ax.legend(fontsize=7)
    for ax in axes.ravel()[n:]:
        ax.set_visible(False)
    save(fig, path)


def write_ensemble(out, cases, results):
    """OUT/ensemble.csv and .md: each combination of the other swept keys, each metric's spread
    over the seeds that finished (measure/spread.py)."""
    from ..measure.spread import ensemble_metrics

    groups = {}
    for cid, values, _ in cases:
        rest = tuple((k, v) for k, v in values.items() if k not in ("sediment.seed", "run.seed"))
        status, _, summary = results.get(cid, ("not run", "", None))
        groups.setdefault(rest, []).append(summary.get("metrics") if status == "ok" and summary else None)
    keys = [k for k, _ in next(iter(groups))] if groups else []
    cols = keys + ["metric", "runs_ok", "mean", "std", "stderr"]
    rows = []
    for rest, metrics in groups.items():
        for name, m in ensemble_metrics([x for x in metrics if x is not None]).items():
            rows.append([v for _, v in rest] + [name, m["n"], m["mean"], m["std"], m["stderr"]])
    write_csv(os.path.join(out, "ensemble.csv"), cols, rows)

    def fmt(v):
        return "-" if v is None else f"{v:.4g}" if isinstance(v, float) else str(v)

    md = [
        "# Ensemble",
        "",
        "Each metric over the seeds that finished: mean, standard deviation (n - 1), standard error.",
        "",
        "| " + " | ".join(cols) + " |",
        "|" + "---|" * len(cols),
    ]
    md += ["| " + " | ".join(fmt(v) for v in r) + " |" for r in rows]
    write_text(os.path.join(out, "ensemble.md"), "\n".join(md) + "\n")
