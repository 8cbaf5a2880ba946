"""One model for any flighted dryer (issue 12): the general case schema, the materials library and
heat and mass transfer on the transport network, through ``rotarydryer.Simulation``."""

import json
import re
import tomllib
from importlib import resources

import numpy as np
import pytest
from typer.testing import CliRunner

from rotarydryer import Simulation
from rotarydryer.cli import app
from rotarydryer.transport.sections import build_sections

NAMES = ("total_holdup_kg", "mean_residence_time_s", "tracer_mean_s", "tracer_std_s", "product_moisture_kg_kg",
         "product_temperature_degC", "gas_outlet_temperature_degC", "energy_balance_error", "water_balance_error")
runner = CliRunner()


def _template_text():
    return (resources.files("rotarydryer.cases") / "templates" / "dryer.toml").read_text()


def _write(tmp_path, name, text):
    p = tmp_path / f"{name}.toml"
    p.write_text(text)
    return str(p)


def _mmg_reversed(tmp_path):
    """The MMG dryer with its sections in reverse order and the gas counter-current."""
    text = (resources.files("rotarydryer.cases") / "ajayi2011_mmg.toml").read_text()
    head, *secs = re.split(r"(?m)^\[\[sections\]\]\n", text)
    last, tests = re.split(r"(?m)^(?=# Tests:)", secs[-1], maxsplit=1)
    secs[-1] = last
    body = "".join("[[sections]]\n" + s.rstrip() + "\n\n" for s in reversed(secs))
    head = head.replace('gas_flow = "co-current"', 'gas_flow = "counter-current"')
    return _write(tmp_path, "mmg_reversed", head + body + tests)


def _two_section_sand(tmp_path):
    text = _template_text()
    first = ('[[sections]]\nname = "lifting"\nkind = "flighted"\nlength = 4.0\nn_cells = 8\ns1 = 0.12\ns2 = 0.0\n'
             'alpha1 = 90.0\nalpha2 = 90.0\n\n')
    text = re.sub(r'(?ms)^\[\[sections\]\]\s*#[^\n]*\nname = "inlet".*?(?=^\[\[sections\]\])', first, text)
    text = text.replace('length = 11.0            # m', 'length = 8.0')
    return _write(tmp_path, "sand_two_flighted", text)


@pytest.fixture(scope="module")
def shipped():
    out = {}
    for name, ov in (("lee2008_invicta", {}), ("ajayi2011_mmg", {"operating.test": 5}), ("song2003_ottawa", {})):
        out[name] = Simulation(name, ov).steady_state().summary()
    return out


@pytest.mark.parametrize("name", ["lee2008_invicta", "ajayi2011_mmg", "song2003_ottawa"])
def test_shipped_cases_report_transport_and_thermal(shipped, name):
    out = shipped[name]
    for key in NAMES:
        assert key in out and np.isfinite(out[key]), key
    assert out["energy_balance_error"] < 1e-9
    assert out["water_balance_error"] < 1e-9
    assert out["solids_balance_error"] < 1e-9
    assert out["mass_balance_error"] < 1e-9       # wet solids: feed = product + evaporation
    assert out["recovery"] == pytest.approx(1.0, abs=1e-9)
    # one total holdup: the phases add up to it, and H/F is its residence time
    parts = out["active_holdup_kg"] + out["passive_holdup_kg"] + out["bed_holdup_kg"]
    assert parts == pytest.approx(out["total_holdup_kg"], rel=1e-12)
    assert out["mean_residence_time_s"] == pytest.approx(out["total_holdup_kg"] / out["outlet_flow_kg_s"], rel=1e-12)
    # the product is drier than the feed, and the gas leaves colder than it came
    assert out["evaporation_kg_s"] > 0


def test_invicta_dries_counter_current_with_computed_repose_angle(shipped):
    out = shipped["lee2008_invicta"]
    sim = Simulation("lee2008_invicta")
    d = sim.thermal_dryer()
    assert d.settings.gas_direction == "counter-current"
    assert d.gas_outlet_stage == 0                  # the gas leaves at the solids inlet
    ss = d.steady_state()
    law = d.laws[0]
    x = ss.moisture_wet[law.P]
    # Lee (2008) Eq. 7.2 on the computed (dry-basis) moisture, not the Eq. 7.3 profile
    phi = law.evaluate(ss.holdup[law.P], x)["repose_angle"]
    assert np.allclose(phi, 1222.2 * x / (1 - x) + 34.5, rtol=1e-12)
    assert np.all(np.diff(x) < 0)                   # dries along the drum
    assert out["product_moisture_kg_kg"] < 0.02 / 1.02


def test_cli_simulate_json_names(tmp_path):
    for args in (["lee2008_invicta"], ["ajayi2011_mmg", "--set", "operating.test=5"], ["song2003_ottawa"]):
        r = runner.invoke(app, ["simulate", *args, "--json"])
        assert r.exit_code == 0, r.output
        d = json.loads(r.output)
        for key in NAMES:
            assert key in d, (args, key)
        assert d["energy_balance_error"] < 1e-9


def test_one_name_one_value_in_every_view():
    """simulate --json, Results (report, app) and sweep rows give the same value for each name."""
    from rotarydryer.cli.sweep import run_point
    from rotarydryer.results import run_case

    ov = {"operating.test": 5}
    r = runner.invoke(app, ["simulate", "ajayi2011_mmg", "--set", "operating.test=5", "--json"])
    cli = json.loads(r.output)
    res = run_case("ajayi2011_mmg", ov, rtd=False).scalars
    row = run_point("ajayi2011_mmg", ov, False)
    summary = Simulation("ajayi2011_mmg", ov).steady_state().summary()
    for key in ("total_holdup_kg", "mean_residence_time_s", "tracer_mean_s", "tracer_std_s", "outlet_flow_kg_s",
                "rtd_std_s", "rtd_mean_residence_time_s",
                "product_moisture_kg_kg", "product_temperature_degC", "gas_outlet_temperature_degC",
                "evaporation_kg_s", "fuel_rate_kg_s", "energy_balance_error"):
        assert cli[key] == pytest.approx(summary[key], rel=1e-9, abs=1e-15), key
        assert res[key] == pytest.approx(summary[key], rel=1e-9, abs=1e-15), key
        if key in row:
            assert row[key] == pytest.approx(summary[key], rel=1e-9, abs=1e-15), key
    # the coupled phases add up to the one total holdup in every view
    assert res["active_holdup_kg"] + res["passive_holdup_kg"] + res["bed_holdup_kg"] == pytest.approx(
        res["total_holdup_kg"], rel=1e-12)
    assert "kiln_bed_holdup_kg" not in cli and "kiln_bed_holdup_kg" not in res


def test_new_template_runs_as_written(tmp_path):
    path = tmp_path / "mydryer.toml"
    r = runner.invoke(app, ["new", "mydryer", "--out", str(path)])
    assert r.exit_code == 0, r.output
    r = runner.invoke(app, ["simulate", str(path), "--json"])
    assert r.exit_code == 0, r.output
    d = json.loads(r.output)
    for key in NAMES:
        assert key in d
    assert d["energy_balance_error"] < 1e-9
    assert d["product_moisture_kg_kg"] < 0.06


def test_mmg_sections_reversed_counter_current(tmp_path):
    out = Simulation(_mmg_reversed(tmp_path), {"operating.test": 4}).steady_state().summary()
    co = Simulation("ajayi2011_mmg", {"operating.test": 4}).steady_state().summary()
    assert out["energy_balance_error"] < 1e-9 and out["water_balance_error"] < 1e-9
    assert out["evaporation_kg_s"] > 0
    assert out["total_holdup_kg"] != pytest.approx(co["total_holdup_kg"], rel=1e-3)


def test_two_section_flighted_sand_dryer(tmp_path):
    sim = Simulation(_two_section_sand(tmp_path))
    assert [s["name"] for s in sim.transport_model().sections] == ["lifting", "flighted"]
    out = sim.steady_state().summary()
    assert out["energy_balance_error"] < 1e-9 and out["water_balance_error"] < 1e-9
    assert out["bed_holdup_kg"] == 0.0
    counter = Simulation(_two_section_sand(tmp_path), {"gas.direction": "counter-current"}).steady_state().summary()
    assert counter["energy_balance_error"] < 1e-9 and counter["water_balance_error"] < 1e-9


@pytest.mark.parametrize("name,ov", [("lee2008_invicta", {}), ("ajayi2011_mmg", {"operating.test": 4}),
                                     ("song2003_ottawa", {})])
def test_without_evaporation_thermal_holdups_equal_transport(name, ov):
    """Evaporation and heat transfer off (area 0) and the transport profile's moisture: the thermal
    model's holdups per node equal the transport network's (same nodes, same families) to 1e-9."""
    sim = Simulation(name, ov)
    d = sim.thermal_dryer(area_scale=0.0, moisture_coupling=False, design_load_smoothing=0.0)
    ss = d.steady_state()
    M = d.model.network.steady_state() * d.feed_rate / d.model.feed_rate
    assert np.max(np.abs(ss.holdup - M)) <= 1e-9 * np.max(M)


@pytest.mark.parametrize("ov", [{"operating.feed_rate": 2.0, "operating.feed_moisture": 0.08},
                                {"gas.inlet_temperature": 180.0, "operating.feed_moisture": 0.03}])
def test_balances_close_on_other_operating_points(ov):
    out = Simulation_from_template(ov).steady_state().summary()
    assert out["energy_balance_error"] < 1e-9
    assert out["water_balance_error"] < 1e-9
    assert out["product_moisture_kg_kg"] <= ov["operating.feed_moisture"] + 1e-12


def Simulation_from_template(ov):
    import tempfile
    from pathlib import Path

    d = Path(tempfile.mkdtemp())
    p = d / "t.toml"
    p.write_text(_template_text())
    return Simulation(str(p), ov)


# ---- bad input --------------------------------------------------------------------------------
def _cli_error(args):
    r = runner.invoke(app, args)
    assert r.exit_code == 2, r.output
    msg = r.output.strip().splitlines()
    assert "Traceback" not in r.output
    return r.output


def test_material_outside_its_moisture_range(tmp_path):
    p = _write(tmp_path, "wet", _template_text())
    out = _cli_error(["simulate", p, "--set", "operating.feed_moisture=0.5"])
    assert "operating.feed_moisture = 0.5" in out and "ottawa_sand_song2003" in out and "0.2" in out


def test_unknown_material(tmp_path):
    p = _write(tmp_path, "unk", _template_text().replace('name = "ottawa_sand_song2003"', 'name = "unobtainium"'))
    out = _cli_error(["simulate", p])
    assert "unobtainium" in out and "raw_sugar_lee2008" in out


def test_empty_and_zero_length_sections(tmp_path):
    text = _template_text()
    no_secs = re.sub(r"(?ms)^\[\[sections\]\].*?(?=^\[gas\])", "", text)
    out = _cli_error(["simulate", _write(tmp_path, "nosec", no_secs)])
    assert "sections" in out
    zero = text.replace("length = 11.0            # m", "length = 0.0")
    out = _cli_error(["simulate", _write(tmp_path, "zero", zero)])
    assert "sections.1.length = 0.0" in out and "greater than 0" in out


def test_build_sections_rejects_empty_list():
    with pytest.raises(ValueError, match=r"sections = \[\] is empty"):
        build_sections([], material=None, feed_rate=1.0, rpm=3.0, slope=2.0)


def test_no_plant_numbers_in_the_thermal_model():
    """Section letters, the zinc laws and MMG constants live in case and material data only."""
    src = (resources.files("rotarydryer.thermal") / "dryer.py").read_text()
    for pattern in ('"B"', '"E"', "419.6", "2043.8", "mmg_", "TRANSPORT_MOISTURE_RANGE", '{"A"', "_SHELL_T"):
        assert pattern not in src, pattern
    data = tomllib.loads((resources.files("rotarydryer.cases") / "ajayi2011_mmg.toml").read_text())
    assert data["thermal"]["unflighted_cells"] == {"A": 12, "E": 24}
