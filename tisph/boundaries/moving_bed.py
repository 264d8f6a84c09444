"""The morphodynamic sand bed as a boundary: columns of BED particles, one per bed station,
wall_layers deep under the bed surface z_b(x), follow the bed as tisph/sediment moves it."""

import numpy as np
import taichi as ti

from ..hooks.module import Module
from ..particles import BED


@ti.data_oriented
class MovingBed(Module):
    """A prescribed-motion boundary like the paddle: particle i of station c sits at its start
    position plus (0, z_b(c) - z_b0(c)) and carries the bed's vertical speed, so the water sees
    the bed rise and fall. The whole column moves, so it stays wall_layers thick and no gap opens
    under the water. Set with solver.set_bed(dz, w) (per station)."""

    name = "moving_bed"
    on = {"moving_bed": True}

    def fields(self, real):
        return {
            "bx0": ti.types.vector(2, real),  # the particle's start position
            "bcol": ti.i32,
        }  # its bed station (-1: not a bed particle)

    def allocate(self, S):
        self.nst = int(S.params.get("bed_stations", 1))
        self.dz = ti.field(S.real, self.nst)  # z_b - z_b0 per station
        self.w = ti.field(S.real, self.nst)  # dz_b/dt per station

    def setup(self, S):
        S.p.bx0.from_numpy(S.particles.x.astype(S.np_real))
        col = getattr(S.particles, "bed_station", None)
        if col is None or len(col) != S.n:
            col = np.full(S.n, -1, np.int32)
        S.p.bcol.from_numpy(np.asarray(col, np.int32))

    @ti.func
    def boundary_motion(self, S, i, k, dt):
        if k == BED:
            c = S.p.bcol[i]
            S.p.x[i] = S.p.bx0[i] + ti.Vector([0.0, self.dz[c]])
            S.p.v[i] = ti.Vector([0.0, self.w[c]])

    @property
    def state_fields(self):
        """Runtime fields a checkpoint keeps (engine/access.py raw_state)."""
        return {"dz": self.dz, "w": self.w}

    def set(self, dz, w):
        self._set(np.ascontiguousarray(dz, dtype=np.float64), np.ascontiguousarray(w, dtype=np.float64))

    @ti.kernel
    def _set(self, dz: ti.types.ndarray(dtype=ti.f64, ndim=1), w: ti.types.ndarray(dtype=ti.f64, ndim=1)):
        # one launch for both (two from_numpy calls cost twice the launch overhead)
        for c in range(self.nst):
            self.dz[c] = ti.cast(dz[c], self.dz.dtype)
            self.w[c] = ti.cast(w[c], self.w.dtype)
