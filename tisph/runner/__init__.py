"""Running a scene: set-up (setup.py), the time loop (loop.py), what it writes as it goes
(outputs.py), the summary at the end (summary.py), and the entry points (entry.py).

What a run writes into OUT (the contract scenes and the benchmark rely on):
  <scene>.mp4 and frames/00000.png ... (unless --no-render)
  probes.csv   time series, columns t + the scene's probe columns
  summary.json scene, dx, particles, steps, sim_time, wall_time_s, particle_steps_per_s, arch,
               leaked_particles, metrics{...}, status
  run.log      the resolved config, warnings and timings
"""
from .entry import output_dir, resolve, run_case, run_scene, simulate  # noqa: F401
from .loop import Run  # noqa: F401
from .setup import (Log, SimulationError, build_case, common_params, config_changes,  # noqa: F401
                    describe_instability, sound_speed)
