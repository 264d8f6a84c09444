"""`python -m tisph.bench`: the options, and which benchmark each runs (the run-time-against-
error ladder unless another is named)."""

import argparse
import os

from . import (
    against,
    gci_examples,
    ladder,
    lanes,
    mao_held,
    ripple_sweep,
    scheme_costs,
    shedding,
    speed,
    standing,
    traffic,
    validate,
)
from .common import PEERS, peers
from .ladder import __doc__ as LADDER_DOC


def _peers(text):
    names = tuple(n.strip() for n in text.split(",") if n.strip())
    bad = [n for n in names if n not in PEERS]
    if bad or not names:
        raise argparse.ArgumentTypeError(f"{text!r}: peers are {', '.join(PEERS)} (comma-separated)")
    return names


def table_options(p):
    """The validation table's and the schemes' options."""
    p.add_argument(
        "--validate",
        action="store_true",
        help="run every validation case and write docs/validation.md, its figures and the README's "
        "table (tisph/bench/validate.py; with --quick: coarse, short versions)",
    )
    p.add_argument(
        "--schemes",
        action="store_true",
        help="run time against error by numerics scheme: four validation cases at two or three spacings "
        "under five schemes (tisph/bench/scheme_costs.py; about 25 minutes on two cores)",
    )
    p.add_argument(
        "--jobs",
        type=int,
        default=0,
        metavar="N",
        help="with --validate or --schemes: runs at a time, each in a process of its own on cores / N CPU "
        "threads (default 0: one a core; 1: one after another on every core)",
    )
    p.add_argument(
        "--resume",
        action="store_true",
        help="with --validate: take a run whose summary.json under --out ended well as run (its wall "
        "time from it) instead of running it again",
    )
    p.add_argument("--docs", help="with --validate: the folder of validation.md (default the tree's docs/)")
    p.add_argument("--readme", help="with --validate: the README whose table to fill (default the tree's; '' none)")


def make_parser():
    """Every benchmark's options (which benchmark each runs: main)."""
    p = argparse.ArgumentParser(
        prog="python -m tisph.bench", description=LADDER_DOC, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--quick", action="store_true", help="coarse ladders and short runs (about 5 minutes)")
    _peer_options(p)
    _run_options(p)
    _speed_options(p)
    _case_bench_options(p)
    table_options(p)
    p.add_argument(
        "--dry-run",
        action="store_true",
        help="exercise every code path in seconds: one tiny case, tiny scaling, no profile (for tests)",
    )
    return p


def _peer_options(p):
    """The peers' codes beside ours (bench/peers/)."""
    p.add_argument(
        "--peer",
        type=_peers,
        default=(),
        metavar="pysph,dualsphysics",
        help="also run these codes' dam break beside ours (with --speed: all three at dp 0.03 and 0.015, back to back)",
    )
    p.add_argument(
        "--peer-ladder",
        action="store_true",
        help="with --speed: tisph and the peers (--peer, default both) on the dam break at dp 0.06, 0.04, "
        "0.03, 0.02 and 0.015, all to 0.7 s: each code's front error against its wall time "
        "(OUT/dambreak_codes.png) and tisph's time to each peer run's error",
    )
    p.add_argument(
        "--peer-venv", help="PySPH's virtual environment (default ~/.cache/tisph/peers/pysph-venv; made if absent)"
    )
    p.add_argument(
        "--dualsphysics",
        metavar="CLONE",
        help="a git clone of DualSPHysics to build its v5.0 CPU solver from, once, into "
        "~/.cache/tisph/peers (needed until it is built)",
    )


def _run_options(p):
    """Where the runs go, on what, and which cases."""
    p.add_argument(
        "--arch",
        choices=["cpu", "gpu"],
        default="cpu",
        help="with --speed: gpu runs the tank ladder on CUDA, Vulkan or Metal, on the CPU with a warning "
        "where none is present",
    )
    p.add_argument(
        "--out",
        help="where the runs and the report go (default renders/bench, renders/validate "
        "with --validate; a --validate with --out or --quick writes its page and "
        "figures there too, and leaves docs/ and the README alone)",
    )
    p.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run the ladders on this Dask scheduler (tcp://host:8786), the path tisph.sweep takes; "
        "timings then share the cluster's cores",
    )
    p.add_argument("--only", nargs="*", help="run only the cases whose name contains one of these words")
    p.add_argument("--no-scaling", action="store_true", help="skip the scaling, specialisation and profile parts")


def _speed_options(p):
    """--speed and --traffic, and their options."""
    p.add_argument(
        "--speed",
        action="store_true",
        help="engine speed only (tisph/bench/speed.py): particle-steps/s from 3.4e3 to 6.5e5 particles, compile",
    )
    p.add_argument(
        "--traffic",
        action="store_true",
        help="kernel launches and host-device transfers a step, one golden case a scene, in the run loop "
        "(tisph/bench/traffic.py; from a source checkout)",
    )
    p.add_argument(
        "--host-drive",
        action="store_true",
        help="with --traffic: a held current's feedback (the tunnel's, the pipeline's) on the host, as the CPU "
        "runs it, not on the device",
    )
    p.add_argument(
        "--lanes",
        action="store_true",
        help="the pair loop's terms in the CPU's vector lanes against the engine's branch form "
        "(tisph/bench/lanes.py; a minute)",
    )
    p.add_argument(
        "--sizes",
        type=lambda t: int(float(t)),
        nargs="+",
        metavar="N",
        help="with --speed: the dam break and the flume at about N particles each (1e4 to 1e6: the GPU "
        "check, with --arch gpu)",
    )
    p.add_argument(
        "--against",
        metavar="REV",
        help="with --speed: the same runs on this git revision, back to back; with --validate and --only: "
        "those validation cases run whole on both trees, the time to each one's error (tisph/bench/against.py)",
    )
    p.add_argument(
        "--repeats", type=int, default=3, help="with --speed or --validate --against: runs (pairs) per case (default 3)"
    )
    p.add_argument(
        "--threads",
        type=int,
        help="with --speed: Taichi's CPU threads in every run (default all cores; "
        "1 measured 4 %% run-to-run spread here against 10 %% on two)",
    )


def _case_bench_options(p):
    """The case benches (--shedding, --mao-held, --ripples, --waves, --standing, --convergence) and their options."""
    p.add_argument(
        "--shedding",
        action="store_true",
        help="vortex shedding behind a pipe above a fixed bed against the gap (tisph/bench/shedding.py)",
    )
    p.add_argument(
        "--mao-held",
        action="store_true",
        help="the pipeline case over Mao's measured beds held still: does the flow erode them where his "
        "did? (tisph/bench/mao_held.py)",
    )
    p.add_argument("--gaps", type=float, nargs="*", help="with --shedding: gaps in pipe diameters (default 0.5 1 2)")
    p.add_argument(
        "--live-bed",
        action="store_true",
        help="with --shedding: the case file as written, its bed scouring, the wake judged over each 2 s of flow",
    )
    p.add_argument(
        "--times",
        type=float,
        nargs="*",
        choices=[11.0, 18.0, 25.0],
        help="with --mao-held: Mao's profiles to hold (default 11 18 25)",
    )
    p.add_argument(
        "--dx",
        type=float,
        help="with --shedding or --mao-held: particle spacing (default the case "
        "file's, D/20); with --waves: one dx in place of the ladder; with --validate --against: the "
        "spacing to run at (default each case's reported one)",
    )
    p.add_argument(
        "--end-time",
        type=float,
        help="with --shedding, --mao-held or --waves: seconds of flow (default 4; 2.5 held; 9.6 waves)",
    )
    p.add_argument(
        "--config",
        help="with --shedding or --mao-held: the pipeline case file whose current and "
        "numerics it runs (default scenes/pipeline_scour_mao.toml)",
    )
    p.add_argument(
        "--ripples",
        action="store_true",
        help="the tunnel's ripples against the orbital diameter, 15 cases through the Dask sweep "
        "(tisph/bench/ripple_sweep.py; about an hour on two cores)",
    )
    p.add_argument(
        "--waves",
        action="store_true",
        help="the default flume against Biesel, tisph at H/dx = 3, 5, 8, 12 and DualSPHysics beside it, "
        "back to back (tisph/bench/peers/flume_codes.py; about an hour on two cores)",
    )
    p.add_argument(
        "--standing",
        action="store_true",
        help="a standing wave in a closed tank: the height the flume's numerics take per period, with "
        "each density diffusion (tisph/bench/standing.py; --dx, --end-time in periods)",
    )
    p.add_argument(
        "--convergence",
        action="store_true",
        help="the breakwater's overtopping and the seawall's peak force at three resolutions, with the "
        "observed order and Roache's GCI (tisph/bench/gci_examples.py; about an hour on two cores)",
    )
    p.add_argument(
        "--peer-finest",
        type=float,
        default=0.0125,
        help="with --waves: the finest dp DualSPHysics runs at (default 0.0125, H/dx = 5; at 0.0075 its two "
        "runs take about two hours)",
    )


def main(argv=None):  # noqa: C901 (one branch a bench the command line names)
    p = make_parser()
    a = p.parse_args(argv)
    a.out_given = a.out is not None
    a.out = a.out or os.path.join("renders", "validate" if a.validate else "bench")
    if a.ripples:
        return ripple_sweep.main(a)
    if a.waves:
        return peers("flume_codes").main(a)
    if a.standing:
        return standing.main(a)
    if a.convergence:
        return gci_examples.main(a)
    if a.jobs < 0:
        p.error(f"--jobs {a.jobs}: at least 0 (0: one a core)")
    if a.validate:
        if a.against:
            if not a.only:
                p.error("--validate --against needs --only: the cases to time (a word of each one's name)")
            if a.quick:
                p.error("--validate --against runs each case whole: --quick does not apply")
            return against.main(a)
        return validate.main(a)
    if a.schemes:
        return scheme_costs.main(a)
    if a.jobs:
        p.error("--jobs needs --validate or --schemes")
    if a.docs is not None or a.readme is not None:
        p.error("--docs and --readme need --validate")
    if a.speed:
        return speed.main(a)
    if a.traffic:
        return traffic.main(a)
    if a.host_drive:
        p.error("--host-drive needs --traffic")
    if a.lanes:
        return lanes.main(a)
    if a.against:
        p.error("--against needs --speed")
    if a.sizes:
        p.error("--sizes needs --speed")
    if a.shedding:
        if a.dry_run:
            a.gaps, a.dx, a.end_time = a.gaps or [2.0], a.dx or 0.006, a.end_time or 0.8
        return shedding.main(a)
    if a.mao_held:
        if a.dry_run:
            a.times, a.dx, a.end_time = a.times or [18.0], a.dx or 0.006, a.end_time or 0.3
        return mao_held.main(a)
    if a.live_bed:
        p.error("--live-bed needs --shedding")
    for name in ("gaps", "times", "dx", "end_time", "config"):
        if getattr(a, name) is not None:
            p.error(
                f"--{name.replace('_', '-')} needs --shedding, --mao-held (or --waves, --standing for --dx, --end-time)"
            )
    return ladder.run(a)
