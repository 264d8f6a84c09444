"""The numerical uncertainty of a run: each metric judged over three spacings (Celik et al. 2008),
and `--convergence` on a case file end to end."""

import json
import os

import pytest

from tests.scenes.test_custom import TANK, WATER
from tisph.measure.gci import verdict
from tisph.scenes import custom


def test_a_second_order_metric_gets_its_order_and_limit():
    f = [1.0 + 3.0 * dx**2 for dx in (0.01, 0.015, 0.0225)]
    m = verdict("x", *f, 1.5, 1.5)
    assert m["order"] == pytest.approx(2.0, rel=1e-6) and m["richardson"] == pytest.approx(1.0, rel=1e-9)
    assert m["gci_fine"] == pytest.approx(1.25 * (f[1] - f[0]) / f[0] / (1.5**2 - 1), rel=1e-6)


def test_unequal_ratios_first_order_is_converging_not_stalled():
    # the middle step is the larger: the change grows, yet f = 1 + 2 dx converges at order 1
    f = [1.0 + 2.0 * dx for dx in (0.005, 0.0075, 0.00875)]
    m = verdict("x", *f, 1.5, 0.00875 / 0.0075)
    assert m["order"] == pytest.approx(1.0, rel=1e-6) and m["richardson"] == pytest.approx(1.0, rel=1e-9)
    assert verdict("x", 1.0, 1.2, 1.25, 1.5, 0.00875 / 0.0075)["reason"].startswith("not converging")


@pytest.mark.parametrize(
    "values, reason",
    [((1.0, 1.1, 1.0), "oscillatory"), ((1.0, 1.2, 1.25), "not converging"), ((2.0, 2.0, 2.0), "the same")],
)
def test_no_gci_without_an_asymptotic_range(values, reason):
    m = verdict("wall_force_max", *values, 1.5, 1.5)
    assert m["reason"].startswith(reason) and m["order"] is None
    assert "peak" in m["note"]


def test_convergence_from_the_command_line(tmp_path):
    path = tmp_path / "tank.toml"
    path.write_text(TANK + WATER + '[[gauge]]\ntype = "pressure"\nx = 1.0\nz = 0.2\nlabel = "p"\n')
    out = tmp_path / "out"
    assert (
        custom.main(
            ["--config", str(path), "--out", str(out), "--no-render", "--quiet", "--end-time", "0.05", "--convergence"]
        )
        == 0
    )
    s = json.loads((out / "summary.json").read_text())["convergence"]
    assert s["dx"] == pytest.approx([0.05, 0.075, 0.1125]) and not s["reason"]
    assert "p_mean" in s["metrics"] and len(s["metrics"]["p_mean"]["values"]) == 3
    for f in ("convergence.md", "convergence.csv", "convergence.png"):
        assert os.path.getsize(out / "convergence" / f) > 0
    assert (out / "convergence" / "dx0.075" / "summary.json").exists()


def test_the_validation_page_s_interval_from_three_spacings_seeds_or_none():
    from tisph.bench.uncertainty import interval
    from tisph.bench.validation_cases import CASES_BY_NAME

    slosh = CASES_BY_NAME["Sloshing, first mode (linear theory)"]
    ref = slosh.reference_value
    rows = [dict(dx=dx, value=ref * (1.0 - 0.5 * dx**2)) for dx in (0.0225, 0.015, 0.01)]
    half, words = interval(slosh, rows)
    # second order: GCI = 1.25 |f2 - f1| / f1 / (1.5^2 - 1), on the error (value / reference - 1)
    f1, f2 = rows[2]["value"], rows[1]["value"]
    assert half == pytest.approx(1.25 * abs(f2 - f1) / (1.5**2 - 1) / ref, rel=1e-6) and "order 2.00" in words
    assert interval(slosh, rows[1:])[0] is None and "two spacings" in interval(slosh, rows[1:])[1]
    rows[0]["value"] = rows[2]["value"]  # oscillatory
    assert interval(slosh, rows)[1] == "no GCI over three spacings: oscillatory"
    tunnel = CASES_BY_NAME["Oscillating tunnel ripples (Wiberg & Harris)"]
    ens = dict(n=3, stderr=0.05, values=[0.8, 0.9, 1.0])
    half, words = interval(tunnel, [dict(dx=0.015, value=0.9), dict(dx=0.01, value=0.9, ensemble=ens)])
    assert half == pytest.approx(0.05) and "3 seeds of the bed" in words and "0.8, 0.9, 1" in words
    mao = CASES_BY_NAME["Pipeline scour (Mao 1986)"]
    half, words = interval(mao, [dict(dx=0.0025, value=0.035, ensemble=dict(ens, key="run.seed"))])
    assert "3 seeds of a perturbed start" in words
    half, words = interval(mao, [dict(dx=0.0025, value=0.035)])
    assert half is None and words.startswith("one spacing: no GCI; one run: its spread in docs/sediment.md")
