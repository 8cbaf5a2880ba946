r"""Study: the predictive MMG transport across Ajayi's six tracer tests (issue 14, item 2).

The case ``ajayi2011_mmg`` with ``transport.parameter_source = "predictive"`` takes the solids
velocity and dispersion of every section from the operating point with two coefficients, c_u and
c_D (`rotarydryer.transport.ajayi_predictive`). This study calibrates the two on one test and
predicts the others:

* **measured E(t)** (`measured_curve`): Ajayi (2011) Appendix B (``load_tracer_dataset``),
  background removed with the case's ``tracer.baseline`` ("leading": median before breakthrough),
  normalised to unit area on the samples (Ajayi (2011) Eq. 3.5-3.6, trapezoidal rule);
* **model E(t)** (`predict`): the case's 60 s tracer pulse simulated at the transport steady
  state, read at the sample times and normalised on the same samples (both curves see the same
  window); its tracer mean and SD are the analytic moments from the injection start
  (``rotarydryer rtd ... --json``: ``tracer_mean_s``, ``tracer_std_s``);
* **R^2** = 1 - sum (E_meas - E_model)^2 / sum (E_meas - mean E_meas)^2 over the samples; the MRT
  error is against Ajayi's published first moment (Table 3.13, ``ajayi_rtd_tests_summary.csv``);
* **calibration** (`calibrate`): unweighted least squares of E(t) by
  `rotarydryer.estimation.fit` (c_u, c_D log-transformed) from a start whose c_u matches the
  measured mean;
* `cross_test` - the matrix "calibrated on test i, predicted test j"; `markdown` - the
  tables of docs/mmg_cross_test.md (``examples/mmg_cross_test.py`` writes them).

Everything is computed from shipped data (tracer files, the test summary, the case file).
Times in s, E in 1/s.
"""

from __future__ import annotations

import csv
import math
import time
import warnings
from dataclasses import dataclass, field
from functools import cache, lru_cache
from importlib import resources

import numpy as np
from scipy.integrate import trapezoid

from .._validation import check_choice
from ..executor import Executor, RunFailure

__all__ = ["CASE", "TESTS", "published", "measured_curve", "r_squared", "Prediction", "predict", "Calibration",
           "calibrate", "CrossTest", "cross_test", "markdown", "moisture_correlation", "table_5_2_consistency"]

CASE = "ajayi2011_mmg"
TESTS = (1, 2, 3, 4, 5, 6)


@lru_cache(maxsize=1)
def _summary() -> dict:
    text = resources.files("rotarydryer.data").joinpath("ajayi_rtd_tests_summary.csv").read_text("utf-8")
    rows = csv.DictReader(ln for ln in text.splitlines() if ln.strip() and not ln.startswith("#"))
    return {int(r["test"]): r for r in rows}


def published(test: int) -> dict:
    """Ajayi's (2011) data of a test (``ajayi_rtd_tests_summary.csv``): ``mrt_min`` (Table 3.13),
    ``feed_t_h``, ``feed_sd_t_h``, ``rpm``, ``moisture_in_pct`` (and SD), ``condition``,
    ``recovery_pct`` (Tables 3.7, 3.12), ``holdup_kg`` (Table 3.14)."""
    r = _summary().get(int(test))
    if r is None:
        raise ValueError(f"test = {test!r} is not one of Ajayi's tests {TESTS}")
    f = lambda k: float(r[k])  # noqa: E731
    return dict(mrt_min=f("MRT_measured_min"), feed_t_h=f("feed_t_h"), feed_sd_t_h=f("feed_sd_t_h"),
                rpm=f("rpm"), moisture_in_pct=f("solid_in_moisture_pct"),
                moisture_in_sd_pct=f("solid_in_moisture_sd_pct"), condition=r["internal_condition"],
                recovery_pct=f("recovery_pct"), holdup_kg=f("holdup_measured_kg"), method=r["tracer_method"])


@cache
def _measured(test: int):
    from ..cases import load_case
    from ..rtd import exit_age_curve, load_tracer_dataset

    baseline = load_case(CASE).tracer.baseline
    d = load_tracer_dataset(f"ajayi2011_test{int(test)}")
    t, e, _ = exit_age_curve(d.time_s, d.signal, time_origin_s=d.time_origin_s, baseline=baseline)
    t.setflags(write=False)
    e.setflags(write=False)
    return t, e


def measured_curve(test: int):
    """(times s from the injection, E 1/s) of a test's measured curve (module docstring)."""
    published(test)
    return _measured(int(test))


def _moments(t, e):
    m = float(trapezoid(t * e, t))
    return m, math.sqrt(max(float(trapezoid((t - m) ** 2 * e, t)), 0.0))


def r_squared(e_measured, e_model) -> float:
    """1 - SSR/SST of ``e_model`` against ``e_measured`` (unweighted)."""
    y, f = np.asarray(e_measured, float), np.asarray(e_model, float)
    sst = float(np.sum((y - y.mean()) ** 2))
    return 1.0 - float(np.sum((y - f) ** 2)) / sst


@dataclass(frozen=True)
class Prediction:
    """One test predicted with (c_u, c_D): tracer mean and SD (analytic, from the injection start, s),
    holdup (kg), model E(t) on the measured samples and R^2; measured curve moments (window, s)."""

    test: int
    velocity_coefficient: float
    dispersion_coefficient: float
    law: str
    tracer_mean_s: float
    tracer_std_s: float
    holdup_kg: float
    r_squared: float
    times_s: np.ndarray = field(repr=False)
    e_model_per_s: np.ndarray = field(repr=False)
    measured_mean_s: float = math.nan
    measured_std_s: float = math.nan
    sections: dict = field(default_factory=dict, repr=False)

    @property
    def published_mrt_s(self) -> float:
        return 60.0 * published(self.test)["mrt_min"]

    @property
    def mrt_error(self) -> float:
        """Relative error of the tracer mean against Ajayi's Table 3.13 first moment (-)."""
        return self.tracer_mean_s / self.published_mrt_s - 1.0


#: Ajayi's thesis model: his regression geometry (Ajayi (2011) Eq. 4.25-4.28), on which the case's c_u and
#: c_D were calibrated; the case default is the exact geometry (issue 16), with which a recalibration on
#: Test 4 predicts Test 5 within -1.0 % (R^2 0.96) and Test 6 within -3.2 % but with R^2 0.88
THESIS_GEOMETRY = {"geometry.method": "ajayi2011_regressions"}


def _overrides(test, cu, cd, law, extra=None) -> dict:
    ov = {**THESIS_GEOMETRY, "operating.test": int(test), "transport.parameter_source": "predictive",
          "transport.predictive_flights": "kiln_velocity",
          "transport.velocity_coefficient": float(cu), "transport.dispersion_coefficient": float(cd),
          "transport.velocity_law": law}
    ov.update(extra or {})
    return ov


@lru_cache(maxsize=4096)
def _predict(test, cu, cd, law, extra):
    from ..simulation import Simulation
    from ..transport import RTDWindowWarning

    t, e = _measured(test)
    sim = Simulation(CASE, _overrides(test, cu, cd, law, dict(extra)))
    ss = sim.transport_steady_state()
    t_end = math.ceil((float(t[-1]) + 60.0) / 10.0) * 10.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RTDWindowWarning)    # the curve is read on the data's window only
        res = ss.rtd(sim.transport_model().tracer_input, t_end=t_end, dt=10.0)
    f = np.interp(t, res.response.time, res.response.exit_age)
    area = float(trapezoid(f, t))
    if not area > 0:
        raise ValueError(f"test {test}: no tracer leaves within the measured window ({t[-1]:.0f} s) at "
                         f"velocity_coefficient = {cu:.4g}")
    f = f / area
    f.setflags(write=False)
    mm, ms = _moments(t, e)
    return Prediction(int(test), float(cu), float(cd), law, float(res.moments["mean"]), float(res.moments["std"]),
                      float(ss.total_holdup), r_squared(e, f), t, f, mm, ms,
                      sim.transport_model().parameters.get("predictive", {}))


def predict(test: int, velocity_coefficient: float, dispersion_coefficient: float, *,
            law: str = "friedman_marshall", overrides: dict | None = None) -> Prediction:
    """Predict ``test`` with the case in predictive mode at (c_u, c_D) (cached per arguments);
    ``overrides``: further case overrides (e.g. ``{"transport.fouling": 0.0}``)."""
    published(test)
    return _predict(int(test), float(velocity_coefficient), float(dispersion_coefficient), law,
                    tuple(sorted((overrides or {}).items())))


@dataclass
class Calibration:
    """c_u and c_D calibrated on one test (least squares on E(t)) and the fit behind them."""

    test: int
    law: str
    velocity_coefficient: float
    dispersion_coefficient: float
    r_squared: float
    n_evaluations: int
    seconds: float
    fit: object = field(repr=False, default=None)


def _start_velocity(test, cu, cd, law, extra) -> float:
    """c_u whose tracer mean matches the measured curve's mean (a few secant steps on log c_u: the
    residence time is roughly proportional to 1/c_u), from ``cu``."""
    target = _moments(*_measured(test))[0]
    x0, f0 = math.log(cu), math.log(predict(test, cu, cd, law=law, overrides=extra).tracer_mean_s / target)
    x1 = x0 + f0                       # tau ~ 1/c_u
    for _ in range(4):
        f1 = math.log(predict(test, math.exp(x1), cd, law=law, overrides=extra).tracer_mean_s / target)
        if abs(f1) < 2e-3 or f1 == f0:
            break
        x0, f0, x1 = x1, f1, x1 - f1 * (x1 - x0) / (f1 - f0)
        x1 = min(max(x1, math.log(0.02)), math.log(5.0))
    return math.exp(x1)


def calibrate(test: int, *, law: str = "friedman_marshall", start: tuple[float, float] | None = None,
              overrides: dict | None = None) -> Calibration:
    """c_u and c_D that fit ``test``'s measured E(t) (unweighted least squares, `rotarydryer.estimation.fit`).

    ``start`` (c_u, c_D): default the case file's calibration; c_u is first moved to match the
    measured mean (`_start_velocity`)."""
    from ..cases import load_case
    from ..estimation import Dataset, Parameter, fit

    check_choice("law", law, ("friedman_marshall", "kramers"))
    t0 = time.perf_counter()
    if start is None:
        tr = load_case(CASE, THESIS_GEOMETRY).transport     # the calibration record of the geometry it runs on
        start = (tr.velocity_coefficient, tr.dispersion_coefficient)
    extra = dict(overrides or {})
    cu0 = _start_velocity(int(test), float(start[0]), float(start[1]), law, extra)
    _, e = measured_curve(test)
    params = [Parameter("velocity_coefficient", cu0, 0.02, 5.0, log=True),
              Parameter("dispersion_coefficient", float(start[1]), 0.01, 1000.0, log=True)]

    def model(v):
        return predict(test, v["velocity_coefficient"], v["dispersion_coefficient"], law=law,
                       overrides=extra).e_model_per_s

    res = fit(model, params, Dataset("tracer", np.array(e)), n_starts=1)
    cu, cd = res.parameters["velocity_coefficient"].value, res.parameters["dispersion_coefficient"].value
    return Calibration(int(test), law, float(cu), float(cd), predict(test, cu, cd, law=law, overrides=extra).r_squared,
                       int(res.n_evaluations), time.perf_counter() - t0, res)


@dataclass
class CrossTest:
    """Calibrations (``calibrations[i]``) and predictions (``predictions[i][j]``: calibrated on i,
    predicted j)."""

    law: str
    calibrations: dict
    predictions: dict
    seconds: float

    def out_of_sample(self, i: int) -> dict:
        """Predictions of the calibration on ``i`` for the other tests."""
        return {j: p for j, p in self.predictions[i].items() if j != i}


def cross_test(calibrate_on=TESTS, predict_for=TESTS, *, law: str = "friedman_marshall",
               overrides: dict | None = None, executor: Executor | None = None) -> CrossTest:
    """Calibrate on each test of ``calibrate_on`` and predict every test of ``predict_for``; the
    calibrations (each with its predictions) run through ``executor`` (`rotarydryer.executor.Executor`,
    default serial; each is independent, so every backend gives the same table)."""
    t0 = time.perf_counter()
    ex = executor or Executor()
    items = list(calibrate_on)
    rows = ex.map(_cross_row, items, args=(list(predict_for), law, overrides), chunks=1)
    cals, preds = {}, {}
    for i, row in zip(items, rows):
        if isinstance(row, RunFailure):
            raise ValueError(f"calibration on test {i}: {row.error}")
        cals[i], preds[i] = row
    return CrossTest(law, cals, preds, time.perf_counter() - t0)


def _cross_row(i, predict_for, law, overrides):
    """One row of `cross_test`: the calibration on test ``i`` and its predictions (top-level, for the executor)."""
    c = calibrate(i, law=law, overrides=overrides)
    return c, {j: predict(j, c.velocity_coefficient, c.dispersion_coefficient, law=law, overrides=overrides)
               for j in predict_for}


def moisture_correlation(cross: CrossTest, tests=(1, 2, 4, 5, 6)) -> float:
    """Pearson r between each test's own calibrated c_u and its feed moisture (Table 3.5-3.11)."""
    x = [published(i)["moisture_in_pct"] for i in tests]
    y = [cross.calibrations[i].velocity_coefficient for i in tests]
    return float(np.corrcoef(x, y)[0, 1])


def table_5_2_consistency(tests=(2, 3, 4, 5, 6)) -> list[dict]:
    """Ajayi's fitted u_s (Table 5.2) against the u_s his own simulation implies: F / m_s, the feed over
    the unflighted-section holdup per metre of his Figs 5.16-5.20 captions (m_s = F/u_s in those
    sections). For each test, the per-test case (``parameter_source = "per_test"``) with either value:
    tracer mean (min) and total holdup (kg) against Table 5.4 (``ajayi_rtd_tests_summary.csv``)."""
    from ..cases import build_model, load_case

    out = []
    for n in tests:
        r = _summary()[int(n)]
        F = float(r["feed_kg_wet_min"]) / 60.0
        implied = F / float(r["unflighted_holdup_model_kg_per_m"])
        row = dict(test=int(n), u_table_5_2_m_s=float(r["u_s_fitted_m_s"]), u_implied_m_s=implied,
                   mrt_table_5_4_min=float(r["MRT_model_min"]), holdup_table_5_4_kg=float(r["holdup_model_kg"]))
        for key, u in (("table_5_2", None), ("implied", implied)):
            ov = {**THESIS_GEOMETRY, "operating.test": int(n)}
            if u is not None:
                ov["transport.solids_velocity"] = u
            m = build_model(load_case(CASE, ov))
            ss = m.steady_state()
            row[f"mrt_{key}_min"] = ss.rtd(m.tracer_input, simulate=False).moments["mean"] / 60.0
            row[f"holdup_{key}_kg"] = float(ss.total_holdup)
        out.append(row)
    return out


def markdown(cross: CrossTest, alternatives: dict | None = None, fouling: dict | None = None,
             consistency: list | None = None) -> str:
    """The tables of docs/mmg_cross_test.md: the test data, the row calibrated on Test 4 (or the
    first calibration), the R^2 and MRT-error matrices; ``alternatives``: label -> CrossTest
    calibrated on the same test, shown as extra rows; ``fouling``: transport.fouling -> Prediction
    of Test 3 with that calibration; ``consistency``: `table_5_2_consistency`."""
    tests = sorted({j for row in cross.predictions.values() for j in row})
    ref = 4 if 4 in cross.calibrations else next(iter(cross.calibrations))
    out = []
    out.append("| test | method | condition | rpm | feed t/h (SD) | feed moisture % (SD) | recovery % "
               "| published MRT min | curve mean / SD min |")
    out.append("|---|---|---|---|---|---|---|---|---|")
    for j in tests:
        p, pr = published(j), cross.predictions[ref][j]
        out.append(f"| {j} | {p['method']} | {p['condition']} | {p['rpm']:g} | "
                   f"{p['feed_t_h']:g} ({p['feed_sd_t_h']:g}) | "
                   f"{p['moisture_in_pct']:g} ({p['moisture_in_sd_pct']:g}) | {p['recovery_pct']:g} | "
                   f"{p['mrt_min']:.2f} | {pr.measured_mean_s / 60:.2f} / {pr.measured_std_s / 60:.2f} |")
    out.append("")
    rows = [("velocity law " + cross.law.replace("_", "-"), cross)] + list((alternatives or {}).items())
    out.append(f"Calibrated on Test {ref}:")
    out.append("")
    out.append("| law | c_u | c_D | test | predicted MRT / SD min | published MRT min | MRT error | holdup t "
               "(measured) | R^2 |")
    out.append("|---|---|---|---|---|---|---|---|---|")
    for label, ct in rows:
        c = ct.calibrations[ref]
        for j in tests:
            p = ct.predictions[ref][j]
            tag = " (calibration)" if j == ref else ""
            out.append(f"| {label} | {c.velocity_coefficient:.4g} | {c.dispersion_coefficient:.4g} | {j}{tag} | "
                       f"{p.tracer_mean_s / 60:.2f} / {p.tracer_std_s / 60:.2f} | {published(j)['mrt_min']:.2f} | "
                       f"{100 * p.mrt_error:+.1f} % | {p.holdup_kg / 1000:.1f} "
                       f"({published(j)['holdup_kg'] / 1000:.1f}) | {p.r_squared:.3f} |")
    out.append("")
    head = "| calibrated on | c_u | c_D | " + " | ".join(f"test {j}" for j in tests) + " |"
    sep = "|---|---|---|" + "---|" * len(tests)
    for title, cell in (("R^2 of E(t) (diagonal: in sample)", lambda p: f"{p.r_squared:.2f}"),
                        ("MRT error against Table 3.13 (diagonal: in sample)",
                         lambda p: f"{100 * p.mrt_error:+.1f} %")):
        out.append(f"{title}:")
        out.append("")
        out.append(head)
        out.append(sep)
        for i, c in cross.calibrations.items():
            cells = [("**" + cell(cross.predictions[i][j]) + "**") if j == i else cell(cross.predictions[i][j])
                     for j in tests]
            out.append(f"| test {i} | {c.velocity_coefficient:.4g} | {c.dispersion_coefficient:.4g} | "
                       + " | ".join(cells) + " |")
        out.append("")
    sec = cross.predictions[ref][ref].sections
    if sec:
        from ..cases import load_case

        lengths = {x.name: x.length for x in load_case(CASE).sections}
        out.append(f"Section values at Test {ref} with this calibration:")
        out.append("")
        out.append("| section | mean moisture kg/kg | repose angle deg | u_s mm/s | D m^2/s | Pe = u_s L / D |")
        out.append("|---|---|---|---|---|---|")
        for name, u in sec["kiln_velocity_m_s"].items():
            D = sec["dispersion_m2_s"].get(name)
            pe = "-" if not D else f"{u * lengths[name] / D:.0f}"
            out.append(f"| {name} | {sec['moisture_kg_kg'][name]:.4f} | {sec['repose_angle_deg'][name]:.1f} | "
                       f"{1000 * u:.2f} | {'-' if D is None else format(D, '.3g')} | {pe} |")
        out.append("")
    own = [i for i in (1, 2, 4, 5, 6) if i in cross.calibrations]
    if len(own) >= 3:
        out.append(f"Own calibration c_u against feed moisture, tests {', '.join(map(str, own))}: Pearson r = "
                   f"{moisture_correlation(cross, own):.2f}.")
        out.append("")
    if fouling:
        out.append(f"Test 3 predicted (calibration on Test {ref}) at other transport.fouling values:")
        out.append("")
        out.append(f"| fouling | predicted MRT / SD min | MRT error | holdup t (Table 3.14: "
                   f"{published(3)['holdup_kg'] / 1000:.1f}) | R^2 |")
        out.append("|---|---|---|---|---|")
        for fo, p in fouling.items():
            out.append(f"| {fo:g} | {p.tracer_mean_s / 60:.2f} / {p.tracer_std_s / 60:.2f} | "
                       f"{100 * p.mrt_error:+.1f} % | {p.holdup_kg / 1000:.1f} | {p.r_squared:.3f} |")
        out.append("")
    if consistency:
        out.append("Per-test mode: Ajayi's Table 5.2 u_s against the u_s of his simulations (F / unflighted "
                   "holdup per metre, Figs 5.16-5.20):")
        out.append("")
        out.append("| test | u_s Table 5.2 m/s | F/m_s m/s | Table 5.4 MRT min / holdup t | case with Table 5.2 u_s "
                   "| case with F/m_s |")
        out.append("|---|---|---|---|---|---|")
        for r in consistency:
            out.append(f"| {r['test']} | {r['u_table_5_2_m_s']:.4g} | {r['u_implied_m_s']:.4f} | "
                       f"{r['mrt_table_5_4_min']:.2f} / {r['holdup_table_5_4_kg'] / 1000:.1f} | "
                       f"{r['mrt_table_5_2_min']:.2f} / {r['holdup_table_5_2_kg'] / 1000:.1f} | "
                       f"{r['mrt_implied_min']:.2f} / {r['holdup_implied_kg'] / 1000:.1f} |")
        out.append("")
    return "\n".join(out).rstrip() + "\n"
