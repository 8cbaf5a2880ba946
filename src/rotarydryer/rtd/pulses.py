r"""Tracer inputs of any shape and duration, and convolution with an RTD.

A measured outlet curve is the convolution of the vessel's RTD E(t) with the
normalised shape u(t) of the tracer input (Levenspiel 1999 ch. 11,
"convolution integral"):

$$
c_{out}(t) = \int_0^t u(s)\,E(t-s)\,ds,\qquad \int u\,dt = 1.
$$

For a convolution the means and variances (and third central moments) add:
$\bar t_{out} = \bar t_E + \bar t_u$, $\sigma^2_{out} = \sigma^2_E +
\sigma^2_u$ ([`convolved_moments`][rotarydryer.rtd.pulses.convolved_moments]). Examples: Lee (2008) App. I Experiment
entity injects a 39.6 s rectangular pulse (mean 19.8 s, variance 130.68 s²);
Ajayi (2011) §4.4 simulates test 4 with a 60 s rectangular pulse.

Input shapes (all start at t = 0 and end at t = ``duration_s``):

* ``"dirac"``: ideal pulse (duration 0), mean 0, variance 0.
* ``"rectangular"``: constant over [0, d]; mean d/2, variance d²/12.
* ``"gaussian"``: normal density centred at d/2 with σ = d/6, truncated to
  [0, d] (±3σ) and renormalised; mean d/2, variance
  σ²[1 − 6φ(3)/(2Φ(3) − 1)] (truncated-normal formula).
* an array: ``pulse_input(times_s, values)`` – any measured or simulated input
  shape, normalised to unit area (trapezoid), linearly interpolated.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import trapezoid
from scipy.stats import norm

from .._validation import check_choice, check_finite, check_range
from .models import AnalyticMoments

__all__ = ["TracerPulse", "pulse_input", "convolve_rtd", "convolve_sampled_rtd", "convolved_moments", "PULSE_KINDS"]

PULSE_KINDS = ("dirac", "rectangular", "gaussian")
_N_NODES = 16  # Gauss-Legendre nodes over a rectangular/gaussian pulse


@dataclass(frozen=True)
class TracerPulse:
    """Normalised tracer input u(t) (1/s) with its moments.

    Build with [`pulse_input`][rotarydryer.rtd.pulses.pulse_input]. ``duration_s`` is the support length (s);
    ``mean_s``, ``variance_s2`` and ``third_central_moment_s3`` are the moments
    of u (s, s², s³).
    """

    kind: str
    duration_s: float
    mean_s: float
    variance_s2: float
    third_central_moment_s3: float
    times_s: np.ndarray | None = field(default=None, repr=False, compare=False)
    values: np.ndarray | None = field(default=None, repr=False, compare=False)

    def density(self, time_s):
        """u(t) in 1/s at ``time_s`` (s); 0 outside [0, duration]. Dirac: not defined -> raises."""
        t = check_finite("time_s", time_s)
        d = self.duration_s
        if self.kind == "dirac":
            raise ValueError("a Dirac pulse has no density; use convolve_rtd, which handles it exactly")
        inside = (t >= 0) & (t <= d)
        if self.kind == "rectangular":
            return np.where(inside, 1.0 / d, 0.0)
        if self.kind == "gaussian":
            s = d / 6.0
            z = (2 * norm.cdf(3.0) - 1.0)
            return np.where(inside, norm.pdf(t, loc=d / 2, scale=s) / z, 0.0)
        return np.interp(t, self.times_s, self.values, left=0.0, right=0.0)

    def nodes(self):
        """Quadrature nodes (s) and weights (-, sum 1) representing u for convolution."""
        if self.kind == "dirac":
            return np.array([0.0]), np.array([1.0])
        if self.kind == "array":
            return _array_nodes(self.times_s, self.values)
        x, w = np.polynomial.legendre.leggauss(_N_NODES)
        d = self.duration_s
        s = 0.5 * d * (x + 1.0)
        ww = 0.5 * d * w * self.density(s)
        return s, ww / ww.sum()

    def moments(self) -> AnalyticMoments:
        """Moments of the input shape as [`AnalyticMoments`][rotarydryer.rtd.pulses.AnalyticMoments]."""
        v = self.variance_s2
        sk = self.third_central_moment_s3 / v**1.5 if v > 0 else 0.0
        return AnalyticMoments(mean_s=self.mean_s, variance_s2=v, skewness=sk)


def _array_nodes(t, u):
    """3-point Gauss-Legendre nodes per interval of a piecewise-linear density (exact to degree 5)."""
    x, w = np.polynomial.legendre.leggauss(3)
    a, b = t[:-1, None], t[1:, None]
    s = 0.5 * (b - a) * x + 0.5 * (a + b)
    ww = 0.5 * (b - a) * w * np.interp(s, t, u)
    s, ww = s.ravel(), ww.ravel()
    return s, ww / ww.sum()


def pulse_input(kind="rectangular", duration_s: float | None = None, values=None) -> TracerPulse:
    """Create a normalised tracer input.

    Parameters
    ----------
    kind : ``"dirac"``, ``"rectangular"``, ``"gaussian"``, or a 1-D array of
        sample times (s, strictly increasing, first >= 0) for an arbitrary
        shape whose signal is given in ``values``.
    duration_s : pulse duration (s) > 0 for ``rectangular``/``gaussian``
        (ignored for ``dirac``; for arrays, the last time).
    values : for an array ``kind``, the input signal (any unit, >= 0, not all
        zero); it is normalised to unit area by the trapezoidal rule.

    Returns
    -------
    TracerPulse
    """
    if not isinstance(kind, str):
        t = check_finite("pulse times_s", kind)
        if values is None:
            raise ValueError("pulse_input with an array of times needs values=")
        v = check_finite("pulse values", values)
        if t.ndim != 1 or t.shape != v.shape or t.size < 2:
            raise ValueError(f"pulse times_s and values must be 1-D of equal length >= 2, got {t.shape} and {v.shape}")
        if np.any(np.diff(t) <= 0):
            raise ValueError("pulse times_s must be strictly increasing")
        if t[0] < 0:
            raise ValueError(f"pulse times_s must start at >= 0 s, got {float(t[0]):.6g}")
        if np.any(v < 0):
            raise ValueError(f"pulse values must be >= 0, got min {float(v.min()):.6g}")
        a = float(trapezoid(v, t))  # exact for the piecewise-linear input
        if not a > 0:
            raise ValueError("pulse values have zero area")
        u = v / a
        s_, w_ = _array_nodes(t, u)  # 3-point Gauss-Legendre per interval: exact moments
        m = float(np.sum(w_ * s_))
        var = float(np.sum(w_ * (s_ - m) ** 2))
        mu3 = float(np.sum(w_ * (s_ - m) ** 3))
        return TracerPulse("array", float(t[-1]), m, var, mu3, times_s=t, values=u)
    check_choice("kind", kind, PULSE_KINDS)
    if kind == "dirac":
        return TracerPulse("dirac", 0.0, 0.0, 0.0, 0.0)
    if duration_s is None:
        raise ValueError(f"pulse_input(kind={kind!r}) needs duration_s (s) > 0")
    d = float(check_range("duration_s", duration_s, 0.0, math.inf, unit="s"))
    if kind == "rectangular":
        return TracerPulse("rectangular", d, d / 2.0, d * d / 12.0, 0.0)
    s = d / 6.0
    z = 2 * norm.cdf(3.0) - 1.0
    var = s * s * (1.0 - 2 * 3.0 * norm.pdf(3.0) / z)
    return TracerPulse("gaussian", d, d / 2.0, var, 0.0)


def convolve_rtd(e_of_t: Callable, time_s, pulse: TracerPulse):
    """Outlet response c_out(t) (1/s) of an RTD to a normalised input.

    Parameters
    ----------
    e_of_t : callable, vectorised E(t) (1/s) of the vessel, E = 0 for t < 0.
    time_s : array, times (s) after the start of the input.
    pulse : [`TracerPulse`][rotarydryer.rtd.pulses.TracerPulse].

    The convolution integral is evaluated by quadrature over the pulse
    (16-point Gauss–Legendre for rectangular/gaussian, 3 points per interval of
    an array input, exact for a Dirac), so it is accurate on any output grid.
    For rectangular and gaussian pulses the rule covers only [0, min(t, d)],
    so the start of E (a jump, kink or fractional power at t = 0) is an end
    point of the rule rather than inside it.
    """
    t = check_finite("time_s", time_s)
    if pulse.kind in ("rectangular", "gaussian"):
        # integrate only over the part of the pulse with t - s >= 0, so that the
        # start of E (often a kink or fractional power) is an end point of the rule
        x, w = np.polynomial.legendre.leggauss(_N_NODES)
        d = pulse.duration_s
        full = np.sum(0.5 * d * w * pulse.density(0.5 * d * (x + 1.0)))  # = 1 up to quadrature error
        upper = np.clip(t, 0.0, d)[..., None]
        s = 0.5 * upper * (x + 1.0)
        ws = 0.5 * upper * w * pulse.density(s) / full
        return np.sum(ws * e_of_t(t[..., None] - s), axis=-1)
    s, w = pulse.nodes()
    return np.sum(w * e_of_t(t[..., None] - s), axis=-1)


def convolve_sampled_rtd(time_s, e_per_s, pulse: TracerPulse, out_time_s=None):
    """Convolve a *sampled* RTD (e.g. a simulated one) with a tracer input.

    E is linearly interpolated between its samples and taken as 0 outside them.
    ``time_s`` (s) increasing, ``e_per_s`` (1/s); the result is returned on
    ``out_time_s`` (default ``time_s``).
    """
    t = check_finite("time_s", time_s)
    e = check_finite("e_per_s", e_per_s)
    if t.shape != e.shape or t.ndim != 1:
        raise ValueError(f"time_s and e_per_s must be 1-D of equal length, got {t.shape} and {e.shape}")
    if np.any(np.diff(t) <= 0):
        raise ValueError("time_s must be strictly increasing")
    out = t if out_time_s is None else check_finite("out_time_s", out_time_s)
    return convolve_rtd(lambda x: np.interp(x, t, e, left=0.0, right=0.0), out, pulse)


def convolved_moments(rtd_moments, pulse: TracerPulse) -> AnalyticMoments:
    """Moments of an RTD convolved with an input: means, variances and μ3 add.

    ``rtd_moments`` is any object with ``mean_s``, ``variance_s2`` and
    optionally ``skewness`` (e.g. [`AnalyticMoments`][rotarydryer.rtd.pulses.AnalyticMoments] or RTDMoments).
    Skewness of the result is None if the RTD's skewness is None.
    """
    m = rtd_moments.mean_s + pulse.mean_s
    v = rtd_moments.variance_s2 + pulse.variance_s2
    sk = getattr(rtd_moments, "skewness", None)
    if sk is None:
        return AnalyticMoments(mean_s=m, variance_s2=v, skewness=None)
    mu3 = sk * np.asarray(rtd_moments.variance_s2) ** 1.5 + pulse.third_central_moment_s3
    return AnalyticMoments(mean_s=m, variance_s2=v, skewness=mu3 / np.asarray(v) ** 1.5)
