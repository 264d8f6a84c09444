"""The command line's entry point: run a scene, or describe it, or study it (--convergence,
--seeds)."""

import os
import sys

from ..case import as_scene
from ..cli import make_parser, overrides_from_args
from ..describe import describe
from ..io import OutputError
from ..settings.config import ConfigError
from .convergence import study as convergence_study
from .ensemble import check_seeds
from .ensemble import study as seeds_study
from .reading import resolve, resolved_notes
from .start import output_dir, simulate


def run_scene(scene, argv=None, prog=None):
    """Entry point of `python -m tisph.scenes.NAME` and `tisph run NAME`. Exit codes: 0 ok, 2 bad
    input, 3 unstable, 130/143 stopped by SIGINT/SIGTERM."""
    scene = as_scene(scene)
    parser = make_parser(scene.NAME, scene.doc, prog)
    args = parser.parse_args(argv)
    if args.describe:
        print(describe(scene, resolved_notes(scene)))
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
            check_seeds(cfg, args.seeds)
        summary = simulate(scene, cfg=cfg, restart=args.restart, force=args.force, echo=True)
        if summary["status"] == "ok" and (args.convergence or args.seeds is not None):
            say = (lambda m: None) if cfg.output.quiet else (lambda m: print(m, file=sys.stderr))
            out = output_dir(scene, cfg)
            if args.convergence:
                entry = convergence_study(scene, args.config, overrides, cfg, summary, out, say)
                say(
                    f"convergence: {os.path.join(out, 'convergence', 'convergence.md')}"
                    + (f" ({entry['reason']})" if entry["reason"] else "")
                )
            else:
                seeds_study(scene, args.config, overrides, cfg, summary, out, args.seeds, say)
                say(f"seeds: {os.path.join(out, 'seeds', 'ensemble.md')}")
    except (ConfigError, OutputError) as e:
        print(f"{parser.prog}: {e}", file=sys.stderr)
        return 2
    if not cfg.output.quiet:
        print(f"wrote {output_dir(scene, cfg)}/", file=sys.stderr)
    if summary["status"] == "interrupted":
        return 143 if "SIGTERM" in summary["message"] else 130
    return {"ok": 0, "unstable": 3}[summary["status"]]
