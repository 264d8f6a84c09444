"""What the modules' pair terms share in the CPU's vector lanes (engine/grid.py, for_neighbours)."""

import taichi as ti

from ..particles import FLUID


@ti.func
def lane_volume(nb, mj, mi):
    """Neighbour j's volume where it is fluid of i's material, else 0: a term within one material
    in the CPU's vector lanes. Two selects, not one on `fluid and same`: with the `and` LLVM left
    the loop scalar where no other term read j's material (the laminar viscosity does)."""
    return ti.select(mj == mi, ti.select(nb.kj == FLUID, nb.vol_j, 0.0), 0.0)
