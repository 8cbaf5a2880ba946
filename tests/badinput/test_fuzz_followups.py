"""Inputs found by fuzzing the CLI that were accepted, ignored or answered with the wrong reason (each
failed before its fix): a schedule that is a folder, a free-text tracer baseline, a correlation's
hint that named a Python keyword, tracer records and lab series whose moments overflowed, keys a
configuration ignores silently, warnings printed twice, a pseudo file system read as a full disk,
and a closed output pipe reported as an error."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import warnings
from collections import namedtuple

import pytest

from rotarydryer import _io
from rotarydryer.cases import UnusedKeyWarning, load_case
from rotarydryer.correlations import mean_residence_time
from rotarydryer.correlations.residence_time import NonPositiveResidenceTime

from .conftest import assert_bad, run_cli

MRT = ["mrt", "--length", "3.05", "--diameter", "0.305", "--slope", "0.083", "--rpm", "5",
       "--gas-mass-flux", "0.5", "--solids-mass-flux", "0.7"]


def test_a_schedule_that_is_a_folder_is_named_so(tmp_path):
    (tmp_path / "s.toml").mkdir()
    res = run_cli(["dynamics", "ajayi2011_mmg", "--set", "operating.test=4", "--schedule", "s.toml"], cwd=tmp_path)
    assert_bad(res, "--schedule", "s.toml", "is a directory")


def test_a_tracer_baseline_is_one_of_the_methods(tmp_path):
    # a free-text field: 'abc' loaded on a case without a measured curve and ran
    res = run_cli(["simulate", "lee2008_invicta", "--set", "tracer.baseline=abc"], cwd=tmp_path)
    assert_bad(res, "tracer.baseline", "'abc'", "'leading'", "'linear'")
    assert load_case("lee2008_invicta", {"tracer.baseline": "linear"}).tracer.baseline == "linear"


def test_a_non_positive_residence_time_names_its_two_terms_not_a_python_keyword(tmp_path):
    res = run_cli([*MRT, "--particle-size", "1e-30"], cwd=tmp_path)
    # the other correlations answer: a per-method row, exit 0
    assert res.exit_code == 0, res.output
    assert "allow_nonpositive" not in res.output
    row = next(line for line in res.output.splitlines() if line.startswith("perry_green_1984"))
    assert "gas term" in row and "slope term" in row and "outside its range" in row
    # from Python the hint stays, and the error is still a ValueError
    with pytest.raises(NonPositiveResidenceTime, match="allow_nonpositive=True") as info:
        mean_residence_time(method="perry_green_1984", length=3.05, diameter=0.305, slope=0.083, rpm=5.0,
                            particle_size=1e-9, gas_mass_flux=5.0, solids_mass_flux=0.7, gas_flow="co-current")
    assert isinstance(info.value, ValueError) and "allow_nonpositive" not in info.value.summary


@pytest.mark.parametrize("rows, fragments", [
    ("0,0\n1e300,1e300\n2e300,2e300\n3e300,1e300\n4e300,0\n", ["time_s reaches 4e+300 s", "1e+09 s", "unit"]),
    ("0,0\n60,1e308\n120,1e308\n180,0\n240,0\n", ["1e+308", "rescale"]),
    ("0,0\n1e-12,1\n2e-12,2\n3e-12,1\n4e-12,0\n", ["spans 4e-12 s", "0.001 s"]),
], ids=["huge-times", "huge-signal", "picosecond-record"])
@pytest.mark.parametrize("command", ["rtd-moments", "rtd-fit"])
def test_a_tracer_record_outside_what_its_moments_hold_is_refused(tmp_path, command, rows, fragments):
    # before: overflow warnings then "(34, 'Numerical result out of range')", or a fit that "did not move", exit 0
    (tmp_path / "t.csv").write_text("time_s,signal\n" + rows, encoding="utf-8")
    res = run_cli([command, "t.csv"], cwd=tmp_path)
    assert_bad(res, "t.csv", *fragments)
    assert "overflow" not in res.output


def test_a_design_load_series_of_huge_numbers_is_refused(tmp_path):
    (tmp_path / "d.csv").write_text("loading_kg,FUF_area_cm2\n" + "".join(f"{k}e300,{min(k, 4)}e300\n"
                                                                           for k in range(1, 9)), encoding="utf-8")
    res = run_cli(["lab", "design-load", "d.csv"], cwd=tmp_path)
    assert_bad(res, "loading reaches 8e+300", "[0, 1e+100]")
    assert "overflow" not in res.output


@pytest.mark.parametrize("case, overrides, fragment", [
    ("lee2008_invicta", {"transport.moisture_scale": 2.0}, "transport.moisture_scale = 2 has no effect"),
    ("lee2008_invicta", {"geometry.design_load_factor": 1.5}, "geometry.design_load_factor = 1.5 has no effect"),
    ("lee2008_invicta", {"transport.kiln_law": "cascade", "transport.kiln_time": 5.0},
     "transport.kiln_time = 5 s has no effect"),
    ("song2003_ottawa", {"transport.backmix": 0.1}, "transport.backmix has no effect"),
    # found by a review of the API (2026-12-07): keys of the trajectory step and of Ajayi's shell loss
    ("lee2008_invicta", {"transport.step_factor": 2.0}, "transport.step_factor has no effect: it sets the trajectory"),
    ("lee2008_invicta", {"transport.curtain_velocity_ratio": 0.5, "transport.curtain_coefficient": 0.2},
     "transport.curtain_coefficient, transport.curtain_velocity_ratio have no effect"),
    ("ajayi2011_mmg", {"shell.loss_factor": 100.0}, "shell.loss_factor = 100 has no effect: it is theta_loss"),
])
def test_a_key_the_configuration_ignores_is_said_to_have_no_effect(case, overrides, fragment):
    with pytest.warns(UnusedKeyWarning, match=fragment.replace(".", r"\.")):
        load_case(case, overrides)


@pytest.mark.parametrize("case, overrides", [
    ("lee2008_invicta", {}), ("ajayi2011_mmg", {}), ("song2003_ottawa", {}),
    # used: the factor of Ajayi's regressions, the scale of the Eq. 3.1 profile
    ("ajayi2011_mmg", {"geometry.method": "ajayi2011_regressions", "geometry.design_load_factor": 1.5}),
    ("ajayi2011_mmg", {"transport.moisture_scale": 0.9}),
    ("ajayi2011_mmg", {"thermal.mode": "ajayi2011", "shell.loss_factor": 20.0}),
    ("song2003_ottawa", {"transport.step_factor": 2.0}),
])
def test_a_used_key_or_a_shipped_case_gets_no_such_warning(case, overrides):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load_case(case, overrides)
    assert not [w for w in caught if issubclass(w.category, UnusedKeyWarning)]


def test_the_same_warning_is_printed_once(tmp_path):
    # the shipped Song case's range warning came from both the transport and the heat-and-mass builds
    res = run_cli(["simulate", "song2003_ottawa"], cwd=tmp_path)
    assert res.exit_code == 0, res.output
    lines = [line for line in res.output.splitlines() if line.startswith("warning:")]
    assert lines and len(lines) == len(set(lines)), lines


def test_a_pseudo_file_system_is_not_a_full_disk(monkeypatch, tmp_path):
    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda d: usage(0, 0, 0))      # /proc, /sys
    _io.check_free_space(tmp_path, 1000)
    monkeypatch.setattr(shutil, "disk_usage", lambda d: usage(10 ** 9, 10 ** 9, 0))
    with pytest.raises(_io.OutputError, match="No space left"):
        _io.check_free_space(tmp_path, 1000)


@pytest.mark.skipif(os.name == "nt", reason="SIGPIPE is POSIX")
def test_a_closed_output_pipe_stops_quietly():
    # `rotarydryer simulate ... | head -1` printed "error: Broken pipe" and exited 2. The reader is closed
    # before the command writes anything (reading a first line and then closing raced the command's
    # remaining writes: on a loaded machine all of them could reach the pipe's buffer first, exit 0)
    proc = subprocess.Popen([sys.executable, "-m", "rotarydryer", "simulate", "lee2008_invicta"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, bufsize=0)
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 141, err
    assert "error" not in err and "Traceback" not in err and "Exception ignored" not in err, err


def test_a_rig_record_the_model_does_not_describe_is_refused_for_that_reason(tmp_path):
    # a ramp of 1 kg/s: the fit's standard error of the angle was 925 deg, refused as "repose_sd = 924.97 deg is
    # outside the allowed range", an option the user had not given
    rows = "".join(f"{k / 100:.2f},{min(max(k / 100 - 2.0, 0.0), 5.0):.4f}\n" for k in range(1000))
    (tmp_path / "rig.csv").write_text("time_s,cell1_kg\n" + rows, encoding="utf-8")
    res = run_cli(["lab", "rig", "rig.csv", "--rpm", "2", "--start-angle", "90", "--bulk-density", "1000"],
                  cwd=tmp_path)
    assert_bad(res, "rig.csv", "does not determine the repose angle", "--repose-angle and --repose-sd")
    assert "repose_sd =" not in res.output


@pytest.mark.parametrize("key, value, interval", [
    ("drum.n_flights", "0", "(allowed range [2, 1000])"),
    ("flight.s1", "-1", "(allowed range (0, inf) m)"),
    ("flight.alpha2", "200", "(allowed range (0, 180) deg)"),
])
def test_a_bounded_field_without_a_limits_entry_quotes_its_interval_and_unit(tmp_path, key, value, interval):
    # pydantic's "Input should be greater than 0" alone: no interval, no unit
    assert_bad(run_cli(["simulate", "lee2008_invicta", "--set", f"{key}={value}"], cwd=tmp_path), key, interval)


# ---- a second round of fuzzing (calibrate, report, balance, sensitivity, dem, audit, fit, validate, new, ...)

TRACER = "time_s,signal\n" + "".join(f"{60 * k},{v}\n" for k, v in enumerate((0, 1, 4, 6, 4, 2, 1, 0.5, 0)))


@pytest.mark.parametrize("args, fragments", [
    # an empty value was read as the case's default; a repeated key's last value won
    (["rtd", "lee2008_invicta", "--set", "operating.rpm="], ["--set operating.rpm", "empty value", "leave out --set operating.rpm"]),
    (["rtd", "lee2008_invicta", "--set", "operating.rpm=4", "--set", "operating.rpm=5"],
     ["--set operating.rpm is given twice", "4 and 5"]),
    # the data of a repeated response counted twice (an interval narrower by sqrt(2)); a sigma and a test ignored
    (["calibrate", "ajayi2011_mmg", "-p", "transport.dispersion", "--tests", "4", "-r", "tracer", "-r", "tracer",
      "-q"], ["--response tracer is given twice"]),
    (["calibrate", "ajayi2011_mmg", "-p", "transport.dispersion", "--tests", "4", "-r", "tracer", "--sigma", "mrt=1",
      "-q"], ["--sigma mrt", "not a fitted response"]),
    (["calibrate", "ajayi2011_mmg", "-p", "transport.dispersion", "--tests", "4", "-r", "tracer", "--set",
      "operating.test=5", "-q"], ["--set operating.test", "--tests"]),
    (["calibrate", "ajayi2011_mmg", "-p", "operating.test", "--tests", "4", "-r", "tracer", "-q"],
     ["operating.test", "whole numbers"]),
    (["calibrate", "ajayi2011_mmg", "-p", "tests.*.gas_flow", "--tests", "4", "-r", "tracer", "-q"],
     ["tests.4.gas_flow", "heat-and-mass key", "thermal response"]),
    # a drum preset took any --set, an unknown key too
    (["report", "invicta", "--set", "nokey.zz=abc", "-o", "r.html"], ["--set", "drum preset"]),
    # the measured outlet was ignored for the solved one; the balance's own terms named, not the options
    (["balance", "--ajayi-test", "6", "--gas-flow", "16.25", "--gas-out", "100"], ["--gas-out", "--gas-flow",
                                                                                  "give one"]),
    (["balance", "--ajayi-test", "6", "--feed", "1e6"], ["no energy balance", "--feed"]),
    (["balance", "--ajayi-test", "6", "--gas-flow", "1e6"], ["--gas-flow", "(0, 1000] kg/s"]),
    (["balance", "--ajayi-test", "7"], ["--ajayi-test = 7", "1-6"]),
    # the case's options without a case
    (["dem", "export", "s", "--section", "B", "--radius", "0.2", "--n-flights", "10", "--s1", "0.05", "--s2", "0.05",
      "--rpm", "6.7"], ["--section applies to --case"]),
    (["dem", "export", "s", "--radius", "0.2", "--n-flights", "10", "--s1", "0.05", "--s2", "0.05", "--rpm", "6.7",
      "--alpha1", "0"], ["--alpha1", "(0, 180) deg"]),
    # no what-if at all
    (["audit", "ajayi2011_mmg", "--recycle", ","], ["--recycle", "no value"]),
    (["audit", "ajayi2011_mmg", "--hold-moisture"], ["--hold-moisture", "--recycle"]),
    # a feed the coupled solver cannot resolve: exit 1 after 8-25 s before
    (["simulate", "ajayi2011_mmg", "--set", "operating.feed_rate=1e-30"], ["operating.feed_rate = 1e-30 kg/s",
                                                                            "of gas.flow", "at least"]),
    # an impossible dryer was 48 failed items, exit 1
    (["validate", "lee2008_invicta", "--set", "drum.radius=1e-30", "-q"], ["flight.s1", "drum.radius"]),
    # the internal parameter's name, not the option's
    (["schema", "--kind", "foo"], ["--kind = 'foo'"]),
    (["rtd", "lee2008_invicta", "--method", "foo"], ["--method = 'foo'"]),
    (["report", "lee2008_invicta", "-o", "r.html", "--repose-angle", "90"], ["--repose-angle = 90 deg"]),
], ids=lambda v: v[0] + "-" + "-".join(a.lstrip("-") for a in v[1:4]) if isinstance(v, list) and v and
    isinstance(v[0], str) and not v[0].startswith(("--", "tests")) else None)
def test_second_round(tmp_path, args, fragments):
    assert_bad(run_cli(args, cwd=tmp_path), *fragments)
    assert not (tmp_path / "r.html").exists() and not (tmp_path / "s").exists()


@pytest.mark.parametrize("text, fragments", [
    (TRACER.replace("time_s,signal", "time_s,signal,signal").replace("\n", ",1\n").replace("signal,1\n", "signal\n"),
     ["'signal' appears twice"]),
    (TRACER.replace("240,4\n", "240,4,7\n"), ["line 6", "expected 2 columns", "got 3"]),
    ("time_s,signal\n" + "".join(f"{60 * k},{v}e-301\n" for k, v in enumerate((0, 1, 4, 6, 4, 2, 1, 0))),
     ["the signal peaks at 6e-301", "[1e-100, 1e+100]"]),
    ("time_s,signal\n" + "".join(f"{60 * k},{v}\n" for k, v in enumerate((0, 0, 0, 5, 0, 0, 0, 0))),
     ["line 5", "the only non-zero signal"]),
], ids=["duplicated-column", "ragged-row", "vanishing-signal", "one-spike"])
def test_a_malformed_tracer_file_is_refused_naming_it(tmp_path, text, fragments):
    # each was fitted (exit 0): one of two signal columns, an extra value dropped, R^2 nan, an infinite error
    (tmp_path / "t.csv").write_text(text, encoding="utf-8")
    assert_bad(run_cli(["rtd-moments", "t.csv"], cwd=tmp_path), "t.csv", *fragments)


def test_a_sensitivity_of_outputs_the_case_does_not_compute_is_refused(tmp_path):
    res = run_cli(["sensitivity", "lee2008_invicta", "--set", "thermal.enabled=false", "--param", "operating.rpm=2,4",
                   "--output", "product_moisture_kg_kg", "--samples", "8", "-q"], cwd=tmp_path)
    assert_bad(res, "product_moisture_kg_kg", "not computed by this case")


def test_new_suggests_a_toml_beside_the_given_path(tmp_path):
    res = run_cli(["new", "x3", "--out", "x3.json"], cwd=tmp_path)
    assert_bad(res, "'x3.toml'")
    assert "x3.json/" not in res.output


# ---- the review of the above: what the new checks must still accept

def test_a_spreadsheets_empty_trailing_columns_still_load(tmp_path):
    (tmp_path / "t.csv").write_text(TRACER.replace("\n", ",,\n"), encoding="utf-8")
    res = run_cli(["rtd-moments", "t.csv"], cwd=tmp_path)
    assert res.exit_code == 0, res.output


def test_a_straight_two_section_flight_still_exports(tmp_path):
    res = run_cli(["dem", "export", "s", "--radius", "0.2", "--n-flights", "10", "--s1", "0.05", "--s2", "0", "--rpm",
                   "6.7", "--alpha2", "180"], cwd=tmp_path)
    assert res.exit_code == 0, res.output


def test_the_predictive_law_uses_the_moisture_scale_whatever_the_model():
    # the predictive beds' velocities move with it: no "has no effect"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load_case("ajayi2011_mmg", {"transport.parameter_source": "predictive", "transport.model": "lee2008",
                                    "transport.moisture_profile": "exponential", "transport.solids_velocity": "none",
                                    "transport.dispersion": "none", "transport.moisture_scale": 0.9})
    assert not [w for w in caught if issubclass(w.category, UnusedKeyWarning)]


def test_reversed_times_are_named_as_such_not_as_a_short_record():
    from rotarydryer.rtd import rtd_moments

    with pytest.raises(ValueError, match="strictly increasing"):
        rtd_moments([40.0, 30.0, 20.0, 10.0, 0.0], [0.0, 1.0, 2.0, 1.0, 0.0])


def test_gas_keys_move_the_transport_only_through_the_trajectory_step():
    from rotarydryer.cases.build import any_trajectory

    assert any_trajectory(load_case("song2003_ottawa"))        # calibrate -p gas.flow -r mrt: a valid fit there
    assert not any_trajectory(load_case("ajayi2011_mmg", {"operating.test": 4}))


# ---- a third round (the leftovers of the second)

def test_a_value_the_schema_refuses_gets_its_refusal_alone(tmp_path):
    # `--set transport.n_cells=2.5`: the calibration's "was fitted with N = 35" warning came before the refusal
    res = run_cli(["rtd", "lee2008_invicta", "--set", "transport.n_cells=2.5"], cwd=tmp_path)
    assert_bad(res, "transport.n_cells", "valid integer")
    assert "calibration" not in res.output and "warning" not in res.output
    # a valid value the calibration was not fitted with still warns, once the case has validated
    with pytest.warns(UserWarning, match="was fitted with transport.n_cells = 35"):
        load_case("lee2008_invicta", {"transport.n_cells": 30})


@pytest.mark.parametrize("args", [
    ["simulate", "lee2008_invicta", "--out", ""],
    ["simulate", "lee2008_invicta", "--out="],
    ["simulate", "lee2008_invicta", "--diagnostics", " "],
    ["lab", "drying", "curves.csv", "--out", ""],
])
def test_an_empty_path_option_is_refused(tmp_path, args):
    # Path('') is the current directory: the outputs landed there unasked, exit 0
    option = next(a for a in args if a.startswith("--")).rstrip("=")
    assert_bad(run_cli(args, cwd=tmp_path), option, "is empty")
    assert not list(tmp_path.iterdir())


def test_a_huge_sample_count_is_echoed_as_given(tmp_path):
    res = run_cli(["sensitivity", "lee2008_invicta", "--param", "operating.rpm=2,4", "--samples", "1e30"], cwd=tmp_path)
    assert_bad(res, "--samples = 1e30", "[2, 65536]")


def _fake_liggghts_deck(tmp_path, monkeypatch, script: str):
    """A deck folder (100 steps) and a stand-in LIGGGHTS that runs the shell ``script``."""
    import json

    fake = tmp_path / "liggghts"
    fake.write_text("#!/bin/sh\n" + script)
    fake.chmod(0o755)
    monkeypatch.setenv("ROTARYDRYER_LIGGGHTS", str(fake))
    deck = tmp_path / "deck"
    deck.mkdir()
    (deck / "in.drum").write_text("# a deck\n")
    (deck / "deck.json").write_text(json.dumps({"derived": {"steps": {"total": 100}}}))
    return deck


def test_a_silent_dem_run_stops_at_its_timeout(tmp_path, monkeypatch):
    # the timeout was checked per printed line: a LIGGGHTS that printed nothing ran on past it
    import time

    from rotarydryer.dem.run import LiggghtsFailed, run_deck

    deck = _fake_liggghts_deck(tmp_path, monkeypatch, "exec sleep 30\n")
    t0 = time.perf_counter()
    with pytest.raises(LiggghtsFailed, match="did not finish within 0.5 s"):
        run_deck(deck, progress=False, timeout=0.5)
    assert time.perf_counter() - t0 < 10.0


def test_a_dem_run_whose_progress_cannot_be_shown_stops_instead_of_hanging(tmp_path, monkeypatch):
    # the reader of LIGGGHTS' screen died on a closed stderr (`... 2>&1 >/dev/null | head -1`): nobody emptied the
    # pipe, LIGGGHTS blocked on its next line and the run waited for ever (found in review)
    import time

    from rotarydryer.dem.run import run_deck

    deck = _fake_liggghts_deck(tmp_path, monkeypatch,
                               "i=0\nwhile [ $i -lt 20000 ]; do echo \"  $i 0 1.0\"; i=$((i+1)); done\nexec sleep 30\n")

    class Closed:
        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")

        def flush(self):
            pass

    t0 = time.perf_counter()
    with pytest.raises(BrokenPipeError):
        run_deck(deck, progress=True, stream=Closed())
    assert time.perf_counter() - t0 < 20.0


@pytest.mark.parametrize("args, fragment", [
    (["simulate", "lee2008_invicta", "--out", "", "--"], "--out is empty"),        # a "--" skipped the check
    (["dem", "export", "", "--case", "lee2008_invicta", "--section", "dryer", "--diameter", "0.01"], "OUT is empty"),
])
def test_an_empty_path_is_refused_wherever_it_is_given(tmp_path, args, fragment):
    assert_bad(run_cli(args, cwd=tmp_path), fragment)
    assert not list(tmp_path.iterdir())


def test_warnings_that_differ_in_a_name_are_not_merged(capsys):
    # "section zone1 ..." and "section zone2 ..." were counted as one warning with other values (found in review)
    from rotarydryer.cli import _warning_printer

    show = _warning_printer()
    for text in ("shell of section zone1 at 612 degC", "shell of section zone2 at 640 degC",
                 "shell of section zone1 at 650 degC"):
        show(text, UserWarning, "x.py", 1)
    show.summary()
    err = capsys.readouterr().err
    assert "zone1 at 612" in err and "zone2 at 640" in err and "zone1 at 650" not in err
    assert "warning: 1 more like 'shell of section zone1 at 612 degC' with other values (not shown)" in err


def test_balance_refuses_a_product_hotter_than_the_gas(tmp_path):
    res = run_cli(["balance", "--material", "raw_sugar_lee2008", "--gas-in", "415.709", "--gas-out", "370.24", "--feed",
                   "0.756", "--moisture-in", "0.021", "--moisture-out", "0.0005", "--product-temperature", "590"],
                  cwd=tmp_path)
    assert_bad(res, "--product-temperature = 590", "above --gas-in = 415.709")
