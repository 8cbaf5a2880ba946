"""Issue 27 pipeline overheads, as same-run ratios of CPU time (never a pass/fail test).

1. ``Simulation(case).steady_state()`` from a fresh object / a second solve on the same Dryer;
2. a ``rotarydryer sweep`` point / a sensitivity-study run of the same case (both warm-started
   from a neighbouring point, as each does in its own loop);
3. a study run / its coupled solve.

Run: ``python benchmarks/bench_pipeline.py [repeats]`` (prints a Markdown table).
"""

from __future__ import annotations

import sys
import time

from rotarydryer import Simulation
from rotarydryer._threads import single_threaded
from rotarydryer.studies.sensitivity import OUTPUTS, _steady_summary
from rotarydryer.studies.sweep import _solve_point

CASES = {"MMG": ("ajayi2011_mmg", {"operating.test": 4}, "operating.feed_rate", 40.0),
         "Invicta": ("lee2008_invicta", {}, "operating.feed_rate", 27.0),
         "Song": ("song2003_ottawa", {}, "operating.rpm", 5.0)}


def cpu(fn, repeat):
    """Median CPU time (s) of ``repeat`` calls."""
    out = []
    for _ in range(repeat):
        t = time.process_time()
        fn()
        out.append(time.process_time() - t)
    out.sort()
    return out[len(out) // 2]


def measure(case, base, key, value, repeat):
    near = {**base, key: value * 1.01}
    at = {**base, key: value}
    warm = Simulation(case, near).steady_state().warm_data()

    def fresh():
        Simulation(case, at).steady_state()

    sim = Simulation(case, at)
    sim.steady_state()
    dryer = sim.dryer()

    def second():
        dryer.steady_state()

    def sweep_point():
        _solve_point(case, at, warm)

    def study_run():
        _steady_summary(case, at, warm)

    def study_run_outputs():     # a Sobol study's run: the study's default outputs only
        _steady_summary(case, at, warm, OUTPUTS)

    d2 = Simulation(case, at).dryer()

    def coupled_solve():
        d2.steady_state(z0=warm["state"], dt0=1e3, factorization=warm["factorization"])

    with single_threaded():
        t = {name: cpu(fn, repeat) for name, fn in
             (("fresh", fresh), ("second", second), ("sweep", sweep_point), ("study", study_run),
              ("study_outputs", study_run_outputs), ("solve", coupled_solve))}
    return t


def main(repeat=7):
    print("| case | fresh / second solve (<= 1.3) | sweep point / study run (<= 1.1) | study run / coupled solve (<= 1.3) "
          "| study run, default outputs / coupled solve | CPU ms: fresh, second, sweep, study, study (outputs), solve |")
    print("|---|---|---|---|---|---|")
    for label, (case, base, key, value) in CASES.items():
        t = measure(case, base, key, value, repeat)
        ms = ", ".join(f"{1e3 * t[k]:.1f}" for k in ("fresh", "second", "sweep", "study", "study_outputs", "solve"))
        print(f"| {label} | {t['fresh'] / t['second']:.2f} | {t['sweep'] / t['study']:.2f} | "
              f"{t['study'] / t['solve']:.2f} | {t['study_outputs'] / t['solve']:.2f} | {ms} |")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 7)
