"""Mutation check: break one piece of physics on purpose and see which tests fail.

    python -m tests.mutations                     # the list of mutations
    python -m tests.mutations NAME [PYTEST ARGS]  # run pytest with NAME applied (default: the quick
                                                  # subset without the golden hashes)
    python -m tests.mutations --all [--out F]     # every mutation, a table of what caught it

A mutation is applied by a pytest plugin before any test imports tisph's physics: a term's pure
function (tisph/terms) is replaced by its negative or by nothing, or a Python step is stubbed. A
test suite that guards the physics it names fails under each of them without the golden hashes.
"""

import inspect

import numpy as np

# name: (module, function, what: "negate" | "zero" | callable(module) that patches, what it breaks)
MUTATIONS = {
    "continuity": ("tisph.terms.continuity", "continuity", "negate", "the continuity equation's sign"),
    "pressure": ("tisph.terms.pressure", "pressure_accel", "negate", "the pressure gradient's sign"),
    "tait": ("tisph.terms.pressure", "tait", "zero", "the equation of state (no pressure)"),
    "artificial_viscosity": ("tisph.terms.viscosity", "artificial_viscosity", "negate", "Monaghan's viscosity's sign"),
    "laminar_viscosity": ("tisph.terms.viscosity", "laminar_viscosity", "zero", "the laminar viscosity"),
    "density_diffusion": ("tisph.terms.diffusion", "density_diffusion", "zero", "density diffusion"),
    "xsph": ("tisph.terms.xsph", "xsph", "zero", "XSPH"),
    "repulsive_wall": ("tisph.terms.repulsive", "lennard_jones", "zero", "the repulsive walls' force"),
    "bingham": ("tisph.terms.rheology", "bingham", "zero", "the Bingham viscosity"),
    "cross": ("tisph.terms.rheology", "cross", "zero", "the Cross viscosity"),
    "sps": ("tisph.terms.sps", "sps_accel", "zero", "the SPS stress's force"),
    "tke": ("tisph.terms.tke", "eddy_viscosity", "zero", "the k equation's eddy viscosity"),
    "drag": ("tisph.terms.drag", "drag_accel", "zero", "fluid-sediment drag"),
    "dem": ("tisph.terms.dem", "contact_force", "zero_first", "DEM contact forces"),
    "bed_frozen": (
        "tisph.sediment.bed",
        "Bed",
        lambda m: setattr(m.Bed, "step", lambda self, tau, dt, deposit=None: np.zeros_like(self.z)),
        "the bed-load bed never moves",
    ),
    "lee_vortex": (
        "tisph.sediment.lee",
        "lee_vortex_shear",
        lambda m: setattr(m, "lee_vortex_shear", lambda tau, *a, **k: tau),
        "the ripples' lee vortex",
    ),
    "vortex_throw": (
        "tisph.sediment.lee",
        "vortex_throw",
        lambda m: setattr(m, "vortex_throw", lambda zones, q, *a, **k: np.zeros(len(q))),
        "the lee vortex's throw over the crest",
    ),
    "shepard": (
        "tisph.physics.shepard",
        "Shepard",
        lambda m: setattr(m.Shepard, "after_step", lambda self, S: None),
        "the Shepard filter never runs",
    ),
    "bed_load": ("tisph.sediment.transport", "bedload_mpm", "zero_py", "Meyer-Peter & Mueller's bed load"),
    "wavemaker": ("tisph.waves.theory", "biesel_piston", "zero_py", "Biesel's piston transfer function"),
}


def _wrap(orig, how):
    """A ti.func with orig's signature returning -orig(...) or 0 * orig(...). Its source goes to a
    file of its own: Taichi compiles a function from its source text, which exec'd code lacks."""
    import importlib.util
    import os
    import tempfile

    import taichi as ti

    params = list(inspect.signature(orig).parameters)
    args = ", ".join(params)
    if how == "zero_first":  # a function that returns (force, state...): the force zeroed, the rest kept
        body = f"    out = _orig({args})\n    return 0.0 * out[0], out[1], out[2]\n"
    else:
        body = f"    return {'-' if how == 'negate' else '0.0 * '}_orig({args})\n"
    src = f"_orig = None\n\n\ndef mutated({args}):\n" + body
    path = os.path.join(tempfile.mkdtemp(prefix="tisph_mutation_"), f"mutated_{orig.__name__}.py")
    with open(path, "w") as f:
        f.write(src)
    spec = importlib.util.spec_from_file_location(f"mutated_{orig.__name__}", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    mod._orig = orig
    return ti.func(mod.mutated)


def apply(name):
    """Apply the mutation, in its module and in every module that imported the name already."""
    import importlib
    import sys

    modname, fname, how, _ = MUTATIONS[name]
    mod = importlib.import_module(modname)
    if callable(how):
        how(mod)
        return
    orig = getattr(mod, fname)
    if how == "zero_py":
        new = lambda *a, **k: 0.0 * np.asarray(orig(*a, **k))  # noqa: E731
    else:
        new = _wrap(orig, how)
    for m in list(sys.modules.values()):
        if m is not None and getattr(m, fname, None) is orig:
            setattr(m, fname, new)
