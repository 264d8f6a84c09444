"""Frames a report can use: metre axes on every particle panel, and the beach's true-scale window."""

import numpy as np
import pytest

from tisph.settings.config import build_config
from tisph.settings.resolved import freeze
from tisph.sweep import scene_named
from tisph.viz.render import Renderer, make_renderer, nice_ticks
from tisph.viz.style import Style


def test_nice_ticks_are_round_and_inside():
    assert nice_ticks(0.0, 1.0, 5) == [0.0, 0.2, 0.4, 0.6, 0.8, 1.0]
    assert nice_ticks(-0.13, 0.47, 3) == [0.0, 0.2, 0.4]
    assert nice_ticks(2.0, 3.0, 10) == pytest.approx([2.0 + 0.1 * k for k in range(11)])
    assert nice_ticks(1.0, 1.0, 4) == []


def dark_rows(img, c0, c1):
    return np.nonzero(img[:, c0:c1].min(axis=(1, 2)) < 100)[0]


# every scene's own framing at a coarse dx: a frame of its initial particles
SCENES = [
    ("dam_break", {"numerics.dx": 0.06}),
    ("tunnel", {"numerics.dx": 0.02}),
    ("beach", {"numerics.dx": 0.03}),
    ("flume", {"numerics.dx": 0.025}),
    ("hatch", {"numerics.dx": 0.0085}),
    ("tank", {"numerics.dx": 0.05}),
    ("erodible_bed", {"numerics.dx": 0.02}),
    ("pipeline_scour", {"numerics.dx": 0.0125}),
]


@pytest.mark.parametrize("name,ov", SCENES, ids=[s for s, _ in SCENES])
def test_every_scene_frame_has_metre_axes(name, ov):
    """Ticks under each particle panel (x) and left of it (z) at the round metre values of the
    panel's view, each with its label beside it; the beach adds its true-scale window."""
    mod = scene_named(name)
    cfg = freeze(build_config(mod.DEFAULTS, None, ov))
    mod.check(cfg)
    case = mod.build(cfg)
    ps = case.particles
    st = dict(x=ps.x, v=np.zeros_like(ps.x), p=np.zeros(len(ps.x)), rho=ps.rho, kind=ps.kind, mat=ps.mat)
    r = make_renderer(case.picture, cfg["output"], cfg["numerics"]["dx"], name, case.u_max)
    img = r.frame(st, 0.0)
    assert r.left >= 32 and img.shape[1] == r.left + r.W + r.BAR
    assert len(r.panels) == len(r.modes) * max(1, len(r.rows)) + (r.zoom is not None)
    for top, H, ((x0, y0), (x1, y1)), _ in r.panels:
        scale = r.W / (x1 - x0)
        xt = [
            v
            for v in nice_ticks(x0, x1, max(2, r.W // (6 * r.font_px)))
            if r.left + (v - x0) * scale <= r.left + r.W - 3.0 * r.font_px
        ]
        assert len(xt) >= 2
        for v in xt:  # a tick mark just under the panel, a label under it
            px = r.left + int(round((v - x0) * scale))
            assert img[top + H + 1, px].max() < 100, (name, v)
            assert (img[top + H + 2 : top + H + r.AXIS, max(px - 2 * r.font_px, 0) : px + 2 * r.font_px] < 100).any()
        zt = [
            v
            for v in nice_ticks(y0, y1, max(2, H // (3 * r.font_px)))
            if top + H - 1 - (v - y0) * scale >= top + 1.6 * r.font_px
        ]
        rows = dark_rows(img[:, : r.left], r.left - 3, r.left)
        for v in zt:  # a tick mark left of the panel at each value
            py = top + H - 1 - int(round((v - y0) * scale))
            assert np.min(np.abs(rows - py)) <= 1, (name, v)
    if name == "beach":
        assert r.zoom is not None
        (a, _), (b, _) = r.zoom.view
        assert b - a == pytest.approx(1.0)  # a metre of the ripple zone
        assert r.zoom.scale == pytest.approx(r.zoom.W / 1.0)


def test_a_long_view_is_drawn_in_rows_that_cover_it():
    """A flume 16 heights long: rows of at most ROW_ASPECT heights' length, end to end, one colour
    bar; a short tank keeps one panel, and so does a frame of two fields."""
    r = Renderer(((0.0, 0.0), (8.0, 0.5)), Style(width=640, dx=0.02, speed_scale=1.0))
    assert len(r.rows) == 2
    assert r.rows[0].view[0][0] == 0.0 and r.rows[0].view[1][0] == r.rows[1].view[0][0] and r.rows[-1].view[1][0] == 8.0
    n = 400
    st = dict(
        x=np.column_stack([np.linspace(0.01, 7.99, n), np.full(n, 0.2)]),
        v=np.zeros((n, 2)),
        p=np.zeros(n),
        rho=np.full(n, 1000.0),
        kind=np.zeros(n, int),
        mat=np.zeros(n, int),
    )
    r.frame(st, 0.0)
    assert len(r.panels) == 2 and r.panels[0][3] is not None and r.panels[1][3] is None
    assert Renderer(((0.0, 0.0), (2.0, 1.0)), Style(width=640, dx=0.02, speed_scale=1.0)).rows == []
    assert (
        Renderer(((0.0, 0.0), (8.0, 0.5)), Style(width=640, dx=0.02, speed_scale=1.0, modes=("speed", "pressure"))).rows
        == []
    )


def test_fields_are_drawn_continuous_and_end_at_the_free_surface():
    """The speed of a block of water interpolated onto the pixels: one colour inside for a uniform
    field, none a spacing above the top row, and no gaps between particles a pixel apart."""
    dx = 0.02
    g = np.mgrid[0:50, 0:10].reshape(2, -1).T * dx + 0.5 * dx
    n = len(g)
    r = Renderer(((0.0, 0.0), (1.0, 0.5)), Style(width=640, dx=dx, speed_scale=2.0, axes=False))
    img = r.frame(
        dict(
            x=g,
            v=np.tile([1.0, 0.0], (n, 1)),
            p=np.zeros(n),
            rho=np.full(n, 1000.0),
            kind=np.zeros(n, int),
            mat=np.zeros(n, int),
        ),
        0.0,
    )
    top, H, _, _ = r.panels[0]
    panel = img[top : top + H, r.left : r.left + r.W].astype(int)
    inside = panel[H - 1 - int(0.1 * r.scale), 20 : r.W // 2]  # 0.1 m up, along the block
    assert np.ptp(inside, axis=0).max() <= 2  # one colour, no disc edges
    above = panel[H - 1 - int((10 * dx + dx) * r.scale), 20 : r.W // 2]  # a spacing above the top row
    assert (above == 255).all()


def test_heights_drawn_exaggerated_as_stated():
    """output.exaggeration = 5: the panel 5 times as tall, the water's top where 5 times its depth
    puts it and no gaps between its rows, the title saying so; its rows keep it; a zoom stays true."""
    dx = 0.02
    g = np.mgrid[0:200, 0:5].reshape(2, -1).T * dx + 0.5 * dx  # 4 m of water 0.1 m deep
    n = len(g)
    st = dict(
        x=g,
        v=np.tile([1.0, 0.0], (n, 1)),
        p=np.zeros(n),
        rho=np.full(n, 1000.0),
        kind=np.zeros(n, int),
        mat=np.zeros(n, int),
    )
    view = ((0.0, 0.0), (4.0, 0.2))
    true = Renderer(view, Style(width=640, dx=dx, speed_scale=2.0, axes=False, rows=False))
    tall = Renderer(view, Style(width=640, dx=dx, speed_scale=2.0, axes=False, rows=False, exaggeration=5.0))
    assert abs(tall.H - 5 * true.H) <= 16 and tall.yscale == pytest.approx(5 * tall.scale)
    img = tall.frame(st, 0.0)
    top, H, _, _ = tall.panels[0]
    panel = img[top : top + H, tall.left : tall.left + tall.W].astype(int)
    col = panel[:, tall.W // 2]
    wet = np.flatnonzero((col != 255).any(axis=1))
    depth_px = H - wet.min()
    assert depth_px == pytest.approx(0.1 * tall.yscale, abs=0.6 * dx * tall.yscale)  # 0.5 m drawn
    assert np.ptp(panel[H - depth_px // 2 - 8 : H - depth_px // 2 + 8, 20 : tall.W - 20], axis=(0, 1)).max() <= 2
    assert "heights x5" in tall.title_line(0.0) and "heights" not in true.title_line(0.0)
    long = Renderer(
        ((0.0, 0.0), (12.0, 0.2)),
        Style(width=640, dx=dx, speed_scale=2.0, exaggeration=5.0, zoom=((1.0, 0.0), (1.5, 0.2))),
    )
    assert long.zoom.exaggeration == 1.0 and long.zoom.yscale == long.zoom.scale
    rows = Renderer(((0.0, 0.0), (12.0, 0.2)), Style(width=640, dx=dx, speed_scale=2.0, exaggeration=5.0))
    assert rows.rows and all(r.exaggeration == 5.0 for r in rows.rows)


def test_zoom_window_from_the_config_and_its_outline():
    """output.zoom sets the window; the main panel outlines where it is."""
    from tisph.scenes import dam_break

    cfg = freeze(
        build_config(dam_break.SCENE.DEFAULTS, None, {"numerics.dx": 0.06, "output.zoom": [0.0, 1.0, 0.0, 0.5]})
    )
    case = dam_break.SCENE.build(cfg)
    ps = case.particles
    st = dict(x=ps.x, v=np.zeros_like(ps.x), p=np.zeros(len(ps.x)), rho=ps.rho, kind=ps.kind, mat=ps.mat)
    r = make_renderer(case.picture, cfg["output"], 0.06, "t", 1.0)
    img = r.frame(st, 0.0)
    assert r.zoom.view == ((0.0, 0.0), (1.0, 0.5))
    top, H, ((x0, y0), _), _ = r.panels[0]
    col = r.left + int(round((1.0 - x0) * r.scale))  # the box's right edge, inside the panel
    row = top + H - 1 - int(round((0.25 - y0) * r.scale))
    assert img[row, col].max() <= 60
    plain = Renderer(case.picture.view, Style(width=480, dx=0.06, speed_scale=1.0, axes=False))
    assert plain.left == 0 and plain.frame(st, 0.0).shape[1] == 480 + plain.BAR


def test_gauges_are_marked_on_the_flume_frame():
    from tisph.runner import resolve
    from tisph.scenes import flume

    cfg = resolve(flume, None, {"numerics.dx": 0.025})
    case = flume.SCENE.build(cfg)
    ps = case.particles
    st = dict(x=ps.x, v=np.zeros_like(ps.x), p=np.zeros(len(ps.x)), rho=ps.rho, kind=ps.kind, mat=ps.mat)
    r = make_renderer(case.picture, cfg["output"], 0.025, "flume", case.u_max)
    img = r.frame(st, 0.0)
    top, H, ((x0, _), _), _ = r.panels[0]
    assert len(r.marks) == 3 and [m[1] for m in r.marks] == ["g1", "g2", "g3"]
    for x, _ in r.marks:
        col = img[top : top + H, r.left + int(round((x - x0) * r.scale))]
        assert (col.max(axis=1) <= 40).sum() >= H // 8  # a dotted line down the panel


def test_the_beach_colours_by_its_waves_own_speed():
    """The beach's colour top is three times the linear near-bed orbital speed at the paddle
    (1.02 m/s at the defaults), and its vorticity range that over 10 dx: one range a movie."""
    import math

    from tisph.runner import resolve
    from tisph.scenes import beach
    from tisph.waves.theory import linear_wave

    cfg = resolve(beach)
    case = beach.SCENE.build(cfg)
    omega, k, _, _, hs = linear_wave(cfg, 0.3)
    u = 1.5 * hs * cfg["paddle"]["stroke"] * omega / math.sinh(k * 0.3)
    assert case.picture.speed_scale == pytest.approx(u) and 0.9 < u < 1.1
    r = make_renderer(case.picture, cfg["output"], cfg["numerics"]["dx"], "beach", case.picture.speed_scale)
    assert r.zoom._colour_range("vorticity", np.array([0.0, 50.0])) == pytest.approx(
        (-u / (10 * 0.0093), u / (10 * 0.0093))
    )


def test_the_pressure_bar_holds_the_first_frames_range():
    """Without a scene's pressure scale the bar is the first frame's (the water at rest: rho g
    depth) for the whole movie, not each frame's: an impact later is drawn against it."""
    dx = 0.02
    g = np.mgrid[0:50, 0:10].reshape(2, -1).T * dx + 0.5 * dx
    n = len(g)
    r = Renderer(((0.0, 0.0), (1.0, 0.5)), Style(width=320, dx=dx, speed_scale=1.0, modes=("pressure",), axes=False))
    st = dict(
        x=g,
        v=np.zeros((n, 2)),
        p=9810.0 * (0.2 - g[:, 1]),
        rho=np.full(n, 1000.0),
        kind=np.zeros(n, int),
        mat=np.zeros(n, int),
    )
    r.frame(st, 0.0)
    first = r.bars[-1][1:3]
    r.frame(dict(st, p=3.0 * st["p"]), 0.1)
    assert r.bars[-1][1:3] == first and 1.5 < first[1] < 2.0  # kPa: rho g 0.19 m


def test_a_case_file_s_slope_is_drawn_as_its_line_not_as_stairs():
    """The breakwater's 1:2 seaward face (x 3.0 to 3.46 m, z 0.05 to 0.28 m) at dx 0.05: in each
    pixel column over it the solid's grey ends within a pixel of the line, where its wall particles
    (stairs a spacing high) would end up to half a spacing off; the same column is drawn grey
    below the face and not above it."""
    import os

    from tisph.runner import resolve
    from tisph.scenes import custom
    from tisph.viz.colours import BOUNDARY

    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    cfg = resolve(custom, os.path.join(root, "scenes", "breakwater.toml"), {"numerics.dx": 0.05})
    case = custom.SCENE.build(cfg)
    ps = case.particles
    st = dict(x=ps.x, v=np.zeros_like(ps.x), p=np.zeros(len(ps.x)), rho=ps.rho, kind=ps.kind, mat=ps.mat)
    r = Renderer(
        ((2.8, -0.1), (3.8, 0.4)),
        Style(width=800, dx=0.05, speed_scale=1.0, axes=False, solid_region=case.picture.solid_region),
    )
    img = r.frame(st, 0.0)
    top, H, ((x0, y0), _), _ = r.panels[0]
    grey = np.abs(img.astype(int) - (np.array(BOUNDARY) * 255).astype(int)).max(axis=2) <= 2
    off = []
    for x in np.linspace(3.05, 3.4, 8):
        col = int((x - x0) * r.scale)
        rows = np.nonzero(grey[top : top + H, col])[0]
        z_top = y0 + (H - rows.min()) / r.scale  # the highest grey pixel's top edge
        off.append(abs(z_top - (0.05 + (x - 3.0) * 0.23 / 0.46)))
    assert max(off) < 1.5 / r.scale
    plain = Renderer(((2.8, -0.1), (3.8, 0.4)), Style(width=800, dx=0.05, speed_scale=1.0, axes=False)).frame(st, 0.0)
    stairs = []
    for x in np.linspace(3.05, 3.4, 8):
        col = int((x - x0) * r.scale)
        rows = np.nonzero(
            np.abs(plain[top : top + H, col].astype(int) - (np.array(BOUNDARY) * 255).astype(int)).max(axis=1) <= 2
        )[0]
        stairs.append(abs(y0 + (H - rows.min()) / r.scale - (0.05 + (x - 3.0) * 0.23 / 0.46)))
    assert max(stairs) > 4 / r.scale  # the particles alone: stairs
