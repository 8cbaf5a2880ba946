"""Exact holdup of a flight of any polygonal shape: the pocket cut by the surface through the tip.

Lee's (2008, section 4.2) assumptions, for any flight: the solids a flight holds fill its pocket
(the region between the flight, the next flight, the drum wall and the chord through both tips;
full, it holds Lee (2008) Eq. 4.8) up to a plane free surface through the flight tip at the dynamic
angle of repose; nothing flows over the tip. The surface runs from the tip ``T`` into the pocket
until it first meets the pocket's boundary at ``H`` (the next flight, the shell or the flight
itself: Lee's phases I-IV, Lee (2008) Fig. 4.6-4.9); the chord ``T H`` cuts the pocket in two and
the flight holds the part on its own side (the boundary from ``H`` round to ``T`` through the shell
and the flight's base). Whenever the line through the tip meets the pocket in that chord only
(a flight bent forward whose tip is the pocket's innermost corner) this is the pocket clipped by the
half-plane below the surface; under a lip bent below the surface (a right-angle tip) the solids it
covers stay held, as in Lee's closed forms (Lee (2008) Eq. 4.14 with alpha2 = 90 deg).

The area follows from Green's theorem with the tip as origin: ``2A = oint (p - T) x dp`` round the
held part. The surface chord passes through ``T`` and adds nothing, so

* a straight edge ``p -> p + D`` (relative to ``T``) adds ``p x D``, and ``(1 - t) p x D`` from the
  point ``p + t D`` on (edges through the tip add nothing);
* the shell arc from root angle ``a2`` down to ``a1`` adds
  ``R^2 (a1 - a2) + R (T_x (cos a1 - cos a2) + T_y (sin a1 - sin a2))``,

summed from ``H`` round to ``T``: a prefix sum per pocket, one gather per angle. Rotating the
surface about the tip by ``dx`` sweeps ``|TH|^2/2 dx``, so ``dA/dx = -|TH|^2 / 2`` (per radian),
the ``-L^2/2`` of every phase of Lee (2008) Eq. 4.14-4.17.

The holdup depends on the root angle ``psi`` and the repose angle ``phi`` only through
``x = psi - phi``. The area is full before the surface leaves the tip chord (psi1, Lee (2008)
Eq. 4.9: discharge starts), zero once it lies along the flight's last section (psi5, Eq. 4.13: the
final discharge angle; from there on, as in Lee's model, empty: refilling at the bottom is not part
of it) and smooth between the angles at which the surface passes a vertex of the pocket (the
*events*; psi1-psi5 for a two-section flight).

Every accepted pocket is seen whole from the tip between psi1 and psi5 (else the held area would jump
somewhere: a hidden corner, a last bend bent backwards, a pocket reaching past the tip chord; refused),
so its boundary, from the next flight's tip ``T'`` round to this flight's last bend, turns one way about
the tip: the element (edge or arc) the surface meets at ``x`` is the one whose angular span holds ``x``
(a search in the sorted events). No intersection is tested against an edge's ends, which is
ill-conditioned where the surface grazes a nearly straight bend or an edge seen end-on. Straight bends
(interior angle within ``_STRAIGHT_TOL`` of 180 deg) are merged first: a polyline with a straight bend
is the pocket of the merged section, with the same holdup, slope and events.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._validation import fmt_number
from .flights import PolygonFlight, segments_intersect

__all__ = ["PocketGeometry", "pocket_geometry", "area_and_slope"]

_DEG = math.pi / 180.0
#: largest jump of the held area at an event, fraction of a full flight (a corner of the pocket
#: hiding part of it from the tip: the area would jump)
_JUMP_TOL = 1e-9
#: a bend whose interior angle is within this of 180 deg (deg) is straight: its two sections are merged
#: (moving the bend onto the merged section changes the pocket by < 1e-10 of its area)
_STRAIGHT_TOL = 1e-9


@dataclass(frozen=True, eq=False)
class PocketGeometry:
    """Fixed geometry of a drum of polygonal flights (SI units, angles in degrees).

    ``off1``..``off5`` are offsets of the root angle from the repose angle (``psi = phi + off``): discharge
    starts (``off1``), the surface passes the next flight's last bend (``off2``), the next flight's root
    (``off3``), this flight's root (``off4``), and the flight is empty (``off5``). ``breaks`` holds every
    event from ``off1`` to ``off5``; the area is smooth between neighbouring breaks. ``bounds`` are the
    events of the boundary's vertices in traversal order (non-decreasing, ``off1`` to ``off5``): element
    ``i`` (edge or arc) is the one the surface meets for ``bounds[i] <= x < bounds[i + 1]``."""

    R: float
    RF: float
    psi_fl: float
    psi_ft: float
    full_area: float
    off1: float
    off2: float
    off3: float
    off4: float
    off5: float
    breaks: tuple[float, ...]
    tip: np.ndarray = field(repr=False)          # T, drum frame of the flight at psi = 0
    px: np.ndarray = field(repr=False)           # straight edges from T' round to the root (traversal
    py: np.ndarray = field(repr=False)           # order, the arc between), start - T
    dx: np.ndarray = field(repr=False)           # edge vectors
    dy: np.ndarray = field(repr=False)
    k: np.ndarray = field(repr=False)            # (p - T) x D
    rest: np.ndarray = field(repr=False)         # Green sum of the boundary after each element, to T
    n_next: int = 0                              # edges of the next flight (before the arc)
    arc_whole: float = 0.0                       # Green integral of the whole arc (root' to root)
    orient: float = 1.0                          # +1: the boundary runs anticlockwise
    beta: float = 0.0                            # arc span, rad (root' at a = beta back to root at a = 0)
    bounds: np.ndarray = field(repr=False, default_factory=lambda: np.zeros(0))   # element spans, deg


def _flight_points(flight: PolygonFlight, R: float, psi_deg: float) -> np.ndarray:
    """Vertices of ``flight`` with its root at ``psi`` (deg), drum frame (m)."""
    return _placed(flight.vertices, R, psi_deg)


def _corners(flight: PolygonFlight) -> np.ndarray:
    """The flight's vertices without its straight bends (interior angle within ``_STRAIGHT_TOL`` of 180
    deg): the root, the real bends and the tip, flight frame (m)."""
    keep = np.abs(flight.angles[1:] - 180.0) > _STRAIGHT_TOL
    return flight.vertices[np.concatenate([[True], keep, [True]])]


def _placed(v: np.ndarray, R: float, psi_deg: float) -> np.ndarray:
    """Flight-frame points ``v`` (m) with the root at ``psi`` (deg), drum frame (m)."""
    p = math.radians(psi_deg)
    c, s = math.cos(p), math.sin(p)
    x, y = v[:, 0], v[:, 1] - R
    return np.column_stack([c * x - s * y, s * x + c * y])


def pocket_geometry(radius: float, n_flights: int, flight: PolygonFlight) -> PocketGeometry:
    """The [`PocketGeometry`][rotarydryer.geometry.polygon.PocketGeometry] of ``n_flights`` flights of shape ``flight`` in a drum of
    ``radius`` (m). Raises ``ValueError`` (naming the flight key, the value and the allowed range) for a
    flight that leaves the drum or reaches past its axis, overlaps its neighbours, or whose pocket the
    tip does not see whole (a hidden corner, a last bend bent backwards, a pocket reaching past the tip
    chord: the held area would jump). Straight bends are merged (`_corners`)."""
    R = float(radius)
    N = int(n_flights)
    key = flight.key
    psi_fl = 360.0 / N                                   # Lee (2008) Eq. 4.5
    local = _corners(flight)                             # straight bends merged
    if np.any(local[1:, 1] >= R):
        k = int(np.argmax(local[1:, 1] >= R)) + 1
        raise ValueError(f"{key}: vertex {k} of the flight is {fmt_number(local[k, 1])} m from the wall along the radius "
                         f"through the root; the allowed range is below radius = {fmt_number(R)} m (a flight must not "
                         "reach past the drum centre)")
    here = _placed(local, R, 0.0)
    r = np.hypot(here[:, 0], here[:, 1])
    if np.any(r[1:] >= R * (1.0 - 1e-12)):
        k = int(np.argmax(r[1:] >= R * (1.0 - 1e-12))) + 1
        raise ValueError(f"{key}: vertex {k} of the flight is {fmt_number(r[k])} m from the drum axis; the allowed range "
                         f"is below radius = {fmt_number(R)} m: the flight is longer than the drum radius allows (it "
                         "would leave the shell)")
    T = here[-1]
    RF = float(np.hypot(*T))
    psi_ft = math.degrees(math.atan2(T[0], -T[1]))     # Lee (2008) Eq. 4.7 (the tip's lead)
    _check_neighbours(flight, R, N, _flight_points(flight, R, 0.0), key)
    nxt = _placed(local, R, psi_fl)
    # the pocket's chain: root -> ... -> T -> T' -> ... -> root' (then the shell arc back to the root)
    chain = np.vstack([here, nxt[::-1]])
    _check_chain(chain, key)
    beta = psi_fl * _DEG
    # signed area: shoelace of the chain closed by the chord root' -> root, less the circular segment
    # between that chord and the arc (the arc runs clockwise round the axis, a decreasing)
    x, y = chain[:, 0], chain[:, 1]
    shoelace = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    signed = shoelace - 0.5 * R * R * (beta - math.sin(beta))
    orient = 1.0 if signed > 0 else -1.0
    # traversal from the tip: T -> T' (adds nothing), the next flight T' -> root', the arc root' -> root,
    # this flight root -> ... -> last bend, and its last section back to T (adds nothing)
    n_here = len(here)
    P = np.vstack([nxt[::-1][:-1], here[:-2]]) - T
    Q = np.vstack([nxt[::-1][1:], here[1:-1]]) - T
    D = Q - P
    kk = P[:, 0] * D[:, 1] - P[:, 1] * D[:, 0]
    n_next = len(nxt) - 1
    arc_whole = _arc_green(R, T, beta, 0.0)
    contrib = np.concatenate([kk[:n_next], [arc_whole], kk[n_next:]])
    rest = np.concatenate([np.cumsum(contrib[::-1])[::-1][1:], [0.0]])   # after each element, to T
    full_area = abs(signed)
    if abs(abs(float(np.sum(contrib))) * 0.5 - full_area) > 1e-9 * full_area:     # pragma: no cover - a bug guard
        raise ValueError(f"{key}: the pocket's area does not add up ({abs(float(np.sum(contrib))) / 2} != {full_area})")
    theta_c = math.degrees(math.atan2(*(nxt[-1] - T)[::-1]))          # tip chord T -> T'
    theta_r = math.degrees(math.atan2(*(here[-2] - T)[::-1]))         # last section T -> bend
    off1 = -theta_c                                   # the surface along the tip chord: Lee (2008) Eq. 4.9
    off1 = off1 - 360.0 * math.floor((off1 + 180.0) / 360.0)
    sweep = (theta_c - theta_r) % 360.0               # the surface turns (clockwise) through the pocket
    off5 = off1 + sweep                               # ... until it lies along the last section: Eq. 4.13
    geom = PocketGeometry(R=R, RF=RF, psi_fl=psi_fl, psi_ft=psi_ft, full_area=full_area, off1=off1, off2=off1,
                          off3=off1, off4=off1, off5=off5, breaks=(off1, off5), tip=T, px=P[:, 0].copy(),
                          py=P[:, 1].copy(), dx=D[:, 0].copy(), dy=D[:, 1].copy(), k=kk, rest=rest,
                          n_next=n_next, arc_whole=arc_whole, orient=orient, beta=beta)

    def event(p):
        a = math.degrees(math.atan2(p[1] - T[1], p[0] - T[0]))
        return off1 + (-a - off1) % 360.0

    events = np.array([event(p) for i, p in enumerate(chain) if i != n_here - 1])
    inner = np.sort(events[(events > off1 + 1e-9) & (events < off5 - 1e-9)])
    inner = inner[np.concatenate([[True], np.diff(inner) > 1e-9])] if inner.size else inner
    last_bend_next = nxt[-2] if len(nxt) > 2 else nxt[-1]    # a straight flight: its tip
    # the event of each vertex of the boundary in traversal order (T', the next flight, root', root, this
    # flight to its last bend), followed continuously along it from off1: a straight edge turns the surface
    # by the angle it subtends at the tip (signed, < 180 deg), the arc clockwise round the tip. Seen whole
    # from the tip they rise from off1 to off5 (_check_visible); each element's span runs from one to the
    # next (rounding evened out: clipped to [off1, off5], non-decreasing)
    V = np.vstack([nxt[::-1], here[:-1]]) - T
    turn = -np.degrees(np.arctan2(V[:-1, 0] * V[1:, 1] - V[:-1, 1] * V[1:, 0],
                                  V[:-1, 0] * V[1:, 0] + V[:-1, 1] * V[1:, 1]))
    turn[n_next] = (event(here[0]) - event(nxt[0])) % 360.0        # the arc, root' -> root
    ev = off1 + np.concatenate([[0.0], np.cumsum(turn)])
    bounds = np.maximum.accumulate(np.clip(ev, off1, off5))
    bounds[0], bounds[-1] = off1, off5
    geom = _replace(geom, off2=min(event(last_bend_next), off5), off3=min(event(nxt[0]), off5),
                    off4=min(event(here[0]), off5), breaks=(off1, *inner.tolist(), off5), bounds=bounds)
    _check_visible(geom, ev, flight)
    return geom


def _arc_green(R: float, T: np.ndarray, a_from: float, a_to: float) -> float:
    """Green integral ``int (p - T) x dp`` along the shell from root angle ``a_from`` to ``a_to`` (rad)."""
    F = lambda a: R * R * a + R * (T[0] * math.cos(a) + T[1] * math.sin(a))   # noqa: E731
    return F(a_to) - F(a_from)


def _check_neighbours(flight: PolygonFlight, R: float, N: int, here: np.ndarray, key: str) -> None:
    """Flights must not meet: this flight against the others whose angular span can reach it."""
    psi_fl = 360.0 / N
    ang = np.degrees(np.arctan2(here[:, 0], -here[:, 1]))
    span = float(np.max(np.abs(ang)))
    reach = min(N - 1, int(math.ceil(2.0 * span / psi_fl)) + 1)
    a, b = here[:-1], here[1:]
    for j in range(1, reach + 1):
        for sign in ((1,) if 2 * j == N else (1, -1)):
            other = _flight_points(flight, R, sign * j * psi_fl)
            c_, d_ = other[:-1], other[1:]
            ii, jj = np.meshgrid(np.arange(len(a)), np.arange(len(c_)), indexing="ij")
            if segments_intersect(a[ii.ravel()], b[ii.ravel()], c_[jj.ravel()], d_[jj.ravel()]).any():
                raise ValueError(f"{key}: flights overlap their neighbours: with n_flights = {N} (spacing "
                                 f"{psi_fl:.4g} deg) a flight meets the flight {j} place{'s' if j > 1 else ''} "
                                 f"{'ahead' if sign > 0 else 'behind'}; use fewer flights or a shorter flight")


def _check_chain(chain: np.ndarray, key: str) -> None:
    """The pocket's boundary (this flight, the tip chord, the next flight) must not cross itself."""
    n = len(chain) - 1
    i, j = np.triu_indices(n, 2)
    hit = segments_intersect(chain[i], chain[i + 1], chain[j], chain[j + 1])
    if hit.any():
        raise ValueError(f"{key}: the flight pocket is not a simple region: the chord from this flight's tip to the "
                         "next flight's tip crosses a flight; use fewer flights or a flight whose tip is its "
                         "outermost point towards the next flight")


def _replace(g: PocketGeometry, **kw) -> PocketGeometry:
    d = {f: getattr(g, f) for f in g.__dataclass_fields__}
    d.update(kw)
    return PocketGeometry(**d)


def _check_visible(geom: PocketGeometry, ev: np.ndarray, flight: PolygonFlight) -> None:
    """Refuse a pocket the tip cannot see whole, in order, from the start of discharge to psi5: somewhere the
    held area would jump, which the surface-through-the-tip model does not describe. ``ev`` are the events
    of the boundary's vertices in traversal order, followed continuously from the next flight's tip ``T'``
    (``off1``) to the last bend (``off5``); they must rise from one to the other (module docstring):

    * an event before ``off1``: the pocket reaches past the chord through the two tips (the next flight's
      tip is a reflex corner of it); the part beyond would be lost the moment discharge starts;
    * an event after ``off5``: the last section is bent backwards (or a corner hides part of the pocket):
      the solids behind it would still be held when the surface lies along it and vanish at psi5;
    * an event going back: a corner hides part of the pocket from the tip (a hook).

    "Before", "after" and "back" by more than ``tol``: the area such a turn could hide, ``(2R)^2/2`` per
    radian, below ``_JUMP_TOL`` of a full flight."""
    key = flight.key
    tol = math.degrees(_JUMP_TOL * geom.full_area / (2.0 * geom.R * geom.R))
    off1, off5 = geom.off1, geom.off5
    if np.any(ev < off1 - tol):
        lost = 1.0 - float(area_and_slope(geom, [off1 + 1e-7], slope=False)[0][0]) / geom.full_area
        raise ValueError(f"{key}: the flight pocket reaches past the chord through the two flight tips (seen from "
                         f"the tip a corner of it lies {off1 - float(np.min(ev)):.3g} deg beyond the chord; the "
                         f"allowed range is 0 deg: on the chord or inside it): as discharge starts (psi - phi = "
                         f"{off1:.4g} deg) the held area would jump by {lost:.2g} of a full flight, which Lee's model "
                         "(full up to the tip chord, Eq. 4.8) does not describe; use a shorter flight or a base angle "
                         "closer to 90 deg")
    bends = np.nonzero(np.abs(flight.angles[1:] - 180.0) > _STRAIGHT_TOL)[0] + 1
    if np.any(ev > off5 + tol) and bends.size and flight.angles[bends[-1]] > 180.0:
        k = int(bends[-1])
        held = float(area_and_slope(geom, [off5 - 1e-7], slope=False)[0][0]) / geom.full_area
        a = fmt_number(flight.angles[k])
        name = f"{key}[{k}].angle = {a} deg" if "segments" in key else f"the interior angle {a} deg at {key}[{k}]"
        raise ValueError(f"{key}: {name} bends the flight's last section backwards; the allowed range of the last "
                         f"bend is (0, 180] deg: the solids behind it ({held:.2g} of a full flight) would still be held "
                         f"when the surface through the tip lies along it (psi - phi = {off5:.4g} deg, psi5) and "
                         "vanish there, which Lee's model (surface through the tip) does not describe")
    back = np.nonzero(np.diff(ev) < -tol)[0]
    if back.size or np.any(ev > off5 + tol):
        at = float(ev[back[0]]) if back.size else off5
        raise ValueError(f"{key}: a corner of the flight pocket hides part of it from the tip (at psi - phi = "
                         f"{at:.4g} deg the surface through the tip passes it and the held area jumps): Lee's model "
                         "(surface through the tip) does not describe a flight with a hook; bend its sections so "
                         "that the whole pocket is seen from the tip")


def area_and_slope(g: PocketGeometry, x_deg, slope: bool = True):
    """Held area (m^2) and, with ``slope``, its derivative dA/dx (m^2 per degree) at offsets ``x = psi - phi`` (deg)
    in [off1, off5] (module docstring): the surface from the tip along ``e = (cos x, -sin x)`` (flight frame)
    to the point ``H`` where it meets the element of the pocket's boundary whose span holds ``x``, and the
    Green sum from ``H`` round to ``T``."""
    xd = np.asarray(x_deg, dtype=float).ravel()
    x = np.radians(xd)
    s, c = np.sin(x), np.cos(x)
    Tx, Ty = float(g.tip[0]), float(g.tip[1])
    R = g.R
    n_elem = g.bounds.size - 1
    elem = np.clip(np.searchsorted(g.bounds, xd, side="right") - 1, 0, n_elem - 1)
    on_arc = elem == g.n_next
    # straight edges: the ray T + r e meets p + t D at t = (p x e) / (e x D); t is clipped to the edge (an
    # edge seen nearly end-on has p x D ~ 0, so an ill-conditioned t moves the area by at most that)
    j = np.where(elem < g.n_next, elem, elem - 1)
    j = np.where(on_arc, 0, j)
    px, py, dx, dy, k = g.px[j], g.py[j], g.dx[j], g.dy[j], g.k[j]
    exD = c * dy + s * dx
    pxe = -(px * s) - py * c
    with np.errstate(divide="ignore", invalid="ignore"):
        t = pxe / exD
    t = np.where(np.isnan(t), 0.0, np.clip(t, 0.0, 1.0))
    two_a = (1.0 - t) * k + g.rest[elem]
    L = np.hypot(px + t * dx, py + t * dy)
    if on_arc.any():
        # the shell: |T + r e| = R, the positive root; its root angle lies on the pocket's arc [0, beta]
        ca, sa = c[on_arc], s[on_arc]
        te = Tx * ca - Ty * sa
        r_arc = -te + np.sqrt(te * te + R * R - (Tx * Tx + Ty * Ty))
        a = np.clip(np.arctan2(Tx + r_arc * ca, -(Ty - r_arc * sa)), 0.0, g.beta)
        two_a[on_arc] = R * R * (0.0 - a) + R * (Tx * (1.0 - np.cos(a)) + Ty * (0.0 - np.sin(a))) + g.rest[g.n_next]
        L[on_arc] = r_arc
    area = (g.orient * 0.5 * two_a).reshape(np.shape(x_deg))
    if not slope:
        return area, None
    return area, (-0.5 * L * L * _DEG).reshape(np.shape(x_deg))
