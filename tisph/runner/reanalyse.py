"""`tisph metrics RUN`: a run's metrics worked out again from what it wrote, without running it.

The case is rebuilt from the resolved config at the head of RUN/run.log (its particles are laid,
nothing compiles) and its metrics are computed from RUN/probes.csv's columns, as the run computed
them at its end (runner/summary.py); each is set beside summary.json's, which it leaves as it is
(after a change to how a metric is worked out, the new value is printed beside the run's). What
the run's final state gave (final_metrics) is not in the probes. A metric that reads what the run
kept besides its probes (a bed below particle scale: the probes hold only its statistics; the
flume's gauges' zero offsets) cannot be worked out again this way and is said to be "not in the
probes" or to differ (docs/scenes.md)."""

import argparse
import json
import math
import os
import warnings

import numpy as np

from .. import registry
from ..errors import ConfigError
from ..io import read_csv
from .reading import rebuild

RTOL = 1e-6  # probes.csv keeps 9 significant digits


def run_config(run_dir):
    """The resolved config's TOML text at the head of run.log (runner/start.py writes it)."""
    path = os.path.join(run_dir, "run.log")
    if not os.path.isfile(path):
        raise ConfigError("RUN", run_dir, "a run's folder with its run.log")
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    if not lines or lines[0] != "# resolved config":
        raise ConfigError("RUN", path, "a run.log that starts with the resolved config")
    body, after_blank = [], False
    for ln in lines[1:]:  # tables apart by blank lines; what follows the last is the log
        if ln.startswith("# ") or (after_blank and ln and not ln.startswith("[")):
            break
        after_blank = not ln
        body.append(ln)
    return "\n".join(body)


def _same(a, b):
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        if not (math.isfinite(a) and math.isfinite(b)):
            return (math.isnan(a) and math.isnan(b)) or a == b
        return abs(a - b) <= RTOL * max(abs(a), abs(b), 1e-30)
    if b is None and isinstance(a, float) and not math.isfinite(a):
        return True  # summary.json writes a missing value as null
    return a == b


def _empty(v):
    """No value: what a metric gives when what it reads is not in the probes."""
    if isinstance(v, (list, tuple)):
        return all(_empty(x) for x in v)
    return v is None or (isinstance(v, float) and math.isnan(v))


def _plain(v):
    if isinstance(v, (np.floating, np.integer)):
        return v.item()
    if isinstance(v, (list, tuple, np.ndarray)):
        return [_plain(x) for x in v]
    return v


def reanalyse(run_dir):
    """(summary, {metric: (stored, recomputed, verdict)}) of the run in run_dir; verdict: "same",
    "differs", or "not in the probes" (it comes out empty where the run's had a value)."""
    with open(os.path.join(run_dir, "summary.json"), encoding="utf-8") as f:
        summary = json.load(f)
    name = summary.get("scene", "")
    if name not in registry.REGISTRY:
        raise ConfigError("RUN", run_dir, "a run of a scene tisph has", f"its summary names {name!r}")
    scene = registry.load(name)
    _, case = rebuild(scene, run_config(run_dir))
    header, cols = read_csv(os.path.join(run_dir, "probes.csv"))
    obs = case.observers
    if tuple(header[1:]) != tuple(obs.probe_columns):
        raise ConfigError(
            "RUN",
            run_dir,
            "probes.csv with the columns this version of the scene writes",
            f"it has {', '.join(header[1:])}",
        )
    arr = {c: np.array(v, float) for c, v in cols.items()}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        new = {k: _plain(v) for k, v in (obs.metrics(arr) if obs.metrics else {}).items()}
    stored = summary.get("metrics", {})

    def verdict(old, v):
        if _same(v, old):
            return "same"
        return "not in the probes" if _empty(v) and not _empty(old) else "differs"

    return summary, {k: (stored.get(k), v, verdict(stored.get(k), v)) for k, v in new.items()}


def _fmt(v):
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, list):
        return "[" + ", ".join(_fmt(x) for x in v) + "]"
    return str(v)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tisph metrics", description=__doc__.split("\n\n")[0])
    ap.add_argument("run", metavar="RUN", help="a run's folder (its summary.json, run.log and probes.csv)")
    a = ap.parse_args(argv)
    summary, rows = reanalyse(a.run)
    width = max((len(k) for k in rows), default=6)
    print(f"{'metric':{width}s}  {'in summary.json':>22s}  {'from probes.csv':>22s}")
    for k, (old, new, v) in rows.items():
        print(f"{k:{width}s}  {_fmt(old):>22s}  {_fmt(new):>22s}  {v.upper() if v == 'differs' else v}")
    differ = [k for k, (_, _, v) in rows.items() if v == "differs"]
    missing = [k for k, (_, _, v) in rows.items() if v == "not in the probes"]
    print(
        f"{sum(v == 'same' for _, _, v in rows.values())} of {len(rows)} the same (relative {RTOL:g})"
        + (f"; differing: {', '.join(differ)}" if differ else "")
        + (f"; not in the probes: {', '.join(missing)}" if missing else "")
    )
    return 0
