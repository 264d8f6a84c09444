"""Compatibility: the run loop now lives in tisph.run, the case in tisph.case."""
from .case import Case, make_case  # noqa: F401
from .run import *  # noqa: F401,F403
from .run import (Log, Run, SimulationError, build_case, common_params, output_dir, resolve,  # noqa: F401
                  run_case, run_scene, simulate, sound_speed)
