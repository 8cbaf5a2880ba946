"""Input schedules of the dynamic dryer (issue 31): readers, values, FMI input table, checks, and
the scheduled run against the plain dynamics."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer import Simulation
from rotarydryer.thermal.schedule import (
    DryerIntegrator,
    InputSchedule,
    apply_inputs,
    base_inputs,
    load_schedule,
    outlets,
    simulate_schedule,
)

CASE, SETS = "ajayi2011_mmg", {"operating.test": 4}


@pytest.fixture(scope="module")
def steady():
    return Simulation(CASE, SETS).thermal_steady_state()


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def test_csv_and_toml_trip_are_the_same_schedule(tmp_path):
    csv = load_schedule(_write(tmp_path, "trip.csv", "time_s,gas_inlet_temperature\n0,500\n600,500\n600,100\n"
                                                     "1200,100\n1200,500\n"))
    toml = load_schedule(_write(tmp_path, "trip.toml", '[[trip]]\nat_s = 600\nduration_s = 600\nvalue = 100\n'))
    base = {"gas_inlet_temperature": 500.0}
    for t in (0, 599.9, 600, 900, 1199.9, 1200, 5000):
        assert csv.value_at("gas_inlet_temperature", t, 500.0) == toml.resolved(base).value_at(
            "gas_inlet_temperature", t, 500.0)
    assert csv.value_at("gas_inlet_temperature", 600, 500.0) == 100.0           # the value after the step
    assert csv.value_at("gas_inlet_temperature", 600, 500.0, left=True) == 500.0
    assert csv.step_times(base) == toml.resolved(base).step_times(base) == [600.0, 1200.0]


def test_ramp_is_linear_and_held_after_its_end():
    s = InputSchedule.from_events({"ramp": [{"input": "feed_rate", "from_s": 100, "to_s": 300, "value": 40}]},
                                  base={"feed_rate": 20.0})
    assert [s.value_at("feed_rate", t, 20.0) for t in (0, 100, 200, 300, 1e4)] == [20, 20, 30, 40, 40]
    assert s.step_times({"feed_rate": 20.0}) == []


def test_trip_with_restart_ramp():
    s = InputSchedule.from_events({"trip": [{"at_s": 60, "duration_s": 120, "value": 100, "restart_s": 240}]})
    r = s.resolved({"gas_inlet_temperature": 500.0})
    assert [r.value_at("gas_inlet_temperature", t, 500.0) for t in (59, 60, 180, 300, 420, 900)] == [
        500, 100, 100, 300, 500, 500]


def test_csv_first_point_away_from_the_case_value_is_a_step():
    s = InputSchedule({"feed_rate": ((600.0, 25.0),)})
    assert s.value_at("feed_rate", 599.0, 29.0) == 29.0 and s.value_at("feed_rate", 600.0, 29.0) == 25.0
    assert s.step_times({"feed_rate": 29.0}) == [600.0]
    sig = s.signals({"feed_rate": 29.0}, 1200.0)
    assert sig["time"].tolist() == [0, 600, 600, 1200] and sig["feed_rate"].tolist() == [29, 29, 25, 25]


@pytest.mark.parametrize("text, match", [
    ("time_s,oven_temperature\n0,1\n", "unknown input 'oven_temperature'"),
    ("when,feed_rate\n0,1\n", "first column must be time_s"),
    ("time_s,feed_rate\n0,abc\n", "line 2 feed_rate: 'abc' is not a number"),
    # the file's own line number, comment and blank lines counted
    ("# a burner trip\ntime_s,feed_rate\n\n# first point\n0,30\n60,abc\n", "line 6 feed_rate: 'abc' is not a number"),
    ("time_s,feed_rate\n10,1\n5,2\n", "must not decrease"),
    ("time_s,gas_inlet_temperature,burner_fuel_rate\n0,500,0.2\n", "not both"),
    ("", "empty schedule"),
])
def test_bad_csv_schedules(tmp_path, text, match):
    with pytest.raises(ValueError, match=match):
        load_schedule(_write(tmp_path, "s.csv", text))


@pytest.mark.parametrize("text, match", [
    ("[[stop]]\nat_s = 1\n", "unknown table"),
    ("[[step]]\nat_s = 1\nvalue = 2\n", "input is required"),
    ('[[step]]\ninput = "feed_rate"\nvalue = 2\n', r"missing key\(s\) \['at_s'\]"),
    ('[[ramp]]\ninput = "feed_rate"\nfrom_s = 10\nto_s = 5\nvalue = 2\n', "must be after"),
    ('[[trip]]\nat_s = 10\nduration_s = -5\nvalue = 2\n', "must be > 0"),
    ('[[step]]\ninput = "feed_rate"\nat_s = 1\nvalue = 2\nspeed = 3\n', "unknown key"),
    ("[[step]\n", "not valid TOML"),
])
def test_bad_toml_schedules(tmp_path, text, match):
    with pytest.raises(ValueError, match=match):
        load_schedule(_write(tmp_path, "s.toml", text))


def test_schedule_file_errors(tmp_path):
    with pytest.raises(ValueError, match="no such file"):
        load_schedule(tmp_path / "missing.csv")
    with pytest.raises(ValueError, match=r"\.csv or \.toml"):
        load_schedule(_write(tmp_path, "s.txt", "x"))


def test_check_names_the_time_grid_and_the_input_range():
    base = {"gas_inlet_temperature": 500.0, "feed_moisture": 0.15}
    with pytest.raises(ValueError, match=r"outside the run's time grid \[0, 3600\] s"):
        InputSchedule({"feed_moisture": ((4000.0, 0.2),)}).check(base, 3600.0)
    with pytest.raises(ValueError, match=r"gas_inlet_temperature=900 .* outside gas.inlet_temperature \(0, 600\] degC"):
        InputSchedule({"gas_inlet_temperature": ((60.0, 900.0),)}).check(base, 3600.0)
    with pytest.raises(ValueError, match="needs a case with a \\[burner\\] block"):
        InputSchedule({"burner_fuel_rate": ((60.0, 0.1),)}).check(base, 3600.0, burner=False)


def test_no_schedule_is_the_plain_dynamics(steady):
    d, z0 = steady.dryer, steady.state
    r = simulate_schedule(d, z0, None, 3600.0, 60.0)
    plain = d.simulate(z0, 3600.0, t_eval=np.arange(0.0, 3601.0, 60.0))
    assert r.restarts == 1
    np.testing.assert_allclose(r.states, plain.states, rtol=1e-10, atol=0)


def test_step_at_zero_is_the_plain_dynamics_of_the_new_inputs(steady):
    d, z0 = steady.dryer, steady.state
    s = InputSchedule({"gas_inlet_temperature": ((0.0, 450.0),)})
    r = simulate_schedule(d, z0, s, 1800.0, 60.0)
    plain = apply_inputs(d, {"gas_inlet_temperature": 450.0}).simulate(z0, 1800.0, t_eval=np.arange(0.0, 1801.0, 60.0))
    # one integration from t = 0 in both; the plain run's steps are clipped at its end: the integrator's tolerance
    np.testing.assert_allclose(r.states, plain.states, rtol=1e-5, atol=0)
    assert r.inputs["gas_inlet_temperature"].tolist() == [450.0] * r.time_s.size


def test_burner_trip_wets_the_product_and_recovers(steady):
    d, z0 = steady.dryer, steady.state
    s = InputSchedule.from_events({"trip": [{"at_s": 600, "duration_s": 600, "value": 100}]})
    r = simulate_schedule(d, z0, s, 7200.0, 60.0)
    pm = r.outlets["product_moisture"]
    # one integration, warm-restarted at the trip and at the burner's restart: nothing else changed
    assert r.restarts == 1 and r.changes == 2
    assert pm.max() > pm[0] + 0.02                          # the trip wets the product
    assert abs(pm[-1] - pm[0]) < 2e-3                       # and it recovers in the 100 min after
    assert r.time_above("product_moisture", pm[0] + 0.01) > 600.0
    held = r.inputs["gas_inlet_temperature"]
    assert held[r.time_s.tolist().index(600.0)] == 100.0 and held[r.time_s.tolist().index(1200.0)] == 500.0


def test_off_grid_step_adds_a_communication_point(steady):
    d, z0 = steady.dryer, steady.state
    s = InputSchedule({"feed_rate": ((90.0, d.feed_rate * 0.9),)})
    r = simulate_schedule(d, z0, s, 300.0, 60.0)
    assert r.time_s.tolist() == [0, 60, 90, 120, 180, 240, 300]


def test_every_schedulable_input_applies(steady):
    d = steady.dryer
    base = base_inputs(d)
    for name, value in base.items():
        new = value * 0.9 if value else 0.1
        d2 = apply_inputs(d, {name: new})
        assert base_inputs(d2)[name] == pytest.approx(new), name


@settings(max_examples=8, deadline=None, derandomize=True)
@given(t_step=st.sampled_from([0.0, 60.0, 150.0]), frac=st.floats(0.7, 1.3))
def test_scheduled_run_conserves_the_solids(steady, t_step, frac):
    """Dry solids held at the end - at the start = dry solids fed - dry solids discharged over the
    run (the feed exact, piecewise constant; the discharge by the trapezoid rule on 10 s points)."""
    d, z0 = steady.dryer, steady.state
    s = InputSchedule({"feed_rate": ((t_step, d.feed_rate * frac),)})
    r = simulate_schedule(d, z0, s, 600.0, 10.0)
    assert np.all(np.isfinite(r.states))
    held = [float(np.sum(d.split(r.states[:, j])[0])) for j in (0, -1)]
    dt = np.diff(r.time_s)
    fed = float(np.sum(r.inputs["feed_rate"][:-1] * (1 - d.feed_moisture) * dt))
    out = np.array([d.product_stream(r.states[:, j])[0] for j in range(r.time_s.size)])
    discharged = float(np.sum(0.5 * (out[1:] + out[:-1]) * dt))
    assert held[1] - held[0] == pytest.approx(fed - discharged, rel=0.02, abs=1e-4 * held[0])


def test_burner_fuel_rate_sets_the_gas_inlet_temperature(steady):
    d = steady.dryer
    assert d.settings.burner is not None
    fuel = base_inputs(d, ["burner_fuel_rate"])["burner_fuel_rate"]
    same = apply_inputs(d, {"burner_fuel_rate": fuel})
    assert same.settings.gas_inlet_temperature == pytest.approx(d.settings.gas_inlet_temperature, abs=0.05)
    less = apply_inputs(d, {"burner_fuel_rate": 0.8 * fuel})
    assert less.settings.gas_inlet_temperature < d.settings.gas_inlet_temperature - 20


@pytest.mark.parametrize("events, t, expected", [
    ({"ramp": [{"input": "feed_rate", "from_s": 0, "to_s": 100, "value": 30}],
      "step": [{"input": "feed_rate", "at_s": 100, "value": 20}]}, (50, 99.9, 100, 200), (25, 29.99, 20, 20)),
    ({"trip": [{"at_s": 100, "duration_s": 50, "value": 100}, {"at_s": 150, "duration_s": 50, "value": 200}]},
     (99, 100, 149, 150, 199, 200), (500, 100, 100, 200, 200, 500)),
    ({"trip": [{"at_s": 100, "duration_s": 50, "value": 100}],
      "step": [{"input": "gas_inlet_temperature", "at_s": 150, "value": 450}]}, (120, 150, 300), (100, 450, 450)),
    ({"point": [{"input": "feed_rate", "at_s": 100, "value": 10}],
      "ramp": [{"input": "feed_rate", "from_s": 100, "to_s": 200, "value": 30}]}, (100, 150, 200), (10, 20, 30)),
])
def test_back_to_back_events(events, t, expected):
    """Events of one input that meet at one time (review of issue 31: refused before)."""
    base = {"feed_rate": 20.0, "gas_inlet_temperature": 500.0}
    s = InputSchedule.from_events(events).resolved(base)
    name = next(iter(s.points))
    assert [s.value_at(name, ti, base[name]) for ti in t] == pytest.approx(list(expected))


def test_ramp_end_is_not_a_step():
    s = InputSchedule({"feed_rate": ((0.0, 0.2), (100.0, 0.6))})
    assert s.step_times({"feed_rate": 0.2}) == []                    # no one-ulp 'step' at the ramp's end


def test_bom_and_single_bracket_table(tmp_path):
    p = tmp_path / "s.csv"
    p.write_bytes("\ufefftime_s,feed_rate\n0,30\n".encode("utf-8"))
    assert load_schedule(p).points == {"feed_rate": ((0.0, 30.0),)}
    q = tmp_path / "s.toml"
    q.write_text('[step]\ninput = "feed_rate"\nat_s = 1\nvalue = 2\n', encoding="utf-8")
    with pytest.raises(ValueError, match=r"must be written \[\[step\]\]"):
        load_schedule(q)


def test_fuel_and_gas_flow_together_use_the_new_air_flow(steady):
    d = steady.dryer
    fuel = base_inputs(d, ["burner_fuel_rate"])["burner_fuel_rate"]
    more_air = apply_inputs(d, {"burner_fuel_rate": fuel, "gas_flow": 1.5 * d.settings.gas_flow})
    assert more_air.settings.gas_inlet_temperature < d.settings.gas_inlet_temperature - 50


def test_short_run_grid_ends_at_t_end(steady):
    r = simulate_schedule(steady.dryer, steady.state, None, 0.3, 0.1)
    assert r.time_s[-1] == 0.3 and len(r.time_s) == 4


def _staircase(dryer, z0, land, rtol=1e-5):
    """A feed rate changed every 60 s for 20 min (a sampled controller's moves) through one integrator:
    the product moisture at each sample and the state each restart carries on from."""
    integ = DryerIntegrator(dryer, z0, rtol=rtol)
    out, starts = [], []
    try:
        for k in range(20):
            integ.restart(apply_inputs(dryer, {"feed_rate": dryer.feed_rate * (1.0 + 0.02 * np.sin(0.7 * k))}))
            starts.append(integ.z.copy())
            out.append(outlets(integ.dryer, integ.advance(60.0 * (k + 1), land=land))["product_moisture"])
    finally:
        integ.close()
    return np.array(out), np.array(starts), integ.nfev


def test_an_input_change_restart_does_not_depend_on_landing_ahead(steady):
    """A step that passed the point of an input change is taken again, cut to land there: the caller that
    knew of the change (a controller, landing ahead) and the one that did not (a schedule, an FMU's master)
    carry on from the same states."""
    d, z0 = steady.dryer, steady.state
    _, ahead, _ = _staircase(d, z0, land=True)
    _, after, _ = _staircase(d, z0, land=False)
    np.testing.assert_array_equal(ahead, after)


def test_kinks_at_every_sample_within_the_tolerance(steady):
    """The warm restart (history kept, the jump of the derivative in the first backward difference) against
    the same staircase at rtol 1e-9: the product moisture within 1e-6 kg/kg (a restart at order 1 with the
    history dropped: 1.2e-6; this one 4.5e-7)."""
    d, z0 = steady.dryer, steady.state
    fast, _, nfev = _staircase(d, z0, land=True)
    tight, _, _ = _staircase(d, z0, land=True, rtol=1e-9)
    assert np.ptp(tight) > 1e-4                      # the moves move the product
    np.testing.assert_allclose(fast, tight, rtol=0, atol=1e-6)
    assert nfev < 40 * 20


@pytest.mark.parametrize("step", [("gas_inlet_humidity", 0.019), ("gas_flow", 5.0)])
def test_template_gas_steps_integrate(tmp_path, step):
    """The `rotarydryer new` template (a co-current sand dryer) after a small step down in the inlet humidity or
    up in the gas flow: the predictor of the step after the change puts the first stage's humidity below -1, and
    the residual there (the nearest physical state's transfer and shell loss) stays finite, so the integrator
    shortens its step instead of factorising a NaN Jacobian ("Factor is exactly singular" before)."""
    case = _write(tmp_path, "my.toml", (resources.files("rotarydryer.cases") / "templates/dryer.toml").read_text())
    ss = Simulation(case).thermal_steady_state()
    name, value = step
    r = simulate_schedule(ss.dryer, ss.state, InputSchedule({name: ((300.0, value),)}), 1200.0, 60.0)
    assert np.all(np.isfinite(r.states)) and r.restarts == 1
    y_out = [outlets(apply_inputs(ss.dryer, {name: v}), z)["exhaust_humidity"]
             for v, z in zip(r.inputs[name], r.states.T)]
    assert y_out[-1] < y_out[0]       # a drier gas, or more of it, leaves less humid


def test_refusals_name_the_schedule_and_the_case_key(tmp_path):
    """Inputs that pass one by one but not together (a gas-flow step at 0 s leaves too little combustion air for
    the fuel held until a later ramp), and a fuel schedule on a case whose burner cannot make its own gas
    temperature: one line naming the schedule, the inputs and the time, or the case key (before: the burner's
    internal message alone, 'target_temperature_c')."""
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    tpl = str(resources.files("rotarydryer.cases") / "templates" / "dryer.toml")
    s1 = _write(tmp_path, "s1.toml", '[[step]]\ninput = "gas_flow"\nat_s = 0\nvalue = 1.4\n\n'
                                     '[[ramp]]\ninput = "burner_fuel_rate"\nfrom_s = 120\nto_s = 420\nvalue = 0.02\n')
    res = CliRunner().invoke(app, ["dynamics", tpl, "--schedule", str(s1), "--t-end", "600", "--json"])
    assert res.exit_code == 2
    msg = res.output.strip().splitlines()[-1]
    assert msg.startswith(f"error: {s1}: gas_flow=1.4 at 0 s: combustion air") and "cannot burn" in msg
    s2 = _write(tmp_path, "s2.toml", '[[step]]\ninput = "burner_fuel_rate"\nat_s = 300\nvalue = 0.02\n')
    res = CliRunner().invoke(app, ["dynamics", tpl, "--set", "gas.burner.combustion_air_share=0.05", "--set",
                                   "gas.inlet_temperature=450", "--schedule", str(s2), "--t-end", "600", "--json"])
    assert res.exit_code == 2
    msg = res.output.strip().splitlines()[-1]
    assert msg.startswith("error: burner_fuel_rate: the case's burner has no fuel rate at its "
                          "gas.inlet_temperature = 450 degC") and "schedule the gas_inlet_temperature instead" in msg


def test_a_recycling_burners_fuel_is_that_of_the_state_it_recycles():
    """With exhaust recycle the burner heats the recycled exhaust too: `dynamics` and `control` took the fuel of
    the case without recycle (0.125 against simulate's 0.101 kg/s), and a fuel schedule at simulate's own fuel
    cooled the product by 41 K (found by fuzzing). The fuel is now the state's (its exhaust recycled), and that
    schedule leaves the steady state where it is."""
    sim = Simulation(CASE, {**SETS, "gas.recycle_fraction": 0.3})
    st = sim.thermal_steady_state()
    d, z = st.dryer, st.state
    fuel = st.fuel_rate()
    assert base_inputs(d, ["burner_fuel_rate"], z)["burner_fuel_rate"] == pytest.approx(fuel, rel=1e-12)
    with pytest.raises(ValueError, match="gas.recycle_fraction: the state whose exhaust is recycled is needed"):
        base_inputs(d, ["burner_fuel_rate"])
    same = apply_inputs(d, {"burner_fuel_rate": fuel}, z)
    assert same.settings.gas_inlet_temperature == pytest.approx(d.settings.gas_inlet_temperature, abs=1e-6)
    res = simulate_schedule(d, z, InputSchedule({"burner_fuel_rate": ((300.0, fuel),)}), 1800.0, 300.0)
    assert float(np.max(np.abs(res.states[:, -1] - z) / d._scale())) < 1e-6
    assert res.inputs["burner_fuel_rate"][0] == pytest.approx(fuel, rel=1e-12)
    less = apply_inputs(d, {"burner_fuel_rate": 0.8 * fuel}, z)
    assert less.settings.gas_inlet_temperature < d.settings.gas_inlet_temperature - 20


def test_two_steps_of_one_input_at_one_time_are_refused():
    """Two [[step]]s of feed_rate at 300 s (3.0 and 2.0) were accepted, the last winning (found by fuzzing);
    events in any file order are taken in time order."""
    with pytest.raises(ValueError, match=r"s.toml \[\[step\]\] #2: feed_rate already has \[\[step\]\] #1 at 300 s: one "
                                         r"step or point per input and time"):
        InputSchedule.from_events({"step": [{"input": "feed_rate", "at_s": 300, "value": 3.0},
                                            {"input": "feed_rate", "at_s": 300, "value": 2.0}]}, "s.toml")
    a = InputSchedule.from_events({"step": [{"input": "feed_rate", "at_s": 900, "value": 3.0},
                                            {"input": "feed_rate", "at_s": 300, "value": 2.0}]}, "a.toml")
    b = InputSchedule.from_events({"step": [{"input": "feed_rate", "at_s": 300, "value": 2.0},
                                            {"input": "feed_rate", "at_s": 900, "value": 3.0}]}, "b.toml")
    assert a.points == b.points


def test_a_step_of_an_input_the_network_depends_on_reaches_the_steady_state_there():
    """Song's pilot drum (a trajectory forward step: the curtains' gas drag) after a +40 K gas step settled at a
    product moisture of 1.33e-5 against the 2.05e-5 of its steady state there (found by fuzzing): the dynamic run
    re-evaluated the coefficients on the case's network, which holds the drag of the case's gas. The network is
    now rebuilt for such inputs, in Simulation.dynamics and in a schedule."""
    sim = Simulation("song2003_ottawa")
    T = sim.case.gas.inlet_temperature + 40.0
    there = Simulation("song2003_ottawa", {"gas.inlet_temperature": T}).steady_state().summary()["product_moisture_kg_kg"]
    dyn = sim.dynamics(t_end=8 * 3600.0, dt=3600.0, gas_inlet_temperature=T)
    assert float(dyn.product_moisture[-1]) == pytest.approx(there, rel=1e-6)
    res = sim.run_schedule(InputSchedule({"gas_inlet_temperature": ((0.0, T),)}), t_end=8 * 3600.0, dt=3600.0)
    assert float(res.outlets["product_moisture"][-1]) == pytest.approx(there, rel=1e-6)
    assert sim.dryer().rebuilt(sim.dryer().settings) is sim.dryer()


def test_a_fuel_trip_to_no_fuel_is_refused_in_the_fuels_terms(steady):
    """A burner trip to no fuel was refused with "give gas.inlet_temperature above 28 degC", a key the schedule
    did not set (found by fuzzing): the message speaks of the fuel rate and what to schedule instead."""
    with pytest.raises(ValueError, match=r"burner_fuel_rate = 0 kg/s heats the gas to .* degC only, too cold to dry .*"
                                         r"schedule a fuel rate that keeps the gas above the feed"):
        apply_inputs(steady.dryer, {"burner_fuel_rate": 0.0})


def test_a_run_ending_where_simulate_warns_warns_too():
    """`simulate` warns of a gas its burner cannot make and of an exhaust below its dew point; a dynamic run ending
    there said nothing (a step to 600 degC on MMG Test 4, whose burner makes 586 degC)."""
    import warnings as w

    from rotarydryer import Simulation
    from rotarydryer.simulation import BurnerCapacityWarning
    from rotarydryer.thermal.audit import SupersaturationWarning
    from rotarydryer.thermal.schedule import InputSchedule

    sched = InputSchedule.from_events({"step": [{"input": "gas_inlet_temperature", "at_s": 60, "value": 600.0}]})
    with w.catch_warnings(record=True) as caught:
        w.simplefilter("always")
        Simulation("ajayi2011_mmg", {"operating.test": 4}).run_schedule(sched, t_end=600.0, dt=60.0)
    msgs = [str(c.message) for c in caught if issubclass(c.category, BurnerCapacityWarning)]
    assert len(msgs) == 1 and "at the end of the run (t = 600 s)" in msgs[0] and "reaches only 586" in msgs[0]
    data = Path(__file__).resolve().parents[1] / "data" / "user_supersaturated.toml"
    with w.catch_warnings(record=True) as caught:
        w.simplefilter("always")
        Simulation(str(data)).run_schedule(None, t_end=120.0, dt=60.0)
    assert any(issubclass(c.category, SupersaturationWarning) and "at the end of the run" in str(c.message)
               for c in caught)
