"""Ensembles (`--seeds N`): a case run with N seeds of its random bed, or of a perturbation of its
start where it has none, each metric's mean, standard deviation and standard error; bad counts
refused before anything runs."""

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
        (dam_break, ["--seeds", "101"], ["--seeds", "from 2 to 100"]),
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


def test_a_case_with_no_random_bed_takes_seeds_of_a_perturbed_start(tmp_path):
    """The dam break has nothing random: its further runs start with each water particle moved by
    up to 1e-3 dx (run.seed, run.perturbation), the walls where they were, and the front's chaos
    carries that into the metrics; the same seed gives the same draw."""
    import numpy as np

    from tisph.particles import FLUID, ParticleSet
    from tisph.runner.setup import perturb

    ps = ParticleSet()
    ps.add(np.random.default_rng(0).uniform(0, 1, (50, 2)), FLUID, 0, 1000.0, 1.0)
    ps.add(np.zeros((5, 2)), 1, 0, 1000.0, 1.0)
    x0 = ps.x.copy()
    perturb(ps, 0.001 * 0.02, 7)
    moved = np.abs(ps.x - x0)
    assert moved[:50].max() <= 2e-5 and moved[:50].min() < moved[:50].max() and moved[:50].mean() > 4e-6
    assert not moved[50:].any()
    again = ParticleSet()
    again.x, again.kind = x0.copy(), ps.kind
    perturb(again, 0.001 * 0.02, 7)
    assert np.array_equal(again.x, ps.x)

    out = tmp_path / "d"
    argv = ["--dx", "0.08", "--end-time", "0.3", "--seeds", "2", "--out", str(out), "--quiet", "--no-render"]
    assert entry.run_scene(dam_break, argv) == 0
    e = json.loads((out / "summary.json").read_text())["ensemble"]
    assert e["key"] == "run.seed" and e["perturbation"] == 0.001 and e["seeds"] == [1, 2] == e["seeds_ok"]
    assert any(m["std"] > 0 for m in e["metrics"].values())
    # an input the same in every run is not drawn as moving for its mean's rounding (3e-16 of 3.43)
    from tisph.runner.ensemble import varying

    e["metrics"]["same"] = dict(n=2, mean=3.43, std=3.1e-16, stderr=2.2e-16, values=[3.43, 3.43])
    assert "same" not in varying(e) and varying(e)
    second = (out / "seeds" / "seed2" / "run.log").read_text()
    assert "perturbation = 0.001" in second and "seed = 2" in second
    assert "run.perturbation = 0.001" in (out / "seeds" / "ensemble.md").read_text()


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
