"""The benchmark's own code paths, in seconds: one tiny case, tiny scaling, no peer, no timing checks."""
import csv
import math

from tisph import bench


def test_bench_dry_run(tmp_path):
    assert bench.main(["--dry-run", "--out", str(tmp_path)]) == 0
    with open(tmp_path / "bench.csv") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["case", "dx", "particles", "steps", "sim_time", "wall_time_s", "compile_time_s",
                             "step_time_s", "particle_steps_per_s", "metric", "error", "status"]
    assert len(rows) == 2 and all(r["status"] == "ok" for r in rows)
    assert all(math.isfinite(float(r["error"])) and int(r["particles"]) > 0 for r in rows)
    md = (tmp_path / "bench.md").read_text()
    for part in ("## Run time against error", "Observed convergence order", "## Scaling", "## Specialisation"):
        assert part in md
    with open(tmp_path / "scaling.csv") as f:
        sc = list(csv.DictReader(f))
    assert float(sc[0]["field_bytes_per_particle"]) > 50


def test_convergence_order():
    assert bench.convergence_order([0.04, 0.02, 0.01], [0.4, 0.1, 0.025]) == __import__("pytest").approx(2.0)
    assert math.isnan(bench.convergence_order([0.04], [0.1]))


def test_speed_bench_refuses_an_unknown_revision_by_name(tmp_path):
    """--speed --against REV checks REV out into a worktree first: a name git does not know is
    refused before anything runs, naming it."""
    import pytest
    from tisph import bench
    with pytest.raises(SystemExit) as e:
        bench.main(["--speed", "--against", "no-such-rev-xyz", "--out", str(tmp_path)])
    assert "no-such-rev-xyz" in str(e.value)


def test_speed_report_gives_the_ratio_per_case():
    import argparse
    from tisph import speed
    a = argparse.Namespace(against="abc123", repeats=3)
    rows = [dict(case="dam break dx 0.03", particles=3426, steps=10, pps=3.0e6, field_bytes=243.4,
                 pps_against=2.0e6, ratio=1.5)]
    text = "\n".join(speed.report(a, rows, 1.3, 0.5))
    assert "| dam break dx 0.03 | 3426 | 10 | 3e+06 | 243.4 | 2e+06 | 1.50 |" in text
    assert "cold 1.30 s" in text and "warm 0.50 s" in text
