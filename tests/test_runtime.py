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


def test_concurrent_runs_take_their_own_offline_cache_folders(tmp_path):
    """Each process holds its own Taichi offline-cache folder while it runs (so two runs never
    share Taichi's cache lock and print its warning), and a later run takes a free, warm one."""
    import subprocess
    import sys
    code = ("import sys, time; from tisph import runtime; print(runtime.cache_folder(), flush=True); "
            "time.sleep(float(sys.argv[1]))")
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path))
    env.pop("TI_OFFLINE_CACHE_FILE_PATH", None)
    procs = [subprocess.Popen([sys.executable, "-c", code, "3"], stdout=subprocess.PIPE, text=True, env=env)
             for _ in range(3)]
    folders = [p.stdout.readline().strip() for p in procs]
    for p in procs:
        p.wait(30)
    assert len(set(folders)) == 3 and all(f.startswith(str(tmp_path)) for f in folders)
    later = subprocess.run([sys.executable, "-c", code, "0"], capture_output=True, text=True, env=env).stdout.strip()
    assert later == os.path.join(str(tmp_path), "tisph", "ticache", "slot0")
    own = subprocess.run([sys.executable, "-c", code, "0"], capture_output=True, text=True,
                         env=dict(env, TI_OFFLINE_CACHE_FILE_PATH=str(tmp_path / "mine"))).stdout.strip()
    assert own == "None"
