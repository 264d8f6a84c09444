"""Particle state: the fields (struct of arrays), the material table and the runtime parameters,
each composed from the declarations of the enabled modules."""
import numpy as np
import taichi as ti

from ..hooks.module import MatParam, Param
from ..runtime import arch_name
from ..settings.engine_keys import KEYED


def types(real):
    """Names modules use for their slot types."""
    return {"real": real, "int": ti.i32, "vec2": ti.types.vector(2, real), "vec3": ti.types.vector(3, real),
            "mat2": ti.types.matrix(2, 2, real)}


def resolve(t, real):
    """A slot type: a name from types(), 'vecN', or a Taichi type."""
    if isinstance(t, str) and t.startswith("vec") and t[3:].isdigit():
        return ti.types.vector(int(t[3:]), real)
    return types(real)[t] if isinstance(t, str) else t


@ti.data_oriented
class ParticleFields:
    """Struct of arrays: one Taichi field per particle property.

    Separate fields rather than one ti.Struct field: the neighbour scan reads positions from a
    compact array, which measured 1.75x faster than an SOA struct field and 1.3x than AOS here.
    """

    def __init__(self, members, n):
        self.names = tuple(members)
        for k, dt in members.items():
            setattr(self, k, ti.field(dt, n) if not hasattr(dt, "n") else ti.Vector.field(dt.n, dt.dtype, n))


def on_cpu():
    return arch_name() in ("x64", "arm64")


def small_int():
    """The type of kind and mat: a byte on the CPU (6 bytes a particle less in each of its three
    copies); 32 bits on a GPU, where 8-bit storage is an optional Vulkan/Metal feature."""
    return ti.i8 if on_cpu() else ti.i32


def core_members(real):
    """The state every case has: what a step carries over, the reorder permutes, a checkpoint
    and the backup keep (p is kept for the snapshots)."""
    vec2 = ti.types.vector(2, real)
    return dict(x=vec2, v=vec2, a=vec2, rho=real, drho=real, m=real, kind=small_int(), mat=small_int(), id=ti.i32,
                p=real)


NP_TYPES = {ti.i8: np.int8, ti.u8: np.uint8, ti.i32: np.int32, ti.i64: np.int64, ti.f32: np.float32,
            ti.f64: np.float64}


def type_bytes(t):
    """Bytes of one value of a field member type (a scalar type or a vector of one)."""
    return getattr(t, "n", 1) * np.dtype(NP_TYPES[getattr(t, "dtype", t)]).itemsize


def np_dtype(field):
    """The NumPy dtype a field's from_numpy takes."""
    return NP_TYPES[field.dtype]


def eval_members(real):
    """The evaluation state, rebuilt from the state in every step's gather and read by the pair
    loop: only the sorted copy has it (16 bytes a particle less in the particles and the backup).
    ir = 1 / rhoe, set once per particle so the pair loop divides by no density."""
    return dict(ve=ti.types.vector(2, real), rhoe=real, ir=real)


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

CORE_MAXIMA = {"amax2": "real", "mumax": "real", "rhodev": "real"}
CORE_STATS = dict(CORE_MAXIMA, bad_code="int", bad_idx="int", leaked="int")


def material_table(S, modules, materials):
    """One field per material parameter, with the values from the material dicts (or the one
    default) to write once every field exists: a field write between field creations would
    put each field in its own SNode tree, and Taichi's LLVM backends allow 512 of them."""
    decl = dict(CORE_MATERIAL)
    for m in modules:
        decl.update(m.material)
    nmat = len(materials)
    writes = []
    for k, d in decl.items():
        f = ti.field(ti.i32 if d.kind == "int" else S.real, nmat)
        setattr(S, "mat_" + (d.field or k), f)
        vals = []
        for n, mat in enumerate(materials):
            v = mat.get(k, d.default)
            if d.convert is not None:
                v = d.convert(v, mat, S)
            if v is None:
                raise ValueError(f"material {mat.get('name', n)!r} lacks {k!r}")
            vals.append(v)
        writes.append((f, vals))
    return writes


def param_struct(S, modules, values, dx):
    """The runtime parameter struct: every enabled module's Params, resolved from `values` (the
    case's params dict) or their one default. A default of 'dx' means the particle spacing.
    Returns the declarations and the resolved values (written by write_params)."""
    decl = dict(CORE_PARAMS)
    for m in modules:
        decl.update(m.params)
    vec2 = ti.types.vector(2, S.real)
    S.prm = ti.types.struct(**{k: (vec2 if d.vector else S.real) for k, d in decl.items()}).field(shape=())
    resolved = {}
    for k, d in decl.items():
        v = values.get(PARAM_ALIASES.get(k, k), values.get(k, d.default))
        if isinstance(v, str) and v == "dx":
            v = dx
        elif callable(v):
            v = v(S, values)
        if v is None:
            raise ValueError(f"solver parameter {k!r} has no value and no default")
        resolved[k] = tuple(v) if d.vector else v
    return decl, resolved


def write_tables(S, material_writes, params):
    """Fill the material table and the parameter struct (after every field was created)."""
    for f, vals in material_writes:
        f.from_numpy(np.asarray(vals, dtype=np.int32 if f.dtype == ti.i32 else S.np_real))
    for k, v in params.items():
        setattr(S.prm[None], k, v)


def stats_struct(S, modules):
    decl = dict(CORE_STATS)
    for m in modules:
        decl.update(m.stats)
        decl.update(m.maxima)
    S.stats = ti.types.struct(**{k: resolve(t, S.real) for k, t in decl.items()}).field(shape=())
    return decl


def float_type(real):
    return np.float64 if real == ti.f64 else np.float32


def load_particles(p, particles, fp):
    """A ParticleSet's initial state into the fields p (fp: the float type); ids in order."""
    p.x.from_numpy(particles.x.astype(fp))
    p.v.from_numpy(particles.v.astype(fp))
    p.rho.from_numpy(particles.rho.astype(fp))
    p.m.from_numpy(particles.m.astype(fp))
    p.kind.from_numpy(particles.kind.astype(np_dtype(p.kind)))
    p.mat.from_numpy(particles.mat.astype(np_dtype(p.mat)))
    p.id.from_numpy(np.arange(len(particles), dtype=np.int32))
