"""What an acceptance check of the Python API found on the default configuration (a `rotarydryer new` case and the
shipped ones): an override no section takes, an unbounded tracer grid, a shell inside the drum, the executor's and the
sweep's options, a feed wetter than its material's laws, a misspelt output, a share above 1."""

from __future__ import annotations

import shutil
from importlib import resources

import numpy as np
import pytest

from rotarydryer import Simulation
from rotarydryer.cases import UnusedKeyWarning, load_case
from rotarydryer.executor import Executor


@pytest.fixture(scope="module")
def new_case(tmp_path_factory):
    path = tmp_path_factory.mktemp("new") / "mycase.toml"
    with resources.as_file(resources.files("rotarydryer.cases") / "templates" / "dryer.toml") as src:
        shutil.copy(src, path)
    return str(path)


@pytest.mark.parametrize("key, value, own", [("drum.n_flights", 2, "n_flights"), ("flight.s1", 5.0, "flight"),
                                             ("transport.n_cells", 5, "n_cells")])
def test_a_default_every_section_replaces_is_said_to_do_nothing(key, value, own):
    """``drum.n_flights = 2`` on the MMG case, whose flighted sections each set their own, ran the base case
    without a word."""
    with pytest.warns(UnusedKeyWarning, match=rf"{key} has no effect: .* \(B, C, D\) sets its own {own}"):
        load_case("ajayi2011_mmg", {key: value})


def test_a_default_a_section_takes_is_not_warned_of(new_case, recwarn):
    load_case(new_case, {"drum.n_flights": 20, "transport.n_cells": 12, "flight.s1": 0.2})
    assert not [w for w in recwarn if issubclass(w.category, UnusedKeyWarning)]


@pytest.mark.parametrize("kw, fragment", [
    (dict(t_end=1e7, dt=1.0), "give 1e+07 time steps; the limit is 200000"),
    (dict(t_end=1e9, dt=1e-3), "the limit is 200000"),
    (dict(dt="a"), "dt must be a real number"),
    (dict(t_end=float("nan")), "t_end = nan s is not a number"),
    (dict(t_end=10.0, dt=100.0), "must be larger than dt"),
])
def test_a_tracer_grid_given_to_rtd_is_bounded(kw, fragment):
    """``Simulation.rtd(t_end=1e7, dt=1)`` ran on past a minute, ``(1e9, 1e-3)`` asked for 7 TiB."""
    with pytest.raises(ValueError, match="^" + r"[^\n]*" + fragment.replace("(", r"\(").replace("+", r"\+")):
        Simulation("lee2008_invicta").rtd(**kw)


def test_a_shell_inside_the_drum_is_refused(new_case):
    with pytest.raises(ValueError, match=r"shell.inner_radius = 0.01 m is outside the allowed range \[0.5, 2\] m"):
        Simulation(new_case, {"shell.inner_radius": 0.01}).steady_state()
    # the MMG case gives its shell (1.90 m): a smaller drum keeps it (a review found 0.8-1.25 x refusing this)
    assert Simulation("ajayi2011_mmg", {"drum.radius": 1.5}).steady_state().summary()["product_moisture_kg_kg"] > 0


def test_a_feed_wetter_than_the_materials_laws_names_the_feed_moisture():
    """The MMG case's feed at 0.99 kg/kg was refused as a negative bulk density."""
    with pytest.raises(ValueError, match=r"operating.feed_moisture = 0.99 kg/kg wet is outside the moisture range of "
                                         r"material 'zinc_concentrate_ajayi2011' \(\[0.08, 0.19\] kg/kg wet"):
        Simulation("ajayi2011_mmg", {"operating.feed_moisture": 0.99}).steady_state()


def test_executor_options_from_python():
    assert Executor(workers=np.int64(2)).workers == 2          # NumPy's integers are whole numbers
    for bad in (2.0, "2"):
        with pytest.raises(ValueError, match=r"--workers = .* is not a whole number"):
            Executor(workers=bad)
    for bad in ("garbage", 123):        # refused at once, not by Dask after its wait
        with pytest.raises(ValueError, match=r"--scheduler = '.*' is not a scheduler address"):
            Executor(scheduler=bad)
    with pytest.raises(ValueError, match=r"fn = .*<lambda> cannot be sent to worker processes"):
        Executor(workers=2).map(lambda x: x, [1, 2])
    with pytest.raises(ValueError, match=r"chunks = 'x': expected a chunk size"):
        Executor().map_chunks(sorted, [1, 2, 3], chunks="x")


@pytest.mark.parametrize("kw, fragment", [
    (dict(workers=-1), "workers = -1 is outside the allowed range [0, inf)"),
    (dict(workers=2.5), "workers = 2.5 is not a whole number"),
    (dict(workers="2"), "workers = '2' is not a whole number"),
    (dict(executor="x"), "executor = 'x' is not a rotarydryer.executor.Executor"),
    (dict(outputs=[1]), "outputs: 1 is not an output name"),
])
def test_sweep_options_are_checked_before_any_run(new_case, kw, fragment):
    with pytest.raises(ValueError) as info:
        Simulation(new_case).sweep({"operating.rpm": [2, 3]}, **kw)
    assert fragment in str(info.value)


def test_a_misspelt_summary_output_is_named(new_case):
    ss = Simulation(new_case).steady_state()
    with pytest.raises(ValueError, match=r"outputs \['nope'\]: not among this run's outputs \(active_holdup_kg"):
        ss.summary(outputs=["nope"])
    assert set(ss.summary(outputs=["tracer_mean_s"])) >= {"tracer_mean_s", "product_moisture_kg_kg"}
    rows = Simulation(new_case).sweep({"operating.rpm": [2, 3]}, outputs=["operating.rpm", "nope"])
    assert all(r["error"].startswith("outputs ['nope']: not among this run's outputs") for r in rows)


def test_a_class_the_gas_carries_off_whole_is_lost_at_most_once(new_case):
    run = Simulation(new_case, {"particle_size.dataset": "lee2008_fine_river_sand"}).steady_state()
    rows = run.thermal.size_class_table()
    assert all(0.0 <= r["lost_as_dust"] <= 1.0 for r in rows)
    gone = [r for r in rows if r["lost_as_dust"] == 1.0]
    assert gone and all(r["rtd_mean_s"] is None for r in gone)


def test_wrong_types_from_python_are_named(new_case):
    from rotarydryer.geometry.curtain import curtain_distribution
    from rotarydryer.lab.drying_curves import fit_models, load_example
    from rotarydryer.studies.energy import energy_audit

    cases = [
        (lambda: Simulation(new_case, {1: 2}), "overrides: key 1 is not a case key"),
        (lambda: Simulation(new_case).steady_state(warm="x"), "warm = 'x': give the warm_data()"),
        (lambda: energy_audit(new_case, recycle="0.2"), "recycle = '0.2': give a number or a list of numbers"),
        (lambda: energy_audit(new_case, recycle=[0.2, "a"]), "recycle: 'a' is not a number"),
        (lambda: energy_audit(new_case, [1, 2]), "overrides = [1, 2]: give a dict of case keys"),
        (lambda: curtain_distribution("x", 40.0), "drum = 'x' is not a FlightedDrum"),
        (lambda: fit_models("curves.csv"), "curves = 'curves.csv' is not a DryingCurves"),
        (lambda: Simulation(new_case).dynamics(600, 60, solid_feed_rate="a"), "solid_feed_rate = 'a' is not a number"),
    ]
    for call, fragment in cases:
        with pytest.raises(ValueError) as info:
            call()
        assert fragment in str(info.value) and "\n" not in str(info.value)
    # one value or one name where a list is expected: taken as that one
    assert list(fit_models(load_example(), "page").fits) == ["page"]


def test_the_schedule_names_of_feed_and_speed_are_dynamic_inputs(new_case):
    sim = Simulation(new_case)
    a = sim.dynamics(600, 60, feed_rate=2.6)
    b = sim.dynamics(600, 60, solid_feed_rate=2.6)
    assert np.array_equal(a.states, b.states)


@pytest.mark.parametrize("key, value, fragment", [
    ("drum.n_flights", "2.5", "drum.n_flights = '2.5': Input should be a valid integer, unable to parse string as an "
                              "integer (allowed range [2, 1000])"),
    ("drum.radius", "big", "(allowed range (0, 20] m)"),
])
def test_a_value_of_another_type_names_the_range(new_case, key, value, fragment):
    with pytest.raises(ValueError) as info:
        load_case(new_case, {key: value})
    assert fragment in str(info.value)


def test_one_balance_one_sign_and_section_lengths_as_given(new_case):
    d = Simulation(new_case).steady_state().to_dict()
    assert d["physical_energy_balance_error"] == d["energy_balance_error"] >= 0      # physical mode: one balance
    case = load_case(new_case)
    assert [r["length_m"] for r in d["shell_sections"]] == [float(s.length) for s in case.sections]
