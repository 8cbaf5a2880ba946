"""The Simulation API's own argument checks."""

import numpy as np
import pytest

from rotarydryer import Simulation


def test_bad_arguments_are_named():
    """Simulation(None) raised AttributeError, sweep(123) TypeError, dynamics(dt=0) ZeroDivisionError and
    dynamics(t_end=-10) returned one point (found by fuzzing)."""
    for case in (None, 123):
        with pytest.raises(ValueError, match=f"case = {case!r}: give a case name"):
            Simulation(case)
    sim = Simulation("lee2008_invicta")
    with pytest.raises(ValueError, match=r"grid = 123: give a list of override dicts"):
        sim.sweep(123)
    with pytest.raises(ValueError, match=r"dt = 0 s is outside the allowed range"):
        sim.dynamics(dt=0)
    with pytest.raises(ValueError, match=r"t_end = -10 s is outside the allowed range"):
        sim.dynamics(t_end=-10)


def test_an_unknown_output_name_and_a_boolean_number_are_refused():
    """A sweep's rows for an output name the runs do not give had the error "'nonexistent'" (a KeyError's text);
    an override of True for a number read as 1.0 kg/s (found by fuzzing)."""
    rows = Simulation("lee2008_invicta").sweep({"operating.rpm": [3.0]}, outputs=["nonexistent"])
    assert rows[0]["error"].startswith("outputs ['nonexistent']: not among this run's outputs (")
    assert "total_holdup_kg" in rows[0]["error"]
    with pytest.raises(ValueError, match=r"--set operating.feed_rate: operating.feed_rate = True is not a number"):
        Simulation("lee2008_invicta", {"operating.feed_rate": True})


def test_a_new_speed_at_or_above_the_critical_speed_is_refused():
    """A dynamic run's (or a study's) new drum speed is checked against the drum's critical speed as the case's
    is: ``dynamics(rotational_speed=30)`` on the 5 m Invicta drum (N_c = 18.9 rev/min) ran (found by fuzzing)."""
    sim = Simulation("lee2008_invicta")
    with pytest.raises(ValueError, match=r"^operating.rpm = 30 rev/min is at or above the critical speed .* "
                                         r"the allowed range is \(0, 18.9\) rev/min"):
        sim.dynamics(t_end=120.0, dt=60.0, rotational_speed=30.0)


# ---- found by a review of the Python API on a `rotarydryer new` case (2026-12-07) --------------------------------
@pytest.fixture(scope="module")
def new_case(tmp_path_factory):
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    where = tmp_path_factory.mktemp("api") / "mydryer.toml"
    res = CliRunner().invoke(app, ["new", "mydryer", "--out", str(where)])
    assert res.exit_code == 0, res.output
    return where


def test_run_case_of_a_case_object_refuses_overrides_it_cannot_apply(new_case):
    """run_case(case object, overrides) returned the case as it was (feed 2.5 kg/s) and recorded the overrides (feed
    4 kg/s) in the results' provenance. The overrides need the case's name or path; a case object loaded with
    overrides records them with ``applied``."""
    from rotarydryer.cases import load_case
    from rotarydryer.simulation import run_case

    case = load_case(str(new_case))
    with pytest.raises(ValueError, match=r"^overrides need a case name or path \(load_case applies them\): this case "
                                         r"object has operating.feed_rate = 2.5, not 4.0; .* applied="):
        run_case(case, {"operating.feed_rate": 4.0}, rtd=False, thermal=False)
    ov = {"operating.feed_rate": 4.0}
    res = run_case(load_case(str(new_case), ov), applied=ov, rtd=False, thermal=False)
    by_path = run_case(new_case, ov, rtd=False, thermal=False)
    assert res.model_choices["overrides"] == ov == by_path.model_choices["overrides"]
    assert res.scalars["total_holdup_kg"] == pytest.approx(by_path.scalars["total_holdup_kg"], rel=1e-12)
    # the old call with the overrides the case object holds: deprecated, the same result
    with pytest.warns(DeprecationWarning, match=r"named with applied="):
        old = run_case(load_case(str(new_case), ov), ov, rtd=False, thermal=False)
    assert old.model_choices["overrides"] == ov and old.scalars["total_holdup_kg"] == res.scalars["total_holdup_kg"]
    with pytest.raises(ValueError, match=r"^applied = "):
        run_case(new_case, applied=ov)


def test_studies_that_reload_the_case_refuse_a_simulation_without_a_name(new_case):
    """A Simulation of a case object or of TOML text made target, sweep and energy_audit fail with "'mydryer (from
    template)' is not a packaged case" (every sweep row an error): they load the case again by its name or path."""
    from rotarydryer.cases import load_case
    from rotarydryer.studies.energy import energy_audit
    from rotarydryer.studies.target import target

    for sim, made in ((Simulation(load_case(str(new_case))), "a case object"),
                      (Simulation.from_text(new_case.read_text(), "mine"), r"TOML text \(Simulation.from_text\)")):
        with pytest.raises(ValueError, match=rf"^a sweep loads the case again .* was made from {made}; give"):
            sim.sweep({"operating.feed_rate": [3.0]})
        with pytest.raises(ValueError, match=rf"^a target loads the case again .* was made from {made}"):
            target(sim, "operating.feed_rate=1,4", "product_moisture_kg_kg<=0.01")
        with pytest.raises(ValueError, match=rf"^an energy audit loads the case again .* was made from {made}"):
            energy_audit(sim)
    assert Simulation(new_case).reloadable_name("a sweep") == str(new_case)


def test_rtd_of_the_reported_state_and_a_zero_time_refused(new_case):
    """Simulation.rtd() runs on the transport-only steady state (the published transport models', `rtd`'s and
    `validate`'s) while summary() and results() report the coupled state's tracer (859 against 851 s): rtd(thermal=True)
    gives the reported one; rtd(t_end=0, dt=0) took the case's values instead of refusing them."""
    sim = Simulation(new_case)
    mean = sim.rtd(thermal=True).tracer_mean
    assert mean == pytest.approx(sim.steady_state().summary()["tracer_mean_s"], rel=2e-3)
    transport = sim.rtd().tracer_mean
    assert transport == pytest.approx(sim.transport_steady_state().tracer_system().moments(
        sim.transport_model().tracer_input)["mean"], rel=2e-3)
    assert abs(mean - transport) > 1e-3 * mean     # the two states differ: the test can tell them apart
    with pytest.raises(ValueError, match=r"t_end = 0 s is outside the allowed range"):
        sim.rtd(t_end=0)
    with pytest.raises(ValueError, match=r"dt = 0 s is outside the allowed range"):
        sim.rtd(dt=0)


def test_sweep_rows_keep_their_inputs_with_outputs_and_summary_refuses_a_bare_name(new_case):
    """With ``outputs`` a sweep's rows held the outputs only (the docstring: its overrides and the outputs);
    summary(outputs="fuel_rate_kg_s") iterated the string's characters and returned a partial dict."""
    sim = Simulation(new_case)
    rows = sim.sweep({"operating.feed_rate": [2.0, 3.0]}, outputs=["product_moisture_kg_kg"])
    assert [sorted(r) for r in rows] == [["operating.feed_rate", "product_moisture_kg_kg"]] * 2
    assert [r["operating.feed_rate"] for r in rows] == [2.0, 3.0]
    with pytest.raises(ValueError, match=r"^outputs = 'fuel_rate_kg_s': give a list of output names"):
        sim.steady_state().summary("fuel_rate_kg_s")


def test_the_unknown_key_error_names_the_material_fields(new_case):
    with pytest.raises(ValueError, match=r"valid keys: .*, material\.<field> \(any field of the material\)$"):
        Simulation(new_case, {"x.y": 1.0})


def test_kilning_beds_that_follow_the_cell_count_warn(new_case):
    """With the template's fixed kilning time each cell holds its excess over the design load for kiln_time: at a
    feed over the flights' capacity the holdup grew 56 % from 5 to 80 cells without a word (found by a review)."""
    import warnings

    from rotarydryer.cases.build import KilnCellsWarning

    over = {"operating.feed_rate": 5.0}
    with pytest.warns(KilnCellsWarning, match=r"each flighted cell .* grow with the cell count \(transport.n_cells\); "
                                              r"transport.kiln_law = 'cascade'") as caught:
        res = Simulation(new_case, over).steady_state().summary()
    assert res["kiln_bed_holdup_kg"] > 0.05 * res["total_holdup_kg"]
    said = [str(w.message) for w in caught if issubclass(w.category, KilnCellsWarning)]
    assert len(said) == 1 and said[0].startswith(      # once, with the mass the run reports
        f"the kilning beds hold {res['kiln_bed_holdup_kg']:,.0f} kg "
        f"({100 * res['kiln_bed_holdup_kg'] / res['total_holdup_kg']:.0f} % of the holdup)")
    with warnings.catch_warnings():
        warnings.simplefilter("error", KilnCellsWarning)
        Simulation(new_case, {**over, "transport.kiln_law": "cascade"}).steady_state()
        Simulation(new_case).steady_state()                 # within the flights' capacity: no kilning beds
        Simulation("lee2008_invicta").steady_state()        # kiln_time calibrated at its cell count


def test_a_dynamic_result_names_its_units(new_case):
    """`Simulation.dynamics()` gave ``product_moisture`` and ``time`` without the unit suffix of every other output
    (its DataFrame and CSV have them): ``product_moisture_kg_kg`` and ``time_s`` are the same arrays."""
    r = Simulation(str(new_case)).dynamics(t_end=120.0, dt=60.0)
    assert r.time_s is r.time and r.product_moisture_kg_kg is r.product_moisture
    np.testing.assert_array_equal(r.time_s, [0.0, 60.0, 120.0])
    df = r.to_dataframe()
    np.testing.assert_array_equal(df["product_moisture_kg_kg"].to_numpy(), r.product_moisture_kg_kg)
    assert df.index.name == "time_s"
