"""Materials library (rotarydryer.properties.materials): data files, kernels, validation."""

import re
import warnings
from importlib import resources

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from rotarydryer.properties.materials import Material, list_materials, load_material
from rotarydryer.properties.solids import SOLIDS
from rotarydryer.thermal import balances
from rotarydryer.thermal.drying import MATERIAL_KINETICS
from rotarydryer.transport.ajayi import mmg_bulk_density, mmg_repose_angle

LIBRARY = ["ottawa_sand_song2003", "raw_sugar_lee2008", "zinc_concentrate_ajayi2011"]


def _library_path(name):
    return str(resources.files("rotarydryer.data") / "materials" / f"{name}.toml")


def test_list_materials():
    assert list_materials() == LIBRARY
    assert all(isinstance(load_material(n), Material) for n in LIBRARY)


def test_mmg_equals_transport_kernels_exactly():
    m = load_material("zinc_concentrate_ajayi2011")
    x = np.linspace(0.08, 0.19, 23)
    np.testing.assert_array_equal(m.repose_angle(x), mmg_repose_angle(x))
    np.testing.assert_array_equal(m.bulk_density(x), mmg_bulk_density(x))
    assert m.repose_angle(0.15) == mmg_repose_angle(0.15) and m.bulk_density(0.15) == mmg_bulk_density(0.15)
    assert m.repose_angle_law == SOLIDS["zinc_concentrate_ajayi2011"]["repose"]
    assert m.bulk_density_law == SOLIDS["zinc_concentrate_ajayi2011"]["density_code"]


def test_mmg_matches_ajayi_model_values():
    """The values the thermal model used before the library (balances, ThermalSettings, MATERIAL_KINETICS)."""
    m = load_material("zinc_concentrate_ajayi2011")
    assert m.moisture_basis == "wet" and m.wet_range() == (0.08, 0.19)  # phi = 26-72 deg
    assert m.heat_capacity == balances.AJAYI_CP_SOLIDS and m.water_heat_capacity == balances.AJAYI_CP_WATER
    assert m.particle_density == 2800.0  # Ajayi App. F rho_p
    assert dict(m.particle_diameter_by_section) == {"A": 0.02, "B": 0.015, "C": 0.012, "D": 0.008, "E": 0.007}
    assert m.particle_diameter == 0.012
    assert m.kinetics == MATERIAL_KINETICS["zinc_concentrate_ajayi2011"]


def test_sugar_lee_eq_7_2_through_the_wet_basis():
    m = load_material("raw_sugar_lee2008")
    assert m.moisture_basis == "dry"
    assert m.repose_angle_law == SOLIDS["raw_sugar_lee2008"]["repose"]
    x_wet = 0.02 / 1.02  # w = 0.02 kg/kg dry, Lee's inlet
    assert float(m.to_basis(x_wet)) == pytest.approx(0.02, rel=1e-14)
    assert float(m.repose_angle(x_wet)) == pytest.approx(58.944, abs=1e-9)
    assert float(m.bulk_density(x_wet)) == 940.0
    assert m.wet_range() == pytest.approx((0.0, 0.04 / 1.04))
    assert m.particle_diameter == 850e-6 and m.kinetics.method == "constant_falling"


def test_ottawa_sand_song():
    m = load_material("ottawa_sand_song2003")
    assert m.particle_diameter == pytest.approx(444e-6)
    np.testing.assert_array_equal(m.bulk_density([0.0, 0.1]), [1650.0, 1650.0])
    np.testing.assert_array_equal(m.repose_angle([0.0, 0.2]), [33.0, 33.0])


@pytest.mark.parametrize("name", LIBRARY)
def test_library_data_consistent(name):
    m = load_material(name)
    assert m.citations and m.repose_angle_source and m.bulk_density_source and m.kinetics.source
    lo, hi = m.wet_range()
    assert np.all(m.bulk_density([lo, hi]) < m.particle_density)  # a bed is less dense than its grains
    assert load_material(_library_path(name)) == m  # the same file through the path form
    assert load_material({"name": name}) is m


def test_kernels_are_unchecked():
    m = load_material("zinc_concentrate_ajayi2011")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert float(m.repose_angle(0.5)) == pytest.approx(419.6 * 0.5 - 7.801)
        assert m.bulk_density(np.zeros((2, 3))).shape == (2, 3)


def test_check_moisture():
    m = load_material("raw_sugar_lee2008")
    lo, hi = m.wet_range()
    m.check_moisture("feed.moisture", np.array([lo, 0.01, hi]))  # ends included
    with pytest.raises(ValueError) as exc:
        m.check_moisture("feed.moisture", [0.01, 0.05])
    msg = str(exc.value)
    assert "\n" not in msg
    assert msg == ("feed.moisture = 0.05 kg/kg wet is outside the moisture range of material 'raw_sugar_lee2008' "
                   f"([0, {hi:g}] kg/kg wet; the repose-angle and bulk-density laws (Lee (2008) Eq. 7.2; "
                   "Lee (2008) code, Table 7.1) hold there only)")
    z = load_material("zinc_concentrate_ajayi2011")
    with pytest.raises(ValueError, match=re.escape("outlet.moisture = 0.07 kg/kg wet is outside the moisture "
                                                   "range of material 'zinc_concentrate_ajayi2011' ([0.08, 0.19]")):
        z.check_moisture("outlet.moisture", 0.07)
    with pytest.raises(ValueError, match="x = nan kg/kg wet"):
        z.check_moisture("x", [0.1, float("nan")])


def test_unknown_material():
    with pytest.raises(ValueError) as exc:
        load_material("xyz")
    assert str(exc.value) == ("material = 'xyz' is not in the materials library (ottawa_sand_song2003, "
                              "raw_sugar_lee2008, zinc_concentrate_ajayi2011) nor a .toml file")
    with pytest.raises(ValueError, match="nor a .toml file"):
        load_material("missing_file.toml")


def test_user_toml_file(tmp_path):
    text = open(_library_path("ottawa_sand_song2003"), encoding="utf-8").read()
    good = tmp_path / "wet_sand.toml"
    good.write_text(text.replace('name = "ottawa_sand_song2003"', 'name = "wet_sand"'), encoding="utf-8")
    assert load_material(good).name == "wet_sand" and load_material(str(good)).particle_diameter == 444e-6
    bad = tmp_path / "bad.toml"
    bad.write_text("name = ", encoding="utf-8")
    with pytest.raises(ValueError, match="is not valid TOML"):
        load_material(bad)


def test_inline_override_merges_tables():
    base = load_material("raw_sugar_lee2008")
    m = load_material({"name": "raw_sugar_lee2008", "heat_capacity": 1300,
                       "kinetics": {"critical_moisture": 0.015}, "bulk_density": {"a": 936.06}})
    assert m.heat_capacity == 1300.0 and base.heat_capacity == 1250.0
    assert m.kinetics.critical_moisture == 0.015 and m.kinetics.equilibrium_moisture == 0.0005
    assert m.bulk_density_law == (936.06, 0.0) and m.bulk_density_source == "case-file override"
    assert m.repose_angle_law == base.repose_angle_law and m.particle_diameter == base.particle_diameter


def test_full_inline_definition():
    spec = {"name": "my_ore", "title": "Test ore", "citations": ["choice"], "moisture_basis": "wet",
            "moisture_range": [0.0, 0.1], "repose_angle": {"a": 100.0, "b": 30.0}, "bulk_density": [1500, -1000],
            "heat_capacity": 800, "particle_density": 3000, "particle_diameter": 0.001,
            "kinetics": {"method": "characteristic_curve", "critical_moisture": 0.05, "exponent": 2.0}}
    m = load_material(spec)
    assert m.name == "my_ore" and m.water_heat_capacity == 4182.0
    assert float(m.bulk_density(0.1)) == pytest.approx(1400.0) and m.kinetics.exponent == 2.0


@pytest.mark.parametrize("override, pattern", [
    ({"heat_capacity": -1}, r"^material\.heat_capacity = -1 is outside the allowed range \(0, 10000\) J/\(kg K\)$"),
    ({"particle_diameter": 0.5}, r"material\.particle_diameter = 0\.5 .*\(0, 0\.2\) m"),
    ({"particle_density": "heavy"}, r"material\.particle_density = 'heavy' .*kg/m3"),
    ({"moisture_basis": "moist"}, r"material\.moisture_basis = 'moist' is not one of 'wet', 'dry'"),
    ({"moisture_range": [0.03, 0.01]}, r"material\.moisture_range\[1\] = 0\.01 .*\(0\.03, 10\) kg/kg dry"),
    ({"moisture_range": [0.0, 0.1]}, r"material\.repose_angle gives 156\.72 deg .*\(0, 90\)"),
    ({"kinetics": {"equilibrium_moisture": 0.02}}, r"material\.kinetics\.critical_moisture = 0\.01 .*"
                                                   r"\(equilibrium_moisture = 0\.02, 10\)"),
    ({"kinetics": {"method": "bogus"}}, r"material\.kinetics\.method = 'bogus'"),
    ({"kinetics": {"rate": 1}}, r"material\.kinetics\.rate is not a field"),
    ({"colour": "brown"}, r"material\.colour is not a material field"),
])
def test_bad_field_names_field_value_and_range(override, pattern):
    with pytest.raises(ValueError, match=pattern):
        load_material({"name": "raw_sugar_lee2008", **override})


def test_missing_field():
    spec = dict(name="new_ore", title="x", citations=["x"], moisture_basis="wet", moisture_range=[0, 0.1],
                repose_angle={"a": 0, "b": 35}, bulk_density={"a": 1500, "b": 0}, particle_density=2600,
                particle_diameter=1e-3, kinetics={"method": "ajayi2011"})
    with pytest.raises(ValueError, match=r"^material\.heat_capacity is missing"):
        load_material(spec)


@given(st.floats(0.0, 0.9))
def test_to_basis_round_trip(x_wet):
    sugar = load_material("raw_sugar_lee2008")
    x_dry = sugar.to_basis(x_wet)
    assert x_dry / (1.0 + x_dry) == pytest.approx(x_wet, rel=1e-12, abs=1e-15)
    assert float(load_material("zinc_concentrate_ajayi2011").to_basis(x_wet)) == x_wet


@given(st.sampled_from(LIBRARY), st.floats(0.0, 1.0))
def test_repose_angle_physical_over_the_range(name, frac):
    m = load_material(name)
    lo, hi = m.wet_range()
    x = lo + frac * (hi - lo)
    m.check_moisture("x", x)
    assert 0.0 < float(m.repose_angle(x)) < 90.0
    assert float(m.bulk_density(x)) > 0.0
