"""Stress suite: cases that break weaker solvers. `python -m tisph.stress [--quick] [--out DIR]`.

Each case must end ok with no leak, or stop cleanly with a message (exit code 3 from the CLI),
or be refused with a clear error. Writes OUT/stress.csv and OUT/stress.md with one row a case:
case, outcome, leaks, max density error, wall time.
"""

import argparse
import os
import sys
import time

import numpy as np

from .case import make_case
from .io import OutputError, ensure_dir, write_csv, write_text
from .particles import FLUID, WALL, ParticleSet, box_walls, tait_B
from .runner import common_params, simulate, sound_speed
from .scenes import dam_break, tank
from .settings.config import ConfigError, physics_from_config


def _variant(base, name, build):
    """A scene with another build(cfg), so a case runs through the ordinary path."""
    cls = type(type(base).__name__ + "Variant", (type(base),), {"NAME": name, "build": lambda self, cfg: build(cfg)})
    return cls()


def _single_particle(cfg):
    """One water particle dropped 0.2 m onto the floor of a tank."""
    dx = cfg.numerics.dx
    rho0 = cfg.materials.water.rho0
    c0, u = sound_speed(cfg, np.sqrt(2 * 9.81 * 0.3))
    ps = ParticleSet()
    ps.add([[0.25, 0.2]], FLUID, 0, rho0, rho0 * dx * dx)
    ps.add(box_walls(0.0, 0.0, 0.5, 0.5, dx, cfg.numerics.wall_layers), WALL, 0, rho0, rho0 * dx * dx)
    mats = [dict(name="water", rho0=rho0, viscosity=1e-3, B=tait_B(rho0, c0))]
    return make_case(
        name="single_particle",
        particles=ps,
        materials=mats,
        domain=((-0.2, -0.2), (0.7, 0.8)),
        params=common_params(cfg, c0, 9.81, 0.3),
        physics=physics_from_config(cfg),
        view=((-0.1, -0.1), (0.6, 0.6)),
        u_max=u,
        container=(0.0, 0.0, 0.5, np.inf),
    )


def _empty(cfg):
    case = tank.SCENE.build(cfg)
    keep = case.particles.kind != FLUID
    ps = ParticleSet()
    ps.add(case.particles.x[keep], WALL, 0, case.particles.rho[keep], case.particles.m[keep])
    case.model.particles = ps
    return case


def cases(quick):
    """(name, scene, overrides, what is expected in words, the outcomes allowed): an outcome is
    ok, stopped (an instability caught with its message) or refused (a clear input error), with
    +warned where the run warned."""
    T = lambda full, short: short if quick else full
    res = (0.06,) if quick else (0.06, 0.04, 0.03)
    out = [
        (
            f"still tank, {T(20.0, 2.0):g} s",
            tank,
            {"run.end_time": T(20.0, 2.0)},
            "no leak, peak speed < 1 % sqrt(gH), density within 1 %",
            ("ok",),
        )
    ]
    for dx in res:
        out.append(
            (
                f"dam break to {T(5.0, 1.0):g} s, dx = {dx}",
                dam_break,
                {"numerics.dx": dx, "run.end_time": T(5.0, 1.0)},
                "no leak, stays stable",
                ("ok",),
            )
        )
    out += [
        # in the short run the low sound speed is warned about and the run stays stable; over
        # 2 s it may be caught as unstable, with its message
        (
            "dam break, sound speed 3x too low",
            dam_break,
            {"numerics.dx": 0.06, "numerics.c0_factor": 10.0 / 3.0, "run.end_time": T(2.0, 0.6)},
            "warned; stable or stops cleanly",
            T(("ok+warned", "stopped+warned"), ("ok+warned",)),
        ),
        (
            "long thin column (5 particles wide)",
            dam_break,
            {
                "numerics.dx": 0.02,
                "geometry.column_width": 0.1,
                "geometry.column_height": 2.0,
                "run.end_time": T(2.0, 0.5),
            },
            "no leak, stays stable",
            ("ok",),
        ),
        (
            "single particle dropped on the floor",
            _variant(tank.SCENE, "single_particle", _single_particle),
            {"run.end_time": T(2.0, 1.0), "numerics.dx": 0.02},
            "lands, no leak",
            ("ok",),
        ),
        ("empty fluid set", _variant(tank.SCENE, "empty", _empty), {}, "refused with a clear error", ("refused",)),
        (
            f"water over a sediment layer (1950 kg/m3) at rest, {T(20.0, 2.0):g} s",
            tank,
            {"geometry.sediment_depth": 0.2, "run.end_time": T(20.0, 2.0)},
            "no leak, interface moves < dx, peak speed < 1 % sqrt(gH)",
            ("ok",),
        ),
    ]
    return out


def run(quick=False, out="renders/stress", log=print):
    ensure_dir(out)
    rows = []
    for name, scene, ov, expect, allowed in cases(quick):
        o = {"output.render": False, "output.quiet": True, "output.snapshot_every": 0.0}
        o.update(ov)
        slug = "".join(c if c.isalnum() else "_" for c in name)[:40]
        t0 = time.perf_counter()
        try:
            s = simulate(scene, o, out=os.path.join(out, slug))
            code = "ok" if s["status"] == "ok" else "stopped"
            outcome = s["status"] if s["status"] == "ok" else f"stopped cleanly ({s['status']}): {s['message'][:90]}"
            if s.get("warnings"):
                outcome += " [warned]"
                code += "+warned"
            leaks = s["leaked_particles"] + s["crossed_wall"]
            rho = f"{s['max_density_error']:.2%}"
            extra = s["metrics"].get("speed_ratio")
            if extra is not None:
                outcome += f", peak speed {extra:.2%} of sqrt(gH)"
            moved = s["metrics"].get("interface_displacement_over_dx")
            if moved is not None:
                outcome += f", interface moved {moved:.2f} dx"
        except (ConfigError, OutputError) as e:
            code, outcome, leaks, rho = "refused", f"clear error: {e}", "", ""
        except Exception as e:  # a crash is a failed stress case, reported as such
            first = (str(e).strip().splitlines() or [""])[0][:120]
            code, outcome, leaks, rho = "crash", f"CRASH {type(e).__name__}: {first}", "", ""
        wall = time.perf_counter() - t0
        verdict = "yes" if code in allowed else f"NO ({code}; expected {' or '.join(allowed)})"
        rows.append((name, outcome, leaks, rho, f"{wall:.1f}", expect, verdict))
        log(f"{name}: {outcome} (leaks {leaks}, max density error {rho}, {wall:.1f} s)")
    header = ("case", "outcome", "leaks", "max_density_error", "wall_time_s", "expected", "as_expected")
    write_csv(os.path.join(out, "stress.csv"), header, rows)
    md = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    md += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    write_text(os.path.join(out, "stress.md"), "\n".join(md) + "\n")
    return rows


def main(argv=None):
    p = argparse.ArgumentParser(
        prog="python -m tisph.stress", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--quick", action="store_true", help="short versions of every case (about a minute)")
    p.add_argument("--out", default="renders/stress", help="output folder (default renders/stress)")
    a = p.parse_args(argv)
    from . import runtime

    runtime.init("cpu", "f32")
    rows = run(a.quick, a.out)
    with open(os.path.join(a.out, "stress.md")) as f:
        print(f.read())
    bad = [r for r in rows if r[1].startswith("CRASH") or (isinstance(r[2], int) and r[2] > 0)]
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
