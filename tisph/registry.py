"""The one list of scenes: every runnable scene by name, which the command line, the API,
--describe, the sweep, the viewer and the golden cases read. A scene registers here once.

A scene module keeps this contract (docs/engine.md, "Adding a scene"):
  NAME        its name, as registered here
  DEFAULTS    every key it reads, at its default (the schema: a case file may set only these)
  RANGES      {dotted key: (lo, hi, lo inclusive, hi inclusive)} beyond the shared ones (optional)
  CHOICES     {dotted key: allowed values} beyond the shared ones (optional)
  check(cfg)  refuses a case it cannot run, with a ConfigError naming the key (optional)
  build(cfg)  -> tisph.case.Case: particles, physics, parameters, observers, picture
  main(argv)  the command line: runner.run_scene(module, argv)
Importing a scene module imports no Taichi: reading, checking and describing a case do not compile.
The modules are named, not imported, here: this file sits below everything it lists.
"""
from __future__ import annotations

import importlib
from types import ModuleType

from .config import ConfigError

# name -> module: register a new scene here, once
REGISTRY = {
    "dam_break": "tisph.scenes.dam_break",
    "hatch": "tisph.scenes.hatch",
    "erodible_bed": "tisph.scenes.erodible_bed",
    "tank": "tisph.scenes.tank",
    "flume": "tisph.scenes.flume",
    "beach": "tisph.scenes.beach",
    "tunnel": "tisph.scenes.tunnel",
    "pipeline_scour": "tisph.scenes.pipeline_scour",
    "custom": "tisph.scenes.custom",
    "poiseuille": "tisph.validation.poiseuille",
}


def names() -> tuple[str, ...]:
    """Every registered scene's name."""
    return tuple(REGISTRY)


def load(name: str) -> ModuleType:
    """The scene module registered as `name`, or a ConfigError naming the choices."""
    if name not in REGISTRY:
        raise ConfigError("scene", name, "one of " + ", ".join(REGISTRY))
    return importlib.import_module(REGISTRY[name])


def modules() -> list[ModuleType]:
    """Every registered scene's module, in the registry's order."""
    return [load(n) for n in REGISTRY]
