r"""Moisture and energy balances of the solids and the gas, per cell (issue 6).

Pure, vectorised building blocks used by [`rotarydryer.thermal.dryer`][rotarydryer.thermal.dryer]:

* **Stream enthalpies** with two selectable accountings (``enthalpy=``):

  ``"physical"`` (default)
      gas: humid-air enthalpy per kg dry gas from [`rotarydryer.properties.humid_air.enthalpy`][rotarydryer.properties.humid_air.enthalpy]
      (NASA-polynomial heat capacities, latent heat at 0.01 °C); vapour leaving wet
      solids at T_s carries $h_v(T_s) = \lambda_0 + \int_0^{T_s} c_{p,v}dT$, the
      same function, so the gas and solids balances are mutually conservative.
  ``"ajayi2011"``
      Ajayi (2011) Eq. 6.7 exactly as coded (App. F L3729-L3760): per kg wet gas
      $h = (1-y)c_{p,g}100 + y c_{p,w}100 + y\lambda + (1-y)c_{p,g}(T-100) + y c_{p,v}(T-100)$
      with c_p,g = 1070 J/(kg K), λ = 2257 kJ/kg and Ajayi's c_p,v polynomial **in kJ/(kg K)**
      (the units error of notes ajayi_energy.md §1.11, kept for reproduction); the
      evaporation source is $R_w(\lambda + c_{p,w}T_s)$ (Eqs. 6.4, 6.7).

  Wet solids (both accountings): $h_s = ((1-x)c_{p,s} + x c_{p,w})T$ per kg wet
  solid, i.e. per kg dry solid $(c_{p,s} + X c_{p,w})T$ (Ajayi (2011) Eq. 6.3,
  reference 0 °C), c_p,s = 505, c_p,w = 4182 J/(kg K) (App. F L3181-L3182).

* **Contact area** (drying only where the solids meet the gas):

  - curtain (active phase of a flighted cell), Ajayi (2011) Eq. 6.62-6.63:
    $A_a = \theta_a m_a\,3/(d_p\rho_p)$ (half of each particle surface exposed);
  - active layer of a rolling bed (unflighted sections), Eq. 6.56-6.61:
    bed segment area $A_{kiln} = m/(\rho_b\Delta z) = R^2(\theta_k - \sin\theta_k)/2$,
    chord $L_c = 2R\sin(\theta_k/2)$, active-layer mass
    $M_{AL} = L_c d_p/A_{kiln}\cdot m$, area
    $A = \theta_{AL}M_{AL}\,3/(d_p\rho_p) = 3\theta_{AL}L_c\rho_b\Delta z/\rho_p$.
    Ajayi evaluates θ_k once per section at the outlet holdup; here it is evaluated per
    slice from the local holdup and local bulk density (the evident intent).

  θ_a, θ_AL are the area correction factors (Ajayi (2011) l.2278: A 2.4, B 1.2, C 0.6,
  D 0.42, E 1.4).

* **Transfer rates** gas -> solids in one gas stage ([`stage_transfer`][rotarydryer.thermal.balances.stage_transfer]):
  convection $Q_c = h_cA(T_g - T_s)$ with Ajayi's $Nu = 0.33Re^{0.6}$ (Eq. 6.41,
  superficial gas velocity over the drum cross-section), radiation gas -> solids
  (Eq. 6.42; ``"ajayi2011"``: ε_s σ A (T_g⁴ - T_s⁴); physical: grey exchange with the WSGG
  gas emissivity), evaporation $R_w = A\,f(X)\,N_w$ with the kinetics of
  [`rotarydryer.thermal.drying`][rotarydryer.thermal.drying] (Chilton-Colburn analogy, Eq. 6.45-6.49). Transfer is
  evaluated at the stage (= outlet) gas temperature as in Ajayi's code (well-mixed stage).

Temperatures in °C (enthalpy reference 0 °C), humidity Y in kg water/kg dry gas, moisture
X in kg water/kg dry solid (Ajayi's x_w = X/(1+X) wet basis at the public API).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .._validation import check_choice, check_finite, check_range
from ..properties import _kernels, water
from ..properties import humid_air as ha
from ..properties.drying import DryingKinetics
from . import radiation as rad

__all__ = ["ENTHALPY_METHODS", "AJAYI_CP_SOLIDS", "AJAYI_CP_WATER", "AJAYI_CP_GAS", "AJAYI_LATENT_HEAT",
           "gas_enthalpy", "gas_heat_capacity", "vapour_source_enthalpy", "solids_enthalpy", "kilning_angle",
           "active_layer_area", "curtain_area", "gas_solids_coefficient", "stage_transfer", "solids_temperature_ceiling"]

ENTHALPY_METHODS = ("physical", "ajayi2011")
AJAYI_CP_SOLIDS = 505.0      # J/(kg K), zinc concentrate, App. F L3182
AJAYI_CP_WATER = 4182.0      # J/(kg K), L3181
AJAYI_CP_GAS = 1070.0        # J/(kg K), L3183
AJAYI_LATENT_HEAT = 2257e3   # J/kg, L3184
SIGMA = 5.67e-8              # W/(m2 K4)
_T_LO, _T_HI = ha.T_MIN_C, ha.T_MAX_C    # property range of humid_air, degC


def _tc(t):
    return np.minimum(np.maximum(np.asarray(t, dtype=float), _T_LO), _T_HI)


def _yc(y, low=0.0):
    return np.minimum(np.maximum(np.asarray(y, dtype=float), low), ha.Y_MAX)


def _check_gas_state(temperature_c, humidity, method):
    """Checks of the gas-enthalpy functions: the method, and (physical) the clipped state is finite."""
    check_choice("method", method, ENTHALPY_METHODS)
    if method == "physical":
        ha._temperature(_tc(temperature_c))
        ha._humidity(_yc(humidity))


_ajayi_cpv = water._ajayi_vapour_cp_kj   # Ajayi's vapour c_p cubic as coded (L3833), numerically kJ/(kg K)


def gas_enthalpy(temperature_c, humidity, method: str = "physical"):
    r"""Specific enthalpy of the dryer gas, J per kg **dry** gas.

    ``method="physical"``: [`rotarydryer.properties.humid_air.enthalpy`][rotarydryer.properties.humid_air.enthalpy] (reference dry
    air at 0 °C, liquid water at 0.01 °C). ``"ajayi2011"``: Ajayi (2011) Eq. 6.7 as coded, per
    kg wet gas times (1 + Y) (c_p,v in kJ/(kg K) as coded - see module docstring).
    Outside the 0-600 °C property range (solver trial states) the enthalpy is continued linearly.

    >>> round(float(gas_enthalpy(500.0, 0.0197, "ajayi2011")) / 1e3, 1)
    587.7
    """
    _check_gas_state(temperature_c, humidity, method)
    return _gas_enthalpy(temperature_c, humidity, method)


def _gas_enthalpy(temperature_c, humidity, method):
    """Unchecked kernel of [`gas_enthalpy`][rotarydryer.thermal.balances.gas_enthalpy]."""
    t_raw = np.asarray(temperature_c, dtype=float)
    t = _tc(t_raw)
    y = _yc(humidity)
    if method == "physical":
        return _physical_enthalpy(t_raw, t, *ha._enthalpy_parts(t), y)
    ext = _extension(t_raw, t, y)
    yw = y / (1.0 + y)
    cpg, cpw, lam = AJAYI_CP_GAS, AJAYI_CP_WATER, AJAYI_LATENT_HEAT
    h = (1 - yw) * cpg * 100 + yw * cpw * 100 + yw * lam + (1 - yw) * cpg * (t - 100) + yw * _ajayi_cpv(t) * (t - 100)
    return (1.0 + y) * h + ext


def _gas_enthalpy_pair(temperature_c, humidity, dy, method):
    """``(_gas_enthalpy(T, Y), _gas_enthalpy(T, Y + dy))``: the same numbers, the temperature
    functions of the physical enthalpy evaluated once for both."""
    if method != "physical":
        return _gas_enthalpy(temperature_c, humidity, method), _gas_enthalpy(temperature_c, humidity + dy, method)
    t_raw = np.asarray(temperature_c, dtype=float)
    t = _tc(t_raw)
    air, vapour = ha._enthalpy_parts(t)
    return tuple(_physical_enthalpy(t_raw, t, air, vapour, _yc(y))
                 for y in (humidity, np.asarray(humidity, dtype=float) + dy))


def _extension(t_raw, t, y):
    """Outside 0-600 degC (solver trial states only) the enthalpy continues linearly, so the balance
    keeps a restoring slope: (T - T_clipped)(1150 + 2200 Y), J/kg dry gas."""
    return (t_raw - t) * (1150.0 + 2200.0 * y)


def _physical_enthalpy(t_raw, t, air, vapour, y):
    """Humid-air enthalpy ([`rotarydryer.properties.humid_air.enthalpy`][rotarydryer.properties.humid_air.enthalpy] from its dry-air and
    vapour parts at the clipped temperature ``t``) plus `_extension`."""
    return air + y * vapour + _extension(t_raw, t, y)


def gas_heat_capacity(temperature_c, humidity, method: str = "physical"):
    """∂h/∂T of [`gas_enthalpy`][rotarydryer.thermal.balances.gas_enthalpy] at constant Y within 0-600 °C, J/(kg dry gas K).

    ``"physical"``: exact, the humid heat [`rotarydryer.properties.humid_air.humid_heat`][rotarydryer.properties.humid_air.humid_heat];
    ``"ajayi2011"``: central difference over ±0.05 K."""
    _check_gas_state(temperature_c, humidity, method)
    return _gas_heat_capacity(temperature_c, humidity, method)


def _gas_heat_capacity(temperature_c, humidity, method):
    """Unchecked kernel of [`gas_heat_capacity`][rotarydryer.thermal.balances.gas_heat_capacity]."""
    if method == "physical":
        return ha._humid_heat(_tc(temperature_c), _yc(humidity))
    t = np.minimum(np.maximum(np.asarray(temperature_c, dtype=float), _T_LO + 0.05), _T_HI - 0.05)
    return (_gas_enthalpy(t + 0.05, humidity, method) - _gas_enthalpy(t - 0.05, humidity, method)) / 0.1


def vapour_source_enthalpy(solids_temperature_c, method: str = "physical"):
    r"""Enthalpy carried by 1 kg of water evaporated from solids at T_s into the gas, J/kg.

    ``"physical"``: $\lambda(0.01\,°C) + \Delta h_{vap}(0.01 \to T_s)$ consistent with
    [`gas_enthalpy`][rotarydryer.thermal.balances.gas_enthalpy]; ``"ajayi2011"``: $\lambda + c_{p,w}T_s$ (Ajayi (2011) Eq. 6.4, 6.7).
    """
    check_choice("method", method, ENTHALPY_METHODS)
    if method == "physical":
        check_finite("temperature_c", _tc(solids_temperature_c))
    return _vapour_source_enthalpy(solids_temperature_c, method)


def _vapour_source_enthalpy(solids_temperature_c, method):
    """Unchecked kernel of [`vapour_source_enthalpy`][rotarydryer.thermal.balances.vapour_source_enthalpy]."""
    t = _tc(solids_temperature_c)
    if method == "ajayi2011":
        return AJAYI_LATENT_HEAT + AJAYI_CP_WATER * t
    return ha._enthalpy_parts(t)[1]       # = ha._vapour_enthalpy(t), compiled with the dry-air part when on


def solids_enthalpy(temperature_c, moisture_dry, cp_solids=AJAYI_CP_SOLIDS, cp_water=AJAYI_CP_WATER):
    r"""Enthalpy of wet solids per kg **dry** solid, J/kg: $(c_{p,s} + Xc_{p,w})T$ (Ajayi (2011) Eq. 6.3).

    >>> float(solids_enthalpy(10.0, 0.25))
    15505.0
    """
    t = np.asarray(temperature_c, dtype=float)
    x = np.asarray(moisture_dry, dtype=float)
    return (cp_solids + x * cp_water) * t


_THETA_GRID = np.linspace(0.0, 2 * math.pi, 4001)
_SEG_GRID = (_THETA_GRID - np.sin(_THETA_GRID)) / (2 * math.pi)   # fill fraction of the circle


def kilning_angle(fill_fraction):
    r"""Central angle θ_k (rad) of a bed filling ``fill_fraction`` of the drum cross-section.

    Inverts $f = (\theta_k - \sin\theta_k)/(2\pi)$ (Ajayi (2011) Eq. 6.56 divided by πR²),
    by interpolation on a 4001-point table (error < 1e-6 rad away from f = 0).

    >>> round(float(kilning_angle(0.5)), 6)
    3.141593
    """
    f = check_range("fill_fraction", fill_fraction, 0.0, 1.0, low_inclusive=True, high_inclusive=True)
    return np.interp(f, _SEG_GRID, _THETA_GRID)


def active_layer_area(holdup, bulk_density, slice_length, radius, particle_diameter, area_factor,
                      particle_density=2800.0):
    r"""Gas-exposed area of the active layer of a rolling bed slice, m² (Ajayi (2011) Eq. 6.56-6.61).

    Parameters: holdup kg per slice; bulk density kg/m³; slice length m; drum radius m;
    particle diameter m; area factor θ_AL (-); particle density kg/m³ (2800, L3185).
    $A = 3\theta_{AL}L_c\rho_b\Delta z/\rho_p$ with the chord L_c of the bed surface.

    >>> round(float(active_layer_area(600.0, 1540.0, 0.105, 1.95, 0.02, 2.4)), 3)
    1.546
    """
    m = np.maximum(np.asarray(holdup, dtype=float), 0.0)
    rho = np.asarray(bulk_density, dtype=float)
    fill = np.minimum(np.maximum(m / (rho * slice_length * math.pi * radius**2), 0.0), 1.0)
    theta = np.interp(fill, _SEG_GRID, _THETA_GRID)
    chord = 2.0 * radius * np.sin(theta / 2.0)
    return 3.0 * area_factor * chord * rho * slice_length / particle_density


def curtain_area(active_holdup, particle_diameter, area_factor, particle_density=2800.0):
    r"""Gas-exposed area of airborne (active) solids, m²: $\theta_a m_a 3/(d_p\rho_p)$ (Ajayi (2011) Eq. 6.63).

    >>> round(float(curtain_area(100.0, 0.015, 1.2)), 3)
    8.571
    """
    return area_factor * np.maximum(np.asarray(active_holdup, dtype=float), 0.0) * 3.0 / (
        np.asarray(particle_diameter, dtype=float) * particle_density)


def gas_solids_coefficient(gas_mass_flow, temperature_c, humidity, particle_diameter, radius,
                           properties: str = "physical"):
    r"""Convective gas-solids coefficient h_c, W/(m² K), and Re: Ajayi (2011) Eq. 6.41, Nu = 0.33 Re^0.6.

    Re on the particle diameter with the superficial velocity $v_g = F_g/(\rho_g\pi R^2)$;
    properties from [`rotarydryer.properties.humid_air`][rotarydryer.properties.humid_air] (``"physical"``) or Ajayi's air
    polynomials (``"ajayi2011"``). Since ρ_g v_g = F_g/(πR²), Re does not depend on the density.
    """
    t = _tc(temperature_c)
    y = _yc(humidity)
    ha._temperature(t)     # only NaN can fail (clipped): the checks of the humid-air properties
    ha._humidity(y)
    return _gas_solids_coefficient(gas_mass_flow, t, y, particle_diameter, radius, properties)


def _gas_solids_coefficient(gas_mass_flow, t, y, particle_diameter, radius, properties):
    """Unchecked kernel of [`gas_solids_coefficient`][rotarydryer.thermal.balances.gas_solids_coefficient] (t, y clipped to the property range)."""
    if properties == "ajayi2011":
        mu, k = ha._viscosity(t, y, True), ha._thermal_conductivity(t, y, True)
    else:
        mu, k = ha._transport(t, y)
    g = np.asarray(gas_mass_flow, dtype=float) / (math.pi * radius**2)
    re = g * particle_diameter / mu
    return 0.33 * re**0.6 * k / particle_diameter, re


def stage_transfer(area, moisture_dry, solids_temperature_c, gas_temperature_c, humidity, gas_mass_flow,
                   particle_diameter, radius, kinetics: DryingKinetics, *, mode: str = "physical",
                   pressure=101325.0, co2_mole_fraction=0.011, solids_emissivity=0.9, dry_guard=2e-3):
    r"""Gas -> solids transfer in a set of gas stages: (R_w kg/s, Q_conv W, Q_rad W), arrays.

    * R_w: evaporation, ``kinetics.rate`` ([`rotarydryer.thermal.drying`][rotarydryer.thermal.drying]; Ajayi (2011)
      Eq. 6.32-6.49) times a guard min(1, X/``dry_guard``) that stops evaporation of the
      last traces of water (X in kg/kg dry; kinetics without a falling rate would otherwise
      drive the moisture negative). Solids temperature is clipped to 0 °C -
      [`solids_temperature_ceiling`][rotarydryer.thermal.balances.solids_temperature_ceiling] (99 °C, lower at
      altitude) for the surface-evaporation model (boiling is outside its range).
    * Q_conv = h_c A (T_g - T_s) (Eq. 6.40-6.41).
    * Q_rad: ``mode="ajayi2011"`` ε_s σ A (T_g⁴ - T_s⁴) (Eq. 6.42 as coded); ``"physical"``
      grey exchange with the WSGG emissivity of the H2O/CO2 gas over the mean beam length
      0.95 D ([`rotarydryer.thermal.radiation`][rotarydryer.thermal.radiation]).

    Checks: clipped gas temperature, humidity and solids temperature finite; area >= 0;
    gas_mass_flow >= 0; particle_diameter, radius > 0; pressure 5e4-2e5 Pa; CO2 partial
    pressure 0-1e6 Pa and radius < 50 m (mean beam length) in the physical mode.
    """
    tg = _tc(gas_temperature_c)
    ha._temperature(tg)     # clipped: only NaN can fail
    ha._humidity(_yc(humidity, 1e-6))
    check_range("gas_mass_flow", gas_mass_flow, 0.0, np.inf, low_inclusive=True, unit="kg/s")
    check_range("particle_diameter", particle_diameter, 0.0, np.inf, unit="m")
    check_range("radius", radius, 0.0, np.inf, unit="m")
    a = check_range("area", np.asarray(area, dtype=float), 0.0, np.inf, low_inclusive=True, unit="m2")
    check_finite("solids_temperature_c", np.clip(np.asarray(solids_temperature_c, dtype=float), 0.0, 99.0))
    p = check_range("pressure", pressure, 5e4, 2e5, low_inclusive=True, high_inclusive=True, unit="Pa")
    beam = None
    if mode != "ajayi2011":
        check_range("co2_partial_pressure", co2_mole_fraction * p, 0.0, 1e6, low_inclusive=True, unit="Pa")
        beam = rad.mean_beam_length(2 * radius)
    return _stage_transfer(a, moisture_dry, solids_temperature_c, gas_temperature_c, humidity, gas_mass_flow,
                           particle_diameter, radius, kinetics, mode, p, co2_mole_fraction, solids_emissivity,
                           dry_guard, beam)


@functools.lru_cache(maxsize=64)
def _ceiling(pressure: float) -> float:
    return min(99.0, float(water.saturation_temperature(0.99 * pressure)))


def solids_temperature_ceiling(pressure):
    """Highest solids temperature of the surface-evaporation model, degC: 99 °C, or where water boils
    lower (a site at altitude, [`rotarydryer.properties.humid_air.standard_atmosphere_pressure`][rotarydryer.properties.humid_air.standard_atmosphere_pressure])
    the temperature whose saturation pressure is 99 % of ``pressure`` (Pa). 99 °C down to 98.75 kPa
    (about 220 m above sea level); 98.0 °C at 500 m, 93.0 °C at 2000 m. Hotter solids (dry, above the
    local boiling point) evaporate at the ceiling's rate (their water is held by the dry guard).

    >>> solids_temperature_ceiling(101325.0), round(solids_temperature_ceiling(79495.2), 1)
    (99.0, 93.0)
    """
    if np.ndim(pressure) == 0:
        return _ceiling(float(pressure))
    return np.minimum(99.0, water.saturation_temperature(0.99 * np.asarray(pressure, dtype=float)))


def _transfer_kernel_parameters(kinetics, radius, pressure, co2_mole_fraction, solids_emissivity, dry_guard,
                                beam_length):
    """(q, curve_x, curve_y): the parameters of the compiled transfer (`rotarydryer.properties._kernels`), or
    None where it does not apply: a mass-transfer basis other than ``"concentration"`` or a saturation pressure
    other than Wagner-Pruss, per-stage arrays of the scalar parameters, or a subclass of DryingKinetics (which
    may override its rate)."""
    if (type(kinetics) is not DryingKinetics or kinetics.basis != "concentration"
            or kinetics.saturation_method != "wagner_pruss" or kinetics.method not in _kernels.KINETICS_CODES):
        return None
    if any(type(v) is not float and np.ndim(v) for v in (radius, pressure, co2_mole_fraction, beam_length,
                                                         solids_emissivity, dry_guard)):
        return None      # per-stage parameters (the public stage_transfer allows them): NumPy broadcasts them
    p = float(pressure)
    if kinetics.method == "ajayi2011":
        xe = xcr = 0.0
    else:
        xe, xcr = float(kinetics.equilibrium_moisture), float(kinetics.critical_moisture)
    curve = kinetics.curve if kinetics.method == "characteristic_curve" and kinetics.curve is not None else None
    cx, cy = ((np.empty(0), np.empty(0)) if curve is None
              else (np.ascontiguousarray(curve[0], dtype=float), np.ascontiguousarray(curve[1], dtype=float)))
    q = _kernels.pack_transfer(float(radius), p, float(co2_mole_fraction) * p / rad.ATM, float(beam_length),
                               float(solids_emissivity), float(dry_guard), SIGMA, kinetics.method, xe, xcr,
                               float(kinetics.exponent), ha._D_SWITCH_K, ha._D_BLEND_K, solids_temperature_ceiling(p))
    return q, cx, cy


def _stage_transfer_compiled(area, moisture_dry, solids_temperature_c, gas_temperature_c, humidity, gas_mass_flow,
                             particle_diameter, radius, kinetics, pressure, co2_mole_fraction, solids_emissivity,
                             dry_guard, beam_length):
    """`_stage_transfer` of the physical mode in one compiled pass per stage
    (`rotarydryer.properties._kernels`), or None: kernels off, parameters the kernel does not take
    (`_transfer_kernel_parameters`), or solids at the boiling point (the NumPy form then names it). The same
    equations, the same numbers to rounding."""
    if _kernels.compiled("transfer") is None:
        return None
    params = _transfer_kernel_parameters(kinetics, radius, pressure, co2_mole_fraction, solids_emissivity, dry_guard,
                                         beam_length)
    if params is None:
        return None
    q, cx, cy = params
    return _kernels.evaluate("transfer", (area, moisture_dry, solids_temperature_c, gas_temperature_c, humidity,
                                          gas_mass_flow, particle_diameter),
                             (q, cx, cy, ha._KERNEL_COEFFICIENTS, rad._KERNEL_COEFFICIENTS, water._PSAT_COEFFICIENTS), 3)


def soft_ceiling(t, top):
    """min(t, top) with its corner rounded over top -/+ CEILING_BLEND_K (`rotarydryer.properties._kernels`) by the
    parabola with both slopes (the solids temperature of the surface-evaporation model, `stage_transfer`)."""
    d = _kernels.CEILING_BLEND_K
    t = np.asarray(t, dtype=float)
    e = t - top + d
    return np.where(t <= top - d, t, np.where(t >= top + d, top, t - e * e / (4.0 * d)))


def _stage_transfer(area, moisture_dry, solids_temperature_c, gas_temperature_c, humidity, gas_mass_flow,
                    particle_diameter, radius, kinetics, mode, pressure, co2_mole_fraction, solids_emissivity,
                    dry_guard, beam_length):
    """Unchecked kernel of [`stage_transfer`][rotarydryer.thermal.balances.stage_transfer] (``beam_length`` = mean beam length, m, physical mode)."""
    if mode != "ajayi2011":
        fast = _stage_transfer_compiled(area, moisture_dry, solids_temperature_c, gas_temperature_c, humidity,
                                        gas_mass_flow, particle_diameter, radius, kinetics, pressure,
                                        co2_mole_fraction, solids_emissivity, dry_guard, beam_length)
        if fast is not None:
            return fast
    tg = _tc(gas_temperature_c)
    ts = soft_ceiling(np.maximum(np.asarray(solids_temperature_c, dtype=float), 0.0), solids_temperature_ceiling(pressure))
    y = _yc(humidity, 1e-6)
    a = np.asarray(area, dtype=float)
    props = "ajayi2011" if mode == "ajayi2011" else "physical"
    hc, _ = _gas_solids_coefficient(gas_mass_flow, tg, y, particle_diameter, radius, props)
    x = np.maximum(np.asarray(moisture_dry, dtype=float), 0.0)
    cp = pr = sc = None
    if mode == "ajayi2011":
        rho = ha._density(tg, y, None, "ajayi2011")
        mu = ha._viscosity(tg, y, True)
        cp, pr, sc = AJAYI_CP_GAS, 0.7, mu / (rho * 2.65e-5)
    rw = kinetics._rate(a, x, hc, ts, tg, y, pressure, cp, pr, sc)
    rw = rw * np.minimum(np.maximum(x / dry_guard, 0.0), 1.0)
    q_conv = hc * a * (tg - np.asarray(solids_temperature_c, dtype=float))
    tgk = tg + 273.15
    tsk = np.asarray(solids_temperature_c, dtype=float) + 273.15
    if mode == "ajayi2011":
        q_rad = solids_emissivity * SIGMA * a * (tgk**4 - tsk**4)
    else:
        p_h2o = ha._vapour_partial_pressure(y, pressure)
        eg = rad._emissivity(tg + 273.15, p_h2o, co2_mole_fraction * pressure, beam_length)
        eg = np.minimum(np.maximum(eg, 1e-6), 1.0)
        q_rad = SIGMA * a * (tgk**4 - tsk**4) / (1.0 / solids_emissivity + 1.0 / eg - 1.0)
    return rw, q_conv, q_rad
