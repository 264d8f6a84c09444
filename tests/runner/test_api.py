"""The Python API: the worked example of docs/api.md runs as it stands, and a case file and a
bad key behave as on the command line."""

import os
import re

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


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
    from tisph.settings.config import ConfigError

    case = tisph.Case.from_toml(os.path.join(ROOT, "scenes", "dam_break_custom.toml"))
    case.set("numerics.dxx", 0.02)
    with pytest.raises(ConfigError, match="numerics.dxx"):
        case.config()
    with pytest.raises(ConfigError, match="scene"):
        tisph.Case.from_toml(os.path.join(ROOT, "scenes", "tunnel.toml"))


def test_a_run_continues_from_its_checkpoint(tmp_path):
    """tisph.run(..., restart=checkpoint) continues a run as --restart does: the continued run ends
    where one straight run ends, bit for bit."""
    import numpy as np

    import tisph

    case = tisph.Case.from_toml(os.path.join(ROOT, "scenes", "dam_break_custom.toml")).set("numerics.dx", 0.08)
    straight = tisph.run(case, out=tmp_path / "a", progress=False, **{"run.end_time": 0.2})
    first = tisph.run(case, out=tmp_path / "b", progress=False, **{"run.end_time": 0.1, "output.checkpoint_every": 0.1})
    assert first.checkpoint is not None
    second = tisph.run(case, out=tmp_path / "b", progress=False, restart=first.checkpoint, **{"run.end_time": 0.2})
    assert second.status == "ok" and second.summary["steps"] == straight.summary["steps"]
    a, b = straight.snapshot(-1), second.snapshot(-1)
    assert a["time"] == b["time"] and np.array_equal(a["position"], b["position"])
