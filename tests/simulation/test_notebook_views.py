"""Notebook-friendly objects (issue 18 part 4) and the Simulation entry points that the views use."""

import pytest

from rotarydryer import Simulation


@pytest.fixture(scope="module")
def song():
    sim = Simulation("song2003_ottawa")
    return sim, sim.steady_state()


def test_short_reprs_and_html(song):
    sim, st = song
    for obj in (sim, st, st.thermal):
        r = repr(obj)
        assert len(r) < 250 and "object at 0x" not in r, r
    assert "product_moisture_kg_kg" in repr(st)
    html = st._repr_html_()
    assert html.startswith("<table>") and "product moisture" in html and "kg/kg" in html


def test_results_repr_dataframe_and_xarray(song):
    sim, _ = song
    res = sim.results()
    assert res.case_name == "song2003_ottawa"
    assert len(repr(res)) < 250 and "total_holdup_kg" in repr(res)
    df = res.to_dataframe()
    assert df.loc["total_holdup_kg", "unit"] == "kg" and df.loc["total_holdup_kg", "value"] > 0
    assert "holdup" in res.to_xarray("nodes")
    with pytest.raises(ValueError, match="dataset = 'nope'"):
        res.to_xarray("nope")
    assert "<table>" in res._repr_html_()


def test_steady_dataframe_matches_summary(song):
    _, st = song
    df = st.to_dataframe()
    assert df.loc["mean_residence_time_s", "value"] == pytest.approx(st.summary()["mean_residence_time_s"])
    assert df.loc["gas_outlet_temperature_degC", "unit"] == "degC"


def test_simulation_fit_by_dataset_name():
    fit = Simulation("lee2008_invicta", {"geometry.method": "lee2008_regressions"}).fit(
        "lee2008_invicta", ["transport.backmix"], n_starts=1)
    p = fit.fit.parameters["transport.backmix"]
    assert 0.0 <= p.value <= 0.95 and p.ci_low <= p.value <= p.ci_high


@pytest.mark.parametrize("wanted", [
    ("product_moisture_kg_kg", "fuel_rate_kg_s"),            # a study's outputs: no audit computed
    ("thermal_efficiency",), ("heat_duty_closure_W",), ("shell_max_wall_temperature_degC",),
    ("gas_outlet_dew_point_margin_K",), ("shell_heat_loss_W",),
])
def test_summary_of_some_outputs_has_the_same_values(wanted):
    """SteadyResult.summary(outputs) computes the costly groups (heat duties, shell temperatures, dew
    point...) only when one of their names is wanted; what it returns is what the full summary says."""
    from rotarydryer.thermal.audit import DUTY_KEYS, SHELL_KEYS

    st = Simulation("ajayi2011_mmg", {"operating.test": 4}).steady_state()
    part = st.summary(list(wanted))       # first: nothing remembered from a full summary
    full = st.summary()
    assert set(wanted) <= set(part)
    assert all(part[k] == full[k] for k in part)
    assert set(DUTY_KEYS) <= set(full) and set(SHELL_KEYS) <= set(full)
    if wanted[0] in ("product_moisture_kg_kg", "shell_heat_loss_W"):
        skipped = {*DUTY_KEYS, *SHELL_KEYS, "thermal_efficiency", "gas_outlet_dew_point_degC"} - {"shell_heat_loss_W"}
        assert not set(part) & skipped        # (the shell loss is the model's own output, in every summary)


def test_coupled_state_cells_are_evaluated_for_the_views_only():
    """The fill check of a run reads holdups only: the design loads and cell coefficients at the computed
    moisture are evaluated when a view asks (a study's runs skip them), and are then the state's own."""
    import numpy as np

    res = Simulation("ajayi2011_mmg", {"operating.test": 4}).steady_state()
    ts = res.thermal.transport_state()
    assert "_cells" not in vars(ts) and "design_load" not in vars(ts)     # not evaluated yet
    design, info = res.thermal._cells_at_state()
    assert np.array_equal(ts.design_load, design, equal_nan=True)
    assert set(ts.cell_info) == set(info) and all(np.array_equal(ts.cell_info[k], info[k], equal_nan=True)
                                                  for k in info)
    # at the computed moisture, not the transport model's assumed one
    assert not np.array_equal(design, np.asarray(ts.model.design_load, dtype=float), equal_nan=True)
