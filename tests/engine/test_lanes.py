"""The force pass's neighbour loops in the CPU's vector lanes (engine/grid.py, for_neighbours'
lanes): every candidate of a stencil row without the support's branch, the row padded to whole
eights with the padding moved out of reach. They sum the same terms as the branch form, in
another order (tests/engine/test_grid.py checks the candidates they visit against brute force,
a domain three cells wide included)."""

import os

import numpy as np
import pytest

from tisph.engine.solver import Solver
from tisph.runner import Log, build_case, resolve
from tisph.scenes import dam_break, flume, pipeline_scour, tunnel

FLUME = {
    "numerics.dx": 0.025,
    "geometry.length": 2.0,
    "geometry.damping_length": 0.6,
    "geometry.gauges_wavelengths": [0.5],
}
# the pipeline with the k equation and its omega: the SPS stress, the velocity gradient, the
# no-slip pipe and the dynamic walls in the lanes (Mao's case takes them at h = 1.6 dx)
PIPE = {
    "numerics.dx": 0.0125,
    "sediment.morph_start": 0.0,
    "numerics.turbulence": "k_equation",
    "numerics.length_scale": "omega",
}
# paper 000's scheme: XSPH, Fourtakas' diffusion and the dynamic walls
PAPER000 = {"numerics.dx": 0.06, "numerics.scheme": "paper000"}
STEPS = 10


def _pair(scene, steps, fields=(), **ov):
    """The state after `steps` steps with the lanes and with the branch form, and the solvers."""
    out = []
    for lanes in (True, False):
        cfg = resolve(scene, overrides=dict({"output.quiet": True}, **ov))
        case = build_case(scene, cfg, Log(os.devnull, True))
        case.params["lanes"] = lanes
        case.params["pair_once"] = False  # the gather pass in both
        s = Solver(case.physics, case.particles, case.materials, case.domain, case.params)
        assert s.lanes == lanes
        s.prime()
        for _ in range(steps):
            s.step()
        out.append((s, s.state(("x", "v", "rho", "kind") + tuple(fields))))
    return out


@pytest.mark.parametrize(
    "scene, ov",
    [
        (dam_break, {"numerics.dx": 0.06}),
        (flume, FLUME),
        (pipeline_scour, PIPE),
        (dam_break, PAPER000),
        (tunnel, {"numerics.dx": 0.02}),
    ],
    ids=["dam_break", "flume", "pipeline", "paper000", "tunnel"],
)
def test_the_lanes_sum_what_the_branch_sums(scene, ov):
    # the pipeline's turbulence, against its own terms: measured after ten steps, k 2.3e-10 m2/s2
    # (of 1.4e-3), omega 3.8e-6 1/s (of 26), v 1.8e-6 m/s; a wall's k let into the k diffusion moved
    # k 6.9e-7, a wall's SPS stress taken for i's mirror moved v 1.4e-4
    bounds = {"kt": 1e-8, "wt": 1e-4, "v": 2e-5} if scene is pipeline_scour else {}
    (a, sa), (b, sb) = _pair(scene, STEPS, tuple(k for k in bounds if k != "v"), **ov)
    assert a.steps == b.steps and abs(a.time - b.time) < 1e-6 * a.time
    fluid = sa["kind"] == 0
    # the same terms added in another order: f32 rounding, which the flow then carries (about
    # 2e-3 kg/m3 and 2e-6 m after ten steps); one neighbour's continuity term more or less
    # would move a density by about 1 % of 1000 kg/m3 a step
    assert np.max(np.abs(sa["rho"] - sb["rho"])[fluid]) < 1e-2
    assert np.max(np.abs(sa["x"] - sb["x"])[fluid]) < 1e-4 * ov["numerics.dx"]
    assert np.isfinite(sa["v"]).all()
    for k, bound in bounds.items():
        assert np.max(np.abs(sa[k] - sb[k])[fluid]) < bound, k


def test_the_lanes_where_they_pay():
    """The sand bed's scheme (the cubic, each pair once where asked) at three reaches: the lanes
    in cells of half a 5 dx support, at h = 1.3 dx in cells of the whole support (rows of about
    20 candidates; half as wide they held 8, padded to 32), none at h = 1 dx (nothing measured
    there); each pair once only in the branch form, where the lanes are not taken."""
    built = {}
    for h in (2.5, 1.3, 1.0):
        ov = {"output.quiet": True, "numerics.dx": 0.06, "numerics.scheme": "bed", "numerics.h_factor": h}
        case = build_case(dam_break, resolve(dam_break, overrides=ov), Log(os.devnull, True))
        case.params["pair_once"] = True
        s = Solver(case.physics, case.particles, case.materials, case.domain, case.params)
        built[h] = (s.lanes, s.grid.cdiv, s.pair_once is not None)
    assert built == {2.5: (True, 2, False), 1.3: (True, 1, False), 1.0: (False, 2, True)}
