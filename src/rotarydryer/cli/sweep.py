"""``rotarydryer sweep``: run a case over a grid or list of overrides, one table out.

Runs on the local cores (``concurrent.futures.ProcessPoolExecutor``) or, given
``--scheduler tcp://host:8786``, on a Dask cluster (``dask.distributed`` is imported only
then and is not a dependency of rotarydryer).
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Optional

import typer

from .._grids import MAX_POINTS, parse_grid
from .._grids import check_points as _check_points
from . import app

__all__ = ["parse_grid", "read_list", "run_point", "run_sweep", "rows_to_csv", "MAX_POINTS"]

KEY_SCALARS = ("total_holdup_kg", "active_holdup_kg", "passive_holdup_kg", "kiln_bed_holdup_kg", "bed_holdup_kg",
               "outlet_flow_kg_s", "mean_residence_time_s", "rtd_std_s", "mass_balance_error", "cells_over",
               "cells_design", "cells_under")


def read_list(path: Path) -> list[dict]:
    """Runs from a CSV file: header = override keys, one row per run ('#' lines ignored)."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"--list {str(path)!r}: not a file")
    if path.stat().st_size > 20_000_000:
        raise ValueError(f"--list {str(path)!r}: {path.stat().st_size / 1e6:.3g} MB; the limit is 20 MB")
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"--list {str(path)!r}: not UTF-8 text (byte {exc.start})") from None
    rows = list(csv.DictReader(line for line in text.splitlines() if line.strip() and not line.startswith("#")))
    _check_points(len(rows), f"--list {str(path)!r}")
    if not rows:
        raise ValueError(f"--list {str(path)!r}: no runs (need a header of override keys and one row per run)")
    return [{k.strip(): v.strip() for k, v in r.items() if v is not None and v.strip() != ""} for r in rows]


def run_point(case: str, overrides: dict, rtd: bool = True) -> dict:
    """One sweep point -> a flat row (overrides + key scalars, units in the names); an
    invalid point gives a row with ``error``.  Top-level so that it pickles for
    process pools and Dask."""
    return _solve_point(case, overrides)[0]


def _solve_point(case: str, overrides: dict, warm=None):
    """(row, warm-start data or None) of one point: the steady state of
    ``Simulation(case, overrides)`` (started from ``warm``, a nearby point's), its summary and
    loading counts. The tracer moments are the analytic ones of that state (what a simulated
    pulse's would tend to), so a point costs one transport and one coupled solve."""
    from .._threads import single_threaded
    from ..simulation import Simulation, check_finite  # the model stack: not at the CLI's start-up

    row = dict(overrides)
    try:
        with single_threaded():      # one BLAS/OpenMP thread per run (no oversubscription, issue 16)
            res = Simulation(case, overrides).steady_state(warm=warm)
            out = {k: float(v) for k, v in {**res.summary(), **res.state.loading_counts()}.items()
                   if isinstance(v, (int, float)) and not isinstance(v, bool)}
            check_finite(out, case)
    except (ValueError, ArithmeticError, MemoryError) as exc:      # one bad point never ends the sweep
        row["error"] = " ".join(str(exc).split()) or type(exc).__name__
        return row, None
    for k in (*KEY_SCALARS, "tracer_mean_s", *THERMAL_SCALARS):
        if k in out:
            row[k] = out[k]
    row["error"] = ""
    return row, res.warm_data()


#: outputs of the coupled heat and mass transfer steady state added to sweep rows
THERMAL_SCALARS = ("product_moisture_kg_kg", "product_temperature_degC", "gas_outlet_temperature_degC",
                   "evaporation_kg_s", "fuel_rate_kg_s", "shell_heat_loss_W", "energy_balance_error")


def run_sweep(case: str, points: list[dict], *, workers: int = 1, scheduler: Optional[str] = None,
              rtd: bool = True, progress=None, rows: Optional[list] = None) -> list[dict]:
    """Run all points; rows come back in the order of ``points``. ``rows`` (a list of
    ``len(points)`` None) is filled as runs finish, so a caller keeps what was computed if the
    sweep is interrupted."""
    if rows is None:
        rows = [None] * len(points)
    tick = progress or (lambda n: None)
    if scheduler:
        try:
            from dask.distributed import Client, as_completed
        except ImportError as exc:
            raise ImportError("--scheduler needs dask.distributed: pip install 'dask[distributed]'") from exc
        with Client(scheduler) as client:
            futs = {client.submit(run_point, case, p, rtd, pure=False): i for i, p in enumerate(points)}
            for f in as_completed(futs):
                rows[futs[f]] = f.result()
                tick(1)
        return rows
    if workers <= 1 or len(points) == 1:
        warm = None
        for i, p in enumerate(points):      # each point starts from the last converged one
            rows[i], data = _solve_point(case, p, warm)
            warm = data or warm
            tick(1)
        return rows
    from concurrent.futures import ProcessPoolExecutor, as_completed

    from .._threads import limit_worker_threads

    with ProcessPoolExecutor(max_workers=min(workers, len(points)), initializer=limit_worker_threads) as ex:
        futs = {ex.submit(run_point, case, p, rtd): i for i, p in enumerate(points)}
        for f in as_completed(futs):
            rows[futs[f]] = f.result()
            tick(1)
    return rows


def rows_to_csv(rows: list[dict]) -> str:
    """CSV text of sweep rows, the ``error`` column last (`rotarydryer._io.csv_text`)."""
    from .._io import csv_text

    return csv_text(rows, last=("error",))


@app.command("sweep", short_help="Run a case over a grid or list of overrides.")
def sweep(
    case: str = typer.Argument(..., help="Case name or .toml file."),
    grid: Optional[list[str]] = typer.Option(None, "--grid", help="KEY=V1,V2,...; several --grid: all combinations."),
    list_: Optional[Path] = typer.Option(None, "--list", help="CSV of runs: header = override keys, a row per run."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Override KEY=VALUE applied to every run."),
    workers: int = typer.Option(1, help="Local worker processes (0: one per core)."),
    scheduler: Optional[str] = typer.Option(None, help="Dask scheduler address, e.g. tcp://10.0.0.5:8786."),
    rtd: bool = typer.Option(True, "--rtd/--no-rtd", help="Also simulate the tracer pulse (RTD SD, tracer mean)."),
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
    (--list runs.csv); --scheduler tcp://HOST:8786 runs the points on a Dask cluster.

    Exit codes: 0 all runs succeeded, 1 some runs failed (see the error column), 2 bad
    input, 3 Dask requested but not installed.
    """
    import os

    from .._io import check_output_target, write_text_atomic
    from ..services._options import check_scheduler, check_workers
    from ._common import Progress, parse_sets

    try:
        base = parse_sets(set_)
        points = parse_grid(grid)
        if list_ is not None:
            if points:
                raise ValueError("give --grid or --list, not both")
            points = read_list(list_)
        if not points:
            raise ValueError("nothing to run: give --grid KEY=V1,V2 or --list runs.csv")
        scheduler = check_scheduler(scheduler)
        n, worker_notes = check_workers(workers, len(points), scheduler=scheduler)
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
    for note in worker_notes:
        typer.echo(f"warning: {note}", err=True)
    rows: list = [None] * len(points)
    interrupted = False
    try:
        with Progress("run", len(points), quiet=quiet or len(points) < 2) as bar:
            run_sweep(case, points, workers=n, scheduler=scheduler, rtd=rtd, progress=bar.advance, rows=rows)
    except ImportError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(3)
    except KeyboardInterrupt:
        interrupted = True
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

        typer.echo(json_text(rows))
    elif out is None:
        typer.echo(text, nl=False)
    else:
        typer.echo(f"table: {out} ({len(rows)} runs)")
    failed = sum(1 for r in rows if r.get("error"))
    if failed:
        typer.echo(f"{failed} of {len(rows)} runs failed (see the error column)", err=True)
        raise typer.Exit(1)
