"""Network engine: analytic moments against tanks-in-series, tracer simulators, steady state."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.transport import EdgeFamily, Network, NoSteadyStateError, TracerInput


def chain(n, k, feed=2.0):
    src = np.arange(n)
    dst = np.r_[np.arange(1, n), -1]
    feedv = np.zeros(n)
    feedv[0] = feed
    return Network(n, [EdgeFamily("flow", src, dst, "linear", rate=np.full(n, k))], feedv,
                   labels={"section": ["s"] * n, "phase": ["bed"] * n, "cell": list(range(n)),
                           "position": list(range(n))})


@settings(max_examples=30, deadline=None)
@given(n=st.integers(1, 60), k=st.floats(0.01, 10))
def test_tanks_in_series_moments(n, k):
    net = chain(n, k)
    M = net.steady_state()
    np.testing.assert_allclose(M, 2.0 / k, rtol=1e-10)
    mom = net.tracer_system(M).moments()
    assert mom["recovery"] == pytest.approx(1.0, abs=1e-9)
    assert mom["mean"] == pytest.approx(n / k, rel=1e-9)  # tau = holdup / flow
    assert mom["variance"] == pytest.approx(n / k**2, rel=1e-8)
    assert mom["skewness"] == pytest.approx(2 / math.sqrt(n), rel=1e-6)


@pytest.mark.parametrize("method", ["expm", "bdf2", "ivp"])
def test_simulators_match_analytic_moments(method):
    net = chain(8, 0.05)
    ts = net.tracer_system(net.steady_state())
    inp = TracerInput.pulse(1.0, 30.0, start=10.0)
    resp = ts.simulate(inp, t_end=2000.0, dt=2.0, method=method)
    sim = resp.moments()
    ana = ts.moments(inp)
    tol = {"expm": 1e-6, "bdf2": 2e-3, "ivp": 2e-3}[method]
    assert sim["recovery"] == pytest.approx(ana["recovery"], abs=tol)
    assert sim["mean"] == pytest.approx(ana["mean"], rel=tol)
    assert sim["std"] == pytest.approx(ana["std"], rel=5 * tol)
    F = resp.cumulative
    assert np.all(np.diff(F) >= -1e-12) and F[-1] == pytest.approx(1.0, abs=1e-3)


def test_bdf2_converges_second_order():
    net = chain(10, 0.1)
    ts = net.tracer_system(net.steady_state())
    inp = TracerInput.pulse(1.0, 20.0)
    ana = ts.moments(inp)["std"]
    e1 = abs(ts.simulate(inp, 1000.0, 4.0, "bdf2").moments()["std"] - ana)
    e2 = abs(ts.simulate(inp, 1000.0, 2.0, "bdf2").moments()["std"] - ana)
    assert e2 < e1 / 2.5  # ~4x for a second-order scheme


def test_capped_network_without_outlet_for_excess_has_no_steady_state():
    # one passive node discharging at most k*cap: a feed above that cannot be carried
    net = Network(2, [EdgeFamily("discharge", [0], [1], "capped", rate=[0.1], cap=[10.0]),
                      EdgeFamily("out", [1], [-1], "linear", rate=[1.0])], np.array([5.0, 0.0]),
                  labels={"section": ["s", "s"], "phase": ["passive", "active"], "cell": [0, 0],
                          "position": [0, 0]})
    with pytest.raises(NoSteadyStateError, match="feed_rate"):
        net.steady_state()
    # ... but below the capacity it exists and is exact
    net.feed = np.array([0.5, 0.0])
    M = net.steady_state()
    np.testing.assert_allclose(M, [5.0, 0.5])


def test_bad_edges():
    with pytest.raises(ValueError, match="outside the allowed range"):
        EdgeFamily("x", [0], [1], "linear", rate=[-1.0])
    with pytest.raises(ValueError, match="kind"):
        EdgeFamily("x", [0], [1], "bogus", rate=[1.0])
    with pytest.raises(ValueError, match="tracer mass"):
        TracerInput.pulse(0.0, 1.0)


def _capped_pair():
    """Node 0 passes at most its design load 1.5 kg on (rate 0.1/s) and kilns the excess; node 1 empties
    through the outlet (rate 0.2/s)."""
    fams = [EdgeFamily("discharge", [0], [1], "capped", rate=[0.1], cap=[1.5]),
            EdgeFamily("kiln", [0], [1], "excess", rate=[0.05], cap=[1.5]),
            EdgeFamily("out", [1], [-1], "linear", rate=[0.2])]
    return Network(2, fams, feed=[0.1, 0.0])


def test_integer_masses_are_masses():
    """Masses given as integers are the same masses (the capped and excess bases are not truncated)."""
    net = _capped_pair()
    np.testing.assert_allclose(net.residual(np.array([2, 1])), net.residual(np.array([2.0, 1.0])), rtol=1e-15)
    np.testing.assert_allclose(net.residual(np.array([2, 1])), [0.1 - 0.15 - 0.025, 0.15 + 0.025 - 0.2], rtol=1e-14)
    np.testing.assert_allclose(net.jacobian(np.array([1, 1])).toarray(), net.jacobian(np.array([1.0, 1.0])).toarray())


def test_a_caller_changing_a_jacobian_does_not_change_the_next():
    """The Jacobian has its own index arrays: dropping its explicit zeros (an over-loaded capped edge) leaves
    the network's pattern intact."""
    net = _capped_pair()
    J = net.jacobian(np.array([2.0, 1.0]))
    J.eliminate_zeros()
    np.testing.assert_allclose(net.jacobian(np.array([0.5, 1.0])).toarray(), [[-0.1, 0.0], [0.1, -0.2]], rtol=1e-15)
