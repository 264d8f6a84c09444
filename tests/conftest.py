import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)


@pytest.fixture(scope="session", autouse=True)
def taichi_cpu():
    """All tests run on the CPU backend, initialised once per session."""
    from tisph import runtime
    runtime.init("cpu", "f32")
    yield
