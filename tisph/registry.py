"""The one list of scenes: every runnable scene by name, which the command line, the API,
--describe, the sweep, the viewer and the golden cases read. A scene registers here once: one
line, its name and the module that holds its Scene (tisph/case.py: the contract) as SCENE.
The modules are named, not imported, here: this file sits below everything it lists, and reading,
checking and describing a case compile nothing.
"""

from __future__ import annotations

import importlib

from .settings.config import ConfigError

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


def load(name: str):
    """The Scene registered as `name`, or a ConfigError naming the choices."""
    if name not in REGISTRY:
        raise ConfigError("scene", name, "one of " + ", ".join(REGISTRY))
    return importlib.import_module(REGISTRY[name]).SCENE


def scenes() -> list:
    """Every registered Scene, in the registry's order."""
    return [load(n) for n in REGISTRY]
