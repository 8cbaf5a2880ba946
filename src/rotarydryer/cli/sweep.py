"""``rotarydryer sweep``: run a case over a grid or list of overrides, one table out.

The points run through the one executor (`rotarydryer.executor`; the library side is
`rotarydryer.studies.sweep`): serially, on warm local worker processes (``--workers N``), on a
Dask LocalCluster made here (``--cluster local:N``) or on a running Dask scheduler (``--scheduler
tcp://host:8786``); ``dask.distributed`` is imported only for the last two and is not a
dependency of rotarydryer. Every backend gives the same table, bit for bit.
"""

import csv
from pathlib import Path
from typing import Optional

import typer

from .._grids import MAX_POINTS, parse_grid
from .._grids import check_points as _check_points
from ..executor import stop_on_first_interrupt
from . import app
from ._common import CLUSTER_HELP, SCHEDULER_HELP, WORKERS_HELP

__all__ = ["parse_grid", "read_list", "rows_to_csv", "MAX_POINTS"]


def read_list(path: Path) -> list[dict]:
    """Runs from a CSV file: header = override keys, one row per run ('#' lines ignored); an empty cell
    leaves that key out of the run (the case's own value)."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"--list {str(path)!r}: not a file")
    if path.stat().st_size > 20_000_000:
        raise ValueError(f"--list {str(path)!r}: {path.stat().st_size / 1e6:.3g} MB; the limit is 20 MB")
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"--list {str(path)!r}: not UTF-8 text (byte {exc.start})") from None
    numbered = [(i, line) for i, line in enumerate(text.splitlines(), 1) if line.strip() and not line.startswith("#")]
    parsed = list(csv.reader(line for _, line in numbered))
    where = f"--list {str(path)!r}"
    if not parsed:
        raise ValueError(f"{where}: no runs (need a header of override keys and one row per run)")
    header = [k.strip() for k in parsed[0]]
    seen = [k for k in header if header.count(k) > 1 or not k]
    if seen:
        raise ValueError(f"{where} line {numbered[0][0]}: the header names {seen[0]!r} "
                         f"{'twice' if seen[0] else '(an empty column name)'}: one column per override key")
    for (line, _), row in zip(numbered[1:], parsed[1:]):
        if len(row) != len(header):
            raise ValueError(f"{where} line {line}: {len(row)} value(s) for the header's {len(header)} column(s)")
    rows = parsed[1:]
    _check_points(len(rows), where)
    if not rows:
        raise ValueError(f"{where}: no runs (need a header of override keys and one row per run)")
    from ..cases import DryerCase, override_key_type, override_value

    numeric = {k for k in header if override_key_type(DryerCase, k) in (float, int)}
    for (line, _), row in zip(numbered[1:], rows):       # a value that is no number: the file's line, not a --set
        for k, v in zip(header, row):
            value = override_value(v.strip()) if v.strip() else None
            if k in numeric and value is not None and (isinstance(value, bool) or not isinstance(value, (int, float))):
                raise ValueError(f"{where} line {line}: {k} = {v.strip()!r} is not a number")
    return [{k: v.strip() for k, v in zip(header, r) if v.strip() != ""} for r in rows]


_MOVED = ("run_point", "run_sweep", "_solve_point", "solve_chunk", "sweep_chunks", "KEY_SCALARS", "THERMAL_SCALARS")


def __getattr__(name):
    """The sweep's library functions moved to `rotarydryer.studies.sweep` (issue 32); their old names
    here load it on first use (the CLI starts without the model stack)."""
    if name in _MOVED:
        from ..studies import sweep as _library

        return getattr(_library, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def rows_to_csv(rows: list[dict]) -> str:
    """CSV text of sweep rows, the ``error`` column last (`rotarydryer._io.csv_text`)."""
    from .._io import csv_text

    return csv_text(rows, last=("error",))


@app.command("sweep", short_help="Run a case over a grid or list of overrides.")
def sweep(
    case: str = typer.Argument(..., help="Case name or .toml file."),
    grid: Optional[list[str]] = typer.Option(None, "--grid", help="KEY=V1,V2,...; several --grid: all combinations."),
    list_: Optional[Path] = typer.Option(None, "--list", help="CSV of runs: header = override keys, a row per run (an empty cell: the case's value)."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Override KEY=VALUE applied to every run."),
    workers: int = typer.Option(1, help=WORKERS_HELP),
    scheduler: Optional[str] = typer.Option(None, help=SCHEDULER_HELP),
    cluster: Optional[str] = typer.Option(None, help=CLUSTER_HELP),
    rtd: bool = typer.Option(True, "--rtd/--no-rtd", help="Report the tracer's moments (tracer mean, RTD SD: the "
                                                         "steady state's analytic ones); --no-rtd leaves them out."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="Write the table (CSV) here."),
    as_json: bool = typer.Option(False, "--json", help="Print the rows as a JSON list."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress lines on stderr."),
):
    """Run a case over a grid or list of overrides; one table (CSV) out.

    \b
    Examples:
      rotarydryer sweep lee2008_invicta --grid operating.rpm=2,3,4 --grid operating.feed_rate=20,27.2
      rotarydryer sweep ajayi2011_mmg --grid operating.test=2,3,4,5,6 --workers 0 -o tests.csv

    A list of runs is a CSV file whose header names the case keys, one row per run
    (--list runs.csv); --scheduler tcp://HOST:8786 runs the points on a Dask cluster,
    --cluster local:N on a Dask LocalCluster made here. Every backend gives the same table.

    Exit codes: 0 all runs succeeded, 1 some runs failed (see the error column), 2 bad
    input (an unreachable scheduler included; every run refused the same way, naming no swept key:
    the case or --set), 3 Dask requested but not installed.
    """
    import os

    from .._io import check_output_target
    from ..services._options import executor_from_options
    from ._common import Progress, connect_executor, parse_sets

    try:
        base = parse_sets(set_)
        points = parse_grid(grid)
        if list_ is not None:
            if points:
                raise ValueError("give --grid or --list, not both")
            points = read_list(list_)
        if not points:
            raise ValueError("nothing to run: give --grid KEY=V1,V2 or --list runs.csv")
        swept = sorted(set().union(*points))
        both = [k for k in swept if k in base]
        if both:
            raise ValueError(f"{', '.join(both)} given by --set and by {'--list' if list_ is not None else '--grid'}: "
                             "a swept key takes its values from the sweep; drop the --set")
        executor, worker_notes = executor_from_options(workers, len(points), scheduler=scheduler, cluster=cluster)
        points = [{**base, **p} for p in points]
        from ..cases import load_case

        load_case(case, points[0])  # fail fast on a bad case or key
        if out is not None:            # fail fast on an output that cannot be written
            target = check_output_target(out)
            folder = target.parent if str(target.parent) else Path(".")
            existing = next((p for p in [folder, *folder.parents] if p.exists()), Path("."))
            if not existing.is_dir() or not os.access(existing, os.W_OK | os.X_OK):
                raise ValueError(f"--out {str(out)!r}: cannot write in {str(existing)!r} (not a writable folder)")
    except (ValueError, OSError) as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)
    from ..studies.sweep import run_sweep, warm_up  # the model stack: not before the options are checked

    connect_executor(executor, warm=((warm_up, (case, points[0])),))   # an unreachable scheduler: refused now
    for note in worker_notes:
        typer.echo(f"warning: {note}", err=True)
    rows: list = [None] * len(points)
    interrupted = False
    # the first interrupt stops the runs, and the next ones are ignored until what finished is saved (a second one
    # anywhere in between, e.g. `timeout` signalling the process and then its group, had lost the rows)
    with stop_on_first_interrupt():
        try:
            with Progress("run", len(points), quiet=quiet or len(points) < 2) as bar:
                run_sweep(case, points, executor=executor, rtd=rtd, progress=bar.advance, rows=rows)
        except KeyboardInterrupt:
            interrupted = True
        _finish(rows, points, out, as_json, interrupted, swept)


def _finish(rows, points, out, as_json, interrupted, swept):
    """Write or print the table (and the interrupted run's note); the exit codes of `sweep`."""
    from .._io import write_text_atomic

    rows = [r if r is not None else {**p, "error": "not run (sweep interrupted)"} for r, p in zip(rows, points)]
    text = rows_to_csv(rows)
    if out is not None:
        try:
            write_text_atomic(out, text)
        except OSError as exc:
            # the computed rows are not thrown away: they go to stdout
            typer.echo(text, nl=False)
            typer.echo(f"error: --out {str(out)!r}: {exc}; the table of {len(rows)} runs was printed to "
                       "stdout instead", err=True)
            raise typer.Exit(2)
    if interrupted:
        if out is None:
            typer.echo(text, nl=False)
        typer.echo(f"error: interrupted; {sum(1 for r in rows if r.get('error') != 'not run (sweep interrupted)')}"
                   f" of {len(rows)} runs finished" + (f", saved to {out}" if out is not None else ""), err=True)
        raise typer.Exit(130)
    if as_json:
        from .._io import json_text
        from ..cases import override_value

        given = set().union(*points)    # the overrides' values as the case reads them: numbers, not their text
        typer.echo(json_text([{k: override_value(v) if k in given and isinstance(v, str) else v for k, v in r.items()}
                              for r in rows]))
    elif out is None:
        typer.echo(text, nl=False)
    else:
        typer.echo(f"table: {out} ({len(rows)} runs)")
    noted = [r["note"] for r in rows if r.get("note")]
    if noted:
        typer.echo(f"warning: {len(noted)} of {len(rows)} runs have no fuel rate (an empty fuel_rate_kg_s; the note column "
                   f"says why), e.g. {noted[0]}", err=True)
    failed = sum(1 for r in rows if r.get("error"))
    errors = {r.get("error") for r in rows}
    if failed == len(rows) > 1 and len(errors) == 1 and not any(k in next(iter(errors)) for k in swept):
        # the same refusal for every run, naming none of the swept keys: the case and --set, not the sweep
        typer.echo(f"error: every run failed the same way, whatever the swept values: {next(iter(errors))}", err=True)
        raise typer.Exit(2)
    if failed:
        typer.echo(f"{failed} of {len(rows)} runs failed (see the error column)", err=True)
        raise typer.Exit(1)
