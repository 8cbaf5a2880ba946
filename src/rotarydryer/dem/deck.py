"""LIGGGHTS 3.8 deck for a thin periodic axial slice of a flighted drum.

The slice is ``n_layers`` particle diameters thick in the axial direction ``z`` (periodic), the
drum axis is the ``z`` axis, gravity points along ``-y`` and the drum turns anticlockwise seen
from ``+z`` (the convention of `rotarydryer.geometry.drum`: the root of the flight at
``psi`` sits at ``(R sin psi, -R cos psi)``). Shell and flights are written as ASCII STL by
NumPy: the shell is a polygon of facets at most ``facet_size`` particle diameters long (the
chord error of the polygon is below 0.1 % of the radius), each flight is one plate per section
(base and tip of a two-section flight, every section of a polygonal flight) cut into facets of the
same size. Walls and particles share one material (atom types 1 and
2 carry the same properties; the wall friction may differ).

The run: particles are poured in passes into a box inside the tip circle (``fix insert/pack``, at
most 20 % solids per pass), settle for
``settle_time`` with the drum at rest, then the drum turns at ``rpm`` (``fix move/mesh rotate``
of both meshes) for ``spinup_revolutions`` before the dumps start, then ``record_revolutions``
are recorded: particle positions and velocities every ``dump_every_deg`` of drum rotation
(``post/particles.dump``) and the drum angle at the same steps (``post/drum_angle.txt``).

Contact model: Hertz-Mindlin with history (``pair_style gran model hertz tangential history``)
and the constant directional torque rolling friction (``rolling_friction cdt``), the standard
LIGGGHTS 3.8 granular model (LIGGGHTS-PUBLIC documentation, ``pair_gran``; Ai et al. (2011)
Powder Technol. 206, 269, model A for the rolling resistance). The time step is a fraction of
the Rayleigh time ``T_R = pi r sqrt(rho / G) / (0.1631 nu + 0.8766)`` (Li et al. (2005) Chem.
Eng. Sci. 60, 2253, Eq. 19; ``G = E / (2 (1 + nu))``).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from .._io import json_text, output_set, write_text_atomic
from .._validation import check_range, fmt_number
from ..geometry import FlightedDrum, PolygonFlight, TwoSectionFlight
from ..geometry.drum import check_speed

__all__ = ["Particles", "SliceDeck", "DeckFiles", "export_deck", "build_slice", "rayleigh_time", "pocket_mouth_width",
           "ARCHING_MOUTH_DIAMETERS",
           "MAX_DIAMETER_FRACTION", "MAX_PARTICLES", "MAX_FACETS", "MAX_DUMP_ROWS", "MAX_SEED", "stl_text", "shell_facets", "flight_facets", "DECK_FORMAT"]

#: particles larger than this fraction of the flight base s1 are refused (the flight would hold a
#: handful of particles and neither the geometric model nor its correction means anything)
MAX_DIAMETER_FRACTION = 0.25
#: most particles one slice deck may hold (a slice is meant for a workstation LIGGGHTS run of
#: minutes to hours; above it the deck is refused, with the smallest diameter that fits)
MAX_PARTICLES = 200_000
#: most triangles of the two STL meshes together (ASCII STL: about 250 bytes each, ~100 MB)
MAX_FACETS = 400_000
#: most particle rows of the recorded dump (frames x particles; ~110 bytes each, ~1 GB)
MAX_DUMP_ROWS = 10_000_000
#: largest random seed (LIGGGHTS takes a prime above 10 000 that fits a 32-bit int)
MAX_SEED = 2_000_000_000
DECK_FORMAT = "rotarydryer-dem-slice/1"
GRAVITY = 9.81  # m/s^2, as rotarydryer.geometry.unloading.GRAVITY


@dataclass(frozen=True)
class Particles:
    """Monodisperse spheres and their contact properties (SI units).

    diameter (m), density (kg/m^3, solid), friction (sliding, particle-particle, -), rolling_friction
    (-), restitution (-), youngs_modulus (Pa; a few MPa is the usual soft-particle choice that keeps
    the packing and the flow and allows a large time step), poisson_ratio (-), wall_friction (-, the
    sliding friction against shell and flights; default: ``friction``), wall_rolling_friction (-, the
    rolling friction against shell and flights; default: ``rolling_friction``)."""

    diameter: float = 0.01
    density: float = 2500.0
    friction: float = 0.5
    rolling_friction: float = 0.1
    restitution: float = 0.5
    youngs_modulus: float = 5.0e6
    poisson_ratio: float = 0.3
    wall_friction: float | None = None
    wall_rolling_friction: float | None = None

    def __post_init__(self):
        check_range("particle diameter (--diameter)", self.diameter, 0.0, 1.0, unit="m")
        check_range("particle density (--density)", self.density, 10.0, 30000.0, unit="kg/m^3")
        check_range("sliding friction (--friction)", self.friction, 0.0, 10.0, low_inclusive=True)
        check_range("rolling friction (--rolling-friction)", self.rolling_friction, 0.0, 1.0, low_inclusive=True)
        check_range("restitution (--restitution)", self.restitution, 0.0, 1.0)
        check_range("Young's modulus (--youngs-modulus)", self.youngs_modulus, 1.0e4, 1.0e12, unit="Pa")
        check_range("Poisson ratio (--poisson-ratio)", self.poisson_ratio, 0.0, 0.5)
        if self.wall_friction is not None:
            check_range("wall friction (--wall-friction)", self.wall_friction, 0.0, 10.0, low_inclusive=True)
        if self.wall_rolling_friction is not None:
            check_range("wall rolling friction (--wall-rolling-friction)", self.wall_rolling_friction, 0.0, 1.0,
                        low_inclusive=True, high_inclusive=True)

    @property
    def wall_mu(self) -> float:
        return self.friction if self.wall_friction is None else float(self.wall_friction)

    @property
    def wall_rolling_mu(self) -> float:
        return self.rolling_friction if self.wall_rolling_friction is None else float(self.wall_rolling_friction)

    @property
    def volume(self) -> float:
        """Volume of one particle, m^3."""
        return math.pi * self.diameter**3 / 6.0

    @property
    def mass(self) -> float:
        return self.density * self.volume


def pocket_mouth_width(drum: FlightedDrum) -> float:
    """Width of a flight pocket's mouth, m: the distance from the tip to the next flight (its base or
    tip plate). Below about five particle diameters the particles arch across it (as in a hopper
    outlet) and the flight holds its load longer than any surface-angle model says."""
    tip = drum.flight_outline(0.0)[-1]
    nxt = drum.flight_outline(drum.flight_spacing)
    out = math.inf
    for a, b in zip(nxt[:-1], nxt[1:]):
        ab = b - a
        t = min(max(float((tip - a) @ ab) / float(ab @ ab), 0.0), 1.0) if float(ab @ ab) > 0 else 0.0
        out = min(out, float(np.linalg.norm(tip - a - t * ab)))
    return out


#: pocket mouths narrower than this many particle diameters arch (export warns)
ARCHING_MOUTH_DIAMETERS = 5.0


def rayleigh_time(p: Particles) -> float:
    """Rayleigh time of the particles, s (Li et al. (2005) Eq. 19)."""
    G = p.youngs_modulus / (2.0 * (1.0 + p.poisson_ratio))
    return math.pi * 0.5 * p.diameter * math.sqrt(p.density / G) / (0.1631 * p.poisson_ratio + 0.8766)


@dataclass(frozen=True)
class SliceDeck:
    """Everything a slice deck is made of (also written to ``deck.json`` beside the deck).

    ``segments`` (``[[length_m, angle_deg], ...]``, a [`PolygonFlight`][rotarydryer.geometry.flights.PolygonFlight]) describes a
    flight of any shape; ``s1``, ``s2``, ``alpha1``, ``alpha2`` then repeat its first two sections. None:
    the two-section flight ``s1``, ``s2``, ``alpha1``, ``alpha2``."""

    radius: float
    n_flights: int
    s1: float
    s2: float
    alpha1: float
    alpha2: float
    rpm: float
    particles: Particles
    n_particles: int
    n_layers: float = 4.0
    settle_time: float = 1.0
    spinup_revolutions: float = 0.5
    record_revolutions: float = 1.0
    dump_every_deg: float = 2.0
    timestep_fraction: float = 0.15
    facet_size: float = 1.5
    seed: int = 5778
    source: str = "cli dimensions"
    loading: float | None = None
    fill_fraction: float | None = None
    extra: dict = field(default_factory=dict)
    #: the step counts written into deck.json at export (the reader uses them, not a recomputation)
    recorded_steps: dict | None = field(default=None, compare=False)
    #: a polygonal flight, ``[[length_m, angle_deg], ...]`` from the root; None: the two-section flight
    segments: list | None = None

    @property
    def drum(self) -> FlightedDrum:
        if self.segments is not None:
            return FlightedDrum(self.radius, self.n_flights, PolygonFlight([tuple(x) for x in self.segments]))
        return FlightedDrum(self.radius, self.n_flights, TwoSectionFlight(self.s1, self.s2, self.alpha1, self.alpha2))

    @property
    def flight_text(self) -> str:
        """The flight for a deck's header and for messages."""
        if self.segments is not None:
            return "sections " + ", ".join(f"({fmt_number(a)} m, {fmt_number(b)} deg)" for a, b in self.segments)
        return f"s1 = {self.s1:g} m, s2 = {self.s2:g} m, alpha1 = {self.alpha1:g} deg, alpha2 = {self.alpha2:g} deg"

    @property
    def length(self) -> float:
        """Axial thickness of the periodic slice, m."""
        return self.n_layers * self.particles.diameter

    @property
    def timestep(self) -> float:
        return self.timestep_fraction * rayleigh_time(self.particles)

    @property
    def period(self) -> float:
        """One drum revolution, s."""
        return 60.0 / self.rpm

    @property
    def froude(self) -> float:
        """Froude number omega^2 R / g of the drum, -."""
        w = 2.0 * math.pi * self.rpm / 60.0
        return w * w * self.radius / GRAVITY

    def steps(self) -> dict:
        """Step counts of the three stages and the dump interval."""
        dt = self.timestep
        settle = int(math.ceil(self.settle_time / dt))
        pour = (len(insertion_passes(self)) - 1) * _fall_steps(self)
        dump_every = max(1, int(round(self.dump_every_deg / 360.0 * self.period / dt)))
        spin = int(math.ceil(self.spinup_revolutions * self.period / dt / dump_every)) * dump_every
        record = int(math.ceil(self.record_revolutions * self.period / dt / dump_every)) * dump_every
        return {"pour": pour, "settle": settle, "spinup": spin, "record": record, "dump_every": dump_every,
                "rotation_start": pour + settle, "total": pour + settle + spin + record}

    def to_dict(self) -> dict:
        d = asdict(self)
        d.pop("recorded_steps", None)
        if d.get("segments") is None:
            d.pop("segments", None)          # a two-section flight: deck.json as before polygonal flights
        d["particles"] = asdict(self.particles)
        d["format"] = DECK_FORMAT
        d["derived"] = {"timestep_s": self.timestep, "period_s": self.period, "froude": self.froude,
                        "slice_length_m": self.length, "rayleigh_time_s": rayleigh_time(self.particles),
                        "d_over_s1": self.particles.diameter / self.s1,
                        "pocket_mouth_in_d": pocket_mouth_width(self.drum) / self.particles.diameter,
                        "steps": self.recorded_steps or self.steps(),
                        "full_holdup_area_m2": self.drum.full_holdup_area}
        return d

    @classmethod
    def from_dict(cls, d: dict) -> SliceDeck:
        if d.get("format") != DECK_FORMAT:
            raise ValueError(f"deck.json: format = {d.get('format')!r} is not {DECK_FORMAT!r} (not a deck written by "
                             "rotarydryer dem export)")
        steps = (d.get("derived") or {}).get("steps")
        d = {k: v for k, v in d.items() if k not in ("format", "derived", "recorded_steps")}
        d["particles"] = Particles(**d["particles"])
        return cls(**d, recorded_steps=steps)


def build_slice(drum: FlightedDrum, particles: Particles, *, rpm: float, loading: float | None = None,
                fill_fraction: float | None = None, repose_guess: float = 35.0, packing_guess: float = 0.6,
                source: str = "cli dimensions", **kw) -> SliceDeck:
    """A `SliceDeck` for a drum, particles and either a dryer ``loading`` (ratio to the geometric
    design load, Lee (2008) Eq. 4.20, at ``repose_guess``) or a ``fill_fraction`` of the drum
    cross-section (bulk solids).

    Refuses particles larger than `MAX_DIAMETER_FRACTION` of the flight base and speeds at or
    above the critical speed."""

    d = particles.diameter
    s1 = drum.flight.s1
    if d > MAX_DIAMETER_FRACTION * s1:
        raise ValueError(
            f"particle diameter (--diameter) = {fmt_number(d)} m is larger than a quarter of the flight base "
            f"s1 = {fmt_number(s1)} m (d/s1 = {d / s1:.3g}); the allowed range is (0, "
            f"{fmt_number(MAX_DIAMETER_FRACTION * s1)}] m: a flight must hold many particles for the "
            "geometric model and its finite-particle correction to apply")
    rpm = check_speed("rpm (--rpm)", rpm, drum.radius, radius_key="radius", warn=False)
    if (loading is None) == (fill_fraction is None):
        raise ValueError("give exactly one of loading (--loading, ratio to the design load) and fill_fraction "
                         "(--fill, fraction of the drum cross-section)")
    n_layers = float(kw.get("n_layers", 4.0))
    check_range("n_layers (--layers)", n_layers, 1.0, 100.0, low_inclusive=True, high_inclusive=True)
    if loading is not None:
        check_range("loading (--loading)", loading, 0.0, 5.0, high_inclusive=True)
        area = float(drum.design_load_area(repose_guess)) * float(loading)
    else:
        check_range("fill_fraction (--fill)", fill_fraction, 0.0, 0.6, high_inclusive=True)
        area = math.pi * drum.radius**2 * float(fill_fraction)
    mouth = pocket_mouth_width(drum) / d
    if mouth < ARCHING_MOUTH_DIAMETERS:

        warnings.warn(f"the pocket mouth (flight tip to the next flight) is {mouth:.1f} particle diameters wide, "
                      f"less than {ARCHING_MOUTH_DIAMETERS:g}: the particles may arch across it and the flights hold "
                      "their load longer than the geometric model (with or without the correction) says",
                      stacklevel=2)
    seed = kw.get("seed", 5778)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= int(seed) <= MAX_SEED:
        raise ValueError(f"seed (--seed) = {seed!r} is outside the allowed range: an integer from 0 to {MAX_SEED} "
                         "(made a prime > 10000 for LIGGGHTS)")
    n_est = area * n_layers * d * packing_guess / particles.volume
    if not math.isfinite(n_est) or n_est > MAX_PARTICLES:
        d_min = d * math.sqrt(n_est / MAX_PARTICLES) if math.isfinite(n_est) else float("nan")
        if math.isfinite(d_min) and d_min > 0:      # rounded up at 3 digits: the diameter advised is accepted
            step = 10.0 ** (math.floor(math.log10(d_min)) - 2)
            d_min = math.ceil(d_min / step * (1 - 1e-12)) * step
        raise ValueError(f"particle diameter (--diameter) = {fmt_number(d)} m gives a slice of {n_est:.3g} particles "
                         f"in a drum of radius {fmt_number(drum.radius)} m; the limit is {MAX_PARTICLES} particles "
                         f"per deck: give --diameter >= {d_min:.3g} m, or a smaller --loading, --fill or --layers")
    n = int(round(n_est))
    if n < 1:
        raise ValueError(f"the slice would hold {n} particles: increase loading (--loading) or fill (--fill)")
    f = drum.flight
    if isinstance(f, TwoSectionFlight):
        dims = dict(s1=f.s1, s2=f.s2, alpha1=f.alpha1, alpha2=f.alpha2, segments=None)
    else:
        segs = [[float(a), float(b)] for a, b in f.segments]
        two = segs[1] if len(segs) > 1 else [0.0, 180.0]
        dims = dict(s1=segs[0][0], s2=two[0], alpha1=segs[0][1], alpha2=two[1], segments=segs)
    deck = SliceDeck(radius=drum.radius, n_flights=drum.n_flights, **dims, rpm=float(rpm), particles=particles,
                     n_particles=n, source=source,
                     loading=None if loading is None else float(loading),
                     fill_fraction=None if fill_fraction is None else float(fill_fraction), **kw)
    check_deck_size(deck)
    return deck


def facet_count(s: SliceDeck) -> int:
    """Triangles of ``shell.stl`` and ``flights.stl`` together (as `shell_facets` and
    `flight_facets` make them, one axial cell), without building them."""
    facet = s.facet_size * s.particles.diameter
    n = 2 * max(48, int(math.ceil(2.0 * math.pi * s.radius / facet)))
    lengths = [a for a, _ in s.segments] if s.segments is not None else [s.s1, s.s2]
    per_flight = sum(2 * max(1, int(math.ceil(seg / facet))) for seg in lengths if seg > 1e-12)
    return n + s.n_flights * per_flight


def check_deck_size(s: SliceDeck) -> None:
    """Refuse (ValueError naming the option and the bound) a deck whose meshes, dump interval or
    dump volume is beyond the documented limits (`MAX_FACETS`, one time step per dump,
    `MAX_DUMP_ROWS`), before anything is written."""
    nf = facet_count(s)
    if nf > MAX_FACETS:
        raise ValueError(f"particle diameter (--diameter) = {fmt_number(s.particles.diameter)} m gives STL meshes of "
                         f"{nf} facets (facets {s.facet_size:g} diameters long on a drum of radius "
                         f"{fmt_number(s.radius)} m); the limit is {MAX_FACETS}: give a larger --diameter")
    deg_per_step = 360.0 * s.timestep / s.period
    check_range("dump_every_deg (--dump-every)", s.dump_every_deg, deg_per_step, 360.0, unit="deg",
                low_inclusive=True, high_inclusive=True)
    st = s.steps()
    rows = (st["record"] // st["dump_every"] + 1) * s.n_particles
    if rows > MAX_DUMP_ROWS:
        raise ValueError(f"dump_every_deg (--dump-every) = {s.dump_every_deg:g} deg with {s.n_particles} particles "
                         f"over {s.record_revolutions:g} revolutions (--revolutions) gives {rows} dump rows; the limit is "
                         f"{MAX_DUMP_ROWS} (about 1 GB): give a larger --dump-every, fewer --revolutions or "
                         "fewer particles")


# ---------------------------------------------------------------------------- STL
def _strip(p: np.ndarray, q: np.ndarray, n: int, z0: float, z1: float, nz: int) -> np.ndarray:
    """Facets (k, 3, 3) of the rectangle swept by segment p->q (2-D) from z0 to z1, n x nz cells."""
    t = np.linspace(0.0, 1.0, n + 1)[:, None]
    xy = p[None, :] * (1 - t) + q[None, :] * t
    z = np.linspace(z0, z1, nz + 1)
    P = np.empty((n + 1, nz + 1, 3))
    P[..., :2] = xy[:, None, :]
    P[..., 2] = z[None, :]
    a, b = P[:-1, :-1], P[1:, :-1]
    c, e = P[1:, 1:], P[:-1, 1:]
    t1 = np.stack([a, b, c], axis=-2).reshape(-1, 3, 3)
    t2 = np.stack([a, c, e], axis=-2).reshape(-1, 3, 3)
    return np.concatenate([t1, t2])


def shell_facets(radius: float, length: float, facet: float, nz: int = 1) -> np.ndarray:
    """Facets of the shell (a polygon with sides of at most ``facet`` m), shape (k, 3, 3)."""
    n = max(48, int(math.ceil(2.0 * math.pi * radius / facet)))
    # polygon circumscribing nothing: vertices on a radius slightly larger so that the polygon's
    # mean radius equals the drum radius (area-preserving)
    rv = radius * math.sqrt((2.0 * math.pi / n) / math.sin(2.0 * math.pi / n))
    a = 2.0 * math.pi * np.arange(n + 1) / n
    pts = np.column_stack([rv * np.cos(a), rv * np.sin(a)])
    return np.concatenate([_strip(pts[i], pts[i + 1], 1, 0.0, length, nz) for i in range(n)])


def flight_facets(drum: FlightedDrum, length: float, facet: float, nz: int = 1, inset: float = 0.0) -> np.ndarray:
    """Facets of all flights (one plate per section: base and tip, or every section of a polygonal
    flight), at drum angle 0, shape (k, 3, 3).

    ``inset`` moves the root inward by that much (m) so that the plate does not touch the shell."""
    out = []
    for i in range(drum.n_flights):
        pts = drum.flight_outline(i * drum.flight_spacing)
        if inset:
            pts = pts.copy()
            pts[0] = pts[0] - inset * pts[0] / np.linalg.norm(pts[0])
        for p, q in zip(pts[:-1], pts[1:]):
            seg = float(np.linalg.norm(q - p))
            if seg <= 1e-12:
                continue
            out.append(_strip(p, q, max(1, int(math.ceil(seg / facet))), 0.0, length, nz))
    return np.concatenate(out)


def stl_text(facets: np.ndarray, name: str) -> str:
    """ASCII STL of facets (k, 3, 3) in m."""
    v1 = facets[:, 1] - facets[:, 0]
    v2 = facets[:, 2] - facets[:, 0]
    nrm = np.cross(v1, v2)
    nrm /= np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-300)
    rows = np.concatenate([nrm[:, None, :], facets], axis=1).reshape(-1, 12)
    fmt = ("  facet normal %.9e %.9e %.9e\n    outer loop\n      vertex %.9e %.9e %.9e\n"
           "      vertex %.9e %.9e %.9e\n      vertex %.9e %.9e %.9e\n    endloop\n  endfacet\n")
    body = "".join(fmt % tuple(r) for r in rows)
    return f"solid {name}\n{body}endsolid {name}\n"


# ---------------------------------------------------------------------------- deck
def _prime_seed(seed: int) -> int:
    """LIGGGHTS wants prime seeds above 10 000: the first prime >= 10 007 + seed."""
    n = 10007 + abs(int(seed))
    while any(n % k == 0 for k in range(2, int(n**0.5) + 1)):
        n += 1
    return n


@dataclass(frozen=True)
class DeckFiles:
    folder: Path
    input: Path
    meta: Path
    shell: Path
    flights: Path


def insertion_passes(s: SliceDeck) -> list[int]:
    """Particles poured in each insertion pass: at most 20 % solids by volume in the pouring box
    (random sequential insertion stalls near 30 %), the rest in further passes."""
    r_ins = _insertion_radius(s)
    box_volume = (1.4 * r_ins) * (0.7 * r_ins) * s.length
    batch = max(1, int(0.2 * box_volume / s.particles.volume))
    n, out = s.n_particles, []
    while n > 0:
        out.append(min(batch, n))
        n -= out[-1]
    return out


def _insertion_radius(s: SliceDeck) -> float:
    d = s.particles.diameter
    drum = s.drum
    if s.segments is None:
        inner = min(drum.tip_radius, s.radius - drum.flight.s1)
    else:                                   # the flights' innermost point
        inner = float(np.min(np.hypot(*drum.flight_outline(0.0).T)))
    return max(inner - 1.0 * d, 2 * d)


def _fall_steps(s: SliceDeck) -> int:
    """Steps for a pass to fall out of the pouring box (free fall over its height, x 1.5)."""
    h = 0.7 * _insertion_radius(s) + s.particles.diameter
    return int(math.ceil(1.5 * math.sqrt(2.0 * h / GRAVITY) / s.timestep))


def _insertion_text(s: SliceDeck, r_ins: float) -> str:
    Lz = s.length
    a = 0.7 * r_ins
    lines = [f"region ins block {-a:.9g} {a:.9g} 0.0 {a:.9g} 0.0 {Lz:.9g} units box"]
    passes = insertion_passes(s)
    seed = _prime_seed(s.seed)
    for i, n in enumerate(passes):
        lines.append(f"fix ins{i} all insert/pack seed {seed} distributiontemplate pdd1 insert_every once "
                     f"overlapcheck yes all_in yes particles_in_region {n} region ins")
        seed = _prime_seed(seed - 10007 + 1)
        if i < len(passes) - 1:
            lines.append(f"run {_fall_steps(s)}")
            lines.append(f"unfix ins{i}")
    return "\n".join(lines)


def deck_text(s: SliceDeck) -> str:
    p = s.particles
    st = s.steps()
    d = p.diameter
    R = s.radius
    Lz = s.length
    half = R * 1.02 + 2 * d
    r_ins = _insertion_radius(s)
    mu, muw, rf, rfw = p.friction, p.wall_mu, p.rolling_friction, p.wall_rolling_mu
    e = p.restitution
    dt = s.timestep
    thermo = max(1, st["total"] // 200)
    insertion = _insertion_text(s, r_ins)
    return f"""# LIGGGHTS 3.8 deck written by rotarydryer.dem (format {DECK_FORMAT})
# flighted drum slice: R = {R:g} m, {s.n_flights} flights ({s.flight_text}),
# {s.rpm:.6g} rev/min (Froude number {s.froude:.4g}), {s.n_particles} spheres of
# d = {d:g} m (d/s1 = {d / s.s1:.4g}), slice {s.n_layers:g} d thick (periodic in z)
atom_style      granular
atom_modify     map array
boundary        f f p
newton          off
communicate     single vel yes
units           si
processors      * * 1

region          domain block {-half:.9g} {half:.9g} {-half:.9g} {half:.9g} 0 {Lz:.9g} units box
create_box      2 domain

neighbor        {0.25 * d:.9g} bin
neigh_modify    delay 0

# material: type 1 particles, type 2 walls (shell and flights)
fix m1 all property/global youngsModulus peratomtype {p.youngs_modulus:.9g} {p.youngs_modulus:.9g}
fix m2 all property/global poissonsRatio peratomtype {p.poisson_ratio:.9g} {p.poisson_ratio:.9g}
fix m3 all property/global coefficientRestitution peratomtypepair 2 {e:.9g} {e:.9g} {e:.9g} {e:.9g}
fix m4 all property/global coefficientFriction peratomtypepair 2 {mu:.9g} {muw:.9g} {muw:.9g} {muw:.9g}
fix m5 all property/global coefficientRollingFriction peratomtypepair 2 {rf:.9g} {rfw:.9g} {rfw:.9g} {rfw:.9g}

pair_style      gran model hertz tangential history rolling_friction cdt
pair_coeff      * *
timestep        {dt:.9g}

fix gravi all gravity {GRAVITY} vector 0.0 -1.0 0.0

fix shell all mesh/surface file shell.stl type 2
fix flights all mesh/surface file flights.stl type 2
fix walls all wall/gran model hertz tangential history rolling_friction cdt mesh n_meshes 2 meshes shell flights

fix pts1 all particletemplate/sphere 15485863 atom_type 1 density constant {p.density:.9g} radius constant {0.5 * d:.9g}
fix pdd1 all particledistribution/discrete 32452843 1 pts1 1.0
fix integr all nve/sphere
compute rke all erotate/sphere
thermo_style    custom step atoms ke c_rke
thermo          {thermo}
thermo_modify   lost ignore norm no

# 1. pouring (in passes) and settling, drum at rest
{insertion}
run {st['settle']}

# 2. rotation at {s.rpm:.6g} rev/min (anticlockwise seen from +z); spin-up, then recording
variable step0 equal {st['rotation_start']}
variable stp equal step
variable theta equal (step-v_step0)*{dt:.12g}*360.0/{s.period:.12g}
fix rot1 all move/mesh mesh shell rotate origin 0. 0. 0. axis 0. 0. 1. period {s.period:.12g}
fix rot2 all move/mesh mesh flights rotate origin 0. 0. 0. axis 0. 0. 1. period {s.period:.12g}
run {st['spinup']}

shell mkdir post
dump dmp all custom {st['dump_every']} post/particles.dump id type x y z vx vy vz radius
dump_modify dmp sort id
fix ang all print {st['dump_every']} "${{stp}} ${{theta}}" file post/drum_angle.txt screen no title "# step drum_angle_deg"
run {st['record']}
"""


def export_deck(s: SliceDeck, folder) -> DeckFiles:
    """Write ``in.drum``, ``shell.stl``, ``flights.stl`` and ``deck.json`` to ``folder`` (atomic writes)."""

    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise ValueError(f"output folder {str(folder)!r} exists and is not a directory")
    d = s.particles.diameter
    facet = s.facet_size * d
    nz = 1
    check_deck_size(s)
    # every text is made before the first file is written: a refused deck leaves no folder
    deck = deck_text(s)
    meta = json_text(s.to_dict(), indent=1) + "\n"
    shell = stl_text(shell_facets(s.radius, s.length, facet, nz), "shell")
    flights = stl_text(flight_facets(s.drum, s.length, facet, nz, inset=0.0), "flights")
    files = DeckFiles(folder, folder / "in.drum", folder / "deck.json", folder / "shell.stl", folder / "flights.stl")
    with output_set(folder):        # all four or none: a failure keeps the previous deck
        write_text_atomic(files.shell, shell)
        write_text_atomic(files.flights, flights)
        write_text_atomic(files.meta, meta)
        write_text_atomic(files.input, deck)
    return files
