"""Frames drawn in a process of their own (tisph/runner/frames.py): the same pictures as drawn in
the run's process, the drawer's errors told to the run, and no drawer left behind a killed run."""

import glob
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from tisph.io import OutputError
from tisph.runner import frames

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the drawer is forked on Linux only")


def _run(out, inline):
    env = dict(os.environ, PYTHONPATH=ROOT, TISPH_INLINE_FRAMES="1" if inline else "0")
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "tisph.scenes.dam_break",
            "--end-time",
            "0.1",
            "--dx",
            "0.04",
            "--out",
            str(out),
            "--quiet",
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    return sorted(glob.glob(os.path.join(str(out), "frames", "*.png")))


def test_frames_drawn_beside_the_run_are_the_ones_drawn_in_it(tmp_path):
    import imageio.v2 as imageio

    a, b = _run(tmp_path / "beside", False), _run(tmp_path / "inline", True)
    assert len(a) == len(b) > 3
    for x, y in zip(a, b):
        assert np.array_equal(imageio.imread(x), imageio.imread(y))
    assert os.path.getsize(tmp_path / "beside" / "dam_break.mp4") > 0


class _Broken:
    def live_inputs(self):
        return []

    def frame(self, st, t, live=None):
        raise ValueError("no picture today")


def test_a_drawer_error_stops_the_run_with_it(tmp_path):
    f = frames.Background(_Broken(), str(tmp_path / "m.mp4"), 10)
    f.draw(str(tmp_path / "0.png"), {}, 0.0)
    with pytest.raises(OutputError, match="no picture today"):
        f.sync()
    f.abort()
    assert not os.path.exists(frames.MovieWriter.tmp_path(str(tmp_path / "m.mp4")))


class _Fine:
    def live_inputs(self):
        return []

    def frame(self, st, t, live=None):
        return np.zeros((16, 16, 3), np.uint8)


def test_a_drawer_killed_without_a_word_stops_the_run(tmp_path):
    f = frames.Background(_Fine(), str(tmp_path / "m.mp4"), 10)
    f.sync()
    os.kill(f.proc.pid, signal.SIGKILL)
    f.proc.join()
    with pytest.raises(OutputError, match="stopped"):
        f.sync()
    f.abort()


CHILD = r"""
import sys, time
from tisph.runner import frames
class Slow:
    def live_inputs(self):
        return []
    def frame(self, st, t, live=None):
        time.sleep(60)
f = frames.Background(Slow(), sys.argv[1], 10)
f.draw(sys.argv[2], {}, 0.0)
print(f.proc.pid, flush=True)
time.sleep(60)
"""


def test_the_drawer_dies_with_a_killed_run(tmp_path):
    env = dict(os.environ, PYTHONPATH=ROOT)
    p = subprocess.Popen(
        [sys.executable, "-c", CHILD, str(tmp_path / "m.mp4"), str(tmp_path / "0.png")],
        stdout=subprocess.PIPE,
        text=True,
        env=env,
    )
    pid = int(p.stdout.readline())
    os.kill(p.pid, signal.SIGKILL)
    p.wait()
    for _ in range(50):
        try:
            os.kill(pid, 0)
            with open(f"/proc/{pid}/stat") as s:
                state = s.read().rsplit(")", 1)[1].split()[0]
        except (ProcessLookupError, FileNotFoundError):
            break
        if state == "Z":  # gone but for its exit status
            break
        time.sleep(0.1)
    else:
        pytest.fail(f"the drawer {pid} outlived the run")
