"""Speed of the vectorised correlations: 1e6 evaluations each (target < 0.1 s; never fails on timing).

Run: ``python -m pytest benchmarks/bench_correlations.py --benchmark-only``
"""

import warnings

import numpy as np
import pytest

from rotarydryer import correlations as c
from rotarydryer.correlations import heat_transfer as ht

N = 1_000_000
RNG = np.random.default_rng(0)


def _u(lo, hi, n=N):
    return RNG.uniform(lo, hi, n)


# Inputs inside every fitted range, so that no warnings are raised inside the timing loop.
MRT = dict(length=_u(2, 20), diameter=_u(0.3, 1), slope=_u(0.067, 0.117), rpm=_u(3, 8),
           particle_size=_u(420e-6, 470e-6), gas_mass_flux=_u(0, 0.3), solids_mass_flux=np.ones(N))
RE = _u(70, 300)
PR = _u(0.6, 0.8)

CASES = {
    "song_2003": lambda: c.song_2003(**MRT),
    "perry_green_1984": lambda: c.perry_green_1984(**MRT),
    "friedman_marshall_1949": lambda: c.friedman_marshall_1949(**MRT, gas_flow="counter-current"),
    "foust_1960": lambda: c.foust_1960(**MRT),
    "sullivan_1927": lambda: c.sullivan_1927(MRT["length"], MRT["diameter"], MRT["slope"], MRT["rpm"], 40.0),
    "sai_1990": lambda: c.sai_1990(MRT["length"], MRT["diameter"], MRT["slope"], MRT["rpm"],
                                   MRT["solids_mass_flux"], _HOLDUP, 1650.0),
    "alvarez_shene_1994": lambda: c.alvarez_shene_1994(MRT["diameter"], MRT["slope"], MRT["rpm"],
                                                       MRT["particle_size"], 1650.0, MRT["solids_mass_flux"],
                                                       MRT["gas_mass_flux"]),
    "saeman_mitchell_1954": lambda: c.saeman_mitchell_1954(MRT["length"], MRT["diameter"], MRT["slope"],
                                                           MRT["rpm"], _u(0, 2), np.pi, 0.01),
    "ua_mccormick_1962": lambda: ht.mccormick_1962_ua(_G, MRT["diameter"]),
    "ua_alvarez_shene_1994": lambda: ht.alvarez_shene_1994_ua(_G, MRT["diameter"], "sand"),
    "nu_ranz_marshall_1952": lambda: c.nusselt_number(RE, PR, method="ranz_marshall_1952"),
    "nu_ajayi_2011": lambda: c.nusselt_number(RE, method="ajayi_2011"),
    "nu_tscheng_watkinson_1979": lambda: c.nusselt_number(RE, method="tscheng_watkinson_1979_solids",
                                                          rotational_reynolds=500.0, fill_fraction=0.1),
    "cd_schiller_naumann_1933": lambda: c.schiller_naumann_1933(RE),
    "cd_haider_levenspiel_1989": lambda: c.haider_levenspiel_1989(RE, 0.846),
    "cd_lee_2008": lambda: c.lee_2008(RE),
}
_G = _u(0.5, 3)
_HOLDUP = 0.05 * 1650 * np.pi / 4 * MRT["diameter"] ** 2 * MRT["length"]  # 5 % fill


@pytest.mark.parametrize("name", list(CASES))
def test_correlation_1e6(benchmark, name):
    f = CASES[name]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the inputs are in range: any warning is a bug in the benchmark
        out = benchmark(f)
    assert np.shape(out) == (N,) and np.all(np.isfinite(out))


def test_terminal_velocity_1e6(benchmark):
    """Iterative (safeguarded Newton in log Re): 1e6 particles."""
    d = _u(50e-6, 5e-3)
    out = benchmark(c.terminal_velocity, d, 1588.0, 1.2, 1.8e-5)
    assert np.all(out > 0)


def test_cascade_trajectory_1e3(benchmark):
    """Time-stepped fall with drag: 1e3 particles, 400 steps each."""
    h = _u(0.3, 3.0, 1000)
    out = benchmark(c.cascade_trajectory, h, 850e-6, 1588.0, 1.2, 1.8e-5, gas_velocity=1.0,
                    gas_flow="counter-current", inclination=2.8)
    assert np.all(np.isfinite(out.fall_time))
