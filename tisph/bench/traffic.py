"""Kernel launches and host-device transfers a step: `python -m tisph.bench --traffic`.

On a GPU every transfer between the host and the device waits for the device to finish what it
was given, and every launch costs microseconds: a step that needs neither lets the host queue
steps ahead. This counts, in the real run loop (runner/loop.py) of one golden case per scene:

- launches: every Taichi kernel called from Python, the ones Taichi runs for to_numpy and
  from_numpy and for a Python-scope element read or write included;
- transfers: each Python-scope read or write of a field element (a read of a struct field is one
  a member), each to_numpy/from_numpy or kernel with a NumPy argument (the array crosses), and
  each kernel that returns a value to the host. A kernel's scalar arguments travel with its
  launch and are not counted apart.

The loop runs as it runs on a GPU: a smooth paddle motion followed on the device by a series
over each batch of steps (engine/access.py, series_fit), where the CPU takes the host's value
every step, and a held current's feedback run by the device (engine/drive.py), where the CPU's
host reads the mean velocity back. A step runs from its step kernel's launch to the next one's: what the host does after it (the
read of a batch of steps, the health check, the backup, a control, the next step's paddle) is
the step's. It "writes nothing" where none of the run's outputs (probes, frames, snapshots,
checkpoints, the scene's events) was written in it. Printed as a table and written to OUT/traffic.md and traffic.json."""

import collections
import contextlib
import importlib
import json
import os
import tempfile

import numpy as np

# one golden case per registered scene, and the cases whose steps have host work of their own
# (a paddle, a drive, a coupled bed, absorption)
CASES = (
    "dam_break",
    "orifice",
    "tank",
    "erodible_bed",
    "poiseuille_bingham",
    "flume",
    "flume_jonswap",
    "beach",
    "beach_bedload",
    "tunnel",
    "tunnel_bedload",
    "pipeline_scour",
    "pipeline_bedload",
    "breakwater",
    "dam_break_custom",
)
STEPS = 200


class Counter:
    """Counts launches by kernel name and transfers by kind while installed (install())."""

    def __init__(self):
        self.launches = collections.Counter()
        self.transfers = collections.Counter()
        self.paused = False  # the count's own reads (whether a step parked) are not the run's

    def snapshot(self):
        return dict(
            mark=self.total(),
            launches=collections.Counter(self.launches),
            transfers=collections.Counter(self.transfers),
        )

    def total(self):
        return sum(self.launches.values()), sum(self.transfers.values())

    @contextlib.contextmanager
    def install(self):
        """Patch Taichi's kernel call and field element accessors; put them back on exit. Field
        accessors made before this are not seen: install before the solver is built."""
        field = importlib.import_module("taichi.lang.field")  # not ti.lang.field: that name is ti.field
        kernel_impl = importlib.import_module("taichi.lang.kernel_impl")
        counter = self
        call, acc_init = kernel_impl.Kernel.__call__, field.SNodeHostAccessor.__init__

        def counted_call(kernel, *args, **kwargs):
            if counter.paused:
                return call(kernel, *args, **kwargs)
            name = kernel.func.__name__
            counter.launches[name] += 1
            if any(isinstance(a, np.ndarray) for a in args):
                counter.transfers[f"array ({name})"] += 1
            if kernel.return_type:
                counter.transfers[f"return ({name})"] += 1
            return call(kernel, *args, **kwargs)

        def counted_init(acc, snode):
            acc_init(acc, snode)
            get, put = acc.getter, acc.setter

            def getter(*key):  # Taichi reads an element with a small kernel of its own
                if counter.paused:
                    return get(*key)
                counter.launches["element read"] += 1
                counter.transfers["element read"] += 1
                return get(*key)

            def setter(value, *key):
                counter.launches["element write"] += 1
                counter.transfers["element write"] += 1
                return put(value, *key)

            acc.getter, acc.setter = getter, setter

        kernel_impl.Kernel.__call__ = counted_call
        field.SNodeHostAccessor.__init__ = counted_init
        try:
            yield self
        finally:
            kernel_impl.Kernel.__call__ = call
            field.SNodeHostAccessor.__init__ = acc_init


def measure(case_id, steps=STEPS, arch="cpu", device_drive=True):
    """Launches and transfers of each of a golden case's first `steps` steps, as its run loop takes
    them (device_drive False: a held current's feedback on the host, as the CPU runs it); returns
    the per-step records and what the costliest quiet step did."""
    from tests.golden.cases import CASES as GOLDEN
    from tests.golden.cases import FAST, ROOT

    from .. import runtime
    from ..runner import Log, Run, build_case, resolve

    _, modname, cfile, ov = next(c for c in GOLDEN if c[0] == case_id)
    scene = importlib.import_module(modname).SCENE
    counter = Counter()
    rows = []
    with tempfile.TemporaryDirectory() as out, counter.install():
        overrides = dict(FAST, **ov, **{"run.max_steps": steps, "output.dir": out, "output.probe_interval": 0.01})
        cfg = resolve(scene, os.path.join(ROOT, cfile) if cfile else None, overrides)
        runtime.init(arch, cfg.run.precision)
        log = Log(os.path.join(out, "run.log"), True)
        case = build_case(scene, cfg, log)
        case.params["paddle_series"] = True  # as a GPU runs it (on the CPU the host gives the paddle,
        case.params["drive_series"] = device_drive  # and runs a held current's feedback,
        case.params["read_elements"] = 0  # and a short batch's log is read element by element,
        case.params["park"] = True  # and a batch of steps stops at the output it was given)
        run = Run(case, cfg, out, log, scene.NAME)
        run.arch = runtime.current_arch()
        wrote = [False]
        for name in ("sample", "frame", "snapshot", "checkpoint", "_still"):
            f = getattr(run, name)
            setattr(run, name, _flagging(f, wrote))
        orig_fire = run.fire_events

        def fire():
            n = len(run.events)
            orig_fire()
            wrote[0] |= len(run.events) != n

        run.fire_events = fire
        last, parked = {}, [0]

        def step_wrapper(step):
            def stepped(*args):
                before = counter.snapshot()
                out = step(*args)
                counter.paused = True
                live = run.solver.stepper.live[None]
                counter.paused = False
                if not live:  # a parked step's launch is the step's that reached the output
                    parked[0] += 1
                    return out
                if last:  # close the previous step: its kernel, the reads and outputs after it
                    rows.append(_row(before, last, wrote[0]))
                last.update(before)
                wrote[0] = False
                return out

            return stepped

        orig_start = run._start

        def start():
            r = orig_start()
            run.solver.stepper.step = step_wrapper(run.solver.stepper.step)
            return r

        run._start = start
        run.execute()
        if last:
            rows.append(_row(counter.snapshot(), last, wrote[0]))
    quiet = [r for r in rows if not r["wrote"]]
    worst = max(quiet, key=lambda r: (r["transfers"], r["launches"])) if quiet else None
    return dict(
        case=case_id,
        scene=scene.NAME,
        particles=len(case.particles),
        steps=len(rows),
        parked=parked[0],
        quiet_steps=len(quiet),
        launches_quiet=_stats([r["launches"] for r in quiet]),
        transfers_quiet=_stats([r["transfers"] for r in quiet]),
        launches_all=_stats([r["launches"] for r in rows]),
        transfers_all=_stats([r["transfers"] for r in rows]),
        worst_quiet=worst,
    )


def _flagging(f, wrote):
    def g(*a, **k):
        wrote[0] = True
        return f(*a, **k)

    return g


def _row(now, last, wrote):
    return dict(
        launches=now["mark"][0] - last["mark"][0],
        transfers=now["mark"][1] - last["mark"][1],
        wrote=wrote,
        which=dict(now["launches"] - last["launches"]),
        what=dict(now["transfers"] - last["transfers"]),
    )


def _stats(v):
    return dict(mean=float(np.mean(v)), min=int(min(v)), max=int(max(v))) if v else None


def table(results):
    lines = [
        "| case | scene | particles | quiet steps | launches a quiet step (mean, max) | transfers a quiet step "
        "(mean, max) | launches a step, all (mean) | transfers a step, all (mean) | parked launches |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        lq, tq = r["launches_quiet"], r["transfers_quiet"]
        lines.append(
            f"| {r['case']} | {r['scene']} | {r['particles']:,} | {r['quiet_steps']} of {r['steps']} | "
            f"{lq['mean']:.2f}, {lq['max']} | {tq['mean']:.2f}, {tq['max']} | "
            f"{r['launches_all']['mean']:.2f} | {r['transfers_all']['mean']:.2f} | {r['parked']} |"
        )
    return "\n".join(lines)


def main(a):
    import sys

    from ..io import ensure_dir

    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    if not os.path.isdir(os.path.join(root, "tests", "golden")):
        raise SystemExit("--traffic runs the golden cases of a source checkout (tests/golden): run it from one")
    sys.path.insert(0, root)
    names = [c for c in CASES if not a.only or any(w in c for w in a.only)]
    steps = 40 if a.dry_run else STEPS
    results = []
    for c in names:
        r = measure(c, steps, a.arch, not a.host_drive)
        results.append(r)
        w = r["worst_quiet"]
        print(
            f"{c}: quiet steps {r['quiet_steps']}/{r['steps']}, launches {r['launches_quiet']}, transfers "
            f"{r['transfers_quiet']}; the costliest quiet step: {w and w['which']} {w and w['what']}",
            flush=True,
        )
    ensure_dir(a.out)
    with open(os.path.join(a.out, "traffic.json"), "w") as f:
        json.dump(results, f, indent=1)
    text = table(results)
    with open(os.path.join(a.out, "traffic.md"), "w") as f:
        f.write(text + "\n")
    print(text)
    return 0
