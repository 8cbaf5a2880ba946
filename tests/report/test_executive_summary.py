"""Issue 18 part 2 (started): specific energy and thermal efficiency of a coupled steady state, and
the report's executive summary."""

import pytest

from rotarydryer import Simulation
from rotarydryer.properties.water import latent_heat


@pytest.mark.parametrize("case,ov", [("song2003_ottawa", {}), ("ajayi2011_mmg", {"operating.test": 4})])
def test_specific_energy_and_efficiency(case, ov):
    o = Simulation(case, ov).steady_state().summary()
    assert 0.0 < o["thermal_efficiency"] < 1.0
    assert 2500.0 < o["specific_energy_kJ_kg_water"] < 10000.0       # direct dryers: 3-6 MJ/kg
    # the two are one identity: efficiency x specific energy = the evaporation duty per kg of water (the
    # latent heat at the temperatures the water evaporates at, rotarydryer.thermal.audit)
    mean_latent = o["heat_duty_evaporation_W"] / o["evaporation_kg_s"] / 1e3
    assert o["thermal_efficiency"] * o["specific_energy_kJ_kg_water"] == pytest.approx(mean_latent, rel=1e-9)
    # ... close to the latent heat at the evaporation temperature (IAPWS; the model's vapour is ideal-gas)
    lam = float(latent_heat(o["evaporation_temperature_degC"])) / 1e3
    assert mean_latent == pytest.approx(lam, rel=5e-3)
    # the heat input exceeds what evaporation and the shell take out of the gas
    assert o["heat_input_W"] > o["evaporation_kg_s"] * lam * 1e3


def test_hotter_gas_costs_more_per_kg_of_water():
    lo = Simulation("song2003_ottawa", {"gas.inlet_temperature": 100.0}).steady_state().summary()
    hi = Simulation("song2003_ottawa", {"gas.inlet_temperature": 140.0}).steady_state().summary()
    assert hi["heat_input_W"] > lo["heat_input_W"]


def test_report_opens_with_an_executive_summary():
    from rotarydryer.report.html import render_report
    from rotarydryer.simulation import run_case

    text = render_report(run_case("song2003_ottawa"))
    i = text.index('id="executive-summary"')
    assert i < text.index('id="summary"') and i < text.index('id="energy"')
    assert "kJ" in text[i:i + 3000] and "Product moisture" in text[i:i + 3000]


def test_figures_are_numbered_with_captions_in_reading_order():
    import re

    from rotarydryer.report.html import render_report
    from rotarydryer.simulation import run_case

    text = render_report(run_case("song2003_ottawa"))
    numbers = [int(n) for n in re.findall(r"<figcaption><b>Figure (\d+)\.</b>", text)]
    assert numbers == list(range(1, len(numbers) + 1)) and len(numbers) >= 4
    assert "@@FIGURE" not in text
    # every picture is a numbered figure: the PNGs and the inline SVG drawing of the dryer
    assert text.count("<figure") == text.count("<img ") + text.count("<svg ") == len(numbers)
