"""The modules, in the order the step kernel calls them. Order matters where modules add to the
same sum (float addition is not associative): the order here is the order of the terms.

Adding a term: write its Module, add it here, add its switch to config.Physics (and the
config key that sets it), and test it (tests/engine/test_terms.py).
"""

from ..boundaries.moving_bed import MovingBed
from ..boundaries.walls import DynamicWall, ExtrapolatedWall, NoSlip, RepulsiveWall, WallImpact
from ..boundaries.wavemaker import Paddle
from ..boundaries.zones import Container, Damping, Drive, Inflow, Outflow, Spray
from ..physics.dual import DualCriteria
from ..physics.fluid import (
    XSPH,
    ArtificialViscosity,
    Continuity,
    DensityDiffusion,
    LaminarViscosity,
    Pressure,
    Shifting,
    VelocityGradient,
)
from ..physics.grains import DEM, Drag, Rheology
from ..physics.shepard import Shepard
from ..physics.suspension import Suspension
from ..physics.turbulence import SPS, TKE, Omega

MODULES = (
    RepulsiveWall,  # view: the wall particle mirrors i's pressure; Lennard-Jones force first
    Continuity,
    Pressure,
    WallImpact,
    ArtificialViscosity,
    NoSlip,  # the ghost velocity, before the viscous terms read it
    LaminarViscosity,
    VelocityGradient,
    TKE,
    Omega,
    SPS,
    DEM,
    Drag,
    DensityDiffusion,
    XSPH,
    Shifting,
    Suspension,
    Rheology,  # finish: the effective viscosity for the next step (may rest the plug)
    Drive,
    Damping,
    Inflow,
    Paddle,
    MovingBed,
    DynamicWall,
    ExtrapolatedWall,
    Outflow,
    Spray,
    Container,
    Shepard,
    DualCriteria,  # last: its finish reads the step's velocity; its dt_limit the final step
)


def enabled_modules(S):
    return [cls(S) for cls in MODULES if cls.enabled(S)]
