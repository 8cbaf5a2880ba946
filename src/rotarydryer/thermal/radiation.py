r"""Gas radiation in the drum: H2O/CO2 emissivity and gas-wall / gas-solids exchange.

Gas emissivity: weighted sum of grey gases (WSGG) of Smith, Shen & Friedman (1982),
J. Heat Transfer 104, 602, Table 2 - three grey gases plus a clear gas,

$$
\varepsilon_g = \sum_{i=1}^{3} a_i(T_g)\,[1 - \exp(-\kappa_i\,p_a L)],\qquad
a_i(T) = \sum_{j=1}^{4} b_{ij} T^{j-1},\qquad p_a = p_{H_2O} + p_{CO_2}\ \text{(atm)}
$$

for the coefficient sets p_w/p_c = 1 and 2, pure CO2 (p_c → 0) and pure H2O (p_w → 0).
Other ratios: the emissivity is interpolated linearly in the CO2 fraction
f_c = p_c/(p_w + p_c) between the sets at f_c = 0 (H2O), 1/3 (ratio 2), 1/2 (ratio 1)
and 1 (CO2) - a documented simplification; for pure H2O or CO2 sets the partial pressure
of that gas alone is used. Fitted for 600-2400 K and p_a L = 0.001-10 atm m; the dryer
gas (370-870 K) is partly below this range (extrapolation, flagged in the docstring;
the a_i stay positive down to 300 K). Absorptivity for wall radiation at T_w:
$\alpha_g = \sum a_i(T_w)[1-\exp(-\kappa_i p_a L)]$ (standard WSGG practice,
Modest 2013 §19.4).

Mean beam length of the freeboard: L_m = 0.95 D for an infinite cylinder radiating to
its wall (Hottel; Incropera et al. 2007 Table 13.4; Modest 2013 Table 19.5 gives 0.94 D).

Exchange:

* gas-wall (Hottel's effective wall emissivity, Hottel & Sarofim 1967; Incropera Eq. 13.x):
  $q = \sigma\,\frac{\varepsilon_w + 1}{2}\,(\varepsilon_g T_g^4 - \alpha_g T_w^4)$ W/m²;
* gas-solids (``method="grey_exchange"``, default): grey gas between two grey surfaces,
  $q = \sigma (T_g^4 - T_s^4)/(1/\varepsilon_s + 1/\varepsilon_g - 1)$;
  ``method="ajayi2011"``: Ajayi's Eq. 6.42 as coded, $q = \varepsilon_s \sigma
  (T_g^4 - T_s^4)$ (gas treated as black; overestimates by 1/ε_g for a thin gas).

Temperatures in °C at the API; fluxes in W/m² of receiving surface.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_choice, check_range
from ..properties import _kernels

__all__ = [
    "STEFAN_BOLTZMANN",
    "mean_beam_length",
    "gas_emissivity",
    "gas_absorptivity",
    "gas_wall_radiation_flux",
    "gas_solids_radiation_flux",
    "radiation_heat_transfer_coefficient",
]

STEFAN_BOLTZMANN = 5.670374419e-8  # W/(m2 K4), CODATA 2018

# Smith, Shen & Friedman (1982) Table 2: kappa_i (1/(atm m)) and b_ij (a_i = sum_j b_ij T^(j-1), T in K).
_SMITH = {
    "h2o": ((0.4098, 6.325, 120.5),
            ((5.977e-1, -5.119e-4, 3.042e-7, -5.564e-11),
             (0.5677e-1, 3.333e-4, -1.967e-7, 2.718e-11),
             (1.800e-1, -2.334e-4, 1.008e-7, -1.454e-11))),
    "ratio2": ((0.4201, 6.516, 131.9),
               ((6.508e-1, -5.551e-4, 3.029e-7, -5.353e-11),
                (-0.2504e-1, 6.112e-4, -3.882e-7, 6.528e-11),
                (2.718e-1, -3.118e-4, 1.221e-7, -1.612e-11))),
    "ratio1": ((0.4303, 7.055, 178.1),
               ((5.150e-1, -2.303e-4, 9.779e-8, -1.494e-11),
                (7.749e-2, 3.399e-4, -2.297e-7, 3.770e-11),
                (1.907e-1, -1.824e-4, 5.608e-8, -5.122e-12))),
    "co2": ((0.3966, 15.64, 394.3),
            ((0.4334e-1, 2.620e-4, -1.560e-7, 2.565e-11),
             (-0.4814e-1, 2.822e-4, -1.794e-7, 3.274e-11),
             (0.5492e-1, 0.1087e-4, -0.3500e-7, 0.9123e-11))),
}
_ANCHORS = (("h2o", 0.0), ("ratio2", 1.0 / 3.0), ("ratio1", 0.5), ("co2", 1.0))
_ANCHOR_FC = np.array([x for _, x in _ANCHORS])
ATM = 101325.0


def mean_beam_length(diameter, factor: float = 0.95):
    """Mean beam length of a long cylindrical gas volume radiating to its wall, m: L = 0.95 D."""
    d = check_range("diameter", diameter, 0.0, 100.0, unit="m")
    return factor * d


def _wsgg(set_name, t_weights, absorption):
    """Smith et al. (1982) WSGG sum: temperature weights a_i(T) times the gray gases' absorption
    factors 1 - exp(-kappa_i p L) (`_wsgg_paths`)."""
    _, b = _SMITH[set_name]
    eps = 0.0
    for bi, absorbed in zip(b, absorption):
        a = bi[0] + t_weights * (bi[1] + t_weights * (bi[2] + t_weights * bi[3]))
        eps = eps + np.maximum(a, 0.0) * absorbed
    return eps


_KERNEL_COEFFICIENTS = _kernels.pack_wsgg([(x, *_SMITH[name]) for name, x in _ANCHORS])


def _wsgg_compiled(t_k, p_h2o, p_co2, path_length):
    """`_emissivity` in one compiled pass (`rotarydryer.properties._kernels`), or None."""
    fast = _kernels.evaluate("wsgg", (t_k, np.asarray(p_h2o, dtype=float) / ATM,
                                      np.asarray(p_co2, dtype=float) / ATM, path_length), (_KERNEL_COEFFICIENTS,), 1)
    return None if fast is None else fast[0]


def _wsgg_paths(p_h2o, p_co2, path_length):
    """What of the WSGG emissivity does not depend on the temperature: the CO2 fraction of the
    radiating gas, the anchor segments that bracket it, and per anchor set its gray gases'
    absorption factors 1 - exp(-kappa p L) (a shell solve evaluates many wall temperatures at one
    gas composition); last, the inputs. With the compiled kernel on, only the inputs (the kernel
    evaluates the whole sum at each temperature)."""
    raw = (p_h2o, p_co2, path_length)
    if _kernels.compiled("wsgg") is not None:
        return None, None, None, raw
    return _wsgg_paths_numpy(*raw)


def _wsgg_paths_numpy(p_h2o, p_co2, path_length):
    ph = p_h2o / ATM
    pc = p_co2 / ATM
    pa = ph + pc
    fc = np.where(pa > 0, pc / np.where(pa > 0, pa, 1.0), 0.0)
    xs = _ANCHOR_FC
    # only the anchor sets that bracket some CO2 fraction are evaluated (the others would be
    # weighted by nothing): usually two of the four for combustion gas with moisture
    seg_of = np.clip(np.searchsorted(xs, fc, side="right") - 1, 0, len(xs) - 2)
    used = np.unique(seg_of)
    absorption = {}
    for k in np.union1d(used, used + 1):
        name = _ANCHORS[k][0]
        p = ph if name == "h2o" else (pc if name == "co2" else pa)
        pl = p * path_length
        absorption[k] = [1.0 - np.exp(-kappa * pl) for kappa in _SMITH[name][0]]
    return fc, used, absorption, (p_h2o, p_co2, path_length)


def _emissivity(t_weights_k, p_h2o, p_co2, path_length):
    fast = _wsgg_compiled(t_weights_k, p_h2o, p_co2, path_length)
    if fast is not None:
        return fast
    return _emissivity_at(t_weights_k, _wsgg_paths_numpy(p_h2o, p_co2, path_length))


def _emissivity_at(t_weights_k, paths):
    """WSGG emissivity at temperatures ``t_weights_k`` (K) of the gas of ``paths`` (`_wsgg_paths`)."""
    fc, used, absorption, raw = paths
    if fc is None:          # the compiled kernel's paths: its inputs only
        fast = _wsgg_compiled(t_weights_k, *raw)
        if fast is not None:
            return fast
        fc, used, absorption, _ = _wsgg_paths_numpy(*raw)
    xs = _ANCHOR_FC
    values = {k: _wsgg(_ANCHORS[k][0], t_weights_k, a) for k, a in absorption.items()}
    out = np.zeros(np.broadcast(fc, *values.values()).shape)
    fcb = fc if np.shape(fc) == out.shape else np.broadcast_to(fc, out.shape)
    for k in used:
        lo, hi = xs[k], xs[k + 1]
        w = (fcb - lo) / (hi - lo)
        seg = (fcb >= lo) & ((fcb < hi) | ((k == len(xs) - 2) & (fcb <= hi)))
        v = (1 - w) * values[k] + w * values[k + 1]       # broadcast to out's shape by the arithmetic
        out = np.where(seg, v, out)
    return np.clip(out, 0.0, 1.0)


def _check_gas(temperature_c, p_h2o, p_co2, path_length):
    t = check_range("gas_temperature_c", temperature_c, 0.0, 2100.0, low_inclusive=True, unit="degC") + 273.15
    ph = check_range("water_partial_pressure", p_h2o, 0.0, 1e6, low_inclusive=True, unit="Pa")
    pc = check_range("co2_partial_pressure", p_co2, 0.0, 1e6, low_inclusive=True, unit="Pa")
    length = check_range("path_length", path_length, 0.0, 100.0, low_inclusive=True, unit="m")
    return t, ph, pc, length


def gas_emissivity(gas_temperature_c, water_partial_pressure, co2_partial_pressure, path_length):
    """Total emissivity of an H2O/CO2 gas, WSGG of Smith et al. (1982).

    Parameters: gas temperature °C; partial pressures Pa; path (mean beam) length m.

    >>> round(float(gas_emissivity(726.85, 10132.5, 10132.5, 1.0)), 4)   # ratio 1, 1000 K, 0.2 atm m
    0.26
    """
    t, ph, pc, length = _check_gas(gas_temperature_c, water_partial_pressure, co2_partial_pressure, path_length)
    return _emissivity(t, ph, pc, length)


def gas_absorptivity(gas_temperature_c, wall_temperature_c, water_partial_pressure, co2_partial_pressure,
                     path_length):
    """Absorptivity of the gas for radiation from a wall at ``wall_temperature_c`` (WSGG weights at T_w)."""
    _, ph, pc, length = _check_gas(gas_temperature_c, water_partial_pressure, co2_partial_pressure, path_length)
    tw = check_range("wall_temperature_c", wall_temperature_c, 0.0, 2100.0, low_inclusive=True, unit="degC") + 273.15
    return _emissivity(tw, ph, pc, length)


def gas_wall_radiation_flux(gas_temperature_c, wall_temperature_c, gas_emissivity_value, wall_emissivity=0.79,
                            gas_absorptivity_value=None):
    """Net radiative flux gas -> wall, W/m² of wall (positive when the gas is hotter).

    Hottel's effective wall emissivity (ε_w + 1)/2; ``gas_absorptivity_value`` defaults to
    the emissivity (grey gas). Ajayi (2011) Eq. 6.53 instead uses h = ε σ (T_g + T_w)(T_g² + T_w²)
    with ε = 0.79 the shell emissivity (gas treated as black): pass
    ``gas_emissivity_value=1`` and ``wall_emissivity=2*0.79-1`` to reproduce it.
    """
    tg = check_range("gas_temperature_c", gas_temperature_c, -273.15, 2100.0, unit="degC") + 273.15
    tw = check_range("wall_temperature_c", wall_temperature_c, -273.15, 2100.0, unit="degC") + 273.15
    eg = check_range("gas_emissivity_value", gas_emissivity_value, 0.0, 1.0, low_inclusive=True,
                     high_inclusive=True)
    ag = eg if gas_absorptivity_value is None else check_range("gas_absorptivity_value", gas_absorptivity_value,
                                                               0.0, 1.0, low_inclusive=True, high_inclusive=True)
    ew = check_range("wall_emissivity", wall_emissivity, 0.0, 1.0, high_inclusive=True)
    return _gas_wall_flux(tg, tw, eg, ag, ew)


def _gas_wall_flux(tg_k, tw_k, eg, ag, ew):
    """Unchecked kernel of [`gas_wall_radiation_flux`][rotarydryer.thermal.radiation.gas_wall_radiation_flux] (temperatures in K)."""
    return STEFAN_BOLTZMANN * 0.5 * (ew + 1.0) * (eg * tg_k**4 - ag * tw_k**4)


def gas_solids_radiation_flux(gas_temperature_c, solids_temperature_c, gas_emissivity_value=1.0,
                              solids_emissivity=0.9, method: str = "grey_exchange"):
    """Net radiative flux gas -> solids surface, W/m² of solids area.

    ``method="ajayi2011"``: Ajayi (2011) Eq. 6.42 / App. F ``rad_solid = e_s σ A (T_g⁴ - T_s⁴)``
    with e_s = 0.9 (the gas emissivity is ignored). ``"grey_exchange"`` (default):
    σ (T_g⁴ - T_s⁴)/(1/ε_s + 1/ε_g - 1).

    >>> round(float(gas_solids_radiation_flux(500.0, 50.0, method="ajayi2011")), 0)
    17679.0
    """
    check_choice("method", method, ("grey_exchange", "ajayi2011"))
    tg = check_range("gas_temperature_c", gas_temperature_c, -273.15, 2100.0, unit="degC") + 273.15
    ts = check_range("solids_temperature_c", solids_temperature_c, -273.15, 2100.0, unit="degC") + 273.15
    es = check_range("solids_emissivity", solids_emissivity, 0.0, 1.0, high_inclusive=True)
    if method == "ajayi2011":
        return es * STEFAN_BOLTZMANN * (tg**4 - ts**4)
    eg = check_range("gas_emissivity_value", gas_emissivity_value, 0.0, 1.0, high_inclusive=True)
    return STEFAN_BOLTZMANN * (tg**4 - ts**4) / (1.0 / es + 1.0 / eg - 1.0)


def radiation_heat_transfer_coefficient(hot_c, cold_c, emissivity):
    """Linearised radiation coefficient h = ε σ (T_1 + T_2)(T_1² + T_2²), W/(m² K) (Ajayi Eqs. 6.53, 6.55)."""
    t1 = check_range("hot_c", hot_c, -273.15, 2100.0, unit="degC") + 273.15
    t2 = check_range("cold_c", cold_c, -273.15, 2100.0, unit="degC") + 273.15
    e = check_range("emissivity", emissivity, 0.0, 1.0, low_inclusive=True, high_inclusive=True)
    return e * STEFAN_BOLTZMANN * (t1 + t2) * (t1**2 + t2**2)
