"""Issue 31: a 2 h schedule run costs at most 3x the plain 2 h dynamics.

MMG Test 4 from its steady state, 60 s reporting: the plain dynamics (``Simulation.dynamics``:
one integration of the step of the gas inlet temperature 500 -> 100 degC at t = 0) against
``rotarydryer dynamics --schedule`` of the burner trip (500 -> 100 degC at 10 min, back at
20 min: three integrations), and a 40 min feed ramp (held at each 60 s interval: an integration
each). CPU and wall time of each, measured in one run, and their ratio to the plain run.

Never a pass/fail test. Run: ``python benchmarks/bench_issue31_schedule.py`` (a Markdown table).
"""

from __future__ import annotations

import time

from rotarydryer import Simulation
from rotarydryer.thermal.schedule import InputSchedule, simulate_schedule


def timed(fn):
    w, c = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w, time.process_time() - c


def main():
    sim = Simulation("ajayi2011_mmg", {"operating.test": 4})
    ss = sim.thermal_steady_state()
    d, z0 = ss.dryer, ss.state
    trip = InputSchedule.from_events({"trip": [{"at_s": 600, "duration_s": 600, "value": 100}]})
    ramp = InputSchedule.from_events({"ramp": [{"input": "feed_rate", "from_s": 600, "to_s": 3000,
                                                "value": 0.8 * d.feed_rate}]})
    _, w0, c0 = timed(lambda: sim.dynamics(7200.0, 60.0, gas_inlet_temperature=100.0))
    rows = [("plain dynamics, gas step at t = 0", 1, w0, c0)]
    for label, sched in (("schedule: burner trip 10 min", trip), ("schedule: feed ramp 40 min", ramp)):
        r, w, c = timed(lambda s=sched: simulate_schedule(d, z0, s, 7200.0, 60.0))
        rows.append((label, r.restarts, w, c))
    print("| 2 h run (MMG Test 4, 60 s points) | integrations | wall (s) | CPU (s) | CPU / plain |")
    print("|---|---|---|---|---|")
    for label, n, w, c in rows:
        print(f"| {label} | {n} | {w:.2f} | {c:.2f} | {c / c0:.2f} |")


if __name__ == "__main__":
    main()
