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
import warnings
from typing import Callable

import numpy as np

from . import __version__
from .cli import make_parser, overrides_from_args
from .config import ConfigError, build_config, dump_toml, physics_from_config, Physics
from .io import OutputError, ensure_dir, write_csv, write_json, write_text
from .particles import FLUID, OUT, KIND_NAMES


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
    notes: list = dataclasses.field(default_factory=list)


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


def describe_instability(solver, code, idx):
    from .solver import BAD_TEXT
    what, cause = BAD_TEXT.get(code, ("unknown", ""))
    s = solver.sorted_state(("x", "v", "rho", "id", "kind", "mat"))
    if 0 <= idx < solver.n:
        x, v, rho, pid = s["x"][idx], s["v"][idx], s["rho"][idx], int(s["id"][idx])
        rho0 = solver.materials[int(s["mat"][idx])]["rho0"]
        where = (f"particle {pid} ({KIND_NAMES.get(int(s['kind'][idx]), '?')}) at x = ({x[0]:.4g}, {x[1]:.4g}) m, "
                 f"|v| = {np.hypot(*v):.4g} m/s, rho = {rho:.6g} kg/m3 (rest {rho0:g})")
    else:
        where = f"time step dt = {solver.dt:.3g} s"
    return (f"unstable at step {solver.steps}, t = {solver.time:.6g} s: {what}; {where}. "
            f"Likely cause: {cause}.")


def run_case(case: Case, cfg: dict, out: str, log: Log, scene_name: str):
    """The time loop. Returns the summary dict (status 'ok' or 'unstable')."""
    from . import runtime
    from .solver import Solver

    run, outc = cfg["run"], cfg["output"]
    render = outc["render"]
    arch = runtime.current_arch()
    t_build = time.perf_counter()
    solver = Solver(case.physics, case.particles, case.materials, case.domain, case.params)
    solver.prime()
    compile_s = time.perf_counter() - t_build
    log(f"{solver.n} particles ({case.particles.count(FLUID)} fluid), h = {solver.h:.4g} m, "
        f"c0 = {solver.c0:.4g} m/s, first dt = {solver.dt:.3g} s, set-up and compile {compile_s:.1f} s")

    renderer = movie = None
    frames_dir = os.path.join(out, "frames")
    if render:
        from .render import Renderer, MovieWriter
        ensure_dir(frames_dir)
        speed = outc["speed_scale"] if outc["speed_scale"] > 0 else case.u_max
        renderer = Renderer(solver, case.view, outc["width"], speed, title=scene_name)
        movie = MovieWriter(os.path.join(out, f"{scene_name}.mp4"), outc["fps"])

    probes = []
    frame_no = 0

    def sample():
        st = solver.state(("x", "v", "kind", "rho", "p"))
        probes.append((solver.time,) + tuple(case.probe(st)) if case.probe else (solver.time,))

    def frame():
        nonlocal frame_no
        from .render import write_png
        img = renderer.frame(solver.time)
        write_png(os.path.join(frames_dir, f"{frame_no:05d}.png"), img)
        movie.append(img)
        frame_no += 1

    t_end, max_steps = run["end_time"], run["max_steps"]
    probe_dt, frame_dt = outc["probe_interval"], outc["frame_interval"]
    next_probe, next_frame = probe_dt, frame_dt
    sample()
    if render:
        frame()

    bar = None
    if not outc["quiet"]:
        try:
            from tqdm import tqdm
            bar = tqdm(total=t_end, unit="sim s", disable=None, file=sys.stderr,
                       bar_format="{l_bar}{bar}| {n:.3f}/{total:.3f} s [{elapsed}<{remaining}{postfix}]")
        except ImportError:
            bar = None

    status, message = "ok", ""
    step_s = 0.0
    t0 = time.perf_counter()
    last_bar = t0
    try:
        while solver.time < t_end - 1e-12 and (max_steps == 0 or solver.steps < max_steps):
            ts = time.perf_counter()
            solver.step()
            step_s += time.perf_counter() - ts
            if solver.steps % 10 == 0 or solver.time >= next_probe:
                bad = solver.check()
                if bad:
                    raise SimulationError(describe_instability(solver, *bad))
            if solver.time >= next_probe - 1e-12:
                sample()
                next_probe += probe_dt * max(1, math.floor((solver.time - next_probe) / probe_dt) + 1)
            if render and solver.time >= next_frame - 1e-12:
                frame()
                next_frame += frame_dt * max(1, math.floor((solver.time - next_frame) / frame_dt) + 1)
            now = time.perf_counter()
            if bar is not None and now - last_bar > 0.25:
                bar.n = min(solver.time, t_end)
                bar.set_postfix_str(f"dt={solver.dt:.2e} s, {solver.n * solver.steps / max(step_s, 1e-9):.3g} "
                                    f"particle-steps/s", refresh=False)
                bar.refresh()
                last_bar = now
        bad = solver.check()
        if bad:
            raise SimulationError(describe_instability(solver, *bad))
        if probes[-1][0] < solver.time:
            sample()
    except SimulationError as e:
        status, message = "unstable", str(e)
        log(message, always=True)
    except KeyboardInterrupt:
        status, message = "interrupted", f"interrupted at step {solver.steps}, t = {solver.time:.6g} s"
        log(message, always=True)
    finally:
        if bar is not None:
            bar.n = min(solver.time, t_end)
            bar.close()
        if movie is not None:
            movie.close()
    wall = time.perf_counter() - t0

    cols = ("t",) + tuple(case.probe_columns)
    write_csv(os.path.join(out, "probes.csv"), cols, probes)
    arr = {c: np.array([r[k] for r in probes], float) for k, c in enumerate(cols)}
    metrics = case.metrics(arr) if case.metrics else {}
    if case.final_metrics:
        metrics.update(case.final_metrics(solver.state(("x", "v", "kind", "rho", "p", "mat"))))
    nb = int(np.sum((case.particles.kind != FLUID)))
    summary = dict(
        scene=scene_name, status=status, message=message, tisph_version=__version__,
        dx=float(cfg["numerics"]["dx"]), particles=int(solver.n),
        fluid_particles=int(case.particles.count(FLUID)), boundary_particles=nb,
        steps=int(solver.steps), sim_time=float(solver.time), wall_time_s=wall,
        step_time_s=step_s, compile_time_s=compile_s,
        particle_steps_per_s=(solver.n * solver.steps / step_s) if step_s > 0 else 0.0,
        wall_s_per_sim_s=(wall / solver.time) if solver.time > 0 else None,
        arch=arch, leaked_particles=int(solver.leaked), frames=frame_no,
        c0=float(solver.c0), h=float(solver.h), physics=case.physics.as_dict(), metrics=metrics,
    )
    write_json(os.path.join(out, "summary.json"), summary)
    log(f"{status}: {solver.steps} steps to t = {solver.time:.4g} s in {wall:.2f} s "
        f"({summary['particle_steps_per_s']:.3g} particle-steps/s), leaked {solver.leaked}")
    if metrics:
        log("metrics: " + json.dumps(metrics))
    return summary


def run_scene(scene, argv=None):
    """Entry point of `python -m tisph.scenes.NAME`. Exit codes: 0 ok, 2 bad input, 3 unstable."""
    name = scene.NAME
    parser = make_parser(name, (scene.__doc__ or "").strip())
    args = parser.parse_args(argv)
    try:
        cfg = build_config(scene.DEFAULTS, args.config, overrides_from_args(args),
                           getattr(scene, "RANGES", None), getattr(scene, "CHOICES", None))
        if hasattr(scene, "check"):
            scene.check(cfg)
    except ConfigError as e:
        print(f"{parser.prog}: {e}", file=sys.stderr)
        return 2
    out = cfg["output"]["dir"] or os.path.join("renders", name)
    try:
        ensure_dir(out)
    except OutputError as e:
        print(f"{parser.prog}: {e}", file=sys.stderr)
        return 2
    log = Log(os.path.join(out, "run.log"), cfg["output"]["quiet"])
    log("# resolved config\n" + dump_toml(cfg), file_only=True)
    from . import runtime
    arch = runtime.init(cfg["run"]["arch"], cfg["run"]["precision"])
    log(f"# {runtime.describe()}, requested {cfg['run']['arch']}", file_only=True)
    if cfg["run"]["arch"] == "gpu" and arch in ("x64", "arm64"):
        log("warning: no GPU backend found, running on the CPU", always=True)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        case = scene.build(cfg)
        c0 = case.params["c0"]
        if c0 < 10.0 * case.u_max * (1 - 1e-9):
            warnings.warn(f"sound speed c0 = {c0:.3g} m/s is below 10 x the expected peak speed "
                          f"{case.u_max:.3g} m/s: density errors above 1 % are likely")
    for w in caught:
        log(f"warning: {w.message}", always=True)
    try:
        summary = run_case(case, cfg, out, log, name)
    except OutputError as e:
        print(f"{parser.prog}: {e}", file=sys.stderr)
        return 2
    finally:
        log.flush()
    if not cfg["output"]["quiet"]:
        print(f"wrote {out}/", file=sys.stderr)
    return {"ok": 0, "unstable": 3, "interrupted": 130}[summary["status"]]


def simulate(scene, overrides=None, out=None, config=None):
    """Run a scene from Python (tests, benchmarks): the same path as the CLI, no argv.

    Returns the summary dict; raises ConfigError on bad input.
    """
    from . import runtime
    cfg = build_config(scene.DEFAULTS, config, overrides or {},
                       getattr(scene, "RANGES", None), getattr(scene, "CHOICES", None))
    if hasattr(scene, "check"):
        scene.check(cfg)
    out = out or cfg["output"]["dir"] or os.path.join("renders", scene.NAME)
    ensure_dir(out)
    log = Log(os.path.join(out, "run.log"), True)
    log("# resolved config\n" + dump_toml(cfg))
    runtime.init(cfg["run"]["arch"], cfg["run"]["precision"])
    case = scene.build(cfg)
    try:
        return run_case(case, cfg, out, log, scene.NAME)
    finally:
        log.flush()
