"""Issue 32 item 3: a 2 h closed-loop control run against the 2 h open-loop dynamics of the same case.

MMG test 4 (the thesis model, regression geometry, as the control tests), a +20 % feed-moisture step
at 10 min, 60 s samples, 120 s dead time, model feed-forward and PI feedback with hand-set FOPDT
models (no identification: the loop alone is timed), against ``ThermalDryer.simulate`` of the same
2 h with the scenario's inputs, and against the closed loop's own input moves replayed open-loop (a
schedule: the plant's transients without the controller). CPU time (``time.process_time``), best of ``REPEATS``, one BLAS
thread; the closed loop's series are saved for ``--compare`` (the "same results to 1e-6" check).

    python benchmarks/bench_issue32_control.py after.npz
    PYTHONPATH=/tmp/before/src python benchmarks/bench_issue32_control.py before.npz
    python benchmarks/bench_issue32_control.py --compare before.npz after.npz
"""

import os
import sys
import time

import numpy as np
from _timing import best_result
from threadpoolctl import threadpool_limits

import rotarydryer
from rotarydryer import Simulation, _jit
from rotarydryer import control as C

REPEATS = 2


def _models():
    return {"gas_inlet_temperature": {k: C.FOPDT(g, 400.0, 300.0) for k, g in
                                      (("product_moisture", -1.2e-4), ("exhaust_temperature", 0.13))},
            "feed_rate": {k: C.FOPDT(g, 400.0, 400.0) for k, g in
                          (("product_moisture", 1.1e-3), ("exhaust_temperature", -2.0))},
            "feed_moisture_dry": {k: C.FOPDT(g, 700.0, 200.0) for k, g in
                                  (("product_moisture", 0.76), ("exhaust_temperature", 110.0))}}


def _replay_schedule(cl):
    """The closed loop's inputs (feed moisture disturbance, gas inlet temperature and feed moves) as an input
    schedule of steps at the samples where they change: the same plant transients without the controller, to
    tell the cost of the moves from the cost of the loop."""
    try:
        from rotarydryer.thermal.schedule import InputSchedule
    except ImportError:
        return None
    t, series = np.asarray(cl.time_s, float), cl.series
    points = {}
    for name, key in (("gas_inlet_temperature", "gas_inlet_temperature_degC"), ("feed_rate", "feed_rate_kg_s"),
                      ("feed_moisture", "feed_moisture_kg_kg")):
        v = np.asarray(series[key], float)
        pts = [(float(t[0]), float(v[0]))]
        for i in range(1, t.size):
            if v[i] != v[i - 1]:
                pts += [(float(t[i]), float(v[i - 1])), (float(t[i]), float(v[i]))]
        points[name] = tuple(pts)
    return InputSchedule(points, source="closed-loop replay")


def best(fn):
    return best_result(fn, REPEATS, clock=time.process_time)


getattr(_jit, "long_runs", lambda: None)()      # many solves: the compiled kernels (the "before" tree: always compiled)


def main(out="control.npz"):
    with threadpool_limits(1):
        d = Simulation("ajayi2011_mmg", {"operating.test": 4, "geometry.method": "ajayi2011_regressions"}).thermal_dryer()
        ss = d.steady_state()
        kw = dict(scenario="feed_moisture_step", magnitude=0.2, t_end_s=7200.0, t_step_s=600.0, models=_models())
        t_cl, cl = best(lambda: C.closed_loop(d, ss, **kw))
        x_new = C._wet_basis(C._dry_basis(d.feed_moisture) * 1.2)
        d2 = C.plant(d, feed_moisture=x_new)
        t_ol, _ = best(lambda: d2.simulate(ss.state, 7200.0, t_eval=np.arange(0.0, 7201.0, 60.0)))
        replay = _replay_schedule(cl)
        t_rp = None
        if replay is not None:      # the "before" tree may lack the schedule runner
            from rotarydryer.thermal.schedule import simulate_schedule
            t_rp, rp = best(lambda: simulate_schedule(d, ss.state, replay, 7200.0, 60.0))
    load = os.getloadavg()[0]
    print(f"{rotarydryer.__file__}: load {load:.2f}; closed loop 2 h {t_cl:.2f} s CPU, open-loop dynamics 2 h "
          f"{t_ol:.3f} s CPU, ratio {t_cl / t_ol:.1f}", flush=True)
    if t_rp is not None:
        print(f"  the closed loop's input moves replayed open-loop (a schedule: {sum(len(v) for v in replay.points.values())} "
              f"points, {rp.restarts} integrations): {t_rp:.2f} s CPU; closed loop / replay {t_cl / t_rp:.2f}", flush=True)
    np.savez(out, **{k: np.asarray(v, float) for k, v in cl.series.items() if k != "fuel_rate_kg_s"})


def compare(a, b):
    a, b = np.load(a), np.load(b)
    for k in a.files:
        x, y = a[k], b[k]
        print(f"{k}: largest absolute difference {float(np.max(np.abs(x - y))):.2g} (scale {float(np.max(np.abs(x))):.3g})")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--compare"]:
        compare(*sys.argv[2:4])
    else:
        main(*sys.argv[1:])
