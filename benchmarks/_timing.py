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
