"""Sweeps and ensembles on Dask distributed: many ordinary scene runs, one per combination of
the swept values, each in OUT/<case-id>/ with all its usual files.

    python -m tisph.sweep SCENE [--config FILE] --set KEY=V1,V2,... [--set KEY=...] [--zip]
                          [--scheduler ADDRESS] [--workers N] [--threads-per-worker T]
                          [--seeds N] [--out DIR] [--resume] [--arch cpu|gpu|auto]

The product of the --set lists (or the lists side by side with --zip). Without --scheduler a
dask.distributed LocalCluster of --workers processes runs them (default: cores / threads per
worker); with --scheduler tcp://host:8786 an existing cluster does. Each worker process
initialises Taichi once with cpu_max_num_threads = --threads-per-worker. Every key and value is
validated before anything is submitted (exit 2, as a scene does). A case that fails (bad
physics, instability, a killed worker) is reported in the table and the others go on; --resume
skips the cases whose summary.json is complete and whose inputs match. Writes OUT/sweep.csv,
OUT/sweep.md and OUT/sweep.png (each metric against the swept values); with --seeds N, each combination with N
seeds of its random bed, and OUT/ensemble.md and .csv (each metric's mean and standard error).
"""

import argparse
import hashlib
import itertools
import json
import os
import sys
import time

from . import registry as scenes
from .io import OutputError, ensure_dir, write_json
from .runner import resolve, simulate
from .runner.sweep_report import write_ensemble, write_tables
from .settings.config import ConfigError, tomllib

CASE_FILE = "sweep_case.json"  # what a case folder was run with: --resume compares it


def scene_named(name):
    """The Scene registered as NAME (tisph.registry.REGISTRY), or a ConfigError naming the choices."""
    try:
        return scenes.load(name)
    except ConfigError as e:
        raise ConfigError("SCENE", name, e.allowed) from None


def parse_value(text):
    """A --set value as TOML reads it (0.3, 4, true, "piston"); a bare word is a string."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def parse_sets(items):
    """['geometry.depth=0.3,0.4', ...] -> [('geometry.depth', [0.3, 0.4]), ...]"""
    out = []
    for it in items:
        key, sep, vals = it.partition("=")
        if not sep or not key or not vals:
            raise ConfigError("--set", it, "KEY=V1,V2,... (a dotted config key and its values)")
        out.append((key.strip(), [parse_value(v.strip()) for v in vals.split(",")]))
    return out


def combinations(sets, zipped=False):
    keys = [k for k, _ in sets]
    if zipped:
        n = {len(v) for _, v in sets}
        if len(n) > 1:
            raise ConfigError("--zip", [f"{k}: {len(v)}" for k, v in sets], "--set lists of equal length")
        rows = zip(*[v for _, v in sets])
    else:
        rows = itertools.product(*[v for _, v in sets])
    return [dict(zip(keys, r)) for r in rows]


def case_id(k, values):
    """A folder name: the case number and each swept key's last part and value."""
    parts = [f"{key.split('.')[-1]}={v}" for key, v in values.items()]
    slug = "_".join(parts)
    slug = "".join(c if (c.isalnum() or c in "=._-") else "-" for c in slug)[:80]
    return f"{k:03d}_{slug}" if slug else f"{k:03d}"


def file_digest(path):
    if not path:
        return ""
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def plan(scene, config, sets, zipped, out, base=None):
    """The cases, each validated: [(id, swept values, overrides)]; a ConfigError on the first bad
    key or value, before anything runs."""
    cases = []
    for k, values in enumerate(combinations(sets, zipped)):
        ov = dict(base or {})
        ov.update(values)
        cid = case_id(k, values)
        ov["output.dir"] = os.path.join(out, cid)
        resolve(scene, config, ov)  # raises ConfigError naming the key
        cases.append((cid, values, ov))
    return cases


def is_done(out, cid, inputs):
    """A case folder whose summary.json is complete and whose inputs match."""
    d = os.path.join(out, cid)
    try:
        with open(os.path.join(d, "summary.json")) as f:
            s = json.load(f)
        with open(os.path.join(d, CASE_FILE)) as f:
            old = json.load(f)
    except (OSError, ValueError):
        return None
    return s if old == inputs and "status" in s else None


# ---------------------------------------------------------------- what a worker runs
def run_case(scene_name, config, overrides, arch, threads):
    """One case on a worker: the ordinary scene run. Returns (status, message, summary or None).
    Taichi is initialised once per worker process with `threads` CPU threads."""
    os.environ.setdefault("TISPH_THREADS", str(threads))
    scene = scene_named(scene_name)
    ov = dict(overrides)
    ov["run.arch"] = arch
    ov.setdefault("output.quiet", True)
    try:
        s = simulate(scene, ov, config=config)
    except (ConfigError, OutputError) as e:
        return "error", str(e), None
    except Exception as e:  # any other failure is this case's, not the sweep's
        return "error", f"{type(e).__name__}: {e}", None
    return s["status"], s.get("message", ""), s


def start_client(scheduler, workers, threads):
    from dask.distributed import Client, LocalCluster

    if scheduler:
        return Client(scheduler), None
    n = workers or max(1, (os.cpu_count() or 1) // threads)
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0", silence_logs=40)
    return Client(cluster), cluster


def execute(tasks, client, progress=True):
    """Submit (key, fn, args) tasks; return {key: what fn returned} as they finish. A task that
    raised, or whose worker died, is ("error", the scheduler's message, None)."""
    from dask.distributed import as_completed

    futs = {client.submit(fn, *args, key=f"tisph-{key}-{time.time_ns()}", pure=False): key for key, fn, args in tasks}
    bar = None
    if progress:
        try:
            from tqdm import tqdm

            bar = tqdm(total=len(futs), unit="case", file=sys.stderr, disable=None)
        except ImportError:
            bar = None
    results, failed = {}, 0
    try:
        for fut in as_completed(list(futs)):
            key = futs[fut]
            try:
                res = fut.result()
            except Exception as e:  # KilledWorker, a lost scheduler, ...
                res = ("error", f"{type(e).__name__}: {e}", None)
            results[key] = res
            failed += isinstance(res, tuple) and res[0] != "ok"
            if bar is not None:
                running = sum(1 for f in futs if f.status == "pending")
                bar.set_postfix_str(f"running {min(running, len(client.ncores()))}, failed {failed}", refresh=False)
                bar.update(1)
    except KeyboardInterrupt:
        for f in futs:
            f.cancel()
        raise
    finally:
        if bar is not None:
            bar.close()
    return results


def seed_set(scene, config, sets, n):
    """--seeds N as one more swept key: the bed's seed (sediment.seed) or, where the case has no
    random bed, the start's perturbation (run.seed, every run with run.perturbation set:
    runner/ensemble.py), from the case's own seed on. Returns the swept (key, values) pairs."""
    from .runner.ensemble import check_seeds, seed_key, seeds_of

    cfg = resolve(scene, config, {})
    check_seeds(cfg, n)
    key, also = seed_key(cfg)
    if any(k == key for k, _ in sets):
        raise ConfigError("--set", key, f"--seeds N or {key} in --set, not both")
    return [(key, seeds_of(cfg, n)), *((k, [v]) for k, v in also.items() if all(k != s for s, _ in sets))]


# ---------------------------------------------------------------- the command
def make_parser():
    p = argparse.ArgumentParser(
        prog="python -m tisph.sweep", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument(
        "scene",
        help="a scene: dam_break, hatch, tank, flume, beach, tunnel, erodible_bed, pipeline_scour, or poiseuille",
    )
    p.add_argument("--config", metavar="FILE", help="TOML case file every case starts from")
    p.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=V1,V2,...",
        help="a config key and the values to sweep (repeat for more keys)",
    )
    p.add_argument(
        "--seeds",
        type=int,
        default=0,
        metavar="N",
        help="each combination with N seeds of its random bed (sediment.seed and the next N - 1), or of a "
        "perturbation of its start where it has none (run.seed, run.perturbation): "
        "OUT/ensemble.md and .csv give each metric's mean, standard deviation and standard error",
    )
    p.add_argument("--zip", action="store_true", help="take the --set lists side by side, not their product")
    p.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler (tcp://host:8786)")
    p.add_argument("--workers", type=int, default=0, help="local worker processes (default: cores / threads)")
    p.add_argument("--threads-per-worker", type=int, default=1, help="Taichi CPU threads per worker")
    p.add_argument("--out", metavar="DIR", help="output folder (default renders/sweep_<scene>/)")
    p.add_argument("--resume", action="store_true", help="skip cases already complete with the same inputs")
    p.add_argument("--arch", choices=("cpu", "gpu", "auto"), default="cpu", help="Taichi backend on the workers")
    p.add_argument("--render", action="store_true", help="let each case write its movie (default: off)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    return p


def main(argv=None):
    args = make_parser().parse_args(argv)
    out = os.path.abspath(args.out or os.path.join("renders", f"sweep_{args.scene}"))  # workers may run elsewhere
    try:
        if args.threads_per_worker < 1:
            raise ConfigError("--threads-per-worker", args.threads_per_worker, "at least 1")
        if args.workers < 0:
            raise ConfigError("--workers", args.workers, "0 (auto) or more")
        scene = scene_named(args.scene)
        sets = parse_sets(args.set)
        if args.seeds:
            sets.extend(seed_set(scene, args.config, sets, args.seeds))
        if not sets:
            raise ConfigError("--set", None, "at least one KEY=V1,V2,... (or --seeds N)")
        base = {} if args.render else {"output.render": False}
        cases = plan(scene, args.config, sets, args.zip, out, base)
        ensure_dir(out)
    except (ConfigError, OutputError) as e:
        print(f"python -m tisph.sweep: {e}", file=sys.stderr)
        return 2
    digest = file_digest(args.config)
    results, todo = {}, []
    for cid, values, ov in cases:
        inputs = dict(scene=args.scene, config_sha256=digest, overrides=ov)
        done = is_done(out, cid, inputs) if args.resume else None
        if done is not None:
            results[cid] = (done["status"], "kept (--resume)", done)
            continue
        ensure_dir(os.path.join(out, cid))
        write_json(os.path.join(out, cid, CASE_FILE), inputs)
        todo.append((cid, run_case, (args.scene, args.config, ov, args.arch, args.threads_per_worker)))
    t0 = time.perf_counter()
    client = cluster = None
    code = 0
    try:
        if todo:
            client, cluster = start_client(args.scheduler, args.workers, args.threads_per_worker)
            results.update(execute(todo, client, progress=not args.quiet))
    except KeyboardInterrupt:
        print(
            "python -m tisph.sweep: interrupted; the finished cases are complete, --resume runs the rest",
            file=sys.stderr,
        )
        code = 130
    except OSError as e:
        print(f"python -m tisph.sweep: cannot reach the Dask scheduler {args.scheduler!r}: {e}", file=sys.stderr)
        code = 2
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
    write_tables(out, cases, results, args.scene, time.perf_counter() - t0)
    if args.seeds:
        write_ensemble(out, cases, results)
    if not args.quiet:
        bad = [c for c, r in results.items() if r[0] != "ok"]
        print(
            f"wrote {out}/sweep.csv, sweep.md, sweep.png: {len(results)} of {len(cases)} cases, {len(bad)} not ok",
            file=sys.stderr,
        )
    return code


if __name__ == "__main__":
    sys.exit(main())
