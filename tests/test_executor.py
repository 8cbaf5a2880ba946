"""The one executor of many-run work (issue 32): chunks, backends, warm long-lived workers, failures."""

from __future__ import annotations

import os
import sys

import pytest

from rotarydryer import executor as ex_mod
from rotarydryer.executor import Executor, RunFailure, parse_cluster, split, worker_info


# top level: the workers unpickle these by name
def squares(chunk, offset=0):
    return [x * x + offset for x in chunk]


def fails_on_three(chunk):
    if 3 in chunk:
        raise ValueError("three is\n  not allowed")
    return [x + 0.5 for x in chunk]


def running_sum(chunk):
    """A chunk computed in order, each item from the one before it (a warm-start chain)."""
    out, acc = [], 0.0
    for x in chunk:
        acc = acc * 0.5 + x
        out.append(acc)
    return out


def young_thresholds(chunk):
    import gc

    return [gc.get_threshold()[0] for _ in chunk]


WARM_CALLS: list = []


class OddItemWarning(UserWarning):
    pass


def warns_on_odd(chunk):
    """Each odd item warns (its own text), as a case's run warns of a range or a supersaturated exhaust."""
    import warnings

    for x in chunk:
        if x % 2:
            warnings.warn(f"item {x} is odd", OddItemWarning, stacklevel=1)
    return list(chunk)


def note_warm(tag):
    WARM_CALLS.append(tag)


def test_split_depends_on_the_count_only():
    assert [(s.start, s.stop) for s in split(10, chunks=4)] == [(0, 3), (3, 6), (6, 8), (8, 10)]
    assert split(0) == []
    assert len(split(200)) == 16 and {s.stop - s.start for s in split(200)} == {12, 13}
    assert len(split(3)) == 3
    assert [s.stop - s.start for s in split(10, min_size=4)] == [5, 5]
    assert max(s.stop - s.start for s in split(1000, max_size=16)) <= 16
    covered = [i for s in split(97, chunks=7) for i in range(s.start, s.stop)]
    assert covered == list(range(97))


@pytest.mark.parametrize("value, fragment", [
    ("local:0", "outside the allowed range [1, 256]"), ("foo", "is not a cluster"), ("local:x", "not a whole number"),
    ("local", "is not a cluster"), ("tcp://h:8786", "--scheduler"), ("local:-2", "outside the allowed range"),
])
def test_bad_cluster_names_the_option(value, fragment):
    with pytest.raises(ValueError, match="--cluster") as info:
        parse_cluster(value)
    assert fragment in str(info.value) and "\n" not in str(info.value)


def test_parse_cluster():
    assert parse_cluster("local:2") == 2 and parse_cluster(" LOCAL:4 ") == 4


def test_bad_executor_options():
    with pytest.raises(ValueError, match="--scheduler or --cluster, not both"):
        Executor(scheduler="tcp://h:8786", cluster="local:2")
    with pytest.raises(ValueError, match="--workers = -1"):
        Executor(workers=-1)
    with pytest.raises(ValueError, match="backend"):
        Executor("threads")


def test_serial_results_in_order_with_progress():
    seen = []
    with Executor() as ex:
        assert ex.backend == "serial" and ex.describe() == "serial"
        out = ex.map_chunks(squares, range(7), chunks=3, args=(1,), progress=seen.append)
    assert out == [x * x + 1 for x in range(7)]
    assert seen == [3, 3, 1]


def test_a_failing_item_is_a_value_and_the_batch_goes_on():
    out = Executor().map_chunks(fails_on_three, [1, 2, 3, 4, 5, 6], chunks=3)
    assert out[:2] == [1.5, 2.5] and out[3:] == [4.5, 5.5, 6.5]
    assert isinstance(out[2], RunFailure) and out[2].error == "three is not allowed"
    per_item = Executor().map(int, ["1", "x", "3"])
    assert per_item[0] == 1 and per_item[2] == 3 and isinstance(per_item[1], RunFailure)
    assert "invalid literal" in per_item[1].error


def test_local_pool_same_results_failures_and_reused_warm_workers():
    """Two calls in one process share one pool: the same worker processes, each warmed once."""
    ex = Executor(workers=2)
    assert ex.backend == "local"
    items = list(range(40))
    want = Executor().map_chunks(running_sum, items, chunks=5)
    warm = ((note_warm, ("a",)),)
    assert ex.map_chunks(running_sum, items, chunks=5, warm=warm) == want
    first = ex.map_chunks(worker_info, list(range(64)), chunks=1, warm=warm)
    second = ex.map_chunks(worker_info, list(range(64)), chunks=1, warm=warm)
    pids = {p for p, _ in first + second}
    assert os.getpid() not in pids and len(pids) <= 2       # the same two long-lived workers in both calls
    warmups = {}
    for p, n in first + second:
        warmups.setdefault(p, set()).add(n)
    assert all(len(v) == 1 for v in warmups.values())      # no warm-up ran again in a worker
    # a failing item in a worker: the chunk is re-run item by item there
    out = ex.map_chunks(fails_on_three, [1, 2, 3, 4, 5, 6], chunks=3)
    assert isinstance(out[2], RunFailure) and out[:2] == [1.5, 2.5] and out[3:] == [4.5, 5.5, 6.5]


def test_spawned_workers_run_each_warm_up_once(monkeypatch):
    monkeypatch.setenv(ex_mod.START_METHOD_ENV, "spawn")
    ex_mod._close_local()
    try:
        ex = Executor(workers=2)
        warm = ((note_warm, ("spawned",)),)
        first = ex.map_chunks(worker_info, list(range(16)), chunks=1, warm=warm)
        pool = ex_mod._POOL["pool"]
        second = ex.map_chunks(worker_info, list(range(16)), chunks=1, warm=warm)
        assert {n for _, n in first + second} == {1}        # once per worker, not per chunk or call
        # the same pool serves both calls (one fast worker may have taken every chunk of the first)
        assert ex_mod._POOL["pool"] is pool and len({p for p, _ in first + second}) <= 2
        assert ex_mod._POOL["key"] == (2, "spawn")
        # each worker collects its young objects in larger batches (`raise_gc_threshold`); not this process
        import gc

        from rotarydryer._startup import GC_YOUNG_THRESHOLD
        before = gc.get_threshold()
        assert set(ex.map_chunks(young_thresholds, list(range(8)), chunks=1)) == {GC_YOUNG_THRESHOLD}
        assert gc.get_threshold() == before
    finally:
        ex_mod._close_local()


JIT_AT_WARM_UP: list = []


def note_jit(tag):
    from rotarydryer import _jit

    JIT_AT_WARM_UP.append((tag, os.getpid(), _jit._LONG))


def test_forked_pool_warms_the_parent_for_long_runs(monkeypatch):
    """A pool connected before its first batch (the CLI's ``connect``) warms the parent for the long runs
    its forked workers make: the warm-up runs with the compiled kernels declared, so the workers inherit
    them loaded instead of each loading them (the sweep's CPU on two workers was 1.14x one worker's)."""
    if "fork" not in __import__("multiprocessing").get_all_start_methods():
        pytest.skip("no fork start method here")
    from rotarydryer import _jit

    monkeypatch.setenv(ex_mod.START_METHOD_ENV, "fork")
    monkeypatch.setattr(_jit, "_LONG", False)
    ex_mod._close_local()
    JIT_AT_WARM_UP.clear()
    try:
        ex = Executor(workers=2)
        warm = ((note_jit, ("fork-connect",)),)
        ex.connect(warm)
        assert JIT_AT_WARM_UP == [("fork-connect", os.getpid(), True)]
        frozen = []
        monkeypatch.setattr(ex_mod.gc, "freeze", lambda: frozen.append("freeze"))
        monkeypatch.setattr(ex_mod.gc, "unfreeze", lambda: frozen.append("unfreeze"))
        out = ex.map_chunks(worker_info, list(range(8)), chunks=1, warm=warm)
        # the forked workers inherit the parent's warm-ups (its count) and do not run this one again
        assert {n for _, n in out} == {ex_mod._WARM_RUNS[0]} and os.getpid() not in {p for p, _ in out}
        # the parent's objects were out of the garbage collector's passes while the workers forked, then back
        assert frozen == ["freeze", "unfreeze"]
        ex.map_chunks(worker_info, list(range(4)), chunks=1, warm=warm)     # the workers live: no second freeze
        assert frozen == ["freeze", "unfreeze"]
    finally:
        ex_mod._close_local()


def test_dask_local_cluster_same_results():
    pytest.importorskip("dask.distributed")
    ex = Executor(cluster="local:2")
    assert ex.backend == "dask" and "LocalCluster of 2" in ex.describe()
    items = list(range(30))
    assert ex.map_chunks(running_sum, items, chunks=4) == Executor().map_chunks(running_sum, items, chunks=4)
    out = ex.map_chunks(fails_on_three, [1, 2, 3, 4], chunks=2)
    assert isinstance(out[2], RunFailure) and out[3] == 4.5
    info = ex.map_chunks(worker_info, list(range(8)), chunks=1)
    assert os.getpid() not in {p for p, _ in info}


@pytest.mark.parametrize("options", [dict(workers=2), dict(cluster="local:2")])
def test_a_workers_warnings_are_raised_where_the_batch_was_made(options, capfd):
    """A worker's warnings come back with its chunk's results and are raised in the process that made the batch, as
    a serial run's are (its filters and its command's printer: one line per text); a Dask worker printed each with
    its source line on its own stderr, a forked worker through its own copy of the printer (found by an acceptance
    check)."""
    import warnings

    if "cluster" in options:
        pytest.importorskip("dask.distributed")
    items = list(range(12))
    with warnings.catch_warnings(record=True) as serial:
        warnings.simplefilter("always")
        assert Executor().map_chunks(warns_on_odd, items, chunks=3) == items
    capfd.readouterr()
    try:
        with warnings.catch_warnings(record=True) as pooled:
            warnings.simplefilter("always")
            assert Executor(**options).map_chunks(warns_on_odd, items, chunks=3) == items
    finally:
        ex_mod._close_local()
    ours = [w for w in pooled if "is odd" in str(w.message)]      # not Dask's own (an unclosed socket, ...)
    assert sorted(str(w.message) for w in ours) == sorted(str(w.message) for w in serial) \
        == sorted(f"item {x} is odd" for x in items if x % 2)
    assert {w.category for w in ours} == {OddItemWarning}
    err = capfd.readouterr().err
    assert "is odd" not in err, err


def warns_the_same(chunk):
    import warnings

    for _ in chunk:
        warnings.warn("the same text", OddItemWarning, stacklevel=1)
    return list(chunk)


def test_a_repeated_warning_is_shown_once_per_batch_as_in_a_serial_run():
    """Forwarded warnings went through warnings.warn_explicit without a registry: the default filter's once per
    place showed one per chunk (10 for 20 items in chunks of 2; found by a review). Its module is the worker's
    module, so that a filter by module matches as in a serial run."""
    import warnings

    def shown(ex):
        with warnings.catch_warnings(record=True) as caught:
            warnings.resetwarnings()
            warnings.simplefilter("default")
            warnings.filterwarnings("ignore", category=OddItemWarning, module="elsewhere")
            ex.map_chunks(warns_the_same, list(range(20)), chunks=2)
        return [str(w.message) for w in caught if issubclass(w.category, OddItemWarning)]

    try:
        assert shown(Executor()) == shown(Executor(workers=2)) == ["the same text"]
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            warnings.filterwarnings("ignore", category=OddItemWarning, module=r"test_executor")
            Executor(workers=2).map_chunks(warns_the_same, list(range(4)), chunks=2)
        assert not [w for w in caught if issubclass(w.category, OddItemWarning)]
    finally:
        ex_mod._close_local()


def test_a_lambda_is_refused_only_where_it_cannot_go():
    """The local pool pickles its function by reference: a lambda is refused up front (each item had become a
    RunFailure "Can't pickle"); one chunk runs here and Dask sends a lambda by value, so both take it."""
    with pytest.raises(ValueError, match=r"fn = .*<lambda> cannot be sent to worker processes"):
        Executor(workers=2).map(lambda x: x, [1, 2, 3, 4])
    assert Executor(workers=2).map(lambda x: x + 1, [1], chunks=1) == [2]
    assert Executor(scheduler="").backend == "serial"
    assert Executor(scheduler="tcp://127.0.0.1").scheduler == "tcp://127.0.0.1"     # Dask's default port


def test_a_tls_scheduler_without_certificates_names_the_configuration():
    """Dask's TLS connector without the client's certificates raised TypeError ("TLS expects a ssl_context"),
    reported as an internal error (found by an acceptance check)."""
    pytest.importorskip("dask.distributed")
    with pytest.raises(ValueError, match=r"--scheduler = 'tls://127.0.0.1:1': a tls:// scheduler needs .*"
                                         r"distributed.comm.tls.ca-file") as info:
        Executor(scheduler="tls://127.0.0.1:1").connect()
    assert "\n" not in str(info.value)


def test_unreachable_scheduler_is_a_one_line_error(monkeypatch):
    pytest.importorskip("dask.distributed")
    monkeypatch.setattr(ex_mod, "CONNECT_TIMEOUT_S", 1.0)
    with pytest.raises(ValueError, match=r"--scheduler = 'tcp://127.0.0.1:1': no Dask scheduler answered") as info:
        Executor(scheduler="tcp://127.0.0.1:1").connect()
    assert "\n" not in str(info.value)


def test_simulation_sweep_same_rows_on_a_pool_and_a_failed_point_is_a_row():
    from rotarydryer import Simulation

    sim = Simulation("ajayi2011_mmg", {"operating.test": 4})
    grid = [{"operating.rpm": r} for r in (2.9, 3.0, 3.1, -1.0, 3.2, 3.3, 2.8, 2.7, 2.6, 2.5)]
    serial = sim.sweep(grid, outputs=["product_moisture_kg_kg", "total_holdup_kg"])
    pooled = sim.sweep(grid, outputs=["product_moisture_kg_kg", "total_holdup_kg"], workers=2)
    assert pooled == serial
    assert "operating.rpm" in serial[3]["error"] and "error" not in serial[4]


@pytest.mark.skipif(sys.platform != "linux", reason="signals to a process group (Linux)")
@pytest.mark.parametrize("backend", [["--workers", "2"], ["--cluster", "local:2"]], ids=["pool", "dask"])
def test_ctrl_c_on_a_two_worker_sweep_keeps_what_finished(tmp_path, backend):
    """Ctrl-C (SIGINT to the whole process group, here twice, as `timeout` sends it) on ``sweep --workers 2`` lost
    the finished runs and printed tracebacks (InvalidStateError, a wake-up pipe's OSError) in most tries (found by
    an acceptance check): the workers ignore it, the command stops them, saves every finished row and says so in one
    line, exit 130; no process is left. On a Dask LocalCluster its workers raised KeyboardInterrupt too: two
    tracebacks and Dask's log lines under the one line (found by an acceptance check)."""
    if backend[0] == "--cluster":
        pytest.importorskip("dask.distributed")
    import os
    import signal
    import subprocess
    import time

    feed = ",".join(f"{36 + 9 * i / 49:.4f}" for i in range(50))
    rpm = ",".join(f"{2.7 + 0.6 * i / 39:.4f}" for i in range(40))      # 2 000 points: far longer than the test waits
    out = tmp_path / "rows.csv"
    proc = subprocess.Popen([sys.executable, "-m", "rotarydryer", "sweep", "ajayi2011_mmg", "--set", "operating.test=4",
                             "--grid", f"operating.feed_rate={feed}", "--grid", f"operating.rpm={rpm}",
                             *backend, "-o", str(out)],
                            stderr=subprocess.PIPE, stdout=subprocess.PIPE, text=True, start_new_session=True)
    try:
        before = []
        while True:                             # the first progress line: some runs have finished
            line = proc.stderr.readline()
            assert line, "".join(before)
            if line.startswith("run "):
                break
            before.append(line)
        os.killpg(proc.pid, signal.SIGINT)
        time.sleep(0.01)       # the second at once, as `timeout` sends it (the old code failed so)
        os.killpg(proc.pid, signal.SIGINT)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    err = "".join(before) + err
    lines = [ln for ln in err.splitlines() if not ln.startswith(("run ", "warning: "))]
    assert proc.returncode == 130, err
    assert len(lines) == 1 and lines[0].startswith("error: interrupted; ") and "saved to" in lines[0], err
    assert "Traceback" not in err
    rows = out.read_text().splitlines()
    assert len(rows) == 2001
    done = int(lines[0].split("; ")[1].split(" of ")[0])
    assert 0 < done < 2000 and sum("not run (sweep interrupted)" not in r for r in rows[1:]) == done
    for _ in range(20):     # a killed Dask worker may stay a zombie until the system reaps it (it runs nothing)
        time.sleep(0.5)
        left = subprocess.run(["pgrep", "-s", str(proc.pid), "-r", "RSDT"], capture_output=True, text=True).stdout
        if not left.split():
            break
    assert not left.split(), f"processes left in the session: {left}"


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT raised in-process (POSIX)")
def test_an_interrupt_while_a_pool_batch_waits_is_noted_not_raised_where_the_thread_is():
    """A KeyboardInterrupt raised inside `concurrent.futures.wait` can leave a future's lock held: the pool's thread
    then waited on it for ever, and so did the Ctrl-C'd `sweep --workers 2` (one CI run of many; 1 of 40 tries
    sending SIGINT as the first progress line appears). The batch's wait notes the signal and stops where it is
    safe; the next ones are ignored; the handler before it is back after, or SIGINT stays ignored until the
    command's own block ends."""
    import signal

    from rotarydryer import executor as ex

    before = signal.getsignal(signal.SIGINT)
    noted: list = []
    reached = []
    with pytest.raises(KeyboardInterrupt):          # a noted signal the block did not act on: raised as it ends
        with ex._interrupt_noted(noted):
            signal.raise_signal(signal.SIGINT)      # noted, not raised here
            signal.raise_signal(signal.SIGINT)      # ignored
            assert noted == [signal.SIGINT]
            reached.append(True)
    assert reached and signal.getsignal(signal.SIGINT) is before
    with ex._interrupt_noted(quiet := []):          # no interrupt: the handler before is back
        pass
    assert not quiet and signal.getsignal(signal.SIGINT) is before
    with ex.stop_on_first_interrupt():
        with pytest.raises(KeyboardInterrupt):
            with ex._interrupt_noted(inner := []):
                signal.raise_signal(signal.SIGINT)
        assert inner and signal.getsignal(signal.SIGINT) is signal.SIG_IGN     # the command saves what finished
    assert signal.getsignal(signal.SIGINT) is before
