"""Speed of the coupled dryer model (transport + heat + mass, issue 6). Never fails on timing.

Run: ``python -m pytest benchmarks/bench_thermal_dryer.py --benchmark-only``
Targets (issue 6): MMG coupled steady state < 2 s; 2 h of dynamics after a step < 20 s.
"""

import dataclasses

import numpy as np
import pytest

from rotarydryer import Simulation
from rotarydryer.thermal import studies
from rotarydryer.thermal.dryer import ThermalDryer
from rotarydryer.transport.sections import build_sections


def _dryer(mode="physical", factor=1.0):
    sim = Simulation("ajayi2011_mmg", {"thermal.mode": mode})
    base = sim.thermal_dryer()
    if factor == 1.0:
        return base
    specs = [dataclasses.replace(sp, n_cells=max(2, int(round(sp.n_cells * factor)))) for sp in base.model.specs]
    model = build_sections(specs, material=base.material, feed_rate=base.feed_rate, rpm=base.rpm,
                           slope=sim.transport_model().parameters["slope"], inlet="danckwerts")
    return ThermalDryer(model, material=base.material, feed_rate=base.feed_rate, feed_moisture=base.feed_moisture,
                        rpm=base.rpm, radius=base.radius, sections=base.section_thermal, settings=base.settings)


@pytest.mark.parametrize("mode", ["physical", "ajayi2011"])
def test_steady_state_mmg(benchmark, mode):
    d = _dryer(mode)
    ss = benchmark.pedantic(d.steady_state, rounds=3, iterations=1)
    assert ss.energy_balance_error < 1e-6
    benchmark.extra_info["unknowns"] = d.n


@pytest.mark.parametrize("factor", [0.5, 1.0, 2.0])
def test_steady_state_scaling(benchmark, factor):
    """Cells x factor in every section (flighted cells at x2 are shorter than the forward step: C_F clipped to 1)."""
    d = _dryer("physical", factor)
    ss = benchmark.pedantic(d.steady_state, rounds=2, iterations=1)
    assert ss.energy_balance_error < 1e-6
    benchmark.extra_info["unknowns"] = d.n


@pytest.mark.parametrize("factor", [0.5, 1.0, 2.0])
def test_dynamics_2h_after_step(benchmark, factor):
    d = _dryer("physical", factor)
    ss = d.steady_state()
    d2 = studies.perturbed(d, gas_inlet_temperature=550.0)

    def run():
        return d2.simulate(ss.state, 7200.0, t_eval=np.linspace(0, 7200, 121))
    res = benchmark.pedantic(run, rounds=2, iterations=1)
    assert np.isfinite(res.product_moisture[-1])
    benchmark.extra_info["unknowns"] = d.n
    benchmark.extra_info["nfev"] = res.nfev
