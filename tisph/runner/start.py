"""Starting a run from Python (simulate), as the command line does: the resolved case, its log,
its build and its time loop."""

import os

from ..case import as_scene
from ..io import OutputError, ensure_dir
from ..particles import FLUID
from ..settings.config import ConfigError, check_file, dump_toml
from ..settings.shared_keys import check_rules
from ..viz.live import display_problem
from .loop import Run
from .reading import resolve
from .setup import Log, build_case


def run_case(case, cfg, out, log, scene_name, restart=None, force=False):
    from .. import runtime

    if case.particles.count(FLUID) == 0:
        raise ConfigError("geometry", "no fluid particles", "a case with at least one fluid particle")
    check_rules(cfg, case.physics, case.particles)
    r = Run(case, cfg, out, log, scene_name, restart, force)
    r.arch = runtime.current_arch()
    try:
        return r.execute()
    except BaseException:
        if getattr(r, "frames", None) is not None:
            r.frames.abort()
        raise


def output_dir(scene, cfg):
    return cfg.output.dir or os.path.join("renders", scene.NAME)


def check_live(cfg):
    """--live (output.live) needs frames and a display: refused before anything compiles."""
    if not cfg.output.live:
        return
    if not cfg.output.render:
        raise ConfigError(
            "output.live",
            True,
            "false with --no-render (output.render = false)",
            "--live shows the frames as they are rendered",
        )
    why = display_problem()
    if why:
        raise ConfigError("output.live", True, "false on a machine without a display", why)


def simulate(scene, overrides=None, out=None, config=None, restart=None, force=False, cfg=None, echo=False):
    """Run a scene: the path the CLI takes, callable from Python (tests, benchmarks).

    Returns the summary dict; raises ConfigError or OutputError on bad input. echo: print
    messages as the CLI does (otherwise only to run.log and only warnings to stderr).
    """
    from .. import runtime

    scene = as_scene(scene)
    cfg = cfg if cfg is not None else resolve(scene, config, overrides)
    check_live(cfg)
    out = out or output_dir(scene, cfg)
    ensure_dir(out)
    log = Log(os.path.join(out, "run.log"), cfg.output.quiet or not echo)
    try:
        log("# resolved config\n" + dump_toml(cfg), file_only=True)
        for note in getattr(cfg, "notes", ()):
            log(note)
        arch = runtime.init(cfg.run.arch, cfg.run.precision)
        log(f"# {runtime.describe()}, requested {cfg.run.arch}", file_only=True)
        if cfg.run.arch == "gpu" and arch in ("x64", "arm64"):
            log("warning: no GPU backend found, running on the CPU", always=True)
        if restart:
            check_file("--restart", restart, "checkpoint.h5 written by tisph")
        case = build_case(scene, cfg, log)
        return run_case(case, cfg, out, log, scene.NAME, restart=restart, force=force)
    except (ConfigError, OutputError) as e:
        log(f"error: {e}", file_only=True)
        raise
    finally:
        log.flush()
