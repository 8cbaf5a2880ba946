r"""Particle size distributions and the size classes the dryer model carries (issue 33).

A feed's particle size distribution (PSD) is given as a sieve analysis (cumulative mass % passing
each sieve opening; Lee (2008) Table 5.3 ships as data) or as a named distribution - Rosin-Rammler
(Rosin & Rammler (1933): $F(d) = 1 - \exp[-(d/d_{63})^n]$) or log-normal (median $d_{50}$,
geometric standard deviation $\sigma_g$). It is cut into ``n`` classes of **equal mass**: class
``i`` holds the material between the cumulative fractions $i/n$ and $(i+1)/n$, its edges are the
sizes at those fractions and its representative diameter is its own mass median, the size at
$(i + 1/2)/n$. A sieve curve is interpolated linearly in $\log d$; the mass passing the finest sieve
is spread log-uniformly down to half its opening (the sieves say nothing finer).

The classes of a dryer are `SizeClasses`: diameters (ascending), mass fractions (summing to 1) and
the ``n + 1`` edges. One class of the material's diameter is the model without a PSD.

    >>> c = rosin_rammler(0.001, 2.0, 4)
    >>> [round(d * 1e3, 4) for d in c.diameters]
    [0.3654, 0.6856, 0.9904, 1.442]
    >>> round(median_diameter(c.edges, c.fractions) * 1e3, 4)      # the d50 of the classes: the distribution's
    0.8326
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from statistics import NormalDist

import numpy as np

from .._validation import check_range

__all__ = ["SizeClasses", "MAX_CLASSES", "single_class", "from_sieve", "rosin_rammler", "lognormal",
           "median_diameter", "percentile_diameter", "DISTRIBUTIONS"]

#: most size classes of a dryer (each multiplies the solids states)
MAX_CLASSES = 20
#: named distributions of ``[particle_size] distribution``
DISTRIBUTIONS = ("rosin_rammler", "lognormal")


@dataclass(frozen=True)
class SizeClasses:
    """Size classes of a feed: ``diameters`` (m, ascending, each class's mass median), ``fractions``
    (mass fractions of the feed, summing to 1) and ``edges`` (m, n + 1 class boundaries)."""

    diameters: tuple
    fractions: tuple
    edges: tuple
    source: str = ""

    @property
    def n(self) -> int:
        return len(self.diameters)


def single_class(diameter: float, source: str = "") -> SizeClasses:
    """One class of ``diameter`` (m): the model without a size distribution."""
    d = float(diameter)
    return SizeClasses((d,), (1.0,), (d, d), source)


def _check_n(n, key):
    if isinstance(n, bool) or not float(n).is_integer() or not 1 <= int(n) <= MAX_CLASSES:
        raise ValueError(f"{key} = {n!r} is outside the allowed range: an integer in [1, {MAX_CLASSES}]")
    return int(n)


def _equal_mass(inverse, n, source) -> SizeClasses:
    """Classes of equal mass from ``inverse(q)``: the size (m) below which a mass fraction q lies."""
    q = np.arange(n + 1) / n
    edges = [float(inverse(v)) for v in q]
    mid = [float(inverse((i + 0.5) / n)) for i in range(n)]
    return SizeClasses(tuple(mid), tuple([1.0 / n] * n), tuple(edges), source)


def from_sieve(sieve_m, passing_pct, n, key: str = "particle_size", source: str = "") -> SizeClasses:
    """``n`` equal-mass classes of a sieve analysis: openings ``sieve_m`` (m, ascending) and the
    cumulative mass % passing each (non-decreasing, 100 at the coarsest sieve that holds nothing).
    Errors name ``key``.sieve_m / .passing_pct, the value and the allowed range."""
    n = _check_n(n, f"{key}.classes")
    d = np.asarray(sieve_m, dtype=float)
    p = np.asarray(passing_pct, dtype=float)
    if d.ndim != 1 or d.size < 2 or p.shape != d.shape:
        raise ValueError(f"{key}.sieve_m and {key}.passing_pct must be lists of the same length, at least 2 "
                         f"(got {d.size} and {p.size})")
    if not np.all(np.isfinite(d)) or np.any(d <= 0):
        raise ValueError(f"{key}.sieve_m = {d.tolist()}: every opening must be a finite size > 0 m")
    if np.any(np.diff(d) <= 0):
        raise ValueError(f"{key}.sieve_m = {d.tolist()}: the openings must increase")
    if not np.all(np.isfinite(p)) or np.any(p < 0) or np.any(p > 100):
        raise ValueError(f"{key}.passing_pct = {p.tolist()}: every value must be in [0, 100] %")
    if np.any(np.diff(p) < 0):
        raise ValueError(f"{key}.passing_pct = {p.tolist()}: a cumulative distribution does not decrease with "
                         "the opening (mass % passing each sieve, finest first)")
    if abs(p[-1] - 100.0) > 0.5:
        raise ValueError(f"{key}.passing_pct = {p.tolist()}: it must reach 100 % at the coarsest sieve (got "
                         f"{p[-1]:g} %): the distribution must hold all the feed")
    f = p / p[-1]
    # a flat stretch carries no mass: the inverse distribution jumps over it, from its first sieve (where the mass
    # below ends) to its last (where the mass above starts); its interior sieves go. (Keeping only its first sieve
    # spread the mass above over the empty stretch: all of a feed between 1.18 and 2.36 mm became classes down to
    # 198 um.)
    step = np.diff(f) > 0
    keep = np.concatenate([[True], step[:-1] | step[1:], [True]]) if f.size > 2 else np.ones(f.size, dtype=bool)
    d, f = d[keep], f[keep]
    if f[0] > 0:       # the mass passing the finest sieve, spread log-uniformly down to half its opening
        d = np.concatenate([[0.5 * d[0]], d])
        f = np.concatenate([[0.0], f])
    first = int(np.flatnonzero(f > 0)[0]) - 1            # the last sieve holding all the feed back
    d, f = d[max(first, 0):], f[max(first, 0):]
    top = int(np.flatnonzero(f >= 1.0)[0])
    d, f = d[:top + 1], f[:top + 1]
    logd = np.log(d)

    def inverse(q):
        return math.exp(float(np.interp(q, f, logd)))
    return _equal_mass(inverse, n, source or "sieve analysis")


def rosin_rammler(d63_m, spread, n, key: str = "particle_size") -> SizeClasses:
    """``n`` equal-mass classes of a Rosin-Rammler distribution (Rosin & Rammler (1933)):
    F(d) = 1 - exp[-(d/d63)^spread]; the end classes' outer edges at F = 0.001 and 0.999."""
    n = _check_n(n, f"{key}.classes")
    d63 = float(check_range(f"{key}.d63", d63_m, 0.0, 0.2, unit="m"))
    k = float(check_range(f"{key}.spread", spread, 0.1, 20.0, low_inclusive=True, high_inclusive=True))

    def inverse(q):
        q = min(max(q, 0.001), 0.999)
        return d63 * (-math.log1p(-q)) ** (1.0 / k)
    return _equal_mass(inverse, n, f"Rosin-Rammler d63 = {d63:g} m, n = {k:g}")


def lognormal(d50_m, sigma_g, n, key: str = "particle_size") -> SizeClasses:
    """``n`` equal-mass classes of a log-normal mass distribution of median ``d50_m`` and geometric
    standard deviation ``sigma_g`` (> 1); the end classes' outer edges at 0.1 % and 99.9 %."""
    n = _check_n(n, f"{key}.classes")
    d50 = float(check_range(f"{key}.d50", d50_m, 0.0, 0.2, unit="m"))
    sg = float(check_range(f"{key}.sigma_g", sigma_g, 1.0, 10.0, high_inclusive=True))
    z = NormalDist()

    def inverse(q):
        return d50 * sg ** z.inv_cdf(min(max(q, 0.001), 0.999))
    return _equal_mass(inverse, n, f"log-normal d50 = {d50:g} m, sigma_g = {sg:g}")


def percentile_diameter(edges, fractions, p: float, diameters=None) -> float:
    """The size (m) below which a mass fraction ``p`` (0-1) lies, of classes with ``edges`` (n + 1, m)
    holding mass ``fractions`` (n, any scale): the cumulative curve through the class edges and, with
    ``diameters`` (each class's mass median), half of each class at its median, linear in log d between
    these points. One class of one size (its two edges equal): that size."""
    e = np.asarray(edges, dtype=float)
    w = np.asarray(fractions, dtype=float)
    total = float(np.sum(w))
    if total <= 0:
        return float("nan")
    if e[0] == e[-1]:
        return float(e[0])
    cum = np.concatenate([[0.0], np.cumsum(w) / total])
    if diameters is None:
        x, y = np.log(e), cum
    else:
        mid = np.log(np.asarray(diameters, dtype=float))
        x = np.empty(2 * w.size + 1)
        y = np.empty_like(x)
        x[0::2], y[0::2] = np.log(e), cum
        x[1::2], y[1::2] = mid, 0.5 * (cum[:-1] + cum[1:])
    keep = np.concatenate([[True], np.diff(y) > 0])
    return float(np.exp(np.interp(p, y[keep], x[keep])))


def median_diameter(edges, fractions, diameters=None) -> float:
    """d50 (m) of classes (`percentile_diameter` at 0.5)."""
    return percentile_diameter(edges, fractions, 0.5, diameters)
