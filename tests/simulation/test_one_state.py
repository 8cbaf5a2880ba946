"""One number per quantity (issue 27): the coupled steady state is what every surface shows, and
the Simulation keeps its overrides through sweeps, fits and results."""

import json
import warnings
from importlib import resources

import numpy as np
import pytest
from typer.testing import CliRunner

from rotarydryer import Simulation
from rotarydryer.cli import app
from rotarydryer.simulation import grid_points, run_case

TEMPLATE = str(resources.files("rotarydryer.cases") / "templates" / "dryer.toml")
CASES = ["lee2008_invicta", "ajayi2011_mmg", "song2003_ottawa", TEMPLATE]


@pytest.fixture(scope="module", params=CASES, ids=["invicta", "mmg", "song", "template"])
def simulated(request):
    r = CliRunner().invoke(app, ["simulate", request.param, "--json"])
    assert r.exit_code == 0, r.output
    return request.param, json.loads(r.stdout)


def test_cells_and_sections_add_up_to_the_total(simulated):
    _, out = simulated
    total = out["total_holdup_kg"]
    assert sum(c["holdup_kg"] for c in out["cells"]) == pytest.approx(total, rel=1e-9)
    assert sum(s["total_kg"] for s in out["sections"].values()) == pytest.approx(total, rel=1e-9)
    for phase in ("active", "passive", "bed"):
        assert sum(c[f"{phase}_kg"] for c in out["cells"]) == pytest.approx(out[f"{phase}_holdup_kg"], rel=1e-9,
                                                                             abs=1e-9)
    # the coupled total differs from the transport-only model's, which keeps its own name
    if "thermal_mode" in out:
        assert out["transport_only_total_holdup_kg"] != pytest.approx(total, rel=1e-6)


def test_cells_are_flighted_cells_and_unflighted_volumes(simulated):
    _, out = simulated
    kinds = {c["kind"] for c in out["cells"]}
    assert kinds <= {"flighted", "unflighted"}
    for c in out["cells"]:
        if c["kind"] == "flighted":
            assert c["holdup_kg"] == pytest.approx(c["passive_kg"] + c["active_kg"], rel=1e-12)
            assert c["state"] in ("under", "design", "over")
        else:
            assert c["passive_kg"] == c["active_kg"] == 0.0 and c["state"] == "unflighted"


def test_holdup_plot_title_states_the_same_total():
    res = Simulation("lee2008_invicta").steady_state()
    fig = res.plot("holdup")
    title = fig.axes[0].get_title()
    assert f"total {res.summary()['total_holdup_kg']:,.0f} kg" in title
    assert f"{res.state.total_holdup:,.0f}" == f"{res.summary()['total_holdup_kg']:,.0f}"


def test_coupled_cells_are_at_the_computed_moisture():
    """With moisture coupling the coupled cells report the repose angle of their own moisture."""
    res = Simulation("lee2008_invicta").steady_state()
    cells = res.state.cell_table()
    x = np.array([c["moisture_kg_kg"] for c in cells])
    assert np.all(np.diff(x) <= 1e-12) and x[0] > x[-1]       # the sugar dries along the drum
    transport = res.simulation.transport_steady_state().cell_table()
    assert [c["repose_angle_deg"] for c in cells] != [c["repose_angle_deg"] for c in transport]


def test_results_datasets_are_the_coupled_state():
    res = run_case("song2003_ottawa")
    total = res.scalars["total_holdup_kg"]
    assert float(res.nodes.holdup.sum()) == pytest.approx(total, rel=1e-12)
    assert float(res.cells.holdup.sum()) == pytest.approx(total, rel=1e-12)
    assert float(res.sections.total_holdup.sum()) == pytest.approx(total, rel=1e-12)
    # one dimension name for the same nodes: the heat-and-mass profiles are per node of `nodes`
    sol = res.datasets["thermal_solids"]
    assert sol.holdup.dims == ("node",) and np.array_equal(sol.holdup.values, res.nodes.holdup.values)
    # the simulated tracer curve is that of the same state as the analytic moments
    t, e = res.rtd.time.values, res.rtd.exit_age.values
    mean = float(np.trapezoid(t * e, t) / np.trapezoid(e, t))
    assert mean == pytest.approx(res.scalars["tracer_mean_s"], rel=2e-3)
    transport_only = run_case("song2003_ottawa", thermal=False).scalars["tracer_mean_s"]
    assert abs(mean / transport_only - 1) > 1e-3


def test_results_run_case_is_a_deprecated_alias():
    import rotarydryer.results as results

    with pytest.warns(DeprecationWarning, match="rotarydryer.simulation.run_case"):
        alias = results.run_case
    assert alias is run_case


def test_sweep_keeps_the_simulations_overrides():
    sim = Simulation("song2003_ottawa", {"gas.flow": 0.05})
    rows = sim.sweep([{"operating.rpm": 4.0}])
    direct = Simulation("song2003_ottawa", {"gas.flow": 0.05, "operating.rpm": 4.0}).steady_state().summary()
    assert rows[0]["gas_flow_kg_s"] == pytest.approx(0.05)
    assert rows[0]["total_holdup_kg"] == pytest.approx(direct["total_holdup_kg"], rel=1e-12)


@pytest.mark.parametrize("grid", [
    ["operating.rpm=3,4", "gas.flow=0.04"],
    {"operating.rpm": [3, 4], "gas.flow": 0.04},
    [{"operating.rpm": "3", "gas.flow": "0.04"}, {"operating.rpm": "4", "gas.flow": "0.04"}],
])
def test_sweep_takes_the_cli_grid_form(grid):
    points = grid_points(grid)
    assert [float(p["operating.rpm"]) for p in points] == [3.0, 4.0]
    assert all(float(p["gas.flow"]) == 0.04 for p in points)


def test_sweep_refuses_an_unknown_grid_form():
    with pytest.raises(ValueError, match="grid"):
        grid_points([1, 2])


def test_fit_keeps_the_simulations_overrides(monkeypatch):
    import rotarydryer.estimation.cases as ec

    seen = {}

    def fake(case_name, data, keys, **kw):
        seen.update(case=case_name, base=kw.get("base_overrides"))
        return "fit"

    monkeypatch.setattr(ec, "fit_case_to_tracer", fake)
    sim = Simulation("lee2008_invicta", {"geometry.method": "lee2008_regressions", "transport.n_cells": 33})
    assert sim.fit("lee2008_invicta", ["transport.backmix"], base_overrides={"transport.kiln_time": 40}) == "fit"
    assert seen["case"] == "lee2008_invicta"
    assert seen["base"] == {"geometry.method": "lee2008_regressions", "transport.n_cells": 33,
                            "transport.kiln_time": 40}


def test_the_dryer_is_built_once(monkeypatch):
    sim = Simulation("song2003_ottawa")
    built = []
    real = sim.thermal_dryer
    monkeypatch.setattr(sim, "thermal_dryer", lambda *a, **k: built.append(1) or real(*a, **k))
    sim.steady_state()
    sim.dynamics(t_end=120.0, dt=60.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim.results(rtd=False)
    assert len(built) == 1


def test_temperatures_end_in_degC_and_the_old_names_warn():
    sim = Simulation("song2003_ottawa")
    th = sim.steady_state().thermal
    dyn = sim.dynamics(t_end=120.0, dt=60.0)
    for obj, name in ((th, "product_temperature"), (th, "gas_outlet_temperature"), (th, "solids_temperature"),
                      (dyn, "product_temperature"), (dyn, "gas_outlet_temperature")):
        new = getattr(obj, f"{name}_degC")
        with pytest.warns(DeprecationWarning, match=f"use .{name}_degC"):
            old = getattr(obj, f"{name}_c")
        assert np.array_equal(old, new)
    assert dyn.to_dataframe()["gas_outlet_temperature_degC"].iloc[-1] == dyn.gas_outlet_temperature_degC[-1]


def test_the_solver_reports_progress_through_a_callback_and_never_prints(capsys):
    d = Simulation("song2003_ottawa").dryer()
    seen = []
    d.steady_state(progress=lambda it, norm, dt: seen.append((it, norm, dt)))
    assert seen and seen[-1][1] < 1e-11
    with pytest.warns(DeprecationWarning, match="progress="):
        d.steady_state(verbose=True)
    assert capsys.readouterr().out == ""
