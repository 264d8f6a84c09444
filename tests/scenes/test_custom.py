"""Custom cases (python -m tisph.scenes.custom): the geometry, the checks a case file gets, the
dam break written as a custom case against the built-in scene, and the example cases at a coarse dx."""

import os
import warnings

import numpy as np
import pytest

from tisph.geometry import Polygon, Polyline, crossings, lattice, read_profile
from tisph.io import read_csv
from tisph.scenes import custom

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TANK = """
[numerics]
dx = 0.05
[domain]
box = [0.0, 2.0, 0.0, 2.0]
[[solid]]
label = "tank"
line = [[0.0, 2.0], [0.0, 0.0], [2.0, 0.0], [2.0, 2.0]]
"""
WATER = """
[[water]]
level = 0.5
"""


def run_cli(tmp_path, text, *flags):
    path = tmp_path / "case.toml"
    path.write_text(text)
    return custom.main(["--config", str(path), "--out", str(tmp_path / "out"), "--no-render", "--quiet", *flags])


def refused(tmp_path, capsys, text):
    assert run_cli(tmp_path, text, "--end-time", "0.01") == 2
    return capsys.readouterr().err


def test_polyline_sides_and_band():
    bed = Polyline([[0.0, 0.0], [1.0, 0.0], [2.0, 0.5]])
    p = np.array([[0.5, -0.1], [0.5, 0.1], [1.8, 0.3], [1.8, 0.5], [-0.5, -0.01], [3.0, 0.9]])
    # below the walk from left to right is solid, also beyond the ends (the end segments as rays)
    assert bed.inside(p).tolist() == [True, False, True, False, True, True]
    pts = lattice(-0.2, 2.2, -0.3, 0.8, 0.05)
    band = bed.band(pts, 0.15)
    assert band.any()
    assert np.all(bed.distance(pts[band]) < 0.15 * 1.5)  # mitred joint: at most a bit beyond the thickness
    assert not band[pts[:, 0] < 0].any() and not band[pts[:, 0] > 2.0 + 0.15].any()  # square ends


def test_tank_line_gives_the_dam_break_walls():
    from tisph.particles import block

    dx, T = 0.025, 0.075
    pts = lattice(-0.2, 4.2, -0.2, 4.2, dx)
    tank = Polyline([[0.0, 4.0], [0.0, 0.0], [4.0, 0.0], [4.0, 4.0]])
    got = pts[tank.band(pts, T)]
    want = np.vstack([block(-T, -T, 4 + T, 0.0, dx), block(-T, 0.0, 0.0, 4.0, dx), block(4.0, 0.0, 4 + T, 4.0, dx)])
    key = lambda a: set(map(tuple, np.round(a / dx * 2).astype(int)))  # noqa: E731
    assert key(got) == key(want)


def test_crossing_and_profile(tmp_path):
    assert crossings([[0, 0], [1, 1], [1, 0], [0, 1]], True)
    assert not crossings([[0, 0], [1, 0], [1, 1], [0, 1]], True)
    f = tmp_path / "p.csv"
    f.write_text("x,z\n2,0.3\n0,0.1\n1,0.2\n")
    assert read_profile(f).tolist() == [[0, 0.1], [1, 0.2], [2, 0.3]]
    f.write_text("x,z\n0,0.1\n0,0.2\n")
    with pytest.raises(ValueError, match="same x"):
        read_profile(f)
    assert Polygon([[0, 0], [1, 0], [1, 1], [0, 1]]).inside(np.array([[0.5, 0.5], [1.5, 0.5]])).tolist() == [
        True,
        False,
    ]


@pytest.mark.parametrize(
    "text, expect",
    [
        (TANK + WATER.replace("level = 0.5", "level = 0.5\nvelocty = [0.0, 0.0]"), "did you mean 'velocity'"),
        (TANK + "[[solid]]\npolygon = [[0.5, 0.5], [1.0, 1.0], [1.0, 0.5], [0.5, 1.0]]\n" + WATER, "solid[1].polygon"),
        (TANK + "[[solid]]\nbox = [0.5, 0.52, 0.1, 1.0]\n" + WATER, "two particle spacings thick"),
        (TANK + "[[solid]]\nbox = [0.5, 1.0, 0.1, 1.0]\ncircle = [1, 1, 0.2]\n" + WATER, "exactly one of"),
        (
            TANK
            + "[[solid]]\nbox = [0.8, 1.2, 0.0, 0.3]\n[[water]]\npolygon = [[0.2, 0.0], [1.0, 0.0], [1.0, 0.5], [0.2, 0.5]]\n",
            "overlap a solid",
        ),
        (TANK.replace("[2.0, 0.0], [2.0, 2.0]", "[2.0, 0.0]") + WATER, "nothing holds it at the domain's right edge"),
        (TANK + WATER + "[[gauge]]\nx = 3.0\n", "gauge[0].x"),
        (TANK + WATER + "[[gauge]]\ntype = \"pressure\"\nx = 1.0\n", "gauge[0].z"),
        (TANK + WATER + "[[gauge]]\ntype = \"pressur\"\nx = 1.0\n", "one of 'surface'"),
        (TANK + WATER + "[paddle]\ntype = \"piston\"\nx = 2.5\n", "paddle.x"),
        (TANK + "[[solid]]\ncsv = \"missing.csv\"\n" + WATER, "solid[1].csv"),
        (TANK + "[[water]]\nlevel = 0.04\n", "two particle spacings"),
    ],
)
def test_bad_case_files_are_refused(tmp_path, capsys, text, expect):
    err = refused(tmp_path, capsys, text)
    assert expect in err, err
    assert "Traceback" not in err


def test_every_error_at_once(tmp_path, capsys):
    err = refused(tmp_path, capsys, TANK + "[[water]]\nlevl = 0.5\n[[gauge]]\ntype = \"x\"\nx = 1.0\n")
    assert "water[0].levl" in err and "gauge[0].type" in err


def test_key_errors_and_the_cases_own_checks_together(tmp_path, capsys):
    """A typo, a string dx and a gauge outside the box in one file: all three, not the first two."""
    text = TANK.replace("dx = 0.05", 'dx = "0.05"') + "[run]\nend_tme = 1.0\n" + WATER + "[[gauge]]\nx = 3.0\n"
    err = refused(tmp_path, capsys, text)
    assert "run.end_tme" in err and "numerics.dx = '0.05'" in err and "gauge[0].x = 3.0" in err, err


def test_a_gauge_on_dry_land_reads_nothing_not_a_sentinel(tmp_path):
    """A surface gauge over the dry part of a slope: no reading (null eta_max and eta_min in the
    metrics), not the surface search's floor of -1e9."""
    import json

    text = """
[numerics]
dx = 0.05
[domain]
box = [0.0, 2.0, 0.0, 1.0]
[[solid]]
line = [[0.0, 1.0], [0.0, 0.0], [1.2, 0.0], [2.0, 0.8], [2.0, 1.0]]
[[water]]
level = 0.3
[[gauge]]
label = "dry"
x = 1.9
"""
    assert run_cli(tmp_path, text, "--end-time", "0.02") == 0
    m = json.loads((tmp_path / "out" / "summary.json").read_text())["metrics"]
    assert m["dry_eta_max"] is None and m["dry_eta_min"] is None


BLOCK = TANK + WATER + "[[solid]]\nlabel = \"block\"\nbox = [1.4, 1.6, 0.0, 0.3]\n"


def test_gauges_are_checked_against_the_geometry(tmp_path, capsys):
    """A pressure point inside a solid and a force line in open water are refused, each naming the
    solid and the fix, together; the same line on the block's face runs."""
    text = BLOCK + (
        '[[gauge]]\ntype = "pressure"\nx = 1.5\nz = 0.1\n[[gauge]]\ntype = "force"\nline = [[1.2, 0.0], [1.2, 0.3]]\n'
    )
    err = refused(tmp_path, capsys, text)
    assert "gauge[0].x = 1.5" in err and "inside solid[1] ('block')" in err, err
    assert "gauge[1].line" in err and "off the nearest solid's face, solid[1] ('block')" in err, err
    ok = BLOCK + '[[gauge]]\ntype = "force"\nline = [[1.4, 0.0], [1.4, 0.3]]\n'
    assert run_cli(tmp_path, ok, "--end-time", "0.01") == 0


def test_a_pressure_gauge_that_stays_dry_has_null_metrics(tmp_path):
    import json

    text = TANK + WATER + '[[gauge]]\ntype = "pressure"\nx = 1.0\nz = 1.5\nlabel = "air"\n'
    assert run_cli(tmp_path, text, "--end-time", "0.02") == 0
    m = json.loads((tmp_path / "out" / "summary.json").read_text())["metrics"]
    assert m["air_max"] is None and m["air_time_of_max"] is None and m["air_mean"] is None


def test_a_level_the_lattice_rounds_is_said_with_the_dx_that_keeps_it(tmp_path):
    text = TANK.replace("dx = 0.05", "dx = 0.03") + WATER.replace("level = 0.5", "level = 0.4")
    with pytest.warns(
        UserWarning,
        match=r"water\[0\]\.level = 0\.4 m fills whole rows of particles up to 0\.39 m.*"
        r"numerics\.dx = 0\.02857 m \(14 rows",
    ):
        custom.SCENE.build(custom_cfg(tmp_path, text))
    with warnings.catch_warnings():  # 0.5 at dx 0.05: kept, nothing said
        warnings.filterwarnings("error", message=".*fills whole rows.*")
        custom.SCENE.build(custom_cfg(tmp_path, TANK + WATER))


def test_a_paddle_at_the_boxs_edge_is_told_where_its_room_ends(tmp_path, capsys):
    """A box starting at the paddle's face: the paddle's room is what is refused (not the water at
    the edge), in numbers that add up: face - travel - plate - wall layers = the box's start."""
    text = (
        "[numerics]\ndx = 0.03\n[domain]\nbox = [0.0, 6.0, 0.0, 0.8]\n[[solid]]\n"
        "line = [[0.0, 0.8], [0.0, 0.0], [6.0, 0.0], [6.0, 0.8]]\n[[water]]\nlevel = 0.42\n"
        '[paddle]\ntype = "piston"\nx = 0.0\nwave_height = 0.04\nperiod = 2.0\n'
    )
    err = refused(tmp_path, capsys, text)
    assert "paddle.x = 0.0" in err and "nothing holds it" not in err, err
    import re

    travel, plate = (float(v) for v in re.search(r"its travel \(([\d.]+) m\) and plate \(([\d.]+) m", err).groups())
    start = float(re.search(r"or domain.box starting at x = (-[\d.]+) m", err).group(1))
    assert abs(-travel - 2 * plate - start) < 2e-4, err


def custom_cfg(tmp_path, text):
    from tisph.runner import resolve

    path = tmp_path / "level.toml"
    path.write_text(text)
    return resolve(custom, str(path), {"output.quiet": True})


def test_water_past_the_box_is_named_as_such(tmp_path, capsys):
    err = refused(tmp_path, capsys, TANK + "[[water]]\npolygon = [[0, 0], [3, 0], [3, 0.5], [0, 0.5]]\n")
    assert "corners inside domain.box" in err and "(3, 0) m lies outside it" in err, err


def test_dam_break_as_custom_case_matches_the_builtin(tmp_path):
    """At dx = 0.025 (4 m and 2 m are whole numbers of spacings) the custom case puts every particle
    where the built-in scene does, and the run agrees to round-off."""
    from tisph.runner import simulate
    from tisph.scenes import dam_break

    ov = {"numerics.dx": 0.025, "run.end_time": 0.18, "output.render": False, "output.quiet": True}
    a = simulate(custom, ov, out=str(tmp_path / "custom"), config=os.path.join(ROOT, "scenes", "dam_break_custom.toml"))
    b = simulate(dam_break, ov, out=str(tmp_path / "builtin"))
    assert a["particles"] == b["particles"] and a["steps"] == b["steps"]
    pa, pb = read_csv(tmp_path / "custom" / "probes.csv")[1], read_csv(tmp_path / "builtin" / "probes.csv")[1]
    assert max(pa["front_surge"]) > 1.3  # the front has moved almost a third of a column width
    assert np.abs(np.array(pa["front_surge"]) - np.array(pb["front_x"])).max() < 1e-5


def _coarse(tmp_path, name, **ov):
    from tisph.runner import simulate

    ov = dict({"output.render": False, "output.quiet": True}, **ov)
    return simulate(custom, ov, out=str(tmp_path / name), config=os.path.join(ROOT, "scenes", f"{name}.toml"))


@pytest.mark.slow
@pytest.mark.long
def test_seawall_reads_hydrostatic_at_rest_then_wave_loads(tmp_path):
    # dx 0.02: the 0.1 m of water at the wall spans the default kernel's 2 h = 0.1 m (at 0.03 the
    # pressure point's kernel is cut by the bed, the surface and the wall at once)
    s = _coarse(tmp_path, "seawall", **{"numerics.dx": 0.02, "run.end_time": 6.8})
    assert s["status"] == "ok"
    c = read_csv(tmp_path / "seawall" / "probes.csv")[1]
    t = np.array(c["t"])
    rest = (t > 0.2) & (t < 1.0)  # the paddle's ramp has sent nothing to the wall yet
    for lab, z in (("p_mid", 0.25),):  # (p_low, 0.01 m over the bed, is dry at this dx: its kernel is cut twice)
        p = np.array(c[f"p_{lab}"])[rest].mean()
        assert abs(p - 1000 * 9.81 * (0.3 - z)) < 0.15 * 1000 * 9.81 * (0.3 - z), (lab, p)
    F = np.array(c["F_wall_force"])[rest].mean()
    d = 0.3 - 0.2
    assert abs(F - 0.5 * 1000 * 9.81 * d * d) < 0.2 * 0.5 * 1000 * 9.81 * d * d, F
    m = s["metrics"]
    assert m["wall_force_max"] > 1.5 * F  # the waves load the wall beyond the still water's force
    assert m["offshore_wave_height"] > 0.05  # a 0.12 m wave at the paddle still 0.05 m high at 1.5 m


@pytest.mark.slow
@pytest.mark.long
def test_breakwater_separates_the_incident_wave_and_measures_the_overtopping(tmp_path):
    s = _coarse(tmp_path, "breakwater", **{"numerics.dx": 0.03, "run.end_time": 9.0})
    assert s["status"] == "ok" and s["mass"]["mass_balance_error"] < 1e-9
    m = s["metrics"]
    # a smooth 1:2 slope reflects a good part of a wave (Seelig & Ahrens: Kr about 0.4-0.6 here)
    assert 0.15 < m["overtopping_reflection_coefficient"] < 0.8
    assert 0.02 < m["overtopping_eurotop_wave_height"] < 0.1 and m["overtopping_eurotop_discharge"] > 0
    assert m["overtopping_freeboard"] == pytest.approx(0.28 - 0.25, abs=0.026)  # level to within a row
    # the discharge is the basin's volume over the window, and the volume never falls
    V = np.array(read_csv(tmp_path / "breakwater" / "probes.csv")[1]["V_overtopping"])
    assert np.all(np.diff(V) >= -1e-12) and m["overtopping_volume_end"] == pytest.approx(V[-1])


@pytest.mark.slow
def test_surveyed_beach_bed_moves_and_keeps_its_sand(tmp_path):
    s = _coarse(tmp_path, "surveyed_beach", **{"numerics.dx": 0.04, "run.end_time": 6.0})
    assert s["status"] == "ok"
    m = s["metrics"]
    assert m["sand_volume_error"] < 1e-12
    assert m["bed_change_rms"] > 1e-5 and m["bed_deposition_max"] > 0 and m["bed_erosion_max"] > 0
    rows = (tmp_path / "surveyed_beach" / "bed_profile.csv").read_text().splitlines()
    assert len(rows) > 10 and (tmp_path / "surveyed_beach" / "bed_profile.png").exists()


def test_a_new_gauge_type_is_one_class(tmp_path, monkeypatch):
    """A gauge type is one Gauge subclass in GAUGE_TYPES (tisph/measure/gauges.py): the case file
    names it, its keys are checked, and its column and metric reach probes.csv and summary.json."""
    from tisph.measure import gauges
    from tisph.particles import FLUID

    class DepthGauge(gauges.Gauge):
        """The water above the floor at x: the highest fluid particle within half a spacing of x."""

        type = "depth"
        needs = {"x": "a number (m): a depth gauge's position"}
        prefixes = ("d",)
        panel = ("depth (m)", 1.0)

        def __init__(self, label, x, from_time=0.0):
            super().__init__(label, from_time)
            self.x = float(x)

        def read(self, st, site):
            x = st["x"][st["kind"] == FLUID]
            near = x[np.abs(x[:, 0] - self.x) < 0.5 * site.dx]
            return [float(near[:, 1].max()) if len(near) else 0.0]

        def metrics(self, c, t, w, period):
            return {f"{self.label}_mean": float(np.mean(np.asarray(c[f"d_{self.label}"])[w]))}

    monkeypatch.setitem(gauges.GAUGE_TYPES, "depth", DepthGauge)
    case = TANK + WATER + '[[gauge]]\ntype = "depth"\nlabel = "mid"\nx = 1.0\n'
    assert run_cli(tmp_path, case, "--max-steps", "3") == 0
    cols = read_csv(tmp_path / "out" / "probes.csv")[1]
    assert 0.45 < cols["d_mid"][0] < 0.5
    import json

    m = json.load(open(tmp_path / "out" / "summary.json"))["metrics"]
    assert m["mid_mean"] == pytest.approx(np.mean(cols["d_mid"]))
    assert run_cli(tmp_path, TANK + WATER + '[[gauge]]\ntype = "depth"\n', "--max-steps", "3") == 2  # no x


def test_harmonic_amplitudes_of_a_record_and_a_panel_a_gauge(tmp_path):
    """The first three harmonics of a record at the paddle's period, null under two periods; the
    gauges figure draws one panel a gauge."""
    import math

    from tisph.measure.gauge_sets import GaugeSet
    from tisph.measure.gauges import SurfaceGauge, harmonic_amplitudes

    T = 2.0
    t = np.arange(0.0, 20.0, 0.01)
    eta = 0.02 * np.cos(2 * math.pi * t / T) + 0.005 * np.sin(4 * math.pi * t / T + 0.3) + 0.001
    h = harmonic_amplitudes("g", t, eta, T, 0.0)
    assert h["g_harmonic_1"] == pytest.approx(0.02, rel=1e-6) and h["g_harmonic_2"] == pytest.approx(0.005, rel=1e-6)
    assert h["g_harmonic_3"] == pytest.approx(0.0, abs=1e-9)
    assert harmonic_amplitudes("g", t, eta, T, 17.0)["g_harmonic_1"] is None  # 1.5 periods left
    heights = []
    for n in (1, 4):
        gs = GaugeSet([SurfaceGauge(f"s{k}", 1.0 + k) for k in range(n)], 0.02, 0.05)
        m = gs.metrics({"t": t, **{f"eta_s{k}": eta for k in range(n)}}, T)
        assert m["s0_harmonic_1"] == pytest.approx(0.02, rel=1e-6)
        gs.plot(str(tmp_path / f"g{n}.png"), "case: gauges")
        import imageio.v2 as imageio

        heights.append(imageio.imread(tmp_path / f"g{n}.png").shape[0])
    assert heights[1] > 2 * heights[0]


def test_an_irregular_sea_gets_hm0_and_tp_at_each_surface_gauge():
    """With paddle.spectrum a surface gauge reports Hm0 and Tp from its spectrum, not a regular
    wave's height and harmonics: a synthetic sea of Hm0 0.1 m peaked at 2 s reads back."""
    import math

    from tisph.scenes.custom.gauges import CaseGauges

    spec = {
        "type": "surface",
        "label": "a",
        "x": 1.0,
        "z": None,
        "line": None,
        "from_time": 0.0,
        "name": "gauge[0]",
        "index": 0,
        "crest": None,
        "cot_slope": 0.0,
        "toe_gauges": [],
    }
    cg = CaseGauges([spec], 0.02, 0.05, 9.81, lambda p: p * 0, lambda x: 0.5, band=(0.25, 1.0))
    t = np.arange(0.0, 400.0, 0.05)
    rng = np.random.default_rng(0)
    fs = np.linspace(0.3, 0.9, 60)
    amp = np.exp(-(((fs - 0.5) / 0.08) ** 2))
    amp *= 0.1 / (4 * np.sqrt((amp**2 / 2).sum()))
    eta = sum(a * np.cos(2 * math.pi * f * t + rng.uniform(0, 2 * math.pi)) for a, f in zip(amp, fs))
    m = cg.metrics({"t": t, "eta_a": eta}, 2.0, 0.5)
    assert m["a_hm0"] == pytest.approx(0.1, rel=0.05) and m["a_tp"] == pytest.approx(2.0, rel=0.02)
    assert "a_wave_height" not in m and "a_harmonic_1" not in m


def test_a_load_record_is_low_passed_beside_its_raw_peaks():
    """A force or pressure gauge reports the extremes of its record low-passed at the case's
    cutoff (half the water's lowest acoustic mode) beside the raw ones: acoustic ringing at 20 Hz
    on a 1 Hz load lifts the raw peak 12 %, the filtered one reads the load's own; a step (an
    impact's rise) overshoots by at most 4 %; a point dry part of the time (a surge reaches it)
    is filtered with its dry samples at 0 Pa, and one dry throughout gives nulls, not NaN."""
    from tisph.measure.gauge_sets import GaugeSet
    from tisph.measure.gauges import PressureGauge
    from tisph.measure.records import low_pass
    from tisph.scenes.custom.gauges import load_cutoff

    cutoff = load_cutoff(10 * np.sqrt(9.81 * 0.4), 0.4)
    assert cutoff == pytest.approx(1.25 * np.sqrt(9.81 / 0.4))
    t = np.arange(0.0, 10.0, 0.01)
    load = 4000 + 1000 * np.sin(2 * np.pi * t)
    ring = 110 * np.sin(2 * np.pi * 20 * t) + 30 * np.sin(2 * np.pi * 23 * t + 1)
    gs = GaugeSet([PressureGauge("wall", 1.0, 0.1)], 0.02, 0.05, cutoff)
    m = gs.metrics({"t": t, "p_wall": load + ring}, 1.0)
    assert m["wall_max"] > 5100 and m["wall_filtered_max"] == pytest.approx(5000, rel=1e-3)
    assert m["wall_filtered_min"] == pytest.approx(3000, rel=2e-3) and m["wall_filter_hz"] == cutoff
    assert abs(m["wall_filtered_time_of_max"] % 1.0 - 0.25) < 0.02
    step = low_pass(t, np.where(t > 5, 1.0, 0.0), cutoff)
    assert 1.0 < step.max() < 1.04 and step[t > 6].mean() == pytest.approx(1.0, abs=1e-3)
    wet_late = np.where(t < 4, np.nan, load)
    late = gs.metrics({"t": t, "p_wall": wet_late + ring}, 1.0)
    assert late["wall_filtered_max"] == pytest.approx(5000, rel=2e-3) and late["wall_filtered_time_of_max"] > 4
    assert late["wall_filtered_min"] < 100 and late["wall_max"] > 5100
    (y,) = [gs.gauges[0].filtered({"t": t, "p_wall": wet_late})]
    assert np.isfinite(y).all() and abs(y[t < 3.5]).max() < 1.0
    dry = gs.metrics({"t": t, "p_wall": np.full(len(t), np.nan)}, 1.0)
    assert dry["wall_filtered_max"] is None and dry["wall_max"] is None and "wall_filter_hz" in dry


def test_surface_gauges_named_as_an_array_split_the_incident_and_reflected_waves(tmp_path, capsys):
    """Surface gauges given one `array` name report the incident and reflected heights and the
    reflection coefficient at the paddle's frequency (Mansard & Funke): a synthetic partial
    standing wave of 4 cm incident and 1 cm reflected reads back from three gauges and from two;
    an array of one gauge, or on a pressure gauge, is refused by name."""
    import math

    from tisph.scenes.custom.gauges import CaseGauges
    from tisph.waves.theory import wavenumber

    T, d = 1.2, 0.4
    k, w = wavenumber(2 * math.pi / T, d, 9.81), 2 * math.pi / T
    t = np.arange(0.0, 30.0, 0.01)
    xs = (2.0, 2.17, 2.41)
    base = {
        "type": "surface",
        "z": None,
        "line": None,
        "from_time": 5.0,
        "index": 0,
        "crest": None,
        "cot_slope": 0.0,
        "toe_gauges": [],
    }
    for labels in (("a", "b", "c"), ("a", "b")):
        specs = [
            dict(base, label=lab, x=x, name=f"gauge[{i}]", array="front") for i, (lab, x) in enumerate(zip(labels, xs))
        ]
        cg = CaseGauges(specs, 0.02, 0.05, 9.81, lambda p: p * 0, lambda x: d)
        eta = {
            f"eta_{q['label']}": 0.02 * np.cos(k * q["x"] - w * t) + 0.005 * np.cos(k * q["x"] + w * t + 0.7)
            for q in specs
        }
        m = cg.metrics({"t": t, **eta}, T, d)
        assert m["front_incident_height"] == pytest.approx(0.04, rel=1e-3), labels
        assert m["front_reflected_height"] == pytest.approx(0.01, rel=1e-2)
        assert m["front_reflection_coefficient"] == pytest.approx(0.25, rel=1e-2)
    one = TANK + WATER + '[[gauge]]\nx = 1.0\narray = "front"\n'
    assert "gauge[0].array = 'front'" in refused(tmp_path, capsys, one)
    wrong = TANK + WATER + '[[gauge]]\ntype = "pressure"\nx = 1.0\nz = 0.1\narray = "front"\n'
    assert "gauge[0].array = 'front'" in refused(tmp_path, capsys, wrong)


def test_a_case_file_names_its_movie_and_frames(tmp_path):
    """The movie, the frames' title and the gauges figure are the case file's name, not the
    scene's (custom); a scene run from its defaults keeps its own."""
    from tisph.runner import resolve
    from tisph.runner.loop import run_title

    path = tmp_path / "my_tank.toml"
    path.write_text(TANK + WATER)
    cfg = resolve(custom, str(path))
    assert run_title(cfg, "custom") == "my_tank" and custom.run_title(cfg, "renders/x") == "my_tank: gauges"
    from tisph.scenes import dam_break

    assert run_title(resolve(dam_break), "dam_break") == "dam_break"
