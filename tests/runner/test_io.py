"""Snapshots ParaView can open, exact restart, signals, kill -9, full disk."""

import json
import os
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import h5py
import numpy as np
import pytest

from tisph import io as tio
from tisph.runner import simulate
from tisph.scenes import dam_break
from tisph.settings.config import tomllib
from tisph.settings.resolved import freeze

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FAST = {"numerics.dx": 0.06, "output.render": False, "output.quiet": True}


def cli(args, cwd, **kw):
    env = dict(os.environ, PYTHONPATH=ROOT)
    return subprocess.Popen(
        [sys.executable, "-m", "tisph.scenes.dam_break", *args],
        cwd=cwd,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        **kw,
    )


def test_snapshots_and_xdmf_are_complete(tmp_path):
    s = simulate(dam_break, dict(FAST, **{"run.end_time": 0.1, "output.snapshot_every": 0.025}), out=str(tmp_path))
    assert s["snapshots"] == 5
    root = ET.parse(tmp_path / "snapshots.xdmf").getroot()
    grids = root.findall(".//Grid[@GridType='Uniform']")
    assert len(grids) == 5
    times = [float(g.find("Time").get("Value")) for g in grids]
    assert times == sorted(times) and times[0] == 0.0 and abs(times[-1] - 0.1) < 0.01
    for g in grids:
        n = int(g.find("Topology").get("NumberOfElements"))
        assert n == s["particles"]
        items = g.findall(".//DataItem")
        names = {a.get("Name") for a in g.findall("Attribute")}
        assert {"velocity", "density", "pressure", "kind", "material", "id"} <= names
        for it in items:
            fname, dset = it.text.split(":")
            dims = tuple(int(d) for d in it.get("Dimensions").split())
            with h5py.File(tmp_path / fname, "r") as f:
                assert f[dset.lstrip("/")].shape == dims
    arrays, attrs = tio.load(tmp_path / "snapshots" / "00004.h5")
    assert arrays["position"].shape == (s["particles"], 2)
    assert attrs["scene"] == "dam_break" and attrs["tisph_version"] and attrs["step"] > 0
    assert abs(attrs["time"] - times[-1]) < 1e-9 and attrs["dt"] > 0
    cfg = tomllib.loads(attrs["config"])
    assert cfg["numerics"]["dx"] == 0.06
    assert np.all(np.diff(arrays["id"]) == 1)  # ordered by particle id


@pytest.mark.slow
def test_restart_matches_uninterrupted_run(tmp_path):
    full = simulate(
        dam_break, dict(FAST, **{"run.end_time": 0.2, "output.snapshot_every": 0.2}), out=str(tmp_path / "full")
    )
    simulate(
        dam_break,
        dict(FAST, **{"run.end_time": 0.1, "output.checkpoint_every": 0.1, "output.snapshot_every": 0.2}),
        out=str(tmp_path / "part"),
    )
    again = simulate(
        dam_break,
        dict(FAST, **{"run.end_time": 0.2, "output.snapshot_every": 0.2}),
        out=str(tmp_path / "part"),
        restart=str(tmp_path / "part" / "checkpoint.h5"),
    )
    assert again["steps"] == full["steps"] and again["sim_time"] == full["sim_time"]
    a, _ = tio.load(tmp_path / "full" / "snapshots" / "00001.h5")
    b, _ = tio.load(tmp_path / "part" / "snapshots" / "00001.h5")
    # The asked bound is 1e-5 relative. The force sums use no atomics: every particle gathers its
    # neighbours in the cell-sorted order, ordered by particle id inside a cell, so the sum order
    # (and every rounding) is the same in both runs; the only atomics are max-reductions for the
    # time step and integer counters, which are exact whatever the order. Hence equality, on any
    # thread count, and the bound holds with room to spare.
    scale = np.abs(a["position"]).max()
    assert np.abs(a["position"] - b["position"]).max() <= 1e-5 * scale
    assert np.array_equal(a["position"], b["position"])
    assert (tmp_path / "full" / "probes.csv").read_text() == (tmp_path / "part" / "probes.csv").read_text()


def test_sigterm_writes_checkpoint_and_restart_finishes(tmp_path):
    out = tmp_path / "o"
    p = cli(
        ["--dx", "0.05", "--end-time", "5", "--no-render", "--out", str(out), "--quiet", "--snapshot-every", "0.01"],
        tmp_path,
    )
    deadline = time.time() + 120
    while not (out / "snapshots" / "00003.h5").exists():
        assert p.poll() is None and time.time() < deadline, p.stderr.read() if p.poll() is not None else "timeout"
        time.sleep(0.2)
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 143, err
    s = json.load(open(out / "summary.json"))
    assert s["status"] == "interrupted" and "--restart" in s["message"]
    arrays, attrs = tio.load(out / "checkpoint.h5")
    assert attrs["kind"] == "tisph checkpoint" and attrs["steps"] == s["steps"]
    t_stop = s["sim_time"]
    r = cli(
        [
            "--dx",
            "0.05",
            "--end-time",
            f"{t_stop + 0.02}",
            "--no-render",
            "--out",
            str(out),
            "--quiet",
            "--snapshot-every",
            "0.01",
            "--restart",
            str(out / "checkpoint.h5"),
        ],
        tmp_path,
    )
    _, err = r.communicate(timeout=300)
    assert r.returncode == 0, err
    s2 = json.load(open(out / "summary.json"))
    assert s2["status"] == "ok" and s2["sim_time"] >= t_stop + 0.02 - 1e-9 and s2["steps"] > s["steps"]


def test_kill_9_leaves_only_complete_files(tmp_path):
    from PIL import Image

    out = tmp_path / "o"
    p = cli(
        [
            "--dx",
            "0.05",
            "--end-time",
            "5",
            "--out",
            str(out),
            "--quiet",
            "--snapshot-every",
            "0.002",
            "--frame-interval",
            "0.004",
            "--checkpoint-every",
            "0.01",
        ],
        tmp_path,
    )
    deadline = time.time() + 120
    while not (out / "snapshots" / "00012.h5").exists():
        assert p.poll() is None and time.time() < deadline
        time.sleep(0.05)
    p.send_signal(signal.SIGKILL)
    p.wait(timeout=60)
    seen = 0
    for root, _, files in os.walk(out):
        for f in files:
            path = os.path.join(root, f)
            if f.startswith("."):  # a temporary name, never a final one
                assert ".part" in f
                continue
            seen += 1
            if f.endswith(".h5"):
                with h5py.File(path, "r") as h:
                    assert len(h.keys()) > 0
            elif f.endswith(".json"):
                json.load(open(path))
            elif f.endswith(".png"):
                Image.open(path).verify()
            elif f.endswith(".xdmf"):
                ET.parse(path)
    assert seen >= 14
    assert not (out / "dam_break.mp4").exists() or (out / "dam_break.mp4").stat().st_size > 0


def test_full_disk_gives_a_clear_error(tmp_path, monkeypatch, capsys):
    import h5py as _h5

    real = _h5.File

    def full(name, mode="r", *a, **k):
        if "w" in mode:
            raise OSError(28, "No space left on device")
        return real(name, mode, *a, **k)

    monkeypatch.setattr(_h5, "File", full)
    from tisph.runner import run_scene

    code = run_scene(
        dam_break, ["--dx", "0.06", "--max-steps", "3", "--no-render", "--quiet", "--out", str(tmp_path / "o")]
    )
    err = capsys.readouterr().err
    assert code == 2
    assert "No space left on device" in err and "snapshots" in err and "Traceback" not in err


@pytest.mark.slow
def test_corrupt_and_foreign_restart_files(tmp_path, capsys):
    from tisph.runner import run_scene

    bad = tmp_path / "garbage.h5"
    bad.write_bytes(b"\x00not hdf5 at all" * 100)
    code = run_scene(
        dam_break, ["--dx", "0.06", "--no-render", "--quiet", "--out", str(tmp_path / "a"), "--restart", str(bad)]
    )
    assert code == 2 and "not a readable tisph HDF5 file" in capsys.readouterr().err
    simulate(dam_break, dict(FAST, **{"run.end_time": 0.01, "output.snapshot_every": 0.01}), out=str(tmp_path / "s"))
    code = run_scene(
        dam_break,
        [
            "--dx",
            "0.06",
            "--no-render",
            "--quiet",
            "--out",
            str(tmp_path / "b"),
            "--restart",
            str(tmp_path / "s" / "snapshots" / "00000.h5"),
        ],
    )
    assert code == 2 and "checkpoint.h5 written by tisph" in capsys.readouterr().err


def test_atomic_write_leaves_nothing_on_failure(tmp_path):
    target = tmp_path / "x.json"
    with pytest.raises(RuntimeError), tio.atomic_path(str(target)) as tmp:
        open(tmp, "w").write("{half")
        raise RuntimeError("crash mid-write")
    assert not target.exists() and os.listdir(tmp_path) == []


def test_kill_9_keeps_probes_and_run_log(tmp_path):
    """probes.csv and run.log are rewritten whole as the run goes: a run killed with -9 leaves
    both readable, with all but its last moments."""
    import signal
    import subprocess
    import sys
    import time as _t

    out = tmp_path / "o"
    p = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "tisph.scenes.dam_break",
            "--dx",
            "0.06",
            "--end-time",
            "30",
            "--no-render",
            "--quiet",
            "--snapshot-every",
            "0",
            "--out",
            str(out),
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        t0 = _t.time()
        rows = []
        while _t.time() - t0 < 120:
            _t.sleep(0.5)
            f = out / "probes.csv"
            if f.exists():
                rows = f.read_text().splitlines()
                if len(rows) > 40:
                    break
        assert len(rows) > 40, "probes.csv never grew"
    finally:
        p.send_signal(signal.SIGKILL)
        p.wait()
    text = (out / "probes.csv").read_text()
    lines = text.splitlines()
    assert lines[0] == "t,front_x,column_h" and text.endswith("\n")
    ts = [float(l.split(",")[0]) for l in lines[1:]]
    assert all(len(l.split(",")) == 3 for l in lines[1:]) and ts == sorted(ts) and len(ts) >= 40
    log = (out / "run.log").read_text()
    assert "# resolved config" in log and "particles" in log
    assert not (out / "summary.json").exists()  # it never finished


def test_snapshots_say_their_units_and_codes_and_the_run_its_disk(tmp_path):
    """Each dataset carries its units, kind and material their codes (also in the XDMF's
    Information for ParaView); the run prints its disk estimate at the start; by default a run
    writes about 50 snapshots on frame times, not one per frame."""
    from tisph.runner.loop import default_snapshot_interval

    s = simulate(dam_break, dict(FAST, **{"run.end_time": 0.05, "output.snapshot_every": 0.025}), out=str(tmp_path))
    with h5py.File(tmp_path / "snapshots" / "00001.h5", "r") as f:
        assert f["pressure"].attrs["units"] == "Pa" and f["position"].attrs["units"] == "m"
        assert f["velocity"].attrs["units"] == "m/s" and f["density"].attrs["units"] == "kg/m3"
        assert "1 wall" in f["kind"].attrs["codes"] and "0 fluid" in f.attrs["kind_codes"]
        assert f["material"].attrs["codes"].startswith("0 water")
    root = ET.parse(tmp_path / "snapshots.xdmf").getroot()
    units = {a.get("Name"): a.find("Information").get("Value") for a in root.iter("Attribute")}
    assert units["pressure"] == "Pa" and units["velocity"] == "m/s"
    log = (tmp_path / "run.log").read_text()
    assert "disk: about" in log and "snapshots" in log
    assert s["snapshots"] == 3
    cfg = freeze({"output": {"frame_interval": 0.04}, "run": {"end_time": 16.0}})
    assert default_snapshot_interval(cfg) == pytest.approx(0.32)  # 50 snapshots over 16 s, on frames
    cfg = freeze({"output": {"frame_interval": 0.05}, "run": {"end_time": 1.0}})
    assert default_snapshot_interval(cfg) == pytest.approx(0.05)  # never finer than the frames
