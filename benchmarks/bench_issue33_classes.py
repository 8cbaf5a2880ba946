"""Issue 33: the coupled heat-and-mass steady state with particle size classes against one class.

MMG test 4 (default configuration) with a log-normal feed around the material's 12 mm (sigma_g 1.6) in
5 and 10 equal-mass classes, and Song's pilot dryer with Lee's fine river sand (gas.flow 0.06 kg/s, so
the fines are entrained): CPU time (``time.process_time``) of ``ThermalDryer.steady_state`` on a freshly
built dryer (the build, which solves the transport start once per network, is timed apart), best of
``REPEATS``, one BLAS thread, compiled kernels. The issue's target: 5 classes / 1 class <= 4 on MMG.

    python benchmarks/bench_issue33_classes.py
"""

import os
import time
import warnings

from threadpoolctl import threadpool_limits

from rotarydryer import Simulation, _jit

REPEATS = 8
CASES = {
    "ajayi2011_mmg": ({"operating.test": 4},
                      lambda k: {"particle_size.distribution": "lognormal", "particle_size.d50": 0.012,
                                 "particle_size.sigma_g": 1.6, "particle_size.classes": k}),
    "song2003_ottawa": ({"gas.flow": 0.06},
                        lambda k: {"particle_size.dataset": "lee2008_fine_river_sand", "particle_size.classes": k}),
}

getattr(_jit, "long_runs", lambda: None)()      # many solves: the compiled kernels (the "before" tree: always compiled)


def timed(case, overrides):
    best_solve, best_build, size = float("inf"), float("inf"), 0
    for _ in range(REPEATS):
        t = time.process_time()
        d = Simulation(case, overrides).thermal_dryer()
        d.initial_state()                 # the transport start, solved once per network
        t_build = time.process_time() - t
        t = time.process_time()
        ss = d.steady_state()
        best_solve = min(best_solve, time.process_time() - t)
        best_build = min(best_build, t_build)
        size = ss.state.size
    return best_solve, best_build, size


def main():
    warnings.simplefilter("ignore")
    timed("ajayi2011_mmg", {"operating.test": 4})         # warm-up: compile the kernels
    print(f"load {os.getloadavg()[0]:.2f}; CPU s, best of {REPEATS}, one BLAS thread")
    with threadpool_limits(1):
        for case, (base, psd) in CASES.items():
            one, build1, n1 = timed(case, base)
            for k in (5, 10):
                t, build, n = timed(case, {**base, **psd(k)})
                print(f"{case}: {k:2d} classes: steady state {t:.3f} s (state {n}), build {build:.3f} s; "
                      f"1 class {one:.3f} s (state {n1}), build {build1:.3f} s; ratio {t / one:.1f}", flush=True)


if __name__ == "__main__":
    main()
