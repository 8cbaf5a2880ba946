"""Bad input of ``rotarydryer sensitivity`` (issue 16): exit 2, an ``error:`` line naming the
option or key and the value, no traceback, nothing written in the working folder."""

from __future__ import annotations

import pytest

from .conftest import assert_bad, run_cli, snapshot

pytest.importorskip("SALib")

S = ["sensitivity", "song2003_ottawa", "--set", "thermal.enabled=false"]
P = ["--param", "operating.rpm=3,5"]

CASES = [
    ("unknown-key", S + ["--param", "operating.nokey=1,2"], ["nokey"]),
    ("low-equals-high", S + ["--param", "operating.rpm=4,4"], ["--param", "operating.rpm", "LOW = 4", "HIGH = 4"]),
    ("low-above-high", S + ["--param", "operating.rpm=5,3"], ["operating.rpm", "LOW = 5", "below"]),
    ("non-numeric", S + ["--param", "operating.rpm=abc,4"], ["operating.rpm", "'abc'", "not a number"]),
    ("nan-bound", S + ["--param", "operating.rpm=nan,4"], ["operating.rpm", "nan", "finite"]),
    ("no-equals", S + ["--param", "operating.rpm"], ["--param", "KEY=LOW,HIGH"]),
    ("three-values", S + ["--param", "operating.rpm=1,2,3"], ["--param", "two numbers"]),
    ("no-param", S, ["--param", "at least one"]),
    ("duplicate-key", S + P + P, ["operating.rpm", "twice"]),
    ("samples-zero", S + P + ["--samples", "0"], ["--samples", "0", "[2, 65536]"]),
    ("samples-one", S + P + ["--samples", "1"], ["--samples", "1", "[2, 65536]", "at least 2 blocks"]),
    ("samples-negative", S + P + ["--samples", "-5"], ["--samples", "-5"]),
    ("samples-huge", S + P + ["--samples", "1000000"], ["--samples", "1000000", "65536"]),
    ("too-many-runs", S + [a for i in range(20) for a in ("--param", f"k{i}=1,2")] + ["--samples", "65536"],
     ["--samples", "65536", "1441792 runs", "1000000"]),
    ("samples-not-integer", S + P + ["--samples", "abc"], ["--samples", "abc"]),
    ("too-many-params", S + [a for i in range(21) for a in ("--param", f"k{i}=1,2")], ["21", "--param", "20"]),
    ("unknown-case", ["sensitivity", "no_such_case"] + P, ["no_such_case"]),
    ("range-refused-by-case", S + ["--param", "operating.rpm=-3,5"], ["operating.rpm", "-3"]),
    ("unknown-output", S + P + ["--output", "nonsense_kg"], ["--output", "nonsense_kg"]),
    ("workers-negative", S + P + ["--workers", "-1"], ["--workers", "-1"]),
    ("set-no-equals", ["sensitivity", "song2003_ottawa", "--set", "thermal.enabled"] + P, ["--set", "thermal.enabled"]),
    # found by fuzzing: the runs took the range, the study's record the dropped --set
    ("set-and-param", S + P + ["--set", "operating.rpm=4"], ["operating.rpm given by --set and by --param"]),
]


@pytest.mark.parametrize("name,argv,fragments", CASES, ids=[c[0] for c in CASES])
def test_sensitivity_bad_input(name, argv, fragments, workdir):
    before = snapshot(workdir)
    res = run_cli(argv + ["--out", "study"], cwd=workdir)
    assert_bad(res, *fragments)
    assert snapshot(workdir) == before


def test_out_is_a_file(workdir):
    (workdir / "study").write_text("keep")
    before = snapshot(workdir)
    res = run_cli(S + P + ["--out", "study"], cwd=workdir)
    assert_bad(res, "--out", "study", "not a directory")
    assert snapshot(workdir) == before


def test_report_sensitivity_not_a_result(workdir):
    (workdir / "x.json").write_text('{"a": 1}')
    before = snapshot(workdir)
    res = run_cli(["report", "invicta", "--sensitivity", "x.json", "-o", "r.html"], cwd=workdir)
    assert_bad(res, "--sensitivity", "x.json", "sobol_sensitivity")
    res = run_cli(["report", "invicta", "--sensitivity", "missing.json", "-o", "r.html"], cwd=workdir)
    assert_bad(res, "--sensitivity", "missing.json")
    assert snapshot(workdir) == before


def test_size_class_dew_point_and_audit_outputs_are_known(workdir):
    """--output dust_rate_kg_s, product_d50_m, gas_outlet_dew_point_margin_K were 'not a known output' though
    simulate and target give them (found by fuzzing)."""
    res = run_cli(["sensitivity", "lee2008_invicta", "--param", "operating.rpm=2.5,3.5", "-n", "4", "-q",
                   "--output", "gas_outlet_dew_point_margin_K", "--output", "dust_rate_kg_s"], cwd=workdir)
    assert res.exit_code == 0, res.output
    assert "gas_outlet_dew_point_margin_K" in res.output and "dust_rate_kg_s" in res.output
