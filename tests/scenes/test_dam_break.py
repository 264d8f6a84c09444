"""Dam break against Martin & Moyce (1952), at coarse resolutions."""

import math

import numpy as np
import pytest

from tisph.io import read_csv
from tisph.runner import simulate
from tisph.scenes import dam_break
from tisph.validation import martin_moyce

T_END = 3.3 / math.sqrt(2 * 9.81 / 1.0)  # the last reference time used, T = 3.3


def run(tmp_path, dx, **ov):
    o = {"numerics.dx": dx, "run.end_time": T_END, "output.render": False, "output.quiet": True}
    o.update(ov)
    out = tmp_path / f"dx{dx}_{ov.get('numerics.wall', 'dynamic')}"
    s = simulate(dam_break, o, out=str(out))
    _, cols = read_csv(out / "probes.csv")
    return s, cols


def test_reference_data_is_tabulated():
    assert len(martin_moyce.T) == len(martin_moyce.Z) == 15
    assert np.all(np.diff(martin_moyce.T) > 0) and np.all(np.diff(martin_moyce.Z) > 0)
    # the error measure is zero on the data itself and sees a shift
    t = martin_moyce.T / math.sqrt(2 * 9.81)
    assert martin_moyce.front_rms_error(t, martin_moyce.Z * 1.0, 1.0)[0] < 1e-12
    assert abs(martin_moyce.front_rms_error(t, martin_moyce.Z + 0.1, 1.0)[0] - 0.1) < 1e-12


@pytest.mark.slow
def test_front_follows_martin_moyce_and_is_resolution_robust(tmp_path):
    coarse, cc = run(tmp_path, 0.06)
    fine, cf = run(tmp_path, 0.03)
    for s in (coarse, fine):
        assert s["status"] == "ok" and s["leaked_particles"] == 0
        assert s["metrics"]["front_points"] == 14
    # Bound: WCSPH fronts lead Martin & Moyce early on because the experiment's gate took time to
    # lift (the measured front starts slowly: Z = 1.11 -> 1.22 between T = 0.41 and 0.84) while the
    # later front speed dZ/dT ~ 1.3 matches. The lead is 0.1-0.3 a in SPH and MPS studies, so an
    # RMS above 0.3 a (10 % of the 3 a run-out) means the solver, not the experiment, is off.
    assert coarse["metrics"]["front_rms_error"] < 0.3
    assert fine["metrics"]["front_rms_error"] < 0.3
    # The error does NOT fall with dx (the lead grows as numerical dissipation falls; measured
    # 0.12, 0.15, 0.17, 0.22, 0.25 for dx = 0.06 ... 0.015): what must hold is that halving dx
    # moves the front by much less than the front has travelled, i.e. the run is resolution-robust.
    T = martin_moyce.T[martin_moyce.T <= 3.3]
    za = np.interp(T, np.array(cc["t"]) * math.sqrt(2 * 9.81), cc["front_x"])
    zb = np.interp(T, np.array(cf["t"]) * math.sqrt(2 * 9.81), cf["front_x"])
    assert np.sqrt(np.mean((za - zb) ** 2)) < 0.15
    # the surge reaches the far wall (x = 4 a) by T = 3.3 and the column has dropped below a
    assert cf["front_x"][-1] > 3.8
    assert cf["column_h"][-1] < 1.2


def test_repulsive_walls_dam_break_holds_water(tmp_path):
    s, cols = run(tmp_path, 0.06, **{"numerics.wall": "repulsive"})
    assert s["status"] == "ok" and s["leaked_particles"] == 0
    assert s["metrics"]["front_rms_error"] < 0.3
    assert np.all(np.isfinite(cols["front_x"]))
