"""Thin-layer drying laws (rotarydryer.properties.thin_layer) and their use as material kinetics
(``method = "thin_layer"`` of rotarydryer.properties.drying and the materials format)."""

import math
from importlib import resources

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from rotarydryer.properties import thin_layer as tl
from rotarydryer.properties.drying import DryingKinetics, unhindered_drying_flux
from rotarydryer.properties.materials import library_table, load_material

R = 8.314462618

# (model, parameters, t = 100 s, MR by hand)
KNOWN = [
    ("lewis", {"k": 1e-3}, math.exp(-0.1)),
    ("page", {"k": 1e-3, "n": 1.5}, math.exp(-1.0)),                              # 100^1.5 = 1000
    ("henderson_pabis", {"a": 0.9, "k": 1e-3}, 0.9 * math.exp(-0.1)),
    ("logarithmic", {"a": 0.9, "k": 1e-3, "c": 0.05}, 0.9 * math.exp(-0.1) + 0.05),
    ("two_term", {"a": 0.6, "k0": 2e-3, "b": 0.4, "k1": 5e-4}, 0.6 * math.exp(-0.2) + 0.4 * math.exp(-0.05)),
    ("midilli", {"a": 1.0, "k": 1e-3, "n": 1.5, "b": -1e-4}, math.exp(-1.0) - 0.01),
]


@pytest.mark.parametrize("model, p, mr", KNOWN, ids=[k[0] for k in KNOWN])
def test_each_law_at_known_values(model, p, mr):
    assert float(tl.moisture_ratio(model, 100.0, p)) == pytest.approx(mr, rel=1e-12)
    # the derivative against a central difference
    h = 1e-3
    fd = (float(tl.moisture_ratio(model, 100.0 + h, p)) - float(tl.moisture_ratio(model, 100.0 - h, p))) / (2 * h)
    assert float(tl.moisture_ratio_rate(model, 100.0, p)) == pytest.approx(fd, rel=1e-6)
    assert set(tl.MODELS[model].parameters) == set(p)


def test_known_values_hand_numbers():
    assert KNOWN[0][2] == pytest.approx(0.904837418, abs=1e-9)
    assert KNOWN[4][2] == pytest.approx(0.871730222, abs=1e-9)


def test_arrhenius_moves_the_rate_constants_only():
    ea, t, tref = 30e3, 353.15, 338.15
    factor = math.exp(-ea / R * (1 / t - 1 / tref))
    assert factor == pytest.approx(1.573371, rel=1e-6)
    p = {"a": 0.6, "k0": 2e-3, "b": 0.4, "k1": 5e-4}
    moved = {"a": 0.6, "k0": 2e-3 * factor, "b": 0.4, "k1": 5e-4 * factor}
    assert float(tl.moisture_ratio("two_term", 100.0, p, t, ea, tref)) == pytest.approx(
        float(tl.moisture_ratio("two_term", 100.0, moved)), rel=1e-12)
    assert float(tl.moisture_ratio("page", 50.0, {"k": 1e-3, "n": 0.8}, tref, ea, tref)) == pytest.approx(
        float(tl.moisture_ratio("page", 50.0, {"k": 1e-3, "n": 0.8})), rel=1e-14)


def test_vectorised_over_time_and_temperature():
    t = np.array([[0.0, 60.0, 600.0]])
    temp = np.array([[323.15], [353.15]])
    mr = tl.moisture_ratio("page", t, {"k": 1e-3, "n": 0.9}, temp, 30e3, 338.15)
    assert mr.shape == (2, 3)
    assert np.all(mr[1, 1:] < mr[0, 1:])          # hotter air dries faster


def test_bad_calls_name_the_argument():
    with pytest.raises(ValueError, match="model = 'weibull'"):
        tl.moisture_ratio("weibull", 1.0, {"k": 1.0})
    with pytest.raises(ValueError, match="the page law takes k, n"):
        tl.moisture_ratio("page", 1.0, {"k": 1.0})
    with pytest.raises(ValueError, match="time_s = -1"):
        tl.moisture_ratio("lewis", -1.0, {"k": 1.0})


@pytest.mark.parametrize("model, p, fragment", [
    ("page", {"k": 1e-3, "n": 12.0}, "parameters.n = 12 is outside the allowed range (0, 10)"),
    ("lewis", {"k": -1e-3}, "parameters.k = -0.001"),
    ("midilli", {"a": 1.0, "k": 1e-3, "n": 1.0, "b": 1e-5}, "b > 0 makes the moisture rise"),
    ("two_term", {"a": 1.2, "k0": 1e-3, "b": -0.2, "k1": 1e-4}, "parameters.b = -0.2"),
    ("logarithmic", {"a": 0.5, "k": 1e-3, "c": 0.995}, "parameters.c = 0.995"),
    ("henderson_pabis", {"a": 3.0, "k": 1e-3}, "MR(0) = a = 3 is outside the allowed range"),
    ("page", {"k": 1e-3, "n": 1.0, "a": 1.0}, "parameters.a is not a parameter of the page law"),
    ("page", {"k": 1e-3}, "parameters.n is missing"),
    ("page", {"k": "fast", "n": 1.0}, "parameters.k = 'fast' must be a finite number"),
])
def test_check_law_names_the_parameter(model, p, fragment):
    with pytest.raises(ValueError) as exc:
        tl.check_law(model, p)
    assert fragment in str(exc.value)


# ------------------------------------------------------------------ property tests (hypothesis)
def _law(draw, model):
    k = draw(st.floats(1e-5, 1e-2))
    n = draw(st.floats(0.3, 3.0))
    a = draw(st.floats(0.5, 1.5))
    out = {"lewis": {"k": k}, "page": {"k": k, "n": n}, "henderson_pabis": {"a": a, "k": k},
           "logarithmic": {"a": a, "k": k, "c": draw(st.floats(-0.3, 0.3))},
           "two_term": {"a": a / 2, "k0": k, "b": a / 2, "k1": k * draw(st.floats(0.01, 0.9))},
           "midilli": {"a": a, "k": k, "n": n, "b": -draw(st.floats(0.0, 1e-6))}}[model]
    return out


@st.composite
def laws(draw):
    model = draw(st.sampled_from(list(tl.MODELS)))
    p = _law(draw, model)
    try:
        tl.check_law(model, p)
    except ValueError:
        assume(False)
    return model, p


@settings(max_examples=80, deadline=None)
@given(laws())
def test_moisture_ratio_at_zero_and_monotone(law):
    model, p = law
    start = {"lewis": 1.0, "page": 1.0, "henderson_pabis": p.get("a"), "logarithmic": p.get("a", 0) + p.get("c", 0),
             "two_term": p.get("a", 0) + p.get("b", 0), "midilli": p.get("a")}[model]
    assert float(tl.moisture_ratio(model, 0.0, p)) == pytest.approx(start, rel=1e-12)
    t = np.geomspace(1e-2, 1e6, 400)
    mr = tl.moisture_ratio(model, t, p)
    assert np.all(np.diff(mr) <= 1e-15)            # never rises for a law check_law accepts
    assert np.all(tl.moisture_ratio_rate(model, t, p) <= 0)


@settings(max_examples=80, deadline=None)
@given(laws(), st.floats(0.05, 0.5), st.floats(0.0, 0.04), st.floats(300.0, 400.0))
def test_local_rate_positive_monotone_and_zero_at_equilibrium(law, x0, xe, temp):
    model, p = law
    x = np.linspace(xe - 0.02, x0 + 0.05, 301)
    r = tl.drying_rate(model, x, temp, p, initial_moisture=x0, equilibrium_moisture=xe)
    assert np.all(np.isfinite(r))
    # the logarithmic law's equilibrium is shifted by c (X_e + c (X_0 - X_e)): it is its own zero
    zero = xe + (p["c"] * (x0 - xe) if model == "logarithmic" else 0.0)
    assert np.all(r[x > zero + 1e-9] > 0) and np.all(r[x < zero - 1e-9] < 0)
    assert float(tl.drying_rate(model, zero, temp, p, initial_moisture=x0, equilibrium_moisture=xe)) == \
        pytest.approx(0.0, abs=1e-12)
    assert np.all(np.diff(r) >= -1e-12 * np.max(np.abs(r)))     # the rate does not fall as X rises


@pytest.mark.parametrize("model, p", [
    ("lewis", {"k": 1e-3}), ("henderson_pabis", {"a": 0.95, "k": 1e-3}),
    ("logarithmic", {"a": 0.9, "k": 1e-3, "c": 0.1}), ("page", {"k": 3e-3, "n": 0.8}),
    ("two_term", {"a": 0.6, "k0": 2e-3, "b": 0.4, "k1": 2e-4}), ("midilli", {"a": 1.0, "k": 3e-3, "n": 0.8, "b": -2e-6}),
])
def test_rate_form_integrates_back_to_the_law(model, p):
    """dX/dt = -r(X) from the law's own start reproduces X(t) = X_e + (X_0 - X_e) MR(t) while MR > MR_FLOOR
    (the equivalent-time form is exact there)."""
    x0, xe = 0.3, 0.02
    start = float(tl.moisture_ratio(model, 0.0, p))
    tt = np.linspace(0.0, 3000.0, 31)
    t0 = 1e-6 if model in ("page", "midilli") else 0.0        # n < 1: infinite rate at t = 0
    x_start = xe + (x0 - xe) * float(tl.moisture_ratio(model, t0, p)) if t0 else xe + (x0 - xe) * start
    sol = solve_ivp(lambda t, x: -tl.drying_rate(model, x, 338.15, p, initial_moisture=x0, equilibrium_moisture=xe),
                    (t0, tt[-1]), [x_start], t_eval=np.maximum(tt, t0), rtol=1e-10, atol=1e-12, method="LSODA")
    law = xe + (x0 - xe) * tl.moisture_ratio(model, np.maximum(tt, t0), p)
    inside = (law - xe) / (x0 - xe) > 2 * tl.MR_FLOOR
    assert inside.sum() > 5
    np.testing.assert_allclose(sol.y[0][inside], law[inside], rtol=2e-4, atol=1e-6)


def test_rate_of_page_with_a_lag_starts_at_its_peak():
    """n > 1: above the moisture of the peak rate the rate is the peak rate (warming is the dryer's)."""
    p = {"k": 1e-5, "n": 1.6}
    t_peak = ((1.6 - 1) / (1.6 * 1e-5)) ** (1 / 1.6)
    peak = -float(tl.moisture_ratio_rate("page", t_peak, p)) * 0.3
    r = tl.drying_rate("page", np.array([0.3, 0.29, 0.35]), 300.0, p, initial_moisture=0.3)
    np.testing.assert_allclose(r, peak, rtol=1e-9)


def test_rate_of_lewis_is_the_first_order_law():
    r = tl.drying_rate("lewis", [0.2, 0.0], 353.15, {"k": 1e-3}, activation_energy=30e3, reference_temperature_K=338.15,
                       initial_moisture=0.3, equilibrium_moisture=0.02)
    k = 1e-3 * math.exp(-30e3 / R * (1 / 353.15 - 1 / 338.15))
    np.testing.assert_allclose(r, [k * 0.18, -k * 0.02], rtol=1e-12)


# ------------------------------------------------------------------ the kinetics and the material format
THIN = {"method": "thin_layer", "model": "page", "parameters": {"k": 7.5e-3, "n": 0.7}, "activation_energy": 30e3,
        "reference_temperature_K": 338.15, "initial_moisture": 0.3, "equilibrium_moisture": 0.01,
        "source": "test law"}


def _material(kinetics=None, **fields):
    t = library_table("ottawa_sand_song2003")
    t.update(name="sand_thin", kinetics=dict(THIN if kinetics is None else kinetics), **fields)
    return load_material(t)


def test_material_with_a_thin_layer_law():
    m = _material()
    k = m.kinetics
    assert k.method == "thin_layer" and k.model == "page" and dict(k.parameters) == {"k": 7.5e-3, "n": 0.7}
    assert k.solids_per_area == pytest.approx(2650.0 * 0.000444 / 3.0)
    assert hash(k) == hash(_material().kinetics)           # hashable: the dryer caches on it
    # the law alone, per kg dry solid, at the gas temperature
    r = k.law_rate(0.2, 50.0)
    assert float(r) == pytest.approx(float(tl.drying_rate("page", 0.2, 323.15, THIN["parameters"], activation_energy=30e3,
                                                           reference_temperature_K=338.15, initial_moisture=0.3,
                                                           equilibrium_moisture=0.01)), rel=1e-12)
    with pytest.raises(ValueError, match="no falling-rate factor"):
        k.factor(0.1)


def test_rate_is_the_law_capped_by_the_external_flux():
    k = _material().kinetics
    x, area = np.array([0.29999, 0.05]), 2.0    # just below X_0 (n < 1: a steep start) and in the tail
    args = (20.0, 45.0, 70.0, 0.01)            # h_c W/(m2 K), T_s, T_g degC, Y kg/kg
    flux = float(unhindered_drying_flux(*args))
    law = k.law_rate(x, 70.0) * k.solids_per_area / (1.0 + x)
    got = k.rate(area, x, *args)
    np.testing.assert_allclose(got, area * np.minimum(flux, law), rtol=1e-12)
    assert law[0] > flux > law[1]             # the first capped by the gas, the second by the solids


@pytest.mark.parametrize("change, fragment", [
    ({"parameters": {"k": 7.5e-3, "n": 11.0}}, "material.kinetics.parameters.n = 11"),
    ({"parameters": {"k": 7.5e-3}}, "material.kinetics.parameters.n is missing"),
    ({"parameters": 3.0}, "material.kinetics.parameters = 3.0"),
    ({"model": "weibull"}, "material.kinetics.model = 'weibull'"),
    ({"activation_energy": -5.0}, "material.kinetics.activation_energy = -5.0"),
    ({"reference_temperature_K": 60.0}, "material.kinetics.reference_temperature_K = 60.0"),
    ({"initial_moisture": 0.005}, "material.kinetics.initial_moisture = 0.005"),
    ({"critical_moisture": 0.1}, "material.kinetics.critical_moisture is not a field of a thin-layer law"),
    ({"exponent": 2.0}, "material.kinetics.exponent is not a field of a thin-layer law"),
    ({"lag": 2.0}, "material.kinetics.lag is not a field"),
])
def test_material_thin_layer_errors_name_the_key(change, fragment):
    kin = {**THIN, **change}
    with pytest.raises(ValueError) as exc:
        _material(kin)
    assert fragment in str(exc.value)


def test_missing_thin_layer_fields():
    for key in ("reference_temperature_K", "initial_moisture"):
        kin = {k: v for k, v in THIN.items() if k != key}
        with pytest.raises(ValueError, match=f"material.kinetics.method='thin_layer' needs {key}"):
            _material(kin)
    with pytest.raises(ValueError, match="needs solids_per_area"):
        DryingKinetics("thin_layer", model="lewis", parameters=(("k", 1e-3),), reference_temperature_K=300.0,
                       initial_moisture=0.3)


def test_case_override_of_kinetics_method_replaces_the_table():
    """A case naming a library material with another kinetics method: the base's X_cr does not mix in."""
    m = load_material({"name": "ottawa_sand_song2003", "kinetics": dict(THIN)})
    assert m.kinetics.method == "thin_layer" and m.kinetics.critical_moisture is None
    # the same method: merged key by key, as before
    m = load_material({"name": "raw_sugar_lee2008", "kinetics": {"critical_moisture": 0.012}})
    assert m.kinetics.method == "constant_falling" and m.kinetics.equilibrium_moisture == 0.0005


def test_material_file_in_case_layout_loads(tmp_path):
    text = (resources.files("rotarydryer.data") / "materials" / "ottawa_sand_song2003.toml").read_text()
    lines = []
    for line in text.splitlines():
        lines.append(f"[material.{line.strip()[1:]}" if line.startswith("[") else line)
    p = tmp_path / "case_layout.toml"
    p.write_text("[material]\n" + "\n".join(lines) + "\n")
    assert load_material(str(p)) == load_material("ottawa_sand_song2003")
