r"""Ideal-gas properties of combustion gases and their mixtures (N2, O2, Ar, CO2, H2O, SO2), 0-600 °C.

Used for the hot gas leaving Ajayi's combustion chamber (Ajayi 2011 Appendix A) and,
through [`rotarydryer.properties.humid_air`][rotarydryer.properties.humid_air], for dry air and water vapour.

Sources
-------
Heat capacity and enthalpy
:   NASA 7-coefficient polynomials, range 200-1000 K: McBride, Zehe & Gordon (2002),
    NASA/TP-2002-211556 (N2, O2, Ar, CO2, H2O; the CO2, H2O and O2 sets are the ones
    distributed with GRI-Mech 3.0). SO2: Shomate equation of the NIST Chemistry WebBook
    (Chase 1998, NIST-JANAF 4th ed.), 298-1200 K. Checked in the tests against the
    ideal-gas heat capacities of CoolProp's reference equations of state (< 0.4 %).

    $$
    c_p/R = a_1 + a_2 T + a_3 T^2 + a_4 T^3 + a_5 T^4,\qquad
    h/(RT) = a_1 + a_2 T/2 + a_3 T^2/3 + a_4 T^3/4 + a_5 T^4/5 + a_6/T
    $$

Viscosity and thermal conductivity of a mixture
:   Pure species in the dilute-gas limit: N2, O2, Ar (and air) by Lemmon & Jacobsen
    (2004, Int. J. Thermophys. 25, 21) Eqs. 2-5; water vapour by IAPWS (2008) Eq. 11
    and IAPWS (2011) Eq. 16; CO2 and SO2 by Chapman-Enskog with the Neufeld et al.
    (1972) collision integral and Lennard-Jones parameters of Poling, Prausnitz &
    O'Connell (2001) App. B (Eq. 9-3.9) and the modified Eucken conductivity
    (Eq. 10-3.3). Mixture rules: Wilke (1950) for viscosity (Poling Eq. 9-5.13) and
    Wassiljewa with the Mason-Saxena (Wilke) coefficients for conductivity (Poling
    Eq. 10-6.1), with N2 + O2 + Ar lumped into pseudo-pure air (Lemmon & Jacobsen 2004),
    as CoolProp's humid-air model does. Against CoolProp's reference correlations at 1 atm, 0-600 °C: N2, O2,
    Ar, air and H2O within 0.25 %; CO2 within 5 % (viscosity) and 10 % (conductivity,
    at 0 °C), which moves a flue-gas mixture with < 5 % CO2 by < 0.5 %.

Temperatures are in K inside the module functions that say so and in °C at the public
API where documented (argument names end in ``_c`` or the docstring says °C).
Compositions are mole fractions in a dict ``{"N2": ..., "O2": ..., ...}`` or an array
whose last axis follows `SPECIES`.
"""

from __future__ import annotations

import functools

import numpy as np

from .._validation import check_positive, check_range

__all__ = [
    "SPECIES",
    "MOLAR_MASS",
    "GAS_CONSTANT",
    "DRY_AIR_COMPOSITION",
    "STANDARD_PRESSURE",
    "species_heat_capacity",
    "species_enthalpy",
    "mixture_molar_mass",
    "mass_fractions",
    "mole_fractions_from_mass",
    "heat_capacity",
    "enthalpy",
    "density",
    "viscosity",
    "thermal_conductivity",
    "composition_array",
    "species_viscosity",
    "species_conductivity",
]

GAS_CONSTANT = 8.314462618  # J/(mol K), CODATA 2018
STANDARD_PRESSURE = 101325.0  # Pa
T_MIN_K = 200.0
T_MAX_K = 1000.0

SPECIES = ("N2", "O2", "Ar", "CO2", "H2O", "SO2")

#: Molar masses, kg/mol (IUPAC 2013 atomic weights).
MOLAR_MASS = {
    "N2": 0.0280134,
    "O2": 0.0319988,
    "Ar": 0.039948,
    "CO2": 0.0440095,
    "H2O": 0.01801528,
    "SO2": 0.0640638,
}

#: Dry air, mole fractions (Lemmon et al. 2000 pseudo-pure air: N2 0.7812, O2 0.2096, Ar 0.0092).
DRY_AIR_COMPOSITION = {"N2": 0.7812, "O2": 0.2096, "Ar": 0.0092, "CO2": 0.0, "H2O": 0.0, "SO2": 0.0}

# NASA 7-coefficient low-temperature (200-1000 K) sets, McBride et al. (2002).
_NASA = {
    "N2": (3.53100528e00, -1.23660988e-04, -5.02999433e-07, 2.43530612e-09, -1.40881235e-12,
           -1.04697628e03, 2.96747038e00),
    "O2": (3.78245636e00, -2.99673416e-03, 9.84730201e-06, -9.68129509e-09, 3.24372837e-12,
           -1.06394356e03, 3.65767573e00),
    "Ar": (2.5, 0.0, 0.0, 0.0, 0.0, -7.45375e02, 4.366),
    "CO2": (2.35677352e00, 8.98459677e-03, -7.12356269e-06, 2.45919022e-09, -1.43699548e-13,
            -4.83719697e04, 9.90105222e00),
    "H2O": (4.19864056e00, -2.03643410e-03, 6.52040211e-06, -5.48797062e-09, 1.77197817e-12,
            -3.02937267e04, -8.49032208e-01),
}
# NIST WebBook Shomate coefficients for SO2, 298-1200 K: cp [J/(mol K)] = A + B t + C t^2 + D t^3 + E/t^2,
# t = T/1000; H - H298 [kJ/mol] = A t + B t^2/2 + C t^3/3 + D t^4/4 - E/t + F - H.
_SHOMATE_SO2 = (21.43049, 74.35094, -57.75217, 16.35534, 0.086731, -305.7688, -296.8422)

# Lennard-Jones parameters (sigma in Angstrom, epsilon/k in K), Poling et al. (2001) App. B.
_LJ = {"N2": (3.798, 71.4), "O2": (3.467, 106.7), "Ar": (3.542, 93.3), "CO2": (3.941, 195.2),
       "H2O": (2.641, 809.1), "SO2": (4.112, 335.4)}


def _t_kelvin(name, temperature_c):
    t = check_range(name, temperature_c, -73.15, 726.85, low_inclusive=True, high_inclusive=True, unit="degC")
    return t + 273.15


def _cp_molar_k(species, t):
    """Molar ideal-gas heat capacity, J/(mol K), of one species at T in K."""
    if species == "SO2":
        A, B, C, D, E, _, _ = _SHOMATE_SO2
        tt = t / 1000.0
        return A + B * tt + C * tt**2 + D * tt**3 + E / tt**2
    a = _NASA[species]
    return GAS_CONSTANT * (a[0] + t * (a[1] + t * (a[2] + t * (a[3] + t * a[4]))))


def _h_molar_k(species, t):
    """Molar ideal-gas enthalpy relative to 298.15 K, J/mol, of one species at T in K."""
    if species == "SO2":
        A, B, C, D, E, F, H = _SHOMATE_SO2

        def h(tk):
            tt = tk / 1000.0
            return 1000.0 * (A * tt + B * tt**2 / 2 + C * tt**3 / 3 + D * tt**4 / 4 - E / tt + F - H)

        return h(t) - h(298.15)
    a = _NASA[species]

    def h(tk):
        return GAS_CONSTANT * (tk * (a[0] + tk * (a[1] / 2 + tk * (a[2] / 3 + tk * (a[3] / 4 + tk * a[4] / 5)))) + a[5])

    return h(t) - h(298.15)


def species_heat_capacity(species: str, temperature_c):
    """Ideal-gas specific heat capacity of one species, J/(kg K), at temperature °C.

    NASA polynomials (McBride et al. 2002) or NIST Shomate (SO2), valid -73 to 727 °C.

    >>> round(float(species_heat_capacity("H2O", 500.0)), 1)
    2131.6
    """
    if species not in MOLAR_MASS:
        raise ValueError(f"species = {species!r} is not one of {', '.join(SPECIES)}")
    _t_kelvin("temperature_c", temperature_c)
    return _species_heat_capacity(species, temperature_c)


def _species_heat_capacity(species, t_c):
    """Unchecked kernel of [`species_heat_capacity`][rotarydryer.properties.combustion.species_heat_capacity] (``t_c`` °C, already validated)."""
    return _cp_molar_k(species, np.asarray(t_c, dtype=float) + 273.15) / MOLAR_MASS[species]


def species_enthalpy(species: str, temperature_c, reference_c: float = 0.0):
    """Ideal-gas specific sensible enthalpy of one species, J/kg, relative to ``reference_c`` (°C).

    >>> round(float(species_enthalpy("N2", 100.0)) / 1e3, 2)   # kJ/kg from 0 to 100 degC
    104.06
    """
    if species not in MOLAR_MASS:
        raise ValueError(f"species = {species!r} is not one of {', '.join(SPECIES)}")
    _t_kelvin("temperature_c", temperature_c)
    _t_kelvin("reference_c", reference_c)
    return _species_enthalpy(species, temperature_c, reference_c)


def _species_enthalpy(species, t_c, reference_c=0.0):
    """Unchecked kernel of [`species_enthalpy`][rotarydryer.properties.combustion.species_enthalpy] (``t_c``, ``reference_c`` °C, already validated)."""
    t = np.asarray(t_c, dtype=float) + 273.15
    return (_h_molar_k(species, t) - _h_reference(species, reference_c)) / MOLAR_MASS[species]


@functools.lru_cache(maxsize=64)
def _h_reference_scalar(species, reference_c):
    return _h_molar_k(species, np.float64(reference_c) + 273.15)


def _h_reference(species, reference_c):
    """_h_molar_k at the reference temperature (°C); scalar references are cached."""
    if np.ndim(reference_c) == 0:
        return _h_reference_scalar(species, float(reference_c))
    return _h_molar_k(species, np.asarray(reference_c, dtype=float) + 273.15)


def composition_array(composition) -> np.ndarray:
    """Mole fractions as an array whose last axis follows `SPECIES`; must sum to 1 (1e-6)."""
    if isinstance(composition, dict):
        unknown = set(composition) - set(SPECIES)
        if unknown:
            raise ValueError(f"composition has unknown species {sorted(unknown)}; allowed {SPECIES}")
        arrays = np.broadcast_arrays(*[np.asarray(composition.get(s, 0.0), dtype=float) for s in SPECIES])
        x = np.stack(arrays, axis=-1)
    else:
        x = np.asarray(composition, dtype=float)
        if x.shape[-1] != len(SPECIES):
            raise ValueError(f"composition array must have last axis of length {len(SPECIES)} ({SPECIES})")
    check_range("composition (mole fractions)", x, 0.0, 1.0, low_inclusive=True, high_inclusive=True)
    total = x.sum(axis=-1)
    if np.any(np.abs(total - 1.0) > 1e-6):
        raise ValueError(f"composition mole fractions must sum to 1, got sums between {total.min()!r} and {total.max()!r}")
    return x


def _molar_masses():
    return np.array([MOLAR_MASS[s] for s in SPECIES])


def mixture_molar_mass(composition):
    """Molar mass of a mixture, kg/mol, from mole fractions."""
    x = composition_array(composition)
    return x @ _molar_masses()


def mass_fractions(composition):
    """Mass fractions (array, last axis `SPECIES`) from mole fractions."""
    x = composition_array(composition)
    m = x * _molar_masses()
    return m / m.sum(axis=-1, keepdims=True)


def mole_fractions_from_mass(mass_fraction):
    """Mole fractions (array, last axis `SPECIES`) from mass fractions."""
    w = composition_array(mass_fraction)
    n = w / _molar_masses()
    return n / n.sum(axis=-1, keepdims=True)


def heat_capacity(temperature_c, composition):
    r"""Mixture specific heat capacity $c_p=\sum_i w_i c_{p,i}$, J/(kg K), ideal gas.

    ``temperature_c`` in °C (-73 to 727 °C) broadcasts against the leading axes of
    ``composition``.

    >>> round(float(heat_capacity(25.0, DRY_AIR_COMPOSITION)), 1)
    1004.9
    """
    w = mass_fractions(composition)
    t = _t_kelvin("temperature_c", temperature_c)
    cps = np.stack([_cp_molar_k(s, t) / MOLAR_MASS[s] for s in SPECIES], axis=-1)
    return np.sum(w * cps, axis=-1)


def enthalpy(temperature_c, composition, reference_c: float = 0.0):
    """Mixture specific sensible enthalpy, J/kg, relative to ``reference_c`` °C (ideal gas)."""
    w = mass_fractions(composition)
    t = _t_kelvin("temperature_c", temperature_c)
    t0 = _t_kelvin("reference_c", reference_c)
    hs = np.stack([(_h_molar_k(s, t) - _h_molar_k(s, t0)) / MOLAR_MASS[s] for s in SPECIES], axis=-1)
    return np.sum(w * hs, axis=-1)


def density(temperature_c, composition, pressure=STANDARD_PRESSURE):
    r"""Ideal-gas density $\rho = P M/(R T)$, kg/m³; T in °C, P in Pa."""
    t = _t_kelvin("temperature_c", temperature_c)
    p = check_positive("pressure", pressure, unit="Pa")
    return p * mixture_molar_mass(composition) / (GAS_CONSTANT * t)


def _neufeld_omega_v(tstar):
    """Neufeld et al. (1972) viscosity collision integral (Poling et al. 2001 Eq. 9-4.3)."""
    return 1.16145 * tstar**-0.14874 + 0.52487 * np.exp(-0.77320 * tstar) + 2.16178 * np.exp(-2.43787 * tstar)


#: IAPWS (2008) Eq. 11 and IAPWS (2011) Eq. 16 dilute-gas coefficients H_i and L_i
_IAPWS_VISCOSITY_H = (1.67752, 2.20462, 0.6366564, -0.241605)
_IAPWS_CONDUCTIVITY_L = (2.443221e-3, 1.323095e-2, 6.770357e-3, -3.454586e-3, 4.096266e-4)


def iapws_vapour_viscosity_dilute(t):
    """Dilute-gas viscosity of water vapour, Pa s, IAPWS (2008) Eq. 11; T in K."""
    tb = t / 647.096
    return 1e-6 * 100.0 * np.sqrt(tb) / sum(hi / tb**i for i, hi in enumerate(_IAPWS_VISCOSITY_H))


def iapws_vapour_conductivity_dilute(t):
    """Dilute-gas thermal conductivity of water vapour, W/(m K), IAPWS (2011) Eq. 16; T in K."""
    tb = t / 647.096
    return 1e-3 * np.sqrt(tb) / sum(li / tb**i for i, li in enumerate(_IAPWS_CONDUCTIVITY_L))


# Lemmon & Jacobsen (2004) dilute-gas parameters: M g/mol, sigma nm, eps/k K, Tc K, N1, N2, t2, N3, t3.
_LEMMON_JACOBSEN = {
    "air": (28.9586, 0.360, 103.3, 132.6312, 1.308, 1.405, -1.1, -1.036, -0.3),
    "N2": (28.01348, 0.3656, 98.94, 126.192, 1.511, 2.117, -1.0, -3.332, -0.7),
    "O2": (31.9988, 0.3428, 118.5, 154.581, 1.036, 6.283, -0.9, -4.262, -0.6),
    "Ar": (39.948, 0.335, 143.2, 150.687, 0.8158, -0.4320, -0.77, 0.0, 0.0),
}
_LJ2004_B = (0.431, -0.4623, 0.08406, 0.005341, -0.00331)


def lemmon_jacobsen_viscosity(fluid: str, t):
    """Dilute-gas viscosity, Pa s, of air, N2, O2 or Ar; Lemmon & Jacobsen (2004) Eqs. 2-4; T in K.

    The residual (density) term is omitted: < 0.2 % at 1 atm above 0 °C.
    """
    m, sigma, eps, *_ = _LEMMON_JACOBSEN[fluid]
    lt = np.log(t / eps)
    omega = np.exp(sum(b * lt**i for i, b in enumerate(_LJ2004_B)))
    return 1e-6 * 0.0266958 * np.sqrt(m * t) / (sigma**2 * omega)


def lemmon_jacobsen_conductivity(fluid: str, t, viscosity=None):
    """Dilute-gas thermal conductivity, W/(m K), of air, N2, O2 or Ar; Lemmon & Jacobsen (2004) Eq. 5; T in K.
    ``viscosity``: [`lemmon_jacobsen_viscosity`][rotarydryer.properties.combustion.lemmon_jacobsen_viscosity] at ``t`` if already evaluated."""
    _, _, _, tc, n1, n2, t2, n3, t3 = _LEMMON_JACOBSEN[fluid]
    tau = tc / t
    mu = lemmon_jacobsen_viscosity(fluid, t) if viscosity is None else viscosity
    return 1e-3 * (n1 * 1e6 * mu + n2 * tau**t2 + n3 * tau**t3)


def _species_viscosity_k(species, t):
    if species == "H2O":
        return iapws_vapour_viscosity_dilute(t)
    if species in _LEMMON_JACOBSEN:
        return lemmon_jacobsen_viscosity(species, t)
    sigma, eps = _LJ[species]
    m = MOLAR_MASS[species] * 1000.0
    # Chapman-Enskog, Poling et al. (2001) Eq. 9-3.9: mu [microPoise] = 26.69 sqrt(M T)/(sigma^2 Omega_v)
    return 26.69e-7 * np.sqrt(m * t) / (sigma**2 * _neufeld_omega_v(t / eps))


def _species_conductivity_k(species, t):
    if species == "H2O":
        return iapws_vapour_conductivity_dilute(t)
    if species in _LEMMON_JACOBSEN:
        return lemmon_jacobsen_conductivity(species, t)
    mu = _species_viscosity_k(species, t)
    cv = _cp_molar_k(species, t) - GAS_CONSTANT
    m = MOLAR_MASS[species]
    # modified Eucken, Poling et al. (2001) Eq. 10-3.3: lambda M/(eta Cv) = 1.32 + 1.77 R/Cv
    return mu * cv / m * (1.32 + 1.77 * GAS_CONSTANT / cv)


def _wilke_phi(mu, m):
    """Wilke (1950) interaction parameters phi_ij, shape (..., n, n)."""
    mu_i = mu[..., :, None]
    mu_j = mu[..., None, :]
    mi = m[..., :, None]
    mj = m[..., None, :]
    return (1.0 + np.sqrt(mu_i / mu_j) * (mj / mi) ** 0.25) ** 2 / np.sqrt(8.0 * (1.0 + mi / mj))


_AIR_LIKE = ("N2", "O2", "Ar")


def _wilke_mix(xs, mu, ms, prop):
    xs, mu, ms, prop = np.broadcast_arrays(xs, mu, ms, prop)
    phi = _wilke_phi(mu, ms)
    denom = np.einsum("...j,...ij->...i", xs, phi)
    safe = np.where(denom > 0, denom, 1.0)
    return np.sum(np.where(xs > 0, xs * prop / safe, 0.0), axis=-1)


def _stack(values):
    return np.stack(np.broadcast_arrays(*values), axis=-1)


def mixture_transport(t_kelvin, x, conductivity=False):
    """Wilke viscosity (or Wassiljewa-Mason-Saxena conductivity) of a mixture; T in K.

    ``x``: mole fractions (last axis SPECIES). N2, O2 and Ar form one "air-like"
    pseudo-component whose property is the Lemmon-Jacobsen (2004) value for air scaled by
    the ratio of the Wilke (Mason-Saxena) mix of N2/O2/Ar at the actual and at the
    standard air composition: mixing N2, O2, Ar individually under-predicts the
    conductivity of air by 1.5 %, this keeps air (and excess-air flue gas) at reference
    accuracy; a pure N2, O2 or Ar stream then carries that 1.5 % (use
    [`species_conductivity`][rotarydryer.properties.combustion.species_conductivity] for pure species).
    """
    idx = {s: i for i, s in enumerate(SPECIES)}
    t = np.asarray(t_kelvin, float)
    xg = _stack([x[..., idx[s]] for s in _AIR_LIKE])
    x_air = xg.sum(axis=-1)
    m_g = np.array([MOLAR_MASS[s] for s in _AIR_LIKE])
    mu_g = _stack([_species_viscosity_k(s, t) for s in _AIR_LIKE])
    p_g = _stack([_species_conductivity_k(s, t) for s in _AIR_LIKE]) if conductivity else mu_g
    x_std = np.array([DRY_AIR_COMPOSITION[s] for s in _AIR_LIKE])
    ref_air = lemmon_jacobsen_conductivity("air", t) if conductivity else lemmon_jacobsen_viscosity("air", t)
    mix_std = _wilke_mix(x_std, mu_g, m_g, p_g)
    xg_norm = np.where((x_air > 0)[..., None], xg / np.where(x_air > 0, x_air, 1.0)[..., None], x_std)
    mix_act = _wilke_mix(xg_norm, mu_g, m_g, p_g)
    p_air = ref_air * mix_act / mix_std
    mu_air = lemmon_jacobsen_viscosity("air", t) * _wilke_mix(xg_norm, mu_g, m_g, mu_g) / _wilke_mix(
        x_std, mu_g, m_g, mu_g)
    m_air = np.where(x_air > 0, (xg * m_g).sum(axis=-1) / np.where(x_air > 0, x_air, 1.0), 0.0289586)
    others = ("CO2", "H2O", "SO2")
    xs = _stack([x_air] + [x[..., idx[s]] for s in others])
    mu = _stack([mu_air] + [_species_viscosity_k(s, t) for s in others])
    ms = _stack([m_air] + [np.full(np.shape(m_air), MOLAR_MASS[s]) for s in others])
    if conductivity:
        prop = _stack([p_air] + [_species_conductivity_k(s, t) for s in others])
    else:
        prop = mu
    return _wilke_mix(xs, mu, ms, prop)


def species_viscosity(species: str, temperature_c):
    """Dilute-gas viscosity of one pure species, Pa s (sources in the module docstring)."""
    if species not in MOLAR_MASS:
        raise ValueError(f"species = {species!r} is not one of {', '.join(SPECIES)}")
    return _species_viscosity_k(species, _t_kelvin("temperature_c", temperature_c))


def species_conductivity(species: str, temperature_c):
    """Dilute-gas thermal conductivity of one pure species, W/(m K)."""
    if species not in MOLAR_MASS:
        raise ValueError(f"species = {species!r} is not one of {', '.join(SPECIES)}")
    return _species_conductivity_k(species, _t_kelvin("temperature_c", temperature_c))


def viscosity(temperature_c, composition):
    """Dynamic viscosity of a dilute gas mixture, Pa s (Chapman-Enskog + IAPWS H2O, Wilke mixing).

    >>> round(float(viscosity(500.0, DRY_AIR_COMPOSITION)) * 1e6, 1)
    36.5
    """
    x = composition_array(composition)
    t = _t_kelvin("temperature_c", temperature_c)
    return mixture_transport(np.asarray(t, float), x)


def thermal_conductivity(temperature_c, composition):
    """Thermal conductivity of a dilute gas mixture, W/(m K) (modified Eucken + IAPWS H2O, Mason-Saxena)."""
    x = composition_array(composition)
    t = _t_kelvin("temperature_c", temperature_c)
    return mixture_transport(np.asarray(t, float), x, conductivity=True)


def _prandtl(temperature_c, composition):
    return heat_capacity(temperature_c, composition) * viscosity(temperature_c, composition) / thermal_conductivity(
        temperature_c, composition)

