"""Measured tracer-curve file format and loader.

Format (CSV, UTF-8)::

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
* A ``signal`` column (any unit; say which in ``# signal_unit:``).
* Further columns are kept as strings in ``TracerData.extra_columns``.

Recognised metadata keys (all optional): ``source``, ``signal_unit``
(``kg/kg``, ``ppm``, ``mg/kg``, ``1/s``, ``1/min``, ``1/h``),
``tracer_mass_kg``, ``feed_rate_kg_s``, ``time_origin_s`` (injection start on
the file's clock, in s), ``pulse_kind`` and ``pulse_duration_s`` (the tracer
input, see :func:`rotarydryer.rtd.pulse_input`).

Validation (``ValueError`` naming the file, the line and the problem): missing
or unknown time column, missing signal column, non-numeric or NaN values,
negative signal, unsorted or duplicate times, fewer than 5 points.
"""

from __future__ import annotations

import csv
import io
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "TracerData",
    "load_tracer_csv",
    "write_tracer_csv",
    "tracer_datasets",
    "load_tracer_dataset",
    "TIME_COLUMNS",
    "MIN_POINTS",
]

TIME_COLUMNS = {"time_s": 1.0, "time_min": 60.0, "time_h": 3600.0}
MIN_POINTS = 5
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
        return _RATE_UNITS.get(self.signal_unit)

    def pulse(self):
        """The tracer input from metadata (``pulse_kind``, ``pulse_duration_s``); Dirac if absent."""
        from .pulses import pulse_input

        kind = str(self.metadata.get("pulse_kind", "dirac"))
        if kind == "dirac":
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
        """:func:`rotarydryer.rtd.rtd_moments` of this curve, with the file's time
        origin and expected area as defaults (override with keyword arguments)."""
        from .analysis import rtd_moments

        kwargs.setdefault("time_origin_s", self.time_origin_s)
        kwargs.setdefault("expected_area", self.expected_area())
        return rtd_moments(self.time_s, self.signal, **kwargs)


def _convert(value: str):
    try:
        x = float(value)
    except ValueError:
        return value
    return x if math.isfinite(x) else value


def parse_tracer_text(text: str, name: str = "<string>") -> TracerData:
    """Parse tracer-CSV text (see module docstring); ``name`` is used in errors."""
    metadata: dict[str, Any] = {}
    comments: list[str] = []
    lines = text.splitlines()
    i = 0
    while i < len(lines) and (lines[i].lstrip().startswith("#") or not lines[i].strip()):
        line = lines[i]
        if line.strip():
            m = _KEY.match(line)
            if m:
                metadata[m.group(1)] = _convert(m.group(2))
            else:
                comments.append(line.lstrip()[1:].strip())
        i += 1
    if comments:
        metadata["comment"] = "\n".join(comments)
    if i >= len(lines):
        raise ValueError(f"{name}: no header line found (expected e.g. 'time_s,signal')")
    header_line = i + 1
    rows = list(csv.reader(io.StringIO("\n".join(lines[i:]))))
    header = [h.strip() for h in rows[0]]
    tcols = [h for h in header if h in TIME_COLUMNS]
    if not tcols:
        other = [h for h in header if h.lower().startswith("time")]
        hint = f" (found {other[0]!r}, which is not a known unit)" if other else ""
        raise ValueError(
            f"{name} line {header_line}: missing time column{hint}; expected one of "
            f"{', '.join(TIME_COLUMNS)} in header {header}"
        )
    if len(tcols) > 1:
        raise ValueError(f"{name} line {header_line}: more than one time column {tcols}; keep exactly one")
    if "signal" not in header:
        raise ValueError(f"{name} line {header_line}: missing 'signal' column in header {header}")
    it, isg = header.index(tcols[0]), header.index("signal")
    times, sig, lineno = [], [], []
    extras = {h: [] for k, h in enumerate(header) if k not in (it, isg)}
    for k, row in enumerate(rows[1:], start=header_line + 1):
        if not row or all(not c.strip() for c in row) or row[0].lstrip().startswith("#"):
            continue
        if len(row) < len(header):
            raise ValueError(f"{name} line {k}: expected {len(header)} columns, got {len(row)}")
        for col, store in ((it, times), (isg, sig)):
            raw = row[col].strip()
            try:
                x = float(raw)
            except ValueError:
                raise ValueError(f"{name} line {k}: {header[col]} = {raw!r} is not a number") from None
            if not math.isfinite(x):
                raise ValueError(f"{name} line {k}: {header[col]} = {raw!r} is NaN or infinite")
            store.append(x)
        for c, h in enumerate(header):
            if h in extras:
                extras[h].append(row[c].strip())
        lineno.append(k)
    t = np.asarray(times) * TIME_COLUMNS[tcols[0]]
    c = np.asarray(sig)
    if t.size < MIN_POINTS:
        raise ValueError(f"{name}: too few points ({t.size}); a tracer curve needs at least {MIN_POINTS}")
    neg = np.nonzero(c < 0)[0]
    if neg.size:
        j = neg[0]
        raise ValueError(f"{name} line {lineno[j]}: negative signal {c[j]!r}; signals must be >= 0")
    dt = np.diff(t)
    bad = np.nonzero(dt <= 0)[0]
    if bad.size:
        j = bad[0] + 1
        what = "duplicate" if dt[j - 1] == 0 else "unsorted"
        raise ValueError(
            f"{name} line {lineno[j]}: {what} time {times[j]!r} after {times[j - 1]!r} "
            f"({tcols[0]}); times must be strictly increasing"
        )
    return TracerData(t, c, metadata, tcols[0], extras, None)


def load_tracer_csv(path) -> TracerData:
    """Load a tracer curve in the rotarydryer tracer-CSV format (see module docstring).

    Parameters
    ----------
    path : str or Path of the CSV file.

    Returns
    -------
    TracerData (time in s on the file's clock, signal, metadata dict).
    """
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"tracer data file {str(p)!r} does not exist")
    d = parse_tracer_text(p.read_text(encoding="utf-8"), name=str(p))
    return TracerData(d.time_s, d.signal, d.metadata, d.time_column, d.extra_columns, str(p))


def write_tracer_csv(path, time_s, signal, metadata: dict | None = None, time_unit: str = "s") -> None:
    """Write a tracer curve in the tracer-CSV format (atomic: temp file + rename).

    ``time_s`` in s is written in ``time_unit`` (``s``, ``min`` or ``h``).
    """
    from .._io import write_text_atomic

    col = f"time_{time_unit}"
    if col not in TIME_COLUMNS:
        raise ValueError(f"time_unit = {time_unit!r} is not one of 's', 'min', 'h'")
    from .._validation import check_finite

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


_DATASET_PREFIX = "tracer_"


def tracer_datasets() -> list[str]:
    """Names of the published tracer curves shipped in ``rotarydryer/data``.

    ``lee2008_invicta`` (Lee (2008) App. I Experiment entity = Fig. 7.1) and
    ``ajayi2011_test1`` ... ``ajayi2011_test6`` (Ajayi (2011) Appendix B).
    """
    from importlib import resources

    root = resources.files("rotarydryer.data")
    return sorted(
        p.name[len(_DATASET_PREFIX) : -4]
        for p in root.iterdir()
        if p.name.startswith(_DATASET_PREFIX) and p.name.endswith(".csv")
    )


def load_tracer_dataset(name: str) -> TracerData:
    """Load a shipped tracer curve by name (see :func:`tracer_datasets`)."""
    from importlib import resources

    names = tracer_datasets()
    if name not in names:
        raise ValueError(f"tracer dataset {name!r} is not one of {', '.join(map(repr, names))}")
    res = resources.files("rotarydryer.data").joinpath(_DATASET_PREFIX + name + ".csv")
    d = parse_tracer_text(res.read_text("utf-8"), name=name)
    return TracerData(d.time_s, d.signal, d.metadata, d.time_column, d.extra_columns, str(res))
