"""The numerics schemes: each a full set of the [numerics] keys that make a scheme (the kernel and
its width, the walls, the viscous terms, the density diffusion, the drift corrections).

A scene's SCHEMA takes one with `numerics(NAME, dx=..., key=value)`; a key it sets beside dx is a
departure from the scheme, and the scene says why in its DEPARTS ({key: reason}; tests/engine/test_schemes.py
holds every scene to its scheme but for those). A user picks another with numerics.scheme in a
case file: the keys they leave unset then take that scheme's values (docs/engine.md).
"""

# waves, sloshing, impacts and sheets (docs/engine.md, docs/waves.md): Wendland h = 2.5 dx, walls
# that carry the water's pressure (Adami et al. 2012) with the Riemann guard of boundaries/walls.py,
# the water's own viscosity, renormalised density diffusion; alpha 0.1 only in a pair with a
# particle thinner-surrounded than a flat surface's top row (a sheet or a droplet: position
# divergence under 1.0, the top row's 1.15), which ring without it; the water's viscosity and the
# density diffusion evaluated every third acoustic step at most and held between (dual time
# stepping, physics/dual.py; docs/performance.md)
_DEFAULT = {
    "kernel": "wendland",
    "h_factor": 2.5,
    "wall": "adami",
    "wall_layers": 5,
    "laminar_viscosity": True,
    "density_diffusion": "antuono",
    "delta": 0.1,
    "artificial_viscosity": 0.0,
    "artificial_viscosity_surface": 0.1,
    "surface_divergence": 1.0,
    "xsph": 0.0,
    "shifting": 0.0,
    "time_stepping": "dual",
}
# what the presets share: dynamic walls, Fourtakas' diffusion, no drift correction, no surface alpha,
# every term every step (as their cases were calibrated and validated)
_DYNAMIC = dict(
    _DEFAULT,
    wall="dynamic",
    wall_layers=3,
    density_diffusion="fourtakas",
    artificial_viscosity_surface=0.0,
    surface_divergence=1.5,
    time_stepping="single",
)
# paper 002: Wendland (eq. 6) at h = 1.3 dx, laminar viscosity (eq. 10)
_PAPER002 = dict(_DYNAMIC, h_factor=1.3)
SCHEMES = {
    "default": _DEFAULT,
    # paper 000's Table 2 (h = 1.5 L0, XSPH 0.1) with alpha 0.02 and density diffusion: its dam
    # breaks on dry and wet beds and its hatch
    "paper000": dict(
        _DYNAMIC, kernel="cubic", h_factor=1.5, laminar_viscosity=False, artificial_viscosity=0.02, xsph=0.1
    ),
    "paper002": _PAPER002,
    # the numerics the sand bed's constants were calibrated with (docs/sediment.md): the tunnel's
    # and the beach's; a bed calibrated on one scheme is not carried to another untested. No
    # artificial viscosity: alpha h c0 / 8's Stokes layer is 1.6 dx at the tunnel's c0
    "bed": dict(_PAPER002, kernel="cubic"),
}
DEFAULT = "default"
SCHEME_KEYS = tuple(SCHEMES[DEFAULT])


def numerics(name, **values):
    """A scene's [numerics] defaults: scheme `name`'s keys, then the scene's own values."""
    return dict(SCHEMES[name], scheme=name, **values)


def apply_scheme(cfg, given):
    """A resolving step: a scheme the user named sets every scheme key they left unset. Returns
    ({dotted key: value}, run.log's note); nothing where the scheme was not named."""
    if "numerics.scheme" not in given:
        return {}, []
    name = cfg.numerics.scheme
    mine = [k for k in SCHEME_KEYS if f"numerics.{k}" in given]
    changes = {f"numerics.{k}": v for k, v in SCHEMES[name].items() if f"numerics.{k}" not in given}
    return changes, [f"numerics.scheme = {name!r}: its numerics" + (f", but {', '.join(mine)} as set" if mine else "")]
