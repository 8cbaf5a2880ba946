"""Issue 30: valid cases that once failed to converge (found by random sampling over the schema's
ranges), each with the cause that was fixed; every one converges with closed balances and finite
outputs. The random-case property test is tests/badinput/test_random_valid_cases.py."""

import json
import math
import warnings

import numpy as np
import pytest
from typer.testing import CliRunner

from rotarydryer.cli import app
from rotarydryer.simulation import Simulation

HARD = [
    # shell loss continued linearly below the ambient (the frozen UA of the clipped loss created 14 % of the energy)
    pytest.param('template', {'drum.radius': 1.83884, 'flight.s1': 0.275826, 'flight.s2': 0.183884, 'drum.n_flights': 28, 'drum.slope': 3.287427, 'operating.feed_rate': 38.877629, 'operating.feed_moisture': 0.047367, 'operating.rpm': 4.162653, 'gas.flow': 1.232566, 'operating.feed_temperature': 33.334656, 'gas.inlet_temperature': 277.273041, 'gas.inlet_humidity': 0.026597, 'gas.direction': 'counter-current', 'shell.ambient_temperature': 44.13435, 'shell.insulation_thickness': 0.119195}, id='template-50'),
    # an evaporation-condensation loop holds more than 0.3 kg/kg inside the drum
    pytest.param('template', {'drum.radius': 0.95243, 'flight.s1': 0.142865, 'flight.s2': 0.095243, 'drum.n_flights': 14, 'drum.slope': 0.815245, 'operating.feed_rate': 0.118861, 'operating.feed_moisture': 0.115837, 'operating.rpm': 8.665636, 'gas.flow': 0.427897, 'operating.feed_temperature': 13.749832, 'gas.inlet_temperature': 567.789004, 'gas.inlet_humidity': 0.066617, 'gas.direction': 'counter-current', 'shell.ambient_temperature': 29.701196, 'shell.insulation_thickness': 0.19779}, id='template-39'),
    # the gas cools below the ambient and the feed (wet-bulb floor)
    pytest.param('lee2008_invicta', {'operating.feed_rate': 65.345644, 'operating.rpm': 1.647546, 'gas.flow': 42.926517, 'operating.feed_moisture': 0.01907, 'operating.feed_temperature': 40.645667, 'gas.inlet_temperature': 81.41535, 'gas.inlet_humidity': 0.005121, 'gas.direction': 'counter-current', 'shell.ambient_temperature': 43.613528, 'shell.insulation_thickness': 0.090648}, id='lee2008_invicta-31'),
    # gas and solids 16 K below the inlet gas's wet bulb
    pytest.param('lee2008_invicta', {'operating.feed_rate': 13.670261, 'operating.rpm': 5.809193, 'gas.flow': 11.412224, 'operating.feed_moisture': 0.022317, 'operating.feed_temperature': 68.100262, 'gas.inlet_temperature': 267.964916, 'gas.inlet_humidity': 0.025188, 'gas.direction': 'counter-current', 'shell.ambient_temperature': 52.130577, 'shell.ambient_humidity': 0.036266, 'shell.insulation_thickness': 0.20272}, id='lee2008_invicta-1070'),
    # Newton from the start failed (a transient march, then Newton): the bounded steps converge from the start
    pytest.param('lee2008_invicta', {'operating.feed_rate': 16.53352, 'operating.rpm': 4.426774, 'gas.flow': 15.791786, 'operating.feed_moisture': 0.026675, 'operating.feed_temperature': 48.385189, 'gas.inlet_temperature': 399.447334, 'gas.inlet_humidity': 0.109761, 'gas.direction': 'counter-current', 'shell.ambient_temperature': 58.087386, 'shell.ambient_humidity': 0.034995, 'shell.insulation_thickness': 0.366303}, id='lee2008_invicta-1012'),
    # Newton's steps on the gas overshoot from the start (humidities from 0 to 0.8 kg/kg and back): a transient
    # march, then Newton; with the step radius the continuation converges alone (29 steps)
    pytest.param('template', {'drum.radius': 2.226927, 'drum.slope': 4.840315, 'drum.n_flights': 28, 'flight.s1': 0.373216, 'flight.s2': 0.0, 'flight.alpha2': 112.52977, 'operating.feed_rate': 6.044227, 'operating.rpm': 4.632345, 'operating.feed_moisture': 0.153973, 'operating.feed_temperature': 7.867327, 'material.name': 'ottawa_sand_song2003', 'transport.model': 'ajayi2011', 'gas.direction': 'counter-current', 'gas.flow': 15.666679, 'gas.inlet_temperature': 563.460399, 'gas.inlet_humidity': 0.045817, 'shell.insulation_thickness': 0.0}, id='template-b21'),
    # transport network: a singular Jacobian at the start is not conclusive
    pytest.param('song2003_ottawa', {'operating.feed_rate': 0.030271, 'operating.rpm': 9.082265, 'gas.flow': 0.105798, 'operating.feed_moisture': 0.043834, 'operating.feed_temperature': 81.809687, 'gas.inlet_temperature': 586.05648, 'gas.inlet_humidity': 0.030825, 'gas.direction': 'counter-current', 'shell.ambient_temperature': 31.249059, 'shell.ambient_humidity': 0.017, 'shell.insulation_thickness': 0.472296}, id='song2003_ottawa-1005'),
    # ambient at -26 degC: the discharge cooling's wet bulb over ice
    pytest.param('ajayi2011_mmg', {'operating.feed_rate': 44.210131, 'operating.rpm': 3.91726, 'gas.flow': 8.212554, 'operating.feed_moisture': 0.085854, 'operating.feed_temperature': 85.963921, 'gas.inlet_temperature': 300.689432, 'gas.inlet_humidity': 0.088009, 'gas.direction': 'counter-current', 'shell.ambient_temperature': -25.984427, 'shell.ambient_humidity': 0.000593, 'shell.insulation_thickness': 0.15273}, id='ajayi2011_mmg-2038'),
    # humid gas condensing on the solids: no NaN specific energy
    pytest.param('ajayi2011_mmg', {'operating.feed_rate': 22.367937, 'operating.rpm': 2.275896, 'gas.flow': 11.993193, 'operating.feed_moisture': 0.185747, 'operating.feed_temperature': 39.348881, 'gas.inlet_temperature': 67.336365, 'gas.inlet_humidity': 0.077634, 'gas.direction': 'co-current', 'shell.ambient_temperature': 13.103709, 'shell.insulation_thickness': 0.033499}, id='ajayi2011_mmg-49'),
    # a feed of grams per hour (found by fuzzing the CLI): the Jacobian's step on the water (2e-9 kg, from the residual
    # scale's 1 kg floor) overshot milligrams of water hundreds of times; Newton converged linearly and stalled
    pytest.param('template', {'operating.feed_rate': 1e-5}, id='template-feed-1e-5'),
    pytest.param('template', {'operating.feed_rate': 1e-6}, id='template-feed-1e-6'),
]


@pytest.fixture(scope="module")
def template(tmp_path_factory):
    path = tmp_path_factory.mktemp("hard") / "mydryer.toml"
    res = CliRunner().invoke(app, ["new", "mydryer", "--out", str(path)])
    assert res.exit_code == 0, res.output
    return str(path)


def _sim(base, ov, template):
    return Simulation(template if base == "template" else base, ov)


@pytest.mark.parametrize("base,ov", HARD)
def test_hard_case_converges(base, ov, template):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = _sim(base, ov, template).steady_state().summary()
    assert s["energy_balance_error"] < 1e-9 and s["water_balance_error"] < 1e-9
    assert all(math.isfinite(v) for v in s.values() if isinstance(v, float))
    assert 0.0 <= s["product_moisture_kg_kg"] < 1.0
    if s["evaporation_kg_s"] <= 1e-12:       # nothing evaporated: both undefined, not NaN
        assert s["specific_energy_kJ_kg_water"] is None and s["thermal_efficiency"] is None
    json.dumps(s, allow_nan=False)


def test_the_march_rescues_what_newton_alone_does_not(template):
    """Where the continuation does not converge within its iterations (here 10, for a dryer that needs 29),
    the transient march reaches the root's basin and Newton finishes: the same state."""
    from rotarydryer.thermal.settings import DryerError

    base, ov = next((p.values[0], p.values[1]) for p in HARD if p.id == "template-b21")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(DryerError, match="no steady state"):
            _sim(base, ov, template).dryer().steady_state(max_iter=10, march=False)
        # a fresh dryer: the same first attempt (a used one starts its shell solves from the failed
        # attempt's last shell temperatures, and its path can differ)
        ss = _sim(base, ov, template).dryer().steady_state(max_iter=10)
        alone = _sim(base, ov, template).dryer().steady_state(march=False)
    assert ss.marched_s > 0 and ss.energy_balance_error < 1e-9
    np.testing.assert_allclose(ss.state, alone.state, rtol=1e-5, atol=1e-9)


def test_bounded_steps_converge_without_the_march(template):
    """Newton's unbounded steps on the gas humidity overshot from this start (a transient march was needed);
    with the step radius the pseudo-transient continuation converges alone, to the same state as a march
    followed by Newton."""
    base, ov = next((p.values[0], p.values[1]) for p in HARD if p.id == "lee2008_invicta-1012")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ss = _sim(base, ov, template).dryer().steady_state(march=False)
        d = _sim(base, ov, template).dryer()
        start = d.initial_state()
        marched = d.simulate(start, 3.0 * float(start[:2 * d.n_classes * d.n_tanks].sum()) / d.feed_rate)
        ref = d.steady_state(np.asarray(marched.states)[:, -1], march=False)
    assert ss.energy_balance_error < 1e-9
    np.testing.assert_allclose(ss.state, ref.state, rtol=1e-7, atol=1e-9 * d.feed_rate)



def test_the_transient_march_has_a_budget():
    """A user dryer whose steady state fell back to the transient march marched for over 10 minutes (fine size
    classes losing most of the feed as dust; found by fuzzing): the march now stops after MARCH_MAX_CALLS residual
    calls a horizon (the largest march of 279 random user dryers took 1 343, of random size-class dryers 9 024) and
    the steady state is refused."""
    import numpy as np
    import pytest

    from rotarydryer import Simulation
    from rotarydryer.thermal import dryer as D

    d = Simulation("song2003_ottawa").thermal_dryer()
    z0 = d.initial_state()
    with pytest.raises(D.DryerError, match=r"did not reach t = 3600 s within 5 residual evaluations") as info:
        d.simulate(z0, 3600.0, max_calls=5)
    assert info.value.reason == "integration" and np.all(np.isfinite(info.value.state))
    assert 9024 < D.MARCH_MAX_CALLS <= 15000


@pytest.mark.parametrize("ov", [{}, {"operating.rpm": 2.6805}])
def test_a_nearly_empty_tank_does_not_hold_up_the_steady_state(ov):
    """Fines nearly all carried off as dust leave tanks of 4e-10 kg, whose temperature rate Newton cannot resolve
    to the test's 1e-11 (scaled) through the kinks of a bone-dry product: the solve failed at 3.5e-7 after 300
    iterations, depending on the run before it in the process (found by fuzzing). The test that accepts a steady
    state counts a tank holding under EMPTY_TANK_MASS_ACCEPT of the feed (a millisecond's) by its heat capacity."""
    from pathlib import Path

    from rotarydryer.thermal.dryer import EMPTY_TANK_MASS_ACCEPT

    case = str(Path(__file__).parents[1] / "data" / "user_dusty_fines.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = Simulation(case, ov)
        r = sim.steady_state()
    s, d = r.summary(), r.thermal.dryer
    assert s["energy_balance_error"] < 1e-9 and s["water_balance_error"] < 1e-9 and r.thermal.residual < 1e-8
    k = d.n_classes * d.n_tanks
    held = r.thermal.state[:k]
    assert held.min() < EMPTY_TANK_MASS_ACCEPT * d.feed_rate      # the case has such tanks


# user dryers with size classes, from benchmarks/bench_issue32_user_dryers.py --classes (seed 1): the template with
# the flighted section's length and these overrides
CLASS_DRYERS = {
    # a fine sugar in five classes: the transient march settles it, with the traces of the finest class's emptied
    # tanks a rounding below zero; Newton starts from the nearest admissible state (refused before: "no steady
    # state reached: scaled residual 1.8e-06")
    "d1_25": (22.771, {"drum.radius": 2.308847292140271, "drum.slope": 4.711990548126865, "drum.n_flights": 17,
                       "flight.s1": 0.310988448163293, "flight.s2": 0.0, "flight.alpha2": 103.62696670960132,
                       "operating.feed_rate": 53.44935569039605, "operating.rpm": 6.290792210785851,
                       "operating.feed_moisture": 0.022274868833209616, "operating.feed_temperature": 36.97882265018653,
                       "material.name": "raw_sugar_lee2008", "transport.model": "ajayi2011",
                       "gas.direction": "co-current", "gas.flow": 32.77575765606839,
                       "gas.inlet_temperature": 223.6118559858924, "gas.inlet_humidity": 0.04449442421786624,
                       "shell.insulation_thickness": 0.0, "particle_size.classes": 5,
                       "particle_size.entrainment": True, "particle_size.distribution": "lognormal",
                       "particle_size.d50": 0.00022658868236771038, "particle_size.sigma_g": 2.5208688419351097}),
    # a zinc concentrate in five classes whose dried fines heat past the boiling point: the evaporation's slope in
    # the solids temperature fell from its steepest to zero at 99 degC (the ceiling of the surface-evaporation
    # model), and Newton cycled across it ("scaled residual 0.0077 after 300 iterations")
    "d1_53": (12.361, {"drum.radius": 0.9019192960732442, "drum.slope": 1.9566010259406958, "drum.n_flights": 27,
                       "flight.s1": 0.07349409020422519, "flight.s2": 0.0, "flight.alpha2": 108.7803689299834,
                       "operating.feed_rate": 4.468390126985238, "operating.rpm": 4.322150477712947,
                       "operating.feed_moisture": 0.12701676954271582, "operating.feed_temperature": 48.6920380758126,
                       "material.name": "zinc_concentrate_ajayi2011", "transport.model": "ajayi2011",
                       "gas.direction": "co-current", "gas.flow": 6.629095685058,
                       "gas.inlet_temperature": 442.2134044919334, "gas.inlet_humidity": 0.054016752838087934,
                       "shell.insulation_thickness": 0.0, "particle_size.classes": 5,
                       "particle_size.entrainment": True, "particle_size.distribution": "lognormal",
                       "particle_size.d50": 0.0003729298850024872, "particle_size.sigma_g": 2.251936320668493}),
}


def _class_dryer(name, template, tmp_path):
    length, ov = CLASS_DRYERS[name]
    text = open(template).read()
    assert "length = 11.0" in text
    path = tmp_path / f"{name}.toml"
    path.write_text(text.replace("length = 11.0", f"length = {length:.3f}"))
    return Simulation(str(path), ov)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(CLASS_DRYERS))
def test_user_dryers_with_fine_size_classes_converge(name, template, tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = _class_dryer(name, template, tmp_path).steady_state()
    s = r.summary()
    assert s["energy_balance_error"] < 1e-9 and s["water_balance_error"] < 1e-9 and r.thermal.residual < 1e-8
    assert all(math.isfinite(v) for v in s.values() if isinstance(v, float))
    if name == "d1_25":
        assert r.thermal.marched_s > 0       # the march, then Newton from the projected state


def test_a_marched_state_starts_newton_from_the_nearest_admissible_state():
    """The march's loose tolerance leaves traces of an emptied tank a rounding below zero (and may overshoot a
    bound): `_projected` moves such a state inside the admissible set and leaves an admissible one as it is."""
    d = Simulation("song2003_ottawa").thermal_dryer()
    z = d.steady_state().state
    assert d._admissible(z)
    np.testing.assert_array_equal(d._projected(z), z)
    bad = z.copy()
    S, W, T, Tg, Y = d.split_classes(bad)
    S[0, 3], W[0, 4], T[0, 5], Tg[2], Y[1] = -1e-8, -1e-7, 1e4, -300.0, -0.01
    assert not d._admissible(bad)
    fixed = d._projected(bad)
    assert d._admissible(fixed) and not d._admissible(bad)        # a copy
    changed = np.flatnonzero(fixed != z)
    assert changed.size == 5


def test_a_stalled_march_is_not_repeated_and_a_longer_one_carries_on(monkeypatch):
    """Where Newton fails after the first march stop, the march carries on from there to the next stop (it was
    integrated again from the start); where the march stalls (its residual budget spent), the longer one, which
    would stall at the same point, is not run: the failure comes at once (user dryers waited 10-20 s more)."""
    from rotarydryer.thermal.dryer import MARCH_HORIZONS, DryerError

    d = Simulation("song2003_ottawa").thermal_dryer()
    start = d.initial_state()
    mrt = float(np.sum(start[:2 * d.n_classes * d.n_tanks])) / d.feed_rate
    calls = []

    def stalled(z0, t_end, **kw):
        calls.append((np.array(z0), t_end))
        raise DryerError("the integration did not reach ...", reason="integration", state=z0)
    monkeypatch.setattr(d, "simulate", stalled)
    with pytest.raises(DryerError, match="no steady state"):
        d.steady_state(max_iter=2)
    assert len(calls) == 1

    calls.clear()

    class Marched:
        def __init__(self, z):
            self.states = z[:, None] * 1.0001

    def marched(z0, t_end, **kw):
        calls.append((np.array(z0), t_end))
        return Marched(np.asarray(z0))
    monkeypatch.setattr(d, "simulate", marched)
    with pytest.raises(DryerError, match="no steady state"):
        d.steady_state(max_iter=2)
    assert len(calls) == len(MARCH_HORIZONS) == 2
    np.testing.assert_allclose(calls[0][1], MARCH_HORIZONS[0] * mrt)
    np.testing.assert_allclose(calls[1][1], (MARCH_HORIZONS[1] - MARCH_HORIZONS[0]) * mrt)
    np.testing.assert_array_equal(calls[1][0], calls[0][0] * 1.0001)      # from where the first one ended


@pytest.mark.slow
def test_a_failure_the_dust_causes_late_names_the_dust(monkeypatch):
    """At the solver's start only the finest of three classes is carried off (a third of the feed, no hint), but
    the gas the iterations wet carries every class off and Newton failed from the feed's shares of the transport
    holdups. The transient march then settled it (since MARCH_MAX_CALLS went from 4 000 to 12 000: its march took
    more, and the solve failed); since the start takes the dust out (`ThermalDryer._dusty_start`, 2026-12-07) Newton
    settles it without the march: a third of the feed in the dust, the finest class all of it, both balances closed.
    From the old start, where the march stalls, the failure names the dust from the last iterate; the same dryer
    without entrainment converges."""
    from pathlib import Path

    from rotarydryer.thermal.dryer import DryerError
    from rotarydryer.thermal.states import dust_share

    case = str(Path(__file__).parents[1] / "data" / "user_dust_runaway.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = Simulation(case).steady_state()
        assert not r.thermal.marched_s and r.thermal.residual < 1e-8
        s = r.summary()
        assert s["energy_balance_error"] < 1e-9 and s["water_balance_error"] < 1e-9
        assert dust_share(r.thermal) == pytest.approx(1.0 / 3.0, abs=0.01)
        assert [round(row["lost_as_dust"], 2) for row in r.thermal.size_class_table()] == [1.0, 0.0, 0.0]

        d = Simulation(case).thermal_dryer()
        monkeypatch.setattr(d, "_dusty_start", lambda S, W, T, Tg, Y: (S, W))      # the feed's shares, as before

        def stalled(z0, t_end, **kw):
            raise DryerError("the integration did not reach ...", reason="integration", state=z0)
        monkeypatch.setattr(d, "simulate", stalled)
        with pytest.raises(ValueError, match=r"no steady state reached.*the dust is the likely cause: at the "
                                             r"solver's last iterate .* lower gas\.flow"):
            d.steady_state()
        s = Simulation(case, {"particle_size.entrainment": False}).steady_state().summary()
    assert s["energy_balance_error"] < 1e-9


def test_a_failure_the_exhaust_recycle_causes_names_the_recycle(template):
    """The `rotarydryer new` template recycling 99 % of its exhaust: the 1 % that leaves must carry out all the water
    evaporated (at 90 % its exhaust already holds 0.4 kg/kg), the iterations run the humidity to the top of the
    humid-air range, and the solve fails; it said "no steady state reached" and nothing more (found by fuzzing)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = Simulation(template, {"gas.recycle_fraction": 0.9}).steady_state().summary()
        assert s["gas_outlet_humidity_kg_kg"] > 0.3
        with pytest.raises(ValueError, match=r"no steady state reached.*the recycled exhaust is the likely cause: "
                                             r"with gas\.recycle_fraction = 0\.99 .* lower gas\.recycle_fraction"):
            Simulation(template, {"gas.recycle_fraction": 0.99}).steady_state()


def test_the_start_takes_the_dust_out(template):
    """Eight classes of Lee's fine river sand, the gas carrying the three finest off (found by fuzzing): the start gave
    every class the feed's share of every tank, the gas then had to empty the fine ones, the pseudo-transient solve
    stalled at a scaled residual of 35 and the transient march took 21 s (20 classes: 174 s). The start now holds each
    class at its own linear network's steady state with the dust edges at the start's gas (`_dusty_start`): the
    dust classes start with what they hold at the steady state, and Newton settles it without the march."""
    ov = {"particle_size.classes": 8, "particle_size.dataset": "lee2008_fine_river_sand",
          "particle_size.entrainment": True}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = Simulation(template, ov)
        d = sim.thermal_dryer()
        z0 = d.initial_state()
        r = sim.steady_state()
    k = d.n_classes * d.n_tanks
    start = (z0[:k] + z0[k:2 * k]).reshape(d.n_classes, d.n_tanks).sum(axis=1)
    end = (r.thermal.state[:k] + r.thermal.state[k:2 * k]).reshape(d.n_classes, d.n_tanks).sum(axis=1)
    lost = [row["lost_as_dust"] for row in r.thermal.size_class_table()]
    assert lost[0] > 0.99 and lost[-1] < 0.01
    # the three classes the gas empties hold what the unflighted bed before the flights holds (17-31 kg), the
    # coarse four about 260 kg; the start holds the same of both within a half (was: 245 kg of each class); the
    # fourth class, of which the gas takes 46 %, starts emptier (the start's gas is a hotter, faster guess)
    assert np.all(end[:3] < 0.15 * end[-1]) and np.all(start[:3] < 0.15 * start[-1])
    np.testing.assert_allclose(start[:3], end[:3], rtol=0.5)
    np.testing.assert_allclose(start[4:], end[4:], rtol=0.25)
    assert not r.thermal.marched_s and r.thermal.residual < 1e-8
    s = r.summary()
    assert s["energy_balance_error"] < 1e-9 and s["water_balance_error"] < 1e-9
    # without entrainment the start is the feed's share of every tank, as before
    d0 = Simulation(template, {**ov, "particle_size.entrainment": False}).thermal_dryer()
    z1 = d0.initial_state()
    held = (z1[:k] + z1[k:2 * k]).reshape(d0.n_classes, d0.n_tanks)
    np.testing.assert_allclose(held / held.sum(axis=0), np.tile(d0.class_feed[:, None], (1, d0.n_tanks)), rtol=1e-9)
