"""Issue 32 item 4: the CPU of one-off commands against ``python -c "import numpy, scipy"``, two trees alternated.

CPU = user + system of the whole child process (``resource.getrusage(RUSAGE_CHILDREN)``), the median of
``REPEATS`` runs; each round runs the yardstick, then each command with the "before" tree and the "after" tree
(``PYTHONPATH``), so that the ratios of one round share the machine's load. Byte-compiled files must exist in both
trees (``python -m compileall -q SRC``): a module compiled from source on every run costs a one-off command tens of
milliseconds. Also the in-process CPU of loading the MMG drum's three geometry tables from the disk cache.

    python -m compileall -q /tmp/before/src src
    python benchmarks/bench_issue32_startup.py /tmp/before/src src
"""

import os
import resource
import statistics
import subprocess
import sys

REPEATS = 9
ROUNDS = 3
COMMANDS = {
    "simulate lee2008_invicta --json": ["-m", "rotarydryer", "simulate", "lee2008_invicta", "--json"],
    "simulate ajayi2011_mmg --set operating.test=4 --json": ["-m", "rotarydryer", "simulate", "ajayi2011_mmg",
                                                             "--set", "operating.test=4", "--json"],
}
GEOMETRY = """
import resource
import rotarydryer.geometry.tabulated as tb
from rotarydryer import Simulation
spent = [0.0]
load = tb._load_disk
def cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime
def timed(*a, **k):
    t = cpu(); out = load(*a, **k); spent[0] += cpu() - t; return out
tb._load_disk = timed
Simulation("ajayi2011_mmg", {"operating.test": 4}).transport_steady_state()
print(spent[0])
"""


def _cpu(args, src):
    env = dict(os.environ, PYTHONPATH=os.path.abspath(src)) if src else dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    vals = []
    for _ in range(REPEATS):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run([sys.executable, *args], env=env, check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        vals.append(r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
    return statistics.median(vals)


def _geometry(src):
    env = dict(os.environ, PYTHONPATH=os.path.abspath(src))
    out = [float(subprocess.run([sys.executable, "-c", GEOMETRY], env=env, check=True, capture_output=True,
                                text=True).stdout.split()[-1]) for _ in range(5)]
    return statistics.median(out)


def main(before, after):
    for r in range(ROUNDS):
        load = os.getloadavg()[0]
        base = _cpu(["-c", "import numpy, scipy"], None)
        print(f"round {r + 1} (load {load:.2f}): import numpy, scipy {base:.3f} s")
        for name, args in COMMANDS.items():
            b, a = _cpu(args, before), _cpu(args, after)
            print(f"  {name}: before {b:.3f} s ({b / base:.2f}x), after {a:.3f} s ({a / base:.2f}x)")
        gb, ga = _geometry(before), _geometry(after)
        print(f"  MMG geometry tables from the disk cache: before {1e3 * gb:.0f} ms, after {1e3 * ga:.0f} ms")


if __name__ == "__main__":
    main(*sys.argv[1:3])
