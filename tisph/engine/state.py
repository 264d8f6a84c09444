"""Particle state: the fields (struct of arrays) composed from the declarations of the enabled
modules, their types and their initial values (the material table and the runtime parameters are
table.py's)."""

import numpy as np
import taichi as ti

from ..runtime import arch_name


def types(real):
    """Names modules use for their slot types."""
    return {
        "real": real,
        "int": ti.i32,
        "bits": ti.i32 if real == ti.f32 else ti.i64,  # a non-negative float's bits (terms/order.py)
        "vec2": ti.types.vector(2, real),
        "vec3": ti.types.vector(3, real),
        "mat2": ti.types.matrix(2, 2, real),
    }


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
    return dict(
        x=vec2, v=vec2, a=vec2, rho=real, drho=real, m=real, kind=small_int(), mat=small_int(), id=ti.i32, p=real
    )


NP_TYPES = {ti.i8: np.int8, ti.u8: np.uint8, ti.i32: np.int32, ti.i64: np.int64, ti.f32: np.float32, ti.f64: np.float64}


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
