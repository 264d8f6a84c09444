"""The scene contract (tisph/case.py) and the resolved case (tisph/settings/resolved.py): a new scene
is one class plus one registry line, a new key is one Key in its SCHEMA, and the case a scene
sees is resolved once and frozen."""

import dataclasses
import json
import sys
import textwrap

import pytest

from tisph import registry
from tisph.runner import resolve
from tisph.settings.config import ConfigError

PUDDLE = '''
"""A puddle: still water in a box (a scene written in one class for the contract's test)."""
import numpy as np

from tisph.case import make_case
from tisph.settings.config import physics_from_config
from tisph.particles import ParticleSet, block, box_walls, hydrostatic_density, tait_B, FLUID, WALL
from tisph.runner import common_params, sound_speed
from tisph.settings.schema import K, POSITIVE
from tisph.case import Scene, resolves
from tisph.settings.schemes import numerics


class Puddle(Scene):
    NAME = "puddle"
    SCHEMA = {
        "run": {"end_time": 0.05},
        "numerics": numerics("default", dx=0.02),
        "geometry": {"width": K(0.4, "the box's inside width", "m", POSITIVE),
                     "depth": K(0.1, "the still water's depth", "m", (0.0, 0.3, False, True))},
        "materials": {"water": {"rho0": 1000.0, "viscosity": 1.0e-3}},
        "output": {"render": False},
    }

    def check(self, cfg):
        resolves(cfg.geometry.depth, 4, "the water", cfg.numerics.dx)

    def build(self, cfg):
        g, dx, rho0 = cfg.geometry, cfg.numerics.dx, cfg.materials.water.rho0
        c0, u = sound_speed(cfg, 0.1, g.depth)
        ps = ParticleSet()
        water = block(0.0, 0.0, g.width, g.depth, dx)
        ps.add(water, FLUID, 0, hydrostatic_density(g.depth - water[:, 1], rho0, c0, 9.81), rho0 * dx * dx)
        ps.add(box_walls(0.0, 0.0, g.width, 2 * g.depth, dx, cfg.numerics.wall_layers), WALL, 0, rho0,
               rho0 * dx * dx)
        pad = 6 * dx + 0.1
        return make_case(name=self.NAME, particles=ps, domain=((-pad, -pad), (g.width + pad, 2 * g.depth + pad)),
                         materials=[dict(name="water", rho0=rho0, viscosity=1e-3, B=tait_B(rho0, c0))],
                         params=common_params(cfg, c0, 9.81, g.depth), physics=physics_from_config(cfg),
                         view=((-0.05, -0.05), (g.width + 0.05, 2 * g.depth)), u_max=u,
                         probe_columns=("level",), probe=lambda st: (float(st["x"][st["kind"] == FLUID, 1].max()),),
                         metrics=lambda cols: dict(level_end=float(cols["level"][-1])))


SCENE = Puddle()
'''


@pytest.fixture
def puddle(tmp_path, monkeypatch):
    """The puddle scene's module on the path and its one registry line."""
    (tmp_path / "puddle_scene.py").write_text(textwrap.dedent(PUDDLE))
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setitem(registry.REGISTRY, "puddle", "puddle_scene")
    yield registry.load("puddle")
    sys.modules.pop("puddle_scene", None)


def test_a_scene_is_one_class_and_one_registry_line(puddle, tmp_path, capsys):
    from tisph.command import main
    from tisph.describe import describe

    assert puddle.DEFAULTS["geometry"]["depth"] == 0.1 and puddle.RANGES["geometry.depth"][1] == 0.3
    out = tmp_path / "run"
    assert main(["run", "puddle", "--max-steps", "20", "--out", str(out), "--quiet"]) == 0
    s = json.load(open(out / "summary.json"))
    assert s["status"] == "ok" and 0.08 < s["metrics"]["level_end"] < 0.11
    # the new key: described from its Key, checked against its range, named in the refusal
    assert "depth = 0.1" in describe(puddle) and "the still water's depth (m)" in describe(puddle)
    case = tmp_path / "deep.toml"
    case.write_text("[geometry]\ndepth = 0.5\n")
    assert main(["run", "puddle", "--config", str(case)]) == 2
    assert "geometry.depth = 0.5" in capsys.readouterr().err
    # the one rule for a length the spacing cannot resolve
    with pytest.raises(ConfigError, match=r"at most 0.025 m \(4 particles across the water\)") as e:
        resolve(puddle, None, {"numerics.dx": 0.04})
    assert e.value.field == "numerics.dx"


def test_the_resolved_case_is_frozen_and_read_by_attribute():
    from tisph.scenes import flume

    cfg = resolve(flume, None, {"paddle.wave_height": 0.05})
    assert cfg.numerics.dx == cfg["numerics"]["dx"] and cfg.materials.water.rho0 == 1000.0
    assert dataclasses.is_dataclass(cfg.numerics) and type(cfg.numerics).__name__ == "Numerics"
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.numerics.dx = 0.1
    with pytest.raises(TypeError):
        cfg.numerics["dx"] = 0.1
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.materials.water = {}
    # the stroke the wave height asks for is a resolving step's value, with its line
    assert cfg.paddle.stroke == pytest.approx(0.0330, abs=1e-4)
    assert any(n.startswith("paddle.stroke = 0.033") for n in cfg.notes)
    # a step's result is a new case; the old one is unchanged
    fine = cfg.replace({"numerics.dx": 0.01})
    assert (fine.numerics.dx, cfg.numerics.dx, fine.notes) == (0.01, 0.0125, cfg.notes)
    with pytest.raises(KeyError, match="numerics.dxx"):
        cfg.replace({"numerics.dxx": 0.01})


def test_every_registered_scene_keeps_the_contract():
    from tisph.case import Scene

    for name in registry.names():
        scene = registry.load(name)
        assert isinstance(scene, Scene) and name == scene.NAME and scene.doc
        assert scene.DEFAULTS and set(scene.DEFAULTS) >= {"run", "numerics", "output"}


def test_a_key_has_one_default():
    """A key the numerics scheme sets has the default scheme's value as its default everywhere it
    is declared: the shared keys, the engine's runtime parameters and every scene on that scheme."""
    from tisph.settings.engine_keys import KEYED
    from tisph.settings.schemes import DEFAULT, SCHEMES
    from tisph.settings.shared_keys import SHARED

    for key, value in SCHEMES[DEFAULT].items():
        assert SHARED["numerics"][key].default == value, key
        if f"numerics.{key}" in KEYED:
            assert KEYED[f"numerics.{key}"].default == value, key
    for name in registry.names():
        num = registry.load(name).DEFAULTS["numerics"]
        scheme = SCHEMES[num["scheme"]]
        assert all(num[k] == v for k, v in scheme.items() if k not in registry.load(name).DEPARTS), name
