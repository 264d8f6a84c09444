"""--live: a window that shows each frame as it is rendered. Without a display it is refused
(exit 2, naming --live and where the frames go instead); under a virtual X server (Xvfb) the
window opens and shows the frame the right way up, and a scene runs to the end with it."""

import ctypes
import ctypes.util
import os
import shutil
import subprocess
import sys
import time

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _env(display):
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    if display:
        env["DISPLAY"] = display
    return env


def test_live_without_a_display_is_refused_before_anything_runs(tmp_path):
    for cmd in (
        [sys.executable, "-m", "tisph.scenes.dam_break", "--live", "--out", str(tmp_path / "run")],
        [sys.executable, "-m", "tisph.view", str(tmp_path), "--all", "--live"],
    ):
        r = subprocess.run(cmd, capture_output=True, text=True, env=_env(""), cwd=ROOT, timeout=120)
        assert r.returncode == 2, r.stderr
        assert "--live" in r.stderr and "display" in r.stderr and "Traceback" not in r.stderr
    assert "tisph.view" in r.stderr or "PNG" in r.stderr
    assert not os.path.exists(tmp_path / "run" / "frames")


def test_live_with_no_render_is_refused(tmp_path):
    r = subprocess.run(
        [sys.executable, "-m", "tisph.scenes.dam_break", "--live", "--no-render", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
    )
    assert r.returncode == 2 and "--no-render" in r.stderr


@pytest.fixture(scope="module")
def xdisplay():
    """A display: the one the tests run under, or a virtual X server started for them."""
    if os.environ.get("DISPLAY"):
        yield os.environ["DISPLAY"]
        return
    xvfb = shutil.which("Xvfb")
    if xvfb is None:
        pytest.skip("no display and no Xvfb (Debian's xvfb package) to make one")
    for n in range(90, 110):
        if not os.path.exists(f"/tmp/.X11-unix/X{n}") and not os.path.exists(f"/tmp/.X{n}-lock"):
            break
    proc = subprocess.Popen(
        [xvfb, f":{n}", "-screen", "0", "1024x768x24", "-nolisten", "tcp"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    for _ in range(100):
        if os.path.exists(f"/tmp/.X11-unix/X{n}"):
            break
        time.sleep(0.05)
    yield f":{n}"
    proc.terminate()
    proc.wait(10)


def _grab(display, w, h):
    """The screen's top-left w x h pixels as RGB, read with Xlib's XGetImage."""
    x11 = ctypes.CDLL(ctypes.util.find_library("X11"))
    x11.XOpenDisplay.restype = ctypes.c_void_p
    x11.XOpenDisplay.argtypes = [ctypes.c_char_p]
    x11.XDefaultRootWindow.restype = ctypes.c_ulong
    x11.XDefaultRootWindow.argtypes = [ctypes.c_void_p]
    x11.XGetImage.restype = ctypes.c_void_p
    x11.XGetImage.argtypes = [
        ctypes.c_void_p,
        ctypes.c_ulong,
        ctypes.c_int,
        ctypes.c_int,
        ctypes.c_uint,
        ctypes.c_uint,
        ctypes.c_ulong,
        ctypes.c_int,
    ]
    x11.XGetPixel.restype = ctypes.c_ulong
    x11.XGetPixel.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_int]
    x11.XDestroyImage.argtypes = [ctypes.c_void_p]
    d = x11.XOpenDisplay(display.encode())
    img = x11.XGetImage(d, x11.XDefaultRootWindow(d), 0, 0, w, h, 0xFFFFFFFF, 2)  # ZPixmap
    out = np.zeros((h, w, 3), np.uint8)
    for y in range(0, h, 4):
        for x in range(0, w, 4):
            p = x11.XGetPixel(img, x, y)
            out[y, x] = ((p >> 16) & 255, (p >> 8) & 255, p & 255)
    x11.XDestroyImage(img)
    return out


SHOW = """
import sys, time
import numpy as np
from tisph.viz.live import LiveWindow, display_problem
assert display_problem() is None, display_problem()
img = np.zeros((120, 200, 3), np.uint8)
img[:60] = (255, 0, 0)
img[60:, :100] = (0, 0, 255)
img[60:, 100:] = (0, 255, 0)
win = LiveWindow("tisph test")
for _ in range(3):
    win.show(img)
    time.sleep(0.1)
print("shown", flush=True)
sys.stdin.readline()
win.close()
"""


def test_live_window_shows_the_frame_the_right_way_up(xdisplay):
    """A frame red on top, blue at the bottom left and green at the bottom right, shown in the
    window (at the screen's corner: Xvfb runs no window manager) reads back the same. The window
    is a fresh process's, as in a run."""
    p = subprocess.Popen(
        [sys.executable, "-c", SHOW],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=_env(xdisplay),
        cwd=ROOT,
    )
    try:
        assert p.stdout.readline().strip() == "shown", p.stderr.read()
        shot = _grab(xdisplay, 200, 120)
    finally:
        p.communicate("\n", timeout=60)
    assert p.returncode == 0
    assert (shot[20, 100] == (255, 0, 0)).all()
    assert (shot[100, 40] == (0, 0, 255)).all()
    assert (shot[100, 160] == (0, 255, 0)).all()


@pytest.mark.slow
def test_scene_runs_to_the_end_with_a_live_window(xdisplay, tmp_path):
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "tisph.scenes.dam_break",
            "--live",
            "--end-time",
            "0.1",
            "--frame-interval",
            "0.02",
            "--quiet",
            "--out",
            str(tmp_path),
        ],
        capture_output=True,
        text=True,
        env=_env(xdisplay),
        cwd=ROOT,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr
    assert len(os.listdir(tmp_path / "frames")) >= 5 and (tmp_path / "dam_break.mp4").exists()
