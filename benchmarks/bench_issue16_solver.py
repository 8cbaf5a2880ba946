"""Issue 16 part 1: coupled steady states and dynamics timed against their own linear algebra.

For each case: the steady state from the case's start (best of 20), the cost of 20 sparse LU
factorisations and solves of the solver's own matrix I/dt - J (the issue's yardstick), their ratio,
and for MMG test 4 the 2 h response to a +10 % feed step (best of 3). One BLAS thread.

Run with the tree to measure, and with ``PYTHONPATH=OLD_CHECKOUT/src`` for the "before" side;
alternate the two in one session (the machine is shared) and compare the saved states:

    python benchmarks/bench_issue16_solver.py after.npz
    PYTHONPATH=/tmp/before/src python benchmarks/bench_issue16_solver.py before.npz
    python benchmarks/bench_issue16_solver.py --compare before.npz after.npz
"""

import sys

import numpy as np
import scipy.sparse as sp
from _timing import best_result
from scipy.sparse.linalg import splu
from threadpoolctl import threadpool_limits

import rotarydryer
from rotarydryer import Simulation, _jit

CASES = (("mmg4", ("ajayi2011_mmg", {"operating.test": 4})),
         ("mmg4_regressions", ("ajayi2011_mmg", {"operating.test": 4, "geometry.method": "ajayi2011_regressions"})),
         ("invicta", ("lee2008_invicta", {})), ("song", ("song2003_ottawa", {})))


getattr(_jit, "long_runs", lambda: None)()      # many solves: the compiled kernels (the "before" tree: always compiled)


def main(out="states.npz"):
    states = {}
    with threadpool_limits(1):
        for name, (case, ov) in CASES:
            sim = Simulation(case, ov)
            d = sim.thermal_dryer()
            ss = d.steady_state()
            t_ss, ss = best_result(d.steady_state, 20)
            z = ss.state
            d.freeze_shell(z)
            A = (sp.identity(d.n, format="csc") / 1e3 - d.jacobian(z)).tocsc()
            d.unfreeze_shell()
            t_lu, _ = best_result(lambda: [splu(A).solve(z) for _ in range(20)], 20)
            states[name] = z
            print(f"{rotarydryer.__file__}: {name}: steady state {t_ss * 1e3:.1f} ms ({ss.iterations} iterations), "
                  f"20 LU {t_lu * 1e3:.2f} ms, ratio {t_ss / t_lu:.1f}", flush=True)
            if name.startswith("mmg4"):
                d2 = sim.thermal_dryer()
                d2.feed_rate *= 1.1
                t_dyn, res = best_result(lambda: d2.simulate(z, 7200.0, t_eval=np.arange(0.0, 7201.0, 60.0)), 3)
                states[name + "_dynamics"] = res.states[:, -1]
                print(f"{rotarydryer.__file__}: {name}: 2 h after a +10 % feed step {t_dyn * 1e3:.0f} ms "
                      f"({res.nfev} residual calls)", flush=True)
    np.savez(out, **states)


def compare(a, b):
    a, b = np.load(a), np.load(b)
    for k in a.files:
        x, y = a[k], b[k]
        rel = float(np.max(np.abs(x - y) / np.maximum(np.abs(x), 1e-9 * np.max(np.abs(x)))))
        print(f"{k}: largest relative difference {rel:.2g}")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--compare"]:
        compare(*sys.argv[2:4])
    else:
        main(*sys.argv[1:])
