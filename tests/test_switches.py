"""Terms a scene does not use are compiled out and their fields never allocated."""
import numpy as np

from tisph.config import build_config, physics_from_config
from tisph.scenes import dam_break
from tisph.solver import Solver


def make(**ov):
    base = {"numerics.dx": 0.06}
    base.update(ov)
    cfg = build_config(dam_break.DEFAULTS, None, base)
    case = dam_break.build(cfg)
    return Solver(case.physics, case.particles, case.materials, case.domain, case.params)


def test_switched_off_terms_have_no_fields_and_change_the_result():
    off = make(**{"numerics.artificial_viscosity": 0.0, "numerics.xsph": 0.0,
                  "numerics.density_diffusion": "none", "numerics.laminar_viscosity": False})
    on = make(**{"numerics.artificial_viscosity": 0.1, "numerics.xsph": 0.3,
                 "numerics.density_diffusion": "fourtakas", "numerics.laminar_viscosity": True})
    assert off.physics.as_dict() == dict(kernel="cubic", wall="dynamic", artificial_viscosity=False,
                                         laminar_viscosity=False, xsph=False, density_diffusion="none",
                                         shepard=False, rheology=False, periodic_x=False, noslip=False,
                                         paddle="none", damping=(), sps=False, drag=False, dem=False, inflow=())
    for k in ("xs", "x0", "sps", "mu", "wn", "cid", "ces"):   # no field for a term that is off
        assert k not in off.members and not hasattr(off.p, k)
    assert not hasattr(off, "mat_drive")
    assert "xs" not in off.members and not hasattr(off.p, "xs") and not hasattr(off.tmp, "xs")
    for s in (off, on):   # a Newtonian scene allocates nothing for rheology
        assert "mu" not in s.members and not hasattr(s, "mat_rheo") and not hasattr(s, "mat_tau")
    assert "xs" in on.members and hasattr(on.p, "xs")
    for s in (off, on):
        for _ in range(300):
            s.step()
        assert s.check() is None
    a, b = off.state(), on.state()
    for k in ("x", "v", "rho", "p"):
        assert np.all(np.isfinite(a[k])) and np.all(np.isfinite(b[k]))
    assert np.abs(a["x"] - b["x"]).max() > 1e-5
    assert np.abs(a["rho"] - b["rho"]).max() > 1e-3


def test_physics_follows_config():
    cfg = build_config(dam_break.DEFAULTS, None, {"numerics.kernel": "wendland", "numerics.wall": "repulsive",
                                                  "numerics.shepard_every": 20})
    ph = physics_from_config(cfg)
    assert ph.kernel == "wendland" and ph.wall == "repulsive" and ph.shepard
    assert ph.artificial_viscosity and ph.density_diffusion == "fourtakas" and not ph.xsph


def test_shepard_and_wendland_run_finite():
    s = make(**{"numerics.kernel": "wendland", "numerics.shepard_every": 10, "numerics.h_factor": 1.5})
    for _ in range(100):
        s.step()
    assert s.check() is None
    st = s.state()
    fl = st["kind"] == 0
    assert np.all(np.isfinite(st["rho"])) and np.abs(st["rho"][fl] / 1000 - 1).max() < 0.05
