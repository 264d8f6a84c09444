"""Your own case: a 2D domain described in a case file, in metres (docs/cases.md).

  python -m tisph.scenes.custom --config scenes/breakwater.toml

[domain] gives the box and gravity; [[solid]] entries are the walls (polylines, polygons, boxes,
circles, a surveyed CSV profile), their particle layers laid on the solid side; [[water]]
entries fill regions below a level or inside a polygon, starting hydrostatic; [paddle] is a
piston or flap wave maker at x (every key of the flume's paddle); [absorber] a damping zone;
domain.outflow open boxes the water leaves through; [[gauge]] entries read the free surface,
velocity, pressure, the force on a wall face and the discharge through a section (overtopping,
with EurOtop's mean discharge beside it). Every particle sits on one lattice (tisph/geometry.py).
"""

import math
from functools import partial

import numpy as np

from ...case import Scene, make_case
from ...measure.records import arrival_time, wave_period
from ...particles import FLUID, MOVING, WALL, ParticleSet, hydrostatic_density, tait_B, wall_density
from ...runner import common_params, run_scene, sound_speed
from ...settings.config import ConfigError, physics_from_config, raise_collected
from ...settings.plausible import warn_case_waves, warn_gauges
from ...settings.schema import POSITIVE, K, with_defaults
from ...settings.schemes import numerics
from ...waves import paddle as wp
from ...waves.absorb import with_control
from ...waves.irregular import IRREGULAR
from ...waves.paddle import PADDLE
from ...waves.theory import linear_wave
from .elements import ELEMENTS, entries, numbers
from .gauges import (
    CaseGauges,
    check_sites,
    load_cutoff,
    observers,
    run_title,  # noqa: F401 (the scene's API)
)
from .layout import Layout, who
from .sand import SAND, SEDIMENT, SandBed, Still
from .sand import check as check_sand

BOX = "[x0, x1, z0, z1] in m with x0 < x1 and z0 < z1"


def _parts(cfg):  # noqa: C901 (one branch a kind of part a case file may hold)
    """The checked entries and the layout, or every error at once."""
    errors = []
    base = cfg.domain.base_dir or "."
    solids = entries(cfg, "solid", base, errors)
    waters = entries(cfg, "water", base, errors)
    gauges = entries(cfg, "gauge", base, errors)
    try:
        box = numbers("domain.box", cfg.domain.box, 4, BOX, (0, 2))
    except ConfigError as e:
        raise_collected(errors + [e])
    outflow = []
    for i, b in enumerate(cfg.domain.outflow):
        try:
            outflow.append(numbers(f"domain.outflow[{i}]", b, 4, BOX, (0, 2)))
        except ConfigError as e:
            errors.append(e)
    if not solids:
        errors.append(ConfigError("solid", [], "at least one [[solid]] (the water needs something to stand on)"))
    if not waters:
        errors.append(ConfigError("water", [], "at least one [[water]] region"))
    labels = [g["label"] for g in gauges]
    for g in gauges:
        if labels.count(g["label"]) > 1:
            errors.append(ConfigError(f"{g['name']}.label", g["label"], "a label no other gauge has"))
        for key, v, lo, hi in (("x", g["x"], box[0], box[1]), ("z", g["z"], box[2], box[3])):
            if v is not None and not lo <= v <= hi:
                errors.append(ConfigError(f"{g['name']}.{key}", v, f"inside domain.box ({lo:g} to {hi:g} m)"))
        surface = [q["label"] for q in gauges if q["type"] == "surface"]
        if any(lab not in surface for lab in g["toe_gauges"]):
            errors.append(ConfigError(f"{g['name']}.toe_gauges", g["toe_gauges"], "labels of surface gauges"))
    for name in {g["array"] for g in gauges if g["array"]}:
        mine = [g for g in gauges if g["array"] == name]
        if len(mine) < 2 or cfg.paddle.type == "none":
            errors.append(
                ConfigError(
                    f"{mine[0]['name']}.array",
                    name,
                    "a name two or more surface gauges share, "
                    "in a case with a paddle (the waves are separated at its frequency)",
                )
            )
    raise_collected(errors)
    num = cfg.numerics
    lay = Layout(box, solids, waters, num.dx, num.wall_layers, errors)
    check_sites(gauges, lay, errors)
    raise_collected(errors)
    p = cfg.paddle
    if p.type != "none":
        lay.water &= lay.pts[:, 0] > p.x
    bad = lay.unheld(outflow, p.x if p.type != "none" else None)
    if bad is not None:
        (x, z), d = bad
        side = {(1, 0): "right", (-1, 0): "left", (0, 1): "top", (0, -1): "bottom"}[d]
        raise ConfigError(
            who(waters[int(lay.region[np.argmin(np.hypot(*(lay.pts - [x, z]).T))])]),
            f"water at ({x:.4g}, {z:.4g}) m",
            "water held by a solid or an outflow",
            f"nothing holds it at the domain's {side} edge: draw a wall there, an outflow box, or lower the level",
        )
    sand_site = check_sand(cfg, solids, box, errors)
    raise_collected(errors)
    if sand_site and cfg.sand.x[0] <= cfg.paddle.x:
        raise ConfigError(
            "sand.x", cfg.sand.x, f"a stretch in front of the paddle (x0 > paddle.x = {cfg.paddle.x:g} m)"
        )
    return box, outflow, solids, waters, gauges, lay, sand_site


def paddle_site(cfg, lay, box):
    """(floor, level, the paddle's particles, motion, parameters and reach), after its checks: water in front of it, a floor under
    its travel, nothing solid in its way."""
    p, dx = cfg.paddle, cfg.numerics.dx
    col = lay.column(p.x)
    if col is None:
        raise ConfigError("paddle.x", p.x, "a position with water just in front of it (x + dx/2)")
    floor, level = col
    depth = level - floor
    length = float(lay.pts[lay.water, 0].max()) - p.x
    wp.check_paddle(cfg, depth, length, default_stroke=0.04)
    parts = wp.paddle(cfg, depth, p.top or box[3], floor)  # built once: the travel here, the particles in build
    reach = parts[3]
    back = p.x - lay.T - reach
    top = p.top or box[3]
    if top <= level:
        raise ConfigError("paddle.top", top, f"above the water at the paddle ({level:.4g} m)")
    if back - lay.T < box[0]:
        raise ConfigError(
            "paddle.x",
            p.x,
            f"at least {box[0] + 2 * lay.T + reach:.4g} m, or domain.box starting "
            f"at x = {back - lay.T:.4g} m or further left",
            f"behind the paddle's face at x = {p.x:g} m its travel ({reach:.3g} m) and plate "
            f"({lay.T:.3g} m: numerics.wall_layers = {cfg.numerics.wall_layers} spacings) reach "
            f"x = {back:.4g} m, and the wall layers that close the water behind it another "
            f"{lay.T:.3g} m, to x = {back - lay.T:.4g} m; domain.box starts at x = {box[0]:g} m",
        )
    pts = lay.pts
    travel = (pts[:, 0] > back) & (pts[:, 0] < p.x + reach)
    blocked = travel & lay.wall & (pts[:, 1] > floor) & (pts[:, 1] < top)
    if blocked.any():
        q = pts[blocked][0]
        raise ConfigError(
            "paddle.x",
            p.x,
            "a position where no solid stands in the paddle's travel",
            f"a wall particle at ({q[0]:.4g}, {q[1]:.4g}) m",
        )
    under = travel & lay.wall & (pts[:, 1] < floor) & (pts[:, 1] > floor - dx)
    cols = np.unique(np.round(pts[under, 0] / dx - 0.5))
    need = int(round((p.x + reach - back) / dx)) - 1
    if len(cols) < need:
        raise ConfigError(
            "paddle.x",
            p.x,
            f"a position with a floor under the paddle's travel ({back:.4g} to "
            f"{p.x + reach:.4g} m at z = {floor:.4g} m): extend the solid under it",
        )
    return floor, level, parts


def release_speed(lay, water, u0, g, height):
    """Colour top of a case without a paddle: twice the mean speed the water reaches if all the
    potential energy it holds above its settled state (the same particles filling the box from
    the bottom) turns into motion, plus its starting speed; at least 5 % of sqrt(g height). A
    dam break's collapse and a tank's slosh each get their own scale, not the free fall that
    bounds the sound speed."""
    free = lay.pts[lay.in_box & ~lay.solid & ~lay.wall]
    settled = np.sort(free[:, 1])[: len(water)]
    fall = max(0.0, float(water[:, 1].mean() - settled.mean())) if len(settled) == len(water) else 0.0
    return max(u0 + 2.0 * math.sqrt(2.0 * g * fall), 0.05 * math.sqrt(g * height))


class Custom(Scene):
    """Your own case: a 2D domain described in a case file, in metres (docs/cases.md)."""

    NAME = "custom"
    ELEMENTS = ELEMENTS

    SCHEMA = {
        "run": {"end_time": 1.0},
        "numerics": numerics("default", dx=0.02),
        "domain": {
            "box": K([], "[x0, x1, z0, z1] m: the region particles may occupy (a particle leaving it is lost)"),
            "gravity": K(9.81, "acting in -z", "m/s2", POSITIVE),
            "outflow": K([], "[[x0, x1, z0, z1], ...] m: open boxes; water entering one leaves the run"),
            "base_dir": K("", "where a solid's CSV is looked for; \"\": the case file's folder"),
        },
        "paddle": dict(
            PADDLE,
            **IRREGULAR,
            type=K("none", "none | piston | flap: the wave maker", choices=("none", "piston", "flap")),
            x=K(0.0, "the paddle's water-side face at rest; the water behind it is removed", "m"),
            top=K(0.0, "the top of the paddle plate; 0: the top of domain.box", "m"),
        ),
        "absorber": {
            "start": K(0.0, "where the damping zone begins (its strength ramps up from here)", "m"),
            "end": K(0.0, "where it is strongest (beyond, too); start = end: no absorber", "m"),
            "rate": K(10.0, "the strongest velocity relaxation rate", "1/s", POSITIVE),
        },
        "solid": [],
        "water": [],
        "gauge": [],
        "sand": SAND,
        "sediment": with_defaults(SEDIMENT, model=K("bedload", SEDIMENT["model"].doc, choices=("bedload",))),
        "materials": {"water": {"rho0": 1000.0, "viscosity": 1.0e-3}},
        "output": {"frame_interval": 0.04, "probe_interval": 0.01},
    }

    def derive(self, cfg, given):
        """The stroke a wave height asks for at the paddle's depth, which the case's layout gives (a
        resolving step: the values and run.log's line)."""
        p = cfg.paddle
        if p.type == "none" or p.get("wave_height", 0.0) <= 0:
            return {}, []
        col = _parts(cfg)[5].column(p.x)
        return wp.stroke_step(cfg, col[1] - col[0], 0.04) if col is not None else ({}, [])  # none: check says why

    def check(self, cfg):
        box, outflow, solids, waters, gauges, lay, _ = _parts(cfg)
        a, p = cfg.absorber, cfg.paddle
        for key in ("start", "end"):
            if a.start != a.end and not box[0] <= a[key] <= box[1]:
                raise ConfigError(f"absorber.{key}", a[key], f"inside domain.box ({box[0]:g} to {box[1]:g} m)")
        if p.type != "none":
            paddle_site(cfg, lay, box)

    def build(self, cfg):  # noqa: C901 (one branch a part a case file may leave out)
        box, outflow, solids, waters, gauges, lay, sand_site = _parts(cfg)
        num, g = cfg.numerics, cfg.domain.gravity
        dx = num.dx
        h = num.h_factor * dx
        rho0 = cfg.materials.water.rho0
        water = lay.pts[lay.water]
        height = float(water[:, 1].max() - water[:, 1].min()) + dx
        # the fastest the water can go: free fall from its highest point to the lowest solid (or the
        # box's floor) under the box, plus any speed it starts with; it bounds a collapse's, a jet's
        # and a wave crest's speed (a breakwater's water falls into a basin below its own bottom)
        walls = lay.pts[lay.wall]
        lowest = min(float(water[:, 1].min()) - 0.5 * dx, float(walls[:, 1].min()) if len(walls) else np.inf)
        drop = float(water[:, 1].max()) + 0.5 * dx - max(lowest, box[2])
        u0 = float(np.hypot(*lay.velocity[lay.water].T).max()) if lay.water.any() else 0.0
        c0, u_max = sound_speed(cfg, u0 + math.sqrt(2 * g * drop), height, g)
        params = common_params(cfg, c0, g, depth=height)
        p = cfg.paddle
        physics_kw, period, paddle_parts, sand = {}, None, None, None
        if p.type != "none":
            floor, level, paddle_parts = paddle_site(cfg, lay, box)
            if p.absorb:
                paddle_parts[1].x_abs += p.x  # the absorbing gauge stands in front of this paddle
            physics_kw["paddle"] = p.type
            period = wave_period(p)
            if sand_site:
                sand = SandBed(cfg, sand_site, lay, Still(level, rho0, c0, g), 2 * math.pi / period, h)
                physics_kw.update(moving_bed=True, materials_used=["water"])
        water = lay.pts[lay.water]
        ps, top = _particles(lay, dx, h, rho0, c0, g)
        still = level if paddle_parts else float(np.median(top))
        if paddle_parts:
            pts, motion, extra, _ = paddle_parts
            pts = pts + [p.x, 0.0]
            extra["pivot"] = (p.x, floor)
            params.update(extra)
            ps.add(pts, MOVING, 0, wall_density(pts, water, dx, h, rho0, c0, g), rho0 * dx * dx)
        if sand:
            sand.add_particles(ps, num.wall_layers)
            params["bed_stations"] = len(sand.stations)
        a = cfg.absorber
        if a.start != a.end:
            physics_kw["damping"] = (a.start, a.end, a.rate)
        pad = 3 * lay.T + 4 * h
        domain = ((box[0] - pad, box[2] - pad), (box[1] + pad, box[3] + pad))
        wall_side, depth_at = partial(_wall_side, water), partial(_depth_at, lay)
        _warn(cfg, lay, waters, gauges, depth_at, level - floor if paddle_parts else None, period)
        band = tuple(b / p.tp for b in p.band) if paddle_parts and p.spectrum else None
        cg = CaseGauges(gauges, dx, h, g, wall_side, depth_at, band, load_cutoff(c0, height))
        parts = observers(cfg, cg, sand, period, still)
        if paddle_parts and p.absorb:  # the absorbing paddle reads its gauge at the same interval
            parts["control"] = with_control(paddle_parts[1], parts.get("control"))
            parts["persist"] += (paddle_parts[1],)
        if not paddle_parts:
            parts["speed_scale"] = release_speed(lay, water, u0, g, height)
        elif not p.series:  # colour top: twice the linear surface orbital speed at the paddle, as the flume's
            omega, k, _, _, F = linear_wave(cfg, level - floor)
            parts["speed_scale"] = (p.hs if p.spectrum else F * p.stroke) * omega / math.tanh(k * (level - floor))
        margin = lay.T + dx
        zones = [(min(a.start, a.end), max(a.start, a.end), "absorber")] if "damping" in physics_kw else []
        return make_case(
            name=self.NAME,
            particles=ps,
            materials=[dict(name="water", rho0=rho0, viscosity=cfg.materials.water.viscosity, B=tait_B(rho0, c0))],
            domain=domain,
            params=params,
            outflow=tuple((b[0], b[2], b[1], b[3]) for b in outflow),
            physics=physics_from_config(cfg, **physics_kw),
            u_max=u_max,
            view=((box[0] - margin, box[2] - margin), (box[1] + margin, box[3] + margin)),
            marks=[(q["x"], q["label"]) for q in gauges if q["type"] == "surface"],
            zones=zones,
            solid_region=lay.solid_region,
            **parts,
        )


def _warn(cfg, lay, waters, gauges, depth_at, depth, period):
    """The gauges, the water levels as laid and the paddle's waves (depth: the still water's
    over the paddle's floor; None: no paddle) warned about before the run."""
    p = cfg.paddle
    warn_gauges(cfg, gauges, depth_at)
    note = ""
    if depth is not None and p.wave_height and not p.series and not p.spectrum:
        note = (
            f" (paddle.stroke = {p.stroke:.4g} m: Biesel's for paddle.wave_height = {p.wave_height:g} m "
            f"in {depth:.4g} m of water)"
        )
    lay.warn_levels(waters, note)
    if depth is not None and not p.series and not p.spectrum:
        omega, k, _, cgroup, F = linear_wave(cfg, depth)
        warn_case_waves(
            cfg,
            F * p.stroke,
            k,
            depth,
            [q["x"] - p.x for q in gauges if q["type"] == "surface" and depth_at(q["x"]) > 0],
            cgroup,
            period,
            arrival_time,
        )


def _particles(lay, dx, h, rho0, c0, g):
    """The water (hydrostatic in its column under the column's surface) and the walls; returns
    the ParticleSet and each water particle's column surface."""
    water = lay.pts[lay.water]
    col = np.round(water[:, 0] / dx - 0.5).astype(int)
    col -= col.min()
    tops = np.full(col.max() + 1, -np.inf)
    np.maximum.at(tops, col, water[:, 1] + 0.5 * dx)
    top = tops[col]
    ps = ParticleSet()
    ps.add(
        water, FLUID, 0, hydrostatic_density(top - water[:, 1], rho0, c0, g), rho0 * dx * dx, v=lay.velocity[lay.water]
    )
    walls = lay.pts[lay.wall]
    ps.add(walls, WALL, 0, wall_density(walls, water, dx, h, rho0, c0, g), rho0 * dx * dx)
    return ps, top


def _wall_side(water, pts):
    """Unit vector from each point towards the nearest water particle at the start."""
    out = np.zeros_like(pts)
    for k, q in enumerate(pts):
        d = water - q
        n = d[np.argmin(np.hypot(d[:, 0], d[:, 1]))]
        out[k] = n / max(np.hypot(*n), 1e-12)
    return out


def _depth_at(lay, x):
    col = lay.column(x)
    return col[1] - col[0] if col else float("nan")


SCENE = Custom()
main = partial(run_scene, SCENE)
