"""The end of a run: probes.csv, the scene's metrics, the mass balance, summary.json, plots."""

import json
import math
import os

import numpy as np

from .. import __version__
from ..io import OutputError, json_safe, write_json
from ..particles import FLUID, OUT, OUTFLOW, SPRAY

# a weakly compressible run whose largest density error passes this warns (Monaghan's c0 = 10 u
# keeps the typical error near 1 %)
DENSITY_ERROR_LIMIT = 0.03


def mass_balance(initial, final):
    """Summed in float64 from the particles' own masses: fluid in the domain + fluid that left
    through open boundaries (+ leaked fluid) = the initial fluid mass."""
    m_dev = initial.m.astype(final["m"].dtype)  # the masses as the solver stores them
    m0 = float(np.sum(m_dev[initial.kind == FLUID], dtype=np.float64))
    m_in = float(np.sum(final["m"][final["kind"] == FLUID], dtype=np.float64))
    m_out = float(np.sum(final["m"][final["kind"] == OUTFLOW], dtype=np.float64))
    m_leak = float(np.sum(final["m"][final["kind"] == OUT], dtype=np.float64))
    m_spray = float(np.sum(final["m"][final["kind"] == SPRAY], dtype=np.float64))
    return dict(
        initial_fluid_mass=m0,
        fluid_mass=m_in,
        outflow_mass=m_out,
        leaked_mass=m_leak,
        spray_mass=m_spray,
        mass_balance_error=abs(m_in + m_out + m_leak + m_spray - m0) / m0 if m0 > 0 else 0.0,
        outflow_particles=int(np.sum(final["kind"] == OUTFLOW)),
        spray_particles=int(np.sum(final["kind"] == SPRAY)),
    )


def crossed_wall(solver, final):
    """Fluid outside the container (the step kernel stops the run at the first crossing, so the
    final state tells it all)."""
    if solver.container is None:
        return 0
    x0, y0, x1, y1, top = solver.container  # with the solver's tolerance
    x = final["x"][final["kind"] == FLUID]
    return int(np.sum((x[:, 1] < y0) | (x[:, 1] > y1) | ((x[:, 1] < top) & ((x[:, 0] < x0) | (x[:, 0] > x1)))))


def _warn_no_value(run, metrics):
    """A metric with no value is said, not left as a silent null."""

    def nan(v):
        return isinstance(v, float) and not math.isfinite(v)

    def no_value(v):  # a list's None is a gauge said at the start to stand dry (WaveGauges)
        if isinstance(v, (list, tuple)):
            return any(nan(x) for x in v)
        return v is None or nan(v)

    undefined = [k for k, v in metrics.items() if no_value(v)]
    if undefined:
        w = (
            f"{len(undefined)} metric(s) have no value: {', '.join(undefined)} (a point gauge with no water "
            f"within its kernel all its window, a run too short for their analysis window, t = {run.solver.time:.4g} "
            "s, or a quantity that never occurred)"
        )
        run.case.warnings.append(w)
        run.log(f"warning: {w}", always=True)


def _density_notes(run):
    """The density error past DENSITY_ERROR_LIMIT: a warning where the bulk of the water passed
    it, a note where only a splash did."""
    s, notes = run.solver, []
    if max(s.rhodev_p999, s.max_density_error) > DENSITY_ERROR_LIMIT:
        w = (
            f"largest density error {s.max_density_error:.1%}, 99.9th percentile {s.rhodev_p999:.1%}, mean "
            f"{s.mean_density_error:.2%}: "
        )
        if s.rhodev_p999 > DENSITY_ERROR_LIMIT:  # the bulk of the water, not a splash
            w += (
                f"the water was compressed more than weak compressibility allows ({DENSITY_ERROR_LIMIT:.0%}); "
                f"raise numerics.c0 (it is {s.c0:.3g} m/s)"
            )
            run.case.warnings.append(w)
            run.log(f"warning: {w}", always=True)
        else:
            notes.append(
                w + "only a few particles (an impact, a splash) passed "
                f"{DENSITY_ERROR_LIMIT:.0%}; the bulk stayed within it"
            )
    return notes


def summarize(run, status, message, wall, step_s, nsteps, compile_s, segment=None):
    """wall and step_s: the whole run's (a restarted run's segments summed); segment: this
    segment's (wall, stepping) seconds, over which particle-steps/s is measured."""
    s, case, cfg, obs = run.solver, run.case, run.cfg, run.case.observers
    run.write_xdmf()
    run.write_probes()
    arr = {c: np.array([r[k] for r in run.probes], float) for k, c in enumerate(run.probe_columns())}
    metrics = obs.metrics(arr) if obs.metrics else {}
    final = s.state(("x", "v", "kind", "rho", "p", "mat", "m"))
    if obs.final_metrics:
        metrics.update(obs.final_metrics(final))

    _warn_no_value(run, metrics)
    density_notes = _density_notes(run)
    mass = mass_balance(case.particles, final)
    if mass["spray_particles"]:
        density_notes.append(
            f"{mass['spray_particles']} particles ({mass['spray_mass'] / mass['initial_fluid_mass']:.2%} "
            "of the water) left the density band as spray and were removed "
            f"(numerics.spray_limit = {cfg.numerics.spray_limit:g})"
        )
    crossed = crossed_wall(s, final)
    nb = int(np.sum(case.particles.kind != FLUID))
    seg_step = segment[1] if segment else step_s
    pps = (s.n * nsteps / seg_step) if seg_step > 0 else 0.0
    summary = dict(
        scene=run.name,
        status=status,
        message=message,
        tisph_version=__version__,
        dx=float(cfg.numerics.dx),
        particles=int(s.n),
        fluid_particles=int(case.particles.count(FLUID)),
        boundary_particles=nb,
        steps=int(s.steps),
        sim_time=float(s.time),
        wall_time_s=wall,
        step_time_s=step_s,
        compile_time_s=compile_s,
        particle_steps_per_s=pps,
        wall_s_per_sim_s=(wall / s.time) if s.time > 0 else None,
        arch=run.arch,
        pair_once=getattr(s, "pair_once", None) is not None,
        leaked_particles=int(s.leaked),
        crossed_wall=crossed,
        max_density_error=s.max_density_error,
        mean_density_error=s.mean_density_error,
        density_error_p999=s.rhodev_p999,
        frames=run.frame_no,
        snapshots=len(run.snapshots),
        c0=float(s.c0),
        h=float(s.h),
        physics=case.physics.as_dict(),
        modules=[m.name for m in s.modules],
        physics_notes=physics_notes(cfg, case.physics) + density_notes,
        warnings=list(case.warnings),
        mass=mass,
        metrics=metrics,
    )
    if run.restart:
        summary["restarted_from"] = os.path.abspath(run.restart)
    if obs.finalize:
        try:
            obs.finalize(run.out, metrics)
        except OutputError:
            raise
        except Exception as e:  # a failed plot must not lose the run's numbers
            run.log(f"warning: could not write the scene's plots: {e}", always=True)
    write_json(os.path.join(run.out, "summary.json"), summary)
    run.log(
        f"{status}: {s.steps} steps to t = {s.time:.4g} s in {wall:.2f} s "
        f"({pps:.3g} particle-steps/s), leaked {s.leaked}, crossed a wall {crossed}, "
        f"max density error {s.max_density_error:.3%}"
    )
    if metrics:
        run.log("metrics: " + json.dumps(json_safe(metrics)))
    return summary


def physics_notes(cfg, physics):
    """Why a compiled switch differs from what the config says."""
    notes = []
    if physics.laminar_viscosity and not cfg.numerics.laminar_viscosity and physics.rheology:
        notes.append(
            "laminar_viscosity is on although numerics.laminar_viscosity = false: a non-Newtonian "
            "material's stress is its rheology's viscosity, which the laminar term applies"
        )
    return notes
