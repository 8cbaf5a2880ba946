r"""Drying-rate kinetics of a material, selectable per material (the unhindered evaporation flux
and the falling-rate period); the gas-solids coefficients and Song's (2003) pilot Ua estimates
are in [`rotarydryer.thermal.drying`][rotarydryer.thermal.drying].

Unhindered (surface-saturated) evaporation flux - Ajayi (2011) Eqs. 6.32-6.49
---------------------------------------------------------------------------

$$
R_w = h_m A_s (P_w(T_s) - P_v),\qquad
h_m = \frac{h_c}{c_{p,g}}\Big(\frac{Pr}{Sc}\Big)^{2/3}\frac{1}{P_{ref}}
$$

(Eq. 6.47 with Eq. 6.48 substituted: St v_g ρ_g = h_c/c_p, so velocity and density
cancel). What $P_{ref}$ is decides the physics (notes ajayi_energy.md §1.8, §5.12
item 11):

``basis="ajayi2011"``
:   $P_{ref} = P_v$, the vapour partial pressure in the gas, as printed in
    Eq. 6.46-6.47 and coded (``hm = (rho_g/Pw_air) St v_g (Pr/Sc)^(2/3)``). The rate
    is then ∝ (P_w/P_v - 1) and diverges for dry gas (y_w → 0): kept only to
    reproduce the thesis; raises for P_v = 0.

``basis="concentration"`` (default, physically consistent)
:   Chilton-Colburn for the vapour concentration: flux = k_c (ρ_v,s - ρ_v,∞) with
    $k_c = h_c/(\rho c_p)\,(Pr/Sc)^{2/3}$ and ρ_v = p M_w/(R T) at the film
    temperature, i.e. $P_{ref} = P\,M_g/M_w$ (Bird, Stewart & Lightfoot 2002
    §22.3; Incropera et al. 2007 Eq. 6.92). With ``high_flux=True`` (default) the
    stagnant-film (Stefan) correction multiplies the flux by
    $\ln[(P-p_{v})/(P-p_{w})]\,P/(p_w - p_v)$ (Bird et al. 2002 Eq. 22.8-22).

``basis="total_pressure"``
:   $P_{ref} = P$: Eq. 6.47 read with the total pressure (a common textbook
    slip; differs from the consistent form by M_w/M_g = 0.62).

Moisture dependence (selectable per material)
---------------------------------------------
``"ajayi2011"``: none - the thesis uses the unhindered rate everywhere (no critical
moisture, no sorption isotherm; Sec. 6.1.1.4).
``"constant_falling"``: constant rate above the critical moisture X_cr, linear falling
rate to the equilibrium moisture X_e (Mujumdar 2006, Handbook of Industrial Drying ch. 1;
Song 2003 §3.4 describes the periods qualitatively).
``"characteristic_curve"``: van Meel (1958) / Keey (1992) characteristic drying curve
$f(\Phi) = \Phi^n$, $\Phi = (X - X_e)/(X_{cr} - X_e)$ clipped to [0, 1], or
a tabulated curve ``curve=(Phi_points, f_points)`` interpolated linearly.
``"thin_layer"``: a thin-layer law fitted to lab drying curves (Lewis, Page, Henderson-Pabis,
logarithmic, two-term, Midilli with Arrhenius rate constants;
[`rotarydryer.properties.thin_layer`][rotarydryer.properties.thin_layer], ``rotarydryer lab drying``), below.

Thin-layer laws in the dryer
----------------------------
The law gives the drying rate per kg of dry solid, $r = -dX/dt$ (kg water/(kg dry solid s)), at
the local moisture and the **gas** temperature (the lab's air temperature; the equivalent-time
form of [`thin_layer.drying_rate`][rotarydryer.properties.thin_layer.drying_rate]). The dryer asks
for an evaporation rate from a gas-contact area A (curtains: $A = \theta\,m\,3/(d_p\rho_p)$,
Ajayi (2011) Eq. 6.63, m the wet mass), so the law becomes a flux per unit of that area,

$$
N_{law} = r\,\frac{\rho_p d_p}{3(1 + X)}
$$

(``solids_per_area`` $= \rho_p d_p/3$, kg of wet solids per m² of contact area, from the
material's particle density and diameter): a curtain with area factor θ = 1 then dries at the
lab's rate per kg, $R_w = A N_{law} = \theta\,S\,r$ (S dry solids). The rate is the smaller
of the law and the unhindered (external, heat-and-mass-transfer-limited) flux,

$$
R_w = A\,\min(N_w, N_{law})\quad(N_w > 0),
$$

so the law holds where the solids control the rate (the falling-rate regime that thin-layer
tests measure) and the gas-side transfer caps it where the law asks for more than the gas can
supply (the start of a law with n < 1, whose rate is infinite at t = 0). Assumptions: the
particles are the lab's size (``particle_diameter`` of the material; a section with another
diameter changes its area, and so its rate per kg, in proportion to d_p,material/d_p,section),
the law's temperature is the local gas temperature, and the lab's air velocity and humidity do
not matter (a thin-layer law has no such terms). Solids in the passive phase do not dry, as
with every kinetics of this module (no contact area).

Moisture in these kinetics is on a **dry basis** X (kg water/kg dry solid); Ajayi's
x_w is wet basis - convert with [`dry_basis`][rotarydryer.properties.drying.dry_basis] / [`wet_basis`][rotarydryer.properties.drying.wet_basis].

Condensation (P_w < P_v) gives a negative rate; ``condensation="allow"`` (default)
returns it, ``"zero"`` clips, ``"raise"`` raises ``ValueError`` ("gas too cold to dry").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import check_choice, check_positive, check_range
from . import humid_air as ha
from . import thin_layer as tl
from . import water

__all__ = [
    "dry_basis",
    "wet_basis",
    "mass_transfer_coefficient",
    "unhindered_drying_flux",
    "falling_rate_factor",
    "DryingKinetics",
    "MATERIAL_KINETICS",
    "drying_rate",
    "check_gas_can_dry",
    "ajayi2011_drying_rate_as_coded",
    "MOISTURE_METHODS",
    "BASES",
    "AJAYI_PRESSURE",
]

MOISTURE_METHODS = ("ajayi2011", "constant_falling", "characteristic_curve", "thin_layer")
#: kelvin at 0 degC
_KELVIN = 273.15
BASES = ("concentration", "ajayi2011", "total_pressure")
AJAYI_PRESSURE = 101045.0  # Pa, Ajayi code L3186


def dry_basis(wet_moisture):
    """Dry-basis moisture X = x/(1-x), kg/kg dry solid, from wet basis x (kg/kg wet solid)."""
    x = check_range("wet_moisture", wet_moisture, 0.0, 1.0, low_inclusive=True, unit="kg/kg wet")
    return x / (1.0 - x)


def wet_basis(dry_moisture):
    """Wet-basis moisture x = X/(1+X) from dry basis X."""
    x = check_range("dry_moisture", dry_moisture, 0.0, np.inf, low_inclusive=True, unit="kg/kg dry")
    return x / (1.0 + x)


def mass_transfer_coefficient(heat_transfer_coefficient, gas_temperature_c, gas_humidity, solids_temperature_c=None,
                              pressure=101325.0, basis: str = "concentration", gas_heat_capacity=None,
                              prandtl=None, schmidt=None):
    r"""Chilton-Colburn mass-transfer coefficient h_m, kg/(m² s Pa); Ajayi (2011) Eqs. 6.45-6.49.

    Parameters
    ----------
    heat_transfer_coefficient : array_like
        Gas-solids h_c, W/(m² K) (e.g. Ajayi's Nu = 0.33 Re^0.6 via
        [`rotarydryer.correlations.heat_transfer.heat_transfer_coefficient`][rotarydryer.correlations.heat_transfer.heat_transfer_coefficient]).
    gas_temperature_c, gas_humidity : array_like
        °C and kg/kg dry gas.
    solids_temperature_c : array_like, optional
        For the film temperature (default: gas temperature).
    basis : {"concentration", "ajayi2011", "total_pressure"}
    gas_heat_capacity, prandtl, schmidt : optional
        Override the property values (Ajayi: 1070 J/(kg K), Pr 0.7, Sc from D_AB = 2.65e-5).

    Examples
    --------
    >>> round(float(mass_transfer_coefficient(60.0, 300.0, 0.05)) * 1e8, 4)
    41.0345
    """
    hc, tg, y, ts, p, cp, pr, sc = _mass_transfer_inputs(heat_transfer_coefficient, gas_temperature_c, gas_humidity,
                                                         solids_temperature_c, pressure, basis, gas_heat_capacity,
                                                         prandtl, schmidt)
    return _mass_transfer_coefficient(hc, tg, y, ts, p, cp, pr, sc, basis)


def _mass_transfer_inputs(heat_transfer_coefficient, gas_temperature_c, gas_humidity, solids_temperature_c,
                          pressure, basis, gas_heat_capacity=None, prandtl=None, schmidt=None):
    """Checks of [`mass_transfer_coefficient`][rotarydryer.properties.drying.mass_transfer_coefficient]; returns (hc, tg, y, ts, p, cp, pr, sc) as arrays
    (ts, cp, pr, sc None when not given)."""
    check_choice("basis", basis, BASES)
    hc = check_range("heat_transfer_coefficient", heat_transfer_coefficient, 0.0, np.inf, low_inclusive=True,
                     unit="W/(m2 K)")
    tg = check_range("gas_temperature_c", gas_temperature_c, 0.0, 600.0, low_inclusive=True, high_inclusive=True,
                     unit="degC")
    y = check_range("gas_humidity", gas_humidity, 0.0, 0.3, low_inclusive=True, high_inclusive=True)
    p = check_range("pressure", pressure, 5e4, 2e5, low_inclusive=True, high_inclusive=True, unit="Pa")
    ts = None if solids_temperature_c is None else check_range("solids_temperature_c", solids_temperature_c, 0.0,
                                                               600.0, low_inclusive=True, unit="degC")
    cp = None if gas_heat_capacity is None else check_positive("gas_heat_capacity", gas_heat_capacity)
    pr = None if prandtl is None else check_positive("prandtl", prandtl)
    sc = None if schmidt is None else check_positive("schmidt", schmidt)
    return hc, tg, y, ts, p, cp, pr, sc


def _mass_transfer_coefficient(hc, tg, y, ts, p, cp, pr, sc, basis):
    """Unchecked kernel of [`mass_transfer_coefficient`][rotarydryer.properties.drying.mass_transfer_coefficient] (arguments as returned by its checks)."""
    film = 0.5 * (tg + (tg if ts is None else ts))
    # the film properties evaluated once (ha._prandtl_number and ha._schmidt_number would each
    # evaluate the mixture viscosity again): the same expressions, the same numbers
    cp_film = ha._heat_capacity(film, y) if cp is None or pr is None else None
    cp = cp_film if cp is None else cp
    if pr is None or sc is None:
        mu, k = ha._transport(film, y)
        if pr is None:
            pr = cp_film * mu / k
        if sc is None:
            sc = mu / (ha._density(film, y, p) * ha._water_vapour_diffusivity(film, p))
    lewis_term = (pr / sc) ** (2.0 / 3.0)
    if basis == "ajayi2011":
        pv = ha._vapour_partial_pressure(y, p)
        if np.any(pv <= 0):
            raise ValueError("basis='ajayi2011' divides by the gas vapour pressure (Ajayi Eq. 6.47): gas_humidity "
                             "must be > 0; use basis='concentration' for dry gas")
        p_ref = pv
    elif basis == "total_pressure":
        p_ref = p
    else:
        xw = ha._water_mole_fraction(y)
        m_g = (1 - xw) * ha.MOLAR_MASS_DRY_AIR + xw * water.MOLAR_MASS_WATER
        p_ref = p * m_g / water.MOLAR_MASS_WATER
    return hc / cp * lewis_term / p_ref


def unhindered_drying_flux(heat_transfer_coefficient, solids_temperature_c, gas_temperature_c, gas_humidity,
                           pressure=101325.0, basis: str = "concentration", saturation_method: str = "wagner_pruss",
                           high_flux: bool = True, condensation: str = "allow", **property_overrides):
    """Evaporation flux from a wet (saturated) surface, kg/(m² s); Ajayi (2011) Eq. 6.32 per unit area.

    ``saturation_method`` selects P_w(T_s): ``"wagner_pruss"`` or Ajayi's Antoine
    ``"antoine_ajayi2011"`` (Eq. 6.33). ``high_flux`` applies the Stefan correction (only
    with ``basis="concentration"``).

    >>> round(float(unhindered_drying_flux(60.0, 50.0, 300.0, 0.05)) * 1e3, 4)
    2.2776
    """
    hc, ts, tg, y, p, cp, pr, sc = _drying_flux_inputs(heat_transfer_coefficient, solids_temperature_c,
                                                       gas_temperature_c, gas_humidity, pressure, basis,
                                                       saturation_method, condensation, **property_overrides)
    return _unhindered_drying_flux(hc, ts, tg, y, p, cp, pr, sc, basis, saturation_method, high_flux, condensation)


def _drying_flux_inputs(heat_transfer_coefficient, solids_temperature_c, gas_temperature_c, gas_humidity, pressure,
                        basis, saturation_method, condensation, gas_heat_capacity=None, prandtl=None,
                        schmidt=None) -> tuple[Any, ...]:
    """Checks of [`unhindered_drying_flux`][rotarydryer.properties.drying.unhindered_drying_flux]; returns (hc, ts, tg, y, p, cp, pr, sc) for the kernel."""
    check_choice("condensation", condensation, ("allow", "zero", "raise"))
    ts = check_range("solids_temperature_c", solids_temperature_c, 0.0, 150.0, low_inclusive=True,
                     high_inclusive=True, unit="degC")
    hc, tg, y, _, p, cp, pr, sc = _mass_transfer_inputs(heat_transfer_coefficient, gas_temperature_c, gas_humidity,
                                                        ts, pressure, basis, gas_heat_capacity, prandtl, schmidt)
    check_choice("method", saturation_method, water.SATURATION_METHODS)
    return hc, ts, tg, y, p, cp, pr, sc


def _unhindered_drying_flux(hc, ts, tg, y, p, cp, pr, sc, basis, saturation_method, high_flux, condensation):
    """Unchecked kernel of [`unhindered_drying_flux`][rotarydryer.properties.drying.unhindered_drying_flux] (arguments as returned by its checks)."""
    hm = _mass_transfer_coefficient(hc, tg, y, ts, p, cp, pr, sc, basis)
    pw = water._saturation_pressure(ts, saturation_method)
    pv = ha._vapour_partial_pressure(y, p)
    drive = pw - pv
    if basis == "concentration" and high_flux:
        if np.any(pw >= p):
            raise ValueError("solids_temperature_c is at or above the boiling point at this pressure: the "
                             "surface-evaporation model does not apply (boiling)")
        close = np.abs(drive) < 1e-9 * p
        ratio = np.where(close, 1.0, np.log((p - pv) / (p - pw)) * p / np.where(close, 1.0, drive))
        flux = hm * drive * np.where(close, p / (p - pv), ratio)
    else:
        flux = hm * drive
    if condensation == "zero":
        flux = np.maximum(flux, 0.0)
    elif condensation == "raise" and np.any(flux < 0):
        raise ValueError("gas too cold to dry: the gas vapour pressure exceeds the vapour pressure at the solids "
                         f"surface (max excess {float(np.max(-drive)):.4g} Pa) - water would condense")
    return flux


def falling_rate_factor(moisture, critical_moisture, equilibrium_moisture=0.0, exponent=1.0, curve=None):
    """Characteristic drying curve f(Φ), Φ = (X - X_e)/(X_cr - X_e) clipped to [0, 1] (van Meel 1958).

    ``exponent`` n gives f = Φ^n (n = 1: linear falling rate); ``curve=(phi, f)`` a tabulated
    curve (Φ increasing from 0 to 1, f from 0 to 1). Moisture on a dry basis.

    >>> float(falling_rate_factor(0.05, 0.10, 0.02))
    0.375
    """
    x = check_range("moisture", moisture, 0.0, np.inf, low_inclusive=True, unit="kg/kg dry")
    xe = check_range("equilibrium_moisture", equilibrium_moisture, 0.0, np.inf, low_inclusive=True)
    xcr = check_range("critical_moisture", critical_moisture, 0.0, np.inf, unit="kg/kg dry")
    if np.any(xcr <= xe):
        raise ValueError("critical_moisture must exceed equilibrium_moisture")
    phi = np.clip((x - xe) / (xcr - xe), 0.0, 1.0)
    if curve is not None:
        pts, vals = (np.asarray(c, float) for c in curve)
        if pts.ndim != 1 or pts.shape != vals.shape or np.any(np.diff(pts) <= 0) or pts[0] > 0 or pts[-1] < 1:
            raise ValueError("curve must be (phi, f) with phi strictly increasing and covering [0, 1]")
        check_range("curve f values", vals, 0.0, 1.0, low_inclusive=True, high_inclusive=True)
        return np.interp(phi, pts, vals)
    n = check_positive("exponent", exponent)
    return phi**n


@dataclass(frozen=True)
class DryingKinetics:
    """Drying kinetics of one material.

    ``method``: one of ``"ajayi2011"``, ``"constant_falling"``, ``"characteristic_curve"``,
    ``"thin_layer"``; ``critical_moisture``, ``equilibrium_moisture`` kg/kg dry (not needed for
    ajayi2011; thin_layer takes no critical moisture); ``exponent`` / ``curve`` for the
    characteristic curve; ``basis`` and ``saturation_method`` of the unhindered flux.

    Thin-layer laws (``method="thin_layer"``, module docstring): ``model`` (a law of
    [`thin_layer`][rotarydryer.properties.thin_layer]: ``"lewis"``, ``"page"``, ...), ``parameters`` ((name, value)
    pairs, the rate constants at ``reference_temperature_K``, time in s), ``activation_energy``
    J/mol, ``reference_temperature_K`` K, ``initial_moisture`` X_0 of the lab curves and
    ``equilibrium_moisture`` X_e, kg/kg dry, and ``solids_per_area`` ρ_p d_p/3, kg/m² (a
    material fills it from its particle density and diameter).

    Below the equilibrium moisture (Φ < 0) the rate of [`rate`][rotarydryer.properties.drying.DryingKinetics.rate] continues linearly in
    Φ = (X - X_e)/(X_cr - X_e): the solids take up water from an unsaturated gas at a rate that
    grows with their distance from equilibrium (sorption towards X_e). The rate is therefore
    continuous with a slope through X_e; a rate that stopped dead at X_e left the steady-state
    Newton iteration of a dryer whose product reaches equilibrium (long residence times) without a
    slope there, and it cycled. Steady states with X >= X_e (drying) are the same as with a rate
    clipped at zero. [`factor`][rotarydryer.properties.drying.DryingKinetics.factor] and [`falling_rate_factor`][rotarydryer.properties.drying.falling_rate_factor] stay the characteristic curve
    itself, in [0, 1].
    """

    method: str = "ajayi2011"
    critical_moisture: float | None = None
    equilibrium_moisture: float = 0.0
    exponent: float = 1.0
    curve: tuple | None = None
    basis: str = "concentration"
    saturation_method: str = "wagner_pruss"
    source: str = ""
    model: str = ""
    parameters: tuple = ()
    activation_energy: float = 0.0
    reference_temperature_K: float | None = None
    initial_moisture: float | None = None
    solids_per_area: float | None = None

    def __post_init__(self):
        check_choice("method", self.method, MOISTURE_METHODS)
        check_choice("basis", self.basis, BASES)
        check_choice("saturation_method", self.saturation_method, water.SATURATION_METHODS)
        if self.method == "thin_layer":
            self._check_thin_layer()
            return
        if self.method != "ajayi2011" and self.critical_moisture is None:
            raise ValueError(f"method={self.method!r} needs critical_moisture (kg/kg dry)")
        if self.method != "ajayi2011":      # the curve's checks once here: _rate evaluates it unchecked
            self.factor(np.array([0.0, float(self.critical_moisture)]))

    def _check_thin_layer(self):
        check_choice("model", self.model, tl.MODELS)
        try:
            pairs = dict(self.parameters)
        except (TypeError, ValueError):
            raise ValueError(f"parameters = {self.parameters!r} must be (name, value) pairs") from None
        law = tl.check_law(self.model, pairs)
        object.__setattr__(self, "parameters", tuple((k, law[k]) for k in tl.MODELS[self.model].parameters))
        check_range("activation_energy", self.activation_energy, 0.0, 1e6, low_inclusive=True, unit="J/mol")
        if self.reference_temperature_K is None:
            raise ValueError("method='thin_layer' needs reference_temperature_K (K, the temperature of the "
                             "rate constants)")
        check_range("reference_temperature_K", self.reference_temperature_K, 200.0, 1000.0, unit="K")
        check_range("equilibrium_moisture", self.equilibrium_moisture, 0.0, 10.0, low_inclusive=True,
                    unit="kg/kg dry")
        if self.initial_moisture is None:
            raise ValueError("method='thin_layer' needs initial_moisture (kg/kg dry, X_0 of the lab curves)")
        check_range("initial_moisture", self.initial_moisture, float(self.equilibrium_moisture), 10.0,
                    unit="kg/kg dry (above equilibrium_moisture)")
        if self.solids_per_area is None:
            raise ValueError("method='thin_layer' needs solids_per_area (kg/m2, rho_p d_p / 3; a material "
                             "sets it from its particle density and diameter)")
        check_range("solids_per_area", self.solids_per_area, 0.0, 1e4, unit="kg/m2")

    def law_rate(self, moisture, gas_temperature_c):
        """Thin-layer drying rate -dX/dt, kg water/(kg dry solid s), at dry-basis ``moisture`` in gas
        at ``gas_temperature_c`` (°C): the law alone, without the external-transfer cap of
        [`rate`][rotarydryer.properties.drying.DryingKinetics.rate] (``method="thin_layer"`` only)."""
        if self.method != "thin_layer":
            raise ValueError(f"law_rate needs method='thin_layer' (this kinetics is {self.method!r})")
        x = check_range("moisture", moisture, unit="kg/kg dry")
        tg = check_range("gas_temperature_c", gas_temperature_c, -_KELVIN, 2000.0, unit="degC")
        return self._law_rate(x, tg)

    def _law_rate(self, moisture, gas_temperature_c):
        """Unchecked [`law_rate`][rotarydryer.properties.drying.DryingKinetics.law_rate]."""
        p = tl._at_temperature(self.model, dict(self.parameters), np.asarray(gas_temperature_c, float) + _KELVIN,
                               self.activation_energy, self.reference_temperature_K)
        return tl._drying_rate(self.model, moisture, p, float(self.initial_moisture),
                               float(self.equilibrium_moisture))

    def factor(self, moisture):
        """Falling-rate factor (1 = unhindered) at dry-basis moisture (not for thin-layer laws,
        whose rate does not scale the unhindered flux: see
        [`law_rate`][rotarydryer.properties.drying.DryingKinetics.law_rate])."""
        if self.method == "thin_layer":
            raise ValueError("a thin-layer law has no falling-rate factor: its rate is the law capped by the "
                             "unhindered flux (DryingKinetics.rate, .law_rate)")
        if self.method == "ajayi2011":
            return np.ones_like(np.asarray(moisture, float))
        n = 1.0 if self.method == "constant_falling" else self.exponent
        curve = self.curve if self.method == "characteristic_curve" else None
        return falling_rate_factor(moisture, self.critical_moisture, self.equilibrium_moisture, n, curve)

    def rate(self, area, moisture, heat_transfer_coefficient, solids_temperature_c, gas_temperature_c,
             gas_humidity, pressure=101325.0, condensation="allow", **property_overrides):
        """Evaporation rate, kg/s, from ``area`` m² of solids at dry-basis ``moisture``."""
        a = check_range("area", area, 0.0, np.inf, low_inclusive=True, unit="m2")
        args = _drying_flux_inputs(heat_transfer_coefficient, solids_temperature_c, gas_temperature_c, gas_humidity,
                                   pressure, self.basis, self.saturation_method, condensation, **property_overrides)
        return self._rate(a, moisture, *args, condensation=condensation)

    def _rate(self, area, moisture, hc, ts, tg, y, p, cp=None, pr=None, sc=None, condensation="allow"):
        """Unchecked kernel of [`rate`][rotarydryer.properties.drying.DryingKinetics.rate] (area, hc, ts, tg, y, p validated arrays; ts 0-150 °C)."""
        flux = _unhindered_drying_flux(hc, ts, tg, y, p, cp, pr, sc, self.basis, self.saturation_method, True,
                                       condensation)
        if self.method == "thin_layer":
            x = np.asarray(moisture, dtype=float)
            law = self._law_rate(x, tg) * float(self.solids_per_area) / (1.0 + np.maximum(x, 0.0))
            return area * np.where(flux > 0, np.minimum(flux, law), flux)
        f = self._factor(moisture)
        return area * np.where(flux > 0, f * flux, flux)

    def _factor(self, moisture):
        """Unchecked [`factor`][rotarydryer.properties.drying.DryingKinetics.factor], continued linearly below the equilibrium moisture (class docstring)."""
        if self.method == "ajayi2011":
            return 1.0
        xe, xcr = self.equilibrium_moisture, self.critical_moisture
        u = (np.asarray(moisture, dtype=float) - xe) / (xcr - xe)
        phi = np.clip(u, 0.0, 1.0)
        if self.method == "characteristic_curve" and self.curve is not None:
            pts, vals = (np.asarray(c, float) for c in self.curve)
            f = np.interp(phi, pts, vals)
        else:
            f = phi ** (1.0 if self.method == "constant_falling" else self.exponent)
        return np.where(u < 0.0, f + u, f)


#: Kinetics per material. Ajayi's zinc concentrate: thesis form (no falling rate);
#: "zinc_concentrate_ajayi2011_thesis": the exact thesis mass-transfer basis and Antoine.
MATERIAL_KINETICS = {
    "zinc_concentrate_ajayi2011": DryingKinetics("ajayi2011", source="Ajayi (2011) Sec. 6.1.1.4, consistent basis"),
    "zinc_concentrate_ajayi2011_thesis": DryingKinetics("ajayi2011", basis="ajayi2011",
                                                        saturation_method="antoine_ajayi2011",
                                                        source="Ajayi (2011) Eqs. 6.32-6.49 as coded"),
}


def drying_rate(area, moisture, heat_transfer_coefficient, solids_temperature_c, gas_temperature_c, gas_humidity,
                material="zinc_concentrate_ajayi2011", kinetics: DryingKinetics | None = None, **kwargs):
    """Evaporation rate, kg/s, with the kinetics registered for ``material`` (or given ``kinetics``).

    >>> round(float(drying_rate(10.0, 0.19, 60.0, 50.0, 300.0, 0.05)) * 1e3, 3)
    22.776
    """
    if kinetics is None:
        check_choice("material", material, MATERIAL_KINETICS)
        kinetics = MATERIAL_KINETICS[material]
    return kinetics.rate(area, moisture, heat_transfer_coefficient, solids_temperature_c, gas_temperature_c,
                         gas_humidity, **kwargs)


def ajayi2011_drying_rate_as_coded(area, heat_transfer_coefficient, solids_temperature_c, gas_temperature_c,
                                   gas_mass_fraction, pressure=AJAYI_PRESSURE):
    r"""Evaporation rate, kg/s, exactly as Ajayi's gPROMS ``Active_Phase`` model (App. F L3911-L4010).

    ``Rw = hm*Area*(Pw_s - Pw_air)``, ``Pw_s = exp(23.56143 - 4030.182/(Ta + 235))``,
    ``Pw_air = H*P*(26/18)``, ``hm = (rho_g/Pw_air)*St*v_g*(Pr/Sc)^(2/3)`` with
    ``St = hc/(Cp_air*rho_g*v_g)`` (so v_g cancels), Cp_air = 1070, Pr = 0.7,
    ``Sc = mu_g/(rho_g*da)``, da = 2.65e-5 m²/s, ρ_g and μ_g from his air polynomials at the
    gas temperature; P = 101045 Pa (sections B-E; 101325 in A). ``gas_mass_fraction`` is
    his H (kg water/kg wet gas). Compatibility only: see the module docstring.

    >>> round(float(ajayi2011_drying_rate_as_coded(1.0, 70.0, 50.0, 300.0, 0.03)) * 1e3, 4)
    64.3803
    """
    a = check_range("area", area, 0.0, np.inf, low_inclusive=True, unit="m2")
    hc = check_range("heat_transfer_coefficient", heat_transfer_coefficient, 0.0, np.inf, low_inclusive=True)
    ts = check_range("solids_temperature_c", solids_temperature_c, 0.0, 150.0, low_inclusive=True, unit="degC")
    tg = check_range("gas_temperature_c", gas_temperature_c, 0.0, 600.0, low_inclusive=True, unit="degC")
    h = check_range("gas_mass_fraction", gas_mass_fraction, 0.0, 0.5, unit="kg/kg wet gas (must be > 0: Ajayi's "
                    "h_m divides by the vapour pressure)")
    p = check_positive("pressure", pressure, unit="Pa")
    rho, mu, _ = ha._ajayi_air(tg)
    sc = mu / (rho * 2.65e-5)
    pw_air = h * p * (26.0 / 18.0)
    hm = hc / 1070.0 * (0.7 / sc) ** (2.0 / 3.0) / pw_air
    pw_s = np.exp(23.56143 - 4030.182 / (ts + 235.0))
    return hm * a * (pw_s - pw_air)


def check_gas_can_dry(gas_temperature_c, gas_humidity, pressure=101325.0):
    """Raise ``ValueError`` if the gas cannot dry wet solids: its wet-bulb temperature must exceed
    its dew point, i.e. relative humidity < 1 (a saturated gas at the wet bulb evaporates nothing).

    Returns the wet-bulb temperature (°C), the steady surface temperature of unhindered drying.
    """
    rh = ha.relative_humidity(gas_temperature_c, gas_humidity, pressure)
    if np.any(rh >= 1.0):
        i = int(np.argmax(rh))
        raise ValueError(f"gas too cold to dry: relative humidity {float(np.ravel(rh)[i]):.3f} >= 1 at "
                         f"{float(np.ravel(np.broadcast_to(gas_temperature_c, rh.shape))[i]):g} degC")
    return ha.wet_bulb_temperature(gas_temperature_c, gas_humidity, pressure)
