"""Safe output files: nothing a user saved is left half-written, lost or made unreadable.

Every file rotarydryer writes goes through `atomic_output` (or the helpers built on it):

* the data go to a temporary file in the destination directory, flushed to disk, which then
  replaces the target with `os.replace`; on any failure (a full disk, a killed write, an
  exception in the writer) the previous file is left exactly as it was and the temporary file
  is removed;
* an existing file keeps its permission bits; a new file gets the usual ``0666 & ~umask``
  (0644 under umask 022), not the 0600 of `tempfile.mkstemp`;
* a target that is a directory, a device, a FIFO or a socket is refused (`OutputError`);
  a symbolic link is followed, so the file it points to is updated and the link stays;
* a missing parent directory is created;
* the temporary file is named ``.NAME.rdtmp-<host>-<pid>-<random>.tmp``; a file of that pattern
  left by a run that was killed (``kill -9``, power loss) is removed at the next write into the same
  folder: when its process is no longer alive on this host (or, for another host or where the
  process cannot be checked, when it is older than `STALE_AFTER_S`). Temporary files of a
  live concurrent run and files not matching the pattern are never touched.

Several files that form one result (``simulate --out DIR``: the JSON and its plots) are written as a
set with `output_set`: every write inside the ``with`` block goes to its temporary file, and
only when all of them are complete are they renamed onto their targets, one after the other. Any
failure before that (a full disk on the third file, an exception, Ctrl-C) removes the temporary
files and leaves the previous set exactly as it was; a rename that fails puts back the files already
renamed (from hard-link backups). Files of the previous set that the new set does not write are
kept (nothing the user has is deleted).

Errors are `OutputError` (a ``ValueError`` and an ``OSError`` subclass) whose message names
the path and the reason, e.g. ``cannot write 'out/rtd.json': No space left on device``.
"""

from __future__ import annotations

import contextlib
import contextvars
import csv
import errno
import hashlib
import io
import json
import math
import os
import re
import secrets
import shutil
import socket
import stat
import subprocess
import time
from pathlib import Path

__all__ = ["OutputError", "atomic_output", "output_set", "OutputSet", "write_text_atomic", "write_bytes_atomic",
           "save_figure", "check_output_target", "check_free_space", "remove_stale_temps", "temp_name",
           "STALE_AFTER_S", "json_text", "csv_text", "finite_or_none", "check_input_file", "MAX_INPUT_FILE_BYTES"]

#: age (s) after which a temporary file of ours whose process cannot be checked (another host,
#: Windows) counts as left over by a killed run
STALE_AFTER_S = 24 * 3600.0
#: bytes; the largest input data file a reader takes (`check_input_file`)
MAX_INPUT_FILE_BYTES = 64_000_000
_TMP_RE = re.compile(r"\..*\.rdtmp-([0-9a-f]{8})-([0-9]{1,10})-[0-9a-f]{8}\.tmp", re.DOTALL)


class OutputError(ValueError, OSError):
    """An output file cannot be written (the message names the path and why)."""


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def check_output_target(path) -> Path:
    """The real file to write for ``path`` (symbolic links followed); raises `OutputError`
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
    """Raise `OutputError` (ENOSPC) if ``directory`` has less than ``nbytes`` (+ 1 MiB) free.

    Used before writers that do not fail cleanly on a full disk (HDF5)."""
    try:
        usage = shutil.disk_usage(directory)
    except OSError:
        return
    free = usage.free
    if usage.total == 0:        # a pseudo file system (/proc, /sys): no space figures; the write says what fails
        return
    if free < int(nbytes) + (1 << 20):
        raise OutputError(f"cannot write {what} to {str(directory)!r}: {os.strerror(errno.ENOSPC)} "
                          f"(needs about {nbytes / 1e6:.3g} MB, {free / 1e6:.3g} MB free)")


def check_input_file(path, what: str = "data file", max_bytes: int = MAX_INPUT_FILE_BYTES) -> Path:
    """``path`` as a Path if it is an existing regular file no larger than ``max_bytes``;
    otherwise ``ValueError`` naming it (``what`` says what it should be)."""
    p = Path(path)
    try:
        st = p.stat()
    except FileNotFoundError:
        raise ValueError(f"{what} {str(p)!r} does not exist") from None
    except OSError as exc:
        raise ValueError(f"cannot read {what} {str(p)!r}: {exc.strerror or exc}") from None
    if stat.S_ISDIR(st.st_mode):
        raise ValueError(f"{what} {str(p)!r} is a directory, not a file")
    if not stat.S_ISREG(st.st_mode):
        raise ValueError(f"{what} {str(p)!r} is not a regular file (a device, FIFO or socket)")
    if st.st_size > max_bytes:
        raise ValueError(f"{what} {str(p)!r} is {st.st_size / 1e6:.1f} MB; the limit is "
                         f"{max_bytes / 1e6:.0f} MB (decimate or split the data)")
    if not os.access(p, os.R_OK):
        raise ValueError(f"cannot read {what} {str(p)!r}: permission denied")
    return p


def _host_tag() -> str:
    return hashlib.sha1(socket.gethostname().encode("utf-8", "replace")).hexdigest()[:8]


def temp_name(name: str) -> str:
    """The temporary file name for a target called ``name``: ``.NAME.rdtmp-<host>-<pid>-<random>.tmp``
    (NAME shortened to 120 bytes so the result stays within the 255-byte limit of a file name)."""
    while len(os.fsencode(name)) > 120:
        name = name[:-1]
    return f".{name}.rdtmp-{_host_tag()}-{os.getpid()}-{secrets.token_hex(4)}.tmp"


def stop_process(proc: subprocess.Popen, grace_s: float) -> None:
    """End a child process: a terminate (mpirun and streamlit pass it on to their own children, and clean up),
    then a kill if it has not ended within ``grace_s`` seconds; returns once it has ended."""
    proc.terminate()
    try:
        proc.wait(timeout=grace_s)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


def _pid_alive(pid: int):
    """True / False whether process ``pid`` runs on this host; None when it cannot be told."""
    if os.name == "nt":         # os.kill(pid, 0) would terminate the process there
        return None
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:     # alive, another user's
        return True
    except OSError:
        return None
    return True


def remove_stale_temps(directory, *, now: float | None = None) -> list[Path]:
    """Remove the temporary files of ours (``.NAME.rdtmp-<host>-<pid>-<random>.tmp``, regular
    files only) in ``directory`` that a killed run left: its process is not alive on this host,
    or (another host, or the process cannot be checked) the file is older than
    `STALE_AFTER_S`. Returns the paths removed; errors are ignored (best effort)."""
    now = time.time() if now is None else now
    host, me = _host_tag(), os.getpid()
    removed: list[Path] = []
    try:
        entries = os.scandir(directory)
    except OSError:
        return removed
    with entries:
        for e in entries:
            m = _TMP_RE.fullmatch(e.name)
            if m is None:
                continue
            try:
                st = e.stat(follow_symlinks=False)
            except OSError:
                continue
            if not stat.S_ISREG(st.st_mode):
                continue
            pid = int(m.group(2))
            if m.group(1) == host:
                if pid == me:           # this process (another thread may be writing it)
                    continue
                alive = _pid_alive(pid)
            else:
                alive = None
            if alive is False or (alive is None and now - st.st_mtime > STALE_AFTER_S):
                try:
                    os.unlink(e.path)
                    removed.append(Path(e.path))
                except OSError:
                    pass
    return removed


def _stage(path, cleaned: set | None = None):
    """Check ``path``, create its folder and an empty temporary file beside the real target;
    returns ``(target, tmp, mode)``. Stale temporary files in the folder are removed first (once
    per folder in a set: ``cleaned``)."""
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
    key = os.path.abspath(directory)
    if cleaned is None or key not in cleaned:
        remove_stale_temps(directory)
        if cleaned is not None:
            cleaned.add(key)
    try:
        tmp = _create_temp(directory, target.name)
    except OSError as exc:
        raise OutputError(f"cannot write {str(path)!r}: {exc.strerror or exc}") from None
    return target, tmp, mode


def _create_temp(directory: Path, name: str) -> str:
    """Create an empty file ``directory/temp_name(name)`` (mode 0600, never an existing one)."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_NOFOLLOW", 0)
    for _ in range(100):
        tmp = os.path.join(directory, temp_name(name))
        try:
            fd = os.open(tmp, flags, 0o600)
        except FileExistsError:
            continue
        os.close(fd)
        return tmp
    raise FileExistsError(errno.EEXIST, "no unused temporary file name")


def _flush_to_disk(tmp: str, mode: int) -> None:
    """fsync the finished temporary file and give it its final permission bits (the point where
    a full disk shows at the latest)."""
    with open(tmp, "rb+") as fh:
        os.fsync(fh.fileno())
    os.chmod(tmp, mode)


class OutputSet:
    """The files of one result, written together (see `output_set`)."""

    def __init__(self, directory=None) -> None:
        self.directory = None if directory is None else Path(directory)
        self._staged: list[tuple[Path, Path, str]] = []      # (path as given, real target, temporary)
        self._cleaned: set = set()
        self.committed = False

    @property
    def files(self) -> list[Path]:
        """The files of the set (as given), in the order written."""
        return [p for p, _, _ in self._staged]

    def _add(self, path, target: Path, tmp: str) -> None:
        for i, (_, t, old) in enumerate(self._staged):
            if t == target:                 # written twice: the later one counts
                _remove(old)
                del self._staged[i]
                break
        self._staged.append((Path(path), target, tmp))

    def _discard(self) -> None:
        for _, _, tmp in self._staged:
            _remove(tmp)
        self._staged.clear()

    def _commit(self) -> None:
        backups: dict[int, str] = {}
        done: list[int] = []
        current: Path | None = None
        try:
            for i, (_, target, _) in enumerate(self._staged):
                if target.exists():
                    backup = os.path.join(target.parent, temp_name(target.name))
                    try:
                        os.link(target, backup)     # the old file, to put back if a rename fails
                        backups[i] = backup
                    except OSError:
                        pass
            for i, (given, target, tmp) in enumerate(self._staged):
                current = given
                os.replace(tmp, target)
                done.append(i)
        except BaseException as exc:
            for i in reversed(done):
                target = self._staged[i][1]
                try:
                    if i in backups:
                        os.replace(backups.pop(i), target)
                    else:
                        os.unlink(target)
                except OSError:
                    pass
            self._discard()
            for b in backups.values():
                _remove(b)
            if isinstance(exc, OSError) and not isinstance(exc, OutputError):
                raise OutputError(f"cannot write {str(current)!r}: {exc.strerror or exc}; the previous files "
                                  "are kept") from None
            raise
        for b in backups.values():
            _remove(b)
        self.committed = True


_ACTIVE: contextvars.ContextVar[OutputSet | None] = contextvars.ContextVar("rotarydryer_output_set", default=None)


@contextlib.contextmanager
def output_set(directory=None):
    """Context manager: every file written inside the block (through `atomic_output` and
    the helpers built on it: `write_text_atomic`, `save_figure`, ``Results.save``)
    belongs to one result set and replaces its target only when the block ends without an
    error and every file is complete; otherwise none does and no temporary file is left (see the
    module docstring). Yields the `OutputSet`. ``directory``, when given, is the set's
    folder (stale temporary files in it are removed at the start). A set opened inside another
    joins the outer one."""
    outer = _ACTIVE.get()
    if outer is not None:
        yield outer
        return
    s = OutputSet(directory)
    if directory is not None and os.path.isdir(directory):
        remove_stale_temps(directory)
        s._cleaned.add(os.path.abspath(directory))
    token = _ACTIVE.set(s)
    try:
        yield s
    except BaseException:
        _ACTIVE.reset(token)
        s._discard()
        raise
    _ACTIVE.reset(token)
    s._commit()


@contextlib.contextmanager
def atomic_output(path):
    """Context manager yielding a temporary path beside ``path``; on a clean exit the temporary
    file replaces ``path`` (see the module docstring), or, inside `output_set`, joins the
    set and replaces ``path`` when the set is complete. The caller writes the whole file to the
    yielded path (any library may do it: ``savefig``, ``to_netcdf``)."""
    active = _ACTIVE.get()
    target, tmp, mode = _stage(path, None if active is None else active._cleaned)
    try:
        yield tmp
        _flush_to_disk(tmp, mode)
        if active is not None:
            active._add(path, target, tmp)
        else:
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
