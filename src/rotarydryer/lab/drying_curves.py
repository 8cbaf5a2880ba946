r"""Drying kinetics from lab drying curves: thin-layer laws with Arrhenius rate constants, fitted,
ranked and written into a material file (``rotarydryer lab drying``, issue 34).

A drying curve is the dry-basis moisture X of a thin layer of the material against time at one
air temperature. The six laws of [`rotarydryer.properties.thin_layer`][rotarydryer.properties.thin_layer] (Lewis, Page,
Henderson-Pabis, logarithmic, two-term, Midilli) are fitted to the moisture ratio
$MR = (X - X_e)/(X_0 - X_e)$ of **all curves at once**: the rate constants follow Arrhenius
from a reference temperature $T_{ref}$ (default: the mean of the curves' air temperatures, in
K), with one activation energy per law; the shape parameters (a, b, c, n) are shared by all
temperatures. Why shared: a law whose shape changed with temperature would need an
interpolation rule between the lab temperatures before a dryer could use it, and a
temperature-independent shape with Arrhenius rate constants is the form the dryer evaluates at
every gas temperature; a law that does not fit with a shared shape shows it in its residuals
and its rank.

Estimation: weighted least squares of [`rotarydryer.estimation.fit`][rotarydryer.estimation.fit] on MR (unit weights,
the residual variance estimated from the fit), rate constants and Page's n in log space,
several starts; 95 % t intervals (asymmetric for log parameters) and the correlation matrix.
The t = 0 rows define X_0 (MR = 1 by definition, not a measurement) and are not residuals.
Ranking: Gaussian log-likelihood criteria with the residual variance counted as a parameter
(p + 1): $AIC = n\ln(SSE/n) + 2(p+1)$, its small-sample form
$AIC_c = AIC + 2(p+1)(p+2)/(n-p-2)$ and $BIC = n\ln(SSE/n) + (p+1)\ln n$; also RMSE
$= \sqrt{SSE/n}$ and $R^2$ of MR. The laws are ranked by **AICc** (Burnham & Anderson (2002)
recommend it over AIC when n/p < 40, the usual case with a few lab curves; the two rank alike
for many points); a law with n <= p + 2 has no AICc and ranks last. Akaike weights
$\exp(-\Delta_i/2)/\sum_j\exp(-\Delta_j/2)$ from the AICc differences. The chosen law
is the first of the ranking that is a drying law (a fit whose values make the moisture
rise, e.g. a Midilli b > 0, or an activation energy below 0, is ranked but not chosen). A law
that nests a simpler one (Midilli -> Page at a = 1, b = 0; Page ->
Lewis at n = 1; ...) says so when the simpler law's values lie inside its 95 % intervals.

Drying-curve CSV (`read_drying_csv`)
------------------------------------
A header line whose names carry their units, then one row per weighing; ``#`` lines are
comments. Columns (others are ignored):

* time: ``time_s`` | ``time_min`` | ``time_h`` (one of them), >= 0;
* moisture: ``moisture_kg_kg_dry`` (X, [0, 50) kg/kg dry) or ``moisture_kg_kg_wet`` (x,
  [0, 1) kg/kg wet; converted, X = x/(1 - x));
* ``air_temperature_degC``: the drying air's temperature, [0, 400] degC, within 2 degC over
  a curve (the curve's temperature is its rows' mean);
* optional ``curve``: a label per curve (several curves at one temperature: replicates);
  without it the rows of one air temperature (within 2 degC of the curve's first row) form one curve;
* optional ``equilibrium_moisture_kg_kg_dry`` | ``equilibrium_moisture_kg_kg_wet``: X_e per
  curve (one value per curve); without it, ``equilibrium_moisture`` (kg/kg dry, all curves)
  or 0.

Each curve starts at time 0 (its initial moisture X_0), its times increase, it has at least
`MIN_CURVE_ROWS` rows, and its moisture falls: a moisture ratio may exceed the lowest earlier
one of its curve, and lie below X_e, by at most the curve's noise allowance (`rise_allowance`):
`RISE_TOLERANCE` (0.05, i.e. 5 % of the curve's free moisture X_0 - X_e), or more on a noisy
curve, where the lowest of many noisy weighings lies further below the curve (the weighing
noise is estimated from the scatter of successive differences); and on a curve of 20 weighings or
more, the mean of a few successive weighings may not rise above the earlier means by more than
their own, smaller noise without a `RisingCurveWarning` (`sustained_rise`: a tail that takes up water,
or weighings that drift). Every other violation is a
``ValueError`` naming the file, the line, the column, the value and the allowed range.

Example data: [`synthetic_drying_curves`][rotarydryer.lab.drying_curves.synthetic_drying_curves] draws noisy curves from a known law;
`EXAMPLE` is the shipped ``rotarydryer/data/drying_curves_example.csv`` (a Page law,
three air temperatures, seed 0), [`load_example`][rotarydryer.lab.drying_curves.load_example] reads it.
"""

from __future__ import annotations

import math
import time
import tomllib
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np
from scipy import stats

from .._plotting import pyplot
from .._validation import check_choice, check_range, fmt_number
from ..estimation.fit import Dataset, FitError, IdentifiabilityWarning, Parameter, fit
from ..properties import thin_layer as tl
from ..properties.materials import library_table, list_materials, load_material
from ..rtd._datafile import MAX_DATA_ROWS, csv_rows, data_lines, parse_number, text_lines, too_many_rows

__all__ = ["TIME_COLUMNS", "MOISTURE_COLUMNS", "EQUILIBRIUM_COLUMNS", "TEMPERATURE_COLUMN", "CURVE_COLUMN",
           "RISE_TOLERANCE", "NOISE_MIN_ROWS", "TREND_WINDOW_FRACTION", "TREND_MIN_WINDOW", "RisingCurveWarning", "rise_allowance", "sustained_rise", "TEMPERATURE_SPREAD", "MIN_CURVE_ROWS", "NESTED", "DryingCurves", "drying_curves",
           "read_drying_csv", "parse_drying_text", "ModelFit", "DryingFit", "fit_model", "fit_models",
           "material_table", "material_toml", "plot_fit", "synthetic_drying_curves", "curves_csv_text", "EXAMPLE",
           "EXAMPLE_LAW", "example_path", "load_example"]

#: time columns and their factor to s
TIME_COLUMNS = {"time_s": 1.0, "time_min": 60.0, "time_h": 3600.0}
#: moisture columns and their basis
MOISTURE_COLUMNS = {"moisture_kg_kg_dry": "dry", "moisture_kg_kg_wet": "wet"}
#: equilibrium-moisture columns and their basis
EQUILIBRIUM_COLUMNS = {"equilibrium_moisture_kg_kg_dry": "dry", "equilibrium_moisture_kg_kg_wet": "wet"}
TEMPERATURE_COLUMN = "air_temperature_degC"
CURVE_COLUMN = "curve"
#: a moisture ratio may exceed the lowest earlier one of its curve (or fall below 0) by this much, or by the
#: allowance of a noisy curve (`rise_allowance`)
RISE_TOLERANCE = 0.05
#: fewest weighings of a curve whose noise is estimated for its rise allowance (`rise_allowance`)
NOISE_MIN_ROWS = 8
#: the sustained-rise test (`sustained_rise`) averages this fraction of a noisy curve's weighings (at least
#: `TREND_MIN_WINDOW`)
TREND_WINDOW_FRACTION = 1.0 / 6.0
TREND_MIN_WINDOW = 4
#: largest spread of the air temperature over a curve's rows, degC
TEMPERATURE_SPREAD = 2.0
#: fewest rows of a curve (t = 0 and two weighings)
MIN_CURVE_ROWS = 3
#: air temperature range, degC
AIR_TEMPERATURE_RANGE = (0.0, 400.0)
#: largest dry-basis moisture, kg/kg dry (x = 0.98 wet)
MAX_DRY_MOISTURE = 50.0
#: largest time of a record, s (about 30 years)
MAX_TIME_S = 1.0e9
#: laws nested in each law: (simpler law, the values of the extra parameters that give it)
NESTED: dict[str, tuple[tuple[str, dict[str, float]], ...]] = {
    "lewis": (),
    "page": (("lewis", {"n": 1.0}),),
    "henderson_pabis": (("lewis", {"a": 1.0}),),
    "logarithmic": (("henderson_pabis", {"c": 0.0}), ("lewis", {"a": 1.0, "c": 0.0})),
    "two_term": (),
    "midilli": (("page", {"a": 1.0, "b": 0.0}), ("lewis", {"a": 1.0, "n": 1.0, "b": 0.0})),
}
_KELVIN = 273.15


# ------------------------------------------------------------------------------------ the data
@dataclass(frozen=True)
class DryingCurves:
    """Drying curves (SI): per point ``curve`` (index into ``ids``), ``time_s`` (s) and ``moisture``
    (X, kg/kg dry); per curve ``ids``, ``air_temperature_degC``, ``initial_moisture`` X_0 and
    ``equilibrium_moisture`` X_e (kg/kg dry); ``name`` (file name for messages), ``columns``
    (the columns read), ``time_unit`` (of the source: "s", "min" or "h", for display)."""

    curve: np.ndarray
    time_s: np.ndarray
    moisture: np.ndarray
    ids: tuple[str, ...]
    air_temperature_degC: np.ndarray
    initial_moisture: np.ndarray
    equilibrium_moisture: np.ndarray
    name: str = "curves"
    columns: dict = field(default_factory=dict)
    time_unit: str = "s"

    @property
    def moisture_ratio(self) -> np.ndarray:
        """MR = (X - X_e)/(X_0 - X_e) per point."""
        xe = self.equilibrium_moisture[self.curve]
        return (self.moisture - xe) / (self.initial_moisture[self.curve] - xe)

    @property
    def temperature_K(self) -> np.ndarray:
        """Air temperature of each point's curve, K."""
        return self.air_temperature_degC[self.curve] + _KELVIN

    @property
    def n_temperatures(self) -> int:
        """Number of distinct air temperatures (curves within `TEMPERATURE_SPREAD` count once)."""
        return len(_temperature_groups(self.air_temperature_degC))

    def as_dict(self) -> list[dict]:
        """One entry per curve, unit-suffixed names."""
        return [{"curve": c, "air_temperature_degC": float(self.air_temperature_degC[i]),
                 "initial_moisture_kg_kg_dry": float(self.initial_moisture[i]),
                 "equilibrium_moisture_kg_kg_dry": float(self.equilibrium_moisture[i]),
                 "points": int(np.sum(self.curve == i)),
                 "duration_s": float(np.max(self.time_s[self.curve == i]))} for i, c in enumerate(self.ids)]


def _temperature_groups(temperatures) -> list[list[float]]:
    """The air temperatures grouped from the lowest up: a group holds the temperatures within
    `TEMPERATURE_SPREAD` of its lowest (50, 51.9, 53.8 and 55.7 degC are two air temperatures, not one chain)."""
    groups: list[list[float]] = []
    for t in sorted(float(v) for v in np.ravel(temperatures)):
        if groups and t - groups[-1][0] <= TEMPERATURE_SPREAD:
            groups[-1].append(t)
        else:
            groups.append([t])
    return groups


def _temperature_label(temp: float, firsts: dict) -> str:
    """The curve label of a row without a ``curve`` column: that of the first row of the curve whose first air
    temperature lies within `TEMPERATURE_SPREAD` of ``temp`` (the nearest), or a new one (``firsts``: label ->
    first temperature, updated). A curve's rows may differ by up to the spread (the measured air temperature
    logged on every row)."""
    near = [(abs(temp - t0), lab) for lab, t0 in firsts.items() if abs(temp - t0) <= TEMPERATURE_SPREAD]
    if near:
        return min(near)[1]
    label = fmt_number(temp)
    firsts[label] = temp
    return label


class RisingCurveWarning(UserWarning):
    """A noisy drying curve whose mean over a few weighings rises beyond their noise (`sustained_rise`)."""


def rise_allowance(mr) -> float:
    """How far (in moisture ratio) a point of the curve with moisture ratios ``mr`` (time order) may lie
    above the lowest earlier one, or below the equilibrium moisture, before the curve is refused as rising:
    `RISE_TOLERANCE`, or on a noisy curve of at least `NOISE_MIN_ROWS` weighings ``sigma (2 sqrt(2 ln n) + 2)``.
    ``sigma`` is the weighing noise, estimated robustly from the second differences of the moisture ratio
    (their median absolute deviation / 0.6745 / sqrt(6): the smooth drying law's curvature is small beside
    the noise on most of a densely weighed curve, and the median ignores where it is not); the lowest of n
    weighings with noise sigma lies about ``sigma sqrt(2 ln n)`` below the curve and one weighing as far above
    it, so a falling curve with ordinary weighing noise passes, and a rise well above the noise (a curve that
    takes up water, a mislabelled row) does not. A sparser curve keeps `RISE_TOLERANCE` (its differences are
    the drying, not the noise)."""
    mr = np.asarray(mr, dtype=float)
    n = mr.size
    if n < NOISE_MIN_ROWS:
        return RISE_TOLERANCE
    return max(RISE_TOLERANCE, _noise_sd(mr) * (2.0 * math.sqrt(2.0 * math.log(n)) + 2.0))


def _noise_sd(mr) -> float:
    """The weighing noise of a curve's moisture ratios (time order), from their second differences (`rise_allowance`)."""
    d2 = np.diff(np.asarray(mr, dtype=float), 2)
    return float(np.median(np.abs(d2 - np.median(d2)))) / 0.6745 / math.sqrt(6.0)


def sustained_rise(mr):
    """``(first, window, rise, allowance)`` of a noisy curve whose moisture rises for several weighings, or None.
    One weighing may lie above the curve by its noise (`rise_allowance`), but the mean of ``window`` successive
    weighings (`TREND_WINDOW_FRACTION` of the curve, at least `TREND_MIN_WINDOW`) has the noise over the square root of the window:
    a run of weighings whose mean lies more than ``sigma / sqrt(window) (2 sqrt(2 ln m) + 2)`` (m windows; at least
    `RISE_TOLERANCE`) above the lowest mean of earlier windows is likely a curve that takes up water, or weighings
    that drift (correlated errors, which the noise estimate from second differences does not see: with AR(1) noise
    of phi 0.5-0.8 and 4 % it flags 1-3.5 % of falling curves), so `drying_curves` warns (`RisingCurveWarning`)
    rather than refuses. (Before, each weighing alone was tested, so a steady rise of a noisy curve's tail within one
    weighing's allowance passed without a word and could change the law chosen; found by an acceptance check.)
    ``first``: the index of the window's first
    weighing; None for a curve of fewer than five windows (20 weighings: its noise estimate is too rough; the
    single-point test applies alone). Falling Page curves with 0.2-8 % noise, 8-80 weighings: 6 of 30 000 refused
    by this test (the single-point test: 74); a rise of 0.2 of the free moisture over the last half of 25 weighings
    with 2 % noise: refused 89 times in 100."""
    mr = np.asarray(mr, dtype=float)
    n = mr.size
    k = max(TREND_MIN_WINDOW, int(round(TREND_WINDOW_FRACTION * n)))
    if n < max(NOISE_MIN_ROWS, 5 * k):
        return None
    mean = np.convolve(mr, np.full(k, 1.0 / k), mode="valid")
    m = mean.size
    allow = max(RISE_TOLERANCE, _noise_sd(mr) / math.sqrt(k) * (2.0 * math.sqrt(2.0 * math.log(m)) + 2.0))
    rise = mean - np.minimum.accumulate(mean)
    over = np.nonzero(rise > allow)[0]
    if not over.size:
        return None
    j = int(over[0])
    return j, k, float(rise[j]), allow


def _check_curves(name, ids, rows, lines):
    """Per-curve checks of `drying_curves` (``rows``: per curve an (n, 4) array of time_s, X,
    air temperature degC, X_e; ``lines``: per curve the line numbers or None). Returns the per-curve
    (temperature, X_0, X_e)."""
    out = []
    for cid, a, ln in zip(ids, rows, lines):
        def where(j, ln=ln, cid=cid):
            return f"{name} line {ln[j]}" if ln is not None else f"{name} curve {cid!r} point {j + 1}"

        t, x, temp, xe = a[:, 0], a[:, 1], a[:, 2], a[:, 3]
        if a.shape[0] < MIN_CURVE_ROWS:
            raise ValueError(f"{name}: curve {cid!r} has {a.shape[0]} row{'s' if a.shape[0] != 1 else ''}; a drying "
                             f"curve needs at least {MIN_CURVE_ROWS} (its initial moisture at time 0 and two weighings)")
        if t[0] != 0.0:
            raise ValueError(f"{where(0)}: curve {cid!r} starts at time {fmt_number(t[0])} s; the first row of a "
                             "curve is its initial moisture at time 0")
        back = np.nonzero(np.diff(t) <= 0)[0]
        if back.size:
            j = int(back[0]) + 1
            raise ValueError(f"{where(j)}: time {fmt_number(t[j])} s of curve {cid!r} is not after the previous "
                             f"{fmt_number(t[j - 1])} s; the times of a curve must increase")
        spread = np.abs(temp - temp[0])
        if np.any(spread > TEMPERATURE_SPREAD):
            j = int(np.argmax(spread))
            raise ValueError(f"{where(j)}: {TEMPERATURE_COLUMN} = {fmt_number(temp[j])} differs from the first row of "
                             f"curve {cid!r} ({fmt_number(temp[0])}) by more than {TEMPERATURE_SPREAD:g} degC; give "
                             f"each air temperature its own curve (column {CURVE_COLUMN})")
        if np.any(xe != xe[0]):
            j = int(np.nonzero(xe != xe[0])[0][0])
            raise ValueError(f"{where(j)}: the equilibrium moisture {fmt_number(xe[j])} kg/kg dry differs from the "
                             f"first row of curve {cid!r} ({fmt_number(xe[0])}); one value per curve")
        x0, xe0 = float(x[0]), float(xe[0])
        if not x0 > xe0:
            raise ValueError(f"{where(0)}: the initial moisture {fmt_number(x0)} kg/kg dry of curve {cid!r} is not "
                             f"above its equilibrium moisture {fmt_number(xe0)} kg/kg dry; nothing to dry")
        mr = (x - xe0) / (x0 - xe0)
        rise = mr - np.minimum.accumulate(mr)
        allow = rise_allowance(mr)
        noisy = "" if allow == RISE_TOLERANCE else f" (this curve's allowance for its weighing noise, {RISE_TOLERANCE:g} at least)"
        if np.any(rise > allow):
            j = int(np.nonzero(rise > allow)[0][0])
            low = float(np.min(x[:j]))
            raise ValueError(f"{where(j)}: the moisture rises to {fmt_number(x[j])} kg/kg dry after "
                             f"{fmt_number(low)} in curve {cid!r} (moisture ratio +{rise[j]:.3f}); a drying curve may "
                             f"rise by at most {allow:.3g} of its free moisture X_0 - X_e{noisy}")
        trend = sustained_rise(mr)
        if trend is not None:       # a statistical sign, not a certainty (drifting weighings look alike): said
            j, k, up, allow_k = trend
            span = (f"lines {ln[j]}-{ln[j + k - 1]}" if ln is not None else f"points {j + 1}-{j + k}")
            warnings.warn(f"{name}: the moisture of curve {cid!r} rises over {k} weighings ({span}): their mean "
                          f"moisture ratio lies +{up:.3f} above the lowest mean of {k} earlier weighings, beyond the "
                          f"{allow_k:.3g} their weighing noise explains; the curve may take up water, or its "
                          "weighings drift: check them (the fit uses the curve as given)", RisingCurveWarning,
                          stacklevel=2)
        if mr[-1] > 1.0 - RISE_TOLERANCE:
            raise ValueError(f"{where(len(x) - 1)}: curve {cid!r} does not dry: its moisture goes from "
                             f"{fmt_number(x0)} to {fmt_number(x[-1])} kg/kg dry, less than {RISE_TOLERANCE:g} of its "
                             "free moisture X_0 - X_e (weighing noise); nothing to fit a drying rate to")
        if np.any(mr < -allow):
            j = int(np.nonzero(mr < -allow)[0][0])
            raise ValueError(f"{where(j)}: the moisture {fmt_number(x[j])} kg/kg dry of curve {cid!r} is below its "
                             f"equilibrium moisture {fmt_number(xe0)} by more than {allow:.3g} of its free "
                             f"moisture{noisy}; check the equilibrium moisture")
        out.append((float(np.mean(temp)), x0, xe0))
    return out


def _assemble(name, ids, rows, lines, columns, time_unit) -> DryingCurves:
    per = _check_curves(name, ids, rows, lines)
    curve = np.concatenate([np.full(a.shape[0], i) for i, a in enumerate(rows)])
    data = np.concatenate(rows)
    return DryingCurves(curve=curve, time_s=data[:, 0], moisture=data[:, 1], ids=tuple(ids),
                        air_temperature_degC=np.array([p[0] for p in per]),
                        initial_moisture=np.array([p[1] for p in per]),
                        equilibrium_moisture=np.array([p[2] for p in per]), name=name, columns=columns,
                        time_unit=time_unit)


def drying_curves(time_s, moisture_dry, air_temperature_degC, curve=None, equilibrium_moisture=0.0, *,
                  name: str = "curves") -> DryingCurves:
    """`DryingCurves` from arrays (one value per point; ``equilibrium_moisture`` kg/kg dry per point
    or one value), with the checks of the CSV reader (the module docstring); ``curve`` labels
    the curves (default: one per air temperature)."""
    t = np.ravel(check_range("time_s", time_s, 0.0, MAX_TIME_S, low_inclusive=True, unit="s"))
    x = np.ravel(check_range("moisture_dry", moisture_dry, 0.0, MAX_DRY_MOISTURE, low_inclusive=True,
                             unit="kg/kg dry"))
    temp = np.ravel(check_range("air_temperature_degC", air_temperature_degC, *AIR_TEMPERATURE_RANGE,
                                low_inclusive=True, high_inclusive=True, unit="degC"))
    xe = np.ravel(check_range("equilibrium_moisture", equilibrium_moisture, 0.0, MAX_DRY_MOISTURE,
                              low_inclusive=True, unit="kg/kg dry"))
    n = t.size
    xe = np.broadcast_to(xe, (n,)) if xe.size == 1 else xe
    temp = np.broadcast_to(temp, (n,)) if temp.size == 1 else temp
    firsts: dict = {}
    labels = ([_temperature_label(float(v), firsts) for v in temp] if curve is None
              else [str(c) for c in np.ravel(curve)])
    if not (x.size == n and temp.size == n and xe.size == n and len(labels) == n):
        raise ValueError(f"{name}: time_s, moisture_dry, air_temperature_degC, curve and equilibrium_moisture must "
                         f"have one value per point ({n})")
    if n == 0:
        raise ValueError(f"{name}: no points")
    ids = list(dict.fromkeys(labels))
    rows = [np.column_stack([t, x, temp, xe])[[lab == c for lab in labels]] for c in ids]
    return _assemble(name, ids, rows, [None] * len(ids), {}, "s")


def read_drying_csv(path, equilibrium_moisture: float | None = None) -> DryingCurves:
    """Read drying curves from a CSV file (the module docstring). The file is read line by line
    (UTF-8, at most 64 MB and 200 000 rows); ``equilibrium_moisture`` (kg/kg dry) applies to every
    curve when the file has no equilibrium column (giving both is an error). Errors name the file,
    the line and the column."""
    p = Path(path)
    return _read_lines(data_lines(p, "drying-curve file"), str(p), equilibrium_moisture)


def parse_drying_text(text: str, name: str = "<string>", equilibrium_moisture: float | None = None) -> DryingCurves:
    """[`read_drying_csv`][rotarydryer.lab.drying_curves.read_drying_csv] of text held in memory; messages name ``name``."""
    return _read_lines(text_lines(text), name, equilibrium_moisture)


def _columns(header, name, lineno) -> dict:
    try:
        [float(c) for c in header]
        numeric = bool(header)
    except ValueError:
        numeric = False
    if numeric:
        raise ValueError(f"{name} line {lineno}: the first line is numbers, not a header; give column names with "
                         f"their units, e.g. time_min,moisture_kg_kg_dry,{TEMPERATURE_COLUMN}")
    dup = sorted({c for c in header if c and header.count(c) > 1})
    if dup:
        raise ValueError(f"{name} line {lineno}: column {dup[0]!r} appears twice in the header")
    out = {}
    for role, names, required in (("time", TIME_COLUMNS, True), ("moisture", MOISTURE_COLUMNS, True),
                                  ("temperature", (TEMPERATURE_COLUMN,), True), ("curve", (CURVE_COLUMN,), False),
                                  ("equilibrium", EQUILIBRIUM_COLUMNS, False)):
        found = [c for c in header if c in names]
        if not found and required:
            raise ValueError(f"{name} line {lineno}: no {role} column; the header must name one of "
                             f"{', '.join(names)} (columns are {', '.join(header) or 'none'})")
        if len(found) > 1:
            raise ValueError(f"{name} line {lineno}: {len(found)} {role} columns ({', '.join(found)}); give one")
        if found:
            out[role] = found[0]
    return out


def _value(raw, name, k, col, lo, hi, unit, hi_closed=True):
    v = parse_number(raw, name, k, col)
    if not (v >= lo and (v <= hi if hi_closed else v < hi)):
        raise ValueError(f"{name} line {k}: {col} = {fmt_number(v)} is outside the allowed range "
                         f"[{fmt_number(lo)}, {fmt_number(hi)}{']' if hi_closed else ')'} {unit}")
    return v


def _moisture(raw, name, k, col, basis):
    if basis == "wet":
        x = _value(raw, name, k, col, 0.0, 1.0, "kg/kg wet", hi_closed=False)
        if x / (1.0 - x) >= MAX_DRY_MOISTURE:
            raise ValueError(f"{name} line {k}: {col} = {fmt_number(x)} is outside the allowed range [0, "
                             f"{fmt_number(MAX_DRY_MOISTURE / (1 + MAX_DRY_MOISTURE))}] kg/kg wet")
        return x / (1.0 - x)
    return _value(raw, name, k, col, 0.0, MAX_DRY_MOISTURE, "kg/kg dry", hi_closed=False)


def _read_lines(numbered_lines, name: str, equilibrium_moisture=None) -> DryingCurves:
    if equilibrium_moisture is not None:
        check_range("equilibrium_moisture", equilibrium_moisture, 0.0, MAX_DRY_MOISTURE, low_inclusive=True,
                    unit="kg/kg dry")
    header: list[str] | None = None
    cols: dict = {}
    idx: dict = {}
    groups: dict[str, list] = {}
    lines: dict[str, list] = {}
    firsts: dict = {}       # without a curve column: label -> the curve's first air temperature
    n = 0
    for k, row in csv_rows(numbered_lines, name):
        if header is None:
            header = [c.strip() for c in row]
            cols = _columns(header, name, k)
            if "equilibrium" in cols and equilibrium_moisture is not None:
                raise ValueError(f"{name} line {k}: the file has an equilibrium column ({cols['equilibrium']}) and "
                                 f"an equilibrium moisture was given too ({fmt_number(equilibrium_moisture)} kg/kg "
                                 "dry); give one")
            idx = {role: header.index(c) for role, c in cols.items()}
            continue
        if len(row) != len(header):
            raise ValueError(f"{name} line {k}: {len(row)} columns, expected {len(header)} ({', '.join(header)})")
        n += 1
        if n > MAX_DATA_ROWS:
            raise too_many_rows(name, k, MAX_DATA_ROWS)
        tcol = cols["time"]
        t = _value(row[idx["time"]], name, k, tcol, 0.0, MAX_TIME_S / TIME_COLUMNS[tcol], tcol.split("_", 1)[1])
        x = _moisture(row[idx["moisture"]], name, k, cols["moisture"], MOISTURE_COLUMNS[cols["moisture"]])
        temp = _value(row[idx["temperature"]], name, k, TEMPERATURE_COLUMN, *AIR_TEMPERATURE_RANGE, "degC")
        if "equilibrium" in cols:
            xe = _moisture(row[idx["equilibrium"]], name, k, cols["equilibrium"], EQUILIBRIUM_COLUMNS[cols["equilibrium"]])
        else:
            xe = 0.0 if equilibrium_moisture is None else float(equilibrium_moisture)
        if "curve" in cols:
            label = row[idx["curve"]].strip()
            if not label:
                raise ValueError(f"{name} line {k}: an empty field in column {CURVE_COLUMN}; label every row's curve")
        else:
            label = _temperature_label(temp, firsts)
        groups.setdefault(label, []).append((t * TIME_COLUMNS[tcol], x, temp, xe))
        lines.setdefault(label, []).append(k)
    if header is None:
        raise ValueError(f"{name}: empty file; expected a header line (e.g. time_min,moisture_kg_kg_dry,"
                         f"{TEMPERATURE_COLUMN})")
    if not groups:
        raise ValueError(f"{name}: no data rows after the header")
    ids = list(groups)
    return _assemble(name, ids, [np.array(groups[c], dtype=float) for c in ids], [lines[c] for c in ids], cols,
                     cols["time"].split("_", 1)[1])


# ------------------------------------------------------------------------------------ fitting
@dataclass(frozen=True)
class Estimate:
    """A fitted quantity: ``value``, ``std_error``, 95 % interval ``ci_low``-``ci_high``, ``unit``,
    ``at_bound``."""

    value: float
    std_error: float
    ci_low: float
    ci_high: float
    unit: str
    at_bound: bool = False

    def as_dict(self) -> dict:
        return {"value": self.value, "std_error": self.std_error, "ci_low": self.ci_low, "ci_high": self.ci_high,
                "unit": self.unit, "at_bound": self.at_bound}


@dataclass
class ModelFit:
    """One law fitted to all curves: ``parameters`` (the law's names, rate constants at
    ``reference_temperature_K``), ``activation_energy`` (J/mol; None with one air temperature),
    ``correlation`` over ``correlation_names`` (the fit's own parametrisation: log of the rate
    constants and of n), goodness of fit and information criteria, ``predictions`` (MR at the
    fitted points), ``notes`` (identifiability, nesting)."""

    model: str
    parameters: dict[str, Estimate]
    activation_energy: Estimate | None
    reference_temperature_K: float
    correlation: np.ndarray
    correlation_names: list[str]
    n_points: int
    n_parameters: int
    sse: float
    rmse: float
    r_squared: float
    aic: float
    aicc: float
    bic: float
    predictions: np.ndarray
    notes: list[str] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def values(self) -> dict[str, float]:
        """The law's parameter values (rate constants at the reference temperature)."""
        return {k: e.value for k, e in self.parameters.items()}

    @property
    def activation_energy_value(self) -> float:
        """Activation energy, J/mol (0 when it was not fitted)."""
        return 0.0 if self.activation_energy is None else self.activation_energy.value

    @property
    def law_problem(self) -> str | None:
        """Why the fitted values are not a drying law the dryer model can use (None: they are):
        [`check_law`][rotarydryer.properties.thin_layer.check_law] and a non-negative activation energy."""
        try:
            tl.check_law(self.model, self.values)
        except ValueError as exc:
            return str(exc)
        if self.activation_energy_value < 0:
            return (f"activation_energy = {self.activation_energy_value:g} J/mol is below 0 (the law dries more slowly "
                    "in hotter air)")
        return self.unidentified

    @property
    def unidentified(self) -> str | None:
        """Which fitted value the curves do not determine (a 95 % interval without a finite end), or None: a law
        whose rate constant is anywhere in [0, inf] is no law (curves flat at their first weighing gave k = 1.6e-14
        1/s, and a dryer whose product left wetter than its feed)."""
        named = dict(self.parameters)
        if self.activation_energy is not None:
            named["activation_energy"] = self.activation_energy
        for k, e in named.items():
            if not (math.isfinite(e.ci_low) and math.isfinite(e.ci_high)):
                return (f"{k} is not identifiable from these curves (95 % interval [{e.ci_low:.3g}, {e.ci_high:.3g}] "
                        f"{e.unit}): the curves hardly change where the law differs (weigh earlier and more often)")
        return None

    def moisture_ratio(self, time_s, air_temperature_degC):
        """MR of the fitted law at ``time_s`` (s) and ``air_temperature_degC``."""
        return tl.moisture_ratio(self.model, time_s, self.values, np.asarray(air_temperature_degC, float) + _KELVIN,
                                 self.activation_energy_value, self.reference_temperature_K)

    def as_dict(self) -> dict:
        d = {"model": self.model, "equation": tl.MODELS[self.model].equation,
             "citation": tl.MODELS[self.model].citation,
             "parameters": {k: e.as_dict() for k, e in self.parameters.items()},
             "activation_energy_J_mol": None if self.activation_energy is None else self.activation_energy.as_dict(),
             "reference_temperature_K": self.reference_temperature_K, "n_points": self.n_points,
             "n_parameters": self.n_parameters, "sse": self.sse, "rmse": self.rmse, "r_squared": self.r_squared,
             "aic": self.aic, "aicc": self.aicc if math.isfinite(self.aicc) else None, "bic": self.bic,
             "correlation": {"names": self.correlation_names, "matrix": self.correlation.tolist()},
             "notes": list(self.notes)}
        return d


@dataclass
class DryingFit:
    """All laws fitted to one set of curves: ``fits`` ranked by AICc (best first), ``skipped``
    (law -> reason), ``reference_temperature_K``."""

    curves: DryingCurves
    reference_temperature_K: float
    fits: dict[str, ModelFit]
    skipped: dict[str, str]

    @property
    def best(self) -> ModelFit:
        """The lowest AICc."""
        return next(iter(self.fits.values()))

    @property
    def best_law(self) -> ModelFit | None:
        """The lowest AICc among the fits that are drying laws (`ModelFit.law_problem` None), or None."""
        return next((f for f in self.fits.values() if f.law_problem is None), None)

    @property
    def criterion(self) -> str:
        """The ranking's criterion: ``"AICc"``, or ``"AIC"`` where no law has an AICc (too few points for the
        small-sample correction of any law, n <= p + 2: the ranking is then by AIC)."""
        return "AICc" if math.isfinite(self.best.aicc) else "AIC"

    def delta_aicc(self, model: str) -> float:
        """The ranking criterion (`criterion`) of ``model`` minus the best's: AICc (inf where it is undefined,
        n <= p + 2), or AIC where no law has an AICc."""
        f = self.fits[model]
        if self.criterion == "AIC":
            return f.aic - self.best.aic
        return math.inf if not math.isfinite(f.aicc) else f.aicc - self.best.aicc

    def akaike_weight(self, model: str) -> float:
        """exp(-delta/2) of the ranking criterion normalised over the fitted laws (0 where it is undefined)."""
        w = {m: math.exp(-0.5 * self.delta_aicc(m)) if math.isfinite(self.delta_aicc(m)) else 0.0 for m in self.fits}
        return w[model] / sum(w.values()) if sum(w.values()) > 0 else math.nan

    def as_dict(self) -> dict:
        return {"file": self.curves.name, "curves": self.curves.as_dict(),
                "reference_temperature_K": self.reference_temperature_K,
                "models": [{"rank": i + 1, **f.as_dict(), "delta_aicc": _finite(self.delta_aicc(m)),
                            "akaike_weight": _finite(self.akaike_weight(m)), "drying_law": f.law_problem is None,
                            "law_problem": f.law_problem} for i, (m, f) in enumerate(self.fits.items())],
                "skipped": [{"model": m, "reason": r} for m, r in self.skipped.items()],
                "ranking_criterion": self.criterion,
                "best": self.best.model, "best_drying_law": None if self.best_law is None else self.best_law.model}


def _finite(v: float) -> float | None:
    return v if math.isfinite(v) else None


def _initial_values(t, temp_k, mr, t_ref, use_ea, page_like):
    """(k_ref, n, Ea kJ/mol) from the linearised Page law ln(-ln MR) = ln k_ref - Ea/R (1/T - 1/T_ref)
    + n ln t (n = 1 unless ``page_like``) on the points with 0.02 < MR < 0.98."""
    ok = (mr > 0.02) & (mr < 0.98) & (t > 0)
    cols = [np.ones(int(ok.sum()))]
    if use_ea:
        cols.append(-(1.0 / temp_k[ok] - 1.0 / t_ref) / tl.GAS_CONSTANT * 1e3)
    z = np.log(-np.log(mr[ok]))
    if page_like:
        cols.append(np.log(t[ok]))
    else:
        z = z - np.log(t[ok])
    A = np.column_stack(cols)
    if ok.sum() <= A.shape[1] or np.linalg.matrix_rank(A) < A.shape[1]:
        return 1.0 / float(np.median(t[t > 0])), 1.0, 30.0
    coef = np.linalg.lstsq(A, z, rcond=None)[0]
    n = float(np.clip(coef[-1], 0.3, 3.0)) if page_like else 1.0
    ea = float(np.clip(coef[1], 0.0, 150.0)) if use_ea else 0.0
    k = float(np.exp(coef[0]))
    if page_like and n != coef[-1]:      # n clipped: k from the mean of the points with that n
        k = float(np.exp(np.mean(z - n * np.log(t[ok]) - (A[:, 1] * ea if use_ea else 0.0))))
    return k, n, ea


def _parameters(model, k0, n0, ea0, use_ea, t_c) -> list[Parameter]:
    ps = []
    for name in tl.MODELS[model].parameters:
        if name == "k" and "n" in tl.MODELS[model].parameters:     # k t^n = k_c (t/t_c)^n: k_c and n barely correlate
            ps.append(Parameter("k_c", k0 * t_c**n0, 0.0, math.inf, log=True))
        elif name == "k":
            ps.append(Parameter("k", k0, 0.0, math.inf, log=True))
        elif name == "k0":
            ps.append(Parameter("k0", 3.0 * k0, 0.0, math.inf, log=True))
        elif name == "k1":
            ps.append(Parameter("k1", k0 / 3.0, 0.0, math.inf, log=True))
        elif name == "n":
            ps.append(Parameter("n", n0, 0.0, math.inf, log=True))
        elif name == "a":
            ps.append(Parameter("a", 0.5 if model == "two_term" else 1.0))
        elif name == "b":
            ps.append(Parameter("b", 0.5) if model == "two_term" else Parameter("b_scaled", 0.0))
        elif name == "c":
            ps.append(Parameter("c", 0.0))
    if use_ea:
        ps.append(Parameter("Ea_kJ_mol", ea0))
    return ps


def _nesting_notes(model, parameters) -> list[str]:
    notes = []
    for simpler, at in NESTED[model]:
        if all(parameters[k].ci_low <= v <= parameters[k].ci_high for k, v in at.items()):
            where = ", ".join(f"{k} = {v:g}" for k, v in at.items())
            notes.append(f"the {simpler} law ({where}) lies inside the 95 % intervals: the extra parameters of "
                         f"{model} are not significant")
    return notes


def _centred_rate_constant(res, params, t_c, unit) -> Estimate:
    """k = k_c t_c^(-n) with its delta-method interval (t quantile, in log space) from the
    covariance of (log k_c, log n)."""
    names = [q.name for q in params]
    ik, i_n = names.index("k_c"), names.index("n")
    vals = np.array([res.parameters[q.name].value if q.log else 1.0 for q in params])
    cov_z = np.asarray(res.covariance) / np.outer(vals, vals)      # back to the fit's (log) space
    k_c, n = res.parameters["k_c"].value, res.parameters["n"].value
    log_k = math.log(k_c) - n * math.log(t_c)
    g = np.zeros(len(params))
    g[ik], g[i_n] = 1.0, -n * math.log(t_c)
    se = math.sqrt(max(float(g @ cov_z @ g), 0.0))
    tq = float(stats.t.ppf(0.975, max(res.dof, 1)))
    k = math.exp(log_k)
    return Estimate(k, k * se, math.exp(log_k - tq * se), math.exp(log_k + tq * se), unit,
                    res.parameters["k_c"].at_bound)


def fit_model(curves: DryingCurves, model: str, reference_temperature_K: float | None = None, *,
              n_starts: int = 4, seed: int = 0) -> ModelFit:
    """Fit thin-layer law ``model`` to all ``curves`` at once (module docstring). Raises ``ValueError``
    when the curves have no more points than the law has parameters, ``FitError`` when no start
    converges."""
    check_choice("model", model, tl.MODELS)
    t_ref = float(np.mean(curves.air_temperature_degC + _KELVIN)) if reference_temperature_K is None else float(
        check_range("reference_temperature_K", reference_temperature_K, 200.0, 1000.0, unit="K"))
    mask = curves.time_s > 0
    t, temp_k, mr = curves.time_s[mask], curves.temperature_K[mask], curves.moisture_ratio[mask]
    use_ea = curves.n_temperatures > 1
    spec = tl.MODELS[model]
    if mr.size <= len(spec.parameters) + use_ea:
        raise ValueError(f"{model}: {mr.size} points after time 0 for {len(spec.parameters) + use_ea} parameters; it "
                         "needs more points than parameters")
    t_max = float(np.max(t))
    t_c = float(np.exp(np.mean(np.log(t))))       # the centre time of the t^n laws' rate constant
    k0, n0, ea0 = _initial_values(t, temp_k, mr, t_ref, use_ea, "n" in spec.parameters)
    params = _parameters(model, k0, n0, ea0, use_ea, t_c)

    def law(values):
        p = {k: v for k, v in values.items() if k not in ("b_scaled", "Ea_kJ_mol", "k_c")}
        if "b_scaled" in values:
            p["b"] = values["b_scaled"] / t_max
        if "k_c" in values:
            p["k"] = values["k_c"] * t_c ** (-values["n"])
        ea = values.get("Ea_kJ_mol", 0.0) * 1e3
        return tl._mr(model, t, tl._at_temperature(model, p, temp_k, ea, t_ref))

    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdentifiabilityWarning)
        warnings.simplefilter("ignore", RuntimeWarning)
        res = fit(law, params, Dataset("moisture_ratio", mr), method="wls", n_starts=n_starts, seed=seed)
    out: dict[str, Estimate] = {}
    for name in spec.parameters:
        if name == "k" and "k_c" in res.parameters:
            out[name] = _centred_rate_constant(res, params, t_c, spec.unit(name))
            continue
        key = "b_scaled" if (model == "midilli" and name == "b") else name
        e = res.parameters[key]
        s = 1.0 / t_max if key == "b_scaled" else 1.0
        out[name] = Estimate(e.value * s, e.std_error * s, e.ci_low * s, e.ci_high * s, spec.unit(name), e.at_bound)
    ea = None
    if use_ea:
        e = res.parameters["Ea_kJ_mol"]
        ea = Estimate(e.value * 1e3, e.std_error * 1e3, e.ci_low * 1e3, e.ci_high * 1e3, "J/mol", e.at_bound)
    n, p = mr.size, len(params)
    sse = float(np.sum(res.residuals["moisture_ratio"] ** 2))
    ll = n * math.log(max(sse / n, 1e-300))
    aic = ll + 2 * (p + 1)
    aicc = aic + 2 * (p + 1) * (p + 2) / (n - p - 2) if n - p - 2 > 0 else math.inf
    names = ["b" if k == "b_scaled" else "activation_energy" if k == "Ea_kJ_mol" else
             f"log k_c (k t_c^n, t_c = {t_c:.4g} s)" if k == "k_c" else
             f"log {k}" if k in spec.rate_constants or k == "n" else k for k in res.names]
    notes = [w.replace("b_scaled", "b").replace("Ea_kJ_mol", "activation_energy").replace("k_c", "k t_c^n")
             for w in res.warnings if "were infeasible and rejected" not in w]     # rejected trial starts: no news
    if not use_ea:
        notes.append("one air temperature: the activation energy cannot be estimated (the law is written without "
                     "temperature dependence, activation_energy = 0); measure at two or more temperatures")
    notes += _nesting_notes(model, out)
    return ModelFit(model=model, parameters=out, activation_energy=ea, reference_temperature_K=t_ref,
                    correlation=np.asarray(res.correlation), correlation_names=names, n_points=n, n_parameters=p,
                    sse=sse, rmse=math.sqrt(sse / n), r_squared=float(res.r_squared), aic=aic, aicc=aicc,
                    bic=ll + (p + 1) * math.log(n), predictions=res.predictions["moisture_ratio"], notes=notes,
                    seconds=time.perf_counter() - t0)


def fit_models(curves: DryingCurves, models: Sequence[str] | None = None, reference_temperature_K: float | None = None,
               *, n_starts: int = 4, seed: int = 0) -> DryingFit:
    """Fit every law of ``models`` (default: all six) and rank them by AICc. A law with no more points
    than parameters, or whose fit does not converge, is skipped with the reason; ``ValueError``
    when none can be fitted."""
    if not isinstance(curves, DryingCurves):      # a file name failed on an attribute (found by an acceptance check)
        raise ValueError(f"curves = {curves!r} is not a DryingCurves: read a CSV first (read_drying_csv(path))")
    if isinstance(models, str):     # one law by its name ("page" was read one letter at a time)
        models = [models]
    models = list(tl.MODELS) if models is None else [check_choice("model", m, tl.MODELS) for m in models]
    if reference_temperature_K is not None:       # checked once here: a bad value is not a law's skip reason
        check_range("reference_temperature_K", reference_temperature_K, 200.0, 1000.0, unit="K")
    fits, skipped = {}, {}
    for m in models:
        try:
            f = fit_model(curves, m, reference_temperature_K, n_starts=n_starts, seed=seed)
        except (ValueError, FitError) as exc:
            skipped[m] = str(exc).removeprefix(f"{m}: ")
            continue
        fits[m] = f
    if not fits:
        reasons = "; ".join(f"{m}: {r}" for m, r in skipped.items())
        raise ValueError(f"{curves.name}: no thin-layer law could be fitted ({reasons})")
    ranked = dict(sorted(fits.items(), key=lambda kv: (kv[1].aicc, kv[1].aic, kv[1].n_parameters)))
    return DryingFit(curves, next(iter(ranked.values())).reference_temperature_K, ranked, skipped)


# ------------------------------------------------------------------------------------ material file
def material_table(drying_fit: DryingFit, model: str, base_material: str, *, name: str | None = None,
                   particle_diameter: float | None = None) -> dict:
    """A complete material table: library material ``base_material``'s fields with the fitted law
    ``model`` as its kinetics (``method = "thin_layer"``), loadable by
    [`load_material`][rotarydryer.properties.materials.load_material] (checked here). The law's X_0 and X_e are the means of the
    curves' values; ``particle_diameter`` (m, the lab sample's; default the base's) sets the
    law's mapping to the dryer's contact area. ``ValueError`` naming the key when the law is not a
    drying law the material format accepts (e.g. a Midilli b > 0)."""
    if base_material not in list_materials():
        raise ValueError(f"base material {base_material!r} is not in the materials library "
                         f"({', '.join(list_materials())})")
    if model not in drying_fit.fits:
        why = drying_fit.skipped.get(model, "not fitted")
        raise ValueError(f"model {model!r} has no fit to write ({why})")
    f = drying_fit.fits[model]
    if f.unidentified is not None:      # even as --model: the material would hold a value the data do not give
        raise ValueError(f"--model {model}: {f.unidentified}; the material is not written")
    c = drying_fit.curves
    table = library_table(base_material)
    name = name or f"{base_material}_{model}"
    if name in list_materials():
        raise ValueError(f"material name {name!r} is a library material; give the new material its own name")
    base_kin = table.get("kinetics", {})
    table["name"] = name
    table["title"] = f"{table['title']} with a {tl.MODELS[model].title} drying law from {Path(c.name).name}"
    temps = ", ".join(f"{v:g}" for v in c.air_temperature_degC)
    table["citations"] = [f"Lab drying curves {Path(c.name).name} ({len(c.ids)} curves at {temps} degC): "
                          f"{tl.MODELS[model].title} thin-layer law ({tl.MODELS[model].citation}) fitted by "
                          "rotarydryer lab drying", *table["citations"]]
    if particle_diameter is not None:
        table["particle_diameter"] = float(check_range("particle_diameter", particle_diameter, 0.0, 0.2, unit="m"))
        table.pop("particle_diameter_by_section", None)     # the base's section sizes are not the lab's
    table["kinetics"] = {
        "method": "thin_layer", "model": model, "parameters": {k: float(v) for k, v in f.values.items()},
        "activation_energy": float(f.activation_energy_value), "reference_temperature_K": float(f.reference_temperature_K),
        "initial_moisture": float(np.mean(c.initial_moisture)),
        "equilibrium_moisture": float(np.mean(c.equilibrium_moisture)),
        "basis": base_kin.get("basis", "concentration"),
        "saturation_method": base_kin.get("saturation_method", "wagner_pruss"),
        "source": (f"{tl.MODELS[model].title} law fitted to {Path(c.name).name} (rotarydryer lab drying): RMSE "
                   f"{f.rmse:.3g} in MR, rate constants at {f.reference_temperature_K:g} K, X_0 and X_e the means of "
                   "the curves'"),
    }
    # the law holds over the curves' moisture: the material's range must reach it (the base's range alone would
    # refuse a feed at the curves' own initial moisture); the base's moisture laws are then extrapolated there
    basis = table.get("moisture_basis", "wet")
    xs = np.array([float(np.min(c.equilibrium_moisture)), float(np.max(c.initial_moisture))])   # kg/kg dry
    xs = xs / (1.0 + xs) if basis == "wet" else xs
    lo0, hi0 = (float(v) for v in table["moisture_range"])
    lo, hi = min(lo0, float(xs[0])), max(hi0, float(xs[1]))
    if (lo, hi) != (lo0, hi0):
        table["moisture_range"] = [lo, hi]
        table["kinetics"]["source"] += (f"; moisture_range widened from the base's [{lo0:g}, {hi0:g}] to the curves' "
                                        f"[{lo:.4g}, {hi:.4g}] kg/kg {basis} (the base's repose angle and bulk density "
                                        "laws are extrapolated there)")
    try:
        load_material(table)
    except ValueError as exc:
        raise ValueError(f"the {model} law cannot be written as a material: {exc}") from None
    return table


def _toml_scalar(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise ValueError(f"a material value is not finite ({v!r})")
        return repr(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_scalar(x) for x in v) + "]"
    s = str(v).replace("\\", "\\\\").replace('"', '\\"').replace("\n", " ")
    return f'"{s}"'


def material_toml(table: Mapping, header: Sequence[str] = ()) -> str:
    """The material ``table`` as a case file's ``[material]`` block (``[material]``, then
    ``[material.kinetics]`` and the other sub-tables); ``header`` lines become ``#`` comments.
    [`load_material`][rotarydryer.properties.materials.load_material] reads the file; in a case it replaces the ``[material]`` block."""
    out = [f"# {h}" for h in header]

    def block(prefix, d):
        out.append(f"[{prefix}]")
        subs = []
        for k, v in d.items():
            if isinstance(v, Mapping):
                subs.append((k, v))
            else:
                out.append(f"{k} = {_toml_scalar(v)}")
        for k, v in subs:
            out.append("")
            block(f"{prefix}.{k}", v)

    block("material", table)
    text = "\n".join(out) + "\n"
    if tomllib.loads(text)["material"] != _plain(table):     # the writer's own check: exact round trip
        raise ValueError("the material table does not survive a TOML round trip")
    return text


def _plain(d):
    if isinstance(d, Mapping):
        return {k: _plain(v) for k, v in d.items()}
    if isinstance(d, tuple):
        return [_plain(v) for v in d]
    if isinstance(d, list):
        return [_plain(v) for v in d]
    return d


# ------------------------------------------------------------------------------------ figure
def plot_fit(drying_fit: DryingFit, model: str | None = None):
    """Figure of the curves (MR against time in the source's unit) with law ``model`` (default:
    the best), and its residuals; returns the matplotlib figure."""
    plt = pyplot()
    f = drying_fit.fits[model or drying_fit.best.model]
    c = drying_fit.curves
    scale = {"s": 1.0, "min": 60.0, "h": 3600.0}[c.time_unit]
    fig, (ax, axr) = plt.subplots(1, 2, figsize=(10, 4), gridspec_kw={"width_ratios": [3, 2]})
    mr = c.moisture_ratio
    fitted = c.time_s > 0
    res = np.full(mr.shape, np.nan)
    res[fitted] = mr[fitted] - f.predictions
    for i, cid in enumerate(c.ids):
        sel = c.curve == i
        t = c.time_s[sel]
        dense = np.linspace(0.0, float(t.max()), 300)
        colour = f"C{i % 10}"
        label = f"{cid} ({c.air_temperature_degC[i]:g} degC)" if cid != fmt_number(c.air_temperature_degC[i]) else (
            f"{c.air_temperature_degC[i]:g} degC")
        ax.plot(t / scale, mr[sel], "o", ms=3.5, color=colour, label=label)
        with np.errstate(divide="ignore", invalid="ignore"):
            ax.plot(dense / scale, f.moisture_ratio(dense, c.air_temperature_degC[i]), "-", color=colour, lw=1.2)
        axr.plot(t / scale, res[sel], "o", ms=3, color=colour)
    ax.set_xlabel(f"time ({c.time_unit})")
    ax.set_ylabel("moisture ratio (X - X_e)/(X_0 - X_e)")
    ea = "" if f.activation_energy is None else f", Ea {f.activation_energy.value / 1e3:.1f} kJ/mol"
    pars = ", ".join(f"{k} {e.value:.3g}" for k, e in f.parameters.items())
    ax.set_title(f"{tl.MODELS[f.model].title}: {pars}{ea} (T_ref {f.reference_temperature_K:.1f} K)", fontsize=9)
    ax.legend(fontsize=8)
    axr.axhline(0.0, color="0.5", lw=0.8)
    axr.set_xlabel(f"time ({c.time_unit})")
    axr.set_ylabel("residual of MR")
    axr.set_title(f"RMSE {f.rmse:.4f}, R^2 {f.r_squared:.5f}", fontsize=9)
    fig.tight_layout()
    return fig


# ------------------------------------------------------------------------------------ example data
#: the law of the shipped example (`EXAMPLE`): Page, k at T_ref in 1/s^n, Ea in J/mol
EXAMPLE_LAW = {"model": "page", "parameters": {"k": 7.5e-3, "n": 0.7}, "activation_energy": 30.0e3,
               "reference_temperature_K": 338.15}
#: file name of the shipped example in ``rotarydryer/data``
EXAMPLE = "drying_curves_example.csv"
_EXAMPLE_K, _EXAMPLE_N, _EXAMPLE_EA, _EXAMPLE_TREF = 7.5e-3, 0.7, 30.0e3, 338.15
_EXAMPLE_TEMPERATURES_DEGC = (50.0, 65.0, 80.0)
_EXAMPLE_EQUILIBRIUM = (0.015, 0.010, 0.007)
_EXAMPLE_X0, _EXAMPLE_NOISE, _EXAMPLE_SEED = 0.30, 0.005, 0


def synthetic_drying_curves(model: str = "page", parameters: Mapping | None = None, *, activation_energy: float = 30e3,
                            reference_temperature_K: float = 338.15, temperatures_degC=(50.0, 65.0, 80.0),
                            times_s=None, initial_moisture: float = 0.30, equilibrium_moisture=0.0,
                            noise_sd: float = 0.005, seed=None) -> DryingCurves:
    """Noisy drying curves from a known law: one curve per air temperature, X = X_e + (X_0 - X_e)
    (MR(t) + e) with e ~ N(0, ``noise_sd``) at t > 0 (the weighings); the t = 0 row is X_0 exactly
    (the sample's initial moisture by oven drying; a law whose MR(0) is not 1, such as
    Henderson-Pabis with a < 1, departs from it at the first weighing, as measured curves do).
    ``parameters`` default `EXAMPLE_LAW`'s; ``times_s``
    default 0 to 150 min every 5 min; ``equilibrium_moisture`` one value or one per temperature
    (kg/kg dry)."""
    p = dict({"k": _EXAMPLE_K, "n": _EXAMPLE_N} if parameters is None else parameters)
    tl.check_law(model, p)
    temps = np.ravel(np.asarray(temperatures_degC, dtype=float))
    times = np.arange(0.0, 9001.0, 300.0) if times_s is None else np.ravel(np.asarray(times_s, dtype=float))
    xe = np.broadcast_to(np.asarray(equilibrium_moisture, dtype=float), temps.shape)
    sd = float(check_range("noise_sd", noise_sd, 0.0, 1.0, low_inclusive=True))
    rng = np.random.default_rng(seed)
    t_all, x_all, temp_all, xe_all, ids = [], [], [], [], []
    for temp, e in zip(temps, xe):
        mr = tl.moisture_ratio(model, times, p, temp + _KELVIN, activation_energy, reference_temperature_K)
        noise = sd * rng.standard_normal(times.size)
        x = np.where(times > 0, e + (initial_moisture - e) * (mr + noise), initial_moisture)
        t_all.append(times)
        x_all.append(np.maximum(x, 0.0))
        temp_all.append(np.full(times.size, temp))
        xe_all.append(np.full(times.size, e))
        ids += [fmt_number(temp)] * times.size
    return drying_curves(np.concatenate(t_all), np.concatenate(x_all), np.concatenate(temp_all), ids,
                         np.concatenate(xe_all), name="synthetic")


def curves_csv_text(curves: DryingCurves, header: Sequence[str] = (), time_unit: str = "min") -> str:
    """The curves as a drying-curve CSV (time in ``time_unit``, dry-basis moisture to 6 decimals,
    the equilibrium column, a curve column); ``header`` lines become ``#`` comments."""
    check_choice("time_unit", time_unit, ("s", "min", "h"))
    col = f"time_{time_unit}"
    lines = [f"# {h}" for h in header]
    lines.append(f"{CURVE_COLUMN},{col},moisture_kg_kg_dry,{TEMPERATURE_COLUMN},equilibrium_moisture_kg_kg_dry")
    for i, t, x in zip(curves.curve, curves.time_s, curves.moisture):
        lines.append(f"{curves.ids[i]},{fmt_number(round(t / TIME_COLUMNS[col], 6))},{x:.6f},"
                     f"{fmt_number(curves.air_temperature_degC[i])},{fmt_number(curves.equilibrium_moisture[i])}")
    return "\n".join(lines) + "\n"


def _example_text() -> str:
    """The text of the shipped example, as `synthetic_drying_curves` makes it (a test checks that the
    shipped file is this text)."""
    curves = synthetic_drying_curves("page", {"k": _EXAMPLE_K, "n": _EXAMPLE_N}, activation_energy=_EXAMPLE_EA,
                                     reference_temperature_K=_EXAMPLE_TREF, temperatures_degC=_EXAMPLE_TEMPERATURES_DEGC,
                                     times_s=np.arange(0.0, 151.0, 5.0) * 60.0, initial_moisture=_EXAMPLE_X0,
                                     equilibrium_moisture=_EXAMPLE_EQUILIBRIUM, noise_sd=_EXAMPLE_NOISE,
                                     seed=_EXAMPLE_SEED)
    header = [
        "Example drying curves generated by rotarydryer.lab.drying_curves.synthetic_drying_curves (not measured):",
        f"Page law MR = exp(-k t^n), k = {_EXAMPLE_K:g} 1/s^n at T_ref = {_EXAMPLE_TREF:g} K (65 degC), "
        f"n = {_EXAMPLE_N:g}, Arrhenius Ea = {_EXAMPLE_EA:g} J/mol;",
        f"X_0 = {_EXAMPLE_X0:g} kg/kg dry, X_e = 0.015 / 0.010 / 0.007 kg/kg dry at 50 / 65 / 80 degC;",
        f"noise N(0, {_EXAMPLE_NOISE:g}) on MR at t > 0 (X_0 exact), numpy default_rng(seed={_EXAMPLE_SEED}).",
    ]
    return curves_csv_text(curves, header, "min")


def example_path() -> Path:
    """Path of the shipped example drying curves (`EXAMPLE`)."""
    return Path(str(resources.files("rotarydryer.data") / EXAMPLE))


def load_example() -> DryingCurves:
    """The shipped example drying curves."""
    return read_drying_csv(example_path())
