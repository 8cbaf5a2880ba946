"""FMI 2.0 co-simulation export (issue 17, part 3): the FMU stepped by fmpy matches the Python model."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pythonfmu", reason="FMU export needs pythonfmu (extra 'fmu')")
fmpy = pytest.importorskip("fmpy", reason="the FMU test needs fmpy (extra 'fmu')")

from rotarydryer.fmu import OUTPUTS, DryerStepper  # noqa: E402

CASE, SETS = "ajayi2011_mmg", {"operating.test": 4}


def test_fmu_matches_python_model_after_feed_step(tmp_path):
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    path = tmp_path / "dryer.fmu"
    res = CliRunner().invoke(app, ["fmu", CASE, "--set", "operating.test=4", "-o", str(path)])
    assert res.exit_code == 0, res.output
    md = fmpy.read_model_description(str(path))
    names = {v.name: v.causality for v in md.modelVariables}
    assert {k for k, c in names.items() if c == "input"} == {"feed_rate", "feed_moisture", "gas_inlet_temperature",
                                                              "rpm"}
    assert {k for k, c in names.items() if c == "output"} == set(OUTPUTS)

    ref = DryerStepper(CASE, SETS)
    f1 = ref.inputs["feed_rate"] * 1.1                      # +10 % feed step at t = 0
    dt, t_end = 600.0, 7200.0
    expected = [dict(ref.outputs)]
    for _ in range(int(t_end / dt)):
        expected.append(ref.step(dt, feed_rate=f1))
    inp = np.array([(0.0, f1)], dtype=[("time", float), ("feed_rate", float)])
    out = fmpy.simulate_fmu(str(path), start_time=0.0, stop_time=t_end, step_size=dt, output_interval=dt,
                            input=inp, output=list(OUTPUTS))
    assert len(out) == len(expected)
    for k in OUTPUTS:
        e = np.array([row[k] for row in expected])
        np.testing.assert_allclose(out[k], e, rtol=1e-6, atol=1e-9 * max(1.0, np.max(np.abs(e))), err_msg=k)
    # the step moved the plant (not a trivially constant comparison)
    assert out["holdup"][-1] > 1.02 * out["holdup"][0]
