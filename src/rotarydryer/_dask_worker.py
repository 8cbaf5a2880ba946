"""The start-up of a worker of a Dask LocalCluster that `rotarydryer.executor` makes (``--cluster local:N``): Dask
runs `dask_setup` in each worker process when it starts (its ``preload``).

A terminal's Ctrl-C reaches every process of the command's group, these workers too: each raised
KeyboardInterrupt in its event loop and printed two tracebacks and Dask's log lines (a task cancelled, a worker
unknown to the scheduler) under the command's one-line message (found by an acceptance check). The process that made
the cluster stops the batch and closes the cluster; the workers ignore the signal and log errors only.
"""

from __future__ import annotations

import logging
import signal
import threading

__all__ = ["dask_setup"]


def dask_setup(worker) -> None:     # noqa: ARG001 - Dask's preload hook: its worker is not needed here
    """Dask's preload hook: SIGINT ignored, the ``distributed`` loggers at ERROR (this worker's process only)."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    logging.getLogger("distributed").setLevel(logging.ERROR)
