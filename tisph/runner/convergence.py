"""`tisph run CASE --convergence`: the case again at 1.5 and 2.25 times its spacing, and for each
metric of summary.json its observed order, Richardson's estimate and the GCI on the case's own
spacing (measure/gci.py), or the reason there is none (oscillatory, not converging yet). The two coarser runs cost about
(1/1.5)^3 + (1/2.25)^3 = 0.38 of the run itself in 2D (particles go as dx^-2, steps as dx^-1).

Writes convergence/convergence.md, convergence.csv and convergence.png in the run's folder (each
rung's own run under convergence/dx<value>/), and `convergence` in summary.json."""

import json
import math
import os

from ..io import ensure_dir, write_csv, write_json, write_text
from ..measure.gci import verdict
from ..settings.config import ConfigError
from .start import simulate

RATIO = 1.5
QUIET = {
    "output.render": False,
    "output.quiet": True,
    "output.snapshot_every": 0.0,
    "output.checkpoint_every": 0.0,
    "output.live": False,
}


def scalars(metrics):
    """The metrics a convergence study can take: finite numbers (not flags or lists)."""
    return {
        k: float(v)
        for k, v in metrics.items()
        if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
    }


def study(scene, config, overrides, cfg, summary, out, log=print):
    """Run the two coarser rungs, judge each metric, write the table, the figure and summary.json's
    `convergence`; returns that entry."""
    dx = cfg.numerics.dx
    rungs = [dx, dx * RATIO, dx * RATIO * RATIO]
    sums, refused = [summary], ""
    for d in rungs[1:]:
        sub = os.path.join(out, "convergence", f"dx{d:.4g}")
        ov = dict(overrides or {}, **QUIET, **{"numerics.dx": d, "output.dir": sub})
        log(f"convergence: the case at dx = {d:.4g} m ({sub})")
        try:
            s = simulate(scene, overrides=ov, config=config, out=sub)
        except ConfigError as e:
            refused = f"the rung at dx = {d:.4g} m was refused: {e}"
            break
        if s["status"] != "ok":
            refused = f"the rung at dx = {d:.4g} m ended {s['status']}: {s['message']}"
            break
        sums.append(s)
    entry = {"dx": rungs, "ratio": RATIO, "metrics": {}, "reason": refused}
    if not refused:
        vals = [scalars(s.get("metrics", {})) for s in sums]
        for k in sorted(set(vals[0]) & set(vals[1]) & set(vals[2])):
            entry["metrics"][k] = verdict(k, vals[0][k], vals[1][k], vals[2][k], RATIO, RATIO)
        entry["cost_over_run"] = sum(s["wall_time_s"] for s in sums[1:]) / max(summary["wall_time_s"], 1e-9)
    folder = ensure_dir(os.path.join(out, "convergence"))
    write_text(os.path.join(folder, "convergence.md"), report(entry))
    write_csv(
        os.path.join(folder, "convergence.csv"),
        ("metric", "dx_fine", "fine", "middle", "coarse", "order", "richardson", "gci_fine", "reason"),
        [
            (k, rungs[0], *m["values"], m["order"], m["richardson"], m["gci_fine"], m["reason"])
            for k, m in entry["metrics"].items()
        ],
    )
    if entry["metrics"]:
        figure(entry, os.path.join(folder, "convergence.png"))
    return add_to_summary(out, "convergence", entry)


def add_to_summary(out, key, entry):
    """A study's entry into the run's summary.json, under key; returns the entry."""
    path = os.path.join(out, "summary.json")
    with open(path) as f:
        full = json.load(f)
    full[key] = entry
    write_json(path, full)
    return entry


def fmt(v, spec=".4g"):
    """A number for a table; '-' for none."""
    return "-" if v is None else format(v, spec)


def report(entry):
    dx = entry["dx"]
    lines = [
        "# Convergence",
        "",
        f"The case at dx = {dx[0]:.4g} m and at {dx[1]:.4g} and {dx[2]:.4g} m (ratio {entry['ratio']:g}); "
        "the observed order, Richardson's estimate and the GCI on the finest spacing by Celik et al. (2008)."
        + (
            f" The two coarser runs took {entry['cost_over_run']:.2f} of the run's wall time."
            if "cost_over_run" in entry
            else ""
        ),
        "",
    ]
    if entry["reason"]:
        return "\n".join(lines + [f"No study: {entry['reason']}.", ""])
    lines += [
        "| metric | fine | middle | coarse | order | Richardson | GCI (fine) | why none |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for k, m in entry["metrics"].items():
        why = "; ".join(x for x in (m["reason"], m.get("note", "")) if x)
        lines.append(
            f"| {k} | {' | '.join(fmt(v) for v in m['values'])} | {fmt(m['order'], '.2f')} | "
            f"{fmt(m['richardson'])} | {fmt(m['gci_fine'], '.2%') if m['gci_fine'] is not None else '-'} | {why} |"
        )
    return "\n".join(lines) + "\n"


def panels(names, path, draw, xlabel):
    """One small panel a metric, four to a row: draw(ax, name) fills each; saved to path."""
    from ..measure.plots import pyplot, save

    plt = pyplot()
    cols = min(4, len(names))
    rows = math.ceil(len(names) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.0 * cols, 2.2 * rows + 0.4), squeeze=False)
    for ax, k in zip(axes.flat, names):
        draw(ax, k)
        ax.tick_params(labelsize=6)
        ax.set_xlabel(xlabel, fontsize=6)
    for ax in list(axes.flat)[len(names) :]:
        ax.axis("off")
    save(fig, path)


def figure(entry, path):
    """Each metric against dx, the Richardson estimate at dx = 0 where there is one."""
    dx = entry["dx"]

    def draw(ax, k):
        m = entry["metrics"][k]
        ax.plot(dx, m["values"], "o-", color="C0", ms=4)
        if m["richardson"] is not None and m["order"] is not None:
            ax.plot([0.0], [m["richardson"]], "s", color="C3", ms=4)
            ax.set_title(f"{k}\np = {m['order']:.2f}, GCI {m['gci_fine']:.1%}", fontsize=7)
        else:
            ax.set_title(f"{k}\n{m['reason'].split(':')[0] or 'no study'}", fontsize=7)
        ax.set_xlim(left=0.0)

    panels(list(entry["metrics"]), path, draw, "dx (m)")
