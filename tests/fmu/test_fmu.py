"""FMI 2.0 co-simulation export (issue 17, part 3): the FMU stepped by fmpy matches the Python model."""

from __future__ import annotations

import re

import numpy as np
import pytest

pytest.importorskip("pythonfmu", reason="FMU export needs pythonfmu (extra 'fmu')")
fmpy = pytest.importorskip("fmpy", reason="the FMU test needs fmpy (extra 'fmu')")

from rotarydryer.fmu import OUTPUTS, DryerStepper, start_values  # noqa: E402

CASE, SETS = "ajayi2011_mmg", {"operating.test": 4}


@pytest.fixture(scope="module")
def fmu_path(tmp_path_factory):
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    path = tmp_path_factory.mktemp("fmu") / "dryer.fmu"
    res = CliRunner().invoke(app, ["fmu", CASE, "--set", "operating.test=4", "-o", str(path)])
    assert res.exit_code == 0, res.output
    return path


def _dynamics_and_fmu(fmu_path, schedule, t_end, tmp_path):
    """(``rotarydryer dynamics --schedule``'s series, the FMU's fmpy result driven by the same table) over ``t_end`` s,
    both reported every 60 s."""
    import json

    from typer.testing import CliRunner

    from rotarydryer.cli import app
    from rotarydryer.thermal.schedule import load_schedule

    res = CliRunner().invoke(app, ["dynamics", CASE, "--set", "operating.test=4", "--schedule", str(schedule),
                                   "--t-end", f"{t_end:g}", "--out", str(tmp_path / "run"), "--json", "--quiet"])
    assert res.exit_code == 0, res.output
    series = json.loads((tmp_path / "run" / "dynamics.json").read_text())["series"]
    inp = load_schedule(schedule).signals(start_values(fmu_path), t_end)
    out = fmpy.simulate_fmu(str(fmu_path), start_time=0.0, stop_time=t_end, step_size=60.0, output_interval=60.0,
                            input=inp, output=list(OUTPUTS))
    return series, out


def test_fmu_matches_python_model_after_feed_step(fmu_path):
    path = fmu_path
    md = fmpy.read_model_description(str(path))
    names = {v.name: v.causality for v in md.modelVariables}
    assert {k for k, c in names.items() if c == "input"} == {"feed_rate", "feed_moisture", "gas_inlet_temperature",
                                                              "rpm", "gas_flow", "gas_inlet_humidity",
                                                              "feed_temperature", "fouling"}
    units = {v.name: v.description for v in md.modelVariables}
    assert units["feed_rate"].endswith("kg/s") and units["exhaust_temperature"].endswith("degC"), units
    assert {k for k, c in names.items() if c == "output"} == set(OUTPUTS)

    ref = DryerStepper(CASE, SETS)
    f1 = ref.inputs["feed_rate"] * 1.1                      # +10 % feed step at t = 0
    dt, t_end = 600.0, 7200.0
    expected = [dict(ref.outputs)]
    for _ in range(int(t_end / dt)):
        expected.append(ref.step(dt, feed_rate=f1))
    inp = np.array([(0.0, f1)], dtype=[("time", float), ("feed_rate", float)])
    out = fmpy.simulate_fmu(str(path), start_time=0.0, stop_time=t_end, step_size=dt, output_interval=dt,
                            input=inp, output=list(OUTPUTS))
    assert len(out) == len(expected)
    for k in OUTPUTS:
        e = np.array([row[k] for row in expected])
        np.testing.assert_allclose(out[k], e, rtol=1e-6, atol=1e-9 * max(1.0, np.max(np.abs(e))), err_msg=k)
    # the step moved the plant (not a trivially constant comparison)
    assert out["holdup"][-1] > 1.02 * out["holdup"][0]


def test_fmu_driven_by_fmpy_with_a_schedule_matches_rotarydryer_dynamics(fmu_path, tmp_path):
    """Issue 31 acceptance: the burner trip (gas inlet 500 -> 100 degC for 10 min) of
    ``rotarydryer dynamics --schedule trip.csv`` and the FMU driven by fmpy with the same table."""
    from rotarydryer.thermal.schedule import OUTLET_NAMES

    trip = tmp_path / "trip.csv"
    trip.write_text("time_s,gas_inlet_temperature\n0,500\n600,500\n600,100\n1200,100\n1200,500\n", encoding="utf-8")
    series, out = _dynamics_and_fmu(fmu_path, trip, 3600.0, tmp_path)
    np.testing.assert_array_equal(out["time"], series["time_s"])
    for k in OUTPUTS:
        e = np.array(series[OUTLET_NAMES[k]])      # the FMU's output k under its name on every other surface
        np.testing.assert_allclose(out[k], e, rtol=1e-6, atol=0, err_msg=k)
    pm = np.array(series["product_moisture_kg_kg"])
    assert pm.max() > pm[0] + 0.02          # the trip moved the plant


def test_two_fmus_in_one_process_run_their_own_dryers(fmu_path, tmp_path):
    """Two exported dryers in one co-simulation process (fmpy loads both here): each runs its own case. Each export's
    Python slave has a module of its own (before: the second FMU imported the first's cached module and ran the
    first's dryer)."""
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    other = tmp_path / "song.fmu"
    res = CliRunner().invoke(app, ["fmu", "song2003_ottawa", "-o", str(other)])
    assert res.exit_code == 0, res.output
    runs = {}
    for path in (fmu_path, other):          # the MMG FMU first: its module is loaded before Song's
        out = fmpy.simulate_fmu(str(path), start_time=0.0, stop_time=120.0, step_size=60.0, output_interval=60.0,
                                output=list(OUTPUTS))
        runs[path.name] = out
    song = DryerStepper("song2003_ottawa", {}).outputs
    for k in OUTPUTS:
        assert runs["song.fmu"][k][0] == pytest.approx(song[k], rel=1e-6, abs=1e-12), k
    assert runs["song.fmu"]["holdup"][0] < 0.01 * runs["dryer.fmu"]["holdup"][0]     # a pilot drum, not MMG


def test_fmu_of_a_case_with_the_thermal_model_off_says_so(tmp_path):
    """A case with a [gas] block and thermal.enabled = false: the refusal says the model is switched off (before:
    'has no [gas] block', which the case has)."""
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    res = CliRunner().invoke(app, ["fmu", "lee2008_invicta", "--set", "thermal.enabled=false", "-o",
                                   str(tmp_path / "x.fmu")])
    assert res.exit_code == 2
    assert "has the heat-and-mass model switched off (thermal.enabled = false)" in res.output
    assert not (tmp_path / "x.fmu").exists()


def test_the_stepper_refuses_a_bad_step_and_keeps_the_last_good_inputs():
    """step(-60) ran time backwards, step(nan) made it NaN, and an input the model refused stayed in the stepper,
    so that every later step failed with its message (found by fuzzing)."""
    s = DryerStepper("lee2008_invicta")
    for dt in (-60.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="a communication step is a finite number of seconds >= 0"):
            s.step(dt)
    assert s.time == 0.0
    with pytest.raises(ValueError, match="gas.flow = 0"):
        s.step(60.0, gas_flow=0.0)
    out = s.step(60.0)
    assert s.time == 60.0 and s.inputs["gas_flow"] > 0 and np.isfinite(out["product_moisture"])


def test_the_command_help_lists_every_fmu_input():
    """`rotarydryer fmu --help` listed four inputs; the FMU has five (gas_flow too, found by fuzzing)."""
    from typer.testing import CliRunner

    from rotarydryer.cli import app
    from rotarydryer.fmu import INPUTS

    res = CliRunner().invoke(app, ["fmu", "--help"], terminal_width=400)
    assert res.exit_code == 0
    text = " ".join(res.output.split())
    assert "inputs " + ", ".join(INPUTS) + ";" in text, text


def test_the_fmu_runs_the_case_it_was_exported_with(tmp_path):
    """The FMU read its case file when it ran: an edited file moved its start (the exhaust jumped 66 K in one step,
    the stored start values being the old ones) and a deleted one stopped fmpy with a bare fatal status (found by
    fuzzing). The file's text is now stored at export."""
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    case = tmp_path / "mine.toml"
    res = CliRunner().invoke(app, ["new", "mine", "--out", str(case)])
    assert res.exit_code == 0, res.output
    path = tmp_path / "mine.fmu"
    res = CliRunner().invoke(app, ["fmu", str(case), "-o", str(path), "-q"])
    assert res.exit_code == 0, res.output
    expected = DryerStepper(str(case)).outputs
    text = case.read_text()
    hotter = re.sub(r"\ninlet_temperature = [0-9.]+", "\ninlet_temperature = 350.0", text)
    assert hotter != text
    case.write_text(hotter, encoding="utf-8")
    edited = DryerStepper(str(case)).outputs
    assert edited["exhaust_temperature"] > expected["exhaust_temperature"] + 10.0       # the edit moves the dryer
    for edit in ("edited", "deleted"):
        if edit == "deleted":
            case.unlink()
        out = fmpy.simulate_fmu(str(path), start_time=0.0, stop_time=120.0, step_size=60.0, output_interval=60.0,
                                output=list(OUTPUTS))
        for k in OUTPUTS:
            np.testing.assert_allclose(out[k], expected[k], rtol=1e-5, atol=1e-9, err_msg=f"{edit}: {k}")


def test_a_scheduled_input_the_fmu_has_moves_it_as_dynamics_does(fmu_path, tmp_path):
    """The FMU had five inputs and ignored a schedule's fouling, humidity or feed temperature without a word (the
    series parted from `dynamics` at 2 400 s); every schedulable input but the burner's fuel is one now."""
    from rotarydryer.thermal.schedule import OUTLET_NAMES

    sched = tmp_path / "s.csv"
    sched.write_text("time_s,fouling,feed_temperature\n0,0,28\n600,0,28\n600,0.2,10\n", encoding="utf-8")
    series, out = _dynamics_and_fmu(fmu_path, sched, 1800.0, tmp_path)
    for k in OUTPUTS:
        np.testing.assert_allclose(out[k], series[OUTLET_NAMES[k]], rtol=1e-6, atol=0, err_msg=k)
    assert abs(out["holdup"][-1] - out["holdup"][0]) > 1e-3 * out["holdup"][0]      # the fouling moved the plant


def test_signals_names_a_missing_start_value(tmp_path):
    """signals() raised a bare KeyError: 'feed_rate' for a schedule of an input its base did not give."""
    from rotarydryer.thermal.schedule import load_schedule

    path = tmp_path / "s.csv"
    path.write_text("time_s,feed_rate\n0,30\n600,35\n", encoding="utf-8")
    with pytest.raises(ValueError, match=r"signals\(\) needs the case's value of feed_rate \(scheduled\)"):
        load_schedule(path).signals({"gas_inlet_temperature": 500.0}, 600.0)


def test_a_case_given_as_text_rebuilds_its_network_as_a_file_does(tmp_path):
    """The FMU's stored case text made a Simulation of a case object, whose model was not rebuilt when a gas input
    moved what its network depends on (the trajectory forward step of a Song copy): after a +60 K step it settled at
    13.5 kg against 9.9 kg (found by a review)."""
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    case = tmp_path / "mysong.toml"
    assert CliRunner().invoke(app, ["new", "mysong", "--from", "song2003_ottawa", "--out", str(case)]).exit_code == 0
    by_path, by_text = DryerStepper(str(case)), DryerStepper(str(case), case_text=case.read_text())
    step = {"gas_inlet_temperature": by_path.inputs["gas_inlet_temperature"] + 60.0}
    start = by_path.outputs["holdup"]
    for _ in range(8):
        a, b = by_path.step(300.0, **step), by_text.step(300.0, **step)
    for k in OUTPUTS:
        assert b[k] == pytest.approx(a[k], rel=1e-9, abs=1e-12), k
    assert a["holdup"] < 0.9 * start         # the step moved the holdup (the rebuilt network's forward step)


def test_the_importers_overrides_are_not_undone_by_the_start_values(fmu_path):
    """The inputs' start values are the exported case's: with the importer's overrides of the feed temperature and
    gas humidity (now inputs too), the first step put the exported values back (the product 68.4 -> 61.1 degC in
    600 s; found by a review). An input left at its start value keeps the value of the case the FMU runs."""
    import json

    ov = {"operating.test": 4, "gas.inlet_humidity": 0.06, "operating.feed_temperature": 60.0}
    ref = DryerStepper(CASE, ov)
    e0, e1 = dict(ref.outputs), ref.step(600.0)
    out = fmpy.simulate_fmu(str(fmu_path), start_time=0.0, stop_time=600.0, step_size=600.0, output_interval=600.0,
                            start_values={"overrides": json.dumps(ov)}, output=list(OUTPUTS))
    for k in OUTPUTS:
        np.testing.assert_allclose(out[k], [e0[k], e1[k]], rtol=1e-6, err_msg=k)
