"""A restarted run equals the uninterrupted one in every output: probes, the scenes' own CSVs
(bed and scour profiles, ripple prediction), metrics, frames; timings aside, wall times summed."""

import json
import os

import pytest

from tisph.case import as_scene
from tisph.runner import simulate
from tisph.scenes import beach, erodible_bed, flume, pipeline_scour, tunnel

FAST = {"output.render": False, "output.quiet": True, "output.snapshot_every": 0.0}
CASES = [
    # (scene, overrides, end): the first segment stops half way (as a killed run would), the
    # second continues from its last checkpoint
    (beach, {"numerics.dx": 0.03, "output.probe_interval": 0.04}, 0.4),
    (
        tunnel,
        {"numerics.dx": 0.02, "sediment.model": "bedload", "sediment.seed_rms": 0.004, "sediment.morfac": 20.0},
        0.5,
    ),
    # the bed and its suspended load move from the start; the water carries its k, which the
    # bed's wall-function shear reads (its filtered k is in the checkpoint), and its omega
    (
        pipeline_scour,
        {
            "numerics.dx": 0.0125,
            "output.probe_interval": 0.01,
            "sediment.suspended": True,
            "sediment.morph_start": 0.0,
            "numerics.turbulence": "k_equation",
            "numerics.length_scale": "omega",
            "numerics.stress_limiter": 0.875,
            "sediment.shear": "wall_function",
        },
        0.06,
    ),
    # each pair once (run.pair_once): its zones cut from the restored state, the same sums' order
    # (Fourtakas' diffusion: the flume's renormalised one gathers; h = 1.2 dx, under the CPU's
    # vector lanes, which would be taken in its place)
    (
        flume,
        {
            "numerics.dx": 0.025,
            "geometry.length": 2.0,
            "geometry.damping_length": 0.6,
            "geometry.gauges_x": [0.5, 1.0],
            "run.pair_once": "on",
            "numerics.h_factor": 1.2,
            "numerics.density_diffusion": "fourtakas",
            "numerics.time_stepping": "single",
        },
        0.3,
    ),
    # the flume's default: the renormalised density gradient, one step behind, and the held viscous
    # and diffusive terms with their schedule (dual time stepping), in the checkpoint
    (
        flume,
        {"numerics.dx": 0.025, "geometry.length": 2.0, "geometry.damping_length": 0.6, "geometry.gauges_x": [0.5, 1.0]},
        0.3,
    ),
    (erodible_bed, {"numerics.dx": 0.025, "output.probe_interval": 0.01}, 0.3),  # a profile at 0.25 s
]
SKIP = {
    "wall_time_s",
    "step_time_s",
    "compile_time_s",
    "particle_steps_per_s",
    "wall_s_per_sim_s",
    "restarted_from",
    "message",
    "metrics",
}


def csvs(d):
    """Every CSV under d (subfolders too: the erodible bed's profiles/)."""
    out = {}
    for root, _, files in os.walk(d):
        for f in files:
            if f.endswith(".csv"):
                p = os.path.join(root, f)
                out[os.path.relpath(p, d)] = open(p).read()
    return out


@pytest.mark.slow
@pytest.mark.parametrize("scene, ov, t2", CASES, ids=[as_scene(c[0]).NAME for c in CASES])
def test_restart_continues_every_output(scene, ov, t2, tmp_path):
    base = dict(FAST, **ov, **{"run.end_time": t2, "output.checkpoint_every": t2 / 8})
    full = simulate(scene, base, out=str(tmp_path / "full"))
    first = simulate(scene, dict(base, **{"run.max_steps": full["steps"] // 2}), out=str(tmp_path / "seg"))
    assert first["sim_time"] < t2
    again = simulate(scene, base, out=str(tmp_path / "seg"), restart=str(tmp_path / "seg" / "checkpoint.h5"))
    assert full["status"] == again["status"] == "ok" and again["steps"] == full["steps"]
    assert first["pair_once"] == again["pair_once"] == full["pair_once"] == ("run.pair_once" in ov)
    a, b = csvs(tmp_path / "full"), csvs(tmp_path / "seg")
    assert sorted(a) == sorted(b) and "probes.csv" in a and (len(a) >= 2 or scene is flume)  # and the scene's own
    for f in a:
        assert a[f] == b[f], f"{f} differs after the restart"
    assert json.dumps(full["metrics"], sort_keys=True) == json.dumps(again["metrics"], sort_keys=True)
    for k in set(full) - SKIP:
        assert full[k] == again[k], k
    assert again["wall_time_s"] >= first["wall_time_s"]  # the segments' wall times summed
