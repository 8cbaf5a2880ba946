"""Malformed case files: one readable message per problem, with the file line; exit code 2."""

import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from rotarydryer.cases import load_case
from rotarydryer.cases.build import rows_shadowed
from rotarydryer.cli import app

BAD = """kind = "lee2008"

[drum]
radius = "big"
length = -12.0
slope = 2.8
n_flights = 28
colour = "red"

[operating]
feed_rate = 27.2
rpm = 3.0
"""


def test_every_problem_reported_with_its_line(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(BAD)
    with pytest.raises(ValueError) as err:
        load_case(str(path))
    msg = str(err.value)
    assert "7 problems" in msg
    assert f"{path}:4: drum.radius = 'big'" in msg  # wrong type
    assert f"{path}:5: drum.length = -12.0" in msg and "greater than 0" in msg  # out of range
    assert f"{path}:8: drum.colour is not a known field" in msg  # unknown key
    assert "flight is missing" in msg  # missing section


def test_cli_exit_code_and_no_traceback(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(BAD)
    res = CliRunner().invoke(app, ["simulate", str(path)])
    assert res.exit_code == 2
    assert "Traceback" not in res.output
    assert res.output.count("\n") >= 7


def test_override_problem_names_the_set_option():
    with pytest.raises(ValueError, match=r"--set transport.n_cells"):
        load_case("lee2008_invicta", {"transport.n_cells": -3})


def test_invalid_toml_syntax(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("kind = \n[drum")
    with pytest.raises(ValueError, match="not valid TOML"):
        load_case(str(path))


def _mmg_variant(tmp_path, old, new):
    from importlib import resources

    text = (resources.files("rotarydryer.cases") / "ajayi2011_mmg.toml").read_text()
    assert old in text
    path = tmp_path / "mmg.toml"
    path.write_text(text.replace(old, new, 1))
    return str(path)


def test_incomplete_flighted_section_named(tmp_path):
    """A flighted Ajayi section without n_cells, regression coefficients or flight dimensions is
    reported with its index and field (it used to fail later with a raw TypeError / KeyError)."""
    path = _mmg_variant(tmp_path, "n_cells = 8\n", "")
    with pytest.raises(ValueError, match=r"sections\[1\] \(B\)\.n_cells is missing"):
        load_case(path, {"operating.test": 4})
    thesis = {"operating.test": 4, "geometry.method": "ajayi2011_regressions"}
    path = _mmg_variant(tmp_path, "regression.area = ", "regression.areas = ")
    load_case(path, {"operating.test": 4})  # the exact geometry (default) does not need the regressions
    with pytest.raises(ValueError, match=r"regression\.area = None.*7 coefficients"):
        load_case(path, thesis)
    path = _mmg_variant(tmp_path, "s1 = 0.12\n", "")
    load_case(path, thesis)  # the regressions do not need s1
    with pytest.raises(ValueError, match=r"sections\[1\] \(B\)\.s1 is missing"):
        load_case(path, {"operating.test": 4})


def test_test_rows_shadowed_by_the_case_files_operating_are_named(tmp_path):
    """A user case (the `rotarydryer new` template, whose [operating] gives the feed and speed) with [[tests]] rows at
    other speeds: each row runs at the [operating] values, which win. `calibrate` (first of the fit's warnings) and
    `validate` (a note in its report) name the rows and keys and say what to do (before: silent, so a calibration
    over the rows ran every test at one operating point). Values given by the caller (--set operating.rpm) are the
    caller's choice: no note; nor for a shipped case, whose rows give their own operating points."""
    import warnings
    from importlib import resources

    from rotarydryer.estimation.calibrate import calibrate
    from rotarydryer.validate import run_validation

    text = (resources.files("rotarydryer.cases") / "templates" / "dryer.toml").read_text()
    text += ("\n[[tests]]\ntest = 1\nfeed_rate = 2.5\nrpm = 4.0\nfeed_moisture = 0.06\ngas_outlet_temperature = 80.0\n"
             "\n[[tests]]\ntest = 2\nfeed_rate = 2.5\nrpm = 4.5\nfeed_moisture = 0.06\ngas_outlet_temperature = 82.0\n")
    p = tmp_path / "rows.toml"
    p.write_text(text)
    said = (r"\[\[tests\]\] row 2 run at the case's operating.rpm = 4, not at its own: values in \[operating\] win over "
            r"a row's; delete those keys from \[operating\]")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = calibrate(str(p), ["thermal.area_scale"])
        assert re.match(said, cal.fit.warnings[0])
        # the advice, followed, gives a valid case (without operating.test the keys' removal was refused; found by
        # review)
        assert "and give operating.test" in cal.fit.warnings[0]
        rep = run_validation([str(p)])
        assert re.match(said, rep.case_notes[str(p)])
        assert rows_note(calibrate(str(p), ["thermal.area_scale"], base_overrides={"operating.rpm": 4.0})) is None
        assert str(p) not in run_validation([str(p)], {"operating.rpm": 4.0}).case_notes
    assert rows_shadowed(load_case("ajayi2011_mmg")) is None


def rows_note(cal):
    return next((w for w in cal.fit.warnings if "[[tests]] row" in w), None)


@pytest.mark.parametrize("key,value", [("mrt_measured_min", 0.0), ("mrt_measured_min", -3.0), ("mrt_model_min", 0.0),
                                       ("holdup_model_kg", -1.0)])
def test_a_test_rows_measured_or_model_figure_must_be_positive(tmp_path, key, value):
    """A [[tests]] row's measured mean residence time of 0 made `validate` stop with "internal error
    (ZeroDivisionError)", and a negative one was compared as if measured (found by fuzzing): the row is refused
    on load, naming the line and the key."""
    from importlib import resources

    text = (resources.files("rotarydryer.cases") / "templates" / "dryer.toml").read_text()
    text += f"\n[[tests]]\ntest = 1\nfeed_rate = 2.5\nrpm = 4.0\nfeed_moisture = 0.06\n{key} = {value}\n"
    p = tmp_path / "rows.toml"
    p.write_text(text)
    with pytest.raises(ValueError, match=rf"tests\.1\.{key} = {value}: Input should be greater than 0"):     # test 1
        load_case(str(p))


def test_a_product_drier_than_the_materials_range_is_run_at_the_ranges_end(tmp_path):
    """A [[tests]] row's measured product moisture below the material's range (zinc concentrate 0.0062 against
    [0.08, 0.19], the coupled model's own prediction) made every item of `validate` fail with "outside the
    moisture range" (found by fuzzing): the transport-only profile feeds only the repose-angle and bulk-density
    laws, which the coupled model also evaluates at the range's end (transport_moisture_clipped). It now runs,
    with a warning naming the key; a product wetter than the range is still refused."""
    import warnings

    import numpy as np

    from rotarydryer import Simulation
    from rotarydryer.properties.solids import PropertyRangeWarning
    from rotarydryer.validate import run_validation

    base = {"operating.test": 4, "thermal.enabled": False}
    with pytest.warns(PropertyRangeWarning, match=r"transport.product_moisture = 0.006 kg/kg wet is below the moisture "
                      r"range of material 'zinc_concentrate_ajayi2011' \(from 0.08 kg/kg wet\)"):
        dry = Simulation("ajayi2011_mmg", {**base, "transport.product_moisture": 0.006}).transport_steady_state()
    at_end = Simulation("ajayi2011_mmg", {**base, "transport.product_moisture": 0.08}).transport_steady_state()
    np.testing.assert_array_equal(dry.masses, at_end.masses)
    with pytest.raises(ValueError, match=r"transport.product_moisture = 0.25 kg/kg wet is outside the moisture range"):
        Simulation("ajayi2011_mmg", {**base, "transport.product_moisture": 0.25}).transport_steady_state()
    from importlib import resources

    text = (resources.files("rotarydryer.cases") / "ajayi2011_mmg.toml").read_text()
    row = "feed_moisture = 0.163\nproduct_moisture = 0.124\n"
    assert text.count(row) == 1
    p = tmp_path / "dry_row.toml"
    p.write_text(text.replace(row, "feed_moisture = 0.163\nproduct_moisture = 0.0062\n"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rep = run_validation([str(p)])
    rows = [item for item in rep.items if "/test4/" in item.id]
    assert rows and all(not item.message and item.model is not None for item in rows), [i.message for i in rows]
    moist = next(item for item in rows if item.quantity.startswith("product_moisture"))
    assert moist.measured == pytest.approx(0.0062)


def test_a_boolean_where_a_number_is_expected_is_refused(tmp_path):
    """``feed_rate = true`` and ``segments = [[true, 90.0], ...]`` were read as 1.0 (pydantic's lax mode: a 1 m flight
    section, a run that converged; found by fuzzing); booleans stay where the schema has them."""
    res = CliRunner().invoke(app, ["new", "mydryer", "--out", str(tmp_path / "d.toml")])
    assert res.exit_code == 0, res.output
    text = (tmp_path / "d.toml").read_text()
    bad = re.sub(r"(?m)^feed_rate = .*$", "feed_rate = true", text, count=1)
    bad = re.sub(r"(?m)^(\[flight\].*)$", r"\1\nsegments = [[true, 90.0], [0.1, 135.0]]", bad, count=1)
    bad = re.sub(r"(?m)^(s1|s2|alpha1|alpha2) = .*\n", "", bad)
    (tmp_path / "bad.toml").write_text(bad)
    with pytest.raises(ValueError) as err:
        load_case(str(tmp_path / "bad.toml"))
    msg = str(err.value)
    assert "(2 problems)" in msg
    assert re.search(r"bad\.toml:\d+: operating\.feed_rate = True holds a boolean \(true/false\) where a number is "
                     r"expected", msg), msg
    assert re.search(r"bad\.toml:\d+: flight\.segments = \[\[True, 90\.0\], \[0\.1, 135\.0\]\] holds a boolean", msg), msg
    ok = load_case(str(tmp_path / "d.toml"), {"thermal.enabled": False, "geometry.tabulated": True})
    assert ok.thermal.enabled is False


def test_the_misread_checks_remember_shared_blocks_and_find_the_same(tmp_path):
    """The boolean and quoted-number walks remember the blocks of a parsed case text by identity (a study's runs
    share them; each run walks only what its overrides copied): a second load finds the same problems, a copy of
    the document (new blocks) the same, and an override that replaces a flagged value clears it."""
    import copy

    import rotarydryer.cases as cases

    res = CliRunner().invoke(app, ["new", "mydryer", "--out", str(tmp_path / "d.toml")])
    assert res.exit_code == 0, res.output
    text = (tmp_path / "d.toml").read_text()
    bad = re.sub(r"(?m)^feed_rate = .*$", "feed_rate = true", text, count=1)
    bad = re.sub(r"(?m)^radius = .*$", 'radius = "1.0"', bad, count=1)
    raw = dict(cases._parse_text(bad, "bad.toml"))
    cls = cases.DryerCase
    first = (cases._boolean_numbers(cls, raw), cases._text_numbers(cls, raw))
    assert first == ((((("operating", "feed_rate"), True),)), ((("drum", "radius"), "1.0"),))
    assert (cases._boolean_numbers(cls, raw), cases._text_numbers(cls, raw)) == first          # remembered
    fresh = copy.deepcopy(raw)
    assert (cases._boolean_numbers(cls, fresh), cases._text_numbers(cls, fresh)) == first      # walked anew
    changed = {**raw, "operating": {**raw["operating"], "feed_rate": 2.0}}      # copied on write, as the loader does
    assert cases._boolean_numbers(cls, changed) == ()
    (tmp_path / "bad.toml").write_text(bad)
    for _ in range(2):
        with pytest.raises(ValueError, match=r"bad\.toml:\d+: operating\.feed_rate = True holds a boolean"):
            load_case(str(tmp_path / "bad.toml"))
    ok = load_case(str(tmp_path / "bad.toml"), {"operating.feed_rate": 2.0, "drum.radius": 1.0})
    assert ok.operating.feed_rate == 2.0 and ok.drum.radius == 1.0
    # a block given as an override value from Python is the loader's copy: changed in place between two loads, it
    # is checked anew (found by review: a remembered block of the caller's own)
    burner = {"combustion_air_share": 0.2, "fuel_carbon_hydrogen_ratio": 7.6}
    assert load_case("ajayi2011_mmg", {"gas.burner": burner}).gas.burner.fuel_carbon_hydrogen_ratio == 7.6
    burner["fuel_carbon_hydrogen_ratio"] = True
    with pytest.raises(ValueError, match=r"gas\.burner\.fuel_carbon_hydrogen_ratio = True holds a boolean"):
        load_case("ajayi2011_mmg", {"gas.burner": burner})


def test_a_quoted_number_in_a_case_file_is_refused(tmp_path):
    """``radius = "1.0"`` (a TOML string) was read as 1.0 by pydantic's lax mode and ran silently (found by fuzzing):
    refused with the file's line and the fix, exit 2; texts stay where the schema has them (names, choices), and an
    override (the command line's --set, a form's field) may still be text."""
    res = CliRunner().invoke(app, ["new", "mydryer", "--out", str(tmp_path / "d.toml")])
    assert res.exit_code == 0, res.output
    text = (tmp_path / "d.toml").read_text()
    bad = re.sub(r"(?m)^radius = .*$", 'radius = "1.0"', text, count=1)
    bad = re.sub(r"(?m)^feed_rate = .*$", 'feed_rate = "2.5"', bad, count=1)
    (tmp_path / "bad.toml").write_text(bad)
    with pytest.raises(ValueError) as err:
        load_case(str(tmp_path / "bad.toml"))
    msg = str(err.value)
    assert "(2 problems)" in msg, msg
    assert re.search(r"bad\.toml:\d+: drum\.radius = '1\.0' is a text \(a quoted TOML string\) where a number is "
                     r"expected: write the number without quotes", msg), msg
    assert re.search(r"bad\.toml:\d+: operating\.feed_rate = '2\.5' is a text", msg), msg
    res = CliRunner().invoke(app, ["simulate", str(tmp_path / "bad.toml"), "--json"])
    assert res.exit_code == 2 and "drum.radius = '1.0' is a text" in res.output
    # the file's value an override replaces is not the run's: no refusal, and the override's text is a number
    ok = load_case(str(tmp_path / "bad.toml"), {"drum.radius": "1.2", "operating.feed_rate": "2.0"})
    assert ok.drum.radius == 1.2 and ok.operating.feed_rate == 2.0
    # a text that is not a number: the schema's own message, not this one
    with pytest.raises(ValueError, match=r"drum\.radius = 'big'.*valid number"):
        load_case(str(tmp_path / "bad.toml"), {"drum.radius": "big", "operating.feed_rate": 2.0})


def test_one_problem_is_one_line():
    """A case with one problem gave two lines, the first ('invalid case ... (1 problem):') naming no key (found by
    fuzzing): one line; two problems keep their count and a line each."""
    res = CliRunner().invoke(app, ["simulate", "lee2008_invicta", "--set", "operating.feed_rate=-1"])
    assert res.exit_code == 2
    assert res.output.strip() == ("error: invalid case 'lee2008_invicta': --set operating.feed_rate: operating.feed_rate "
                                  "= '-1': Input should be greater than 0 (allowed range (0, 1000] kg/s)")
    with pytest.raises(ValueError, match=r"\(2 problems\):\n--set operating.feed_rate: .*\n--set operating.rpm: "):
        load_case("lee2008_invicta", {"operating.feed_rate": -1, "operating.rpm": -1})


def _reference_holds_bool(value) -> bool:
    if isinstance(value, bool):
        return True
    return isinstance(value, (list, tuple)) and any(_reference_holds_bool(v) for v in value)


_leaves = st.one_of(st.booleans(), st.integers(), st.floats(allow_nan=False), st.text(max_size=3), st.none())


@settings(max_examples=200, deadline=None)
@given(st.recursive(_leaves, lambda inner: st.lists(inner, max_size=4) | st.tuples(inner, inner), max_leaves=12))
def test_boolean_check_of_lists_finds_a_boolean_at_any_depth(value):
    """The case loader's boolean check (numbers tested by type only) agrees with the plain recursive definition."""
    from rotarydryer.cases import _holds_bool

    assert _holds_bool(value) == _reference_holds_bool(value)


def test_a_bad_test_row_is_named_by_its_test_number(tmp_path):
    """A bad value in test 2's [[tests]] row was named `tests.1.product_moisture` (the list index), which the
    calibration keys read as test 1's."""
    from importlib import resources

    text = (resources.files("rotarydryer") / "cases" / "ajayi2011_mmg.toml").read_text()
    head, sep, rest = text.partition("\n[[tests]]\ntest = 2\n")
    assert sep
    rest = re.sub(r"(?m)^product_moisture = [^\n#]*", "product_moisture = nan ", rest, count=1)
    path = tmp_path / "m.toml"
    path.write_text(head + sep + rest)
    with pytest.raises(ValueError, match=r"tests\.2\.product_moisture = nan"):
        load_case(str(path))


def test_an_exhaust_measured_hotter_than_the_gas_and_the_feed_is_refused(tmp_path):
    """A [[tests]] row with an exhaust of 300 degC under a 250 degC gas and a 20 degC feed was accepted; a calibration
    then drove that row's gas flow to 1000 kg/s and exited 0 (found by review): refused when the case loads."""
    from pathlib import Path

    text = (Path(__file__).parent / "data" / "user_dryers" / "plant_tests_rows.toml").read_text()
    bad = text.replace("gas_outlet_temperature = 96.0", "gas_outlet_temperature = 300.0")
    assert bad != text
    (tmp_path / "bad.toml").write_text(bad)
    with pytest.raises(ValueError, match=r"tests\.2\.gas_outlet_temperature = 300 degC is above the gas inlet "
                                         r"temperature \(250 degC\) and the feed's"):
        load_case(str(tmp_path / "bad.toml"))
    ok = load_case(str(Path(__file__).parent / "data" / "user_dryers" / "plant_tests_rows.toml"))
    assert ok.tests[1].gas_outlet_temperature == 96.0


@pytest.mark.parametrize("temperature, humidity, altitude", [(25.0, 0.2, 0.0), (-35.0, 0.01, 0.0), (13.1, 0.0197, 2000.0)])
def test_outside_air_wetter_than_saturated_is_taken_as_saturated_with_a_warning(temperature, humidity, altitude):
    """The outside air's humidity was only held to [0, 0.3] kg/kg: 0.3 at -39 degC ran without a word (found by an
    acceptance check). Above saturation at the ambient temperature and the site's pressure the model takes saturated
    air and says so, naming the key and its range there; at or below it the case's value, unchanged."""
    import warnings

    from rotarydryer import Simulation
    from rotarydryer.cases.build import AmbientHumidityWarning
    from rotarydryer.properties.humid_air import saturation_humidity, standard_atmosphere_pressure

    over = {"shell.ambient_temperature": temperature, "shell.ambient_humidity": humidity, "site.altitude": altitude}
    y_sat = float(saturation_humidity(temperature, standard_atmosphere_pressure(altitude)))
    assert humidity > y_sat
    with pytest.warns(AmbientHumidityWarning, match=r"shell.ambient_humidity = .* give shell.ambient_humidity in \[0, ") as got:
        st = Simulation("ajayi2011_mmg", over).thermal_settings()
    assert st.ambient_humidity == y_sat
    top = float(re.search(r"in \[0, ([0-9.e-]+)\]", str(got[0].message)).group(1))
    assert 0.999 * y_sat < top <= y_sat         # the range's end as typed is not above saturation
    with warnings.catch_warnings():
        warnings.simplefilter("error", AmbientHumidityWarning)
        st = Simulation("ajayi2011_mmg", {**over, "shell.ambient_humidity": 0.999 * y_sat}).thermal_settings()
    assert st.ambient_humidity == 0.999 * y_sat
