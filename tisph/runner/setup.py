"""Run set-up: sound speed and common parameters, the log, building a case, the instability
message, and what a restart may change."""

import sys
import warnings
from collections.abc import Mapping

import numpy as np

from ..errors import SimulationError, unstable  # noqa: F401  (the runner's: re-exported)
from ..io import OutputError, write_text
from ..particles import FLUID, KIND_NAMES, RUN_BYTES_PER_PARTICLE, check_fits
from ..settings.resolved import thaw


def sound_speed(cfg, u_max, depth=0.0, g=9.81):
    """c0 from the config, or c0_factor * max(u_max, sqrt(g depth)): Monaghan's (1994) rule that c0
    be ten times the larger of the flow speed and the gravity-wave speed keeps the density error
    near 1 % (paper 000: B = 100 rho0 u^2 / gamma, i.e. c0 = 10 u). Without the depth term a slow
    flow under deep water is compressed g depth / c0^2 by its own weight alone (measured in the
    tunnel, 0.15 m of water at c0 = 7.1 m/s: largest density error 7.9 %; at 12.1 m/s, 2.9 %, and
    2.1 % once its water no longer starts with a gap over the bed: tisph/sediment/initial.py)."""
    n = cfg.numerics
    if n.u_max > 0:
        u_max = n.u_max
    c0 = n.c0 if n.c0 > 0 else n.c0_factor * max(u_max, (g * depth) ** 0.5)
    return c0, u_max


def common_params(cfg, c0, g=9.81, depth=1.0):
    """The numeric parameters every scene passes to the solver."""
    n = cfg.numerics
    dx = n.dx
    wall_D = n.wall_strength if n.wall_strength > 0 else 5.0 * g * depth
    return dict(
        dx=dx,
        h=n.h_factor * dx,
        c0=c0,
        g=(0.0, -g),
        wall_D=wall_D,
        wall_r0=dx,
        shepard_every=n.shepard_every,
        **keyed_params(cfg),
    )


def keyed_params(cfg):
    """Every runtime parameter a module declares with a config key (Param.key), from the config: a
    new module's key reaches the solver without a line here (a missed one would run at its default)."""
    from ..engine.enabled import MODULES
    from ..engine.table import CORE_PARAMS, PARAM_ALIASES

    out = {}
    for decl in [CORE_PARAMS] + [m.params for m in MODULES]:
        for name, p in decl.items():
            if p.key:
                sec, key = p.key.split(".")
                out[PARAM_ALIASES.get(name, name)] = getattr(cfg, sec).get(key, p.default)  # a scene without the key
    return out


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


# each pair once compiles about 1.8 s longer (cold) and steps about 10 % faster at 3e6
# particle-steps/s: it repays its compile beyond about 5e7 particle-steps; at 1e8 it gains twice
# what it costs (docs/performance.md)
PAIR_ONCE_MIN = 1e8


def pair_once_wanted(cfg, n, h, c0):
    """run.pair_once: on, off, or auto: on when the run's particle-steps to its end time,
    estimated from its acoustic step cfl h / c0, reach PAIR_ONCE_MIN. Not from run.max_steps:
    a segment stopped by it and the run restarted from its checkpoint must choose alike."""
    mode = cfg.run.pair_once
    if mode != "auto":
        return mode == "on"
    steps = cfg.run.end_time / (cfg.numerics.cfl * h / c0)
    return n * steps >= PAIR_ONCE_MIN


def perturb(particles, amplitude, seed):
    """run.perturbation: each fluid particle (water, or a sand phase) moved by up to `amplitude` (m) in x and z, drawn from
    `seed`; one draw of the noise a run would carry, for an ensemble of a case with no random bed."""
    if amplitude > 0.0:
        water = particles.kind == FLUID
        rng = np.random.default_rng(int(seed))
        particles.x[water] += amplitude * rng.uniform(-1.0, 1.0, (int(water.sum()), 2))


def build_case(scene, cfg, log):
    """scene.build(cfg), with its warnings and the sound-speed check logged."""
    from ..case import as_scene

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        case = as_scene(scene).build(cfg)
        perturb(case.particles, cfg.run.perturbation * cfg.numerics.dx, cfg.run.seed)
        c0 = case.params["c0"]
        case.params["pair_once"] = pair_once_wanted(cfg, len(case.particles), case.params["h"], c0)
        if c0 < 10.0 * case.u_max * (1 - 1e-9):
            warnings.warn(
                f"sound speed c0 = {c0:.3g} m/s is below 10 x the expected peak speed "
                f"{case.u_max:.3g} m/s: density errors above 1 % are likely"
            )
        check_size(case, cfg)
    for w in caught:
        log(f"warning: {w.message}", always=True)
    case.warnings = [str(w.message) for w in caught]
    return case


# The engine's speed on these 2-core machines (python -m tisph.bench: 1.7e6 to 2.8e6
# particle-steps/s for the dam break); the run-time warning uses the upper figure.
PARTICLE_STEPS_PER_S = 2.8e6


def check_size(case, cfg):
    """Refuse a case that cannot fit in memory; warn when one will take very long."""
    n = len(case.particles)
    dx = cfg.numerics.dx
    check_fits(n, RUN_BYTES_PER_PARTICLE, dx, "this case")
    p = case.params
    from ..engine.table import CORE_PARAMS

    dt = p.get("cfl", CORE_PARAMS["cfl"].default) * p["h"] / p["c0"]  # the acoustic step, an upper bound
    wall_per_sim_s = n / PARTICLE_STEPS_PER_S / dt
    if wall_per_sim_s > 3600.0:
        warnings.warn(
            f"{n:,} particles at dt about {dt:.2g} s: expect about {wall_per_sim_s / 3600:.3g} hours "
            f"of wall time per simulated second on 2 cores (at {PARTICLE_STEPS_PER_S:.2g} "
            f"particle-steps/s); numerics.dx = {dx:g}"
        )


def describe_instability(solver, code, pid):
    from ..hooks.health import BAD_TEXT

    what, cause = BAD_TEXT.get(code, ("unknown", ""))
    s = solver.state(("x", "v", "rho", "kind", "mat"))  # ordered by particle id
    if 0 <= pid < solver.n:
        x, v, rho = s["x"][pid], s["v"][pid], s["rho"][pid]
        rho0 = solver.materials[int(s["mat"][pid])]["rho0"]
        where = (
            f"particle {pid} ({KIND_NAMES.get(int(s['kind'][pid]), '?')}) at x = ({x[0]:.4g}, {x[1]:.4g}) m, "
            f"|v| = {np.hypot(*v):.4g} m/s, rho = {rho:.6g} kg/m3 (rest {rho0:g})"
        )
    else:
        where = f"time step dt = {solver.dt:.3g} s"
    return unstable(solver, what, where, cause)


# Keys a restart may change: when and how to stop, and what to write.
RESTART_FREE = ("run.end_time", "run.max_steps", "run.arch", "output")


def run_settings(cfg):
    """The config less what a restart may change (RESTART_FREE): what must match to continue."""
    c = thaw(cfg)
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
        if isinstance(va, Mapping) and isinstance(vb, Mapping):
            out += config_changes(va, vb, f"{prefix}{k}.")
        elif va != vb:
            out.append(f"{prefix}{k}: {va!r} -> {vb!r}")
    return out
