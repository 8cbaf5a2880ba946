"""Issue 30: the schema's ranges are the runtime's (rotarydryer._limits declares both).

Before, ``rotarydryer schema`` allowed gas.flow, gas.leak_air_flow = 1000, thermal.area_scale = 100,
shell.loss_factor = 1000 and shell.insulation_thickness = 2 and the run refused them."""

from __future__ import annotations

import math

import pytest

from rotarydryer._limits import LIMITS, check_key, describe_limit
from rotarydryer.cases import DryerSpec
from rotarydryer.simulation import Simulation

BOUNDS = ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum")


def _schema_fields():
    """{dotted key: JSON-schema bounds} of every bounded scalar of the dryer schema."""
    s = DryerSpec.model_json_schema()
    defs = s.get("$defs", {})
    out = {}

    def walk(props, prefix):
        for k, v in props.items():
            alts = [v, *v.get("anyOf", [])]
            for a in alts:
                if "$ref" in a:
                    walk(defs[a["$ref"].split("/")[-1]].get("properties", {}), prefix + k + ".")
            b = {}
            for a in alts:
                b.update({kk: a[kk] for kk in BOUNDS if kk in a})
            if b:
                out[prefix + k] = b
    walk(s["properties"], "")
    return out


def _expected(lim):
    b = {}
    if math.isfinite(lim.low):
        b["minimum" if lim.low_inclusive else "exclusiveMinimum"] = lim.low
    if math.isfinite(lim.high):
        b["maximum" if lim.high_inclusive else "exclusiveMaximum"] = lim.high
    return b


def test_every_declared_limit_is_the_schemas():
    fields = _schema_fields()
    checked = 0
    for key, lim in LIMITS.items():
        if key in fields:
            assert fields[key] == _expected(lim), key
            checked += 1
    assert checked >= 20


@pytest.mark.parametrize("key", ["gas.flow", "gas.leak_air_flow", "thermal.area_scale", "shell.loss_factor",
                                 "shell.insulation_thickness", "gas.inlet_temperature"])
def test_the_schemas_upper_bound_passes_the_runtime_check(key, tmp_path):
    """The reported five (and the gas temperature): the schema's closed upper bound is accepted by the
    model's own check; past it the message names the key and the same interval."""
    lim = LIMITS[key]
    assert lim.high_inclusive
    assert float(check_key(key, lim.high)) == lim.high
    with pytest.raises(ValueError) as e:
        check_key(key, lim.high * 1.001)
    assert key in str(e.value) and describe_limit(key) in str(e.value)
    # the built heat-and-mass model accepts the bound (no range error for the key; a physical refusal may follow)
    sim = Simulation("lee2008_invicta", {key: lim.high})
    try:
        sim.dryer()
    except ValueError as exc:
        assert "outside the allowed range" not in str(exc) or key not in str(exc), str(exc)


# ---- the [transport], [geometry], drum and operating keys (one declaration, read by the transport model) ----
TRANSPORT_KEYS = ("transport.n_cells", "transport.unflighted_cells", "transport.kiln_time", "transport.backmix",
                  "transport.drag_reduction", "transport.curtain_velocity_ratio", "transport.curtain_coefficient",
                  "transport.step_factor", "transport.velocity_coefficient", "transport.dispersion_coefficient",
                  "transport.core_fraction", "transport.core_time", "transport.passive_rate",
                  "transport.exchange_rate", "transport.return_rate", "transport.kiln_rate",
                  "transport.solids_velocity", "transport.dispersion", "transport.product_moisture",
                  "transport.moisture_scale", "transport.fouling", "geometry.design_load_factor")
DRUM_KEYS = ("drum.radius", "drum.length", "drum.slope", "operating.feed_rate", "operating.rpm",
             "operating.feed_moisture")


@pytest.mark.parametrize("key", TRANSPORT_KEYS + DRUM_KEYS)
def test_transport_and_drum_keys_are_the_schemas(key):
    """Each key is declared once and the dryer schema (``rotarydryer schema``) shows that interval."""
    assert key in LIMITS
    assert _schema_fields()[key] == _expected(LIMITS[key]), key


def _edges(lim):
    """Values at and just beyond each finite end of ``lim``."""
    out = []
    for end in (lim.low, lim.high):
        if math.isfinite(end):
            step = max(abs(end), 1.0) * 1e-6
            out += [end - step, end, end + step]
    return out


@pytest.mark.parametrize("key", TRANSPORT_KEYS + DRUM_KEYS)
def test_the_schema_accepts_what_the_runtime_check_accepts(key):
    """At and around each end of the range, the case schema and the runtime check (check_key, which the
    transport model calls) agree value by value: no value passes one and fails the other."""
    from pydantic import ValidationError, create_model

    import rotarydryer.cases as cases

    section, field = key.split(".")
    block = {"transport": cases.DryerTransport, "geometry": cases.DryerGeometry, "drum": cases.DryerDrum,
             "operating": cases.DryerOperating}[section]
    finfo = block.model_fields[field]
    one = create_model("One", x=(finfo.annotation, finfo))
    integer = "int" in str(finfo.annotation)
    for v in _edges(LIMITS[key]):
        if integer and v != round(v):
            continue        # an integer field refuses a fraction for its type, not its range
        try:
            one.model_validate({"x": v})
            schema_ok = True
        except ValidationError:
            schema_ok = False
        try:
            check_key(key, v)
            runtime_ok = True
        except ValueError as exc:
            runtime_ok = False
            assert key in str(exc) and describe_limit(key) in str(exc), str(exc)
        assert schema_ok == runtime_ok, (key, v, schema_ok, runtime_ok)


def _raises_with(key, fn, *args, **kw):
    with pytest.raises(ValueError) as e:
        fn(*args, **kw)
    msg = str(e.value)
    assert describe_limit(key) in msg, msg
    return msg


def test_the_transport_models_check_the_declared_ranges():
    """The runtime checks of rotarydryer.transport quote the declared interval (they call check_key)."""
    from rotarydryer.transport.ajayi import AjayiRegressions
    from rotarydryer.transport.ajayi_predictive import kramers_velocity, particle_dispersion
    from rotarydryer.transport.core_variants import add_stagnant_core
    from rotarydryer.transport.forward_step import CurtainGas
    from rotarydryer.transport.models import lee2008, sheehan2005_model1

    lee = dict(geometry=None, n_cells=10, feed_rate=1.0, length=10.0, rpm=3.0, slope=2.0, bulk_density=800.0,
               repose_angle=40.0, kiln_time=10.0, backmix=0.0, drag_reduction=1.0)
    for key, value in (("backmix", 1.5), ("drag_reduction", -1.0), ("kiln_time", 0.0), ("n_cells", 100001)):
        msg = _raises_with(f"transport.{key}", lee2008, **{**lee, key: value})
        assert f"transport.{key} = " in msg
    m1 = dict(n_cells=10, feed_rate=1.0, length=10.0, passive_rate=0.01, exchange_rate=0.01, return_rate=0.01,
              kiln_rate=0.01, design_load=100.0)
    for key in ("passive_rate", "exchange_rate", "return_rate", "kiln_rate"):
        _raises_with(f"transport.{key}", sheehan2005_model1, **{**m1, key: -1.0})
    gas = dict(gas_mass_flow=10.0, gas_density=1.0, gas_viscosity=2e-5, radius=1.0, gas_flow="counter-current",
               particle_diameter=1e-3, particle_density=1500.0)
    for key, value in (("step_factor", 100.0), ("curtain_coefficient", 1e4), ("velocity_ratio", 1.01)):
        name = "transport.curtain_velocity_ratio" if key == "velocity_ratio" else f"transport.{key}"
        _raises_with(name, CurtainGas, **{**gas, key: value})
    CurtainGas(**{**gas, "step_factor": 99.9, "curtain_coefficient": 0.0, "velocity_ratio": 1.0})
    _raises_with("transport.core_fraction", add_stagnant_core, None, 10.5, 10.0)
    _raises_with("transport.core_time", add_stagnant_core, None, 1.0, 2e6)
    _raises_with("transport.velocity_coefficient", kramers_velocity, 0.01, 3.0, 1.0, 2.0, 40.0, coefficient=101.0)
    _raises_with("transport.dispersion_coefficient", particle_dispersion, 0.01, 1e-3, 1.1e4)
    msg = _raises_with("geometry.design_load_factor", AjayiRegressions, [0.0] * 7, [0.0] * 11, 1.0, 0.0)
    assert "geometry.design_load_factor = 0" in msg
    # transport.kiln_time = inf: no kilning (library callers; a case file cannot hold inf)
    assert float(check_key("transport.kiln_time", math.inf)) == math.inf


def test_a_materials_transport_coefficients_have_the_case_keys_ranges():
    from rotarydryer.properties.materials import TRANSPORT_COEFFICIENTS, _coefficient

    for k, lim in TRANSPORT_COEFFICIENTS.items():
        assert lim is LIMITS[f"transport.{k}"]
        with pytest.raises(ValueError, match=rf"material\.transport\.{k} = .* allowed range"):
            _coefficient(k, lim.high * 2)


#: keys of the old formats and the keys of the one specification they become
LEGACY = {
    "LeeCase": {"operating.feed_rate": "operating.feed_rate", "operating.rpm": "operating.rpm",
                "transport.n_cells": "transport.n_cells", "transport.kiln_time": "transport.kiln_time",
                "transport.backmix": "transport.backmix", "transport.drag_reduction": "transport.drag_reduction",
                "transport.step_factor": "transport.step_factor", "drum.slope": "drum.slope"},
    "AjayiCase": {"drum.radius": "drum.radius", "operating.feed_rate": "operating.feed_rate",
                  "solids.moisture_scale": "transport.moisture_scale",
                  "transport.solids_velocity": "transport.solids_velocity",
                  "transport.kiln_velocity": "transport.solids_velocity", "transport.dispersion": "transport.dispersion",
                  "transport.fouling": "transport.fouling",
                  "transport.velocity_coefficient": "transport.velocity_coefficient",
                  "transport.dispersion_coefficient": "transport.dispersion_coefficient",
                  "transport.design_load_factor": "geometry.design_load_factor",
                  "thermal.area_scale": "thermal.area_scale", "thermal.gas_inlet_temperature": "gas.inlet_temperature",
                  "thermal.gas_inlet_humidity": "gas.inlet_humidity",
                  "thermal.solids_inlet_temperature": "operating.feed_temperature",
                  "thermal.ambient_temperature": "shell.ambient_temperature",
                  "thermal.shell_inner_radius": "shell.inner_radius", "thermal.shell_thickness": "shell.thickness",
                  "thermal.loss_factor": "shell.loss_factor", "thermal.leak_air_flow": "gas.leak_air_flow"},
}


@pytest.mark.parametrize("kind", sorted(LEGACY))
def test_the_legacy_formats_take_the_bounds_of_the_keys_they_become(kind):
    import rotarydryer.cases.readers as readers

    s = getattr(readers, kind).model_json_schema()
    defs = s.get("$defs", {})

    def bounds(dotted):
        sec, fld = dotted.split(".")
        ref = s["properties"][sec]
        ref = next(a for a in [ref, *ref.get("anyOf", []), *ref.get("allOf", [])] if "$ref" in a)["$ref"]
        v = defs[ref.split("/")[-1]]["properties"][fld]
        return {k: a[k] for a in [v, *v.get("anyOf", [])] for k in BOUNDS if k in a}

    for old, new in LEGACY[kind].items():
        assert bounds(old) == _expected(LIMITS[new]), (old, new)
    # the gas flows of the old formats: the heat-and-mass model's (0, high] of gas.flow
    if kind == "AjayiCase":
        assert bounds("thermal.gas_flow") == {"exclusiveMinimum": 0.0, "maximum": LIMITS["gas.flow"].high}


def test_out_of_range_transport_key_via_the_cli_names_key_value_and_range():
    from .conftest import assert_bad, run_cli

    res = run_cli(["simulate", "lee2008_invicta", "--set", "transport.step_factor=100", "--set",
                   "thermal.enabled=false"])
    assert_bad(res, "transport.step_factor", "'100'", describe_limit("transport.step_factor"))
    problem = [ln for ln in res.output.splitlines() if "transport.step_factor" in ln]
    assert len(problem) == 1 and "(0, 100)" in problem[0], res.output
    # a [[parameter_sets]] row names its own field and the range of the key it sets
    res = run_cli(["simulate", "lee2008_invicta", "--set", "transport.backmix=1.5"])
    assert_bad(res, "transport.backmix", "1.5", describe_limit("transport.backmix"))


def test_docs_errors_md_lists_every_limit():
    """docs/errors.md holds the generated table of LIMITS (python -m rotarydryer._limits --update-docs)."""
    from pathlib import Path

    from rotarydryer._limits import DOC_BEGIN, DOC_END, limits_table

    text = (Path(__file__).parents[2] / "docs" / "errors.md").read_text(encoding="utf-8")
    block = text.split(DOC_BEGIN, 1)[1].split(DOC_END, 1)[0]
    assert block.strip() == limits_table().strip(), "run python -m rotarydryer._limits --update-docs"
    for key in LIMITS:
        assert f"| `{key}` | `{describe_limit(key)}` |" in block
