"""The parameter table: a runtime parameter read and written by name, kept by a checkpoint's
snapshot and restored, refused by name where the case has none; the material table one field a
material parameter, filled from the case's materials."""

import os

import numpy as np
import pytest

from tisph import runtime
from tisph.engine.solver import Solver
from tisph.particles import FLUID
from tisph.runner import Log, build_case, resolve
from tisph.scenes import dam_break


def test_table_reads_writes_and_restores_by_name():
    runtime.init("cpu", "f32")
    cfg = resolve(dam_break, overrides={"numerics.dx": 0.06, "output.quiet": True})
    case = build_case(dam_break, cfg, Log(os.devnull, True))
    s = Solver(case.physics, case.particles, case.materials, case.domain, case.params)
    t = s.table
    assert t.get("c0") == pytest.approx(s.c0, rel=1e-6) and t.get("g") == pytest.approx((0.0, -9.81))
    kept = t.snapshot()
    t.set("g", (0.5, -9.0))
    assert t.get("g") == pytest.approx((0.5, -9.0))
    s.step()  # the kernel reads the new gravity: the fluid drifts in x
    fl = s.state(("v", "kind"))
    assert np.mean(fl["v"][fl["kind"] == FLUID][:, 0]) > 0.0
    t.restore(kept)
    assert t.get("g") == pytest.approx((0.0, -9.81))
    with pytest.raises(KeyError, match="'drive'"):  # a dam break has no periodic drive
        t.set("drive", (1.0, 0.0))
    rho0 = [m["rho0"] for m in case.materials]
    assert np.allclose(s.mat.rho0.to_numpy(), rho0) and t.has_stat("amax2") and not t.has("drive")
