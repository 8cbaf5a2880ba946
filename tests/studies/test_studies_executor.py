"""Issue 32: the cross-validation studies run their independent cases through the one executor and
give the serial numbers bit for bit on worker processes."""

from __future__ import annotations

import numpy as np

from rotarydryer.executor import Executor
from rotarydryer.studies import mmg_cross_test as mct
from rotarydryer.studies import predictive_transport as pt
from rotarydryer.studies import song_pilot as sp


def test_song_pilot_predictions_on_worker_processes():
    c = sp.Coefficients(*sp.SONG_PILOT_FITS["all"])
    idx = np.arange(0, 73, 3)
    serial = sp.PilotModel().predict(c, idx)
    pooled = sp.PilotModel(executor=Executor(workers=2)).predict(c, idx)
    for name in ("tau", "holdup", "drag_reduction", "kiln_time", "velocity_ratio", "release_rate", "design_load"):
        np.testing.assert_array_equal(getattr(pooled, name), getattr(serial, name))


def test_mmg_cross_test_rows_on_worker_processes():
    serial = mct.cross_test((4, 5), (4, 5))
    pooled = mct.cross_test((4, 5), (4, 5), executor=Executor(workers=2))
    for i in (4, 5):
        a, b = serial.calibrations[i], pooled.calibrations[i]
        assert (a.velocity_coefficient, a.dispersion_coefficient) == (b.velocity_coefficient, b.dispersion_coefficient)
        for j in (4, 5):
            assert pooled.predictions[i][j].tracer_mean_s == serial.predictions[i][j].tracer_mean_s


def test_predictive_leave_one_out_on_worker_processes():
    serial = pt.mmg_leave_one_out(tests=(4, 5))
    pooled = pt.mmg_leave_one_out(tests=(4, 5), executor=Executor(workers=2))
    assert pooled["calibrations"] == serial["calibrations"]
    assert pooled["summary"] == serial["summary"]
