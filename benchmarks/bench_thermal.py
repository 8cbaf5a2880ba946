"""Speed of the heat- and mass-transfer building blocks (issue 6). Never fails on timing.

Run: ``python -m pytest benchmarks/bench_thermal.py --benchmark-only``
"""

import numpy as np
import pytest

from rotarydryer.properties import humid_air as ha
from rotarydryer.properties import water
from rotarydryer.thermal import burner, drying, radiation, shell

RNG = np.random.default_rng(0)
N = 100_000
T = RNG.uniform(0.0, 600.0, N)
Y = RNG.uniform(0.0, 0.3, N)
TS = RNG.uniform(20.0, 90.0, N)


CASES = {
    "humid_air.heat_capacity": lambda: ha.heat_capacity(T, Y),
    "humid_air.enthalpy": lambda: ha.enthalpy(T, Y),
    "humid_air.density": lambda: ha.density(T, Y),
    "humid_air.viscosity": lambda: ha.viscosity(T, Y),
    "humid_air.thermal_conductivity": lambda: ha.thermal_conductivity(T, Y),
    "water.saturation_pressure": lambda: water.saturation_pressure(TS),
    "water.latent_heat": lambda: water.latent_heat(TS),
    "radiation.gas_emissivity": lambda: radiation.gas_emissivity(T, 4000.0 + 0 * T, 1100.0, 3.6),
    "drying.unhindered_flux": lambda: drying.unhindered_drying_flux(70.0, TS, np.maximum(T, 100.0), Y),
}


@pytest.mark.parametrize("name", list(CASES))
def test_vectorised_1e5(benchmark, name):
    out = benchmark(CASES[name])
    assert np.shape(out) == (N,) and np.all(np.isfinite(out))


def test_wet_bulb_1e4(benchmark):
    t = np.linspace(100.0, 600.0, 10_000)
    out = benchmark(ha.wet_bulb_temperature, t, 0.05)
    assert np.all(np.isfinite(out))


@pytest.mark.parametrize("n_cells", [50, 222, 1000, 10_000])
def test_shell_network_scaling(benchmark, n_cells):
    """Shell temperature solved at every axial cell (vectorised bisection)."""
    tg = np.linspace(500.0, 131.0, n_cells)
    r = benchmark(shell.shell_heat_loss, tg, 31.3, 22.2 / n_cells)
    assert r.energy_balance_error < 1e-9


def test_burner_forward(benchmark):
    air_d, air_c = burner.normal_volume_to_mass(88050.0), burner.normal_volume_to_mass(23698.0)
    g = benchmark(burner.combustion_chamber, 750 / 3600, air_c, air_d)
    assert g.energy_balance_error < 1e-9


def test_burner_inverse(benchmark):
    air_d, air_c = burner.normal_volume_to_mass(88050.0), burner.normal_volume_to_mass(23698.0)
    f = benchmark(burner.fuel_rate_for_temperature, 500.0, air_c, air_d)
    assert f > 0
