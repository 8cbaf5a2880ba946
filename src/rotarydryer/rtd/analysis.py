r"""Moments and distributions of residence-time curves (simulated or measured).

Definitions (Levenspiel 1999 ch. 11; Lee (2008) Eq. 2.2–2.3; Ajayi (2011)
Eq. 3.5–3.8): for an outlet tracer signal c(t) after a pulse injected at the
time origin,

$$
A = \int c\,dt,\quad E(t) = c(t)/A,\quad F(t) = \int_0^t E\,dt',\quad
\bar t = \int t\,E\,dt,\quad \sigma^2 = \int (t-\bar t)^2 E\,dt,\quad
\gamma = \frac{\int (t-\bar t)^3 E\,dt}{\sigma^3}.
$$

All integrals use the trapezoidal rule on the samples as given (this is what
Ajayi (2011) Eq. 3.7–3.8 prescribes and it reproduces Lee (2008) Table 7.3 on
the Invicta data: 11.08 min / 6.73 min), so uniform simulated grids and
irregularly sampled measurements are handled by the same code. Moments are
products integrated by the trapezoidal rule (∫ t·c dt, not t times ∫ c dt).

Treatment of measured curves, in this order:

1. **Time origin**: times are shifted by ``time_origin_s`` (the start of the
   tracer injection; Lee's gPROMS data start the pulse at t = 21600 s).
2. **Baseline** (background) removal, ``baseline=``:
   ``"none"``; ``"leading"`` — the median of the samples before breakthrough
   (before the first sample above ``breakthrough_fraction`` × peak, measured
   above the minimum) or of those inside ``baseline_window_s``;
   ``"trailing"`` — the median of the samples after the last one above that
   level (or inside ``baseline_window_s``); ``"linear"`` — a straight line
   through the leading and trailing medians (at the median times of the two
   windows), for drifting instruments; or a number (constant background in
   signal units). The median is used because the background samples of
   tracer tests contain outliers (Ajayi (2011) App. B test 4: 0.076 and
   2.04 ppm among ~0.9 ppm). After subtraction negative values are clipped to
   zero (``clip_negative=True``) as in the derived Ajayi moments of the notes.
3. **Truncated tail**: the curve counts as truncated when its last value is
   above ``tail_threshold`` × peak (after baseline removal). This is always
   reported. With ``tail="exponential"`` (always) or ``tail="auto"`` (only
   when truncated), an exponential $c = c_T e^{-k(t-T)}$ fitted by
   linear least squares to log c of the last ``tail_points`` positive samples
   after the peak (default 5) is appended from the last
   sample time T to infinity; its contributions to A and to the moments are
   analytic (∫ t^n e^{-kt}). The fitted value at T (not the raw last sample)
   is used as c_T, which makes the extrapolation less sensitive to one noisy
   point. The extrapolated fraction of the area is reported.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from scipy.integrate import cumulative_trapezoid, trapezoid

from .._validation import check_choice, check_finite, check_range
from ._datafile import fmt

__all__ = ["RTDMoments", "rtd_moments", "exit_age_curve", "subtract_baseline", "BASELINE_METHODS", "TAIL_METHODS"]

BASELINE_METHODS = ("none", "leading", "trailing", "linear")
#: an exponential tail extrapolated from a curve that ends above this fraction of its peak (still near its
#: top, where the decay is not yet exponential), or that makes up more than TAIL_EXTRAPOLATED_WARN of the area,
#: gets a warning (a curve cut at 62 % of its peak gave a recovery of 1.22 and a mean 12 % long)
TAIL_END_WARN = 0.3
TAIL_EXTRAPOLATED_WARN = 0.25
TAIL_METHODS = ("none", "exponential", "auto")
#: s; the largest |time| of a tracer record (32 years: larger is a unit error, and its third moment overflows)
MAX_RECORD_TIME_S = 1e9
#: s; the shortest span of a tracer record (a record of picoseconds is a unit error, not a curve to fit)
MIN_RECORD_SPAN_S = 1e-3
#: the largest |signal| (its moments, signal x time^3, stay finite; a tracer signal is rescaled, not lost)
MAX_SIGNAL = 1e100
#: the smallest peak of a tracer-CSV signal (a fit's residuals of a 1e-300 signal vanish: R^2 NaN; rescale it)
MIN_SIGNAL_PEAK = 1e-100


@dataclass(frozen=True)
class RTDMoments:
    """Moments of an RTD curve, with how they were obtained.

    Attributes
    ----------
    mean_s : mean residence time t̄ (s), measured from ``time_origin_s``.
    variance_s2 : variance σ² (s²).
    std_s : standard deviation σ (s).
    skewness : standardised skewness μ3/σ³ (-).
    third_central_moment_s3 : μ3 (s³).
    area : ∫ c dt after baseline removal, including any extrapolated tail
        (signal unit × s).
    recovery : area / expected_area (-), or None when no expected area given.
    baseline : constant baseline subtracted (signal unit; for ``"linear"`` the
        value at the peak time), 0 when none.
    baseline_method : the method used.
    time_origin_s : time origin (s) in the input clock.
    first_time_s, last_time_s : first and last sample time after the shift (s).
    n_points : number of samples.
    tail_truncated : True if the last value exceeds tail_threshold × peak.
    tail_end_fraction_of_peak : last value / peak (-).
    tail_extrapolated : True if an exponential tail was appended.
    tail_decay_rate_per_s : fitted decay rate k (1/s) or None.
    extrapolated_area_fraction : share of ``area`` from the extrapolated tail (-).
    """

    mean_s: float
    variance_s2: float
    std_s: float
    skewness: float
    third_central_moment_s3: float
    area: float
    recovery: float | None
    baseline: float
    baseline_method: str
    time_origin_s: float
    first_time_s: float
    last_time_s: float
    n_points: int
    tail_truncated: bool
    tail_end_fraction_of_peak: float
    tail_extrapolated: bool
    tail_decay_rate_per_s: float | None
    extrapolated_area_fraction: float

    @property
    def mean_min(self) -> float:
        """Mean residence time in minutes."""
        return self.mean_s / 60.0

    @property
    def std_min(self) -> float:
        """Standard deviation in minutes."""
        return self.std_s / 60.0

    def to_dict(self) -> dict[str, Any]:
        """Plain dict of all fields (JSON-serialisable)."""
        return asdict(self)


def _validate_curve(time_s, signal, min_points=3):
    t = check_finite("time_s", time_s)
    c = check_finite("signal", signal)
    if t.ndim != 1 or c.ndim != 1:
        raise ValueError(f"time_s and signal must be 1-D, got shapes {t.shape} and {c.shape}")
    if t.size != c.size:
        raise ValueError(f"time_s and signal must have the same length, got {t.size} and {c.size}")
    if t.size < min_points:
        raise ValueError(f"an RTD curve needs at least {min_points} points, got {t.size}")
    big = float(np.max(np.abs(t)))
    if big > MAX_RECORD_TIME_S:
        raise ValueError(f"time_s reaches {fmt(big)} s; a tracer record lies within {MAX_RECORD_TIME_S:g} s (32 years) "
                         "of its origin: are the times in seconds?")
    if float(np.max(np.abs(c))) > MAX_SIGNAL:
        raise ValueError(f"signal reaches {fmt(float(np.max(np.abs(c))))}; the allowed range is [-{MAX_SIGNAL:g}, "
                         f"{MAX_SIGNAL:g}] (the RTD does not depend on the signal's unit: rescale it)")
    dt = np.diff(t)
    if np.any(dt <= 0):
        i = int(np.argmax(dt <= 0))
        raise ValueError(
            f"time_s must be strictly increasing; time_s[{i + 1}] = {fmt(t[i + 1])} s "
            f"follows time_s[{i}] = {fmt(t[i])} s"
        )
    span = float(t[-1] - t[0])
    if span < MIN_RECORD_SPAN_S:
        raise ValueError(f"time_s spans {fmt(span)} s; a tracer record spans at least {MIN_RECORD_SPAN_S:g} s: are "
                         "the times in seconds?")
    return t, c


def _baseline(t, c, method, window, breakthrough_fraction):
    """Return the baseline array (same shape as c) and a representative value."""
    if not isinstance(method, str):
        b = float(check_finite("baseline", method))
        lo, hi = float(np.min(c)), float(np.max(c))
        if b < lo - (hi - lo):
            raise ValueError(
                f"baseline = {fmt(b)} lies below the lowest sample ({fmt(lo)}) by more than the signal's whole "
                f"range ({fmt(hi - lo)}): a background is the level the signal sits at before and after the "
                "tracer, and this one would add more area than the tracer; give a baseline inside the signal's "
                "range (or 'leading', 'trailing', 'linear')"
            )
        return np.full_like(c, b), b
    check_choice("baseline", method, BASELINE_METHODS)
    if method == "none":
        return np.zeros_like(c), 0.0
    lo = np.min(c)
    level = lo + breakthrough_fraction * (np.max(c) - lo)
    above = np.nonzero(c > level)[0]
    if above.size == 0:
        raise ValueError(f"baseline={method!r}: the signal is constant ({fmt(lo)}); there is no tracer peak")

    def window_mask(which):
        if window is not None:
            w0, w1 = (float(x) for x in window)
            m = (t >= w0) & (t <= w1)
        elif which == "leading":
            m = np.arange(t.size) < above[0]
        else:
            m = np.arange(t.size) > above[-1]
        if not np.any(m):
            if window is not None:
                where = f"baseline_window_s={window!r}"
            elif which == "leading":
                where = "before breakthrough"
            else:
                where = "after the signal returns below breakthrough_fraction of the peak"
            raise ValueError(
                f"baseline={method!r}: no samples in the {which} baseline window ({where}); "
                "give baseline_window_s or a numeric baseline"
            )
        return m

    if method in ("leading", "trailing"):
        m = window_mask(method)
        b = float(np.median(c[m]))
        return np.full_like(c, b), b
    # linear
    m0, m1 = window_mask("leading"), window_mask("trailing")
    t0, b0 = float(np.median(t[m0])), float(np.median(c[m0]))
    t1, b1 = float(np.median(t[m1])), float(np.median(c[m1]))
    slope = (b1 - b0) / (t1 - t0) if t1 > t0 else 0.0
    line = b0 + slope * (t - t0)
    return line, float(line[int(np.argmax(c))])


def _fit_tail(t, y, tail_points):
    ipk = int(np.argmax(y))
    cand = np.nonzero((np.arange(y.size) > ipk) & (y > 0))[0]
    n = int(tail_points)
    if cand.size < max(n, 2):
        raise ValueError(
            f"tail extrapolation needs at least tail_points = {n} positive samples after the peak, "
            f"found {cand.size}"
        )
    idx = cand[-n:]
    tt, ly = t[idx], np.log(y[idx])
    slope, intercept = np.polyfit(tt, ly, 1)
    k = -slope
    if not (k > 0 and np.isfinite(k)):
        raise ValueError(
            f"tail extrapolation: the last {n} tail samples do not decay "
            f"(fitted rate {fmt(k)} 1/s); the curve cannot be extrapolated exponentially"
        )
    c_end = float(np.exp(intercept + slope * t[-1]))
    return float(k), c_end


def _prepare(time_s, signal, time_origin_s, baseline, baseline_window_s, breakthrough_fraction, clip_negative):
    t, c = _validate_curve(time_s, signal)
    t0 = float(check_finite("time_origin_s", time_origin_s))
    if t0 >= t[-1]:
        raise ValueError(
            f"time_origin_s = {fmt(t0)} s is at or after the last sample ({fmt(t[-1])} s); the tracer "
            "injection must start before the data end"
        )
    check_range("breakthrough_fraction", breakthrough_fraction, 0.0, 1.0)
    line, bval = _baseline(t, c, baseline, baseline_window_s, breakthrough_fraction)
    y = c - line
    if clip_negative:
        y = np.maximum(y, 0.0)
    ts = t - t0
    if not np.max(y) > 0:
        raise ValueError("signal has no positive part after baseline removal; cannot form an RTD")
    return ts, y, bval, t0


def rtd_moments(
    time_s,
    signal,
    *,
    time_origin_s: float = 0.0,
    baseline="none",
    baseline_window_s: tuple[float, float] | None = None,
    breakthrough_fraction: float = 0.05,
    clip_negative: bool = True,
    tail: str = "none",
    tail_threshold: float = 0.01,
    tail_points: int = 5,
    expected_area: float | None = None,
) -> RTDMoments:
    """Moments of a tracer outlet curve (trapezoidal rule; see module docstring).

    Parameters
    ----------
    time_s : 1-D array, sample times (s), strictly increasing; any spacing.
    signal : 1-D array, outlet tracer signal (any unit: concentration, ppm,
        normalised E in 1/s or 1/h...). The unit only affects ``area``.
    time_origin_s : start of the tracer injection on the ``time_s`` clock (s).
    baseline : ``"none"``, ``"leading"``, ``"trailing"``, ``"linear"`` or a number
        (signal unit).
    baseline_window_s : optional (start, end) window (s, input clock) for the
        ``"leading"``/``"trailing"`` median.
    breakthrough_fraction : (0, 1), level (fraction of peak above the minimum)
        that defines breakthrough for the automatic baseline windows.
    clip_negative : clip negative values to 0 after baseline removal.
    tail : ``"none"`` (detect and report only), ``"exponential"`` (always
        extrapolate) or ``"auto"`` (extrapolate only if truncated).
    tail_threshold : (0, 1), last value / peak above which the tail counts as
        truncated.
    tail_points : number (>= 2) of tail samples used for the exponential fit.
    expected_area : area corresponding to 100 % recovery (signal unit × s);
        if given, ``recovery = area / expected_area``.

    Returns
    -------
    RTDMoments
    """
    check_choice("tail", tail, TAIL_METHODS)
    check_range("tail_threshold", tail_threshold, 0.0, 1.0)
    check_range("tail_points", tail_points, 2, math.inf, low_inclusive=True)
    ts, y, bval, t0 = _prepare(
        time_s, signal, time_origin_s, baseline, baseline_window_s, breakthrough_fraction, clip_negative
    )
    peak = float(np.max(y))
    end_frac = float(y[-1] / peak)
    truncated = end_frac > tail_threshold
    extrapolate = tail == "exponential" or (tail == "auto" and truncated)

    area_data = float(trapezoid(y, ts))
    if not area_data > 0:
        raise ValueError("the RTD curve has zero area after baseline removal")
    c = float(trapezoid(ts * y, ts)) / area_data  # data-only mean, used as shift
    u = ts - c
    raw = [area_data] + [float(trapezoid(u**n * y, ts)) for n in (1, 2, 3)]
    k = None
    if extrapolate:
        k, c_end = _fit_tail(ts, y, tail_points)
        T = ts[-1] - c
        # ∫_T^∞ u^n c_end e^{-k(u-T)} du for n = 0..3
        tails = [
            c_end / k,
            c_end * (T / k + 1 / k**2),
            c_end * (T**2 / k + 2 * T / k**2 + 2 / k**3),
            c_end * (T**3 / k + 3 * T**2 / k**2 + 6 * T / k**3 + 6 / k**4),
        ]
        raw = [r + tl for r, tl in zip(raw, tails, strict=True)]
        extra_frac = tails[0] / raw[0]
    else:
        extra_frac = 0.0
    area = raw[0]
    if extrapolate and (end_frac > TAIL_END_WARN or extra_frac > TAIL_EXTRAPOLATED_WARN):
        warnings.warn(
            f"the tail is extrapolated from a curve that ends at {end_frac:.0%} of its peak, and makes "
            f"{extra_frac:.0%} of the area: the moments rest on the fitted exponential more than on the data "
            "(a curve cut near its top has not begun its exponential decay); record until the signal returns "
            "near its baseline",
            UserWarning,
            stacklevel=2,
        )
    m1, m2, m3 = raw[1] / area, raw[2] / area, raw[3] / area
    mean = c + m1
    var = m2 - m1**2
    mu3 = m3 - 3 * m1 * m2 + 2 * m1**3
    span = float(ts[-1] - ts[0])
    if not var > 1e-12 * span**2:
        raise ValueError(
            f"the RTD curve has a negligible variance ({fmt(var)} s^2 over a {fmt(span)} s record): "
            "the peak is not resolved by the samples (fewer than two non-zero samples?)"
        )
    if not mean > 0:
        raise ValueError(
            f"the mean residence time is {fmt(mean)} s (not > 0): the time origin {fmt(t0)} s is after most "
            "of the tracer signal; check time_origin_s (the start of the injection)"
        )
    std = math.sqrt(var)
    recovery = None
    if expected_area is not None:
        ea = float(check_range("expected_area", expected_area, 0.0, math.inf))
        recovery = area / ea
    return RTDMoments(
        mean_s=float(mean),
        variance_s2=float(var),
        std_s=std,
        skewness=float(mu3 / std**3),
        third_central_moment_s3=float(mu3),
        area=float(area),
        recovery=recovery,
        baseline=float(bval),
        baseline_method=baseline if isinstance(baseline, str) else "constant",
        time_origin_s=t0,
        first_time_s=float(ts[0]),
        last_time_s=float(ts[-1]),
        n_points=int(ts.size),
        tail_truncated=bool(truncated),
        tail_end_fraction_of_peak=end_frac,
        tail_extrapolated=bool(extrapolate),
        tail_decay_rate_per_s=k,
        extrapolated_area_fraction=float(extra_frac),
    )


def exit_age_curve(
    time_s,
    signal,
    *,
    time_origin_s: float = 0.0,
    baseline="none",
    baseline_window_s: tuple[float, float] | None = None,
    breakthrough_fraction: float = 0.05,
    clip_negative: bool = True,
):
    """E(t) and F(t) of a tracer curve on its own samples.

    Same preprocessing as [`rtd_moments`][rotarydryer.rtd.analysis.rtd_moments] (time origin, baseline, clipping);
    E = c / ∫c dt (trapezoidal), F = cumulative trapezoid of E (F(t_last) = 1).

    Returns
    -------
    (time_s, e_per_s, f) : times shifted to the origin (s), E (1/s), F (-).
    """
    ts, y, _, _ = _prepare(
        time_s, signal, time_origin_s, baseline, baseline_window_s, breakthrough_fraction, clip_negative
    )
    area = float(trapezoid(y, ts))
    e = y / area
    f = cumulative_trapezoid(e, ts, initial=0.0)
    return ts, e, f


def subtract_baseline(
    time_s,
    signal,
    baseline="leading",
    *,
    baseline_window_s: tuple[float, float] | None = None,
    breakthrough_fraction: float = 0.05,
    clip_negative: bool = True,
):
    """Remove a background from a tracer curve (methods as [`rtd_moments`][rotarydryer.rtd.analysis.rtd_moments]).

    Returns
    -------
    (signal_corrected, baseline_value) : corrected signal (same unit, clipped at
    0 if ``clip_negative``) and the baseline value (for ``"linear"`` at the peak).
    """
    t, c = _validate_curve(time_s, signal)
    check_range("breakthrough_fraction", breakthrough_fraction, 0.0, 1.0)
    line, bval = _baseline(t, c, baseline, baseline_window_s, breakthrough_fraction)
    y = c - line
    return (np.maximum(y, 0.0) if clip_negative else y), bval
