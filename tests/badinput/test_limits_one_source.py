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
