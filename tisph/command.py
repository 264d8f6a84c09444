"""The `tisph` command, as `pysph run` and `pysph view` are for PySPH:

    tisph run SCENE|FILE [flags]     run a scene by name, or a case file (its scene from its [domain]
                                     table or its header's `python -m tisph.scenes.NAME` line)
    tisph describe SCENE             every key of a scene: default, allowed, meaning
    tisph scenes                     the scenes there are
    tisph view RUN [flags]           render a run again from its snapshots
    tisph metrics RUN                a run's metrics worked out again from its probes.csv
    tisph sweep SCENE [flags]        sweeps and ensembles (Dask)
    tisph bench [flags]              benchmarks and validation
    tisph stress [flags]             the stress suite

`python -m tisph.scenes.NAME`, `python -m tisph.view` and the others keep working; `tisph CMD -h`
gives each one's flags.
"""

from __future__ import annotations

import os
import re
import sys

from . import registry
from .errors import ConfigError
from .settings.config import read_toml


def scene_line(scene, width=100):
    """What a scene is, in one line: its class's docstring (importing a scene imports no Taichi)."""
    line = " ".join((type(scene).__doc__ or scene.NAME).split()).rstrip(".")
    return line if len(line) <= width else line[: width - 3].rsplit(" ", 1)[0] + "..."


COMMANDS = ("run", "describe", "scenes", "view", "metrics", "sweep", "bench", "stress")


def scene_of_file(path: str) -> str:
    """The scene a case file is for: custom with a [domain] table, else the one its header's
    `python -m tisph.scenes.NAME` line names."""
    if "domain" in read_toml(path):
        return "custom"
    with open(path, encoding="utf-8") as f:
        m = re.search(r"python -m tisph\.(?:scenes|validation)\.(\w+)", f.read())
    if not m or m.group(1) not in registry.REGISTRY:
        raise ConfigError(
            path,
            "a case file",
            "a custom case (a [domain] table) or a header line naming its scene, "
            "e.g. '#   python -m tisph.scenes.flume --config my_flume.toml'",
            "or run it as: tisph run SCENE --config FILE",
        )
    return m.group(1)


def run(argv: list[str]) -> int:
    if not argv or argv[0] in ("-h", "--help"):
        print(
            "usage: tisph run SCENE|FILE [flags]   (scenes: " + ", ".join(registry.names()) + "; "
            "tisph run SCENE -h: the flags)"
        )
        return 0 if argv else 2
    what, rest = argv[0], argv[1:]
    if what in registry.REGISTRY:
        name = what
    elif os.path.isfile(what):
        name = scene_of_file(what)
        rest = ["--config", what] + rest
    else:
        raise ConfigError("tisph run", what, "a scene (" + ", ".join(registry.names()) + ") or a case file that exists")
    from .runner import run_scene

    return run_scene(registry.load(name), rest, prog=f"tisph run {what}")


def describe(argv: list[str]) -> int:
    if len(argv) != 1 or argv[0] not in registry.REGISTRY:
        raise ConfigError("tisph describe", " ".join(argv), "one scene: " + ", ".join(registry.names()))
    from .describe import describe as text
    from .runner.reading import resolved_notes

    scene = registry.load(argv[0])
    print(text(scene, resolved_notes(scene)))
    return 0


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    cmd, rest = argv[0], argv[1:]
    try:
        if cmd == "run":
            return run(rest)
        if cmd == "describe":
            return describe(rest)
        if cmd == "scenes":
            for name in registry.names():
                print(f"{name:16s} {scene_line(registry.load(name))}")
            return 0
        if cmd == "view":
            from .view import main as view

            return view(rest)
        if cmd == "metrics":
            from .runner.reanalyse import main as metrics

            return metrics(rest)
        if cmd == "sweep":
            from .sweep import main as sweep

            return sweep(rest)
        if cmd == "bench":
            from .bench.cli import main as bench

            return bench(rest)
        if cmd == "stress":
            from .stress import main as stress

            return stress(rest)
    except ConfigError as e:
        print(f"tisph {cmd}: {e}", file=sys.stderr)
        return 2
    print(f"tisph: unknown command {cmd!r}; the commands are {', '.join(COMMANDS)} (tisph -h)", file=sys.stderr)
    return 2


def console() -> int:
    """The console script: main, quiet when its reader stops early (tisph describe flume | head)."""
    try:
        return main()
    except BrokenPipeError:
        sys.stderr.close()  # nothing more can be said to a closed pipe
        return 0


if __name__ == "__main__":
    sys.exit(console())
