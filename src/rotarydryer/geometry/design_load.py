"""Design load, loading factor and loading state of a flighted drum.

The *design load* is the passive (flight- and drum-borne) solids holdup at which
the first unloading flight (FUF) starts discharging exactly at the horizontal
(Lee (2008) section 4.4.1; Ajayi (2011) section 2.2). All areas here are
cross-sectional areas of solids in the **whole drum cross-section**, m^2; multiply
by bulk density (kg/m^3) and length (m) for kg.

Methods (``method=``), all evaluated with the exact flight geometry:

``"lee2008"`` (default)
:   Geometric, first-unloading-flight method with vertical symmetry, Lee (2008)
    Eq. 4.20-4.21: ``A_des = H0 + 2 sum_{i=1}^{n} H_max(psi_0 + i psi_fl)`` over the
    upper-half flights (``n = ceil(N_F/2) - 1``; ``N_F/2 - 1`` for even ``N_F``).

``"baker1988"``
:   Baker (1988) as given by Ajayi (2011) Eq. 2.4, ``2 sum_{i=f}^{n} M_i - M_FUF``:
    algebraically identical to ``"lee2008"``; kept under its own name.

``"porter1963"``
:   Porter's assumption, Lee (2008) Eq. 4.19 / Ajayi (2011) Eq. 2.2: ``N_F H0 / 2``.

``"kelly1977"``
:   Kelly & O'Donnell (1977), Ajayi (2011) Eq. 2.3: ``(N_F + 1) H0 / 2``.

``"ajayi2011"``
:   Ajayi's modified Baker model, Ajayi (2011) Eq. 4.19 / 5.16: ``1.24 x Baker``,
    the factor correcting Baker's mean under-prediction (-24.3 %) of his pilot-drum
    design loads.

``H0`` is the holdup of the FUF. ``convention="root"`` (default) puts its root at
90 deg, which reproduces Lee's regression Eq. 4.27 (and so his Ch. 7); ``"tip"``
puts its tip at 90 deg as Lee's text says (design loads 8-10 % higher).
"""

from __future__ import annotations

import math

import numpy as np

from .._validation import check_choice, check_range
from .drum import _H, FlightedDrum
from .unloading import first_unloading_angle

__all__ = [
    "DESIGN_LOAD_METHODS",
    "design_load_methods",
    "design_load_area",
    "design_load_mass",
    "loading_factor",
    "loading_state",
    "LOADING_STATES",
]

DESIGN_LOAD_METHODS = ("lee2008", "baker1988", "porter1963", "kelly1977", "ajayi2011")
LOADING_STATES = ("under-loaded", "design-loaded", "over-loaded")
AJAYI_BAKER_FACTOR = 1.24  #: Ajayi (2011) Eq. 4.19


def design_load_methods() -> tuple[str, ...]:
    """Names accepted by ``design_load_area(..., method=...)``."""
    return DESIGN_LOAD_METHODS


def _area_weights(n_flights: int, method: str) -> tuple[float, float]:
    """``(a, b)`` with the design-load area ``a H0 + b (H0 + 2 sum H_i)`` of ``method``, one of them 0:
    Porter (1963) n/2 and Kelly (1977) (n + 1)/2 first-unloading-flight holdups, Baker (1988) = Lee
    (2008) Eq. 4.20 the sum itself, Ajayi (2011) Eq. 4.19 1.24 times it."""
    return {"porter1963": (n_flights / 2.0, 0.0), "kelly1977": ((n_flights + 1) / 2.0, 0.0),
            "ajayi2011": (0.0, AJAYI_BAKER_FACTOR)}.get(method, (0.0, 1.0))


def _upper_flight_holdups(drum: FlightedDrum, phi, convention, particle_diameter=None):
    """H0 (FUF) and holdups of the upper-half flights at design, m^2. Shapes (...), (..., n).

    With a ``particle_diameter`` (m) the holdups carry the finite-particle correction
    ([`rotarydryer.geometry.drum.finite_particle_correction`][rotarydryer.geometry.drum.finite_particle_correction])."""
    c = drum._c
    delta = None if particle_diameter is None else drum._layer(particle_diameter)
    psi0 = first_unloading_angle(drum, convention)
    n = math.ceil(drum.n_flights / 2) - 1
    phi = np.asarray(phi, dtype=float)
    psi = psi0 + c.psi_fl * np.arange(1, n + 1)
    ph = phi[..., None]
    hi = _H(c, np.broadcast_to(psi, ph.shape[:-1] + (n,)), np.broadcast_to(ph, ph.shape[:-1] + (n,)), delta)
    h0 = _H(c, np.full_like(phi, psi0), phi, delta)
    return h0, hi


def design_load_area(drum: FlightedDrum, repose_angle, *, method: str = "lee2008", convention: str = "root",
                     particle_diameter=None):
    """Design-load cross-sectional area of passive solids in the whole drum, m^2.

    See the module docstring for the methods and conventions. Vectorised over
    ``repose_angle`` (deg, in (0, 90)). ``particle_diameter`` (m, optional) applies the
    finite-particle correction to every flight holdup (``docs/dem.md``); ``None`` is the
    continuum model.

    Examples
    --------
    >>> from rotarydryer.geometry import FlightedDrum, TwoSectionFlight
    >>> drum = FlightedDrum(2.5, 28, TwoSectionFlight(0.195, 0.183, 90, 117))
    >>> round(float(design_load_area(drum, 50.0)) * 940 * 12)   # kg, Lee Table 7.6: 6 784
    6786
    """
    check_choice("method", method, DESIGN_LOAD_METHODS)
    phi = check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg")
    h0, hi = _upper_flight_holdups(drum, phi, convention, particle_diameter)
    a, b = _area_weights(drum.n_flights, method)
    return a * h0 if b == 0.0 else b * (h0 + 2.0 * hi.sum(-1))  # Lee (2008) Eq. 4.20 = Baker (1988)


def design_load_mass(drum: FlightedDrum, repose_angle, bulk_density, length, **kwargs):  # noqa: D417
    """Design load in kg: [`design_load_area`][rotarydryer.geometry.design_load.design_load_area] x bulk density (kg/m^3) x length (m)."""
    rho = check_range("bulk_density", bulk_density, 0.0, math.inf, unit="kg/m^3")
    ell = check_range("length", length, 0.0, math.inf, unit="m")
    return design_load_area(drum, repose_angle, **kwargs) * rho * ell


def loading_factor(drum: FlightedDrum, dryer_loading, repose_angle, *, convention: str = "root",
                   particle_diameter=None, smoothing=0.0):
    """Flight loading factor ``f_load`` from the dryer loading ``d_load = M_p / M_p,des``.

    Solves Lee (2008) Eq. 4.22 exactly,
    ``d M_des = f H0 + 2 sum_i min(f H0, H_max(psi_i))``:
    the right-hand side is piecewise linear and strictly increasing in ``f``, so the
    inverse is found segment by segment (no iteration). ``f = 1`` for ``d >= 1``
    (a flight never holds more than its design load; the excess kilns).
    Vectorised over both arguments. ``dryer_loading`` must be >= 0. ``particle_diameter`` (m,
    optional): finite-particle correction of the holdups (``docs/dem.md``). ``smoothing`` > 0 rounds
    the kinks of ``f(d)`` over that width of ``d`` (see `_invert_eq_4_22`).
    """
    d = check_range("dryer_loading", dryer_loading, 0.0, math.inf, low_inclusive=True)
    phi = check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg")
    d, phi = np.broadcast_arrays(d, phi)
    h0, hi = _upper_flight_holdups(drum, phi, convention, particle_diameter)
    return _invert_eq_4_22(d, h0, hi, smoothing)


def _invert_eq_4_22(d, h0, hi, smoothing=0.0):
    """``f`` from the dryer loading ``d`` and the design holdups ``H0`` (...) and ``H_i`` (..., n):
    Lee (2008) Eq. 4.22 inverted segment by segment (see [`loading_factor`][rotarydryer.geometry.design_load.loading_factor]).

    ``smoothing`` > 0 rounds every kink of the piecewise-linear ``f(d)`` (where a flight fills, and
    ``f = 1`` from ``d = 1``) over that width of ``d``: ``max(0, x)`` becomes
    ``(x + sqrt(x^2 + w^2)) / 2``, so Newton sees a smooth map (as the thermal model's smoothed
    design-load switch ``design_load_smoothing``, of the same width)."""
    r = np.sort(np.clip(hi / h0[..., None], 0.0, 1.0), axis=-1)  # breakpoints in f
    n = r.shape[-1]
    # g(f) = f + 2 sum_i min(f, r_i); g(1) = M_des/H0
    bp = np.concatenate([np.zeros(r.shape[:-1] + (1,)), r, np.ones(r.shape[:-1] + (1,))], axis=-1)
    # g at the breakpoints: g(b_k) = b_k + 2 * (sum_{i<k} r_i + (n - k) b_k) for sorted r
    csum = np.concatenate([np.zeros(r.shape[:-1] + (1,)), np.cumsum(r, -1)], axis=-1)
    k = np.arange(n + 2)
    below = np.minimum(k, n)
    g = bp + 2.0 * (np.take_along_axis(csum, np.broadcast_to(below, bp.shape), -1) + (n - below) * bp)
    if smoothing > 0.0:
        return _smoothed_inverse(d, bp, g / g[..., -1:], float(smoothing))
    target = d * g[..., -1]
    seg = np.clip((g < target[..., None]).sum(-1) - 1, 0, n)
    g0 = np.take_along_axis(g, seg[..., None], -1)[..., 0]
    g1 = np.take_along_axis(g, seg[..., None] + 1, -1)[..., 0]
    b0 = np.take_along_axis(bp, seg[..., None], -1)[..., 0]
    b1 = np.take_along_axis(bp, seg[..., None] + 1, -1)[..., 0]
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.where(g1 > g0, b0 + (target - g0) * (b1 - b0) / (g1 - g0), b0)
    return np.where(d >= 1.0, 1.0, np.clip(f, 0.0, 1.0))


def _smoothed_inverse(d, f_knots, d_knots, w):
    """The piecewise-linear ``f(d)`` through ``(d_k, f_k)`` (then flat at 1) as a sum of ramps
    ``f = s_0 d + sum_k (s_k - s_{k-1}) max(0, d - d_k)``, each ramp's kink rounded over ``w``."""
    dd = np.diff(d_knots, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(dd > 1e-15, np.diff(f_knots, axis=-1) / np.where(dd > 1e-15, dd, 1.0), np.nan)
    # a degenerate segment (two equal knots) has no slope of its own: the previous one continues
    s = np.concatenate([s, np.zeros(s.shape[:-1] + (1,))], axis=-1)   # flat beyond d = 1
    idx = np.where(np.isnan(s), 0, np.arange(s.shape[-1]))
    idx = np.maximum.accumulate(idx, axis=-1)
    s = np.take_along_axis(np.nan_to_num(s, nan=0.0), idx, -1)
    jumps = np.diff(s, axis=-1)                                        # at d_knots[1:]
    x = d[..., None] - d_knots[..., 1:]
    ramp = 0.5 * (x + np.sqrt(x * x + w * w))
    x0 = d - d_knots[..., 0]
    f = s[..., 0] * 0.5 * (x0 + np.sqrt(x0 * x0 + w * w)) + (jumps * ramp).sum(-1)
    return np.clip(f, 0.0, 1.0)


def loading_state(dryer_loading, tolerance: float = 0.02):
    """Classify ``d_load = M_p/M_p,des``: under-, design- or over-loaded (Lee (2008) section 3.2).

    ``|d - 1| <= tolerance`` counts as design-loaded. Returns an array of strings
    from `LOADING_STATES`.
    """
    d = check_range("dryer_loading", dryer_loading, 0.0, math.inf, low_inclusive=True)
    tol = float(check_range("tolerance", tolerance, 0.0, 1.0, low_inclusive=True))
    return np.where(d < 1.0 - tol, LOADING_STATES[0], np.where(d > 1.0 + tol, LOADING_STATES[2], LOADING_STATES[1]))
