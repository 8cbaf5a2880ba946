"""The DEM batch's options (`python -m rotarydryer.dem.calibrate`) are checked as every many-run command's: one line,
exit code 2, before anything runs (found by an acceptance check: --jobs 0, -1 or 1000 and --only with a misspelt run
ran without a word, "--scheduler nonsense" was refused after 21 s, a usage error printed argparse's usage block)."""

from __future__ import annotations

import pytest

from rotarydryer.dem import calibrate


@pytest.mark.parametrize("argv, fragment", [
    (["--jobs", "-1"], "--jobs = -1 is outside the allowed range [0, inf)"),
    (["--jobs", "1.5"], "argument --jobs: invalid int value: '1.5'"),
    (["--only", "nosuchrun"], "--only nosuchrun: no such run of the calibration campaign; runs: c1_A_d020_over_lowFr"),
    (["--polygon", "--only", "c1_A_d020_over_lowFr"], "no such run of the polygon campaign"),
    (["--only"], "--only: no run named"),
    (["--scheduler", "nonsense"], "--scheduler = 'nonsense' is not a scheduler address"),
    (["--scheduler", "tcp://127.0.0.1:1", "--cluster", "local:2"], "give one, not both"),
    (["--cluster", "local:0"], "--cluster = 'local:0'"),
    (["--np", "0"], "--np = 0 is outside the allowed range [1, 256]"),
    (["--bogus"], "unrecognized arguments: --bogus"),
])
def test_a_bad_option_is_one_line_and_exit_2(argv, fragment, capsys, tmp_path):
    assert calibrate.main([*argv, "--work", str(tmp_path / "w")]) == 2
    out, err = capsys.readouterr()
    assert err.startswith("error: ") and fragment in err and err.count("\n") == 1, err
    assert "usage:" not in err and out == ""
    assert not (tmp_path / "w").exists()        # nothing exported


def test_export_only_says_each_warning_once_on_one_line(capsys, tmp_path):
    assert calibrate.main(["--export-only", "--only", "c1_A_d020_over_lowFr", "c1_A_d020_over_lowFr",
                           "--work", str(tmp_path)]) == 0
    err = capsys.readouterr().err
    assert all(line.startswith("warning: ") for line in err.splitlines()), err
    assert len(set(err.splitlines())) == len(err.splitlines())
    assert (tmp_path / "c1_A_d020_over_lowFr").is_dir()
