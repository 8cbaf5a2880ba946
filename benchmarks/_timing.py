"""Shared timing helper of the benchmark scripts."""

import time


def best(fn, *args, repeat=3):
    """Shortest wall time (s) of ``repeat`` calls of ``fn(*args)``."""
    out = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn(*args)
        out.append(time.perf_counter() - t)
    return min(out)


def best_result(fn, repeat=3, clock=time.perf_counter):
    """``(shortest time of repeat calls of fn(), the last call's result)``; ``clock``: wall time by
    default, ``time.process_time`` for CPU time on a shared machine."""
    out, ts = None, []
    for _ in range(repeat):
        t = clock()
        out = fn()
        ts.append(clock() - t)
    return min(ts), out
