"""Golden states: every scene default and case file, coarse, a fixed number of steps, must end
bit for bit where tests/golden/states.json says. Each case protects the modules it compiles
(listed in states.json); a failure names them and says which fields and probe columns moved and
by how much, so round-off (a relative change near 1e-7 in f32) is told from a broken term.

A change that legitimately moves a result re-records the hashes in a commit of its own that
says which cases changed and why: `python -m tests.golden.cases --write`.
"""

import json

import pytest

from tests.golden.cases import CASES, STATES, moved, run

GOLDEN = json.load(open(STATES))


def covering_cases():
    """The fewest cases that together compile every module any case compiles (greedy, the
    smaller case first on a tie): the quick subset runs these, the whole suite all of them."""
    left = {m for v in GOLDEN.values() for m in v["modules"]}
    chosen = []
    while left:
        best = max(
            GOLDEN, key=lambda k: (len(left & set(GOLDEN[k]["modules"])), -GOLDEN[k]["particles"] * GOLDEN[k]["steps"])
        )
        chosen.append(best)
        left -= set(GOLDEN[best]["modules"])
    return chosen


QUICK = covering_cases()


@pytest.mark.parametrize(
    "case_id", [c[0] if c[0] in QUICK else pytest.param(c[0], marks=pytest.mark.slow) for c in CASES]
)
def test_golden_state(case_id):
    want = GOLDEN[case_id]
    got = run(case_id)
    assert got["status"] == "ok"
    assert (got["particles"], got["steps"]) == (want["particles"], want["steps"])
    # a case that stops compiling a module stops protecting it, even if its numbers held
    assert sorted(got["modules"]) == sorted(want["modules"]), (got["modules"], want["modules"])
    if got["probes"] != want["probes"] or got["state"] != want["state"]:
        what = "final state" if got["state"] != want["state"] else "probes.csv"
        pytest.fail(
            f"{case_id}: {what} differs from the recorded one. The case protects the modules "
            f"{', '.join(want['modules'])}. What moved:\n  " + "\n  ".join(moved(want, got))
        )


def test_every_registered_scene_has_a_golden_case():
    """The registry is the one list of scenes: each has its default or a case file protected here."""
    from tisph import registry as scenes

    covered = {module for _, module, _, _ in CASES}
    assert set(scenes.REGISTRY.values()) <= covered, set(scenes.REGISTRY.values()) - covered
