"""The Python API: the worked example of docs/api.md runs as it stands, and a case file and a
bad key behave as on the command line."""
import os
import re

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def test_the_worked_example_of_docs_api_runs(tmp_path, monkeypatch):
    text = open(os.path.join(ROOT, "docs", "api.md"), encoding="utf-8").read()
    block = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    scope = {}
    exec(compile(block, "docs/api.md", "exec"), scope)
    r = scope["result"]
    assert r.summary["particles"] > 400 and r.summary["steps"] > 100
    assert (tmp_path / "renders" / "api_example" / "probes.csv").exists()
    # the wall gauge starts at the column's hydrostatic pressure at z = 0.3 m under 1.2 m of water
    assert r.probes["p_wall"][0] == pytest.approx(1000 * 9.81 * 0.9, rel=0.05)


def test_a_bad_key_is_a_config_error_naming_it():
    import tisph
    from tisph.config import ConfigError
    case = tisph.Case.from_toml(os.path.join(ROOT, "scenes", "dam_break_custom.toml"))
    case.set("numerics.dxx", 0.02)
    with pytest.raises(ConfigError, match="numerics.dxx"):
        case.config()
    with pytest.raises(ConfigError, match="scene"):
        tisph.Case.from_toml(os.path.join(ROOT, "scenes", "tunnel.toml"))
