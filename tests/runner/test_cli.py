"""The shared CLI: every flag parses, the scene runs from the command line, frames show water."""

import json
import os
import subprocess
import sys
from collections.abc import Mapping

import numpy as np
import pytest

from tisph.cli import FLAG_KEYS, make_parser, overrides_from_args
from tisph.scenes import dam_break
from tisph.settings.config import build_config
from tisph.settings.resolved import freeze

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


# no GPU backend for the process: the Vulkan loader finds no driver, CUDA no device
NO_GPU = {"VK_ICD_FILENAMES": "/nonexistent.json", "VK_DRIVER_FILES": "/nonexistent.json", "CUDA_VISIBLE_DEVICES": ""}


def run_cli(args, cwd, **env_extra):
    env = dict(os.environ, PYTHONPATH=ROOT, **env_extra)
    return subprocess.run(
        [sys.executable, "-m", "tisph.scenes.dam_break", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )


def test_every_flag_parses_to_its_config_key():
    p = make_parser("dam_break")
    a = p.parse_args(
        [
            "--config",
            "x.toml",
            "--dx",
            "0.05",
            "--end-time",
            "0.3",
            "--max-steps",
            "7",
            "--out",
            "o",
            "--arch",
            "gpu",
            "--no-render",
            "--fps",
            "12",
            "--frame-interval",
            "0.05",
            "--quiet",
        ]
    )
    ov = overrides_from_args(a)
    assert a.config == "x.toml"
    assert ov == {
        "numerics.dx": 0.05,
        "run.end_time": 0.3,
        "run.max_steps": 7,
        "output.dir": "o",
        "run.arch": "gpu",
        "output.fps": 12,
        "output.frame_interval": 0.05,
        "output.render": False,
        "output.quiet": True,
    }
    cfg = freeze(build_config(dam_break.SCENE.DEFAULTS, None, ov))  # every key exists in the schema
    assert cfg["numerics"]["dx"] == 0.05 and cfg["output"]["render"] is False
    assert set(FLAG_KEYS) <= set(vars(a))


def test_help_lists_the_flags():
    with pytest.raises(SystemExit) as e:
        make_parser("dam_break").parse_args(["--help"])
    assert e.value.code == 0


def test_bad_flag_value_exits_2():
    with pytest.raises(SystemExit) as e:
        make_parser("dam_break").parse_args(["--arch", "tpu"])
    assert e.value.code == 2


def test_dam_break_runs_five_steps_from_the_command_line(tmp_path):
    r = run_cli(["--max-steps", "5", "--no-render", "--out", str(tmp_path / "o")], tmp_path)
    assert r.returncode == 0, r.stderr
    s = json.load(open(tmp_path / "o" / "summary.json"))
    assert s["steps"] == 5 and s["status"] == "ok"
    for k in (
        "scene",
        "dx",
        "particles",
        "fluid_particles",
        "boundary_particles",
        "steps",
        "sim_time",
        "wall_time_s",
        "particle_steps_per_s",
        "arch",
        "leaked_particles",
        "metrics",
    ):
        assert k in s
    assert s["fluid_particles"] + s["boundary_particles"] == s["particles"]
    assert (tmp_path / "o" / "probes.csv").read_text().splitlines()[0] == "t,front_x,column_h"
    assert not (tmp_path / "o" / "frames").exists()


def test_progress_off_a_terminal_is_a_line_every_five_percent(tmp_path):
    """stderr is a pipe here, as under a batch scheduler: no progress bar, but one line per 5 % of
    the run, in run.log as well."""
    r = run_cli(["--end-time", "0.1", "--dx", "0.05", "--no-render", "--out", str(tmp_path / "o")], tmp_path)
    assert r.returncode == 0, r.stderr
    lines = [ln for ln in r.stderr.splitlines() if ln.startswith("progress")]
    assert len(lines) == 20 and lines[-1].startswith("progress 100 %")
    assert "particle-steps/s" in lines[0] and "left" in lines[0]
    log = (tmp_path / "o" / "run.log").read_text().splitlines()
    assert sum(ln.startswith("progress") for ln in log) == 20
    # the step's runtime parameters as resolved, in run.log only
    said = [ln for ln in log if ln.startswith("the step's runtime parameters")]
    assert len(said) == 1 and "cfl = 0.4," in said[0] and "g = (0, -9.81) m/s2" in said[0]
    assert "runtime parameters" not in r.stderr


def test_bad_config_key_exits_2_naming_it(tmp_path):
    cfgf = tmp_path / "bad.toml"
    cfgf.write_text("[numerics]\nxpsh = 0.1\n")
    r = run_cli(["--config", str(cfgf), "--out", str(tmp_path / "o")], tmp_path)
    assert r.returncode == 2
    assert "numerics.xpsh" in r.stderr and "numerics.xsph" in r.stderr
    assert "Traceback" not in r.stderr


@pytest.mark.slow
def test_rendered_run_writes_frames_and_movie(tmp_path):
    r = run_cli(
        ["--max-steps", "40", "--frame-interval", "0.001", "--out", str(tmp_path / "o"), "--dx", "0.06", "--quiet"],
        tmp_path,
    )
    assert r.returncode == 0, r.stderr
    frames = sorted(os.listdir(tmp_path / "o" / "frames"))
    assert frames[0] == "00000.png" and len(frames) >= 2
    mp4 = tmp_path / "o" / "dam_break.mp4"
    assert mp4.stat().st_size > 1000
    import imageio.v2 as imageio

    rd = imageio.get_reader(str(mp4))
    assert rd.count_frames() == len(frames)
    assert not [f for f in os.listdir(tmp_path / "o") if ".part" in f]


def test_frame_shows_water_where_the_column_stands():
    from tisph.settings.config import build_config
    from tisph.viz.render import Renderer, colormap
    from tisph.viz.style import Style

    cfg = freeze(build_config(dam_break.SCENE.DEFAULTS, None, {"numerics.dx": 0.05}))
    case = dam_break.SCENE.build(cfg)
    ps = case.particles
    st = dict(x=ps.x, v=np.zeros_like(ps.x), p=np.zeros(len(ps.x)), rho=ps.rho, kind=ps.kind, mat=ps.mat)
    r = Renderer(case.picture.view, Style(width=480, dx=0.05, speed_scale=case.u_max))
    img = r.frame(st, 0.0)
    (x0, y0), _ = r.view
    head = r.panel_top  # the title strip above the panel

    def pix(x, y):
        return img[head + r.H - 1 - int((y - y0) * r.scale), r.left + int((x - x0) * r.scale)].astype(int)

    water = (colormap(0.0) * 255).astype(int)
    for x, y in [(0.5, 1.0), (0.2, 0.3), (0.8, 1.8)]:  # inside the column, at rest
        assert np.abs(pix(x, y) - water).max() <= 12
    assert (pix(3.0, 1.0) == 255).all()  # empty tank: background
    g = pix(-0.04, 1.0)  # left wall: grey
    assert g[0] == g[1] == g[2] and 100 < g[0] < 180
    assert img.shape[1] == r.left + r.W + r.BAR and img.dtype == np.uint8
    assert (img[: head - 2, : r.W // 2] == 255).mean() > 0.8  # the label strip is text on white, no particles


@pytest.mark.parametrize("field", ["speed", "pressure", "density", "material", "vorticity"])
def test_every_output_field_draws_a_frame(field):
    """output.field: each field colours the fluid; the colour bar of a coloured field spans its
    range, a flat (material) frame has none."""
    from tisph.settings.config import build_config
    from tisph.viz.render import Renderer
    from tisph.viz.style import Style

    cfg = freeze(build_config(dam_break.SCENE.DEFAULTS, None, {"numerics.dx": 0.05}))
    case = dam_break.SCENE.build(cfg)
    ps = case.particles
    rng = np.random.default_rng(0)
    st = dict(
        x=ps.x, v=rng.normal(size=ps.x.shape), p=1e4 * rng.random(len(ps.x)), rho=ps.rho, kind=ps.kind, mat=ps.mat
    )
    r = Renderer(case.picture.view, Style(width=320, dx=0.05, speed_scale=2.0, modes=(field,)))
    img = r.frame(st, 0.5)
    assert img.shape == (img.shape[0], r.left + r.W + r.BAR, 3)
    assert (r.bars[0] is None) == (field == "material")


def test_describe_lists_every_key_with_default_range_and_meaning():
    """--describe is generated from the code: every key of the resolved config, its default,
    its allowed values, and the comment written beside the default."""
    from tisph.describe import describe, rows
    from tisph.scenes import beach, erodible_bed, flume, hatch, pipeline_scour, tank, tunnel

    for scene in (s.SCENE for s in (beach, dam_break, flume, hatch, pipeline_scour, tank, tunnel, erodible_bed)):
        r = rows(scene)
        cfg = freeze(build_config(scene.DEFAULTS, None, {}, scene.RANGES, scene.CHOICES))
        n = sum(1 for t in cfg.values() for v in t.values() if not isinstance(v, Mapping)) + sum(
            len(v) for t in cfg.values() for v in t.values() if isinstance(v, Mapping)
        )
        assert len(r) == n
        assert sum(bool(m) for *_, m in r) > 0.7 * n, scene.NAME  # most keys say what they mean
    text = describe(beach)
    line = next(ln for ln in text.splitlines() if ln.strip().startswith("lee_vortex ="))
    assert "0.5" in line and ">= 0.0 and <= 1.0" in line and "lee" in line.split(")", 1)[1]
    r = run_cli(["--describe"], ROOT)
    assert r.returncode == 0 and "[numerics]" in r.stdout and "dx = 0.03" in r.stdout


def test_every_scene_has_a_current_case_file_of_all_its_keys():
    """scenes/defaults/NAME.toml sets every key at its default with its range and meaning beside
    it, generated from the code; a change to a default, range or comment must regenerate it
    (python -m tisph.describe --write scenes/defaults). Loaded, it gives the defaults."""
    import tomllib

    from tisph.describe import as_toml, scenes
    from tisph.settings.config import flatten

    names = []
    for scene in scenes():
        path = os.path.join(ROOT, "scenes", "defaults", f"{scene.NAME}.toml")
        assert open(path).read() == as_toml(scene), f"{path} is stale: python -m tisph.describe --write scenes/defaults"
        cfg = freeze(
            build_config(scene.DEFAULTS, None, {}, getattr(scene, "RANGES", None), getattr(scene, "CHOICES", None))
        )
        with open(path, "rb") as f:
            assert flatten(tomllib.load(f)) == flatten(cfg)
        names.append(scene.NAME)
    assert {"beach", "dam_break", "erodible_bed", "hatch", "pipeline_scour"} <= set(names)


def test_arch_gpu_without_a_gpu_falls_back_to_the_cpu_with_a_warning(tmp_path):
    """The GPU backends hidden from the process (NO_GPU), so the fallback runs on any machine."""
    r = run_cli(
        ["--arch", "gpu", "--dx", "0.1", "--end-time", "0.02", "--no-render", "--out", str(tmp_path / "o")],
        tmp_path,
        **NO_GPU,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    assert "warning: no GPU backend found, running on the CPU" in r.stderr
    s = json.load(open(tmp_path / "o" / "summary.json"))
    assert s["status"] == "ok" and s["steps"] > 0


def test_every_case_file_is_valid_for_the_scene_its_header_names():
    """Each scenes/*.toml names its command in its header (python -m tisph.scenes.NAME --config
    scenes/FILE); the file passes that scene's checks as it stands, so a renamed key or a changed
    range cannot leave a shipped case file that exits 2."""
    import glob
    import importlib
    import re

    from tisph.runner.entry import resolve

    files = sorted(glob.glob(os.path.join(ROOT, "scenes", "*.toml")))
    assert len(files) >= 15
    for path in files:
        text = open(path).read()
        m = re.search(r"python -m tisph\.scenes\.(\w+) --config scenes/" + re.escape(os.path.basename(path)), text)
        assert m, f"{os.path.basename(path)}: no 'python -m tisph.scenes.NAME --config scenes/FILE' line"
        resolve(importlib.import_module(f"tisph.scenes.{m.group(1)}"), path)


@pytest.mark.parametrize(
    "name", ["beach", "tunnel", "flume", "tank", "dam_break", "hatch", "erodible_bed", "pipeline_scour", "custom"]
)
def test_every_key_has_one_description_of_its_own(name):
    """--describe gives every key a description taken from its own table: a scene's geometry.width
    is not the frame's width in pixels, sediment.seed and paddle.seed keep their own words, and no
    description leans on the line above it ("its ...", "or ...")."""
    from tisph.describe import rows
    from tisph.sweep import scene_named

    seen = {}
    for key, _, _, meaning in rows(scene_named(name)):
        assert meaning, f"{name}: {key} has no description"
        assert meaning.split()[0].lower() not in ("its", "their", "and", "or", "that"), (key, meaning)
        seen[key] = meaning
    if "geometry.width" in seen:
        assert "pixel" not in seen["geometry.width"]
    if "paddle.seed" in seen and "sediment.seed" in seen:
        assert seen["paddle.seed"] != seen["sediment.seed"]


def test_reading_checking_and_describing_every_scene_imports_no_taichi():
    """The scenes, their checks and --describe are plain Python: a bad case file is refused, and
    every key described, before Taichi is imported (it is the engine's alone)."""
    code = (
        "import sys\n"
        "from tisph import registry as scenes\n"
        "from tisph.describe import describe\n"
        "from tisph.runner import resolve\n"
        "for name in scenes.names():\n"
        "    m = scenes.load(name)\n"
        "    describe(m)\n"
        "    if name != 'custom':\n"
        "        resolve(m, None, {})\n"
        "print('taichi' in sys.modules)\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip().splitlines()[-1] == "False"


def test_the_tisph_command_runs_describes_and_lists_scenes(tmp_path, capsys):
    """`tisph run SCENE|FILE`, `tisph describe SCENE`, `tisph scenes` (the console script
    pyproject.toml installs): a case file's scene from its header, a bad name refused by name."""
    import tomllib

    from tisph import registry
    from tisph.command import main

    with open(os.path.join(ROOT, "pyproject.toml"), "rb") as f:
        assert tomllib.load(f)["project"]["scripts"]["tisph"] == "tisph.command:console"
    assert main(["scenes"]) == 0
    listed = capsys.readouterr().out
    assert all(name in listed for name in registry.names())
    assert "Wave flume: a piston or flap paddle" in listed and "tisph.scenes." not in listed  # what each is
    assert main(["describe", "tank"]) == 0 and "sediment_depth" in capsys.readouterr().out
    assert main(["describe", "custom"]) == 0
    text = capsys.readouterr().out  # a case of one's own: its geometry's tables first
    assert text.index("[domain]") < text.index("[[solid]]") < text.index("[[gauge]]") < text.index("[run]")
    out = tmp_path / "hatch"
    assert (
        main(
            [
                "run",
                os.path.join(ROOT, "scenes", "hatch.toml"),
                "--max-steps",
                "2",
                "--no-render",
                "--quiet",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    assert json.load(open(out / "summary.json"))["scene"] == "hatch"
    assert main(["run", "no_such_scene"]) == 2
    assert "no_such_scene" in capsys.readouterr().err
    bare = tmp_path / "bare.toml"
    bare.write_text("[numerics]\ndx = 0.02\n")
    assert main(["run", str(bare)]) == 2
    assert "header line naming its scene" in capsys.readouterr().err


def test_the_tisph_command_is_quiet_when_its_reader_stops_early():
    """`tisph describe flume | head -1`: the first line, and no traceback for the closed pipe."""
    r = subprocess.run(
        f"{sys.executable} -m tisph.command describe flume | head -1",
        shell=True,
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
    )
    assert r.stdout.startswith("Config keys of flume") and "Traceback" not in r.stderr, r.stderr
