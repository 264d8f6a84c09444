"""The benchmark's own code paths, in seconds: one tiny case, tiny scaling, no peer, no timing checks."""

import csv
import json
import math
import os

import numpy as np
import pytest

from tisph.bench import cli
from tisph.bench import ladder as bench

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.mark.slow
def test_bench_dry_run(tmp_path):
    assert cli.main(["--dry-run", "--out", str(tmp_path)]) == 0
    with open(tmp_path / "bench.csv") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == [
        "case",
        "dx",
        "particles",
        "steps",
        "sim_time",
        "wall_time_s",
        "compile_time_s",
        "step_time_s",
        "particle_steps_per_s",
        "metric",
        "error",
        "status",
    ]
    assert len(rows) == 2 and all(r["status"] == "ok" for r in rows)
    # the ladder's first case as configured: a 0.4 m tank to 0.2 s at dx 0.05 and 0.04 (8 and 10
    # rows, five wall layers), whose particle and step counts are fixed, and whose pressure error
    # falls as dx does (the default kernel reaches five rows: 7 % at 8 rows, 3.9 % at 10)
    assert [int(r["particles"]) for r in rows] == [320, 400] and [int(r["steps"]) for r in rows] == [200, 200]
    err = [float(r["error"]) for r in rows]
    assert 0 < err[1] < err[0] and err[1] < 0.05, err
    assert "| hydrostatic tank | rho g d below the top two rows |" in (tmp_path / "bench.md").read_text()
    md = (tmp_path / "bench.md").read_text()
    for part in ("## Run time against error", "Observed convergence order", "## Scaling", "## Specialisation"):
        assert part in md
    with open(tmp_path / "scaling.csv") as f:
        sc = list(csv.DictReader(f))
    assert float(sc[0]["field_bytes_per_particle"]) > 50


def test_convergence_order():
    assert bench.convergence_order([0.04, 0.02, 0.01], [0.4, 0.1, 0.025]) == __import__("pytest").approx(2.0)
    assert math.isnan(bench.convergence_order([0.04], [0.1]))


def test_speed_bench_refuses_an_unknown_revision_by_name(tmp_path):
    """--speed --against REV checks REV out into a worktree first: a name git does not know is
    refused before anything runs, naming it."""
    import pytest

    with pytest.raises(SystemExit) as e:
        cli.main(["--speed", "--against", "no-such-rev-xyz", "--out", str(tmp_path)])
    assert "no-such-rev-xyz" in str(e.value)


def test_speed_measures_a_known_case_in_a_fresh_process_and_reports_its_ratio():
    """--speed's measurement runs this tree in a fresh process: the dam break at dx 0.08 has 1100
    particles (its five wall layers included), runs the 20 steps asked, and its rate is the particles times the steps over the
    time; the report gives the ratio against another revision's rate."""
    import argparse

    from tisph.bench import speed

    m = speed.measure(speed.ROOT, "dam_break", {"numerics.dx": 0.08}, 20)
    assert m["particles"] == 1100 and m["steps"] == 20 and m["arch"] == "x64"
    assert m["pps"] == pytest.approx(1100 * 20 / m["seconds"], rel=1e-9) and 50 < m["field_bytes"] < 1000
    a = argparse.Namespace(against="abc123", repeats=1)
    rows = [
        dict(
            case="dam break dx 0.08",
            particles=m["particles"],
            steps=20,
            pps=m["pps"],
            field_bytes=m["field_bytes"],
            pps_against=m["pps"] / 2,
            ratio=2.0,
            arch=m["arch"],
        )
    ]
    text = "\n".join(speed.report(a, rows, 1.3, 0.5))
    assert "| dam break dx 0.08 | 1100 | 20 |" in text and "| 2.00 |" in text
    assert "cold 1.30 s" in text and "warm 0.50 s" in text


def test_wake_spectrum_finds_a_shedding_frequency_and_not_in_noise():
    """tisph/bench/shedding.py: a 1.4 Hz oscillation sampled every 0.05 s for 3 s, with noise, gives
    its frequency (within the spectrum's 1/3 Hz resolution), its amplitude / sqrt(2) and most of
    the power; noise alone spreads its power over the spectrum."""
    import numpy as np

    from tisph.bench.shedding import wake_spectrum

    rng = np.random.default_rng(3)
    t = np.arange(1.0, 4.0, 0.05)
    std, f, share = wake_spectrum(t, 0.2 + 0.06 * np.sin(2 * np.pi * 1.4 * t) + 0.005 * rng.standard_normal(len(t)))
    assert abs(f - 1.4) <= 1.0 / 3.0 / 2 + 1e-9
    assert abs(std - 0.06 / np.sqrt(2)) < 0.006
    assert share > 0.5
    std, f, share = wake_spectrum(t, 0.01 * rng.standard_normal(len(t)))
    assert share < 0.3
    assert all(np.isnan(wake_spectrum(t[:5], t[:5])))


def test_live_bed_windows_split_the_series_from_the_bed_start():
    """--shedding --live-bed: 2 s windows from the bed's start; a last piece under half a window
    joins the one before, every sample after the start lands in exactly one window."""
    import numpy as np

    from tisph.bench.shedding import windows

    t = np.round(np.arange(0.0, 8.31, 0.05), 10)
    v = np.stack([t, -t], axis=1)
    w = windows(t, v, 0.5)
    assert [(a, round(b, 2)) for a, b, _ in w] == [(0.5, 2.5), (2.5, 4.5), (4.5, 6.5), (6.5, 8.3)]
    assert sum(len(x) for _, _, x in w) == int(np.sum(t >= 0.5))
    assert w[0][2][0, 0] == 0.5 and w[0][2][-1, 0] < 2.5 and w[-1][2][-1, 0] == 8.3
    m = t <= 7.3
    assert [(a, round(b, 2)) for a, b, _ in windows(t[m], v[m], 0.5)] == [(0.5, 2.5), (2.5, 4.5), (4.5, 7.3)]


@pytest.mark.slow
@pytest.mark.long
def test_shedding_bench_dry_run(tmp_path):
    """--shedding --dry-run: the whole path (the fixed-bed run, the snapshots read and deleted,
    the table) on a tiny case in seconds, from a case file given with --config (Mao's with the
    omega length)."""
    src = open(os.path.join(ROOT, "scenes", "pipeline_scour_mao.toml")).read()
    assert 'turbulence = "k_equation"\n' in src
    cfg = tmp_path / "mao_omega.toml"
    cfg.write_text(src.replace('turbulence = "k_equation"\n', 'turbulence = "k_equation"\nlength_scale = "omega"\n', 1))
    assert cli.main(["--shedding", "--dry-run", "--out", str(tmp_path), "--config", str(cfg)]) == 0
    md = (tmp_path / "shedding.md").read_text()
    assert "| 2 | 0.006 |" in md and "mao_omega.toml" in md
    assert "length_scale = \"omega\"" in (tmp_path / "runs" / "shedding_gap2" / "run.log").read_text()
    rows = (tmp_path / "shedding.csv").read_text().splitlines()
    assert len(rows) == 2 and rows[0].startswith("gap_over_D")
    assert not (tmp_path / "runs" / "shedding_gap2" / "snapshots").exists()
    assert cli.main(["--shedding", "--live-bed", "--dry-run", "--out", str(tmp_path / "live")]) == 0
    md = (tmp_path / "live" / "shedding.md").read_text()
    assert "The wake over a scouring bed" in md and "| 0.5-0.8 |" in md and "scheme paper002" in md
    assert not (tmp_path / "live" / "runs" / "shedding_live_bed" / "snapshots").exists()
    with pytest.raises(SystemExit):
        cli.main(["--live-bed"])
    with pytest.raises(SystemExit):
        cli.main(["--gaps", "1.0"])
    with pytest.raises(SystemExit):
        cli.main(["--config", str(cfg)])


@pytest.mark.slow
def test_mao_held_bench_dry_run(tmp_path):
    """--mao-held --dry-run: Mao's 18 s bed is the run's initial bed (geometry.initial_profile)
    and stays put; the run writes the bed shear at every probe; the report has the rates by region
    beside Mao's, with the wake's verdict; the snapshots it was read from are gone; the figure is
    written."""
    from tisph.io import read_station_rows
    from tisph.validation import mao

    assert cli.main(["--mao-held", "--dry-run", "--out", str(tmp_path)]) == 0
    run = tmp_path / "runs" / "mao_held_18s"
    summary = json.loads((run / "summary.json").read_text())
    assert summary["metrics"]["mao_time_offset"] == 18.0  # his clock starts at his bed's time
    t, x, beds = read_station_rows(run / "scour_profile.csv")
    header = [(run / f).read_text().splitlines()[0] for f in ("scour_profile.csv", "bed_shear.csv")]
    assert header[0] == header[1]
    z0, z1 = beds[0], beds[-1]
    xc = 0.5 * 1.25  # the case file's 25 D, the pipe in the middle
    hs = float(np.median(z0[np.abs(x - xc) > 8 * mao.D]))
    assert np.abs(z0 - hs - mao.profile_bed(18.0, x - xc)).max() < 1e-6
    assert np.array_equal(z0, z1) and len(t) > 2  # held still
    md = (tmp_path / "mao_held.md").read_text()
    for region in ("upstream", "hole", "lee", "dune"):
        assert f"| 18 s | {region} (" in md
    assert "| wake sheds (St; v std m/s) |" in md and not (run / "snapshots").exists()
    rows = (tmp_path / "mao_held.csv").read_text().splitlines()
    assert rows[0].startswith("t_mao,x_over_D") and len(rows) == 1 + 17
    assert (tmp_path / "mao_held.png").stat().st_size > 10000
    with pytest.raises(SystemExit):
        cli.main(["--times", "18"])
    with pytest.raises(SystemExit):
        cli.main(["--mao-held", "--times", "12"])


def test_mao_held_rate_is_exner_of_the_bed_model():
    """The held bed's rate is the case's bed model's Exner rate: none under a uniform shear on a
    periodic flat bed, erosion where the shear rises along the current and deposition where it
    falls, and the sand it moves is conserved."""
    from tisph.bench.mao_held import exner_rate
    from tisph.sediment import keys

    sed = dict(
        keys.DEFAULTS,
        shear="wall_function",
        lee_transit=True,
        settling_delay=True,
        deposition_length=0.3,
        gravity_coefficient=0.0,
    )
    st = (np.arange(400) + 0.5) * 0.0025
    z = np.full(len(st), 0.075)
    flat = exner_rate(sed, st, z, [np.full(len(st), 2.0)] * 3, 0.00036, 2650.0, 1000.0)
    assert np.abs(flat).max() < 1e-12
    tau = 2.0 + 2.0 * np.exp(-(((st - 0.5) / 0.05) ** 2))
    r = exner_rate(sed, st, z, [tau] * 3, 0.00036, 2650.0, 1000.0)
    assert r[np.argmin(np.abs(st - 0.45))] < 0 < r[np.argmin(np.abs(st - 0.6))]
    assert abs(r.sum()) < 1e-9 * np.abs(r).sum()


def test_shedding_verdict_needs_a_peak_at_a_strouhal_number():
    """A wake sheds when a peak at St 0.1-0.4 holds 30 % of the power and v varies by 5 % of U;
    a strong peak at St 0.05 (the wake's drift) does not count."""
    from tisph.bench.shedding import verdict

    U, D = 0.35, 0.05
    assert verdict([0.05, 0.07], [1.64, 1.64], [0.75, 0.8], U, D) == (1, True)
    assert verdict([0.01, 0.019], [0.33, 0.33], [0.33, 0.2], U, D) == (0, False)  # drift
    assert verdict([0.011, 0.019], [1.31, 0.33], [0.54, 0.6], U, D) == (0, True)  # the band's peak decides
    assert verdict([0.005, 0.008], [1.4, 1.4], [0.9, 0.9], U, D)[1] is False  # too weak


def _validate(tmp_path, *only):
    readme = tmp_path / "README.md"
    readme.write_text("# x\n<!-- validation:start -->\nold\n<!-- validation:end -->\nafter\n")
    args = [
        "--validate",
        "--quick",
        "--docs",
        str(tmp_path / "docs"),
        "--readme",
        str(readme),
        "--out",
        str(tmp_path / "runs"),
    ]
    assert cli.main(args + (["--only", *only] if only else [])) == 0
    return (tmp_path / "docs" / "validation.md").read_text(), readme.read_text()


def test_validate_quick_one_case_writes_its_row_figure_and_cost(tmp_path):
    """--validate on the tank alone: its row with particles and steps from the run, its figure and
    the cost figure; --only leaves the README's table alone."""
    md, readme = _validate(tmp_path, "tank")
    row = next(line for line in md.splitlines() if line.startswith("| Still water in a tank |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[5] == "0.05" and int(cells[6]) == 340 and int(cells[7]) > 100
    assert float(cells[4]) < 0.1  # the pressure error of a still tank
    assert cells[3] == "one spacing: no GCI"  # a quick run has one spacing
    assert (tmp_path / "docs" / "validation" / "still_water_in_a_tank.png").stat().st_size > 5000
    assert (tmp_path / "docs" / "validation" / "cost.png").exists()
    assert "A quick run" in md and "old" in readme


def test_validate_jobs_runs_side_by_side_with_the_serial_values(tmp_path):
    """--jobs 2: the table's runs in two worker processes of one thread each give the values and
    steps of the same runs one after another, and the page says how they ran."""
    import json

    from tisph.runner.pool import plan, stages

    assert plan(0, 10, cores=2) == (2, 1) and plan(0, 1, cores=8) == (1, 8) and plan(3, 10, cores=8) == (3, 2)
    # a run of 20,000 particles or more alone on every core first, the rest side by side
    assert stages(["a", "b", "c"], [50000, 100, 0], 0, cores=2) == [(["a"], 1, 2), (["b", "c"], 2, 1)]
    assert stages(["a", "b"], [50000, 100], 1, cores=2) == [(["a", "b"], 1, 2)]
    (tmp_path / "serial").mkdir()
    _validate(tmp_path / "serial", "tank")
    common = ["--validate", "--quick", "--readme", "", "--only", "tank", "hatch"]
    assert cli.main(common + ["--jobs", "2", "--docs", str(tmp_path / "par"), "--out", str(tmp_path / "runs2")]) == 0
    rows = {
        d: json.loads(
            (tmp_path / d / "docs" / "validation" / "results.json").read_text()
            if d == "serial"
            else (tmp_path / d / "validation" / "results.json").read_text()
        )
        for d in ("serial", "par")
    }
    tank = [rows[d]["Still water in a tank"]["rows"][0] for d in ("serial", "par")]
    assert tank[0]["value"] == tank[1]["value"] and tank[0]["steps"] == tank[1]["steps"]
    assert tank[1]["threads"] == 1 and tank[1]["jobs"] == 2
    assert rows["par"]["Hatch (paper 000 section 4.1)"]["rows"][0]["status"] == "ok"
    assert "2 runs side by side on 1 CPU thread each" in (tmp_path / "par" / "validation.md").read_text()


def test_a_stale_taichi_cache_lock_is_cleared_and_a_fresh_one_kept(tmp_path):
    """A Taichi cache lock left by a killed process (older than a minute) is removed under tisph's
    guard, so later runs write their cache again; a fresh one (a live writer) is left alone."""
    import os

    from tisph.runtime import clear_stale_lock

    old, new = tmp_path / "old.lock", tmp_path / "new.lock"
    old.write_text("")
    new.write_text("")
    os.utime(old, (0, 0))
    clear_stale_lock(str(old))
    clear_stale_lock(str(new))
    assert not old.exists() and new.exists()


@pytest.mark.slow
@pytest.mark.long
def test_validate_quick_runs_every_case(tmp_path):
    """--validate --quick runs every validation case, writes a row and a figure for each and fills
    the README's table between its markers."""
    from tisph.bench.validate import CASES, slug

    md, readme = _validate(tmp_path)
    for c in CASES:
        assert f"| {c.name} |" in md, c.name
        assert (tmp_path / "docs" / "validation" / f"{slug(c.name)}.png").exists(), c.name
        assert f"| {c.name} |" in readme
    assert "old" not in readme and readme.endswith("after\n")
    assert "failed" not in md


def test_ripple_sweep_cases_and_dry_run(tmp_path):
    """--ripples: at least 8 cases with ripples over mobility 20-180 and d0 0.15-0.6 m, T 1.5-3.5 s,
    two above 240, each periodic length holding at least six predicted ripples, each run 200 bed
    periods (a seeded bed 300), the faster beds at a lower morfac; the seeded runs of the
    calibration case, and its resolution pair at twice the length; --dry-run runs the whole path
    through the Dask sweep and writes the table, the CSV and both figures."""
    from tisph.bench import ripple_sweep as rb

    cases = rb.cases()
    rip = [ov for _, kind, ov in cases if kind in ("check", "calibration")]
    psi = [rb.mobility(ov["geometry.orbital_diameter"], ov["geometry.period"]) for ov in rip]
    assert len(rip) >= 8 and min(psi) <= 21 and 160 <= max(psi) <= 180
    assert sum(kind == "sheet" for _, kind, _ in cases) == 2
    assert all(
        rb.mobility(ov["geometry.orbital_diameter"], ov["geometry.period"]) > 240
        for _, kind, ov in cases
        if kind == "sheet"
    )
    for _, kind, ov in cases:
        lam = rb.wiberg_harris(ov["geometry.orbital_diameter"], rb.GRAIN)[0]
        assert ov["geometry.length"] >= 6 * lam
        # 200 bed periods, at a morfac that turns the bed over no faster than the default tunnel's
        periods = rb.SEEDED_BED_PERIODS if kind == "seeded" else rb.BED_PERIODS
        assert ov["run.end_time"] * ov["sediment.morfac"] / ov["geometry.period"] == pytest.approx(periods, rel=1e-3)
        assert ov["sediment.morfac"] <= rb.MORFAC
    assert [ov["sediment.morfac"] for _, _, ov in cases if ov["geometry.orbital_diameter"] == 0.4] == [5.9, 4.2, 4.2]
    # seeded at 1.5 d0 at two more orbital diameters, each over sand its seed fits in (sand_depth - 2 dx)
    long_seeds = [
        ov
        for _, kind, ov in cases
        if kind == "seeded" and ov["geometry.seed_ripple_length"] > ov["geometry.orbital_diameter"]
    ]
    assert sorted(ov["geometry.orbital_diameter"] for ov in long_seeds) == [0.3, 0.4, 0.5]
    assert all(
        ov["geometry.seed_ripple_height"] <= ov["geometry.sand_depth"] - 2 * ov["numerics.dx"] for ov in long_seeds
    )
    assert {k for _, k, _ in cases} == {"calibration", "check", "sheet", "seeded", "resolution"}
    pair = [ov for _, kind, ov in cases if kind == "resolution"]
    assert len(pair) == 2 and pair[0]["geometry.length"] >= 12 * rb.wiberg_harris(0.3, rb.GRAIN)[0]
    assert pair[1]["numerics.dx"] == pytest.approx(pair[0]["numerics.dx"] / 1.5, rel=1e-4)
    assert {k: v for k, v in pair[0].items() if k != "numerics.dx"} == {
        k: v for k, v in pair[1].items() if k != "numerics.dx"
    }
    assert rb.held_bed_periods(np.array([0.0, 1.0, 2.0, 3.0]), np.array([0.3, 0.2, 0.2, 0.2]), 1.0, 10.0) == 20.0
    # in the band (d0 = 0.3: 0.15-0.225 m) from t = 1 on, two lengths in it taking turns
    t, lam = np.arange(6.0), np.array([0.3, 0.2, 0.17, 0.2, 0.17, 0.2])
    assert rb.held_bed_periods(t, lam, 1.0, 10.0, 0.3) == 40.0 and rb.held_bed_periods(t, lam, 1.0, 10.0) == 0.0
    assert cli.main(["--ripples", "--dry-run", "--out", str(tmp_path)]) == 0
    for f in ("ripples.md", "ripples.csv", "ripples.png", "growth.png"):
        assert (tmp_path / "ripples" / f).stat().st_size > 100


def test_peers_are_a_comma_separated_list_of_known_codes(capsys):
    assert cli._peers("pysph,dualsphysics") == ("pysph", "dualsphysics")
    with pytest.raises(SystemExit) as e:
        cli.main(["--speed", "--peer", "pysph,dualsph"])
    assert e.value.code == 2
    assert "'pysph,dualsph': peers are pysph, dualsphysics" in capsys.readouterr().err


def test_peers_benches_left_out_of_an_install_say_where_they_are(monkeypatch, capsys):
    """The wheel leaves tisph/bench/peers/ out (pyproject.toml): --waves and --peer then exit 2
    saying where the peers' benches come from, not with an ImportError."""
    from tisph.bench import common

    def missing(name):
        raise ModuleNotFoundError(f"No module named {name!r}", name=name)

    monkeypatch.setattr(common.importlib, "import_module", missing)
    with pytest.raises(SystemExit) as e:
        cli.main(["--waves", "--quick"])
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert "tisph/bench/peers/" in err and "a clone of tisph's source (pip install -e .)" in err


def test_dualsphysics_case_and_its_csv_are_read(tmp_path):
    from tisph.bench.peers import dualsphysics

    xml = (
        '<definition dp="0.01" units_comment="m"><special><gauges/></special>'
        '<parameter key="TimeMax" value="2.0" /><parameter key="TimeOut" value="0.01" />'
        '<coefsound value="20" comment="" />'
    )
    s = dualsphysics.case_xml(xml, 0.015, 0.3, 0.02, coefsound=14.14)
    assert 'dp="0.015"' in s and 'key="TimeMax" value="0.3"' in s and 'key="TimeOut" value="0.02"' in s
    assert "<special>" not in s and '<coefsound value="14.14"' in s
    with pytest.raises(dualsphysics.NotAvailable, match="TimeOut"):
        dualsphysics.case_xml(xml.replace("TimeOut", "Tout"), 0.015, 0.3, 0.02)
    # PartVTK's CSV at two times: the front is the rightmost fluid within 2 dp of the floor + dp / 2
    rows = {0: [(0.005, 0.005), (0.995, 0.005), (0.5, 1.0)], 1: [(0.005, 0.005), (1.4, 0.015), (2.0, 0.5)]}
    for k, pts in rows.items():
        body = "".join(f"  {x:.7E};  0.0000000E+00;  {z:.7E};\n" for x, z in pts)
        (tmp_path / f"PartFluid_{k:04d}.csv").write_text(
            f"TimeStep [s];Np;Nbound\n{0.1 * k};3;10\n\nPos.x [m];Pos.y [m];Pos.z [m];\n{body}"
        )
    (tmp_path / "PartFluid_Info.csv").write_text("not a time")
    t, front = dualsphysics._fronts(str(tmp_path), 0.01)
    assert list(t) == [0.0, 0.1]
    assert front == pytest.approx([1.0, 1.405])
    with pytest.raises(dualsphysics.NotAvailable, match="--dualsphysics"):
        dualsphysics.ensure(str(tmp_path / "cache"), None, print)


def test_time_to_the_same_error_takes_tisphs_quickest_run_as_good_as_each_peer_run(tmp_path):
    from tisph.bench.peers import dambreak_codes

    t = np.linspace(0.0, 0.7, 71)

    def row(code, dx, rms, wall, speed=4.0):
        return dict(code=code, dx=dx, tf=0.7, rms=rms, wall_s=wall, loop_s=wall / 2, t=t, front=1.0 + speed * t)

    rows = [
        row("tisph", 0.06, 0.12, 4.0, speed=3.0),
        row("tisph", 0.03, 0.19, 8.0, speed=3.9),
        row("tisph", 0.015, 0.17, 20.0, speed=4.0),
        row("peer", 0.03, 0.26, 9.0, speed=4.2),  # tisph's 0.06 run is better against the experiment
        row("peer", 0.015, 0.11, 60.0, speed=4.2),  # better than every tisph run
    ]
    pairs = dambreak_codes.time_to_error(rows)
    assert [(p["dx"], o and o["dx"]) for p, o in pairs] == [(0.03, 0.06), (0.015, None)]
    md = "\n".join(dambreak_codes._time_to_error_md(rows))
    assert "| peer, dp 0.03 | 0.260 | 9.0 (4.5) | dp 0.06: 0.120 | 4.0 (2.0) | 2.2 | 2.2 |" in md
    assert "| peer, dp 0.015 | 0.110 | 60.0 (30.0) | none of tisph's runs | - | - | - |" in md
    # the converged front: the mean of the two codes at dp 0.015 (speed 4.1), while it is at most 3.5 a
    finest, spread = dambreak_codes.converged(rows)
    assert [r["code"] for r in finest] == ["tisph", "peer"]
    grid = np.linspace(0.0, 0.7, 141)  # converged()'s
    keep = grid[1.0 + 4.1 * grid <= 3.5]
    assert rows[2]["conv"] == pytest.approx(np.sqrt(np.mean((0.1 * keep) ** 2)), rel=1e-9)
    assert rows[2]["conv"] == pytest.approx(rows[4]["conv"]) == pytest.approx(spread)
    assert rows[0]["conv"] > rows[1]["conv"] > rows[2]["conv"]  # the slow front is the furthest off
    # against it the peer's dp 0.03 run (0.1 t off) is matched only by tisph's finest
    assert [(p["dx"], o and o["dx"]) for p, o in dambreak_codes.time_to_error(rows, "conv")] == [
        (0.03, 0.015),
        (0.015, 0.015),
    ]
    dambreak_codes.figure(rows, str(tmp_path / "f.png"))
    assert (tmp_path / "f.png").stat().st_size > 10_000


def test_peer_ladder_runs_both_peers_over_five_spacings_and_writes_its_page(tmp_path, monkeypatch):
    """--speed --peer-ladder runs only the peers' dam breaks (not the engine's speed cases) over
    the ladder, both peers unless --peer names some, into OUT/dambreak_codes.md."""
    from tisph.bench.peers import dambreak_codes

    seen = {}

    def compare(out, log, peers, venv, dsph, runs):
        seen.update(peers=peers, runs=runs)
        return ["## stub"]

    monkeypatch.setattr(dambreak_codes, "compare", compare)
    assert cli.main(["--speed", "--peer-ladder", "--out", str(tmp_path)]) == 0
    assert seen == {"peers": ("pysph", "dualsphysics"), "runs": dambreak_codes.LADDER}
    assert [dx for dx, _ in dambreak_codes.LADDER] == [0.06, 0.04, 0.03, 0.02, 0.015]
    assert "## stub" in (tmp_path / "dambreak_codes.md").read_text()
    assert not (tmp_path / "speed.md").exists()
    cli.main(["--speed", "--peer-ladder", "--peer", "dualsphysics", "--out", str(tmp_path)])
    assert seen["peers"] == ("dualsphysics",)


@pytest.mark.slow
def test_speed_bench_on_gpu_falls_back_to_the_cpu_with_a_warning(tmp_path):
    import subprocess
    import sys

    from tests.runner.test_cli import NO_GPU  # the GPU backends hidden, so it falls back on any machine

    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "tisph.bench",
            "--speed",
            "--arch",
            "gpu",
            "--sizes",
            "3000",
            "--quick",
            "--repeats",
            "1",
            "--out",
            str(tmp_path),
        ],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=600,
        env=dict(os.environ, **NO_GPU),
    )
    assert r.returncode == 0, r.stderr[-2000:]
    assert "warning: --arch gpu: Taichi found no GPU" in r.stderr
    md = (tmp_path / "speed.md").read_text()
    assert "Taichi arch x64" in md
    # --sizes: the dam break and the flume at about the particles asked (the GPU check's cases)
    rows = [line for line in md.splitlines() if line.startswith(("| dam break 3e+03", "| flume 3e+03"))]
    assert len(rows) == 2, md
    for row in rows:
        n = int(row.split("|")[2])
        assert 0.7 * 3000 < n < 1.3 * 3000, row


def test_waves_bench_builds_dualsphysics_flume_and_reads_its_gauges(tmp_path):
    """The DualSPHysics flume is the default flume: its gauges at ours (their x measured from the
    piston's face, half a spacing out), Biesel's height for its piston, water to the depth on the
    lattice, c0 as asked; the SWL records go through the flume scene's window and height."""
    import xml.etree.ElementTree as ET

    from tisph.bench.peers import flume_codes as waves

    f = waves.flume_setup(0.0125)
    xml, info = waves.flume_xml(0.0125, 9.6, f, waves.MATCHED)
    root = ET.fromstring(xml)
    xs = [float(g.find("point0").get("x")) for g in root.iter("swl")]
    assert xs == pytest.approx([x + 0.00625 for x in f["gauges"]], abs=1e-5)
    assert float(root.find(".//piston/waveheight").get("value")) == pytest.approx(f["height"], rel=1e-5)
    assert float(root.find(".//piston/depth").get("value")) == pytest.approx(0.25)
    assert float(root.find(".//speedsound").get("value")) == pytest.approx(10 * math.sqrt(9.81 * 0.25), rel=1e-5)
    assert info["h"] == pytest.approx(2.5 * 0.0125)
    fill = root.find(".//fillbox")
    assert float(fill.find("size").get("z")) == pytest.approx(0.25 + 0.0125)  # its border row stays empty
    assert float(root.find(".//damping/dampingzone/limitmin").get("x")) == pytest.approx(4.5125 - 1.2)
    # 0.02 does not divide 0.25: both codes hold round(12.5) = 12 rows
    assert waves.flume_xml(0.02, 1.0, waves.flume_setup(0.02), waves.OWN)[1]["depth"] == pytest.approx(0.24)
    # gauge records: a wave of 0.9 Biesel arriving on the group velocity, a still level of 0.27 m
    t = np.arange(0.0, 9.6, 0.01)
    recs = []
    for x in f["gauges"]:
        t0 = waves.arrival_time(f["paddle"], x, f["cg"]) - f["period"]
        eta = np.where(t > t0, 0.45 * f["height"] * np.sin(2 * math.pi * (t - t0) / f["period"]), 0.0)
        recs.append((t, 0.27 + eta))
    H, err = waves.heights(f, recs)
    assert pytest.approx([0.9 * f["height"]] * 3, rel=0.01) == H
    assert err == pytest.approx([0.1] * 3, abs=0.01)
    lines = ["time [s];swlx [m];swly [m];swlz [m]"] + [f"{a:.6f};1;0;{b:.6f}" for a, b in zip(*recs[0])]
    (tmp_path / "GaugesSWL_g0.csv").write_text("\n".join(lines) + "\n")
    ((tt, zz),) = waves._swl(str(tmp_path), ["g0"])
    assert zz == pytest.approx(recs[0][1], abs=1e-6) and tt[-1] == pytest.approx(9.59)


def test_waves_bench_refuses_a_dx_the_flume_refuses(capsys):
    assert cli.main(["--waves", "--dx", "0.04"]) == 2
    err = capsys.readouterr().err
    assert "numerics.dx = 0.04" in err and "8 particles across the depth" in err


def test_a_quick_validation_writes_only_under_its_out(tmp_path):
    """--validate --quick --out DIR writes the page, its figures and results under DIR: the tree's
    docs/validation.md, its figures and the README stay as they are."""
    import os

    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    watched = [
        os.path.join(root, p)
        for p in ("README.md", "docs/validation.md", "docs/validation/cost.png", "docs/validation/results.json")
    ]
    before = {p: open(p, "rb").read() for p in watched if os.path.exists(p)}
    assert cli.main(["--validate", "--quick", "--only", "tank", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "validation.md").exists() and (tmp_path / "validation" / "cost.png").exists()
    assert {p: open(p, "rb").read() for p in before} == before


def test_gci_recovers_a_known_order_and_its_limit_and_refuses_oscillation():
    """Roache's GCI (tisph/bench/gci_examples.py): f = 1 + dx^2 at dx = 0.3, 0.2, 0.13 gives p = 2
    and the limit 1 (uneven ratios, Celik et al.'s iteration); a sign change gives no order."""
    from tisph.bench.gci_examples import gci

    dx = (0.13, 0.2, 0.3)
    f = [1.0 + d * d for d in dx]
    p, ext, g21, g32 = gci(*f, dx[1] / dx[0], dx[2] / dx[1])
    assert p == pytest.approx(2.0, rel=1e-6) and ext == pytest.approx(1.0, rel=1e-6)
    assert g21 == pytest.approx(1.25 * (f[1] - f[0]) / f[0] / ((dx[1] / dx[0]) ** 2 - 1), rel=1e-6) and g32 > g21
    assert all(math.isnan(v) for v in gci(1.0, 1.1, 1.05, 1.5, 1.5))


def test_bench_bad_case_file_is_a_message_not_a_traceback(tmp_path):
    """python -m tisph.bench --shedding --config F with a key the pipeline refuses: the key, the
    value and what is allowed, exit 2."""
    import subprocess
    import sys

    src = open(os.path.join(ROOT, "scenes", "pipeline_scour_mao.toml")).read()
    cfg = tmp_path / "bad.toml"
    cfg.write_text(src.replace('turbulence = "k_equation"\n', 'turbulence = "smagorinsky"\n', 1))
    r = subprocess.run(
        [sys.executable, "-m", "tisph.bench", "--shedding", "--config", str(cfg), "--out", str(tmp_path / "out")],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert r.returncode == 2, r.stderr
    assert "sediment.shear = 'wall_function' is not allowed" in r.stderr and "Traceback" not in r.stderr


def test_schemes_bench_writes_every_run_its_table_and_figure(tmp_path, monkeypatch):
    """--schemes: every case at each of its spacings under every scheme, each run's keys the
    case's own and the scheme's; the table lists them all, the figure has a panel a case. The runs
    are stood in for (the real ones take about 25 minutes: a benchmark)."""
    import json

    from tisph.bench import scheme_costs as schemes

    seen = []

    def fake(case, dx, out, quick):
        seen.append((case.name, dict(case.overrides), dx))
        return dict(
            case=case.name,
            dx=dx,
            particles=100,
            steps=10,
            wall=1.0 / dx,
            pps=1e6,
            value=0.1,
            error=dx,
            density=0.0,
            also={},
            dir=out,
            status="ok",
            date="",
        )

    monkeypatch.setattr(schemes, "run_one", fake)
    assert cli.main(["--schemes", "--jobs", "1", "--out", str(tmp_path)]) == 0
    n = sum(len(v) for v in schemes.LADDERS.values()) * len(schemes.SCHEMES)
    assert len(seen) == n
    assert ("Sloshing, first mode (linear theory)", {"numerics.scheme": "paper000"}, 0.015) in seen
    assert any(name.startswith("Dam break on a wet") and ov == {"numerics.h_factor": 2.0} for name, ov, _ in seen)
    rows = json.loads((tmp_path / "schemes" / "schemes.json").read_text())
    assert len(rows) == n and {r["scheme"] for r in rows} == set(schemes.SCHEMES)
    assert (tmp_path / "schemes" / "schemes.png").stat().st_size > 20000
    assert (tmp_path / "schemes" / "schemes.md").read_text().count("| Wave flume") == 2 * len(schemes.SCHEMES)


def test_validate_against_a_revision_times_a_whole_case_on_both_trees(tmp_path):
    """--validate --against REV --only WORD: the still tank run whole at dx 0.05 on this tree and
    on HEAD; the same case, particles and error on both (the engine is HEAD's), and the row's
    speed-up is REV's wall time over this tree's."""
    assert (
        cli.main(
            [
                "--validate",
                "--against",
                "HEAD",
                "--only",
                "tank",
                "--dx",
                "0.05",
                "--repeats",
                "1",
                "--out",
                str(tmp_path),
            ]
        )
        == 0
    )
    with open(tmp_path / "against.csv") as f:
        (row,) = list(csv.DictReader(f))
    assert row["case"] == "Still water in a tank" and float(row["dx"]) == 0.05 and int(row["particles"]) == 340
    assert row["error"] == row["error_against"] and row["same_error"] == "True"
    assert float(row["speedup"]) == pytest.approx(float(row["wall_against"]) / float(row["wall"]), rel=1e-6)
    assert "| Still water in a tank | 0.05 | 340 |" in (tmp_path / "against.md").read_text()


def test_validate_against_says_when_the_errors_differ_and_refuses_an_unknown_case(capsys):
    """Where the trees' errors differ the ratio is a cost ratio, and the report says so; a word
    names every case it matches; a case no validation row names is refused with exit 2, naming the
    word."""
    import argparse

    from tisph.bench import against

    new = [dict(case="c", dx=0.1, particles=10, steps=100, wall=w, error=0.05) for w in (10.0, 12.0)]
    rev = [dict(case="c", dx=0.1, particles=10, steps=120, wall=w, error=0.06) for w in (20.0, 18.0)]
    row = against.summary(new, rev)
    assert row["speedup"] == pytest.approx(1.75) and row["speedup_min"] == 1.5 and not row["same_error"]
    text = against.report(argparse.Namespace(against="abc", repeats=2), [row])
    assert "1.75x (1.50-2.00): a cost ratio (the errors differ)" in text
    # a word names every case it matches, as --validate --only runs them: in the table's order, once
    assert against.case_names(["Stoker", "poiseuille", "alpha 0.4"]) == [
        "Poiseuille, Newtonian",
        "Poiseuille, Bingham 10 Pa",
        "Dam break on a wet bed, alpha 0.1 (Stoker)",
        "Dam break on a wet bed, alpha 0.4 (Stoker)",
    ]
    with pytest.raises(SystemExit) as e:
        cli.main(["--validate", "--against", "HEAD", "--only", "no-such-case"])
    assert e.value.code == 2 and "no-such-case" in capsys.readouterr().err
    with pytest.raises(SystemExit) as e:
        cli.main(["--validate", "--against", "HEAD", "--only", "tank", "--quick"])
    assert e.value.code == 2 and "--quick does not apply" in capsys.readouterr().err
