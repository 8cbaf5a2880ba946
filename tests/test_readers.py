"""The plant formats (kind lee2008, ajayi2011) are readers into the one dryer specification."""

from pathlib import Path

import pytest

from rotarydryer import Simulation
from rotarydryer.cases import DryerCase, load_case, load_case_text

LEGACY = Path(__file__).parent / "data" / "legacy"


#: the thesis configurations, where the shipped cases' calibration records hold the published values
#: the old files carry as plain keys ([[parameter_sets]], the tests' u_s and D, thermal.mode_values)
THESIS = {"lee2008_invicta": {"geometry.method": "lee2008_regressions"},
          "ajayi2011_mmg": {"geometry.method": "ajayi2011_regressions"}}
#: what the shipped cases hold beyond the old formats: the calibration records and the plant's measured outlets
#: (Lee's Table 7.2 values: a [[parameter_sets]] row in the old file, the record's transport keys in the new;
#: test_old_file_gives_the_same_steady_state checks they are the same numbers)
_NEW_ONLY = ("calibrations", "parameter_sets", "mode_values", "gas_outlet_temperature", "product_temperature",
             "holdup_measured_kg", "moisture_profile", "kiln_time", "backmix", "drag_reduction",
             "kiln_bed_area")   # the thesis-geometry physical calibration was fitted without the kiln beds


def _comparable(d):
    if isinstance(d, dict):
        return {k: _comparable(v) for k, v in d.items() if k not in _NEW_ONLY}
    if isinstance(d, list):
        return [_comparable(v) for v in d]
    return d


@pytest.mark.parametrize("name", ["lee2008_invicta", "ajayi2011_mmg"])
def test_old_file_reads_into_the_shipped_spec(name):
    old = load_case(str(LEGACY / f"{name}.toml"), THESIS[name])
    new = load_case(name, THESIS[name])
    assert isinstance(old, DryerCase) and isinstance(new, DryerCase)
    assert _comparable(old.model_dump()) == _comparable(new.model_dump())


@pytest.mark.parametrize("name, overrides", [
    ("lee2008_invicta", {"transport.n_cells": 30, "thermal.enabled": False, **THESIS["lee2008_invicta"]}),
    ("ajayi2011_mmg", {"operating.test": 3, **THESIS["ajayi2011_mmg"]}),
])
def test_old_file_gives_the_same_steady_state(name, overrides):
    a = Simulation(str(LEGACY / f"{name}.toml"), overrides).transport_steady_state()
    b = Simulation(name, overrides).transport_steady_state()
    assert a.total_holdup == pytest.approx(b.total_holdup, rel=1e-12)


def test_old_override_keys_warn_and_name_the_replacement():
    with pytest.warns(FutureWarning, match="'solids.moisture_inlet' is deprecated: use 'operating.feed_moisture'"):
        old = load_case("lee2008_invicta", {"solids.moisture_inlet": 0.015})
    assert old.operating.feed_moisture == pytest.approx(0.015 / 1.015, rel=1e-15)
    with pytest.warns(FutureWarning, match="use 'gas.inlet_temperature'"):
        c = load_case("ajayi2011_mmg", {"thermal.gas_inlet_temperature": 480})
    assert c.gas.inlet_temperature == 480
    new = Simulation("ajayi2011_mmg", {"gas.inlet_temperature": 480}).thermal_settings()
    assert new.gas_inlet_temperature == 480


def test_one_gas_direction_in_an_old_lee_file():
    text = (LEGACY / "lee2008_invicta.toml").read_text()
    text = text.replace('direction = "counter-current"', 'direction = "co-current"')
    with pytest.raises(ValueError, match=r"gas\.direction = 'co-current' disagrees with operating\.gas_flow"):
        load_case_text(text, "old.toml")


def test_the_test_row_gives_the_operating_point():
    from rotarydryer.cases.build import operating_point, product_moisture

    c = load_case("ajayi2011_mmg", {"operating.test": 5})
    assert operating_point(c)[:3] == (32.333333, 2.0, 0.1653)
    assert product_moisture(c) == 0.12
    assert Simulation("ajayi2011_mmg", {"operating.test": 5}).thermal_settings().gas_inlet_temperature == 509.0
    with pytest.raises(ValueError, match=r"operating\.test = 9 is not in the case's \[\[tests\]\]"):
        load_case("ajayi2011_mmg", {"operating.test": 9})


def test_an_old_mmg_file_without_regression_coefficients_names_them():
    text = (LEGACY / "ajayi2011_mmg.toml").read_text()
    start = text.index("regression.area = [-8.44")
    text = text[:start] + text[text.index("\n", start) + 1:]        # section B loses its area coefficients
    with pytest.raises(ValueError, match=r"sections\[1\] \(B\)\.regression\.area = None: geometry\.method = "
                                         r"'ajayi2011_regressions' needs 7 coefficients"):
        load_case_text(text, "old.toml", {"geometry.method": "ajayi2011_regressions"})
    assert load_case_text(text, "old.toml").geometry.method == "exact"     # the exact geometry does not need them


def test_a_test_rows_gas_flow_leaves_the_format_default_for_the_others():
    text = (LEGACY / "ajayi2011_mmg.toml").read_text()
    text = text.replace("test = 4\n", "test = 4\ngas_flow = 20.0\n", 1)
    assert Simulation(load_case_text(text, "old.toml")).thermal_settings().gas_flow == 20.0
    assert Simulation(load_case_text(text, "old.toml", {"operating.test": 5})).thermal_settings().gas_flow == 16.25


def test_an_old_key_and_its_replacement_together_are_refused():
    with pytest.raises(ValueError, match="'transport.kiln_velocity' and 'transport.solids_velocity' set the same"):
        load_case("ajayi2011_mmg", {"transport.solids_velocity": 0.01, "transport.kiln_velocity": 0.05})


def test_the_thesis_formats_load_on_first_use():
    """A ``kind = "dryer"`` case (every shipped case) never loads the thesis formats' schemas (10 ms of a one-off
    command); a file of one does, and the package's old names are still there."""
    import subprocess
    import sys

    code = ("import sys\nfrom rotarydryer.cases import load_case\nload_case('lee2008_invicta', {'solids.moisture_inlet': "
            "0.1})\nprint('rotarydryer.cases.readers' in sys.modules)\n"
            f"load_case({str(LEGACY / 'lee2008_invicta.toml')!r})\nprint('rotarydryer.cases.readers' in sys.modules)\n"
            "from rotarydryer.cases import AjayiCase, CASE_KINDS, CASE_MODELS, LEGACY_KEYS, LeeCase, SCHEMAS\n"
            "print(CASE_KINDS == ('dryer', *SCHEMAS), CASE_MODELS['lee2008'] is LeeCase, "
            "'solids.moisture_inlet' in LEGACY_KEYS, AjayiCase.__name__)")
    out = subprocess.run([sys.executable, "-W", "ignore", "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["False", "True", "True", "True", "True", "AjayiCase"]


def test_the_packages_case_models_are_one_object():
    import rotarydryer.cases as cases

    assert cases.CASE_MODELS is cases.CASE_MODELS and cases.READERS is cases.READERS
    # the package's list of the readers' names is their module's own list (less what cases.legacy_keys provides)
    from rotarydryer.cases import readers

    assert cases._READER_NAMES == set(readers.__all__) - {"translate_legacy_overrides"}


def test_an_unknown_name_of_the_package_is_an_attribute_error():
    import rotarydryer.cases as cases

    with pytest.raises(AttributeError, match="has no attribute 'LeeCas'"):
        cases.LeeCas  # noqa: B018
    with pytest.raises(ValueError, match=r"kind = 'lee2009' is not one of 'dryer', 'lee2008', 'ajayi2011'"):
        load_case_text('kind = "lee2009"\n')
