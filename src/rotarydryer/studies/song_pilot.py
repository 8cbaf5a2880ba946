r"""Study: Song's (2003) Ottawa pilot dryer predicted by the predictive transport law (issue 14, part 4).

Song (2003) Appendix A.1 lists 73 mean residence times of dry building sand in the Ottawa
pilot drum (3.05 m x 0.305 m, 9 lifters, co-current ambient air) over feed 3.1-15.3 kg/min,
gas 0-0.1824 m^3/s, 3-8 rpm and slope 0.067-0.117 m/m (``song_appendixA_mrt.csv``; the case's
``[[tests]]`` rows 1-73). This module keeps only the study -- fits, cross-validation, tables
and figures; it has no model of its own. Every prediction is the steady state of

    ``Simulation("song2003_ottawa", PilotModel.overrides(i, coefficients)).transport_steady_state()``

with the case's predictive transport law (``transport.parameter_source = "predictive"``:
Lee's (2008) slice network with the forward step of each cascade from the particle
trajectories through the co-current air, Sherritt's curtain velocity with the constant
``transport.curtain_coefficient`` K, the landing advance ``transport.step_factor`` c_0, the
excess over the design load kilned at the cascade speed, ``kiln_law = "cascade"``, the
flights' loading factor fixed at 1; docs/predictive_transport.md). The two coefficients are
fitted here by cross-validation, and the out-of-sample error is compared with the
correlations of `rotarydryer.correlations` (docs/song_pilot.md).

Air: Song's conversion of Ori_G (m^3/s) to kg with 1.1774 kg/m^3 (notes song.md 7.2), at
26.85 degC (dry air of 1.1774 kg/m^3 at 101325 Pa).

Units: SI (kg, s, m, kg/s) unless a name says otherwise; slopes in m/m (Song) and deg
(``drum.slope`` of the case schema).
"""

from __future__ import annotations

import dataclasses
import math
import re
import warnings
from dataclasses import dataclass

import numpy as np

from .._validation import check_range
from ..executor import Executor, RunFailure
from ..transport.forward_step import SHERRITT_EXPONENTS, sherritt_form  # noqa: F401  (SHERRITT_EXPONENTS: re-exported)

__all__ = [
    "CASE",
    "AIR_DENSITY",
    "AIR_TEMPERATURE",
    "PilotRuns",
    "pilot_runs",
    "Coefficients",
    "curtain_velocity_ratio",
    "PilotModel",
    "PilotPrediction",
    "fit_coefficients",
    "split_halves",
    "split_extrapolation",
    "cross_validate",
    "extrapolate",
    "correlation_predictions",
    "refit_song_eq45",
    "error_summary",
    "comparison_table",
    "baseline_predictions",
    "PER_TEST_SETTINGS",
    "table41_comparison",
    "speed_sequence",
    "step_test",
    "simulate_steps",
    "record_of",
    "step_record_csv",
    "markdown",
    "series_of",
    "command_line",
    "run_transport_model",
    "SONG_PILOT_FITS",
]

CASE = "song2003_ottawa"
#: kg/m^3: Song's conversion of Ori_G (m^3/s) to a mass flow (App. A: G = Ori_G 1.1774 3600/A)
AIR_DENSITY = 1.1774
#: degC: ambient air of Song's runs (dry air of 1.1774 kg/m^3 at 101325 Pa is at 26.9 degC)
AIR_TEMPERATURE = 26.85

#: (step_factor, curtain_coefficient) fitted by :func:`fit_coefficients` (least squares on log tau)
#: to all 73 runs, to each half of :func:`split_halves` and to the "base" runs of
#: :func:`split_extrapolation` (reproduced by tests/studies/test_song_pilot.py; start values of the fits), the
#: runs' gas at :data:`AIR_TEMPERATURE`
SONG_PILOT_FITS = {
    "all": (2.434868, 0.1224377),
    "odd": (2.427786, 0.1237944),
    "even": (2.438785, 0.1217600),
    "base": (2.405063, 0.1226585),
}


# ------------------------------------------------------------------------------------ data
@dataclass(frozen=True)
class PilotRuns:
    """Song (2003) Appendix A.1 runs (arrays of equal length, SI).

    ``src_line`` line of the thesis; ``feed_rate`` kg/s (dry sand); ``gas_flow`` kg/s (Ori_G x
    1.1774 kg/m^3); ``rpm``; ``slope`` m/m (Song); ``tau`` measured mean residence time, s."""

    src_line: np.ndarray
    feed_rate: np.ndarray
    gas_flow: np.ndarray
    rpm: np.ndarray
    slope: np.ndarray
    tau: np.ndarray

    def __len__(self):
        return int(self.src_line.size)

    @property
    def slope_deg(self) -> np.ndarray:
        """Drum inclination of the case schema, deg: atan(slope in m/m) (0.067/0.083/0.117 m/m =
        3.83/4.74/6.67 deg)."""
        return np.degrees(np.arctan(self.slope))

    def subset(self, idx) -> PilotRuns:
        idx = np.asarray(idx)
        return PilotRuns(*(getattr(self, f.name)[idx] for f in dataclasses.fields(self)))


def pilot_runs() -> PilotRuns:
    """The 73 runs of Song (2003) Appendix A.1 (``song_appendixA_mrt.csv``, L1497-1572), in file order."""
    from ..correlations import song_2003_appendix_a
    from ..published import read_published_csv

    d = song_2003_appendix_a()
    gas = np.array([float(r["Ori_G_m3_s"]) for r in read_published_csv("song_appendixA_mrt.csv")]) * AIR_DENSITY
    return PilotRuns(src_line=d["src_line"], feed_rate=d["solids_feed_rate"], gas_flow=gas, rpm=d["rpm"],
                     slope=d["slope"], tau=d["mean_residence_time"])


# ------------------------------------------------------------------------------------ coefficients
@dataclass(frozen=True)
class Coefficients:
    """The two global coefficients of the predictive law: ``step_factor`` c_0 (-, case key
    ``transport.step_factor``), advance of a cascade without gas over the drag-free fall
    h_m sin(theta); ``curtain_coefficient`` K (``transport.curtain_coefficient``), Sherritt's
    constant of `curtain_velocity_ratio` (h in m, q in kg/(s m))."""

    step_factor: float
    curtain_coefficient: float

    def __post_init__(self):
        check_range("step_factor", self.step_factor, 0.0, 100.0)
        check_range("curtain_coefficient", self.curtain_coefficient, 0.0, 1e4, low_inclusive=True)


def curtain_velocity_ratio(fall_height, release_rate, coefficient):
    r"""Gas velocity inside a curtain over the bulk gas velocity, Sherritt's form (Lee (2008) Eq. 2.14),
    with checked inputs: `rotarydryer.transport.forward_step.sherritt_form`, the curtain law of
    the network.

    $$
    c_v = \min(1,\ K\, h^{-0.76} q^{-0.86})
    $$

    Parameters
    ----------
    fall_height : array_like
        h, mean fall height, m (> 0).
    release_rate : array_like
        q, release of the flights into the curtain per metre of drum, kg/(s m) (> 0).
    coefficient : float
        K, replaces Sherritt's 1.546 L^0.44 (``transport.curtain_coefficient``).

    Returns
    -------
    ndarray
        c_v in [0, 1].

    Examples
    --------
    >>> round(float(curtain_velocity_ratio(0.2, 1.0, 0.4)), 4)
    1.0
    >>> round(float(curtain_velocity_ratio(0.2, 10.0, 0.1)), 4)
    0.0469
    """
    h = check_range("fall_height", fall_height, 0.0, math.inf, unit="m")
    q = check_range("release_rate", release_rate, 0.0, math.inf, unit="kg/(s m)")
    K = float(check_range("curtain_coefficient", coefficient, 0.0, math.inf, low_inclusive=True))
    return sherritt_form(h, q, K)


# ------------------------------------------------------------------------------------ model
def _simulation(case, overrides):
    """``(Simulation(case, overrides), its transport steady state)``, the case loader's warnings
    suppressed (the runs are inside the case's ranges by construction; the study reports errors)."""
    from .. import Simulation

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = Simulation(case, overrides)
        return sim, sim.transport_steady_state()


def _case_rows(case) -> dict:
    """{Appendix A source line: [[tests]] row} of the case's rows 1.. whose ``source`` names a line."""
    from .. import Simulation

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tests = Simulation(case).case.tests
    out = {}
    for row in tests:
        m = re.search(r"App\. A L(\d+)", row.source or "")
        if row.test and m:
            out[int(m.group(1))] = row
    return out


@dataclass
class PilotPrediction:
    """Predictions for the runs ``idx`` (arrays aligned with ``idx``), from each steady state of
    ``Simulation(case, overrides)``: ``tau`` s, ``holdup`` kg; from its model's ``cell_info``
    (means over the cells): ``drag_reduction`` C_F^G of the trajectory step at the design load
    (``C_F_G``), ``velocity_ratio`` c_v (``curtain_velocity_ratio``; NaN without gas),
    ``kiln_time`` s of the cascade kiln law, (t_p + t_a) dL/(c_0 h_m sin(theta)); ``release_rate``
    q kg/(s m), the mean flight discharge of the steady state over the cell length;
    ``design_load`` kg (whole drum)."""

    idx: np.ndarray
    tau: np.ndarray
    holdup: np.ndarray
    drag_reduction: np.ndarray
    kiln_time: np.ndarray
    velocity_ratio: np.ndarray
    release_rate: np.ndarray
    design_load: np.ndarray


class PilotModel:
    """The ``song2003_ottawa`` case at the operating points of ``runs``.

    Parameters
    ----------
    runs : PilotRuns, optional
        Default `pilot_runs` (all 73).
    case : str
        Case name or file (default ``song2003_ottawa``).

    A run whose Appendix A source line is one of the case's ``[[tests]]`` rows (with the same
    conditions) takes that row's numbers, so its explicit overrides reproduce
    ``{"operating.test": N}`` exactly; ``tests[i]`` is that N (None for other runs).
    """

    def __init__(self, runs: PilotRuns | None = None, case: str = CASE, executor: Executor | None = None):
        self.runs = pilot_runs() if runs is None else runs
        self.case = case
        #: runs the steady states of `predict` (default serially; each run starts cold, so every backend
        #: gives the same predictions)
        self.executor = executor or Executor()
        rows = _case_rows(case)
        r = self.runs
        self.tests: list[int | None] = []
        self._rows = []
        for i in range(len(r)):
            row = rows.get(int(r.src_line[i]))
            same = row is not None and all(
                v is not None and math.isclose(float(v), float(w), rel_tol=1e-6, abs_tol=1e-9) for v, w in
                ((row.feed_rate, r.feed_rate[i]), (row.rpm, r.rpm[i]), (row.slope, r.slope_deg[i]),
                 (row.gas_flow, r.gas_flow[i])))
            self.tests.append(int(row.test) if same and row is not None else None)
            self._rows.append(row if same else None)

    # -------------------------------------------------------------- per-run inputs
    def base_overrides(self, i: int) -> dict:
        """Case overrides of run ``i`` without the transport coefficients: no heat and mass
        transfer, dry feed (kg/s), speed, slope (deg = atan of Song's m/m), gas (kg/s) at ambient
        temperature, the predictive transport law. A run of the case's ``[[tests]]`` takes the row's
        numbers (the case's humidity and the rest as ``{"operating.test": N}``)."""
        r, row = self.runs, self._rows[i]
        if row is not None:
            feed, rpm, slope, gas = (float(row.feed_rate), float(row.rpm), float(row.slope), float(row.gas_flow))
        else:
            feed, rpm, slope, gas = (float(r.feed_rate[i]), float(r.rpm[i]), float(r.slope_deg[i]),
                                     float(r.gas_flow[i]))
        return {"thermal.enabled": False, "operating.feed_moisture": 0.0, "operating.feed_rate": feed,
                "operating.rpm": rpm, "drum.slope": slope, "gas.flow": gas,
                "gas.inlet_temperature": AIR_TEMPERATURE, "transport.parameter_source": "predictive"}

    def overrides(self, i: int, coefficients: Coefficients) -> dict:
        """Complete case overrides of run ``i``: `base_overrides` plus the two coefficients
        (``rotarydryer rtd song2003_ottawa --set KEY=VALUE ...`` reproduces the prediction)."""
        c = coefficients if isinstance(coefficients, Coefficients) else Coefficients(*coefficients)
        ov = self.base_overrides(i)
        ov.update({"transport.step_factor": float(c.step_factor),
                   "transport.curtain_coefficient": float(c.curtain_coefficient)})
        return ov

    def gas_velocity(self, i: int) -> float:
        """Superficial gas velocity U_g = G/(rho_g pi R^2), m/s, with Song's air density and the
        case's drum radius 0.1525 m."""
        return float(self.runs.gas_flow[i]) / (AIR_DENSITY * math.pi * 0.1525**2)

    # -------------------------------------------------------------- prediction
    def steady_state(self, i: int, coefficients: Coefficients):
        """The transport steady state of run ``i``: ``Simulation(case, overrides(i, c)).transport_steady_state()``."""
        return _simulation(self.case, self.overrides(i, coefficients))[1]

    def predict(self, coefficients: Coefficients, idx=None) -> PilotPrediction:
        """Steady states of the runs ``idx`` (default all) with the two coefficients, one
        ``Simulation(case, overrides(i, coefficients))`` per run (the network solves the curtain
        velocity's fixed point itself)."""
        if not isinstance(coefficients, Coefficients):
            coefficients = Coefficients(*coefficients)
        idx = np.arange(len(self.runs)) if idx is None else np.asarray(idx, dtype=int).ravel()
        n = idx.size
        out = {k: np.full(n, np.nan) for k in ("tau", "holdup", "drag_reduction", "kiln_time", "velocity_ratio",
                                               "release_rate", "design_load")}
        c0 = coefficients.step_factor
        items = [(self.overrides(int(i), coefficients), bool(self.runs.gas_flow[i] > 0)) for i in idx]
        ex = self.executor
        # each run starts cold: the chunking does not change the results
        warm = ((_predict_run, (items[0], self.case, c0)),) if items else ()     # imports, kernels, one run
        rows = ex.map(_predict_run, items, args=(self.case, c0), chunks=ex.independent_chunks(len(items)), warm=warm)
        for k, row in enumerate(rows):
            if isinstance(row, RunFailure):
                raise ValueError(f"run {int(idx[k])} of {self.case}: {row.error}")
            for key, v in row.items():
                out[key][k] = v
        return PilotPrediction(idx=idx, **out)


def _predict_run(item, case, c0) -> dict:
    """The numbers of `PilotPrediction` of one run (``item``: its overrides and whether it has gas);
    top-level, so that it pickles for worker processes."""
    overrides, has_gas = item
    sim, ss = _simulation(case, overrides)
    m = ss.model
    info = m.cell_info
    dl = float(m.specs[0].length / m.specs[0].n_cells)
    sin_t = math.sin(math.radians(float(sim.case.drum.slope)))
    tp, ta, h = (np.asarray(info[key], float) for key in ("passive_time_s", "fall_time_s", "fall_height_m"))
    return {"tau": ss.mean_residence_time, "holdup": ss.total_holdup, "drag_reduction": float(np.mean(info["C_F_G"])),
            "kiln_time": float(np.mean((tp + ta) * dl / (c0 * h * sin_t))),
            "velocity_ratio": float(np.mean(info["curtain_velocity_ratio"])) if has_gas else math.nan,
            "release_rate": float(np.mean(ss.flow("discharge"))) / dl, "design_load": float(np.nansum(m.design_load))}


# ------------------------------------------------------------------------------------ fitting
def fit_coefficients(model: PilotModel, idx=None, start=(2.45, 0.093)) -> tuple[Coefficients, dict]:
    """Least-squares fit of the two coefficients to the runs ``idx`` (default all): residuals
    ln(tau_model/tau_measured), i.e. relative errors, equally weighted; parameters on a log scale;
    every evaluation is `PilotModel.predict` (one Simulation per run, about 1 s for 73 runs;
    a fit takes 10-40 of them). Returns the coefficients and ``dict(cost, nfev, success)``."""
    from scipy.optimize import least_squares

    idx = np.arange(len(model.runs)) if idx is None else np.asarray(idx, dtype=int).ravel()
    meas = model.runs.tau[idx]

    def resid(p):
        return np.log(model.predict(Coefficients(*np.exp(p)), idx).tau / meas)

    r = least_squares(resid, np.log(np.asarray(start, float)), diff_step=1e-6, x_scale=1.0, xtol=1e-10, ftol=1e-12,
                      gtol=1e-12, max_nfev=200)
    return Coefficients(*np.exp(r.x)), dict(cost=float(r.cost), nfev=int(r.nfev), success=bool(r.success))


def split_halves(runs: PilotRuns):
    """Two halves of the runs in Appendix A order: the 1st, 3rd, 5th ... row ("odd", 37 runs) and
    the 2nd, 4th ... ("even", 36). Song lists the runs series by series (feed without and with gas,
    gas, speed, slope), so each half holds about half of every series (and of every repeat)."""
    n = len(runs)
    return {"odd": np.arange(0, n, 2), "even": np.arange(1, n, 2)}


def error_summary(predicted, measured) -> dict:
    """Relative errors of ``predicted`` against ``measured``: mean absolute (%), max absolute (%),
    mean (bias, %), RMSE (same unit as the inputs) and SSE."""
    p, m = np.asarray(predicted, float), np.asarray(measured, float)
    e = p / m - 1.0
    return dict(mape_pct=float(100 * np.mean(np.abs(e))), max_pct=float(100 * np.max(np.abs(e))),
                bias_pct=float(100 * np.mean(e)), rmse=float(np.sqrt(np.mean((p - m) ** 2))),
                sse=float(np.sum((p - m) ** 2)), n=int(p.size))


def split_extrapolation(runs: PilotRuns):
    """Extrapolation split: ``base`` = the runs at Song's base speed and slope (5 rpm, 0.083 m/m;
    feed and gas series, 53 runs), ``other`` = the speed and slope series (3, 6, 8 rpm; 0.067 and
    0.117 m/m; 20 runs), predicted from a fit on ``base`` only."""
    base = (runs.rpm == 5.0) & (runs.slope == 0.083)
    return {"base": np.nonzero(base)[0], "other": np.nonzero(~base)[0]}


def cross_validate(model: PilotModel, start=None) -> dict:
    """Two-fold cross-validation on `split_halves`: fit on one half, predict the other,
    and the reverse. Returns per fold (key: the training half) the coefficients, the fit summary,
    the out-of-sample prediction and its errors, and ``tau_out`` (s): every run predicted by the
    fit that did not see it, with ``errors`` over all 73."""
    halves = split_halves(model.runs)
    tau_out = np.full(len(model.runs), np.nan)
    folds = {}
    for train, test in (("odd", "even"), ("even", "odd")):
        coef, info = fit_coefficients(model, halves[train], start=start or SONG_PILOT_FITS[train])
        pred = model.predict(coef, halves[test])
        tau_out[halves[test]] = pred.tau
        folds[train] = dict(coefficients=coef, fit=info, test=test, prediction=pred,
                            errors=error_summary(pred.tau, model.runs.tau[halves[test]]))
    return dict(folds=folds, tau_out=tau_out, halves=halves, errors=error_summary(tau_out, model.runs.tau))


def extrapolate(model: PilotModel, start=None) -> dict:
    """Fit on the ``base`` runs of `split_extrapolation`, predict the speed and slope series:
    ``coefficients``, ``fit``, ``prediction`` and ``errors`` (on the 20 ``other`` runs)."""
    sp = split_extrapolation(model.runs)
    coef, info = fit_coefficients(model, sp["base"], start=start or SONG_PILOT_FITS["base"])
    pred = model.predict(coef, sp["other"])
    return dict(coefficients=coef, fit=info, prediction=pred, split=sp,
                errors=error_summary(pred.tau, model.runs.tau[sp["other"]]))


# ------------------------------------------------------------------------------------ correlations
def _fluxes(runs: PilotRuns, area: float):
    return runs.gas_flow / area, runs.feed_rate / area


def correlation_predictions(runs: PilotRuns, length=3.05, diameter=0.305, particle_size=444e-6) -> dict:
    """Mean residence time (s) of every run by the correlations Song evaluates (Song (2003) Eq.
    4.2-4.5: Friedman & Marshall, Foust et al., Perry & Green, Song & Thibault) from
    `rotarydryer.correlations`, co-current, G/F as the mass-flux ratio (notes song.md 7.3)."""
    from .. import correlations as co

    g, f = _fluxes(runs, math.pi * diameter**2 / 4)
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", co.CorrelationRangeWarning)
        for name, fn in (("friedman_marshall_1949", co.friedman_marshall_1949), ("foust_1960", co.foust_1960),
                         ("perry_green_1984", co.perry_green_1984), ("song_2003", co.song_2003)):
            out[name] = np.asarray(fn(length, diameter, runs.slope, runs.rpm, particle_size, g, f, "co-current",
                                      allow_nonpositive=True), float)
    return out


def refit_song_eq45(runs: PilotRuns, idx=None, length=3.05, diameter=0.305, particle_size=444e-6):
    r"""The two constants (a, b) of Song's Eq. 4.5 form tau = a L/(s n D) - (b/D_p^0.5) L G/F (tau
    in s, D_p in um) fitted by linear least squares on tau to the runs ``idx`` (Song fitted all 73:
    a = 14.3, b = 354). Returns (a, b) and a function tau(runs) -> s."""
    idx = np.arange(len(runs)) if idx is None else np.asarray(idx, dtype=int).ravel()
    g, f = _fluxes(runs, math.pi * diameter**2 / 4)
    x1 = length / (runs.slope * runs.rpm * diameter)
    x2 = -length / math.sqrt(particle_size * 1e6) * g / f
    X = np.column_stack([x1, x2])
    (a, b), *_ = np.linalg.lstsq(X[idx], runs.tau[idx], rcond=None)
    return (float(a), float(b)), (lambda r: np.asarray(
        a * length / (r.slope * r.rpm * diameter) - b * length / math.sqrt(particle_size * 1e6)
        * (r.gas_flow / r.feed_rate), float))


#: the case's fitted-step transport settings before the predictive law (``baseline_predictions`` "case")
PER_TEST_SETTINGS = {"transport.parameter_source": "per_test", "transport.forward_step": "fitted",
                     "transport.kiln_time": 10.0, "transport.drag_reduction": 1.0, "transport.backmix": 0.0,
                     "transport.loading": "state"}


def baseline_predictions(model: PilotModel) -> dict:
    """Mean residence time (s) of every run by the case's network with nothing fitted here:

    * ``"case"``: the case's fitted-step settings (`PER_TEST_SETTINGS`:
      ``transport.parameter_source = "per_test"``, Lee's step C_F^G = ``drag_reduction`` = 1,
      kilning time 10 s, loading from the state), the configuration of the case before the
      predictive law, at the run's conditions;
    * ``"trajectory"``: the same with ``transport.forward_step = "trajectory"`` and Sherritt's curtain
      velocity as printed (``step_factor`` 1, ``curtain_coefficient`` 1.546; Lee (2008) Eq. 2.14;
      `rotarydryer.transport.forward_step`);
    * ``"predictive"``: the case as shipped, the predictive law with the coefficients of its
      ``[[calibrations]]`` record (fitted to all 73 runs: in sample), i.e. `PilotModel.base_overrides`."""
    from ..transport.forward_step import SHERRITT_COEFFICIENT

    out = {}
    traj = {**PER_TEST_SETTINGS, "transport.forward_step": "trajectory", "transport.step_factor": 1.0,
            "transport.curtain_coefficient": SHERRITT_COEFFICIENT}
    for key, extra in (("case", PER_TEST_SETTINGS), ("trajectory", traj), ("predictive", {})):
        tau = np.empty(len(model.runs))
        for i in range(len(model.runs)):
            tau[i] = _simulation(model.case, {**model.base_overrides(i), **extra})[1].mean_residence_time
        out[key] = tau
    return out


def comparison_table(model: PilotModel, cv: dict | None = None, extrapolation: dict | None = None,
                     baselines: dict | None = None) -> list[dict]:
    """Rows comparing the predictive law with the correlations, each with ``errors`` on all 73
    runs and ``errors_other`` on the 20 speed/slope runs of `split_extrapolation`:

    * the predictive law, cross-validated (`cross_validate`; ``errors_other``: fitted on the
      53 base runs only, `extrapolate`);
    * Song's Eq. 4.5 form with its two constants refitted the same ways;
    * the published correlations as printed (Song's Eq. 4.5 was fitted by Song on these very runs:
      in sample; the others' constants come from other dryers);
    * the case's network with nothing fitted here (`baseline_predictions`; ``baselines`` reuses
      them): the former fitted-step settings, the trajectory step with Sherritt's constant as printed,
      and the case as shipped (the predictive law with its calibration record, in sample)."""
    runs = model.runs
    cv = cross_validate(model) if cv is None else cv
    ex = extrapolate(model) if extrapolation is None else extrapolation
    other = ex["split"]["other"]
    rows = [dict(name="predictive law (this study)", fitted=2, how="2-fold cross-validation (out of sample)",
                 errors=cv["errors"], errors_other=ex["errors"])]
    halves = split_halves(runs)
    tau = np.full(len(runs), np.nan)
    for train, test in (("odd", "even"), ("even", "odd")):
        _, fn = refit_song_eq45(runs, halves[train])
        tau[halves[test]] = fn(runs.subset(halves[test]))
    _, fn = refit_song_eq45(runs, ex["split"]["base"])
    rows.append(dict(name="Song Eq. 4.5 form, refitted", fitted=2, how="2-fold cross-validation (out of sample)",
                     errors=error_summary(tau, runs.tau),
                     errors_other=error_summary(fn(runs.subset(other)), runs.tau[other])))
    labels = {"song_2003": ("Song (2003) Eq. 4.5, printed", 2, "fitted by Song on all 73 runs (in sample)"),
              "perry_green_1984": ("Perry & Green (1984), Song Eq. 4.4", 0, "published constants"),
              "friedman_marshall_1949": ("Friedman & Marshall (1949), Song Eq. 4.2", 0, "published constants"),
              "foust_1960": ("Foust et al. (1960), Song Eq. 4.3", 0, "published constants")}
    corr = correlation_predictions(runs)
    for key in ("song_2003", "perry_green_1984", "friedman_marshall_1949", "foust_1960"):
        name, k, how = labels[key]
        rows.append(dict(name=name, fitted=k, how=how, errors=error_summary(corr[key], runs.tau),
                         errors_other=error_summary(corr[key][other], runs.tau[other])))
    base = baseline_predictions(model) if baselines is None else baselines
    for key, name, k, how in (
            ("predictive", "case as shipped (predictive, calibration record)", 2,
             "calibration record: fitted to all 73 runs (in sample)"),
            ("case", "case network, fitted-step settings (per_test: C_F^G = 1, t_kiln = 10 s)", 0, "nothing fitted"),
            ("trajectory", "case network, trajectory step (Sherritt as printed)", 0, "nothing fitted")):
        rows.append(dict(name=name, fitted=k, how=how, errors=error_summary(base[key], runs.tau),
                         errors_other=error_summary(base[key][other], runs.tau[other])))
    return rows


# ------------------------------------------------------------------------------------ step experiments
def _custom_runs(feed_kg_min, gas_m3_s, rpm, slope_m_m, tau_min=None, src_line=None) -> PilotRuns:
    """PilotRuns from Song's units (kg/min, m^3/s, rpm, m/m, min); broadcast."""
    f, g, n, s = np.broadcast_arrays(*(np.atleast_1d(np.asarray(x, float)) for x in
                                       (feed_kg_min, gas_m3_s, rpm, slope_m_m)))
    tau = np.full(f.shape, np.nan) if tau_min is None else np.broadcast_to(np.asarray(tau_min, float), f.shape) * 60
    line = np.zeros(f.shape, int) if src_line is None else np.broadcast_to(np.asarray(src_line), f.shape)
    return PilotRuns(src_line=np.array(line), feed_rate=f / 60, gas_flow=g * AIR_DENSITY, rpm=n.copy(),
                     slope=s.copy(), tau=np.array(tau))


def run_transport_model(model: PilotModel, i: int, coefficients: Coefficients):
    """(TransportModel, SteadyState) of run ``i`` through ``Simulation(case, model.overrides(i, ...))``."""
    ss = model.steady_state(i, coefficients)
    return ss.model, ss


def simulate_steps(segments, dt: float = 1.0, settle: float = 1e-7, max_duration: float = 86400.0) -> dict:
    """Feed and discharge records of a step experiment on the transport network (the mass dynamics
    dM/dt of `rotarydryer.transport.network.Network.simulate_masses`, BDF, rtol 1e-10).

    ``segments``: list of ``(transport_model, feed_kg_s)`` in order, all with the same nodes (one
    case; a new model is a step of speed, slope or gas, a new feed a feed step). The dryer starts
    empty. Each segment runs in whole ``dt`` samples until every node's dM/dt is below ``settle``
    times the largest feed (zero feed: until the holdup is below ``settle`` of the largest holdup).

    Returns ``time_s``; ``feed_kg_s``; ``discharge_kg_s`` (the outlet flow of the state); a step is a
    repeated time with the values before and after it; ``discharged_kg``, the mass on Song's
    balance (fed minus holdup: exact, no quadrature); ``holdup_kg``; ``steps_s`` (segment starts)
    and ``end_holdup_kg`` (holdup at the end of each segment)."""
    check_range("dt", dt, 0.0, 3600.0, unit="s")
    check_range("settle", settle, 0.0, 0.1)
    n = segments[0][0].network.n
    f_ref = max(float(F) for _, F in segments)
    if not f_ref > 0:
        raise ValueError("simulate_steps: every segment has zero feed")
    M = np.zeros(n)
    t = 0.0
    fed = 0.0
    rows = [(0.0, 0.0, 0.0, 0.0, 0.0)]          # time, feed, discharge, fed, holdup: empty, before the first step
    starts, ends = [], []
    h_ref = 0.0
    for model, F in segments:
        net = model.network
        if net.n != n:
            raise ValueError("simulate_steps: every segment must be a model of the same dryer (same nodes)")
        F = float(check_range("feed", F, 0.0, math.inf, low_inclusive=True, unit="kg/s"))
        vec = net.feed / net.feed.sum() * F
        tau = model.steady_state().mean_residence_time if F > 0 else 600.0
        chunk = dt * max(10, math.ceil(tau / 2 / dt))
        starts.append(t)
        rows.append((t, F, net.boundary_flow(M), fed, float(M.sum())))      # after the step
        t_seg = t
        while True:
            te = t + np.arange(1, int(round(chunk / dt)) + 1) * dt
            sol = net.simulate_masses(M, (t, te[-1]), t_eval=te, feed_fn=lambda _t, v=vec: v, rtol=1e-10,
                                      atol=1e-12 * max(h_ref, f_ref * 600.0))
            Ms = np.maximum(sol.y, 0.0)
            for j, tj in enumerate(te):
                hj = float(Ms[:, j].sum())
                rows.append((float(tj), F, net.boundary_flow(Ms[:, j]), fed + F * (tj - t_seg), hj))
            M, t = Ms[:, -1].copy(), float(te[-1])
            h_ref = max(h_ref, float(M.sum()))
            if F > 0:
                r = net.residual(M) - net.feed + vec
                done = float(np.max(np.abs(r))) <= settle * f_ref
            else:
                done = float(M.sum()) <= settle * h_ref
            if done:
                break
            if t - t_seg > max_duration:
                raise ValueError(f"simulate_steps: no steady state within {max_duration:g} s of the step at "
                                 f"{t_seg:g} s")
        fed += F * (t - t_seg)
        ends.append(float(M.sum()))
    a = np.array(rows, float)
    balance = np.maximum.accumulate(np.maximum(a[:, 3] - a[:, 4], 0.0))      # rounding: never falls
    return dict(time_s=a[:, 0], feed_kg_s=a[:, 1], discharge_kg_s=a[:, 2], discharged_kg=balance,
                holdup_kg=a[:, 4], steps_s=np.array(starts), end_holdup_kg=np.array(ends))


def record_of(rec: dict, name: str = "simulated record"):
    """`rotarydryer.lab.steps.StepRecord` of a `simulate_steps` record: the feed rate
    and the mass on the balance (as Song recorded)."""
    from ..lab import steps as sm

    return sm.step_record(rec["time_s"], rec["feed_kg_s"], discharged=rec["discharged_kg"], name=name)


def step_record_csv(rec: dict, note: str = "") -> str:
    """A simulated record as the CSV that ``rotarydryer lab steps`` reads: time_s, feed_kg_min (a
    repeated time at each step) and discharged_kg (the mass on Song's balance)."""
    lines = [f"# simulated step experiment, rotarydryer.studies.song_pilot{(': ' + note) if note else ''}",
             "time_s,feed_kg_min,discharged_kg"]
    lines += [f"{t:.6f},{f * 60:.12g},{d:.12g}" for t, f, d in
              zip(rec["time_s"], rec["feed_kg_s"], rec["discharged_kg"])]
    return "\n".join(lines) + "\n"


def step_test(model: PilotModel, i: int, coefficients: Coefficients, dt: float = 1.0) -> dict:
    """Song's up/down step test (Fig. 4.2-4.3) simulated on run ``i``: empty dryer, feed 0 -> F
    until steady, then F -> 0 until empty; the record analysed by
    `rotarydryer.lab.steps.analyse_steps`. Returns ``record`` (`simulate_steps`),
    ``analysis``, ``steady_holdup_kg`` (the model's steady state) and ``feed_kg_s``."""
    from ..lab import steps as sm

    tm, ss = run_transport_model(model, i, coefficients)
    F = float(model.runs.feed_rate[i])
    rec = simulate_steps([(tm, F), (tm, 0.0)], dt=dt)
    a = sm.analyse_steps(record_of(rec, f"run at src line {int(model.runs.src_line[i])}"))
    return dict(record=rec, analysis=a, steady_holdup_kg=float(ss.total_holdup), feed_kg_s=F)


def table41_comparison(model: PilotModel | None = None, fits: dict | None = None, dt: float = 1.0) -> list[dict]:
    """Song's Table 4.1 against the simulated step test of each run (`step_test`).

    Runs 2-5 take the conditions of their Appendix A row (``appendix_src_line``) and the
    coefficients of the cross-validation half that did *not* contain that row (``fits``: {"odd",
    "even", "all"} -> Coefficients, default `SONG_PILOT_FITS`); run 1 has no Appendix A row
    and is simulated at run 2's speed, slope and no gas (an assumption) with Song's feed 5.40 kg/min
    and the coefficients fitted to all 73 runs."""
    from ..published import read_published_csv

    model = PilotModel() if model is None else model
    fits = {k: Coefficients(*v) if not isinstance(v, Coefficients) else v
            for k, v in (fits or SONG_PILOT_FITS).items()}
    halves = split_halves(model.runs)
    rows = []
    for r in read_published_csv("song_table4_1_dynamic_method.csv"):
        num = lambda k: float(r[k]) if r[k].strip() else None  # noqa: E731
        if r["appendix_src_line"].strip():
            i = int(np.nonzero(model.runs.src_line == int(r["appendix_src_line"]))[0][0])
            key = "even" if i in halves["odd"] else "odd"
            m, j, assumed = model, i, ""
        else:
            base = int(np.nonzero(model.runs.src_line == 1551)[0][0])
            rr = model.runs
            m = PilotModel(_custom_runs(num("F_mass_time_kg_min"), rr.gas_flow[base] / AIR_DENSITY, rr.rpm[base],
                                        rr.slope[base], num("tau_min"), 0), case=model.case)
            j, key, assumed = 0, "all", "conditions not printed: run 2's speed, slope and no gas assumed"
        res = step_test(m, j, fits[key], dt=dt)
        a = res["analysis"]
        song_h = [x for x in (num("H_up_kg"), num("H_down_kg")) if x is not None]
        F = res["feed_kg_s"]
        rows.append(dict(run=int(r["run"]), appendix_src_line=r["appendix_src_line"] or None, assumed=assumed,
                         coefficients=key, feed_kg_min=F * 60, gas_kg_min=float(m.runs.gas_flow[j]) * 60,
                         rpm=float(m.runs.rpm[j]), slope_m_m=float(m.runs.slope[j]),
                         song_h_up_kg=num("H_up_kg"), song_h_down_kg=num("H_down_kg"), song_h_meas_kg=num("H_meas_kg"),
                         song_tau_min=num("tau_min"), model_h_up_kg=a.h_up_kg, model_h_down_kg=a.h_down_kg,
                         model_steady_holdup_kg=res["steady_holdup_kg"],
                         model_tau_min=a.h_up_kg / F / 60, up_down_pct=a.up_down_pct,
                         closure_pct=a.closure["residual_pct"],
                         holdup_error_pct=100 * (a.h_up_kg / float(np.mean(song_h)) - 1)))
    return rows


def speed_sequence(coefficients: Coefficients | None = None, rpm=(3.0, 5.0, 8.0, 6.0), feed_kg_min=5.37,
                   slope_m_m=0.083, dt: float = 1.0, case: str = CASE) -> dict:
    """Song's Fig. 4.6 experiment simulated: an empty dryer fed ``feed_kg_min`` at the first speed,
    then steps of the speed (the feed unchanged), then the feed stopped; no gas. The speeds and the
    feed are inferred (notes song.md 6.3: the reconciled Table 4.2 holdups match the Appendix A
    rows at 3 -> 5 -> 8 -> 6 rpm and about 5.37 kg/min). The speed steps do not show in the feed
    record, so the analysis is given the step times. Returns ``record``, ``analysis``, ``song``
    (Table 4.2's areas of Fig. 4.6) and ``model_holdups_kg`` (steady state at each speed)."""
    from ..lab import steps as sm
    from ..published import read_published_csv

    coefficients = Coefficients(*SONG_PILOT_FITS["all"]) if coefficients is None else coefficients
    model = PilotModel(_custom_runs(feed_kg_min, 0.0, np.asarray(rpm, float), slope_m_m), case=case)
    F = float(model.runs.feed_rate[0])
    segs, holdups = [], []
    for i in range(len(model.runs)):
        tm, ss = run_transport_model(model, i, coefficients)
        segs.append((tm, F))
        holdups.append(float(ss.total_holdup))
    segs.append((segs[-1][0], 0.0))
    rec = simulate_steps(segs, dt=dt)
    a = sm.analyse_steps(record_of(rec, "speed steps " + " -> ".join(f"{r:g}" for r in rpm) + " rpm"),
                         steps=rec["steps_s"])
    row = next(r for r in read_published_csv("song_table4_2_holdup_areas.csv") if r["figure"] == "4.6")
    song = [float(row[f"dH{k}_kg"]) for k in range(1, 6) if row[f"dH{k}_kg"].strip()]
    return dict(record=rec, analysis=a, song_areas_kg=song, song_residual_pct=float(row["resid_pct"]),
                model_holdups_kg=holdups, rpm=list(rpm), feed_kg_min=feed_kg_min)


# ------------------------------------------------------------------------------------ report
def series_of(runs: PilotRuns) -> list[str]:
    """Label of the Appendix A series each run belongs to: "no gas" / "gas" at Song's base speed
    and slope (5 rpm, 0.083 m/m), "speed" (3, 6, 8 rpm) or "slope" (0.067, 0.117 m/m)."""
    out = []
    for n, s, g in zip(runs.rpm, runs.slope, runs.gas_flow):
        if n != 5.0:
            out.append("speed")
        elif s != 0.083:
            out.append("slope")
        else:
            out.append("gas" if g > 0 else "no gas")
    return out


def command_line(model: PilotModel, i: int, coefficients: Coefficients) -> str:
    """The ``rotarydryer rtd`` command that reproduces the prediction of run ``i``: a run of the
    case's ``[[tests]]`` by its row (``--set operating.test=N``) and the two coefficients, any other
    run by all of `PilotModel.overrides`."""
    c = coefficients if isinstance(coefficients, Coefficients) else Coefficients(*coefficients)
    ov: dict = ({"operating.test": model.tests[i], "transport.step_factor": float(c.step_factor),
                 "transport.curtain_coefficient": float(c.curtain_coefficient)} if model.tests[i] is not None
                else model.overrides(i, c))
    parts = []
    for k, v in ov.items():
        text = str(v).lower() if isinstance(v, bool) else f"{v:.10g}" if isinstance(v, float) else str(v)
        parts.append(f"--set {k}={text}")
    return f"rotarydryer rtd {model.case} " + " ".join(parts) + " --json"


def markdown(model: PilotModel, fits: dict, cv: dict, extrapolation: dict, table: list, table41: list,
             speed: dict) -> str:
    """The generated block of docs/song_pilot.md (tables), from the results of this module."""
    runs = model.runs
    L = []
    L.append("**Coefficients** (least squares on ln tau; c_0 = `step_factor`, K = `curtain_coefficient`):\n")
    L.append("| fitted on | runs | c_0 | K | in-sample MAPE % |")
    L.append("|---|---|---|---|---|")
    names = {"all": "all runs", "odd": "odd rows (half A)", "even": "even rows (half B)",
             "base": "5 rpm, 0.083 m/m (base)"}
    for key, (c, n, err) in fits.items():
        L.append(f"| {names[key]} | {n} | {c.step_factor:.4f} | {c.curtain_coefficient:.4f} | {err:.2f} |")
    L.append("")
    L.append("**Mean residence time, all 73 runs and the 20 speed/slope runs** (errors relative to the "
             "measured tau; \"out of sample\": each run predicted by coefficients fitted without it):\n")
    L.append("| model | fitted constants | how | MAPE % (73) | max % (73) | bias % (73) | MAPE % (20) | max % (20) |")
    L.append("|---|---|---|---|---|---|---|---|")
    for r in table:
        e, o = r["errors"], r["errors_other"]
        how = r["how"]
        if r["name"].startswith("predictive law") or r["name"].startswith("Song Eq. 4.5 form"):
            how += "; (20): fitted on the 53 base runs"
        L.append(f"| {r['name']} | {r['fitted']} | {how} | {e['mape_pct']:.2f} | {e['max_pct']:.1f} | "
                 f"{e['bias_pct']:+.2f} | {o['mape_pct']:.2f} | {o['max_pct']:.1f} |")
    L.append("")
    L.append("**Cross-validated errors by series** (predictive law, out of sample):\n")
    L.append("| series | runs | MAPE % | max % | bias % |")
    L.append("|---|---|---|---|---|")
    ser = np.array(series_of(runs))
    for name in ("no gas", "gas", "speed", "slope"):
        k = ser == name
        e = error_summary(cv["tau_out"][k], runs.tau[k])
        L.append(f"| {name} | {int(k.sum())} | {e['mape_pct']:.2f} | {e['max_pct']:.1f} | {e['bias_pct']:+.2f} |")
    L.append("")
    L.append("**Song's Table 4.1 against the simulated step test** (transport dynamics of the case; feed 0 -> F "
             "until steady, then F -> 0 until empty; `rotarydryer.lab.steps` on the records):\n")
    L.append("| run | App. A line | F kg/min | G kg/min | rpm | s m/m | Song H up / down / weighed kg | "
             "Song tau min | model H1 / H2 kg | model tau min | H error % | closure residual % |")
    L.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in table41:
        song = " / ".join("-" if r[k] is None else f"{r[k]:.2f}"
                          for k in ("song_h_up_kg", "song_h_down_kg", "song_h_meas_kg"))
        line = r["appendix_src_line"] or "none*"
        L.append(f"| {r['run']} | {line} | {r['feed_kg_min']:.2f} | {r['gas_kg_min']:.2f} | {r['rpm']:g} | "
                 f"{r['slope_m_m']:.3f} | {song} | {r['song_tau_min']:.2f} | {r['model_h_up_kg']:.2f} / "
                 f"{r['model_h_down_kg']:.2f} | {r['model_tau_min']:.2f} | {r['holdup_error_pct']:+.1f} | "
                 f"{r['closure_pct']:.1e} |")
    L.append("")
    L.append("\\* run 1: conditions not printed; simulated at run 2's speed, slope and no gas.\n")
    a = speed["analysis"]
    song = speed["song_areas_kg"]
    R, pct, rec = _reconcile(song)
    L.append(f"**Speed steps {' -> '.join(f'{r:g}' for r in speed['rpm'])} rpm, then the feed stopped** "
             f"(Fig. 4.6 as inferred: {speed['feed_kg_min']:g} kg/min, no gas): areas dH kg\n")
    L.append("| | " + " | ".join(f"dH{k + 1}" for k in range(len(song))) + " | sum dH | residual % |")
    L.append("|---|" + "---|" * (len(song) + 2))
    L.append("| Song Table 4.2 | " + " | ".join(f"{x:.2f}" for x in song) + f" | {R:+.2f} | {pct:.2f} |")
    L.append("| Song, reconciled | " + " | ".join(f"{x:.2f}" for x in rec) + " | 0 | - |")
    sm_areas = [sg["area_kg"] for sg in a.segments]
    L.append("| model (simulated record) | " + " | ".join(f"{x:.2f}" for x in sm_areas)
             + f" | {a.closure['residual_kg']:+.1e} | {a.closure['residual_pct']:.1e} |")
    L.append("")
    return "\n".join(L) + "\n"


def _reconcile(areas):
    from ..lab.steps import reconcile

    return reconcile(areas)
