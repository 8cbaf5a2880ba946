"""Safe output files: nothing a user saved is left half-written, lost or made unreadable.

Every file rotarydryer writes goes through :func:`atomic_output` (or the helpers built on it):

* the data go to a temporary file in the destination directory, flushed to disk, which then
  replaces the target with :func:`os.replace`; on any failure (a full disk, a killed write, an
  exception in the writer) the previous file is left exactly as it was and the temporary file
  is removed;
* an existing file keeps its permission bits; a new file gets the usual ``0666 & ~umask``
  (0644 under umask 022), not the 0600 of :func:`tempfile.mkstemp`;
* a target that is a directory, a device, a FIFO or a socket is refused (:class:`OutputError`);
  a symbolic link is followed, so the file it points to is updated and the link stays;
* a missing parent directory is created.

Errors are :class:`OutputError` (a ``ValueError`` and an ``OSError`` subclass) whose message names
the path and the reason, e.g. ``cannot write 'out/rtd.json': No space left on device``.
"""

from __future__ import annotations

import contextlib
import csv
import errno
import io
import json
import math
import os
import shutil
import stat
import tempfile
from pathlib import Path

__all__ = ["OutputError", "atomic_output", "write_text_atomic", "write_bytes_atomic", "save_figure",
           "check_output_target", "check_free_space", "json_text", "csv_text", "finite_or_none"]


class OutputError(ValueError, OSError):
    """An output file cannot be written (the message names the path and why)."""


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def check_output_target(path) -> Path:
    """The real file to write for ``path`` (symbolic links followed); raises :class:`OutputError`
    if it is a directory, device, FIFO or socket, or its parent is not a directory."""
    path = Path(path)
    if path.is_symlink():
        path = Path(os.path.realpath(path))
    try:
        st = path.stat()
    except FileNotFoundError:
        st = None
    except OSError as exc:
        raise OutputError(f"cannot write {str(path)!r}: {exc.strerror or exc}") from None
    if st is not None and not stat.S_ISREG(st.st_mode):
        what = ("a directory" if stat.S_ISDIR(st.st_mode) else "a FIFO" if stat.S_ISFIFO(st.st_mode)
                else "a device" if (stat.S_ISCHR(st.st_mode) or stat.S_ISBLK(st.st_mode))
                else "a socket" if stat.S_ISSOCK(st.st_mode) else "not a regular file")
        raise OutputError(f"cannot write {str(path)!r}: it is {what}; give a file name")
    parent = path.parent if str(path.parent) else Path(".")
    if parent.exists() and not parent.is_dir():
        raise OutputError(f"cannot write {str(path)!r}: {str(parent)!r} is not a directory")
    return path


def check_free_space(directory, nbytes: int, what: str = "the output") -> None:
    """Raise :class:`OutputError` (ENOSPC) if ``directory`` has less than ``nbytes`` (+ 1 MiB) free.

    Used before writers that do not fail cleanly on a full disk (HDF5)."""
    try:
        free = shutil.disk_usage(directory).free
    except OSError:
        return
    if free < int(nbytes) + (1 << 20):
        raise OutputError(f"cannot write {what} to {str(directory)!r}: {os.strerror(errno.ENOSPC)} "
                          f"(needs about {nbytes / 1e6:.3g} MB, {free / 1e6:.3g} MB free)")


@contextlib.contextmanager
def atomic_output(path):
    """Context manager yielding a temporary path beside ``path``; on a clean exit the temporary
    file replaces ``path`` (see the module docstring). The caller writes the whole file to the
    yielded path (any library may do it: ``savefig``, ``to_netcdf``)."""
    target = check_output_target(path)
    directory = target.parent if str(target.parent) else Path(".")
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"cannot create the directory {str(directory)!r} for {str(path)!r}: "
                          f"{exc.strerror or exc}") from None
    try:
        mode = stat.S_IMODE(target.stat().st_mode)
    except FileNotFoundError:
        mode = 0o666 & ~_umask()
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=directory)
    except OSError as exc:
        raise OutputError(f"cannot write {str(path)!r}: {exc.strerror or exc}") from None
    os.close(fd)
    try:
        yield tmp
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        os.chmod(tmp, mode)
        os.replace(tmp, target)
    except OSError as exc:
        _remove(tmp)
        if isinstance(exc, OutputError):
            raise
        raise OutputError(f"cannot write {str(path)!r}: {exc.strerror or exc}") from None
    except BaseException:
        _remove(tmp)
        raise


def _remove(tmp):
    try:
        os.unlink(tmp)
    except FileNotFoundError:
        pass
    except OSError:
        pass


def write_bytes_atomic(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (see the module docstring); returns ``path``."""
    with atomic_output(path) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(data)
    return Path(path)


def write_text_atomic(path, text: str, encoding: str = "utf-8", newline: str | None = None) -> Path:
    """Write ``text`` to ``path`` atomically (see the module docstring); returns ``path``."""
    with atomic_output(path) as tmp:
        with open(tmp, "w", encoding=encoding, newline=newline) as fh:
            fh.write(text)
    return Path(path)


def save_figure(fig, path, **kwargs) -> Path:
    """``fig.savefig`` to ``path`` atomically (rendered in memory first; the format from the
    suffix, PNG by default); the figure is closed afterwards."""
    fmt = kwargs.pop("format", None) or (Path(path).suffix.lstrip(".").lower() or "png")
    buf = io.BytesIO()
    try:
        fig.savefig(buf, format=fmt, **kwargs)
    finally:
        try:
            import matplotlib.pyplot as plt

            plt.close(fig)
        except Exception:  # noqa: BLE001 - closing is best effort
            pass
    return write_bytes_atomic(path, buf.getvalue())


def finite_or_none(obj):
    """``obj`` with every non-finite float (NaN, inf) replaced by None, recursively (dicts, lists,
    tuples, NumPy scalars and arrays), so that the JSON written is valid JSON."""

    import numpy as np

    if isinstance(obj, dict):
        return {k: finite_or_none(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite_or_none(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return finite_or_none(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def json_text(obj, **kwargs) -> str:
    """``json.dumps`` of ``obj`` as strict JSON (NaN and inf become null)."""

    kwargs.setdefault("default", float)
    return json.dumps(finite_or_none(obj), allow_nan=False, **kwargs)


def csv_text(rows: list[dict], last: tuple = ()) -> str:
    """CSV text of ``rows`` (dicts): the columns in order of first appearance, then the ``last``
    columns (always present, e.g. a sweep's ``error``); floats by ``repr`` (they read back exactly),
    ``None`` as an empty cell."""

    cols = list(dict.fromkeys(k for r in rows for k in r if k not in last)) + list(last)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=cols, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: ("" if v is None else repr(v) if isinstance(v, float) else v) for k, v in r.items()})
    return buf.getvalue()
