"""Compiled forms of the physics every residual of the dryer calls (numba, optional).

* Humid-air transport properties (`rotarydryer.properties.humid_air._transport`: Lemmon &
  Jacobsen (2004) dilute air, IAPWS (2008, 2011) dilute water vapour, Wilke (1950) / Mason-Saxena
  mixing, Poling et al. (2001) Eqs. 9-5.13, 10-6.1), the humid heat and the enthalpy parts (NASA
  polynomials, McBride et al. 2002), the Wagner & Pruss (1993) saturation pressure, the Marrero &
  Mason (1972) diffusivity and the Smith, Shen & Friedman (1982) WSGG emissivity;
* the gas -> solids transfer of a set of gas stages (`rotarydryer.thermal.balances._stage_transfer`,
  physical mode) and the shell-loss network with its shell temperature solved
  (`rotarydryer.thermal.shell.shell_heat_loss`), built from the scalar forms above;
* the steady-state solver's step (`rotarydryer.thermal.dryer.ThermalDryer._radius_step`, `_bounded_step`,
  `_admissible`, `_residual_norm`: a dozen NumPy calls each on 80-300 numbers, called three to five times an iteration).

Each is one compiled loop per element instead of dozens of NumPy calls on small arrays. The NumPy
functions stay the references: the same equations with the same coefficients (packed from the
reference tables by the ``pack*`` functions), the same numbers to rounding, and for the shell the
same root to its 1e-9 K tolerance (``tests/properties/test_property_kernels.py``,
``tests/thermal/test_compiled_physics.py``). One module: numba's disk cache tracks the file of a
compiled function, not the files of the functions it calls. Plain loops, so the module imports
without numba; `compiled` returns None when the kernels are off (`rotarydryer._jit`)
and the callers then take their NumPy path.
"""

from __future__ import annotations

import math

import numpy as np

from .. import _jit

# offsets into the packed coefficient array (pack)
_B, _H, _L, _MA, _MW, _RATIO, _NASA, _WAIR, _MSP, _HREF, _LAT, _R = 9, 14, 18, 23, 24, 25, 26, 54, 57, 60, 64, 65
_WILKE = 66      # Wilke's mass-ratio terms (M_w/M_a)^0.25, (M_a/M_w)^0.25, sqrt(8(1 + M_a/M_w)), sqrt(8(1 + M_w/M_a))
_SIZE = 70


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
                        np.asarray(air_molar_masses, float), np.asarray(h_ref_j_mol, float), [latent_ref, gas_constant],
                        [(molar_mass_h2o / molar_mass_air) ** 0.25, (molar_mass_air / molar_mass_h2o) ** 0.25,
                         math.sqrt(8.0 * (1.0 + molar_mass_air / molar_mass_h2o)),
                         math.sqrt(8.0 * (1.0 + molar_mass_h2o / molar_mass_air))]])
    assert c.size == _SIZE
    return c


#: the functions the kernels call, by name: compiled with the first kernel (`compiled`)
_HELPERS: dict = {}


def _helper(fn):
    """A function the kernels call: plain Python until the first kernel is compiled, when `compiled`
    puts its compiled form in this module's namespace (numba resolves the kernels' globals then)."""
    _HELPERS[fn.__name__] = fn
    return fn


@_helper
def _transport_at(t, y, c):
    """(viscosity Pa s, conductivity W/(m K)) of humid air at t °C, Y kg/kg: Lemmon & Jacobsen (2004) Eqs. 2-5
    dilute air, IAPWS (2008) Eq. 11 / IAPWS (2011) Eq. 16 dilute vapour, Wilke (1950) mixing (Poling et al.
    (2001) Eqs. 9-5.13, 10-6.1)."""
    m_a, sigma, eps, tc, n1, n2, t2, n3, t3 = c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8]
    tk = t + 273.15
    lt = math.log(tk / eps)
    s = 0.0
    p = 1.0
    for j in range(5):
        s += c[_B + j] * p
        p *= lt
    mu_a = 1e-6 * 0.0266958 * math.sqrt(m_a * tk) / (sigma * sigma * math.exp(s))
    tau = tc / tk
    k_a = 1e-3 * (n1 * 1e6 * mu_a + n2 * tau ** t2 + n3 * tau ** t3)
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
    xa = 1.0 - y / (y + c[_RATIO])
    xw = 1.0 - xa
    f12 = 1.0 + math.sqrt(mu_a / mu_v) * c[_WILKE]
    f21 = 1.0 + math.sqrt(mu_v / mu_a) * c[_WILKE + 1]
    phi12 = f12 * f12 / c[_WILKE + 2]
    phi21 = f21 * f21 / c[_WILKE + 3]
    da = xa + xw * phi12
    dw = xw + xa * phi21
    return xa * mu_a / da + xw * mu_v / dw, xa * k_a / da + xw * k_v / dw


def _transport_loop(t, y, c, mu, k):
    """`_transport_at` over flat arrays."""
    for i in range(t.size):
        mu[i], k[i] = _transport_at(t[i], y[i], c)


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


@_helper
def _humid_heat_at(t, y, c):
    """Humid heat c_pa + Y c_pv of humid air at t °C, J/(kg dry air K) (NASA polynomials)."""
    tk = t + 273.15
    cpa = 0.0
    for s in range(3):
        cpa += c[_WAIR + s] * (_cp_molar(c, s, tk) / c[_MSP + s])
    return cpa + y * (_cp_molar(c, 3, tk) / c[_MW])


@_helper
def _air_enthalpy_at(tk, c):
    """Dry-air enthalpy above 0 °C at tk K, J/kg (NASA polynomials)."""
    ha = 0.0
    for s in range(3):
        ha += c[_WAIR + s] * ((_h_molar(c, s, tk) - c[_HREF + s]) / c[_MSP + s])
    return ha


@_helper
def _vapour_enthalpy_at(tk, c):
    """Vapour enthalpy above liquid water at 0.01 °C at tk K, J/kg (NASA polynomial and the latent heat)."""
    return c[_LAT] + (_h_molar(c, 3, tk) - c[_HREF + 3]) / c[_MW]


def _heat_loop(t, y, c, humid_heat, air_enthalpy, vapour_enthalpy):
    """Humid heat c_pa + Y c_pv (J/(kg dry air K)), the dry-air enthalpy above 0 °C and the vapour
    enthalpy above liquid water at 0.01 °C (J/kg) at t °C (flat arrays)."""
    for i in range(t.size):
        tk = t[i] + 273.15
        air_enthalpy[i] = _air_enthalpy_at(tk, c)
        vapour_enthalpy[i] = _vapour_enthalpy_at(tk, c)
        humid_heat[i] = _humid_heat_at(t[i], y[i], c)


@_helper
def _wsgg_at(tt, h, co, length, c):
    """Smith, Shen & Friedman (1982) WSGG emissivity at tt K of a gas with H2O and CO2 partial pressures
    h, co (atm) over the path ``length`` (m), interpolated in the CO2 fraction between the anchor sets
    (`rotarydryer.thermal.radiation._emissivity`); c: per anchor set its CO2 fraction, then
    kappa_1..3 and b_ij (i = 1..3, j = 1..4) (`pack_wsgg`)."""
    pa = h + co
    fc = co / pa if pa > 0 else 0.0
    k = 0
    while k < 2 and fc >= c[16 * (k + 1)]:
        k += 1
    lo = c[16 * k]
    hi = c[16 * (k + 1)]
    if not (fc >= lo and (fc < hi or (k == 2 and fc <= hi))):
        return 0.0
    w = (fc - lo) / (hi - lo)
    v = 0.0
    for side in range(2):
        a = 16 * (k + side)
        p = h if k + side == 0 else (co if k + side == 3 else pa)
        pl = p * length
        eps = 0.0
        for g in range(3):
            b = a + 4 + 4 * g
            weight = c[b] + tt * (c[b + 1] + tt * (c[b + 2] + tt * c[b + 3]))
            eps = eps + max(weight, 0.0) * (1.0 - math.exp(-c[a + 1 + g] * pl))
        v += (1.0 - w) * eps if side == 0 else w * eps
    return min(max(v, 0.0), 1.0)


def _wsgg_loop(t, ph, pc, length, c, out):
    """`_wsgg_at` over flat arrays."""
    for i in range(t.size):
        out[i] = _wsgg_at(t[i], ph[i], pc[i], length[i], c)


def pack_wsgg(anchors):
    """WSGG coefficients for `_wsgg_loop`: per anchor set (in the order of their CO2 fractions)
    ``(co2_fraction, (kappa_1..3), ((b_1j), (b_2j), (b_3j)))``."""
    rows = []
    for fc, kappa, b in anchors:
        rows.append(np.concatenate([[fc], np.asarray(kappa, float), np.asarray(b, float).ravel()]))
    c = np.concatenate(rows)
    assert c.size == 16 * len(anchors) == 64
    return c


@_helper
def _psat_at(x, c):
    """Wagner & Pruss (1993) Eq. 2.5 saturation pressure over liquid water (x >= 273.16 K), IAPWS R14-08
    (2011) Eq. 6 sublimation pressure below, Pa, at x K (`rotarydryer.properties.water._saturation_pressure`);
    c: Tc, pc, Tt, pt, a_1..6, their exponents, then the ice a_1..3 and b_1..3 (`pack_psat`)."""
    tc, pc, tt, pt = c[0], c[1], c[2], c[3]
    if x >= tt:
        tau = 1.0 - x / tc
        f = 0.0
        for j in range(6):
            f = f + c[4 + j] * tau ** c[10 + j]
        return pc * math.exp(tc / x * f)
    theta = x / tt
    f = 0.0
    for j in range(3):
        f = f + c[16 + j] * theta ** c[19 + j]
    return pt * math.exp(f / theta)


def _psat_loop(t, c, out):
    """`_psat_at` over flat arrays."""
    for i in range(t.size):
        out[i] = _psat_at(t[i], c)


def pack_psat(tc, pc, tt, pt, a, exponents, ice_a, ice_b):
    """Coefficients of `_psat_loop`."""
    c = np.concatenate([[tc, pc, tt, pt], a, exponents, ice_a, ice_b]).astype(float)
    assert c.size == 22
    return c


@_helper
def _diffusivity_at(x, p_atm, switch_k, blend_k):
    """Marrero & Mason (1972) water-vapour diffusivity in air, m2/s, at x K and p atm, the two power laws
    blended over switch_k +- blend_k (`rotarydryer.properties.humid_air._water_vapour_diffusivity`)."""
    low = 1.87e-10 * x ** 2.072
    high = 2.75e-9 * x ** 1.632
    s = min(max((x - (switch_k - blend_k)) / (2.0 * blend_k), 0.0), 1.0)
    if s <= 0.0:
        v = low
    elif s >= 1.0:
        v = high
    else:
        v = low + s ** 3 * (s * (6.0 * s - 15.0) + 10.0) * (high - low)
    return v / p_atm


def _diffusivity_loop(t, p_atm, switch_k, blend_k, out):
    """`_diffusivity_at` over flat arrays."""
    for i in range(t.size):
        out[i] = _diffusivity_at(t[i], p_atm[i], switch_k, blend_k)


# ----------------------------------------------------------------------------------------------------
# the shell-loss network of rotarydryer.thermal.shell.shell_heat_loss (kept in this module: numba's disk
# cache tracks the file of a compiled function, not the files of the functions it calls)
#: layout of the shell parameters (pack_shell)
_SH_TA, _SH_PC, _SH_RI, _SH_RO, _SH_ROUT, _SH_REXP, _SH_DSC, _SH_KSC, _SH_DINS, _SH_KINS = range(10)
_SH_EI, _SH_EO, _SH_WIND, _SH_YA, _SH_P, _SH_K0, _SH_K1, _SH_SIGMA, _SH_G, _SH_BEAM, _SH_XTOL = range(10, 21)


def pack_shell(ambient_c, co2_partial_atm, inner_radius, outer_radius, outside_radius, exposed_radius,
               scale_thickness, scale_conductivity, insulation_thickness, insulation_conductivity, inner_emissivity,
               outer_emissivity, wind_speed, ambient_humidity, pressure, steel_k0, steel_k1, sigma, gravity,
               beam_length, xtol):
    """Parameters of `_shell_loop` (one drum and its surroundings), in the order of the ``_SH_`` offsets."""
    return np.array([ambient_c, co2_partial_atm, inner_radius, outer_radius, outside_radius, exposed_radius,
                     scale_thickness, scale_conductivity, insulation_thickness, insulation_conductivity,
                     inner_emissivity, outer_emissivity, wind_speed, ambient_humidity, pressure, steel_k0, steel_k1,
                     sigma, gravity, beam_length, xtol], dtype=float)


@_helper
def _shell_outside(to, q, c):
    """Outside flux W/m2 at outer surface temperature ``to``: natural convection on a horizontal
    cylinder (Churchill & Chu 1975; Ajayi (2011) Eq. 6.54) with film properties, optional cross-wind
    (Churchill & Bernstein 1977, Nu^3 = Nu_N^3 + Nu_F^3), radiation to ambient (Ajayi Eq. 6.55)."""
    ta = q[_SH_TA]
    ya = q[_SH_YA]
    d_out = 2 * q[_SH_ROUT]
    film = 0.5 * (to + ta)
    rho = q[_SH_P] * c[_MA] * (1.0 + ya) / (c[_R] * (film + 273.15) * (1.0 + ya / c[_RATIO]))
    mu, k = _transport_at(film, ya, c)
    nu_air = mu / rho
    alpha = k / (rho * (_humid_heat_at(film, ya, c) / (1.0 + ya)))
    pr = nu_air / alpha
    beta = 1.0 / (film + 273.15)
    ra = q[_SH_G] * beta * max(to - ta, 0.0) * d_out ** 3 / (nu_air * alpha)
    nu = (0.60 + 0.387 * ra ** (1.0 / 6.0) / (1.0 + (0.559 / pr) ** (9.0 / 16.0)) ** (8.0 / 27.0)) ** 2
    if q[_SH_WIND] > 0:
        re = q[_SH_WIND] * d_out / nu_air
        nu_f = 0.3 + 0.62 * re ** 0.5 * pr ** (1 / 3) / (1 + (0.4 / pr) ** (2 / 3)) ** 0.25 * (
            1 + (re / 282000.0) ** (5 / 8)) ** (4 / 5)
        nu = (nu ** 3 + nu_f ** 3) ** (1 / 3)
    h_o = nu * k / d_out
    return h_o * (to - ta) + q[_SH_EO] * q[_SH_SIGMA] * ((to + 273.15) ** 4 - (ta + 273.15) ** 4)


@_helper
def _shell_inner(to, tg, q, c, cond):
    """(inner surface temperature, outside loss W per metre) at outer temperature ``to``: conduction
    ln(r2/r1)/(2 pi k) per layer, the steel's k = k0 - k1 T at the mean steel temperature (3 passes);
    ``cond``: (ln(r_o/r_i) of the steel, the scale's and the insulation's resistance), `_shell_layers`."""
    qp = _shell_outside(to, q, c) * 2 * math.pi * q[_SH_ROUT]
    twi = to
    for _ in range(3):
        t_steel = 0.5 * (min(max(twi, to), max(tg, to)) + to)
        rc = cond[0] / (2 * math.pi * (q[_SH_K0] - q[_SH_K1] * t_steel))
        if q[_SH_DSC] > 0:
            rc = rc + cond[1]
        if q[_SH_DINS] > 0:
            rc = rc + cond[2]
        twi = to + qp * rc
    return twi, qp


@_helper
def _shell_layers(q):
    """What `_shell_inner` needs of the drum's layers, computed once per solve."""
    r_sc = math.log(q[_SH_RI] / q[_SH_REXP]) / (2 * math.pi * q[_SH_KSC]) if q[_SH_DSC] > 0 else 0.0
    r_ins = math.log(q[_SH_ROUT] / q[_SH_RO]) / (2 * math.pi * q[_SH_KINS]) if q[_SH_DINS] > 0 else 0.0
    return math.log(q[_SH_RO] / q[_SH_RI]), r_sc, r_ins


@_helper
def _shell_inside(twi, tg, y, st, mu, k_g, eg, ph, q, c, w):
    """Inside flux W/m2 at inner surface temperature ``twi``: Sieder & Tate (1936) convection (Ajayi
    (2011) Eq. 6.52; ``st`` = 0.027 Re^0.8 Pr^(1/3) of the gas) and gas-wall radiation with Hottel's
    effective wall emissivity (WSGG absorptivity)."""
    twi_c = min(max(twi, 0.0), 600.0)
    mu_s = _transport_at(twi_c, y, c)[0]
    h_c = st * (mu / mu_s) ** 0.14 * k_g / (2 * q[_SH_REXP])
    ag = _wsgg_at(twi_c + 273.15, ph, q[_SH_PC], q[_SH_BEAM], w)
    tgk = tg + 273.15
    q_r = q[_SH_SIGMA] * 0.5 * (q[_SH_EI] + 1.0) * (eg * tgk ** 4 - ag * (twi + 273.15) ** 4)
    return h_c * (tg - twi) + q_r


@_helper
def _shell_balance(to, tg, y, st, mu, k_g, eg, ph, q, c, w, cond):
    """(inside minus outside flow W per metre, inner surface temperature, inside flow W per metre, outside
    flow W per metre) at outer temperature ``to``."""
    twi, qp_out = _shell_inner(to, tg, q, c, cond)
    qp_in = _shell_inside(min(twi, tg), tg, y, st, mu, k_g, eg, ph, q, c, w) * 2 * math.pi * q[_SH_REXP]
    return qp_in - qp_out, twi, qp_in, qp_out


@_helper
def _shell_residual(to, tg, y, st, mu, k_g, eg, ph, q, c, w, cond):
    return _shell_balance(to, tg, y, st, mu, k_g, eg, ph, q, c, w, cond)[0]


def _shell_loop(tg, mg, seg, y, guess, slope_guess, q, c, w, loss, outer, slope_out):
    """Shell heat loss (W per segment) and outer surface temperature (°C) per element, the outer
    temperature the root of inside = outside flux per metre (`rotarydryer.thermal.shell.shell_heat_loss`):
    Newton's method from ``guess`` (NaN: none) until a step is below the tolerance (12 steps at most; each
    element on its own, so one more evaluation costs little), else the Illinois iteration of
    `rotarydryer.thermal._roots.illinois` on [ambient, gas]. The first slope is ``slope_guess`` (the
    last slope of a previous solve, ``slope_out``; NaN: a forward difference), then the secant through the
    last two iterates. False if an element is not finite or its gas is below ambient (the caller then
    takes the checked NumPy path)."""
    ta = q[_SH_TA]
    xtol = q[_SH_XTOL]
    r_exp = q[_SH_REXP]
    cond = _shell_layers(q)
    for i in range(tg.size):
        t = tg[i]
        yy = y[i]
        if not (t >= ta and math.isfinite(t) and math.isfinite(yy) and math.isfinite(mg[i])):
            return False
        # gas-side properties at the gas temperature
        rho = q[_SH_P] * c[_MA] * (1.0 + yy) / (c[_R] * (t + 273.15) * (1.0 + yy / c[_RATIO]))
        mu, k_g = _transport_at(t, yy, c)
        pr = _humid_heat_at(t, yy, c) / (1.0 + yy) * mu / k_g
        velocity = mg[i] / (rho * math.pi * r_exp ** 2)
        re_in = velocity * (2 * r_exp) * rho / mu
        st = 0.027 * re_in ** 0.8 * pr ** (1.0 / 3.0)
        ph = yy / (yy + c[_RATIO]) * q[_SH_P] / 101325.0
        eg = _wsgg_at(t + 273.15, ph, q[_SH_PC], q[_SH_BEAM], w)
        lo = ta
        hi = t
        root = math.nan
        twi0, qin0, qout0 = math.inf, 0.0, 0.0      # the flows of Newton's last evaluation
        slope_out[i] = math.nan
        g = guess[i]
        if math.isfinite(g):            # Newton's method from the guess
            x = min(max(g, lo), hi)
            # the first slope by a forward difference, then the secant through the last two iterates
            # (one evaluation per step; superlinear, as the difference Newton's method it replaces)
            f0, twi0, qin0, qout0 = _shell_balance(x, t, yy, st, mu, k_g, eg, ph, q, c, w, cond)
            slope = slope_guess[i]      # the last slope of the previous solve, or a forward difference
            if not (math.isfinite(slope) and slope != 0):
                f1 = _shell_residual(x + 1e-3, t, yy, st, mu, k_g, eg, ph, q, c, w, cond)
                slope = (f1 - f0) / 1e-3
            for _ in range(12):
                if not (math.isfinite(f0) and math.isfinite(slope) and slope != 0):
                    break
                x_new = min(max(x - f0 / slope, lo), hi)
                if abs(x_new - x) < xtol:       # a step below the tolerance (no contraction estimate:
                    root = x_new                # near the convection kink at ambient it can stop early)
                    slope_out[i] = slope
                    break
                f_new, twi0, qin0, qout0 = _shell_balance(x_new, t, yy, st, mu, k_g, eg, ph, q, c, w, cond)
                slope = (f_new - f0) / (x_new - x)
                x, f0 = x_new, f_new
        if not math.isfinite(root):     # the bracketed root (Illinois)
            a, b = lo, hi
            fa = _shell_residual(a, t, yy, st, mu, k_g, eg, ph, q, c, w, cond)
            fb = _shell_residual(b, t, yy, st, mu, k_g, eg, ph, q, c, w, cond)
            x = a if fa == 0 else b
            done = fa == 0 or fb == 0
            side = 0
            for _ in range(100):
                if done:
                    break
                denom = fb - fa
                x_new = (a * fb - b * fa) / denom if denom != 0 else 0.5 * (a + b)
                if not math.isfinite(x_new) or x_new < min(a, b) or x_new > max(a, b):
                    x_new = 0.5 * (a + b)
                x_prev = x
                x = x_new
                fx = _shell_residual(x, t, yy, st, mu, k_g, eg, ph, q, c, w, cond)
                if np.sign(fx) == np.sign(fa):
                    if side == 1:
                        fb = 0.5 * fb
                    a = x
                    fa = fx
                    side = 1
                else:
                    if side == -1:
                        fa = 0.5 * fa
                    b = x
                    fb = fx
                    side = -1
                done = fx == 0 or abs(b - a) < xtol or abs(x - x_prev) < 0.1 * xtol
            root = 0.5 * (a + b) if abs(b - a) < xtol else x
            twi0 = math.inf
        if twi0 <= t:       # Newton's last evaluation, less than the tolerance from the root: its flows
            qp_in, qp_out = qin0, qout0
        else:
            twi, qp_out = _shell_inner(root, t, q, c, cond)
            qp_in = _shell_inside(twi, t, yy, st, mu, k_g, eg, ph, q, c, w) * 2 * math.pi * r_exp
        loss[i] = 0.5 * (qp_in + qp_out) * seg[i]
        outer[i] = root
        if not (math.isfinite(loss[i]) and math.isfinite(root)):
            return False
    return True


#: half-width (K) of the rounded corner where the solids temperature of the surface-evaporation model meets its
#: ceiling (rotarydryer.thermal.balances.solids_temperature_ceiling)
CEILING_BLEND_K = 1.0


@_helper
def _soft_ceiling(t, top):
    """min(t, top) with its corner rounded over top -/+ CEILING_BLEND_K by the parabola with both slopes: t up to
    top - CEILING_BLEND_K, top from top + CEILING_BLEND_K (the evaporation's slope in the solids temperature,
    steep near the boiling point, falls to zero over 2 K instead of at once)."""
    d = CEILING_BLEND_K
    if t <= top - d:
        return t
    if t >= top + d:
        return top
    e = t - top + d
    return t - e * e / (4.0 * d)


# ----------------------------------------------------------------------------------------------------
# gas -> solids transfer of a set of gas stages (rotarydryer.thermal.balances._stage_transfer, physical mode)
_TR_RADIUS, _TR_P, _TR_PC, _TR_BEAM, _TR_ES, _TR_GUARD, _TR_SIGMA, _TR_METHOD, _TR_XE, _TR_XCR, _TR_EXP = range(11)
_TR_DSWITCH, _TR_DBLEND, _TR_TSMAX = 11, 12, 13
#: drying-kinetics methods of the kernel (DryingKinetics.method)
KINETICS_CODES = {"ajayi2011": 0.0, "constant_falling": 1.0, "characteristic_curve": 2.0}


def pack_transfer(radius, pressure, co2_partial_atm, beam_length, solids_emissivity, dry_guard, sigma, method,
                  equilibrium_moisture, critical_moisture, exponent, diffusivity_switch_k, diffusivity_blend_k,
                  solids_ceiling=99.0):
    """Parameters of `_transfer_loop`, in the order of the ``_TR_`` offsets (``method``: a key of
    `KINETICS_CODES`; ``solids_ceiling``: the solids temperature's clip, degC,
    `rotarydryer.thermal.balances.solids_temperature_ceiling`)."""
    return np.array([radius, pressure, co2_partial_atm, beam_length, solids_emissivity, dry_guard, sigma,
                     KINETICS_CODES[method], equilibrium_moisture, critical_moisture, exponent, diffusivity_switch_k,
                     diffusivity_blend_k, solids_ceiling], dtype=float)


@_helper
def _transfer_at(a, x_raw, ts_raw, tg_raw, y_raw, fg, dp, q, curve_x, curve_y, c, w, ps):
    """Evaporation (kg/s), convective and radiative heat (W) from the gas to the solids of one stage:
    Nu = 0.33 Re^0.6 (Ajayi (2011) Eq. 6.41), Chilton-Colburn mass transfer on the concentration basis
    with the Stefan (high-flux) correction and Wagner-Pruss saturation at the solids surface (Ajayi
    (2011) Eq. 6.32-6.49 in this package's consistent form), the falling-rate factor of the kinetics,
    grey gas-solids radiation with the WSGG emissivity: (True, R_w, Q_conv, Q_rad), or (False, 0, 0, 0)
    where the solids boil (the caller then takes the checked NumPy path, which names it)."""
    radius, p, sigma = q[_TR_RADIUS], q[_TR_P], q[_TR_SIGMA]
    method = q[_TR_METHOD]
    xe, xcr = q[_TR_XE], q[_TR_XCR]
    tg = min(max(tg_raw, -40.0), 600.0)   # humid_air.T_MIN_C, T_MAX_C
    ts = _soft_ceiling(max(ts_raw, 0.0), q[_TR_TSMAX])
    y = min(max(y_raw, 1e-6), 1.0)    # humid_air.Y_MAX
    # gas-solids coefficient at the gas temperature
    mu, k = _transport_at(tg, y, c)
    re = fg / (math.pi * radius ** 2) * dp / mu
    hc = 0.33 * re ** 0.6 * k / dp
    x = max(x_raw, 0.0)
    # mass transfer coefficient (film properties), concentration basis
    film = 0.5 * (tg + ts)
    cp = _humid_heat_at(film, y, c) / (1.0 + y)
    mu_f, k_f = _transport_at(film, y, c)
    pr = cp * mu_f / k_f
    rho_f = p * c[_MA] * (1.0 + y) / (c[_R] * (film + 273.15) * (1.0 + y / c[_RATIO]))
    sc = mu_f / (rho_f * _diffusivity_at(film + 273.15, p / 101325.0, q[_TR_DSWITCH], q[_TR_DBLEND]))
    lewis = (pr / sc) ** (2.0 / 3.0)
    xw = y / (y + c[_RATIO])
    m_g = (1 - xw) * c[_MA] + xw * c[_MW]
    hm = hc / cp * lewis / (p * m_g / c[_MW])
    pw = _psat_at(ts + 273.15, ps)
    pv = xw * p
    drive = pw - pv
    if pw >= p:
        return False, 0.0, 0.0, 0.0
    if abs(drive) < 1e-9 * p:
        flux = hm * drive * (p / (p - pv))
    else:
        flux = hm * drive * (math.log((p - pv) / (p - pw)) * p / drive)
    # falling-rate factor, continued linearly below the equilibrium moisture
    if method == 0.0:
        f = 1.0
    else:
        u = (x - xe) / (xcr - xe)
        phi = min(max(u, 0.0), 1.0)
        if method == 2.0 and curve_x.size:
            f = np.interp(phi, curve_x, curve_y)
        else:
            f = phi ** (1.0 if method == 1.0 else q[_TR_EXP])
        if u < 0.0:
            f = f + u
    rate = a * (f * flux if flux > 0 else flux)
    rw = rate * min(max(x / q[_TR_GUARD], 0.0), 1.0)
    qc = hc * a * (tg - ts_raw)
    tgk = tg + 273.15
    tsk = ts_raw + 273.15
    eg = min(max(_wsgg_at(tg + 273.15, pv / 101325.0, q[_TR_PC], q[_TR_BEAM], w), 1e-6), 1.0)
    qr = sigma * a * (tgk ** 4 - tsk ** 4) / (1.0 / q[_TR_ES] + 1.0 / eg - 1.0)
    return True, rw, qc, qr


def _transfer_loop(a, x_raw, ts_raw, tg_raw, y_raw, fg, dp, q, curve_x, curve_y, c, w, ps, rw, qc, qr):
    """`_transfer_at` over flat arrays: False where the solids of a stage boil (the caller then takes
    the checked NumPy path, which names it)."""
    for i in range(a.size):
        ok, r, h, e = _transfer_at(a[i], x_raw[i], ts_raw[i], tg_raw[i], y_raw[i], fg[i], dp[i], q, curve_x, curve_y,
                                   c, w, ps)
        if not ok:
            return False
        rw[i] = r
        qc[i] = h
        qr[i] = e
    return True


# ----------------------------------------------------------------------------------------------------
# the cell balance of a dryer of one size class (rotarydryer.thermal.dryer.ThermalDryer._rhs, physical mode)
_CB_NT, _CB_NG, _CB_ENTRY, _CB_FS, _CB_FW, _CB_FH, _CB_CPS, _CB_CPW, _CB_SFLOOR, _CB_TTOP = range(10)
_CB_SMOOTH, _CB_RHOP, _CB_FD, _CB_CE0, _CB_YMAX, _CB_BASE, _CB_KILN, _CB_R, _CB_R2 = range(10, 19)
#: the gas enthalpy's humidity step of the derivative dh/dY (ThermalDryer._rhs)
CB_DY = 1e-4


def pack_cells(n_tanks, n_gas, entry, feed_solids, feed_water, feed_enthalpy, cp_solids, cp_water, solids_floor,
               solids_ceiling, smoothing, particle_density, dry_gas_flow, empty_heat_capacity, y_max, use_base, kiln,
               radius):
    """Parameters of `_cell_balance_loop`, in the order of the ``_CB_`` offsets."""
    return np.array([n_tanks, n_gas, entry, feed_solids, feed_water, feed_enthalpy, cp_solids, cp_water, solids_floor,
                     solids_ceiling, smoothing, particle_density, dry_gas_flow, empty_heat_capacity, y_max,
                     1.0 if use_base else 0.0, 1.0 if kiln else 0.0, radius, radius**2], dtype=float)


@_helper
def _bed_area_at(holdup, rho, length, radius, r2, area_factor, particle_density, seg, theta_grid):
    """Gas-exposed area of a rolling bed's active layer, m^2: 3 theta_AL L_c rho_b dz / rho_p with the chord L_c of
    the bed surface (Ajayi (2011) Eq. 6.56-6.61; `rotarydryer.thermal.balances.active_layer_area`)."""
    mass = max(holdup, 0.0)
    fill = min(max(mass / (rho * length * math.pi * r2), 0.0), 1.0)
    angle = np.interp(fill, seg, theta_grid)
    chord = 2.0 * radius * math.sin(angle / 2.0)
    return 3.0 * area_factor * chord * rho * length / particle_density


def _cell_balance_loop(z, k, cap, a_bed, kiln_des, kiln_rho, qloss, y_in, h_in, src, dst, ce_edge, ce_excess, gas_tank,
                       tank_stage, gas_up, is_bed, kiln_tank, kiln_stage, dp, theta, holdup, gas_len, seg, theta_grid, p,
                       q, curve_x, curve_y, c, w, ps, base, dz, rec):
    """Time derivatives of the states ``z`` (rows) of a dryer of one size class: the wet-solids flows of the
    network's edges (coefficients ``k`` and design loads ``cap`` of each row from the section laws, the cap
    min(M, M_des) smoothed), the solids, water and enthalpy balances of the tanks (Ajayi (2011) Eq. 6.1-6.4,
    6.8-6.11), the gas-solids transfer of each gas stage (`_transfer_at`; curtain area Eq. 6.63, the rolling beds'
    areas ``a_bed`` given, the kiln beds' from the passive solids above the design load ``kiln_des`` of the passive
    tank ``kiln_tank`` of each kiln stage ``kiln_stage``, at bulk density ``kiln_rho``), and the gas balances of the stages in plug flow with their
    shell loss ``qloss`` (Eq. 6.50-6.55) and inlet gas (``y_in``, ``h_in`` per row): the same equations and the
    same operations as the NumPy form (`rotarydryer.thermal.dryer.ThermalDryer._rhs`), per state.

    ``base``: the last single state's transfer inputs and outputs per stage (area, X, T_s, T_g, Y, R_w, Q_conv,
    Q_rad), the vapour enthalpy at the solids temperature and the gas enthalpies and humid heat (h, h at Y + CB_DY,
    c_s), each reused where a row's inputs equal them (p[_CB_BASE]); ``rec``: those of row 0. False where the solids
    of a stage boil (the NumPy form names it)."""
    nt = int(p[_CB_NT])
    ng = int(p[_CB_NG])
    entry = int(p[_CB_ENTRY])
    cps = p[_CB_CPS]
    cpw = p[_CB_CPW]
    sfloor = p[_CB_SFLOOR]
    ttop = p[_CB_TTOP]
    smooth = p[_CB_SMOOTH]
    rhop = p[_CB_RHOP]
    fd = p[_CB_FD]
    ce0 = p[_CB_CE0]
    ymax = p[_CB_YMAX]
    use_base = p[_CB_BASE] != 0.0
    kiln = p[_CB_KILN] != 0.0
    radius = p[_CB_R]
    r2 = p[_CB_R2]
    kiln_smooth = max(smooth, 1e-3)
    nk = kiln_tank.size
    a_kiln = np.empty(ng)
    ne = src.size
    nce = ce_edge.size
    rows = z.shape[0]
    # the smoothed cap where any width is non-zero (the NumPy form's test over the whole call), else the minimum
    smoothed = False
    if smooth != 0.0:
        for r in range(rows):
            for j in range(nce):
                if cap[r, j] != 0.0:
                    smoothed = True
    S = np.empty(nt)
    W = np.empty(nt)
    T = np.empty(nt)
    m = np.empty(nt)
    b = np.empty(ne)
    in_s = np.empty(nt)
    in_w = np.empty(nt)
    in_h = np.empty(nt)
    out_s = np.empty(nt)
    out_w = np.empty(nt)
    out_h = np.empty(nt)
    rw_t = np.empty(nt)
    qh_t = np.empty(nt)
    rw = np.empty(ng)
    qc = np.empty(ng)
    qr = np.empty(ng)
    hv = np.empty(ng)
    h = np.empty(ng)
    hw = np.empty(ng)
    cs = np.empty(ng)
    for r in range(rows):
        for i in range(nt):
            S[i] = max(z[r, i], sfloor)
            W[i] = max(z[r, nt + i], 0.0)
            T[i] = min(max(z[r, 2 * nt + i], -20.0), ttop)
            m[i] = S[i] + W[i]
            in_s[i] = 0.0
            in_w[i] = 0.0
            in_h[i] = 0.0
            out_s[i] = 0.0
            out_w[i] = 0.0
            out_h[i] = 0.0
            rw_t[i] = 0.0
            qh_t[i] = 0.0
        # the edges' flows: the coefficient times the source's mass, or its part up to / above the design load
        for e in range(ne):
            b[e] = m[src[e]]
        for j in range(nce):
            e = ce_edge[j]
            ms = m[src[e]]
            cj = cap[r, j]
            if smoothed:
                eps = smooth * cj
                sm = 0.5 * (ms + cj - math.sqrt((ms - cj) * (ms - cj) + eps * eps))
            else:
                sm = min(ms, cj)
            b[e] = ms - sm if ce_excess[j] != 0 else sm
        for e in range(ne):
            t = src[e]
            ms = m[t]
            f = (k[r, e] * b[e]) * (ms / max(ms, 1e-300))
            ms2 = max(ms, 1e-12)
            fs = S[t] / ms2
            fw = W[t] / ms2
            fh = (cps * fs + cpw * fw) * T[t]
            out_s[t] += f * fs
            out_w[t] += f * fw
            out_h[t] += f * fh
            d = dst[e]
            if d >= 0:
                in_s[d] += f * fs
                in_w[d] += f * fw
                in_h[d] += f * fh
        if kiln:
            for i in range(ng):
                a_kiln[i] = 0.0
            for j in range(nk):
                mp = m[kiln_tank[j]]
                des = kiln_des[r, j]
                eps = kiln_smooth * max(des, 1e-9)
                sm = 0.5 * (mp + des - math.sqrt((mp - des) * (mp - des) + eps * eps))
                st = kiln_stage[j]
                a_kiln[st] += _bed_area_at(max(mp - sm, 0.0), kiln_rho[r, j], gas_len[st], radius, r2, theta[st], rhop,
                                           seg, theta_grid)
        in_s[entry] += p[_CB_FS]
        in_w[entry] += p[_CB_FW]
        in_h[entry] += p[_CB_FH]
        # the gas-solids transfer of each stage
        for i in range(ng):
            t = gas_tank[i]
            x = W[t] / max(S[t], 1e-12)
            if is_bed[i] != 0:
                area = a_bed[r, i]
            else:
                area = theta[i] * max(m[t], 0.0) * 3.0 / (dp[i] * rhop)
            if kiln:
                area = area + a_kiln[i]
            tg_raw = z[r, 3 * nt + i]
            y_raw = z[r, 3 * nt + ng + i]
            yc = min(max(y_raw, 0.0), ymax)
            if (use_base and area == base[0, i] and x == base[1, i] and T[t] == base[2, i] and tg_raw == base[3, i]
                    and y_raw == base[4, i]):
                rw[i] = base[5, i]
                qc[i] = base[6, i]
                qr[i] = base[7, i]
            else:
                ok, rw[i], qc[i], qr[i] = _transfer_at(area, x, T[t], tg_raw, y_raw, fd * (1.0 + yc), dp[i], q,
                                                       curve_x, curve_y, c, w, ps)
                if not ok:
                    return False
            if use_base and T[t] == base[2, i]:
                hv[i] = base[8, i]
            else:
                hv[i] = _vapour_enthalpy_at(min(max(T[t], -40.0), 600.0) + 273.15, c)
            if rows == 1:
                rec[0, i] = area
                rec[1, i] = x
                rec[2, i] = T[t]
                rec[3, i] = tg_raw
                rec[4, i] = y_raw
                rec[5, i] = rw[i]
                rec[6, i] = qc[i]
                rec[7, i] = qr[i]
                rec[8, i] = hv[i]
            rw_t[t] = rw[i]
            qh_t[t] = qc[i] + qr[i] - rw[i] * hv[i]
        # the solids tanks: dry solids, water and the temperature from the enthalpy balance
        for i in range(nt):
            ds = in_s[i] - out_s[i]
            dw = in_w[i] - out_w[i] - rw_t[i]
            du = in_h[i] - out_h[i] + qh_t[i]
            cap_h = S[i] * cps + W[i] * cpw
            u = cap_h / ce0
            ce = ce0 / (1.0 + u * u)
            cap_h = cap_h + ce
            tg_near = z[r, 3 * nt + tank_stage[i]]
            dz[r, i] = ds
            dz[r, nt + i] = dw
            dz[r, 2 * nt + i] = (du - T[i] * (cps * ds + cpw * dw) + ce * (tg_near - T[i])) / cap_h
        # the gas stages: enthalpy (extended linearly outside the property range) and humidity balances
        for i in range(ng):
            tg_raw = z[r, 3 * nt + i]
            y_raw = z[r, 3 * nt + ng + i]
            if use_base and tg_raw == base[3, i] and y_raw == base[4, i]:
                h[i] = base[9, i]
                hw[i] = base[10, i]
                cs[i] = base[11, i]
            else:
                tg = min(max(tg_raw, -40.0), 600.0)
                tk = tg + 273.15
                air = _air_enthalpy_at(tk, c)
                vap = _vapour_enthalpy_at(tk, c)
                yc = min(max(y_raw, 0.0), ymax)
                yw = min(max(y_raw + CB_DY, 0.0), ymax)
                h[i] = air + yc * vap + (tg_raw - tg) * (1150.0 + 2200.0 * yc)
                hw[i] = air + yw * vap + (tg_raw - tg) * (1150.0 + 2200.0 * yw)
                cs[i] = _humid_heat_at(tg, yc, c)
            if rows == 1:
                rec[9, i] = h[i]
                rec[10, i] = hw[i]
                rec[11, i] = cs[i]
        for i in range(ng):
            tg_raw = z[r, 3 * nt + i]
            y_raw = z[r, 3 * nt + ng + i]
            up = gas_up[i]
            if up >= 0:
                y_up = z[r, 3 * nt + ng + up]
                h_up = h[up]
            else:
                y_up = y_in[r]
                h_up = h_in[r]
            dym = fd * (y_up - y_raw) + rw[i]
            dh = fd * (h_up - h[i]) + rw[i] * hv[i] - qc[i] - qr[i] - qloss[r, i]
            dhdy = (hw[i] - h[i]) / CB_DY
            dy = dym / holdup[i]
            dz[r, 3 * nt + i] = (dh / holdup[i] - dhdy * dy) / cs[i]
            dz[r, 3 * nt + ng + i] = dy
    return True


@_helper
def _nmax(a, b):
    """``np.maximum`` of two floats: a NaN either side gives NaN, a tie the second (NumPy's -0.0 / 0.0)."""
    return a if (a > b or a != a) else b


@_helper
def _nmin(a, b):
    """``np.minimum`` of two floats: a NaN either side gives NaN, a tie the second."""
    return a if (a < b or a != a) else b


def _step_norm_loop(f, z, sc, p, out):
    """The steady-state test's scaled residual max |f_i|/scale_i at state ``z``
    (`rotarydryer.thermal.dryer.ThermalDryer._residual_norm`): ``p`` = (tanks x classes k, c_p solids, c_p water,
    heat-capacity floor), the temperature rows 2k..3k weighted by min(1, max(S c_p + W c_pw, 0) / floor); a NaN
    anywhere gives NaN (as ``np.max``)."""
    k = int(p[0])
    cp, cpw, floor = p[1], p[2], p[3]
    best = -1.0
    for i in range(f.size):
        r = abs(f[i]) / sc[i]
        if 2 * k <= i < 3 * k:
            j = i - 2 * k
            r *= _nmin(1.0, _nmax(z[j] * cp + z[k + j] * cpw, 0.0) / floor)
        if r != r:
            out[0] = r
            return True
        if r > best:
            best = r
    out[0] = best
    return True


def _step_radius_loop(dz, sc, p, out, big):
    """``dz`` times radius / b in ``out`` and b = max |dz_i| / sc_i over i >= k in ``big`` (NaN if one is, as
    ``np.max``), ``p`` = (k, radius): `rotarydryer.thermal.dryer.ThermalDryer._radius_step` (``out`` written
    only where b exceeds the radius)."""
    k, radius = int(p[0]), p[1]
    b = -1.0
    for i in range(k, dz.size):
        r = abs(dz[i]) / sc[i]
        if r != r:
            b = r
            break
        if r > b:
            b = r
    big[0] = b
    if b > radius:
        factor = radius / b
        for i in range(dz.size):
            out[i] = dz[i] * factor
    return True


def _step_bounded_loop(z, dz, p, zn):
    """``z + dz`` kept inside the admissible states by the fraction-to-boundary rule
    (`rotarydryer.thermal.dryer.ThermalDryer._bounded_step`, the same operations element by element): ``p`` =
    (tanks x classes k, gas stages, solids T low, high, gas T low, high, humidity high, the water's margin below
    zero)."""
    k, ng = int(p[0]), int(p[1])
    lo_t, hi_t, lo_g, hi_g, hi_y, w_margin = p[2], p[3], p[4], p[5], p[6], p[7]
    for i in range(zn.size):
        zn[i] = z[i] + dz[i]
    for i in range(k):
        zn[i] = _nmax(zn[i], 0.2 * z[i])
        w = z[k + i]
        zn[k + i] = _nmax(zn[k + i], _nmin(0.2 * w, w) - w_margin)
        t = z[2 * k + i]
        v = _nmax(zn[2 * k + i], _nmin(lo_t + 0.2 * (t - lo_t), t))
        zn[2 * k + i] = _nmin(v, _nmax(hi_t - 0.2 * (hi_t - t), t))
    for i in range(ng):
        t = z[3 * k + i]
        v = _nmax(zn[3 * k + i], _nmin(lo_g + 0.2 * (t - lo_g), t))
        zn[3 * k + i] = _nmin(v, _nmax(hi_g - 0.2 * (hi_g - t), t))
        y = z[3 * k + ng + i]
        v = _nmax(zn[3 * k + ng + i], 0.0)
        zn[3 * k + ng + i] = _nmin(v, _nmax(hi_y - 0.2 * (hi_y - y), y))
    return True


def _step_admissible_loop(z, p, out):
    """1.0 where ``z`` is an admissible state (`rotarydryer.thermal.dryer.ThermalDryer._admissible`), else 0.0 (a
    NaN is not): ``p`` = (k, gas stages, solids T low, high, gas T low, high, humidity high, the water's floor)."""
    k, ng = int(p[0]), int(p[1])
    lo_t, hi_t, lo_g, hi_g, hi_y, w_floor = p[2], p[3], p[4], p[5], p[6], p[7]
    out[0] = 0.0
    for i in range(k):
        if not (z[i] > 0.0 and z[k + i] > w_floor and z[2 * k + i] > lo_t and z[2 * k + i] < hi_t):
            return True
    for i in range(ng):
        t, y = z[3 * k + i], z[3 * k + ng + i]
        if not (t > lo_g and t < hi_g and y > -1e-6 and y < hi_y):
            return True
    out[0] = 1.0
    return True


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


def evaluate(name, inputs, params, n_out):
    """Kernel ``name`` elementwise over ``inputs`` (broadcast to one shape, `flat`) with the
    scalars or coefficient arrays ``params``: its ``n_out`` results in that shape, or None (kernels
    off, numba failed, or the kernel declined its inputs: the caller takes its NumPy path). The
    kernels' arguments are the flat inputs, then ``params``, then the output arrays."""
    if compiled(name) is None:
        return None
    shape, flat_inputs = flat(*inputs)
    outs = [np.empty(flat_inputs[0].size) for _ in range(n_out)]
    if not call(name, *flat_inputs, *params, *outs):
        return None
    return shaped(shape, *outs)


_LOOPS = {"transport": _transport_loop, "heat": _heat_loop, "wsgg": _wsgg_loop, "psat": _psat_loop,
          "diffusivity": _diffusivity_loop, "shell": _shell_loop, "transfer": _transfer_loop,
          "cells": _cell_balance_loop, "step_norm": _step_norm_loop, "step_bounded": _step_bounded_loop,
          "step_admissible": _step_admissible_loop, "step_radius": _step_radius_loop}
#: each kernel's argument kinds (`rotarydryer._aot`: ``a`` a float array, ``o`` an output array, ``f`` a float)
_KINDS = {"transport": "aaaoo", "heat": "aaaooo", "wsgg": "aaaaao", "psat": "aao", "diffusivity": "aaffo",
          "shell": "aaaaaaaaaooo", "transfer": "aaaaaaaaaaaaaooo",
          "cells": "mmmmmmmaannnnnnnnnnaaaaaaaaaaaaamMM", "step_norm": "aaaao", "step_bounded": "aaao",
          "step_admissible": "aao", "step_radius": "aaaoo"}
#: what the ahead-of-time module compiles (`rotarydryer._aot`)
AOT_KERNELS = {name: (fn, _KINDS[name]) for name, fn in _LOOPS.items()}
_compiled: dict = {}
_HELPERS_COMPILED: list = []


def compiled(name):
    """The compiled kernel ``name`` (a key of ``_LOOPS``), or None when compiled kernels are off."""
    if not _jit.enabled():
        return None
    fn = _compiled.get(name)
    if fn is None:
        fn = _jit.aot(name, _KINDS[name])     # the ahead-of-time module's, once built
        if fn is not None:
            _compiled[name] = fn
            return fn
        if not _HELPERS_COMPILED:   # the helpers first: the kernels' globals must be compiled functions
            for helper, py in _HELPERS.items():
                globals()[helper] = _jit.kernel(py) or py
            _HELPERS_COMPILED.append(True)
        fn = _jit.kernel(_LOOPS[name])
        if fn is None:
            return None
        _compiled[name] = fn
    return fn


def call(name, *args):
    """Run kernel ``name`` on ``args``: False (and, if numba failed, the kernels off with a warning) when
    it did not give its results, else True."""
    fn = compiled(name)
    if fn is None:
        return False
    try:
        ok = fn(*args)
    except Exception as exc:     # a numba that cannot compile here: the NumPy references instead
        _jit.disable(f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}")
        return False
    return ok is not False
