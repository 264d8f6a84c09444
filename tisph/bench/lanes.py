"""What the CPU's vector units could give the pair loop: `python -m tisph.bench --lanes`.

Taichi compiles for the host (AVX2 and FMA here: its kernels' code uses ymm registers), and
LLVM's loop vectoriser packs eight neighbours' arithmetic into one instruction where it can; the
engine's branch form of the pair loop stays scalar, and the default scheme's runs in the lanes
(engine/grid.py; docs/performance.md, "The pair loop in vector lanes"). This bench times one
pass of four pair terms of the default scheme's kind (continuity, Tait pressure, Molteni's
density diffusion, Morris' viscosity: Wendland at h = 2.5 dx, the engine's grid of cells half the
support wide, the particles sorted by cell) written several ways, on one lattice:

- branch: the engine's branch form, the terms inside `if r2 < support^2`;
- lanes: the terms for every candidate, without a branch (the kernel is zero past its
  support), over each stencil row's range padded to whole eights, the lanes past the row's end
  moved out of reach;
- lanes, blocked: the same inside the engine's loop shape, a parallel loop over blocks of
  particles with a serial loop over each block's particles;
- lanes, float max / integer max: with a running maximum besides the sums (the step's viscous
  signal speed), as a float, or as the integer order of its non-negative IEEE bits.

Each is timed as the best and the median of seven sets of 20 passes; the sums are compared with
the branch form's (the vector forms add in another order). Then the branch form against the
lanes with the integer maximum at h = 1.3 to 2.5 dx, in cells of half the support and of the
whole (a 3 x 3 stencil), which the engine takes under a support of 3.9 dx (engine/solver.py).
Writes OUT/lanes.md."""

import os
import time

import numpy as np
import taichi as ti

FORMS = ("branch", "lanes", "lanes, blocked", "lanes, float max", "lanes, integer max")
BLOCK = 64  # particles a block in the blocked form
REACHES = (1.3, 1.6, 2.0, 2.5)  # h / dx: the lanes against the branch form by the kernel's reach


def lattice(nx_p, ny_p, dx, seed=0, h_factor=2.5, cdiv=2):
    """Particle positions on a jittered lattice, and the cell grid's sort: (x, start, ncx, ncy,
    cell); cells of the support 2 h over cdiv (the engine's 2, or 1 in the lanes at short reach)."""
    h = h_factor * dx
    cell = 2.0 * h / cdiv
    rng = np.random.default_rng(seed)
    ij = np.stack(np.meshgrid(np.arange(nx_p), np.arange(ny_p), indexing="ij"), -1).reshape(-1, 2)
    x = (ij + 0.5) * dx + rng.uniform(-0.1, 0.1, ij.shape) * dx
    ncx, ncy = int(nx_p * dx / cell) + 1, int(ny_p * dx / cell) + 1
    key = (x[:, 1] // cell).astype(int) * ncx + (x[:, 0] // cell).astype(int)
    order = np.argsort(key, kind="stable")
    start = np.searchsorted(key[order], np.arange(ncx * ncy + 1))
    return x[order], start, ncx, ncy, cell


def build(nx_p=200, ny_p=100, dx=0.01, seed=0, h_factor=2.5, cdiv=2):
    """(launch(form), read(), particles): the pass over one lattice (Taichi must be initialised)."""
    p = PairPass(nx_p, ny_p, dx, seed, h_factor, cdiv)
    return p.launch, p.read, p.n


@ti.data_oriented
class PairPass:
    """The lattice's fields and the pass written each way (FORMS)."""

    def __init__(self, nx_p, ny_p, dx, seed, h_factor, cdiv):
        x_np, start_np, self.ncx, self.ncy, self.cell = lattice(nx_p, ny_p, dx, seed, h_factor, cdiv)
        self.cdiv = cdiv
        n = self.n = len(x_np)
        self.h = h = h_factor * dx
        self.sup2 = (2.0 * h) ** 2
        self.far = 2.0 * 2.0 * h
        self.m = 1000.0 * dx * dx
        self.gs = -5.0 * 7.0 / (4.0 * np.pi * h**4)  # Wendland's grad W / r factor
        self.c0, self.delta, self.mu, self.eta2 = 20.0, 0.1, 1e-3, 0.01 * h * h
        rng = np.random.default_rng(seed + 1)
        self.x, self.v = ti.Vector.field(2, ti.f32, n), ti.Vector.field(2, ti.f32, n)
        self.rho, self.p = ti.field(ti.f32, n), ti.field(ti.f32, n)
        self.start = ti.field(ti.i32, self.ncx * self.ncy + 1)
        self.drho, self.acc, self.sig = ti.field(ti.f32, n), ti.Vector.field(2, ti.f32, n), ti.field(ti.f32, n)
        self.x.from_numpy(x_np.astype(np.float32))
        self.v.from_numpy(rng.normal(0.0, 0.1, (n, 2)).astype(np.float32))
        self.rho.from_numpy((1000.0 + rng.normal(0.0, 1.0, n)).astype(np.float32))
        self.p.from_numpy(rng.normal(0.0, 100.0, n).astype(np.float32))
        self.start.from_numpy(start_np.astype(np.int32))

    @ti.func
    def terms(self, xi, vi, ri, pi, j, r, r2, s: ti.template()):
        """The four terms of neighbour j into s (a, d), and the pair's signal speed, returned."""
        t = ti.max(1.0 - 0.5 * ti.sqrt(r2) / self.h, 0.0)
        g = self.gs * t * t * t * r
        vij = vi - self.v[j]
        rj = self.rho[j]
        rg = r.dot(g)
        ie = 1.0 / (r2 + self.eta2)
        s.d += self.m * vij.dot(g) + 2.0 * self.delta * self.h * self.c0 * (ri - rj) * rg * ie * self.m / rj
        s.a += -self.m * (pi + self.p[j]) / (ri * rj) * g + 2.0 * self.mu * self.m / (ri * rj) * rg * ie * vij
        return ti.select(t > 0.0, ti.abs(self.h * vij.dot(r) * ie), 0.0)

    @ti.func
    def particle(self, i, lanes: ti.template(), fmax: ti.template()):  # noqa: C901 (ti.static: one form compiled)
        xi, vi, ri, pi = self.x[i], self.v[i], self.rho[i], self.p[i]
        cx, cy = int(xi[0] / self.cell), int(xi[1] / self.cell)
        s = ti.Struct(a=ti.Vector([0.0, 0.0]), d=0.0, f=0.0, b=0)  # sums; the maximum as a float, as bits
        d = ti.static(self.cdiv)
        for dy in range(-d, d + 1):
            yy = cy + dy
            if 0 <= yy < self.ncy:
                j0 = self.start[yy * self.ncx + ti.max(cx - d, 0)]
                je = self.start[yy * self.ncx + ti.min(cx + d, self.ncx - 1) + 1]
                j1 = je
                if ti.static(lanes):
                    j1 = ti.min(j0 + ti.max((je - j0 + 7) // 8 * 8, 32), self.n)
                for j in range(j0, j1):
                    r = xi - self.x[j]
                    if ti.static(lanes):
                        r = ti.select(j < je, r, ti.Vector([self.far, 0.0]))
                    r2 = r.dot(r)
                    if ti.static(lanes) or r2 < self.sup2:
                        sig = self.terms(xi, vi, ri, pi, j, r, r2, s)
                        if ti.static(fmax == 1):
                            s.f = ti.max(s.f, sig)
                        elif ti.static(fmax == 2):
                            s.b = ti.max(s.b, ti.bit_cast(sig, ti.i32))
        self.drho[i] = s.d
        self.acc[i] = s.a
        self.sig[i] = ti.bit_cast(s.b, ti.f32) if ti.static(fmax == 2) else s.f

    @ti.kernel
    def flat(self, lanes: ti.template(), fmax: ti.template()):
        for i in range(self.n):
            self.particle(i, lanes, fmax)

    @ti.kernel
    def blocked(self, lanes: ti.template()):
        for b in range((self.n + BLOCK - 1) // BLOCK):
            for i in range(b * BLOCK, ti.min((b + 1) * BLOCK, self.n)):
                self.particle(i, lanes, 0)

    def launch(self, form):
        {
            "branch": lambda: self.flat(False, 0),
            "lanes": lambda: self.flat(True, 0),
            "lanes, blocked": lambda: self.blocked(True),
            "lanes, float max": lambda: self.flat(True, 1),
            "lanes, integer max": lambda: self.flat(True, 2),
        }[form]()

    def read(self):
        return self.drho.to_numpy(), self.acc.to_numpy(), self.sig.to_numpy()


def time_form(launch, read, form, sets=7, calls=20):
    """Best and median seconds a pass (Taichi's kernels are asynchronous: a read ends each set)."""
    launch(form)
    read()
    ts = []
    for _ in range(sets):
        t0 = time.perf_counter()
        for _ in range(calls):
            launch(form)
        read()
        ts.append((time.perf_counter() - t0) / calls)
    return min(ts), float(np.median(ts))


def agreement(ref, out):
    """The largest difference of drho and a from the reference's, relative to their largest."""
    return max(float(np.max(np.abs(o - r)) / max(float(np.max(np.abs(r))), 1e-30)) for r, o in zip(ref[:2], out[:2]))


def main(a):
    from .. import runtime
    from ..io import ensure_dir, write_text

    runtime.init("cpu", "f32")
    launch, read, n = build(60, 30) if a.dry_run else build()
    sets, calls = (2, 2) if a.dry_run else (7, 20)
    launch("branch")
    ref = read()
    rows = []
    for form in FORMS:
        launch(form)
        out = read()
        best, med = time_form(launch, read, form, sets, calls)
        rows.append((form, best, med, agreement(ref, out)))
        print(f"{form}: best {best * 1e3:.2f} ms, median {med * 1e3:.2f} ms a pass", flush=True)
    b0 = rows[0][1]
    lines = [
        "# The pair loop in vector lanes",
        "",
        f"{n} particles (Wendland h = 2.5 dx, cells half the support), one pass of four pair terms; "
        f"Taichi CPU, f32, fast math (as the engine runs); best and median of {sets} sets of {calls} passes.",
        "",
        "| form | best ms | median ms | speed against branch (best) | sums against branch (largest relative) |",
        "|---|---|---|---|---|",
    ]
    lines += [f"| {f} | {b * 1e3:.2f} | {m * 1e3:.2f} | {b0 / b:.2f}x | {e:.1e} |" for f, b, m, e in rows]
    lines += [
        "",
        "By the kernel's reach: the branch form in cells of half the support (the engine's), the lanes in cells "
        "of half (a row holds about 5 (h / dx)^2 candidates) and of the whole support (3 x 3 cells, 12 (h / dx)^2):",
        "",
        "| h / dx | branch ms | lanes, integer max, ms | speed | lanes, whole-support cells, ms | speed |",
        "|---|---|---|---|---|---|",
    ]
    for hf in REACHES:
        t = {}
        for cdiv in (2, 1):
            launch, read, _ = build(60, 30, h_factor=hf, cdiv=cdiv) if a.dry_run else build(h_factor=hf, cdiv=cdiv)
            if cdiv == 2:
                t["b"] = time_form(launch, read, "branch", sets, calls)[0]
            t[cdiv] = time_form(launch, read, "lanes, integer max", sets, calls)[0]
        tb = t["b"]
        lines.append(
            f"| {hf:g} | {tb * 1e3:.2f} | {t[2] * 1e3:.2f} | {tb / t[2]:.2f}x | {t[1] * 1e3:.2f} | {tb / t[1]:.2f}x |"
        )
        print(lines[-1], flush=True)
    ensure_dir(a.out)
    write_text(os.path.join(a.out, "lanes.md"), "\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0
