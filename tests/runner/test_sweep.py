"""Sweeps on Dask distributed (python -m tisph.sweep): a local cluster of two single-thread
workers, cases equal bit for bit to the same runs one by one, failures kept to their case,
--resume, and bad keys refused before any worker starts."""

import csv
import json
import os
import time

import pytest

pytest.importorskip("dask.distributed")

from tisph.runner import simulate  # noqa: E402
from tisph.scenes import tank  # noqa: E402
from tisph.sweep import main  # noqa: E402

TANK = ["--set", "geometry.depth=0.3,0.4", "--set", "numerics.dx=0.04,0.05", "--set", "run.max_steps=150"]


def rows(out):
    with open(os.path.join(out, "sweep.csv")) as f:
        return list(csv.DictReader(f))


@pytest.mark.slow
@pytest.mark.long
def test_tank_sweep_on_two_workers_equals_the_runs_one_by_one(tmp_path):
    out = str(tmp_path / "sw")
    assert main(["tank"] + TANK + ["--workers", "2", "--threads-per-worker", "1", "--out", out, "--quiet"]) == 0
    r = rows(out)
    assert len(r) == 4 and all(x["status"] == "ok" for x in r)
    assert {(x["geometry.depth"], x["numerics.dx"]) for x in r} == {
        ("0.3", "0.04"),
        ("0.3", "0.05"),
        ("0.4", "0.04"),
        ("0.4", "0.05"),
    }
    for x in r:
        d = os.path.join(out, x["case"])
        for f in ("summary.json", "probes.csv", "run.log"):
            assert os.path.exists(os.path.join(d, f))
        s = json.load(open(os.path.join(d, "summary.json")))
        one = simulate(
            tank,
            {
                "geometry.depth": float(x["geometry.depth"]),
                "numerics.dx": float(x["numerics.dx"]),
                "run.max_steps": 150,
                "output.render": False,
                "output.quiet": True,
            },
            out=str(tmp_path / "one" / x["case"]),
        )
        assert s["metrics"] == one["metrics"]  # deterministic per case, bit for bit
        assert s["steps"] == one["steps"] == 150
    for f in ("sweep.md", "sweep.png"):
        assert os.path.getsize(os.path.join(out, f)) > 0


@pytest.mark.slow
def test_a_failing_case_does_not_stop_the_others(tmp_path):
    out = str(tmp_path / "sw")
    # on paper 000's scheme, which CFL 1.0 takes apart (the default scheme holds at 1.0)
    code = main(
        [
            "dam_break",
            "--set",
            "numerics.cfl=0.4,1.0",
            "--set",
            "numerics.dx=0.06",
            "--set",
            "numerics.scheme=paper000",
            "--set",
            "run.end_time=1.0",
            "--workers",
            "2",
            "--out",
            out,
            "--quiet",
        ]
    )
    assert code == 0
    r = {float(x["numerics.cfl"]): x for x in rows(out)}
    assert r[0.4]["status"] == "ok"
    assert r[1.0]["status"] == "unstable" and "unstable at step" in r[1.0]["message"]


@pytest.mark.slow
def test_resume_runs_only_the_missing_cases(tmp_path):
    out = str(tmp_path / "sw")
    half = ["--set", "geometry.depth=0.3", "--set", "numerics.dx=0.04,0.05", "--set", "run.max_steps=150"]
    assert main(["tank"] + half + ["--workers", "2", "--out", out, "--quiet"]) == 0
    first = {x["case"]: os.path.getmtime(os.path.join(out, x["case"], "summary.json")) for x in rows(out)}
    assert len(first) == 2
    time.sleep(0.05)
    assert main(["tank"] + TANK + ["--workers", "2", "--out", out, "--quiet", "--resume"]) == 0
    r = rows(out)
    assert len(r) == 4 and all(x["status"] == "ok" for x in r)
    kept = [x for x in r if x["message"] == "kept (--resume)"]
    assert sorted(x["case"] for x in kept) == sorted(first)
    for c, t in first.items():  # the kept cases were not run again
        assert os.path.getmtime(os.path.join(out, c, "summary.json")) == t


@pytest.mark.parametrize(
    "argv, words",
    [
        (["tank", "--set", "geometry.depht=0.3,0.4"], ["geometry.depht", "geometry.depth"]),
        (["tank", "--set", "numerics.dx=0.04,-1"], ["numerics.dx", "-1", "> 0"]),
        (["tank", "--set", "numerics.dx"], ["--set", "KEY=V1,V2"]),
        (["tank", "--zip", "--set", "numerics.dx=0.04,0.05", "--set", "geometry.depth=0.3"], ["--zip", "equal length"]),
        (["tunel", "--set", "numerics.dx=0.04"], ["SCENE", "tunel", "tunnel"]),
        (["tank", "--seeds", "1"], ["--seeds", "from 2 to 100"]),
        (["tank", "--seeds", "2", "--set", "run.seed=4,5"], ["run.seed", "not both"]),
        (["tunnel", "--seeds", "2", "--set", "sediment.seed=4,5"], ["sediment.seed", "not both"]),
    ],
)
def test_bad_key_or_value_exits_2_before_any_worker(argv, words, tmp_path, capsys):
    t0 = time.perf_counter()
    assert main(argv + ["--out", str(tmp_path / "sw"), "--quiet"]) == 2
    err = capsys.readouterr().err
    for w in words:
        assert w in err, (w, err)
    assert time.perf_counter() - t0 < 5.0  # refused before a cluster started
    assert not os.path.exists(tmp_path / "sw" / "sweep.csv")
