"""Bad command-line input (issue 13): balance, mrt, sweep, schema/new, report, simulate/rtd
overrides and fit options. Each case: exit 2, an ``error:`` line naming the option or key and the
value, no traceback, nothing written in the working folder."""

from __future__ import annotations

import pytest

from .conftest import assert_bad, run_cli, snapshot

B = ["balance", "--gas-in", "500", "--gas-out", "130", "--feed", "40", "--moisture-in", "0.15",
     "--moisture-out", "0.12", "--product-temperature", "46"]


def _sub(argv, opt, value):
    argv = list(argv)
    argv[argv.index(opt) + 1] = value
    return argv


BALANCE = [
    ("gas-in-nan", _sub(B, "--gas-in", "nan"), ["--gas-in", "nan"]),
    ("gas-in-too-hot", _sub(B, "--gas-in", "900"), ["--gas-in", "900"]),
    ("gas-out-above-in", _sub(B, "--gas-in", "100"), ["--gas-out", "130", "--gas-in"]),
    ("feed-negative", _sub(B, "--feed", "-1"), ["--feed", "-1"]),
    ("feed-zero", _sub(B, "--feed", "0"), ["--feed", "0"]),
    ("feed-inf", _sub(B, "--feed", "inf"), ["--feed", "inf"]),
    ("moisture-in-above-1", _sub(B, "--moisture-in", "1.5"), ["--moisture-in", "1.5"]),
    ("moisture-out-above-in", _sub(B, "--moisture-out", "0.2"), ["--moisture-out", "0.2", "--moisture-in"]),
    ("moisture-out-negative", _sub(B, "--moisture-out", "-0.1"), ["--moisture-out", "-0.1"]),
    ("product-temperature-huge", _sub(B, "--product-temperature", "1e300"), ["--product-temperature", "1e+300"]),
    ("gas-flow-zero", B + ["--gas-flow", "0"], ["--gas-flow", "0"]),
    ("gas-flow-nan", B + ["--gas-flow", "nan"], ["--gas-flow", "nan"]),
    ("shell-loss-negative", B + ["--shell-loss", "-5"], ["--shell-loss", "-5"]),
    ("shell-loss-inf", B + ["--shell-loss", "inf"], ["--shell-loss", "inf"]),
    ("feed-temperature-below-absolute", B + ["--feed-temperature", "-300"], ["--feed-temperature", "-300"]),
    ("gas-humidity-5", B + ["--gas-humidity", "5"], ["--gas-humidity", "5"]),
    ("ajayi-test-9", ["balance", "--ajayi-test", "9"], ["test", "9"]),
    ("missing-values", ["balance", "--gas-in", "500"], ["missing", "--feed"]),
    ("not-a-number", _sub(B, "--feed", "abc"), ["--feed", "valid number"]),
]

MRT = ["mrt", "--length", "12", "--diameter", "2", "--slope", "0.05", "--rpm", "3"]
CORRELATIONS = [
    ("length-negative", _sub(MRT, "--length", "-1"), ["length"]),
    ("diameter-zero", _sub(MRT, "--diameter", "0"), ["diameter"]),
    ("rpm-nan", _sub(MRT, "--rpm", "nan"), ["rpm", "nan"]),
    ("slope-inf", _sub(MRT, "--slope", "inf"), ["slope"]),
    ("gas-flow-word", MRT + ["--gas-flow", "sideways"], ["sideways"]),
    ("method-unknown", MRT + ["--method", "nobody1999"], ["nobody1999"]),
    ("particle-size-negative", MRT + ["--particle-size", "-1e-3", "--gas-mass-flux", "1", "--solids-mass-flux", "1",
                                         "--method", "friedman_marshall_1949"],
     ["particle"]),
]

FAST = ["--set", "thermal.enabled=false", "--no-rtd"]
SWEEP = [
    ("grid-no-equals", ["sweep", "song2003_ottawa", "--grid", "operating.rpm"], ["--grid", "operating.rpm"]),
    ("grid-no-values", ["sweep", "song2003_ottawa", "--grid", "operating.rpm=,"], ["--grid", "no values"]),
    ("grid-unknown-key", ["sweep", "song2003_ottawa", "--grid", "nokey=1,2"], ["nokey"]),
    ("grid-too-many-points", ["sweep", "song2003_ottawa", "--grid", "operating.rpm=" + ",".join(map(str, range(1, 201))),
                              "--grid", "operating.feed_rate=" + ",".join(f"{x / 100:g}" for x in range(1, 101))],
     ["20000 runs", "10000"]),
    ("workers-negative", ["sweep", "song2003_ottawa", "--workers", "-1", "--grid", "operating.rpm=3"],
     ["workers", "-1"]),
    ("list-missing", ["sweep", "song2003_ottawa", "--list", "/nonexistent/runs.csv"], ["--list", "runs.csv"]),
    ("list-is-a-folder", ["sweep", "song2003_ottawa", "--list", "/etc"], ["--list", "/etc"]),
    ("grid-and-list", ["sweep", "song2003_ottawa", "--grid", "operating.rpm=3", "--list", "x.csv"],
     ["--grid or --list"]),
    ("nothing-to-run", ["sweep", "song2003_ottawa"], ["nothing to run"]),
    ("grid-bad-value", ["sweep", "song2003_ottawa", "--grid", "operating.rpm=abc", *FAST], ["operating.rpm", "abc"]),
    ("unknown-case", ["sweep", "no_such_case", "--grid", "operating.rpm=3"], ["no_such_case"]),
]

SCHEMA_NEW = [
    ("schema-kind", ["schema", "--kind", "bogus"], ["kind", "bogus"]),
    ("new-path-name", ["new", "../evil"], ["case_name", "../evil"]),
    ("new-slash-name", ["new", "a/b"], ["case_name", "a/b"]),
    ("new-unknown-base", ["new", "x", "--from", "nope"], ["--from", "nope"]),
    ("new-empty-name", ["new", ""], ["case_name"]),
]

REPORT = [
    ("unknown-source", ["report", "nonexistent_case"], ["nonexistent_case"]),
    ("system-file", ["report", "/etc/passwd"], ["/etc/passwd"]),
    ("repose-nan", ["report", "invicta", "--repose-angle", "nan"], ["--repose-angle", "nan"]),
    ("repose-95", ["report", "invicta", "--repose-angle", "95"], ["--repose-angle", "95"]),
    ("save-a-drum", ["report", "invicta", "--save", "x.nc"], ["--save", "invicta"]),
    ("bad-set", ["report", "song2003_ottawa", "--set", "operating.rpm=-3"], ["operating.rpm", "-3"]),
]

SIMULATE = [
    ("unknown-case", ["simulate", "nope"], ["nope"]),
    ("system-file", ["simulate", "/etc/passwd"], ["/etc/passwd"]),
    ("device", ["simulate", "/dev/null"], ["/dev/null"]),
    ("set-no-equals", ["simulate", "song2003_ottawa", "--set", "noequals"], ["--set", "noequals"]),
    ("set-unknown-key", ["simulate", "song2003_ottawa", "--set", "operating.nope=1"], ["operating.nope"]),
    ("rpm-nan", ["simulate", "song2003_ottawa", "--set", "operating.rpm=nan"], ["operating.rpm", "nan"]),
    ("rpm-inf", ["simulate", "song2003_ottawa", "--set", "operating.rpm=inf"], ["operating.rpm", "inf"]),
    ("radius-negative", ["simulate", "song2003_ottawa", "--set", "drum.radius=-1"], ["drum.radius", "-1"]),
    ("cells-zero", ["simulate", "lee2008_invicta", "--set", "transport.n_cells=0"], ["transport.n_cells", "0"]),
    ("slope-45", ["simulate", "song2003_ottawa", "--set", "drum.slope=45"], ["drum.slope", "45"]),
    ("gas-direction", ["simulate", "song2003_ottawa", "--set", "gas.direction=up"], ["gas.direction", "up"]),
    ("material-unknown", ["simulate", "song2003_ottawa", "--set", "material.name=cheese"], ["material", "cheese"]),
    ("burner-share", ["simulate", "ajayi2011_mmg", "--set", "thermal.burner.combustion_air_share=2"],
     ["combustion_air_share", "2"]),
    ("test-7", ["simulate", "ajayi2011_mmg", "--set", "operating.test=7"], ["test", "7"]),
    ("rtd-method", ["rtd", "song2003_ottawa", "--method", "bogus"], ["method", "bogus"]),
    ("rtd-dt-too-fine", ["rtd", "lee2008_invicta", "--set", "tracer.dt=1e-6"], ["tracer.dt"]),
    ("rtd-t-end-negative", ["rtd", "lee2008_invicta", "--set", "tracer.t_end=-5"], ["tracer.t_end", "-5"]),
]

FIT = [
    ("data-missing", ["fit", "lee2008_invicta", "nope.csv", "-p", "transport.backmix"], ["nope.csv"]),
    ("param-unknown", ["fit", "lee2008_invicta", "lee2008_invicta", "-p", "nokey"], ["nokey"]),
    ("param-not-numeric", ["fit", "lee2008_invicta", "lee2008_invicta", "-p", "transport.loading"],
     ["transport.loading"]),
    ("method", ["fit", "lee2008_invicta", "lee2008_invicta", "-p", "transport.backmix", "--method", "xx"],
     ["method", "xx"]),
    ("scale", ["fit", "lee2008_invicta", "lee2008_invicta", "-p", "transport.backmix", "--scale", "xx"],
     ["scale", "xx"]),
    ("starts-zero", ["fit", "lee2008_invicta", "lee2008_invicta", "-p", "transport.backmix", "--starts", "0"],
     ["starts", "0"]),
]

ALL = ([("balance-" + i, a, f) for i, a, f in BALANCE] + [("mrt-" + i, a, f) for i, a, f in CORRELATIONS]
       + [("sweep-" + i, a, f) for i, a, f in SWEEP] + SCHEMA_NEW + [("report-" + i, a, f) for i, a, f in REPORT]
       + [("simulate-" + i, a, f) for i, a, f in SIMULATE] + [("fit-" + i, a, f) for i, a, f in FIT])


@pytest.mark.parametrize("argv,fragments", [pytest.param(a, f, id=i) for i, a, f in ALL])
def test_bad_cli_input(argv, fragments, workdir):
    before = snapshot(workdir)
    res = run_cli(argv, cwd=workdir)
    assert_bad(res, *fragments)
    assert snapshot(workdir) == before


@pytest.mark.parametrize("args,line", [
    # the type checker's "Input should be a valid integer, unable to parse string as an integer" in plain words
    (["sweep", "lee2008_invicta", "--workers", "abc"],
     "error: Invalid value for '--workers': not a valid integer (a whole number) (got 'abc'); "
     "see 'rotarydryer sweep --help'"),
    (["lab", "drying", "x.csv", "--equilibrium-moisture=abc"],
     "error: Invalid value for '--equilibrium-moisture': not a valid number (got 'abc'); "
     "see 'rotarydryer lab drying --help'"),
    (["simulate", "lee2008_invicta", "--set"],
     "error: Option '--set' requires an argument; see 'rotarydryer simulate --help'"),
    (["simulate"], "error: Missing argument 'case'; see 'rotarydryer simulate --help'"),
    (["bogus"], "error: No such command 'bogus'; see 'rotarydryer --help'"),
])
def test_usage_errors_are_one_line_naming_the_option_and_value(args, line):
    """click's usage errors were three lines starting with "Usage: ...", and a bad value was not shown (found by
    fuzzing): one ``error:`` line naming the option and the value, exit code 2."""
    res = run_cli(args)
    assert res.exit_code == 2
    assert res.output.strip() == line


@pytest.mark.parametrize("option, value, fragment", [
    ("--solids-mass-flux", "nan", "not a finite number"), ("--solids-mass-flux", "-1", "(0, inf) kg/(m^2 s)"),
    ("--solids-mass-flux", "0", "(0, inf) kg/(m^2 s)"), ("--repose-angle", "nan", "not a finite number"),
    ("--gas-mass-flux", "inf", "not a finite number"), ("--rpm", "0", "(0, inf) rev/min"),
])
def test_mrt_refuses_a_bad_number_even_where_other_methods_do_not_use_it(option, value, fragment):
    """A NaN or negative solids flux was one method's table row and the command exited 0 with the rest (fuzzing)."""
    args = {"--length": "3.05", "--diameter": "0.305", "--slope": "0.083", "--rpm": "5", "--particle-size": "444e-6",
            "--gas-mass-flux": "0.5", "--solids-mass-flux": "0.7", option: value}
    assert_bad(run_cli(["mrt", *[x for kv in args.items() for x in kv]]), option, fragment)
