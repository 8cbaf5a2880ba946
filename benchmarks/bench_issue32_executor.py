"""Issue 32 item 1: one executor for many-run work; before/after in one run, same-run ratios.

1. ``rotarydryer sweep`` of 200 MMG points (test 4, 20 feed rates x 10 speeds), from a fresh
   process each time: ``--workers 1``, ``--workers 2``, a Dask LocalCluster of 2 single-threaded
   worker processes (after: ``--cluster local:2``, made by the command; both trees: ``--scheduler``
   on a cluster started beforehand by this script, its CPU counted). CPU = the command's process
   and its children (``resource.getrusage(RUSAGE_CHILDREN)``) plus, for ``--scheduler``, the
   cluster's processes (psutil); wall time; the machine load (``os.getloadavg``) before and after.
   The CSVs of the "after" backends are compared text for text.
2. The same 200 points from Python, ``run_sweep`` called twice in one process: the first call
   pays the workers' start-up, the second what long-lived workers cost (CPU of this process, its
   live and ended children; with ``--scheduler`` the cluster's CPU over both calls is shown apart).
3. A Sobol study of 8 inputs on the same model (``benchmarks/bench_sensitivity.py``'s inputs) with 2
   local workers, ``--sobol-samples`` base samples (x 10 runs); the time of 10^4 runs is projected
   linearly from it (wall x 10^4 / runs: the start-up is counted in full, so the projection is high).

"before" is a source tree of the commit the branch started from (``git archive BASE src``),
"after" this worktree's ``src``. Run from the worktree:

    git archive dd8422e src | tar -x -C /tmp/before && \\
        python benchmarks/bench_issue32_executor.py --before /tmp/before/src [--sobol-samples 128]

Never a pass/fail test: the machine is shared, so compare the ratios of one run.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
AFTER = HERE.parent / "src"
FEED = ",".join(f"{36 + 9 * i / 19:.3f}" for i in range(20))
SPEED = ",".join(f"{2.7 + 0.6 * i / 9:.3f}" for i in range(10))
SWEEP = ["sweep", "ajayi2011_mmg", "--set", "operating.test=4", "--grid", f"operating.feed_rate={FEED}",
         "--grid", f"operating.rpm={SPEED}", "-q"]


def set_speeds(n: int) -> None:
    """``n`` speeds instead of 10 (a sweep of 20 n points; the CLI table only)."""
    SWEEP[7] = "operating.rpm=" + ",".join(f"{2.7 + 0.6 * i / (n - 1):.4f}" for i in range(n))
CLUSTER = """
import sys, time
from dask.distributed import LocalCluster
cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
print(cluster.scheduler_address, flush=True)
sys.stdin.read()
cluster.close()
"""
LIBRARY = """
import json, os, resource, sys, time
import psutil
sys.path.insert(0, {bench!r})
from bench_issue32_executor import library_points
points = library_points()
mode, address = {mode!r}, {address!r}
after = {after!r}
if after:
    from rotarydryer.executor import Executor
    from rotarydryer.studies.sweep import run_sweep
    ex = {{"serial": Executor(), "local": Executor(workers=2), "dask": Executor(cluster="local:2"),
           "scheduler": Executor(scheduler=address)}}[mode]
    call = lambda: run_sweep("ajayi2011_mmg", points, executor=ex)
else:
    from rotarydryer.cli.sweep import run_sweep
    kw = {{"serial": dict(workers=1), "local": dict(workers=2), "scheduler": dict(scheduler=address)}}[mode]
    call = lambda: run_sweep("ajayi2011_mmg", points, **kw)
me = psutil.Process()

def cpu():
    live = 0.0
    for p in me.children(recursive=True):
        try:
            t = p.cpu_times()
            live += t.user + t.system
        except psutil.NoSuchProcess:
            pass
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + live + r.ru_utime + r.ru_stime

out = []
for _ in range(2):
    c, t = cpu(), time.perf_counter()
    rows = call()
    out.append(dict(wall=time.perf_counter() - t, cpu=cpu() - c, failed=sum(bool(r["error"]) for r in rows)))
print(json.dumps(out))
"""
SOBOL = """
import sys, time
sys.path.insert(0, {bench!r})
from bench_sensitivity import MMG_PARAMS
from rotarydryer.studies.sensitivity import sobol_study
t = time.perf_counter()
res = sobol_study("ajayi2011_mmg", MMG_PARAMS, {samples}, workers=2)
print(res.n_runs, res.n_failed, time.perf_counter() - t)
"""


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _tree_cpu(pid: int) -> float:
    import psutil

    try:
        proc = psutil.Process(pid)
        procs = [proc, *proc.children(recursive=True)]
    except psutil.NoSuchProcess:
        return 0.0
    total = 0.0
    for p in procs:
        try:
            t = p.cpu_times()
            total += t.user + t.system + t.children_user + t.children_system
        except psutil.NoSuchProcess:
            pass
    return total


def _env(src: Path) -> dict:
    return {**os.environ, "PYTHONPATH": str(src), "ROTARYDRYER_JIT": os.environ.get("ROTARYDRYER_JIT", "1")}


def run_cli(src: Path, args: list, extra_pid=None) -> dict:
    load0 = os.getloadavg()[0]
    cpu0, x0 = _children_cpu(), _tree_cpu(extra_pid) if extra_pid else 0.0
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "rotarydryer", *args], env=_env(src), capture_output=True, text=True)
    wall = time.perf_counter() - t0
    cpu = _children_cpu() - cpu0 + ((_tree_cpu(extra_pid) - x0) if extra_pid else 0.0)
    if proc.returncode not in (0, 1):
        raise RuntimeError(f"{args}: exit {proc.returncode}: {proc.stderr[-2000:]}")
    return dict(wall=wall, cpu=cpu, load=(load0, os.getloadavg()[0]), exit=proc.returncode)


class Cluster:
    """A LocalCluster of 2 worker processes in its own process (for --scheduler)."""

    def __init__(self, src: Path):
        self.proc = subprocess.Popen([sys.executable, "-c", CLUSTER], env=_env(src), stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        self.address = self.proc.stdout.readline().strip()

    def close(self):
        self.proc.stdin.close()
        self.proc.wait(timeout=60)


def sweep_table(before: Path, after: Path, out_dir: Path, repeat: int) -> tuple[list, dict]:
    rows, csvs = [], {}
    trees = [("before", before), ("after", after)]
    for _label, src in trees:        # numba caches and the first imports of each tree, not timed
        run_cli(src, ["sweep", "ajayi2011_mmg", "--set", "operating.test=4", "--grid", "operating.rpm=3,3.1", "-q"])
    clusters = {label: Cluster(src) for label, src in trees}
    try:
        for r in range(repeat):
            for label, src in trees:
                configs = [("--workers 1", ["--workers", "1"], None), ("--workers 2", ["--workers", "2"], None),
                           ("--scheduler (LocalCluster 2)", ["--scheduler", clusters[label].address],
                            clusters[label].proc.pid)]
                if label == "after":
                    configs.append(("--cluster local:2", ["--cluster", "local:2"], None))
                for name, extra, pid in configs:
                    csv = out_dir / f"{label}_{name.split()[0].strip('-')}_{extra[-1].replace(':', '')[-6:]}_{r}.csv"
                    m = run_cli(src, [*SWEEP, *extra, "-o", str(csv)], extra_pid=pid)
                    m.update(tree=label, config=name, repeat=r)
                    rows.append(m)
                    csvs[(label, name, r)] = csv.read_text()
                    print(f"# sweep {label} {name}: wall {m['wall']:.2f} s, CPU {m['cpu']:.2f} s, "
                          f"load {m['load'][0]:.2f}->{m['load'][1]:.2f}", file=sys.stderr, flush=True)
    finally:
        for c in clusters.values():
            c.close()
    return rows, csvs


def library_points() -> list:
    """The 200 points of the sweep as override dicts (the library calls)."""
    feed = [float(v) for v in FEED.split(",")]
    speed = [float(v) for v in SPEED.split(",")]
    return [{"operating.test": 4, "operating.feed_rate": f, "operating.rpm": n} for f in feed for n in speed]


def library_table(before: Path, after: Path) -> list:
    """Two calls of the 200-point sweep in one process: the first pays the workers' start-up, the
    second shows what long-lived workers cost per call (extra scheduler CPU counted as above)."""
    import json

    rows = []
    clusters = {"before": Cluster(before), "after": Cluster(after)}
    try:
        for label, src, modes in (("before", before, ("serial", "local", "scheduler")),
                                  ("after", after, ("serial", "local", "dask", "scheduler"))):
            for mode in modes:
                pid = clusters[label].proc.pid if mode == "scheduler" else None
                x0 = _tree_cpu(pid) if pid else 0.0
                code = LIBRARY.format(bench=str(HERE), mode=mode, address=clusters[label].address,
                                      after=label == "after")
                load0 = os.getloadavg()[0]
                proc = subprocess.run([sys.executable, "-c", code], env=_env(src), capture_output=True, text=True)
                if proc.returncode:
                    raise RuntimeError(proc.stderr[-2000:])
                calls = json.loads(proc.stdout.strip().splitlines()[-1])
                extra = (_tree_cpu(pid) - x0) if pid else 0.0     # the external cluster's CPU, both calls
                rows.append(dict(tree=label, mode=mode, calls=calls, cluster_cpu=extra,
                                 load=(load0, os.getloadavg()[0])))
                print(f"# library {label} {mode}: {calls} cluster CPU {extra:.2f}", file=sys.stderr, flush=True)
    finally:
        for c in clusters.values():
            c.close()
    return rows


def sobol_run(src: Path, samples: int) -> dict:
    load0 = os.getloadavg()[0]
    cpu0 = _children_cpu()
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", SOBOL.format(bench=str(HERE), samples=samples)], env=_env(src),
                          capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode:
        raise RuntimeError(proc.stderr[-2000:])
    n_runs, n_failed, study = proc.stdout.split()
    return dict(wall=wall, cpu=_children_cpu() - cpu0, runs=int(n_runs), failed=int(n_failed), study=float(study),
                load=(load0, os.getloadavg()[0]))


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--before", type=Path, required=True, help="src/ of the commit before (git archive BASE src)")
    ap.add_argument("--after", type=Path, default=AFTER)
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--sobol-samples", type=int, default=128)
    ap.add_argument("--skip", default="", help="comma list: sweep, library, sobol")
    ap.add_argument("--speeds", type=int, default=10, help="speeds of the CLI sweep (20 x speeds points)")
    a = ap.parse_args(argv)
    skip = set(filter(None, a.skip.split(",")))
    if a.speeds != 10:
        set_speeds(a.speeds)
    print(f"# {datetime.datetime.now():%Y-%m-%d %H:%M} {platform.node()} {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}; load at start {os.getloadavg()[0]:.2f}")
    if "sweep" not in skip:
        with tempfile.TemporaryDirectory() as tmp:
            rows, csvs = sweep_table(a.before, a.after, Path(tmp), a.repeat)
        print(f"\n## {20 * a.speeds}-point MMG sweep (`rotarydryer sweep`, fresh process each)\n")
        print("| tree | backend | wall s | CPU s | CPU / --workers 1 | wall speed-up vs --workers 1 | load before -> after |")
        print("|---|---|---|---|---|---|---|")
        for r in rows:
            ref = next(x for x in rows if x["tree"] == r["tree"] and x["repeat"] == r["repeat"]
                       and x["config"] == "--workers 1")
            print(f"| {r['tree']} | {r['config']} | {r['wall']:.2f} | {r['cpu']:.2f} | {r['cpu'] / ref['cpu']:.3f} | "
                  f"{ref['wall'] / r['wall']:.2f} | {r['load'][0]:.2f} -> {r['load'][1]:.2f} |")
        for r in range(a.repeat):
            after = {k[1]: v for k, v in csvs.items() if k[0] == "after" and k[2] == r}
            before = {k[1]: v for k, v in csvs.items() if k[0] == "before" and k[2] == r}
            same_after = len(set(after.values())) == 1
            same_before = len(set(before.values())) == 1
            print(f"\nCSV text identical across the backends: after {'yes' if same_after else 'NO'} "
                  f"({len(after)} backends); before {'yes' if same_before else 'no'} ({len(before)} backends)")
    if "library" not in skip:
        rows = library_table(a.before, a.after)
        print("\n## 200-point MMG sweep from Python, two calls in one process (`run_sweep`)\n")
        print("| tree | backend | 1st call wall s | 1st call CPU s | 2nd call wall s | 2nd call CPU s | "
              "2nd call CPU / serial | 2nd call speed-up vs serial | scheduler CPU (both calls) | load |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for r in rows:
            ref = next(x for x in rows if x["tree"] == r["tree"] and x["mode"] == "serial")["calls"][1]
            one, two = r["calls"]
            print(f"| {r['tree']} | {r['mode']} | {one['wall']:.2f} | {one['cpu']:.2f} | {two['wall']:.2f} | "
                  f"{two['cpu']:.2f} | {two['cpu'] / ref['cpu']:.3f} | {ref['wall'] / two['wall']:.2f} | "
                  f"{r['cluster_cpu']:.2f} | {r['load'][0]:.2f} -> {r['load'][1]:.2f} |", flush=True)
    if "sobol" not in skip:
        print(f"\n## Sobol study, 8 inputs, {a.sobol_samples} base samples, 2 local workers (one process each)\n")
        print("| tree | runs | failed | wall s | CPU s | CPU ms per run | projected 10^4 runs, wall s | load before -> after |")
        print("|---|---|---|---|---|---|---|---|")
        for label, src in (("before", a.before), ("after", a.after)):
            m = sobol_run(src, a.sobol_samples)
            print(f"| {label} | {m['runs']} | {m['failed']} | {m['wall']:.1f} | {m['cpu']:.1f} | "
                  f"{1e3 * m['cpu'] / m['runs']:.1f} | {m['wall'] * 1e4 / m['runs']:.0f} | "
                  f"{m['load'][0]:.2f} -> {m['load'][1]:.2f} |", flush=True)


if __name__ == "__main__":
    main()
