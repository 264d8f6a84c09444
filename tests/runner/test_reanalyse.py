"""`tisph metrics RUN` (tisph/runner/reanalyse.py): a run's metrics worked out again from its probes
and its resolved config, the same as the run's own; a bad folder refused by name."""

import json

import pytest

from tisph import command
from tisph.runner import simulate
from tisph.runner.reanalyse import reanalyse
from tisph.scenes import dam_break, flume


@pytest.mark.parametrize(
    "scene, ov",
    [(dam_break, {"numerics.dx": 0.06, "run.end_time": 0.3}), (flume, {"numerics.dx": 0.03, "run.end_time": 2.0})],
)
def test_metrics_from_the_probes_are_the_runs(tmp_path, scene, ov, capsys):
    out = tmp_path / scene.__name__.rsplit(".", 1)[1]
    s = simulate(scene, dict(ov, **{"output.render": False, "output.quiet": True}), out=str(out))
    assert s["status"] == "ok"
    _, rows = reanalyse(str(out))
    # the flume's gauges keep their zero offsets (their first readings) themselves, not in the probes
    kept = {"gauge_zero_offset"} if scene is flume else set()
    assert rows and all(v == "same" for k, (_, _, v) in rows.items() if k not in kept), rows
    assert all(rows[k][2] == "not in the probes" for k in kept)
    # a metric worked out differently is said, and the run's summary.json is left as it was
    summary = json.loads((out / "summary.json").read_text())
    key = next(k for k, v in summary["metrics"].items() if isinstance(v, float))
    summary["metrics"][key] = 123.0
    (out / "summary.json").write_text(json.dumps(summary))
    assert command.main(["metrics", str(out)]) == 0
    said = capsys.readouterr().out
    assert f"differing: {key}" in said
    assert json.loads((out / "summary.json").read_text()) == summary


def test_a_folder_that_is_not_a_run_is_refused(tmp_path, capsys):
    (tmp_path / "summary.json").write_text(json.dumps({"scene": "dam_break", "metrics": {}}))
    assert command.main(["metrics", str(tmp_path)]) == 2
    assert "run.log" in capsys.readouterr().err
