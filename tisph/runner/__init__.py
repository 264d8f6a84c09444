"""Running a scene: set-up (setup.py), the time loop (loop.py), what it writes as it goes
(outputs.py), the summary at the end (summary.py), reading a case (reading.py), starting a run from Python (start.py) and the command line's entry
point (entry.py).

What a run writes into OUT (the contract scenes and the benchmark rely on):
  <scene>.mp4 and frames/00000.png ... (unless --no-render)
  probes.csv   time series, columns t + the scene's probe columns
  summary.json scene, dx, particles, steps, sim_time, wall_time_s, particle_steps_per_s, arch,
               leaked_particles, metrics{...}, status
  run.log      the resolved config, warnings and timings
"""

from .entry import run_scene  # noqa: F401
from .loop import Run  # noqa: F401
from .reading import resolve  # noqa: F401
from .setup import Log, SimulationError, build_case, common_params, config_changes, describe_instability, sound_speed  # noqa: F401
from .start import output_dir, run_case, simulate  # noqa: F401
