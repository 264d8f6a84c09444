"""A tank at rest keeps hydrostatic pressure, stays still and keeps its water, for both wall types."""
import pytest

from tisph.run import simulate
from tisph.scenes import tank


@pytest.mark.slow
@pytest.mark.parametrize("wall", ["dynamic", "repulsive"])
def test_tank_at_rest(wall, tmp_path):
    s = simulate(tank, {"numerics.wall": wall, "numerics.dx": 0.025, "geometry.depth": 0.4,
                        "geometry.width": 0.4, "geometry.tank_height": 0.5, "run.end_time": 1.5,
                        "output.render": False, "output.quiet": True}, out=str(tmp_path))
    m = s["metrics"]
    assert s["status"] == "ok"
    assert s["leaked_particles"] == 0 and m["crossed_wall"] == 0
    assert m["layers_checked"] >= 12
    assert m["pressure_error"] < 0.03          # p = rho g d within 3 % below the top two rows
    assert m["speed_ratio"] < 0.01             # settled: peak speed below 1 % of sqrt(g H)
    assert m["peak_speed_ratio_max"] < 0.05    # and it never sloshed
