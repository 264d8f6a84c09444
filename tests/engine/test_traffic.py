"""A step with no host work: steps run in batches with one read of the device a batch
(Solver.step_ahead), and give the state, time and step count of single steps bit for bit;
the run loop's steps that write nothing mostly read nothing (tisph/bench/traffic.py counts)."""

import os

import numpy as np
import pytest

from tisph.bench.traffic import Counter, measure
from tisph.engine.solver import Solver
from tisph.runner import Log, build_case, resolve
from tisph.scenes import dam_break, flume


def _solver(scene, **ov):
    cfg = resolve(scene, overrides=dict({"output.quiet": True}, **ov))
    case = build_case(scene, cfg, Log(os.devnull, True))
    return Solver(case.physics, case.particles, case.materials, case.domain, case.params)


def test_a_batch_of_steps_is_single_steps_bit_for_bit_with_one_transfer():
    one, many = _solver(dam_break, **{"numerics.dx": 0.06}), _solver(dam_break, **{"numerics.dx": 0.06})
    for _ in range(50):
        one.step()
    many.prime()
    c = Counter()
    with c.install():
        many.step_ahead(20)
        launches, transfers = c.total()
    many.step_ahead(30)
    assert (launches, transfers) == (21, 1), (c.launches, c.transfers)  # 20 steps, one read of the log
    assert many.steps == one.steps == 50 and many.time == one.time and many.dt == one.dt
    a, b = one.state(("x", "v", "rho")), many.state(("x", "v", "rho"))
    for k in a:
        assert np.array_equal(a[k], b[k]), k
    with pytest.raises(ValueError, match="1 to"):
        many.step_ahead(many.batch + 1)


FLUME = {
    "numerics.dx": 0.025,
    "geometry.length": 2.0,
    "geometry.damping_length": 0.6,
    "geometry.gauges_wavelengths": [0.5, 1.0],
    "paddle.type": "flap",
}


def test_the_paddles_series_over_a_batch_follows_its_motion():
    """A GPU's path, forced on the CPU: the paddle from a Chebyshev series over each batch gives
    the host-driven run's state to round-off (f32 rounding of the series against that of
    motion(t)), the same steps and time, and the paddle where motion(t) puts it."""
    host, dev = _solver(flume, **FLUME), _solver(flume, **FLUME)
    assert not host.paddle_series and not host.steps_ahead_allowed  # the CPU's default
    dev.paddle_series = True
    assert dev.steps_ahead_allowed
    for _ in range(300):
        host.step()
    dev.prime()
    while dev.steps < 300:
        dev.step_ahead(min(dev.batch, 300 - dev.steps))
    assert dev.time == host.time and dev.steps == host.steps
    d, _ = dev.motion(dev.time)
    assert abs(float(dev.prm[None].pd) - d) <= 1e-6 * abs(d) + 1e-9  # a flap's angle, rad
    a, b = host.state(("x", "v")), dev.state(("x", "v"))
    # measured 1.8e-4 dx and 6e-4 of the top speed; adding the pair terms in another order (the
    # vector lanes against the branch form) moves this flume 5.4e-3 dx and 5.7e-3 over its 300 steps
    assert np.max(np.abs(a["x"] - b["x"])) < 1e-3 * 0.025
    assert np.max(np.abs(a["v"] - b["v"])) < 1e-3 * np.max(np.abs(a["v"]))


def test_a_batch_across_the_ramps_end_follows_it_in_two_pieces():
    """The ramp's end is a kink no one series follows: a batch across it takes one series on each
    side, and the device's paddle is the host's to round-off, with no step alone. A ramp this
    steep (0.15 periods) amplifies the series' f32 rounding to 1.5e-3 dx after 300 steps whether
    the steps across the kink go alone (as they did) or in two pieces (1.8e-3 dx)."""
    from tisph.engine.batch import CHEB, series_fit

    ov = dict(FLUME, **{"paddle.ramp_periods": 0.15})
    host, dev = _solver(flume, **ov), _solver(flume, **ov)
    (end,) = dev.motion.breaks
    assert series_fit(dev.motion, end - 0.01, 0.02)[2 * CHEB + 2] == pytest.approx(0.01)  # where it splits
    dev.paddle_series = True
    for _ in range(300):
        host.step()
    assert host.time > end + 0.01
    dev.prime()
    while dev.steps < 300:
        n = min(dev.batch, 300 - dev.steps)
        assert dev.step_ahead(n) == n  # none alone, across the kink too
    assert dev.time == host.time
    d, _ = dev.motion(dev.time)
    assert abs(float(dev.prm[None].pd) - d) <= 1e-6 * abs(d) + 1e-9
    a, b = host.state(("x", "v")), dev.state(("x", "v"))
    assert np.max(np.abs(a["x"] - b["x"])) < 5e-3 * 0.025
    assert np.max(np.abs(a["v"] - b["v"])) < 3e-3 * np.max(np.abs(a["v"]))


def test_a_batch_no_series_follows_halves_until_one_does():
    """batch.fit_steps: a motion too fast for one series over the batch, or with two kinks in it,
    is followed over half the steps, or a quarter, not one step at a time."""
    import math

    from tisph.engine.batch import fit_steps, series_fit

    def fast(t):
        return math.sin(50.0 * t), 50.0 * math.cos(50.0 * t)

    n, fit = fit_steps(fast, 0.3, 512, 1e-3)
    assert 1 < n < 512 and fit is not None
    assert series_fit(fast, 0.3, 2 * n * 1e-3) is None  # the largest that holds
    kinks = lambda t: (min(t, 0.1) + max(t - 0.2, 0.0), 1.0)  # noqa: E731
    assert series_fit(kinks, 0.05, 64 * 0.004, breaks=(0.1, 0.2)) is None
    assert fit_steps(kinks, 0.05, 64, 0.004, breaks=(0.1, 0.2))[0] == 32  # one kink in half the span
    assert fit_steps(fast, 0.3, 1, 1e-3) == (1, None)


def test_an_absorbing_paddle_steps_one_at_a_time():
    s = _solver(flume, **dict(FLUME, **{"paddle.absorb": True}))
    s.paddle_series = True
    assert not s.steps_ahead_allowed  # its correction integrates call by call
    s.step_ahead(1)
    with pytest.raises(ValueError, match="paddle"):
        s.step_ahead(2)


def test_the_run_loops_quiet_steps_read_nothing():
    """As a GPU runs it: a batch reaches past the next output and its last steps park, so the one
    read is on the step that writes."""
    r = measure("tank", steps=120)
    assert r["quiet_steps"] > 100
    assert r["transfers_quiet"]["max"] == 0, r  # before batches: 1 a step; before parking: 0.11
    assert r["launches_quiet"]["max"] == 1  # the step kernel alone
    assert 0 < r["parked"] < 0.15 * r["steps"], r  # a probe every ten steps, at most one parked after it


def test_the_tunnels_quiet_steps_read_nothing_with_its_drive_on_the_device(capsys):
    """The tunnel's run loop as a GPU runs it: its drive's feedback on the device, no quiet step
    reads the device; on the host (--host-drive, the CPU's way) one step in ten reads the mean
    velocity and the batch's log."""
    from tisph.bench import cli

    dev, host = measure("tunnel", steps=60), measure("tunnel", steps=60, device_drive=False)
    assert dev["transfers_quiet"]["max"] == 0 and dev["launches_quiet"]["max"] == 2, dev  # the step, the control
    assert host["transfers_quiet"]["max"] == 2, host
    with pytest.raises(SystemExit) as e:
        cli.main(["--host-drive"])
    assert e.value.code == 2 and "--host-drive needs --traffic" in capsys.readouterr().err


def test_only_the_held_currents_own_control_leaves_the_host():
    """The run loop skips the case's control only where it is the held current's update that
    the device runs; any other control (a coupled bed's, say) still runs on the host."""
    from types import SimpleNamespace as NS

    from tisph.measure.control import HeldCurrent
    from tisph.runner.loop import Run

    held = HeldCurrent()
    run = lambda control, drive: NS(case=NS(observers=NS(control=control)), solver=NS(drive=drive))  # noqa: E731
    other = lambda s: None  # noqa: E731
    assert Run._host_control(run(held.update, NS(held=held))) is None
    assert Run._host_control(run(other, NS(held=held))) is other
    assert Run._host_control(run(held.update, None)) == held.update  # the CPU: the host runs it
    assert Run._host_control(run(None, NS(held=held))) is None


def test_steps_past_the_time_given_park():
    """A batch given `until` takes the steps single steps take to reach it and parks the rest,
    bit for bit; with Shepard's filter every 3 steps, whose kernel parks with them; a step after
    the health went bad parks."""
    ov = {"numerics.dx": 0.06, "numerics.shepard_every": 3}
    one, many = _solver(dam_break, **ov), _solver(dam_break, **ov)
    one.prime()
    while one.time < 0.03 - 1e-12:
        one.step()
    assert one.steps > 12
    many.prime()
    taken = many.step_ahead(one.steps + 20, until=0.03 - 1e-12)
    assert taken == many.steps == one.steps and many.time == one.time and many.dt == one.dt
    a, b = one.state(("x", "v", "rho")), many.state(("x", "v", "rho"))
    for k in a:
        assert np.array_equal(a[k], b[k]), k
    many.stats[None].bad_code = 1
    assert many.step_ahead(5) == 1 and many.health == 1
    many.health = 0
    assert many.read_health() == 1  # the health's own slot, past the host's batch of 64
    assert many.batch == 64 < many.stepper.slot_health


def test_a_run_that_parks_writes_what_one_that_does_not_writes(tmp_path):
    """The run loop with parking (a GPU's) and without (the CPU's): the same probes and end state."""
    from tisph.runner import Run

    ends = []
    for park in (False, True):
        out = str(tmp_path / f"park_{park}")
        ov = {"numerics.dx": 0.06, "run.end_time": 0.15, "output.probe_interval": 0.01, "output.dir": out}
        cfg = resolve(dam_break, overrides=dict(ov, **{"output.quiet": True}))
        log = Log(os.path.join(out, "run.log"), True)
        case = build_case(dam_break, cfg, log)
        case.params["park"] = park
        run = Run(case, cfg, out, log, dam_break.SCENE.NAME)
        run.arch = "cpu"
        run.execute()
        s = run.solver
        assert s.park == park
        with open(os.path.join(out, "probes.csv"), "rb") as f:
            ends.append((f.read(), s.steps, s.time, s.state(("x", "v", "rho"))))
    (pa, na, ta, xa), (pb, nb, tb, xb) = ends
    assert pa == pb and na == nb and ta == tb
    for k in xa:
        assert np.array_equal(xa[k], xb[k]), k


def _tunnel(device):
    """The tunnel's particle bed at dx 0.02, its drive's feedback run by the host (the CPU's
    default) or, forced as a GPU runs it, by the device; and the case's HeldCurrent."""
    from tisph.scenes import tunnel

    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    cfg = resolve(tunnel, os.path.join(root, "scenes", "tunnel_bingham.toml"), {"numerics.dx": 0.02})
    case = build_case(tunnel, cfg, Log(os.devnull, True))
    if device:
        case.params["drive_series"] = True
    s = Solver(case.physics, case.particles, case.materials, case.domain, case.params)
    return s, case.params["held_current"]


def test_a_held_current_runs_on_the_device_with_no_read_and_restarts():
    """The tunnel's drive: its feedback on the device (engine/drive.py) follows the host's to
    round-off over 400 steps (40 control steps, the ramp's end not yet reached); a batch of 40
    steps with 4 control steps in it reads the device once, at its end, besides the law's series
    uploaded at its start; its state saved as a checkpoint saves it (sync, the observers' pickle)
    and loaded into a fresh solver (load) continues as the run that was not stopped, bit for bit."""
    from tisph.runner.outputs import observer_state, restore_observers

    host, hh = _tunnel(False)
    dev, dh = _tunnel(True)
    assert host.drive is None and dev.drive is not None
    host.prime()
    while host.steps < 400:
        host.step_ahead(10)
        hh.update(host)
    dev.prime()
    c = Counter()
    with c.install():
        assert dev.step_ahead(40) == 40
        launches, transfers = c.total()
    assert (launches, transfers) == (46, 2), (c.launches, c.transfers)  # 40 steps, 4 controls, upload and read
    while dev.steps < 200:
        dev.step_ahead(40)
    assert dev.drive.stale and dh.ctl.t == 0.0  # the host's copy untouched until something reads it
    arrays, scal = dev.raw_state()
    dev.sync_drive()
    assert dh.ctl.t == pytest.approx(dev.time, rel=1e-7)  # step 200 was a control step
    blob = observer_state((dh.ctl,))
    while dev.steps < 400:
        dev.step_ahead(40)
    dev.sync_drive()
    assert dev.steps == host.steps and dev.time == pytest.approx(host.time, rel=1e-7)
    assert dh.ctl.t == pytest.approx(hh.ctl.t, rel=1e-7)
    # measured 5e-7 of the drive and 1.2e-5 of the integral
    assert dh.ctl.value == pytest.approx(hh.ctl.value, rel=1e-5)
    assert dh.ctl.integral == pytest.approx(hh.ctl.integral, rel=1e-4)
    assert float(dev.prm[None].drive[0]) == pytest.approx(dh.ctl.value, rel=1e-6)
    a, b = host.state(("x", "v")), dev.state(("x", "v", "rho"))
    assert np.max(np.abs(a["x"] - b["x"])) < 1e-4 * 0.02
    assert np.max(np.abs(a["v"] - b["v"])) < 1e-2 * np.max(np.abs(a["v"]))
    two, th = _tunnel(True)
    two.load_raw_state(arrays, scal)
    restore_observers((th.ctl,), blob)
    two.load_drive()
    while two.steps < 400:
        two.step_ahead(40)
    two.sync_drive()
    assert vars(th.ctl) == vars(dh.ctl) and two.time == dev.time
    c = two.state(("x", "v", "rho"))
    for k in c:
        assert np.array_equal(b[k], c[k]), k
