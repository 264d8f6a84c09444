"""tisph from Python: build a case, run it, read what it wrote (docs/api.md).

    import tisph
    case = tisph.Case.from_toml("scenes/breakwater.toml")     # a custom case file
    case.set("run.end_time", 4.0)
    result = tisph.run(case, out="renders/bw", render=False)
    result.summary["metrics"], result.probes["t"], result.snapshot(-1)["position"]

A case is a scene and the settings a case file would hold; tisph.run takes the same path as
`python -m tisph.scenes.NAME` (every key checked, ConfigError on bad input; Ctrl-C or SIGTERM
stops it with a checkpoint that tisph.run(case, restart=...) continues from).
"""

from __future__ import annotations

import copy
import json
import os
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from . import registry as scenes
from .describe import describe
from .geometry import Circle, Polygon, Polyline
from .io import load, read_csv, snapshot_files
from .runner import output_dir, resolve, simulate
from .runner.reading import resolved_notes
from .settings.config import ConfigError, read_toml, set_path

SCENES = scenes.names()


def _entry(shape):
    """A geometry object (tisph.geometry) or a dict as a [[solid]] entry."""
    if isinstance(shape, dict):
        return dict(shape)
    if isinstance(shape, Circle):
        return {"circle": [float(shape.c[0]), float(shape.c[1]), shape.r], "label": shape.label}
    if isinstance(shape, Polyline):
        return {"line": shape.pts.tolist(), "label": shape.label}
    if isinstance(shape, Polygon):
        return {"polygon": shape.pts.tolist(), "label": shape.label}
    raise ConfigError("solid", repr(shape), "a tisph.geometry Polyline, Polygon or Circle, or a dict of [[solid]] keys")


class Case:
    """A scene and its settings (the tables of a case file, as nested dicts)."""

    def __init__(self, scene: str = "custom", settings: dict | None = None, base_dir: str = ".") -> None:
        self.scene = scene
        self.spec = scenes.load(scene)  # its Scene (tisph.case.Scene)
        self.settings = copy.deepcopy(settings or {})
        self.base_dir = os.path.abspath(base_dir)

    @classmethod
    def from_toml(cls, path: str | os.PathLike, scene: str | None = None) -> Case:
        """A case file; the scene is `custom` when the file has a [domain] table, else name it."""
        settings = read_toml(path)
        scene = scene or ("custom" if "domain" in settings else None)
        if scene is None:
            raise ConfigError(
                "scene",
                None,
                "a scene name for a built-in scene's case file, e.g. Case.from_toml(path, scene=\"tunnel\")",
            )
        return cls(scene, settings, os.path.dirname(os.path.abspath(path)))

    @classmethod
    def custom(
        cls, box: Sequence[float], solids: Iterable, water: Iterable[dict], gauges: Iterable[dict] = (), **tables: dict
    ) -> Case:
        """A custom case from Python: box [x0, x1, z0, z1]; solids: tisph.geometry shapes (or
        dicts of [[solid]] keys); water and gauges: dicts of [[water]] and [[gauge]] keys; tables:
        any other table, e.g. numerics={"dx": 0.02}, paddle={...}, run={"end_time": 2.0}."""
        s = {k: dict(v) for k, v in tables.items()}
        s.setdefault("domain", {})["box"] = [float(v) for v in box]
        s["solid"] = [_entry(v) for v in solids]
        s["water"] = [dict(v) for v in water]
        s["gauge"] = [dict(v) for v in gauges]
        return cls("custom", s)

    def set(self, key: str, value: Any) -> Case:
        """Set a dotted key (run.end_time, numerics.dx): checked when the case is resolved."""
        set_path(self.settings, key, value)
        return self

    def config(self, **overrides: Any) -> dict:
        """The resolved, checked config (ConfigError naming every bad key)."""
        return resolve(self.spec, self.file_settings(), overrides)

    def file_settings(self) -> dict:
        """A copy of the case file's settings, a custom case's CSVs looked for beside it."""
        settings = copy.deepcopy(self.settings)
        if self.scene == "custom":
            settings.setdefault("domain", {}).setdefault("base_dir", self.base_dir)
        return settings

    def describe(self) -> str:
        """Every key of the case's scene with its default, what is allowed and what it means."""
        return describe(self.spec, resolved_notes(self.spec))


class Result:
    """What a run wrote into its folder: summary, probes, snapshots."""

    def __init__(self, out: str | os.PathLike) -> None:
        self.out = out
        with open(os.path.join(out, "summary.json")) as f:
            self.summary = json.load(f)
        self.status = self.summary["status"]
        self.metrics = self.summary.get("metrics", {})

    @property
    def probes(self) -> dict[str, np.ndarray]:
        """probes.csv as {column: NumPy array}."""
        path = os.path.join(self.out, "probes.csv")
        if not os.path.exists(path):
            return {}
        return {k: np.asarray(v) for k, v in read_csv(path)[1].items()}

    def dataframe(self):
        """probes.csv as a pandas DataFrame (pandas must be installed)."""
        import pandas

        return pandas.DataFrame(self.probes)

    @property
    def snapshots(self) -> list[str]:
        """The snapshot files in time order."""
        return snapshot_files(self.out)

    def snapshot(self, k: int = -1) -> dict[str, Any]:
        """Snapshot k's particles as {name: array} (position (N, 2), velocity, pressure, kind, ...) and
        its time as ["time"]."""
        arrays, attrs = load(self.snapshots[k])
        arrays["time"] = float(attrs.get("time", attrs.get("t", np.nan)))
        return arrays

    @property
    def checkpoint(self) -> str | None:
        """The checkpoint an interrupted run left (None if there is none)."""
        path = os.path.join(self.out, "checkpoint.h5")
        return path if os.path.exists(path) else None

    def __repr__(self):
        s = self.summary
        return (
            f"Result({self.out!r}: {s['status']}, {s.get('particles')} particles, {s.get('steps')} steps, "
            f"{s.get('wall_time_s', 0):.3g} s)"
        )


def run(
    case: Case | str,
    out: str | os.PathLike | None = None,
    render: bool = False,
    progress: bool = True,
    restart: str | None = None,
    force: bool = False,
    convergence: bool = False,
    seeds: int = 0,
    **overrides: Any,
) -> Result:
    """Run a case (a Case, a case file's path or a built-in scene's name) and return its Result.
    overrides: dotted keys, e.g. run(case, **{"numerics.dx": 0.04}). convergence: also the case at
    1.5 and 2.25 times its dx, each metric's GCI (runner/convergence.py; Result.summary["convergence"]).
    seeds: N > 1 runs it with N seeds of its random bed (or, with none, of its start perturbed by
    run.perturbation), each metric's mean and standard error (runner/ensemble.py;
    Result.summary["ensemble"])."""
    if isinstance(case, str):
        case = Case.from_toml(case) if os.path.isfile(case) else Case(case)
    ov = dict(overrides)
    ov["output.render"] = bool(render)
    ov["output.quiet"] = not progress
    if out:
        ov["output.dir"] = str(out)
    cfg = case.config(**ov)
    if seeds:
        from .runner.ensemble import check_seeds

        if convergence:
            raise ConfigError("seeds", seeds, "one study a run: seeds or convergence, not both")
        check_seeds(cfg, seeds)
    out = output_dir(case.spec, cfg)
    summary = simulate(case.spec, cfg=cfg, out=out, restart=restart, force=force, echo=progress)
    if convergence and summary["status"] == "ok":
        from .runner.convergence import study

        study(case.spec, case.file_settings(), ov, cfg, summary, out, print if progress else (lambda m: None))
    if seeds and summary["status"] == "ok":
        from .runner import ensemble

        ensemble.study(
            case.spec, case.file_settings(), ov, cfg, summary, out, seeds, print if progress else (lambda m: None)
        )
    return Result(out)
