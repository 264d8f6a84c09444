"""Physical plausibility: impossible cases are refused by name with the reason (and a units guess),
cases beyond what the model resolves are warned about at the start and their spoiled metric is
null, not a number."""

import math

import pytest

from tisph.measure.gauge_sets import WaveGauges
from tisph.runner import resolve
from tisph.runner.setup import build_case
from tisph.scenes import beach, flume, tunnel
from tisph.settings.config import ConfigError
from tisph.waves import theory as wm


def refused(scene, ov, key, *words):
    with pytest.raises(ConfigError) as e:
        resolve(scene, None, ov)
    msg = str(e.value)
    assert e.value.field == key, msg
    for w in words:
        assert w in msg, msg
    return msg


def warned(scene, ov, *words):
    case = build_case(scene, resolve(scene, None, ov), lambda *a, **k: None)
    hits = [w for w in case.warnings if all(x in w for x in words)]
    assert hits, case.warnings
    return case


CM = {"numerics.dx": 2.0, "geometry.depth": 40.0, "geometry.wall_height": 60.0, "paddle.stroke": 4.03}


def test_a_flume_written_in_centimetres_or_millimetres_is_refused_with_that_guess():
    refused(flume, CM, "paddle.stroke", "Miche", "centimetres", "depth = 40, dx = 2")
    mm = {"numerics.dx": 20.0, "geometry.depth": 400.0, "geometry.wall_height": 600.0, "paddle.stroke": 40.3}
    refused(flume, mm, "paddle.stroke", "millimetres")
    # only the stroke in centimetres: beyond the depth, with no units guess for metres elsewhere
    msg = refused(flume, {"paddle.stroke": 4.0}, "paddle.stroke", "at most the depth")
    assert "centimetres" not in msg


def test_waves_steeper_than_miche_are_refused_on_the_key_that_set_them():
    refused(flume, {"paddle.stroke": 0.2, "paddle.period": 0.5}, "paddle.stroke", "Miche", "H / L")
    refused(flume, {"paddle.wave_height": 0.1, "paddle.period": 0.5}, "paddle.wave_height", "Miche")
    # a steep but possible wave passes: H / L = 0.1 against 0.142 tanh(kh)
    _, k, L, _, r = wm.linear_wave(resolve(flume, None, {"paddle.wave_height": 0.1, "paddle.period": 0.9}), 0.25)
    assert 0.142 * math.tanh(k * 0.25) > 0.1 / L


def test_a_wavelength_the_kernel_cannot_carry_is_refused():
    refused(
        flume,
        {
            "numerics.dx": 0.01,
            "numerics.h_factor": 3.0,
            "numerics.kernel": "wendland",
            "numerics.wall_layers": 6,
            "paddle.period": 0.4,
            "paddle.stroke": 0.01,
        },
        "numerics.dx",
        "a tenth of the wavelength",
    )


def test_water_in_grams_per_cubic_centimetre_is_refused():
    refused(flume, {"materials.water.rho0": 1.0}, "materials.water.rho0", "g/cm3")
    refused(tunnel, {"materials.water.rho0": 100.0}, "materials.water.rho0", "between 900")


def test_too_short_a_run_says_the_end_time_its_gauges_need():
    case = warned(flume, {"run.end_time": 5.0}, "run.end_time = 5 s", "needs at least 3", "gives them")
    need = [w for w in case.warnings if "gives them" in w][0]
    t = float(need.split("run.end_time = ")[-1].split(" s gives")[0])
    cfg = resolve(flume, None, {"run.end_time": t})
    assert not [w for w in build_case(flume, cfg, lambda *a, **k: None).warnings if "gives them" in w]


def test_a_wave_under_three_spacings_and_a_nonlinear_wave_are_warned_about():
    warned(flume, {"paddle.stroke": 0.015, "numerics.dx": 0.0125}, "dx: under 3 dx")
    warned(
        flume,
        {"paddle.period": 3.0, "paddle.stroke": 0.1, "geometry.length": 30.0, "geometry.damping_length": 8.0},
        "Ursell",
    )


def test_gauges_on_dry_land_are_warned_about_and_report_no_height():
    ov = {
        "geometry.slope": 15.0,
        "geometry.depth": 0.25,
        "paddle.stroke": 0.2,
        "geometry.length": 8.0,
        "geometry.toe_x": 1.5,
        "geometry.gauges_x": [1.0, 3.0, 4.5, 5.5, 6.5],
        "numerics.dx": 0.03,
    }
    case = warned(beach, ov, "x = 5.5, 6.5 m stand on dry land", "5.25")
    g = WaveGauges([1.0, 6.0], 0.02, 0.026, 0.3, dry_from=5.25)
    import numpy as np

    t = np.linspace(0, 20, 2001)
    c = {"t": t, "eta_x1.00": 0.05 * np.sin(2 * np.pi * t / 2.5), "eta_x6.00": np.zeros_like(t)}
    m = g.metrics(c, {"ramp_periods": 1.0, "period": 2.5}, 1.5)
    assert m["wave_height_at_gauges"][1] is None and m["wave_height_at_gauges"][0] == pytest.approx(0.1, rel=0.02)
    assert m["gauges_on_dry_land"] == [6.0]
    assert case is not None


def test_a_wave_height_is_named_as_written_with_the_centimetre_guess():
    """A height the user gave is what the message names (not the stroke derived from it, with its
    round-off), and a height in centimetres is guessed as such."""
    from tisph.settings.config import ConfigError

    with pytest.raises(ConfigError) as e:
        resolve(flume, None, {"paddle.wave_height": 5.0})
    assert e.value.field == "paddle.wave_height" and "looks like centimetres" in str(e.value)
    assert "0.05 m here" in str(e.value)
    with pytest.raises(ConfigError) as e:
        resolve(flume, None, {"paddle.wave_height": 0.005, "paddle.period": 0.5, "numerics.dx": 0.025})
    assert e.value.field == "paddle.wave_height" and e.value.value == 0.005
    assert "0.00251 m" in str(e.value) and "0.0025100" not in str(e.value)


def test_a_custom_case_is_warned_as_the_flume_is(tmp_path):
    """The custom case's gauges and waves get the flume's and the beach's warnings, from the same
    place: a wave under 3 dx, a gauge on dry land, a window after the end, too few wave periods."""
    from tisph.runner import simulate
    from tisph.scenes import custom

    case = tmp_path / "c.toml"
    case.write_text("""
[numerics]
dx = 0.03
[run]
end_time = 0.3
[domain]
box = [-0.4, 6.5, 0.0, 0.8]
[[solid]]
line = [[-0.4, 0.8], [-0.4, 0.0], [4.0, 0.0], [6.5, 0.5], [6.5, 0.8]]
[[water]]
level = 0.3
[paddle]
type = "piston"
wave_height = 0.05
period = 1.2
[[gauge]]
type = "surface"
x = 2.0
[[gauge]]
type = "surface"
x = 6.3
from_time = 1.0
""")
    simulate(
        custom,
        {"run.max_steps": 1, "output.render": False, "output.quiet": True, "output.snapshot_every": 0.0},
        out=str(tmp_path / "out"),
        config=str(case),
    )
    said = (tmp_path / "out" / "run.log").read_text()  # the run logs its set-up's warnings
    assert "surface2 (x = 6.3 m) stand on dry land" in said
    assert "from_time = 1 s) start their statistics at or after run.end_time" in said
    assert "the wave height 0.05 m is 1.7 dx" in said
    assert "wave periods at the gauge at x = 2 m" in said
