"""Issue 17: bad input to ``rotarydryer design`` and ``rotarydryer control`` (exit 2, ``error:``
naming the option or constraint, no traceback, nothing written) and the unstable-controller warning."""

from __future__ import annotations

import pytest

from .conftest import assert_bad, run_cli, snapshot


def _refused(args, workdir, *fragments):
    before = snapshot(workdir)
    res = run_cli(args, cwd=workdir)
    assert_bad(res, *fragments)
    assert snapshot(workdir) == before, "a refused command wrote to the working folder"
    return res.output


@pytest.mark.parametrize("args,fragments", [
    (["--duty", "raw_sugar", "--objective", "beauty"], ["--objective", "beauty", "volume"]),
    (["--duty", "raw_sugar", "--ld-min", "8", "--ld-max", "4"], ["--ld-max = 4", "allowed"]),
    (["--duty", "raw_sugar", "--moisture-out", "0.02"], ["--moisture-out = 0.02", "must be below --moisture-in = 0.01"]),
    (["--duty", "coffee"], ["--duty", "coffee", "raw_sugar"]),
    (["--material", "raw_sugar_lee2008", "--feed", "20"], ["missing", "--moisture-in", "--gas-in"]),
    (["--duty", "raw_sugar", "--speed-fraction", "1.5"], ["--speed-fraction = 1.5", "allowed"]),
    (["--check", "my_plant"], ["--check", "my_plant", "ajayi2011_mmg"]),
    (["--duty", "raw_sugar", "--out", "afile.txt/sub"], ["--out", "is a file"]),
    # both the gas flow and the transfer units: --ntu was ignored (found by fuzzing)
    (["--duty", "raw_sugar", "--gas-flow", "20", "--ntu", "2"], ["--gas-flow = 20 kg/s and --ntu = 2: give one"]),
    # --set without --check: ignored, exit 0 (found by fuzzing)
    (["--duty", "raw_sugar", "--set", "drum.radius=-1"], ["--set drum.radius=-1 needs --check plant"]),
])
def test_design_bad_options(args, fragments, workdir):
    if "afile.txt/sub" in args:
        (workdir / "afile.txt").write_text("x")
    _refused(["design", *args], workdir, *fragments)


def test_design_infeasible_duty_names_blocking_constraint(workdir):
    """No drum of at most 1.5 m carries 22 kg/s of air below the sugar's terminal velocity."""
    _refused(["design", "--duty", "raw_sugar", "--d-max", "1.5", "--no-verify"], workdir,
             "infeasible duty", "blocking constraint 'gas entrainment'", "--entrainment-fraction")


@pytest.mark.parametrize("args,fragments", [
    (["--scenario", "earthquake"], ["--scenario", "earthquake", "feed_moisture_step"]),
    (["--sample-time", "0"], ["--sample-time = 0", "allowed"]),
    (["--measured", "colour"], ["--measured", "colour", "product_moisture"]),
    (["--feedforward", "psychic"], ["--feedforward", "psychic", "model"]),
    (["--magnitude", "0.5", "--scenario", "fouling_ramp", "--gas-t-max", "700"], ["--gas-t-max = 700", "600"]),
    (["--step-time", "9000", "--duration", "3600"], ["--step-time = 9000", "allowed"]),
    (["--magnitude", "0.6"], ["--magnitude = 0.6", "feed too wet", "at most +0.204"]),   # named by its option (fuzzing)
    (["--tolerance", "0"], ["--tolerance = 0", "allowed"]),
    (["--product-moisture-max", "1.5"], ["--product-moisture-max = 1.5", "allowed"]),
    (["--product-temperature-band", "50"], ["--product-temperature-band = '50'", "LOW,HIGH"]),
    (["--product-temperature-band", "50,40"], ["--product-temperature-band = 50,40", "low end"]),
])
def test_control_bad_options(args, fragments, workdir):
    _refused(["control", "ajayi2011_mmg", "--set", "operating.test=4", *args], workdir, *fragments)


def test_control_schedule_with_scenario_options_is_refused(workdir):
    """--schedule with --scenario/--magnitude/--step-time ran the schedule and ignored the three (fuzzing)."""
    (workdir / "s.toml").write_text('[[step]]\ninput = "feed_moisture"\nat_s = 600\nvalue = 0.17\n')
    _refused(["control", "ajayi2011_mmg", "--set", "operating.test=4", "--schedule", "s.toml", "--magnitude", "0.5"],
             workdir, "--schedule and --magnitude: the schedule is the disturbance; give one or the other")


def test_control_unstable_gain_is_warned(workdir):
    """A hand-set gain far beyond the FOPDT+PI stability limit: the run goes on, with a warning."""
    res = run_cli(["control", "ajayi2011_mmg", "--set", "operating.test=4", "--kc", "40", "--duration", "240",
                   "--sample-time", "120", "--no-open-loop", "--feedforward", "off"], cwd=workdir)
    assert res.exit_code == 0, res.output
    assert "warning:" in res.output and "unstable loop" in res.output and "stability limit" in res.output


@pytest.mark.parametrize("args,fragments", [
    (["ajayi2011_mmg", "-o", "dryer.txt"], ["-o", "dryer.txt", ".fmu"]),
    (["no_such_case", "-o", "dryer.fmu"], ["no_such_case"]),
    (["ajayi2011_mmg", "--set", "operating.rpm=-3", "-o", "dryer.fmu"], ["operating.rpm"]),
])
def test_fmu_bad_options(args, fragments, workdir):
    _refused(["fmu", *args], workdir, *fragments)
