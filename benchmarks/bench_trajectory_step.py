"""Trajectory forward step (issue 14 part 1): all 35 cells of Invicta inside a steady state.

Target: below 50 ms. Measured: the transport model built and solved with
``transport.forward_step = "trajectory"`` (cold: the (fall height, gas velocity) table of the
trajectories is built first; warm: the table is cached per gas/particle/slope), against the fitted
step; and one evaluation of the step for 35 cells from the table, against integrating the 35
trajectories directly.

Run: python benchmarks/bench_trajectory_step.py        (or with pytest --benchmark-only)
"""

from __future__ import annotations

import time
import warnings

import numpy as np
from _timing import best  # noqa: E402

from rotarydryer.cases import build_model, load_case
from rotarydryer.correlations import cascade_trajectory
from rotarydryer.transport.forward_step import forward_step_table, trajectory_forward_step

warnings.simplefilter("ignore")
# N = 35 with the trajectory step needs C_B = 0 (with Lee's 0.68 the step does not fit the cell)
CASE = {"thermal.enabled": False, "transport.n_cells": 35, "transport.backmix": 0.0}


def _case(method, step):
    return load_case("lee2008_invicta", {**CASE, "geometry.method": method, "transport.forward_step": step})


def steady(case):
    m = build_model(case)
    return m.steady_state()


def main():
    rows = []
    for method in ("lee2008_regressions", "exact"):
        fitted, traj = _case(method, "fitted"), _case(method, "trajectory")
        steady(fitted), steady(traj)                        # imports, geometry caches
        forward_step_table.cache_clear()
        t = time.perf_counter()
        steady(traj)
        cold = time.perf_counter() - t
        rows.append((method, best(lambda: steady(fitted), repeat=7), cold, best(lambda: steady(traj), repeat=7)))
    print("Invicta N = 35, build + steady state (s):")
    print("geometry              fitted    trajectory cold  trajectory warm")
    for method, f, c, w in rows:
        print(f"{method:20s}  {f * 1e3:6.1f} ms  {c * 1e3:8.1f} ms    {w * 1e3:8.1f} ms")
    m = build_model(_case("exact", "trajectory"))
    gas, ci = m.specs[0].gas, m.cell_info
    h, q = ci["fall_height_m"], np.full(35, 90.0)
    forward_step_table.cache_clear()
    t_table = best(lambda: (forward_step_table.cache_clear(), forward_step_table(gas, 2.8)), repeat=3)
    t_eval = best(lambda: trajectory_forward_step(gas, 2.8, h, q), repeat=50)
    u = ci["curtain_velocity_ratio"] * gas.gas_velocity
    t_direct = best(lambda: cascade_trajectory(h * np.cos(np.radians(2.8)), gas.particle_diameter,
                                               gas.particle_density, gas.gas_density, gas.gas_viscosity,
                                               gas_velocity=u, gas_flow=gas.gas_flow, inclination=2.8), repeat=3)
    print(f"table (33 x 17 trajectories): {t_table * 1e3:.1f} ms; step of 35 cells from the table: "
          f"{t_eval * 1e6:.0f} us; 35 trajectories integrated directly (400 steps): {t_direct * 1e3:.1f} ms")


def test_trajectory_steady_state(benchmark):
    case = _case("exact", "trajectory")
    ss = benchmark(steady, case)
    assert ss.mass_balance_error < 1e-9


if __name__ == "__main__":
    main()
