"""Bad input to what issue 14 part 6 made reachable: ``rtd-fit --model/--baseline/--n-cells``,
``fit --baseline/--profile/--profile-points``, the case keys ``transport.core``, ``core_fraction``,
``core_time`` and Lee's ``transport.model = "sheehan2005_model1"`` with its rates. Each case: exit 2,
an ``error:`` line naming the option or key and the value, no traceback, nothing written."""

from __future__ import annotations

import pytest

from .conftest import assert_bad, run_cli, snapshot

LEE = "lee2008_invicta"
FIT = ["fit", LEE, LEE, "-p", "transport.backmix"]
CORE = ["--set", "transport.core=diffusive", "--set", "transport.core_fraction=0.5",
        "--set", "transport.core_time=1000"]
MODEL1 = ["--set", "transport.model=sheehan2005_model1", "--set", "transport.passive_rate=0.05",
          "--set", "transport.exchange_rate=0.1", "--set", "transport.return_rate=1",
          "--set", "transport.kiln_rate=0.1"]


def _replace(argv, key, value):
    """``argv`` with the ``--set key=...`` pair set to ``value``."""
    return [f"{key}={value}" if a.startswith(key + "=") else a for a in argv]


RTD_FIT = [
    ("model-hyphen", ["rtd-fit", LEE, "--model", "cholette-cloutier"], ["--model", "cholette-cloutier"]),
    ("model-empty", ["rtd-fit", LEE, "--model", ""], ["--model"]),
    ("baseline-word", ["rtd-fit", LEE, "--baseline", "fitted"], ["--baseline", "fitted", "fit"]),
    ("baseline-nan", ["rtd-fit", LEE, "--baseline", "nan"], ["--baseline", "nan"]),
    ("moments-baseline-fit", ["rtd-moments", LEE, "--baseline", "fit"], ["--baseline", "fit", "rtd-fit"]),
    ("n-cells-zero", ["rtd-fit", LEE, "--model", "interactive_mixers", "--n-cells", "0"], ["--n-cells", "0"]),
    ("n-cells-huge", ["rtd-fit", LEE, "--model", "cholette_cloutier", "--n-cells", "99999"],
     ["--n-cells", "99999", "5000"]),
    ("n-cells-fraction", ["rtd-fit", LEE, "--model", "interactive_mixers", "--n-cells", "2.5"],
     ["--n-cells", "integer"]),
    ("n-cells-wrong-model", ["rtd-fit", LEE, "--n-cells", "10"], ["--n-cells", "tanks_in_series"]),
]

FIT_OPTIONS = [
    ("baseline-word", FIT + ["--baseline", "yes"], ["--baseline", "yes"]),
    ("baseline-method", FIT + ["--baseline", "leading"], ["--baseline", "leading", "none, fit"]),
    ("profile-with-value", FIT + ["--profile=3"], ["--profile"]),
    ("profile-points-without-profile", FIT + ["--profile-points", "5"], ["--profile-points", "--profile"]),
    ("profile-points-two", FIT + ["--profile", "--profile-points", "2"], ["--profile-points", "2"]),
    ("profile-points-huge", FIT + ["--profile", "--profile-points", "1000"], ["--profile-points", "1000"]),
    ("profile-points-word", FIT + ["--profile", "--profile-points", "abc"], ["--profile-points"]),
]

CASE_KEYS = [
    ("core-unknown", ["rtd", LEE, "--set", "transport.core=triple"], ["transport.core", "triple"]),
    ("core-without-fraction-and-time", ["rtd", LEE, "--set", "transport.core=diffusive"],
     ["transport.core", "transport.core_fraction", "transport.core_time"]),
    ("core-fraction-above-10", ["rtd", LEE, *_replace(CORE, "transport.core_fraction", "11")],
     ["transport.core_fraction", "11"]),
    ("core-fraction-negative", ["rtd", LEE, *_replace(CORE, "transport.core_fraction", "-0.1")],
     ["transport.core_fraction", "-0.1"]),
    ("core-time-zero", ["rtd", LEE, *_replace(CORE, "transport.core_time", "0")], ["transport.core_time", "0"]),
    ("core-time-huge", ["rtd", LEE, *_replace(CORE, "transport.core_time", "2e6")], ["transport.core_time"]),
    ("core-time-nan", ["rtd", LEE, *_replace(CORE, "transport.core_time", "nan")], ["transport.core_time"]),
    ("core-fraction-without-core", ["rtd", LEE, "--set", "transport.core_fraction=0.3"],
     ["transport.core_fraction", "transport.core = 'none'"]),
    ("dryer-core-without-time", ["rtd", "song2003_ottawa", "--set", "transport.core=first_order",
                                 "--set", "transport.core_fraction=0.2"], ["transport.core_time"]),
    ("core-with-heat-and-mass", ["simulate", LEE, *CORE], ["transport.core = 'diffusive'", "thermal.enabled"]),
    ("model1-without-rates", ["rtd", LEE, "--set", "transport.model=sheehan2005_model1"],
     ["sheehan2005_model1", "transport.passive_rate", "transport.kiln_rate"]),
    ("model1-negative-rate", ["rtd", LEE, *_replace(MODEL1, "transport.passive_rate", "-1")],
     ["transport.passive_rate", "-1"]),
    ("model1-zero-exchange", ["rtd", LEE, *_replace(MODEL1, "transport.exchange_rate", "0")],
     ["transport.exchange_rate", "0"]),
    ("model1-nothing-leaves", ["rtd", LEE, *_replace(_replace(MODEL1, "transport.passive_rate", "0"),
                                                     "transport.kiln_rate", "0")],
     ["transport.passive_rate = 0", "transport.kiln_rate = 0"]),
    ("model1-rates-on-lee2008", ["rtd", LEE, "--set", "transport.kiln_rate=0.1"],
     ["transport.kiln_rate", "sheehan2005_model1"]),
    ("model-unknown", ["rtd", LEE, "--set", "transport.model=sheehan2005_model3"],
     ["transport.model", "sheehan2005_model3"]),
]

ALL = ([("rtd-fit-" + i, a, f) for i, a, f in RTD_FIT] + [("fit-" + i, a, f) for i, a, f in FIT_OPTIONS]
       + [("case-" + i, a, f) for i, a, f in CASE_KEYS])


@pytest.mark.parametrize("argv,fragments", [pytest.param(a, f, id=i) for i, a, f in ALL])
def test_bad_reachability_input(argv, fragments, workdir):
    before = snapshot(workdir)
    res = run_cli(argv, cwd=workdir)
    assert_bad(res, *fragments)
    assert snapshot(workdir) == before


def test_fit_out_is_a_file_refused_before_fitting(workdir):
    (workdir / "taken").write_text("x")
    before = snapshot(workdir)
    res = run_cli(FIT + ["--profile", "--out", "taken"], cwd=workdir)
    assert_bad(res, "--out", "taken", "not a directory")
    assert snapshot(workdir) == before
