"""Flights: two-section flights (Lee (2008)) and flights of any polygonal shape.

Conventions (drawn in ``docs/geometry_conventions.png``):

* ``s1`` is the length of the flight **base** (from the root, where the flight is
  welded to the drum wall, to the bend), ``s2`` the length of the **tip** section
  (bend to tip), both in m. ``s2 = 0`` is a straight single-section flight.
* ``alpha1`` (deg) is the angle between the flight base and the drum wall measured
  inside the flight's pocket, i.e. on the side facing the direction of rotation.
  90 is a radial base; below 90 the base leans forward (into the pocket).
* ``alpha2`` (deg) is the interior angle between base and tip at the bend, the tip
  being bent forward (towards the direction of rotation). Lee's Invicta flights
  have ``alpha2 = 117``: the tip points 27 deg inward of the tangent direction.

Lee (2008) reduces a flight whose base is not perpendicular to the wall to an
*equivalent perpendicular flight*: the tip section is extended backwards until it
meets the radial line through the root (Lee (2008) Eq. 4.1-4.4).

A [`PolygonFlight`][rotarydryer.geometry.flights.PolygonFlight] is a polyline of any number of straight
sections in the same convention: the first angle is the base-to-wall angle (``alpha1``), every
further angle the interior angle at a bend between the previous section and the next (``alpha2``
for a two-section flight; 180 is straight on, below 180 the flight bends forward, above 180
backward). ``TwoSectionFlight(s1, s2, a1, a2)`` is ``PolygonFlight([(s1, a1), (s2, a2)])``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._validation import check_range, fmt_number

__all__ = ["TwoSectionFlight", "PolygonFlight", "MAX_SEGMENTS"]

#: most straight sections of a polygonal flight (a curved flight drawn with a few degrees per section)
MAX_SEGMENTS = 50


@dataclass(frozen=True)
class TwoSectionFlight:
    """A straight, unserrated two-section flight (Lee (2008) Fig. 4.2).

    Parameters
    ----------
    s1 : float
        Base length, m (> 0).
    s2 : float
        Tip length, m (>= 0; 0 is a straight single-section flight).
    alpha1 : float
        Base-to-wall angle inside the pocket, deg, in (0, 180); 90 is radial.
    alpha2 : float
        Interior base-to-tip angle at the bend, deg, in (0, 180]. Ignored (taken
        as 180, a straight continuation) when ``s2 == 0``.
    serration_width, serration_depth, serrations_per_metre : float, optional
        Triangular serrations of the tip (m, m, 1/m). When given, the tip length
        is replaced by the area-averaged tip length
        ``s2 - serration_width * serration_depth * serrations_per_metre / 2``
        (Sheehan's serrated-flight correction, Lee (2008) Eq. 4.18).

    Examples
    --------
    >>> f = TwoSectionFlight(s1=0.195, s2=0.183, alpha1=90.0, alpha2=117.0)
    >>> round(f.equivalent_s2, 3)
    0.183
    """

    s1: float
    s2: float
    alpha1: float = 90.0
    alpha2: float = 90.0
    serration_width: float = 0.0
    serration_depth: float = 0.0
    serrations_per_metre: float = 0.0
    # derived, perpendicular-equivalent quantities (Lee (2008) Eq. 4.1-4.4)
    equivalent_s1: float = field(init=False, repr=False)
    equivalent_s2: float = field(init=False, repr=False)
    equivalent_alpha1: float = field(init=False, repr=False)
    equivalent_alpha2: float = field(init=False, repr=False)

    def __post_init__(self) -> None:
        s1 = float(check_range("s1", self.s1, 0.0, math.inf, unit="m"))
        s2 = float(check_range("s2", self.s2, 0.0, math.inf, low_inclusive=True, unit="m"))
        a1 = float(check_range("alpha1", self.alpha1, 0.0, 180.0, unit="deg"))
        for name in ("serration_width", "serration_depth", "serrations_per_metre"):
            check_range(name, getattr(self, name), 0.0, math.inf, low_inclusive=True)
        cut = 0.5 * self.serration_width * self.serration_depth * self.serrations_per_metre
        if cut > 0.0:
            if cut >= s2:
                raise ValueError(
                    f"serrations remove {cut:g} m of the tip length s2 = {s2:g} m; "
                    "the area-averaged tip length must stay > 0"
                )
            s2 = s2 - cut
        if s2 == 0.0:
            a2 = 180.0
        else:
            a2 = float(
                check_range("alpha2", self.alpha2, 0.0, 180.0, high_inclusive=True, unit="deg")
            )
        object.__setattr__(self, "s1", s1)
        object.__setattr__(self, "alpha1", a1)
        # the nominal tip length stays visible as ``s2``; the effective one is used
        object.__setattr__(self, "_s2_effective", s2)
        object.__setattr__(self, "_alpha2_effective", a2)

        a1p = 90.0 - a1  # Lee (2008) Eq. 4.1
        a2p = a2 - a1p  # Lee (2008) Eq. 4.2
        if not 0.0 < a2p <= 180.0:
            raise ValueError(
                f"alpha2 = {fmt_number(self.alpha2)} deg with alpha1 = {fmt_number(a1)} deg gives an "
                f"equivalent tip angle alpha2' = {a2p:g} deg; the allowed range is (0, 180]: "
                "the tip would point back into the wall"
            )
        if abs(a1p) < 1e-12:
            s1p, s2p = s1, s2
        else:
            sin_a2p = math.sin(math.radians(a2p))
            # Lee (2008) Eq. 4.3-4.4 (sine rule in the triangle root, bend, equivalent bend)
            s1p = s1 * math.sin(math.radians(180.0 - a2)) / sin_a2p
            s2p = s2 + s1 * math.sin(math.radians(a1p)) / sin_a2p
        if s1p < 0.0 or s2p < 0.0:
            raise ValueError(
                f"alpha1 = {fmt_number(a1)} deg and alpha2 = {fmt_number(a2)} deg give a flight whose tip "
                "section, extended backwards, does not meet the radial line through the "
                "root inside the drum; use alpha1 closer to 90 deg"
            )
        object.__setattr__(self, "equivalent_alpha1", a1p)
        object.__setattr__(self, "equivalent_alpha2", a2p)
        object.__setattr__(self, "equivalent_s1", s1p)
        object.__setattr__(self, "equivalent_s2", s2p)

    @property
    def effective_s2(self) -> float:
        """Tip length used in the geometry, m (after the serration correction, Lee Eq. 4.18)."""
        return self._s2_effective  # type: ignore[attr-defined]

    @property
    def effective_alpha2(self) -> float:
        """Base-to-tip angle used in the geometry, deg (180 for a straight flight)."""
        return self._alpha2_effective  # type: ignore[attr-defined]

    def tip_radius(self, radius: float) -> float:
        """Flight-tip radius ``R_F`` in a drum of radius ``radius`` (m), Lee (2008) Eq. 4.6:
        ``R_F^2 = (R - s1')^2 + s2'^2 - 2 (R - s1') s2' cos(180 - alpha2')``."""
        x = float(check_range("radius", radius, 0.0, math.inf, unit="m")) - self.equivalent_s1
        s2p = self.equivalent_s2
        return math.sqrt(x * x + s2p * s2p - 2.0 * x * s2p * math.cos(math.radians(180.0 - self.equivalent_alpha2)))

    def to_polygon(self) -> PolygonFlight:
        """The same flight as a [`PolygonFlight`][rotarydryer.geometry.flights.PolygonFlight] (the serrated tip by its
        area-averaged length, Lee (2008) Eq. 4.18; a straight flight as one section)."""
        if self.effective_s2 == 0.0:
            return PolygonFlight([(self.s1, self.alpha1)])
        return PolygonFlight([(self.s1, self.alpha1), (self.effective_s2, self.effective_alpha2)])

    @property
    def root_to_tip(self) -> float:
        """Distance from the root to the tip, m (law of cosines in the triangle root, bend, tip)."""
        s1, s2, a2 = self.s1, self.effective_s2, math.radians(self.effective_alpha2)
        return math.sqrt(s1 * s1 + s2 * s2 - 2.0 * s1 * s2 * math.cos(a2))


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


def segments_intersect(p, q, a, b) -> np.ndarray:
    """Whether segments ``p[k]->q[k]`` and ``a[k]->b[k]`` (arrays (k, 2)) meet (touching counts)."""
    p, q, a, b = (np.asarray(v, dtype=float).reshape(-1, 2) for v in (p, q, a, b))
    r, s = q - p, b - a
    scale = np.maximum(np.maximum(np.hypot(*r.T), np.hypot(*s.T)), 1e-300)
    eps = 1e-12 * scale * scale
    d1 = _cross(*s.T, *(p - a).T)
    d2 = _cross(*s.T, *(q - a).T)
    d3 = _cross(*r.T, *(a - p).T)
    d4 = _cross(*r.T, *(b - p).T)
    proper = (((d1 > eps) & (d2 < -eps)) | ((d1 < -eps) & (d2 > eps))) & \
             (((d3 > eps) & (d4 < -eps)) | ((d3 < -eps) & (d4 > eps)))

    def on(c, u, v, d):     # point c on segment u->v, given the cross product d (collinear)
        lo, hi = np.minimum(u, v) - 1e-12 * scale[:, None], np.maximum(u, v) + 1e-12 * scale[:, None]
        return (np.abs(d) <= eps) & np.all((c >= lo) & (c <= hi), axis=1)

    return proper | on(p, a, b, d1) | on(q, a, b, d2) | on(a, p, q, d3) | on(b, p, q, d4)


@dataclass(frozen=True, init=False)
class PolygonFlight:
    """A flight of any number of straight sections: a polyline from the root on the drum wall to the tip.

    Parameters
    ----------
    segments : sequence of (length, angle)
        From the root: each section's length (m, > 0) and angle (deg). The first angle is the
        base-to-wall angle inside the pocket (``alpha1`` of [`TwoSectionFlight`][rotarydryer.geometry.flights.TwoSectionFlight],
        in (0, 180); 90 is radial); every further angle is the interior angle at the bend between
        the previous section and this one (``alpha2``, in (0, 360); 180 is straight on, below 180
        the section bends forward, towards the direction of rotation, above 180 backward).
    vertices : sequence of (x, y), keyword only
        Instead of ``segments``: the polyline's points (m) in the flight's own frame, the first
        the root ``(0, 0)``; ``x`` along the drum wall in the direction of rotation, ``y`` inward
        along the radius through the root.
    key : str, keyword only
        How messages name the input (``segments`` or ``vertices`` by default; e.g. ``flight.segments``
        for a case key).

    A polyline that does not start at the root (open: it does not close the pocket against the wall),
    that crosses itself, or whose sections are not > 0 long raises ``ValueError`` naming the key,
    the value and the allowed range. Whether it fits a drum (inside the shell, not past the axis,
    clear of the next flight, a pocket the tip sees whole: its last bend not bent backwards) is checked
    by [`FlightedDrum`][rotarydryer.geometry.drum.FlightedDrum]; a bend of 180 deg is no bend there (the
    flight holds exactly what the merged section holds).

    Examples
    --------
    >>> f = PolygonFlight([(0.195, 90.0), (0.1, 135.0), (0.09, 135.0)])
    >>> f.n_segments, round(float(f.tip[0]), 4), round(float(f.tip[1]), 4)
    (3, 0.1607, 0.2657)
    >>> PolygonFlight([(0.195, 90.0), (0.183, 117.0)]).as_two_section()
    TwoSectionFlight(s1=0.195, s2=0.183, alpha1=90.0, alpha2=117.0, serration_width=0.0, serration_depth=0.0, serrations_per_metre=0.0)
    """

    segments: tuple[tuple[float, float], ...]
    key: str = field(default="segments", repr=False, compare=False)

    def __init__(self, segments=None, *, vertices=None, key: str | None = None):
        if (segments is None) == (vertices is None):
            raise ValueError("give the flight as segments (length, angle) or as vertices (x, y), not both or neither")
        if vertices is not None:
            key = key or "vertices"
            segs = _segments_from_vertices(vertices, key)
        else:
            key = key or "segments"
            segs = _check_segments(segments, key)
        object.__setattr__(self, "segments", segs)
        object.__setattr__(self, "key", key)
        v = self.vertices
        _check_simple(v, key)

    # ---------------------------------------------------------------- derived
    @property
    def n_segments(self) -> int:
        """Number of straight sections."""
        return len(self.segments)

    @property
    def lengths(self) -> np.ndarray:
        """Section lengths from the root, m."""
        return np.array([s[0] for s in self.segments])

    @property
    def angles(self) -> np.ndarray:
        """Base-to-wall angle and the interior angles at the bends, deg."""
        return np.array([s[1] for s in self.segments])

    @property
    def directions(self) -> np.ndarray:
        """Direction of each section in the flight's frame, deg from the wall tangent (forward), anticlockwise."""
        a = self.angles
        return a[0] + np.concatenate([[0.0], np.cumsum(a[1:] - 180.0)])

    @property
    def vertices(self) -> np.ndarray:
        """Points of the polyline (m), shape (n_segments + 1, 2), in the flight's frame: root ``(0, 0)``,
        ``x`` forward along the wall, ``y`` inward along the radius through the root."""
        th = np.radians(self.directions)
        steps = self.lengths[:, None] * np.column_stack([np.cos(th), np.sin(th)])
        return np.vstack([np.zeros((1, 2)), np.cumsum(steps, axis=0)])

    @property
    def tip(self) -> np.ndarray:
        """The tip (last vertex), m, in the flight's frame."""
        return self.vertices[-1]

    @property
    def s1(self) -> float:
        """Length of the base (the first section), m: the flight size particle diameters are compared with."""
        return float(self.segments[0][0])

    @property
    def alpha1(self) -> float:
        """Base-to-wall angle, deg."""
        return float(self.segments[0][1])

    @property
    def developed_length(self) -> float:
        """Sum of the section lengths, m (the plate a flight is bent from)."""
        return float(self.lengths.sum())

    def as_two_section(self) -> TwoSectionFlight | None:
        """The [`TwoSectionFlight`][rotarydryer.geometry.flights.TwoSectionFlight] of a flight of one or two sections whose
        angles that class accepts (alpha1 in (0, 180), alpha2 in (0, 180]); else None."""
        if self.n_segments > 2:
            return None
        (s1, a1), (s2, a2) = self.segments[0], (self.segments[1] if self.n_segments == 2 else (0.0, 180.0))
        if not 0.0 < a2 <= 180.0:
            return None
        try:
            return TwoSectionFlight(s1, s2, a1, a2)
        except ValueError:
            return None

    def to_dict(self) -> dict:
        """``{"segments": [[length_m, angle_deg], ...]}``."""
        return {"segments": [[float(a), float(b)] for a, b in self.segments]}


def _check_segments(segments, key: str) -> tuple[tuple[float, float], ...]:
    if isinstance(segments, (str, bytes)) or any(isinstance(r, (str, bytes)) for r in segments):
        # a string iterates as characters: "abc" would read as three one-letter "pairs"
        raise ValueError(f"{key} = {segments!r} is not a list of (length, angle) pairs")
    try:
        rows = [tuple(r) for r in segments]
    except TypeError:
        raise ValueError(f"{key} = {segments!r} is not a list of (length, angle) pairs") from None
    if not 1 <= len(rows) <= MAX_SEGMENTS:
        raise ValueError(f"{key} has {len(rows)} sections; the allowed range is 1 to {MAX_SEGMENTS} "
                         "(length m, angle deg) pairs")
    out = []
    for k, r in enumerate(rows):
        if len(r) != 2:
            raise ValueError(f"{key}[{k}] = {list(r)!r} is not a (length, angle) pair")
        length = float(check_range(f"{key}[{k}].length", r[0], 0.0, math.inf, unit="m"))
        if k == 0:
            angle = float(check_range(f"{key}[0].angle (base to wall)", r[1], 0.0, 180.0, unit="deg"))
        else:
            angle = float(check_range(f"{key}[{k}].angle (interior angle at the bend)", r[1], 0.0, 360.0, unit="deg"))
        out.append((length, angle))
    return tuple(out)


def _segments_from_vertices(vertices, key: str) -> tuple[tuple[float, float], ...]:
    try:
        v = np.asarray(vertices, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{key} = {vertices!r} is not a list of (x, y) points in m") from None
    if v.ndim != 2 or v.shape[1] != 2:
        raise ValueError(f"{key} = {vertices!r} is not a list of (x, y) points in m")
    if not 2 <= len(v) <= MAX_SEGMENTS + 1:
        raise ValueError(f"{key} has {len(v)} points; the allowed range is 2 to {MAX_SEGMENTS + 1} (x, y) points")
    check_range(key, v, unit="m")           # finite
    if np.any(v[0] != 0.0):
        raise ValueError(f"{key}[0] = ({fmt_number(v[0, 0])}, {fmt_number(v[0, 1])}) m is not the root (0, 0): the "
                         "flight polyline is open (it must start at the drum wall, where the flight is welded)")
    d = np.diff(v, axis=0)
    lengths = np.hypot(d[:, 0], d[:, 1])
    for k, L in enumerate(lengths):
        if not L > 0.0:
            raise ValueError(f"{key}[{k + 1}] = {key}[{k}] = ({fmt_number(v[k, 0])}, {fmt_number(v[k, 1])}) m: a "
                             "section of zero length; the allowed range of a section's length is (0, inf) m")
    th = np.degrees(np.arctan2(d[:, 1], d[:, 0]))
    if not 0.0 < th[0] < 180.0:
        raise ValueError(f"{key}[1] = ({fmt_number(v[1, 0])}, {fmt_number(v[1, 1])}) m: the base points "
                         f"{-th[0]:.4g} deg below the drum wall; its angle to the wall must be in (0, 180) deg "
                         "(y > 0: into the drum)")
    turns = np.mod(th[1:] - th[:-1] + 180.0, 360.0)      # interior angle at each bend
    for k, a in enumerate(turns):
        if not 0.0 < a < 360.0:
            raise ValueError(f"{key}[{k + 2}]: the flight folds back onto itself at {key}[{k + 1}] (interior angle "
                             f"{a:g} deg; the allowed range is (0, 360) deg)")
    return tuple((float(L), float(a)) for L, a in zip(lengths, np.concatenate([[th[0]], turns])))


def _check_simple(v: np.ndarray, key: str) -> None:
    """Refuse a polyline whose non-adjacent sections meet (self-intersecting)."""
    n = len(v) - 1
    i, j = np.triu_indices(n, 2)
    if i.size == 0:
        return
    hit = segments_intersect(v[i], v[i + 1], v[j], v[j + 1])
    if hit.any():
        a, b = int(i[np.argmax(hit)]), int(j[np.argmax(hit)])
        raise ValueError(f"{key}: the flight polyline intersects itself (section {a} crosses section {b}); a flight "
                         "must be a simple polyline from the root to the tip")
