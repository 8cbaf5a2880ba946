"""Before/after in one run (issue 12): MMG test 4 coupled steady state and 2 h of dynamics after a
10 % feed step, for the code at a given commit and for this tree, each in its own interpreter.

Run: git worktree add /tmp/oldtree 92b2a6a && python benchmarks/bench_issue12_before_after.py /tmp/oldtree/src
"""
import json
import os
import subprocess
import sys

code = r'''
import time, json, numpy as np, sys
from rotarydryer.cases import load_case
try:
    from rotarydryer.simulation import build_thermal_dryer
except ImportError:
    from rotarydryer.thermal.dryer import build_thermal_dryer
from rotarydryer.thermal.studies import perturbed
out = {}
for mode in ("physical", "ajayi2011"):
    d = build_thermal_dryer(load_case("ajayi2011_mmg", {"operating.test": 4, "thermal.mode": mode}))
    ts = []
    for _ in range(5):
        t = time.perf_counter(); ss = d.steady_state(); ts.append(time.perf_counter() - t)
    d2 = perturbed(d, solid_feed_rate=d.feed_rate * 1.1)
    td = []
    for _ in range(2):
        t = time.perf_counter(); d2.simulate(ss.state, 7200.0, t_eval=np.arange(0, 7201, 60.0)); td.append(time.perf_counter() - t)
    out[mode] = dict(unknowns=d.n, steady_s=min(ts), dynamics_s=min(td))
print(json.dumps(out))
'''
res = {}

here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src")
old = sys.argv[1] if len(sys.argv) > 1 else "/tmp/oldtree/src"
for label, path in (("before", old), ("after", here)):
    r = subprocess.run([sys.executable, "-c", code], env={**os.environ, "PYTHONPATH": path}, capture_output=True,
                       text=True)
    if r.returncode:
        print(label, r.stderr[-2000:])
        continue
    res[label] = json.loads(r.stdout.strip().splitlines()[-1])
print(json.dumps(res, indent=1))
