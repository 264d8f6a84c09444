"""The stress suite's short version: each case ends as it is expected to (ok, stopped cleanly or
refused, and warned where it should be), with no crash and no leak."""

import csv

import pytest

from tisph.stress import run


@pytest.mark.slow
@pytest.mark.long
def test_stress_quick(tmp_path):
    rows = run(quick=True, out=str(tmp_path), log=lambda *a: None)
    by = {r[0]: r for r in rows}
    assert len(rows) >= 7
    for name, outcome, leaks, rho, wall, expect, verdict in rows:
        assert verdict == "yes", (name, outcome, verdict)
        assert not outcome.startswith("CRASH"), (name, outcome)
        if outcome.startswith("clear error"):
            assert "empty" in name and "no fluid particles" in outcome
            continue
        assert leaks == 0, (name, leaks)
    low_c0 = by["dam break, sound speed 3x too low"][1]
    assert "[warned]" in low_c0 and low_c0.startswith("ok")
    sed = [r for r in rows if r[0].startswith("water over a sediment")][0]
    assert sed[1].startswith("ok") and "interface moved 0." in sed[1]
    tank_row = [r for r in rows if r[0].startswith("still tank")][0]
    assert tank_row[1].startswith("ok") and float(tank_row[3].rstrip("%")) < 1.0
    with open(tmp_path / "stress.csv") as f:
        assert next(csv.reader(f)) == [
            "case",
            "outcome",
            "leaks",
            "max_density_error",
            "wall_time_s",
            "expected",
            "as_expected",
        ]
    assert (tmp_path / "stress.md").read_text().startswith("| case |")
