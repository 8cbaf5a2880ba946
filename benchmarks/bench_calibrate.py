"""Issue 28: ``rotarydryer calibrate ajayi2011_mmg`` over the six tracer tests and the thermal data.

Reports wall and CPU time, evaluations and solves of

1. the per-test transport calibration (u_s and D of tests 1-6, Test 3's fouling; E(t) and MRT of each),
2. the shared heat-and-mass calibration (area scale, discharge-cooling NTU, a gas flow per test; exhaust,
   product moisture and temperature of tests 3-6),

and, as a same-run ratio, the CPU of one coupled solve inside the calibration against a warm coupled
solve of the same test (``Simulation(...).steady_state(warm=...)`` on a parameter change, the sweep's
way: one heat-and-mass model, warm-started). Never a pass/fail test.

Run: ``python benchmarks/bench_calibrate.py [repeats]`` (prints a Markdown table).
"""

from __future__ import annotations

import sys
import time
import warnings

from rotarydryer import Simulation
from rotarydryer.estimation.calibrate import calibrate

CASE = "ajayi2011_mmg"
THERMAL = ["thermal.area_scale", "tests.*.gas_flow", "thermal.discharge_cooling_ntu"]
THERMAL_RESPONSES = ["gas_outlet_temperature", "product_moisture", "product_temperature"]


def timed(fn):
    w, c = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w, time.process_time() - c


def warm_solve_cpu(repeat: int) -> float:
    """Median CPU (s) of a warm coupled solve of Test 4 after a 1 % change of the area scale."""
    base = {"operating.test": 4}
    src = Simulation(CASE, base)
    warm = src.steady_state().warm_data()
    scale = src.case.thermal.area_scale
    out = []
    for i in range(repeat):
        sim = Simulation(CASE, {**base, "thermal.area_scale": scale * (1.0 + 0.01 * (i + 1))})
        t = time.process_time()
        sim.steady_state(warm=warm)
        out.append(time.process_time() - t)
    out.sort()
    return out[len(out) // 2]


def main(repeat: int = 7) -> str:
    warnings.simplefilter("ignore")
    rows = []
    tr, w1, c1 = timed(lambda: calibrate(CASE, ["tests.*.solids_velocity", "tests.*.dispersion", "tests.3.fouling"],
                                         tests=[1, 2, 3, 4, 5, 6], responses=["tracer", "mrt"]))
    rows.append(("transport, 6 tracer tests (13 parameters)", w1, c1, tr.fit.n_evaluations, tr.n_solves))
    th, w2, c2 = timed(lambda: calibrate(CASE, THERMAL, tests=[3, 4, 5, 6], responses=THERMAL_RESPONSES))
    rows.append(("heat and mass, tests 3-6 (6 parameters)", w2, c2, th.fit.n_evaluations, th.n_solves))
    warm = warm_solve_cpu(repeat)
    lines = ["| calibration | wall s | CPU s | evaluations | solves | CPU per solve ms |", "|---|---|---|---|---|---|"]
    for name, w, c, n_eval, n_solves in rows:
        lines.append(f"| {name} | {w:.1f} | {c:.1f} | {n_eval} | {n_solves} | {1e3 * c / n_solves:.1f} |")
    ratio = (c2 / th.n_solves) / warm
    lines.append("")
    lines.append(f"warm coupled solve of Test 4 (median of {repeat}): {1e3 * warm:.1f} ms CPU; one coupled solve "
                 f"inside the heat-and-mass calibration / warm solve = {ratio:.2f} (target <= 1.3)")
    return "\n".join(lines)


if __name__ == "__main__":
    print(main(int(sys.argv[1]) if len(sys.argv) > 1 else 7))
