"""Issue 16 part 1: coupled steady states (MMG test 4, Invicta, Song) timed and compared.

Run with the tree to measure, and with ``PYTHONPATH=OLD_CHECKOUT/src`` for the "before" side;
alternate the two in one session (the machine is shared) and compare the saved states:

    OMP_NUM_THREADS=1 PYTHONPATH=/tmp/before/src python benchmarks/bench_issue16_solver.py before.npz
    OMP_NUM_THREADS=1 python benchmarks/bench_issue16_solver.py after.npz
"""

import sys
import time

import numpy as np

import rotarydryer
from rotarydryer import Simulation

CASES = (("mmg4", ("ajayi2011_mmg", {"operating.test": 4})), ("invicta", ("lee2008_invicta", {})),
         ("song", ("song2003_ottawa", {})))


def main(out="states.npz"):
    states = {}
    for name, (case, ov) in CASES:
        d = Simulation(case, ov).thermal_dryer()
        ss = d.steady_state()
        ts = []
        for _ in range(3):
            t = time.perf_counter()
            ss = d.steady_state()
            ts.append(time.perf_counter() - t)
        states[name] = ss.state
        print(f"{rotarydryer.__file__}: {name} steady state {min(ts):.4f} s ({ss.iterations} iterations)", flush=True)
    np.savez(out, **states)


if __name__ == "__main__":
    main(*sys.argv[1:])
