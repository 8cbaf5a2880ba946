"""A material's ``max_temperature``: solids hotter than it (raw sugar above the 186 degC where sucrose melts) get a
`SolidsTemperatureWarning` naming where and how hot; a bad limit is refused naming the key."""

from __future__ import annotations

import warnings

import pytest
from typer.testing import CliRunner

from rotarydryer import Simulation
from rotarydryer.cli import app
from rotarydryer.properties.materials import library_table, load_material
from rotarydryer.thermal.audit import SolidsTemperatureWarning, solids_temperature_message


def _hot_warnings(case, overrides):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = Simulation(case, overrides).steady_state()
    return res, [str(w.message) for w in caught if issubclass(w.category, SolidsTemperatureWarning)]


def test_raw_sugar_carries_its_melting_point():
    m = load_material("raw_sugar_lee2008")
    assert m.max_temperature == 186.0 and "sucrose" in m.max_temperature_source
    assert load_material("ottawa_sand_song2003").max_temperature is None      # no source gives one


def test_sugar_heated_past_its_melting_point_warns():
    # a random user dryer heated raw sugar to 415 degC without a word: a hot gas on a small feed
    res, msgs = _hot_warnings("lee2008_invicta", {"gas.inlet_temperature": 600.0, "operating.feed_rate": 5.0})
    hottest = float(res.thermal.solids_temperature_degC.max())
    assert hottest > 186.0
    assert len(msgs) == 1, msgs
    assert "material.max_temperature = 186 degC" in msgs[0] and "raw_sugar_lee2008" in msgs[0]
    assert f"{hottest:.4g} degC" in msgs[0] and "gas.inlet_temperature" in msgs[0]


def test_the_shipped_sugar_dryer_stays_below_it():
    res, msgs = _hot_warnings("lee2008_invicta", {})
    assert msgs == [] and float(res.thermal.solids_temperature_degC.max()) < 186.0


@pytest.mark.parametrize("margin, warns", [(-1.0, True), (1.0, False)])
def test_the_limit_is_the_hottest_solids(margin, warns):
    base = Simulation("song2003_ottawa").steady_state().thermal
    hottest = float(base.solids_temperature_degC.max())
    _, msgs = _hot_warnings("song2003_ottawa", {"material.max_temperature": hottest + margin})
    assert bool(msgs) is warns
    if warns:
        assert "section flighted" in msgs[0]


def test_an_emptied_cell_does_not_count():
    """A tank holding no solids takes the gas temperature (a virtual heat capacity): not the solids'."""
    res = Simulation("song2003_ottawa").steady_state().thermal
    t = res.solids_temperature_degC.copy()
    res.solids_temperature_degC = t
    res.holdup = res.holdup.copy()
    res.holdup[0] = 0.0
    t[0] = 1000.0
    assert solids_temperature_message(res) is None


@pytest.mark.parametrize("value", [-5.0, 0.0, 5000.0, "hot", True])
def test_a_bad_limit_is_refused_naming_the_key(value):
    table = library_table("ottawa_sand_song2003")
    table["max_temperature"] = value
    with pytest.raises(ValueError, match=r"material\.max_temperature = .* is outside the allowed range \(0, 3000\) degC"):
        load_material(table)


def test_the_cli_prints_it_once_and_succeeds():
    res = CliRunner().invoke(app, ["simulate", "lee2008_invicta", "--set", "gas.inlet_temperature=600",
                                   "--set", "operating.feed_rate=5", "--json"])
    assert res.exit_code == 0, res.output
    lines = [ln for ln in res.output.splitlines() if "material.max_temperature" in ln]
    assert len(lines) == 1 and lines[0].startswith("warning: the solids reach"), res.output


def test_a_limit_of_the_case_does_not_cite_the_librarys_source():
    """material.max_temperature overridden in a case: the warning cited sucrose's melting point beside the case's
    30 degC (found by a review)."""
    _, msgs = _hot_warnings("lee2008_invicta", {"material.max_temperature": 30.0})
    assert len(msgs) == 1 and "(the case's value)" in msgs[0] and "sucrose" not in msgs[0]
