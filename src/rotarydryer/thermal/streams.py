r"""Enthalpy of gas and solids streams and the overall (outlet-data) energy balance of a dryer.

Reference state (as Ajayi 2011, L1885-L1887): liquid water at 0 °C (0.01 °C for the
IAPWS-based physical model), dry gas and dry solids at 0 °C.

Gas stream, [`gas_stream_enthalpy`][rotarydryer.thermal.streams.gas_stream_enthalpy] (W = kg/s x J/kg):

``method="physical"`` (default)
:   humid-air enthalpy of [`rotarydryer.properties.humid_air`][rotarydryer.properties.humid_air] (NASA ideal-gas
    heat capacities, latent heat at 0.01 °C), times the dry-gas flow.

``method="ajayi2011"``
:   Ajayi's Eq. 6.7 path (heat liquid to 100 °C, evaporate at λ = 2257 kJ/kg, superheat):
    $h_g = (1-y)c_{p,g}100 + y c_{p,w}100 + y\lambda + (1-y)c_{p,g}(T-100) + y c_{p,v}(T-100)$
    per kg wet gas, y = mass fraction, c_pg = 1070, c_pw = 4182, c_pv from his cubic read in
    kJ/(kg K) (x 1000: the consistent reading).

``method="ajayi2011_as_coded"``
:   the same with c_pv used as printed (≈ 2 "J/(kg K)", vapour superheat ~1000x too small).

Solids stream, [`solids_stream_enthalpy`][rotarydryer.thermal.streams.solids_stream_enthalpy]: Ajayi Eq. 6.3,
$h_s = (x c_{p,w} + (1-x) c_{p,s})\,T$ per kg wet solids, x wet basis
(c_pw = 4182, c_ps = 505 J/(kg K) for zinc concentrate, L3181-L3182).

[`implied_heat_loss`][rotarydryer.thermal.streams.implied_heat_loss] closes the overall balance on measured outlet data: the heat
that must leave through the shell for the measured outlets to be consistent. For Ajayi's
Test 4 with his gas flow F_ain it is 6.8 MW (notes ajayi_energy.md §2.2; both Cp_v
readings) - the imbalance his θ_loss = 15 absorbs. With the gas flow that his burner
(Appendix A, 750 kg/h fuel) can actually heat to 500 °C it is ~1 MW, of the order of the
physical shell loss ([`.shell`][rotarydryer.thermal.shell]).
"""

from __future__ import annotations

import functools

import numpy as np

from .._validation import check_choice, check_range
from ..properties import humid_air as ha
from ..properties import water

__all__ = ["gas_stream_enthalpy", "solids_stream_enthalpy", "evaporation_rate", "exhaust_humidity", "implied_heat_loss",
           "discharge_cooling",
           "AJAYI_ZINC_HEAT_CAPACITY", "AJAYI_WATER_HEAT_CAPACITY"]

AJAYI_ZINC_HEAT_CAPACITY = 505.0  # J/(kg K), L3182
AJAYI_WATER_HEAT_CAPACITY = 4182.0  # J/(kg K), L3181
AJAYI_GAS_HEAT_CAPACITY = 1070.0  # J/(kg K), L3183
AJAYI_LATENT_HEAT = 2257e3  # J/kg, L3184


def gas_stream_enthalpy(mass_flow, temperature_c, humidity, method: str = "physical"):
    """Enthalpy flow of a humid gas stream, W.

    Parameters
    ----------
    mass_flow : array_like
        Wet-gas mass flow, kg/s.
    temperature_c : array_like
        °C (0-600).
    humidity : array_like
        Humidity ratio, kg water/kg dry gas (Ajayi's mass fraction y = Y/(1+Y)).
    method : {"physical", "ajayi2011", "ajayi2011_as_coded"}

    >>> round(float(gas_stream_enthalpy(112675.6688 / 3600, 500.0, 0.0193 / 0.9807, "ajayi2011_as_coded")) / 1e6, 2)
    18.04
    """
    check_choice("method", method, ("physical", "ajayi2011", "ajayi2011_as_coded"))
    m = check_range("mass_flow", mass_flow, 0.0, np.inf, low_inclusive=True, unit="kg/s")
    t = check_range("temperature_c", temperature_c, 0.0, 600.0, low_inclusive=True, high_inclusive=True,
                    unit="degC")
    y = check_range("humidity", humidity, 0.0, 0.3, low_inclusive=True, high_inclusive=True, unit="kg/kg dry gas")
    if method == "physical":
        return m / (1.0 + y) * ha.enthalpy(t, y)
    yw = y / (1.0 + y)
    cpv = water.vapour_heat_capacity(t, method="ajayi2011" if method == "ajayi2011" else "ajayi2011_as_coded")
    cpg, cpw, lam = AJAYI_GAS_HEAT_CAPACITY, AJAYI_WATER_HEAT_CAPACITY, AJAYI_LATENT_HEAT
    h = (1 - yw) * cpg * 100 + yw * cpw * 100 + yw * lam + (1 - yw) * cpg * (t - 100) + yw * cpv * (t - 100)
    return m * h


def solids_stream_enthalpy(mass_flow, moisture, temperature_c, solids_heat_capacity=AJAYI_ZINC_HEAT_CAPACITY,
                           water_heat_capacity=AJAYI_WATER_HEAT_CAPACITY):
    """Enthalpy flow of wet solids, W; Ajayi (2011) Eq. 6.3 (moisture wet basis, T °C, reference 0 °C).

    >>> round(float(solids_stream_enthalpy(40.644, 0.163, 28.0)) / 1e6, 3)
    1.257
    """
    m = check_range("mass_flow", mass_flow, 0.0, np.inf, low_inclusive=True, unit="kg/s")
    x = check_range("moisture", moisture, 0.0, 1.0, low_inclusive=True, unit="kg/kg wet")
    t = check_range("temperature_c", temperature_c, -20.0, 600.0, unit="degC")      # the gas's bound: solids no hotter
    return m * (x * water_heat_capacity + (1 - x) * solids_heat_capacity) * t


def evaporation_rate(feed_rate, moisture_in, moisture_out):
    """Water evaporated, kg/s, from the wet feed rate and inlet/outlet moisture (wet basis)."""
    f = check_range("feed_rate", feed_rate, 0.0, np.inf, low_inclusive=True, unit="kg/s")
    xi = check_range("moisture_in", moisture_in, 0.0, 1.0, low_inclusive=True)
    xo = check_range("moisture_out", moisture_out, 0.0, 1.0, low_inclusive=True)
    if np.any(xo >= 1.0):
        raise ValueError("moisture_out must be < 1")
    return f - f * (1 - xi) / (1 - xo)


def exhaust_humidity(gas_flow, gas_humidity_in, evaporation):
    """Humidity of the gas leaving, kg/kg dry gas: the inlet's plus the water evaporated into it.

    ``gas_flow`` kg/s wet gas in, ``gas_humidity_in`` kg/kg dry gas, ``evaporation`` kg/s; the
    dry-gas flow gas_flow / (1 + Y_in) is conserved.
    """
    return gas_humidity_in + evaporation * (1.0 + gas_humidity_in) / gas_flow


def implied_heat_loss(gas_flow_in, gas_in_c, gas_humidity_in, gas_out_c, feed_rate, moisture_in, moisture_out,
                      solids_in_c, solids_out_c, method: str = "physical", **solids_kwargs):
    """Overall dryer energy balance on outlet data: heat that must be lost, W, and its parts.

    Returns a dict: evaporation (kg/s), gas_out_humidity (kg/kg dry gas), gas_in, gas_out,
    solids_in, solids_out (W) and heat_loss = gas_in + solids_in - gas_out - solids_out (W).
    The water mass balance closes by construction (evaporated water enters the gas).

    >>> r = implied_heat_loss(112675.6688 / 3600, 500.0, 0.0193 / 0.9807, 131.0, 146320 / 3600, 0.163, 0.124,
    ...                       28.0, 46.0, method="ajayi2011_as_coded")
    >>> round(r["evaporation"], 2), round(r["heat_loss"] / 1e6, 2)
    (1.81, 6.82)
    """
    evap = evaporation_rate(feed_rate, moisture_in, moisture_out)
    g_in = float(np.asarray(gas_flow_in))
    y_in = np.asarray(gas_humidity_in, float)
    y_out = exhaust_humidity(g_in, y_in, evap)
    gas_in = gas_stream_enthalpy(g_in, gas_in_c, y_in, method)
    gas_out = gas_stream_enthalpy(g_in + evap, gas_out_c, y_out, method)
    s_in = solids_stream_enthalpy(feed_rate, moisture_in, solids_in_c, **solids_kwargs)
    s_out = solids_stream_enthalpy(feed_rate - evap, moisture_out, solids_out_c, **solids_kwargs)
    return {"evaporation": float(evap), "gas_out_humidity": float(y_out), "gas_in": float(gas_in),
            "gas_out": float(gas_out), "solids_in": float(s_in), "solids_out": float(s_out),
            "heat_loss": float(gas_in + s_in - gas_out - s_out)}


@functools.lru_cache(maxsize=64)
def _ambient_wet_bulb(ambient_c: float, ambient_humidity: float) -> float:
    """The wet bulb of one ambient air, °C: a case's site, the same for every state of a sweep or a study
    (an iterative solve, 1.4 ms: 7 % of an MMG sweep point)."""
    return float(ha.wet_bulb_temperature(ambient_c, ambient_humidity))


def _wet_bulb(ambient_c, ambient_humidity):
    if np.ndim(ambient_c) == 0 and np.ndim(ambient_humidity) == 0:
        return _ambient_wet_bulb(float(ambient_c), float(ambient_humidity))
    return ha.wet_bulb_temperature(ambient_c, ambient_humidity)


def discharge_cooling(temperature_c, moisture_wet, ntu, ambient_c, ambient_humidity, solids_heat_capacity,
                      water_heat_capacity=4182.0):
    r"""Wet product cooled by ambient air between the drum outlet and a temperature sensor downstream.

    A wet product leaving the drum above the ambient wet-bulb temperature cools on the discharge
    chute or conveyor mostly by evaporation. With the Lewis relation (Le = 1) the driving force of
    the combined heat and mass transfer is the enthalpy difference of saturated air at the solids
    temperature and the ambient air (Merkel 1925, as in cooling-tower design; Mujumdar (2006)
    Handbook of Industrial Drying ch. 1), so the solids temperature relaxes towards the ambient
    wet-bulb temperature $T_{wb}$:

    $$
    T_{sensor} = T_{wb} + (T_p - T_{wb})\,e^{-NTU}
    $$

    where NTU = h a t / c of the exposure (h a: transfer coefficient times area per kg of dry
    solids, t: the time to the sensor, c: the wet solids' heat capacity per kg of dry solids). The
    heat released, $c (T_p - T_{sensor})$, evaporates the share
    $1 - c_h (\bar T - T_a)/(h_s(\bar T) - h_a)$ of it (the sensible part of the Merkel driving
    force at the mean temperature $\bar T$, c_h the humid heat of the ambient air).

    Parameters: product temperature °C and moisture kg/kg wet at the drum outlet; NTU (-, >= 0);
    ambient temperature °C and humidity kg/kg dry air; heat capacities J/(kg K) of the dry solids
    and of water. Returns ``(temperature_c, moisture_wet)`` at the sensor (arrays; NTU = 0 or a
    product at or below the wet bulb: unchanged).

    >>> t, x = discharge_cooling(61.6, 0.124, 0.56, 26.0, 0.0197, 505.0)
    >>> round(float(t), 1), round(float(x), 4)
    (45.9, 0.119)
    """
    tp = np.asarray(temperature_c, dtype=float)
    xw = np.asarray(moisture_wet, dtype=float)
    ntu = np.asarray(check_range("thermal.discharge_cooling_ntu", ntu, 0.0, 50.0, low_inclusive=True,
                                 high_inclusive=True), dtype=float)
    t_wb = _wet_bulb(ambient_c, ambient_humidity)
    drop = np.maximum(tp - t_wb, 0.0) * (1.0 - np.exp(-ntu))
    ts = tp - drop
    x_dry = xw / np.maximum(1.0 - xw, 1e-12)
    c = solids_heat_capacity + water_heat_capacity * x_dry            # J/(K kg dry solids)
    tm = 0.5 * (tp + ts)
    tq = np.minimum(tm, 70.0)     # saturated air above 70 degC leaves the humid-air range (Y > 0.3): its share there
    h_sat = ha.enthalpy(tq, ha.saturation_humidity(tq))
    h_amb = ha.enthalpy(ambient_c, ambient_humidity)
    sensible = ha.humid_heat(ambient_c, ambient_humidity) * (tq - ambient_c)
    share = np.clip(1.0 - sensible / np.maximum(h_sat - h_amb, 1e-9), 0.0, 1.0)
    dx = share * c * drop / water.latent_heat(tm)
    x_new = np.maximum(x_dry - dx, 0.0)
    return ts, x_new / (1.0 + x_new)
