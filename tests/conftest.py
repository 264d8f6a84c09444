import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)

# the suite's test processes share the cores: one Taichi thread each, not every core each (a
# test's loops are short, where a second thread gains little and two processes of two threads
# each oversubscribe two cores); runs a test starts inherit it
if os.environ.get("PYTEST_XDIST_WORKER") and "TISPH_THREADS" not in os.environ:
    _workers = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1"))
    os.environ["TISPH_THREADS"] = str(max(1, (os.cpu_count() or 1) // _workers))


@pytest.fixture(scope="session", autouse=True)
def taichi_cpu():
    """All tests run on the CPU backend, initialised once per session."""
    from tisph import runtime

    runtime.init("cpu", "f32")
    yield
