"""Issue 29: the predictive transport law from the case keys.

Reports wall and CPU time of

1. Song's 73 Appendix A runs through the CLI's path: per run a case load with ``operating.test = N``
   and the transport steady state (``Simulation(case, overrides).transport_steady_state()``, what
   ``rotarydryer rtd song2003_ottawa --set operating.test=N`` runs; the geometry tables are built once
   per drum and reused), target < 5 s;
2. the same 73 runs as one ``rotarydryer calibrate`` evaluation costs (the calibration's own count);
3. the MMG leave-one-out: 6 calibrations (c_0 and c_D on one tracer curve each) and 30 predictions
   (:func:`rotarydryer.studies.predictive_transport.mmg_leave_one_out`), target < 2 min on 2 cores.

Never a pass/fail test. Run: ``python benchmarks/bench_predictive.py [repeats]`` (a Markdown table).
"""

from __future__ import annotations

import sys
import time
import warnings

from rotarydryer.studies import predictive_transport as pt


def timed(fn):
    w, c = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w, time.process_time() - c


def main(repeat: int = 3) -> str:
    warnings.simplefilter("ignore")
    runs = pt.song_runs()
    tests = [r.test for r in runs]
    pt.song_predict({}, tests[:2])          # warm: imports, geometry tables of the drum
    song = [timed(lambda: pt.song_predict({}, tests)) for _ in range(repeat)]
    w, c = min(s[1] for s in song), min(s[2] for s in song)
    loo, lw, lc = timed(pt.mmg_leave_one_out)
    rows = [(f"Song's 73 runs, case load + transport steady state each (best of {repeat})", w, c, 73),
            ("MMG leave-one-out: 6 calibrations + 30 predictions", lw, lc, loo["summary"]["n"])]
    lines = ["| run | wall s | CPU s | predictions | per prediction ms (CPU) |", "|---|---|---|---|---|"]
    for name, wall, cpu, n in rows:
        lines.append(f"| {name} | {wall:.2f} | {cpu:.2f} | {n} | {1000 * cpu / n:.1f} |")
    return "\n".join(lines)


if __name__ == "__main__":
    print(main(int(sys.argv[1]) if len(sys.argv) > 1 else 3))
