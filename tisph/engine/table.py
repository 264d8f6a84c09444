"""The parameter table: the runtime parameters (one struct on the device), the material table (one
field per material parameter) and the step's statistics, each composed from the core's
declarations and the enabled modules'.

The solver builds it and hands its fields to the step kernel, where the modules read them as
S.prm[None].name, S.mat.name[material] and S.stats[None].name. In Python scope (the run loop,
checkpoints, the run log) it is read and written through its methods: get, set, snapshot,
restore, describe."""

import dataclasses
import json
import types

import numpy as np
import taichi as ti

from ..hooks.module import MatParam, Param
from ..settings.engine_keys import KEYED
from .state import float_type, resolve

# Per-material parameters of the core: rest density, Tait B, and the viscosity (Newtonian mu,
# Bingham mu_B, Cross mu_inf).
CORE_MATERIAL = {
    "rho0": MatParam(None, "kg/m3", "rest density"),
    "B": MatParam(None, "Pa", "Tait stiffness B = rho0 c0^2 / gamma (paper 000 eq. 12)"),
    "viscosity": MatParam(0.0, "Pa s", "dynamic viscosity (Bingham mu_B, Cross mu_inf)", field="mu"),
}

# Runtime parameters of the core (one default each; the modules add theirs).
CORE_PARAMS = {
    "c0": Param(None, "m/s", (0.0, None), "numerical sound speed"),
    "g": Param((0.0, -9.81), "m/s2", (None, None), "gravity", vector=True),
    "cfl": KEYED["numerics.cfl"],
    "dt_max": KEYED["numerics.dt_max"],
    "band": KEYED["numerics.density_band"],
    "dt_floor": Param(1e-9, "s", (0.0, None), "a time step below this stops the run"),
    "dt": Param(0.0, "s", (0.0, None), "the current time step (set by the kernel)"),
}
# The names solver params dicts use where they differ from the field's.
PARAM_ALIASES = {"band": "density_band", "eps": "xsph"}

# The maxima the force pass raises for every case (the modules add theirs; stepper.py keeps them).
CORE_MAXIMA = {"amax2": "real", "mumax": "real", "rhodev": "real"}
CORE_STATS = dict(CORE_MAXIMA, bad_code="int", bad_idx="int", leaked="int")


@dataclasses.dataclass(frozen=True)
class Setup:
    """What a default computed from the case reads (a Param's or a MatParam's callable): the
    spacing, the kernel's h, the sound speed, the step's CFL, the materials and the particles."""

    dx: float
    h: float
    c0: float
    materials: list
    particles: object
    cfl: float = 0.0


@ti.data_oriented
class ParamTable:
    def __init__(self, modules, values, setup, real):
        """modules: the enabled modules; values: the case's params dict (dx, h, c0 and the
        modules' runtime parameters; a missing one takes its one default); setup: Setup; real:
        the float type. Creates the fields; write() fills them once every field of the solver
        exists (a field write between field creations would put each field in its own SNode
        tree, and Taichi's LLVM backends allow 512 of them)."""
        self.real = real
        self.np_real = float_type(real)
        self.decl, self.values = self._params(modules, values, setup)
        self.setup = dataclasses.replace(setup, cfl=float(self.values["cfl"]))  # the viscosity cap reads it
        self.mat = types.SimpleNamespace()
        self._mat_writes = self._materials(modules, self.setup)
        self.stat_decl = dict(CORE_STATS)
        for m in modules:
            self.stat_decl.update(m.stats)
            self.stat_decl.update(m.maxima)
        self.stats = ti.types.struct(**{k: resolve(t, real) for k, t in self.stat_decl.items()}).field(shape=())

    def _params(self, modules, values, setup):
        """The runtime parameter struct: every enabled module's Params, resolved from `values` or
        their one default. A default of 'dx' means the particle spacing; a callable takes
        (setup, values)."""
        decl = dict(CORE_PARAMS)
        for m in modules:
            decl.update(m.params)
        vec2 = ti.types.vector(2, self.real)
        self.prm = ti.types.struct(**{k: (vec2 if d.vector else self.real) for k, d in decl.items()}).field(shape=())
        resolved = {}
        for k, d in decl.items():
            v = values.get(PARAM_ALIASES.get(k, k), values.get(k, d.default))
            if isinstance(v, str) and v == "dx":
                v = setup.dx
            elif callable(v):
                v = v(setup, values)
            if v is None:
                raise ValueError(f"solver parameter {k!r} has no value and no default")
            resolved[k] = tuple(v) if d.vector else v
        return decl, resolved

    def _materials(self, modules, setup):
        """One field per material parameter (self.mat.<field>), with the values from the material
        dicts (or the one default; a MatParam's convert(value, mat, setup)) to write later."""
        decl = dict(CORE_MATERIAL)
        for m in modules:
            decl.update(m.material)
        writes = []
        for k, d in decl.items():
            f = ti.field(ti.i32 if d.kind == "int" else self.real, len(setup.materials))
            setattr(self.mat, d.field or k, f)
            vals = []
            for n, mat in enumerate(setup.materials):
                v = mat.get(k, d.default)
                if d.convert is not None:
                    v = d.convert(v, mat, setup)
                if v is None:
                    raise ValueError(f"material {mat.get('name', n)!r} lacks {k!r}")
                vals.append(v)
            writes.append((f, vals))
        return writes

    def write(self):
        """Fill the material table and the parameter struct (after every field was created)."""
        for f, vals in self._mat_writes:
            f.from_numpy(np.asarray(vals, dtype=np.int32 if f.dtype == ti.i32 else self.np_real))
        for k, v in self.values.items():
            setattr(self.prm[None], k, v)

    def has(self, name):
        return name in self.decl

    def has_stat(self, name):
        return name in self.stat_decl

    def get(self, name):
        """A runtime parameter's value on the device (a tuple for a vector)."""
        v = getattr(self.prm[None], name)
        return tuple(float(u) for u in v) if self.decl[name].vector else float(v)

    def set(self, name, value):
        """A runtime parameter's value, from Python scope (between steps)."""
        if name not in self.decl:
            raise KeyError(f"no runtime parameter {name!r} in this case (it has {sorted(self.decl)})")
        setattr(self.prm[None], name, tuple(value) if self.decl[name].vector else value)

    def snapshot(self):
        """Every runtime parameter as it stands, as JSON (what a checkpoint keeps: the runtime
        inputs, drive and paddle, not their defaults)."""
        return json.dumps({k: (list(self.get(k)) if d.vector else self.get(k)) for k, d in self.decl.items()})

    def restore(self, text):
        for k, v in json.loads(text).items():
            if k in self.decl:
                self.set(k, v)

    def describe(self):
        """Each runtime parameter as resolved, "name = value unit", for run.log."""

        def text(v):
            if isinstance(v, tuple):
                return "(" + ", ".join(f"{u:.4g}" for u in v) + ")"
            return f"{v:.4g}" if isinstance(v, float) else str(v)

        return ", ".join(
            f"{k} = {text(self.values[k])}" + (f" {d.unit}" if d.unit not in ("", "-") else "")
            for k, d in self.decl.items()
        )

    @ti.kernel
    def set_dt(self, dt: ti.f64):
        self.prm[None].dt = ti.cast(dt, self.real)

    @ti.kernel
    def set_drive(self, gx: ti.f64, gy: ti.f64):
        """A kernel: a third of the time of a Python-scope struct write."""
        self.prm[None].drive = ti.Vector([ti.cast(gx, self.real), ti.cast(gy, self.real)])
