r"""Gas-solids heat-transfer correlations for rotary dryers.

Volumetric coefficients (Song 2003 Eq. 3.2, Table 3.1):

$$
U_a = K\, f(\phi)\, G^{c}\, D^{d}
$$

with Ua in W/(m³ K), G the gas mass flux in kg/(m² s) and D the dryer diameter
in m (Song converted every row to these SI units, L1006).

Particle Nusselt correlations (Song 2003 Eq. 3.6, Table 3.2):

$$
Nu_p = \frac{U d_p}{k} = b + c\, Re_p^{d}\, Pr^{e}, \qquad Re_p = \frac{G d_p}{\mu}
$$

and Ajayi (2011) Eq. 6.41, Nu = 0.33 Re^0.6. Ambiguity: Song (L1034) says k
is the conductivity of the *solids*; in the Nu-Re-Pr correlations it is the
*gas* conductivity, which is what [`heat_transfer_coefficient`][rotarydryer.correlations.heat_transfer.heat_transfer_coefficient] expects
(Ajayi 2011 Eq. 6.41 also uses k_g).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from .._validation import check_choice, check_positive, check_range
from ._common import as_result, warn_outside

__all__ = [
    "volumetric_heat_transfer_coefficient",
    "volumetric_heat_transfer_coefficient_methods",
    "miller_1942_ua",
    "friedman_marshall_1949_ua",
    "mccormick_1962_ua",
    "myklestad_1963_ua",
    "sharples_1964_ua",
    "douglas_1993_ua",
    "alvarez_shene_1994_ua",
    "nusselt_number",
    "nusselt_number_methods",
    "van_krevelen_hoftijzer_nu",
    "mcadams_1951_nu",
    "ranz_marshall_1952_nu",
    "kunii_levenspiel_1977_nu",
    "tscheng_watkinson_1979_solids_nu",
    "tscheng_watkinson_1979_wall_nu",
    "chang_1994_nu",
    "alvarez_shene_1994_nu",
    "ajayi_2011_nu",
    "heat_transfer_coefficient",
    "log_mean_temperature_difference",
    "ua_from_drying_data",
    "chilton_colburn_mass_transfer_coefficient",
]

MATERIALS = ("saw dust", "sand", "soya meal")


def _g_d(gas_mass_flux, diameter):
    g = check_positive("gas_mass_flux", gas_mass_flux, unit="kg/(m2 s)")
    d = check_positive("diameter", diameter, unit="m")
    return g, d


# ------------------------------------------------------------------ Ua, Table 3.1


def miller_1942_ua(gas_mass_flux, diameter, n_flights=6, twelve_flight_factor="ditto"):
    r"""Volumetric heat-transfer coefficient, Miller et al. (1942).

    $$
    U_a = 89\,(N_f - 1)\,G^{0.46}/D \quad (6\ \text{flights}), \qquad
    U_a = 62\,(N_f - 1)\,G^{0.60}/D \quad (12\ \text{flights})
    $$

    Song (2003) Table 3.1 rows L994-995 in Eq. 3.2. The printed "(N_r − 1)" is
    read as (N_f − 1), N_f the number of flights.

    Parameters
    ----------
    gas_mass_flux : array_like
        Gas mass flux G, kg/(m² s).
    diameter : array_like
        Dryer diameter D, m.
    n_flights : {6, 12}
        Number of flights; Miller et al. give constants for 6 and 12 only.
    twelve_flight_factor : {"ditto", "none"}
        The f(φ) cell of the 12-flight row is blank. ``"ditto"`` (default)
        reads the blank as "same as above", f = (N_f − 1) = 11; ``"none"``
        takes f = 1. Default chosen because with f = 1 twelve flights would give
        a Ua seven times lower than six flights, against the physics (more
        flights, more curtains).

    Returns
    -------
    float or ndarray
        Ua, W/(m³ K).

    Examples
    --------
    >>> round(miller_1942_ua(2.72, 0.31, n_flights=6), 0)
    2275.0
    """
    g, d = _g_d(gas_mass_flux, diameter)
    if n_flights not in (6, 12):
        raise ValueError(f"n_flights = {n_flights!r} is not one of 6, 12 (the rows of Miller et al. 1942)")
    check_choice("twelve_flight_factor", twelve_flight_factor, ("ditto", "none"))
    if n_flights == 6:
        return as_result(89.0 * 5.0 * g**0.46 / d)
    f = 11.0 if twelve_flight_factor == "ditto" else 1.0
    return as_result(62.0 * f * g**0.60 / d)


def friedman_marshall_1949_ua(gas_mass_flux, diameter, gas_flow="counter-current", constant=None):
    r"""Volumetric heat-transfer coefficient, Friedman & Marshall (1949).

    $$
    U_a = K\, G^{c}/D, \quad K = 10,\ c = 0.16\ \text{(counter-current)}; \quad c = 0.40\ \text{(co-current)}
    $$

    Song (2003) Table 3.1 rows L996-997. The co-current constant K is not given
    in Song, so it must be passed as ``constant`` (W/(m³ K) per unit G^0.40/D).

    Parameters
    ----------
    gas_mass_flux : array_like
        G, kg/(m² s).
    diameter : array_like
        D, m.
    gas_flow : {"counter-current", "co-current"}
    constant : float, optional
        K; defaults to 10 for counter-current, required for co-current.

    Returns
    -------
    float or ndarray
        Ua, W/(m³ K).

    Examples
    --------
    >>> round(friedman_marshall_1949_ua(2.72, 0.31), 1)
    37.9
    """
    g, d = _g_d(gas_mass_flux, diameter)
    check_choice("gas_flow", gas_flow, ("counter-current", "co-current"))
    if gas_flow == "counter-current":
        k = 10.0 if constant is None else float(check_positive("constant", constant))
        return as_result(k * g**0.16 / d)
    if constant is None:
        raise ValueError("friedman_marshall_1949_ua: the co-current constant K is not given in Song (2003) "
                         "Table 3.1; pass constant=K")
    return as_result(float(check_positive("constant", constant)) * g**0.40 / d)


def mccormick_1962_ua(gas_mass_flux, diameter):
    r"""Volumetric heat-transfer coefficient, McCormick (1962): $U_a = 237\,G^{0.67}/D$.

    Song (2003) Table 3.1 L998; recommended for US industrial design (Treybal
    1980, via Song L1010). G in kg/(m² s), D in m; returns Ua in W/(m³ K).

    Examples
    --------
    >>> round(mccormick_1962_ua(2.72, 0.31), 0)
    1495.0
    """
    g, d = _g_d(gas_mass_flux, diameter)
    return as_result(237.0 * g**0.67 / d)


def myklestad_1963_ua(gas_mass_flux, diameter=None):
    r"""Volumetric heat-transfer coefficient, Myklestad (1963a): $U_a = 423\,G^{0.80}$.

    Song (2003) Table 3.1 L999 (exponent d = 0: no diameter dependence;
    ``diameter`` is accepted and ignored for a uniform signature). G in
    kg/(m² s); returns Ua in W/(m³ K).

    Examples
    --------
    >>> round(myklestad_1963_ua(2.72), 1)
    941.9
    """
    g = check_positive("gas_mass_flux", gas_mass_flux, unit="kg/(m2 s)")
    return as_result(423.0 * g**0.80)


def sharples_1964_ua(gas_mass_flux, rpm, constant):
    r"""Volumetric heat-transfer coefficient, Sharples et al. (1964): $U_a = K\,n\,G^{0.5}$.

    Song (2003) Table 3.1 L1000; K is not given in Song and must be supplied.
    G in kg/(m² s), n in rev/min; returns Ua in W/(m³ K).

    Examples
    --------
    >>> round(sharples_1964_ua(1.0, 5.0, constant=20.0), 1)
    100.0
    """
    g = check_positive("gas_mass_flux", gas_mass_flux, unit="kg/(m2 s)")
    n = check_positive("rpm", rpm, unit="rev/min")
    k = check_positive("constant", constant)
    return as_result(k * n * g**0.5)


def douglas_1993_ua(gas_mass_flux, holdup, solids_density, dryer_volume, constant, exponent):
    r"""Volumetric heat-transfer coefficient, Douglas et al. (1993).

    $$
    U_a = K\,\left(\frac{100\,H}{\rho_s V}\right)^{\beta} G^{0.16}
    $$

    Song (2003) Table 3.1 L1001; printed "(H100/ρ_s V)^β", read as the percent
    volumetric holdup to a power β (not the Cholette-Cloutier β). K and β are not
    given and must be supplied.

    Parameters
    ----------
    gas_mass_flux : array_like
        G, kg/(m² s).
    holdup : array_like
        Solids holdup H, kg.
    solids_density : array_like
        ρ_s, kg/m³.
    dryer_volume : array_like
        V, m³.
    constant, exponent : float
        K and β.

    Returns
    -------
    float or ndarray
        Ua, W/(m³ K).

    Examples
    --------
    >>> round(douglas_1993_ua(1.0, 30.0, 1650.0, 0.2228, constant=100.0, exponent=0.5), 2)
    285.67
    """
    g = check_positive("gas_mass_flux", gas_mass_flux, unit="kg/(m2 s)")
    h = check_positive("holdup", holdup, unit="kg")
    rho = check_positive("solids_density", solids_density, unit="kg/m3")
    v = check_positive("dryer_volume", dryer_volume, unit="m3")
    k = check_positive("constant", constant)
    beta = check_range("exponent", exponent, -5.0, 5.0)
    return as_result(k * (100.0 * h / (rho * v)) ** beta * g**0.16)


_AS_UA = {"saw dust": (271.0, 0.719), "sand": (276.0, 0.828), "soya meal": (283.0, 0.834)}


def alvarez_shene_1994_ua(gas_mass_flux, diameter, material="sand"):
    r"""Volumetric heat-transfer coefficient, Alvarez & Shene (1994): $U_a = K\,G^{c}/D$.

    Song (2003) Table 3.1 L1002-1004: K = 271, 276, 283 and c = 0.719, 0.828,
    0.834 for saw dust, sand and soya meal. G in kg/(m² s), D in m; returns Ua in
    W/(m³ K).

    Examples
    --------
    >>> round(alvarez_shene_1994_ua(2.72, 0.31, "sand"), 0)
    2039.0
    """
    g, d = _g_d(gas_mass_flux, diameter)
    check_choice("material", material, MATERIALS)
    k, c = _AS_UA[material]
    return as_result(k * g**c / d)


_UA_METHODS: dict[str, tuple[Callable[..., Any], tuple[str, ...]]] = {
    "mccormick_1962": (mccormick_1962_ua, ("gas_mass_flux", "diameter")),
    "myklestad_1963": (myklestad_1963_ua, ("gas_mass_flux",)),
    "alvarez_shene_1994": (alvarez_shene_1994_ua, ("gas_mass_flux", "diameter", "material")),
    "miller_1942": (miller_1942_ua, ("gas_mass_flux", "diameter", "n_flights")),
    "friedman_marshall_1949": (friedman_marshall_1949_ua, ("gas_mass_flux", "diameter", "gas_flow", "constant")),
    "sharples_1964": (sharples_1964_ua, ("gas_mass_flux", "rpm", "constant")),
    "douglas_1993": (douglas_1993_ua, ("gas_mass_flux", "holdup", "solids_density", "dryer_volume",
                                       "constant", "exponent")),
}
_UA_OPTIONAL = {"material", "gas_flow", "n_flights", "twelve_flight_factor"}


def volumetric_heat_transfer_coefficient_methods(**inputs) -> list[str]:
    """List the Ua correlations (Song 2003 Table 3.1) that can be evaluated with the given inputs.

    ``friedman_marshall_1949`` is listed without ``constant`` only for
    counter-current gas (its co-current constant is not published in Song).

    Examples
    --------
    >>> volumetric_heat_transfer_coefficient_methods(gas_mass_flux=2.0, diameter=0.3)
    ['mccormick_1962', 'myklestad_1963', 'alvarez_shene_1994', 'miller_1942', 'friedman_marshall_1949']
    """
    given = {k for k, v in inputs.items() if v is not None}
    out = []
    for name, (_, needed) in _UA_METHODS.items():
        req = set(needed) - _UA_OPTIONAL
        if name == "friedman_marshall_1949" and inputs.get("gas_flow", "counter-current") == "counter-current":
            req = req - {"constant"}
        if req <= given:
            out.append(name)
    return out


def volumetric_heat_transfer_coefficient(method: str = "mccormick_1962", **inputs):
    """Volumetric gas-solids heat-transfer coefficient Ua, W/(m³ K), by the chosen correlation.

    Parameters
    ----------
    method : str
        One of ``mccormick_1962`` (default), ``myklestad_1963``,
        ``alvarez_shene_1994``, ``miller_1942``, ``friedman_marshall_1949``,
        ``sharples_1964``, ``douglas_1993`` (Song 2003 Table 3.1).
    **inputs
        ``gas_mass_flux`` kg/(m² s), ``diameter`` m and the method-specific
        arguments (see each function). Unused inputs are ignored.

    Examples
    --------
    >>> round(volumetric_heat_transfer_coefficient("alvarez_shene_1994", gas_mass_flux=2.72,
    ...                                            diameter=0.31, material="sand"), 0)
    2039.0
    """
    check_choice("method", method, _UA_METHODS)
    func, needed = _UA_METHODS[method]
    extra = ("twelve_flight_factor",) if method == "miller_1942" else ()
    kwargs = {k: inputs[k] for k in needed + extra if inputs.get(k) is not None}
    return func(**kwargs)


# ------------------------------------------------------------------ Nusselt, Table 3.2


def _re_pr(reynolds, prandtl, need_pr=True):
    re = check_range("reynolds", reynolds, 0.0, math.inf, low_inclusive=True)
    if not need_pr:
        return re, None
    pr = check_positive("prandtl", prandtl)
    return re, pr


def van_krevelen_hoftijzer_nu(reynolds, prandtl):
    r"""Particle Nusselt number, Van Krevelen & Hoftijzer (via Mujumdar 1995): $Nu = Re^{0.5} Pr^{0.33}$.

    Song (2003) Table 3.2 L1040 (constant-rate drying period). Re_p = G d_p/μ.

    Examples
    --------
    >>> round(van_krevelen_hoftijzer_nu(100.0, 0.71), 3)
    8.931
    """
    re, pr = _re_pr(reynolds, prandtl)
    return as_result(re**0.5 * pr**0.33)


def mcadams_1951_nu(reynolds, prandtl=None):
    r"""Particle Nusselt number, McAdams (1951): $Nu = 0.33\,Re^{0.6}$.

    Song (2003) Table 3.2 L1041 (no Pr dependence).

    Examples
    --------
    >>> round(mcadams_1951_nu(100.0), 3)
    5.23
    """
    re, _ = _re_pr(reynolds, prandtl, need_pr=False)
    return as_result(0.33 * re**0.6)


def ranz_marshall_1952_nu(reynolds, prandtl, particle_diameter=None):
    r"""Particle Nusselt number, Ranz & Marshall (1952): $Nu = 2 + 0.6\,Re^{1/2} Pr^{1/3}$.

    Song (2003) Table 3.2 L1042, noted there for large particles, d_p > 1.4 mm;
    also Ajayi (2011) Eq. 6.37 (not used by Ajayi). If ``particle_diameter``
    (m) is given and below 1.4 mm a CorrelationRangeWarning is issued.

    Examples
    --------
    >>> round(ranz_marshall_1952_nu(100.0, 0.71), 3)
    7.353
    """
    re, pr = _re_pr(reynolds, prandtl)
    if particle_diameter is not None:
        dp = check_positive("particle_diameter", particle_diameter, unit="m")
        warn_outside("particle_diameter", dp, 1.4e-3, math.inf, unit="m",
                     source="Ranz & Marshall (1952) per Song (2003) Table 3.2")
    return as_result(2.0 + 0.6 * re**0.5 * pr ** (1.0 / 3.0))


def kunii_levenspiel_1977_nu(reynolds, prandtl=None):
    r"""Particle Nusselt number, Kunii & Levenspiel (1977): $Nu = 0.03\,Re^{1.3}$.

    Song (2003) Table 3.2 L1045 (small particles; no numeric range given).

    Examples
    --------
    >>> round(kunii_levenspiel_1977_nu(100.0), 3)
    11.943
    """
    re, _ = _re_pr(reynolds, prandtl, need_pr=False)
    return as_result(0.03 * re**1.3)


def tscheng_watkinson_1979_solids_nu(reynolds, rotational_reynolds, fill_fraction, prandtl=None):
    r"""Gas-to-solids Nusselt number, Tscheng & Watkinson (1979).

    $$
    Nu = 0.46\, Re^{0.535}\, Re_T^{0.104}\, f^{-0.341}
    $$

    Song (2003) Table 3.2 L1046; Re_T is the rotational Reynolds number and f
    the fraction of solid fill (Song nomenclature L221, L249).

    Examples
    --------
    >>> round(tscheng_watkinson_1979_solids_nu(100.0, 1000.0, 0.1), 3)
    24.308
    """
    re, _ = _re_pr(reynolds, prandtl, need_pr=False)
    ret = check_positive("rotational_reynolds", rotational_reynolds)
    f = check_range("fill_fraction", fill_fraction, 0.0, 1.0, high_inclusive=True)
    return as_result(0.46 * re**0.535 * ret**0.104 * f**-0.341)


def tscheng_watkinson_1979_wall_nu(reynolds, rotational_reynolds, prandtl=None):
    r"""Gas-to-wall Nusselt number, Tscheng & Watkinson (1979): $Nu = 1.54\,Re^{0.575} Re_T^{-0.292}$.

    Song (2003) Table 3.2 L1047; the b and e cells are blank and read as 0.

    Examples
    --------
    >>> round(tscheng_watkinson_1979_wall_nu(100.0, 1000.0), 3)
    2.894
    """
    re, _ = _re_pr(reynolds, prandtl, need_pr=False)
    ret = check_positive("rotational_reynolds", rotational_reynolds)
    return as_result(1.54 * re**0.575 * ret**-0.292)


def chang_1994_nu(reynolds, prandtl=None):
    r"""Particle Nusselt number, Chang (1994): $Nu = 0.019\,Re^{1.358}$.

    Song (2003) Table 3.2 L1048.

    Examples
    --------
    >>> round(chang_1994_nu(100.0), 3)
    9.88
    """
    re, _ = _re_pr(reynolds, prandtl, need_pr=False)
    return as_result(0.019 * re**1.358)


_AS_NU = {"saw dust": (0.065, 0.638), "sand": (0.0908, 0.394), "soya meal": (0.0219, 0.825)}


def alvarez_shene_1994_nu(reynolds, material="sand", prandtl=None):
    r"""Particle Nusselt number, Alvarez & Shene (1994): $Nu = c\,Re^{d}$.

    Song (2003) Table 3.2 L1049-1051: (c, d) = (0.065, 0.638) saw dust,
    (0.0908, 0.394) sand, (0.0219, 0.825) soya meal; regressed on their own dryer.

    Examples
    --------
    >>> round(alvarez_shene_1994_nu(100.0, "sand"), 4)
    0.5573
    """
    re, _ = _re_pr(reynolds, prandtl, need_pr=False)
    check_choice("material", material, MATERIALS)
    c, d = _AS_NU[material]
    return as_result(c * re**d)


def ajayi_2011_nu(reynolds, prandtl=None):
    r"""Particle Nusselt number used by Ajayi (2011) Eq. 6.41: $Nu = 0.33\,Re^{0.6}$.

    Flow over spheres (Kelly 1987; Didriksen 2002; Raffak et al. 2008 via Ajayi);
    the same constants as McAdams (1951) in Song's Table 3.2. Ajayi evaluates Re
    with the superficial gas velocity over the full drum cross-section and the
    section particle diameter, and takes gas properties at the gas temperature.

    Examples
    --------
    >>> round(ajayi_2011_nu(1490.0), 2)
    26.45
    """
    re, _ = _re_pr(reynolds, prandtl, need_pr=False)
    return as_result(0.33 * re**0.6)


_NU_METHODS: dict[str, tuple[Callable[..., Any], tuple[str, ...]]] = {
    "ranz_marshall_1952": (ranz_marshall_1952_nu, ("reynolds", "prandtl")),
    "ajayi_2011": (ajayi_2011_nu, ("reynolds",)),
    "mcadams_1951": (mcadams_1951_nu, ("reynolds",)),
    "van_krevelen_hoftijzer": (van_krevelen_hoftijzer_nu, ("reynolds", "prandtl")),
    "kunii_levenspiel_1977": (kunii_levenspiel_1977_nu, ("reynolds",)),
    "chang_1994": (chang_1994_nu, ("reynolds",)),
    "alvarez_shene_1994": (alvarez_shene_1994_nu, ("reynolds", "material")),
    "tscheng_watkinson_1979_solids": (tscheng_watkinson_1979_solids_nu,
                                      ("reynolds", "rotational_reynolds", "fill_fraction")),
    "tscheng_watkinson_1979_wall": (tscheng_watkinson_1979_wall_nu, ("reynolds", "rotational_reynolds")),
}


def nusselt_number_methods(**inputs) -> list[str]:
    """List the particle Nusselt correlations that can be evaluated with the given inputs.

    ``material`` defaults to sand, so ``alvarez_shene_1994`` needs only Re.

    Examples
    --------
    >>> nusselt_number_methods(reynolds=100.0)
    ['ajayi_2011', 'mcadams_1951', 'kunii_levenspiel_1977', 'chang_1994', 'alvarez_shene_1994']
    """
    given = {k for k, v in inputs.items() if v is not None} | {"material"}
    return [name for name, (_, needed) in _NU_METHODS.items() if set(needed) <= given]


def nusselt_number(reynolds, prandtl=None, method: str = "ranz_marshall_1952", **inputs):
    """Particle Nusselt number Nu_p = U d_p/k by the chosen correlation (Song 2003 Eq. 3.6).

    Parameters
    ----------
    reynolds : array_like
        Particle Reynolds number Re_p = G d_p/μ (G gas mass flux kg/(m² s),
        d_p m, μ Pa s).
    prandtl : array_like, optional
        Gas Prandtl number (needed by Ranz-Marshall and Van Krevelen-Hoftijzer).
    method : str
        Key of a Song (2003) Table 3.2 row or ``ajayi_2011``.
    **inputs
        ``rotational_reynolds``, ``fill_fraction``, ``material``,
        ``particle_diameter`` for the methods that use them.

    Examples
    --------
    >>> round(nusselt_number(100.0, 0.71, method="ranz_marshall_1952"), 3)
    7.353
    """
    check_choice("method", method, _NU_METHODS)
    func, needed = _NU_METHODS[method]
    kwargs = {k: inputs[k] for k in needed if k not in ("reynolds", "prandtl") and inputs.get(k) is not None}
    if method == "ranz_marshall_1952" and inputs.get("particle_diameter") is not None:
        kwargs["particle_diameter"] = inputs["particle_diameter"]
    if "prandtl" in needed:
        if prandtl is None:
            raise ValueError(f"nusselt_number(method={method!r}) needs prandtl")
        return func(reynolds, prandtl, **kwargs)
    return func(reynolds, **kwargs)


def heat_transfer_coefficient(nusselt, thermal_conductivity, particle_diameter):
    r"""Film heat-transfer coefficient from a Nusselt number, $U = Nu\,k/d_p$, W/(m² K).

    Song (2003) Eq. 3.6; Ajayi (2011) Eq. 6.41 (h_c = Nu k_g/d_p).

    Parameters
    ----------
    nusselt : array_like
        Nu, dimensionless.
    thermal_conductivity : array_like
        Gas thermal conductivity k, W/(m K).
    particle_diameter : array_like
        d_p, m.

    Examples
    --------
    >>> round(heat_transfer_coefficient(ajayi_2011_nu(1490.0), 0.0561, 0.02), 1)
    74.2
    """
    nu = check_range("nusselt", nusselt, 0.0, math.inf, low_inclusive=True)
    k = check_positive("thermal_conductivity", thermal_conductivity, unit="W/(m K)")
    d = check_positive("particle_diameter", particle_diameter, unit="m")
    return as_result(nu * k / d)


# ------------------------------------------------------------------ estimation from data


def log_mean_temperature_difference(delta_in, delta_out):
    r"""Log-mean of two temperature differences, K: $(\Delta_1-\Delta_2)/\ln(\Delta_1/\Delta_2)$.

    Song (2003) Eqs. 3.1 and 3.9. Both differences must be positive (same sign
    convention at both ends); equal differences return that difference.

    Examples
    --------
    >>> round(log_mean_temperature_difference(100 - 12.3, 38 - 27), 2)
    36.95
    """
    a = check_positive("delta_in", delta_in, unit="K")
    b = check_positive("delta_out", delta_out, unit="K")
    ratio = a / b
    close = np.abs(ratio - 1.0) < 1e-9
    safe = np.where(close, 2.0, ratio)
    lm = np.where(close, a, (a - b) / np.log(safe))
    return as_result(lm)


def ua_from_drying_data(dry_solids_rate, moisture_in, moisture_out, dryer_volume,
                        gas_in, gas_out, solids_in, solids_out, latent_heat=2.5e6):
    r"""Volumetric heat-transfer coefficient estimated from dryer data, Song (2003) Eq. 3.9.

    $$
    U_a = \frac{F\,\lambda\,(X_{in} - X_{out})}{V\,(T_g - T_s)_{LM}}
    $$

    All heat lost by the gas is assumed to evaporate water (no losses, no
    sensible heating of the solids); co-current log mean over the two ends.

    Parameters
    ----------
    dry_solids_rate : array_like
        F, kg dry solids/s.
    moisture_in, moisture_out : array_like
        X, kg water/kg dry solids.
    dryer_volume : array_like
        V, m³.
    gas_in, gas_out, solids_in, solids_out : array_like
        Gas and solids temperatures at the inlet and outlet, °C or K (only
        differences are used).
    latent_heat : float
        λ, J/kg (Song L952: 2500 kJ/kg).

    Returns
    -------
    float or ndarray
        Ua, W/(m³ K).

    Examples
    --------
    >>> F = 67.5 / 3600 / 1.0845                   # Song (2003) L1108, 100 °C run
    >>> V = math.pi / 4 * 0.31**2 * 3.0
    >>> round(ua_from_drying_data(F, 0.0845, 0.0382, V, 100, 38, 12.3, 27), 1)
    239.2
    """
    f = check_positive("dry_solids_rate", dry_solids_rate, unit="kg/s")
    xi = check_range("moisture_in", moisture_in, 0.0, math.inf, low_inclusive=True, unit="kg/kg")
    xo = check_range("moisture_out", moisture_out, 0.0, math.inf, low_inclusive=True, unit="kg/kg")
    v = check_positive("dryer_volume", dryer_volume, unit="m3")
    lam = check_positive("latent_heat", latent_heat, unit="J/kg")
    lmtd = log_mean_temperature_difference(np.asarray(gas_in, float) - np.asarray(solids_in, float),
                                           np.asarray(gas_out, float) - np.asarray(solids_out, float))
    return as_result(f * lam * (xi - xo) / (v * lmtd))


def chilton_colburn_mass_transfer_coefficient(ua, gas_density, gas_heat_capacity, schmidt, prandtl,
                                              gas_temperature, water_molar_mass=0.018015):
    r"""Volumetric mass-transfer coefficient from Ua by the Chilton-Colburn analogy, Song (2003) Eq. 3.8.

    $$
    K_m a = \frac{U_a\, M}{\rho_g\, c_p\, (Sc/Pr)^{2/3}\, R_0\, T}
    $$

    Song prints ρ_s; read here as the **gas** density ρ_g, because only that
    reproduces Song's Table 3.3 Chilton-Colburn column (notes/song.md §5.4).

    Parameters
    ----------
    ua : array_like
        W/(m³ K).
    gas_density : array_like
        ρ_g, kg/m³.
    gas_heat_capacity : array_like
        c_p, J/(kg K).
    schmidt, prandtl : array_like
        Sc and Pr of the gas.
    gas_temperature : array_like
        T, K.
    water_molar_mass : float
        M, kg/mol.

    Returns
    -------
    float or ndarray
        K_m a, kg water/(m³ s Pa). (Song's Table 3.3 is per kPa: multiply by 1000.)

    Examples
    --------
    >>> rho = 101325 * 0.02897 / (8.314 * 330.0)
    >>> round(1e3 * chilton_colburn_mass_transfer_coefficient(225.3, rho, 1006.0, 0.60, 0.71, 330.0), 5)
    0.00154
    """
    ua = check_range("ua", ua, 0.0, math.inf, low_inclusive=True, unit="W/(m3 K)")
    rho = check_positive("gas_density", gas_density, unit="kg/m3")
    cp = check_positive("gas_heat_capacity", gas_heat_capacity, unit="J/(kg K)")
    sc = check_positive("schmidt", schmidt)
    pr = check_positive("prandtl", prandtl)
    t = check_positive("gas_temperature", gas_temperature, unit="K")
    m = check_positive("water_molar_mass", water_molar_mass, unit="kg/mol")
    return as_result(ua * m / (rho * cp * (sc / pr) ** (2.0 / 3.0) * 8.314 * t))
