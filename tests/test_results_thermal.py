"""Results of a case with a heat and mass transfer model carry the thermal outputs."""

import pytest

pytest.importorskip("xarray")

from rotarydryer.results import Results
from rotarydryer.simulation import run_case  # noqa: E402


def test_thermal_outputs_saved_and_loaded(tmp_path):
    res = run_case("ajayi2011_mmg", {"operating.test": 4}, rtd=False)
    assert {"thermal_solids", "thermal_gas", "energy_balance"} <= set(res.datasets)
    eb = res.datasets["energy_balance"]
    p_in = float(eb.power.values[eb.direction.values == "in"].sum())
    p_out = float(eb.power.values[eb.direction.values == "out"].sum())
    assert abs(p_in - p_out) <= 1e-6 * p_in  # the energy balance closes
    assert res.scalars["energy_balance_error"] < 1e-6
    assert 0.0 < res.scalars["product_moisture_kg_kg"] < 0.2
    assert res.datasets["thermal_gas"].temperature.attrs["units"] == "degC"
    path = res.save(tmp_path / "t4.nc")
    assert Results.load(path) == res


def test_transport_only_when_asked():
    res = run_case("ajayi2011_mmg", {"operating.test": 4}, rtd=False, thermal=False)
    assert "energy_balance" not in res.datasets
    assert "energy_balance" not in run_case("lee2008_invicta", rtd=False, thermal=False).datasets
    assert "energy_balance" in run_case("lee2008_invicta", rtd=False).datasets    # issue 12: Invicta dries
