"""Measured tracer-curve file format and loader.

Format (CSV, UTF-8):

    # source: Lee (2008) PhD thesis, Appendix I ...   <- optional metadata lines
    # signal_unit: 1/h                                 <- "# key: value"
    # tracer_mass_kg: 0.397
    # feed_rate_kg_s: 27.22
    time_min,signal,source_line                        <- header
    5.3333,0.378,12547
    ...

* Lines starting with ``#`` before the header are metadata. ``# key: value``
  (key = letters, digits, ``_``, ``-`` or ``.``) is stored as
  ``metadata[key] = value`` (string; numbers are converted to float when the
  whole value parses). Other ``#`` lines are kept in ``metadata["comment"]``.
* Exactly one time column named with its unit: ``time_s``, ``time_min`` or
  ``time_h``; it is converted to seconds.
* A ``signal`` column (any unit; say which in ``# signal_unit:``), or ``E_per_s`` (E(t) in 1/s, the column of
  ``rotarydryer rtd --out``'s ``rtd.csv``, which reads back as it was written).
* Further columns are kept as strings in ``TracerData.extra_columns``.

Recognised metadata keys (all optional): ``source``, ``signal_unit``
(``kg/kg``, ``ppm``, ``mg/kg``, ``1/s``, ``1/min``, ``1/h``),
``tracer_mass_kg``, ``feed_rate_kg_s``, ``time_origin_s`` (injection start on
the file's clock, in s), ``pulse_kind`` and ``pulse_duration_s`` (the tracer
input, see [`rotarydryer.rtd.pulse_input`][rotarydryer.rtd.pulse_input]).

Validation (``ValueError`` naming the file, the line and the problem): missing
or unknown time column, missing signal column, non-numeric or NaN values,
negative time or signal, unsorted or duplicate times, fewer than 5 points, a
signal that is 0 everywhere, non-numeric or out-of-range numeric metadata, an
unknown ``pulse_kind``, a ``time_origin_s`` at or after the last sample (or after
all the non-zero signal). Limits: a file is read line by line, must be UTF-8
text, at most 64 MB and [`MAX_TRACER_ROWS`][rotarydryer.rtd.tracer_data.MAX_TRACER_ROWS] (200 000) data rows.
"""

from __future__ import annotations

import csv
import io
import math
import re
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from .._io import write_text_atomic
from .._validation import check_finite
from ..data import TRACER_PREFIX, tracer_dataset_names
from ._datafile import MAX_DATA_ROWS, csv_rows, data_lines, fmt, parse_number, text_lines, too_many_rows
from .analysis import MAX_RECORD_TIME_S, MAX_SIGNAL, MIN_RECORD_SPAN_S, MIN_SIGNAL_PEAK, rtd_moments
from .pulses import PULSE_KINDS, pulse_input

__all__ = [
    "TracerData",
    "load_tracer_csv",
    "write_tracer_csv",
    "tracer_datasets",
    "load_tracer_dataset",
    "TIME_COLUMNS",
    "MIN_POINTS",
    "MAX_TRACER_ROWS",
]

TIME_COLUMNS = {"time_s": 1.0, "time_min": 60.0, "time_h": 3600.0}
MIN_POINTS = 5
MAX_TRACER_ROWS = MAX_DATA_ROWS
"""Most data rows in one tracer file (200 000; read line by line, the file is refused beyond)."""
_MASS_FRACTION_UNITS = {"kg/kg": 1.0, "ppm": 1e-6, "mg/kg": 1e-6, "ppb": 1e-9}
_RATE_UNITS = {"1/s": 1.0, "1/min": 1 / 60.0, "1/h": 1 / 3600.0}
_KEY = re.compile(r"^\s*#\s*([A-Za-z][A-Za-z0-9_.\-]*)\s*:\s*(.*?)\s*$")


@dataclass(frozen=True, eq=False)
class TracerData:
    """A measured tracer outlet curve.

    Attributes
    ----------
    time_s : sample times (s) on the file's clock.
    signal : outlet signal (unit in ``metadata["signal_unit"]`` if given).
    metadata : dict of ``# key: value`` lines (floats where numeric).
    time_column : name of the time column in the file (records the unit).
    extra_columns : other columns, as lists of strings.
    path : file the data came from (or None).
    """

    time_s: np.ndarray
    signal: np.ndarray
    metadata: dict[str, Any] = field(default_factory=dict)
    time_column: str = "time_s"
    extra_columns: dict[str, list[str]] = field(default_factory=dict, repr=False)
    path: str | None = None

    @property
    def time_origin_s(self) -> float:
        """Injection start (s) on the file's clock (metadata ``time_origin_s``, default 0)."""
        return float(self.metadata.get("time_origin_s", 0.0))

    @property
    def signal_unit(self) -> str | None:
        return self.metadata.get("signal_unit")

    @property
    def rate_factor(self) -> float | None:
        """Factor converting the signal to E(t) in 1/s when ``signal_unit`` is a normalised
        RTD (1/s, 1/min, 1/h); None for any other unit (a raw concentration)."""
        return _RATE_UNITS.get(self.signal_unit or "")

    def pulse(self):
        """The tracer input from metadata (``pulse_kind``, ``pulse_duration_s``); Dirac if absent."""

        kind = str(self.metadata.get("pulse_kind", "dirac"))
        if kind == "dirac" or self.metadata.get("pulse_duration_s") == 0.0:
            return pulse_input("dirac")
        return pulse_input(kind, float(self.metadata["pulse_duration_s"]))

    def expected_area(self) -> float | None:
        """Area ∫signal dt (signal unit × s) that corresponds to 100 % recovery.

        * ``signal_unit`` a normalised RTD (1/s, 1/min, 1/h): 1 / (1 s in that unit),
          e.g. 3600 for 1/h.
        * a mass fraction (kg/kg, ppm, mg/kg): recovered mass = feed_rate_kg_s ×
          factor × ∫signal dt (Ajayi (2011) Eq. 3.7–3.8), so the expected area is
          tracer_mass_kg / (feed_rate_kg_s × factor). Needs both metadata keys.

        Returns None when the metadata do not allow it.
        """
        u = self.signal_unit
        if self.rate_factor is not None:
            return 1.0 / self.rate_factor
        if u in _MASS_FRACTION_UNITS and "tracer_mass_kg" in self.metadata and "feed_rate_kg_s" in self.metadata:
            return float(self.metadata["tracer_mass_kg"]) / (
                float(self.metadata["feed_rate_kg_s"]) * _MASS_FRACTION_UNITS[u]
            )
        return None

    def moments(self, **kwargs):
        """[`rotarydryer.rtd.rtd_moments`][rotarydryer.rtd.rtd_moments] of this curve, with the file's time
        origin and expected area as defaults (override with keyword arguments)."""

        kwargs.setdefault("time_origin_s", self.time_origin_s)
        kwargs.setdefault("expected_area", self.expected_area())
        return rtd_moments(self.time_s, self.signal, **kwargs)


def _convert(value: str):
    try:
        x = float(value)
    except ValueError:
        return value
    return x if math.isfinite(x) else value


# numeric metadata keys: (exclusive lower bound, unit)
#: the signal column of `rotarydryer rtd --out`'s rtd.csv (the model's E(t), 1/s), read in place of ``signal``
MODEL_RTD_COLUMN = "E_per_s"

_NUMERIC_METADATA = {
    "time_origin_s": (-math.inf, "s"),
    "tracer_mass_kg": (0.0, "kg"),
    "feed_rate_kg_s": (0.0, "kg/s"),
    "pulse_duration_s": (0.0, "s"),
}


def _check_metadata(metadata: dict, meta_lines: dict, name: str) -> None:
    """Numeric metadata must be finite numbers in range; ``pulse_kind`` a known kind."""

    for key, (low, unit) in _NUMERIC_METADATA.items():
        if key not in metadata:
            continue
        v = metadata[key]
        where = f"{name} line {meta_lines[key]}"
        if not isinstance(v, float):
            raise ValueError(f"{where}: {key} = {v!r} is not a finite number ({unit})")
        if key == "pulse_duration_s" and v == 0.0:     # a pulse of no duration: a Dirac pulse (as --pulse-s 0)
            if metadata.get("pulse_kind", "dirac") != "dirac":
                raise ValueError(f"{where}: pulse_duration_s = 0 s with pulse_kind = {metadata['pulse_kind']!r}: give "
                                 "the pulse's duration (> 0 s), or 'pulse_kind: dirac' for an instantaneous one")
            continue
        if not v > low:
            raise ValueError(f"{where}: {key} = {fmt(v)} {unit} must be > {fmt(low)} {unit}"
                             + (" (0 s: a Dirac pulse)" if key == "pulse_duration_s" else ""))
    if "pulse_kind" in metadata:
        kind = metadata["pulse_kind"]
        if kind not in PULSE_KINDS:
            raise ValueError(f"{name} line {meta_lines['pulse_kind']}: pulse_kind = {kind!r} is not one of "
                             f"{', '.join(PULSE_KINDS)}")
        if kind != "dirac" and "pulse_duration_s" not in metadata:
            raise ValueError(f"{name} line {meta_lines['pulse_kind']}: pulse_kind = {kind!r} needs a "
                             "'# pulse_duration_s:' line (s)")


def parse_tracer_text(text: str, name: str = "<string>", *, max_rows: int | None = None) -> TracerData:
    """Parse tracer-CSV text (see module docstring); ``name`` is used in errors."""
    return _parse_tracer_lines(text_lines(text), name, max_rows=max_rows)


def _parse_tracer_lines(lines, name: str, *, max_rows: int | None = None) -> TracerData:
    """Parse ``(line number, text)`` pairs (see [`parse_tracer_text`][rotarydryer.rtd.tracer_data.parse_tracer_text]); stops with an error
    after ``max_rows`` (default [`MAX_TRACER_ROWS`][rotarydryer.rtd.tracer_data.MAX_TRACER_ROWS]) data rows."""
    limit = MAX_TRACER_ROWS if max_rows is None else int(max_rows)
    metadata: dict[str, Any] = {}
    meta_lines: dict[str, int] = {}
    comments: list[str] = []
    lines = iter(lines)
    header_line, header_text = None, None
    for k, line in lines:
        if line.lstrip().startswith("#") or not line.strip():
            if line.strip():
                m = _KEY.match(line)
                if m:
                    metadata[m.group(1)] = _convert(m.group(2))
                    meta_lines[m.group(1)] = k
                else:
                    comments.append(line.lstrip()[1:].strip())
            continue
        header_line, header_text = k, line
        break
    if comments:
        metadata["comment"] = "\n".join(comments)
    if header_line is None:
        raise ValueError(f"{name}: no header line found (expected e.g. 'time_s,signal')")
    try:
        header = [h.strip() for h in next(csv.reader([header_text or ""]))]
    except csv.Error as exc:
        raise ValueError(f"{name} line {header_line}: unreadable header ({exc})") from None
    tcols = [h for h in header if h in TIME_COLUMNS]
    if not tcols:
        other = [h for h in header if h.lower().startswith("time")]
        hint = f" (found {other[0]!r}, which is not a known unit)" if other else ""
        raise ValueError(
            f"{name} line {header_line}: missing time column{hint}; expected one of "
            f"{', '.join(TIME_COLUMNS)} in header {', '.join(header)}"
        )
    if len(tcols) > 1:
        raise ValueError(f"{name} line {header_line}: more than one time column ({', '.join(tcols)}); "
                         "keep exactly one")
    signal_col = "signal"
    if "signal" not in header and MODEL_RTD_COLUMN in header:
        # `rotarydryer rtd --out`'s rtd.csv: the model's tracer curve, E(t) in 1/s, read back as it was written
        signal_col = MODEL_RTD_COLUMN
        if metadata.setdefault("signal_unit", "1/s") != "1/s":
            raise ValueError(f"{name} line {meta_lines['signal_unit']}: signal_unit {metadata['signal_unit']!r} for an "
                             f"{MODEL_RTD_COLUMN} column (E(t) in 1/s); leave signal_unit out or give 1/s")
    if signal_col not in header:
        raise ValueError(f"{name} line {header_line}: missing 'signal' column in header {', '.join(header)} (or "
                         f"{MODEL_RTD_COLUMN!r}, E(t) in 1/s, as `rotarydryer rtd --out` writes it)")
    twice = sorted({h for h in header if h and header.count(h) > 1})     # blank names: a spreadsheet's empty columns
    if twice:       # the first of two signal columns was used silently (found by fuzzing)
        raise ValueError(f"{name} line {header_line}: column {twice[0]!r} appears twice in the header; give each "
                         "column once")
    _check_metadata(metadata, meta_lines, name)
    it, isg = header.index(tcols[0]), header.index(signal_col)
    times: list[float] = []
    sig: list[float] = []
    lineno: list[int] = []
    extras: dict[str, list[str]] = {h: [] for k, h in enumerate(header) if k not in (it, isg)}
    for k, row in csv_rows(lines, name):
        if len(times) >= limit:
            raise too_many_rows(name, k, limit)
        # too few cells, or an extra value (dropped silently before; found by fuzzing); a spreadsheet's empty
        # trailing cells are not values
        if len(row) < len(header) or any(c.strip() for c in row[len(header):]):
            raise ValueError(f"{name} line {k}: expected {len(header)} columns ({', '.join(header)}), "
                             f"got {len(row)}")
        t_k = parse_number(row[it], name, k, header[it])
        s_k = parse_number(row[isg], name, k, header[isg])
        if t_k < 0:
            raise ValueError(f"{name} line {k}: {header[it]} = {fmt(t_k)} is negative; times are read on a "
                             "clock that starts at 0 (give the injection time in '# time_origin_s:')")
        if s_k < 0:
            raise ValueError(f"{name} line {k}: negative signal {fmt(s_k)}; signals must be >= 0")
        if times and t_k <= times[-1]:
            what = "duplicate" if t_k == times[-1] else "unsorted"
            raise ValueError(
                f"{name} line {k}: {what} time {fmt(t_k)} after {fmt(times[-1])} (line {lineno[-1]}, "
                f"{tcols[0]}); times must be strictly increasing"
            )
        times.append(t_k)
        sig.append(s_k)
        for col, h in enumerate(header):
            if h in extras:
                extras[h].append(row[col].strip())
        lineno.append(k)
    t = np.asarray(times, dtype=float) * TIME_COLUMNS[tcols[0]]
    c = np.asarray(sig, dtype=float)
    if t.size == 0:
        raise ValueError(f"{name}: no data rows after the header (line {header_line}); "
                         f"a tracer curve needs at least {MIN_POINTS} points")
    if t.size < MIN_POINTS:
        raise ValueError(f"{name}: too few points ({t.size}); a tracer curve needs at least {MIN_POINTS}")
    if not np.any(c > 0):
        raise ValueError(f"{name}: the signal is 0 on every line; there is no tracer curve")
    if np.count_nonzero(c > 0) < 2:     # a fit to it printed an infinite standard error, exit 0 (found by fuzzing)
        raise ValueError(f"{name} line {lineno[int(np.argmax(c > 0))]}: the only non-zero signal; a tracer curve needs "
                         "a peak the samples resolve (two or more non-zero samples)")
    # a record whose moments or model fit overflow or vanish (found by fuzzing: "array must not contain infs or
    # NaNs", "Maximum allowed size exceeded", R^2 nan), refused as `rtd_moments` refuses it, naming the file
    if float(t[-1]) > MAX_RECORD_TIME_S:
        raise ValueError(f"{name} line {lineno[-1]}: {tcols[0]} reaches {fmt(float(t[-1]))} s; a tracer record lies "
                         f"within {MAX_RECORD_TIME_S:g} s (32 years) of its origin: is the time column's unit right?")
    if float(t[-1] - t[0]) < MIN_RECORD_SPAN_S:
        raise ValueError(f"{name}: the record spans {fmt(float(t[-1] - t[0]))} s; a tracer record spans at least "
                         f"{MIN_RECORD_SPAN_S:g} s: is the time column's unit right?")
    peak = float(np.max(c))
    if not MIN_SIGNAL_PEAK <= peak <= MAX_SIGNAL:
        raise ValueError(f"{name}: the signal peaks at {fmt(peak)}; the allowed range of its peak is "
                         f"[{MIN_SIGNAL_PEAK:g}, {MAX_SIGNAL:g}] (an RTD does not depend on the signal's unit: rescale it)")
    if "time_origin_s" in metadata:
        t0 = float(metadata["time_origin_s"])
        where = f"{name} line {meta_lines['time_origin_s']}"
        if t0 >= t[-1]:
            raise ValueError(
                f"{where}: time_origin_s = {fmt(t0)} s is at or after the last sample ({fmt(t[-1])} s, "
                f"line {lineno[-1]}); the tracer injection must start before the data end"
            )
        if not np.any(c[t > t0] > 0):
            raise ValueError(
                f"{where}: time_origin_s = {fmt(t0)} s is after all the tracer signal (last non-zero sample "
                f"at {fmt(t[np.flatnonzero(c > 0)[-1]])} s); the injection must precede the response"
            )
    return TracerData(t, c, metadata, tcols[0], extras, None)


def load_tracer_csv(path, *, max_rows: int | None = None) -> TracerData:
    """Load a tracer curve in the rotarydryer tracer-CSV format (see module docstring).

    Parameters
    ----------
    path : str or Path of the CSV file (UTF-8; at most [`MAX_TRACER_ROWS`][rotarydryer.rtd.tracer_data.MAX_TRACER_ROWS] data rows and
        64 MB, read line by line).

    Returns
    -------
    TracerData (time in s on the file's clock, signal, metadata dict).
    """
    p = Path(path)
    d = _parse_tracer_lines(data_lines(p, "tracer data file"), str(p), max_rows=max_rows)
    return TracerData(d.time_s, d.signal, d.metadata, d.time_column, d.extra_columns, str(p))


def write_tracer_csv(path, time_s, signal, metadata: dict | None = None, time_unit: str = "s") -> None:
    """Write a tracer curve in the tracer-CSV format (atomic: temp file + rename).

    ``time_s`` in s is written in ``time_unit`` (``s``, ``min`` or ``h``).
    """

    col = f"time_{time_unit}"
    if col not in TIME_COLUMNS:
        raise ValueError(f"time_unit = {time_unit!r} is not one of 's', 'min', 'h'")

    t = check_finite("time_s", time_s) / TIME_COLUMNS[col]
    c = check_finite("signal", signal)
    if t.ndim != 1 or t.shape != c.shape:
        raise ValueError(f"time_s and signal must be 1-D of equal length, got shapes {t.shape} and {c.shape}")
    out = io.StringIO()
    for k, v in (metadata or {}).items():
        out.write(f"# {k}: {v}\n")
    out.write(f"{col},signal\n")
    for a, b in zip(t, c, strict=True):
        out.write(f"{float(a)!r},{float(b)!r}\n")
    write_text_atomic(path, out.getvalue())


def tracer_datasets() -> list[str]:
    """Names of the published tracer curves shipped in ``rotarydryer/data``.

    ``lee2008_invicta`` (Lee (2008) App. I Experiment entity = Fig. 7.1) and
    ``ajayi2011_test1`` ... ``ajayi2011_test6`` (Ajayi (2011) Appendix B).
    """
    return tracer_dataset_names()


def load_tracer_dataset(name: str) -> TracerData:
    """Load a shipped tracer curve by name (see [`tracer_datasets`][rotarydryer.rtd.tracer_data.tracer_datasets])."""

    names = tracer_datasets()
    if name not in names:
        raise ValueError(f"tracer dataset {name!r} is not one of {', '.join(map(repr, names))}")
    res = resources.files("rotarydryer.data").joinpath(TRACER_PREFIX + name + ".csv")
    d = parse_tracer_text(res.read_text("utf-8"), name=name)
    return TracerData(d.time_s, d.signal, d.metadata, d.time_column, d.extra_columns, str(res))
