"""Each pair once (tisph/engine/pairs.py): the same terms as the gather pass to rounding, and the
same bits on any number of threads (the zones, not the threads, set the order of the sums). The
CPU's vector lanes beat it and it is not taken where they are, so these runs set them off
(`lanes`), or reach under them (h = 1.2 dx)."""

import os
import subprocess
import sys

import numpy as np

from tisph import runtime
from tisph.engine.solver import Solver
from tisph.runner import Log, build_case, resolve
from tisph.runner.setup import PAIR_ONCE_MIN, pair_once_wanted
from tisph.scenes import dam_break, flume, pipeline_scour, tunnel

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _pair(scene, ov, steps):
    runtime.init("cpu", "f32")
    cfg = resolve(scene, overrides=dict(ov, **{"output.quiet": True}))
    case = build_case(scene, cfg, Log(os.devnull, True))
    out = []
    for once in (False, True):
        s = Solver(
            case.physics, case.particles, case.materials, case.domain, dict(case.params, pair_once=once, lanes=False)
        )
        assert (s.pair_once is not None) == once
        for _ in range(steps):
            s.step()
        out.append((s, s.state(("x", "v", "rho"))))
    return out


def test_pair_once_gives_the_gather_pass_terms_to_rounding():
    # the dam break (walls, an impact, the wall guard and the sheets' alpha; the default scheme's
    # renormalised diffusion gathers, so Fourtakas'), the tunnel (periodic in x: pairs across the
    # seam) and the flume (a moving paddle, extrapolated walls)
    # every term every step: dual time stepping's two sums gather (physics/dual.py)
    FT = {"numerics.density_diffusion": "fourtakas", "numerics.time_stepping": "single"}
    for scene, ov in (
        (dam_break, dict(FT, **{"numerics.dx": 0.04})),
        (tunnel, {}),
        (flume, dict(FT, **{"numerics.dx": 0.025})),
    ):
        (g, a), (o, b) = _pair(scene, ov, 150)
        assert abs(g.time / o.time - 1.0) < 1e-6  # dt follows the largest acceleration
        assert not np.array_equal(a["rho"], b["rho"])  # the sums ran in another order
        assert np.abs(a["x"] - b["x"]).max() < 1e-5
        assert np.abs(a["v"] - b["v"]).max() < 1e-3
        assert np.abs(a["rho"] / b["rho"] - 1.0).max() < 1e-5


def test_pair_once_gives_the_no_slip_gradient_and_turbulence_terms_to_rounding():
    # the pipeline (Mao's physics): a no-slip pipe, the velocity gradient, the k equation and the
    # SPS stress, periodic in x; their two-sided forms (pair2) against the gather pass
    ov = {"numerics.dx": 0.0125, "sediment.morph_start": 0.0, "numerics.turbulence": "k_equation"}
    (g, a), (o, b) = _pair(pipeline_scour, ov, 150)
    assert {"noslip", "velocity_gradient", "tke", "sps"} <= {m.name for m in o.hooks["pair"]}
    assert not np.array_equal(a["v"], b["v"])
    assert np.abs(a["x"] - b["x"]).max() < 1e-5
    assert np.abs(a["v"] - b["v"]).max() < 1e-3
    assert np.abs(a["rho"] / b["rho"] - 1.0).max() < 1e-5
    ka, kb = g.state(("kt",))["kt"], o.state(("kt",))["kt"]
    assert np.abs(ka - kb).max() < 1e-3 * np.abs(ka).max()


CHILD = r"""
import hashlib, os, sys
from tisph import runtime
runtime.init("cpu", "f32")
from tisph.engine.solver import Solver
from tisph.runner import Log, build_case, resolve
from tisph.runner.setup import PAIR_ONCE_MIN, pair_once_wanted
from tisph.scenes import dam_break
cfg = resolve(dam_break, overrides={"numerics.dx": 0.03, "output.quiet": True,
                                    "numerics.density_diffusion": "fourtakas", "numerics.time_stepping": "single"})
case = build_case(dam_break, cfg, Log(os.devnull, True))
s = Solver(case.physics, case.particles, case.materials, case.domain, dict(case.params, pair_once=True, lanes=False))
assert s.pair_once is not None
for _ in range(200):
    s.step()
st = s.state(("x", "v", "rho"))
print(hashlib.sha1(b"".join(st[k].tobytes() for k in ("x", "v", "rho"))).hexdigest())
"""


def test_pair_once_is_the_same_bit_for_bit_on_one_and_two_threads():
    digests = []
    for threads in ("1", "2"):
        env = dict(os.environ, TISPH_THREADS=threads, PYTHONPATH=ROOT)
        r = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, env=env, timeout=300)
        assert r.returncode == 0, r.stderr[-2000:]
        digests.append(r.stdout.strip().splitlines()[-1])
    assert digests[0] == digests[1]


def test_zones_are_dealt_round_the_threads():
    """A shallow domain's water fills the first zones of each phase: in row order one thread's
    piece of the loop would hold them all (the flume's pass ran as on one thread)."""
    from tisph.engine.pairs import deal

    assert deal(8, 2) == [0, 2, 4, 6, 1, 3, 5, 7]  # thread 0: zones 0, 2, 4, 6 of the phase
    assert deal(8, 1) == list(range(8))
    for t in (1, 2, 3, 4, 8, 16):
        assert sorted(deal(8, t)) == list(range(8))
        piece = -(-8 // t) if t <= 8 else 1
        firsts = [deal(8, t)[q] for q in range(0, 8, piece)]
        assert t > 8 or 8 % t or firsts == list(range(t))  # each thread starts on its own low zone


def test_auto_takes_each_pair_once_where_the_run_repays_its_compile():
    cfg = resolve(dam_break, overrides={"numerics.dx": 0.03})
    n, h, c0 = 3426, 0.039, 62.6
    steps = cfg["run"]["end_time"] / (cfg["numerics"]["cfl"] * h / c0)
    assert pair_once_wanted(cfg, n, h, c0) == (n * steps >= PAIR_ONCE_MIN) is False  # a short run: 1.1e7
    assert pair_once_wanted(cfg, 10 * n, h, c0)
    cfg = cfg.replace({"run.max_steps": 100})  # a segment of a run chooses as the whole run (restarts)
    assert pair_once_wanted(cfg, 10 * n, h, c0)
    for mode, want in (("on", True), ("off", False)):
        assert pair_once_wanted(cfg.replace({"run.pair_once": mode}), n, h, c0) is want
    runtime.init("cpu", "f32")
    case = build_case(
        dam_break,
        resolve(
            dam_break,
            overrides={
                "numerics.dx": 0.04,
                "numerics.h_factor": 1.2,  # a support of 2.4 dx: under the lanes' reach
                "run.pair_once": "on",
                "numerics.density_diffusion": "fourtakas",
                "numerics.time_stepping": "single",
            },
        ),
        Log(os.devnull, True),
    )
    s = case.model.solver()
    assert case.params["pair_once"] and s.pair_once is not None and not s.lanes
