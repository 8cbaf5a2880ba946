"""Compiled forms of the humid-air property functions every residual of the dryer calls (numba, optional).

Transport properties (:func:`rotarydryer.properties.humid_air._transport`: Lemmon & Jacobsen (2004)
dilute air, IAPWS (2008, 2011) dilute water vapour, Wilke (1950) / Mason-Saxena mixing, Poling et
al. (2001) Eqs. 9-5.13, 10-6.1), the humid heat and the enthalpy parts of
:mod:`rotarydryer.properties.humid_air` (NASA polynomials, McBride et al. 2002) in one compiled
loop per element instead of some 40 NumPy calls on small arrays each. The NumPy functions of
:mod:`~rotarydryer.properties.humid_air` stay the reference: the same equations with the same
coefficients (packed from :mod:`~rotarydryer.properties.combustion` by :func:`pack`), the same
numbers to rounding (``tests/properties/test_property_kernels.py``). Plain loops, so the module
imports without numba; :func:`compiled` returns None when the kernels are off
(:mod:`rotarydryer._jit`) and the callers then take their NumPy path.
"""

from __future__ import annotations

import math

import numpy as np

from .. import _jit

# offsets into the packed coefficient array (pack)
_B, _H, _L, _MA, _MW, _RATIO, _NASA, _WAIR, _MSP, _HREF, _LAT, _R = 9, 14, 18, 23, 24, 25, 26, 54, 57, 60, 64, 65
_SIZE = 66


def pack(lemmon_air, lj_b, iapws_h, iapws_l, molar_mass_air, molar_mass_h2o, nasa, air_weights, air_molar_masses,
         h_ref_j_mol, latent_ref, gas_constant):
    """The coefficients of the reference functions as one float array (read by the kernels).

    ``lemmon_air``: Lemmon & Jacobsen (2004) air parameters (M, sigma, eps/k, Tc, N1, N2, t2, N3, t3);
    ``lj_b``: their collision-integral coefficients; ``iapws_h``, ``iapws_l``: IAPWS (2008) Eq. 11 and
    IAPWS (2011) Eq. 16 dilute-gas coefficients; ``nasa``: the NASA coefficients (a1..a7) of N2, O2,
    Ar and H2O; ``air_weights``, ``air_molar_masses``: mass fractions in dry air and molar masses
    (kg/mol) of N2, O2, Ar; ``h_ref_j_mol``: molar
    enthalpy above 298.15 K of N2, O2, Ar at 0 °C and of H2O at 0.01 °C; ``latent_ref``: latent heat
    at 0.01 °C, J/kg; ``gas_constant`` J/(mol K)."""
    c = np.concatenate([np.asarray(lemmon_air, float), np.asarray(lj_b, float), np.asarray(iapws_h, float),
                        np.asarray(iapws_l, float), [molar_mass_air, molar_mass_h2o, molar_mass_h2o / molar_mass_air],
                        np.asarray(nasa, float).ravel(), np.asarray(air_weights, float),
                        np.asarray(air_molar_masses, float), np.asarray(h_ref_j_mol, float), [latent_ref, gas_constant]])
    assert c.size == _SIZE
    return c


def _transport_loop(t, y, c, mu, k):
    """Viscosity (Wilke) and conductivity (Mason-Saxena) of humid air at t °C, Y kg/kg (flat arrays)."""
    m_a, sigma, eps, tc, n1, n2, t2, n3, t3 = c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8]
    ma, mw = c[_MA], c[_MW]
    # Wilke's mass ratios (Poling et al. (2001) Eq. 9-5.14)
    q12 = (mw / ma) ** 0.25
    q21 = (ma / mw) ** 0.25
    s12 = math.sqrt(8.0 * (1.0 + ma / mw))
    s21 = math.sqrt(8.0 * (1.0 + mw / ma))
    for i in range(t.size):
        tk = t[i] + 273.15
        # air, Lemmon & Jacobsen (2004) Eqs. 2-5 (dilute gas)
        lt = math.log(tk / eps)
        s = 0.0
        p = 1.0
        for j in range(5):
            s += c[_B + j] * p
            p *= lt
        mu_a = 1e-6 * 0.0266958 * math.sqrt(m_a * tk) / (sigma * sigma * math.exp(s))
        tau = tc / tk
        k_a = 1e-3 * (n1 * 1e6 * mu_a + n2 * tau ** t2 + n3 * tau ** t3)
        # water vapour, IAPWS (2008) Eq. 11 and IAPWS (2011) Eq. 16 (dilute gas)
        tb = tk / 647.096
        sh = 0.0
        p = 1.0
        for j in range(4):
            sh += c[_H + j] / p
            p *= tb
        sl = 0.0
        p = 1.0
        for j in range(5):
            sl += c[_L + j] / p
            p *= tb
        rt = math.sqrt(tb)
        mu_v = 1e-4 * rt / sh
        k_v = 1e-3 * rt / sl
        # mixing: x_a = 1 - x_w, x_w = Y / (Y + M_w / M_a)
        yy = y[i]
        xa = 1.0 - yy / (yy + c[_RATIO])
        xw = 1.0 - xa
        f12 = 1.0 + math.sqrt(mu_a / mu_v) * q12
        f21 = 1.0 + math.sqrt(mu_v / mu_a) * q21
        phi12 = f12 * f12 / s12
        phi21 = f21 * f21 / s21
        da = xa + xw * phi12
        dw = xw + xa * phi21
        mu[i] = xa * mu_a / da + xw * mu_v / dw
        k[i] = xa * k_a / da + xw * k_v / dw


def _helper(fn):
    """A function the kernels call: compiled with them (plain Python without numba, never called then)."""
    return _jit.kernel(fn) or fn


@_helper
def _cp_molar(c, species, tk):
    a = _NASA + 7 * species
    return c[_R] * (c[a] + tk * (c[a + 1] + tk * (c[a + 2] + tk * (c[a + 3] + tk * c[a + 4]))))


@_helper
def _h_nasa(c, a, x):
    return c[_R] * (x * (c[a] + x * (c[a + 1] / 2 + x * (c[a + 2] / 3 + x * (c[a + 3] / 4 + x * c[a + 4] / 5))))
                    + c[a + 5])


@_helper
def _h_molar(c, species, tk):
    """NASA molar enthalpy relative to 298.15 K, J/mol."""
    a = _NASA + 7 * species
    return _h_nasa(c, a, tk) - _h_nasa(c, a, 298.15)


def _heat_loop(t, y, c, humid_heat, air_enthalpy, vapour_enthalpy):
    """Humid heat c_pa + Y c_pv (J/(kg dry air K)), the dry-air enthalpy above 0 °C and the vapour
    enthalpy above liquid water at 0.01 °C (J/kg) at t °C (flat arrays; y may be empty: then only
    the enthalpies)."""
    mw = c[_MW]
    for i in range(t.size):
        tk = t[i] + 273.15
        cpa = 0.0
        ha = 0.0
        for s in range(3):
            w = c[_WAIR + s]
            cpa += w * (_cp_molar(c, s, tk) / c[_MSP + s])
            ha += w * ((_h_molar(c, s, tk) - c[_HREF + s]) / c[_MSP + s])
        hv = c[_LAT] + (_h_molar(c, 3, tk) - c[_HREF + 3]) / mw
        if y.size:
            humid_heat[i] = cpa + y[i] * (_cp_molar(c, 3, tk) / mw)
        air_enthalpy[i] = ha
        vapour_enthalpy[i] = hv


def _wsgg_loop(t, ph, pc, length, c, out):
    """Smith, Shen & Friedman (1982) WSGG emissivity at t K of a gas with H2O and CO2 partial pressures
    ph, pc (atm) over the path ``length`` (m), interpolated in the CO2 fraction between the anchor sets
    (:func:`rotarydryer.thermal.radiation._emissivity`); c: per anchor set its CO2 fraction, then
    kappa_1..3 and b_ij (i = 1..3, j = 1..4) (:func:`pack_wsgg`); flat arrays."""
    for i in range(t.size):
        h = ph[i]
        co = pc[i]
        pa = h + co
        fc = co / pa if pa > 0 else 0.0
        k = 0
        while k < 2 and fc >= c[16 * (k + 1)]:
            k += 1
        lo = c[16 * k]
        hi = c[16 * (k + 1)]
        if not (fc >= lo and (fc < hi or (k == 2 and fc <= hi))):
            out[i] = 0.0
            continue
        w = (fc - lo) / (hi - lo)
        tt = t[i]
        v = 0.0
        for side in range(2):
            a = 16 * (k + side)
            p = h if k + side == 0 else (co if k + side == 3 else pa)
            pl = p * length[i]
            eps = 0.0
            for g in range(3):
                b = a + 4 + 4 * g
                weight = c[b] + tt * (c[b + 1] + tt * (c[b + 2] + tt * c[b + 3]))
                eps = eps + max(weight, 0.0) * (1.0 - math.exp(-c[a + 1 + g] * pl))
            v += (1.0 - w) * eps if side == 0 else w * eps
        out[i] = min(max(v, 0.0), 1.0)


def pack_wsgg(anchors):
    """WSGG coefficients for :func:`_wsgg_loop`: per anchor set (in the order of their CO2 fractions)
    ``(co2_fraction, (kappa_1..3), ((b_1j), (b_2j), (b_3j)))``."""
    rows = []
    for fc, kappa, b in anchors:
        rows.append(np.concatenate([[fc], np.asarray(kappa, float), np.asarray(b, float).ravel()]))
    c = np.concatenate(rows)
    assert c.size == 16 * len(anchors) == 64
    return c


def _psat_loop(t, c, out):
    """Wagner & Pruss (1993) Eq. 2.5 saturation pressure over liquid water (t >= 273.16 K), IAPWS R14-08
    (2011) Eq. 6 sublimation pressure below, Pa, at t K (:func:`rotarydryer.properties.water._saturation_pressure`);
    c: Tc, pc, Tt, pt, a_1..6, their exponents, then the ice a_1..3 and b_1..3 (:func:`pack_psat`)."""
    tc, pc, tt, pt = c[0], c[1], c[2], c[3]
    for i in range(t.size):
        x = t[i]
        if x >= tt:
            tau = 1.0 - x / tc
            f = 0.0
            for j in range(6):
                f = f + c[4 + j] * tau ** c[10 + j]
            out[i] = pc * math.exp(tc / x * f)
        else:
            theta = x / tt
            f = 0.0
            for j in range(3):
                f = f + c[16 + j] * theta ** c[19 + j]
            out[i] = pt * math.exp(f / theta)


def pack_psat(tc, pc, tt, pt, a, exponents, ice_a, ice_b):
    """Coefficients of :func:`_psat_loop`."""
    c = np.concatenate([[tc, pc, tt, pt], a, exponents, ice_a, ice_b]).astype(float)
    assert c.size == 22
    return c


def _diffusivity_loop(t, p_atm, switch_k, blend_k, out):
    """Marrero & Mason (1972) water-vapour diffusivity in air, m2/s, at t K and p atm, the two power laws
    blended over switch_k +- blend_k (:func:`rotarydryer.properties.humid_air._water_vapour_diffusivity`)."""
    for i in range(t.size):
        x = t[i]
        low = 1.87e-10 * x ** 2.072
        high = 2.75e-9 * x ** 1.632
        s = min(max((x - (switch_k - blend_k)) / (2.0 * blend_k), 0.0), 1.0)
        if s <= 0.0:
            v = low
        elif s >= 1.0:
            v = high
        else:
            v = low + s ** 3 * (s * (6.0 * s - 15.0) + 10.0) * (high - low)
        out[i] = v / p_atm[i]


def flat(*arrays):
    """Float arrays broadcast to one shape: (shape, C-contiguous flat arrays, copies where needed)."""
    a = [np.asarray(x, dtype=float) for x in arrays]
    shape = a[0].shape
    if all(x.shape == shape and x.flags.c_contiguous for x in a):     # the solvers' usual case: no copies
        return shape, [x.reshape(-1) for x in a]
    if any(x.shape != shape for x in a[1:]):
        shape = np.broadcast_shapes(*(x.shape for x in a))
    out = []
    for x in a:
        if x.shape == shape:
            out.append(np.ascontiguousarray(x).reshape(-1))
        elif x.ndim == 0:
            out.append(np.full(math.prod(shape), x))
        else:
            out.append(np.ascontiguousarray(np.broadcast_to(x, shape)).reshape(-1))
    return shape, out


def shaped(shape, *flat_arrays):
    """The flat results in ``shape`` (NumPy scalars for shape ())."""
    return tuple(x.reshape(shape) if shape else x[0] for x in flat_arrays)


_LOOPS = {"transport": _transport_loop, "heat": _heat_loop, "wsgg": _wsgg_loop, "psat": _psat_loop,
          "diffusivity": _diffusivity_loop}
_compiled = {}


def compiled(name):
    """The compiled kernel ``name`` (a key of ``_LOOPS``), or None when compiled kernels are off."""
    if not _jit.enabled():
        return None
    fn = _compiled.get(name)
    if fn is None:
        fn = _jit.kernel(_LOOPS[name])
        if fn is None:
            return None
        _compiled[name] = fn
    return fn


def call(name, *args):
    """Run kernel ``name`` on ``args``; False (and the kernels off, with a warning) if numba fails."""
    fn = compiled(name)
    if fn is None:
        return False
    try:
        fn(*args)
    except Exception as exc:     # a numba that cannot compile here: the NumPy references instead
        _jit.disable(f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}")
        return False
    return True
