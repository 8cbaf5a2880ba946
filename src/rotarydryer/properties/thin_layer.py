r"""Thin-layer drying laws: the moisture ratio of a thin layer of solids drying in air of constant
temperature, with Arrhenius rate constants, and the local drying rate each law gives.

Moisture ratio $MR = (X - X_e)/(X_0 - X_e)$ with X the dry-basis moisture (kg water/kg dry
solid), X_0 the initial and X_e the equilibrium moisture; time t in s.

| model | $MR(t)$ | parameters | source |
|---|---|---|---|
| ``lewis`` | $e^{-kt}$ | k (1/s) | Lewis (1921) |
| ``page`` | $e^{-kt^n}$ | k (1/s^n), n | Page (1949) |
| ``henderson_pabis`` | $a e^{-kt}$ | a, k (1/s) | Henderson & Pabis (1961) |
| ``logarithmic`` | $a e^{-kt} + c$ | a, k (1/s), c | Yagcioglu et al. (1999) |
| ``two_term`` | $a e^{-k_0t} + b e^{-k_1t}$ | a, k0 (1/s), b, k1 (1/s) | Henderson (1974) |
| ``midilli`` | $a e^{-kt^n} + b t$ | a, k (1/s^n), n, b (1/s) | Midilli et al. (2002) |

Temperature: the rate constants (k; k0 and k1) follow Arrhenius,

$$
k(T) = k_{ref}\exp\Big[-\frac{E_a}{R}\Big(\frac{1}{T} - \frac{1}{T_{ref}}\Big)\Big],
$$

T the air temperature in K, $T_{ref}$ a reference temperature (the fit reports its own) and
one activation energy $E_a$ (J/mol) for all rate constants of a law; the shape parameters
(a, b, c, n) do not depend on temperature.

Local drying rate
-----------------
A thin-layer law is a batch curve, MR against time since the start at X_0. A dryer model
needs the rate as a function of the local state, $-dX/dt = f(X, T)$. The **equivalent time**
gives it: the time $t_{eq}$ at which the law reaches the local moisture ratio,
$MR(t_{eq}, T) = (X - X_e)/(X_0 - X_e)$, and then

$$
-\frac{dX}{dt} = -(X_0 - X_e)\,\frac{dMR}{dt}\Big|_{t_{eq}},
$$

([`drying_rate`][rotarydryer.properties.thin_layer.drying_rate], kg water/(kg dry solid s)).
For the exponential laws this is exact and independent of X_0: Lewis and Henderson-Pabis give
$k(X - X_e)$, the logarithmic law $k(X - X_e - c(X_0 - X_e))$ (an equilibrium shifted by c).
Page, two-term and Midilli depend on X_0 through MR; the law's X_0 is the lab's (the material
file records it). Page has the closed form $t_{eq} = (-\ln MR/k)^{1/n}$; two-term and Midilli
are inverted by bisection in $\ln t$ (they decrease monotonically for the parameters
[`check_law`][rotarydryer.properties.thin_layer.check_law] accepts). Choices where the law itself is silent:

* above the start of the law (X above X_0, or MR above the law's MR(0) < 1) the rate is the
  rate at the start; where the start rate is infinite (n < 1) it is the rate at
  $t = 10^{-6}\,k^{-1/n}$ (the dryer's external-transfer limit caps it anyway,
  [`rotarydryer.properties.drying`][rotarydryer.properties.drying]);
* a law whose rate first rises (n > 1: the lab sample warming up) has a rate that is taken
  as non-decreasing in X: states above the moisture of the peak rate dry at the peak rate (a
  dryer's energy balance models the warming itself);
* below MR = `MR_FLOOR` (1 % of the lab's free moisture) the rate goes linearly to zero at
  X_e and reverses below it (sorption), as the falling-rate kinetics of the package do; the
  law is not extrapolated into its tail.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .._validation import check_choice, check_range

__all__ = ["GAS_CONSTANT", "MR_FLOOR", "ThinLayerModel", "MODELS", "arrhenius", "moisture_ratio",
           "moisture_ratio_rate", "drying_rate", "check_law"]

GAS_CONSTANT = 8.314462618   # J/(mol K), CODATA 2018
#: moisture ratio below which the local rate goes linearly to zero at X_e (module docstring)
MR_FLOOR = 0.01
#: start of the law for rates that are infinite at t = 0 (n < 1), in units of k^(-1/n)
_T_START = 1e-6
_BISECTIONS = 60


@dataclass(frozen=True)
class ThinLayerModel:
    """One thin-layer law: its name, equation, parameter names (in order), the rate constants
    among them (Arrhenius) and its source."""

    name: str
    title: str
    equation: str
    parameters: tuple[str, ...]
    rate_constants: tuple[str, ...]
    citation: str

    def unit(self, parameter: str) -> str:
        """Unit of ``parameter`` (time in s)."""
        if parameter in self.rate_constants:
            return "1/s^n" if "n" in self.parameters else "1/s"
        if self.name == "midilli" and parameter == "b":
            return "1/s"
        return "-"


MODELS: dict[str, ThinLayerModel] = {m.name: m for m in (
    ThinLayerModel("lewis", "Lewis (Newton)", "MR = exp(-k t)", ("k",), ("k",), "Lewis (1921)"),
    ThinLayerModel("page", "Page", "MR = exp(-k t^n)", ("k", "n"), ("k",), "Page (1949)"),
    ThinLayerModel("henderson_pabis", "Henderson-Pabis", "MR = a exp(-k t)", ("a", "k"), ("k",),
                   "Henderson & Pabis (1961)"),
    ThinLayerModel("logarithmic", "Logarithmic", "MR = a exp(-k t) + c", ("a", "k", "c"), ("k",),
                   "Yagcioglu et al. (1999)"),
    ThinLayerModel("two_term", "Two-term", "MR = a exp(-k0 t) + b exp(-k1 t)", ("a", "k0", "b", "k1"),
                   ("k0", "k1"), "Henderson (1974)"),
    ThinLayerModel("midilli", "Midilli", "MR = a exp(-k t^n) + b t", ("a", "k", "n", "b"), ("k",),
                   "Midilli et al. (2002)"),
)}


def arrhenius(rate_constant, activation_energy, temperature_K, reference_temperature_K):
    """Rate constant at ``temperature_K`` from its value at ``reference_temperature_K`` (K) and the
    activation energy (J/mol): $k_{ref}\\exp[-E_a/R\\,(1/T - 1/T_{ref})]$. Unchecked, vectorised.

    >>> round(float(arrhenius(1e-3, 30e3, 353.15, 338.15)), 7)
    0.0015734
    """
    t = np.asarray(temperature_K, dtype=float)
    return np.asarray(rate_constant, dtype=float) * np.exp(
        -np.asarray(activation_energy, dtype=float) / GAS_CONSTANT * (1.0 / t - 1.0 / np.asarray(reference_temperature_K,
                                                                                                   dtype=float)))


def _at_temperature(model: str, parameters: Mapping, temperature_K, activation_energy, reference_temperature_K):
    """The parameters with the rate constants at ``temperature_K`` (unchecked)."""
    p = dict(parameters)
    if temperature_K is None:
        return p
    for name in MODELS[model].rate_constants:
        p[name] = arrhenius(p[name], activation_energy, temperature_K, reference_temperature_K)
    return p


def _mr(model: str, t, p):
    """Unchecked MR(t) with the rate constants at the temperature of interest (arrays broadcast)."""
    if model == "lewis":
        return np.exp(-p["k"] * t)
    if model == "page":
        return np.exp(-p["k"] * t ** p["n"])
    if model == "henderson_pabis":
        return p["a"] * np.exp(-p["k"] * t)
    if model == "logarithmic":
        return p["a"] * np.exp(-p["k"] * t) + p["c"]
    if model == "two_term":
        return p["a"] * np.exp(-p["k0"] * t) + p["b"] * np.exp(-p["k1"] * t)
    return p["a"] * np.exp(-p["k"] * t ** p["n"]) + p["b"] * t          # midilli


def _mr_rate(model: str, t, p):
    """Unchecked dMR/dt (1/s), negative while drying (t > 0 for the t^n laws)."""
    if model == "lewis":
        return -p["k"] * np.exp(-p["k"] * t)
    if model == "henderson_pabis" or model == "logarithmic":
        return -p["a"] * p["k"] * np.exp(-p["k"] * t)
    if model == "two_term":
        return -p["a"] * p["k0"] * np.exp(-p["k0"] * t) - p["b"] * p["k1"] * np.exp(-p["k1"] * t)
    k, n = p["k"], p["n"]
    g = -k * n * t ** (n - 1.0) * np.exp(-k * t ** n)
    return g if model == "page" else p["a"] * g + p["b"]


def _checked(model, time_s, parameters):
    check_choice("model", model, MODELS)
    names = MODELS[model].parameters
    if not isinstance(parameters, Mapping) or set(parameters) != set(names):
        got = sorted(parameters) if isinstance(parameters, Mapping) else parameters
        raise ValueError(f"parameters = {got!r}: the {model} law takes {', '.join(names)}")
    p = {k: check_range(f"parameters.{k}", parameters[k]) for k in names}
    t = check_range("time_s", time_s, 0.0, math.inf, low_inclusive=True, unit="s")
    return t, p


def moisture_ratio(model: str, time_s, parameters: Mapping, temperature_K=None, activation_energy=0.0,
                   reference_temperature_K=None):
    """Moisture ratio MR of thin-layer law ``model`` at ``time_s`` (s).

    ``parameters`` maps the law's names (`ThinLayerModel.parameters`) to values, the rate
    constants at ``reference_temperature_K``; with ``temperature_K`` (K) they are moved to that
    temperature by Arrhenius with ``activation_energy`` (J/mol), without it they are used as
    given. Vectorised over time, temperature and the parameters.

    >>> round(float(moisture_ratio("page", 3600.0, {"k": 1.5e-3, "n": 0.9})), 4)
    0.0925
    """
    t, p = _checked(model, time_s, parameters)
    if temperature_K is not None:
        check_range("temperature_K", temperature_K, 0.0, math.inf, unit="K")
        check_range("reference_temperature_K", reference_temperature_K, 0.0, math.inf, unit="K")
    return _mr(model, t, _at_temperature(model, p, temperature_K, activation_energy, reference_temperature_K))


def moisture_ratio_rate(model: str, time_s, parameters: Mapping, temperature_K=None, activation_energy=0.0,
                        reference_temperature_K=None):
    """dMR/dt (1/s) of thin-layer law ``model`` at ``time_s`` (s); arguments as
    [`moisture_ratio`][rotarydryer.properties.thin_layer.moisture_ratio]. Negative while drying; infinite at t = 0 for n < 1.

    >>> round(float(moisture_ratio_rate("lewis", 100.0, {"k": 1e-3})), 8)
    -0.00090484
    """
    t, p = _checked(model, time_s, parameters)
    if temperature_K is not None:
        check_range("temperature_K", temperature_K, 0.0, math.inf, unit="K")
        check_range("reference_temperature_K", reference_temperature_K, 0.0, math.inf, unit="K")
    with np.errstate(divide="ignore"):
        return _mr_rate(model, t, _at_temperature(model, p, temperature_K, activation_energy,
                                                  reference_temperature_K))


def check_law(model: str, parameters: Mapping) -> dict:
    """Check that ``parameters`` make ``model`` a drying law (MR decreasing with time to below
    `MR_FLOOR`); returns them as floats. ``ValueError`` names the parameter, its value and the
    allowed range:

    * rate constants k, k0, k1 > 0; exponent n in (0, 10);
    * MR(0) (a; a + b for two-term; a + c for logarithmic) in (`MR_FLOOR`, 2]; a > 0;
    * logarithmic: c < 1 - `MR_FLOOR` (the law must dry below MR_FLOOR);
    * two-term: b > 0 (a negative term makes the moisture rise);
    * Midilli: b <= 0 (b > 0 makes the moisture rise at long times).
    """
    check_choice("model", model, MODELS)
    names = MODELS[model].parameters
    if not isinstance(parameters, Mapping):
        raise ValueError(f"parameters = {parameters!r} must be a table of {', '.join(names)}")
    extra = sorted(set(parameters) - set(names))
    if extra:
        raise ValueError(f"parameters.{extra[0]} is not a parameter of the {model} law (its parameters: "
                         f"{', '.join(names)})")
    missing = [k for k in names if k not in parameters]
    if missing:
        raise ValueError(f"parameters.{missing[0]} is missing (the {model} law takes {', '.join(names)})")
    p = {}
    for k in names:
        v = parameters[k]
        if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) or not math.isfinite(v):
            raise ValueError(f"parameters.{k} = {v!r} must be a finite number")
        p[k] = float(v)

    def fail(key, allowed):
        raise ValueError(f"parameters.{key} = {p[key]:g} is outside the allowed range {allowed} for a drying law")

    for k in MODELS[model].rate_constants:
        if not p[k] > 0:
            fail(k, f"(0, inf) {MODELS[model].unit(k)}")
    if "n" in p and not 0 < p["n"] < 10:
        fail("n", "(0, 10)")
    if "a" in p and not p["a"] > 0:
        fail("a", "(0, inf)")
    if model == "two_term" and not p["b"] > 0:
        fail("b", "(0, inf) (a negative term makes the moisture rise)")
    if model == "midilli" and not p["b"] <= 0:
        fail("b", "(-inf, 0] 1/s (b > 0 makes the moisture rise at long times)")
    if model == "logarithmic" and not p["c"] < 1 - MR_FLOOR:
        fail("c", f"(-inf, {1 - MR_FLOOR:g}) (the law must dry below MR = {MR_FLOOR:g})")
    start = {"henderson_pabis": p.get("a"), "midilli": p.get("a"), "two_term": p.get("a", 0) + p.get("b", 0),
             "logarithmic": p.get("a", 0) + p.get("c", 0)}.get(model)
    if start is not None and not MR_FLOOR < start <= 2.0:
        key = {"two_term": "a + b", "logarithmic": "a + c"}.get(model, "a")
        raise ValueError(f"parameters: MR(0) = {key} = {start:g} is outside the allowed range "
                         f"({MR_FLOOR:g}, 2] for a drying law")
    return p


def _start_time(model: str, p):
    """Where the local rate law starts (module docstring): the peak-rate time for n > 1, else a
    tiny time on the law's own scale (two-term: the faster constant's)."""
    if model == "two_term":
        return _T_START / np.maximum(p["k0"], p["k1"])
    k, n = p["k"], p["n"]
    scale = k ** (-1.0 / n)
    with np.errstate(invalid="ignore"):
        peak = np.where(n > 1.0, (np.maximum(n - 1.0, 0.0) / (n * k)) ** (1.0 / n), 0.0)
    return np.maximum(peak, _T_START * scale)


def _end_time(model: str, p):
    """A time by which MR is below `MR_FLOOR` (b <= 0 only lowers Midilli's MR)."""
    if model == "two_term":
        return np.log((p["a"] + p["b"]) / MR_FLOOR) / np.minimum(p["k0"], p["k1"])
    a = p["a"] if model == "midilli" else 1.0
    return (np.log(np.maximum(a / MR_FLOOR, 1.0 + 1e-12)) / p["k"]) ** (1.0 / p["n"])


def _equivalent_time(model: str, mr, p):
    """t_eq with MR(t_eq) = mr for Page (closed form), two-term and Midilli (bisection in ln t),
    inside [start, end] (unchecked; mr in [MR_FLOOR, MR(start)])."""
    t0, t1 = _start_time(model, p), _end_time(model, p)
    if model == "page":
        t = (-np.log(mr) / p["k"]) ** (1.0 / p["n"])
        return np.clip(t, t0, None)
    lo = np.log(t0) + 0.0 * mr
    hi = np.log(np.maximum(t1, t0)) + 0.0 * mr
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        above = _mr(model, np.exp(mid), p) > mr         # not yet down to mr: t_eq is later
        lo = np.where(above, mid, lo)
        hi = np.where(above, hi, mid)
    return np.exp(0.5 * (lo + hi))


def _drying_rate(model: str, moisture, p, initial_moisture, equilibrium_moisture):
    """Unchecked [`drying_rate`][rotarydryer.properties.thin_layer.drying_rate] (``p``: rate constants at the temperature)."""
    x = np.asarray(moisture, dtype=float)
    span = initial_moisture - equilibrium_moisture
    if model in ("lewis", "henderson_pabis"):
        return p["k"] * (x - equilibrium_moisture)
    if model == "logarithmic":
        return p["k"] * (x - equilibrium_moisture - p["c"] * span)
    mr = (x - equilibrium_moisture) / span
    top = _mr(model, _start_time(model, p), p)
    m = np.clip(mr, MR_FLOOR, np.maximum(top, MR_FLOOR))
    t = _equivalent_time(model, m, p)
    g = -_mr_rate(model, t, p)
    return span * np.where(mr < MR_FLOOR, g * mr / MR_FLOOR, g)


def drying_rate(model: str, moisture, temperature_K, parameters: Mapping, *, activation_energy=0.0,
                reference_temperature_K=None, initial_moisture, equilibrium_moisture=0.0):
    """Local drying rate $-dX/dt$, kg water/(kg dry solid s), of thin-layer law ``model`` at dry-basis
    ``moisture`` (kg/kg dry) in air at ``temperature_K`` (K): the equivalent-time form of the
    module docstring. ``parameters`` at ``reference_temperature_K`` (default: ``temperature_K``,
    i.e. the parameters hold at that temperature), ``activation_energy`` J/mol;
    ``initial_moisture`` X_0 and ``equilibrium_moisture`` X_e of the law, kg/kg dry.

    >>> round(float(drying_rate("lewis", 0.2, 333.15, {"k": 1e-3}, initial_moisture=0.3,
    ...                         equilibrium_moisture=0.02)), 6)
    0.00018
    """
    p = check_law(model, parameters)
    x = check_range("moisture", moisture, unit="kg/kg dry")
    temp = check_range("temperature_K", temperature_K, 0.0, math.inf, unit="K")
    ref = temp if reference_temperature_K is None else check_range("reference_temperature_K",
                                                                  reference_temperature_K, 0.0, math.inf, unit="K")
    ea = float(check_range("activation_energy", activation_energy, unit="J/mol"))
    xe = float(check_range("equilibrium_moisture", equilibrium_moisture, 0.0, math.inf, low_inclusive=True,
                           unit="kg/kg dry"))
    x0 = float(check_range("initial_moisture", initial_moisture, xe, math.inf, unit="kg/kg dry"))
    return _drying_rate(model, x, _at_temperature(model, p, temp, ea, ref), x0, xe)
