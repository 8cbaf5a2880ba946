"""Issue 31: a one-input target on MMG takes at most 15 coupled solves.

``rotarydryer target ajayi2011_mmg --find operating.feed_rate --such-that product_moisture_kg_kg<=0.12``
(the default bracket, 0.25x-4x the case's feed, whose top overfills the drum and is moved), and the
same with a given bracket [20, 40] kg/s: the number of coupled steady states, wall and CPU time.

Never a pass/fail test. Run: ``python benchmarks/bench_issue31_target.py`` (a Markdown table).
"""

from __future__ import annotations

import time
import warnings

from rotarydryer.studies.target import target


def timed(fn):
    w, c = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w, time.process_time() - c


def main():
    print("| target | bracket | steady states | feed (kg/s) | wall (s) | CPU (s) |")
    print("|---|---|---|---|---|---|")
    for bounds in (None, (20.0, 40.0)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res, wall, cpu = timed(lambda: target("ajayi2011_mmg", "operating.feed_rate",
                                                  "product_moisture_kg_kg<=0.12", bounds))
        shown = "default" if bounds is None else f"[{bounds[0]:g}, {bounds[1]:g}]"
        print(f"| moisture <= 0.12 | {shown} | {res.evaluations} | {res.value:.2f} | {wall:.2f} | {cpu:.2f} |")


if __name__ == "__main__":
    main()
