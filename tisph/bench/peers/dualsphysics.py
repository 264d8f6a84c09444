"""DualSPHysics 5.0 (CPU) as a peer of the speed bench: build it from its source in a cache
folder (only when asked), run its 2D dam-break example (examples/main/01_DamBreak,
CaseDambreakVal2D: a 1 x 2 m column in a 4 m tank, the case tisph's dam break runs) at a dp and
end time, and read its particles, steps, time-loop wall time and surge front.

Its source is not on PyPI: pass a clone of github.com/DualSPHysics/DualSPHysics (a work tree or
its .git folder) with --dualsphysics; its v5.0 commit (2021-02-01, V50 below) is the last that ships
the Linux GenCase and PartVTK binaries the case needs. The CPU solver is built with
`make -f Makefile_cpu USE_GCC5=YES COMPILE_CHRONO=NO COMPILE_CHRONO_OMP=NO` (its bundled static
libraries use the old C++ string ABI; a dam break needs no Chrono), about a minute on two cores.

The front is read the way pysph_runs.py reads PySPH's: the rightmost fluid particle within two
spacings of the floor, plus half a spacing, from the back wall's face (the first fluid column
less half a spacing), from PartVTK's CSV of the fluid at each output time.
"""

import csv
import glob
import os
import re
import shutil
import subprocess
import time

import numpy as np

V50 = "1dfd0cd8ff5b8cd1bf45a3cf2c50d17d22a4a967"  # v5.0, 2021-02-01
EXAMPLE = os.path.join("examples", "main", "01_DamBreak", "CaseDambreakVal2D_Def.xml")
BIN = os.path.join("bin", "linux")
SOLVER = "DualSPHysics5.0CPU_linux64"
# what the example sets, and what it is set to: the bench states these beside the timings
SETTINGS = (
    "Wendland kernel, h = sqrt(2) dp (coefh 1), Verlet with CFL 0.2, c0 = 20 sqrt(g H) (coefsound 20), "
    "artificial viscosity 0.02, Fourtakas density diffusion 0.1, dynamic boundary particles (DBC), "
    "2 OpenMP threads; its gauges off"
)


class NotAvailable(Exception):
    """DualSPHysics cannot be built or run here: the bench says why and goes on without it."""


def _extract(gitdir, dest, log):
    """v5.0's tree from a git folder, blob by blob: a partial clone may lack the large Windows and
    Chrono libraries, which the Linux CPU build does not use."""
    ls = subprocess.run(["git", f"--git-dir={gitdir}", "ls-tree", "-r", V50], capture_output=True, text=True)
    if ls.returncode != 0:
        raise NotAvailable(f"{gitdir} has no commit {V50} (DualSPHysics v5.0): {ls.stderr.strip()}")
    skipped = 0
    for line in ls.stdout.splitlines():
        meta, path = line.split("\t", 1)
        mode, kind, obj = meta.split()
        if kind != "blob" or not path.startswith(("src/", "bin/linux/", "examples/main/01_DamBreak/")):
            continue
        blob = subprocess.run(["git", f"--git-dir={gitdir}", "cat-file", "blob", obj], capture_output=True)
        if blob.returncode != 0:
            skipped += 1
            continue
        target = os.path.join(dest, path)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        with open(target, "wb") as f:
            f.write(blob.stdout)
        if mode == "100755" or path.startswith("bin/linux/"):  # the repository stores its tools 644
            os.chmod(target, 0o755)
    if skipped:
        log(f"DualSPHysics: {skipped} files absent from {gitdir} (not needed for the CPU build)")


def _git_dir(source):
    for cand in (source, os.path.join(source, ".git")):
        r = subprocess.run(["git", f"--git-dir={cand}", "rev-parse", "--git-dir"], capture_output=True, text=True)
        if r.returncode == 0:
            return cand
    return None


def ensure(cache, source, log):
    """The folder of v5.0's Linux binaries with the CPU solver built; builds it once into cache."""
    root = os.path.join(cache, "dualsphysics-5.0")
    bindir = os.path.join(root, BIN)
    if os.path.exists(os.path.join(bindir, SOLVER)):
        return root
    if not source:
        raise NotAvailable(
            "not built yet and no source given: clone https://github.com/DualSPHysics/DualSPHysics "
            "and pass its folder with --dualsphysics (its v5.0 commit is used)"
        )
    if not os.path.isdir(source):
        raise NotAvailable(f"--dualsphysics {source}: no such folder")
    tmp = root + ".partial"
    shutil.rmtree(tmp, ignore_errors=True)
    gitdir = _git_dir(source)
    if gitdir:
        log(f"DualSPHysics: extracting v5.0 ({V50}) from {gitdir}")
        _extract(gitdir, tmp, log)
    elif os.path.exists(os.path.join(source, "src", "source", "Makefile_cpu")):
        shutil.copytree(source, tmp)
    else:
        raise NotAvailable(f"--dualsphysics {source}: neither a git clone of DualSPHysics nor its source tree")
    log("DualSPHysics: building the CPU solver (make -f Makefile_cpu, about a minute on two cores)")
    t0 = time.perf_counter()
    r = subprocess.run(
        ["make", "-f", "Makefile_cpu", "-j2", "USE_GCC5=YES", "COMPILE_CHRONO=NO", "COMPILE_CHRONO_OMP=NO"],
        cwd=os.path.join(tmp, "src", "source"),
        capture_output=True,
        text=True,
    )
    if r.returncode != 0 or not os.path.exists(os.path.join(tmp, BIN, SOLVER)):
        raise NotAvailable(f"building DualSPHysics failed: {r.stderr[-1500:]}")
    log(f"DualSPHysics: built in {time.perf_counter() - t0:.0f} s")
    shutil.rmtree(root, ignore_errors=True)
    os.rename(tmp, root)
    return root


def case_xml(text, dp, tmax, tout, coefsound=None):
    """The example's case definition at dp, run to tmax with output every tout, gauges off."""

    def param(key, value, s):
        s2, n = re.subn(rf'(<parameter key="{key}" value=")[^"]*"', rf'\g<1>{value}"', s)
        if n != 1:
            raise NotAvailable(f"the example's parameter {key} was not found")
        return s2

    s = re.sub(r'dp="[^"]*"', f'dp="{dp:g}"', text, count=1)
    s = param("TimeMax", f"{tmax:g}", s)
    s = param("TimeOut", f"{tout:g}", s)
    s = re.sub(r"<special>.*?</special>", "", s, flags=re.S)
    if coefsound is not None:
        s = re.sub(r'(<coefsound value=")[^"]*"', rf'\g<1>{coefsound:g}"', s)
    return s


def _read_run_csv(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f, delimiter=";") if r]
    head = [h.strip() for h in rows[0]]
    vals = rows[1]
    get = lambda k: vals[head.index(k)]
    return dict(particles=int(get("Np")), steps=int(get("Steps")), loop_s=float(get("TSimul")))


def _fronts(csv_dir, dp):
    files = [f for f in glob.glob(os.path.join(csv_dir, "PartFluid_*.csv")) if re.search(r"_\d+\.csv$", f)]
    files.sort(key=lambda f: int(re.search(r"_(\d+)\.csv$", f).group(1)))
    t, front = [], []
    x0 = z0 = None
    for f in files:
        with open(f) as fh:
            lines = fh.read().splitlines()
        # PartVTK's CSV: a line of names (TimeStep [s];Np;...) and its values, then the
        # particles' header (Pos.x [m];...) and rows, ';'-separated
        head_i = next(k for k, ln in enumerate(lines) if ln.startswith("Pos.x"))
        head = [h.strip() for h in lines[head_i].split(";")]
        data = np.array(
            [[float(v) for v in ln.split(";")[: len(head)] if v != ""] for ln in lines[head_i + 1 :] if ln.strip()]
        )
        x = data[:, head.index("Pos.x [m]") if "Pos.x [m]" in head else head.index("Pos.x")]
        z = data[:, head.index("Pos.z [m]") if "Pos.z [m]" in head else head.index("Pos.z")]
        if x0 is None:
            x0, z0 = x.min() - 0.5 * dp, z.min() - 0.5 * dp
        near = z - z0 < 2 * dp
        t.append(float(lines[1].split(";")[0]))
        front.append(float(x[near].max() + 0.5 * dp - x0) if near.any() else float("nan"))
    return np.array(t), np.array(front)


def run_xml(root, d, name, xml, threads=2):
    """GenCase and the CPU solver on the case definition `xml` in folder d (emptied first):
    particles, steps and the time loop's seconds (its Run.csv), the process's wall seconds, and
    the output folder with the environment its tools need."""
    bindir = os.path.join(root, BIN)
    env = dict(os.environ, LD_LIBRARY_PATH=bindir + os.pathsep + os.environ.get("LD_LIBRARY_PATH", ""))
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    with open(os.path.join(d, f"{name}_Def.xml"), "w") as f:
        f.write(xml)
    out = os.path.join(d, "out")
    r = subprocess.run(
        [os.path.join(bindir, "GenCase_linux64"), os.path.join(d, f"{name}_Def"), os.path.join(out, name), "-save:all"],
        capture_output=True,
        text=True,
        env=env,
    )
    if r.returncode != 0:
        raise NotAvailable(f"GenCase failed: {(r.stdout + r.stderr)[-1500:]}")
    t0 = time.perf_counter()
    r = subprocess.run(
        [
            os.path.join(bindir, SOLVER),
            os.path.join(out, name),
            out,
            "-dirdataout",
            "data",
            "-svres",
            f"-ompthreads:{threads}",
        ],
        capture_output=True,
        text=True,
        env=env,
    )
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        raise NotAvailable(f"DualSPHysics failed: {(r.stdout + r.stderr)[-1500:]}")
    return dict(_read_run_csv(os.path.join(out, "Run.csv")), wall_s=wall, out=out, env=env)


def run(root, work, dp, tmax, coefsound=None, threads=2):
    """The dam break at dp to tmax: particles, steps, wall times, the front history and the settings."""
    d = os.path.join(work, f"dualsphysics_dam_break_dp{dp:g}" + ("" if coefsound is None else f"_cs{coefsound:g}"))
    with open(os.path.join(root, EXAMPLE)) as f:
        text = f.read()
    res = run_xml(root, d, "Dambreak", case_xml(text, dp, tmax, 0.01, coefsound), threads)
    out, env = res.pop("out"), res.pop("env")
    r = subprocess.run(
        [
            os.path.join(root, BIN, "PartVTK_linux64"),
            "-dirin",
            os.path.join(out, "data"),
            "-savecsv",
            os.path.join(d, "csv", "PartFluid"),
            "-onlytype:-all,+fluid",
            "-vars:-all",
        ],
        capture_output=True,
        text=True,
        env=env,
    )
    if r.returncode != 0:
        raise NotAvailable(f"PartVTK failed: {(r.stdout + r.stderr)[-1500:]}")
    t, front = _fronts(os.path.join(d, "csv"), dp)
    settings = SETTINGS if coefsound is None else SETTINGS.replace("coefsound 20", f"coefsound {coefsound:g}")
    return dict(res, t=t, front=front, settings=settings)
