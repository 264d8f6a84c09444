"""Runs side by side (tisph/runner/pool.py): a kill of the process that holds them, plain or -9,
stops its worker processes too, so no run goes on alone."""

import os
import signal
import subprocess
import sys
import time

import pytest

CODE = (
    "import time\nfrom tisph.runner.pool import run_all\n"
    "run_all([(i, time.sleep, (60,)) for i in range(2)], 2, 1, lambda *a: None)\n"
)


def children(pid):
    out = []
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid and fields[0] != "Z":
                out.append(int(d))
    return out


def alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL], ids=["kill", "kill -9"])
def test_a_killed_pool_leaves_no_worker_running(sig):
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    p = subprocess.Popen([sys.executable, "-c", CODE], cwd=root)
    workers = []
    for _ in range(200):  # the two workers and the resource tracker start
        workers = [c for c in children(p.pid) if "spawn_main" in open(f"/proc/{c}/cmdline").read()]
        if len(workers) == 2:
            break
        time.sleep(0.1)
    assert len(workers) == 2
    time.sleep(1.0)
    p.send_signal(sig)
    p.wait(timeout=30)
    deadline = time.time() + 20
    while any(alive(w) for w in workers) and time.time() < deadline:
        time.sleep(0.2)
    assert not any(alive(w) for w in workers)
