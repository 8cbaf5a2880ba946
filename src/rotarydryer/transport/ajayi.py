r"""Ajayi (2011) Ch. 5: multi-section transport model of the MMG Karumba dryer.

Sections in series (co-current, feed and gas enter at A; Ajayi (2011) Fig. 5.1):
A (unflighted, chains) -> B, C, D (flighted, own flight geometry each) -> mixing
cell -> E (unflighted) -> outlet.

* **Flighted sections** (Ajayi (2011) Eq. 5.1-5.3, 5.17-5.19; notes
  ajayi_transport.md Section 4.2): per cell a passive and an active tank;
  discharge P -> A at k_2 min(m_p, m_load) (Eq. 5.17-5.18, design-load cap);
  active outflow k_3 m_a split into forward C_F to the next passive tank and
  return (1 - C_F) to the same passive tank, C_F = maf_h sin(theta)/dl (Ajayi's
  code; no drag: particles 6-18 mm); kilning P_i -> P_{i+1} at k_4 m_p with
  k_4 = u_s/dl on the *whole* passive mass (Eq. 5.19, "kilning velocity" u_s).
  Coefficients depend on the cell's loading through the geometry model.
* **Unflighted sections** (Eq. 5.4-5.14): axially dispersed plug flow
  dm/dt = D m'' - u_s m' (m = kg/m), discretised conservatively by finite
  volumes: face flux u_s m - D dm/dz with central differencing of advection when
  the cell Peclet number u dz/D <= 2 (second order, non-negative coefficients) and
  upwind otherwise; outlet face advective only (Ajayi's D m'' = 0 at z = L and
  the Danckwerts dm/dz = 0 coincide here).  Inlet of the *first* section:

  - ``"ajayi"`` (default; Eq. 5.11-5.13 as coded): Dirichlet m(0) = F/u_s,
    x(0) = x_in; the half-cell dispersive flux 2D(m(0) - m_1)/dz is an open
    boundary, so tracer can diffuse back out of the inlet (recovery < 1,
    reported);
  - ``"danckwerts"``: closed inlet, the whole feed enters the first volume
    (flux condition u m - D m' = F), recovery exactly 1.

  A section fed by an upstream section (E after the mixing cell) always uses
  the flux inlet: with a Dirichlet value tied to an upstream flow the
  transient balance would create or destroy solids.
* **Mixing cell** (code l.5277-5335): no holdup; it joins the kilning outflow of
  D's last passive tank and the forward flow of its last active tank and feeds E.

Geometry per flighted section is injected (same interface as Lee's model):
[`AjayiRegressions`][rotarydryer.transport.ajayi.AjayiRegressions] (Ajayi's gPROMS regressions, per section) or the exact
``rotarydryer.geometry.FlightedDrum``.
"""

from __future__ import annotations

import math

import numpy as np

from .._limits import check_key
from .._validation import check_range, fmt_number
from ..geometry.lee2008_regressions import _poly_phi_f
from ..geometry.unloading import CascadeSummary
from ..properties.solids import SOLIDS
from .sections import SectionSpec, build_sections, unflighted_cells_auto

__all__ = ["AjayiRegressions", "mmg_moisture_profile", "mmg_test_moisture_profile", "unflighted_cells_auto",
           "ajayi2011"]

G = 9.81  # m/s^2, as in Ajayi's code (maf_h = 0.5*9.81*maft^2)


def mmg_moisture_profile(position, scale=1.0):
    r"""Solids moisture x_w (kg/kg wet) at axial position z (m), Ajayi (2011) Eq. 3.1:
    x_w = (0.1006 z + 2.218)/(z + 13.51), times ``scale`` (Ajayi "scaled" it to each
    test's inlet/outlet moisture by an unstated method; default 1 = unscaled)."""
    z = check_range("position", position, 0.0, math.inf, low_inclusive=True, unit="m")
    return scale * (0.1006 * z + 2.218) / (z + 13.51)


def mmg_test_moisture_profile(position, moisture_inlet, moisture_outlet, length=22.2):
    r"""Solids moisture x_w (kg/kg wet) at z (m) for one test: Ajayi (2011) Eq. 3.1 mapped affinely
    onto the test's inlet and product moisture (Tables 3.5-3.11),

    x_w(z) = x_out + (x_in - x_out) (p(z) - p(L)) / (p(0) - p(L)),  p = Eq. 3.1,

    so x_w(0) = x_in and x_w(L) = x_out with the measured shape in between (Ajayi "scaled" Eq. 3.1 to
    each test's inlet/outlet moisture, l.1669, by a method he does not give; this is one such map)."""
    z = check_range("position", position, 0.0, math.inf, low_inclusive=True, unit="m")
    L = float(check_range("length", length, 0.0, math.inf, unit="m"))
    x_in = check_range("moisture_inlet", moisture_inlet, 0.0, 1.0, unit="kg/kg wet")
    x_out = check_range("moisture_outlet", moisture_outlet, 0.0, 1.0, unit="kg/kg wet")
    p0, pL = mmg_moisture_profile(0.0), mmg_moisture_profile(L)
    return x_out + (x_in - x_out) * (mmg_moisture_profile(z) - pL) / (p0 - pL)


_ZINC = SOLIDS["zinc_concentrate_ajayi2011"]


def mmg_repose_angle(moisture):
    """Dynamic angle of repose (deg) of zinc concentrate, Ajayi (2011) Eq. 3.2: 419.6 x_w - 7.801.

    Unchecked (inner loops of the solvers); the checked, range-warning version is
    [`rotarydryer.properties.solids.repose_angle`][rotarydryer.properties.solids.repose_angle], from whose table the coefficients come."""
    a, b = _ZINC["repose"]
    return a * np.asarray(moisture, dtype=float) + b


def mmg_bulk_density(moisture):
    """Consolidated bulk density (kg/m^3), Ajayi (2011) Eq. 3.4 with the code's coefficients
    2043.81 - 3095.24 x_w (text: 2043.8 - 3095.2). Unchecked, as [`mmg_repose_angle`][rotarydryer.transport.ajayi.mmg_repose_angle]."""
    a, b = _ZINC["density_code"]
    return a + b * np.asarray(moisture, dtype=float)


class AjayiRegressions:
    r"""Ajayi (2011) per-section geometric regressions (Appendix F, gPROMS code).

    Fitted by Ajayi to Lee's Excel unloading model for one MMG flight section:

    * design load m_load = 1.24 rho_b dl A_s(phi) with the 6th-order Baker-area
      polynomial A_s (m^2; code l.4972-4974 etc.) and Ajayi's CFD factor 1.24
      (Ajayi (2011) Section 4.5, l.1498, 1667); [`design_load_area`][rotarydryer.transport.ajayi.AjayiRegressions.design_load_area] returns
      ``design_load_factor * A_s``;
    * mass-averaged fall time maft(phi, U) (s), U = 1 - load;
    * fall height maf_h = g maft^2 / 2 (m);
    * passive time t_pas = acos(1 - (maf_h cos(theta))^2/(2 R^2)) / omega (s), with
      the *drum* radius R as coded (Eq. 4.22 of the thesis writes R_F; the code is
      followed because it produced the published fits);
    * loading: Ajayi's code uses the dryer loading directly, load = min(m_p/m_load, 1),
      so [`loading_factor`][rotarydryer.transport.ajayi.AjayiRegressions.loading_factor] is min(d, 1).

    Parameters
    ----------
    area_coefficients : 7 floats, p0..p6 (m^2, phi in deg)
    fall_time_coefficients : 11 floats, q0..q10 (s)
    radius : float, drum radius R (m)
    design_load_factor : float, default 1.24
    """

    name = "ajayi2011_regressions"
    default_passive_time_branch = None

    def __init__(self, area_coefficients, fall_time_coefficients, radius, design_load_factor=1.24):
        self.p = tuple(float(x) for x in area_coefficients)
        self.q = tuple(float(x) for x in fall_time_coefficients)
        if len(self.p) != 7 or len(self.q) != 11:
            raise ValueError("AjayiRegressions needs 7 area (p0..p6) and 11 fall-time (q0..q10) coefficients")
        self.radius = float(check_range("drum.radius", radius, 0.0, math.inf, unit="m"))
        self.design_load_factor = float(check_key("geometry.design_load_factor", design_load_factor))

    def __repr__(self):
        return f"AjayiRegressions(radius={self.radius:g}, design_load_factor={self.design_load_factor:g})"

    def design_load_area(self, repose_angle):
        """design_load_factor * A_s(phi), m^2 (phi in deg)."""
        phi = _inside(repose_angle, 0.0, 90.0)
        if phi is None:
            phi = check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg")
        return self.design_load_factor * sum(c * phi**i for i, c in enumerate(self.p))

    def loading_factor(self, dryer_loading, repose_angle):
        """Ajayi's load = min(d_load, 1) (-)."""
        d = _inside(dryer_loading, 0.0, math.inf, low_inclusive=True)
        if d is None:
            d = check_range("dryer_loading", dryer_loading, 0.0, math.inf, low_inclusive=True)
        return np.minimum(d, 1.0) + 0.0 * np.asarray(repose_angle, dtype=float)

    def cascade(self, repose_angle, loading_factor=1.0, *, rpm, slope=0.0, passive_time_branch=None):
        """Cascade summary (deg, m, s, s); ``passive_time_branch`` is not used (Ajayi's acos form)."""
        phi = _inside(repose_angle, 0.0, 90.0)
        f = _inside(loading_factor, 0.0, 1.0, low_inclusive=True, high_inclusive=True)
        if phi is None or f is None or not (isinstance(rpm, (int, float)) and 0.0 < rpm < math.inf) \
                or not (isinstance(slope, (int, float)) and 0.0 <= slope < 45.0):   # the error messages
            phi = check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg")
            f = check_range("loading_factor", loading_factor, 0.0, 1.0, low_inclusive=True, high_inclusive=True)
            rpm = check_range("rpm", rpm, 0.0, math.inf, unit="rev/min")
            slope = check_range("slope", slope, 0.0, 45.0, low_inclusive=True, unit="deg")
        th = math.radians(float(slope))
        U = 1.0 - f
        t = _poly_phi_f(self.q, phi, U)  # same 11-term (phi, U) form as Lee's Eq. 4.24-4.25
        h = 0.5 * G * t**2
        arg = 1.0 - (h * math.cos(th)) ** 2 / (2.0 * self.radius**2)
        if np.any(arg < -1):
            raise ValueError(
                f"drum.radius = {fmt_number(self.radius)} m is too small for the Ajayi (2011) regressions: their "
                f"fall height {float(np.max(h)):.3g} m exceeds the drum diameter {2 * self.radius:.3g} m (they were "
                "fitted to the MMG drum, radius 1.95 m); use geometry.method = 'exact' for another drum")
        omega = rpm * 2.0 * math.pi / 60.0
        ang = np.arccos(arg)
        tp = ang / omega
        psi = 90.0 + np.degrees(ang) / 2.0
        psi, h, t, tp = (np.array(a, float) for a in np.broadcast_arrays(psi, h, t, tp))
        nan = np.full(psi.shape, np.nan)  # not given by the regressions (as Lee2008Regressions)
        return CascadeSummary(mean_release_angle=psi, mean_fall_height=h, mean_fall_time=t, passive_time=tp,
                              discharge_start_angle=nan, initial_holdup_area=nan)


def _inside(x, low, high, low_inclusive=False, high_inclusive=False):
    """``x`` as a float array when every value lies in the range (NaN does not), else None: the
    cheap test of the solvers' calls; the caller then calls ``check_range`` for the message."""
    a = np.asarray(x, dtype=float)
    ok = (a >= low if low_inclusive else a > low) & (a <= high if high_inclusive else a < high)
    return a if ok.all() else None


def _flighted_positions(sections):
    """Axial positions (m) of the flighted cells' centres of ``sections`` (dicts, flow order)."""
    pos, x0 = [], 0.0
    for s in sections:
        L = float(s["length"])
        if s["kind"] != "unflighted":
            N = int(s["n_cells"])
            pos.append(x0 + (np.arange(N) + 0.5) * L / N)
        x0 += L
    return np.concatenate(pos) if pos else np.zeros(0)


def _base_moisture(pos, sections, moisture_ends):
    """Unscaled moisture (kg/kg wet) at ``pos``: Eq. 3.1, or its map onto (x_in, x_out)."""
    if moisture_ends is None:
        return mmg_moisture_profile(pos, 1.0)
    length = sum(float(s["length"]) for s in sections)
    return mmg_test_moisture_profile(pos, moisture_ends[0], moisture_ends[1], length)


def eq31_moisture(pos, sections, moisture_ends=None):
    """Unscaled moisture (kg/kg wet) at ``pos`` (m) of a dryer of ``sections`` (dicts with
    ``length``): Ajayi (2011) Eq. 3.1, or its map onto ``moisture_ends`` = (x_in, x_out)."""
    return _base_moisture(pos, sections, moisture_ends)


def check_moisture_scale(scale, sections, material, moisture_ends=None, key="solids.moisture_scale"):
    """The Eq. 3.1 profile times ``scale`` inside the material's moisture range (message names ``key``)."""
    return _check_moisture_scale(scale, sections, material, moisture_ends, key=key)


def _check_moisture_scale(scale, sections, material, moisture_ends=None, key="solids.moisture_scale"):
    """``solids.moisture_scale`` must keep the Eq. 3.1 profile inside the material's moisture range
    (where its repose-angle and bulk-density laws hold): the message names the key, its value and
    the allowed range of the scale for this dryer."""
    s = float(check_key("transport.moisture_scale", scale, key))
    pos = _flighted_positions(sections)
    if pos.size == 0 or material is None:
        return
    base = _base_moisture(pos, sections, moisture_ends)
    lo, hi = material.wet_range()
    pmin, pmax = float(np.min(base)), float(np.max(base))
    if s * pmin >= lo - 1e-12 and s * pmax <= hi + 1e-12:
        return
    raise ValueError(
        f"{key} = {fmt_number(s)} puts the solids moisture (Ajayi (2011) Eq. 3.1"
        f"{'' if moisture_ends is None else ' mapped onto the test inlet/product moisture'} x "
        f"{fmt_number(s)}) at {s * pmin:.3g} to {s * pmax:.3g} kg/kg wet, outside the moisture range "
        f"[{lo:g}, {hi:g}] kg/kg wet of material '{material.name}' (its repose-angle and bulk-density laws "
        f"hold there only); the allowed range of {key} for this dryer is "
        f"[{lo / pmin:.3g}, {hi / pmax:.3g}]")


def _per_section(key, value, names, need, *, low_inclusive, unit):
    """``value`` (one number, or a dict section name -> number) as a dict over ``need`` (checked
    >= 0 or > 0; a dict must name every section of ``need`` and no unknown one)."""
    if isinstance(value, dict):
        unknown = sorted(set(value) - set(names))
        missing = [n for n in need if n not in value]
        if unknown or missing:
            raise ValueError(f"{key} = {value!r}: " + "; ".join(
                ([f"unknown section(s) {', '.join(map(repr, unknown))}"] if unknown else [])
                + ([f"missing section(s) {', '.join(map(repr, missing))}"] if missing else []))
                + f" (sections: {', '.join(names)})")
        return {n: float(check_range(f"{key} (section {n})", value[n], 0.0, math.inf, low_inclusive=low_inclusive,
                                     unit=unit)) for n in need}
    v = float(check_range(key, value, 0.0, math.inf, low_inclusive=low_inclusive, unit=unit))
    return {n: v for n in need}


def _recorded(value):
    """A model parameter as recorded in ``model.parameters``: the number, or a copy of the dict."""
    return {k: float(v) for k, v in value.items()} if isinstance(value, dict) else float(value)


def ajayi2011(*, sections, feed_rate, rpm, slope, radius, kiln_velocity, dispersion,
              geometries, material, moisture_scale=1.0, inlet="ajayi", unflighted_cells=None,
              tracer_input=None, gas_flow="co-current", name="ajayi2011", fouling=0.0, moisture_ends=None):
    r"""Build the Ajayi (2011) multi-section model.

    Parameters
    ----------
    sections : list of dict
        In flow order; each ``name``, ``kind`` ("flighted"/"unflighted"), ``length``
        (m) and for flighted ``n_cells``.
    feed_rate : float, kg/s (wet solids)
    rpm : float, rev/min; slope : float, deg; radius : float, drum radius m
    kiln_velocity : float or dict
        u_s (m/s): unflighted-bed velocity and kilning velocity of the flighted
        cells (Ajayi's code uses one value, Eq. 5.19); or a dict section name -> u_s
        (the predictive parameterisation, `rotarydryer.transport.ajayi_predictive`,
        gives each section its own).
    dispersion : float or dict
        Axial dispersion coefficient of the unflighted sections, m^2/s (>= 0); or a dict
        section name -> value (unflighted sections only).
    geometries : dict
        Section name -> cell geometry model (cascade / design_load_area / loading_factor).
    moisture_scale : float
        Factor on Eq. 3.1 (or on the test profile of ``moisture_ends``).
    moisture_ends : (float, float), optional
        Inlet and product moisture (kg/kg wet) of the test: the flighted cells' moisture is then
        [`mmg_test_moisture_profile`][rotarydryer.transport.ajayi.mmg_test_moisture_profile] (times ``moisture_scale``) instead of Eq. 3.1.
    inlet : {"ajayi", "danckwerts"}
        Inlet condition of a first unflighted section (module docstring).
    unflighted_cells : int, optional
        Finite volumes per unflighted section; default [`unflighted_cells_auto`][rotarydryer.transport.ajayi.unflighted_cells_auto].
    gas_flow : str
        Recorded only: Ajayi's model has no gas drag on the solids.
    fouling : float
        Fraction of the flights' loading capacity lost to scale (Ajayi (2011) Eq. 5.21; Test 3:
        0.8, l.1715): the design load is multiplied by (1 - fouling).
    material : Material
        Repose angle and bulk density versus moisture (the MMG case names the library's
        ``zinc_concentrate_ajayi2011``, Ajayi (2011) Eq. 3.2, 3.4).
    """

    F = float(check_range("operating.feed_rate", feed_rate, 0.0, math.inf, unit="kg/s"))
    rpm = float(check_range("operating.rpm", rpm, 0.0, math.inf, unit="rev/min"))
    theta = float(check_range("drum.slope", slope, 0.0, 45.0, low_inclusive=True, unit="deg"))
    names = [s["name"] for s in sections]
    u_of = _per_section("transport.kiln_velocity", kiln_velocity, names, names, low_inclusive=False, unit="m/s")
    D_of = _per_section("transport.dispersion", dispersion, names,
                        [s["name"] for s in sections if s["kind"] == "unflighted"], low_inclusive=True,
                        unit="m^2/s")
    if inlet not in ("ajayi", "danckwerts"):
        raise ValueError(f"transport.unflighted_inlet = {inlet!r} is not one of 'ajayi', 'danckwerts'")
    _check_moisture_scale(moisture_scale, sections, material, moisture_ends)
    specs = []
    x0 = 0.0
    for s in sections:
        L = float(s["length"])
        u = u_of[s["name"]]
        if s["kind"] == "unflighted":
            specs.append(SectionSpec(name=s["name"], kind="unflighted", length=L, n_cells=unflighted_cells,
                                     velocity=u, dispersion=D_of[s["name"]]))
        else:
            N = int(s["n_cells"])
            pos = x0 + (np.arange(N) + 0.5) * L / N
            specs.append(SectionSpec(name=s["name"], kind="flighted", length=L, n_cells=N,
                                     geometry=geometries[s["name"]], kilning="velocity", kiln_velocity=u,
                                     drag_reduction=1.0, backmix=0.0, loading="state", fouling=fouling,
                                     moisture=moisture_scale * _base_moisture(pos, sections, moisture_ends)))
        x0 += L
    params = dict(feed_rate=F, rpm=rpm, slope=theta, radius=radius, kiln_velocity=_recorded(kiln_velocity),
                  dispersion=_recorded(dispersion),
                  moisture_scale=moisture_scale, unflighted_inlet=inlet, gas_flow=gas_flow, fouling=fouling,
                  geometry={k: repr(v) for k, v in geometries.items()})
    if moisture_ends is not None:
        params["moisture_ends"] = [float(x) for x in moisture_ends]
    check_key("transport.fouling", fouling)
    model = build_sections(specs, material=material, feed_rate=F, rpm=rpm, slope=theta, inlet=inlet,
                           tracer_input=tracer_input, name=name, parameters=params)
    model.parameters["unflighted_cells"] = {s["name"]: s["n_cells"] for s in model.sections
                                            if s["kind"] == "unflighted"}
    ci = model.cell_info
    model.cell_info = {k: ci[k] for k in ("repose_angle_deg", "bulk_density_kg_m3", "moisture_kg_kg")}
    return model
