"""A table of bad inputs: each gives exit code 2 and one message naming the field, the value and
what is allowed; none reaches Taichi or prints a traceback."""

import pytest

from tisph.case import as_scene
from tisph.runner import run_scene
from tisph.scenes import beach, dam_break, flume, pipeline_scour, tank, tunnel

CASES = [
    # (scene, argv, TOML text or None, words the message must contain)
    (dam_break, ["--dx", "-0.01"], None, ["numerics.dx", "-0.01", "> 0"]),
    (dam_break, ["--dx", "0"], None, ["numerics.dx", "> 0"]),
    (dam_break, ["--end-time", "-1"], None, ["run.end_time", "> 0"]),
    (dam_break, ["--max-steps", "-5"], None, ["run.max_steps", ">= 0"]),
    (dam_break, ["--fps", "0"], None, ["output.fps", ">= 1"]),
    (dam_break, ["--frame-interval", "0"], None, ["output.frame_interval", "> 0"]),
    (dam_break, ["--snapshot-every", "-2"], None, ["output.snapshot_every", ">= -1"]),
    (dam_break, ["--checkpoint-every", "-1"], None, ["output.checkpoint_every", ">= 0"]),
    (dam_break, ["--config", "missing.toml"], None, ["--config", "missing.toml", "existing TOML"]),
    (dam_break, [], "[numerics\ndx = 1", ["--config", "valid TOML"]),
    (dam_break, [], "[numerix]\ndx = 0.1\n", ["numerix", "did you mean 'numerics'"]),
    (dam_break, [], "[materials.water]\nviscosty = 1e-3\n", ["materials.water.viscosty", "materials.water.viscosity"]),
    (dam_break, [], "[numerics]\ndx = \"0.1\"\n", ["numerics.dx", "'0.1'", "a number"]),
    (dam_break, [], "[numerics]\nxsph = 0.6\n", ["numerics.xsph", "0.6", "<= 0.5"]),
    (dam_break, [], "[numerics]\ndelta = -0.1\n", ["numerics.delta", ">= 0"]),
    (dam_break, [], "[numerics]\nkernel = \"quintic\"\n", ["numerics.kernel", "quintic", "'wendland'"]),
    (dam_break, [], "[numerics]\ndensity_diffusion = \"yes\"\n", ["numerics.density_diffusion", "'fourtakas'"]),
    (dam_break, [], "[numerics]\nh_factor = 0.5\n", ["numerics.h_factor", ">= 1.0"]),
    (dam_break, [], "[numerics]\nwall_layers = 0\n", ["numerics.wall_layers", ">= 1"]),
    (dam_break, [], "[numerics]\nh_factor = 3.0\n", ["numerics.wall_layers", "5", "at least 6", "2 h = 6 dx"]),
    (dam_break, [], "[numerics]\ncfl = 0\n", ["numerics.cfl", "> 0"]),
    (dam_break, [], "[numerics]\ndx = nan\n", ["numerics.dx", "nan"]),
    # the turbulence keys belong to the scene with SPS turbulence (the pipeline) and are refused elsewhere
    (dam_break, [], "[numerics]\nmixing_length = 0.01\n", ["numerics.mixing_length", "0.01", "no SPS turbulence"]),
    (
        dam_break,
        [],
        "[numerics]\nturbulence = \"k_equation\"\n",
        ["numerics.turbulence", "k_equation", "no SPS turbulence"],
    ),
    (
        pipeline_scour,
        [],
        "[geometry]\nsps = false\n[numerics]\nmixing_length = 0.01\n",
        ["numerics.mixing_length", "0.01", "without SPS"],
    ),
    (
        pipeline_scour,
        [],
        "[numerics]\nstress_limiter = 0.875\n",
        ["numerics.stress_limiter", "0.875", "without the k equation"],
    ),
    (pipeline_scour, [], "[numerics]\nstress_limiter = -1.0\n", ["numerics.stress_limiter", ">= 0"]),
    (
        pipeline_scour,
        [],
        "[numerics]\nlength_scale = \"omega\"\n",
        ["numerics.length_scale", "omega", "without the k equation"],
    ),
    (
        pipeline_scour,
        [],
        "[numerics]\nturbulence = \"k_epsilon\"\n",
        ["numerics.turbulence", "k_epsilon", "'k_equation'"],
    ),
    (dam_break, [], "[numerics]\nshifting = 20.0\n", ["numerics.shifting", "20", "<= 10"]),
    (dam_break, [], "[geometry]\ncolumn_height = 5.0\n", ["geometry.column_height", "tank_height"]),
    (dam_break, [], "[geometry]\ncolumn_width = -1.0\n", ["geometry.column_width", "> 0"]),
    (dam_break, [], "[numerics]\ndx = 0.3\n", ["numerics.dx", "4 particles"]),
    (dam_break, [], "[materials.water]\nrho0 = -1000.0\n", ["materials.water.rho0", "> 0"]),
    (dam_break, [], "[materials.water]\nviscosity = -1.0\n", ["materials.water.viscosity", ">= 0"]),
    (dam_break, [], "[materials.oil]\nrho0 = 900.0\n", ["materials.oil", "materials.water"]),
    (dam_break, [], "[output]\nrender = \"yes\"\n", ["output.render", "true or false"]),
    (dam_break, [], "[run]\nprecision = \"f16\"\n", ["run.precision", "'f32'"]),
    (dam_break, [], "[run]\nmax_steps = 2.5\n", ["run.max_steps", "an integer"]),
    (tank, [], "[geometry]\ndepth = 2.0\n", ["geometry.depth", "tank_height"]),
    (tunnel, [], "[geometry]\nsand_depth = 0.02\n", ["geometry.sand_depth", "0.02", "4 dx"]),
    (tunnel, [], "[geometry]\nperiod = 0.0\n", ["geometry.period", "> 0"]),
    (
        tunnel,
        [],
        "[geometry]\nseed_ripple_height = 0.07\n",
        ["geometry.seed_ripple_height", "0.07", "sand_depth - 2 dx"],
    ),
    (beach, [], "[geometry]\ngrain_diameter = -0.001\n", ["geometry.grain_diameter", "-0.001", "> 0"]),
    (beach, [], "[geometry]\ngauges_x = [1.0, 9.0]\n", ["geometry.gauges_x", "9.0", "(0, 5.3)"]),
    (tunnel, [], "[sediment]\nporosity = 1.5\n", ["sediment.porosity", "1.5", "<= 0.9"]),
    (tunnel, [], "[sediment]\nmodel = \"grains\"\n", ["sediment.model", "grains", "'bedload'"]),
    (tunnel, [], "[sediment]\nrepose_angle = 80.0\n", ["sediment.repose_angle", "80.0", "<= 60"]),
    (tunnel, [], "[sediment]\nmorfac = 0.5\n", ["sediment.morfac", ">= 1"]),
    (tunnel, [], "[sediment]\nmodel = \"bedload\"\nsuspended = true\n", ["sediment.suspended", "True", "pipeline"]),
    (
        pipeline_scour,
        [],
        "[sediment]\nmodel = \"particles\"\nsuspended = true\n",
        ["sediment.suspended", "True", "bedload"],
    ),
    # a [sediment] key the particle sand ignores is refused, not dropped
    (
        beach,
        [],
        "[sediment]\nmodel = \"particles\"\nmorfac = 10.0\nlee_vortex = 0.2\n",
        ["sediment.morfac", "10.0", "sediment.lee_vortex", "0.2", "SPH particles"],
    ),
    (
        tunnel,
        [],
        "[sediment]\nmodel = \"bedload\"\nshear = \"log_far_field\"\n",
        ["sediment.shear", "log_far_field", "'waves' or 'log'"],
    ),
    (
        tunnel,
        [],
        "[sediment]\nmodel = \"bedload\"\nshear = \"wall_function\"\n",
        ["sediment.shear", "wall_function", "'waves' or 'log'"],
    ),
    (
        pipeline_scour,
        [],
        "[sediment]\nshear = \"wall_function\"\n",
        ["sediment.shear", "wall_function", "'k_equation'", "'smagorinsky'"],
    ),
    (tunnel, [], "[sediment]\nmodel = \"bedload\"\nlee_transit = true\n", ["sediment.lee_transit", "True", "waves"]),
    (pipeline_scour, [], "[sediment]\nsettling_delay = true\n", ["sediment.settling_delay", "True", "lee_transit"]),
    (
        pipeline_scour,
        [],
        "[geometry]\ninitial_profile = \"mao_12s\"\n",
        ["geometry.initial_profile", "mao_12s", "'mao_11s'"],
    ),
    (
        pipeline_scour,
        [],
        "[geometry]\ninitial_profile = \"mao_25s\"\nsand_depth = 0.1\npipe_diameter = 0.1\n",
        ["geometry.initial_profile", "mao_25s", "sand_depth", "deepest point"],
    ),
    (pipeline_scour, [], "[sediment]\nsettling_velocity = -0.01\n", ["sediment.settling_velocity", "-0.01", ">= 0"]),
    (dam_break, [], "[output]\nfield = \"concentration\"\n", ["output.field", "concentration", "sediment.suspended"]),
    # a spacing whose particles cannot fit: refused before anything is allocated
    (
        dam_break,
        ["--dx", "1e-6"],
        None,
        ["numerics.dx", "1e-06", "fit in this machine's memory", "2e+12 points", "available"],
    ),
    (beach, ["--dx", "1e-6"], None, ["numerics.dx", "fit in this machine's memory", "TB"]),
    (pipeline_scour, ["--dx", "1e-6"], None, ["numerics.dx", "fit in this machine's memory"]),
    (tunnel, ["--dx", "1e-6"], None, ["numerics.dx", "fit in this machine's memory"]),
    # path-valued flags and keys that name a folder
    (dam_break, ["--config", "."], None, ["--config", "'.'", "a TOML file", "it is a folder"]),
    (dam_break, ["--restart", "."], None, ["--restart", "'.'", "a checkpoint.h5", "it is a folder"]),
    (dam_break, ["--restart", "missing.h5"], None, ["--restart", "missing.h5", "an existing checkpoint.h5"]),
    (flume, [], "[paddle]\nseries = \".\"\n", ["paddle.series", "'.'", "a CSV file", "it is a folder"]),
    # the waves' keys
    (flume, [], "[paddle]\norder = 3\n", ["paddle.order", "3", "<= 2"]),
    (flume, [], "[paddle]\nseries = \"s.csv\"\norder = 2\n", ["paddle.order", "1 with a series"]),
    (
        flume,
        [],
        "[geometry]\ndepth = 5.0\nwall_height = 6.0\n[paddle]\nperiod = 0.8\nstroke = 0.02\norder = 2\n",
        ["paddle.order", "k2 h = 126", "at most 100"],
    ),
    (flume, [], "[geometry]\narray_gauges = 2\n", ["geometry.array_gauges", "2", "0 (no array) or 3 to 12"]),
    (flume, [], "[numerics]\nwall = \"adamy\"\n", ["numerics.wall", "adamy", "adami"]),
    (flume, [], "[paddle]\nspectrum = \"jonswop\"\n", ["paddle.spectrum", "jonswop", "'jonswap'"]),
    (flume, [], "[paddle]\nspectrum = \"jonswap\"\nhs = 0.0\ntp = 1.0\n", ["paddle.hs", "> 0 with paddle.spectrum"]),
    (
        flume,
        [],
        "[paddle]\nspectrum = \"pm\"\nhs = 0.04\ntp = 0.9\nband = [0.5, 3.0]\n",
        ["paddle.band", "[0.5, 3.0]", "at least 8 h", "lower the band's top or dx"],
    ),
    (flume, [], "[paddle]\nspectrum = \"jonswap\"\nhs = 0.3\ntp = 1.5\n", ["paddle.hs", "more than half the depth"]),
    (
        flume,
        [],
        "[paddle]\nspectrum = \"jonswap\"\nhs = 0.04\ntp = 0.9\norder = 2\n",
        ["paddle.order", "1 with a spectrum"],
    ),
    (beach, [], "[paddle]\nspectrum = \"jonswap\"\n", ["paddle.spectrum", "unknown"]),
]


@pytest.mark.parametrize(
    "scene, argv, toml, words",
    CASES,
    ids=[f"{as_scene(c[0]).NAME}:{' '.join(c[1]) or c[2].splitlines()[-1]}" for c in CASES],
)
def test_bad_input(scene, argv, toml, words, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    args = list(argv)
    if toml is not None:
        (tmp_path / "case.toml").write_text(toml)
        args += ["--config", "case.toml"]
    code = run_scene(scene, args + ["--out", str(tmp_path / "o"), "--no-render", "--quiet"])
    err = capsys.readouterr().err
    assert code == 2
    assert "Traceback" not in err
    for w in words:
        assert w in err, (w, err)


def test_unwritable_output_folder(tmp_path, capsys):
    f = tmp_path / "a_file"
    f.write_text("x")
    code = run_scene(dam_break, ["--out", str(f / "sub"), "--no-render", "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and "cannot create output folder" in err and str(f / "sub") in err


@pytest.mark.slow
def test_changed_config_refused_on_restart_unless_forced(tmp_path, capsys):
    out = str(tmp_path / "o")
    assert (
        run_scene(
            dam_break,
            [
                "--dx",
                "0.06",
                "--end-time",
                "0.01",
                "--checkpoint-every",
                "0.01",
                "--no-render",
                "--quiet",
                "--out",
                out,
            ],
        )
        == 0
    )
    ck = str(tmp_path / "o" / "checkpoint.h5")
    cfg = tmp_path / "c.toml"
    cfg.write_text("[numerics]\nartificial_viscosity = 0.2\n")
    code = run_scene(
        dam_break,
        [
            "--dx",
            "0.06",
            "--config",
            str(cfg),
            "--end-time",
            "0.02",
            "--no-render",
            "--quiet",
            "--out",
            out,
            "--restart",
            ck,
        ],
    )
    err = capsys.readouterr().err
    assert code == 2 and "numerics.artificial_viscosity: 0.0 -> 0.2" in err and "--force" in err
    code = run_scene(
        dam_break,
        [
            "--dx",
            "0.06",
            "--config",
            str(cfg),
            "--end-time",
            "0.02",
            "--no-render",
            "--quiet",
            "--out",
            out,
            "--restart",
            ck,
            "--force",
        ],
    )
    assert code == 0


def test_byte_order_mark_is_accepted(tmp_path):
    """A case file saved with a UTF-8 byte-order mark (several Windows editors write one) reads."""
    cfg = tmp_path / "bom.toml"
    cfg.write_bytes(b"\xef\xbb\xbf[run]\nend_time = 0.004\n")
    code = run_scene(
        dam_break, ["--config", str(cfg), "--dx", "0.06", "--no-render", "--quiet", "--out", str(tmp_path / "o")]
    )
    assert code == 0
    import json

    assert json.load(open(tmp_path / "o" / "summary.json"))["sim_time"] >= 0.004
