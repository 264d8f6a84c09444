"""The kernel view (tisph/engine/view.py): the step kernel and the modules' hooks read the
solver's parts through it, and nothing else of the solver reaches a kernel."""

import os

import pytest
import taichi as ti

from tisph import runtime
from tisph.engine.solver import Solver
from tisph.engine.view import NAMES, KernelView
from tisph.runner import Log, build_case, resolve
from tisph.scenes import dam_break


def test_hooks_see_the_parts_through_the_view_and_nothing_else_of_the_solver():
    runtime.init("cpu", "f32")
    cfg = resolve(dam_break, overrides={"numerics.dx": 0.06, "output.quiet": True})
    case = build_case(dam_break, cfg, Log(os.devnull, True))
    s = Solver(case.physics, case.particles, case.materials, case.domain, case.params)
    V = s.stepper.S
    assert isinstance(V, KernelView) and set(KernelView.__slots__) == set(NAMES)
    assert V.p is s.p and V.tmp is s.tmp and V.prm is s.prm and V.grid is s.grid and V.stepper is s.stepper
    assert s.module("dual_criteria").S is V  # dual time stepping's two passes hand the hooks the view
    s.step()  # the step kernel compiles against the view

    @ti.kernel
    def n_particles() -> ti.i32:
        return V.n

    @ti.kernel
    def reach_the_particle_set() -> ti.i32:
        return len(V.particles)

    assert n_particles() == s.n
    with pytest.raises(Exception, match="particles"):
        reach_the_particle_set()
    with pytest.raises(AttributeError):
        V.time  # the run's state is the solver's
