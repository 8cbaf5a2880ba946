"""Thread oversubscription (issue 16 part 3): fits with the default BLAS threading against one thread.

The Lee Invicta 3-parameter fit and the Ajayi test-4 2-parameter fit (the same fits as
``bench_estimation.py``) are timed, alternately, (a) with the BLAS/OpenMP pools as the process
found them (OpenBLAS: one thread per core) and (b) inside :func:`rotarydryer._threads.single_threaded`.
Target: (a) at most 1.2x (b) -- met once the fit entry points run under ``single_threaded()``
(then (a) and (b) run the same code). ``--entry`` times (a) with ``fit_case_to_tracer`` wrapped
in ``single_threaded()`` as the proposed one-line change does.

Run: python benchmarks/bench_threads.py [--repeat 3] [--entry]
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_estimation import ajayi_fit, lee_fit  # noqa: E402

from rotarydryer._threads import single_threaded  # noqa: E402


def _best(fn, repeat, limit):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        if limit:
            with single_threaded():
                fn()
        else:
            fn()
        times.append(time.perf_counter() - t0)
    return min(times), times


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--entry", action="store_true",
                    help="wrap fit_case_to_tracer in single_threaded() (the proposed change) for (a)")
    args = ap.parse_args(argv)
    from threadpoolctl import threadpool_info

    if args.entry:
        import bench_estimation

        bench_estimation.fit_case_to_tracer = single_threaded()(bench_estimation.fit_case_to_tracer)
    pools = ", ".join(f"{i['internal_api']} {i['num_threads']} threads" for i in threadpool_info())
    print(f"# {datetime.date.today()} {platform.node()} {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} cores, Python {platform.python_version()}; pools: {pools}"
          + ("; fit entry wrapped in single_threaded()" if args.entry else ""))
    print("| fit | default threading | one thread | ratio |")
    print("|---|---|---|---|")
    for name, fn in (("Lee Invicta 3-parameter", lee_fit), ("Ajayi test 4 2-parameter", ajayi_fit)):
        fn()  # warm caches (case files, geometry tables, imports)
        a, b = [], []
        for _ in range(args.repeat):       # alternate so that load from other processes hits both
            a.append(_best(fn, 1, False)[0])
            b.append(_best(fn, 1, True)[0])
        print(f"| {name} | {min(a):.2f} s | {min(b):.2f} s | {min(a) / min(b):.2f} |", flush=True)


if __name__ == "__main__":
    main()
