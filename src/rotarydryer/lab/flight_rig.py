"""Flight-unloading rig: load-cell signals, filtering, alignment and repose-angle fits.

Lee (2008) ch. 5 unloaded a single 1 m flight section, turned by a stepper motor,
into a tray on four load cells sampled at 100 Hz. His analysis (Lee (2008) section
5.4.2-5.4.3 and the Appendix II Matlab code) was:

1. sum the four load cells and subtract the initial mass;
2. low-pass filter with a 200th-order FIR filter (``fir1(200, 0.03)``);
3. differentiate with central differences (Matlab ``gradient``) to a discharge rate;
4. align the start of unloading (first positive rate) with the model start;
5. compare with the geometric model at the mean measured repose angle and at
   +/- 2 standard deviations (his "95 % band").

This module does the same, with two corrections, and adds a least-squares fit of
the repose angle with a confidence interval.

Choices where the sources disagree or are wrong
-----------------------------------------------
* **Cut-off frequency.** The text (Lee (2008) l.5871) says 3 Hz; the code
  ``fir1(200, 0.03)`` normalises the cut-off to the Nyquist frequency (50 Hz), which is
  **1.5 Hz**. The code is what produced the thesis figures, so the default is
  [`LEE_CUTOFF_CODE`][rotarydryer.lab.flight_rig.LEE_CUTOFF_CODE] = 1.5 Hz; ``cutoff=LEE_CUTOFF_TEXT`` (3 Hz) gives the text
  reading. The filter is designed exactly as ``fir1``: 201 taps, Hamming window,
  unit gain at DC (``scipy.signal.firwin``).
* **Group delay.** Lee's ``conv`` output is delayed by 100 samples (1.0 s) and was not
  corrected. The default ``phase="zero"`` applies the same linear-phase filter once
  and removes its exact group delay of (numtaps - 1)/2 samples, so the magnitude
  response is Lee's (-6 dB at the cut-off) and the phase is zero. ``phase="filtfilt"``
  (forward-backward, squared magnitude response) and ``phase="causal"`` (Lee's
  uncorrected delay, for reproducing his plots) are selectable. Signal ends are padded
  by odd reflection, as ``filtfilt`` does.
* **Unloading start.** Lee's criterion (the last non-positive rate sample before the
  peak) is available as ``method="lee2008"``; it is biased early by the filter's
  impulse-response length. The default ``method="steepest"`` takes the steepest rise
  of the filtered rate: the rate jumps at the start of unloading (the sudden start Lee
  observed; the geometric holdup slope is non-zero there), and a symmetric (zero-phase)
  filter leaves the steepest point of a step where the step is.
* **Repose angle and alignment are confounded.** The held area depends on the root
  angle ``psi`` and the repose angle ``phi`` only through ``psi - phi`` (rotating the
  flight and the surface together changes nothing), so a run aligned at an *unknown*
  angle cannot identify ``phi`` (a shift of ``phi`` is a shift of time by
  ``phi/omega``). The fit therefore needs the root angle ``start_angle`` at the start
  of unloading (Lee measured the initial angle from the camera images, section 5.4.1)
  and uses Lee's Matlab assumption that the flight then holds its geometric holdup
  ``H(start_angle, phi)`` (the surface already at the repose angle): the total mass
  discharged then identifies ``phi``. With a measured initial fill instead
  (``initial_holdup=``), the start time and ``phi`` cannot both be fitted; asking for
  both raises ``ValueError``.
* **Fitted signal.** The fit uses the unfiltered (summed) mass by default: filtering
  correlates the noise and would make ordinary least-squares intervals too narrow.
  Residual autocorrelation (vibration) is allowed for by an AR(1) variance inflation
  ``(1 + r)/(1 - r)`` (``ci_method="ar1"``, the default; ``"ols"`` switches it off).

Model
-----
Accumulated discharged mass (Lee (2008) Appendix II, ``am = m(1) - m``; section 5.4.3):

    m(t) = m_off + rho_b L [H(psi_0, phi) - H(psi(t), phi)],
    psi(t) = psi_0 + omega (t - t_0) for t > t_0, psi_0 before,

with ``H`` the exact held area of [`FlightedDrum.holdup_area`][rotarydryer.geometry.drum.FlightedDrum.holdup_area] (Lee (2008)
Eq. 4.14-4.17; for the single rig flight only phases III and IV matter, the
"drum" radius being the flight's radius of curvature, see [`rig_drum`][rotarydryer.lab.flight_rig.rig_drum]).
"""

from __future__ import annotations

import math
import warnings
from array import array
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import NamedTuple, Optional

import numpy as np

from .._io import write_text_atomic
from .._validation import check_choice, check_finite, check_positive, check_range
from ..estimation.uncertainty import linearised_uncertainty
from ..geometry import FlightedDrum, TwoSectionFlight

__all__ = [
    "LEE_CUTOFF_CODE",
    "LEE_CUTOFF_TEXT",
    "LEE_NUMTAPS",
    "LEE_SAMPLE_RATE",
    "MAX_RIG_ROWS",
    "MAX_RIG_MASS_KG",
    "FILTER_PHASES",
    "ONSET_METHODS",
    "RIG_FLIGHTS",
    "RigRun",
    "RigFit",
    "ReposeBand",
    "RigAnalysis",
    "read_rig_csv",
    "parse_rig_text",
    "write_rig_csv",
    "design_lowpass",
    "lowpass",
    "mass_rate",
    "detect_unloading_start",
    "rig_drum",
    "accumulated_mass",
    "model_discharge_rate",
    "synthetic_run",
    "fit_repose_angle",
    "repose_band",
    "fraction_inside",
    "analyse_run",
    "plot_analysis",
]

LEE_SAMPLE_RATE = 100.0
"""Load-cell sampling rate of Lee's rig, Hz (Lee (2008) l.5678)."""
LEE_NUMTAPS = 201
"""Taps of Lee's FIR filter: ``fir1(200, ...)`` is order 200 (Lee (2008) Appendix II)."""
LEE_CUTOFF_CODE = 1.5
"""Cut-off of ``fir1(200, 0.03)`` at 100 Hz (0.03 x Nyquist), Hz: what Lee's code ran."""
LEE_CUTOFF_TEXT = 3.0
"""Cut-off stated in Lee (2008) l.5871, Hz (0.03 x sampling rate)."""

FILTER_PHASES = ("zero", "filtfilt", "causal")
ONSET_METHODS = ("hinge", "steepest", "lee2008")

# Lee (2008) Table 5.1 (lee_flight_dimensions.csv): s1, s2 (m), alpha1, alpha2 (deg),
# radius of curvature of the flight back (m; None = flat), section length (m).
RIG_FLIGHTS = {
    "full_scale": dict(s1=0.200, s2=0.220, alpha1=90.0, alpha2=117.0, curvature=2.5, length=1.0),
    "half_scale": dict(s1=0.100, s2=0.110, alpha1=90.0, alpha2=117.0, curvature=1.25, length=1.0),
    "alternative": dict(s1=0.150, s2=0.180, alpha1=90.0, alpha2=100.0, curvature=None, length=1.0),
    # Lee (2008) Appendix II Matlab default (R 2.5 m, s1 0.1, s2 0.11, 90/120 deg)
    "lee_code": dict(s1=0.100, s2=0.110, alpha1=90.0, alpha2=120.0, curvature=2.5, length=1.0),
}

MAX_RIG_ROWS = 200_000
"""Most samples read from one rig file (33 min at 100 Hz); the reader stops with an error beyond."""
MAX_RIG_MASS_KG = 1.0e6
"""Largest load-cell reading of a rig record, kg (a flight of a plant drum holds tens of kg; the bound keeps the sums
and the fit finite); the reader refuses a larger one."""

_FLAT_RADIUS = 50.0  # m: radius standing in for a flat flight back ("No Curve")


# ---------------------------------------------------------------------------- data
@dataclass(frozen=True)
class RigRun:
    """One load-cell record: ``time`` (s, uniformly sampled) and summed ``mass`` (kg)."""

    time: np.ndarray
    mass: np.ndarray
    source: str = ""

    def __post_init__(self):
        t = check_finite("time", self.time).ravel()
        m = check_finite("mass", self.mass).ravel()
        if t.size != m.size:
            raise ValueError(f"time and mass must have the same length, got {t.size} and {m.size}")
        if t.size < 8:
            raise ValueError(f"a rig run needs at least 8 samples, got {t.size}")
        dt = np.diff(t)
        if np.any(dt <= 0):
            raise ValueError("time must be strictly increasing")
        if np.ptp(dt) > 1e-6 * max(abs(dt.mean()), 1e-12) + 1e-9:
            raise ValueError(
                f"time must be uniformly sampled; sample intervals range from {dt.min():g} to {dt.max():g} s"
            )
        object.__setattr__(self, "time", t)
        object.__setattr__(self, "mass", m)

    @property
    def sample_interval(self) -> float:
        """Sample interval, s."""
        return float((self.time[-1] - self.time[0]) / (self.time.size - 1))

    @property
    def sample_rate(self) -> float:
        """Sampling rate, Hz."""
        return 1.0 / self.sample_interval


def read_rig_csv(path, *, time_column: int = 0, max_rows: Optional[int] = None) -> RigRun:
    """Read a load-cell CSV: a time column (s) and one or more load-cell columns (kg).

    Lines starting with ``#`` are skipped; a header row (non-numeric) is allowed before the
    data. All columns other than ``time_column`` are summed (Lee (2008) section 5.4.2 step 1:
    sum of the four load cells), as in Lee's Matlab input (column 1 time, column 2 summed mass).

    The file is read line by line (UTF-8, at most 64 MB) and refused beyond ``max_rows``
    (default [`MAX_RIG_ROWS`][rotarydryer.lab.flight_rig.MAX_RIG_ROWS], 200 000 samples = 33 min at 100 Hz). Errors name the file,
    the line and the column: ``rig.csv line 17: 'abc' is not a number in column time_s``;
    times must be finite, strictly increasing and uniformly sampled.
    """
    from ..rtd._datafile import data_lines

    path = Path(path)
    return _read_rig_lines(data_lines(path, "rig data file"), str(path), time_column=time_column, max_rows=max_rows)


def parse_rig_text(text: str, name: str = "<string>", *, time_column: int = 0,
                   max_rows: Optional[int] = None) -> RigRun:
    """[`read_rig_csv`][rotarydryer.lab.flight_rig.read_rig_csv] of the text of a load-cell CSV held in memory (e.g. an upload to the
    web app; nothing is written to disk); messages name ``name`` as they name the file."""
    from ..rtd._datafile import text_lines

    return _read_rig_lines(text_lines(text), name, time_column=time_column, max_rows=max_rows)


def _read_rig_lines(numbered_lines, name: str, *, time_column: int = 0, max_rows: Optional[int] = None) -> RigRun:
    from ..rtd._datafile import csv_rows, parse_number, too_many_rows

    limit = MAX_RIG_ROWS if max_rows is None else int(max_rows)
    header: Optional[list] = None
    ncol = None
    first_line = None
    cols: list = []
    lines = []
    for k, row in csv_rows(numbered_lines, name):
        if ncol is None:
            try:
                [float(v) for v in row]
            except ValueError:
                if header is not None:
                    raise ValueError(f"{name} line {k}: a second header row before the data: "
                                     f"{', '.join(c.strip() for c in row)}") from None
                header = [c.strip() or f"column {j + 1}" for j, c in enumerate(row)]
                continue  # header
            ncol = len(row)
            first_line = k
            if header is not None and len(header) != ncol:
                raise ValueError(f"{name} line {k}: {ncol} columns, but the header has {len(header)} "
                                 f"({', '.join(header)})")
            if ncol < 2:
                raise ValueError(f"{name} line {k}: 1 column; a rig record needs a time column and at least one "
                                 "load-cell column")
            names = header or [f"column {j + 1}" for j in range(ncol)]
            cols = [array("d") for _ in range(ncol)]
        if len(row) != ncol:
            raise ValueError(f"{name} line {k}: {len(row)} columns, expected {ncol} as on line {first_line}")
        if len(lines) >= limit:
            raise too_many_rows(name, k, limit)
        for j, v in enumerate(row):
            cols[j].append(parse_number(v, name, k, names[j]))
        lines.append(k)
    if ncol is None:
        raise ValueError(f"{name}: no numeric data rows (expected a time column (s) and load-cell columns (kg))")
    if isinstance(time_column, bool) or int(time_column) != time_column or not 0 <= time_column < ncol:
        raise ValueError(f"time_column = {time_column} is not a column of {name} (0 .. {ncol - 1})")
    tc = int(time_column)
    # the header's units, where a column names one (time_min, load_g); a name without one is s and kg as ever (a
    # time_min column was read as seconds; found by fuzzing)
    t = np.frombuffer(cols[tc], dtype=float) * _unit_factor(names[tc], _RIG_TIME_UNITS)
    m = np.zeros_like(t)
    for j in range(ncol):
        if j != tc:
            v = np.frombuffer(cols[j], dtype=float) * _unit_factor(names[j], _RIG_MASS_UNITS)
            big = np.flatnonzero(np.abs(v) > MAX_RIG_MASS_KG)
            if big.size:        # a reading no load cell gives (1e300 kg "fitted" a repose angle; found by fuzzing)
                i = int(big[0])
                raise ValueError(f"{name} line {lines[i]}: {names[j]} = {_fmt(v[i])} kg is outside the allowed range "
                                 f"[-{_fmt(MAX_RIG_MASS_KG)}, {_fmt(MAX_RIG_MASS_KG)}] kg of a load-cell reading")
            m += v
    tname = names[tc]
    if t.size < 8:
        raise ValueError(f"{name}: a rig run needs at least 8 samples, got {t.size}")
    dt = np.diff(t)
    bad = np.flatnonzero(dt <= 0)
    if bad.size:
        i = int(bad[0]) + 1
        raise ValueError(f"{name} line {lines[i]}: {tname} = {_fmt(t[i])} s is not after {_fmt(t[i - 1])} s "
                         f"(line {lines[i - 1]}); times must be strictly increasing")
    mean_dt = (t[-1] - t[0]) / (t.size - 1)
    dev = np.abs(dt - mean_dt)
    if np.ptp(dt) > 1e-6 * max(abs(dt.mean()), 1e-12) + 1e-9:  # the criterion of RigRun
        i = int(np.argmax(dev)) + 1
        raise ValueError(
            f"{name} line {lines[i]}: the time step {_fmt(dt[i - 1])} s from line {lines[i - 1]} differs from "
            f"the mean step {_fmt(mean_dt)} s; the record must be uniformly sampled (time in column {tname}, s)"
        )
    return RigRun(t.copy(), m, source=name)


#: a rig record's column name suffix -> its factor to s (time) or kg (load cells)
_RIG_TIME_UNITS = {"_s": 1.0, "_ms": 1e-3, "_min": 60.0, "_h": 3600.0}
_RIG_MASS_UNITS = {"_kg": 1.0, "_g": 1e-3, "_t": 1e3}


def _unit_factor(name: str, units: dict) -> float:
    """The factor of the unit a column's name ends with (``units``), else 1 (a name without a unit)."""
    key = str(name).strip().lower()
    return next((f for suf, f in sorted(units.items(), key=lambda kv: -len(kv[0])) if key.endswith(suf)), 1.0)


def _fmt(x) -> str:
    from ..rtd._datafile import fmt

    return fmt(x)


def write_rig_csv(path, run: RigRun, comment: str = "") -> None:
    """Write ``run`` as ``time_s,mass_kg`` CSV (optional ``#`` comment first line)."""
    lines = ([f"# {comment}"] if comment else []) + ["time_s,mass_kg"]
    lines += [f"{t:.6f},{m:.6f}" for t, m in zip(run.time, run.mass)]
    write_text_atomic(path, "\n".join(lines) + "\n", newline="")


# ---------------------------------------------------------------------------- filtering
def design_lowpass(cutoff: float = LEE_CUTOFF_CODE, sample_rate: float = LEE_SAMPLE_RATE,
                   numtaps: int = LEE_NUMTAPS) -> np.ndarray:
    """Linear-phase FIR low-pass taps, identical to Matlab ``fir1(numtaps-1, cutoff/(fs/2))``.

    Hamming window, unit gain at DC, -6 dB at ``cutoff`` (Hz). Lee (2008) Appendix II
    uses ``fir1(200, 0.03)`` at 100 Hz, i.e. ``cutoff = 1.5`` Hz (default).
    """
    from scipy.signal import firwin

    fs = float(check_positive("sample_rate", sample_rate, unit="Hz"))
    fc = float(check_range("cutoff", cutoff, 0.0, fs / 2.0, unit="Hz"))
    if isinstance(numtaps, bool) or int(numtaps) != numtaps or numtaps < 3 or numtaps % 2 == 0:
        raise ValueError(f"numtaps = {numtaps!r} must be an odd integer >= 3 (type I linear-phase FIR)")
    return firwin(int(numtaps), fc, window="hamming", fs=fs)


def lowpass(signal, sample_rate: float = LEE_SAMPLE_RATE, cutoff: float = LEE_CUTOFF_CODE,
            numtaps: int = LEE_NUMTAPS, *, phase: str = "zero") -> np.ndarray:
    """Low-pass filter a load-cell signal with Lee's FIR filter (see the module notes).

    Parameters
    ----------
    signal : array_like
        Samples (kg), uniformly spaced; filtered along the last axis.
    sample_rate : float
        Hz. cutoff : float, Hz (default 1.5, Lee's code; 3.0 is his text).
    phase : {"zero", "filtfilt", "causal"}
        ``"zero"``: single pass, exact group-delay correction (default);
        ``"filtfilt"``: forward-backward; ``"causal"``: Lee's uncorrected ``conv``
        (delayed by (numtaps-1)/2 samples, output truncated to the input length).
    """
    from scipy.signal import filtfilt, lfilter, lfilter_zi

    check_choice("phase", phase, FILTER_PHASES)
    x = check_finite("signal", signal)
    taps = design_lowpass(cutoff, sample_rate, numtaps)
    n = x.shape[-1]
    half = (len(taps) - 1) // 2
    if phase == "causal":
        zi = lfilter_zi(taps, [1.0])
        zi = zi.reshape((1,) * (x.ndim - 1) + (-1,)) * x[..., :1]
        return lfilter(taps, [1.0], x, axis=-1, zi=zi)[0]
    if phase == "filtfilt":
        padlen = min(3 * len(taps), n - 1)
        return filtfilt(taps, [1.0], x, axis=-1, padlen=padlen)
    # odd reflection padding (as filtfilt), one pass, drop the group delay
    pad = min(half, n - 1)
    left = 2.0 * x[..., :1] - x[..., pad:0:-1]
    right = 2.0 * x[..., -1:] - x[..., -2:-pad - 2:-1]
    ext = np.concatenate([left, x, right], axis=-1)
    extra = half - pad  # if the signal is shorter than the filter, pad with edge values
    if extra > 0:
        ext = np.concatenate([np.repeat(ext[..., :1], extra, -1), ext, np.repeat(ext[..., -1:], extra, -1)], -1)
    from scipy.signal import oaconvolve

    shape = (1,) * (ext.ndim - 1) + (-1,)
    return oaconvolve(ext, taps.reshape(shape), mode="valid", axes=-1)


def mass_rate(mass, sample_rate: float = LEE_SAMPLE_RATE) -> np.ndarray:
    """Discharge rate dm/dt, kg/s: central differences, one-sided at the ends (Matlab ``gradient``,
    Lee (2008) section 5.4.2 step 4)."""
    fs = float(check_positive("sample_rate", sample_rate, unit="Hz"))
    m = check_finite("mass", mass)
    return np.gradient(m, 1.0 / fs, axis=-1)


def detect_unloading_start(time, mass, *, method: str = "hinge", cutoff: float = LEE_CUTOFF_CODE,
                           numtaps: int = LEE_NUMTAPS, phase: str = "zero", window: Optional[float] = None) -> float:
    """Time (s) at which unloading starts, from a raw accumulated-mass record (kg).

    The record is filtered with [`lowpass`][rotarydryer.lab.flight_rig.lowpass] (``cutoff`` Hz, ``phase``) and
    differentiated ([`mass_rate`][rotarydryer.lab.flight_rig.mass_rate]). Methods:

    * ``"hinge"`` (default): least-squares fit, on the *filtered* mass, of the
      *filtered* model "constant, then a cubic in (t - t_s)" (a hinge: the rate jumps
      at t_s, the sudden start Lee observed), over ``window`` s (default: the filter
      length + 0.5 s) either side of the steepest-rise estimate; profile over t_s.
      Because model and data pass through the same filter, the estimate is not
      shifted by the filter, whatever its phase.
    * ``"steepest"``: the steepest rise of the filtered rate before it first reaches
      30 % of its maximum (plus half the filter length), sub-sample refined. Unbiased
      for a step in the rate under a zero-phase filter, but shifted by the slope of
      the rate after the step (about 2 samples at 8 rpm, 1.5 Hz).
    * ``"lee2008"``: Lee (2008) Appendix II, the last sample with rate <= 0 before the
      peak rate (early by up to half the filter's impulse response).
    """
    from scipy.optimize import minimize_scalar

    check_choice("method", method, ONSET_METHODS)
    t = check_finite("time", time).ravel()
    m = check_finite("mass", mass).ravel()
    if t.size != m.size or t.size < 5:
        raise ValueError("time and mass must have the same length (>= 5)")
    dt = float(t[1] - t[0])
    fs = 1.0 / dt
    mf = lowpass(m, fs, cutoff, numtaps, phase=phase)
    r = mass_rate(mf, fs)
    rmax = float(r.max())
    if rmax <= 0:
        raise ValueError("the mass never increases: no unloading in this record")
    if method == "lee2008":
        ipk = int(np.argmax(r))
        nonpos = np.flatnonzero(r[: ipk + 1] <= 0.0)
        return float(t[nonpos[-1]] if nonpos.size else t[0])
    half = (int(numtaps) - 1) // 2
    if method == "hinge" and (phase == "causal" or cutoff > LEE_CUTOFF_CODE):
        # the starting value from the zero-phase rate at no more than Lee's 1.5 Hz: at a higher cutoff the noise's
        # steepest rises outgrow the start's (at 10 Hz a start of -0.11 s, before the record, for 2.0 s; found by
        # fuzzing); the hinge fit itself uses the given filter
        r = mass_rate(lowpass(m, fs, min(cutoff, LEE_CUTOFF_CODE), numtaps, phase="zero"), fs)
    elif phase == "causal":
        r = np.concatenate([r[half:], np.full(half, r[-1])])  # search on the delay-free axis
    i30 = int(np.argmax(r >= 0.3 * float(r.max())))      # of the rate the start is sought on
    stop = min(r.size - 1, i30 + half)
    d = np.gradient(r, t)
    i = int(np.argmax(d[: stop + 1]))
    ts = float(t[i])
    if 0 < i < r.size - 1:
        y0, y1, y2 = d[i - 1], d[i], d[i + 1]
        den = y0 - 2.0 * y1 + y2
        off = 0.5 * (y0 - y2) / den if den < 0 else 0.0
        ts = float(t[i] + np.clip(off, -0.5, 0.5) * dt)
    if method == "steepest":
        return ts
    w = float(window) if window is not None else half * dt + 0.5
    # work on a segment: the window plus a margin longer than the filter's reach
    margin = (3 if phase == "filtfilt" else 2) * int(numtaps) * dt
    centre = ts + (half * dt if phase == "causal" else 0.0)  # the causal response lags by the group delay
    seg = (t >= centre - w - margin) & (t <= centre + w + margin)
    ts_seg, y_seg = t[seg], mf[seg]
    sel = (ts_seg >= centre - w) & (ts_seg <= centre + w)
    if sel.sum() < 8:
        return ts

    def sse(tc):
        tau = np.maximum(ts_seg - tc, 0.0)
        B = np.vstack([np.ones_like(tau), tau, tau**2, tau**3])
        Bf = lowpass(B, fs, cutoff, numtaps, phase=phase)[:, sel].T
        coef, *_ = np.linalg.lstsq(Bf, y_seg[sel], rcond=None)
        res = y_seg[sel] - Bf @ coef
        return float(res @ res)

    span = max(0.25, 0.25 * w)
    grid = ts + np.linspace(-span, span, 21)
    vals = [sse(g) for g in grid]
    k = int(np.argmin(vals))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    res = minimize_scalar(sse, bounds=(lo, hi), method="bounded", options={"xatol": 1e-4 * dt})
    return float(min(max(res.x, t[0]), t[-1]))      # a start inside the record


# ---------------------------------------------------------------------------- geometric model
def rig_drum(flight: str = "alternative", *, flat_radius: float = _FLAT_RADIUS) -> FlightedDrum:
    """A [`FlightedDrum`][rotarydryer.lab.flight_rig.FlightedDrum] representing one of Lee's rig flights (Lee (2008) Table 5.1).

    The "drum radius" is the radius of curvature of the flight back (Full Scale
    2.5 m, Half Scale 1.25 m); the flat-backed Alternative flight ("No Curve") uses
    ``flat_radius`` (default 50 m; the held area at root angles >= 90 deg changes by
    < 0.2 % between 25 m and 50 m). Two flights 180 deg apart: the rig has a single
    flight, and with this spacing the neighbour never touches the held solids once
    the surface meets the back (Lee's phases III and IV, the only ones in his rig code).
    ``"lee_code"`` is the Appendix II Matlab default (R 2.5 m, s1 0.1 m, s2 0.11 m,
    alpha2 120 deg).
    """
    check_choice("flight", flight, RIG_FLIGHTS)
    e = RIG_FLIGHTS[flight]
    radius = e["curvature"] if e["curvature"] is not None else float(check_positive("flat_radius", flat_radius, "m"))
    return FlightedDrum(radius, 2, TwoSectionFlight(e["s1"], e["s2"], e["alpha1"], e["alpha2"]))


def _check_model_args(drum, rpm, bulk_density, length):
    if not isinstance(drum, FlightedDrum):
        raise ValueError(f"drum must be a FlightedDrum, got {type(drum).__name__}")
    return (float(check_positive("rpm", rpm, "rpm")), check_positive("bulk_density", bulk_density, "kg/m^3"),
            float(check_positive("length", length, "m")))


class _Kinematics(NamedTuple):
    """Checked model inputs and the flight's root angle, broadcast against the repose angle."""

    time: np.ndarray  # s
    start_time: float  # s
    psi0: float  # root angle at the start of unloading, deg
    psi: np.ndarray  # root angle psi(t), deg, broadcast with phi
    phi: np.ndarray  # repose angle, deg, broadcast with psi
    psi5: np.ndarray  # root angle at which the flight is empty, deg
    rpm: float
    rho: np.ndarray  # bulk density, kg/m^3
    length: float  # m


def _kinematics(time, drum, repose_angle, rpm, start_angle, bulk_density, length, start_time) -> _Kinematics:
    """Validate the model inputs and turn the flight: ``psi(t) = start_angle + 6 rpm max(t - start_time, 0)``."""
    rpm, rho, L = _check_model_args(drum, rpm, bulk_density, length)
    t = check_finite("time", time)
    psi0 = float(check_finite("start_angle", start_angle))
    t0 = float(check_finite("start_time", start_time))
    phi = check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg")
    psi = psi0 + 6.0 * rpm * np.maximum(t - t0, 0.0)
    psi_b, phi_b = np.broadcast_arrays(psi, phi)
    psi5 = np.asarray(drum.transition_angles(phi_b).psi5)
    return _Kinematics(t, t0, psi0, psi_b, phi_b, psi5, rpm, rho, L)


def accumulated_mass(time, drum: FlightedDrum, repose_angle, *, rpm: float, start_angle: float,
                     bulk_density, length: float = 1.0, start_time: float = 0.0, mass_offset: float = 0.0,
                     initial_holdup: Optional[float] = None) -> np.ndarray:
    """Geometric-model accumulated discharged mass on the tray, kg.

    ``m(t) = m_off + rho_b L [H0 - min(H0, H(psi(t), phi))]`` with
    ``psi(t) = start_angle + 6 rpm (t - start_time)`` (deg) after ``start_time`` (s),
    ``H`` the held area (m^2, Lee (2008) Eq. 4.14-4.17) and ``H0`` the initial holdup:
    ``H(start_angle, phi)`` by default (Lee (2008) Appendix II), or ``initial_holdup``
    (m^2 per m) for a measured fill. Broadcasts ``time`` (s) against ``repose_angle``
    (deg) and ``bulk_density`` (kg/m^3).
    """
    k = _kinematics(time, drum, repose_angle, rpm, start_angle, bulk_density, length, start_time)
    moff = float(check_finite("mass_offset", mass_offset))
    # no wrap-around: once past psi5 the flight stays empty (single unloading)
    h = np.where(k.psi >= k.psi5, 0.0, drum.holdup_area(np.minimum(k.psi, k.psi5), k.phi))
    if initial_holdup is None:
        h0 = drum.holdup_area(np.full_like(k.psi, k.psi0), k.phi)
    else:
        h0 = float(check_range("initial_holdup", initial_holdup, 0.0, math.inf, low_inclusive=True, unit="m^2"))
    return moff + k.rho * k.length * (h0 - np.minimum(h0, h))


def model_discharge_rate(time, drum: FlightedDrum, repose_angle, *, rpm: float, start_angle: float,
                         bulk_density, length: float = 1.0, start_time: float = 0.0,
                         initial_holdup: Optional[float] = None) -> np.ndarray:
    """Geometric-model discharge rate, kg/s: ``rho_b L omega |dH/dpsi|`` while unloading
    (Lee (2008) l.4789), zero before ``start_time`` and after the flight is empty."""
    k = _kinematics(time, drum, repose_angle, rpm, start_angle, bulk_density, length, start_time)
    rate = drum.discharge_rate(np.minimum(k.psi, k.psi5), k.phi, k.rpm)
    active = (np.broadcast_to(k.time, k.psi.shape) > k.start_time) & (k.psi < k.psi5)
    if initial_holdup is not None:
        active &= drum.holdup_area(np.minimum(k.psi, k.psi5), k.phi) < initial_holdup
    return np.where(active, k.rho * k.length * rate, 0.0)


def synthetic_run(drum: FlightedDrum, repose_angle: float, *, rpm: float, start_angle: float,
                  bulk_density: float, length: float = 1.0, sample_rate: float = LEE_SAMPLE_RATE,
                  start_time: float = 2.0, tail: float = 2.0, mass_offset: float = 30.0,
                  noise_sd: float = 0.05, noise_correlation: float = 0.0,
                  vibration_amplitude: float = 0.0, vibration_frequency: float = 8.0,
                  seed=None) -> RigRun:
    """A synthetic rig record from the geometric model plus load-cell noise.

    Samples at ``sample_rate`` (Hz) from 0 to ``start_time`` + the unloading time +
    ``tail`` (s). Noise: Gaussian, standard deviation ``noise_sd`` (kg), AR(1) with
    lag-1 correlation ``noise_correlation`` in [0, 1), plus an optional sinusoidal
    vibration (``vibration_amplitude`` kg at ``vibration_frequency`` Hz, random phase;
    Lee attributes his noise to motor vibration, section 5.2.2). ``mass_offset`` (kg)
    stands for the preload (Lee used about 30 kg, l.5898). Seeded by ``seed``.
    """
    rpm_ = float(check_positive("rpm", rpm, "rpm"))
    fs = float(check_positive("sample_rate", sample_rate, "Hz"))
    sd = float(check_range("noise_sd", noise_sd, 0.0, math.inf, low_inclusive=True, unit="kg"))
    rho_ar = float(check_range("noise_correlation", noise_correlation, 0.0, 1.0, low_inclusive=True))
    amp = float(check_range("vibration_amplitude", vibration_amplitude, 0.0, math.inf, low_inclusive=True, unit="kg"))
    fv = float(check_positive("vibration_frequency", vibration_frequency, "Hz"))
    t0 = float(check_range("start_time", start_time, 0.0, math.inf, low_inclusive=True, unit="s"))
    tail = float(check_range("tail", tail, 0.0, math.inf, low_inclusive=True, unit="s"))
    phi = float(check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg"))
    psi5 = float(drum.transition_angles(phi).psi5)
    if psi5 <= start_angle:
        raise ValueError(
            f"start_angle = {_fmt(start_angle)} deg is past the end of unloading ({psi5:.1f} deg at "
            f"repose_angle {phi:g} deg): nothing to unload"
        )
    duration = t0 + (psi5 - start_angle) / (6.0 * rpm_) + tail
    n = int(math.floor(duration * fs)) + 1
    t = np.arange(n) / fs
    m = accumulated_mass(t, drum, phi, rpm=rpm_, start_angle=start_angle, bulk_density=bulk_density,
                         length=length, start_time=t0, mass_offset=mass_offset)
    rng = np.random.default_rng(seed)
    e = rng.standard_normal(n)
    if rho_ar > 0:
        from scipy.signal import lfilter

        e = lfilter([math.sqrt(1.0 - rho_ar**2)], [1.0, -rho_ar], e)
        e[0] = rng.standard_normal()  # stationary start
    noise = sd * e
    if amp > 0:
        noise += amp * np.sin(2 * math.pi * fv * t + rng.uniform(0, 2 * math.pi))
    return RigRun(t, m + noise, source="synthetic")


# ---------------------------------------------------------------------------- fitting
@dataclass(frozen=True)
class RigFit:
    """Least-squares fit of the geometric unloading model to one rig run.

    ``params``/``stderr``/``ci`` are keyed by parameter name: ``repose_angle`` (deg),
    ``mass_offset`` (kg), and optionally ``start_time`` (s), ``bulk_density`` (kg/m^3).
    ``ci`` holds (low, high) at ``confidence``. ``residual_sd`` in kg, ``ar1`` the
    lag-1 residual autocorrelation, ``inflation`` the variance factor applied.
    """

    params: dict
    stderr: dict
    ci: dict
    covariance: np.ndarray
    names: tuple
    residual_sd: float
    ar1: float
    inflation: float
    confidence: float
    n: int
    success: bool
    model: dict = field(repr=False, default_factory=dict)

    @property
    def repose_angle(self) -> float:
        """Fitted dynamic angle of repose, deg."""
        return self.params["repose_angle"]

    @property
    def repose_angle_ci(self) -> tuple:
        """Confidence interval of the repose angle, deg."""
        return self.ci["repose_angle"]


def _holdup_and_slope(drum, psi, phi):
    psi5 = float(drum.transition_angles(phi).psi5)
    p = np.minimum(psi, psi5)
    h = np.where(psi >= psi5, 0.0, drum.holdup_area(p, phi))
    s = np.where(psi >= psi5, 0.0, drum.holdup_slope(p, phi))
    return h, s


def fit_repose_angle(run: RigRun, drum: FlightedDrum, *, rpm: float, start_angle: float, bulk_density: float,
                     length: float = 1.0, fit_start_time: bool = True, fit_bulk_density: bool = False,
                     initial_holdup: Optional[float] = None, start_time: Optional[float] = None,
                     repose_guess: Optional[float] = None, confidence: float = 0.95, ci_method: str = "ar1",
                     signal: str = "raw", cutoff: float = LEE_CUTOFF_CODE) -> RigFit:
    """Fit the dynamic angle of repose (deg) to a rig run by least squares, with a confidence interval.

    Model: [`accumulated_mass`][rotarydryer.lab.flight_rig.accumulated_mass]. Free parameters: ``repose_angle`` and
    ``mass_offset`` always; ``start_time`` if ``fit_start_time`` (otherwise
    ``start_time`` must be given, s); ``bulk_density`` if ``fit_bulk_density``
    (``bulk_density`` is then the starting value). ``start_angle`` (deg) is the flight
    root angle at the start of unloading (Lee (2008) measured it from the images).

    Uncertainty: Gauss-Newton covariance ``s^2 (J^T J)^-1`` with the analytic Jacobian
    (``dH/dphi = -dH/dpsi``, see the module notes), times the AR(1) inflation factor
    ``(1 + r)/(1 - r)`` for ``ci_method="ar1"`` (r = lag-1 residual autocorrelation,
    clipped at 0); Student-t intervals with n - p degrees of freedom.
    ``signal="filtered"`` fits the zero-phase filtered mass instead of the raw one
    (intervals then rely on the AR(1) correction and are approximate).
    """
    from scipy.optimize import brentq, least_squares

    if not isinstance(run, RigRun):
        raise ValueError(f"run must be a RigRun, got {type(run).__name__}")
    rpm_, rho0, L = _check_model_args(drum, rpm, bulk_density, length)
    rho0 = float(rho0)
    conf = float(check_range("confidence", confidence, 0.0, 1.0))
    check_choice("ci_method", ci_method, ("ar1", "ols"))
    check_choice("signal", signal, ("raw", "filtered"))
    psi0 = float(check_finite("start_angle", start_angle))
    psi5_max = float(drum.transition_angles(89.5).psi5)
    if psi0 >= psi5_max:
        raise ValueError(
            f"start_angle = {_fmt(psi0)} deg is past the end of unloading of this flight ({psi5_max:.1f} deg even "
            "at a repose angle of 89.5 deg): the flight holds no solids there"
        )
    if initial_holdup is not None and fit_start_time:
        raise ValueError(
            "fit_start_time=True with a given initial_holdup: the start time and the repose angle are "
            "not separately identifiable (the held area depends on psi - phi only); give start_time "
            "(s) and set fit_start_time=False, or drop initial_holdup"
        )
    if not fit_start_time and start_time is None:
        raise ValueError("start_time (s) is required when fit_start_time=False")
    t = run.time
    fs = run.sample_rate
    y_raw = run.mass
    y = y_raw if signal == "raw" else lowpass(y_raw, fs, cutoff)
    omega = 6.0 * rpm_  # deg/s

    # ---- starting values
    t0_guess = (float(start_time) if start_time is not None
                else detect_unloading_start(t, y_raw, method="steepest", cutoff=cutoff))
    pre = t < t0_guess
    moff_guess = float(np.median(y_raw[pre])) if pre.sum() >= 3 else float(y_raw[0])
    post = y_raw[-max(5, t.size // 20):]
    dm = float(np.median(post)) - moff_guess
    if repose_guess is None:
        # total discharged mass identifies phi: rho L H(psi0, phi) = dm
        def g(phi):
            return rho0 * L * float(drum.holdup_area(psi0, phi)) - dm

        lo, hi = 1.0, 89.0
        grid = np.linspace(lo, hi, 89)
        vals = np.array([g(p) for p in grid])
        k = np.flatnonzero(np.sign(vals[:-1]) != np.sign(vals[1:]))
        if initial_holdup is None and k.size:
            repose_guess = brentq(g, grid[k[0]], grid[k[0] + 1])
        else:
            repose_guess = 40.0
    names = ["repose_angle", "mass_offset"]
    x0 = [float(repose_guess), moff_guess]
    lb, ub = [RIG_REPOSE_BOUNDS[0], -np.inf], [RIG_REPOSE_BOUNDS[1], np.inf]
    if fit_start_time:
        names.append("start_time")
        x0.append(t0_guess)
        lb.append(float(t[0]) - 10.0)
        ub.append(float(t[-1]))
    if fit_bulk_density:
        names.append("bulk_density")
        x0.append(rho0)
        lb.append(1e-3 * rho0)
        ub.append(1e3 * rho0)
    idx = {n: i for i, n in enumerate(names)}

    def unpack(p):
        phi = p[0]
        moff = p[1]
        t0 = p[idx["start_time"]] if fit_start_time else float(start_time)
        rho = p[idx["bulk_density"]] if fit_bulk_density else rho0
        return phi, moff, t0, rho

    def parts(p):
        phi, moff, t0, rho = unpack(p)
        tau = np.maximum(t - t0, 0.0)
        psi = psi0 + omega * tau
        h, s = _holdup_and_slope(drum, psi, phi)
        if initial_holdup is None:
            h0, s0 = _holdup_and_slope(drum, np.array([psi0]), phi)
            h0, s0 = float(h0[0]), float(s0[0])
            drop = h0 - h
            ds_phi = -s0 + s  # d(h0 - h)/dphi with dH/dphi = -dH/dpsi
            ds_t0 = np.where(t > t0, omega * s, 0.0)
        else:
            h0 = float(initial_holdup)
            below = h < h0
            drop = np.where(below, h0 - h, 0.0)
            ds_phi = np.where(below, s, 0.0)
            ds_t0 = np.where(below & (t > t0), omega * s, 0.0)
        return phi, moff, t0, rho, drop, ds_phi, ds_t0

    def resid(p):
        phi, moff, t0, rho, drop, _, _ = parts(p)
        return moff + rho * L * drop - y

    def jac(p):
        phi, moff, t0, rho, drop, ds_phi, ds_t0 = parts(p)
        J = np.empty((t.size, len(names)))
        J[:, 0] = rho * L * ds_phi
        J[:, 1] = 1.0
        if fit_start_time:
            J[:, idx["start_time"]] = rho * L * ds_t0
        if fit_bulk_density:
            J[:, idx["bulk_density"]] = L * drop
        return J

    scale = [1.0, max(1.0, abs(dm)), 1.0, rho0][: len(names)]
    if fit_bulk_density and not fit_start_time:
        scale = [1.0, max(1.0, abs(dm)), rho0]
    x0 = np.clip(x0, np.array(lb) + 1e-9, np.array(ub) - 1e-9)
    sol = least_squares(resid, x0, jac=jac, bounds=(lb, ub), x_scale=scale, method="trf")
    r = sol.fun
    n, p = t.size, len(names)
    rc = r - r.mean()
    ar1 = float((rc[1:] @ rc[:-1]) / (rc @ rc)) if rc @ rc > 0 else 0.0
    infl = 1.0
    if ci_method == "ar1":
        r1 = min(max(ar1, 0.0), 0.99)
        infl = (1.0 + r1) / (1.0 - r1)
    # s^2 (J^T J)^-1 x AR(1) inflation; the pseudo-inverse only for an exactly singular J^T J
    unc = linearised_uncertainty(jac(sol.x), r, max(n - p, 1), estimates=sol.x, confidence=conf,
                                 variance_inflation=infl, inverse="inv", singular_rtol=1e-10)
    cov, se, s2 = unc.covariance, unc.std_errors, unc.residual_variance
    if unc.singular:
        # a pseudo-inverse would report a standard error of 0 for what the data cannot determine
        combo = " + ".join(f"{c:.2g} {names[i]}" for i, c in enumerate(unc.null_direction) if abs(c) > 1e-3)
        warnings.warn(f"the rig signal does not determine the fitted parameters separately (direction {combo}); "
                      "their standard errors and intervals are set to inf", RuntimeWarning, stacklevel=2)
        se = np.full_like(se, np.inf)
        unc = replace(unc, std_errors=se, ci_low=np.full_like(se, -np.inf), ci_high=np.full_like(se, np.inf))
    params = {k: float(sol.x[i]) for k, i in idx.items()}
    if not fit_start_time:
        params["start_time"] = float(start_time)
    if not fit_bulk_density:
        params["bulk_density"] = rho0
    stderr = {k: float(se[i]) for k, i in idx.items()}
    ci = {k: (float(unc.ci_low[i]), float(unc.ci_high[i])) for k, i in idx.items()}
    model = {"time": t, "mass": resid(sol.x) + y, "data": y}
    _warn_poor_fit(sol.x[0], (lb[0], ub[0]), r, y, ci["repose_angle"])
    return RigFit(params=params, stderr=stderr, ci=ci, covariance=cov, names=tuple(names),
                  residual_sd=math.sqrt(s2), ar1=ar1, inflation=infl, confidence=conf, n=n,
                  success=bool(sol.success), model=model)


#: a rig fit explaining less than this share of the record's variance is reported as not describing it
RIG_MIN_R2 = 0.9
#: the search range of a rig fit's repose angle, deg
RIG_REPOSE_BOUNDS = (0.5, 89.5)


def _warn_poor_fit(phi, bounds, residuals, data, phi_ci) -> None:
    """Warn (``RuntimeWarning``) when the fitted unloading model does not describe the record: the repose
    angle at a bound of its search, its interval reaching outside (0, 90) deg, or the model explaining less
    than `RIG_MIN_R2` of the mass signal's variance. Such a fit is not a measurement of the repose angle
    (found by fuzzing: 0.5 deg, interval -24.9 to 25.9 deg, residual SD 38.5 kg, printed as results)."""
    sst = float(np.sum((data - data.mean()) ** 2))
    r2 = 1.0 - float(residuals @ residuals) / sst if sst > 0 else 0.0
    why = []
    if min(phi - bounds[0], bounds[1] - phi) < 1e-3:
        why.append(f"the repose angle ends at the bound of its search ({phi:.3g} deg)")
    if not (phi_ci[0] > 0.0 and phi_ci[1] < 90.0):
        why.append(f"its {phi_ci[0]:.3g} to {phi_ci[1]:.3g} deg interval leaves (0, 90) deg")
    if r2 < RIG_MIN_R2:
        why.append(f"the model explains {max(r2, 0.0):.0%} of the mass signal's variance")
    if why:
        warnings.warn("the unloading model does not describe this record, so the fit is not a measurement of the "
                      f"repose angle: {'; '.join(why)}; check --start-angle, --flight, --rpm and the record's "
                      "columns (time, load cells in kg)", RuntimeWarning, stacklevel=3)


# ---------------------------------------------------------------------------- band and analysis
@dataclass(frozen=True)
class ReposeBand:
    """Model band over repose angles ``phi +/- k SD`` (Lee (2008) section 5.4.3).

    ``mass_*`` accumulated mass (kg) and ``rate_*`` discharge rate (kg/s) at the mean
    angle and the pointwise lower/upper envelope over the band, on ``time`` (s).
    """

    time: np.ndarray
    mass_mean: np.ndarray
    mass_low: np.ndarray
    mass_high: np.ndarray
    rate_mean: np.ndarray
    rate_low: np.ndarray
    rate_high: np.ndarray
    repose_low: float
    repose_high: float


def repose_band(time, drum: FlightedDrum, repose_angle: float, repose_sd: float, *, rpm: float,
                start_angle: float, bulk_density: float, length: float = 1.0, start_time: float = 0.0,
                mass_offset: float = 0.0, k: float = 2.0, n_angles: int = 21) -> ReposeBand:
    """The geometric model at ``repose_angle`` (deg) and its band over ``repose_angle +/- k*repose_sd``.

    Lee (2008) ran his model at the mean angle and at mean +/- 2 SD ("95 %", Appendix
    II). The model is not monotone in the angle at every instant, so the band here is
    the pointwise envelope over ``n_angles`` angles spanning the interval (it contains
    Lee's two curves). ``k = 2`` by default; Table 5.5 gives the SDs.
    """
    phi = float(check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg"))
    sd = float(check_range("repose_sd", repose_sd, 0.0, 90.0, low_inclusive=True, unit="deg"))
    kk = float(check_range("k", k, 0.0, math.inf, low_inclusive=True))
    if isinstance(n_angles, bool) or int(n_angles) != n_angles or n_angles < 2:
        raise ValueError(f"n_angles = {n_angles!r} must be an integer >= 2")
    lo, hi = max(phi - kk * sd, 0.01), min(phi + kk * sd, 89.99)
    t = check_finite("time", time).ravel()
    angles = np.linspace(lo, hi, int(n_angles))[:, None]
    kw = dict(rpm=rpm, start_angle=start_angle, bulk_density=bulk_density, length=length, start_time=start_time)
    M = accumulated_mass(t[None, :], drum, angles, mass_offset=mass_offset, **kw)
    Rt = model_discharge_rate(t[None, :], drum, angles, **kw)
    m0 = accumulated_mass(t, drum, phi, mass_offset=mass_offset, **kw)
    r0 = model_discharge_rate(t, drum, phi, **kw)
    return ReposeBand(t, m0, np.minimum(M.min(0), m0), np.maximum(M.max(0), m0), r0,
                      np.minimum(Rt.min(0), r0), np.maximum(Rt.max(0), r0), lo, hi)


def fraction_inside(values, low, high) -> float:
    """Fraction of samples with ``low <= values <= high`` (Lee's inside-the-band criterion)."""
    v, lo, hi = np.broadcast_arrays(check_finite("values", values), check_finite("low", low),
                                    check_finite("high", high))
    if v.size == 0:
        raise ValueError("values is empty")
    return float(np.mean((v >= lo) & (v <= hi)))


@dataclass(frozen=True)
class RigAnalysis:
    """Result of [`analyse_run`][rotarydryer.lab.flight_rig.analyse_run]: filtered signals, alignment and the band comparison."""

    time: np.ndarray  # s, aligned: 0 at the detected start of unloading
    mass: np.ndarray  # kg, filtered, offset removed
    rate: np.ndarray  # kg/s, from the filtered mass
    start_time: float  # s, detected start of unloading in the record's time base
    band: ReposeBand
    inside_mass: float
    inside_rate: float
    cutoff: float
    phase: str
    fit: Optional[RigFit] = None


def analyse_run(run: RigRun, drum: FlightedDrum, *, rpm: float, start_angle: float, bulk_density: float,
                repose_angle: Optional[float] = None, repose_sd: float = 0.0, length: float = 1.0,
                cutoff: float = LEE_CUTOFF_CODE, phase: str = "zero", onset: str = "hinge",
                fit: bool = True, k: float = 2.0) -> RigAnalysis:
    """Lee's analysis of one run (Lee (2008) section 5.4), optionally with a repose-angle fit.

    Filters ([`lowpass`][rotarydryer.lab.flight_rig.lowpass]), differentiates ([`mass_rate`][rotarydryer.lab.flight_rig.mass_rate]), detects the start
    of unloading ([`detect_unloading_start`][rotarydryer.lab.flight_rig.detect_unloading_start]) and removes the pre-start offset;
    fits the repose angle if ``fit`` (used for the band when ``repose_angle`` is None);
    and reports the fraction of the filtered mass and rate samples (from the start of
    unloading on) inside the model band at ``repose_angle +/- k repose_sd``.
    """
    check_choice("phase", phase, FILTER_PHASES)
    fs = run.sample_rate
    mf = lowpass(run.mass, fs, cutoff, phase=phase)
    rf = mass_rate(mf, fs)
    ts = detect_unloading_start(run.time, run.mass, method=onset, cutoff=cutoff, phase=phase)
    pre = run.time < ts
    off = float(np.mean(mf[pre])) if pre.sum() >= 3 else float(mf[0])
    f = None
    if fit:
        f = fit_repose_angle(run, drum, rpm=rpm, start_angle=start_angle, bulk_density=bulk_density,
                             length=length, cutoff=cutoff)
    if repose_angle is None:
        if f is None:
            raise ValueError("repose_angle is required when fit=False")
        repose_angle = f.repose_angle
        if repose_sd == 0.0:
            repose_sd = f.stderr["repose_angle"]
            if not repose_sd < 90.0:    # was "repose_sd = 925 deg is outside the allowed range", an option not given
                raise ValueError(f"the repose-angle fit leaves the angle unconstrained (standard error {repose_sd:.3g} "
                                 "deg): the unloading model does not describe this record, so there is no model band "
                                 "to compare it with; check --start-angle, --flight, --rpm and the record's columns "
                                 "(time, load cells in kg), or give --repose-angle and --repose-sd")
    ta = run.time - ts
    band = repose_band(ta, drum, repose_angle, repose_sd, rpm=rpm, start_angle=start_angle,
                       bulk_density=bulk_density, length=length, start_time=0.0, k=k)
    after = ta >= 0
    m = mf - off
    tol_m = 1e-9
    inside_m = fraction_inside(m[after], band.mass_low[after] - tol_m, band.mass_high[after] + tol_m)
    inside_r = fraction_inside(rf[after], band.rate_low[after] - tol_m, band.rate_high[after] + tol_m)
    return RigAnalysis(ta, m, rf, ts, band, inside_m, inside_r, float(cutoff), phase, f)


def plot_analysis(analysis: RigAnalysis, title: str = ""):
    """Figure: filtered accumulated mass and discharge rate against aligned time with the
    model band (Lee (2008) Figs 5.20-5.21 style). Returns the Matplotlib figure."""
    from .._plotting import pyplot

    plt = pyplot()

    a, b = analysis, analysis.band
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    lab_band = f"model, repose {b.repose_low:.1f}-{b.repose_high:.1f} deg"
    ax1.fill_between(b.time, b.mass_low, b.mass_high, color="C1", alpha=0.3, label=lab_band)
    ax1.plot(b.time, b.mass_mean, "C1-", lw=1.2, label="model, mean angle")
    ax1.plot(a.time, a.mass, "k-", lw=0.8, label=f"data, FIR {a.cutoff:g} Hz ({a.phase} phase)")
    ax1.set_ylabel("accumulated mass, kg")
    ax1.legend(fontsize=8, loc="lower right")
    ax2.fill_between(b.time, b.rate_low, b.rate_high, color="C1", alpha=0.3)
    ax2.plot(b.time, b.rate_mean, "C1-", lw=1.2)
    ax2.plot(a.time, a.rate, "k-", lw=0.8)
    ax2.set_ylabel("discharge rate, kg/s")
    ax2.set_xlabel("time from start of unloading, s")
    fit = f", fitted repose {a.fit.repose_angle:.2f} deg" if a.fit is not None else ""
    ax1.set_title(title or f"inside band: mass {100 * a.inside_mass:.0f} %, rate {100 * a.inside_rate:.0f} %{fit}",
                  fontsize=9)
    fig.tight_layout()
    return fig
