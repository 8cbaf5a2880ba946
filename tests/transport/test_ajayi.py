"""Ajayi (2011) multi-section model (MMG Karumba): Table 5.4 acceptance and properties."""

import math

import numpy as np
import pytest

from rotarydryer.cases import build_model, load_case
from rotarydryer.properties.materials import load_material
from rotarydryer.transport.ajayi import ajayi2011, unflighted_cells_auto

from .conftest import read_csv

TESTS = {int(r["test"]): r for r in read_csv("ajayi_rtd_tests_summary.csv")}


#: Ajayi's thesis model: his regression geometry (Ajayi (2011) Eq. 4.25-4.28); the case default is the exact one
THESIS = {"geometry.method": "ajayi2011_regressions"}


def steady(**ov):
    return build_model(load_case("ajayi2011_mmg", {**THESIS, **ov})).steady_state()


def test_table_5_4_test_4():
    ss = steady()
    rtd = ss.rtd(simulate=False)  # 60 s pulse, time from pulse start (as the thesis' tau integral)
    assert rtd.tracer_mean / 60 == pytest.approx(float(TESTS[4]["MRT_model_min"]), rel=0.03)
    assert ss.total_holdup == pytest.approx(float(TESTS[4]["holdup_model_kg"]), rel=0.05)
    # the flighted cells are under-loaded (0.6-0.8 of m_load), the unflighted sections hold most solids
    assert set(ss.loading_state) == {"under"}
    h = ss.section_holdups()
    assert h["A"]["bed_kg"] + h["E"]["bed_kg"] > 0.6 * ss.total_holdup
    # steady unflighted bed: m_s = F/u_s (kg/m)
    F, u = ss.model.parameters["feed_rate"], ss.model.parameters["kiln_velocity"]
    bed = ss.masses[ss.phase == "bed"]
    dz = 7.5 / ss.model.parameters["unflighted_cells"]["E"]
    np.testing.assert_allclose(bed[-10:] / dz, F / u, rtol=1e-9)


@pytest.mark.parametrize("inlet", ["ajayi", "danckwerts"])
def test_balance_and_recovery(inlet):
    ss = steady(**{"transport.unflighted_inlet": inlet})
    assert ss.mass_balance_error < 1e-9
    mom = ss.tracer_system().moments()
    assert mom["recovery"] == pytest.approx(1.0, abs=1e-6)
    r = ss.rtd(t_end=3600.0, dt=10.0)  # 282 nodes: BDF2 (O(dt^2)) with 5 s internal steps
    assert r.response.moments()["recovery"] == pytest.approx(1.0, abs=1e-4)
    assert r.response.moments()["mean"] == pytest.approx(r.moments["mean"], rel=1e-3)
    assert r.response.moments()["std"] == pytest.approx(r.moments["std"], rel=5e-3)
    exact = ss.rtd(t_end=3600.0, dt=10.0, method="expm").response.moments()
    assert exact["mean"] == pytest.approx(r.moments["mean"], rel=1e-8)


def test_unflighted_grid_independence():
    a = steady().rtd(simulate=False).moments
    n = steady().model.parameters["unflighted_cells"]
    b = steady(**{"transport.unflighted_cells": 2 * max(n.values())}).rtd(simulate=False).moments
    assert b["mean"] == pytest.approx(a["mean"], rel=2e-3)
    assert b["std"] == pytest.approx(a["std"], rel=0.03)


@pytest.mark.parametrize("pe", [5.0, 40.0])
def test_closed_dispersion_section_matches_analytic(pe):
    # one unflighted section with the Danckwerts (closed) inlet: mean L/u and the closed-closed
    # variance sigma^2/tau^2 = 2/Pe - 2/Pe^2 (1 - exp(-Pe)) (Levenspiel)
    L, u = 5.0, 0.02
    D = u * L / pe
    m = ajayi2011(sections=[dict(name="A", kind="unflighted", length=L)], feed_rate=10.0, rpm=3, slope=4,
                  radius=1.95, kiln_velocity=u, dispersion=D, geometries={}, inlet="danckwerts",
                  unflighted_cells=800, material=load_material("zinc_concentrate_ajayi2011"))
    mom = m.steady_state().tracer_system().moments()
    tau = L / u
    assert mom["mean"] == pytest.approx(tau, rel=1e-9)
    assert mom["variance"] / tau**2 == pytest.approx(2 / pe - 2 / pe**2 * (1 - math.exp(-pe)), rel=0.01)


def test_holdup_trends():
    base = steady().total_holdup
    feed = build_model(load_case("ajayi2011_mmg", {"operating.feed_rate": 45.0})).steady_state().total_holdup
    assert feed > base
    fast = steady(**{"operating.rpm": 4.0}).total_holdup
    slow = steady(**{"operating.rpm": 2.0}).total_holdup
    assert slow > base > fast


def test_exact_geometry_runs():
    ss = steady(**{"geometry.method": "exact"})
    assert ss.mass_balance_error < 1e-9
    assert 0.9 < ss.total_holdup / float(TESTS[4]["holdup_model_kg"]) < 1.1


def test_auto_grid_keeps_cell_peclet_below_two():
    n = unflighted_cells_auto(7.5, 0.01557, 0.000399686)
    assert 0.01557 * 7.5 / n / 0.000399686 <= 2.0


@pytest.mark.parametrize("ov, key", [
    ({"operating.test": 7}, r"operating\.test = 7"),
    ({"transport.dispersion": -1}, r"transport\.dispersion = -1"),
    ({"transport.solids_velocity": 0}, r"transport\.solids_velocity = 0"),
    ({"transport.n_cell": 3}, r"unknown override key 'transport\.n_cell'"),
])
def test_bad_input(ov, key):
    with pytest.raises(ValueError, match=key):
        build_model(load_case("ajayi2011_mmg", ov))


def test_test_1_not_modelled():
    """Ajayi's Table 5.2 has no Test 1: in the thesis configuration it has no u_s, D."""
    with pytest.raises(ValueError, match=r"operating\.test = 1"):
        build_model(load_case("ajayi2011_mmg", {"operating.test": 1, "geometry.method": "ajayi2011_regressions"}))
