"""Run golden cases on one backend and keep their final states, for a comparison across
backends (tests/engine/test_vulkan.py runs this in a process of its own, one Taichi arch a process):

    python -m tests.golden.dump --arch gpu --out states.npz CASE [CASE ...]

writes states.npz (CASE/x, CASE/v, CASE/rho, CASE/kind by particle id) and states.json (each
case's arch, status, steps, particles, modules and wall seconds)."""

import argparse
import json
import os
import sys
import time

import numpy as np


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--arch", default="gpu", choices=("cpu", "gpu"))
    ap.add_argument("--out", required=True)
    ap.add_argument("--steps", type=int, default=None)
    ap.add_argument("cases", nargs="+")
    a = ap.parse_args(argv)
    from tests.golden.cases import STEPS, run

    arrays, meta = {}, {}
    for cid in a.cases:
        t0 = time.perf_counter()
        d = run(cid, steps=a.steps or STEPS, arch=a.arch, arrays=True)
        for k, v in d.pop("arrays").items():
            arrays[f"{cid}/{k}"] = v
        meta[cid] = dict(
            arch=d["arch"],
            status=d["status"],
            steps=d["steps"],
            particles=d["particles"],
            modules=d["modules"],
            wall_s=time.perf_counter() - t0,
        )
        print(
            f"{cid}: {d['arch']} {d['particles']} particles {d['steps']} steps {meta[cid]['wall_s']:.1f} s", flush=True
        )
    np.savez(a.out, **arrays)
    with open(os.path.splitext(a.out)[0] + ".json", "w") as f:
        json.dump(meta, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    sys.exit(main())
