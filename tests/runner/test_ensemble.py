"""Ensembles (`--seeds N`): a case run with N seeds of its random bed, each metric's mean,
standard deviation and standard error; a case with nothing random refused before it runs."""

import json
import math
import os

import pytest

from tisph.measure.spread import ensemble_metrics, spread
from tisph.runner import entry
from tisph.scenes import dam_break, tunnel


def test_spread_of_four_values_and_a_missing_one():
    m = spread([1.0, 2.0, None, 3.0, 4.0])
    assert m["n"] == 4 and m["mean"] == 2.5
    assert m["std"] == pytest.approx(math.sqrt(5.0 / 3.0)) and m["stderr"] == pytest.approx(math.sqrt(5.0 / 12.0))
    assert m["values"] == [1.0, 2.0, None, 3.0, 4.0]
    assert spread([7.0])["std"] is None
    e = ensemble_metrics([{"a": 1.0, "flag": True}, None, {"a": 3.0, "b": float("nan")}])
    assert list(e) == ["a"] and e["a"]["n"] == 2


@pytest.mark.parametrize(
    "scene, argv, words",
    [
        (dam_break, ["--seeds", "3"], ["--seeds", "nothing random"]),
        (tunnel, ["--seeds", "1"], ["--seeds", "from 2 to 100"]),
        (tunnel, ["--seeds", "2", "--convergence"], ["--seeds", "not both"]),
    ],
)
def test_seeds_refused_before_the_run(scene, argv, words, tmp_path, capsys):
    assert entry.run_scene(scene, argv + ["--out", str(tmp_path / "o"), "--quiet", "--no-render"]) == 2
    err = capsys.readouterr().err
    for w in words:
        assert w in err, (w, err)
    assert not os.path.exists(tmp_path / "o" / "summary.json")


def test_seeds_on_the_tunnel(tmp_path):
    out = tmp_path / "t"
    assert (
        entry.run_scene(
            tunnel, ["--dx", "0.02", "--end-time", "0.3", "--seeds", "2", "--out", str(out), "--quiet", "--no-render"]
        )
        == 0
    )
    e = json.loads((out / "summary.json").read_text())["ensemble"]
    assert e["seeds"] == [1, 2] and e["seeds_ok"] == [1, 2]
    assert all(m["n"] == 2 and len(m["values"]) == 2 for m in e["metrics"].values())
    # the two beds differ: some metric differs between the seeds
    assert any(m["std"] > 0 for m in e["metrics"].values())
    for f in ("ensemble.md", "ensemble.csv", "ensemble.png"):
        assert os.path.getsize(out / "seeds" / f) > 0
    assert json.loads((out / "seeds" / "seed2" / "summary.json").read_text())["status"] == "ok"


def test_a_sweep_with_seeds_writes_each_combination_s_spread(tmp_path):
    from tisph.sweep import write_ensemble

    cases, results = [], {}
    for dx in (0.01, 0.02):
        for seed, ripples in ((1, 7.0), (2, 8.0), (3, None)):
            cid = f"dx{dx}_s{seed}"
            cases.append((cid, {"numerics.dx": dx, "sediment.seed": seed}, {}))
            results[cid] = (
                ("ok", "", {"metrics": {"ripple_count": ripples + dx}})
                if ripples
                else ("unstable", "unstable at step 9", None)
            )
    write_ensemble(str(tmp_path), cases, results)
    rows = (tmp_path / "ensemble.csv").read_text().splitlines()
    assert rows[0] == "numerics.dx,metric,runs_ok,mean,std,stderr"
    assert rows[1].startswith("0.01,ripple_count,2,7.51,0.707") and rows[2].startswith("0.02,ripple_count,2,7.52,")
    assert "| 0.02 | ripple_count | 2 | 7.52 |" in (tmp_path / "ensemble.md").read_text()
