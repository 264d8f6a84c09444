"""Runs a scene: config -> particles -> solver loop with probes, frames, progress -> files.

What a run writes into OUT (the contract scenes and the benchmark rely on):
  <scene>.mp4 and frames/00000.png ... (unless --no-render)
  probes.csv   time series, columns t + the scene's probe columns
  summary.json scene, dx, particles, steps, sim_time, wall_time_s, particle_steps_per_s, arch,
               leaked_particles, metrics{...}, status
  run.log      the resolved config, warnings and timings
"""
import dataclasses
import json
import math
import os
import sys
import time
import time as time_mod
import warnings
from typing import Callable

import numpy as np

from . import __version__
from .cli import make_parser, overrides_from_args
from .config import ConfigError, build_config, dump_toml, Physics
from .io import OutputError, ensure_dir, write_csv, write_json, write_text
from .particles import FLUID, OUT, OUTFLOW, KIND_NAMES


class SimulationError(RuntimeError):
    """The run went unstable; the message says where, what and a likely cause."""


@dataclasses.dataclass
class Case:
    """What a scene's build(cfg) returns."""
    name: str
    particles: object
    materials: list
    domain: tuple
    params: dict
    physics: Physics
    view: tuple
    u_max: float
    probe_columns: tuple = ()
    probe: Callable = None            # probe(state: dict) -> tuple of floats
    metrics: Callable = None          # metrics(columns: dict of np arrays) -> dict
    final_metrics: Callable = None    # final_metrics(state: dict of np arrays) -> dict
    container: tuple = None           # (x0, y0, x1, y1[, wall top]) the walls enclose: fluid outside
                                      # (below the wall top) crossed a wall, and the run stops
    outflow: tuple = ()               # open boundaries: boxes (x0, y0, x1, y1) fluid leaves through
    events: list = dataclasses.field(default_factory=list)  # [(t, callback(state, t))] at exact times
    finalize: Callable = None         # finalize(out, metrics) -> None: plots, extra files
    stills: tuple = ()                # simulated times of named stills, stills/t0.040.png
    notes: list = dataclasses.field(default_factory=list)
    render_modes: tuple = ("speed",)  # stacked panels: speed | phase | flat (see render.Renderer)
    mat_colors: tuple = None          # per material: an RGB colour (sediment) or None (by speed)
    control: Callable = None          # control(solver) every control_every steps (a driving force)
    control_every: int = 10
    pressure_scale: float = 0.0       # top of the "pressure" render mode's colour bar (Pa)


def sound_speed(cfg, u_max):
    """c0 from the config, or c0_factor * u_max (paper 000: B = 100 rho0 u^2 / gamma, i.e. c0 = 10 u)."""
    n = cfg["numerics"]
    if n["u_max"] > 0:
        u_max = n["u_max"]
    c0 = n["c0"] if n["c0"] > 0 else n["c0_factor"] * u_max
    return c0, u_max


def common_params(cfg, c0, g=9.81, depth=1.0):
    """The numeric parameters every scene passes to the solver."""
    n = cfg["numerics"]
    dx = n["dx"]
    wall_D = n["wall_strength"] if n["wall_strength"] > 0 else 5.0 * g * depth
    return dict(dx=dx, h=n["h_factor"] * dx, c0=c0, alpha=n["artificial_viscosity"], xsph=n["xsph"],
                delta=n["delta"], g=(0.0, -g), wall_D=wall_D, wall_r0=dx, cfl=n["cfl"],
                dt_max=n["dt_max"], density_band=n["density_band"], shepard_every=n["shepard_every"])


class Log:
    def __init__(self, path, quiet):
        self.path, self.quiet, self.lines = path, quiet, []

    def __call__(self, msg, always=False, file_only=False):
        self.lines.append(msg)
        if always or not (self.quiet or file_only):
            print(msg, file=sys.stderr)

    def flush(self):
        try:
            write_text(self.path, "\n".join(self.lines) + "\n")
        except OutputError:
            pass


def build_case(scene, cfg, log):
    """scene.build(cfg), with its warnings and the sound-speed check logged."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        case = scene.build(cfg)
        c0 = case.params["c0"]
        if c0 < 10.0 * case.u_max * (1 - 1e-9):
            warnings.warn(f"sound speed c0 = {c0:.3g} m/s is below 10 x the expected peak speed "
                          f"{case.u_max:.3g} m/s: density errors above 1 % are likely")
    for w in caught:
        log(f"warning: {w.message}", always=True)
    case.warnings = [str(w.message) for w in caught]
    return case


def describe_instability(solver, code, pid):
    from .solver import BAD_TEXT
    what, cause = BAD_TEXT.get(code, ("unknown", ""))
    s = solver.state(("x", "v", "rho", "kind", "mat"))   # ordered by particle id
    if 0 <= pid < solver.n:
        x, v, rho = s["x"][pid], s["v"][pid], s["rho"][pid]
        rho0 = solver.materials[int(s["mat"][pid])]["rho0"]
        where = (f"particle {pid} ({KIND_NAMES.get(int(s['kind'][pid]), '?')}) at x = ({x[0]:.4g}, {x[1]:.4g}) m, "
                 f"|v| = {np.hypot(*v):.4g} m/s, rho = {rho:.6g} kg/m3 (rest {rho0:g})")
    else:
        where = f"time step dt = {solver.dt:.3g} s"
    return (f"unstable at step {solver.steps}, t = {solver.time:.6g} s: {what}; {where}. "
            f"Likely cause: {cause}.")


# Keys a restart may change: when and how to stop, and what to write.
RESTART_FREE = ("run.end_time", "run.max_steps", "run.arch", "output")


def _strip(cfg):
    import copy
    c = copy.deepcopy(cfg)
    for k in RESTART_FREE:
        parts = k.split(".")
        d = c
        for p in parts[:-1]:
            d = d.get(p, {})
        d.pop(parts[-1], None)
    return c


def config_changes(a, b, prefix=""):
    """Dotted keys whose values differ between two resolved configs."""
    out = []
    for k in sorted(set(a) | set(b)):
        va, vb = a.get(k), b.get(k)
        if isinstance(va, dict) and isinstance(vb, dict):
            out += config_changes(va, vb, f"{prefix}{k}.")
        elif va != vb:
            out.append(f"{prefix}{k}: {va!r} -> {vb!r}")
    return out


class Run:
    """One simulation run: the time loop and everything it writes."""

    def __init__(self, case: Case, cfg: dict, out: str, log: Log, scene_name: str,
                 restart=None, force=False):
        self.case, self.cfg, self.out, self.log, self.name = case, cfg, out, log, scene_name
        self.restart, self.force = restart, force
        o = cfg["output"]
        self.render = o["render"]
        self.frame_dt = o["frame_interval"]
        self.probe_dt = o["probe_interval"]
        se = o["snapshot_every"]
        self.snap_dt = self.frame_dt if se < 0 else se
        self.ckpt_dt = o["checkpoint_every"]
        self.probes, self.snapshots = [], []
        self.frame_no = 0
        self._xdmf_at = 0.0
        self._xdmf_dirty = False
        self.next = dict(probe=0.0, frame=0.0, snapshot=0.0, checkpoint=self.ckpt_dt)
        self.signal = None
        self.events = sorted(case.events, key=lambda e: e[0])
        if self.render:
            self.events += [(t, self._still) for t in case.stills]
            self.events.sort(key=lambda e: e[0])

    # -------------------------------------------------------------- outputs
    def _still(self, state, t):
        from .render import write_png
        from .io import ensure_dir
        ensure_dir(os.path.join(self.out, "stills"))
        write_png(os.path.join(self.out, "stills", f"t{t:.3f}.png"), self.renderer.frame(state["t"]))

    def fire_events(self):
        while self.events and self.solver.time >= self.events[0][0] - 1e-12:
            t, cb = self.events.pop(0)
            st = self.solver.state(("x", "v", "kind", "rho", "p", "m", "mat"))
            st["t"] = self.solver.time    # the actual time, at or just after the scheduled t
            st["out"] = self.out
            cb(st, t)

    def sample(self):
        st = self.solver.state(("x", "v", "kind", "rho", "p", "m", "mat"))
        st["t"] = self.solver.time
        row = (self.solver.time,) + (tuple(float(v) for v in self.case.probe(st)) if self.case.probe else ())
        self.probes.append(row)

    def frame(self):
        from .render import write_png
        img = self.renderer.frame(self.solver.time)
        write_png(os.path.join(self.out, "frames", f"{self.frame_no:05d}.png"), img)
        self.movie.append(img)
        self.frame_no += 1

    def snapshot_attrs(self, time, step, dt):
        return dict(scene=self.name, tisph_version=__version__, config=dump_toml(self.cfg),
                    time=float(time), step=int(step), dt=float(dt))

    def snapshot(self, state=None, name=None, time=None, step=None):
        from .io import write_snapshot, SNAPSHOT_FIELDS
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
        from .io import write_xdmf
        if self._xdmf_dirty:
            write_xdmf(os.path.join(self.out, "snapshots.xdmf"),
                       [(t, rel, n, {k: (v[0], np.dtype(v[1])) for k, v in sh.items()})
                        for t, rel, n, sh in self.snapshots])
            self._xdmf_dirty = False
            self._xdmf_at = time_mod.perf_counter()

    def checkpoint(self, path=None):
        import h5py
        from .io import atomic_path, OutputError
        path = path or os.path.join(self.out, "checkpoint.h5")
        arrays, scal = self.solver.raw_state()
        try:
            with atomic_path(path) as tmp:
                with h5py.File(tmp, "w") as f:
                    g = f.create_group("particles")
                    for k, a in arrays.items():
                        g.create_dataset(k, data=a)
                    f.create_dataset("probes", data=np.array(self.probes, float).reshape(len(self.probes), -1))
                    for k, v in scal.items():
                        f.attrs[k] = v
                    f.attrs.update(dict(kind="tisph checkpoint", scene=self.name, tisph_version=__version__,
                                        config=dump_toml(self.cfg), frame_no=self.frame_no,
                                        next=json.dumps(self.next), snapshots=json.dumps(self.snapshots)))
        except OSError as e:
            raise OutputError(f"cannot write checkpoint {path!r}: {e}") from None
        self.log(f"checkpoint at step {self.solver.steps}, t = {self.solver.time:.6g} s: {path}", file_only=True)
        return path

    def resume(self):
        """Load self.restart into the solver and the run's own state."""
        from .io import load
        arrays, attrs = load(self.restart)
        if attrs.get("kind") != "tisph checkpoint" or "particles" not in arrays:
            raise ConfigError("--restart", self.restart, "a checkpoint.h5 written by tisph")
        if attrs.get("scene") != self.name:
            raise ConfigError("--restart", self.restart, f"a checkpoint of scene {self.name!r}",
                              f"it is a checkpoint of {attrs.get('scene')!r}")
        from .config import tomllib as _toml
        old = _toml.loads(attrs["config"])
        changes = config_changes(_strip(old), _strip(self.cfg))
        if changes and not self.force:
            raise ConfigError("--restart", self.restart, "the config the checkpoint was written with "
                              "(or pass --force)", "changed: " + "; ".join(changes))
        if changes:
            self.log("warning: restarting with a changed config: " + "; ".join(changes), always=True)
        try:
            self.solver.load_raw_state(arrays["particles"], attrs)
        except ValueError as e:
            raise ConfigError("--restart", self.restart, "a checkpoint of this case", str(e)) from None
        self.probes = [tuple(r) for r in np.asarray(arrays["probes"]).tolist()]
        self.frame_no = int(attrs["frame_no"])
        self.next = json.loads(attrs["next"])
        self.snapshots = [tuple(x) for x in json.loads(attrs["snapshots"])]
        self.log(f"restarted from {self.restart} at step {self.solver.steps}, t = {self.solver.time:.6g} s")

    @property
    def next_output(self):
        """Time of the next output that is switched on (an off output never advances its entry)."""
        on = {"probe": self.probe_dt, "frame": self.frame_dt if self.render else 0.0,
              "snapshot": self.snap_dt, "checkpoint": self.ckpt_dt}
        due = [self.next[k] for k, dt in on.items() if dt > 0]
        return min(due) if due else float("inf")

    def _due(self, key, interval):
        """Whether an output is due now; schedules the next one on the interval grid."""
        if interval <= 0 or self.solver.time < self.next[key] - 1e-12:
            return False
        k = math.floor(self.solver.time / interval + 1e-9) + 1
        self.next[key] = k * interval
        return True

    # -------------------------------------------------------------- the loop
    def execute(self):
        from .io import clean_stale_parts
        from .solver import Solver
        run, outc = self.cfg["run"], self.cfg["output"]
        clean_stale_parts(self.out)
        t_build = time.perf_counter()
        s = self.solver = Solver(self.case.physics, self.case.particles, self.case.materials,
                                 self.case.domain, self.case.params, outflow=self.case.outflow,
                                 container=self.case.container)
        s.enable_backup()
        if self.restart:
            self.resume()
            self.events = [e for e in self.events if e[0] > s.time + 1e-12]
        else:
            s.prime()
        compile_s = time.perf_counter() - t_build
        self.log(f"{s.n} particles ({self.case.particles.count(FLUID)} fluid), h = {s.h:.4g} m, "
                 f"c0 = {s.c0:.4g} m/s, dt = {s.dt:.3g} s, set-up and compile {compile_s:.1f} s")

        self.renderer = self.movie = None
        if self.render:
            from .render import Renderer, MovieWriter
            from .io import ensure_dir
            ensure_dir(os.path.join(self.out, "frames"))
            speed = outc["speed_scale"] if outc["speed_scale"] > 0 else self.case.u_max
            self.renderer = Renderer(s, self.case.view, outc["width"], speed, title=self.name,
                                     modes=self.case.render_modes, mat_colors=self.case.mat_colors,
                                     pressure_scale=self.case.pressure_scale)
            self.movie = MovieWriter(os.path.join(self.out, f"{self.name}.mp4"), outc["fps"])
            if self.restart:  # the movie is rebuilt from the frames already on disk
                import imageio.v2 as imageio
                for k in range(self.frame_no):
                    f = os.path.join(self.out, "frames", f"{k:05d}.png")
                    if os.path.exists(f):
                        self.movie.append(imageio.imread(f))
        if self.snap_dt > 0:
            from .io import ensure_dir
            ensure_dir(os.path.join(self.out, "snapshots"))

        def outputs():
            self.fire_events()
            if self._due("probe", self.probe_dt):
                self.sample()
            if self.render and self._due("frame", self.frame_dt):
                self.frame()
            if self._due("snapshot", self.snap_dt):
                self.snapshot()
            if self.ckpt_dt > 0 and self._due("checkpoint", self.ckpt_dt):
                self.checkpoint()

        if not self.restart:
            outputs()
        s.backup()

        bar = None
        t_end, max_steps = run["end_time"], run["max_steps"]
        if not outc["quiet"]:
            try:
                from tqdm import tqdm
                bar = tqdm(total=t_end, unit="sim s", disable=None, file=sys.stderr,
                           bar_format="{l_bar}{bar}| {n:.3f}/{total:.3f} s [{elapsed}<{remaining}{postfix}]")
            except ImportError:
                bar = None

        import signal as _signal
        old = {}

        def on_signal(signum, frame):
            self.signal = signum
        for sig in (_signal.SIGINT, _signal.SIGTERM):
            try:
                old[sig] = _signal.signal(sig, on_signal)
            except ValueError:  # not the main thread
                pass

        status, message = "ok", ""
        step_s, steps0 = 0.0, s.steps
        t0 = last_bar = time.perf_counter()
        try:
            while s.time < t_end - 1e-12 and (max_steps == 0 or s.steps < max_steps):
                ts = time.perf_counter()
                s.step()
                if self.case.control is not None and s.steps % self.case.control_every == 0:
                    self.case.control(s)
                step_s += time.perf_counter() - ts
                if s.steps % 10 == 0 or s.time >= self.next_output - 1e-12:
                    bad = s.check()
                    if bad:
                        raise SimulationError(describe_instability(s, *bad))
                    if s.steps % 10 == 0:
                        s.backup()
                outputs()
                if self.signal is not None:
                    raise KeyboardInterrupt
                now = time.perf_counter()
                if bar is not None and now - last_bar > 0.25:
                    bar.n = min(s.time, t_end)
                    bar.set_postfix_str(f"dt={s.dt:.2e} s, {s.n * (s.steps - steps0) / max(step_s, 1e-9):.3g} "
                                        f"particle-steps/s", refresh=False)
                    bar.refresh()
                    last_bar = now
            bad = s.check()
            if bad:
                raise SimulationError(describe_instability(s, *bad))
            if not self.probes or self.probes[-1][0] < s.time:
                self.sample()
        except SimulationError as e:
            status, message = "unstable", str(e)
            self.log(message, always=True)
            if self.snap_dt > 0:
                self.snapshot(state=s.backup_state(s.snapshot_members), name="last_good.h5",
                              time=s.bak_time, step=s.bak_steps)
                self.log(f"wrote the last healthy state (step {s.bak_steps}, t = {s.bak_time:.6g} s) to "
                         f"snapshots/last_good.h5", always=True)
        except KeyboardInterrupt:
            sig = self.signal if self.signal is not None else _signal.SIGINT
            status = "interrupted"
            path = self.checkpoint()
            message = (f"stopped by {_signal.Signals(sig).name} at step {s.steps}, t = {s.time:.6g} s; "
                       f"continue with --restart {path}")
            self.log(message, always=True)
        finally:
            for sig, h in old.items():
                _signal.signal(sig, h)
            if bar is not None:
                bar.n = min(s.time, t_end)
                bar.close()
            if self.movie is not None:
                self.movie.close()
        wall = time.perf_counter() - t0
        return self.finish(status, message, wall, step_s, s.steps - steps0, compile_s)

    def finish(self, status, message, wall, step_s, nsteps, compile_s):
        s, case, cfg = self.solver, self.case, self.cfg
        self.write_xdmf()
        cols = ("t",) + tuple(case.probe_columns)
        write_csv(os.path.join(self.out, "probes.csv"), cols, self.probes)
        arr = {c: np.array([r[k] for r in self.probes], float) for k, c in enumerate(cols)}
        metrics = case.metrics(arr) if case.metrics else {}
        final = s.state(("x", "v", "kind", "rho", "p", "mat", "m"))
        if case.final_metrics:
            metrics.update(case.final_metrics(final))
        # mass balance, summed in float64 from the particles' own masses: fluid in the domain +
        # fluid that left through open boundaries (+ leaked fluid) = the initial fluid mass
        m_dev = case.particles.m.astype(final["m"].dtype)  # the masses as the solver stores them
        m0 = float(np.sum(m_dev[case.particles.kind == FLUID], dtype=np.float64))
        m_in = float(np.sum(final["m"][final["kind"] == FLUID], dtype=np.float64))
        m_out = float(np.sum(final["m"][final["kind"] == OUTFLOW], dtype=np.float64))
        m_leak = float(np.sum(final["m"][final["kind"] == OUT], dtype=np.float64))
        mass = dict(initial_fluid_mass=m0, fluid_mass=m_in, outflow_mass=m_out, leaked_mass=m_leak,
                    mass_balance_error=abs(m_in + m_out + m_leak - m0) / m0 if m0 > 0 else 0.0,
                    outflow_particles=int(np.sum(final["kind"] == OUTFLOW)))
        # the step kernel stops the run at the first crossing, so the final state tells it all
        crossed = 0
        if s.container is not None:
            x0, y0, x1, y1, top = s.container   # with the solver's tolerance
            x = final["x"][final["kind"] == FLUID]
            crossed = int(np.sum((x[:, 1] < y0) | (x[:, 1] > y1) |
                                 ((x[:, 1] < top) & ((x[:, 0] < x0) | (x[:, 0] > x1)))))
        nb = int(np.sum(case.particles.kind != FLUID))
        pps = (s.n * nsteps / step_s) if step_s > 0 else 0.0
        summary = dict(
            scene=self.name, status=status, message=message, tisph_version=__version__,
            dx=float(cfg["numerics"]["dx"]), particles=int(s.n),
            fluid_particles=int(case.particles.count(FLUID)), boundary_particles=nb,
            steps=int(s.steps), sim_time=float(s.time), wall_time_s=wall, step_time_s=step_s,
            compile_time_s=compile_s, particle_steps_per_s=pps,
            wall_s_per_sim_s=(wall / s.time) if s.time > 0 else None,
            arch=self.arch, leaked_particles=int(s.leaked), crossed_wall=crossed,
            max_density_error=s.max_density_error, frames=self.frame_no,
            snapshots=len(self.snapshots), c0=float(s.c0), h=float(s.h),
            physics=case.physics.as_dict(), warnings=list(getattr(case, "warnings", [])),
            mass=mass, metrics=metrics,
        )
        if self.restart:
            summary["restarted_from"] = os.path.abspath(self.restart)
        if case.finalize:
            try:
                case.finalize(self.out, metrics)
            except OutputError:
                raise
            except Exception as e:  # a failed plot must not lose the run's numbers
                self.log(f"warning: could not write the scene's plots: {e}", always=True)
        write_json(os.path.join(self.out, "summary.json"), summary)
        self.log(f"{status}: {s.steps} steps to t = {s.time:.4g} s in {wall:.2f} s "
                 f"({pps:.3g} particle-steps/s), leaked {s.leaked}, crossed a wall {crossed}, "
                 f"max density error {s.max_density_error:.3%}")
        if metrics:
            self.log("metrics: " + json.dumps(metrics))
        return summary


def run_case(case, cfg, out, log, scene_name, restart=None, force=False):
    from . import runtime
    if case.particles.count(FLUID) == 0:
        raise ConfigError("geometry", "no fluid particles", "a case with at least one fluid particle")
    r = Run(case, cfg, out, log, scene_name, restart, force)
    r.arch = runtime.current_arch()
    try:
        return r.execute()
    except BaseException:
        if getattr(r, "movie", None) is not None:
            r.movie.abort()
        raise


def output_dir(scene, cfg):
    return cfg["output"]["dir"] or os.path.join("renders", scene.NAME)


def resolve(scene, config=None, overrides=None):
    """The validated config of a scene: defaults <- TOML <- overrides, then the scene's checks."""
    cfg = build_config(scene.DEFAULTS, config, overrides or {},
                       getattr(scene, "RANGES", None), getattr(scene, "CHOICES", None))
    if hasattr(scene, "check"):
        scene.check(cfg)
    return cfg


def run_scene(scene, argv=None):
    """Entry point of `python -m tisph.scenes.NAME`. Exit codes: 0 ok, 2 bad input, 3 unstable,
    130/143 stopped by SIGINT/SIGTERM."""
    parser = make_parser(scene.NAME, (scene.__doc__ or "").strip())
    args = parser.parse_args(argv)
    try:
        cfg = resolve(scene, args.config, overrides_from_args(args))
        summary = simulate(scene, cfg=cfg, restart=args.restart, force=args.force, echo=True)
    except (ConfigError, OutputError) as e:
        print(f"{parser.prog}: {e}", file=sys.stderr)
        return 2
    if not cfg["output"]["quiet"]:
        print(f"wrote {output_dir(scene, cfg)}/", file=sys.stderr)
    if summary["status"] == "interrupted":
        return 143 if "SIGTERM" in summary["message"] else 130
    return {"ok": 0, "unstable": 3}[summary["status"]]


def simulate(scene, overrides=None, out=None, config=None, restart=None, force=False, cfg=None,
             echo=False):
    """Run a scene: the path the CLI takes, callable from Python (tests, benchmarks).

    Returns the summary dict; raises ConfigError or OutputError on bad input. echo: print
    messages as the CLI does (otherwise only to run.log and only warnings to stderr).
    """
    from . import runtime
    cfg = cfg if cfg is not None else resolve(scene, config, overrides)
    out = out or output_dir(scene, cfg)
    ensure_dir(out)
    log = Log(os.path.join(out, "run.log"), cfg["output"]["quiet"] or not echo)
    try:
        log("# resolved config\n" + dump_toml(cfg), file_only=True)
        arch = runtime.init(cfg["run"]["arch"], cfg["run"]["precision"])
        log(f"# {runtime.describe()}, requested {cfg['run']['arch']}", file_only=True)
        if cfg["run"]["arch"] == "gpu" and arch in ("x64", "arm64"):
            log("warning: no GPU backend found, running on the CPU", always=True)
        case = build_case(scene, cfg, log)
        return run_case(case, cfg, out, log, scene.NAME, restart=restart, force=force)
    except (ConfigError, OutputError) as e:
        log(f"error: {e}", file_only=True)
        raise
    finally:
        log.flush()
