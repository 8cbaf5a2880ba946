"""A case over a list of overrides, one row per run: what ``rotarydryer sweep`` runs.

>>> from rotarydryer.studies.sweep import run_sweep
>>> rows = run_sweep("song2003_ottawa", [{"operating.rpm": 4}, {"operating.rpm": 5}])  # doctest: +SKIP
>>> rows[0]["total_holdup_kg"], rows[0]["error"]                                      # doctest: +SKIP

The points run through the one executor (`rotarydryer.executor.Executor`): serially, on warm local
worker processes, or on a Dask cluster. They are cut into chunks that depend on the number of
points only (`sweep_chunks`); a chunk's first point starts cold and each later one from the last
converged point of its chunk (`rotarydryer.simulation.Simulation.steady_state` ``warm``), so
every backend and worker count gives the same table, bit for bit. A point that fails is a row with
its ``error`` (one line); it never ends the sweep.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Optional

from .._threads import single_threaded
from ..executor import Executor, RunFailure, split
from ..simulation import SWEEP_MAX_CHUNK, SWEEP_MIN_CHUNK, Simulation, check_finite
from ..thermal.states import fuel_rate_note

__all__ = ["KEY_SCALARS", "RTD_SCALARS", "SIZE_CLASS_SCALARS", "THERMAL_SCALARS", "SWEEP_MIN_CHUNK", "SWEEP_MAX_CHUNK", "run_point", "run_sweep",
           "sweep_chunks", "solve_chunk", "warm_up"]

#: transport outputs of a sweep row (names with their unit)
KEY_SCALARS = ("total_holdup_kg", "active_holdup_kg", "passive_holdup_kg", "kiln_bed_holdup_kg", "bed_holdup_kg",
               "outlet_flow_kg_s", "mean_residence_time_s", "rtd_std_s", "mass_balance_error", "cells_over",
               "cells_design", "cells_under")
#: the tracer's moments in a row (left out with ``rtd=False``)
RTD_SCALARS = ("tracer_mean_s", "rtd_std_s")
#: outputs of the coupled heat and mass transfer steady state added to sweep rows
THERMAL_SCALARS = ("product_moisture_kg_kg", "product_temperature_degC", "gas_outlet_temperature_degC",
                   "evaporation_kg_s", "fuel_rate_kg_s", "shell_heat_loss_W", "energy_balance_error")
#: outputs added to the rows of a feed in size classes (the gas carries the fines off): the CSV of a
#: single-class case keeps its columns
SIZE_CLASS_SCALARS = ("dust_rate_kg_s", "product_d50_m")


def sweep_chunks(n: int) -> list[slice]:
    """The chunks of a sweep of ``n`` points (`rotarydryer.executor.split`: 16 as even ones, at
    least `SWEEP_MIN_CHUNK` and at most `SWEEP_MAX_CHUNK` points each); they depend on ``n`` only."""
    return split(n, min_size=SWEEP_MIN_CHUNK, max_size=SWEEP_MAX_CHUNK)


def _solve_point(case, overrides: dict, warm=None):
    """(row, warm-start data or None) of one point: the steady state of
    ``Simulation(case, overrides)`` (started from ``warm``, a nearby point's), its summary and
    loading counts. The tracer moments are the analytic ones of that state (what a simulated
    pulse's would tend to), so a point costs one transport and one coupled solve."""
    row = dict(overrides)
    try:
        with single_threaded():      # one BLAS/OpenMP thread per run (no oversubscription, issue 16)
            res = Simulation(case, overrides).steady_state(warm=warm)
            summary = res.summary()
            out = {k: float(v) for k, v in {**summary, **res.state.loading_counts()}.items()
                   if isinstance(v, (int, float)) and not isinstance(v, bool)}
            check_finite(out, str(case))
    except (ValueError, ArithmeticError, MemoryError) as exc:      # one bad point never ends the sweep
        row["error"] = " ".join(str(exc).split()) or type(exc).__name__
        return row, None
    dryer = getattr(getattr(res, "thermal", None), "dryer", None)
    classes = getattr(dryer, "n_classes", 1) > 1 or bool(getattr(dryer, "dusty", False))     # one dusty class too
    for k in (*KEY_SCALARS, "tracer_mean_s", *THERMAL_SCALARS, *(SIZE_CLASS_SCALARS if classes else ())):
        if k in out:
            row[k] = out[k]
    note = fuel_rate_note(summary)
    if note:    # the burner cannot reach the point's gas inlet temperature: an empty fuel rate, and why
        row["fuel_rate_kg_s"] = None
        row["note"] = note
    row["error"] = ""
    return row, res.warm_data()


def run_point(case, overrides: dict, rtd: bool = True) -> dict:
    """One sweep point from a cold start -> a flat row (overrides + key scalars, units in the names; ``rtd=False``:
    without the tracer's moments); an invalid point gives a row with ``error``."""
    row = _solve_point(case, overrides)[0]
    return row if rtd else _without_rtd(row)


def _without_rtd(row: dict) -> dict:
    """``row`` without the tracer's moments (RTD_SCALARS)."""
    return {k: v for k, v in row.items() if k not in RTD_SCALARS}


def solve_chunk(points: Sequence[dict], case) -> list[dict]:
    """Rows of a chunk of points, in order: the first from a cold start, each later one from the last
    converged point before it in the chunk. Top-level, so that it pickles for worker processes."""
    rows, warm = [], None
    for p in points:
        row, data = _solve_point(case, p, warm)
        warm = data or warm
        rows.append(row)
    return rows


def warm_up(case, overrides: dict) -> None:
    """A worker's warm-up before its first chunk: imports, compiled kernels, geometry tables, one
    model built and solved (the result is dropped; the runs report their own errors)."""
    _solve_point(case, overrides)


def run_sweep(case, points: list[dict], *, workers: int = 1, scheduler: Optional[str] = None,
              cluster: Optional[str] = None, executor: Optional[Executor] = None, rtd: bool = True,
              progress: Optional[Callable[[int], object]] = None, rows: Optional[list] = None) -> list[dict]:
    """Run all points; rows come back in the order of ``points``, the same whatever runs them
    (``executor``, or one made of ``workers`` local processes, a Dask ``scheduler`` address or a
    ``cluster`` "local:N"). ``rows`` (a list of ``len(points)`` None) is filled as chunks finish,
    so a caller keeps what was computed if the sweep is interrupted; ``progress(n)`` after each chunk.
    ``rtd=False``: the rows without the tracer's moments (RTD_SCALARS)."""
    points = [dict(p) for p in points]
    if rows is None:
        rows = [None] * len(points)
    ex = executor or Executor(workers=max(1, int(workers)), scheduler=scheduler, cluster=cluster)
    warm = ((warm_up, (case, points[0])),) if points else ()
    ex.map_chunks(solve_chunk, points, chunks=sweep_chunks(len(points)), args=(case,), warm=warm,
                  progress=progress, results=rows)
    for i, r in enumerate(rows):
        if isinstance(r, RunFailure):
            rows[i] = {**points[i], "error": r.error}
        elif not rtd:       # without the tracer's moments (the steady state's analytic ones)
            rows[i] = _without_rtd(r)
    return rows
