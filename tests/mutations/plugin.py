"""The pytest plugin that applies TISPH_MUTATION before the tests import tisph's physics, and
writes each failed test with its exception type to TISPH_MUTATION_REPORT."""

import os

from . import apply

if os.environ.get("TISPH_MUTATION"):
    apply(os.environ["TISPH_MUTATION"])


def pytest_runtest_makereport(item, call):
    path = os.environ.get("TISPH_MUTATION_REPORT")
    if path and call.excinfo is not None and call.when == "call":
        kind = (
            "assertion"
            if call.excinfo.errisinstance(AssertionError) or call.excinfo.typename == "Failed"
            else call.excinfo.typename
        )
        with open(path, "a") as f:
            f.write(f"{item.nodeid.split('[')[0]}\t{kind}\n")
