"""Compatibility: the solver now lives in tisph.engine (state, grid, modules, the step kernel)."""
from .engine.health import BAD_TEXT  # noqa: F401
from .engine.solver import Solver  # noqa: F401
