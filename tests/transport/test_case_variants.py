"""Issue 14 part 6: Sheehan et al. (2005) Model 1 and the stagnant-core variant reachable from case
files (``transport.model = "sheehan2005_model1"`` on the Lee case, ``transport.core``) and the CLI."""

import json
import warnings

import numpy as np
import pytest
from typer.testing import CliRunner

from rotarydryer import Simulation
from rotarydryer.cases import build_model, load_case
from rotarydryer.cli import app
from rotarydryer.studies.invicta_rtd_spread import INVICTA_FITS, invicta_model
from rotarydryer.transport.models import sheehan2005_model1

runner = CliRunner()
RATES = dict(passive_rate=0.05, exchange_rate=0.1, return_rate=1.0, kiln_rate=0.1)
MODEL1 = {"transport.model": "sheehan2005_model1", **{f"transport.{k}": v for k, v in RATES.items()}}


def _core(kind, beta, t):
    return {"transport.core": kind, "transport.core_fraction": beta, "transport.core_time": t}


def test_lee_case_model1_is_sheehans_model1():
    """With a constant repose angle every cell has the same design load: the Lee case with
    transport.model = 'sheehan2005_model1' is the standalone Model 1 (notes lee_models.md 4.2)."""
    case = load_case("lee2008_invicta", {**MODEL1, "solids.repose_angle": 40.0, "thermal.enabled": False})
    model = build_model(case)
    assert model.name == "sheehan2005_model1"
    des = model.design_load[np.isfinite(model.design_load)]
    assert np.allclose(des, des[0], rtol=1e-12)
    ref = sheehan2005_model1(n_cells=case.transport.n_cells, feed_rate=case.operating.feed_rate,
                             length=case.drum.length, design_load=float(des.sum()), **RATES)
    a, b = model.steady_state(), ref.steady_state()
    assert a.total_holdup == pytest.approx(b.total_holdup, rel=1e-9)
    ma, mb = a.tracer_system().moments(), b.tracer_system().moments()
    assert ma["recovery"] == pytest.approx(1.0, abs=1e-9)
    assert ma["mean"] == pytest.approx(mb["mean"], rel=1e-8)
    assert ma["std"] == pytest.approx(mb["std"], rel=1e-8)
    # faster passive transport: less holdup
    faster = build_model(load_case("lee2008_invicta", {**MODEL1, "transport.passive_rate": 0.1,
                                                       "solids.repose_angle": 40.0}))
    assert faster.steady_state().total_holdup < a.total_holdup


def test_lee_case_model1_runs_with_heat_and_mass_transfer():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = Simulation("lee2008_invicta", MODEL1).steady_state().summary()
    assert s["tracer_mean_s"] > 0 and 0 < s["evaporation_kg_s"] < 1.0


@pytest.mark.parametrize("core", ["first_order", "diffusive"])
def test_core_from_the_case_equals_the_study_variant(core):
    """transport.core on the Lee case builds what studies/invicta_rtd_spread.py builds (the same
    add_stagnant_core on the same model)."""
    fit = INVICTA_FITS["diffusive_core" if core == "diffusive" else "first_order_core"]
    v, n = fit["values"], fit.get("n_cells", 35)
    ov = {"geometry.method": "lee2008_regressions", "transport.n_cells": n, "thermal.enabled": False,
          **{f"transport.{k}": v[k] for k in ("kiln_time", "backmix", "drag_reduction")},
          **_core(core, v["core_fraction"], v["core_time"])}
    mine = build_model(load_case("lee2008_invicta", ov)).steady_state()
    ref = invicta_model(v, n_cells=n, core_model=core).steady_state()
    assert mine.total_holdup == pytest.approx(ref.total_holdup, rel=1e-10)
    m1, m2 = mine.tracer_system().moments(mine.model.tracer_input), ref.tracer_system().moments(ref.model.tracer_input)
    assert m1["mean"] == pytest.approx(m2["mean"], rel=1e-10)
    assert m1["std"] == pytest.approx(m2["std"], rel=1e-8)
    assert mine.model.parameters["core_model"] == core


@pytest.mark.parametrize("case,base", [("lee2008_invicta", {"thermal.enabled": False}),
                                       ("song2003_ottawa", {"thermal.enabled": False})])
def test_core_holds_beta_times_the_passive_mass(case, base):
    """At steady state the core holds core_fraction x the mobile passive mass and every other flow is
    unchanged (rotarydryer.transport.core_variants): holdup and mean residence time grow by exactly
    that mass; recovery stays 1."""
    plain = build_model(load_case(case, base)).steady_state()
    for kind in ("first_order", "diffusive"):
        ss = build_model(load_case(case, {**base, **_core(kind, 0.3, 500.0)})).steady_state()
        assert ss.passive_holdup == pytest.approx(plain.passive_holdup, rel=1e-9)
        assert ss.total_holdup == pytest.approx(plain.total_holdup + 0.3 * plain.passive_holdup, rel=1e-9)
        m = ss.tracer_system().moments()
        assert m["recovery"] == pytest.approx(1.0, abs=1e-9)
        assert m["mean"] == pytest.approx(ss.total_holdup / ss.outlet_flow, rel=1e-8)
        assert m["std"] > plain.tracer_system().moments()["std"]
        assert hasattr(ss.model, "specs") and ss.model.cell_length.size == ss.model.network.n
        assert len(ss.model.checks) == 1      # the fill check of the case


def test_core_is_refused_by_the_heat_and_mass_model():
    with pytest.raises(ValueError, match="transport.core = 'diffusive' is a transport-only variant.*thermal.enabled"):
        Simulation("lee2008_invicta", _core("diffusive", 0.5, 1000.0)).steady_state()


def test_rtd_cli_with_a_diffusive_core():
    sets = ["--set", "transport.core=diffusive", "--set", "transport.core_fraction=0.63",
            "--set", "transport.core_time=12250", "--set", "transport.n_cells=24", "--set", "transport.backmix=0",
            "--set", "transport.drag_reduction=1", "--set", "transport.kiln_time=19.19",
            "--set", "geometry.method=lee2008_regressions"]
    res = runner.invoke(app, ["rtd", "lee2008_invicta", *sets, "--json"])
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout.strip().splitlines()[-1])
    assert d["model"] == "lee2008+diffusive_core"
    assert d["tracer_std_s"] > 5 * 60.0      # the core's slow tail (docs/rtd_spread.md)
    res = runner.invoke(app, ["rtd", "lee2008_invicta", "--set", "transport.model=sheehan2005_model1",
                              *[x for k, v in RATES.items() for x in ("--set", f"transport.{k}={v}")], "--json"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout.strip().splitlines()[-1])["model"] == "sheehan2005_model1"
