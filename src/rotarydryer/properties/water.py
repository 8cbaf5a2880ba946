r"""Water and steam properties needed by the dryer: vapour pressure, latent heat, heat capacities.

Temperatures are in °C at the API (argument ``temperature_c``), pressures in Pa, SI otherwise.

Saturation (vapour) pressure, [`saturation_pressure`][rotarydryer.properties.water.saturation_pressure]
:   ``"wagner_pruss"`` (default)
    :   Wagner & Pruss (1993), J. Phys. Chem. Ref. Data 22, 783, Eq. 2.5 - the
        auxiliary equation of IAPWS-95 (IAPWS SR1-86(1992)), 0.01-373.946 °C;
        below 0.01 °C the sublimation pressure over ice, IAPWS R14-08(2011) Eq. 6
        (Wagner, Riethmann, Feistel & Harvey 2011). Agrees with IAPWS-95 within
        0.01 % (tests against CoolProp).

    ``"antoine_ajayi2011"``
    :   Ajayi (2011) Eq. 6.33 (after Felder & Rousseau 2005) as coded in his
        Appendix F (L4000): $P = \exp(23.56143 - 4030.182/(T + 235))$, T in °C,
        P in Pa (the text prints 23.561). Within 0.4 % of IAPWS over 0-100 °C,
        drifting to 4 % at 200 °C.

Latent heat of vaporisation, [`latent_heat`][rotarydryer.properties.water.latent_heat]
:   ``"clapeyron_wagner_pruss"`` (default): Clausius-Clapeyron
    $\Delta h = T\,(dp/dT)\,(1/\rho'' - 1/\rho')$ with the Wagner & Pruss
    (1993) auxiliary equations for $p_s$, $\rho'$ (Eq. 2.6) and
    $\rho''$ (Eq. 2.7); within 0.1 % of IAPWS-95 from 0 to 300 °C.
    ``"ajayi2011"``: the constant 2257 kJ/kg of Ajayi's code (L3184; value at 100 °C).
    ``"song2003"``: the constant 2500 kJ/kg of Song (2003) L952 (value at 0 °C).

Heat capacities
:   Liquid, [`liquid_heat_capacity`][rotarydryer.properties.water.liquid_heat_capacity]: ``"dippr"`` (default) DIPPR equation 100
    for water as tabulated in Perry's Chemical Engineers' Handbook (8th ed.,
    Table 2-153), 0-260 °C at saturation; ``"ajayi2011"`` the constant 4182 J/(kg K).
    Vapour (ideal gas), [`vapour_heat_capacity`][rotarydryer.properties.water.vapour_heat_capacity]: ``"nasa"`` (default) NASA
    polynomial (McBride et al. 2002); ``"ajayi2011"`` Ajayi's cubic in T+273
    (Appendix F L3833) read in kJ/(kg K) and returned in J/(kg K) (the physically
    consistent reading); ``"ajayi2011_as_coded"`` the same number used directly as
    J/(kg K), as the gPROMS code does (notes ajayi_energy.md §1.11: a 1000x
    under-weighting of the vapour superheat, kept only to reproduce the thesis).
"""

from __future__ import annotations

import numpy as np

from .._validation import check_choice, check_range
from . import _kernels
from .combustion import MOLAR_MASS, species_heat_capacity

__all__ = [
    "CRITICAL_TEMPERATURE",
    "CRITICAL_PRESSURE",
    "saturation_pressure",
    "saturation_pressure_derivative",
    "saturation_temperature",
    "latent_heat",
    "liquid_heat_capacity",
    "vapour_heat_capacity",
    "MOLAR_MASS_WATER",
]

CRITICAL_TEMPERATURE = 647.096  # K, IAPWS-95
CRITICAL_PRESSURE = 22.064e6  # Pa
CRITICAL_DENSITY = 322.0  # kg/m3
TRIPLE_TEMPERATURE = 273.16  # K
TRIPLE_PRESSURE = 611.657  # Pa
MOLAR_MASS_WATER = MOLAR_MASS["H2O"]

_WP_A = (-7.85951783, 1.84408259, -11.7866497, 22.6807411, -15.9618719, 1.80122502)
_WP_EXP = (1.0, 1.5, 3.0, 3.5, 4.0, 7.5)
_WP_B = (1.99274064, 1.09965342, -0.510839303, -1.75493479, -45.5170352, -6.74694450e05)
_WP_B_EXP = (1 / 3, 2 / 3, 5 / 3, 16 / 3, 43 / 3, 110 / 3)
_WP_C = (-2.03150240, -2.68302940, -5.38626492, -17.2991605, -44.7586581, -63.9201063)
_WP_C_EXP = (2 / 6, 4 / 6, 8 / 6, 18 / 6, 37 / 6, 71 / 6)
_ICE_A = (-0.212144006e2, 0.273203819e2, -0.610598130e1)
_ICE_B = (0.333333333e-2, 0.120666667e1, 0.170333333e1)

_ANTOINE_AJAYI = (23.56143, 4030.182, 235.0)

SATURATION_METHODS = ("wagner_pruss", "antoine_ajayi2011")
_PSAT_COEFFICIENTS = _kernels.pack_psat(CRITICAL_TEMPERATURE, CRITICAL_PRESSURE, TRIPLE_TEMPERATURE, TRIPLE_PRESSURE,
                                        _WP_A, _WP_EXP, _ICE_A, _ICE_B)
LATENT_HEAT_METHODS = ("clapeyron_wagner_pruss", "ajayi2011", "song2003")


def _wp_f(tau):
    return sum(a * tau**e for a, e in zip(_WP_A, _WP_EXP))


def _wp_fprime(tau):
    return sum(a * e * tau ** (e - 1) for a, e in zip(_WP_A, _WP_EXP))


def _psat_liquid_k(t):
    tau = 1.0 - t / CRITICAL_TEMPERATURE
    return CRITICAL_PRESSURE * np.exp(CRITICAL_TEMPERATURE / t * _wp_f(tau))


def _psat_ice_k(t):
    theta = t / TRIPLE_TEMPERATURE
    return TRIPLE_PRESSURE * np.exp(sum(a * theta**b for a, b in zip(_ICE_A, _ICE_B)) / theta)


def saturation_pressure(temperature_c, method: str = "wagner_pruss"):
    """Saturation vapour pressure of water (over ice below 0.01 °C), Pa.

    Parameters
    ----------
    temperature_c : array_like
        Temperature, °C; -100 to 373.946 °C for ``"wagner_pruss"``, -50 to 250 °C for
        the Antoine form (beyond which it is meaningless).
    method : {"wagner_pruss", "antoine_ajayi2011"}
        See the module docstring.

    Examples
    --------
    >>> round(float(saturation_pressure(100.0)), 0)
    101418.0
    >>> round(float(saturation_pressure(100.0, method="antoine_ajayi2011")), 0)
    101828.0
    """
    check_choice("method", method, SATURATION_METHODS)
    if method == "antoine_ajayi2011":
        check_range("temperature_c", temperature_c, -50.0, 250.0, low_inclusive=True, high_inclusive=True,
                    unit="degC")
    else:
        check_range("temperature_c", temperature_c, -100.0, CRITICAL_TEMPERATURE - 273.15, low_inclusive=True,
                    high_inclusive=True, unit="degC")
    return _saturation_pressure(temperature_c, method)


def _saturation_pressure(temperature_c, method="wagner_pruss"):
    """Unchecked kernel of [`saturation_pressure`][rotarydryer.properties.water.saturation_pressure] (inputs already validated)."""
    if method == "antoine_ajayi2011":
        a, b, c = _ANTOINE_AJAYI
        return np.exp(a - b / (np.asarray(temperature_c, dtype=float) + c))
    t = np.asarray(temperature_c, dtype=float) + 273.15
    fast = _kernels.evaluate("psat", (t,), (_PSAT_COEFFICIENTS,), 1)
    return _saturation_pressure_numpy_k(t) if fast is None else fast[0]


def _saturation_pressure_numpy_k(t):
    """Wagner-Pruss / IAPWS sublimation pressure at t K in NumPy (the reference of the compiled kernel)."""
    liquid = t >= TRIPLE_TEMPERATURE
    return np.where(liquid, _psat_liquid_k(np.maximum(t, TRIPLE_TEMPERATURE)),
                    _psat_ice_k(np.minimum(t, TRIPLE_TEMPERATURE)))


def saturation_pressure_derivative(temperature_c):
    """dp_s/dT of the Wagner-Pruss equation, Pa/K, 0.01-373.9 °C (liquid-vapour line)."""
    t = check_range("temperature_c", temperature_c, 0.01, CRITICAL_TEMPERATURE - 273.15 - 1e-6,
                    low_inclusive=True, high_inclusive=True, unit="degC") + 273.15
    tau = 1.0 - t / CRITICAL_TEMPERATURE
    p = _psat_liquid_k(t)
    return -p / t * (np.log(p / CRITICAL_PRESSURE) + _wp_fprime(tau))


def saturation_temperature(pressure):
    """Saturation (boiling or frost) temperature, °C, at vapour pressure ``pressure`` Pa.

    Inverse of [`saturation_pressure`][rotarydryer.properties.water.saturation_pressure] (Wagner-Pruss / IAPWS ice), solved by a
    vectorised Newton iteration on ln p (converges to 1e-10 K in < 10 steps).
    Range 0.0015 Pa (-100 °C) to 22.064 MPa.

    >>> round(float(saturation_temperature(101325.0)), 3)
    99.974
    """
    p = check_range("pressure", pressure, saturation_pressure(-100.0), CRITICAL_PRESSURE, low_inclusive=True,
                    high_inclusive=True, unit="Pa")
    lnp = np.log(p)
    # initial guess from a two-constant Clausius-Clapeyron fit through (0.01 C, 100 C)
    t = 1.0 / (1.0 / 273.16 - (lnp - np.log(611.657)) * 8.314462618 / (MOLAR_MASS_WATER * 2.5e6))
    t = np.clip(t, 173.15, CRITICAL_TEMPERATURE)
    for _ in range(50):
        ps = np.where(t >= TRIPLE_TEMPERATURE, _psat_liquid_k(np.maximum(t, TRIPLE_TEMPERATURE)),
                      _psat_ice_k(np.minimum(t, TRIPLE_TEMPERATURE)))
        h = 1e-4
        ps2 = np.where(t + h >= TRIPLE_TEMPERATURE, _psat_liquid_k(np.maximum(t + h, TRIPLE_TEMPERATURE)),
                       _psat_ice_k(np.minimum(t + h, TRIPLE_TEMPERATURE)))
        dlnp = (np.log(ps2) - np.log(ps)) / h
        step = (np.log(ps) - lnp) / dlnp
        t = np.clip(t - step, 173.15, CRITICAL_TEMPERATURE)
        if np.all(np.abs(step) < 1e-10):
            break
    return t - 273.15


def latent_heat(temperature_c, method: str = "clapeyron_wagner_pruss"):
    """Latent heat of vaporisation of water, J/kg, at temperature °C (0-370 °C).

    Examples
    --------
    >>> round(float(latent_heat(100.0)) / 1e3, 1)
    2256.6
    >>> float(latent_heat(100.0, method="ajayi2011"))
    2257000.0
    """
    check_choice("method", method, LATENT_HEAT_METHODS)
    t = check_range("temperature_c", temperature_c, 0.0, 370.0, low_inclusive=True, high_inclusive=True,
                    unit="degC")
    if method == "ajayi2011":
        return np.full_like(t, 2257.0e3)
    if method == "song2003":
        return np.full_like(t, 2500.0e3)
    tc = np.maximum(t, 0.01)
    tk = tc + 273.15
    tau = 1.0 - tk / CRITICAL_TEMPERATURE
    rho_l = CRITICAL_DENSITY * (1.0 + sum(b * tau**e for b, e in zip(_WP_B, _WP_B_EXP)))
    rho_v = CRITICAL_DENSITY * np.exp(sum(c * tau**e for c, e in zip(_WP_C, _WP_C_EXP)))
    return tk * saturation_pressure_derivative(tc) * (1.0 / rho_v - 1.0 / rho_l)


def liquid_heat_capacity(temperature_c, method: str = "dippr"):
    """Specific heat capacity of liquid water, J/(kg K), 0-260 °C.

    ``"dippr"``: Perry's Handbook (8th ed.) Table 2-153, DIPPR Eq. 100,
    $c_p = (276370 - 2090.1T + 8.125T^2 - 0.014116T^3 + 9.3701\\times10^{-6}T^4)/M$
    J/(kmol K), T in K, M = 18.015 kg/kmol. ``"ajayi2011"``: 4182 J/(kg K) (L3181).

    >>> round(float(liquid_heat_capacity(25.0)), 0)
    4184.0
    """
    check_choice("method", method, ("dippr", "ajayi2011"))
    t = check_range("temperature_c", temperature_c, 0.0, 260.0, low_inclusive=True, high_inclusive=True,
                    unit="degC")
    if method == "ajayi2011":
        return np.full_like(t, 4182.0)
    tk = t + 273.15
    cp_molar = 276370.0 - 2090.1 * tk + 8.125 * tk**2 - 0.014116 * tk**3 + 9.3701e-6 * tk**4
    return cp_molar / (MOLAR_MASS_WATER * 1000.0)


def vapour_heat_capacity(temperature_c, method: str = "nasa"):
    """Ideal-gas specific heat capacity of water vapour, J/(kg K), -73 to 727 °C.

    Examples
    --------
    >>> round(float(vapour_heat_capacity(500.0)), 0)
    2132.0
    >>> round(float(vapour_heat_capacity(500.0, method="ajayi2011")), 0)
    2124.0
    >>> round(float(vapour_heat_capacity(500.0, method="ajayi2011_as_coded")), 3)
    2.124
    """
    check_choice("method", method, ("nasa", "ajayi2011", "ajayi2011_as_coded"))
    if method == "nasa":
        return species_heat_capacity("H2O", temperature_c)
    t = check_range("temperature_c", temperature_c, -73.15, 726.85, low_inclusive=True, high_inclusive=True,
                    unit="degC")
    return _ajayi_vapour_cp_kj(t) * (1000.0 if method == "ajayi2011" else 1.0)


def _ajayi_vapour_cp_kj(temperature_c):
    """Ajayi's (2011) water-vapour c_p cubic as coded (App. F L3833), numerically kJ/(kg K); unchecked."""
    tk = temperature_c + 273.0  # Ajayi uses T + 273
    return -3.1759e-10 * tk**3 + 9.1451537e-07 * tk**2 - 1.4971847134e-04 * tk + 1.84044937134494
