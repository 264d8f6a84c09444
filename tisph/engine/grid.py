"""Cell grid: cell keys, counting sort by cell (then by id), reorder, and the neighbour visitor.

Cells are half the kernel support with a 5 x 5 stencil (25 h^2 of candidates instead of 36 h^2
with cells of the support), numbered row by row, so the cells of one stencil row are one
contiguous range of the sorted particles: one range per row, not one per cell.
"""

import math

import numpy as np
import taichi as ti

from ..runtime import blocks
from .state import on_cpu, type_bytes

LANE_MIN = 32  # a padded row's least length: LLVM's vector loop takes eight lanes four times a pass
# the lanes' cells (solver.py): half the support wide (a 5 x 5 stencil) where the support reaches
# WHOLE_CELL spacings or more, else the whole support (3 x 3), whose rows are long enough to fill
# the padded 32; and no lanes under LANE_SUPPORT spacings (the cubic at h = 1.3 dx reaches 2.6)
WHOLE_CELL = 3.9
LANE_SUPPORT = 2.55


@ti.data_oriented
class Grid:
    def __init__(self, n, domain, support, periodic_x, cdiv=2):
        """cdiv: cells a support spans (2: cells half the support wide, a 5 x 5 stencil; 1: 3 x 3)."""
        lo, hi = np.asarray(domain[0], float), np.asarray(domain[1], float)
        self.n = n
        self.periodic_x = periodic_x
        self.support = support
        self.cdiv = int(cdiv)
        self.cell = support / self.cdiv
        self.cell_y = self.cell
        self.ny = max(1, int(math.ceil((hi[1] - lo[1]) / self.cell)))
        if periodic_x:
            # the domain's x extent is one period; cells tile it exactly (slightly wider than needed)
            self.period = float(hi[0] - lo[0])
            self.nx = int(math.floor(self.period / self.cell))
            if self.nx < 2 * self.cdiv + 1:
                raise ValueError(
                    f"periodic length {self.period:g} m is shorter than {2 * self.cdiv + 1} cells "
                    f"of {self.cell:g} m: lengthen the domain or reduce h"
                )
            self.cell_x = self.period / self.nx
            self.inv_period = 1.0 / self.period  # nearest image: r/P is never near a half in the stencil
        else:
            self.period = 0.0
            self.nx = max(1, int(math.ceil((hi[0] - lo[0]) / self.cell)))
            self.cell_x = self.cell
        self.ncells = self.nx * self.ny
        self.lo = (float(lo[0]), float(lo[1]))
        self.hi = (float(lo[0] + self.nx * self.cell_x), float(lo[1] + self.ny * self.cell_y))
        self.key = ti.field(ti.i32, n)
        self.order = ti.field(ti.i32, n)
        self.cnt = ti.field(ti.i32, self.ncells + 2)
        # whether a cell holds fluid (a flag, written without atomics: every writer writes 1);
        # a byte on the CPU, where it saves 3 bytes a cell (28 of 232 bytes a particle in the
        # dam break); 32 bits on a GPU, where 8-bit storage is an optional Vulkan/Metal feature
        self.fdtype = ti.u8 if on_cpu() else ti.i32
        self.fcnt = ti.field(self.fdtype, self.ncells + 2)
        self.fbytes = type_bytes(self.fdtype)
        self.start = ti.field(ti.i32, self.ncells + 2)
        # a GPU's prefix sum goes by blocks of cells (block_total, block_offsets, block_prefix); the
        # CPU's runs serially (prefix)
        self.scan_block, self.nscan = blocks(self.ncells + 1)
        self.bsum = None if on_cpu() else ti.field(ti.i32, self.nscan)

    def nbytes(self):
        return (8 + self.fbytes) * (self.ncells + 2) + 2 * self.n * 4 + (4 * self.nscan if self.bsum is not None else 0)

    @ti.func
    def cell_of(self, x):
        c = ti.floor((x - ti.Vector(self.lo)) / ti.Vector([self.cell_x, self.cell_y]), ti.i32)
        return ti.Vector([ti.max(0, ti.min(self.nx - 1, c[0])), ti.max(0, ti.min(self.ny - 1, c[1]))])

    @ti.func
    def key_of(self, x):
        c = self.cell_of(x)
        return c[1] * self.nx + c[0]

    @ti.func
    def inside(self, x):
        return self.lo[0] <= x[0] < self.hi[0] and self.lo[1] <= x[1] < self.hi[1]

    @ti.func
    def wrap(self, x):
        """Periodic in x: back into [lo, lo + period)."""
        y = x
        if ti.static(self.periodic_x):
            y[0] = x[0] - self.period * ti.floor((x[0] - self.lo[0]) / self.period)
            # in float32 a particle a hair left of lo wraps to exactly lo + period (measured: a
            # sand grain at x = -1e-8 became x = 1.0 and counted as leaving the domain)
            if y[0] >= self.lo[0] + self.period:
                y[0] = self.lo[0]
        return y

    # ---------------------------------------------------------------- counting sort, per item
    @ti.func
    def prefix(self):
        """Serial prefix sum over the cell counts (cells are few next to particles); cnt becomes
        a write cursor. One task: the running sum stays in a register (reading start[c] back
        chained every cell to the store before it)."""
        run = 0
        for c in range(self.ncells + 1):
            n = self.cnt[c]
            self.start[c] = run
            self.cnt[c] = run
            run += n
        self.start[self.ncells + 1] = run

    @ti.func
    def block_total(self, b):
        """A GPU's prefix sum, first pass (parallel over b): block b's count of particles."""
        t = 0
        for c in range(b * self.scan_block, ti.min((b + 1) * self.scan_block, self.ncells + 1)):
            t += self.cnt[c]
        self.bsum[b] = t

    @ti.func
    def block_offsets(self):
        """Second pass (one task): each block's total becomes its first cell's start."""
        run = 0
        for b in range(self.nscan):
            t = self.bsum[b]
            self.bsum[b] = run
            run += t
        self.start[self.ncells + 1] = run

    @ti.func
    def block_prefix(self, b):
        """Third pass (parallel over b): prefix()'s running sum within block b from its start."""
        run = self.bsum[b]
        for c in range(b * self.scan_block, ti.min((b + 1) * self.scan_block, self.ncells + 1)):
            n = self.cnt[c]
            self.start[c] = run
            self.cnt[c] = run
            run += n

    @ti.func
    def scatter(self, i):
        slot = ti.atomic_add(self.cnt[self.key[i]], 1)
        self.order[slot] = i

    @ti.func
    def sort_cell(self, c, ids: ti.template()):
        """Order cell c's particles by id (insertion sort: a cell holds a few), so every
        neighbour sum runs in the same order whatever the threads did: bitwise restarts."""
        s0 = self.start[c]
        s1 = self.start[c + 1]
        self.cnt[c] = 0
        if c < self.ncells:
            for a in range(s0 + 1, s1):
                v = self.order[a]
                vid = ids[v]
                b = a - 1
                while b >= s0 and ids[self.order[b]] > vid:
                    self.order[b + 1] = self.order[b]
                    b -= 1
                self.order[b + 1] = v

    # ---------------------------------------------------------------- neighbours
    @ti.func
    def for_neighbours(
        self, src: ti.template(), i, xi, task: ti.template(), acc: ti.template(), lanes: ti.template() = False
    ):
        """Visit every j of `src` within the kernel support of xi: task(i, j, r, r2, acc).

        j = i is visited too: a `j != i` test in this loop measured 2.7x slower, and every
        gradient term vanishes at r = 0 anyway; a task that must skip itself tests r2 > 0.

        lanes (the CPU, tasks of lane-safe modules: hooks/module.py): task is called for every
        candidate of a stencil row, without the support's branch, over the row's range padded
        to whole eights (at least 32: the vectorised loop's four unrolled eights), the padding's
        lanes moved out of reach. LLVM then packs eight candidates into each instruction
        (AVX2); a branch around the terms, a row shorter than the unrolled loop or a float
        maximum leaves the loop scalar (`python -m tisph.bench --lanes`).
        """
        self._visit(src, i, xi, task, acc, False, lanes)

    @ti.func
    def for_forward(self, src: ti.template(), i, xi, task: ti.template(), acc: ti.template()):
        """The forward half of i's stencil (engine/pairs.py): its own cell row after i in the
        sorted order, and the rows above; each pair of neighbours is in one of the two halves."""
        self._visit(src, i, xi, task, acc, True, False)

    @ti.func
    def _visit(  # noqa: C901 (ti.static branches: one is compiled)
        self,
        src: ti.template(),
        i,
        xi,
        task: ti.template(),
        acc: ti.template(),
        forward: ti.template(),
        lanes: ti.template(),
    ):
        c = self.cell_of(xi)
        dy0 = -self.cdiv
        if ti.static(forward):
            dy0 = 0
        if ti.static(not self.periodic_x):
            x0 = ti.max(c[0] - self.cdiv, 0)
            x1 = ti.min(c[0] + self.cdiv, self.nx - 1)
            for dy in range(dy0, self.cdiv + 1):  # runtime: one copy of the pair tasks (compiles 4x faster)
                cy = c[1] + dy
                if 0 <= cy < self.ny:
                    row = cy * self.nx
                    j0 = self.start[row + x0]
                    if ti.static(forward):
                        if dy == 0:
                            j0 = ti.max(j0, i + 1)
                    self._row(src, i, xi, task, acc, j0, self.start[row + x1 + 1], lanes)
        else:
            # periodic in x: a row's five cells are one range, or two where they wrap past the
            # seam (the wrapped part first where it comes first, so the sum runs in the same
            # order as cell by cell did); r is the nearest image
            d = self.cdiv
            for dy in range(dy0, d + 1):
                cy = c[1] + dy
                if 0 <= cy < self.ny:
                    row = cy * self.nx
                    lo = c[0] - d  # the first cell, and one past the last
                    hi = c[0] + d + 1
                    b0 = 0
                    b1 = 0
                    if lo < 0:
                        lo += self.nx
                        b0 = self.start[row]
                        b1 = self.start[row + hi]
                        hi = self.nx
                    elif hi > self.nx:
                        b0 = self.start[row]
                        b1 = self.start[row + hi - self.nx]
                        hi = self.nx
                    a0 = self.start[row + lo]
                    a1 = self.start[row + hi]
                    for seg in range(2):  # a runtime loop: one copy of the pair tasks
                        j0, j1 = a0, a1
                        if seg == 1:
                            j0, j1 = b0, b1
                        if ti.static(forward):
                            if dy == 0:
                                j0 = ti.max(j0, i + 1)
                        self._row(src, i, xi, task, acc, j0, j1, lanes)

    @ti.func
    def _row(self, src: ti.template(), i, xi, task: ti.template(), acc: ti.template(), j0, j1, lanes: ti.template()):
        """The candidates j0 <= j < j1 of one stencil row (r the nearest image where periodic);
        with lanes, the row padded and every candidate taken (for_neighbours)."""
        jp = j1
        if ti.static(lanes):
            if j1 > j0:  # an empty row (above the water, beyond a wall) takes no padded lanes
                jp = ti.min(j0 + ti.max((j1 - j0 + 7) // 8 * 8, LANE_MIN), src.x.shape[0])
        for j in range(j0, jp):
            r = xi - src.x[j]
            if ti.static(self.periodic_x):
                r[0] -= self.period * ti.round(r[0] * self.inv_period)
            if ti.static(lanes):
                r = ti.select(j < j1, r, ti.Vector([2.0 * self.support, 0.0]))  # past the row: no weight
                task(i, j, r, r.dot(r), acc)
            else:
                r2 = r.dot(r)
                if r2 < self.support * self.support:
                    task(i, j, r, r2, acc)

    @ti.func
    def fluid_near(self, xi):
        """Whether any fluid particle lies in the cells around xi (from this step's counts)."""
        c = self.cell_of(xi)
        found = False
        for dy in ti.static(range(-self.cdiv, self.cdiv + 1)):
            cy = c[1] + dy
            if 0 <= cy < self.ny:
                for dxo in range(-self.cdiv, self.cdiv + 1):
                    cx = c[0] + dxo
                    if ti.static(self.periodic_x):
                        cx = (cx + self.nx) % self.nx
                    if 0 <= cx < self.nx:
                        if self.fcnt[cy * self.nx + cx] > 0:
                            found = True
        return found
