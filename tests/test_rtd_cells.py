"""Song (2003) Eq. 2.10-2.16 cell models (interactive mixers with dead zones) and the fitted tracer
background: E(t) against the exact linear system, recovery and moments against the analytic values,
fitting (integer N scan, baseline) and the ``rtd-fit`` command."""

import json
import warnings

import numpy as np
import pytest
import scipy.linalg as sl
from typer.testing import CliRunner

from rotarydryer.cli import app
from rotarydryer.rtd import (
    CELL_MODELS,
    RTD_FIT_MODELS,
    RTD_MODELS,
    CholetteCloutier,
    TanksInSeries,
    cholette_cloutier_e,
    cholette_cloutier_moments,
    convolve_rtd,
    fit_rtd_model,
    fit_tracer_data,
    load_tracer_dataset,
    pulse_input,
)
from rotarydryer.rtd.fitting import _integer_minimum

runner = CliRunner()

#: (N, k 1/s, alpha, beta): no dead zone, fast and slow exchange, both inversion branches (N <= 20: Talbot)
CASES = [(1, 0.1, 1.0, 1.0), (3, 0.05, 1.0, 1.0), (5, 0.02, 0.7, 0.5), (12, 0.3, 0.4, 3.0), (4, 0.01, 0.95, 0.01),
         (30, 1.0, 0.9, 50.0), (45, 5.0, 0.7, 0.5), (60, 2.0, 0.5, 0.01)]


def exact_e(t, n, k, alpha, beta):
    """E(t) of Song Eq. 2.10-2.16 at steady state from the matrix exponential of the 2N tracer
    balances (Eq. 2.11, 2.13): active masses (N - j + 1) F/k, dead masses (1 - alpha)/alpha of them,
    exchange beta F each way; unit feed F = 1."""
    c = (1 - alpha) / alpha
    ma = np.array([(n - j) / k for j in range(n)])
    md = ma * c
    K = np.zeros((2 * n, 2 * n))
    for j in range(n):
        a, d = 2 * j, 2 * j + 1
        K[a, a] -= 1.0 / ma[j]
        if j + 1 < n:
            K[2 * (j + 1), a] += 1.0 / ma[j]
        if c > 0:
            K[d, a] += beta / ma[j]
            K[a, a] -= beta / ma[j]
            K[a, d] += beta / md[j]
            K[d, d] -= beta / md[j]
        else:
            K[d, d] = -1.0
    return np.array([sl.expm(K * tt)[2 * (n - 1), 0] / ma[-1] for tt in t])


@pytest.mark.parametrize("n,k,alpha,beta", CASES)
def test_e_equals_the_exact_linear_system(n, k, alpha, beta):
    m = cholette_cloutier_moments(n, k, alpha, beta)
    t = np.r_[np.linspace(max(m.mean_s - 4 * m.std_s, 1e-3), m.mean_s + 6 * m.std_s, 20),
              m.mean_s * np.array([0.1, 0.5, 2.0, 4.0])]
    ref = exact_e(t, n, k, alpha, beta)
    assert np.max(np.abs(cholette_cloutier_e(t, n, k, alpha, beta) - ref)) < 1e-7 * ref.max()


@pytest.mark.parametrize("n,k,alpha,beta", CASES)
def test_recovery_and_moments_equal_the_analytic_values(n, k, alpha, beta):
    m = cholette_cloutier_moments(n, k, alpha, beta)
    # integrate on a grid that resolves the peak (the active zones) and reaches the slow tail
    sd_active = np.sqrt(cholette_cloutier_moments(n, k).variance_s2)
    t = np.unique(np.r_[np.linspace(0, m.mean_s + 8 * sd_active, 10001),
                        np.linspace(0, m.mean_s + 40 * m.std_s, 20001)])
    e = cholette_cloutier_e(t, n, k, alpha, beta)
    area = np.trapezoid(e, t)
    mean = np.trapezoid(t * e, t)
    var = np.trapezoid((t - mean) ** 2 * e, t)
    mu3 = np.trapezoid((t - mean) ** 3 * e, t)
    assert area == pytest.approx(1.0, abs=2e-5)
    assert mean == pytest.approx(m.mean_s, rel=2e-4)
    assert var == pytest.approx(m.variance_s2, rel=5e-3)
    assert mu3 / var**1.5 == pytest.approx(m.skewness, rel=2e-2, abs=2e-3)


def test_moments_are_song_tau_and_the_hypoexponential_without_dead_zones():
    n, k = np.arange(1, 50), 0.37
    m = cholette_cloutier_moments(n, k)
    # Song (2003) notes: tau = N(N+1)/(2 k alpha); without dead zones the cells are exponentials of
    # means m/k, m = 1..N (each cell holds (N - j + 1) F/k)
    np.testing.assert_allclose(m.mean_s, n * (n + 1) / (2 * k), rtol=1e-14)
    np.testing.assert_allclose(m.variance_s2, [np.sum((np.arange(1, q + 1) / k) ** 2) for q in n], rtol=1e-12)
    mu3 = [2 * np.sum((np.arange(1, q + 1) / k) ** 3) for q in n]
    np.testing.assert_allclose(m.skewness * m.variance_s2**1.5, mu3, rtol=1e-12)
    # dead zones add (1 - alpha)/alpha of the active time to the mean, whatever beta
    md = cholette_cloutier_moments(20, k, 0.6, [0.01, 1.0, 100.0])
    np.testing.assert_allclose(md.mean_s, 20 * 21 / (2 * k * 0.6), rtol=1e-14)
    assert np.all(np.diff(md.variance_s2) < 0)     # slower exchange: longer stays, more spread


def test_vectorised_over_time_and_parameters():
    t = np.array([[50.0], [150.0], [400.0]])
    n = np.array([3, 8, 25, 40])
    e = cholette_cloutier_e(t, n, 0.2, 0.8, 0.7)
    assert e.shape == (3, 4)
    for i in range(3):
        for j in range(4):
            assert e[i, j] == pytest.approx(cholette_cloutier_e(float(t[i, 0]), int(n[j]), 0.2, 0.8, 0.7), rel=1e-12)
    assert cholette_cloutier_e(-5.0, 3, 0.2) == 0.0
    assert cholette_cloutier_e(0.0, 1, 0.2) == pytest.approx(0.2)     # N = 1: E(0) = k
    # alpha = 1: the exchange ratio does not matter
    assert cholette_cloutier_e(100.0, 6, 0.1, 1.0, 5.0) == cholette_cloutier_e(100.0, 6, 0.1, 1.0, 0.3)


@pytest.mark.parametrize("n", [10, 150])
def test_outlet_response_is_the_convolution(n):
    model = CholetteCloutier(n, 1.0, 0.8, 0.4)
    mo = model.moments()
    t = np.linspace(-50.0, mo.mean_s + 8 * mo.std_s, 200)
    for pulse in (pulse_input("dirac"), pulse_input("rectangular", 0.5 * mo.std_s),
                  pulse_input("rectangular", 3 * mo.std_s)):
        ref = convolve_rtd(model.e, t, pulse)
        assert np.max(np.abs(model.outlet(t, pulse) - ref)) < 1e-7 * ref.max()


@pytest.mark.parametrize("kwargs,fragment", [
    (dict(n_cells=2.5), "n_cells"), (dict(n_cells=0), "n_cells"), (dict(conductance_per_s=0.0), "conductance_per_s"),
    (dict(active_fraction=1.2), "active_fraction"), (dict(active_fraction=0.0), "active_fraction"),
    (dict(exchange_ratio=0.0), "exchange_ratio"), (dict(exchange_ratio=np.nan), "exchange_ratio"),
])
def test_bad_parameters_name_the_argument(kwargs, fragment):
    args = dict(n_cells=5, conductance_per_s=0.1, active_fraction=0.8, exchange_ratio=1.0, **{})
    args.update(kwargs)
    with pytest.raises(ValueError, match=fragment):
        cholette_cloutier_e(10.0, **args)
    with pytest.raises(ValueError, match=fragment):
        cholette_cloutier_moments(**args)


def test_registered_models():
    assert RTD_FIT_MODELS == RTD_MODELS + CELL_MODELS
    assert CELL_MODELS == ("interactive_mixers", "cholette_cloutier")
    from rotarydryer.cli import rtdfit

    assert rtdfit._MODELS == RTD_FIT_MODELS and rtdfit._CELL_MODELS == CELL_MODELS


def test_integer_minimum_finds_the_minimum_of_a_unimodal_function():
    for target in (1, 7, 40, 333, 4999):
        calls = []

        def f(n, target=target):
            calls.append(n)
            return (np.log(n) - np.log(target)) ** 2

        assert _integer_minimum(f, 12, 5000) == target
        assert len(set(calls)) < 40


PULSE = pulse_input("rectangular", 40.0)


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
@pytest.mark.parametrize("kind,truth", [("interactive_mixers", CholetteCloutier(9, 0.02)),
                                        ("cholette_cloutier", CholetteCloutier(9, 0.02, 0.75, 0.05))])
def test_noise_free_round_trip_scans_to_the_true_number_of_cells(kind, truth):
    t = np.linspace(20.0, 12000.0, 150)
    y = 2.5 * convolve_rtd(truth.e, t - 60.0, PULSE)
    f = fit_rtd_model(t, y, kind, pulse=PULSE, fit_scale=True, fit_delay=True)
    assert f.fixed["n_cells"] == truth.n_cells
    assert f.n_cells_scan[truth.n_cells] == min(f.n_cells_scan.values())
    for k in truth.parameter_names[: len(f.parameter_names) - 2]:
        assert f.values[k] == pytest.approx(getattr(truth, k), rel=1e-4)
    assert f.values["scale"] == pytest.approx(2.5, rel=1e-5)
    assert f.values["delay_s"] == pytest.approx(60.0, abs=0.05)
    assert f.rtd_moments.mean_s == pytest.approx(truth.moments().mean_s, rel=1e-5)
    # the fixed N: the same answer without the scan
    g = fit_rtd_model(t, y, kind, pulse=PULSE, fit_scale=True, fit_delay=True, n_cells=truth.n_cells)
    assert g.objective == pytest.approx(f.objective, abs=1e-10 * float(y @ y))
    assert set(g.n_cells_scan) == {truth.n_cells}


def test_fitted_baseline_recovers_a_known_background():
    model = TanksInSeries(600.0, 12.0)
    t = np.linspace(0.0, 3000.0, 80)
    y = 4.0 * convolve_rtd(model.e, t, PULSE) + 0.002
    f = fit_rtd_model(t, y, "tanks_in_series", pulse=PULSE, fit_scale=True, fit_baseline=True)
    assert f.parameter_names[-1] == "baseline"
    assert f.values["baseline"] == pytest.approx(0.002, rel=1e-6)
    assert f.values["mean_residence_time_s"] == pytest.approx(600.0, rel=1e-6)
    assert f.predict(t) == pytest.approx(y, abs=1e-9)
    assert "baseline" in f.to_dict()["parameters"]


@pytest.mark.parametrize("kind", ["tanks_in_series", "interactive_mixers"])
def test_ajayi_test4_background_is_positive_and_improves_the_fit(kind):
    """Ajayi's raw lithium (ppm) is not background-corrected (data-set notes; notes ajayi_transport.md:
    about 0.56-0.9 ppm before the tracer arrives): the fitted constant is positive, of that order,
    and lowers the residual sum of squares."""
    d = load_tracer_dataset("ajayi2011_test4")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        plain = fit_tracer_data(d, kind)
        bg = fit_tracer_data(d, kind, fit_baseline=True)
    b = bg.values["baseline"]
    early = np.asarray(d.signal)[np.asarray(d.time_s) <= 720.0]      # samples before the tracer arrives
    assert 0.1 < b < 2.0
    assert b == pytest.approx(float(np.median(early)), rel=0.5)
    assert bg.ci_low["baseline"] < b < bg.ci_high["baseline"]
    assert bg.objective < plain.objective and bg.r_squared > plain.r_squared


def test_n_cells_only_for_the_cell_models():
    t = np.linspace(0, 100, 30)
    y = TanksInSeries(30.0, 3.0).e(t)
    with pytest.raises(ValueError, match="n_cells"):
        fit_rtd_model(t, y, "tanks_in_series", n_cells=4)
    with pytest.raises(ValueError, match="n_cells"):
        fit_rtd_model(t, y, "interactive_mixers", n_cells=2.5)
    with pytest.raises(ValueError, match="model"):
        fit_rtd_model(t, y, "cholette")


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_rtd_fit_cli_cell_model_and_baseline(tmp_path):
    res = runner.invoke(app, ["rtd-fit", "ajayi2011_test4", "--model", "interactive_mixers", "--baseline", "fit",
                              "--json", "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout.strip().splitlines()[-1])
    assert d["model"] == "interactive_mixers" and d["fixed"]["n_cells"] >= 1
    assert 0.1 < d["parameters"]["baseline"]["value"] < 2.0
    assert (tmp_path / "rtd_fit.png").stat().st_size > 10_000
    res = runner.invoke(app, ["rtd-fit", "lee2008_invicta", "--model", "cholette_cloutier", "--n-cells", "30"])
    assert res.exit_code == 0, res.output
    assert "number of cells N = 30 (given (--n-cells))" in res.output
    for name in ("conductance_per_s", "active_fraction", "exchange_ratio"):
        assert name in res.output
