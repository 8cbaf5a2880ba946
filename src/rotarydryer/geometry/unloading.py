"""Cascade from the flights: release point, fall height and time, cycle times.

Mass averages are dH-weighted over the discharge *into the curtain*, i.e. from
the angle at which a flight starts to discharge into the airborne phase to the
angle psi5 at which it is empty (Lee (2008) Eq. 3.3 and 3.5; notes section 6.6):

* a design-loaded flight starts at its first-unloading-flight position
  (``convention="root"``: root at 90 deg; ``"tip"``: tip at 90 deg);
* an under-loaded flight (loading factor ``f < 1``) holds ``f * H0_des`` and
  starts where its maximum holdup falls to that value.

Fall-height definitions (Lee's two readings are incompatible, notes section 6.6):

``"chord"`` (default)
:   The particle falls vertically from the tip circle to where it crosses the tip
    circle again at the bottom: ``h = 2 R_F |cos(psi + psi_ft)| / cos(slope)``.
    This is the geometry behind Lee (2008) Eq. 4.26 and the physical reading of
    Lee's Ch. 3 statement that solids rejoin the passive phase at the flight-tip
    radius. Chosen as default because it is the only one consistent with a
    vertical fall and with Eq. 4.26.

``"eq3.5"``
:   Lee (2008) Eq. 3.5 taken literally: from the release height to the lowest
    point of the tip circle, ``h = R_F (1 - cos(psi + psi_ft)) / cos(slope)``.

``"ajayi2011"``
:   Ajayi (2011) Eq. 4.20: the chord plus half the flight depth
    ``(R - R_F)/2`` ("judgement-based" landing on the bed).

The fall time is the free-fall time ``sqrt(2 h / g)`` (zero initial velocity, no
drag), mass-averaged as ``t_m = (1/H0) integral sqrt(2 h/g) dH``; this is what
Lee's reported numbers imply (0.824 s < sqrt(2 x 4.164/g)), whereas Eq. 3.6 as
printed is ``sqrt(2 h_m / g)``.

Passive-time branches (Lee (2008) Eq. 3.4; notes section 5.6):

``"eq3.4"`` (default)
:   ``t_p = (2 psi_m - 180) / omega``: the arc from the landing point
    ``180 - psi_m`` (vertically below the release point) back to ``psi_m``.

``"lee2008_ch7"``
:   One revolution minus that arc, ``t_p = (540 - 2 psi_m) / omega``. With Lee's
    regressions this is what reproduces his Ch. 7 tables (Table 7.6); it is
    offered for comparison, not as physics.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validation import check_choice, check_range
from ..correlations.trajectory import cascade_trajectory
from .drum import _H, _S, FlightedDrum

__all__ = [
    "CascadeDrag",
    "CascadeSummary",
    "GRAVITY",
    "FALL_HEIGHT_DEFINITIONS",
    "PASSIVE_TIME_BRANCHES",
    "DESIGN_CONVENTIONS",
    "fall_height",
    "first_unloading_angle",
    "cascade",
    "discharge_start_angle",
]

GRAVITY = 9.81  #: m/s^2, the value used by Lee (2008) and Ajayi (2011) in their codes
FALL_HEIGHT_DEFINITIONS = ("chord", "eq3.5", "ajayi2011")
PASSIVE_TIME_BRANCHES = ("eq3.4", "lee2008_ch7")
DESIGN_CONVENTIONS = ("root", "tip")

# Gauss-Legendre nodes for the mass averages (each phase is smooth; the sqrt
# singularity of the fall time at the start is removed by a substitution).
_GL_X, _GL_W = np.polynomial.legendre.leggauss(24)


@dataclass(frozen=True)
class CascadeSummary:
    """dH-weighted (mass-averaged) cascade properties of one flight, arrays.

    Attributes
    ----------
    mean_release_angle : ndarray
        Mass-averaged flight-root angle at release ``psi_m``, deg from the drum bottom
        (Lee (2008) Eq. 3.3).
    mean_fall_height : ndarray
        Mass-averaged fall height ``h_m``, m (Lee (2008) Eq. 3.5, chosen definition).
    mean_fall_time : ndarray
        Mass-averaged free-fall time ``t_m``, s: the active-phase residence time.
    passive_time : ndarray
        Passive (flight-borne) residence time ``t_p``, s (Lee (2008) Eq. 3.4, chosen branch).
    discharge_start_angle : ndarray
        Root angle where discharge into the curtain starts, deg.
    initial_holdup_area : ndarray
        Holdup of the flight when it starts discharging into the curtain ``H0``, m^2
        per m of flight.
    mean_axial_step : ndarray
        Mass-averaged axial advance of a cascade towards the discharge, m: ``h tan(slope)``
        for a free fall (Lee (2008) Eq. 3.7, d_0 = h_m sin(theta) with h_m vertical), or from
        the particle trajectory through the gas with a [`CascadeDrag`][rotarydryer.geometry.unloading.CascadeDrag] (negative when a
        counter-current gas blows the solids back).
    """

    mean_release_angle: np.ndarray
    mean_fall_height: np.ndarray
    mean_fall_time: np.ndarray
    passive_time: np.ndarray
    discharge_start_angle: np.ndarray
    initial_holdup_area: np.ndarray
    mean_axial_step: np.ndarray | None = None

    @property
    def active_time(self) -> np.ndarray:
        """Active (airborne) residence time, s: the mass-averaged fall time."""
        return self.mean_fall_time

    @property
    def cycle_time(self) -> np.ndarray:
        """Active plus passive residence time, s."""
        return self.mean_fall_time + self.passive_time

    @property
    def airborne_ratio(self) -> np.ndarray:
        """Active to passive holdup ratio ``t_a / t_p`` (Ajayi (2011) Eq. 4.23), -."""
        return self.mean_fall_time / self.passive_time

    def to_dict(self) -> dict:
        """Plain-Python dictionary (lists for arrays) with units in the keys."""
        keys = {
            "mean_release_angle_deg": self.mean_release_angle,
            "mean_fall_height_m": self.mean_fall_height,
            "mean_fall_time_s": self.mean_fall_time,
            "passive_time_s": self.passive_time,
            "discharge_start_angle_deg": self.discharge_start_angle,
            "initial_holdup_area_m2": self.initial_holdup_area,
        }
        if self.mean_axial_step is not None:
            keys["mean_axial_step_m"] = self.mean_axial_step
        return {k: np.asarray(v).tolist() for k, v in keys.items()}


@dataclass(frozen=True)
class CascadeDrag:
    """Particles and gas for a fall with drag (instead of free fall) in [`cascade`][rotarydryer.geometry.unloading.cascade].

    The fall of each released element is integrated through the axial gas stream by
    [`rotarydryer.correlations.cascade_trajectory`][rotarydryer.correlations.cascade_trajectory] (isolated-particle drag, Lee (2008)
    ch. 6): fall time and axial displacement. Lee's CFD shows that particles inside a
    curtain feel a reduced gas velocity, so ``gas_velocity`` is the velocity *in the
    curtain* (an upper bound when the bulk velocity is used).

    Attributes: particle_diameter (m), particle_density (kg/m^3), gas_density (kg/m^3),
    gas_viscosity (Pa s), gas_velocity (m/s, >= 0), gas_flow ("co-current" or
    "counter-current"), method (drag correlation name, default Schiller-Naumann).
    """

    particle_diameter: float
    particle_density: float
    gas_density: float = 1.2
    gas_viscosity: float = 1.8e-5
    gas_velocity: float = 0.0
    gas_flow: str = "co-current"
    method: str = "schiller_naumann_1933"


def fall_height(drum: FlightedDrum, psi, *, definition: str = "chord", slope=0.0) -> np.ndarray:
    """Fall height of solids released from the tip of a flight whose root is at ``psi``, m.

    ``slope`` is the drum inclination, deg (the vertical height is the height in the
    drum cross-section divided by ``cos(slope)``, Lee (2008) Eq. 3.5). See the module
    docstring for the definitions. Zero where the tip is below the horizontal.
    """
    check_choice("definition", definition, FALL_HEIGHT_DEFINITIONS)
    slope = check_range("slope", slope, -45.0, 45.0, unit="deg")
    c = drum._c
    chi = np.radians(np.asarray(psi, dtype=float) + c.psi_ft)
    return _fall_height(c, chi, definition) / np.cos(np.radians(slope))


def _fall_height(c, chi, definition):
    cos_chi = np.cos(chi)
    if definition == "chord":
        return 2.0 * c.RF * np.maximum(-cos_chi, 0.0)
    if definition == "eq3.5":
        return np.where(cos_chi <= 0.0, c.RF * (1.0 - cos_chi), 0.0)
    # ajayi2011: chord plus half the flight depth, only once discharging
    return np.where(cos_chi <= 0.0, 2.0 * c.RF * (-cos_chi) + 0.5 * (c.R - c.RF), 0.0)


def first_unloading_angle(drum: FlightedDrum, convention: str = "root") -> float:
    """Root angle of the first unloading flight (FUF) of a design-loaded drum, deg.

    ``"root"``: the FUF has its root at 90 deg. This reproduces Lee's design-load
    regression Eq. 4.27 to 0.3 % and hence all of his Ch. 7 (notes section 6.5), and is
    the default. ``"tip"``: its tip at 90 deg, as Lee's text (section 4.4.1) states.
    """
    check_choice("convention", convention, DESIGN_CONVENTIONS)
    return 90.0 if convention == "root" else 90.0 - drum.tip_angle


def discharge_start_angle(drum: FlightedDrum, repose_angle, loading_factor=1.0, *, convention="root",
                          particle_diameter=None):
    """Root angle (deg) where a flight with loading factor ``f`` starts discharging into the curtain.

    Solves ``H_max(psi) = f H_max(psi_FUF)`` for the first ``psi >= psi_FUF`` by
    bisection (H_max is non-increasing). Returns ``(angle, H0)`` with ``H0 = f H0_des``.
    ``particle_diameter`` (m, optional): finite-particle correction (``docs/dem.md``).
    """
    f = check_range("loading_factor", loading_factor, 0.0, 1.0, low_inclusive=True, high_inclusive=True)
    phi = check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg")
    f, phi = np.broadcast_arrays(f, phi)
    c = drum._c
    delta = None if particle_diameter is None else drum._layer(particle_diameter)
    psi0 = first_unloading_angle(drum, convention)
    h_des = _H(c, np.full_like(phi, psi0), phi, delta)
    target = f * h_des
    lo = np.full_like(phi, psi0)
    hi = phi + c.off5
    hi = np.maximum(hi, lo)
    full = f >= 1.0
    for _ in range(0 if np.all(full) else 48):  # interval <= 360 deg -> 1e-12 deg
        mid = 0.5 * (lo + hi)
        above = _H(c, mid, phi, delta) > target
        lo = np.where(above, mid, lo)
        hi = np.where(above, hi, mid)
    start = np.where(full, psi0, hi)
    return start, target


def cascade(
    drum: FlightedDrum,
    repose_angle,
    loading_factor=1.0,
    *,
    rpm,
    slope=0.0,
    fall_height: str = "chord",
    passive_time_branch: str = "eq3.4",
    convention: str = "root",
    drag: CascadeDrag | None = None,
    particle_diameter=None,
) -> CascadeSummary:
    """Mass-averaged release angle, fall height, fall time and passive time of one flight.

    Parameters
    ----------
    drum : FlightedDrum
    repose_angle : array_like
        Dynamic angle of repose, deg, in (0, 90).
    loading_factor : array_like
        Flight loading factor ``f_load = H0/H0_des`` in [0, 1] (Lee (2008) section 4.4.2);
        1 at and above design load. Broadcasts with ``repose_angle``.
    rpm : float
        Drum speed, rev/min (> 0).
    slope : float
        Drum inclination, deg.
    fall_height, passive_time_branch, convention : str
        See the module docstring.
    drag : CascadeDrag, optional
        Fall through the gas with drag; default free fall (zero initial velocity, no drag).
    particle_diameter : float, optional
        Particle diameter, m: the flight holdup carries the finite-particle correction
        (``docs/dem.md``); ``None`` (default) is Lee's continuum model.

    Notes
    -----
    ``psi_m = (1/H0) integral psi (-dH)``, ``h_m = (1/H0) integral h (-dH)``,
    ``t_m = (1/H0) integral sqrt(2h/g) (-dH)`` over the discharge into the curtain
    (Lee (2008) Eq. 3.3, 3.5, 3.6 as mass averages), evaluated by Gauss-Legendre
    quadrature phase by phase with the analytic dH/dpsi (error < 1e-8 relative).
    A flight with ``f = 0`` releases nothing; its averages are the limits ``f -> 0``
    (everything at psi5).
    """
    check_choice("fall_height", fall_height, FALL_HEIGHT_DEFINITIONS)
    check_choice("passive_time_branch", passive_time_branch, PASSIVE_TIME_BRANCHES)
    rpm = check_range("rpm", rpm, 0.0, math.inf, unit="rpm")
    from .drum import check_speed

    check_speed("rpm", rpm, drum.radius, radius_key="radius", warn=False, refuse=False)
    slope = check_range("slope", slope, -45.0, 45.0, unit="deg")
    c = drum._c
    delta = None if particle_diameter is None else drum._layer(particle_diameter)
    start, h0 = discharge_start_angle(drum, repose_angle, loading_factor, convention=convention,
                                      particle_diameter=particle_diameter)
    phi = np.broadcast_to(check_range("repose_angle", repose_angle, 0.0, 90.0), start.shape)
    psi5 = phi + c.off5
    # integration breakpoints: phase boundaries (every event of a polygonal flight) and the chord kink
    # at tip angle 270
    cuts = [phi + o for o in c.breaks[1:-1]] + [np.full_like(phi, 270.0 - c.psi_ft)]
    edges = np.sort(np.stack([start] + [np.clip(x, start, psi5) for x in cuts] + [psi5], axis=-1), axis=-1)
    acc = {"w": 0.0, "psi": 0.0, "h": 0.0, "t": 0.0, "x": 0.0}
    tan_s = np.tan(np.radians(slope))
    for k in range(edges.shape[-1] - 1):
        a, b = edges[..., k, None], edges[..., k + 1, None]
        if k == 0:  # psi = a + (b - a) u^2 removes the sqrt singularity at the start
            u = 0.5 * (_GL_X + 1.0)
            psi = a + (b - a) * u**2
            jac = (b - a) * 2.0 * u * 0.5 * _GL_W
        else:
            psi = 0.5 * (a + b) + 0.5 * (b - a) * _GL_X
            jac = 0.5 * (b - a) * _GL_W
        ph = np.broadcast_to(phi[..., None], psi.shape)
        w = -_S(c, psi, ph, delta) * jac  # dH >= 0, m^2
        h = _fall_height(c, np.radians(psi + c.psi_ft), fall_height)
        acc["w"] = acc["w"] + w.sum(-1)
        acc["psi"] = acc["psi"] + (w * psi).sum(-1)
        acc["h"] = acc["h"] + (w * h).sum(-1)
        if drag is None:
            acc["t"] = acc["t"] + (w * np.sqrt(2.0 * h / GRAVITY)).sum(-1)
            acc["x"] = acc["x"] + (w * h * tan_s).sum(-1)
        else:
            t_d, x_d = _drag_fall(drag, h, slope)
            acc["t"] = acc["t"] + (w * t_d).sum(-1)
            acc["x"] = acc["x"] + (w * x_d).sum(-1)
    wsum = acc["w"]
    empty = wsum <= 1e-14 * c.full_area
    safe = np.where(empty, 1.0, wsum)
    h5 = _fall_height(c, np.radians(psi5 + c.psi_ft), fall_height)
    psi_m = np.where(empty, psi5, acc["psi"] / safe)
    h_m = np.where(empty, h5, acc["h"] / safe)
    cos_s = np.cos(np.radians(slope))
    if drag is None:
        t5, x5 = np.sqrt(2.0 * h5 / GRAVITY), h5 * tan_s
        t_scale = 1.0 / np.sqrt(cos_s)  # fall over the vertical height h / cos(slope)
    else:
        t5, x5 = _drag_fall(drag, h5, slope)
        t_scale = 1.0  # the trajectory already falls through the inclined drum
    t_m = np.where(empty, t5, acc["t"] / safe) * t_scale
    x_m = np.where(empty, x5, acc["x"] / safe)
    h_m = h_m / cos_s
    omega = 6.0 * rpm  # deg/s
    arc = 2.0 * psi_m - 180.0  # Lee (2008) Eq. 3.4
    t_p = arc / omega if passive_time_branch == "eq3.4" else (360.0 - arc) / omega
    return CascadeSummary(
        mean_release_angle=psi_m,
        mean_fall_height=h_m,
        mean_fall_time=t_m,
        passive_time=t_p,
        discharge_start_angle=start,
        initial_holdup_area=h0,
        mean_axial_step=x_m,
    )


def _drag_fall(drag: CascadeDrag, h, slope):
    """Fall time (s) and axial displacement (m) through the gas for section fall heights ``h``."""

    h = np.asarray(h, dtype=float)
    r = cascade_trajectory(np.maximum(h, 1e-6), drag.particle_diameter, drag.particle_density, drag.gas_density,
                           drag.gas_viscosity, gas_velocity=drag.gas_velocity, gas_flow=drag.gas_flow,
                           inclination=float(slope), method=drag.method)
    t = np.where(h > 1e-6, np.asarray(r.fall_time).reshape(h.shape), 0.0)
    x = np.where(h > 1e-6, np.asarray(r.axial_displacement).reshape(h.shape), 0.0)
    return t, x
