"""The start-up cache of Taichi's debug text gives Taichi's own text, position by position."""
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
