r"""Combustion chamber of a direct-fired dryer: fuel oil + combustion air + dilution air -> hot gas.

After Ajayi (2011) Appendix A (MMG Karumba dryer), made complete and energy-consistent.

What Ajayi gives (notes ajayi_energy.md §3) and how it is read here
-------------------------------------------------------------------
* Fan curves (Eqs. A1, A2), fan opening x in %, flow in Nm³/h:
  dilution $\dot V = 951.5x + 8662$, combustion $\dot V = 209.95x + 6283.4$.
  Table A1 lists 88050 Nm³/h (dilution, 83.43 %) and 23698 Nm³/h (combustion, 15.80 %);
  the second number is A1 evaluated at 15.80 %, not A2 (which gives 9601). Both
  readings are selectable in [`fan_flow`][rotarydryer.thermal.burner.fan_flow] (``curve="as_labelled"`` default,
  ``"a1_for_both"`` reproduces Table A1). kmol/h = Nm³/h / 22.414 (0 °C, 1 atm).
* Fuel (Table A2, recycled fuel oil): water 0.35 wt %, sulphur 0.95 wt %, C:H = 7.6
  printed "mol/mol". Default reading: **mass** ratio (C 87.2 wt %, H 11.5 wt %, typical
  of fuel oil); the molar reading (C 97.6 %, H 1.1 %, coke-like) is selectable
  (``FuelOil(ratio_basis="molar")``).
* Element balances (Eqs. A5-A9) and closure (A10): the printed closure has no O2 in
  the hot gas although the air is ~14x stoichiometric; here O2 is a product
  ($x_{O_2}$ = supplied - consumed), which closes every element balance exactly.
* Ajayi writes no energy balance (the hot-gas temperature is read from PI). Here the
  adiabatic (or lossy) chamber energy balance fixes the temperature:

    $$
    \sum_{prod} \dot n_i\,[\bar h_i(T) - \bar h_i(T_0)] =
    \sum_{air} \dot n_j\,[\bar h_j(T_{air}) - \bar h_j(T_0)]
    + \dot m_f c_{p,f}(T_f - T_0) + (1-f_{loss})\,\dot m_f\,LHV,\quad T_0 = 25\,°C
    $$

  with ideal-gas enthalpies from [`rotarydryer.properties.combustion`][rotarydryer.properties.combustion] and the
  lower heating value from the Channiwala & Parikh (2002, Fuel 81, 1051) HHV
  correlation, $HHV = 0.3491C + 1.1783H + 0.1005S$ MJ/kg (wt %), minus the latent
  heat at 25 °C (2.442 MJ/kg) of the water formed and the fuel moisture. For Ajayi's
  fuel: HHV 44.1 MJ/kg, LHV 41.6 MJ/kg.

Result of the reproduction (tests/thermal/test_burner.py): Table A1 flows and kmol/h,
the stoichiometric O2 demand (76 kmol/h at 750 kg/h fuel), 19 % O2 in the hot gas, and
F_ain = 112676 kg/h of the gPROMS code = the Table A1 dilution air as humid air at
H = 0.0193 (112441 kg/h, within 0.3 %). The energy balance shows that 750 kg/h of fuel
heats the Table A1 air (dilution + combustion, 39.8 kg/s of hot gas) only to 235 °C;
500 °C needs 1767 kg/h of fuel with that air, or 16.8 kg/s of air (17.0 kg/s of hot gas,
half of F_ain) with 750 kg/h - the notes' "gas flow ~2x too high", quantified.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validation import check_choice, check_positive, check_range
from ..properties import combustion as comb
from ..properties import humid_air as ha
from ._roots import illinois

__all__ = [
    "FuelOil",
    "AJAYI_FUEL_OIL",
    "HotGas",
    "fan_flow",
    "normal_volume_to_molar",
    "normal_volume_to_mass",
    "combustion_chamber",
    "fuel_rate_for_temperature",
    "fuel_rate_with_recycle",
    "AJAYI_AIR_HUMIDITY",
]

NORMAL_MOLAR_VOLUME = 22.414  # m3/kmol at 0 degC, 1 atm (Ajayi App. A)
REFERENCE_C = 25.0
LATENT_HEAT_25C = 2.442e6  # J/kg, IAPWS at 25 degC
# element molar masses (g/mol) consistent with the species molar masses, so that mass is conserved exactly
_M_O2 = 1000.0 * comb.MOLAR_MASS["O2"]
_M_C = 1000.0 * comb.MOLAR_MASS["CO2"] - _M_O2
_M_H = 0.5 * (1000.0 * comb.MOLAR_MASS["H2O"] - 0.5 * _M_O2)
_M_S = 1000.0 * comb.MOLAR_MASS["SO2"] - _M_O2
#: Ajayi's gas inlet humidity 0.0193 kg/kg wet gas (L3227) as kg/kg dry air.
AJAYI_AIR_HUMIDITY = 0.0193 / (1.0 - 0.0193)


@dataclass(frozen=True)
class FuelOil:
    """Liquid fuel composition (mass fractions as received) and heating value.

    Parameters
    ----------
    water_mass_fraction, sulphur_mass_fraction : float
        kg/kg fuel (Ajayi 2011 Table A2: 0.0035, 0.0095).
    carbon_hydrogen_ratio : float
        C:H ratio (Table A2: 7.6).
    ratio_basis : {"mass", "molar"}
        How to read the C:H ratio (default ``"mass"``, see module docstring).
    lower_heating_value : float, optional
        J/kg; default from Channiwala & Parikh (2002).
    heat_capacity : float
        Liquid fuel heat capacity, J/(kg K) (1900, typical fuel oil).
    """

    water_mass_fraction: float = 0.0035
    sulphur_mass_fraction: float = 0.0095
    carbon_hydrogen_ratio: float = 7.6
    ratio_basis: str = "mass"
    lower_heating_value: float | None = None
    heat_capacity: float = 1900.0

    def __post_init__(self):
        check_range("water_mass_fraction", self.water_mass_fraction, 0.0, 0.5, low_inclusive=True)
        check_range("sulphur_mass_fraction", self.sulphur_mass_fraction, 0.0, 0.1, low_inclusive=True)
        check_positive("carbon_hydrogen_ratio", self.carbon_hydrogen_ratio)
        check_choice("ratio_basis", self.ratio_basis, ("mass", "molar"))
        if self.lower_heating_value is not None:
            check_range("lower_heating_value", self.lower_heating_value, 1e6, 1e8, unit="J/kg")

    @property
    def hydrogen_mass_fraction(self) -> float:
        rest = 1.0 - self.water_mass_fraction - self.sulphur_mass_fraction
        ratio = self.carbon_hydrogen_ratio * (_M_C / _M_H if self.ratio_basis == "molar" else 1.0)
        return rest / (1.0 + ratio)

    @property
    def carbon_mass_fraction(self) -> float:
        return 1.0 - self.water_mass_fraction - self.sulphur_mass_fraction - self.hydrogen_mass_fraction

    @property
    def higher_heating_value(self) -> float:
        """J/kg, Channiwala & Parikh (2002) with wt % as received."""
        c, h, s = 100 * self.carbon_mass_fraction, 100 * self.hydrogen_mass_fraction, 100 * self.sulphur_mass_fraction
        return 1e6 * (0.3491 * c + 1.1783 * h + 0.1005 * s)

    @property
    def lhv(self) -> float:
        """Lower heating value, J/kg (water formed and fuel water as vapour at 25 °C)."""
        if self.lower_heating_value is not None:
            return float(self.lower_heating_value)
        water_formed = self.hydrogen_mass_fraction * 1000.0 * comb.MOLAR_MASS["H2O"] / (2 * _M_H)
        return self.higher_heating_value - LATENT_HEAT_25C * (water_formed + self.water_mass_fraction)

    def stoichiometric_oxygen(self) -> float:
        """kmol O2 per kg fuel for complete combustion to CO2, H2O, SO2."""
        return (self.carbon_mass_fraction / _M_C + self.hydrogen_mass_fraction / (4 * _M_H)
                + self.sulphur_mass_fraction / _M_S)


#: Ajayi (2011) Table A2 recycled fuel oil, C:H read as a mass ratio.
AJAYI_FUEL_OIL = FuelOil()


@dataclass(frozen=True)
class Burner:
    """A direct-fired burner that makes the drying gas (case data: ``[gas.burner]``).

    combustion_air_share : fraction of the air (combustion + dilution) that goes through the burner
    (Ajayi (2011) Table A1: 23 698 of 111 748 kg/h at Karumba). heat_loss_fraction : share of the
    fuel's heat lost by the combustion chamber. fuel : [`FuelOil`][rotarydryer.thermal.burner.FuelOil].
    The fuel rate is what heats the case's gas flow (air at ambient) to the gas inlet temperature.
    """

    combustion_air_share: float
    heat_loss_fraction: float = 0.0
    fuel: FuelOil = AJAYI_FUEL_OIL

    def __post_init__(self):
        check_range("gas.burner.combustion_air_share", self.combustion_air_share, 0.0, 1.0)
        check_range("gas.burner.heat_loss_fraction", self.heat_loss_fraction, 0.0, 0.5, low_inclusive=True)


def fan_flow(opening_pct, fan: str = "dilution", curve: str = "as_labelled"):
    """Air flow from the fan opening, Nm³/h, Ajayi (2011) Eqs. A1-A2.

    >>> round(float(fan_flow(83.43)), 1)
    88045.6
    >>> round(float(fan_flow(15.80, "combustion")), 1), round(float(fan_flow(15.80, "combustion", "a1_for_both")), 1)
    (9600.6, 23695.7)
    """
    x = check_range("opening_pct", opening_pct, 0.0, 100.0, low_inclusive=True, high_inclusive=True, unit="%")
    check_choice("fan", fan, ("dilution", "combustion"))
    check_choice("curve", curve, ("as_labelled", "a1_for_both"))
    if fan == "dilution" or curve == "a1_for_both":
        return 951.5 * x + 8662.0
    return 209.95 * x + 6283.4


def normal_volume_to_molar(flow_nm3_per_h):
    """kmol/h from Nm³/h (0 °C, 1 atm, 22.414 m³/kmol), as Ajayi's Table A1."""
    return check_range("flow_nm3_per_h", flow_nm3_per_h, 0.0, np.inf, low_inclusive=True) / NORMAL_MOLAR_VOLUME


def normal_volume_to_mass(flow_nm3_per_h, humidity=AJAYI_AIR_HUMIDITY):
    """kg/s of humid air from Nm³/h of humid air with humidity ratio Y (kg/kg dry air)."""
    kmol_s = normal_volume_to_molar(flow_nm3_per_h) / 3600.0
    y = check_range("humidity", humidity, 0.0, 0.3, low_inclusive=True, high_inclusive=True)
    m_w = comb.MOLAR_MASS["H2O"]
    xw = y / (y + m_w / ha.MOLAR_MASS_DRY_AIR)
    molar_mass = (1 - xw) * ha.MOLAR_MASS_DRY_AIR + xw * m_w  # kg/mol
    return kmol_s * 1000.0 * molar_mass


@dataclass(frozen=True)
class HotGas:
    """Hot gas leaving the combustion chamber (all SI; flows per second).

    Attributes: ``mass_flow`` kg/s, ``molar_flow`` kmol/s, ``composition`` mole
    fractions (dict, keys of `rotarydryer.properties.combustion.SPECIES`),
    ``temperature_c`` °C, ``humidity`` kg water/kg of the other gases (the dryer's
    "dry gas" basis), ``heat_release`` W (LHV x burnt fuel x (1 - loss)),
    ``heat_loss`` W, ``excess_oxygen_ratio`` = O2 supplied by the combustion air /
    stoichiometric O2, ``oxygen_wet`` mole fraction, ``element_balance_error`` and
    ``energy_balance_error`` (relative).
    """

    mass_flow: np.ndarray
    molar_flow: np.ndarray
    composition: dict
    temperature_c: np.ndarray
    humidity: np.ndarray
    heat_release: np.ndarray
    heat_loss: np.ndarray
    excess_oxygen_ratio: np.ndarray
    oxygen_wet: np.ndarray
    element_balance_error: float
    energy_balance_error: float


def _air_moles(mass_flow, humidity):
    """Species molar flows (kmol/s, dict) of humid air of mass flow kg/s and humidity Y."""
    dry = mass_flow / (1.0 + humidity)
    n_dry = dry / (ha.MOLAR_MASS_DRY_AIR * 1000.0)
    out = {s: comb.DRY_AIR_COMPOSITION[s] * n_dry for s in ("N2", "O2", "Ar")}
    out["H2O"] = (mass_flow - dry) / (1000.0 * comb.MOLAR_MASS["H2O"])
    return out


def _h_molar(species, t_c):
    """kJ/kmol (= J/mol) sensible enthalpy relative to 25 degC."""
    return comb.species_enthalpy(species, t_c, REFERENCE_C) * comb.MOLAR_MASS[species]


def _products(fuel_rate, air_c, air_d, fuel: FuelOil):
    n = {s: 0.0 for s in comb.SPECIES}
    for air in (air_c, air_d):
        for s, v in air.items():
            n[s] = n[s] + v
    c = fuel_rate * fuel.carbon_mass_fraction / _M_C
    h2 = fuel_rate * fuel.hydrogen_mass_fraction / (2 * _M_H)
    s_ = fuel_rate * fuel.sulphur_mass_fraction / _M_S
    w = fuel_rate * fuel.water_mass_fraction / (1000.0 * comb.MOLAR_MASS["H2O"])
    n["CO2"] = n["CO2"] + c
    n["H2O"] = n["H2O"] + h2 + w
    n["SO2"] = n["SO2"] + s_
    n["O2"] = n["O2"] - c - 0.5 * h2 - s_
    return n, (c, h2, s_, w)


def _chamber_inputs(fuel_rate, combustion_air, dilution_air, air_temperature_c, air_humidity, fuel_temperature_c,
                    heat_loss_fraction):
    """The checks of [`combustion_chamber`][rotarydryer.thermal.burner.combustion_chamber]: (f, ac, ad, ta, y) broadcast, tf, loss."""
    f = check_range("fuel_rate", fuel_rate, 0.0, np.inf, low_inclusive=True, unit="kg/s")
    ac = check_range("combustion_air", combustion_air, 0.0, np.inf, low_inclusive=True, unit="kg/s")
    ad = check_range("dilution_air", dilution_air, 0.0, np.inf, low_inclusive=True, unit="kg/s")
    ta = check_range("air_temperature_c", air_temperature_c, -40.0, 400.0, unit="degC")
    y = check_range("air_humidity", air_humidity, 0.0, 0.3, low_inclusive=True, high_inclusive=True,
                    unit="kg/kg dry air")
    tf = check_range("fuel_temperature_c", fuel_temperature_c, -20.0, 200.0, unit="degC")
    loss = check_range("heat_loss_fraction", heat_loss_fraction, 0.0, 1.0, low_inclusive=True)
    f, ac, ad, ta, y = np.broadcast_arrays(f, ac, ad, ta, y)
    if np.any(ac + ad <= 0):
        raise ValueError("combustion_air + dilution_air must be > 0 kg/s")
    return f, ac, ad, ta, y, tf, loss


def combustion_chamber(fuel_rate, combustion_air, dilution_air, air_temperature_c=26.0,
                       air_humidity=AJAYI_AIR_HUMIDITY, fuel: FuelOil = AJAYI_FUEL_OIL,
                       fuel_temperature_c=25.0, heat_loss_fraction=0.0) -> HotGas:
    """Hot-gas flow, composition and temperature from a fuel-oil combustion chamber.

    Parameters
    ----------
    fuel_rate : array_like
        Fuel oil mass flow, kg/s (Ajayi's typical 750 kg/h = 0.2083 kg/s, L2426).
    combustion_air, dilution_air : array_like
        Humid-air mass flows, kg/s (see [`fan_flow`][rotarydryer.thermal.burner.fan_flow] and [`normal_volume_to_mass`][rotarydryer.thermal.burner.normal_volume_to_mass]).
    air_temperature_c : array_like
        Temperature of both air streams, °C (Ajayi's ambient 26 °C, L3231).
    air_humidity : array_like
        kg water/kg dry air (default Ajayi's H_ain 0.0193 kg/kg wet gas).
    fuel : FuelOil
    fuel_temperature_c : float
        °C.
    heat_loss_fraction : float
        Fraction of the heat release lost through the chamber walls (0 = adiabatic).

    Raises
    ------
    ValueError
        If the combustion air cannot supply the stoichiometric oxygen of the fuel, or the
        gas temperature would exceed 726 °C (property range; add dilution air).

    Examples
    --------
    >>> air_d = normal_volume_to_mass(88050.0)            # Table A1 dilution air
    >>> air_c = normal_volume_to_mass(23698.0)            # Table A1 combustion air
    >>> gas = combustion_chamber(750 / 3600, air_c, air_d)
    >>> round(float(gas.temperature_c), 0), round(float(gas.mass_flow), 2)
    (235.0, 39.85)
    """
    f, ac, ad, ta, y, tf, loss = _chamber_inputs(fuel_rate, combustion_air, dilution_air, air_temperature_c,
                                                 air_humidity, fuel_temperature_c, heat_loss_fraction)
    air_c = _air_moles(ac, y)
    air_d = _air_moles(ad, y)
    need = f * fuel.stoichiometric_oxygen()
    if np.any(need > air_c["O2"] * (1 + 1e-12)):
        i = np.argmax(need - air_c["O2"])
        raise ValueError(
            f"combustion air {float(ac.flat[i]):.4g} kg/s supplies {float(air_c['O2'].flat[i]) * 3600:.4g} kmol/h O2 but "
            f"fuel_rate {float(f.flat[i]):.4g} kg/s needs {float(need.flat[i]) * 3600:.4g} kmol/h: the flame cannot burn it "
            "(increase combustion air or reduce fuel)")
    n, (c, h2, s_, w) = _products(f, air_c, air_d, fuel)
    # element balances (kmol/s of atoms)
    el_in = {"C": c, "H": 2 * h2 + 2 * w + 2 * (air_c["H2O"] + air_d["H2O"]), "S": s_,
             "N": 2 * (air_c["N2"] + air_d["N2"]),
             "O": 2 * (air_c["O2"] + air_d["O2"]) + air_c["H2O"] + air_d["H2O"] + w}
    el_out = {"C": n["CO2"], "H": 2 * n["H2O"], "S": n["SO2"], "N": 2 * n["N2"],
              "O": 2 * n["CO2"] + n["H2O"] + 2 * n["SO2"] + 2 * n["O2"]}
    el_err = max(float(np.max(np.abs(el_out[k] - el_in[k]) / np.maximum(el_in[k], 1e-30))) for k in el_in
                 if np.any(el_in[k] > 0))
    # energy balance
    q_release = (1.0 - loss) * f * fuel.lhv
    h_air = sum((air_c[s] + air_d[s]) * _h_molar(s, ta) for s in ("N2", "O2", "Ar", "H2O")) * 1000.0  # W
    rhs = h_air + f * fuel.heat_capacity * (tf - REFERENCE_C) + q_release

    def h_prod(t):
        return sum(n[s] * _h_molar(s, t) for s in comb.SPECIES) * 1000.0

    lo = np.full(f.shape, -40.0)
    hi = np.full(f.shape, 726.85)
    f_hi = h_prod(hi) - rhs
    if np.any(f_hi < 0):
        raise ValueError("hot-gas temperature would exceed 726 degC (outside the gas-property range): "
                         "increase dilution_air or reduce fuel_rate")
    t_gas = illinois(lambda t: h_prod(t) - rhs, lo, hi, f_hi=f_hi, xtol=1e-10)
    e_err = float(np.max(np.abs(h_prod(t_gas) - rhs) / np.maximum(np.abs(rhs), 1.0)))
    total = sum(n[s] for s in comb.SPECIES)
    x = {s: n[s] / total for s in comb.SPECIES}
    mass = sum(n[s] * comb.MOLAR_MASS[s] * 1000.0 for s in comb.SPECIES)
    water = n["H2O"] * comb.MOLAR_MASS["H2O"] * 1000.0
    supplied = air_c["O2"]
    with np.errstate(divide="ignore", over="ignore"):
        excess = np.where(need > 0, supplied / np.where(need > 0, need, 1.0), np.inf)
    return HotGas(mass_flow=mass, molar_flow=total, composition=x, temperature_c=t_gas,
                  humidity=water / (mass - water), heat_release=q_release, heat_loss=loss * f * fuel.lhv,
                  excess_oxygen_ratio=excess, oxygen_wet=x["O2"], element_balance_error=el_err,
                  energy_balance_error=e_err)


def _fuel_rate_in_range(target, combustion_air, dilution_air, f_max, kw):
    """The closed-form fuel rate when it lies in [0, f_max] (scalar inputs); None otherwise, and then
    the bracketed search raises the burner's error. The chamber's input checks raise here, as the
    search's first chamber evaluation would."""
    unknown = set(kw) - {"air_temperature_c", "air_humidity", "fuel_temperature_c", "heat_loss_fraction", "fuel"}
    ta, y, tf, loss = (kw.get("air_temperature_c", 26.0), kw.get("air_humidity", AJAYI_AIR_HUMIDITY),
                       kw.get("fuel_temperature_c", 25.0), kw.get("heat_loss_fraction", 0.0))
    if unknown or any(np.ndim(v) != 0 for v in (ta, y, tf, loss, combustion_air, dilution_air)):
        return None
    _chamber_inputs(0.0, combustion_air, dilution_air, ta, y, tf, loss)
    ta, y, tf, loss, ad = (float(v) for v in (ta, y, tf, loss, dilution_air))
    if not target >= ta:
        return None
    f = _fuel_rate_linear(target, combustion_air, ad, kw.get("fuel", AJAYI_FUEL_OIL), ta, y, tf, loss)
    if target == ta:
        f = 0.0                  # the air itself: no fuel (the closed form gives +-1e-16)
    return f if math.isfinite(f) and 0.0 <= f <= f_max else None


def fuel_rate_for_temperature(target_temperature_c, combustion_air, dilution_air, max_fuel_rate=None,
                              **chamber_kwargs):
    """Fuel rate, kg/s, that brings the hot gas to ``target_temperature_c`` (°C).

    The fuel rate is bounded by ``max_fuel_rate`` (burner capacity, kg/s) and by the
    stoichiometric limit of the combustion air. Raises ``ValueError`` naming the
    reachable temperature when the burner cannot reach the set temperature, or when the
    target is below the temperature of the air itself. Array arguments are evaluated
    element by element.

    >>> air_d, air_c = normal_volume_to_mass(88050.0), normal_volume_to_mass(23698.0)
    >>> round(float(fuel_rate_for_temperature(500.0, air_c, air_d)) * 3600, 0)   # kg/h
    1767.0
    """
    args = np.broadcast_arrays(np.asarray(target_temperature_c, float), np.asarray(combustion_air, float),
                               np.asarray(dilution_air, float),
                               np.asarray(np.inf if max_fuel_rate is None else max_fuel_rate, float))
    out = np.empty(args[0].shape)
    for idx in np.ndindex(out.shape):
        mf = None if np.isinf(args[3][idx]) else float(args[3][idx])
        out[idx] = _fuel_rate_scalar(float(args[0][idx]), float(args[1][idx]), float(args[2][idx]), mf,
                                     **chamber_kwargs)
    return out if out.ndim else float(out)


def _fuel_rate_linear(target_c, combustion_air, dilution_air, fuel=AJAYI_FUEL_OIL, air_temperature_c=26.0,
                      air_humidity=AJAYI_AIR_HUMIDITY, fuel_temperature_c=25.0, heat_loss_fraction=0.0):
    """Fuel rate (kg/s) whose products leave [`combustion_chamber`][rotarydryer.thermal.burner.combustion_chamber] at ``target_c`` °C, in closed form.

    At a given gas temperature the chamber's energy balance is linear in the fuel rate f: the
    product moles are n(f) = n(0) + f dn (``_products``), the heat in is h_air + f (c_p,fuel
    (T_f - 25) + (1 - loss) LHV). So f = (h_air - n(0).h(T)) / (dn.h(T) - c_p,fuel (T_f - 25) -
    (1 - loss) LHV): the root that bracketing the chamber temperature over f finds, without the
    two nested root searches. Unchecked: the caller checks the inputs and the range of f."""
    air_c = _air_moles(combustion_air, air_humidity)
    air_d = _air_moles(dilution_air, air_humidity)
    n0, _ = _products(0.0, air_c, air_d, fuel)
    n1, _ = _products(1.0, air_c, air_d, fuel)

    def h(species, t):   # kJ/kmol relative to 25 degC, as _h_molar (unchecked)
        return comb._species_enthalpy(species, t, REFERENCE_C) * comb.MOLAR_MASS[species]
    h_air = sum((air_c[s] + air_d[s]) * h(s, air_temperature_c) for s in ("N2", "O2", "Ar", "H2O")) * 1000.0
    hk = {s: h(s, target_c) for s in comb.SPECIES}
    hp0 = sum(n0[s] * hk[s] for s in comb.SPECIES) * 1000.0
    dhp = sum((n1[s] - n0[s]) * hk[s] for s in comb.SPECIES) * 1000.0
    heat_per_fuel = fuel.heat_capacity * (fuel_temperature_c - REFERENCE_C) + (1.0 - heat_loss_fraction) * fuel.lhv
    return float((h_air - hp0) / (dhp - heat_per_fuel))


def fuel_rate_with_recycle(target_temperature_c, combustion_air, dilution_air, recycle_gas, recycle_temperature_c,
                           recycle_humidity, *, air_temperature_c=26.0, air_humidity=AJAYI_AIR_HUMIDITY,
                           fuel: FuelOil = AJAYI_FUEL_OIL, fuel_temperature_c=25.0, heat_loss_fraction=0.0):
    """Fuel rate, kg/s, that brings combustion air, dilution air (both humid air at
    ``air_temperature_c`` and ``air_humidity``) and recycled dryer exhaust (``recycle_gas`` kg/s of
    humid gas at ``recycle_temperature_c`` °C and ``recycle_humidity`` kg/kg dry gas, taken as humid
    air as the dryer model takes its gas) to ``target_temperature_c`` °C.

    The chamber balance of [`combustion_chamber`][rotarydryer.thermal.burner.combustion_chamber] with a third
    stream entering at its own temperature; at the products' temperature it is linear in the fuel rate
    (as `_fuel_rate_linear`), solved in closed form. The recycled gas joins the dilution side: the
    flame burns in the combustion air. Raises ``ValueError`` when no fuel rate in [0, the combustion
    air's stoichiometric limit] gives the target (the streams alone are hotter, or the flame would
    need more oxygen) or when ``dilution_air`` < 0 (the recycle leaves too little fresh air).

    >>> air_d, air_c = normal_volume_to_mass(88050.0), normal_volume_to_mass(23698.0)
    >>> f0 = fuel_rate_for_temperature(500.0, air_c, air_d)
    >>> f1 = fuel_rate_with_recycle(500.0, air_c, air_d - 5.0, 5.0, 120.0, 0.08)
    >>> round(f0 * 3600), round(f1 * 3600)      # kg/h: 5 kg/s of the dilution air from a 120 degC exhaust
    (1767, 1733)
    """
    target = float(check_range("target_temperature_c", target_temperature_c, -20.0, 726.0, unit="degC"))
    ac = float(check_range("combustion_air", combustion_air, 0.0, np.inf, unit="kg/s"))
    if not float(dilution_air) >= 0.0:
        raise ValueError(f"dilution air {float(dilution_air):.4g} kg/s < 0: the recycled exhaust leaves less fresh "
                         "air than the burner's combustion air")
    _chamber_inputs(0.0, ac, dilution_air, air_temperature_c, air_humidity, fuel_temperature_c, heat_loss_fraction)
    rg = float(check_range("recycle_gas", recycle_gas, 0.0, np.inf, low_inclusive=True, unit="kg/s"))
    tr = float(check_range("recycle_temperature_c", recycle_temperature_c, -20.0, 726.0, unit="degC"))
    yr = float(check_range("recycle_humidity", recycle_humidity, 0.0, 1.0, low_inclusive=True, high_inclusive=True,
                           unit="kg/kg dry gas"))
    ta, y = float(air_temperature_c), float(air_humidity)
    air_c, air_d, rec = _air_moles(ac, y), _air_moles(float(dilution_air), y), _air_moles(rg, yr)
    side = {sp: air_d[sp] + rec[sp] for sp in air_d}      # dilution and recycle: one stream of products
    n0, _ = _products(0.0, air_c, side, fuel)
    n1, _ = _products(1.0, air_c, side, fuel)

    def h(species, t):   # kJ/kmol relative to 25 degC, as _h_molar (unchecked)
        return comb._species_enthalpy(species, t, REFERENCE_C) * comb.MOLAR_MASS[species]
    h_in = sum((air_c[sp] + air_d[sp]) * h(sp, ta) + rec[sp] * h(sp, tr) for sp in ("N2", "O2", "Ar", "H2O")) * 1000.0
    hk = {sp: h(sp, target) for sp in comb.SPECIES}
    hp0 = sum(n0[sp] * hk[sp] for sp in comb.SPECIES) * 1000.0
    dhp = sum((n1[sp] - n0[sp]) * hk[sp] for sp in comb.SPECIES) * 1000.0
    heat_per_fuel = fuel.heat_capacity * (float(fuel_temperature_c) - REFERENCE_C) + (1.0 - heat_loss_fraction) * fuel.lhv
    f = float((h_in - hp0) / (dhp - heat_per_fuel))
    f_max = air_c["O2"] / fuel.stoichiometric_oxygen()
    if not f >= 0.0:
        raise ValueError(f"target_temperature_c = {target:g} degC is below the temperature of the air and recycled "
                         "gas mixed: no fuel rate gives it")
    if f > f_max:
        raise ValueError(f"burner cannot reach target_temperature_c = {target:g} degC: it needs {f * 3600:.4g} kg/h "
                         f"of fuel, above the {f_max * 3600:.4g} kg/h the combustion air's oxygen burns")
    return f


def _fuel_rate_scalar(target_temperature_c, combustion_air, dilution_air, max_fuel_rate=None, **chamber_kwargs):
    target = check_range("target_temperature_c", target_temperature_c, -20.0, 726.0, unit="degC")
    fuel = chamber_kwargs.get("fuel", AJAYI_FUEL_OIL)
    kw = dict(chamber_kwargs)
    y = kw.get("air_humidity", AJAYI_AIR_HUMIDITY)
    ac = check_range("combustion_air", combustion_air, 0.0, np.inf, unit="kg/s")
    o2 = _air_moles(ac, np.asarray(y, float))["O2"]
    f_stoich = o2 / fuel.stoichiometric_oxygen()
    f_max = f_stoich if max_fuel_rate is None else np.minimum(f_stoich, check_positive("max_fuel_rate",
                                                                                       max_fuel_rate, "kg/s"))
    target, f_max = np.broadcast_arrays(target, f_max)
    fast = _fuel_rate_in_range(float(target), ac, dilution_air, float(f_max), kw)
    if fast is not None:
        return fast
    t0 = combustion_chamber(0.0, combustion_air, dilution_air, **kw).temperature_c
    if np.any(target < t0 - 1e-9):
        raise ValueError(f"target_temperature_c = {float(np.min(target)):g} degC is below the air temperature "
                         f"{float(np.min(t0)):.4g} degC: no fuel rate gives it")
    if np.all(target <= t0 + 1e-9):   # the air temperature itself (no bracket: both ends above the target)
        return 0.0
    try:
        t_max = combustion_chamber(f_max, combustion_air, dilution_air, **kw).temperature_c
    except ValueError:
        t_max = np.full(target.shape, 726.85)
    if np.any(t_max < target):
        i = int(np.argmax(target - t_max))
        limit = "burner capacity max_fuel_rate" if max_fuel_rate is not None and \
            float(np.ravel(f_max)[i]) < float(np.ravel(np.broadcast_to(f_stoich, f_max.shape))[i]) else \
            "stoichiometric oxygen of the combustion air"
        raise ValueError(
            f"burner cannot reach target_temperature_c = {float(target.flat[i]):g} degC: at the maximum fuel rate "
            f"{float(f_max.flat[i]) * 3600:.4g} kg/h (limited by the {limit}) the gas reaches only "
            f"{float(np.ravel(t_max)[i]):.4g} degC")
    def resid(fuel):
        try:
            return combustion_chamber(fuel, combustion_air, dilution_air, **kw).temperature_c - target
        except ValueError:  # beyond the property range: certainly above the target (<= 726 degC)
            return np.full(np.shape(fuel), 1000.0)

    return float(illinois(resid, 0.0, f_max, xtol=1e-12))
