"""What the step kernel and the modules' hooks read: the kernel view. They take it as S, not the
solver, so a module reaches the particles, the parameters and the grid through these names and
nothing else (the solver's Python side, its run state and its API stay out of the kernels).

  the particle store (store.py):   p (the state), tmp (its sorted copy), pairs (the two, member by member)
  the parameter table (table.py):  table, prm (runtime parameters), mat (the material table),
                                   stats (the step's statistics), has_stat
  the grid (grid.py):              grid
  the stepper (stepper.py):        stepper (neighbour_view, for dual time stepping's two passes)
  the kernel's constants:          K, h, inv_h, w_scale, g_scale, eta2, dx, n, real, bits, cpu,
                                   lanes (the pair loop in vector lanes, grid.py)
  the step's composition:          physics (the compiled-in switches), hooks, fast, slow (the
                                   hooks by rate, physics/dual.py), dual, outflow, container

A module's Python side (setup, after_step, its own kernels launched from Python) takes the solver.
"""

import taichi as ti

NAMES = (
    "p", "tmp", "pairs",
    "table", "prm", "mat", "stats", "has_stat",
    "grid",
    "stepper",
    "K", "h", "inv_h", "w_scale", "g_scale", "eta2", "dx", "n", "real", "bits", "cpu", "lanes",
    "physics", "hooks", "fast", "slow", "dual", "outflow", "container",
)  # fmt: skip


@ti.data_oriented  # Taichi reads a data-oriented object's attributes at compile time
class KernelView:
    """The names above, taken from the solver once its parts are built (none of them is rebound
    afterwards); any other name is an AttributeError when the kernel is compiled."""

    __slots__ = NAMES

    def __init__(self, solver, stepper):
        for k in NAMES:
            setattr(self, k, stepper if k == "stepper" else getattr(solver, k))
