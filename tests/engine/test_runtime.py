"""What tisph changes in Taichi's start-up: the cached debug text and the guard around its cache."""

import os

KERNELS = """import taichi as ti
from tisph import runtime
runtime.init("cpu", "f32")
f = ti.field(ti.f32, 8)


@ti.func
def twice(x):
    return x * 2.0


@ti.func
def broken(x):
    return x + missing_in_func


@ti.kernel
def good():
    for i in range(8):
        f[i] = twice(ti.cast(i, ti.f32)) + twice(1.0)


@ti.kernel
def bad():
    for i in range(8):
        f[i] = twice(1.0) + missing_in_kernel * 2.0


@ti.kernel
def bad_in_func():
    for i in range(8):
        f[i] = twice(1.0) + broken(1.0)


good()
print(f[3])
for k in (bad, bad_in_func):
    try:
        k()
    except Exception as e:
        print(type(e).__name__, e)
"""


def test_kernel_errors_name_the_line_and_code_with_the_start_up_cache(tmp_path):
    """tisph keeps Taichi's per-node debug text per source position (runtime.py: 0.4 s of a 1 s
    warm start). A user's kernel error must still name the file, the line and the code that
    caused it, also inside a ti.func inlined after other kernels inlined their own."""
    import subprocess
    import sys

    script = tmp_path / "kernels.py"
    script.write_text(KERNELS)
    r = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120)
    lines = r.stdout.splitlines()
    assert lines[0] == "8.0", r.stdout + r.stderr  # twice() inlined twice computes 2*3 + 2
    out = "\n".join(lines)
    assert f'File "{script}", line 26, in bad:' in out, out
    assert "f[i] = twice(1.0) + missing_in_kernel * 2.0" in out
    assert f'File "{script}", line 14, in broken:' in out, out
    assert "return x + missing_in_func" in out
    assert out.count("TaichiNameError") == 2


def test_concurrent_processes_take_turns_at_taichis_cache(tmp_path):
    """While one process holds the guard around Taichi's cache (as at its start and its final
    write), another's ti.init waits for it, so the two never meet at Taichi's own lock file; both
    then compile and exit without Taichi's lock warning."""
    import subprocess
    import sys
    import time

    env = dict(os.environ, TI_OFFLINE_CACHE_FILE_PATH=str(tmp_path / "cache"))
    hold = (
        "import time; from tisph import runtime\nwith runtime.cache_guard():\n"
        "    print('held', flush=True); time.sleep(2.0)"
    )
    run = (
        "import time; t = time.perf_counter(); from tisph import runtime; import taichi as ti; "
        "runtime.init('cpu', 'f32'); print(time.perf_counter() - t, flush=True); f = ti.field(ti.f32, 4)\n"
        "@ti.kernel\ndef k():\n    for i in f: f[i] = i\nk()"
    )
    script = tmp_path / "run.py"  # Taichi reads a kernel's source from its file
    script.write_text(run)
    a = subprocess.Popen([sys.executable, "-c", hold], stdout=subprocess.PIPE, text=True, env=env)
    assert a.stdout.readline().strip() == "held"
    t0 = time.perf_counter()
    b = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=120)
    a.wait(30)
    assert b.returncode == 0, b.stderr
    assert time.perf_counter() - t0 > 1.5  # it waited for the holder
    assert "Lock" not in b.stderr and (tmp_path / "cache" / "tisph.flock").exists()
