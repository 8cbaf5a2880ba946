"""One BLAS/OpenMP thread for the project's own solves, fits and parallel runs (issue 16).

The coupled steady states and fits work on small dense and sparse matrices (a few hundred
unknowns): a multithreaded BLAS spends more on waking and synchronising its threads than on
the arithmetic, and a process pool or a Dask worker with one BLAS pool per process oversubscribes
the cores. Measured on a 2-core machine, fits ran 4.6x slower with the default OpenBLAS threading
than with one thread (``benchmarks/bench_threads.py``).

>>> from rotarydryer._threads import single_threaded
>>> with single_threaded():          # BLAS/OpenMP pools limited to 1 thread inside
...     pass
>>> @single_threaded()
... def solve():                     # or as a decorator
...     pass

The limits are process-wide while active (threadpoolctl changes the pools of the loaded native
libraries) and the previous limits come back on exit. ``threadpoolctl`` is a dependency; if it
cannot be imported, `single_threaded` does nothing (the results are the same, only slower).
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading

__all__ = ["single_threaded", "limit_worker_threads", "command_blas_threads", "THREAD_ENV_VARS", "BLAS_ENV_VARS"]

#: environment variables read by BLAS/OpenMP libraries when they load (set for worker processes)
THREAD_ENV_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
                   "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")

#: the BLAS libraries' own variables (OpenMP's left alone: a program a command starts, e.g. LIGGGHTS, keeps its threads)
BLAS_ENV_VARS = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS", "VECLIB_MAXIMUM_THREADS")

_state = threading.local()
_worker_limits = None   # the process-wide limits of limit_worker_threads (kept alive on purpose)
_CONTROLLER: list = [None, -1]      # threadpoolctl's controller of the loaded libraries, len(sys.modules) then
_LOADED_SINGLE = [False]    # command_blas_threads found no BLAS loaded and every BLAS variable at 1


def _controller():
    """threadpoolctl's controller of the native libraries loaded in this process, kept while no module has been
    imported since it was made (a new library comes with an import: an extension module or one that loads it).
    Making one inspects every loaded library, 1.3-1.4 ms; a limit through a kept one costs 0.02 ms: a sweep
    entered one per point, 5 % of an MMG point's CPU. None when threadpoolctl cannot be imported."""
    n = len(sys.modules)
    if _CONTROLLER[1] != n:
        try:
            from threadpoolctl import ThreadpoolController
        except ImportError:          # pragma: no cover - a declared dependency
            return None
        _CONTROLLER[:] = [ThreadpoolController(), len(sys.modules)]
    return _CONTROLLER[0]


def _depth() -> int:
    return getattr(_state, "depth", 0)


class single_threaded(contextlib.ContextDecorator):
    """Context manager and decorator: BLAS/OpenMP thread pools limited to ``limits`` (1) threads.

    Re-entrant and cheap when nested: only the outermost level calls threadpoolctl, through a
    controller kept until a module is imported (`_controller`: it inspects the loaded libraries
    once, about a millisecond); inner levels are no-ops.
    """

    def __init__(self, limits: int = 1):
        if isinstance(limits, bool) or not isinstance(limits, int) or limits < 1:
            raise ValueError(f"limits = {limits!r} is outside the allowed range: an integer >= 1")
        self.limits = limits
        self._ctx = None
        self._outer = False

    def _recreate_cm(self):              # a fresh instance per decorated call (recursion, threads)
        return type(self)(self.limits)

    def __enter__(self):
        self._outer = _depth() == 0
        _state.depth = _depth() + 1
        if self._outer and not (self.limits == 1 and _LOADED_SINGLE[0]):
            controller = _controller()
            self._ctx = None if controller is None else controller.limit(limits=self.limits)
        return self

    def __exit__(self, *exc):
        _state.depth = max(_depth() - 1, 0)
        if self._outer and self._ctx is not None:
            self._ctx.restore_original_limits()
            self._ctx = None
        return False


def limit_worker_threads(limits: int = 1) -> None:
    """For the start of a worker process (process-pool initializer, Dask worker): limit the
    BLAS/OpenMP pools to ``limits`` threads for the rest of the process, both in the libraries
    already loaded (threadpoolctl) and, through the environment, in those loaded later."""
    global _worker_limits
    for var in THREAD_ENV_VARS:
        os.environ[var] = str(limits)
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:                  # pragma: no cover - a declared dependency
        return
    _worker_limits = threadpool_limits(limits=limits)


def command_blas_threads() -> None:
    """For a command-line process, before NumPy loads: one BLAS thread, unless the user's environment
    names a number (kept). The project's solves run on one thread anyway (`single_threaded`); a BLAS
    that starts its thread pool when it loads costs a one-off command its threads' start-up and
    spinning for nothing: ``rotarydryer simulate lee2008_invicta --json`` 0.89-0.97 s of CPU with the
    pool, 0.68-0.73 s without (2 cores, OpenBLAS 0.3.31). When every BLAS variable is then 1 and NumPy
    has not loaded yet, each BLAS this process loads has one thread: `single_threaded` (one thread)
    then leaves threadpoolctl alone (its look at the loaded libraries cost a one-off command 6-10 ms). This
    covers the BLAS only: OpenMP's variable stays the user's (a program a command starts keeps its threads), and
    the project loads no OpenMP runtime (its compiled kernels are serial); one loaded by another library in a
    command process is not limited."""
    for var in BLAS_ENV_VARS:
        os.environ.setdefault(var, "1")
    _LOADED_SINGLE[0] = "numpy" not in sys.modules and all(os.environ.get(v) == "1" for v in BLAS_ENV_VARS)
