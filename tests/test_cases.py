"""Case files: loading, overrides, validation errors, both geometry methods."""

import numpy as np
import pytest

from rotarydryer.cases import LeeCase, build_model, list_cases, load_case, measured_rtd, valid_override_keys

REQUIRED_LEE_KEYS = ["transport.n_cells", "transport.kiln_time", "transport.backmix",
                     "transport.drag_reduction", "geometry.method"]


def test_packaged_cases():
    assert "lee2008_invicta" in list_cases()


def test_lee_override_keys_exist():
    keys = valid_override_keys(LeeCase)
    for k in REQUIRED_LEE_KEYS:
        assert k in keys


def test_defaults_and_table_7_2_lookup():
    c = load_case("lee2008_invicta")
    assert c.geometry.method == "exact"
    assert c.transport.n_cells == 35
    m = build_model(load_case("lee2008_invicta", {"geometry.method": "lee2008_regressions",
                                                  "transport.n_cells": "33"}))
    assert m.parameters["kiln_time"] == 9.28 and m.parameters["backmix"] == 0.57
    assert m.parameters["drag_reduction"] == 0.41 and m.parameters["n_cells"] == 33


def test_explicit_coefficients_override_table():
    m = build_model(load_case("lee2008_invicta", {"geometry.method": "lee2008_regressions",
                                                  "transport.kiln_time": 7.704, "transport.backmix": 0.5374,
                                                  "transport.drag_reduction": 0.3649}))
    assert m.parameters["kiln_time"] == 7.704


def test_unknown_key_lists_valid_keys():
    with pytest.raises(ValueError, match=r"unknown override key 'transport\.ncells'.*transport\.n_cells"):
        load_case("lee2008_invicta", {"transport.ncells": 3})


@pytest.mark.parametrize("key, value, match", [
    ("transport.n_cells", "abc", r"transport\.n_cells = 'abc'"),
    ("transport.n_cells", 0, r"transport\.n_cells = 0"),
    ("transport.backmix", 1.5, r"transport\.backmix = 1\.5"),
    ("transport.kiln_time", -1, r"transport\.kiln_time = -1"),
    ("geometry.method", "bogus", r"geometry\.method = 'bogus'"),
    ("operating.feed_rate", -3, r"operating\.feed_rate = -3"),
])
def test_invalid_values_name_key_and_value(key, value, match):
    with pytest.raises(ValueError, match=match):
        load_case("lee2008_invicta", {key: value})


def test_n_cells_above_limit_and_without_parameters():
    # no calibration of N = 40: the closest (Lee's N = 35) is used, with a warning, and its coefficients
    # do not fit 40 cells
    from rotarydryer.cases.calibration import CalibrationWarning

    with pytest.warns(CalibrationWarning, match="transport.n_cells = 35"), \
            pytest.raises(ValueError, match=r"transport\.n_cells = 40 makes the return coefficient"):
        build_model(load_case("lee2008_invicta", {"transport.n_cells": 40, "geometry.method": "lee2008_regressions"}))
    with pytest.raises(ValueError, match=r"transport\.n_cells = 40 makes the return coefficient.*<= 37"):
        build_model(load_case("lee2008_invicta", {
            "transport.n_cells": 40, "geometry.method": "lee2008_regressions", "transport.kiln_time": 8.69,
            "transport.backmix": 0.68, "transport.drag_reduction": 0.48}))


def test_unknown_case():
    with pytest.raises(ValueError, match="lee2008_invicta"):
        load_case("no_such_case")


@pytest.mark.parametrize("method", ["exact", "lee2008_regressions"])
def test_both_geometry_methods_run(method):
    ss = build_model(load_case("lee2008_invicta", {"geometry.method": method})).steady_state()
    assert ss.mass_balance_error < 1e-9
    assert 10000 < ss.total_holdup < 30000  # Invicta: ~14 000 kg known (Lee l.10913)
    assert ss.rtd(simulate=False).moments["recovery"] == pytest.approx(1.0, abs=1e-6)


def test_measured_invicta_rtd_moments():
    # Lee (2008) Table 7.3, experiment: mean 11.08 min, SD 6.73 min (times from injection start)
    t, E = measured_rtd(load_case("lee2008_invicta"))
    m0 = np.trapezoid(E, t)
    mean = np.trapezoid(t * E, t) / m0
    sd = np.sqrt(np.trapezoid((t - mean) ** 2 * E, t) / m0)
    assert m0 == pytest.approx(1.0, abs=1e-3)
    assert mean / 60 == pytest.approx(11.08, abs=0.005)
    assert sd / 60 == pytest.approx(6.73, abs=0.005)


def test_ajayi_case_keys_and_methods():
    from rotarydryer.cases import AjayiCase

    assert "operating.test" in valid_override_keys(AjayiCase)
    assert "ajayi2011_mmg" in list_cases()
    for method in ("ajayi2011_regressions", "exact"):
        ss = build_model(load_case("ajayi2011_mmg", {"geometry.method": method, "operating.test": "6"})).steady_state()
        assert ss.mass_balance_error < 1e-9


def test_case_from_toml_path(tmp_path):
    from importlib import resources

    text = (resources.files("rotarydryer.cases") / "lee2008_invicta.toml").read_text()
    p = tmp_path / "my.toml"
    p.write_text(text.replace("n_cells = 35             #", "n_cells = 31             #"))
    assert load_case(str(p)).transport.n_cells == 31


def test_ajayi_measured_rtd_follows_test_and_baseline():
    from rotarydryer.cases import measured_rtd_moments

    m4 = measured_rtd_moments(load_case("ajayi2011_mmg"))
    m6 = measured_rtd_moments(load_case("ajayi2011_mmg", {"operating.test": 6}))
    assert m4["baseline"] > 0 and m4["baseline_method"] == "leading"
    # Ajayi Table 3.13: 15.21 and 15.61 min (his background/truncation treatment is not stated)
    assert m4["mean_s"] / 60 == pytest.approx(15.21, rel=0.02)
    assert m6["mean_s"] / 60 == pytest.approx(15.61, rel=0.02)
