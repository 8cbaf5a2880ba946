"""Reading user data files (tracer curves, flight-rig records, design-load tables) safely.

Every measured-data file is read through `data_lines`, which

* refuses a missing path, a directory, a device or FIFO, and a file larger than
  `MAX_DATA_FILE_BYTES` (checked with ``stat`` before reading, and again while reading);
* reads line by line (the file is never held in memory as a whole) and refuses a line longer
  than `MAX_LINE_CHARS`, NUL bytes (a binary file) and bytes that are not UTF-8, naming
  the file and the line;
* leaves the row count to the parser, which stops at `MAX_DATA_ROWS` data rows
  (`too_many_rows` gives the message), so a runaway file fails after reading at most that
  many rows.

All errors are ``ValueError`` whose message starts with the file name (and the line where there
is one): ``rig.csv line 17: 'abc' is not a number in column time_s``.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Iterator

from .._io import MAX_INPUT_FILE_BYTES, check_input_file

__all__ = ["csv_rows", "MAX_DATA_ROWS", "MAX_DATA_FILE_BYTES", "MAX_LINE_CHARS", "check_input_file", "data_lines",
           "text_lines", "too_many_rows", "parse_number", "fmt"]

MAX_DATA_ROWS = 200_000
"""Most data rows read from one file (100 Hz rig records: 33 min; tracer curves have < 10^4)."""
MAX_DATA_FILE_BYTES = MAX_INPUT_FILE_BYTES
"""Largest data file read, bytes (64 MB)."""
MAX_LINE_CHARS = 1 << 20
"""Longest line read, bytes (1 MiB)."""


def fmt(x) -> str:
    """A number as the user would write it (no NumPy repr): ``1.5``, ``-3``, ``nan``."""
    try:
        v = float(x)
    except (TypeError, ValueError):
        return repr(x)
    if math.isfinite(v) and v == int(v) and abs(v) < 1e15:
        return str(int(v))
    return f"{v:.6g}"


def _decode(raw: bytes, name: str, lineno: int) -> str:
    if b"\x00" in raw:
        raise ValueError(f"{name} line {lineno}: contains NUL bytes; this is a binary file, not a text (CSV) file")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(
            f"{name} line {lineno}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at character {exc.start + 1}); "
            "save the file as UTF-8 CSV"
        ) from None
    if lineno == 1 and text.startswith("\ufeff"):  # byte-order mark of Excel's "CSV UTF-8"
        text = text[1:]
    return text.rstrip("\r\n")


def data_lines(path, what: str = "data file", max_bytes: int = MAX_DATA_FILE_BYTES) -> Iterator[tuple[int, str]]:
    """``(line number, text)`` of each line of a UTF-8 text file, checked as the module says.

    The file name in messages is ``str(path)``. Raises ``ValueError``.
    """
    p = check_input_file(path, what, max_bytes)
    name = str(p)
    total = 0
    try:
        fh = open(p, "rb")
    except OSError as exc:
        raise ValueError(f"cannot read {what} {name!r}: {exc.strerror or exc}") from None
    with fh:
        lineno = 0
        while True:
            try:
                raw = fh.readline(MAX_LINE_CHARS + 1)
            except OSError as exc:
                raise ValueError(f"cannot read {what} {name!r}: {exc.strerror or exc}") from None
            if not raw:
                return
            lineno += 1
            total += len(raw)
            if len(raw) > MAX_LINE_CHARS:
                raise ValueError(f"{name} line {lineno}: longer than {MAX_LINE_CHARS // 1024} kB; "
                                 "this is not a data (CSV) file")
            if total > max_bytes:
                raise ValueError(f"{what} {name!r} is larger than the limit of {max_bytes / 1e6:.0f} MB")
            yield lineno, _decode(raw, name, lineno)


def text_lines(text: str) -> Iterator[tuple[int, str]]:
    """``(line number, text)`` of the lines of a string (the same interface as `data_lines`)."""
    for k, line in enumerate(text.splitlines(), start=1):
        if k == 1 and line.startswith("\ufeff"):
            line = line[1:]
        yield k, line


def too_many_rows(name: str, lineno: int, limit: int = MAX_DATA_ROWS) -> ValueError:
    """The error for a file with more than ``limit`` data rows (found at ``lineno``)."""
    return ValueError(f"{name} line {lineno}: more than {limit} data rows; the limit is {limit} rows "
                      "(decimate or split the record)")


def parse_number(raw: str, name: str, lineno: int, column: str, *, finite: bool = True) -> float:
    """``float(raw)`` or ``ValueError`` naming the file, line and column."""
    s = raw.strip()
    try:
        x = float(s)
    except ValueError:
        shown = s if len(s) <= 40 else s[:37] + "..."
        what = "an empty field" if not s else repr(shown)
        raise ValueError(f"{name} line {lineno}: {what} is not a number in column {column}") from None
    if finite and not math.isfinite(x):
        raise ValueError(f"{name} line {lineno}: {column} = {s!r} is NaN or infinite; give a finite number")
    return x


def csv_rows(lines, name: str, *, skip_comments: bool = True) -> Iterator[tuple[int, list]]:
    """CSV rows of numbered ``lines`` (from `data_lines` or `text_lines`) as
    ``(line number, fields)``; blank rows (and ``#`` rows with ``skip_comments``) are skipped, a
    malformed row names the file and line."""

    current = [0]

    def text():
        for k, line in lines:
            current[0] = k
            yield line

    reader = csv.reader(text())
    while True:
        try:
            row = next(reader)
        except StopIteration:
            return
        except csv.Error as exc:
            raise ValueError(f"{name} line {current[0]}: unreadable CSV ({exc})") from None
        if not row or all(not c.strip() for c in row) or (skip_comments and row[0].lstrip().startswith("#")):
            continue
        yield current[0], row
