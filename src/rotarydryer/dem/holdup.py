"""Flight holdup from DEM dumps, and its comparison with the geometric model.

For every recorded frame and every flight (root at ``psi_i = theta + i psi_fl``, ``theta`` the drum
angle): the particles whose centres lie in the flight's pocket (the region between this flight, the
next flight, the shell and the chord through both tips, Lee (2008) Eq. 4.8; the polygon of
`rotarydryer.geometry.FlightedDrum.pocket_polygon`) and that move with it (speed relative to
the rigid rotation below ``max(omega R, sqrt(g d))``) are counted. Their solid volume divided by
the packing fraction of the bulk and the slice thickness is the holdup area, m^2 per m of flight,
the quantity of Lee (2008) Eq. 4.14-4.17.

Measured beside it:

* **packing fraction of the bulk**: particle centres counted in vertical cylinders of radius
  2.5 d (through the whole periodic slice) centred on particles (not counted), at least 2.5 d from the shell and
  the flights; the cylinders inside the bulk are those within 15 % of the 95th percentile (the
  others cut a free surface); their median;
* **dynamic repose angle of unloading flights**: the top particle of every d-wide column of the
  held solids of flights whose tip is at 60-150 deg, those within 1.5 d of a flight or the shell
  dropped (there the top is a wall, not the free surface), a Theil-Sen line; the median of the
  flights' angles;
* **airborne fraction**: particles outside every pocket falling faster than ``sqrt(4 g d)``
  (the speed after a free fall of two diameters), averaged over the frames.

The comparison (`compare`) evaluates the geometric model at the measured repose angle with
and without the finite-particle correction, capped at the measured plateau (an under-loaded flight
holds ``f H0`` until ``H_max`` falls below it, Lee (2008) section 4.4.2), over the unloading range
(from the measured start of unloading to the later of the measured end and psi5): RMS and bias
(model minus DEM) as % of a full flight, and the start and end of unloading (holdup below 97 % of
the plateau; below 3 % of a full flight).
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._io import json_text, save_figure, write_text_atomic
from .deck import GRAVITY, SliceDeck
from .dumps import DumpFrames, read_dump

__all__ = ["DemHoldup", "analyse_run", "analyse_frames", "compare", "write_reduced_csv", "read_reduced_csv",
           "plot_comparison", "liggghts_version", "check_geometry", "BIN_DEG"]

BIN_DEG = 2.0  # deg, width of the angle bins of the reduced profile
_START_FRACTION = 0.97
_MIN_SURFACE_POINTS = 5
_LEVEL_UNTIL_DEG = 60.0  # a flight's level: its largest holdup between the bottom and this root angle  # top particles (away from the walls) needed for a surface angle
_END_FRACTION = 0.03


@dataclass
class DemHoldup:
    """Reduced DEM result of one slice run: one sample per recorded frame and flight (areas in m^2
    per m of flight)."""

    deck: SliceDeck
    frame: np.ndarray
    flight: np.ndarray
    psi_deg: np.ndarray
    holdup_area_m2: np.ndarray
    packing_fraction: float
    repose_angle_deg: float
    repose_angle_iqr_deg: float
    airborne_fraction: float
    n_particles: int
    n_frames: int
    liggghts_version: str = "unknown"
    extra: dict = field(default_factory=dict)

    @property
    def full_area(self) -> float:
        return self.deck.drum.full_holdup_area

    @property
    def loading(self) -> float:
        """Actual loading: particles in the slice over those of the design load (35 deg, packing 0.6)."""
        if not self.deck.loading:
            return float("nan")
        return self.n_particles / (self.deck.n_particles / self.deck.loading)

    def profile(self, bin_deg: float = BIN_DEG):
        """Mean and standard deviation over flights and frames per angle bin: (psi, mean, std, n)."""
        edges = np.arange(0.0, 360.0 + bin_deg, bin_deg)
        k = np.clip(np.digitize(self.psi_deg, edges) - 1, 0, len(edges) - 2)
        n = np.bincount(k, minlength=len(edges) - 1)
        s1 = np.bincount(k, self.holdup_area_m2, minlength=len(edges) - 1)
        s2 = np.bincount(k, self.holdup_area_m2**2, minlength=len(edges) - 1)
        ok = n > 0
        mean = s1[ok] / n[ok]
        std = np.sqrt(np.maximum(s2[ok] / n[ok] - mean**2, 0.0))
        return 0.5 * (edges[:-1] + edges[1:])[ok], mean, std, n[ok]

    def comparison(self, surface_layer=None) -> dict:
        return compare(self, surface_layer=surface_layer)

    def summary_line(self) -> str:
        c = self.comparison()
        return (f"{self.n_particles} particles, {self.n_frames} frames; packing {self.packing_fraction:.3f}, "
                f"repose {self.repose_angle_deg:.1f} deg, airborne {100 * self.airborne_fraction:.1f} %; "
                f"RMS plain {c['plain']['rms_pct']:.1f} %, corrected {c['corrected']['rms_pct']:.1f} % of a full flight")


def liggghts_version(folder) -> str:
    """The LIGGGHTS version line of a run's log (``log.liggghts``), or "unknown"."""
    for name in ("log.liggghts", "screen.txt"):
        p = Path(folder) / name
        if p.is_file():
            with open(p, "rb") as fh:
                head = fh.read(4096).decode("utf-8", "replace")
            m = re.search(r"LIGGGHTS \(Version ([^,)]+)", head)
            if m:
                return m.group(1).strip()
    return "unknown"


def _load_deck(folder: Path) -> SliceDeck:
    p = folder / "deck.json"
    if not p.is_file():
        raise ValueError(f"{str(folder)!r} holds no deck.json: give the folder written by rotarydryer dem export")
    try:
        d = json.loads(p.read_text("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"{str(p)!r} is not valid JSON ({exc})") from None
    try:
        return SliceDeck.from_dict(d)
    except TypeError as exc:
        raise ValueError(f"{str(p)!r} is not a deck description ({exc})") from None


def analyse_run(folder, *, every: int = 1) -> DemHoldup:
    """Read ``deck.json`` and ``post/particles.dump`` of a run folder and reduce them."""
    folder = Path(folder)
    deck = _load_deck(folder)
    frames = read_dump(folder / "post" / "particles.dump", every=every)
    res = analyse_frames(deck, frames)
    res.liggghts_version = liggghts_version(folder)
    log = folder / "log.liggghts"
    if log.is_file():
        loops = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs", log.read_text("utf-8", "replace"))
        if loops:
            res.extra["wall_time_s"] = round(sum(float(t) for t, _ in loops), 1)
            res.extra["mpi_ranks"] = int(loops[-1][1])
    return res


def check_geometry(deck: SliceDeck, frames: DumpFrames) -> None:
    """Raise ``ValueError`` when the dumps do not come from this deck's geometry."""
    d = deck.particles.diameter
    half = deck.radius * 1.02 + 2 * d
    want = np.array([[-half, half], [-half, half], [0.0, deck.length]])
    tol = 1e-6 + 1e-4 * half
    for name in ("id", "x", "y", "vx", "vy"):
        if name not in frames.columns:
            raise ValueError(f"{str(frames.path)!r}: dump has no column {name!r} (columns {', '.join(frames.columns)})")
    bad = np.abs(frames.box - want[None]).max(axis=(1, 2))
    if np.any(bad > tol):
        f = int(np.argmax(bad > tol))
        b = frames.box[f]
        raise ValueError(
            f"{str(frames.path)!r} comes from another geometry: its box is x [{b[0, 0]:.4g}, {b[0, 1]:.4g}], "
            f"y [{b[1, 0]:.4g}, {b[1, 1]:.4g}], z [{b[2, 0]:.4g}, {b[2, 1]:.4g}] m, the deck's (R = {deck.radius:g} m, "
            f"slice {deck.length:g} m) is x, y [{-half:.4g}, {half:.4g}], z [0, {deck.length:.4g}] m")
    if "radius" in frames.columns:
        r = frames.column(0, "radius")
        if r.size and np.any(np.abs(r - 0.5 * d) > 1e-6 * d + 1e-12):
            raise ValueError(f"{str(frames.path)!r} comes from another deck: particle radius {float(np.median(r)):.4g} m, "
                             f"the deck's is {0.5 * d:.4g} m")
    for f in (0, len(frames) - 1):
        x, y = frames.column(f, "x"), frames.column(f, "y")
        rr = np.hypot(x, y)
        if rr.size and rr.max() > deck.radius + 0.5 * d:
            raise ValueError(
                f"{str(frames.path)!r} comes from another geometry: a particle at {rr.max():.4g} m from the axis "
                f"(frame {f + 1}) is outside the drum of radius {deck.radius:g} m")


def _drum_angles(deck: SliceDeck, steps: np.ndarray) -> np.ndarray:
    st = deck.recorded_steps or deck.steps()
    start = st.get("rotation_start", st["settle"])
    return (steps - start) * deck.timestep * 360.0 / deck.period


def _point_segment_dist(px, py, a, b):
    ab = b - a
    t = np.clip(((px - a[0]) * ab[0] + (py - a[1]) * ab[1]) / float(ab @ ab), 0.0, 1.0)
    return np.hypot(px - a[0] - t * ab[0], py - a[1] - t * ab[1])


def analyse_frames(deck: SliceDeck, frames: DumpFrames) -> DemHoldup:
    """Reduce dump frames of a run of ``deck`` (see the module docstring)."""
    from matplotlib.path import Path as MPath
    from scipy.spatial import cKDTree

    check_geometry(deck, frames)
    drum = deck.drum
    c = drum._c
    d = deck.particles.diameter
    R, Lz = deck.radius, deck.length
    vp = deck.particles.volume
    omega = 2.0 * math.pi * deck.rpm / 60.0
    v_tol = max(omega * R, math.sqrt(GRAVITY * d))
    v_fall = math.sqrt(4.0 * GRAVITY * d)
    theta = _drum_angles(deck, frames.steps)
    if np.any(theta < -1e-6):
        raise ValueError(f"{str(frames.path)!r}: frames before the drum starts turning (step "
                         f"{int(frames.steps[0])}); the deck records only while it turns")
    pocket = drum.pocket_polygon(0.0, n_arc=96)
    mpath = MPath(pocket)
    r_min = c.RF * math.cos(math.radians(0.5 * c.psi_fl)) - d
    nf = drum.n_flights
    ang_lo, ang_hi = -2.0, c.psi_fl + c.psi_ft + 2.0  # pocket span from the root, deg
    psi_s, h_s, fl_s = [], [], []
    reps, air, packs, rep_psi = [], [], [], []
    r_p = 2.5 * d
    ix, iy = frames.columns.index("x"), frames.columns.index("y")
    ivx, ivy = frames.columns.index("vx"), frames.columns.index("vy")
    n_part = []
    outline0 = drum.flight_outline(0.0)
    for f in range(len(frames)):
        D = frames.data[f]
        x, y, vx, vy = D[:, ix], D[:, iy], D[:, ivx], D[:, ivy]
        n_part.append(len(x))
        rr = np.hypot(x, y)
        # angular position measured like psi: (R sin a, -R cos a) -> a = atan2(x, -y)
        a = np.degrees(np.arctan2(x, -y))
        rel = np.hypot(vx + omega * y, vy - omega * x)
        moving = rel < v_tol
        in_any = np.zeros(len(x), bool)
        for i in range(nf):
            psi_i = theta[f] + i * c.psi_fl
            da = np.mod(a - psi_i, 360.0)
            cand = (rr > r_min) & (da > ang_lo % 360.0 if ang_lo >= 0 else (da < ang_hi) | (da > 360.0 + ang_lo))
            cand &= (da < ang_hi) | (da > 360.0 + ang_lo)
            idx = np.nonzero(cand)[0]
            if idx.size == 0:
                psi_s.append(psi_i % 360.0)
                h_s.append(0.0)
                fl_s.append((f, i))
                continue
            t = math.radians(psi_i)
            ct, st_ = math.cos(t), math.sin(t)
            # rotate back by psi_i into the frame of the flight at psi = 0 (anticlockwise rotation by -psi_i)
            xr = ct * x[idx] + st_ * y[idx]
            yr = -st_ * x[idx] + ct * y[idx]
            inside = mpath.contains_points(np.column_stack([xr, yr]))
            held = idx[inside & moving[idx]]
            in_any[idx[inside]] = True
            psi_s.append(psi_i % 360.0)
            h_s.append(float(held.size))
            fl_s.append((f, i))
            # repose angle of unloading flights whose pocket is in the rising half
            tip_ang = (psi_i + c.psi_ft) % 360.0
            if 60.0 < tip_ang < 150.0 and held.size >= 12:
                walls = []
                for k in (i, i + 1):
                    t2 = math.radians(theta[f] + k * c.psi_fl)
                    rot = np.array([[math.cos(t2), -math.sin(t2)], [math.sin(t2), math.cos(t2)]])
                    o = outline0 @ rot.T
                    walls += list(zip(o[:-1], o[1:]))
                ang = _surface_angle(x[held], y[held], d, walls, R)
                if ang is not None:
                    reps.append(ang)
                    rep_psi.append(psi_i % 360.0)
        air.append(float(np.sum((~in_any) & (vy < -v_fall)) / max(len(x), 1)))
        if f % max(1, len(frames) // 20) == 0:
            packs.extend(_bulk_packing(x, y, drum, theta[f], d, r_p, Lz, vp, outline0, cKDTree))
    if not packs:
        raise ValueError("no bulk region found in the dumps to measure the packing fraction (too few particles)")
    packs = np.asarray(packs)
    p95 = np.percentile(packs, 95)
    phi_b = float(np.median(packs[packs >= 0.85 * p95]))
    psi_s = np.asarray(psi_s)
    h_s = np.asarray(h_s) * vp / (phi_b * Lz)
    reps = np.asarray(reps)
    q1, med, q3 = np.percentile(reps, [25, 50, 75]) if reps.size else (np.nan, np.nan, np.nan)
    fl_s = np.asarray(fl_s, dtype=int).reshape(-1, 2)
    out = DemHoldup(deck=deck, frame=fl_s[:, 0], flight=fl_s[:, 1], psi_deg=psi_s, holdup_area_m2=h_s,
                    packing_fraction=phi_b, repose_angle_deg=float(med), repose_angle_iqr_deg=float(q3 - q1),
                    airborne_fraction=float(np.mean(air)), n_particles=int(np.median(n_part)),
                    n_frames=len(frames))
    out.extra["repose_samples"] = np.column_stack([rep_psi, reps]) if len(reps) else np.empty((0, 2))
    out.extra["repose_angle_samples"] = int(len(reps))
    return out


def _surface_angle(x, y, d, walls, radius):
    """Angle (deg) of the free surface of held solids: the top particle of every d-wide column,
    keeping those more than one diameter from the walls (the flights' plates ``walls``, a list of
    segments, and the shell), Theil-Sen line (median of the pairwise slopes)."""
    xb = np.floor((x - x.min()) / d).astype(int)
    nb = xb.max() + 1
    if nb < 5:
        return None
    order = np.lexsort((-y, xb))
    first = np.ones(len(order), bool)
    first[1:] = xb[order][1:] != xb[order][:-1]
    top = order[first]
    tx, ty = x[top], y[top]
    far = np.hypot(tx, ty) < radius - 1.5 * d
    for a, b in walls:
        far &= _point_segment_dist(tx, ty, a, b) > 1.5 * d
    tx, ty = tx[far], ty[far]
    if tx.size < _MIN_SURFACE_POINTS:
        return None
    i, j = np.triu_indices(tx.size, 1)
    dx = tx[j] - tx[i]
    ok = np.abs(dx) > 0.5 * d
    if not np.any(ok):
        return None
    slope = float(np.median((ty[j] - ty[i])[ok] / dx[ok]))
    ang = math.degrees(math.atan(slope))
    return ang if 5.0 < ang < 85.0 else None


def _bulk_packing(x, y, drum, theta, d, r_p, Lz, vp, outline0, cKDTree):
    """Local packing fractions in cylinders of radius r_p centred on particles inside a bed."""
    ok = np.hypot(x, y) < drum.radius - r_p
    px, py = x[ok], y[ok]
    cand = px
    if cand.size == 0:
        return []
    dmin = np.full(cand.size, np.inf)
    for i in range(drum.n_flights):
        t = math.radians(theta + i * drum.flight_spacing)
        rot = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
        pts = outline0 @ rot.T
        for a, b in zip(pts[:-1], pts[1:]):
            dmin = np.minimum(dmin, _point_segment_dist(px, py, a, b))
    keep = dmin > r_p
    if not np.any(keep):
        return []
    tree = cKDTree(np.column_stack([x, y]))
    centres = np.column_stack([px[keep], py[keep]])
    n1 = np.array([len(v) for v in tree.query_ball_point(centres, r_p)])
    return list((n1 - 1) * vp / (math.pi * r_p**2 * Lz))  # the centre particle itself not counted


# ---------------------------------------------------------------------------- comparison
def _unwrap(psi):
    """Angles on [-90, 270): the filling at the bottom (270-360) comes before 0."""
    psi = np.asarray(psi, dtype=float)
    return np.where(psi >= 270.0, psi - 360.0, psi)


def _drum_angle_of_frames(res: DemHoldup) -> dict:
    """Drum angle (deg, cumulative since the rotation started) of every frame, from flight 0's root
    (which starts at 0) and the recorded spin-up."""
    m0 = res.flight == 0
    fr = res.frame[m0]
    o = np.argsort(fr)
    a = np.degrees(np.unwrap(np.radians(res.psi_deg[m0][o])))
    spin = 360.0 * float(res.deck.spinup_revolutions)
    a = a + 360.0 * np.round((spin - a[0]) / 360.0)
    return dict(zip(fr[o].tolist(), a.tolist()))


def _flight_tracks(res: DemHoldup, steady: bool = False):
    """Per flight: unwrapped angle (deg, [-90, 270)) and holdup (m^2) in time order. With ``steady``,
    only the samples taken after the flight, since the drum started turning, has gone down the
    empty side (root at 270 deg) and through the bottom: its load then comes from the turning bed,
    not from the settled bed or the pouring (flight i starts with its root at i psi_fl)."""
    out = []
    theta = _drum_angle_of_frames(res) if steady else None
    sp = res.deck.drum.flight_spacing
    for i in np.unique(res.flight):
        m = res.flight == i
        o = np.argsort(res.frame[m])
        psi, h, fr = _unwrap(res.psi_deg[m][o]), res.holdup_area_m2[m][o], res.frame[m][o]
        if steady:
            psi0 = (int(i) * sp) % 360.0
            need = 360.0 if psi0 <= 270.0 else 720.0
            keep = np.array([psi0 + theta.get(int(f), -1e9) >= need for f in fr], dtype=bool)
            psi, h = psi[keep], h[keep]
        # one track per pass: split where the angle wraps from 270 back to -90 deg
        cuts = np.nonzero(np.diff(psi) < 0.0)[0] + 1
        for a, b in zip(np.r_[0, cuts], np.r_[cuts, len(psi)]):
            if b > a:
                out.append((psi[a:b], h[a:b]))
    return out


def compare(res: DemHoldup, *, surface_layer=None, repose_angle=None, last_angle=None, steady=True) -> dict:
    """Geometric model (plain and with the finite-particle correction) against the DEM, flight by flight.

    Every flight is followed through the recording. Its largest load between leaving the bed (root
    angle 0) and 60 deg (or, if first seen later, its load then) is its level ``H_l`` (Lee (2008) section 4.4.2: a flight holds ``f H0`` until
    ``H_max`` falls below it); the model predicts ``min(H_max(psi), H_l)``. The unloading range is
    made of the samples from root angle 0 to the model's end of unloading psi5 (Lee (2008) Eq. 4.13
    at the repose angle; ``last_angle`` to change it) where the DEM or either model (plain,
    corrected) holds less than 97 % of ``H_l``, except where all three hold less than 1 % of a full
    flight: the same samples for both models. (Solids a DEM flight still holds past psi5 show in
    the end of unloading.) RMS, bias (model minus DEM) and largest difference in
    % of a full flight over all flights' samples; start (below 97 % of the level) and end (below 3 %
    of a full flight) of unloading as medians over the flights.
    Returns ``{"plain": {...}, "corrected": {...}, "dem": {...}}``."""
    drum = res.deck.drum
    full = drum.full_holdup_area
    if repose_angle is not None:
        phi = float(repose_angle)
    else:
        phi = float(res.extra.get("repose_angle_used_deg", res.repose_angle_deg))
    if not math.isfinite(phi):
        raise ValueError("the dumps hold no unloading flight with a measurable surface (too few particles or frames): "
                         "no dynamic repose angle was measured; give one (--repose-angle, deg)")
    d = res.deck.particles.diameter
    psi5 = float(drum.transition_angles(phi).psi5)
    top = psi5 if last_angle is None else float(last_angle)
    tracks = []
    for psi, h in _flight_tracks(res, steady=steady):
        w = (psi >= 0.0) & (psi <= psi5 + 60.0)
        if np.count_nonzero(w) < 3:
            continue
        early = psi[w] <= _LEVEL_UNTIL_DEG
        lvl = float(np.max(h[w][early])) if early.any() else float(h[w][0])
        tracks.append((psi[w], h[w], lvl))
    out = {"dem": {"repose_angle_deg": phi, "n_flights_tracked": len(tracks)}, "last_angle_deg": top}
    dem_start, dem_end = [], []  # noqa: F841
    for p, h, lvl in tracks:
        j = np.nonzero(h < _START_FRACTION * lvl)[0]
        dem_start.append(p[j[0]] if j.size else np.nan)
        j = np.nonzero(h < _END_FRACTION * full)[0]
        dem_end.append(p[j[0]] if j.size else np.nan)
    out["dem"]["start_deg"] = _nanmedian(dem_start)
    out["dem"]["end_deg"] = _nanmedian(dem_end)
    preds = {}
    for name, dp in (("plain", None), ("corrected", d)):
        kw = {} if dp is None else {"particle_diameter": dp, "surface_layer": surface_layer}
        preds[name] = [np.minimum(drum.holdup_area(np.mod(p, 360.0), phi, **kw), lvl) for p, h, lvl in tracks]
    # samples in the unloading range: DEM or either model below 97 % of the flight's level, and not
    # all three empty (below 1 % of a full flight)
    masks = []
    for k, (p, h, lvl) in enumerate(tracks):
        hp, hc = preds["plain"][k], preds["corrected"][k]
        unl = (h < _START_FRACTION * lvl) | (hp < _START_FRACTION * lvl) | (hc < _START_FRACTION * lvl)
        empty = (h < 0.01 * full) & (hp < 0.01 * full) & (hc < 0.01 * full)
        masks.append(unl & ~empty & (p <= top))
    for name in ("plain", "corrected"):
        errs, starts, ends = [], [], []
        for k, (p, h, lvl) in enumerate(tracks):
            hm = preds[name][k]
            j = np.nonzero(hm < _START_FRACTION * lvl)[0]
            starts.append(p[j[0]] if j.size else np.nan)
            j = np.nonzero(hm < _END_FRACTION * full)[0]
            ends.append(p[j[0]] if j.size else np.nan)
            errs.append((hm[masks[k]] - h[masks[k]]) / full * 100.0)
        e = np.concatenate(errs) if errs else np.empty(0)
        out[name] = {"rms_pct": float(np.sqrt(np.mean(e**2))) if e.size else float("nan"),
                     "bias_pct": float(np.mean(e)) if e.size else float("nan"),
                     "max_abs_pct": float(np.max(np.abs(e))) if e.size else float("nan"),
                     "start_deg": _nanmedian(starts), "end_deg": _nanmedian(ends), "n_samples": int(e.size)}
    return out


def _nanmedian(v) -> float:
    v = np.asarray(v, dtype=float)
    v = v[np.isfinite(v)]
    return float(np.median(v)) if v.size else float("nan")


# ---------------------------------------------------------------------------- reduced CSV
def write_reduced_csv(res: DemHoldup, path, *, role: str = "") -> Path:
    """Reduced run: one row per recorded frame and flight, ``frame, flight, psi_deg, holdup_area_m2,
    holdup_fraction``; the header (``#`` lines, JSON) holds the deck, the LIGGGHTS version and the
    measured packing fraction, repose angle and airborne fraction."""

    meta = {"liggghts_version": res.liggghts_version, "role": role, "n_particles": res.n_particles,
            "n_frames": res.n_frames, "packing_fraction": round(res.packing_fraction, 5),
            "repose_angle_deg": round(res.repose_angle_deg, 3),
            "repose_angle_iqr_deg": round(res.repose_angle_iqr_deg, 3),
            "repose_angle_samples": int(res.extra.get("repose_angle_samples", 0)),
            "wall_time_s": res.extra.get("wall_time_s"), "mpi_ranks": res.extra.get("mpi_ranks"),
            "airborne_fraction": round(res.airborne_fraction, 5),
            "full_holdup_area_m2": res.full_area}
    lines = ["# rotarydryer DEM slice: holdup of every flight versus its root angle, every recorded frame "
             "(rotarydryer.dem.holdup)",
             "# measured: " + json_text(meta),
             "# deck: " + json_text(res.deck.to_dict()),
             "frame,flight,psi_deg,holdup_area_m2,holdup_fraction"]
    full = res.full_area
    for fr, fl, p, h in zip(res.frame, res.flight, res.psi_deg, res.holdup_area_m2):
        lines.append(f"{int(fr)},{int(fl)},{p:.3f},{h:.6e},{h / full:.5f}")
    return write_text_atomic(path, "\n".join(lines) + "\n")


def read_reduced_csv(path) -> DemHoldup:
    """A `DemHoldup` from a reduced CSV (`write_reduced_csv`)."""
    path = Path(path)
    text = path.read_text("utf-8")
    meta = deck = None
    rows = []
    for line in text.splitlines():
        if line.startswith("# measured: "):
            meta = json.loads(line[len("# measured: "):])
        elif line.startswith("# deck: "):
            deck = SliceDeck.from_dict(json.loads(line[len("# deck: "):]))
        elif line and not line.startswith("#") and not line.startswith("frame"):
            rows.append([float(v) for v in line.split(",")])
    if meta is None or deck is None or not rows:
        raise ValueError(f"{str(path)!r} is not a reduced DEM CSV written by rotarydryer (no '# measured:'/'# deck:' "
                         "header or no rows)")
    a = np.array(rows)
    res = DemHoldup(deck=deck, frame=a[:, 0].astype(int), flight=a[:, 1].astype(int), psi_deg=a[:, 2],
                    holdup_area_m2=a[:, 3], packing_fraction=meta["packing_fraction"],
                    repose_angle_deg=meta["repose_angle_deg"], repose_angle_iqr_deg=meta["repose_angle_iqr_deg"],
                    airborne_fraction=meta["airborne_fraction"], n_particles=meta["n_particles"],
                    n_frames=meta["n_frames"], liggghts_version=meta["liggghts_version"])
    res.extra["role"] = meta.get("role", "")
    res.extra["repose_angle_samples"] = int(meta.get("repose_angle_samples", 0))
    for key in ("wall_time_s", "mpi_ranks"):
        if meta.get(key) is not None:
            res.extra[key] = meta[key]
    return res


def plot_comparison(res: DemHoldup, path, *, surface_layer=None, title: str | None = None, repose_angle=None):
    """Every flight's DEM holdup versus its angle (one line per flight) with the plain and corrected
    geometric model (``min(H_max, level)`` for each flight's level), saved to ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt


    drum = res.deck.drum
    full = drum.full_holdup_area
    cmp_ = compare(res, surface_layer=surface_layer, repose_angle=repose_angle)
    phi = cmp_["dem"]["repose_angle_deg"]
    fine = np.arange(-60.0, 270.0, 0.2)
    fig, ax = plt.subplots(figsize=(7, 4))
    hp = drum.holdup_area(np.mod(fine, 360), phi) / full
    hc = drum.holdup_area(np.mod(fine, 360), phi, particle_diameter=res.deck.particles.diameter,
                          surface_layer=surface_layer) / full
    for psi, h in _flight_tracks(res):
        ax.plot(psi, h / full, "-", color="0.88", lw=0.6)
    first = True
    for psi, h in _flight_tracks(res, steady=True):
        w = psi >= 0.0
        if np.count_nonzero(w) < 3:
            continue
        ax.plot(psi, h / full, "-", color="0.45", lw=0.8,
                label="DEM, one line per flight (light: filled before the drum turned)" if first else None)
        early = psi[w] <= _LEVEL_UNTIL_DEG
        lvl = np.max(h[w][early]) if early.any() else h[w][0]
        ax.plot(psi[w], np.minimum(np.interp(psi[w], fine, hp), lvl / full), "b:", lw=0.8)
        ax.plot(psi[w], np.minimum(np.interp(psi[w], fine, hc), lvl / full), "r:", lw=0.8)
        first = False
    ax.axvline(cmp_["last_angle_deg"], color="k", lw=0.5, ls="--")
    ax.plot(fine, hp, "b-", label=f"geometric model H_max, phi = {phi:.1f} deg (RMS {cmp_['plain']['rms_pct']:.1f} %)")
    ax.plot(fine, hc, "r-", label=f"with finite-particle correction (RMS {cmp_['corrected']['rms_pct']:.1f} %)")
    ax.set_xlabel("flight-root angle psi, deg from the bottom")
    ax.set_ylabel("holdup / full flight")
    ax.set_xlim(-60, 250)
    ax.set_ylim(0, 1.15)
    ax.legend(fontsize=7, loc="upper right")
    ax.set_title(title or f"{res.deck.source}: d/s1 = {res.deck.particles.diameter / res.deck.s1:.3g}", fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path, dpi=110)
