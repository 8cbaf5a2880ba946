"""Issue 16 part 2: exact geometry at surrogate cost (rotarydryer.geometry.tabulated).

Measured in one run, interleaved (the machine is shared; each figure is the best of many calls):

1. 10^4 (repose angle, loading) pairs of fall time, passive time (from the release angle) and
   design load: Lee's regressions (Lee (2008) Eq. 4.24-4.27), the exact geometry evaluated
   directly, and the tabulated exact geometry; plus the one-off table build per drum.
2. Coupled steady states of MMG Test 4 and Invicta: regression geometry, exact geometry direct,
   exact geometry tabulated (the tables built before timing, as in a study or a solver loop).

    OMP_NUM_THREADS=1 python benchmarks/bench_issue16_geometry.py
"""

import time

import numpy as np
from _timing import best

from rotarydryer import Simulation
from rotarydryer.geometry import FlightedDrum, TwoSectionFlight
from rotarydryer.geometry.lee2008_regressions import Lee2008Regressions
from rotarydryer.geometry.tabulated import GeometryTable


def pairs():
    drum = FlightedDrum(2.5, 28, TwoSectionFlight(0.195, 0.183, 90, 117))   # Invicta (Lee (2008) Table 4.1)
    t0 = time.perf_counter()
    table = GeometryTable(drum)
    build = time.perf_counter() - t0
    reg = Lee2008Regressions()
    rng = np.random.default_rng(1)
    phi, f = rng.uniform(20.0, 70.0, 10_000), rng.uniform(0.0, 1.0, 10_000)   # Lee's regression range

    def regression():
        reg.mean_fall_time(phi, f), reg.mean_release_angle(phi, f), reg.design_load_area(phi)

    def direct():
        drum.cascade(phi, f, rpm=3.0), drum.design_load_area(phi)

    def tabulated():
        table.cascade(phi, f, rpm=3.0), table.design_load_area(phi)

    times = {"regression": [], "direct": [], "tabulated": []}
    for _ in range(30):   # interleaved rounds
        times["regression"].append(best(regression, repeat=5))
        times["tabulated"].append(best(tabulated, repeat=5))
        if len(times["direct"]) < 3:
            times["direct"].append(best(direct, repeat=1))
    t = {k: min(v) for k, v in times.items()}
    print(f"table build (Invicta drum): {build:.2f} s")
    print(f"10^4 pairs: regressions {t['regression'] * 1e3:.3f} ms, exact direct {t['direct'] * 1e3:.1f} ms "
          f"({t['direct'] / t['regression']:.0f}x), exact tabulated {t['tabulated'] * 1e3:.3f} ms "
          f"({t['tabulated'] / t['regression']:.2f}x)")


def solves():
    cases = (("MMG Test 4", "ajayi2011_mmg", {"operating.test": 4}, "ajayi2011_regressions"),
             ("Invicta", "lee2008_invicta", {}, "lee2008_regressions"))
    for name, case, ov, regression in cases:
        variants = {"regressions": {"geometry.method": regression},
                    "exact direct": {"geometry.method": "exact", "geometry.tabulated": False},
                    "exact tabulated": {"geometry.method": "exact", "geometry.tabulated": True}}
        dryers = {k: Simulation(case, {**ov, **v}).thermal_dryer() for k, v in variants.items()}
        for d in dryers.values():
            d.steady_state()   # warm: tables built, caches filled
        times = {k: [] for k in dryers}
        for _ in range(3):
            for k, d in dryers.items():
                times[k].append(best(d.steady_state, repeat=2))
        t = {k: min(v) for k, v in times.items()}
        print(f"{name} coupled steady state: " + ", ".join(
            f"{k} {v:.3f} s ({v / t['regressions']:.2f}x)" for k, v in t.items()))


if __name__ == "__main__":
    pairs()
    solves()
