"""What a step that went wrong raises, and its message (without Taichi: the runner and the bed
coupling raise it too)."""


class SimulationError(RuntimeError):
    """The run went unstable; the message says where, what and a likely cause."""


def unstable(solver, what, where, cause):
    """The SimulationError message of every instability: when, what went wrong, where, a likely cause."""
    return f"unstable at step {solver.steps}, t = {solver.time:.6g} s: {what}; {where}. Likely cause: {cause}."
