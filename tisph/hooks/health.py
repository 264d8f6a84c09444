"""Health codes the step kernel raises, and the messages a run that goes unstable prints."""

import taichi as ti

# Codes of the instability detector, most severe last (the kernel keeps the maximum).
BAD_NONE, BAD_DENSITY, BAD_SPRAY, BAD_SPEED, BAD_SPILL, BAD_WALL, BAD_LEAK, BAD_DT, BAD_NAN = range(9)
BAD_TEXT = {
    BAD_SPRAY: (
        "more of the water left the density band than numerics.spray_limit allows as spray",
        "the flow came apart in bulk, not as spray off a breaker: raise the sound speed, lower "
        "dx, or check the forces; a particle torn off alone is removed, this many is an instability",
    ),
    BAD_SPILL: (
        "a fluid particle went over a side wall and out of the tank",
        "a jet or splash overtopped the walls: raise the walls, or the sound speed is too low "
        "and the run-up too violent",
    ),
    BAD_WALL: (
        "a fluid particle crossed a wall",
        "particles penetrated the wall: wall force too weak (numerics.wall_strength), walls too "
        "thin (numerics.wall_layers), sound speed too low for the impact, or time step too large",
    ),
    BAD_LEAK: (
        "a fluid particle left the simulation domain",
        "particles penetrated the wall or were thrown out of the domain",
    ),
    BAD_DENSITY: (
        "density left the allowed band around rest density",
        "particles compressed against a wall or torn apart: time step too large for this "
        "sound speed, or sound speed too low for the flow",
    ),
    BAD_SPEED: (
        "speed exceeded the sound speed",
        "the flow is faster than the equation of state allows: raise c0 or check forces",
    ),
    BAD_DT: (
        "time step collapsed below its floor",
        "a force blew up (particles penetrated the wall, or two particles overlap)",
    ),
    BAD_NAN: (
        "NaN or Inf in acceleration or density",
        "dt too large for this sound speed, or particles penetrated the wall",
    ),
}


@ti.func
def is_bad(x):
    return ti.math.isnan(x) or ti.math.isinf(x)


@ti.func
def report(stats: ti.template(), code, pid):
    """Raise `code` for particle id `pid` (an id, not a slot: slots change at every re-sort and
    the runner reads this up to 10 steps later)."""
    ti.atomic_max(stats[None].bad_code, code)
    ti.atomic_min(stats[None].bad_idx, pid)


@ti.func
def fluid_code(a, rho, v2, dev, c0, band):
    """The health of one fluid particle after its step: NaN, speed, density band."""
    code = BAD_NONE
    if is_bad(a.dot(a)) or is_bad(rho):
        code = BAD_NAN
    elif v2 > c0 * c0:
        code = BAD_SPEED
    elif dev > band:
        code = BAD_DENSITY
    return code
