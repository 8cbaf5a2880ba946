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
