"""Issue 34 item 1: flights of any shape (rotarydryer.geometry.polygon) against two-section flights.

Measured in one run, interleaved (the machine is shared; CPU time, each figure the best of many calls):

1. The holdup profile over 0-360 deg at 0.1 deg (3600 root angles; holdup and discharge rate) of the
   Invicta two-section flight by Lee's closed forms, and of the three-section and EAD presets (and the
   Invicta flight itself) by the exact pocket computation. Target: polygon <= 3x the two-section flight.
2. Tabulated for the solver (rotarydryer.geometry.tabulated): 10^4 (repose angle, loading) pairs of
   fall time, passive time and design load from the tables, and one compiled pass of the cell
   coefficients (GeometryTable.cell_values) for 40 cells; plus the one-off table build per drum.
   Target: a polygonal flight at the two-section cost.

    OMP_NUM_THREADS=1 python benchmarks/bench_issue34_flights.py
"""

import time

import numpy as np

from rotarydryer.geometry import FlightedDrum, TwoSectionFlight
from rotarydryer.geometry.presets import preset_drum
from rotarydryer.geometry.tabulated import GeometryTable

PSI = np.arange(0.0, 360.0, 0.1)


def cpu_best(fn, repeat=5, number=20):
    """Shortest CPU time (s) per call of ``fn`` over ``repeat`` batches of ``number`` calls."""
    out = []
    for _ in range(repeat):
        t = time.process_time()
        for _ in range(number):
            fn()
        out.append((time.process_time() - t) / number)
    return min(out)


def drums():
    inv = FlightedDrum(2.5, 28, TwoSectionFlight(0.195, 0.183, 90.0, 117.0))
    return {"two-section (Invicta, closed forms)": inv,
            "Invicta flight, polygon path": FlightedDrum(2.5, 28, inv.flight, geometry="polygon"),
            "three-section preset": preset_drum("invicta_three_section")[0],
            "EAD preset": preset_drum("invicta_ead")[0]}


def profiles(ds):
    def job(d):
        return lambda: (d.holdup_area(PSI, 45.0), d.discharge_rate(PSI, 45.0, 3.0))

    times = {k: [] for k in ds}
    for _ in range(10):                      # interleaved rounds
        for k, d in ds.items():
            times[k].append(cpu_best(job(d), repeat=3, number=20))
    t = {k: min(v) for k, v in times.items()}
    base = t["two-section (Invicta, closed forms)"]
    print("holdup + discharge-rate profile, 0-360 deg at 0.1 deg (3600 angles), CPU time:")
    for k, v in t.items():
        print(f"  {k:38s} {v * 1e3:7.3f} ms  ({v / base:.2f}x)")
    return t


def tables(ds):
    rng = np.random.default_rng(1)
    phi, f = rng.uniform(20.0, 70.0, 10_000), rng.uniform(0.0, 1.0, 10_000)
    cphi = np.linspace(35.0, 55.0, 40)
    rho = np.full(40, 940.0)
    builds, tabs = {}, {}
    for k, d in ds.items():
        t0 = time.process_time()
        tabs[k] = GeometryTable(d)
        builds[k] = time.process_time() - t0
    mp = {k: 0.8 * rho * 0.3 * t.design_load_area(cphi) for k, t in tabs.items()}

    def pairs(t):
        return lambda: (t.cascade(phi, f, rpm=3.0), t.design_load_area(phi))

    def cells(k, t):
        return lambda: t.cell_values(cphi, rho, mp[k], length=0.3, rpm=3.0)

    kernel = all(t.cell_values(cphi, rho, mp[k], length=0.3, rpm=3.0) is not None for k, t in tabs.items())
    tp = {k: [] for k in tabs}
    tc = {k: [] for k in tabs}
    for _ in range(10):
        for k, t in tabs.items():
            tp[k].append(cpu_best(pairs(t), repeat=3, number=5))
            if kernel:
                tc[k].append(cpu_best(cells(k, t), repeat=3, number=200))
    base = "two-section (Invicta, closed forms)"
    print("tabulated for the solver (CPU time):")
    for k in tabs:
        p = min(tp[k])
        line = f"  {k:38s} 10^4 pairs {p * 1e3:7.3f} ms ({p / min(tp[base]):.2f}x)"
        if kernel:
            c = min(tc[k])
            line += f", 40 cells compiled {c * 1e6:7.1f} us ({c / min(tc[base]):.2f}x)"
        line += f", table build {builds[k]:.2f} s"
        print(line)
    if not kernel:
        print("  (compiled cell kernel off: numba absent or ROTARYDRYER_JIT=0)")


if __name__ == "__main__":
    ds = drums()
    profiles(ds)
    tables(ds)
