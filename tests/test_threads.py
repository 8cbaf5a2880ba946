"""One BLAS/OpenMP thread for the project's own solves and parallel runs (issue 16 part 3)."""

from __future__ import annotations

import numpy as np  # noqa: F401 - loads the BLAS
import pytest

threadpoolctl = pytest.importorskip("threadpoolctl")

from rotarydryer._threads import single_threaded  # noqa: E402


def _max_threads():
    info = threadpoolctl.threadpool_info()
    return max((i["num_threads"] for i in info), default=1)


def test_context_manager_limits_and_restores():
    before = _max_threads()
    with single_threaded():
        assert _max_threads() == 1
        with single_threaded():          # nested: no-op
            assert _max_threads() == 1
        assert _max_threads() == 1
    assert _max_threads() == before


def test_decorator_recursive():
    before = _max_threads()

    @single_threaded()
    def f(n):
        return f(n - 1) if n else _max_threads()

    assert f(3) == 1 and f(0) == 1
    assert _max_threads() == before


def test_bad_limit():
    with pytest.raises(ValueError, match="limits = 0"):
        single_threaded(0)


def test_sweep_point_runs_single_threaded(monkeypatch):
    from rotarydryer.simulation import Simulation
    from rotarydryer.studies.sweep import run_point

    seen = []

    def fake_steady_state(self, warm=None):
        seen.append(_max_threads())
        raise ValueError("stop here")

    monkeypatch.setattr(Simulation, "steady_state", fake_steady_state)
    row = run_point("song2003_ottawa", {"operating.rpm": "4"})
    assert seen == [1] and row["error"] == "stop here"


@pytest.mark.parametrize("given, want", [(None, 1), ("2", 2)])
def test_a_command_process_loads_its_blas_with_one_thread(given, want):
    """The command line sets one BLAS thread before NumPy loads (no thread pool to start in a one-off
    command); a number the user's environment names is kept."""
    import json
    import os
    import subprocess
    import sys

    from rotarydryer._threads import BLAS_ENV_VARS

    env = {k: v for k, v in os.environ.items() if k not in BLAS_ENV_VARS and k != "OMP_NUM_THREADS"}
    if given is not None:
        env["OPENBLAS_NUM_THREADS"] = given
    code = ("import rotarydryer.cli, os, json, sys, numpy\n"
            "from rotarydryer._threads import single_threaded\n"
            "with single_threaded():\n"
            "    looked = 'threadpoolctl' in sys.modules\n"
            "    from threadpoolctl import threadpool_info\n"
            "    inside = [p['num_threads'] for p in threadpool_info() if p['user_api'] == 'blas']\n"
            "print(json.dumps([os.environ.get('OPENBLAS_NUM_THREADS'), looked, inside, "
            "[p['num_threads'] for p in threadpool_info() if p['user_api'] == 'blas']]))")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    var, looked, inside, threads = json.loads(out.stdout)
    assert var == str(want)
    assert threads and all(n == want if want == 1 else 1 <= n <= want for n in threads)   # (a 1-core machine: 1)
    # the solves' one thread: with the pools loaded at one thread, threadpoolctl is not even looked at
    assert inside == [1] * len(threads) and looked == (want != 1)


def test_the_controller_is_kept_until_a_module_is_imported(monkeypatch):
    """One inspection of the loaded libraries serves every run until a module is imported (a sweep entered one
    per point, 1.3 ms each); a library loaded later, here NumPy's BLAS after a first limit, is limited too."""
    import json
    import os
    import subprocess
    import sys

    from rotarydryer import _threads
    from rotarydryer._threads import BLAS_ENV_VARS

    monkeypatch.setattr(_threads, "_LOADED_SINGLE", [False])     # this process may have the command's variables
    with single_threaded():
        pass
    kept = _threads._CONTROLLER[0]
    assert kept is not None
    with single_threaded():
        assert _max_threads() == 1
    assert _threads._CONTROLLER[0] is kept

    env = {k: v for k, v in os.environ.items() if k not in BLAS_ENV_VARS and k != "OMP_NUM_THREADS"}
    env["OPENBLAS_NUM_THREADS"] = "2"       # a pool of two threads when NumPy loads, on a 1-core machine too
    code = ("import json, sys\n"
            "from rotarydryer._threads import single_threaded\n"
            "assert 'numpy' not in sys.modules\n"
            "with single_threaded():\n"
            "    pass\n"
            "import numpy\n"
            "from threadpoolctl import threadpool_info\n"
            "def blas():\n"
            "    return [p['num_threads'] for p in threadpool_info() if p['user_api'] == 'blas']\n"
            "before = blas()\n"
            "with single_threaded():\n"
            "    inside = blas()\n"
            "print(json.dumps([before, inside, blas()]))")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    before, inside, after = json.loads(out.stdout)
    assert before and max(before) == 2 and inside == [1] * len(before) and after == before
