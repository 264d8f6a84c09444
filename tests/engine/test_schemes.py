"""The numerics schemes (tisph/settings/schemes.py): every scene on its scheme but for the departures it
names, a scheme named in a case file, and the extrapolated wall's guard against penetration."""

import numpy as np
import pytest

from tisph.registry import REGISTRY, load
from tisph.runner import resolve
from tisph.settings.schemes import SCHEME_KEYS, SCHEMES


@pytest.mark.parametrize("name", sorted(REGISTRY))
def test_every_scene_runs_its_scheme_but_where_it_says_why(name):
    scene = load(name)
    num = scene.DEFAULTS["numerics"]
    departs = scene.DEPARTS
    scheme = SCHEMES[num["scheme"]]
    for key in SCHEME_KEYS:
        if key in departs:
            assert num[key] != scheme[key], f"{name}: {key} is listed as a departure but is the scheme's"
            assert len(departs[key]) > 10
        else:
            assert num[key] == scheme[key], f"{name}: numerics.{key} = {num[key]!r}, its scheme's {scheme[key]!r}"


def test_the_waves_and_impacts_run_the_default_scheme():
    for name in ("dam_break", "tank", "flume", "custom"):
        assert load(name).DEFAULTS["numerics"]["scheme"] == "default"


def test_a_scheme_named_in_a_case_sets_the_keys_it_leaves_unset():
    from tisph.scenes import dam_break

    cfg = resolve(dam_break, {"numerics": {"scheme": "paper000", "h_factor": 1.3}})
    num = cfg["numerics"]
    assert num["kernel"] == "cubic" and num["wall"] == "dynamic" and num["xsph"] == 0.1
    assert num["h_factor"] == 1.3  # as set
    assert any("paper000" in n and "h_factor" in n for n in cfg.notes)
    default = resolve(dam_break)["numerics"]
    assert default["kernel"] == "wendland" and default["wall"] == "adami" and not resolve(dam_break).notes


def test_an_unknown_scheme_is_refused_with_the_choices():
    from tisph.scenes import dam_break
    from tisph.settings.config import ConfigError

    with pytest.raises(ConfigError, match="paper000"):
        resolve(dam_break, {"numerics": {"scheme": "fast"}})


def test_riemann_wall_pressure_grows_from_a_waves_to_the_water_hammer():
    """Zhang, Hu & Adams (2017): 2 rho c0 beta u_n with beta = min(6 u_n / c0, 1); none moving away."""
    import taichi as ti

    from tisph import runtime
    from tisph.terms.pressure import riemann_wall_pressure

    runtime.init("cpu", "f64")
    out = ti.field(ti.f64, shape=4)

    @ti.kernel
    def k(c0: ti.f64):
        n = ti.Vector([0.0, 1.0])  # the wall's normal, into the water
        for q in ti.static(range(4)):
            un = (-1.0, 0.1, 2.0, 10.0)[q]  # closing speed on the wall
            out[q] = riemann_wall_pressure(1000.0, c0, ti.Vector([0.3, -un]), n)

    k(20.0)
    got = out.to_numpy()
    want = [0.0, 2 * 1000 * 0.1 * 0.6, 2 * 1000 * 2.0 * 12.0, 2 * 1000 * 10.0 * 20.0]
    assert np.allclose(got, want, rtol=1e-9)
