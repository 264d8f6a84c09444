"""PySPH peer for the benchmark: install PySPH 1.0b2 in its own virtual environment (under the
bench output folder) if absent, run its stock dam_break_2d (dx = 0.03, --openmp, two threads,
tf = 0.7 s; its stock scheme crashes near t = 0.94 s) and the same example at dx = 0.015 to
tf = 0.55 s (there the stock scheme's dt falls to 1.5e-6 s and it dies of a segmentation fault at
t = 0.58 s, measured), run our
dam break on the same geometry, dx and end time, and compare wall time and the front error
against Martin & Moyce, the front taken from both codes' output the same way: the rightmost
fluid particle within two particle spacings of the floor, plus half a spacing, measured from the
back wall's face.

The stock example's --dx changes the lattice and the scheme's h0 but gives every particle the
module's h and m, which are for dx = 0.03 (its create_particles uses them): at another dx a
subclass (FINE) sets each particle's h = hdx dx and m = rho0 dx^2.
"""

import json
import os
import subprocess
import sys
import time

import numpy as np

from ...io import ensure_dir, write_text
from ...validation import martin_moyce
from ..common import cache_dir, this_tree_env

TF = 0.7
DX = 0.03
DXS = ((0.03, TF), (0.015, 0.55))  # (dx, end time): the stock example, and twice as fine

EXTRACT = r"""
import glob, json, sys
import numpy as np
from pysph.solver.utils import load
import re
dx = float(sys.argv[2])
files = [f for f in glob.glob(sys.argv[1] + '/*') if re.search(r'_(\d+)\.(npz|hdf5)$', f)]
files.sort(key=lambda f: int(re.search(r'_(\d+)\.', f).group(1)))
out = []
x0 = None
for f in files:
    d = load(f)
    fl = d['arrays']['fluid']
    x, y = fl.get('x'), fl.get('y')
    if x0 is None:
        x0 = float(x.min()) - 0.5 * dx   # the back wall's face
        y0 = float(y.min()) - 0.5 * dx   # the floor
    m = y - y0 < 2 * dx
    out.append((float(d['solver_data']['t']), float(x[m].max() + 0.5 * dx - x0) if m.any() else float('nan'),
                int(d['solver_data'].get('count', 0)), int(len(x)),
                int(sum(len(a.get('x')) for a in d['arrays'].values()))))
print(json.dumps(out))
"""

FINE = r"""
from pysph.examples.dam_break_2d import DamBreak2D, ro


class DamBreakAtDx(DamBreak2D):
    def create_particles(self):
        arrays = super().create_particles()
        for pa in arrays:
            pa.h[:] = self.h
            pa.m[:] = ro * self.dx ** 2
        return arrays


if __name__ == '__main__':
    DamBreakAtDx(fname='dam_break_2d').run()
"""


def venv_python(root):
    return os.path.join(root, "bin", "python")


def ensure_pysph(root, log):
    py = venv_python(root)
    if os.path.exists(py):
        r = subprocess.run([py, "-c", "import pysph, sys; print(pysph.__version__)"], capture_output=True, text=True)
        if r.returncode == 0:
            return py
    log(f"installing PySPH 1.0b2 into {root} (builds from source, a few minutes)")
    subprocess.run([sys.executable, "-m", "venv", root], check=True)
    # with pip's build isolation it fetches its own Cython, cyarray and compyle (measured: about
    # 4 minutes here); --no-build-isolation against the venv's packages fails to compile
    # --no-cache-dir: a cyarray wheel cached from a NumPy 1 build fails to import under NumPy 2;
    # matplotlib: the example's post-processing plots its front
    subprocess.run([py, "-m", "pip", "install", "-q", "--no-cache-dir", "pysph==1.0b2", "matplotlib"], check=True)
    return py


def run_pysph(py, out, dx=DX, tf=TF):
    d = os.path.join(out, f"pysph_dam_break_2d_dx{dx:g}")
    env = dict(os.environ, OMP_NUM_THREADS="2")
    if dx == DX:
        cmd = [py, "-m", "pysph.examples.dam_break_2d"]
    else:
        ensure_dir(d)
        script = os.path.join(d, "dam_break_at_dx.py")
        write_text(script, FINE)
        cmd = [py, script, "--dx", str(dx)]
    t0 = time.perf_counter()
    r = subprocess.run(
        cmd + ["--openmp", "--tf", str(tf), "-d", d, "--pfreq", str(int(20 * DX / dx))],
        capture_output=True,
        text=True,
        env=env,
    )
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        raise RuntimeError(f"PySPH run failed (return code {r.returncode}): {r.stderr[-2000:]}")
    e = subprocess.run([py, "-c", EXTRACT, d, str(dx)], capture_output=True, text=True)
    if e.returncode != 0:
        raise RuntimeError(f"reading PySPH output failed: {e.stderr[-2000:]}")
    rows = json.loads(e.stdout)
    try:  # PySPH's own timing of its time loop (after set-up and its cached compilation)
        with open(os.path.join(d, "dam_break_2d.info")) as f:
            run_s = float(json.load(f)["cpu_time"])
    except (OSError, ValueError, KeyError):
        run_s = float("nan")
    t = np.array([r[0] for r in rows])
    front = np.array([r[1] for r in rows])
    steps = max(r[2] for r in rows)
    n = rows[0][3]
    return dict(
        wall_time_s=wall,
        run_s=run_s,
        steps=steps,
        fluid_particles=n,
        particles=rows[0][4],
        t=t,
        front=front,
        log=r.stdout[-3000:],
    )


def compare(out, log, venv=None, dxs=DXS):
    root = venv or os.path.join(cache_dir(), "pysph-venv")
    try:
        py = ensure_pysph(root, log)
    except Exception as e:
        log(f"PySPH comparison skipped: {e}")
        return ["## PySPH comparison", "", f"Not run: {e}", ""]
    md = [
        "## PySPH comparison (dam break)",
        "",
        "| dx | to t (s) | code | fluid particles | steps | wall s (with start-up) | time loop s | front RMS vs Martin & Moyce |",
        "|---|---|---|---|---|---|---|---|",
    ]
    notes = []
    for dx, tf in dxs:
        try:
            p = run_pysph(py, out, dx, tf)
        except Exception as e:
            log(f"PySPH at dx {dx:g} skipped: {e}")
            notes.append(f"dx {dx:g}: PySPH not run: {e}")
            continue
        rows, note = _side_by_side(out, log, dx, tf, p)
        md += rows
        notes.append(note)
    md += (
        [""]
        + notes
        + [
            "",
            "PySPH: stock dam_break_2d (WCSPH, Wendland quintic, PEC integrator, 2 OpenMP threads); "
            "at dx other than 0.03 with h and m set for that dx (a subclass, see tisph/bench/peers/pysph_runs.py). tisph: "
            "the dam_break scene (Taichi CPU, 2 threads, f32). Both run from the command line in a fresh "
            "process. tisph's start-up is Taichi's kernel compilation (from its offline cache when "
            "warm); PySPH's compiled extension is cached from an earlier run.",
            "",
        ]
    )
    return md


def run_tisph_dam_break(out, dx, tf):
    """Our dam break at dx to tf as a peer's is run, from the command line in a fresh process (the
    wall time counts the interpreter, the imports and the compile for both; in the bench's own
    process, after its other work, our start-up measured 2.7-4.2 s against 1.7-1.9 s fresh):
    (summary, wall seconds, the run's folder)."""
    d = os.path.join(out, f"tisph_dam_break_dx{dx:g}_t{tf:g}")
    t0 = time.perf_counter()
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "tisph.scenes.dam_break",
            "--dx",
            str(dx),
            "--end-time",
            str(tf),
            "--no-render",
            "--quiet",
            "--snapshot-every",
            "0",
            "--out",
            d,
        ],
        capture_output=True,
        text=True,
        env=this_tree_env(),
    )
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        raise RuntimeError(f"tisph's dam break failed (return code {r.returncode}): {r.stderr[-2000:]}")
    with open(os.path.join(d, "summary.json")) as f:
        return json.load(f), wall, d


def _side_by_side(out, log, dx, tf, p):
    """Our dam break at dx beside PySPH's run p: (table rows, one line of ratios)."""
    rms_p, npts = martin_moyce.front_rms_error(p["t"], p["front"], 1.0)
    s, wall, _ = run_tisph_dam_break(out, dx, tf)
    rms_t = s["metrics"]["front_rms_error"]
    ratio = p["wall_time_s"] / wall
    ratio_run = p["run_s"] / s["wall_time_s"]
    log(
        f"dx {dx:g}: PySPH {p['wall_time_s']:.1f} s ({p['run_s']:.1f} s loop), front RMS {rms_p:.3f}; tisph "
        f"{wall:.1f} s ({s['wall_time_s']:.1f} s loop), front RMS {rms_t:.3f}; ratio {ratio:.2f}x ({ratio_run:.2f}x loop)"
    )
    rows = [
        f"| {dx:g} | {tf:g} | PySPH 1.0b2 | {p['fluid_particles']} | {p['steps']} | {p['wall_time_s']:.1f} | "
        f"{p['run_s']:.1f} | {rms_p:.3f} |",
        f"| {dx:g} | {tf:g} | tisph | {s['fluid_particles']} | {s['steps']} | {wall:.1f} | {s['wall_time_s']:.1f} | "
        f"{rms_t:.3f} |",
    ]
    note = (
        f"dx {dx:g}: tisph {ratio:.2f}x faster in wall time with start-up, {ratio_run:.2f}x in the time loop "
        f"(goal: 4x at equal or lower front error; compile {s['compile_time_s']:.1f} s); front error over "
        f"{npts} Martin & Moyce points to t = {tf:g} s."
    )
    return rows, note
