"""Config loading: strict keys with suggestions, types and ranges, the shipped case files."""
import os

import pytest

from tisph.config import ConfigError, build_config, dump_toml, merge, read_toml
from tisph.scenes import dam_break, tank

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@pytest.mark.parametrize("ov, field, text", [
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
])
def test_bad_input_names_field_and_allowed(ov, field, text):
    with pytest.raises(ConfigError) as e:
        cfg = build_config(dam_break.DEFAULTS, None, ov, dam_break.RANGES)
        dam_break.check(cfg)
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
    a = build_config(dam_break.DEFAULTS, os.path.join(ROOT, "scenes", "dam_break.toml"))
    b = build_config(dam_break.DEFAULTS)
    assert a == b


def test_dump_round_trips(tmp_path):
    cfg = build_config(tank.DEFAULTS)
    f = tmp_path / "c.toml"
    f.write_text(dump_toml(cfg))
    assert merge(cfg, read_toml(f)) == cfg
