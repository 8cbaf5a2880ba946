r"""Humid-air properties for the drying gas, 0-600 °C, humidity 0-0.3 kg/kg dry air, vectorised.

State variables: temperature ``temperature_c`` (°C), humidity ratio ``humidity``
$Y$ (kg water vapour per kg **dry** air) and total pressure ``pressure`` (Pa,
default 101325). Ajayi (2011) writes gas humidity as a mass fraction (kg water/kg
wet gas, his ``H``/``y_w``): convert with [`humidity_from_mass_fraction`][rotarydryer.properties.humid_air.humidity_from_mass_fraction].

Model: ideal mixture of dry air and water vapour (no enhancement factor).

* Heat capacity, enthalpy: NASA polynomials (McBride et al. 2002) for N2, O2, Ar and
  H2O; dry air = 78.12 % N2, 20.96 % O2, 0.92 % Ar (mole). Enthalpy per kg dry air
  relative to dry air at 0 °C and liquid water at 0.01 °C (the ASHRAE/CoolProp
  convention): $h = h_a(T) + Y\,[\Delta h_v(0.01\,°C) + h_v(T) - h_v(0.01\,°C)]$
  (ASHRAE Handbook Fundamentals 2017 ch. 1 Eq. 30 with exact property functions).
* Density: ideal gas, $\rho = P M_a (1+Y)/(R T (1 + Y M_a/M_w))$, per m³ of humid air.
* Viscosity and conductivity: dry air by Lemmon & Jacobsen (2004) (dilute gas), water
  vapour by IAPWS (2008, 2011) (dilute gas); Wilke (1950) / Wassiljewa-Mason-Saxena
  mixing (Poling et al. 2001 Eqs. 9-5.13, 10-6.1).
* Water-vapour diffusivity in air: Marrero & Mason (1972) fit as given by Mills (2001,
  Heat Transfer, Table 3.1 note): $D = 1.87\times10^{-10}T^{2.072}/P$ (280-450 K),
  $2.75\times10^{-9}T^{1.632}/P$ (450-1070 K), P in atm, D in m²/s. Below
  280 K (down to 0 °C) the first branch is extrapolated (≈1 % uncertainty). The two
  branches are blended smoothly over 449.5-450.5 K (they differ there by 2e-4 in value and a
  quarter in slope; the kink made Newton's method cycle), each used unchanged outside.
* Site pressure: [`standard_atmosphere_pressure`][rotarydryer.properties.humid_air.standard_atmosphere_pressure], the
  ISO 2533 (ICAO) standard atmosphere's pressure at an altitude (a case's ``site.altitude``).
* Saturation, relative humidity, dew point, wet bulb: Wagner-Pruss saturation
  pressure ([`.water`][rotarydryer.properties.humid_air.water]); the wet-bulb temperature is the adiabatic-saturation
  (thermodynamic) wet bulb, ASHRAE (2017) ch. 1 Eq. 33, solved by bisection.

Validation (tests/properties/test_humid_air.py): against CoolProp ``HAPropsSI`` (valid to
350 °C) density and enthalpy (0.5 % with a 0.5 kJ/kg floor near h = 0) within 0.5 % over
0-350 °C and Y = 0-0.3 (unsaturated states); heat capacity within 0.5 % for RH ≤ 0.2 and
2 % closer to saturation (HAPropsSI is a real-gas model: 1.6 % at 80 °C, Y = 0.3).
350-600 °C: air and water-vapour values against CoolProp ``PropsSI`` within 0.5 %.
Transport: HAPropsSI evaluates the vapour viscosity/conductivity at saturation at the
total pressure (valid near 100 °C only), so the mixture is checked against Wilke's rule on
CoolProp pure-fluid values (0.5 %, 20-600 °C) and against HAPropsSI at 100 °C (0.5 %).
Relative humidity and wet bulb against psychrolib (10-90 °C: 0.5 %, 0.1 K); wet bulb
against CoolProp within 0.15 K (0-350 °C).

Compatibility option ``method="ajayi2011"`` on [`density`][rotarydryer.properties.humid_air.density], [`viscosity`][rotarydryer.properties.humid_air.viscosity]
and [`thermal_conductivity`][rotarydryer.properties.humid_air.thermal_conductivity]: the dry-air polynomials of Ajayi (2011) Appendix F
(L3825-L3829; fits to Incropera & DeWitt tables, T in °C), independent of humidity.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_choice, check_range
from . import _kernels, water
from .combustion import (
    DRY_AIR_COMPOSITION,
    GAS_CONSTANT,
    MOLAR_MASS,
    _species_enthalpy,
    _species_heat_capacity,
    iapws_vapour_conductivity_dilute,
    iapws_vapour_viscosity_dilute,
    lemmon_jacobsen_conductivity,
    lemmon_jacobsen_viscosity,
)

__all__ = [
    "MOLAR_MASS_DRY_AIR",
    "STANDARD_PRESSURE",
    "humidity_from_mass_fraction",
    "mass_fraction_from_humidity",
    "water_mole_fraction",
    "vapour_partial_pressure",
    "humidity_from_vapour_pressure",
    "gas_composition",
    "dry_air_heat_capacity",
    "humid_heat",
    "heat_capacity",
    "enthalpy",
    "density",
    "viscosity",
    "thermal_conductivity",
    "prandtl_number",
    "water_vapour_diffusivity",
    "schmidt_number",
    "saturation_humidity",
    "relative_humidity",
    "humidity_from_relative_humidity",
    "dew_point",
    "wet_bulb_temperature",
    "standard_atmosphere_pressure",
]

STANDARD_PRESSURE = 101325.0
_AIR_SPECIES = ("N2", "O2", "Ar")
MOLAR_MASS_DRY_AIR = sum(DRY_AIR_COMPOSITION[s] * MOLAR_MASS[s] for s in _AIR_SPECIES)  # kg/mol
_W_AIR = {s: DRY_AIR_COMPOSITION[s] * MOLAR_MASS[s] / MOLAR_MASS_DRY_AIR for s in _AIR_SPECIES}
_RATIO = MOLAR_MASS["H2O"] / MOLAR_MASS_DRY_AIR  # 0.6220
T_MAX_C = 600.0
#: lowest temperature of the humid-air functions, degC: the coldest ambient of a case
#: (shell.ambient_temperature > -40 degC); the vapour pressure is then that over supercooled water
#: (the Wagner-Pruss equation extended, as psychrometric practice does to -40 degC)
T_MIN_C = -40.0
#: highest humidity of the humid-air functions, kg water / kg dry air (water mole fraction 0.62):
#: the ideal-gas mixture and its mixing rules hold at any composition; a counter-current dryer's
#: evaporation-condensation loop (water evaporated at the hot end, condensed on the cold feed and
#: carried back by the solids) holds more than 0.3 kg/kg inside the drum
Y_MAX = 1.0


#: ISO 2533:1975 (ICAO) standard atmosphere, troposphere: sea-level pressure (Pa) and temperature (K),
#: temperature lapse rate (K/m) and the exponent g0 M / (R L) of the pressure law
_ISA_P0, _ISA_T0, _ISA_LAPSE, _ISA_EXPONENT = 101325.0, 288.15, 0.0065, 5.25588


def standard_atmosphere_pressure(altitude_m):
    r"""Pressure of the standard atmosphere at an altitude, Pa (ISO 2533:1975, the ICAO standard
    atmosphere, troposphere): $p = p_0 (1 - L h / T_0)^{g_0 M / (R L)}$ with $p_0$ = 101 325 Pa,
    $T_0$ = 288.15 K, $L$ = 0.0065 K/m and the exponent 5.25588; ``altitude_m`` in m above sea
    level (-2000 to 11 000 m, the troposphere of the standard). The mean pressure of a site: the
    weather moves it by about +-3 %. At 0 m exactly 101 325 Pa.

    >>> float(standard_atmosphere_pressure(0.0)), round(float(standard_atmosphere_pressure(2000.0)))
    (101325.0, 79495)
    """
    h = check_range("altitude_m", altitude_m, -2000.0, 11000.0, low_inclusive=True, high_inclusive=True, unit="m")
    return _ISA_P0 * (1.0 - _ISA_LAPSE * h / _ISA_T0) ** _ISA_EXPONENT


def _temperature(temperature_c, name="temperature_c", high=T_MAX_C):
    return check_range(name, temperature_c, T_MIN_C, high, low_inclusive=True, high_inclusive=True, unit="degC")


def _humidity(humidity):
    return check_range("humidity", humidity, 0.0, Y_MAX, low_inclusive=True, high_inclusive=True,
                       unit="kg/kg dry air")


def _pressure(pressure):
    return check_range("pressure", pressure, 5e4, 2e5, low_inclusive=True, high_inclusive=True, unit="Pa")


def humidity_from_mass_fraction(mass_fraction):
    """Humidity ratio Y, kg/kg dry air, from the water mass fraction y (kg/kg wet gas): Y = y/(1-y).

    >>> round(float(humidity_from_mass_fraction(0.0193)), 5)    # Ajayi (2011) gas inlet, L3227
    0.01968
    """
    y = check_range("mass_fraction", mass_fraction, 0.0, Y_MAX / (1 + Y_MAX), low_inclusive=True,
                    high_inclusive=True, unit="kg/kg wet gas")
    return y / (1.0 - y)


def mass_fraction_from_humidity(humidity):
    """Water mass fraction y, kg/kg wet gas, from the humidity ratio Y: y = Y/(1+Y)."""
    y = _humidity(humidity)
    return y / (1.0 + y)


def water_mole_fraction(humidity):
    """Mole fraction of water vapour in humid air, x = Y/(Y + M_w/M_a)."""
    return _water_mole_fraction(_humidity(humidity))


def _water_mole_fraction(y):
    return y / (y + _RATIO)


def vapour_partial_pressure(humidity, pressure=STANDARD_PRESSURE):
    """Partial pressure of water vapour p_v = x P, Pa (ideal mixture).

    >>> round(float(vapour_partial_pressure(0.01)), 1)
    1603.0
    """
    return _vapour_partial_pressure(_humidity(humidity), _pressure(pressure))


def _vapour_partial_pressure(y, p):
    return _water_mole_fraction(y) * p


def humidity_from_vapour_pressure(vapour_pressure, pressure=STANDARD_PRESSURE):
    """Humidity ratio from the vapour partial pressure: Y = (M_w/M_a) p_v/(P - p_v), kg/kg dry air."""
    p = _pressure(pressure)
    pv = check_range("vapour_pressure", vapour_pressure, 0.0, np.max(p), low_inclusive=True, unit="Pa")
    if np.any(pv >= p):
        raise ValueError("vapour_pressure must be below the total pressure")
    y = _RATIO * pv / (p - pv)
    if np.any(y > Y_MAX):
        raise ValueError(f"vapour_pressure gives humidity {np.max(y):.4g} kg/kg above the model range [0, {Y_MAX}]")
    return y


def gas_composition(humidity):
    """Mole fractions of humid air as a dict for [`rotarydryer.properties.combustion`][rotarydryer.properties.combustion]."""
    xw = water_mole_fraction(humidity)
    comp = {s: DRY_AIR_COMPOSITION[s] * (1.0 - xw) for s in ("N2", "O2", "Ar", "CO2", "SO2")}
    comp["H2O"] = xw
    return comp


def dry_air_heat_capacity(temperature_c):
    """Ideal-gas heat capacity of dry air, J/(kg K).

    >>> round(float(dry_air_heat_capacity(25.0)), 1)
    1004.9
    """
    return _dry_air_heat_capacity(_temperature(temperature_c))


def _dry_air_heat_capacity(t):
    return sum(_W_AIR[s] * _species_heat_capacity(s, t) for s in _AIR_SPECIES)


def _dry_air_enthalpy(t):
    return sum(_W_AIR[s] * _species_enthalpy(s, t, 0.0) for s in _AIR_SPECIES)


def _heat_terms(t, y=0.0):
    """``(_humid_heat(t, y), _dry_air_enthalpy(t), _vapour_enthalpy(t))`` in one compiled pass
    (`._kernels`), or None when the kernels are off."""
    return _kernels.evaluate("heat", (t, y), (_KERNEL_COEFFICIENTS,), 3)


def _enthalpy_parts(t):
    """``(_dry_air_enthalpy(t), _vapour_enthalpy(t))`` of humid air at t °C (unchecked): the parts
    of [`enthalpy`][rotarydryer.properties.humid_air.enthalpy] = air + Y vapour."""
    fast = _heat_terms(t)
    if fast is not None:
        return fast[1:]
    return _dry_air_enthalpy(t), _vapour_enthalpy(t)


def humid_heat(temperature_c, humidity):
    """Humid heat c_s = c_pa + Y c_pv, J/(K kg dry air) (= ∂h/∂T of [`enthalpy`][rotarydryer.properties.humid_air.enthalpy] at constant Y)."""
    y = _humidity(humidity)
    return _humid_heat(_temperature(temperature_c), y)


def _humid_heat(t, y):
    fast = _heat_terms(t, y)
    if fast is not None:
        return fast[0]
    return _dry_air_heat_capacity(t) + y * _species_heat_capacity("H2O", t)


def heat_capacity(temperature_c, humidity):
    """Specific heat capacity of humid air, J/(kg humid air K): (c_pa + Y c_pv)/(1+Y).

    >>> round(float(heat_capacity(100.0, 0.05)), 1)
    1053.0
    """
    y = _humidity(humidity)
    return _heat_capacity(_temperature(temperature_c), y)


def _heat_capacity(t, y):
    return _humid_heat(t, y) / (1.0 + y)


#: latent heat of water at 0.01 degC, J/kg (reference state of the enthalpies)
_LATENT_REF = float(water.latent_heat(0.01))


def _vapour_enthalpy(t):
    """Water vapour at t °C relative to liquid water at 0.01 °C, J/kg (= ∂h/∂Y of [`enthalpy`][rotarydryer.properties.humid_air.enthalpy])."""
    return _LATENT_REF + _species_enthalpy("H2O", t, 0.01)


def enthalpy(temperature_c, humidity):
    """Specific enthalpy of humid air, J/kg **dry air**; zero for dry air at 0 °C and liquid water at 0.01 °C.

    >>> round(float(enthalpy(25.0, 0.01)) / 1e3, 2)
    50.58
    """
    return _enthalpy(_temperature(temperature_c), _humidity(humidity))


def _enthalpy(t, y):
    """Unchecked kernel of [`enthalpy`][rotarydryer.properties.humid_air.enthalpy] (t °C in 0-600, y in 0-0.3)."""
    air, vapour = _enthalpy_parts(t)
    return air + y * vapour


def density(temperature_c, humidity, pressure=STANDARD_PRESSURE, method: str = "ideal_gas"):
    """Density of humid air, kg of humid air per m³.

    ``method="ajayi2011"``: Ajayi (2011) App. F L3827 quartic in T (°C) for air at
    1 atm, independent of humidity and pressure (compatibility only).

    >>> round(float(density(20.0, 0.0)), 4)
    1.2038
    """
    check_choice("method", method, ("ideal_gas", "ajayi2011"))
    t = _temperature(temperature_c)
    y = _humidity(humidity)
    if method == "ajayi2011":
        return _density(t, y, None, method)
    return _density(t, y, _pressure(pressure), method)


def _ajayi_air(t):
    """Ajayi's (2011) air-property polynomials in °C as coded (App. F L3825-L3829), unchecked:
    density kg/m³ (quartic), viscosity Pa s, thermal conductivity W/(m K) (quadratics)."""
    rho = 6.417e-13 * t**4 - 2.673e-9 * t**3 + 4.129e-6 * t**2 - 3.037e-3 * t + 1.225
    mu = -7.479e-12 * t**2 + 3.746e-8 * t + 1.824e-5
    k = -1.249e-8 * t**2 + 6.699e-5 * t + 2.541e-2
    return rho, mu, k


def _density(t, y, p, method="ideal_gas"):
    if method == "ajayi2011":
        return _ajayi_air(t)[0] + 0.0 * y
    return p * MOLAR_MASS_DRY_AIR * (1.0 + y) / (GAS_CONSTANT * (t + 273.15) * (1.0 + y / _RATIO))


def _air_and_vapour(t):
    tk = t + 273.15
    mu_a = lemmon_jacobsen_viscosity("air", tk)
    return (mu_a, iapws_vapour_viscosity_dilute(tk), lemmon_jacobsen_conductivity("air", tk, viscosity=mu_a),
            iapws_vapour_conductivity_dilute(tk))


def _wilke_binary(x1, p1, p2, mu1, mu2, m1, m2):
    x2 = 1.0 - x1
    phi12 = (1.0 + np.sqrt(mu1 / mu2) * (m2 / m1) ** 0.25) ** 2 / np.sqrt(8.0 * (1.0 + m1 / m2))
    phi21 = (1.0 + np.sqrt(mu2 / mu1) * (m1 / m2) ** 0.25) ** 2 / np.sqrt(8.0 * (1.0 + m2 / m1))
    return x1 * p1 / (x1 + x2 * phi12) + x2 * p2 / (x2 + x1 * phi21)


def viscosity(temperature_c, humidity, method: str = "wilke"):
    """Dynamic viscosity of humid air, Pa s.

    ``method="ajayi2011"``: L3829 quadratic for air, independent of humidity.

    >>> round(float(viscosity(20.0, 0.0)) * 1e6, 3)
    18.191
    """
    check_choice("method", method, ("wilke", "ajayi2011"))
    return _viscosity(_temperature(temperature_c), _humidity(humidity), method == "ajayi2011")


def _viscosity(t, y, ajayi2011=False):
    if ajayi2011:
        return _ajayi_air(t)[1] + 0.0 * y
    return _transport(t, y)[0]


def _transport(t, y):
    """Viscosity (Wilke) and thermal conductivity (Mason-Saxena) of humid air, unchecked: (mu, k);
    one compiled pass when the kernels are on (`._kernels`), else `_transport_numpy`."""
    fast = _kernels.evaluate("transport", (t, y), (_KERNEL_COEFFICIENTS,), 2)
    return _transport_numpy(t, y) if fast is None else fast


def _transport_numpy(t, y):
    """`_transport` in NumPy (the reference of the compiled kernel)."""
    mu_a, mu_v, k_a, k_v = _air_and_vapour(t)
    xa = 1.0 - _water_mole_fraction(y)
    return (_wilke_binary(xa, mu_a, mu_v, mu_a, mu_v, MOLAR_MASS_DRY_AIR, MOLAR_MASS["H2O"]),
            _wilke_binary(xa, k_a, k_v, mu_a, mu_v, MOLAR_MASS_DRY_AIR, MOLAR_MASS["H2O"]))


def _pack_kernel_coefficients():
    from . import combustion as cb

    air = ("N2", "O2", "Ar")
    return _kernels.pack(cb._LEMMON_JACOBSEN["air"], cb._LJ2004_B, cb._IAPWS_VISCOSITY_H, cb._IAPWS_CONDUCTIVITY_L,
                         MOLAR_MASS_DRY_AIR, MOLAR_MASS["H2O"], [cb._NASA[s] for s in air + ("H2O",)],
                         [_W_AIR[s] for s in air], [MOLAR_MASS[s] for s in air],
                         [cb._h_reference_scalar(s, 0.0) for s in air] + [cb._h_reference_scalar("H2O", 0.01)],
                         _LATENT_REF, GAS_CONSTANT)


#: the coefficients of the functions above, packed for the compiled kernels (:mod:`._kernels`)
_KERNEL_COEFFICIENTS = _pack_kernel_coefficients()


def thermal_conductivity(temperature_c, humidity, method: str = "mason_saxena"):
    """Thermal conductivity of humid air, W/(m K).

    ``method="ajayi2011"``: L3825 quadratic for air, independent of humidity.

    >>> round(float(thermal_conductivity(20.0, 0.0)) * 1e3, 2)
    25.84
    """
    check_choice("method", method, ("mason_saxena", "ajayi2011"))
    return _thermal_conductivity(_temperature(temperature_c), _humidity(humidity), method == "ajayi2011")


def _thermal_conductivity(t, y, ajayi2011=False):
    if ajayi2011:
        return _ajayi_air(t)[2] + 0.0 * y
    return _transport(t, y)[1]


def prandtl_number(temperature_c, humidity):
    """Prandtl number c_p μ/k of humid air (Ajayi uses the constants 0.7 and 0.70752)."""
    y = _humidity(humidity)   # checked first, as heat_capacity does
    return _prandtl_number(_temperature(temperature_c), y)


def _prandtl_number(t, y):
    mu, k = _transport(t, y)
    return _heat_capacity(t, y) * mu / k


def water_vapour_diffusivity(temperature_c, pressure=STANDARD_PRESSURE):
    """Binary diffusion coefficient of water vapour in air, m²/s (Marrero & Mason 1972).

    Ajayi (2011) uses the constant 2.65e-5 m²/s (L4008), this correlation's value at 33 °C.

    >>> round(float(water_vapour_diffusivity(25.0)) * 1e5, 3)
    2.505
    """
    return _water_vapour_diffusivity(_temperature(temperature_c), _pressure(pressure))


#: Marrero & Mason (1972) fit one power law below 450 K and another above: their values meet there to
#: 2e-4 but their slopes differ by a quarter. Within +-0.5 K of 450 K the two are blended (C2
#: "smootherstep" weight in T), so a solver whose film temperature sits at 450 K sees a smooth function
#: (Newton's method cycled on that kink); outside the window each fit is used unchanged (the shipped
#: cases' steady states move by less than 1e-13).
_D_SWITCH_K, _D_BLEND_K = 450.0, 0.5


def _water_vapour_diffusivity(t_c, p):
    fast = _kernels.evaluate("diffusivity", (np.asarray(t_c, dtype=float) + 273.15,
                                             np.asarray(p, dtype=float) / STANDARD_PRESSURE),
                             (_D_SWITCH_K, _D_BLEND_K), 1)
    return _water_vapour_diffusivity_numpy(t_c, p) if fast is None else fast[0]


def _water_vapour_diffusivity_numpy(t_c, p):
    """`_water_vapour_diffusivity` in NumPy (the reference of the compiled kernel)."""
    t = t_c + 273.15
    p_atm = p / STANDARD_PRESSURE
    low = 1.87e-10 * t**2.072
    high = 2.75e-9 * t**1.632
    s = np.clip((t - (_D_SWITCH_K - _D_BLEND_K)) / (2.0 * _D_BLEND_K), 0.0, 1.0)
    blend = low + s**3 * (s * (6.0 * s - 15.0) + 10.0) * (high - low)
    return np.where(s <= 0.0, low, np.where(s >= 1.0, high, blend)) / p_atm


def schmidt_number(temperature_c, humidity, pressure=STANDARD_PRESSURE):
    """Schmidt number μ/(ρ D) of water vapour in humid air."""
    return _schmidt_number(_temperature(temperature_c), _humidity(humidity), _pressure(pressure))


def _schmidt_number(t, y, p):
    return _viscosity(t, y) / (_density(t, y, p) * _water_vapour_diffusivity(t, p))


def saturation_humidity(temperature_c, pressure=STANDARD_PRESSURE):
    """Humidity of saturated air, kg/kg dry air; raises where p_s(T) ≥ P (no saturated humid air).

    >>> round(float(saturation_humidity(30.0)), 5)
    0.02722
    """
    t = _temperature(temperature_c, high=water.CRITICAL_TEMPERATURE - 273.15)
    p = _pressure(pressure)
    ps = water.saturation_pressure(t)
    if np.any(ps >= p):
        raise ValueError(f"temperature_c = {np.max(t):g} degC is at or above the boiling point at {np.max(p):g} Pa: "
                         "saturated humid air does not exist")
    return _RATIO * ps / (p - ps)


def relative_humidity(temperature_c, humidity, pressure=STANDARD_PRESSURE):
    """Relative humidity p_v/p_s(T), 0-1 (values above 1 mean supersaturation).

    Above the critical temperature (373.946 °C) p_s is capped at the critical pressure
    (vapour cannot condense there; the returned ratio is then only an indicator).

    >>> round(float(relative_humidity(30.0, 0.0137)), 4)
    0.5141
    """
    t = _temperature(temperature_c)
    pv = vapour_partial_pressure(humidity, pressure)
    tc = np.minimum(t, water.CRITICAL_TEMPERATURE - 273.15)
    return pv / water.saturation_pressure(tc)


def humidity_from_relative_humidity(temperature_c, relative_humidity, pressure=STANDARD_PRESSURE):
    """Humidity ratio, kg/kg dry air, from relative humidity (0-1) and temperature (Ajayi 2011 Eqs. A3-A4).

    >>> round(float(humidity_from_relative_humidity(26.0, 0.8)), 5)
    0.01697
    """
    t = _temperature(temperature_c, high=water.CRITICAL_TEMPERATURE - 273.15)
    rh = check_range("relative_humidity", relative_humidity, 0.0, 1.0, low_inclusive=True, high_inclusive=True)
    pv = rh * water.saturation_pressure(t)
    return humidity_from_vapour_pressure(pv, pressure)


def dew_point(humidity, pressure=STANDARD_PRESSURE):
    """Dew-point (frost-point below 0.01 °C) temperature, °C, of humid air.

    >>> round(float(dew_point(0.01)), 3)
    14.039
    """
    y = check_range("humidity", humidity, 0.0, Y_MAX, low_inclusive=False, high_inclusive=True,
                    unit="kg/kg dry air (must be > 0 for a dew point)")
    return water.saturation_temperature(vapour_partial_pressure(y, pressure))


def _wet_bulb_residual(t, y, p):
    """The adiabatic-saturation balance of `wet_bulb_temperature` as a function of a trial wet-bulb
    temperature: positive below the wet bulb, negative above it."""
    h = enthalpy(t, y)

    def residual(tw):
        ps = water.saturation_pressure(tw)
        ys = _RATIO * ps / (p - ps)
        hw = np.where(tw >= 0.0, 4186.0 * (tw - 0.01), -333430.0 + 2040.0 * tw)   # water; ice below 0 degC
        return h + (ys - y) * hw - _enthalpy(tw, ys)
    return residual


def wet_bulb_below(temperature_c, humidity, threshold_c, pressure=STANDARD_PRESSURE):
    """Is the wet-bulb temperature (`wet_bulb_temperature`) below ``threshold_c`` (°C)? One evaluation
    of its balance at the threshold instead of the root (a model's check of its inlet gas)."""
    t, y, p = np.broadcast_arrays(_temperature(temperature_c), _humidity(humidity), _pressure(pressure))
    # the balance one ulp below the threshold: at 0 degC the bulb's enthalpy jumps from ice to water (Eq. 34 / 33),
    # and the question is whether the root lies below, on the ice side (a wet bulb of -0.84 degC was said not to be
    # below 0 degC at 60 kPa)
    at = np.nextafter(float(threshold_c), -np.inf)
    residual = _wet_bulb_residual(t, y, p)
    water = residual(np.zeros_like(t)) > 0      # a liquid bulb at or above 0 degC (`wet_bulb_temperature`)
    root_below = residual(np.full_like(t, at)) < 0
    # above 0 degC: a liquid bulb below the threshold, or an ice bulb (below 0); at or below 0 degC: an ice bulb
    # below the threshold (a liquid bulb is at or above 0 degC)
    below = (~water | root_below) if at > 0 else (~water & root_below)
    return np.asarray(below)


def wet_bulb_temperature(temperature_c, humidity, pressure=STANDARD_PRESSURE):
    r"""Thermodynamic (adiabatic-saturation) wet-bulb temperature, °C.

    Solves $h(T,Y) + (Y_s(T_{wb}) - Y)\,h_w(T_{wb}) = h(T_{wb}, Y_s(T_{wb}))$
    (ASHRAE 2017 ch. 1 Eq. 33) by vectorised secant steps on a bisection bracket to 1e-10 K; h_w is the liquid
    enthalpy from the DIPPR heat capacity, below 0 °C that of ice (ASHRAE 2017 ch. 1 Eq. 34:
    the ice-bulb temperature, over the frost-point vapour pressure). Near 0 °C at low pressure the
    balance has a root on each side of the heat of fusion's jump; the liquid bulb (at or above
    0 °C) is taken then. A wet bulb below T_MIN_C (-40 °C) raises.

    >>> round(float(wet_bulb_temperature(500.0, 0.0197)), 2)
    66.24
    """
    t = _temperature(temperature_c)
    y = _humidity(humidity)
    p = _pressure(pressure)
    t, y, p = np.broadcast_arrays(t, y, p)
    residual = _wet_bulb_residual(t, y, p)
    tb = water.saturation_temperature(p)
    lo = np.full_like(t, T_MIN_C)
    hi = np.minimum(t, tb - 1e-6)
    # the bulb's enthalpy drops by the heat of fusion from water to ice at 0 degC (Eq. 33 / 34), so near 0 degC
    # at low pressure the balance can have a root on each side: the liquid bulb (at or above 0 degC) when the
    # water branch has one, the ice bulb otherwise
    on_water = (residual(np.zeros_like(t)) > 0) & (hi > 0)
    lo = np.where(on_water, 0.0, lo)
    hi = np.where(on_water, hi, np.minimum(hi, np.nextafter(0.0, -np.inf)))
    f_lo = residual(lo)
    if np.any(f_lo < 0):
        raise ValueError(f"wet_bulb_temperature: the wet-bulb temperature is below {T_MIN_C:g} degC, outside the "
                         "model range")
    # secant steps kept inside the bracket (a step that leaves it bisects): the balance falls monotonically
    # through its one root, reached in about 8 evaluations to 1e-10 K instead of 40 bisections
    x0, f0 = lo, f_lo
    x = hi
    f = residual(x)
    for _ in range(100):
        pos = f > 0
        lo = np.where(pos, x, lo)
        hi = np.where(pos, hi, x)
        with np.errstate(divide="ignore", invalid="ignore"):
            xn = x - f * (x - x0) / (f - f0)
        xn = np.where(np.isfinite(xn) & (xn > lo) & (xn < hi), xn, 0.5 * (lo + hi))
        if np.all((np.abs(xn - x) < 1e-10) | (hi - lo < 1e-9)):
            return xn
        x0, f0 = x, f
        x = xn
        f = residual(x)
    return x
