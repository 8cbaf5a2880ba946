"""The executor options every many-run front end shares (``--workers``/``--jobs``, ``--scheduler``, ``--cluster``):
checked values, or a one-line ``ValueError`` naming the option, the value and the allowed range (import-light: `os`
only; `rotarydryer.executor` is imported when an executor is made). The command line, the app and the DEM batch
(`rotarydryer.dem.calibrate`) read them here (re-exported by `rotarydryer.services._options`)."""

from __future__ import annotations

import numbers
import os

__all__ = ["check_scheduler", "check_workers", "check_cluster", "executor_from_options", "usable_cpus"]


def usable_cpus() -> int:
    """CPU cores this process may run on (its affinity mask where the OS has one), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def check_workers(workers, n_runs: int, *, scheduler=None, option: str = "--workers") -> tuple[int, list[str]]:
    """``(local worker processes, warnings)`` of ``--workers`` (0: one per usable core) for a job of
    ``n_runs`` runs: a ``ValueError`` naming the option below 0 or not an integer; clamped (with a
    warning naming the option and the bound) to the usable CPU cores (`usable_cpus`) and to
    ``n_runs``. With a Dask ``scheduler`` the local count is not used (the cluster has its own)."""
    cpus = usable_cpus()
    # the range as the option takes it: a count above the cores is taken (capped, with a warning), so the range is not
    # [0, cores] (-1 was "outside [0, 2]" while 1000 ran on 2; found by an acceptance check)
    allowed = (f"the allowed range [0, inf) (0: one per core; more than the {cpus} usable CPU cores run as {cpus}, "
               "with a warning)")
    if isinstance(workers, bool) or not isinstance(workers, numbers.Integral):
        raise ValueError(f"{option} = {workers!r} is not a whole number in {allowed}")
    workers = int(workers)      # any integer type (NumPy's from a script's array)
    if workers < 0:
        raise ValueError(f"{option} = {workers} is outside {allowed}")
    notes: list[str] = []
    if scheduler:
        return max(1, min(workers or 1, max(1, n_runs))), notes
    n = workers if workers > 0 else cpus
    over_cpus = n > cpus
    n = min(n, cpus)
    over_runs = n > max(1, n_runs) and workers > 0
    n = min(n, max(1, n_runs))
    # one warning with the number used (more workers than both the cores and the runs gave two, "using 2" and
    # "using 1"; found by review)
    if over_cpus and over_runs:
        notes.append(f"{option} = {workers} is more than the {cpus} usable CPU cores and the {n_runs} runs; using {n}")
    elif over_cpus:
        notes.append(f"{option} = {workers} is more than the {cpus} usable CPU cores; using {n} "
                     f"(give {'--scheduler' if option.startswith('--') else 'scheduler='} for a Dask cluster)")
    elif over_runs:
        notes.append(f"{option} = {workers} is more than the {n_runs} runs; using {n}")
    return n, notes


def check_scheduler(address, option: str = "--scheduler"):
    """`rotarydryer.executor.check_scheduler` (imported when called: the executor is not needed to start a command)."""
    from .executor import check_scheduler as check

    return check(address, option)


def check_cluster(cluster, option: str = "--cluster") -> tuple[int | None, list[str]]:
    """``(workers, warnings)`` of ``--cluster local:N`` (a Dask LocalCluster of N worker processes on this
    machine): a one-line ``ValueError`` naming the option, the value and the form for anything else;
    N above the usable CPU cores is clamped with a warning. ``None`` passes."""
    if cluster is None:
        return None, []
    from .executor import parse_cluster

    n = parse_cluster(cluster, option)
    cpus = usable_cpus()
    if n > cpus:
        return cpus, [f"{option} = local:{n} is more than the {cpus} usable CPU cores; using local:{cpus} "
                      "(give --scheduler for a cluster of several machines)"]
    return n, []


def executor_from_options(workers, n_runs: int, *, scheduler=None, cluster=None, workers_option: str = "--workers"):
    """``(Executor, warnings)`` of the options ``--workers``, ``--scheduler``, ``--cluster`` that every
    many-run command shares (`rotarydryer.executor.Executor`): ``--workers N`` local worker
    processes (0: one per core; clamped to the cores and to ``n_runs``), ``--scheduler ADDRESS`` a
    running Dask scheduler, ``--cluster local:N`` a Dask LocalCluster made here. Bad values and
    ``--scheduler`` with ``--cluster`` are one-line ``ValueError`` naming the option. Nothing is
    started: `Executor.connect` reaches the scheduler or starts the cluster. ``workers_option``: the name the
    front end gives the worker count (the DEM batch's ``--jobs``)."""
    from .executor import Executor

    scheduler = check_scheduler(scheduler)
    if scheduler and cluster is not None:
        raise ValueError(f"--scheduler = {scheduler!r} and --cluster = {cluster!r}: give one, not both "
                         "(--scheduler joins a running Dask cluster, --cluster local:N makes one here)")
    n_cluster, notes = check_cluster(cluster)
    remote = scheduler or cluster
    n, more = check_workers(workers, n_runs, scheduler=remote, option=workers_option)
    notes += more
    if remote:
        if workers != 1:
            notes.append(f"{workers_option} = {workers} is not used with {'--scheduler' if scheduler else '--cluster'} "
                         "(the cluster's workers run the cases)")
        return Executor(scheduler=scheduler, cluster=None if scheduler else f"local:{n_cluster}"), notes
    return Executor(workers=max(1, n)), notes
