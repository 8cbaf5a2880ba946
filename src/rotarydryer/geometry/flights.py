"""Two-section flights and their perpendicular-equivalent geometry.

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
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from .._validation import check_range, fmt_number

__all__ = ["TwoSectionFlight"]


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

    @property
    def root_to_tip(self) -> float:
        """Distance from the root to the tip, m (law of cosines in the triangle root, bend, tip)."""
        s1, s2, a2 = self.s1, self.effective_s2, math.radians(self.effective_alpha2)
        return math.sqrt(s1 * s1 + s2 * s2 - 2.0 * s1 * s2 * math.cos(a2))
