"""Sparse finite-difference Jacobians with column grouping (rotarydryer._sparse_fd)."""

import sys

import numpy as np
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer._sparse_fd import FDPlan, column_groups, sparse_fd_jacobian


def _random_pattern(seed, m, n, density):
    rng = np.random.default_rng(seed)
    a = sp.random(m, n, density=density, format="csc", random_state=rng)
    a = a + sp.eye(m, n, format="csc")              # never an empty column
    a.data[:] = rng.uniform(-3.0, 3.0, a.nnz)
    return a


@given(st.integers(0, 10_000), st.integers(1, 60), st.integers(1, 60), st.floats(0.0, 0.3))
@settings(max_examples=60, deadline=None)
def test_groups_never_share_a_row(seed, m, n, density):
    pat = _random_pattern(seed, m, n, density)
    g = column_groups(pat)
    assert g.shape == (n,) and g.min() == 0
    for k in range(g.max() + 1):
        # rows hit by the columns of one group: no row counted twice
        counts = np.asarray((pat[:, g == k] != 0).sum(axis=1)).ravel()
        assert counts.max() <= 1


def _greedy_group_by_group(pattern):
    """The reference greedy grouping (Curtis, Powell & Reid 1974): each column in order joins the first group whose
    rows it does not touch, else starts a new one."""
    pat = sp.csc_matrix(pattern, dtype=bool)
    pat.eliminate_zeros()
    occupied, groups = [], []
    for j in range(pat.shape[1]):
        rows = set(pat.indices[pat.indptr[j]:pat.indptr[j + 1]].tolist())
        for g, occ in enumerate(occupied):
            if not occ & rows:
                occ |= rows
                groups.append(g)
                break
        else:
            occupied.append(set(rows))
            groups.append(len(occupied) - 1)
    return np.array(groups)


@given(st.integers(0, 10_000), st.integers(1, 200), st.integers(1, 200), st.floats(0.0, 0.5))
@settings(max_examples=60, deadline=None)
def test_groups_are_the_greedy_reference_groups(seed, m, n, density):
    """The one-pass grouping (each row's groups as bits) gives exactly the column-by-column greedy groups, also
    beyond 64 groups (dense patterns)."""
    pat = _random_pattern(seed, m, n, density)
    np.testing.assert_array_equal(column_groups(pat), _greedy_group_by_group(pat))


@given(st.integers(0, 10_000), st.integers(1, 40), st.floats(0.0, 0.3))
@settings(max_examples=40, deadline=None)
def test_linear_map_is_recovered(seed, n, density):
    a = _random_pattern(seed, n, n, density)
    x = np.random.default_rng(seed + 1).normal(size=n)
    jac = sparse_fd_jacobian(lambda v: a @ v, x, a != 0)
    np.testing.assert_allclose(jac.toarray(), a.toarray(), atol=1e-6 * (1 + np.abs(a).max()))


@given(st.integers(0, 10_000), st.integers(1, 40), st.floats(0.0, 0.3))
@settings(max_examples=40, deadline=None)
def test_vectorized_equals_group_by_group(seed, n, density):
    """One call with every group's perturbation as a column gives the same entries."""
    a = _random_pattern(seed, n, n, density)
    x = np.random.default_rng(seed + 1).normal(size=n)
    calls = []

    def f(v):
        calls.append(v.shape)
        return np.tanh(a @ v) + v ** 2
    one = sparse_fd_jacobian(f, x, a != 0, vectorized=True)
    n_groups = column_groups(a != 0).max() + 1
    assert calls[-1] == (n, n_groups)
    assert len(calls) == 2                            # f0 and the batch
    ref = sparse_fd_jacobian(f, x, a != 0)
    np.testing.assert_allclose(one.toarray(), ref.toarray(), rtol=1e-12, atol=1e-12)


@given(st.integers(0, 10_000), st.integers(1, 50), st.floats(0.0, 0.3), st.booleans())
@settings(max_examples=40, deadline=None)
def test_shifted_lu_solves_with_the_kept_column_order(seed, n, density, full_diagonal):
    """FDPlan.shifted_lu: shift I - J solved to rounding by the first factorisation (COLAMD) and by the
    next ones in its column order, for Jacobians of other values on the same pattern; a pattern
    without the whole diagonal (or another matrix) is factorised as it is."""
    rng = np.random.default_rng(seed)
    a = _random_pattern(seed, n, n, density)
    if not full_diagonal and n > 1:
        a = a.tolil()
        a[0, 0] = 0.0
        a = a.tocsc()
        a.eliminate_zeros()
    plan = FDPlan(a != 0)
    for k in range(3):
        J = sparse_fd_jacobian(lambda v, k=k: (a * (1.0 + k)) @ v + 0.1 * np.sin(v), rng.normal(size=n), plan,
                               vectorized=True)
        shift = 10.0 ** rng.uniform(-3, 2)
        A = (shift * sp.identity(n) - J).toarray()
        b = rng.normal(size=n)
        x = plan.shifted_lu(J, shift).solve(b)
        assert plan.shifted_lu(J, shift).shape == (n, n)
        np.testing.assert_allclose(A @ x, b, atol=1e-9 * (1 + np.abs(A).max() * np.abs(x).max()))
    other = sp.csc_matrix(np.eye(n) * 2.0)      # not this plan's pattern: factorised as given
    np.testing.assert_allclose(plan.shifted_lu(other, 1.0).solve(np.ones(n)), -np.ones(n))


@given(st.integers(0, 10_000), st.integers(2, 40), st.floats(0.05, 0.3))
@settings(max_examples=40, deadline=None)
def test_shifted_lu_of_the_entries_alone_with_exact_zeros_that_move(seed, n, density):
    """FDPlan.shifted_lu of a Jacobian's entries (`jacobian_data`) as of its matrix, where each Jacobian holds exact
    zeros at other places (the compacted pattern kept from one factorisation is rebuilt for the next): every
    factorisation solves its own shift I - J, also after the later ones (their matrix object's arrays are replaced,
    not written)."""
    rng = np.random.default_rng(seed)
    a = _random_pattern(seed, n, n, density) + sp.identity(n, format="csc")
    plan = FDPlan(a != 0)
    kept = []
    for _ in range(5):
        data = rng.normal(size=plan.rows.size)
        data[rng.random(data.size) < 0.3] = 0.0            # exact zeros, somewhere else each time
        shift = 10.0 ** rng.uniform(-1, 2)
        A = shift * np.eye(n) - plan.matrix(data).toarray()
        if abs(np.linalg.det(A)) < 1e-8:
            continue
        lu = plan.shifted_lu(data, shift)
        ref = plan.shifted_lu(plan.matrix(data), shift)
        b = rng.normal(size=n)
        np.testing.assert_allclose(lu.solve(b), ref.solve(b), rtol=0, atol=0)
        kept.append((lu, A, b))
    for lu, A, b in kept:
        x = lu.solve(b)
        np.testing.assert_allclose(A @ x, b, atol=1e-8 * (1 + np.abs(A).max() * np.abs(x).max()))


def test_jacobian_data_is_the_matrix_entries():
    """`FDPlan.jacobian_data` gives `sparse_fd_jacobian`'s entries in the pattern's order (the same numbers)."""
    rng = np.random.default_rng(3)
    n = 30
    a = _random_pattern(3, n, n, 0.2) + sp.identity(n, format="csc")
    plan = FDPlan(a != 0)

    def f(v):
        return (a @ v) ** 2 + np.sin(v if v.ndim == 1 else v)

    x = rng.normal(size=n)
    step = np.full(n, 1e-7)
    J = sparse_fd_jacobian(f, x, plan, step=step, vectorized=False)      # group by group, not through jacobian_data
    data = plan.jacobian_data(f, x, step, f(x))
    np.testing.assert_allclose(plan.matrix(data).toarray(), J.toarray(), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(data, J.data, rtol=1e-12, atol=1e-12)
    assert plan.matrix(data).nnz == plan.pattern.nnz


def test_shifted_lu_from_threads_sharing_a_plan():
    """Threads that share a plan (the copies of a dryer share theirs) each factorise their own matrix: every
    factorisation solves the system it was given (a matrix object reused across calls gave 62 wrong ones in 12 000
    calls from four threads)."""
    import threading

    n = 60
    a = _random_pattern(7, n, n, 0.15) + sp.identity(n, format="csc")
    plan = FDPlan(a != 0)
    rng = np.random.default_rng(7)
    plan.shifted_lu(rng.normal(size=plan.rows.size), 10.0)      # the first factorisation sets the column order
    wrong = []

    def work(seed):
        r = np.random.default_rng(seed)
        for _ in range(300):
            data = r.normal(size=plan.rows.size)
            shift = 10.0 + r.random()
            x = plan.shifted_lu(data, shift).solve(np.ones(n))
            A = shift * np.eye(n) - plan.matrix(data).toarray()
            if not np.allclose(A @ x, 1.0, atol=1e-8):
                wrong.append(seed)
    threads = [threading.Thread(target=work, args=(s,)) for s in range(4)]
    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)         # the threads interleave between any two bytecodes
    try:
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    finally:
        sys.setswitchinterval(interval)
    assert not wrong


def test_banded_nonlinear_matches_analytic_and_uses_few_groups():
    n = 200

    def f(x):
        r = x ** 3
        r[1:] += np.sin(x[:-1])
        r[:-1] += 2.0 * x[1:]
        return r

    x = np.linspace(-1.0, 1.0, n)
    pat = sp.diags([1.0, 1.0, 1.0], [-1, 0, 1], shape=(n, n))
    groups = column_groups(pat)
    assert groups.max() + 1 == 3                      # tridiagonal: three evaluations
    exact = sp.diags([np.cos(x[:-1]), 3 * x ** 2, np.full(n - 1, 2.0)], [-1, 0, 1]).toarray()
    jac = sparse_fd_jacobian(f, x, pat, groups, step=1e-7)
    np.testing.assert_allclose(jac.toarray(), exact, atol=1e-6)


def test_dryer_jacobian_matches_dense_differences():
    """The MMG dryer's grouped Jacobian equals the column-by-column one."""
    from rotarydryer.cases import load_case
    from rotarydryer.simulation import build_thermal_dryer
    d = build_thermal_dryer(load_case("ajayi2011_mmg", {"operating.test": 4}))
    z = d.initial_state()
    d.freeze_shell(z)      # as the solvers do: the shell root (tolerance 1e-9 K) would add its own noise
    jac = d.jacobian(z).toarray()
    n_groups = d._groups.max() + 1
    assert n_groups < d.n / 10
    f0 = d.rhs(0.0, z)
    step = np.maximum(np.abs(z) * 1e-7, d._scale() * 1e-8)
    cols = np.random.default_rng(0).choice(d.n, 25, replace=False)
    for j in cols:
        z1 = z.copy()
        z1[j] += step[j]
        dense = (d.rhs(0.0, z1) - f0) / (z1[j] - z[j])
        np.testing.assert_allclose(jac[:, j], dense, rtol=1e-9, atol=1e-9 * np.abs(dense).max())
