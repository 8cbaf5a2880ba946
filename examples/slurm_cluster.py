"""A Dask cluster on Slurm (or PBS) for rotarydryer's many-run commands, with dask-jobqueue.

    python examples/slurm_cluster.py --jobs 4 --cores 8 --memory 16GB --queue compute
    python examples/slurm_cluster.py --pbs --jobs 2 --cores 16 --memory 32GB --queue workq

The script submits ``--jobs`` batch jobs, each running one single-threaded Dask worker process
per core, prints the scheduler address, and keeps the cluster up until Ctrl-C; meanwhile run the
commands against it, e.g.

    rotarydryer sweep ajayi2011_mmg --grid operating.rpm=2.8,3.0,3.2 --scheduler tcp://ADDRESS:8786

dask-jobqueue is not a dependency of rotarydryer (``pip install dask-jobqueue``). Without it, or
with ``--dry-run``, the script prints the job it would submit and exits (what the test suite runs).
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import time


def cluster_options(a) -> dict:
    """Keyword arguments of ``SLURMCluster`` / ``PBSCluster``: one worker process per core, one thread
    each (the solves use one BLAS thread; the parallelism is across runs)."""
    opts = dict(cores=a.cores, processes=a.cores, memory=a.memory, walltime=a.walltime,
                job_script_prologue=[f"export {v}=1" for v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                                                "MKL_NUM_THREADS")])
    if a.queue:
        opts["queue"] = a.queue
    if a.account:
        opts["account"] = a.account
    return opts


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pbs", action="store_true", help="PBS instead of Slurm")
    ap.add_argument("--jobs", type=int, default=2, help="batch jobs to submit")
    ap.add_argument("--cores", type=int, default=4, help="cores (= worker processes) per job")
    ap.add_argument("--memory", default="8GB", help="memory per job")
    ap.add_argument("--walltime", default="01:00:00", help="wall time per job")
    ap.add_argument("--queue", default=None, help="partition (Slurm) or queue (PBS)")
    ap.add_argument("--account", default=None, help="account to charge")
    ap.add_argument("--dry-run", action="store_true", help="print the job script and exit")
    a, _ = ap.parse_known_args(argv)      # the test suite passes a folder; it is not used
    opts = cluster_options(a)
    kind = "PBSCluster" if a.pbs else "SLURMCluster"
    if a.dry_run or importlib.util.find_spec("dask_jobqueue") is None:
        why = "--dry-run" if a.dry_run else "dask-jobqueue is not installed (pip install dask-jobqueue)"
        print(f"{why}: would build dask_jobqueue.{kind}(" + ", ".join(f"{k}={v!r}" for k, v in opts.items())
              + f") and submit {a.jobs} jobs of {a.cores} single-threaded worker processes")
        return 0
    import dask_jobqueue  # only here: not a dependency

    cluster = getattr(dask_jobqueue, kind)(**opts)
    print(cluster.job_script())
    cluster.scale(jobs=a.jobs)
    print(f"scheduler: {cluster.scheduler_address}  (Ctrl-C stops the cluster)", flush=True)
    try:
        while True:
            time.sleep(60)
    except KeyboardInterrupt:
        pass
    finally:
        cluster.close()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
