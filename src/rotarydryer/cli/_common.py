"""Argument helpers shared by the command modules (kept import-light)."""

import os
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Optional

from ..services._options import check_option  # noqa: F401  (re-exported: the commands' range checks)

#: help of the executor options every many-run command shares (`rotarydryer.services._options.executor_from_options`)
WORKERS_HELP = "Local worker processes (0: one per core)."
SCHEDULER_HELP = "Dask scheduler address, e.g. tcp://10.0.0.5:8786."
CLUSTER_HELP = "local:N: a Dask LocalCluster of N worker processes here."


def connect_executor(executor, warm=()) -> None:
    """Start the local pool, reach the Dask scheduler or start the LocalCluster of ``executor`` now,
    before anything runs or is written: exit 3 (one line) when Dask is not installed, exit 2 when
    the scheduler does not answer or the cluster does not start."""
    import typer

    try:
        executor.connect(warm)
    except ImportError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(3)
    except (ValueError, OSError) as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)


def parse_sets(sets: Optional[list[str]]) -> dict:
    """``["operating.rpm=4", ...]`` -> ``{"operating.rpm": "4"}``; the case model converts the
    values to their types and checks them."""
    out: dict = {}
    for item in sets or []:
        if "=" not in item:
            raise ValueError(f"--set {item!r}: expected KEY=VALUE, e.g. transport.n_cells=35")
        k, v = (x.strip() for x in item.split("=", 1))
        if not k:
            raise ValueError(f"--set {item!r}: no key before '='; expected KEY=VALUE, e.g. transport.n_cells=35")
        if not v:       # was read as "none" (the case's default) without a word said
            raise ValueError(f"--set {k}: empty value; give a value, or leave out --set {k} to keep the case's own "
                             f"({k}=none clears an optional key)")
        if k in out:    # the last one won, silently
            raise ValueError(f"--set {k} is given twice ({out[k]} and {v}); give each key once")
        out[k] = v
    return out


def load_tracer(data: str):
    """A tracer curve from a CSV file path or the name of a shipped data set."""
    from ..rtd import load_tracer_csv, load_tracer_dataset, tracer_datasets

    p = Path(data)
    if data in tracer_datasets() and not p.exists():
        return load_tracer_dataset(data)
    if p.exists() or p.is_symlink() or p.suffix or any(sep in data for sep in ("/", "\\")):
        return load_tracer_csv(p)  # names the file: missing, a directory, not UTF-8, too large...
    raise ValueError(
        f"DATA {data!r} is neither an existing file nor a shipped data set "
        f"({', '.join(tracer_datasets())})"
    )


def check_out_dir(option: str, out) -> None:
    """Refuse, before any work is done, an output directory option that cannot be one: an
    existing file, a path under a file (``a_file.txt/sub``), or a place where no directory can be
    made (a read-only or virtual file system: a probe directory is made there and removed at once;
    found by fuzzing: ``design --out /proc/d`` ran its whole search first). Nothing is left behind."""
    if out is None:
        return
    p = Path(out)
    if p.exists() and not p.is_dir():
        raise ValueError(f"{option} {str(p)!r} is an existing file, not a directory; give a directory for the outputs")
    q = p
    while not q.exists():
        if q.parent == q:
            return
        q = q.parent
    if not q.is_dir():
        raise ValueError(f"{option} {str(p)!r}: cannot create the directory, {str(q)!r} is a file")
    _probe_writable(option, p, q)


def _probe_writable(option: str, p: Path, q: Path) -> None:
    """Refuse ``option``'s path ``p`` where nothing can be made in its existing folder ``q`` (a read-only or virtual
    file system): a probe directory is made there and removed at once, nothing is left behind."""
    try:
        os.rmdir(tempfile.mkdtemp(prefix=".rotarydryer-probe-", dir=q))
    except OSError as exc:
        raise ValueError(f"{option} {str(p)!r}: cannot write in {str(q)!r} ({exc.strerror or exc})") from None


@contextmanager
def written_set(out, option: str = "--out", errors: tuple = (OSError,)) -> Iterator[None]:
    """The files written inside the block form one result set in ``out`` (`rotarydryer._io.output_set`:
    all of them or none, a failure keeps the previous set); a write that fails (``errors``) is a one-line
    ``error: --out 'DIR': ...`` on stderr naming the option, exit 2."""
    import typer

    from .._io import output_set

    try:
        with output_set(out):
            yield
    except errors as exc:
        typer.echo(f"error: {option} {str(out)!r}: {exc}", err=True)
        raise typer.Exit(2) from None


def check_out_file(option: str, out, suffixes=None) -> None:
    """Refuse, before any work is done, an output file option that is a directory, lies under a file, has an
    unknown suffix (``suffixes``: allowed lower-case suffixes without the dot; none = any) or lies where no file
    can be written (a probe directory is made in its folder and removed at once; found by review: ``report -o
    /proc/x.html`` ran the whole report first)."""
    if out is None:
        return
    p = Path(out)
    if p.is_dir():
        name = f"out.{suffixes[0]}" if suffixes else "annotated.png"
        raise ValueError(f"{option} {str(p)!r} is a directory; give a file name (e.g. {str(p / name)!r})")
    if suffixes is not None and p.suffix and p.suffix.lower().lstrip(".") not in suffixes:
        raise ValueError(f"{option} {str(p)!r}: unknown file type {p.suffix!r}; use one of "
                         f"{', '.join('.' + s for s in suffixes)}")
    q = p.parent
    while not q.exists():
        if q.parent == q:
            return
        q = q.parent
    if not q.is_dir():
        raise ValueError(f"{option} {str(p)!r}: cannot create the file, {str(q)!r} is a file")
    _probe_writable(option, p, q)      # before the work, not after it


class Progress:
    """The one progress style of the long commands (fit, calibrate, design, sweep, sensitivity, dynamics,
    control, validate, fmu), on stderr so that stdout
    stays clean for --json and tables.

    ``label k/n[: note]``: on a terminal one line updated in place (with a bar when the total is
    known), ended by a newline on `close`; otherwise (a pipe, a log file, CI) one plain line per
    step; nothing at all with ``quiet``.

        >>> with Progress("run", total=3, quiet=True) as p:
        ...     p.advance()
    """

    def __init__(self, label: str, total: Optional[int] = None, *, quiet: bool = False, stream=None):
        self.label, self.total, self.quiet = label, total, bool(quiet)
        self.stream = stream if stream is not None else sys.stderr
        self.done = 0
        try:
            self.tty = bool(self.stream.isatty())
        except (AttributeError, ValueError):
            self.tty = False
        self._open = False

    def _write(self, text: str) -> None:
        if self.quiet:
            return
        if self.tty:
            self.stream.write("\r\x1b[2K" + text)
            self._open = True
        else:
            self.stream.write(text + "\n")
        self.stream.flush()

    def update(self, k: int, n: Optional[int] = None, note: str = "", label: Optional[str] = None) -> None:
        """Step ``k`` of ``n`` (default the total) is done; ``note``: a few words after it."""
        n = self.total if n is None else n
        self.done = k
        name = self.label if label is None else label
        count = f"{k}/{n}" if n else f"{k}"
        bar = ""
        if self.tty and n:
            full = int(round(20 * min(max(k / n, 0.0), 1.0)))
            bar = " [" + "#" * full + "-" * (20 - full) + "]"
        self._write(f"{name} {count}{bar}" + (f": {note}" if note else ""))

    def advance(self, steps: int = 1) -> None:
        """``steps`` more done (the ``progress(n)`` callback of `rotarydryer.cli.sweep.run_sweep`)."""
        self.update(self.done + int(steps))

    def message(self, text: str) -> None:
        """A progress message of the library (e.g. ``design: generation 5/60, ...``), as it is."""
        self._write(str(text))

    def close(self) -> None:
        if self._open and not self.quiet:
            self.stream.write("\n")
            self.stream.flush()
        self._open = False

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False
