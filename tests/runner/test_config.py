"""Config loading: strict keys with suggestions, types and ranges, the shipped case files."""

import os

import pytest

from tisph.scenes import dam_break, tank
from tisph.settings.config import ConfigError, build_config, dump_toml, merge, read_toml
from tisph.settings.resolved import freeze

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.mark.parametrize(
    "ov, field, text",
    [
        ({"numerics.dxx": 0.1}, "numerics.dxx", "numerics.dx"),
        ({"numerics.dx": -0.01}, "numerics.dx", "> 0"),
        ({"numerics.dx": "fine"}, "numerics.dx", "a number"),
        ({"numerics.xsph": 0.7}, "numerics.xsph", "<= 0.5"),
        ({"numerics.kernel": "gauss"}, "numerics.kernel", "'cubic'"),
        ({"numerics.wall": "ghost"}, "numerics.wall", "'dynamic'"),
        ({"run.end_time": 0.0}, "run.end_time", "> 0"),
        ({"run.max_steps": 2.5}, "run.max_steps", "an integer"),
        ({"output.render": "yes"}, "output.render", "true or false"),
        ({"materials.water.rho0": 0.0}, "materials.water.rho0", "> 0"),
        ({"materials.oil.rho0": 900.0}, "materials.oil", "materials.water"),
        ({"geometry.column_width": 5.0}, "geometry.column_width", "tank_width"),
        ({"numerics.dx": 0.4}, "numerics.dx", "4 particles"),
    ],
)
def test_bad_input_names_field_and_allowed(ov, field, text):
    with pytest.raises(ConfigError) as e:
        cfg = freeze(build_config(dam_break.SCENE.DEFAULTS, None, ov, dam_break.SCENE.RANGES))
        dam_break.SCENE.check(cfg)
    assert e.value.field == field
    assert text in str(e.value)


def test_toml_errors(tmp_path):
    bad = tmp_path / "b.toml"
    bad.write_text("[numerics\ndx = 1")
    with pytest.raises(ConfigError, match="valid TOML"):
        read_toml(bad)
    with pytest.raises(ConfigError, match="existing TOML"):
        read_toml(tmp_path / "missing.toml")


def test_shipped_case_file_reproduces_defaults():
    a = freeze(build_config(dam_break.SCENE.DEFAULTS, os.path.join(ROOT, "scenes", "dam_break.toml")))
    b = freeze(build_config(dam_break.SCENE.DEFAULTS))
    assert a == b


def test_dump_round_trips(tmp_path):
    cfg = freeze(build_config(tank.SCENE.DEFAULTS))
    f = tmp_path / "c.toml"
    f.write_text(dump_toml(cfg))
    assert merge(cfg, read_toml(f)) == cfg


def test_every_bad_key_is_reported_at_once(tmp_path):
    """A case file with three mistakes (an unknown key, a wrong type, a value out of range) gets
    one error line for each, not only the first."""
    f = tmp_path / "c.toml"
    f.write_text('[numerics]\ndxx = 0.1\ndx = "fine"\n[run]\nend_time = -1.0\n')
    with pytest.raises(ConfigError) as e:
        build_config(dam_break.SCENE.DEFAULTS, f, {"numerics.xsph": 0.7}, dam_break.SCENE.RANGES)
    lines = str(e.value).splitlines()
    assert len(lines) == 4
    for field in ("numerics.dxx", "numerics.dx", "run.end_time", "numerics.xsph"):
        assert sum(line.startswith(f"config error: {field} = ") for line in lines) == 1, (field, lines)


def test_summary_says_why_laminar_viscosity_is_on_when_the_config_says_off():
    from tisph.runner.summary import physics_notes
    from tisph.settings.config import physics_from_config

    cfg = freeze(
        build_config(tank.SCENE.DEFAULTS, None, {"geometry.sediment_depth": 0.2, "numerics.laminar_viscosity": False})
    )
    assert cfg["numerics"]["laminar_viscosity"] is False
    ph = physics_from_config(cfg)
    assert ph.laminar_viscosity and "rheology" in physics_notes(cfg, ph)[0]
    water_only = physics_from_config(cfg, materials_used=["water"])
    assert not water_only.laminar_viscosity and physics_notes(cfg, water_only) == []


def test_every_keyed_module_parameter_reaches_the_solver():
    """A module's Param with a config key is passed to the solver from that key (a key the scenes
    did not pass ran at its default: numerics.stress_limiter, found by a bench that changed nothing)."""
    from tisph.engine.table import PARAM_ALIASES
    from tisph.runner import resolve
    from tisph.runner.setup import common_params
    from tisph.scenes import pipeline_scour
    from tisph.settings.engine_keys import KEYED

    cfg = resolve(
        pipeline_scour,
        None,
        {
            "numerics.turbulence": "k_equation",
            "numerics.stress_limiter": 0.5,
            "numerics.mixing_length": 0.003,
            "numerics.delta": 0.05,
        },
    )
    prm = common_params(cfg, 10.0)
    keys = set(KEYED)
    assert {"numerics.stress_limiter", "numerics.mixing_length", "numerics.cfl"} <= keys
    names = {PARAM_ALIASES.get(k, k) for k in prm}
    for p in KEYED.values():
        sec, name = p.key.split(".")
        assert any(prm.get(n) == cfg[sec][name] for n in names), p.key
    assert prm["stress_limiter"] == 0.5 and prm["mixing_length"] == 0.003 and prm["delta"] == 0.05
