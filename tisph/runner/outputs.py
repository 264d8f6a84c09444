"""What a run writes while it goes: probes, frames, stills, snapshots, the XDMF index,
checkpoints, and reading a checkpoint back. A mixin of run.loop.Run."""

import json
import math
import os
import pickle
import time as time_mod

import numpy as np

from .. import __version__
from ..io import SNAPSHOT_FIELDS, OutputError, atomic_path, ensure_dir, load, write_csv, write_snapshot, write_xdmf
from ..settings.config import ConfigError, dump_toml
from ..settings.config import tomllib as _toml
from ..viz.render import STATE
from .setup import config_changes, run_settings

FLUSH_S = 0.5  # wall seconds between rewrites of probes.csv and run.log during a run


class _Ref:
    """Stands for another persisted observer in a checkpoint (an attribute that points at it)."""

    def __init__(self, k):
        self.k = k


def observer_state(persist):
    """The observers' history as bytes (pickle: a checkpoint is tisph's own file, read back by
    tisph): lists and dicts by content, other objects by their attributes; an attribute that is
    another persisted observer is kept as a reference to it, so a restart rewires it to the live
    object instead of a stale copy."""
    ids = {id(o): k for k, o in enumerate(persist)}
    out = []
    for o in persist:
        if isinstance(o, (list, dict)):
            out.append(list(o) if isinstance(o, list) else dict(o))
        else:
            out.append({a: (_Ref(ids[id(v)]) if id(v) in ids else v) for a, v in vars(o).items()})
    return pickle.dumps(out)


def restore_observers(persist, blob):
    """Put a checkpoint's observer history back into the same objects (in place, so the scene's
    closures and methods see it)."""
    states = pickle.loads(blob)
    if len(states) != len(persist):
        raise ConfigError(
            "--restart", "observers", f"a checkpoint of this case ({len(persist)} observers)", f"it holds {len(states)}"
        )
    for o, st in zip(persist, states):
        if isinstance(o, list):
            o[:] = st
        elif isinstance(o, dict):
            o.clear()
            o.update(st)
        else:
            vars(o).update({a: (persist[v.k] if isinstance(v, _Ref) else v) for a, v in st.items()})


class Outputs:
    # -------------------------------------------------------------- outputs
    def _still(self, state, t):
        ensure_dir(os.path.join(self.out, "stills"))
        self.frames.draw(os.path.join(self.out, "stills", f"t{t:.3f}.png"), state, state["t"], movie=False)

    def fire_events(self):
        while self.events and self.solver.time >= self.events[0][0] - 1e-12:
            t, cb = self.events.pop(0)
            st = self.solver.state(("x", "v", "kind", "rho", "p", "m", "mat") + self.solver.optional_members)
            st["t"] = self.solver.time  # the actual time, at or just after the scheduled t
            st["out"] = self.out
            cb(st, t)

    def sample(self):
        self.solver.sync_drive()  # a probe may read the drive's controller
        st = self.solver.state(("x", "v", "kind", "rho", "p", "m", "mat"))
        st["t"] = self.solver.time
        self.solver.sample_density_error(st)
        row = (self.solver.time,) + (
            tuple(float(v) for v in self.case.observers.probe(st)) if self.case.observers.probe else ()
        )
        self.probes.append(row)
        self.flush_series()

    def flush_series(self, force=False):
        """probes.csv and run.log as they stand, each written whole (temporary name, rename), at
        most every FLUSH_S of wall time: a run killed with -9 keeps all but its last moments."""
        now = time_mod.perf_counter()
        if not force and now - self._flushed_at < FLUSH_S:
            return
        self._flushed_at = now
        self.write_probes()
        self.log.flush()

    def write_probes(self):
        """probes.csv: t and the scene's probe columns, every sample so far."""
        write_csv(os.path.join(self.out, "probes.csv"), self.probe_columns(), self.probes)

    def probe_columns(self):
        return ("t",) + tuple(self.case.observers.probe_columns)

    def frame(self):
        s = self.solver
        self.frames.draw(
            os.path.join(self.out, "frames", f"{self.frame_no:05d}.png"), s.state(STATE + s.optional_members), s.time
        )
        self.frame_no += 1

    def snapshot_attrs(self, time, step, dt):
        return dict(
            scene=self.name,
            tisph_version=__version__,
            config=dump_toml(self.cfg),
            time=float(time),
            step=int(step),
            dt=float(dt),
            material_names=", ".join(f"{i} {m.get('name', '')}" for i, m in enumerate(self.case.materials)),
        )

    def snapshot(self, state=None, name=None, time=None, step=None):
        s = self.solver
        state = state if state is not None else s.state(s.snapshot_members)
        time = s.time if time is None else time
        step = s.steps if step is None else step
        name = name or f"{len(self.snapshots):05d}.h5"
        path = os.path.join(self.out, "snapshots", name)
        write_snapshot(path, state, self.snapshot_attrs(time, step, s.dt))
        if name[0].isdigit():
            shapes = {}
            for k, a in state.items():
                a = np.asarray(a)
                shape = (a.shape[0], 3) if a.ndim == 2 else a.shape
                shapes[SNAPSHOT_FIELDS.get(k, (k,))[0]] = (shape, a.dtype.str)
            self.snapshots.append((float(time), f"snapshots/{name}", s.n, shapes))
            self._xdmf_dirty = True
            # the XDMF lists every snapshot, so rewriting it each time is quadratic: at most every 2 s
            if len(self.snapshots) <= 20 or time_mod.perf_counter() - self._xdmf_at > 2.0:
                self.write_xdmf()

    def write_xdmf(self):
        if self._xdmf_dirty:
            write_xdmf(
                os.path.join(self.out, "snapshots.xdmf"),
                [(t, rel, n, {k: (v[0], np.dtype(v[1])) for k, v in sh.items()}) for t, rel, n, sh in self.snapshots],
            )
            self._xdmf_dirty = False
            self._xdmf_at = time_mod.perf_counter()

    def checkpoint(self, path=None):
        import h5py

        path = path or os.path.join(self.out, "checkpoint.h5")
        if self.frames is not None:
            self.frames.sync()  # the frames it counts on disk first
        arrays, scal = self.solver.raw_state()
        self.solver.sync_drive()  # the controller's state with the observers'
        try:
            with atomic_path(path) as tmp, h5py.File(tmp, "w") as f:
                g = f.create_group("particles")
                for k, a in arrays.items():
                    g.create_dataset(k, data=a)
                f.create_dataset("probes", data=np.array(self.probes, float).reshape(len(self.probes), -1))
                f.create_dataset("observers", data=np.frombuffer(observer_state(self.case.observers.persist), np.uint8))
                for k, v in scal.items():
                    f.attrs[k] = v
                f.attrs.update(
                    dict(
                        kind="tisph checkpoint",
                        scene=self.name,
                        tisph_version=__version__,
                        config=dump_toml(self.cfg),
                        frame_no=self.frame_no,
                        next=json.dumps(self.next),
                        snapshots=json.dumps(self.snapshots),
                        wall_time_s=self.wall_so_far(),
                        step_time_s=self.step_s_so_far(),
                    )
                )
        except OSError as e:
            raise OutputError(f"cannot write checkpoint {path!r}: {e}") from None
        self.log(f"checkpoint at step {self.solver.steps}, t = {self.solver.time:.6g} s: {path}", file_only=True)
        return path

    def resume(self):
        """Load self.restart into the solver and the run's own state."""
        arrays, attrs = load(self.restart)
        if attrs.get("kind") != "tisph checkpoint" or "particles" not in arrays:
            raise ConfigError("--restart", self.restart, "a checkpoint.h5 written by tisph")
        if attrs.get("scene") != self.name:
            raise ConfigError(
                "--restart",
                self.restart,
                f"a checkpoint of scene {self.name!r}",
                f"it is a checkpoint of {attrs.get('scene')!r}",
            )
        old = _toml.loads(attrs["config"])
        changes = config_changes(run_settings(old), run_settings(self.cfg))
        if changes and not self.force:
            raise ConfigError(
                "--restart",
                self.restart,
                "the config the checkpoint was written with (or pass --force)",
                "changed: " + "; ".join(changes),
            )
        if changes:
            self.log("warning: restarting with a changed config: " + "; ".join(changes), always=True)
        try:
            self.solver.load_raw_state(arrays["particles"], attrs)
        except ValueError as e:
            raise ConfigError("--restart", self.restart, "a checkpoint of this case", str(e)) from None
        self.probes = [tuple(r) for r in np.asarray(arrays["probes"]).tolist()]
        if "observers" in arrays:
            restore_observers(self.case.observers.persist, np.asarray(arrays["observers"], np.uint8).tobytes())
        self.wall_before = float(attrs.get("wall_time_s", 0.0))
        self.step_before = float(attrs.get("step_time_s", 0.0))
        self.frame_no = int(attrs["frame_no"])
        self.next = json.loads(attrs["next"])
        self.snapshots = [tuple(x) for x in json.loads(attrs["snapshots"])]
        self.log(f"restarted from {self.restart} at step {self.solver.steps}, t = {self.solver.time:.6g} s")

    @property
    def next_output(self):
        """Time of the next output that is switched on (an off output never advances its entry)."""
        on = {
            "probe": self.probe_dt,
            "frame": self.frame_dt if self.render else 0.0,
            "snapshot": self.snap_dt,
            "checkpoint": self.ckpt_dt,
        }
        due = [self.next[k] for k, dt in on.items() if dt > 0]
        return min(due) if due else float("inf")

    def _due(self, key, interval):
        """Whether an output is due now; schedules the next one on the interval grid."""
        if interval <= 0 or self.solver.time < self.next[key] - 1e-12:
            return False
        k = math.floor(self.solver.time / interval + 1e-9) + 1
        self.next[key] = k * interval
        return True
