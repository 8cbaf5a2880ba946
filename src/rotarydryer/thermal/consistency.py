r"""Is a plant test energetically consistent? Gas flow implied by measured outlets, and bounds.

The gas flow through an industrial dryer is rarely metered (Ajayi (2011) App. A: it is
inferred from fan openings and fan curves; the per-test openings are not published). The
overall steady balance of a test, written on its *measured* inlets and outlets,

$$
\dot H_{g,in}(G) + \dot H_{s,in} = \dot H_{g,out}(G) + \dot H_{s,out} + Q_{loss},
$$

(enthalpies of [`rotarydryer.thermal.streams`][rotarydryer.thermal.streams]; Ajayi (2011) Eq. 6.3 and 6.7 with physical
humid-air enthalpies) has one unknown, the gas flow G, once the shell loss is given: this
module solves it ([`implied_gas_flow`][rotarydryer.thermal.consistency.implied_gas_flow]), and, the other way round, the gas outlet
temperature that a given gas flow allows ([`balance_gas_outlet_temperature`][rotarydryer.thermal.consistency.balance_gas_outlet_temperature]). Any model
that conserves energy obeys these relations, whatever its transfer coefficients, so they
bound what such a model can predict ([`max_gas_outlet_temperature`][rotarydryer.thermal.consistency.max_gas_outlet_temperature]).

[`measured_balances`][rotarydryer.thermal.consistency.measured_balances] applies them to Ajayi's PI data (Tables 3.5-3.11). Findings
(``docs/thermal_dryer.md``): the six tests imply gas flows from 14 to 24 kg/s, so the gas
flow was not constant between tests, and the measured product temperatures (45-50 °C) lie
below the dew point of the exhaust that the measured balance implies (56-62 °C).

All functions: temperatures in °C, flows in kg/s (wet), moisture kg/kg wet basis, humidity
kg/kg dry gas, heat in W.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from .._validation import check_range
from ..properties import humid_air as ha
from ..published import read_published_csv
from .streams import evaporation_rate, exhaust_humidity, implied_heat_loss

__all__ = ["implied_gas_flow", "balance_gas_outlet_temperature", "max_gas_outlet_temperature",
           "TestBalance", "measured_balances", "pi_test_conditions"]

_Y_MAX = 0.3              # kg/kg dry gas, the top of the exhaust humidities these plant-data inversions search


def _loss_at(gas_flow, gas_in_c, gas_humidity_in, gas_out_c, feed_rate, moisture_in, moisture_out, solids_in_c,
             solids_out_c, method, **solids):
    return implied_heat_loss(gas_flow, gas_in_c, gas_humidity_in, gas_out_c, feed_rate, moisture_in, moisture_out,
                             solids_in_c, solids_out_c, method=method, **solids)["heat_loss"]


def _humidity_in(gas_humidity_in) -> float:
    return float(check_range("gas_humidity_in", gas_humidity_in, 0.0, _Y_MAX, low_inclusive=True,
                             unit="kg/kg dry gas"))


def implied_gas_flow(gas_in_c, gas_humidity_in, gas_out_c, feed_rate, moisture_in, moisture_out, solids_in_c,
                     solids_out_c, heat_loss=0.0, method: str = "physical", max_gas_flow=1000.0, **solids) -> float:
    """Wet gas flow into the dryer, kg/s, that closes the overall energy balance of measured data.

    Parameters
    ----------
    gas_in_c, gas_out_c : float
        Gas inlet and outlet temperature, °C (outlet below inlet).
    gas_humidity_in : float
        Inlet gas humidity, kg/kg dry gas.
    feed_rate : float
        Wet feed, kg/s.
    moisture_in, moisture_out : float
        Feed and product moisture, kg/kg wet basis (out < in: the dryer dries).
    solids_in_c, solids_out_c : float
        Feed and product temperature, °C.
    heat_loss : float
        Shell heat loss, W (>= 0).
    method : {"physical", "ajayi2011", "ajayi2011_as_coded"}
        Gas enthalpy accounting ([`rotarydryer.thermal.streams.gas_stream_enthalpy`][rotarydryer.thermal.streams.gas_stream_enthalpy]).
    **solids
        ``solids_heat_capacity``, ``water_heat_capacity`` J/(kg K) of
        [`solids_stream_enthalpy`][rotarydryer.thermal.streams.solids_stream_enthalpy] (default Ajayi's zinc concentrate).

    Raises
    ------
    ValueError
        naming the reason when no gas flow up to ``max_gas_flow`` closes the balance.
    """
    t_in = check_range("gas_in_c", gas_in_c, 0.0, 600.0, low_inclusive=True, high_inclusive=True, unit="degC")
    t_out = check_range("gas_out_c", gas_out_c, 0.0, float(t_in), low_inclusive=True, unit="degC (below gas_in_c)")
    check_range("heat_loss", heat_loss, 0.0, np.inf, low_inclusive=True, unit="W")
    evap = float(evaporation_rate(feed_rate, moisture_in, moisture_out))
    if evap <= 0.0:
        raise ValueError(f"moisture_out = {moisture_out} must be below moisture_in = {moisture_in}: "
                         "the balance implies a gas flow only for a test that dries")
    y_in = _humidity_in(gas_humidity_in)
    g_lo = evap / (_Y_MAX - y_in) * (1.0 + y_in) * (1.0 + 1e-9)   # exhaust at the property range's top
    args = (t_in, y_in, t_out, feed_rate, moisture_in, moisture_out, solids_in_c, solids_out_c, method)

    def resid(g):
        return _loss_at(g, *args, **solids) - heat_loss

    f_lo, f_hi = resid(g_lo), resid(max_gas_flow)
    if f_lo > 0.0:
        raise ValueError(f"even the smallest gas flow that can carry the evaporated water ({g_lo:.3g} kg/s, exhaust "
                         f"at {_Y_MAX} kg/kg) brings more heat than the outlets take: heat_loss = {heat_loss:.4g} W "
                         "is too small for these data")
    if f_hi < 0.0:
        raise ValueError(f"no gas flow up to {max_gas_flow} kg/s supplies the heat the outlets and "
                         f"heat_loss = {heat_loss:.4g} W take (gas {float(t_in)} -> {float(t_out)} degC)")
    from scipy.optimize import brentq  # start-up: scipy.optimize costs 0.4-0.7 s to import

    return float(brentq(resid, g_lo, max_gas_flow, xtol=1e-10, rtol=1e-12))


def balance_gas_outlet_temperature(gas_flow, gas_in_c, gas_humidity_in, feed_rate, moisture_in, moisture_out,
                                   solids_in_c, solids_out_c, heat_loss=0.0, method: str = "physical", **solids) -> float:
    """Gas outlet temperature, °C, at which the overall energy balance closes for a given gas flow.

    Same arguments as [`implied_gas_flow`][rotarydryer.thermal.consistency.implied_gas_flow], with ``gas_flow`` (kg/s wet) given and the gas
    outlet temperature solved. Every energy-conserving model with these inlets and outlets
    (product moisture and temperature) predicts this gas outlet temperature.

    Raises ``ValueError`` when no temperature in 0-600 °C closes the balance (the gas cannot
    supply the heat the solids take, or the water it must carry exceeds 0.3 kg/kg).
    """
    g = float(check_range("gas_flow", gas_flow, 0.0, np.inf, unit="kg/s"))
    y_in = _humidity_in(gas_humidity_in)
    evap = float(evaporation_rate(feed_rate, moisture_in, moisture_out))
    if exhaust_humidity(g, y_in, evap) > _Y_MAX:
        raise ValueError(f"gas_flow = {g} kg/s cannot carry the {evap:.3g} kg/s evaporated: the exhaust would hold "
                         f"more than {_Y_MAX} kg/kg")

    def resid(t_out):
        return _loss_at(g, gas_in_c, y_in, t_out, feed_rate, moisture_in, moisture_out, solids_in_c,
                        solids_out_c, method, **solids) - heat_loss

    r_lo, r_hi = resid(0.0), resid(600.0)
    if r_lo < 0.0:
        raise ValueError(f"gas_flow = {g} kg/s cannot supply the heat: the outlets and heat_loss = {heat_loss:.4g} W "
                         "need more than cooling the gas to 0 degC gives")
    if r_hi > 0.0:
        raise ValueError("the balance needs a gas outlet above 600 degC")
    from scipy.optimize import brentq  # start-up: scipy.optimize costs 0.4-0.7 s to import

    return float(brentq(resid, 0.0, 600.0, xtol=1e-9, rtol=1e-12))


def max_gas_outlet_temperature(gas_flow, gas_in_c, gas_humidity_in, feed_rate, moisture_in, max_moisture_out,
                               solids_in_c, heat_loss=0.0, method: str = "physical") -> dict:
    """Highest gas outlet temperature an energy-conserving dryer can reach, °C, with the product
    no wetter than ``max_moisture_out`` and no colder than the dew point of its exhaust.

    The outlet gas temperature falls as more water is evaporated and as the product leaves
    hotter; the product of a dryer that is still drying at its discharge cannot be colder than
    the dew point of the gas there (co-current: the exhaust), or water would condense on it.
    So the bound is the balance at ``moisture_out = max_moisture_out`` and ``solids_out_c =``
    dew point of the exhaust. Returns a dict with ``gas_out_c``, ``product_c`` (= the dew point),
    ``exhaust_humidity`` (kg/kg dry gas) and ``evaporation`` (kg/s).
    """
    g = float(check_range("gas_flow", gas_flow, 0.0, np.inf, unit="kg/s"))
    y_in = _humidity_in(gas_humidity_in)
    evap = float(evaporation_rate(feed_rate, moisture_in, max_moisture_out))
    y_out = exhaust_humidity(g, y_in, evap)
    t_dew = float(ha.dew_point(min(y_out, _Y_MAX)))
    t_out = balance_gas_outlet_temperature(g, gas_in_c, y_in, feed_rate, moisture_in, max_moisture_out, solids_in_c,
                                           t_dew, heat_loss=heat_loss, method=method)
    return {"gas_out_c": t_out, "product_c": t_dew, "exhaust_humidity": y_out, "evaporation": evap}


def pi_test_conditions(test: int) -> dict:
    """Measured means of Ajayi's test ``test`` (1-6; Tables 3.5-3.11) in SI units.

    Keys: feed_rate (kg/s wet), moisture_in, moisture_out (kg/kg wet), gas_in_c, gas_out_c,
    product_c (°C), rpm, scaled (bool); standard deviations with a ``_sd`` suffix where published.
    """

    r = pi_operating_conditions(test)

    def num(key, scale=1.0):
        return float(r[key]) * scale if r.get(key, "").strip() else float("nan")

    return {"feed_rate": num("solid_feed_t_per_h", 1 / 3.6), "feed_rate_sd": num("solid_feed_sd_t_per_h", 1 / 3.6),
            "moisture_in": num("solid_inlet_moisture_pct", 0.01),
            "moisture_in_sd": num("solid_inlet_moisture_sd_pct", 0.01),
            "moisture_out": num("product_moisture_pct", 0.01), "gas_in_c": num("gas_inlet_T_C"),
            "gas_in_sd": num("gas_inlet_T_sd_C"), "gas_out_c": num("gas_outlet_T_C"),
            "gas_out_sd": num("gas_outlet_T_sd_C"), "product_c": num("product_T_C"), "rpm": num("speed_rpm"),
            "scaled": r["internal_condition"].strip().lower() == "scaled"}


@dataclasses.dataclass(frozen=True)
class TestBalance:
    """Overall balance of one measured test (see [`measured_balances`][rotarydryer.thermal.consistency.measured_balances])."""

    test: int
    evaporation: float             # kg/s, from feed and moisture in/out
    heat_loss: float               # W, shell loss assumed
    gas_flow: float                # kg/s wet, implied with the measured product temperature
    gas_flow_at_product_c: float   # kg/s wet, implied with product_c_assumed
    product_c_assumed: float       # °C
    exhaust_humidity: float        # kg/kg dry gas at gas_flow
    exhaust_dew_point_c: float     # °C at gas_flow
    product_c: float               # °C, measured


def measured_balances(tests: Sequence[int] = (1, 2, 3, 4, 5, 6), heat_loss=0.0, product_c=None,
                      gas_humidity_in=0.0193 / (1 - 0.0193), solids_in_c=28.0,
                      method: str = "physical") -> list[TestBalance]:
    """Gas flow implied by each of Ajayi's PI tests (Tables 3.5-3.11) and the exhaust dew point.

    Parameters
    ----------
    tests : sequence of int
        Test numbers 1-6.
    heat_loss : float or sequence of float
        Shell heat loss per test, W (e.g. the physical model's ``shell_heat_loss_w``).
    product_c : float or sequence of float, optional
        A product temperature, °C, for the second implied gas flow (e.g. the model's); default
        the measured one.
    gas_humidity_in, solids_in_c :
        Inlet gas humidity (kg/kg dry gas; Ajayi l.3227) and feed temperature (°C; l.3241),
        which the PI tables do not give per test.
    """
    n = len(tests)
    losses = np.broadcast_to(np.asarray(heat_loss, dtype=float), (n,))
    out = []
    for i, t in enumerate(tests):
        c = pi_test_conditions(int(t))
        common = dict(gas_in_c=c["gas_in_c"], gas_humidity_in=gas_humidity_in, gas_out_c=c["gas_out_c"],
                      feed_rate=c["feed_rate"], moisture_in=c["moisture_in"], moisture_out=c["moisture_out"],
                      solids_in_c=solids_in_c, heat_loss=float(losses[i]), method=method)
        g = implied_gas_flow(solids_out_c=c["product_c"], **common)
        tp = c["product_c"] if product_c is None else float(np.broadcast_to(product_c, (n,))[i])
        g2 = g if product_c is None else implied_gas_flow(solids_out_c=tp, **common)
        evap = float(evaporation_rate(c["feed_rate"], c["moisture_in"], c["moisture_out"]))
        y_out = exhaust_humidity(g, gas_humidity_in, evap)
        out.append(TestBalance(test=int(t), evaporation=evap, heat_loss=float(losses[i]), gas_flow=g,
                               gas_flow_at_product_c=g2, product_c_assumed=tp, exhaust_humidity=y_out,
                               exhaust_dew_point_c=float(ha.dew_point(y_out)), product_c=c["product_c"]))
    return out


def pi_operating_conditions(test_number):
    """PI operating conditions of an Ajayi test (package data ``ajayi_pi_operating_conditions.csv``): dict."""

    for r in read_published_csv("ajayi_pi_operating_conditions.csv"):
        if int(r["test"]) == int(test_number):
            return r
    raise ValueError(f"test = {test_number} is not one of 1-6")
