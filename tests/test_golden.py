"""Golden states: every scene default and case file, coarse, a fixed number of steps, must end
bit for bit where tests/golden/states.json says (recorded before the engine refactor).

A change that legitimately moves a result re-records the hashes in a commit of its own that
says which cases changed and why: `python -m tests.golden.cases --write`.
"""
import json

import pytest

from tests.golden.cases import CASES, STATES, run

GOLDEN = json.load(open(STATES))


@pytest.mark.parametrize("case_id", [c[0] for c in CASES])
def test_golden_state(case_id):
    want = GOLDEN[case_id]
    got = run(case_id)
    assert got["status"] == "ok"
    assert (got["particles"], got["steps"]) == (want["particles"], want["steps"])
    assert got["probes"] == want["probes"], f"{case_id}: probes.csv differs"
    assert got["state"] == want["state"], (f"{case_id}: final state differs "
                                           f"(sum of x {got['x_sum']!r} against {want['x_sum']!r})")
