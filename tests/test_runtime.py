"""The start-up cache of Taichi's debug text gives Taichi's own text, position by position."""
import os

import taichi as ti
from taichi.lang.ast import ast_transformer_utils as u

from tisph import runtime


def test_cached_debug_info_is_taichis_own():
    runtime.init("cpu", "f32")
    cached = u.ASTTransformerContext.get_pos_info
    assert getattr(cached, "cached", False)
    orig = next(c.cell_contents for c in cached.__closure__
                if callable(c.cell_contents) and c.cell_contents.__name__ == "get_pos_info")
    seen = []

    def check(self, node):
        a, b = cached(self, node), orig(self, node)
        seen.append(a == b)
        return b

    u.ASTTransformerContext.get_pos_info = check
    try:
        f = ti.field(ti.f32, 8)

        @ti.func
        def twice(x):
            y = x * 2.0
            if y > 1.0:
                y -= 1.0
            return y

        @ti.kernel
        def k():
            for i in range(8):
                f[i] = twice(ti.cast(i, ti.f32)) + twice(1.0)   # the ti.func inlined twice

        k()
    finally:
        u.ASTTransformerContext.get_pos_info = cached
    assert len(seen) > 10 and all(seen)
    assert f[3] == 5.0 + 1.0


def test_concurrent_processes_take_turns_at_taichis_cache(tmp_path):
    """While one process holds the guard around Taichi's cache (as at its start and its final
    write), another's ti.init waits for it, so the two never meet at Taichi's own lock file; both
    then compile and exit without Taichi's lock warning."""
    import subprocess
    import sys
    import time
    env = dict(os.environ, TI_OFFLINE_CACHE_FILE_PATH=str(tmp_path / "cache"))
    hold = ("import time; from tisph import runtime\nwith runtime.cache_guard():\n"
            "    print('held', flush=True); time.sleep(2.0)")
    run = ("import time; t = time.perf_counter(); from tisph import runtime; import taichi as ti; "
           "runtime.init('cpu', 'f32'); print(time.perf_counter() - t, flush=True); f = ti.field(ti.f32, 4)\n"
           "@ti.kernel\ndef k():\n    for i in f: f[i] = i\nk()")
    script = tmp_path / "run.py"            # Taichi reads a kernel's source from its file
    script.write_text(run)
    a = subprocess.Popen([sys.executable, "-c", hold], stdout=subprocess.PIPE, text=True, env=env)
    assert a.stdout.readline().strip() == "held"
    t0 = time.perf_counter()
    b = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=120)
    a.wait(30)
    assert b.returncode == 0, b.stderr
    assert time.perf_counter() - t0 > 1.5          # it waited for the holder
    assert "Lock" not in b.stderr and (tmp_path / "cache" / "tisph.flock").exists()
