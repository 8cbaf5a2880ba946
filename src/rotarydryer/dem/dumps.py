"""Reading LIGGGHTS ``dump custom`` text files (one file, many frames) into NumPy arrays."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["DumpFrames", "read_dump", "MAX_DUMP_BYTES"]

#: refuse dump files larger than this (a recorded revolution of a few thousand particles is ~50 MB)
MAX_DUMP_BYTES = 4 << 30


@dataclass
class DumpFrames:
    """Frames of a dump: ``steps`` (F,), ``box`` (F, 3, 2) in m, ``columns`` (names) and ``data``:
    a list of F arrays (N_f, C) (particles sorted by id when the deck sorts them)."""

    path: Path
    steps: np.ndarray
    box: np.ndarray
    columns: tuple
    data: list

    def column(self, f: int, name: str) -> np.ndarray:
        return self.data[f][:, self.columns.index(name)]

    def __len__(self) -> int:
        return len(self.steps)


def read_dump(path, *, max_frames: int | None = None, every: int = 1) -> DumpFrames:
    """Read a ``dump custom`` text file (``ITEM: TIMESTEP`` ... blocks).

    Raises ``ValueError`` naming the file and the frame for anything that is not such a dump
    (missing items, a column count that does not match the header, non-numeric values)."""
    path = Path(path)
    try:
        size = path.stat().st_size
    except FileNotFoundError:
        raise ValueError(f"dump file {str(path)!r} does not exist (run the deck first: rotarydryer dem run)") from None
    if size > MAX_DUMP_BYTES:
        raise ValueError(f"dump file {str(path)!r} is {size / 1e9:.3g} GB, larger than the limit of "
                         f"{MAX_DUMP_BYTES / 1e9:.3g} GB")
    raw = path.read_bytes()
    if not raw.startswith(b"ITEM: TIMESTEP"):
        raise ValueError(f"{str(path)!r} is not a LIGGGHTS dump file: it does not start with 'ITEM: TIMESTEP'")
    chunks = raw.split(b"ITEM: TIMESTEP\n")[1:]
    steps, boxes, data = [], [], []
    columns = None
    for k, ch in enumerate(chunks):
        if every > 1 and k % every:
            continue
        if max_frames is not None and len(steps) >= max_frames:
            break
        parts = ch.split(b"\n", 8)
        try:
            if len(parts) < 8 or not parts[1].startswith(b"ITEM: NUMBER OF ATOMS") or not parts[3].startswith(
                    b"ITEM: BOX BOUNDS") or not parts[7].startswith(b"ITEM: ATOMS"):
                raise ValueError("missing ITEM lines")
            step = int(parts[0])
            n = int(parts[2])
            box = np.array([parts[4].split()[:2], parts[5].split()[:2], parts[6].split()[:2]], dtype=float)
            cols = tuple(c.decode() for c in parts[7].split()[2:])
            body = parts[8] if len(parts) > 8 else b""
            vals = np.array(body.split(), dtype=float)
            if vals.size != n * len(cols):
                if k == len(chunks) - 1 and vals.size < n * len(cols):
                    break  # the last frame is being written (run still going)
                raise ValueError(f"{vals.size} numbers for {n} atoms x {len(cols)} columns")
        except ValueError as exc:
            raise ValueError(f"{str(path)!r}, frame {k + 1}: not a readable dump frame ({exc})") from None
        if columns is None:
            columns = cols
        elif cols != columns:
            raise ValueError(f"{str(path)!r}, frame {k + 1}: columns {cols} differ from the first frame's {columns}")
        steps.append(step)
        boxes.append(box)
        data.append(vals.reshape(n, len(cols)))
    if not steps:
        raise ValueError(f"{str(path)!r} holds no complete dump frame")
    return DumpFrames(path, np.array(steps), np.array(boxes), columns, data)
