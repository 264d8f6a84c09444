"""Entry points: run a scene from the command line (run_scene) or from Python (simulate)."""
import os
import sys

from ..cli import make_parser, overrides_from_args
from ..config import ConfigError, ConfigErrors, build_config, raise_collected, dump_toml, flatten, read_toml, check_file
from ..sediment.coupling import refuse_unused_sediment_keys
from ..io import OutputError, ensure_dir
from ..plausible import check_materials
from ..particles import FLUID
from ..shared_keys import check_rules
from ..waves.paddle import paddle_notes
from .loop import Run
from .setup import Log, build_case
from ..describe import describe
from ..viz.live import display_problem
from ..schemes import apply_scheme


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
        if getattr(r, "movie", None) is not None:
            r.movie.abort()
        raise


def output_dir(scene, cfg):
    return cfg["output"]["dir"] or os.path.join("renders", scene.NAME)


class ResolvedConfig(dict):
    """A resolved config; notes: run.log's lines on the values the scene chose itself (derive)."""
    notes: list

    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        self.notes = []


def given_keys(config, overrides):
    """The dotted keys the user set, in the case file and as overrides (flags, the API)."""
    keys = set(overrides or {})
    if config:
        keys |= set(flatten(config if isinstance(config, dict) else read_toml(config)))
    return keys


def resolve(scene, config=None, overrides=None):
    """The validated config of a scene: defaults <- TOML <- overrides; then what the scene derives
    from the physics for a key the user left at its default (derive: the tunnel's dx and morfac),
    said in cfg.notes; then the scene's checks."""
    errors = []
    cfg = ResolvedConfig(build_config(scene.DEFAULTS, config, overrides or {}, getattr(scene, "RANGES", None),
                                      getattr(scene, "CHOICES", None), errors=errors))
    if not errors:
        return _checked(scene, cfg, config, overrides)
    # the scene's checks on the rest (each bad key at its default), so every error shows at once;
    # what they find about a key already reported, or a check the defaults cannot pass, is left out
    bad = {e.field for e in errors}
    try:
        _checked(scene, cfg, config, overrides)
    except ConfigErrors as e:
        errors += [x for x in e.errors if x.field not in bad]
    except ConfigError as e:
        errors += [e] if e.field not in bad else []
    except Exception:       # noqa: BLE001  (a check that cannot run on what is left stands aside)
        pass
    raise_collected(errors)


def _checked(scene, cfg, config, overrides):
    refuse_unused_sediment_keys(cfg, scene.DEFAULTS)
    if isinstance(config, str) and cfg.get("domain", {}).get("base_dir") == "":
        cfg["domain"]["base_dir"] = os.path.dirname(os.path.abspath(config))   # a case's files sit beside it
    check_materials(cfg)
    given = given_keys(config, overrides)
    cfg.notes += apply_scheme(cfg, given)
    if hasattr(scene, "derive"):
        cfg.notes += scene.derive(cfg, given)
    if hasattr(scene, "check"):
        scene.check(cfg)
    return cfg


def run_scene(scene, argv=None, prog=None):
    """Entry point of `python -m tisph.scenes.NAME` and `tisph run NAME`. Exit codes: 0 ok, 2 bad
    input, 3 unstable, 130/143 stopped by SIGINT/SIGTERM."""
    parser = make_parser(scene.NAME, (scene.__doc__ or "").strip(), prog)
    args = parser.parse_args(argv)
    if args.describe:
        print(describe(scene))
        return 0
    try:
        overrides = overrides_from_args(args)
        for flag, on in (("--convergence", args.convergence), ("--seeds", args.seeds is not None)):
            if on and args.restart:
                raise ConfigError(flag, True, "a run from its start (not with --restart)")
        if args.convergence and args.seeds is not None:
            raise ConfigError("--seeds", args.seeds, "one study a run: --seeds or --convergence, not both")
        cfg = resolve(scene, args.config, overrides)
        if args.seeds is not None:
            from .ensemble import check_seeds
            check_seeds(cfg, args.seeds)
        summary = simulate(scene, cfg=cfg, restart=args.restart, force=args.force, echo=True)
        if summary["status"] == "ok" and (args.convergence or args.seeds is not None):
            say = (lambda m: None) if cfg["output"]["quiet"] else (lambda m: print(m, file=sys.stderr))
            out = output_dir(scene, cfg)
            if args.convergence:
                from .convergence import study
                entry = study(scene, args.config, overrides, cfg, summary, out, say)
                say(f"convergence: {os.path.join(out, 'convergence', 'convergence.md')}"
                    + (f" ({entry['reason']})" if entry["reason"] else ""))
            else:
                from . import ensemble
                ensemble.study(scene, args.config, overrides, cfg, summary, out, args.seeds, say)
                say(f"seeds: {os.path.join(out, 'seeds', 'ensemble.md')}")
    except (ConfigError, OutputError) as e:
        print(f"{parser.prog}: {e}", file=sys.stderr)
        return 2
    if not cfg["output"]["quiet"]:
        print(f"wrote {output_dir(scene, cfg)}/", file=sys.stderr)
    if summary["status"] == "interrupted":
        return 143 if "SIGTERM" in summary["message"] else 130
    return {"ok": 0, "unstable": 3}[summary["status"]]


def check_live(cfg):
    """--live (output.live) needs frames and a display: refused before anything compiles."""
    if not cfg["output"]["live"]:
        return
    if not cfg["output"]["render"]:
        raise ConfigError("output.live", True, "false with --no-render (output.render = false)",
                          "--live shows the frames as they are rendered")
    why = display_problem()
    if why:
        raise ConfigError("output.live", True, "false on a machine without a display", why)


def simulate(scene, overrides=None, out=None, config=None, restart=None, force=False, cfg=None,
             echo=False):
    """Run a scene: the path the CLI takes, callable from Python (tests, benchmarks).

    Returns the summary dict; raises ConfigError or OutputError on bad input. echo: print
    messages as the CLI does (otherwise only to run.log and only warnings to stderr).
    """
    from .. import runtime
    cfg = cfg if cfg is not None else resolve(scene, config, overrides)
    check_live(cfg)
    out = out or output_dir(scene, cfg)
    ensure_dir(out)
    log = Log(os.path.join(out, "run.log"), cfg["output"]["quiet"] or not echo)
    try:
        log("# resolved config\n" + dump_toml(cfg), file_only=True)
        for note in paddle_notes(cfg):
            log(note, file_only=True)
        for note in getattr(cfg, "notes", ()):
            log(note)
        arch = runtime.init(cfg["run"]["arch"], cfg["run"]["precision"])
        log(f"# {runtime.describe()}, requested {cfg['run']['arch']}", file_only=True)
        if cfg["run"]["arch"] == "gpu" and arch in ("x64", "arm64"):
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
