"""The time loop of one run: build the solver, step it, check its health, call the outputs,
stop cleanly on instability or a signal."""

import math
import os
import signal as _signal
import sys
import time

from ..case import Case
from ..io import clean_stale_parts, ensure_dir
from ..particles import FLUID
from ..viz.live import LiveWindow
from ..viz.render import make_renderer
from .frames import open_frames
from .outputs import Outputs
from .setup import Log, SimulationError, describe_instability
from .summary import summarize

# a run that will write more than this warns at its start
DISK_WARN_BYTES = 1e9
# snapshots a run writes by default (output.snapshot_every = -1): enough to view its evolution in
# ParaView or tisph.view, few enough that a default run of every scene stays under 200 MB
DEFAULT_SNAPSHOTS = 50


def default_snapshot_interval(cfg):
    """output.snapshot_every = -1: about DEFAULT_SNAPSHOTS over the run, on the frame times (a whole
    number of frame intervals)."""
    f = cfg.output.frame_interval
    return f * max(1, math.ceil(cfg.run.end_time / DEFAULT_SNAPSHOTS / f - 1e-9))


def run_title(cfg, scene_name):
    """What the frames, the movie and the window are called: the case file's name (my_bar.toml:
    my_bar.mp4), else the scene's."""
    case_file = getattr(cfg, "case_file", "")
    return os.path.splitext(os.path.basename(case_file))[0] if case_file else scene_name


class Run(Outputs):
    """One simulation run: the time loop and everything it writes."""

    def __init__(self, case: Case, cfg: dict, out: str, log: Log, scene_name: str, restart=None, force=False):
        self.case, self.cfg, self.out, self.log, self.name = case, cfg, out, log, scene_name
        self.title = run_title(cfg, scene_name)
        self.restart, self.force = restart, force
        o = cfg.output
        self.render = o.render
        self.frame_dt = o.frame_interval
        self.probe_dt = o.probe_interval
        se = o.snapshot_every
        self.snap_dt = default_snapshot_interval(cfg) if se < 0 else se
        self.ckpt_dt = o.checkpoint_every
        self.probes, self.snapshots = [], []
        self.frame_no = 0
        self._xdmf_at = 0.0
        self._xdmf_dirty = False
        self.next = dict(probe=0.0, frame=0.0, snapshot=0.0, checkpoint=self.ckpt_dt)
        self.signal = None
        self.wall_before = self.step_before = 0.0  # earlier segments of a restarted run
        self._t0 = None
        self.step_s = 0.0
        self._flushed_at = 0.0
        self.events = sorted(case.observers.events, key=lambda e: e[0])
        if self.render:
            self.events += [(t, self._still) for t in case.observers.stills]
            self.events.sort(key=lambda e: e[0])

    # -------------------------------------------------------------- set-up
    def disk_estimate(self):
        """Bytes the run's snapshots, frames (with the movie) and checkpoints will take, from the
        first of each written (at t = 0) and how many the run will write; printed at the start."""
        t_end = self.cfg.run.end_time

        def first(folder, ext):
            d = os.path.join(self.out, folder)
            files = sorted(f for f in os.listdir(d) if f.endswith(ext)) if os.path.isdir(d) else []
            return os.path.getsize(os.path.join(d, files[0])) if files else 0

        parts = {}
        if self.snap_dt > 0:
            parts["snapshots"] = first("snapshots", ".h5") * (int(t_end / self.snap_dt) + 1)
        if self.render:
            n = int(t_end / self.frame_dt) + 1
            # the first frame (still water) compresses about 3 times better than later ones (the
            # beach: 38 KB against 115 KB); the movie adds about a tenth
            parts["frames and movie"] = first("frames", ".png") * n * 3.3
        if self.ckpt_dt > 0:
            parts["checkpoints"] = 2 * first("snapshots", ".h5")  # two kept, each about a snapshot
        return parts

    def _say_disk(self):
        parts = self.disk_estimate()
        total = sum(parts.values())
        if not total:
            return
        text = ", ".join(f"{k} {v / 1e6:.0f} MB" for k, v in parts.items() if v)
        self.log(f"disk: about {total / 1e6:.0f} MB in {self.out} ({text})")
        if total > DISK_WARN_BYTES:
            w = (
                f"this run will write about {total / 1e9:.1f} GB ({text}); output.snapshot_every and "
                "output.frame_interval set how much"
            )
            self.case.warnings.append(w)
            self.log(f"warning: {w}", always=True)

    def _start(self):
        """Build the solver (compiles on the first step), restart or prime it; returns seconds."""
        t_build = time.perf_counter()
        s = self.solver = self.case.model.solver()
        s.enable_backup()
        if self.restart:
            self.resume()
            s.load_drive()  # the controller's state as the checkpoint kept it
            self.events = [e for e in self.events if e[0] > s.time + 1e-12]
        else:
            s.prime()
        compile_s = time.perf_counter() - t_build
        self.log(
            f"{s.n} particles ({self.case.particles.count(FLUID)} fluid), h = {s.h:.4g} m, "
            f"c0 = {s.c0:.4g} m/s, dt = {s.dt:.3g} s, set-up and compile {compile_s:.1f} s"
        )
        self.log("the step's runtime parameters, as resolved: " + s.table.describe(), file_only=True)
        return compile_s

    def _open_movie(self):
        self.renderer = self.frames = None
        if not self.render:
            return
        live = LiveWindow(f"tisph: {self.title}") if self.cfg.output.live else None
        outc, pic = self.cfg.output, self.case.picture
        ensure_dir(os.path.join(self.out, "frames"))
        speed = outc["speed_scale"] if outc["speed_scale"] > 0 else (pic.speed_scale or pic.u_max)
        self.renderer = make_renderer(pic, outc, self.solver.dx, self.title, speed)
        # a restart's movie is rebuilt from the frames already on disk
        rebuild = [
            os.path.join(self.out, "frames", f"{k:05d}.png") for k in range(self.frame_no if self.restart else 0)
        ]
        self.frames = open_frames(
            self.renderer, os.path.join(self.out, f"{self.title}.mp4"), outc["fps"], rebuild, live
        )

    def _progress_bar(self):
        if self.cfg.output.quiet:
            return None
        try:
            from tqdm import tqdm
        except ImportError:
            return None
        return tqdm(
            total=self.cfg.run.end_time,
            unit="sim s",
            disable=None,
            file=sys.stderr,
            bar_format="{l_bar}{bar}| {n:.3f}/{total:.3f} s [{elapsed}<{remaining}{postfix}]",
        )

    def _catch_signals(self):
        """SIGINT and SIGTERM set a flag the loop reads (it then writes a checkpoint)."""

        def on_signal(signum, frame):
            self.signal = signum

        old = {}
        for sig in (_signal.SIGINT, _signal.SIGTERM):
            try:
                old[sig] = _signal.signal(sig, on_signal)
            except ValueError:  # not the main thread
                pass
        return old

    def outputs(self):
        self.fire_events()
        if self._due("probe", self.probe_dt):
            self.sample()
        if self.render and self._due("frame", self.frame_dt):
            self.frame()
        if self._due("snapshot", self.snap_dt):
            self.snapshot()
        if self.ckpt_dt > 0 and self._due("checkpoint", self.ckpt_dt):
            self.checkpoint()

    # -------------------------------------------------------------- the loop
    def execute(self):
        clean_stale_parts(self.out)
        compile_s = self._start()
        self._open_movie()
        if self.snap_dt > 0:
            ensure_dir(os.path.join(self.out, "snapshots"))
        if not self.restart:
            self.outputs()
            if self.frames is not None:
                self.frames.sync()  # the first frame on disk: the estimate reads its size
            self._say_disk()
        self.solver.backup()
        bar = self._progress_bar()
        old = self._catch_signals()
        status, message = "ok", ""
        self.step_s, self.steps0 = 0.0, self.solver.steps
        t0 = self._t0 = time.perf_counter()
        try:
            self._loop(bar)
        except SimulationError as e:
            status, message = "unstable", str(e)
            self._on_unstable(message)
        except KeyboardInterrupt:
            status, message = "interrupted", self._on_signal()
        finally:
            for sig, h in old.items():
                _signal.signal(sig, h)
            if bar is not None:
                bar.n = min(self.solver.time, self.cfg.run.end_time)
                bar.close()
            if self.frames is not None:
                self.frames.close()
        wall = time.perf_counter() - t0
        return summarize(
            self,
            status,
            message,
            wall + self.wall_before,
            self.step_s + self.step_before,
            self.solver.steps - self.steps0,
            compile_s,
            segment=(wall, self.step_s),
        )

    def wall_so_far(self):
        """Wall seconds of this run's loop so far, earlier segments included."""
        return self.wall_before + (time.perf_counter() - self._t0 if self._t0 is not None else 0.0)

    def step_s_so_far(self):
        return self.step_before + self.step_s

    def _loop(self, bar):
        s, obs = self.solver, self.case.observers
        t_end, max_steps = self.cfg.run.end_time, self.cfg.run.max_steps
        last_bar = time.perf_counter()
        # off a terminal (a log being tailed, a batch job) a progress line every 5 % instead of the bar
        report = not self.cfg.output.quiet and (bar is None or bar.disable)

        def next_pct():
            return (math.floor(20.0 * s.time / t_end + 1e-9) + 1) * t_end / 20.0

        t_report = next_pct()
        backed = s.steps
        control = self._control = self._host_control()
        while s.time < t_end - 1e-12 and (max_steps == 0 or s.steps < max_steps):
            ts = time.perf_counter()
            n, left = self._quiet_steps(t_end, max_steps)
            s.step_ahead(n, left if s.park else None)
            if control is not None and s.steps % obs.control_every == 0:
                control(s)
            self.step_s += time.perf_counter() - ts
            if not s.health_read and (s.time >= self.next_output - 1e-12 or self._event_due()):
                s.read_health()  # a single step reads it every 10 steps, and before anything is written
            if s.health:  # hooks/health.py's BAD_NONE is 0
                raise SimulationError(describe_instability(s, *s.check()))
            if s.health_read and s.steps - backed >= 10:
                s.backup()
                backed = s.steps
            self.outputs()
            if self.signal is not None:
                raise KeyboardInterrupt
            if report and s.time >= t_report - 1e-12:
                self._progress_line(t_end)
                t_report = next_pct()
            now = time.perf_counter()
            if bar is not None and not bar.disable and now - last_bar > 0.25:
                bar.n = min(s.time, t_end)
                bar.set_postfix_str(
                    f"dt={s.dt:.2e} s, {s.n * (s.steps - self.steps0) / max(self.step_s, 1e-9):.3g} particle-steps/s",
                    refresh=False,
                )
                bar.refresh()
                last_bar = now
        bad = s.check()
        if bad:
            raise SimulationError(describe_instability(s, *bad))
        if not self.probes or self.probes[-1][0] < s.time:
            self.sample()

    def _host_control(self):
        """The case's control where the host runs it: not a held current's feedback that the
        device runs after its control steps (engine/drive.py)."""
        control, drive = self.case.observers.control, self.solver.drive
        return None if control is None or (drive is not None and control == drive.held.update) else control

    def _event_due(self):
        return bool(self.events) and self.solver.time >= self.events[0][0] - 1e-12

    def _quiet_steps(self, t_end, max_steps):
        """(n, left): how many steps may run with no read of the device between them
        (solver.step_ahead), and the seconds left to the next output, event or the end. None
        but the last step may reach that horizon (no step is longer than dt_bound); where the
        solver parks (a GPU), past it, the steps after it parked. The last is at most a control
        step or the step cap."""
        s, obs = self.solver, self.case.observers
        horizon = min(t_end, self.next_output, self.events[0][0] if self.events else math.inf)
        left = horizon - 1e-12 - s.time
        if not s.steps_ahead_allowed:
            return 1, left
        n = math.floor(left / s.dt_bound)
        if s.park:  # to the horizon at the last step's dt and 3 % more: the steps after it park
            n = max(n, math.ceil(1.03 * left / s.dt))
        if max_steps:
            n = min(n, max_steps - s.steps)
        if self._control is not None:
            n = min(n, obs.control_every - s.steps % obs.control_every)
        return max(1, min(n, s.batch)), left

    def _progress_line(self, t_end):
        s = self.solver
        wall = self.wall_so_far()
        rate = s.n * (s.steps - self.steps0) / max(self.step_s, 1e-9)
        left = max(wall / max(s.time, 1e-12) * (t_end - s.time), 0.0)
        self.log(
            f"progress {min(100.0 * s.time / t_end, 100.0):3.0f} %: t = {s.time:.4g} of {t_end:g} s, step {s.steps}, "
            f"dt = {s.dt:.3g} s, {rate:.3g} particle-steps/s, wall {wall:.0f} s, about {left:.0f} s left"
        )

    def _on_unstable(self, message):
        s = self.solver
        self.log(message, always=True)
        if self.snap_dt > 0:
            self.snapshot(
                state=s.backup_state(s.snapshot_members), name="last_good.h5", time=s.bak_time, step=s.bak_steps
            )
            self.log(
                f"wrote the last healthy state (step {s.bak_steps}, t = {s.bak_time:.6g} s) to snapshots/last_good.h5",
                always=True,
            )

    def _on_signal(self):
        s = self.solver
        sig = self.signal if self.signal is not None else _signal.SIGINT
        path = self.checkpoint()
        message = (
            f"stopped by {_signal.Signals(sig).name} at step {s.steps}, t = {s.time:.6g} s; "
            f"continue with --restart {path}"
        )
        self.log(message, always=True)
        return message
