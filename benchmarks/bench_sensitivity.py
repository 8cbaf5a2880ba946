"""Global sensitivity throughput (issue 16 part 4): Sobol study of 8 inputs on the MMG coupled model.

Acceptance target: at least 10^4 model runs in under 3 minutes on the 2-core machine. This script
runs a smaller study (``--samples`` base samples x (8 + 2) runs) with warm starts and with cold
starts, measures runs per second (wall clock, ``--workers`` processes, study overhead included)
and extrapolates linearly to 10^4 runs (N = 1000 base samples). Warm starts can only help, so
the projection from a short study is fair if the per-run cost does not change with N.

Run: python benchmarks/bench_sensitivity.py [--samples 16] [--workers 2] [--modes warm,cold]
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import time

from rotarydryer.studies.sensitivity import sobol_study

#: 8 uncertain inputs of the MMG test-4 case (about +-5 % around the nominal values)
MMG_PARAMS = {
    "operating.feed_rate": (38.6, 42.7),            # kg/s (test 4: 40.67)
    "operating.rpm": (2.85, 3.15),                  # rev/min (3.0)
    "gas.flow": (15.4, 17.1),                       # kg/s (16.25)
    "thermal.area_scale": (2.45, 2.75),             # - (2.6)
    "gas.inlet_temperature": (480.0, 520.0),        # degC (500)
    "transport.moisture_scale": (0.95, 1.05),       # - (1.0)
    "operating.feed_temperature": (24.0, 32.0),     # degC (28)
    "shell.ambient_temperature": (20.0, 32.0),      # degC (26)
}
TARGET_RUNS = 10_000
TARGET_SECONDS = 180.0


def run(samples: int, workers: int, warm: bool):
    t0 = time.perf_counter()
    res = sobol_study("ajayi2011_mmg", MMG_PARAMS, samples, workers=workers, warm_start=warm)
    return res, time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=16)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--modes", default="warm,cold")
    args = ap.parse_args(argv)
    print(f"# {datetime.date.today()} {platform.node()} {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}; ajayi2011_mmg, 8 inputs, {args.workers} workers")
    print("| starts | base samples | runs | failed | wall time | runs/s | projected 10^4 runs | target |")
    print("|---|---|---|---|---|---|---|---|")
    for mode in args.modes.split(","):
        res, dt = run(args.samples, args.workers, mode == "warm")
        rate = res.n_runs / dt
        proj = TARGET_RUNS / rate
        print(f"| {mode} | {args.samples} | {res.n_runs} | {res.n_failed} | {dt:.1f} s | {rate:.2f} | "
              f"{proj:.0f} s ({proj / 60:.1f} min) | {'met' if proj < TARGET_SECONDS else 'not met'} "
              f"(< {TARGET_SECONDS:.0f} s) |", flush=True)
        for o in res.outputs:
            top = max(res.indices[o].items(), key=lambda kv: kv[1]["ST"] if kv[1]["ST"] == kv[1]["ST"] else -1)
            print(f"#   {mode} {o}: largest ST {top[0]} = {top[1]['ST']:.3f} +- {top[1]['ST_conf']:.3f}")


if __name__ == "__main__":
    main()
