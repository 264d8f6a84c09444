"""A run that goes unstable stops with a message and leaves its last healthy state readable."""
import json
import re

import numpy as np

from tisph import io as tio
from tisph.runner import run_scene
from tisph.scenes import dam_break


def test_instability_is_detected_reported_and_saved(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text("[numerics]\ncfl = 1.0\n")   # five times the stable CFL number
    out = tmp_path / "o"
    code = run_scene(dam_break, ["--config", str(cfg), "--dx", "0.06", "--out", str(out), "--quiet",
                                 "--snapshot-every", "0.01"])
    err = capsys.readouterr().err
    assert code == 3
    msg = [l for l in err.splitlines() if l.startswith("unstable at step")][0]
    assert re.search(r"unstable at step \d+, t = [0-9.e-]+ s: .+; particle \d+ \(fluid\) at x = \(", msg)
    assert "rho = " in msg and "Likely cause:" in msg
    s = json.load(open(out / "summary.json"))
    assert s["status"] == "unstable" and s["message"] == msg
    arrays, attrs = tio.load(out / "snapshots" / "last_good.h5")
    assert attrs["step"] < s["steps"] and attrs["step"] % 10 == 0
    for k in ("position", "velocity", "density", "pressure"):
        assert np.all(np.isfinite(arrays[k]))
    rho = arrays["density"][arrays["kind"] == 0]
    assert np.abs(rho / 1000 - 1).max() < 0.3
    assert (out / "probes.csv").read_text().count("\n") >= 2
