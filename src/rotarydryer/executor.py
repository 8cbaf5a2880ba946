"""One executor for every many-run workload: serial, warm local workers, or Dask distributed.

Sweeps, Sobol studies, design-search populations, multi-start fits, calibrations,
cross-validation studies and DEM batches all run their cases through `Executor`:

>>> from rotarydryer.executor import Executor
>>> def square_all(chunk):                   # top level, so that it pickles
...     return [x * x for x in chunk]
>>> with Executor() as ex:                   # serial; Executor(workers=2), Executor(cluster="local:2") ...
...     ex.map_chunks(square_all, [1, 2, 3], chunks=2)
[1, 4, 9]

**Backends.** ``"serial"`` runs the chunks one after the other in this process. ``"local"`` runs
them on a pool of long-lived worker processes (`concurrent.futures.ProcessPoolExecutor`), one
per process and kept for the next call: the pool of a given size is made once per process and
closed at exit. On Linux the workers are forked from this process after it has run the
workload's warm-up (imports, compiled kernels, geometry tables, a first model built and solved),
so a worker starts warm at no extra CPU cost; elsewhere (or when this process already runs
threads) they are started fresh and each runs the warm-up once. ``"dask"`` submits the chunks to
a Dask cluster: a running scheduler (``scheduler="tcp://HOST:8786"``, e.g. one that dask-jobqueue
started on Slurm or PBS) or a `distributed.LocalCluster` of ``N`` single-threaded worker
processes made here (``cluster="local:N"``). ``dask.distributed`` is imported only then; it is
not a dependency of rotarydryer. Every worker process (local or Dask) limits BLAS/OpenMP to one
thread (`rotarydryer._threads.limit_worker_threads`) and runs each warm-up once.

**The same numbers whatever the backend.** A batch is cut into chunks (`split`) that depend on
the number of items only, never on the backend or the worker count; the workload's function
solves a chunk's items in order from a cold start (warm-starting each item from the ones before it
*in the chunk*), so a serial run, a local pool and a Dask cluster compute the same chunks the same
way and give the same results bit for bit.

**Failures.** A chunk function that raises does not end the batch: its chunk is run again one item
at a time, and each item that raises becomes a `RunFailure` (its one-line message) in the results;
a worker process that dies turns its chunk's items into `RunFailure` values. ``KeyboardInterrupt``
stops the batch (the results list passed as ``results`` keeps what finished).

**Overhead.** Measured on the 2-core machine (issue 32): a chunk costs about 0.2 ms of dispatch on
the local pool and about 5 ms of CPU (client, scheduler and worker together) on a Dask
LocalCluster; a chunk of a sweep or a Sobol study holds 0.2-4 s of model runs, so the dispatch is
below 5 % on either.
"""

from __future__ import annotations

import atexit
import concurrent.futures
import contextlib
import gc
import math
import numbers
import os
import pickle
import signal
import sys
import threading
import uuid
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Optional

from . import _jit
from ._startup import raise_gc_threshold
from ._threads import limit_worker_threads

__all__ = ["BACKENDS", "TARGET_CHUNKS", "CONNECT_TIMEOUT_S", "START_METHOD_ENV", "MAX_LOCAL_WORKERS", "Executor",
           "RunFailure", "check_scheduler", "one_line", "parse_cluster", "split", "shutdown_all", "worker_info"]

#: backends of `Executor`
BACKENDS = ("serial", "local", "dask")
#: chunks a batch is cut into by default: a power of two, so that 1, 2, 4, 8 or 16 workers share them evenly
TARGET_CHUNKS = 16
#: seconds to wait for a Dask scheduler before an address is refused
CONNECT_TIMEOUT_S = 10.0
#: how often, s, a local pool's batch looks for a noted Ctrl-C while it waits for its chunks (`_interrupt_noted`)
INTERRUPT_POLL_S = 0.05
#: environment variable naming the start method of local workers ("fork", "spawn", "forkserver")
START_METHOD_ENV = "ROTARYDRYER_WORKER_START"
#: most local worker processes or LocalCluster workers one executor may start
MAX_LOCAL_WORKERS = 256


@dataclass(frozen=True)
class RunFailure:
    """An item of a batch that raised: ``error`` is its one-line message. It stands in the results
    in the item's place (a batch never ends on one failed run)."""

    error: str

    def __str__(self) -> str:
        return self.error


def one_line(exc: BaseException) -> str:
    """The message of ``exc`` on one line (its type name when it has none)."""
    return " ".join(str(exc).split()) or type(exc).__name__


def split(n: int, *, chunks: int = TARGET_CHUNKS, min_size: int = 1, max_size: Optional[int] = None) -> list[slice]:
    """Contiguous slices of ``range(n)``, as even as possible (sizes differ by at most one, the
    larger first): ``chunks`` of them, fewer where a slice would hold fewer than ``min_size``
    items, more where it would hold more than ``max_size``. They depend on these numbers only,
    never on the backend or the worker count (the results of a chunk do not change with them).

    >>> [(s.start, s.stop) for s in split(10, chunks=4)]
    [(0, 3), (3, 6), (6, 8), (8, 10)]
    >>> [(s.start, s.stop) for s in split(10, min_size=4)]
    [(0, 5), (5, 10)]
    """
    n = int(n)
    if n <= 0:
        return []
    k = max(1, int(chunks))
    if max_size:
        k = max(k, math.ceil(n / max(1, int(max_size))))
    k = min(k, max(1, n // max(1, int(min_size))), n)
    base, extra = divmod(n, k)
    out, start = [], 0
    for i in range(k):
        size = base + (1 if i < extra else 0)
        out.append(slice(start, start + size))
        start += size
    return out


def parse_cluster(value, option: str = "--cluster") -> int:
    """The worker count of ``local:N`` (a Dask LocalCluster of N single-threaded worker processes
    made on this machine), or a one-line ``ValueError`` naming ``option``, the value and the form."""
    text = str(value).strip()
    kind, sep, count = text.partition(":")
    form = f"expected local:N with N from 1 to {MAX_LOCAL_WORKERS} (a Dask LocalCluster of N worker processes), e.g. local:2"
    if kind.strip().lower() != "local" or not sep:
        raise ValueError(f"{option} = {text!r} is not a cluster; {form}; for a running scheduler give --scheduler ADDRESS")
    try:
        n = int(count.strip())
    except ValueError:
        raise ValueError(f"{option} = {text!r}: {count.strip()!r} is not a whole number of workers; {form}") from None
    if not 1 <= n <= MAX_LOCAL_WORKERS:
        raise ValueError(f"{option} = {text!r}: {n} workers is outside the allowed range [1, {MAX_LOCAL_WORKERS}]; {form}")
    return n


# ------------------------------------------------------------------------------------ in every process
_WARMED: set = set()        # keys of the warm-ups run in this process
_WARM_RUNS = [0]            # how many warm-ups this process ran (worker_info)
_SET_UP = [False]           # BLAS threads limited in this worker process


def _warm_key(fn, args) -> tuple:
    try:
        blob = pickle.dumps(args, protocol=4)
    except Exception:       # noqa: BLE001 - an argument that does not pickle: its repr names it
        blob = repr(args).encode()
    return getattr(fn, "__module__", ""), getattr(fn, "__qualname__", repr(fn)), blob


#: warnings a worker's warm-ups raised, sent with its next chunk's results (`_run_chunk`): a warning said once per
#: process (a cache's, the compiled kernels') fires in the warm-up and never again in the runs
_WARM_WARNINGS: list = []


def _ensure_warm(warm, in_worker: bool = False) -> None:
    """Run each ``(fn, args)`` of ``warm`` once in this process (a warm-up that fails is not retried:
    it only saves time, the runs report their own errors). In a worker process (``in_worker``) its warnings are kept
    for the next chunk's results (`_WARM_WARNINGS`); in the process that made the batch they are shown as raised."""
    for fn, args in warm or ():
        key = _warm_key(fn, args)
        if key in _WARMED:
            continue
        _WARMED.add(key)
        _WARM_RUNS[0] += 1
        try:
            if in_worker:
                with warnings.catch_warnings(record=True) as caught:
                    fn(*args)
                _WARM_WARNINGS.extend(caught)
            else:
                fn(*args)
        except Exception:   # noqa: BLE001 - the first run of the chunk reports the error
            pass


def _worker_setup() -> None:
    if not _SET_UP[0]:
        _SET_UP[0] = True
        limit_worker_threads()
        _jit.long_runs()        # a worker runs many cases: the compiled kernels pay (ROTARYDRYER_JIT=auto)


def _init_worker(warm) -> None:
    """Initializer of a local worker process: one BLAS thread, the young objects collected in larger batches (a
    worker runs many cases, each making many short-lived objects: 2-4 % of a Sobol run; a process of the pool only,
    not a Dask worker, which other work may share), then the warm-ups (nothing to do when the process was forked
    from a warm parent)."""
    _worker_setup()
    raise_gc_threshold()
    # a Ctrl-C reaches the whole process group: the process that made the batch stops it (and these workers), keeping
    # what finished; a worker that raised KeyboardInterrupt itself broke the pool under it (found by an acceptance
    # check: tracebacks, and the finished runs lost)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _ensure_warm(warm, in_worker=True)


def worker_info(_items=None) -> list:
    """``[(pid, warm-ups run in this process)]`` for each item (a chunk function for tests)."""
    return [(os.getpid(), _WARM_RUNS[0]) for _ in (_items or [None])]


class _Reported:
    """A chunk's results from a worker process with the warnings its runs raised there: (text, category, file,
    line, module) each, shown by the process that made the batch (`_shown`) as its own runs' warnings are."""

    __slots__ = ("results", "warnings")

    def __init__(self, results: list, caught: list):
        self.results = results
        self.warnings = [_portable(w) for w in caught]

    def __getstate__(self):
        return (self.results, self.warnings)

    def __setstate__(self, state):
        self.results, self.warnings = state


def _portable(w) -> tuple:
    """(text, category, file, line, module name) of a caught warning; a category that does not pickle becomes
    UserWarning. The module (for a filter's ``module=``) is the loaded module of the warning's file."""
    category = w.category
    try:
        pickle.dumps(category)
    except Exception:       # noqa: BLE001 - a class made at run time: its text still says what happened
        category = UserWarning
    filename = str(w.filename)
    return (str(w.message), category, filename, int(w.lineno or 0), _module_of(filename))


_MODULE_OF: dict = {}


def _module_of(filename: str) -> Optional[str]:
    """The name of the loaded module whose file is ``filename`` (None: not found; Python then takes the file name)."""
    name = _MODULE_OF.get(filename)
    if name is None and filename not in _MODULE_OF:
        for mod_name, mod in list(sys.modules.items()):
            if getattr(mod, "__file__", None) == filename:
                name = mod_name
                break
        _MODULE_OF[filename] = name
    return name


def _shown(out, registry: dict):
    """The results of a chunk; the warnings a worker caught (`_Reported`) are raised here, in the process that made
    the batch, where its user sees them as those of a serial run: its own warning filters (by module too) and
    printer (the command's one line per text, with the count of those alike), not a worker's stderr (a Dask worker
    printed each with its source line, a forked worker with its own count; found by an acceptance check).
    ``registry``: the batch's, so that a warning the filters show once per place is shown once per batch, not once
    per chunk."""
    if not isinstance(out, _Reported):
        return out
    for text, category, filename, lineno, module in out.warnings:
        warnings.warn_explicit(text, category, filename, lineno, module=module, registry=registry)
    return out.results


def check_scheduler(address, option: str = "--scheduler") -> Optional[str]:
    """A Dask scheduler address the commands support, ``tcp://HOST:PORT`` or ``tls://HOST:PORT``
    (``HOST:PORT`` means tcp), returned as given; ``None`` passes. Else a one-line ``ValueError``
    naming the option and the value."""
    if address is None:
        return None
    a = str(address).strip()
    form = "expected tcp://HOST:PORT or tls://HOST:PORT (PORT 1-65535), e.g. tcp://10.0.0.5:8786"
    scheme, sep, rest = a.partition("://")
    if not sep:
        scheme, rest = "tcp", a
    if scheme.lower() == "inproc":     # a scheduler in this process (LocalCluster(processes=False))
        if not rest.strip("/"):
            raise ValueError(f"{option} = {a!r} is not a scheduler address: inproc:// needs the address "
                             f"of a scheduler in this process; {form}")
        return a
    if scheme.lower() not in ("tcp", "tls"):
        raise ValueError(f"{option} = {a!r}: the protocol {scheme + '://'!r} is not supported; {form}")
    host, colon, port = rest.rstrip("/").rpartition(":")
    host = host.strip("[]")
    if not colon or not host or any(c.isspace() for c in host) or "/" in host:
        raise ValueError(f"{option} = {a!r} is not a scheduler address; {form}")
    if not port.isdigit() or not 1 <= int(port) <= 65535:
        raise ValueError(f"{option} = {a!r}: port {port!r} is outside the allowed range 1-65535; {form}")
    return a


def _check_sends(fn) -> None:
    """Refuse up front a chunk function that cannot reach the local pool's workers (it is pickled by reference): a
    lambda or a function defined inside another made every item a RunFailure "Can't pickle local object" (found by
    an acceptance check)."""
    try:
        pickle.dumps(fn, protocol=pickle.HIGHEST_PROTOCOL)
    except Exception as exc:        # noqa: BLE001 - pickle raises several kinds
        name = getattr(fn, "__qualname__", repr(fn))
        raise ValueError(f"fn = {name} cannot be sent to worker processes ({one_line(exc)}): define it at the top "
                         "level of a module (or run serially)") from None


def _run_chunk(fn, items, args, warm, origin: int):
    """Run one chunk where it landed: worker set-up (not in the process that made the batch),
    warm-ups, then ``fn(items, *args)``; a chunk that raises is run again one item at a time and
    each failing item becomes a `RunFailure`. In a worker process the warnings of the runs come back
    with the results (`_Reported`)."""
    if os.getpid() == origin:
        return _chunk_results(fn, items, args)
    _worker_setup()
    _ensure_warm(warm, in_worker=True)
    with warnings.catch_warnings(record=True) as caught:
        out = _chunk_results(fn, items, args)
    early, _WARM_WARNINGS[:] = list(_WARM_WARNINGS), []
    return _Reported(out, early + caught)


def _chunk_results(fn, items, args) -> list:
    items = list(items)
    try:
        out = list(fn(items, *args))
        if len(out) != len(items):
            raise RuntimeError(f"{getattr(fn, '__name__', fn)} returned {len(out)} results for {len(items)} items")
        return out
    except Exception as exc:    # noqa: BLE001 - one bad run never ends the batch
        if len(items) == 1:
            return [RunFailure(one_line(exc))]
    res = []
    for item in items:
        try:
            one = list(fn([item], *args))
            res.append(one[0] if len(one) == 1 else RunFailure(f"{len(one)} results for one item"))
        except Exception as exc:    # noqa: BLE001
            res.append(RunFailure(one_line(exc)))
    return res


def _each(items, fn, *args):
    """Chunk function of `Executor.map`: ``fn(item, *args)`` for each item, a `RunFailure` for one
    that raises."""
    out = []
    for item in items:
        try:
            out.append(fn(item, *args))
        except Exception as exc:    # noqa: BLE001 - one bad run never ends the batch
            out.append(RunFailure(one_line(exc)))
    return out


class _Box:
    """An opaque holder: Dask does not look inside it for tasks (it would walk a list of dicts)."""

    __slots__ = ("value",)

    def __init__(self, value):
        self.value = value

    def __getstate__(self):
        return (self.value,)        # never a false state (pickle would skip __setstate__)

    def __setstate__(self, state):
        self.value = state[0]


def _run_boxed(box: _Box):
    return _run_chunk(*box.value)


# ------------------------------------------------------------------------------------ long-lived resources
_LOCK = threading.RLock()
_POOL: dict = {}            # "key": (workers, start method), "pool": ProcessPoolExecutor
_DASK: dict = {}            # key -> (client, cluster or None)


def _pool_context():
    """The local pool's start method and its multiprocessing context: ``$ROTARYDRYER_WORKER_START`` where it
    names one this platform has, else fork on Linux from a process with one thread, else spawn."""
    # imported here, where a pool is made: not a cost of every command that imports this module
    import multiprocessing

    chosen = os.environ.get(START_METHOD_ENV, "").strip().lower()
    if not (chosen in ("fork", "spawn", "forkserver") and chosen in multiprocessing.get_all_start_methods()):
        # fork: workers inherit the warm parent (safe: no other thread holds a lock)
        chosen = "fork" if sys.platform.startswith("linux") and threading.active_count() == 1 else "spawn"
    return chosen, multiprocessing.get_context(chosen)


def _local_pool(workers: int, warm) -> concurrent.futures.ProcessPoolExecutor:
    """The process's pool of ``workers`` long-lived workers (made on first use, kept for later calls;
    a pool of another size, or a broken one, is closed first)."""
    with _LOCK:
        pool = _POOL.get("pool")
        if pool is None or _POOL["key"][0] != workers or getattr(pool, "_broken", False):
            _close_local()
            method, context = _pool_context()
            pool = concurrent.futures.ProcessPoolExecutor(max_workers=workers, mp_context=context,
                                                          initializer=_init_worker, initargs=(tuple(warm or ()),))
            _POOL.update(key=(workers, method), pool=pool)
        if _POOL["key"][1] == "fork" and not getattr(pool, "_processes", None):
            # the workers, forked at the first chunk, inherit this warm process: its warm-up uses the
            # compiled kernels the workers will use (loaded once here, not once per worker)
            _jit.long_runs()
            _ensure_warm(warm)
        return pool


@contextlib.contextmanager
def _sigint_handler(handler):
    """SIGINT handled by ``handler`` inside, the handler before it restored after; in the main thread only (elsewhere
    nothing changes), and nothing changes where SIGINT is ignored already."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.getsignal(signal.SIGINT)
    if previous in (signal.SIG_IGN, None, handler):     # ignored, or the same handler's block around this one
        yield
        return
    signal.signal(signal.SIGINT, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _first_interrupt(signum, frame):
    """A SIGINT handler: KeyboardInterrupt, and the next interrupts ignored (until `_sigint_handler` restores)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    raise KeyboardInterrupt


@contextlib.contextmanager
def _interrupt_noted(noted: list):
    """Inside: a SIGINT is appended to ``noted`` (the next ones ignored) instead of raising KeyboardInterrupt where
    the main thread happens to be, for a loop that checks ``noted`` where it is safe to stop. An exception raised by
    a signal inside `concurrent.futures.wait` can leave a future's lock held (it takes them one by one): the pool's
    own thread then waited on it for ever and so did the interrupted command (a Ctrl-C on ``sweep --workers 2``
    hung in one CI run of many). On leaving after an interrupt, SIGINT stays ignored where the handler before was
    `_first_interrupt` (the command's block ignores the next ones until it ends), else the handler before is back.
    A signal noted that the block did not act on is raised as KeyboardInterrupt as it ends. In the main thread only,
    and nothing changes where SIGINT is ignored already."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.getsignal(signal.SIGINT)
    if previous in (signal.SIG_IGN, None):
        yield
        return

    def note(signum, frame):
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        noted.append(signum)

    signal.signal(signal.SIGINT, note)
    try:
        yield
    finally:
        ignore = noted and previous is _first_interrupt
        signal.signal(signal.SIGINT, signal.SIG_IGN if ignore else previous)
    if noted:       # noted after the block's last look (its work done): the interrupt is still the caller's
        raise KeyboardInterrupt


def stop_on_first_interrupt():
    """Inside: the first SIGINT raises KeyboardInterrupt and the next ones are ignored until the block ends (a
    command around a whole batch and the saving of what finished; a block inside it changes nothing)."""
    return _sigint_handler(_first_interrupt)


def _close_local(kill: bool = False) -> None:
    with _LOCK:
        pool = _POOL.pop("pool", None)
        _POOL.pop("key", None)
    if pool is None:
        return
    if kill:        # an interrupted batch: do not wait for the chunks that are running
        for proc in list(getattr(pool, "_processes", {}).values()):
            try:
                proc.terminate()
            except Exception:   # noqa: BLE001 - already gone
                pass
        # the pool's thread finds its workers gone, fails what is left and ends: waited for, so that nothing of it
        # runs on at the interpreter's exit (an OSError traceback from its wake-up pipe)
        pool.shutdown(wait=True)
        return
    pool.shutdown(wait=True, cancel_futures=True)


def _dask_client(scheduler: Optional[str], n_local: Optional[int]):
    """A Dask client of the scheduler at ``scheduler`` or of a LocalCluster of ``n_local`` workers,
    made once per process (closed at exit). ImportError when Dask is not installed; ValueError
    naming the option when the scheduler cannot be reached."""
    key = ("scheduler", scheduler) if scheduler else ("local", n_local)
    with _LOCK:
        held = _DASK.get(key)
        if held is not None and getattr(held[0], "status", "") == "running":
            return held[0]
        try:
            from dask.distributed import Client, LocalCluster  # optional: only when a cluster is asked for
        except ImportError as exc:
            what = "--scheduler" if scheduler else "--cluster"
            raise ImportError(f"{what} needs dask.distributed: pip install 'dask[distributed]'") from exc
        cluster = None
        if scheduler:
            try:
                client = Client(scheduler, timeout=f"{CONNECT_TIMEOUT_S:g}s", set_as_default=False)
            except (OSError, TimeoutError) as exc:
                raise ValueError(f"--scheduler = {scheduler!r}: no Dask scheduler answered within "
                                 f"{CONNECT_TIMEOUT_S:g} s ({one_line(exc)})") from None
            except (TypeError, ValueError) as exc:
                if not scheduler.lower().startswith("tls://"):
                    raise
                # Dask's TLS connector without certificates: "TLS expects a `ssl_context` argument ... Instead got
                # None", which read as an internal error (found by an acceptance check)
                raise ValueError(f"--scheduler = {scheduler!r}: a tls:// scheduler needs this client's TLS "
                                 "certificates in the Dask configuration (distributed.comm.tls.ca-file, "
                                 "distributed.comm.tls.client.cert and .key, e.g. in ~/.config/dask/distributed.yaml "
                                 f"or DASK_DISTRIBUTED__COMM__TLS__CA_FILE) ({one_line(exc)})") from None
        else:
            import dask  # optional: only when a cluster is asked for

            try:
                # the workers' statistical profiler samples every thread's stack every 10 ms (a few % of the runs)
                # the scheduler's HTTP server (health and metrics routes, even without a dashboard) moves off a taken
                # port 8787 with a warning that read like a user error (found by fuzzing)
                with dask.config.set({"distributed.worker.profile.enabled": False}), warnings.catch_warnings():
                    warnings.filterwarnings("ignore", message=r"Port \d+ is already in use")
                    cluster = LocalCluster(n_workers=int(n_local or 1), threads_per_worker=1, processes=True,
                                           dashboard_address=None, preload=["rotarydryer._dask_worker"])
            except (OSError, RuntimeError) as exc:
                raise ValueError(f"--cluster = 'local:{n_local}': the Dask LocalCluster did not start "
                                 f"({one_line(exc)})") from None
            client = Client(cluster, set_as_default=False)
        if not str(scheduler or "").startswith("inproc://"):    # a scheduler in this process belongs to its caller
            _DASK[key] = (client, cluster)
        return client


def _close_dask(key) -> None:
    """Close the Dask client and LocalCluster kept under ``key`` after an interrupted batch, at once: the workers
    running a chunk are killed, not waited for, and the closing's own log lines (a worker "still alive ... killing",
    a heartbeat from a worker the scheduler forgot) are left out (the command has said what happened)."""
    import logging

    with _LOCK:
        held = _DASK.pop(key, None)
    if held is None:
        return
    client, cluster = held
    log = logging.getLogger("distributed")
    level = log.level
    log.setLevel(logging.CRITICAL)
    try:
        for thing, kw in ((client, {}), (cluster, {"timeout": 2})):
            if thing is not None:
                with contextlib.suppress(Exception):
                    thing.close(**kw)
    finally:
        log.setLevel(level)


def _release(client) -> None:
    """Close ``client`` unless it is one of the kept ones (a client of an in-process scheduler)."""
    if all(client is not held[0] for held in _DASK.values()):
        client.close()


def shutdown_all() -> None:
    """Close the local pool and the Dask clients and clusters this process made (at exit)."""
    _close_local()
    with _LOCK:
        held = list(_DASK.values())
        _DASK.clear()
    for client, cluster in held:
        for thing in (client, cluster):
            if thing is not None:
                try:
                    thing.close()
                except Exception:   # noqa: BLE001 - closing at exit: nothing to report to
                    pass


atexit.register(shutdown_all)


# ------------------------------------------------------------------------------------ the executor
class Executor:
    """Runs a batch of items in chunks: serially, on warm local workers, or on a Dask cluster.

    Parameters
    ----------
    backend : {"serial", "local", "dask"}, optional
        Default: ``"dask"`` with ``scheduler`` or ``cluster``, ``"local"`` with ``workers`` > 1,
        else ``"serial"``.
    workers : int
        Local worker processes (``"local"``).
    scheduler : str, optional
        Address of a running Dask scheduler, e.g. ``tcp://10.0.0.5:8786``.
    cluster : str, optional
        ``"local:N"``: a Dask LocalCluster of N single-threaded worker processes on this machine.

    Pools, clients and clusters are kept for later calls in the process (closed at exit);
    `close` leaves them, `shutdown_all` closes them.
    """

    def __init__(self, backend: Optional[str] = None, *, workers: int = 1, scheduler: Optional[str] = None,
                 cluster: Optional[str] = None):
        if scheduler and cluster:
            raise ValueError("give --scheduler or --cluster, not both (--cluster local:N makes a cluster, "
                             "--scheduler joins a running one)")
        # a whole number of any integer type (NumPy's too); a fraction or a text is not one (np.int64(2), 2.0 and
        # '2' were all "outside the allowed range [1, 256]"; found by an acceptance check)
        if isinstance(workers, bool) or not isinstance(workers, numbers.Integral):
            raise ValueError(f"--workers = {workers!r} is not a whole number (allowed range [1, {MAX_LOCAL_WORKERS}])")
        workers = int(workers)
        if not 1 <= workers <= MAX_LOCAL_WORKERS:
            raise ValueError(f"--workers = {workers!r} is outside the allowed range [1, {MAX_LOCAL_WORKERS}]")
        if isinstance(scheduler, str) and not scheduler.strip():
            scheduler = None            # no scheduler (as before)
        if scheduler is not None and not (isinstance(scheduler, str) and "://" in scheduler):
            # no address at all (a number, a word), refused here, not by Dask after its wait; an address with a
            # protocol (tcp://host without a port, ws://, ucx://) is Dask's to reach
            scheduler = check_scheduler(scheduler)
        self.cluster_workers: Optional[int] = parse_cluster(cluster) if cluster else None
        if backend is None:
            backend = "dask" if (scheduler or cluster) else ("local" if workers > 1 else "serial")
        if backend not in BACKENDS:
            raise ValueError(f"backend = {backend!r} is not one of {', '.join(BACKENDS)}")
        if backend == "dask" and not (scheduler or cluster):
            raise ValueError("backend 'dask' needs --scheduler ADDRESS or --cluster local:N")
        self.backend: str = backend
        self.workers: int = int(workers)
        self.scheduler: Optional[str] = scheduler
        self.cluster: Optional[str] = cluster

    def __repr__(self):
        return f"<Executor {self.describe()}>"

    def describe(self) -> str:
        """In words: ``serial``, ``2 local worker processes``, ``Dask cluster tcp://... ``."""
        if self.backend == "serial":
            return "serial"
        if self.backend == "local":
            return f"{self.workers} local worker processes"
        return f"Dask scheduler {self.scheduler}" if self.scheduler else f"Dask LocalCluster of {self.cluster_workers} workers"

    @property
    def parallel(self) -> bool:
        return self.backend != "serial"

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def close(self) -> None:
        """Nothing to release: pools and clusters are kept for the next call (`shutdown_all` closes them)."""

    def connect(self, warm=()) -> None:
        """Start the pool, or reach the scheduler / start the LocalCluster, now: a front end calls
        this while it checks its options, so an unreachable scheduler is a one-line error (ValueError
        naming the option; ImportError without Dask) before anything runs or is written."""
        if self.backend == "local":
            _local_pool(self.workers, warm)
        elif self.backend == "dask":
            _release(_dask_client(self.scheduler, self.cluster_workers))

    def independent_chunks(self, n: int) -> list[slice]:
        """Chunks of ``n`` items whose results do not depend on the chunking (each item computed on its
        own, e.g. from a cold start): one chunk serially, two per worker on the local pool (dynamic
        balance at little dispatch), `TARGET_CHUNKS` on Dask (whose worker count may change)."""
        if self.backend == "serial":
            return split(n, chunks=1)
        return split(n, chunks=2 * self.workers if self.backend == "local" else TARGET_CHUNKS)

    # ------------------------------------------------------------------ batches
    def map_chunks(self, fn: Callable, items: Sequence, *, chunks=None, args: tuple = (), warm=(),
                   progress: Optional[Callable[[int], Any]] = None, results: Optional[list] = None) -> list:
        """``fn(chunk_items, *args)`` over the chunks of ``items``; one result per item, in the order
        of ``items``.

        ``fn`` is a top-level function (it pickles) returning one result per item of its chunk; it
        runs the chunk in order, e.g. each item warm-started from the one before it. ``chunks``: a
        list of slices, a chunk size (int), or None (`split` of ``len(items)``). ``warm``: ``(fn,
        args)`` pairs each worker runs once before its first chunk (imports, kernels, a model built
        and solved). ``progress(n)`` after each chunk with its item count; ``results`` (a list of
        ``len(items)``) is filled as chunks finish. An item whose run raised is a `RunFailure`."""
        items = list(items)
        n = len(items)
        if results is None:
            results = [None] * n
        elif len(results) != n:
            raise ValueError(f"results has {len(results)} places for {n} items")
        if isinstance(chunks, numbers.Integral) and not isinstance(chunks, bool):
            size = max(1, int(chunks))
            slices = [slice(i, min(n, i + size)) for i in range(0, n, size)]
        elif chunks is None:
            slices = split(n)
        else:
            try:
                given = None if isinstance(chunks, (str, bytes, dict)) else list(chunks)
            except TypeError:
                given = None
            if given is None or not all(isinstance(sl, slice) for sl in given):
                raise ValueError(f"chunks = {chunks!r}: expected a chunk size (a whole number), a list of slices of "
                                 "the items, or None (the default split)")
            slices = given
        tick = progress or (lambda k: None)
        warm = tuple(warm or ())
        origin = os.getpid()
        _jit.long_runs()        # a batch of runs here or in forked workers: the compiled kernels pay

        registry: dict = {}

        def store(sl: slice, out) -> None:
            results[sl] = _shown(out, registry)
            tick(sl.stop - sl.start)

        if self.backend == "serial" or (self.backend == "local" and len(slices) <= 1):
            for sl in slices:
                store(sl, _run_chunk(fn, items[sl], args, (), origin))
            return results
        if self.backend == "local":
            # the pool pickles the function by reference (Dask's cloudpickle sends a lambda by value)
            _check_sends(args[0] if fn is _each and args else fn)
            self._map_local(fn, items, slices, args, warm, origin, store)
        else:
            self._map_dask(fn, items, slices, args, warm, origin, store)
        return results

    def map(self, fn: Callable, items: Sequence, *, args: tuple = (), chunks=None, warm=(),
            progress: Optional[Callable[[int], Any]] = None, results: Optional[list] = None) -> list:
        """``fn(item, *args)`` for each item (a top-level function), in chunks as `map_chunks`; an
        item that raises is a `RunFailure` in the results."""
        return self.map_chunks(_each, items, chunks=chunks, args=(fn, *args), warm=warm, progress=progress,
                               results=results)

    def _map_local(self, fn, items, slices, args, warm, origin, store) -> None:
        pool = _local_pool(self.workers, warm)
        futures = {}
        # the workers fork at the first submission: the parent's objects are left out of their garbage
        # collections (gc.freeze, as the gc module's documentation advises before a fork), whose passes would
        # otherwise write to every inherited object and copy its memory page into each worker
        forking = _POOL.get("key", (0, ""))[1] == "fork" and not getattr(pool, "_processes", None)
        noted: list = []        # a SIGINT, noted by the handler and acted on here (`_interrupt_noted`)
        with _interrupt_noted(noted):
            try:
                if forking:
                    gc.freeze()
                try:
                    for sl in slices:
                        futures[pool.submit(_run_chunk, fn, items[sl], args, warm, origin)] = sl
                finally:
                    if forking:
                        gc.unfreeze()
                pending = set(futures)
                while pending:
                    if noted:
                        raise KeyboardInterrupt
                    done, pending = concurrent.futures.wait(pending, timeout=INTERRUPT_POLL_S,
                                                            return_when=concurrent.futures.FIRST_COMPLETED)
                    for f in done:
                        sl = futures[f]
                        try:
                            out = f.result()
                        except Exception as exc:    # noqa: BLE001 - a worker died (BrokenProcessPool) or did not pickle
                            out = [RunFailure(f"worker process failed: {one_line(exc)}")] * (sl.stop - sl.start)
                        store(sl, out)
            except KeyboardInterrupt:
                # later interrupts are ignored until the workers are stopped (a second Ctrl-C, or `timeout`
                # signalling the process and then its group, had cut the stop short: the workers ran on); no future
                # is cancelled here: the pool's own thread fails every one left once its workers are gone, and a
                # future cancelled beside it made that thread fail (InvalidStateError, Python 3.11)
                _close_local(kill=True)
                raise
        if getattr(pool, "_broken", False):
            _close_local()

    def _map_dask(self, fn, items, slices, args, warm, origin, store) -> None:
        from dask.distributed import as_completed  # optional: only when a cluster is asked for

        client = _dask_client(self.scheduler, self.cluster_workers)
        tag = f"rotarydryer-{getattr(fn, '__name__', 'run')}-{uuid.uuid4().hex[:12]}"
        futures = {}
        try:
            boxes = [_Box((fn, items[sl], args, warm, origin)) for sl in slices]
            submitted = client.map(_run_boxed, boxes, key=[f"{tag}-{i}" for i in range(len(slices))])
            futures = dict(zip(submitted, slices))        # one message to the scheduler for the batch
            for f in as_completed(list(futures), loop=client.loop):
                sl = futures[f]
                try:
                    out = f.result()
                except Exception as exc:    # noqa: BLE001 - a worker died (KilledWorker), a result did not pickle
                    out = [RunFailure(f"Dask task failed: {one_line(exc)}")] * (sl.stop - sl.start)
                store(sl, out)
        except KeyboardInterrupt:
            if self.scheduler:
                client.cancel(list(futures))
            else:       # a LocalCluster made here: closed now (its workers in the middle of a chunk are stopped)
                _close_dask(("local", self.cluster_workers))
            raise
        finally:
            _release(client)

