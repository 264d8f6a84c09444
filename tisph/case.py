"""A scene's contract (Scene: one class a scene, registered by one line in tisph/registry.py;
docs/engine.md, "Adding a scene") and what its build(cfg) returns: the solver's input (Model),
what is measured and written while it runs (Observers) and how it is drawn (Picture), kept apart
so the solver never sees a probe and a probe never writes the solver's fields. The runner,
--describe, the sweep and the viewer read a scene only through the contract; importing a scene
imports no Taichi.

After PySPH's Application (create_particles, the scheme, post_process), with the settings resolved
before anything is built: derive and check see the whole case, build turns it into particles,
physics, observers and a picture.
"""

from __future__ import annotations

import dataclasses
import sys
from typing import Callable

from .errors import ConfigError
from .settings.config import Physics
from .settings.schema import choices, ranges, values


@dataclasses.dataclass
class Model:
    """The solver's input: particles, materials, domain, runtime parameters, compiled physics."""

    particles: object
    materials: list
    domain: tuple
    params: dict
    physics: Physics
    outflow: tuple = ()  # open boundaries: boxes (x0, y0, x1, y1) fluid leaves through
    container: tuple = None  # (x0, y0, x1, y1[, wall top]) the walls enclose: fluid outside
    # (below the wall top) crossed a wall, and the run stops

    def solver(self):
        from .engine.solver import Solver

        return Solver(
            self.physics,
            self.particles,
            self.materials,
            self.domain,
            self.params,
            outflow=self.outflow,
            container=self.container,
        )


@dataclasses.dataclass
class Observers:
    """Probes, metrics, events and controls of a run."""

    probe_columns: tuple = ()
    probe: Callable = None  # probe(state: dict) -> tuple of floats
    metrics: Callable = None  # metrics(columns: dict of np arrays) -> dict
    final_metrics: Callable = None  # final_metrics(state: dict of np arrays) -> dict
    events: list = dataclasses.field(default_factory=list)  # [(t, callback(state, t))] at exact times
    finalize: Callable = None  # finalize(out, metrics) -> None: plots, extra files
    stills: tuple = ()  # simulated times of named stills, stills/t0.040.png
    control: Callable = None  # control(solver) every control_every steps (through its set_* methods)
    control_every: int = 10
    persist: tuple = ()  # the observers' mutable history (lists, dicts, objects): a
    # checkpoint keeps it, so a restart continues every output


@dataclasses.dataclass
class Picture:
    """How frames are drawn."""

    view: tuple
    u_max: float  # the expected peak speed (colour scale, sound-speed check)
    render_modes: tuple = ("speed",)  # stacked panels: speed | phase | flat | pressure (render.Renderer)
    mat_colors: tuple = None  # per material: an RGB colour (sediment) or None (by speed)
    speed_scale: float = 0.0  # top of the speed colour bar (m/s); 0: u_max
    pressure_scale: float = 0.0  # top of the "pressure" panel's colour bar (Pa)
    bed_panel: Callable = None  # bed_panel(x0, x1, n) -> (x, bed change): a panel under the frame
    bed_label: str = ""  # what the bed panel's label adds (the morphological factor)
    bed_range: float = 0.0  # m: the bed panel's half-height for the whole movie; 0: grows with the bed
    bed_surface: Callable = None  # bed_surface(x) -> z_b: the sand under it is filled in sand colour
    zoom: tuple = None  # ((x0, y0), (x1, y1)): a window at true scale under the frame
    marks: tuple = ()  # (x, label) of gauges: a dotted line across the frame
    zones: tuple = ()  # (x0, x1, label) of zones (an absorber): a bar under the frame
    solid_region: Callable = None  # solid_region(points) -> mask: the solids filled as drawn, not as stairs


_PARTS = {cls: {f.name for f in dataclasses.fields(cls)} for cls in (Model, Observers, Picture)}


@dataclasses.dataclass
class Case:
    name: str
    model: Model
    observers: Observers
    picture: Picture
    notes: list = dataclasses.field(default_factory=list)
    warnings: list = dataclasses.field(default_factory=list)

    # the model's parts, read often enough to name
    particles = property(lambda self: self.model.particles)
    materials = property(lambda self: self.model.materials)
    domain = property(lambda self: self.model.domain)
    params = property(lambda self: self.model.params)
    physics = property(lambda self: self.model.physics)
    u_max = property(lambda self: self.picture.u_max)


def make_case(name, notes=None, **parts):
    """A Case from keyword arguments, each sorted into the Model, Observers or Picture it
    belongs to; an unknown keyword is an error."""
    kw = {cls: {} for cls in _PARTS}
    for k, v in parts.items():
        owner = next((cls for cls, names in _PARTS.items() if k in names), None)
        if owner is None:
            raise TypeError(f"make_case(): unknown part {k!r}")
        kw[owner][k] = v
    return Case(name, Model(**kw[Model]), Observers(**kw[Observers]), Picture(**kw[Picture]), notes=list(notes or []))


class Scene:
    """A scene: its keys (SCHEMA; DEFAULTS, RANGES and CHOICES are derived from it once, here),
    the values it derives, its checks and its build; its docstring, one line, is what `tisph
    scenes` lists. Override what the scene needs:

      NAME        its name, as registered
      SCHEMA      its keys (tisph/settings/schema.py's Keys) laid on the shared ones
      DEPARTS     {numerics key: why} where it leaves its scheme (tests/engine/test_schemes.py)
      ELEMENTS    the keys of each entry of its lists of tables (a case of one's own: [[solid]])
      derive(cfg, given) -> ({dotted key: value}, notes): values it chooses for keys the user left
                  unset (given: the keys the user set); each with run.log's line saying why
      check(cfg)  refuses a case it cannot run with a ConfigError naming the key
      build(cfg)  -> tisph.case.Case: particles, physics, parameters, observers, picture
    Its module holds the instance as SCENE and `main = partial(run_scene, SCENE)`, which
    `python -m tisph.scenes.NAME` runs.
    """

    NAME: str = ""
    SCHEMA: dict = {}
    DEPARTS: dict = {}
    ELEMENTS: dict = {}
    DEFAULTS: dict = {}
    RANGES: dict = {}
    CHOICES: dict = {}

    def __init_subclass__(cls, **kw):
        super().__init_subclass__(**kw)
        if "SCHEMA" in cls.__dict__:
            cls.DEFAULTS, cls.RANGES, cls.CHOICES = values(cls.SCHEMA), ranges(cls.SCHEMA), choices(cls.SCHEMA)

    @property
    def doc(self) -> str:
        """What the scene is: its module's docstring (the command line's description)."""
        return (sys.modules[type(self).__module__].__doc__ or type(self).__doc__ or "").strip()

    @property
    def module(self) -> str:
        """The module `python -m` runs it as."""
        return type(self).__module__

    def derive(self, cfg, given):
        return {}, []

    def check(self, cfg):
        return None

    def build(self, cfg):
        raise NotImplementedError(f"{type(self).__name__}.build")

    def __repr__(self):
        return f"<scene {self.NAME}>"


def resolves(length, n, what, dx, key="numerics.dx", value=None):
    """The one refusal of a length the spacing cannot resolve: under n particles across `what`.
    key: the key to name (numerics.dx, or the length's own key with its value)."""
    if length / dx >= n - 1e-9:
        return
    if key == "numerics.dx":
        raise ConfigError(key, dx, f"at most {length / n:.4g} m ({n} particles across {what})")
    raise ConfigError(key, value, f"at least {n} dx ({n * dx:.4g} m: {n} particles across {what})")


def as_scene(scene):
    """The Scene of a scene or of its module (tisph.scenes.dam_break: its SCENE)."""
    if isinstance(scene, Scene):
        return scene
    found = getattr(scene, "SCENE", None)
    if isinstance(found, Scene):
        return found
    raise TypeError(f"not a scene: {scene!r} (a tisph.case.Scene, or a module with one as SCENE)")
