"""What the benchmark tools share: the source tree they run, one case run, and their Markdown tables."""

import importlib
import os
import sys
import time

from ..runner import simulate

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# the codes the peers' benches run beside tisph (tisph/bench/peers/)
PEERS = ("pysph", "dualsphysics")


def peers(name):
    """A module of tisph/bench/peers/: the benches that build DualSPHysics and install PySPH to run
    them beside tisph. They build and install other codes, so the wheel leaves them out; they run
    from a clone of tisph's source (pip install -e .)."""
    try:
        return importlib.import_module(f"{__package__}.peers.{name}")
    except ModuleNotFoundError as e:
        if not (e.name or "").startswith(f"{__package__}.peers"):
            raise
        print(
            f"error: --peer and --waves run the peers' benches (tisph/bench/peers/), which build DualSPHysics and "
            f"install PySPH: they come with a clone of tisph's source (pip install -e .), not with the installed "
            f"package {os.path.dirname(os.path.dirname(os.path.abspath(__file__)))}",
            file=sys.stderr,
        )
        raise SystemExit(2) from None


def this_tree_env():
    """The environment of a child Python process that imports this tree's tisph."""
    return dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))


def cache_dir():
    """Where the peers are built or installed, once: $XDG_CACHE_HOME/tisph/peers."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "tisph", "peers")


def named(cases, words):
    """The cases whose name contains one of the words (any case), in their order; every case where
    there are no words (the benches' --only)."""
    return [c for c in cases if not words or any(w.lower() in c.name.lower() for w in words)]


def table(header, rows):
    """A Markdown table."""
    md = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    md += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(md)


def run_case(case, dx, quick, out):
    """One run of a benchmark or validation case (scene, config, overrides, quick_overrides) at dx,
    without pictures or snapshots, into out: (summary, wall seconds)."""
    ov = {"output.render": False, "output.quiet": True, "output.snapshot_every": 0.0, "numerics.dx": dx}
    ov.update(case.overrides)
    if quick:
        ov.update(case.quick_overrides)
    cfg = os.path.join(ROOT, "scenes", case.config) if case.config else None
    t0 = time.perf_counter()
    s = simulate(importlib.import_module(f"tisph.{case.scene}"), ov, out=out, config=cfg)
    if s["status"] == "interrupted":  # Ctrl-C or a kill stops the whole bench, not this case alone
        raise SystemExit(143 if "SIGTERM" in s.get("message", "") else 130)
    return s, time.perf_counter() - t0
