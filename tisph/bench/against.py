"""Time to the same error against another revision: validation cases run whole on this tree and on
REV, back to back.

    python -m tisph.bench --validate --against REV --only WORD [WORD ...] [--dx DX] [--repeats N]

Every case an --only word names (a word of its name in the validation table) runs at --dx (default the
spacing its table row reports) on this tree and on REV (a temporary git worktree), alternately,
every other pair REV first, --repeats pairs, each run a whole process on every core, as the
validation table runs it alone (each tree its own case file and its own error). Where the two
trees reach the same error, the median of the pairs' wall-time ratios is the speed-up in the time
to that error; where the errors differ, both are reported and the ratio is only a cost ratio.
Writes OUT/against.md and OUT/against.csv.
"""

import json
import os
import statistics
import subprocess
import sys
import tempfile

from ..io import ensure_dir, write_csv, write_text
from .common import ROOT, named
from .speed import remove_worktree, worktree

# run in the tree under test: its own validation table (an older tree kept it in validate.py)
CHILD = """
import json, sys, tempfile
from tisph.bench import validate
name, dx = sys.argv[1], float(sys.argv[2])
hit = [c for c in validate.CASES if c.name.lower() == name.lower()]
if not hit:
    sys.exit(f"no validation case is named {name!r} in this tree")
case = hit[0]
with tempfile.TemporaryDirectory() as d:
    r = validate.run_one(case, dx if dx > 0 else case.ladder[-1], d, False)
print(json.dumps(dict(case=case.name, dx=r["dx"], particles=r["particles"], steps=r["steps"],
                      wall=r["wall"], error=r["error"])))
"""


def run_tree(tree, name, dx):
    """One whole validation run of the case named `name` in a fresh process on the tree at `tree`."""
    env = dict(os.environ, PYTHONPATH=tree)
    r = subprocess.run(
        [sys.executable, "-c", CHILD, name, str(dx or 0.0)], cwd=tree, capture_output=True, text=True, env=env
    )
    if r.returncode != 0:
        raise RuntimeError(f"{name} on {tree}: {(r.stderr or r.stdout).strip()[-800:]}")
    return json.loads(r.stdout.strip().splitlines()[-1])


def case_names(words):
    """Every validation case whose name contains one of the --only words, in the table's order, as
    --validate --only runs them (exit 2 naming a word that names none)."""
    from .validation_cases import CASES

    for w in words:
        if not named(CASES, [w]):
            names = "; ".join(c.name for c in CASES)
            print(
                f"python -m tisph.bench: error: --only {w!r}: no validation case's name contains it ({names})",
                file=sys.stderr,
            )
            raise SystemExit(2)
    return [c.name for c in named(CASES, words)]


def run(a, log):
    names = case_names(a.only or [])
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        old = worktree(a.against, tmp)
        try:
            for name in names:
                new, rev = [], []
                for k in range(a.repeats):
                    order = ((old, rev), (ROOT, new)) if k % 2 else ((ROOT, new), (old, rev))
                    for tree, into in order:
                        try:
                            into.append(run_tree(tree, name, a.dx))
                        except RuntimeError as e:  # a case REV lacks, or a run that failed: said, not a traceback
                            raise SystemExit(f"python -m tisph.bench --validate --against: {e}") from None
                    log(
                        f"{new[-1]['case']}: {new[-1]['wall']:.1f} s (error {new[-1]['error']:.4g}), "
                        f"{a.against}: {rev[-1]['wall']:.1f} s (error {rev[-1]['error']:.4g})"
                    )
                rows.append(summary(new, rev))
        finally:
            remove_worktree(old)
    return rows


def summary(new, rev):
    """One case's row: walls, errors, and the median of the pairs' ratios (REV's time / this tree's)."""
    same = all(n["error"] == r["error"] for n, r in zip(new, rev))
    ratios = [r["wall"] / n["wall"] for n, r in zip(new, rev)]
    return dict(
        case=new[0]["case"],
        dx=new[0]["dx"],
        particles=new[0]["particles"],
        steps=new[0]["steps"],
        steps_against=rev[0]["steps"],
        wall=statistics.median(n["wall"] for n in new),
        wall_against=statistics.median(r["wall"] for r in rev),
        error=new[0]["error"],
        error_against=rev[0]["error"],
        same_error=same,
        speedup=statistics.median(ratios),
        speedup_min=min(ratios),
        speedup_max=max(ratios),
        pairs=len(new),
    )


def report(a, rows):
    lines = [
        f"# Time to the same error: this tree against {a.against}",
        "",
        f"Whole validation runs, one at a time on every core, alternating with {a.against} "
        f"({a.repeats} pairs a case; the median wall time of each, and of the pairs' ratios).",
        "",
        f"| case | dx | particles | steps (this / {a.against}) | error (this / {a.against}) | wall s (this / "
        f"{a.against}) | speed-up, median (range) |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        ratio = f"{r['speedup']:.2f}x ({r['speedup_min']:.2f}-{r['speedup_max']:.2f})"
        lines.append(
            f"| {r['case']} | {r['dx']:g} | {r['particles']:,} | {r['steps']:,} / {r['steps_against']:,} | "
            f"{r['error']:.4g} / {r['error_against']:.4g} | {r['wall']:.1f} / {r['wall_against']:.1f} | "
            + (ratio if r["same_error"] else f"{ratio}: a cost ratio (the errors differ)")
            + " |"
        )
    return "\n".join(lines) + "\n"


def main(a):
    ensure_dir(a.out)
    rows = run(a, lambda m: print(m, flush=True))
    keys = list(rows[0]) if rows else []
    write_csv(os.path.join(a.out, "against.csv"), keys, [[r[k] for k in keys] for r in rows])
    text = report(a, rows)
    write_text(os.path.join(a.out, "against.md"), text)
    print(text)
    return 0
