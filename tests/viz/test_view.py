"""tisph.view: a run's snapshots rendered again from the HDF5 files alone."""

import os

import imageio.v2 as imageio
import numpy as np

from tisph import view
from tisph.runner import simulate
from tisph.scenes import dam_break
from tisph.viz.render import Renderer
from tisph.viz.style import Style


def test_view_renders_snapshots_to_png_and_mp4(tmp_path, capsys):
    out = tmp_path / "db"
    simulate(
        dam_break,
        {
            "numerics.dx": 0.06,
            "run.end_time": 0.06,
            "output.render": False,
            "output.quiet": True,
            "output.snapshot_every": 0.02,
        },
        out=str(out),
    )
    assert view.main([str(out), "--field", "pressure", "--time", "0.04", "--width", "480"]) == 0
    # named by the snapshot's own time: the first step at or after 0.04 s
    name = next(n for n in os.listdir(out / "view") if n.startswith("pressure_t0.04"))
    png = out / "view" / name
    img = imageio.imread(png)
    r = Renderer(((0, 0), (1, 1)), Style(width=480))
    assert img.shape[1] == r.left + 480 + r.BAR
    # the scene's own framing: the same as the live run's frames would have
    assert view.main([str(out), "--all", "--mp4", "--width", "320"]) == 0
    pngs = sorted(p for p in os.listdir(out / "view") if p.startswith("speed_t"))
    assert len(pngs) == 4  # t = 0, 0.02, 0.04, 0.06
    rd = imageio.get_reader(str(out / "view" / "speed.mp4"))
    assert rd.count_frames() == 4
    # the pressure picture is not the speed picture
    a = imageio.imread(out / "view" / name.replace("pressure", "speed")).astype(int)
    assert a.shape != img.shape or np.abs(a - img).mean() > 1


def test_view_refuses_bad_input_by_name(tmp_path, capsys):
    assert view.main([str(tmp_path)]) == 2
    assert "holds no snapshots" in capsys.readouterr().err
    out = tmp_path / "db"
    simulate(
        dam_break,
        {
            "numerics.dx": 0.06,
            "run.max_steps": 2,
            "output.render": False,
            "output.quiet": True,
            "output.snapshot_every": 0.001,
        },
        out=str(out),
    )
    assert view.main([str(out), "--view", "1", "0", "0", "1"]) == 2
    assert "--view" in capsys.readouterr().err


def test_view_finds_a_bed_load_bed_from_its_particles():
    """The sand under a bed-load bed is filled from its BED particles: z_b = top layer + dx/2."""
    from tisph.particles import BED, FLUID

    dx = 0.02
    xs = (np.arange(10) + 0.5) * dx
    zb = 0.1 + 0.01 * np.sin(xs * 20)
    x = np.vstack([np.column_stack([xs, zb - (k + 0.5) * dx]) for k in range(3)] + [[[0.05, 0.3]]])
    kind = np.array([BED] * 30 + [FLUID])
    f = view.bed_surface_of(dict(x=x, kind=kind), dx)
    assert np.allclose(f(xs), zb)
    assert view.bed_surface_of(dict(x=x[-1:], kind=kind[-1:]), dx) is None


def test_view_range_is_in_the_bars_unit_and_names_its_picture(tmp_path):
    """--range for pressure is in kPa, as the bar says; pictures with another range or view get
    their own names instead of overwriting; the default pressure range is the water's."""
    from tisph.viz.render import Renderer
    from tisph.viz.style import Style

    out = tmp_path / "db"
    simulate(
        dam_break,
        {
            "numerics.dx": 0.06,
            "run.end_time": 0.02,
            "output.render": False,
            "output.quiet": True,
            "output.snapshot_every": 0.02,
        },
        out=str(out),
    )
    assert view.main([str(out), "--field", "pressure", "--range", "0", "4.5", "--width", "320"]) == 0
    assert view.main([str(out), "--field", "pressure", "--width", "320"]) == 0
    names = sorted(os.listdir(out / "view"))
    t = next(n for n in names if n.startswith("pressure_t0.02"))[len("pressure_t") :]
    assert "pressure_range0,4.5_t" + t in names
    n = 50
    x = np.column_stack([np.linspace(0.1, 0.9, n), np.linspace(0.1, 0.9, n)])
    st = dict(
        x=x,
        v=np.zeros((n, 2)),
        p=np.linspace(0, 4000.0, n),
        rho=np.full(n, 1000.0),
        kind=np.zeros(n, int),
        mat=np.zeros(n, int),
    )
    r = Renderer(((0, 0), (1, 1)), Style(width=320, dx=0.02, modes=("pressure",), vrange=(0.0, 4.5)))
    r.frame(st, 0.0)
    assert r.bars[0][1:3] == (0.0, 4.5)  # the bar says 0 to 4.5 kPa ...
    assert r._colour_range("pressure", st["p"]) == (0.0, 4500.0)  # ... and colours 0 to 4500 Pa
    auto = Renderer(((0, 0), (1, 1)), Style(width=320, dx=0.02, modes=("pressure",)))
    lo, hi = auto._colour_range("pressure", st["p"])
    assert lo == 0.0 and 3900.0 < hi <= 4000.0  # the water's 99.5th percentile


def test_view_does_not_repeat_the_runs_warnings(tmp_path):
    """A case whose build warns (a wave under 3 dx): the run said so; rebuilding its framing for a
    view says nothing."""
    import warnings

    from tisph.scenes import flume

    out = tmp_path / "fl"
    simulate(
        flume,
        {
            "numerics.dx": 0.03,
            "run.end_time": 0.02,
            "output.render": False,
            "output.quiet": True,
            "output.snapshot_every": 0.01,
            "geometry.length": 2.0,
            "geometry.damping_length": 0.6,
            "geometry.gauges_wavelengths": [0.5, 1.0],
        },
        out=str(out),
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert view.main([str(out), "--width", "240"]) == 0
    assert not [w for w in caught if issubclass(w.category, UserWarning)], [str(w.message) for w in caught]
