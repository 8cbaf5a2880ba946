"""A flighted drum: exact geometric flight holdup versus rotation angle.

Angle convention (Lee (2008) Fig. 4.4; drawn in ``docs/geometry_conventions.png``):
``psi`` is the angular position of the flight **root** (its attachment to the drum
wall), measured from the bottom of the drum in the direction of rotation, in
degrees. ``psi = 90`` puts the root at the side of the drum where flights rise
(the "9 o'clock" or "3 o'clock" position depending on the viewing side),
``psi = 180`` at the top. In drawings and coordinates the drum is viewed so
that it turns **anticlockwise**: the root is at ``(R sin psi, -R cos psi)``.

The flight tip leads the root by the tip angle ``psi_ft`` (Lee (2008) Eq. 4.7),
so the tip sits at ``psi + psi_ft`` on the flight-tip circle of radius ``R_F``.

Two computations of the held area, chosen by ``geometry=``: Lee's closed forms for a two-section
flight (``"lee2008"``, Lee (2008) Eq. 4.14-4.17) and the exact clipping of the pocket for a flight of
any polygonal shape (``"polygon"``, `rotarydryer.geometry.polygon`). ``"auto"`` (default) takes
the closed forms for a two-section flight and the clipping for any other; both agree on a
two-section flight to about 1e-14 of a full flight (``tests/geometry/test_polygon.py``).

The material held by a flight is bounded by the flight, the drum wall, the next
flight and a plane surface through the flight tip inclined at the dynamic angle
of repose ``repose_angle`` to the horizontal (Lee (2008) section 4.2; free-flowing
solids, surface flow, no flow over the tip).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .._validation import check_choice, check_finite, check_range, fmt_number
from . import polygon as _poly
from .flights import PolygonFlight, TwoSectionFlight
from .polygon import PocketGeometry, pocket_geometry

__all__ = ["FlightedDrum", "TransitionAngles", "GEOMETRY_PATHS", "CriticalSpeedWarning", "critical_speed", "check_speed",
           "CRITICAL_SPEED_WARN_FRACTION", "SURFACE_LAYER", "finite_particle_correction", "surface_layer_thickness"]

_DEG = math.pi / 180.0

#: the held-area computations of `FlightedDrum` (``geometry=``): "auto", Lee's closed forms, polygon clipping
GEOMETRY_PATHS = ("auto", "lee2008", "polygon")

#: above this fraction of the critical speed (Froude number omega^2 R / g = 0.25) :func:`check_speed`
#: warns: the gravity-only unloading model (Lee (2008) Ch. 4) neglects the centrifugal force
CRITICAL_SPEED_WARN_FRACTION = 0.5


class CriticalSpeedWarning(UserWarning):
    """The drum turns at more than half its critical speed: centrifugal forces (neglected by the
    gravity-only flight-unloading model) are no longer small."""


def critical_speed(radius) -> float:
    """Critical speed of a drum, rev/min: N_c = 42.3 / sqrt(D) with D = 2 ``radius`` in m (the
    speed at which the centrifugal acceleration omega^2 R equals g and the solids ride round with
    the wall instead of cascading)."""
    R = float(check_range("radius", radius, 0.0, math.inf, unit="m"))
    return 42.3 / math.sqrt(2.0 * R)


def check_speed(key: str, rpm, radius, *, radius_key: str = "drum.radius", warn: bool = True,
                refuse: bool = True) -> float:
    """Check a drum speed (rev/min) against the critical speed of a drum of ``radius`` (m).

    At or above the critical speed ``N_c`` it raises ``ValueError`` naming ``key``, the speed and
    the critical speed (with ``refuse=False`` it only warns, [`CriticalSpeedWarning`][rotarydryer.geometry.drum.CriticalSpeedWarning]); between
    `CRITICAL_SPEED_WARN_FRACTION` of it and ``N_c`` it warns when ``warn``. Returns the
    largest speed as a float."""

    n = float(np.max(check_range(key, rpm, 0.0, math.inf, unit="rev/min")))
    R = float(check_range(radius_key, radius, 0.0, math.inf, unit="m"))
    nc = critical_speed(R)
    if n >= nc:
        msg = (f"{key} = {fmt_number(n)} rev/min is at or above the critical speed of the drum, "
               f"N_c = 42.3/sqrt(D) = {nc:.3g} rev/min for D = 2 x {radius_key} = {2 * R:g} m: the solids would "
               f"ride round with the wall instead of cascading; the allowed range is (0, {nc:.3g}) rev/min "
               f"(flighted dryers run at 1-5 rev/min, below {CRITICAL_SPEED_WARN_FRACTION:.0%} of N_c)")
        if refuse:
            raise ValueError(msg)
        warnings.warn(msg, CriticalSpeedWarning, stacklevel=2)
        return n
    if warn and n > CRITICAL_SPEED_WARN_FRACTION * nc:
        warnings.warn(
            f"{key} = {fmt_number(n)} rev/min is {n / nc:.0%} of the critical speed N_c = {nc:.3g} rev/min "
            f"of the drum (D = {2 * R:g} m): above {CRITICAL_SPEED_WARN_FRACTION:.0%} the centrifugal force, "
            "neglected by the flight-unloading model (Lee (2008) Ch. 4), is no longer small",
            CriticalSpeedWarning, stacklevel=2)
    return n


class TransitionAngles(NamedTuple):
    """The five transition angles of Lee (2008) Eq. 4.9-4.13, deg (flight-root position).

    psi1: discharge starts (surface through both tips, Eq. 4.9);
    psi2: surface reaches the next flight's bend (Eq. 4.10);
    psi3: surface reaches the next flight's root (Eq. 4.11);
    psi4: surface reaches this flight's root (Eq. 4.12);
    psi5: the tip section itself is at the repose angle: flight empty (Eq. 4.13).
    """

    psi1: np.ndarray
    psi2: np.ndarray
    psi3: np.ndarray
    psi4: np.ndarray
    psi5: np.ndarray


@dataclass(frozen=True)
class _Consts:
    """Fixed (repose-angle independent) geometry of one drum, SI units and degrees."""

    R: float
    RF: float
    psi_fl: float
    psi_ft: float
    s1: float
    s2: float
    a1p: float
    a2: float
    s1p: float
    s2p: float
    a2p: float
    full_area: float
    s_ft: float
    alpha_ft: float
    s_a: float
    alpha_a: float
    off1: float
    off2: float
    off3: float
    off4: float
    off5: float
    area_tri_ft: float  # triangle (tip, next tip, next bend)
    area_const3: float  # the two constant triangles of Eq. 4.16

    @property
    def breaks(self) -> tuple[float, ...]:
        """Offsets (deg) of the phase boundaries from the repose angle, psi1 to psi5 (Lee (2008) Eq. 4.9-4.13)."""
        return (self.off1, self.off2, self.off3, self.off4, self.off5)


class FlightedDrum:
    """A drum of radius ``radius`` with ``n_flights`` identical, equally spaced flights.

    Parameters
    ----------
    radius : float
        Drum (inner shell) radius ``R``, m.
    n_flights : int
        Number of flights around the circumference ``N_F`` (>= 2).
    flight : TwoSectionFlight or PolygonFlight
        The flight shape.
    geometry : str, keyword only
        ``"auto"`` (default): Lee's closed forms (Lee (2008) Eq. 4.14-4.17) for a two-section flight,
        the exact clipping of the pocket (`rotarydryer.geometry.polygon`) for any other; ``"lee2008"``
        or ``"polygon"`` to choose. A `PolygonFlight` of two sections outside Lee's four-phase model
        (e.g. a tip bent backwards) takes the clipping under ``"auto"``.

    Examples
    --------
    CSR Invicta Mill dryer No. 2 (Lee (2008) Table 4.1):

    >>> from rotarydryer.geometry import TwoSectionFlight, FlightedDrum
    >>> drum = FlightedDrum(2.5, 28, TwoSectionFlight(0.195, 0.183, 90.0, 117.0))
    >>> round(drum.tip_radius, 5), round(drum.tip_angle, 4)
    (2.22789, 4.1971)
    >>> [round(float(a), 1) for a in drum.transition_angles(30.0)]
    [19.4, 34.1, 58.7, 150.4, 183.0]
    """

    _c: _Consts | PocketGeometry

    def __init__(self, radius: float, n_flights: int, flight: TwoSectionFlight | PolygonFlight, *,
                 geometry: str = "auto"):
        R = float(check_range("radius", radius, 0.0, math.inf, unit="m"))
        if isinstance(n_flights, bool) or int(n_flights) != n_flights or n_flights < 2:
            raise ValueError(
                f"n_flights = {fmt_number(n_flights) if isinstance(n_flights, (int, float)) else repr(n_flights)} "
                "is not allowed; it must be an integer >= 2"
            )
        if isinstance(flight, TwoSectionFlight):
            two: TwoSectionFlight | None = flight
        elif isinstance(flight, PolygonFlight):
            two = flight.as_two_section()
        else:
            raise ValueError(f"flight must be a TwoSectionFlight or a PolygonFlight, got {type(flight).__name__}")
        check_choice("geometry", geometry, GEOMETRY_PATHS)
        self.radius = R
        self.n_flights = int(n_flights)
        self.flight = flight
        self._two = two
        if geometry == "lee2008" and two is None:
            raise ValueError(f"geometry = 'lee2008' (Lee's closed forms) needs a flight of one or two sections "
                             f"with alpha2 <= 180 deg; this flight has {flight.n_segments} sections: use "  # type: ignore[union-attr]
                             "geometry = 'polygon' (or 'auto')")
        if geometry == "polygon" or two is None:
            self._c = pocket_geometry(R, self.n_flights, self.profile)
            self.geometry = "polygon"
            return
        try:
            self._c = self._fixed_geometry()
        except ValueError:
            if geometry == "lee2008" or isinstance(flight, TwoSectionFlight):
                raise
            self._c = pocket_geometry(R, self.n_flights, self.profile)   # outside Lee's four phases
            self.geometry = "polygon"
            return
        self.geometry = "lee2008"

    @property
    def profile(self) -> PolygonFlight:
        """The flight as a [`PolygonFlight`][rotarydryer.geometry.flights.PolygonFlight] (a two-section flight converted)."""
        f = self.flight
        return f.to_polygon() if isinstance(f, TwoSectionFlight) else f

    @property
    def is_polygon(self) -> bool:
        """Whether the held area is computed by clipping the pocket (``geometry == "polygon"``)."""
        return isinstance(self._c, PocketGeometry)

    # ------------------------------------------------------------------ fixed geometry
    def _fixed_geometry(self) -> _Consts:
        f = self._two
        assert f is not None
        R, N = self.radius, self.n_flights
        s1, s2 = f.s1, f.effective_s2
        a1p, a2 = f.equivalent_alpha1, f.effective_alpha2
        s1p, s2p, a2p = f.equivalent_s1, f.equivalent_s2, f.equivalent_alpha2
        if s1 >= R:
            raise ValueError(
                f"flight s1 = {s1:g} m does not fit the drum: it must be < radius = {R:g} m"
            )
        if s1p >= R:
            raise ValueError(
                f"flight does not fit the drum: its equivalent perpendicular base "
                f"s1' = {s1p:g} m must be < radius = {R:g} m"
            )
        psi_fl = 360.0 / N  # Lee (2008) Eq. 4.5
        sup = 180.0 - a2p  # alpha2'_sup: angle at the bend between base continued inward and tip
        # Lee (2008) Eq. 4.6: flight-tip radius (law of cosines, triangle centre-bend'-tip)
        x = R - s1p
        RF = f.tip_radius(R)
        RF2 = RF * RF
        if not 0.0 < RF < R:
            raise ValueError(
                f"flight tip is outside the drum or at its centre: tip radius {RF:g} m must be "
                f"in (0, {R:g}) m (radius)"
            )
        # Lee (2008) Eq. 4.7 (atan2 form of the sine rule, valid for obtuse angles too)
        psi_ft = math.degrees(math.atan2(s2p * math.sin(sup * _DEG), x - s2p * math.cos(sup * _DEG)))
        if psi_ft >= psi_fl:
            raise ValueError(
                f"flights overlap their neighbours: the tip leads the root by {psi_ft:.3f} deg, "
                f"which must be < the flight spacing 360/n_flights = {psi_fl:.3f} deg"
            )
        # Lee (2008) Eq. 4.8: holdup area of a full flight (sector minus tip-tip triangle)
        full_area = math.pi * R * R * psi_fl / 360.0 - 0.5 * RF2 * math.sin(psi_fl * _DEG)
        # auxiliary quantities of Eq. 4.9-4.11
        s_ft = 2.0 * RF * math.sin(0.5 * psi_fl * _DEG)
        alpha_ft = 90.0 + 0.5 * psi_fl - psi_ft - sup
        s_a = math.sqrt(max(s2 * s2 + s_ft * s_ft - 2.0 * s2 * s_ft * math.cos(alpha_ft * _DEG), 0.0))
        alpha_a = math.degrees(
            math.atan2(s2 * math.sin(alpha_ft * _DEG), s_ft - s2 * math.cos(alpha_ft * _DEG))
        )
        th = (psi_fl - psi_ft) * _DEG
        gam3 = math.degrees(math.atan2(RF * math.sin(th), R - RF * math.cos(th)))
        root_tip = f.root_to_tip
        gam4 = math.degrees(math.atan2(s2 * math.sin(a2 * _DEG), s1 - s2 * math.cos(a2 * _DEG)))
        off1 = -0.5 * psi_fl - psi_ft  # Eq. 4.9
        off2 = off1 + alpha_a  # Eq. 4.10
        off3 = 90.0 - psi_fl - gam3  # Eq. 4.11
        off4 = 90.0 + a1p + gam4  # Eq. 4.12
        off5 = 90.0 + sup  # Eq. 4.13
        offs = (off1, off2, off3, off4, off5)
        if any(b < a - 1e-9 for a, b in zip(offs, offs[1:])):
            raise ValueError(
                "flight geometry not supported by Lee's four-phase unloading model: the "
                f"transition points are out of order (offsets {', '.join(f'{o:.2f}' for o in offs)} "
                "deg from the repose angle); check that the flights do not overlap and that "
                "alpha2 bends the tip forward (a PolygonFlight of the same sections is computed by clipping)"
            )
        if root_tip <= 0.0:
            raise ValueError("flight has zero length")
        area_tri_ft = 0.5 * s_ft * s2 * math.sin(alpha_ft * _DEG)
        area_const3 = 0.5 * (R - s1p) * s2p * math.sin(a2p * _DEG) + 0.5 * s1 * s1p * math.sin(
            a1p * _DEG
        )
        return _Consts(
            R=R, RF=RF, psi_fl=psi_fl, psi_ft=psi_ft, s1=s1, s2=s2, a1p=a1p, a2=a2, s1p=s1p,
            s2p=s2p, a2p=a2p, full_area=full_area, s_ft=s_ft, alpha_ft=alpha_ft, s_a=s_a,
            alpha_a=alpha_a, off1=off1, off2=off2, off3=off3, off4=off4, off5=off5,
            area_tri_ft=area_tri_ft, area_const3=area_const3,
        )

    def __repr__(self) -> str:
        f = self.flight
        if not isinstance(f, TwoSectionFlight) or self.geometry != "lee2008":
            extra = ", geometry='polygon'" if self.is_polygon and self._two is not None else ""
            return f"FlightedDrum(radius={self.radius!r}, n_flights={self.n_flights!r}, flight={f!r}{extra})"
        return (
            f"FlightedDrum(radius={self.radius!r}, n_flights={self.n_flights!r}, "
            f"flight=TwoSectionFlight(s1={f.s1!r}, s2={f.s2!r}, alpha1={f.alpha1!r}, "
            f"alpha2={f.alpha2!r}))"
        )

    @property
    def critical_speed(self) -> float:
        """Critical speed N_c = 42.3/sqrt(D) of the drum, rev/min ([`critical_speed`][rotarydryer.geometry.drum.critical_speed])."""
        return critical_speed(self.radius)

    @property
    def tip_radius(self) -> float:
        """Flight-tip radius ``R_F``, m (Lee (2008) Eq. 4.6)."""
        return self._c.RF

    @property
    def tip_angle(self) -> float:
        """Angle ``psi_ft`` by which the tip leads the root, deg (Lee (2008) Eq. 4.7)."""
        return self._c.psi_ft

    @property
    def flight_spacing(self) -> float:
        """Angle between neighbouring flights ``psi_fl = 360/N_F``, deg (Lee (2008) Eq. 4.5)."""
        return self._c.psi_fl

    @property
    def full_holdup_area(self) -> float:
        """Cross-sectional area held by a full flight, m^2 (Lee (2008) Eq. 4.8).

        Multiply by bulk density (kg/m^3) and flight length (m) for kg. This is the
        most a flight ever holds (buried in the bed), not its design load.
        """
        return self._c.full_area

    # ------------------------------------------------------------------ transition points
    def transition_angles(self, repose_angle) -> TransitionAngles:
        """Transition angles psi1..psi5 for a dynamic angle of repose (deg), Lee (2008) Eq. 4.9-4.13.

        All five shift one-for-one with the repose angle. Returns arrays shaped like
        ``repose_angle``. For a polygonal flight: psi1 discharge starts (the surface leaves the tip
        chord), psi2 the surface passes the next flight's last bend, psi3 the next flight's root,
        psi4 this flight's root, psi5 empty (the surface along the last section); the other
        corners of the pocket are in `unloading_events`.
        """
        phi = _check_repose(repose_angle)
        c = self._c
        return TransitionAngles(phi + c.off1, phi + c.off2, phi + c.off3, phi + c.off4, phi + c.off5)

    def final_discharge_angle(self, repose_angle) -> np.ndarray:
        """Root angle at which the flight is empty, psi5, deg (Lee (2008) Eq. 4.13; for any flight,
        where the surface through the tip lies along its last section)."""
        return self.transition_angles(repose_angle).psi5

    @property
    def unloading_events(self) -> tuple[float, ...]:
        """Offsets from the repose angle (deg) of every angle at which the held area changes form,
        from psi1 (discharge starts) to psi5 (empty): Lee's transition points (Lee (2008) Eq. 4.9-4.13)
        for a two-section flight, the surface passing each corner of the pocket for a polygonal one."""
        return tuple(float(v) for v in self._c.breaks)

    # ------------------------------------------------------------------ holdup
    def holdup_area(self, psi, repose_angle, particle_diameter=None, *, surface_layer=None) -> np.ndarray:
        """Cross-sectional area of solids held by one flight, m^2 (per m of flight length).

        Parameters
        ----------
        psi : array_like
            Flight-root position, deg from the drum bottom in the direction of
            rotation; wrapped into [0, 360).
        repose_angle : array_like
            Dynamic angle of repose, deg, in (0, 90). Broadcasts with ``psi``.
        particle_diameter : float, optional
            Particle diameter ``d``, m: adds the finite-particle correction
            ([`finite_particle_correction`][rotarydryer.geometry.drum.finite_particle_correction]; ``docs/dem.md``), a surface layer of
            ``surface_layer`` diameters (default `SURFACE_LAYER`, calibrated on DEM).
            ``None`` (default) is Lee's continuum model, unchanged.

        Notes
        -----
        Full flight below psi1 (Lee (2008) Eq. 4.8); phases I-IV between the
        transition points (Eq. 4.14-4.17, with the non-perpendicular correction of
        Eq. 4.1-4.4 in phase III); empty from psi5 on (refilling at the bottom of
        the drum is not part of Lee's model). Multiply by bulk density and length
        for kg.
        """
        psi, phi = _prepare(psi, repose_angle)
        if particle_diameter is None:
            return _holdup(self._c, psi, phi)
        return _holdup_fp(self._c, psi, phi, self._layer(particle_diameter, surface_layer))

    def holdup_slope(self, psi, repose_angle, particle_diameter=None, *, surface_layer=None) -> np.ndarray:
        """Derivative dH/dpsi of [`holdup_area`][rotarydryer.geometry.drum.FlightedDrum.holdup_area], m^2 per degree (<= 0): analytic for the
        continuum model, a central difference (1e-4 deg) with a ``particle_diameter``."""
        psi, phi = _prepare(psi, repose_angle)
        if particle_diameter is None:
            return _holdup_slope(self._c, psi, phi)
        return _holdup_slope_fp(self._c, psi, phi, self._layer(particle_diameter, surface_layer))

    def discharge_rate(self, psi, repose_angle, rpm, particle_diameter=None, *, surface_layer=None) -> np.ndarray:
        """Flight discharge rate ``-omega dH/dpsi``, m^2/s per m of flight length (Lee (2008) l.4789).

        ``rpm`` is the drum speed in revolutions per minute. Multiply by bulk density
        (kg/m^3) and flight length (m) for kg/s. Discharge before the tip reaches
        the horizontal rolls into the next flight rather than into the curtain.
        """
        rpm = check_range("rpm", rpm, 0.0, math.inf, unit="rpm")
        return -self.holdup_slope(psi, repose_angle, particle_diameter, surface_layer=surface_layer) * (6.0 * rpm)

    def surface_layer_thickness(self, particle_diameter, surface_layer=None) -> float:
        """Thickness ``delta = k d`` of the finite-particle surface layer, m (``docs/dem.md``).

        Raises ``ValueError`` for particles larger than a quarter of the flight base."""
        return self._layer(particle_diameter, surface_layer)

    def _layer(self, particle_diameter, surface_layer=None) -> float:
        return surface_layer_thickness(self.flight.s1, particle_diameter, surface_layer)

    # ------------------------------------------------------------------ unloading, design load
    def cascade(self, repose_angle, loading_factor=1.0, *, rpm, slope=0.0, fall_height="chord",
                passive_time_branch="eq3.4", convention="root", drag=None, particle_diameter=None):
        """Mass-averaged cascade properties; see [`rotarydryer.geometry.unloading.cascade`][rotarydryer.geometry.unloading.cascade]."""
        from .unloading import cascade

        return cascade(self, repose_angle, loading_factor, rpm=rpm, slope=slope,
                       fall_height=fall_height, passive_time_branch=passive_time_branch,
                       convention=convention, drag=drag, particle_diameter=particle_diameter)

    def design_load_area(self, repose_angle, *, method="lee2008", convention="root", particle_diameter=None):
        """Design-load area of passive solids in the drum cross-section, m^2.

        See [`rotarydryer.geometry.design_load.design_load_area`][rotarydryer.geometry.design_load.design_load_area].
        """
        from .design_load import design_load_area

        return design_load_area(self, repose_angle, method=method, convention=convention,
                                particle_diameter=particle_diameter)

    def loading_factor(self, dryer_loading, repose_angle, *, convention="root", particle_diameter=None,
                       smoothing=0.0):
        """Flight loading factor from the dryer loading (Lee (2008) Eq. 4.22, solved exactly).

        See [`rotarydryer.geometry.design_load.loading_factor`][rotarydryer.geometry.design_load.loading_factor].
        """
        from .design_load import loading_factor

        return loading_factor(self, dryer_loading, repose_angle, convention=convention,
                              particle_diameter=particle_diameter, smoothing=smoothing)

    # ------------------------------------------------------------------ coordinates
    def flight_outline(self, psi: float) -> np.ndarray:
        """Points (root, bend(s), tip) of the flight whose root is at ``psi`` deg, m: shape (3, 2) for
        a two-section flight under Lee's closed forms, (n_segments + 1, 2) for a polygonal flight.

        Origin at the drum centre, y up, drum turning anticlockwise.
        """
        psi = float(check_finite("psi", psi, unit="deg"))
        if self.is_polygon:
            return _poly._flight_points(self.profile, self.radius, psi)
        f = self._two
        assert f is not None
        p = math.radians(float(psi))
        R = self.radius
        root = np.array([R * math.sin(p), -R * math.cos(p)])
        th1 = p + math.radians(f.alpha1)  # base direction: alpha1 from the forward tangent
        bend = root + f.s1 * np.array([math.cos(th1), math.sin(th1)])
        th2 = th1 + math.pi + math.radians(f.effective_alpha2)
        tip = bend + f.effective_s2 * np.array([math.cos(th2), math.sin(th2)])
        return np.vstack([root, bend, tip])

    def pocket_polygon(self, psi: float, n_arc: int = 64) -> np.ndarray:
        """Polygon (m) of the region a full flight at ``psi`` can hold: between this flight,
        the next flight ahead, the drum wall and the chord through both tips (Lee Eq. 4.8)."""
        here = self.flight_outline(psi)
        nxt = self.flight_outline(psi + self.flight_spacing)
        a = np.radians(np.linspace(psi + self.flight_spacing, psi, n_arc))[1:-1]
        arc = np.column_stack([self.radius * np.sin(a), -self.radius * np.cos(a)])
        return np.vstack([here, nxt[::-1], arc])

    def held_polygon(self, psi: float, repose_angle: float, n_arc: int = 64) -> np.ndarray:
        """Polygon (m) of the solids held by the flight at ``psi`` for a repose angle (deg).

        The pocket polygon clipped by the half-plane below the material surface through
        the tip. Used for drawings; [`holdup_area`][rotarydryer.geometry.drum.FlightedDrum.holdup_area] is the exact area.
        """
        _check_repose(repose_angle)
        psi = float(psi) % 360.0
        if psi >= float(self.transition_angles(repose_angle).psi5):
            return np.empty((0, 2))
        if self.is_polygon:
            return self._held_polygon_ray(psi, float(repose_angle), n_arc)
        tip = self.flight_outline(psi)[-1]
        phi = math.radians(float(repose_angle))
        normal = np.array([-math.sin(phi), math.cos(phi)])  # points above the surface
        return _clip_halfplane(self.pocket_polygon(psi, n_arc), tip, normal)

    def _held_polygon_ray(self, psi: float, phi: float, n_arc: int) -> np.ndarray:
        """Held solids of a polygonal flight: the surface from the tip to where it first meets the
        pocket, and the pocket's boundary from there round to the tip (`rotarydryer.geometry.polygon`)."""
        c = self._c
        pts = self.pocket_polygon(psi, n_arc)
        if psi - phi < c.off1:
            return pts
        it = len(self.flight_outline(psi)) - 1
        order = np.roll(np.arange(len(pts)), -it)            # from the tip round the pocket
        ring = pts[order]
        T = ring[0]
        e = np.array([math.cos(math.radians(phi)), math.sin(math.radians(phi))])
        best, hit = math.inf, None
        for k in range(1, len(ring) - 1):                    # edges not through the tip
            p, q = ring[k], ring[k + 1]
            d = q - p
            den = e[0] * d[1] - e[1] * d[0]
            if abs(den) < 1e-15:
                continue
            w = p - T
            r = (w[0] * d[1] - w[1] * d[0]) / den
            t = (w[0] * e[1] - w[1] * e[0]) / den
            if r > 1e-12 * self.radius and -1e-12 <= t <= 1.0 + 1e-12 and r < best:
                best, hit = r, (k, min(max(t, 0.0), 1.0))
        if hit is None:
            return np.empty((0, 2))
        k, t = hit
        H = ring[k] + t * (ring[k + 1] - ring[k])
        return np.vstack([H, ring[k + 1:], T[None, :]])


# ---------------------------------------------------------------------- internals
def _check_repose(repose_angle) -> np.ndarray:
    return check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg")


def _prepare(psi, repose_angle):
    psi = np.mod(check_finite("psi", psi, unit="deg"), 360.0)
    phi = _check_repose(repose_angle)
    return np.broadcast_arrays(psi, phi)


def _phase_I(c: _Consts, psi, phi, slope: bool):
    """Lee (2008) Eq. 4.14: triangle between the surface and the tip chord removed."""
    d = _DEG
    aft = c.alpha_ft * d
    delta = (psi + c.psi_ft + 0.5 * c.psi_fl - phi) * d
    s = np.sin(aft + delta)
    if slope:
        return -0.5 * c.s_ft**2 * math.sin(aft) ** 2 / s**2 * d
    return c.full_area - 0.5 * c.s_ft**2 * math.sin(aft) * np.sin(delta) / s


def _phase_II(c: _Consts, psi, phi, slope: bool):
    """Lee (2008) Eq. 4.15: the surface meets the next flight's base."""
    d = _DEG
    eps = (psi + c.psi_ft + 0.5 * c.psi_fl - c.alpha_a - phi) * d
    zeta = (180.0 + c.alpha_ft + c.alpha_a - c.a2) * d
    s = np.sin(eps + zeta)
    if slope:
        return -0.5 * c.s_a**2 * math.sin(zeta) ** 2 / s**2 * d
    return c.full_area - c.area_tri_ft - 0.5 * c.s_a**2 * np.sin(eps) * math.sin(zeta) / s


def _phase_III(c: _Consts, psi, phi, slope: bool):
    """Lee (2008) Eq. 4.16: the surface meets the drum wall between the roots."""
    d = _DEG
    k = c.RF / c.R
    u = (psi + c.psi_ft + 90.0 - phi) * d
    su = np.clip(k * np.sin(u), -1.0, 1.0)
    beta = (90.0 + phi - psi - c.psi_ft) * d - np.arcsin(su)
    if slope:
        dbeta = -1.0 - k * np.cos(u) / np.sqrt(1.0 - su**2)
        return (0.5 * c.R**2 - 0.5 * c.R * c.RF * np.cos(beta)) * dbeta * d
    return 0.5 * c.R**2 * (c.psi_ft * d + beta) - 0.5 * c.R * c.RF * np.sin(beta) - c.area_const3


def _phase_IV(c: _Consts, psi, phi, slope: bool):
    """Lee (2008) Eq. 4.17: the surface meets this flight's base."""
    d = _DEG
    gam = (90.0 + phi + 180.0 - c.a2p - psi) * d
    a2 = c.a2 * d
    s = np.sin(a2 + gam)
    if slope:
        return -0.5 * c.s2**2 * math.sin(a2) ** 2 / s**2 * d
    return 0.5 * c.s2**2 * math.sin(a2) * np.sin(gam) / s


_PHASES = (_phase_I, _phase_II, _phase_III, _phase_IV)


def _phase_index(c: _Consts, psi, phi):
    """0: full (before psi1), 1-4: phases I-IV, 5: empty (from psi5 on)."""
    x = psi - phi
    return (
        (x >= c.off1).astype(np.int8)
        + (x >= c.off2)
        + (x >= c.off3)
        + (x >= c.off4)
        + (x >= c.off5)
    )


def _evaluate(c: _Consts, psi, phi, slope: bool):
    """Piecewise holdup (or its slope, per degree): each point evaluates only its own phase."""
    psi, phi = np.broadcast_arrays(np.asarray(psi, dtype=float), np.asarray(phi, dtype=float))
    idx = _phase_index(c, psi, phi)
    out = np.zeros(psi.shape)
    if not slope:
        out[idx == 0] = c.full_area
    with np.errstate(all="ignore"):
        for k, fn in enumerate(_PHASES, start=1):
            m = idx == k
            if m.any():
                out[m] = fn(c, psi[m], phi[m], slope)
    if slope:
        return np.minimum(out, 0.0)
    return np.clip(out, 0.0, c.full_area)


def _holdup(c, psi, phi):
    if isinstance(c, PocketGeometry):
        return _poly_evaluate(c, psi, phi, slope=False)
    return _evaluate(c, psi, phi, slope=False)


def _poly_evaluate(c: PocketGeometry, psi, phi, slope: bool):
    """Holdup (or its slope, per degree) of a polygonal flight: full before psi1, the clipped pocket
    (`rotarydryer.geometry.polygon.area_and_slope`) until psi5, empty from psi5 on."""
    psi, phi = np.broadcast_arrays(np.asarray(psi, dtype=float), np.asarray(phi, dtype=float))
    x = psi - phi
    act = (x >= c.off1) & (x < c.off5)
    out = np.zeros(psi.shape) if slope else np.where(x < c.off1, c.full_area, 0.0)
    if act.any():
        a, sl = _poly.area_and_slope(c, x[act], slope=slope)
        out[act] = sl if slope else a
    if slope:
        return np.minimum(out, 0.0)
    return np.clip(out, 0.0, c.full_area)


def _poly_both(c: PocketGeometry, psi, phi):
    """Holdup (m^2) and slope (m^2/deg) of a polygonal flight in one pass, and the active mask."""
    psi, phi = np.broadcast_arrays(np.asarray(psi, dtype=float), np.asarray(phi, dtype=float))
    x = psi - phi
    act = (x >= c.off1) & (x < c.off5)
    h = np.where(x < c.off1, c.full_area, 0.0)
    sl = np.zeros(psi.shape)
    if act.any():
        h[act], sl[act] = _poly.area_and_slope(c, x[act], slope=True)
    return np.clip(h, 0.0, c.full_area), np.minimum(sl, 0.0), act


# ---------------------------------------------------------------------- finite-particle correction
#: Thickness of the finite-particle surface layer in particle diameters, ``k`` in ``delta = k d``:
#: least squares over the project's DEM runs marked "fit" (``src/rotarydryer/data/dem/``, fitted by
#: ``rotarydryer.dem.fit.fit_report``: k = 1.514 on the five fit runs; docs/dem.md); the seven
#: held-out runs validate it (pooled RMS 3.7 % of a full flight against 5.7 % without).
SURFACE_LAYER = 1.51
#: particles larger than this fraction of the flight base s1 are refused
MAX_PARTICLE_FRACTION = 0.25


def surface_layer_thickness(s1: float, particle_diameter, surface_layer=None) -> float:
    """``delta = k d`` (m) for particles of ``particle_diameter`` (m) on flights of base ``s1`` (m)."""
    try:
        d = float(particle_diameter)
        ok = math.isfinite(d) and d >= 0.0
    except (TypeError, ValueError):
        ok = False
    if not ok:
        d = float(check_range("particle_diameter", particle_diameter, 0.0, math.inf, low_inclusive=True, unit="m"))
    if d > MAX_PARTICLE_FRACTION * s1:
        raise ValueError(
            f"particle_diameter = {fmt_number(d)} m is larger than a quarter of the flight base s1 = {fmt_number(s1)} m "
            f"(d/s1 = {d / s1:.3g}); the allowed range is [0, {fmt_number(MAX_PARTICLE_FRACTION * s1)}] m: the "
            "flight would hold a handful of particles and no continuum model applies")
    k = SURFACE_LAYER if surface_layer is None else float(
        check_range("surface_layer", surface_layer, 0.0, 20.0, low_inclusive=True, high_inclusive=True))
    return k * d


def _both_I(c: _Consts, psi, phi):
    """Lee (2008) Eq. 4.14 and its slope (m^2, m^2/deg) sharing the trigonometry."""
    aft = c.alpha_ft * _DEG
    delta = (psi + c.psi_ft + 0.5 * c.psi_fl - phi) * _DEG
    s = np.sin(aft + delta)
    k = 0.5 * c.s_ft**2 * math.sin(aft)
    return c.full_area - k * np.sin(delta) / s, -k * math.sin(aft) / (s * s) * _DEG


def _both_II(c: _Consts, psi, phi):
    """Lee (2008) Eq. 4.15 and its slope."""
    eps = (psi + c.psi_ft + 0.5 * c.psi_fl - c.alpha_a - phi) * _DEG
    zeta = (180.0 + c.alpha_ft + c.alpha_a - c.a2) * _DEG
    s = np.sin(eps + zeta)
    k = 0.5 * c.s_a**2 * math.sin(zeta)
    return c.full_area - c.area_tri_ft - k * np.sin(eps) / s, -k * math.sin(zeta) / (s * s) * _DEG


def _both_III(c: _Consts, psi, phi):
    """Lee (2008) Eq. 4.16 and its slope."""
    k = c.RF / c.R
    u = (psi + c.psi_ft + 90.0 - phi) * _DEG
    su = np.clip(k * np.sin(u), -1.0, 1.0)
    beta = (90.0 + phi - psi - c.psi_ft) * _DEG - np.arcsin(su)
    dbeta = -1.0 - k * np.cos(u) / np.sqrt(1.0 - su * su)
    h = 0.5 * c.R**2 * (c.psi_ft * _DEG + beta) - 0.5 * c.R * c.RF * np.sin(beta) - c.area_const3
    return h, (0.5 * c.R**2 - 0.5 * c.R * c.RF * np.cos(beta)) * dbeta * _DEG


def _both_IV(c: _Consts, psi, phi):
    """Lee (2008) Eq. 4.17 and its slope."""
    gam = (90.0 + phi + 180.0 - c.a2p - psi) * _DEG
    a2 = c.a2 * _DEG
    s = np.sin(a2 + gam)
    k = 0.5 * c.s2**2 * math.sin(a2)
    return k * np.sin(gam) / s, -k * math.sin(a2) / (s * s) * _DEG


_BOTH = (_both_I, _both_II, _both_III, _both_IV)


# Holdup and surface chord length L (tip to where the surface meets the pocket boundary), m^2 and m.
# L^2 / 2 = -dH/dpsi (per radian): L = s_ft sin(alpha_ft) / |sin(alpha_ft + delta)| in phase I, the
# same with s_a, zeta in II and s2, alpha2 in IV (Eq. 4.14, 4.15, 4.17: triangles with the surface
# as a side); phase III: the chord of the shell circle through the tip, L = R cos(asin(k sin u)) +
# R_F cos u (Eq. 4.16 geometry).
def _hL_I(c: _Consts, psi, phi):
    aft = c.alpha_ft * _DEG
    delta = (psi + c.psi_ft + 0.5 * c.psi_fl - phi) * _DEG
    s = np.sin(aft + delta)
    return c.full_area - 0.5 * c.s_ft**2 * math.sin(aft) * np.sin(delta) / s, c.s_ft * math.sin(aft) / np.abs(s)


def _hL_II(c: _Consts, psi, phi):
    eps = (psi + c.psi_ft + 0.5 * c.psi_fl - c.alpha_a - phi) * _DEG
    zeta = (180.0 + c.alpha_ft + c.alpha_a - c.a2) * _DEG
    s = np.sin(eps + zeta)
    k = 0.5 * c.s_a**2 * math.sin(zeta)
    return c.full_area - c.area_tri_ft - k * np.sin(eps) / s, c.s_a * abs(math.sin(zeta)) / np.abs(s)


def _hL_III(c: _Consts, psi, phi):
    k = c.RF / c.R
    u = (psi + c.psi_ft + 90.0 - phi) * _DEG
    su = np.clip(k * np.sin(u), -1.0, 1.0)
    asu = np.arcsin(su)
    beta = (90.0 + phi - psi - c.psi_ft) * _DEG - asu
    h = 0.5 * c.R**2 * (c.psi_ft * _DEG + beta) - 0.5 * c.R * c.RF * np.sin(beta) - c.area_const3
    return h, c.R * np.cos(asu) + c.RF * np.cos(u)


def _hL_IV(c: _Consts, psi, phi):
    gam = (90.0 + phi + 180.0 - c.a2p - psi) * _DEG
    a2 = c.a2 * _DEG
    s = np.sin(a2 + gam)
    return 0.5 * c.s2**2 * math.sin(a2) * np.sin(gam) / s, c.s2 * abs(math.sin(a2)) / np.abs(s)


_HL = (_hL_I, _hL_II, _hL_III, _hL_IV)


def _holdup_and_slope(c, psi, phi):
    """Holdup (m^2), its slope (m^2/deg) and the phase index in one pass over the phases (for a
    polygonal flight the index is 1 between psi1 and psi5, else 0 before and 5 after)."""
    if isinstance(c, PocketGeometry):
        h, sl, act = _poly_both(c, psi, phi)
        x = np.asarray(psi, dtype=float) - np.asarray(phi, dtype=float)
        return h, sl, np.where(act, 1, np.where(x < c.off1, 0, 5)).astype(np.int8)
    psi, phi = np.broadcast_arrays(np.asarray(psi, dtype=float), np.asarray(phi, dtype=float))
    idx = _phase_index(c, psi, phi)
    h = np.zeros(psi.shape)
    sl = np.zeros(psi.shape)
    h[idx == 0] = c.full_area
    with np.errstate(all="ignore"):
        for k, fn in enumerate(_BOTH, start=1):
            m = idx == k
            if m.any():
                h[m], sl[m] = fn(c, psi[m], phi[m])
    return np.clip(h, 0.0, c.full_area), np.minimum(sl, 0.0), idx


def _strip_area(c, w, h, L, delta):
    """The correction dA for wedge angles ``w`` (rad), holdups ``h`` (m^2) and surface chords ``L`` (m)."""
    with np.errstate(all="ignore"):
        de = np.fmin(delta, h / L)
        cot = np.maximum(1.0 / np.tan(np.minimum(w, math.pi)), 0.0)  # 0 for w >= 90 deg
        cut = de * cot
        da = np.where(cut < L, de * (L - 0.5 * cut), 0.5 * L * L / cot)
    return np.fmin(np.fmax(da, 0.0), c.full_area - h)


def finite_particle_correction(drum: FlightedDrum, psi, repose_angle, particle_diameter, surface_layer=None):
    """Extra holdup of a flight of particles over the continuum model, m^2 (``docs/dem.md``).

    The free surface of a bed of particles of diameter d stands a layer ``delta = k d`` above the
    continuum surface through the tip (the last particles rest on the thin tip and on each other,
    their centres and the envelope of the top layer lie above the plane through the tip). The
    extra solids are the strip of width ``delta`` over the surface chord, cut where the strip
    leaves the pocket at the chord through the tips (it curves down onto the tip):

    * surface chord length ``L = sqrt(2 |dH/dpsi|)`` (dH/dpsi per radian): rotating the plane
      surface by dpsi about the tip sweeps ``L^2/2 dpsi`` (exact for every phase of Lee (2008)
      Eq. 4.14-4.17, the area depending on psi - phi only);
    * wedge angle between the tip chord and the surface ``w = psi - psi1`` (Lee (2008) Eq. 4.9);
    * layer limited by the mean depth of the held solids ``H/L`` (a layer cannot stand on less);
    * ``dA = delta_e L - delta_e^2 cot(w)/2`` while the strip is longer than its cut-off
      (``delta_e cot w < L``), else ``L^2 tan(w) / 2``; ``cot w`` taken as 0 for ``w >= 90 deg``;
      and ``H + dA <= H_full`` (Lee (2008) Eq. 4.8).

    ``dA -> 0`` as ``d/s1 -> 0`` (``dA/H_full ~ k d/s1``). Vectorised over ``psi`` and ``repose_angle``."""
    psi, phi = _prepare(psi, repose_angle)
    c = drum._c
    h, sl, idx = _holdup_and_slope(c, psi, phi)
    return _fp_from(c, psi, phi, drum._layer(particle_diameter, surface_layer), h, sl, idx)


def _fp_from(c, psi, phi, delta, h, sl, idx):
    w = (np.asarray(psi, dtype=float) - phi - c.off1) * _DEG
    act = (idx > 0) & (idx < 5)
    da = np.zeros(h.shape)
    da[act] = _strip_area(c, w[act], h[act], np.sqrt(sl[act] * (-2.0 / _DEG)), delta)
    return da


def _holdup_fp(c, psi, phi, delta):
    """Holdup with the finite-particle correction, m^2 ([`finite_particle_correction`][rotarydryer.geometry.drum.finite_particle_correction])."""
    if delta == 0.0:
        return _holdup(c, psi, phi)
    if isinstance(c, PocketGeometry):
        h, sl, act = _poly_both(c, psi, phi)
        x = np.broadcast_to(np.asarray(psi, dtype=float) - np.asarray(phi, dtype=float), h.shape)
        out = h.copy()
        if act.any():
            ha = h[act]
            L = np.sqrt(sl[act] * (-2.0 / _DEG))      # L^2/2 = -dH/dpsi per radian
            out[act] = ha + _strip_area(c, (x[act] - c.off1) * _DEG, ha, L, delta)
        return out
    psi, phi = np.broadcast_arrays(np.asarray(psi, dtype=float), np.asarray(phi, dtype=float))
    x = psi - phi
    idx = _phase_index(c, psi, phi)
    out = np.where(idx == 0, c.full_area, 0.0)
    act = (idx > 0) & (idx < 5)
    if not act.any():
        return out
    pa, fa, ia = psi[act], phi[act], idx[act]
    h = np.empty(pa.shape)
    L = np.empty(pa.shape)
    with np.errstate(all="ignore"):
        for k, fn in enumerate(_HL, start=1):
            m = ia == k
            if m.any():
                h[m], L[m] = fn(c, pa[m], fa[m])
    np.clip(h, 0.0, c.full_area, out=h)
    out[act] = h + _strip_area(c, (x[act] - c.off1) * _DEG, h, L, delta)
    return out


_FD_STEP = 1e-4  # deg


def _holdup_slope_fp(c, psi, phi, delta):
    """Slope of `_holdup_fp`, m^2/deg (central difference, <= 0)."""
    if delta == 0.0:
        return _holdup_slope(c, psi, phi)
    psi, phi = np.broadcast_arrays(np.asarray(psi, dtype=float), np.asarray(phi, dtype=float))
    hp = _holdup_fp(c, psi + _FD_STEP, phi, delta)
    hm = _holdup_fp(c, psi - _FD_STEP, phi, delta)
    return np.minimum((hp - hm) / (2.0 * _FD_STEP), 0.0)


def _H(c, psi, phi, delta=None):
    """Holdup for the internal callers: the continuum model for ``delta is None``."""
    if delta is None:
        return _holdup(c, psi, phi)
    return _holdup_fp(c, psi, phi, delta)


def _S(c, psi, phi, delta=None):
    """Holdup slope for the internal callers: the continuum model for ``delta is None``."""
    if delta is None:
        return _holdup_slope(c, psi, phi)
    return _holdup_slope_fp(c, psi, phi, delta)


def _holdup_slope(c, psi, phi):
    if isinstance(c, PocketGeometry):
        return _poly_evaluate(c, psi, phi, slope=True)
    return _evaluate(c, psi, phi, slope=True)


def _clip_halfplane(poly: np.ndarray, point: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Keep the part of polygon ``poly`` where ``(p - point) . normal <= 0``.

    One step of Sutherland-Hodgman clipping against a single half-plane; exact for
    any simple polygon as far as the area and the drawn outline are concerned.
    """
    dist = (poly - point) @ normal
    out = []
    n = len(poly)
    for i in range(n):
        p, q = poly[i], poly[(i + 1) % n]
        dp, dq = dist[i], dist[(i + 1) % n]
        if dp <= 0.0:
            out.append(p)
        if (dp < 0.0 < dq) or (dq < 0.0 < dp):
            t = dp / (dp - dq)
            out.append(p + t * (q - p))
    return np.array(out) if out else np.empty((0, 2))
