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
