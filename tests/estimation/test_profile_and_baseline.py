"""Profile likelihood and the fitted tracer background of case fits (issue 14 part 6):
``profile_likelihood`` against exact results, ``fit_case_to_tracer(baseline="fit")``,
``profile_case_fit`` and ``rotarydryer fit --baseline fit --profile``."""

import json
import math
import warnings

import numpy as np
import pytest
from scipy import stats
from typer.testing import CliRunner

from rotarydryer import rtd
from rotarydryer.cli import app
from rotarydryer.estimation import Dataset, Parameter, fit, profile_likelihood
from rotarydryer.estimation.cases import BASELINE, baseline_parameter, fit_case_to_tracer, profile_case_fit

runner = CliRunner()
AJAYI4 = {"operating.test": 4, "geometry.method": "ajayi2011_regressions"}


def _line_data(n=400, seed=1):
    rng = np.random.default_rng(seed)
    x = np.linspace(0.0, 1.0, n)
    return x, 2.0 + 3.0 * x + 0.1 * rng.standard_normal(n)


def test_profile_of_a_linear_model_is_the_wald_interval():
    """For a linear model with Gaussian errors the profile of SSE/s^2 is exactly quadratic: the
    profile interval is the Wald one with the chi2 quantile in place of the t quantile."""
    x, y = _line_data()
    params = [Parameter("a", 1.0), Parameter("b", 1.0)]
    model = lambda v: v["a"] + v["b"] * x  # noqa: E731
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = fit(model, params, Dataset("y", y), n_starts=1)
        p = profile_likelihood(model, params, Dataset("y", y), r, "b", n_points=9)
    est = r.parameters["b"]
    half = math.sqrt(stats.chi2.ppf(0.95, 1)) * est.std_error
    assert p.ci_low == pytest.approx(est.value - half, rel=1e-3)
    assert p.ci_high == pytest.approx(est.value + half, rel=1e-3)
    assert not (p.flat or p.open_low or p.open_high)
    assert p.delta.min() == pytest.approx(0.0, abs=1e-9)


def test_profile_grid_is_extended_until_it_crosses():
    """A grid of +/- 0.5 standard errors never reaches the threshold: the sides are extended and
    give the same interval as a wide grid."""
    x, y = _line_data()
    params = [Parameter("a", 1.0), Parameter("b", 1.0)]
    model = lambda v: v["a"] + v["b"] * x  # noqa: E731
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = fit(model, params, Dataset("y", y), n_starts=1)
        narrow = profile_likelihood(model, params, Dataset("y", y), r, "a", n_points=5, span=0.5)
        wide = profile_likelihood(model, params, Dataset("y", y), r, "a", n_points=41, span=4.0)
        stuck = profile_likelihood(model, params, Dataset("y", y), r, "a", n_points=5, span=0.5, extend=0)
    assert not (narrow.open_low or narrow.open_high)
    assert narrow.ci_low == pytest.approx(wide.ci_low, rel=1e-3)
    assert narrow.ci_high == pytest.approx(wide.ci_high, rel=1e-3)
    assert stuck.flat and stuck.open_low and stuck.open_high


def test_profile_points_the_model_refuses_end_the_interval():
    x, y = _line_data()
    params = [Parameter("a", 1.0), Parameter("b", 1.0)]

    def model(v):
        if v["b"] > 3.0 + 1e-9 and v["a"] < 100:    # infeasible above b = 3 (near the estimate)
            raise ValueError("b too large")
        return v["a"] + v["b"] * x

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = fit(model, [Parameter("a", 1.0), Parameter("b", 1.0, upper=3.0)], Dataset("y", y), n_starts=1)
        p = profile_likelihood(model, params, Dataset("y", y), r, "b", n_points=9)
    assert np.isinf(p.delta[p.values > 3.0 + 1e-9]).all()
    assert p.ci_high <= 3.0 + 1e-9


def test_baseline_parameter_start_and_bounds():
    y = np.r_[np.full(30, 0.6), np.linspace(1, 50, 10), np.full(10, 0.7)]
    p = baseline_parameter(y)
    assert p.name == BASELINE and not p.log
    assert p.initial == pytest.approx(0.6)
    assert (p.lower, p.upper) == (-50.0, 50.0)
    with pytest.raises(ValueError, match="baseline"):
        baseline_parameter(np.zeros(5))


@pytest.fixture(scope="module")
def ajayi4_fits():
    data = rtd.load_tracer_dataset("ajayi2011_test4")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plain = fit_case_to_tracer("ajayi2011_mmg", data, ["transport.dispersion"], base_overrides=AJAYI4,
                                   scale="fit", n_starts=1)
        bg = fit_case_to_tracer("ajayi2011_mmg", data, ["transport.dispersion"], base_overrides=AJAYI4,
                                scale="fit", n_starts=1, baseline="fit")
    return data, plain, bg


def test_case_fit_background_on_ajayi_test4(ajayi4_fits):
    """Ajayi's raw ppm carry a lithium background (notes ajayi_transport.md: about 0.56-0.9 ppm before
    the tracer arrives): the fitted constant is positive, of that order, and the fit improves."""
    data, plain, bg = ajayi4_fits
    b = bg.fit.parameters[BASELINE]
    early = np.asarray(data.signal)[np.asarray(data.time_s) <= 720.0]    # before the tracer arrives
    assert 0.1 < b.value < 2.0
    assert b.value == pytest.approx(float(np.median(early)), rel=0.6)
    assert b.ci_low < b.value < b.ci_high
    assert bg.keys == ["transport.dispersion", BASELINE]
    assert bg.fit.objective < plain.fit.objective
    assert bg.fit.r_squared > plain.fit.r_squared


def test_profile_case_fit(ajayi4_fits):
    _, _, bg = ajayi4_fits
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        prof = profile_case_fit(bg, [BASELINE], n_points=7)
    p, est = prof[BASELINE], bg.fit.parameters[BASELINE]
    assert p.ci_low < est.value < p.ci_high
    assert not (p.flat or p.open_low or p.open_high)
    # the baseline enters linearly: its profile is close to the Wald interval
    assert p.ci_low == pytest.approx(est.ci_low, abs=0.25 * (est.ci_high - est.ci_low))
    assert p.ci_high == pytest.approx(est.ci_high, abs=0.25 * (est.ci_high - est.ci_low))
    with pytest.raises(ValueError, match="n_points"):
        profile_case_fit(bg, n_points=2)
    with pytest.raises(ValueError, match="transport.bogus"):
        profile_case_fit(bg, ["transport.bogus"])


def test_fit_cli_baseline_and_profile(tmp_path):
    res = runner.invoke(app, ["fit", "ajayi2011_mmg", "ajayi2011_test4", "-p", "transport.dispersion",
                              "--set", "operating.test=4", "--set", "geometry.method=ajayi2011_regressions",
                              "--scale", "fit", "--starts", "1", "--baseline", "fit",
                              "--profile", "--profile-points", "5", "--json", "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout.strip().splitlines()[-1])
    assert d["baseline"] == "fit"
    for k in ("transport.dispersion", BASELINE):
        p = d["parameters"][k]
        assert p["profile_ci_low"] < p["value"] < p["profile_ci_high"]
        assert len(d["profiles"][k]["values"]) == len(d["profiles"][k]["delta"]) >= 5
    assert 0.1 < d["parameters"][BASELINE]["value"] < 2.0
    saved = json.loads((tmp_path / "fit.json").read_text())
    assert saved["parameters"]["transport.dispersion"]["profile_ci_high"] == pytest.approx(
        d["parameters"]["transport.dispersion"]["profile_ci_high"])
    assert (tmp_path / "profile.png").stat().st_size > 10_000
    res = runner.invoke(app, ["fit", "ajayi2011_mmg", "ajayi2011_test4", "-p", "transport.dispersion",
                              "--set", "operating.test=4", "--scale", "fit", "--starts", "1", "--profile",
                              "--profile-points", "5"])
    assert res.exit_code == 0, res.output
    assert "95% CI (Wald)" in res.output and "95% CI (profile likelihood)" in res.output
