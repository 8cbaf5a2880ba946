"""Coupled steady state and 2 h dynamics of every shipped dryer through rotarydryer.Simulation
(issue 12). Run: python benchmarks/bench_any_dryer.py  (prints a Markdown table)."""


import numpy as np
from _timing import best  # noqa: E402

from rotarydryer import Simulation

CASES = [("ajayi2011_mmg", {"operating.test": 4}), ("ajayi2011_mmg", {"operating.test": 4, "thermal.mode": "ajayi2011"}),
         ("lee2008_invicta", {}), ("song2003_ottawa", {})]


if __name__ == "__main__":
    print("| case | unknowns | steady state (s) | 2 h dynamics after a 10 % feed step (s) |")
    print("|---|---|---|---|")
    for name, ov in CASES:
        sim = Simulation(name, ov)
        d = sim.thermal_dryer()
        ss = d.steady_state()
        t_ss = best(lambda: sim.thermal_dryer().steady_state())
        from rotarydryer.thermal.studies import perturbed

        d2 = perturbed(d, solid_feed_rate=d.feed_rate * 1.1)
        t_dyn = best(lambda: d2.simulate(ss.state, 7200.0, t_eval=np.arange(0, 7201, 60.0)), repeat=1)
        print(f"| {name} {ov} | {d.n} | {t_ss:.3f} | {t_dyn:.2f} |")
