"""Sparse finite-difference Jacobians with column grouping (Curtis, Powell & Reid 1974).

Columns of a Jacobian whose sparsity patterns share no row can be perturbed together: one
residual evaluation per *group* instead of per column. For the MMG dryer (516 unknowns) the
greedy grouping needs about 20 evaluations.

SciPy implements the same idea, but only in the private module ``scipy.optimize._numdiff``
(``group_columns``, ``approx_derivative``), which may change without notice; this module is
the small public-API replacement (NumPy and ``scipy.sparse`` only).
"""

from __future__ import annotations

import copy

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

__all__ = ["column_groups", "sparse_fd_jacobian", "FDPlan", "shifted"]


def column_groups(pattern) -> np.ndarray:
    """Greedy column grouping of a sparsity pattern (Curtis-Powell-Reid).

    Parameters
    ----------
    pattern : array_like or sparse matrix, shape (m, n)
        Nonzero where the Jacobian may be nonzero.

    Returns
    -------
    numpy.ndarray of int, shape (n,)
        Group number of each column, 0 .. n_groups - 1; no two columns of a group have a
        nonzero in the same row.
    """
    pat = sp.csc_matrix(pattern, dtype=bool)
    pat.eliminate_zeros()
    m, n = pat.shape
    # each row's groups so far as the bits of a Python integer: a column's group is the lowest group none of its
    # rows holds, found in one pass over its nonzeros (O(nnz); the search group by group with NumPy took
    # 10 ms of a one-off command at 280-516 unknowns, this 0.8 ms), the same groups
    indptr, indices = pat.indptr.tolist(), pat.indices.tolist()
    held = [0] * m
    groups = [0] * n
    for j in range(n):
        rows = indices[indptr[j]:indptr[j + 1]]
        used = 0
        for r in rows:
            used |= held[r]
        bit = ~used & (used + 1)           # the lowest group not used by these rows
        for r in rows:
            held[r] |= bit
        groups[j] = bit.bit_length() - 1
    return np.array(groups, dtype=np.intp)


class FDPlan:
    """What `sparse_fd_jacobian` derives from a pattern and its column groups, kept for a pattern
    that is reused (a solver's Jacobians): the pattern as sorted CSC, each entry's row, column and
    group, and the number of groups."""

    def __init__(self, pattern, groups=None):
        pat = sp.csc_matrix(pattern, dtype=bool)
        pat.eliminate_zeros()
        pat.sort_indices()
        self.pattern = pat
        self.groups = column_groups(pat) if groups is None else np.asarray(groups)
        self.rows = pat.indices
        self.cols = np.repeat(np.arange(pat.shape[1]), np.diff(pat.indptr))
        self.entry_group = self.groups[self.cols]
        self.n_groups = int(self.groups.max()) + 1 if self.groups.size else 0
        self._diag = None
        self._order = None
        self._ordered = None      # the column-ordered matrix of shifted_lu (copied, its arrays replaced, each time)
        self._kept = None         # (exact zeros, entries kept, their rows, column pointers) of the last one
        self._col_index = None

    def matrix(self, data) -> sp.csc_matrix:
        """The CSC matrix of this plan's pattern with entries ``data`` (in the pattern's order, as
        `jacobian_data` returns them)."""
        pat = self.pattern
        return sp.csc_matrix((data, pat.indices.copy(), pat.indptr.copy()), shape=pat.shape)

    def jacobian_data(self, fun, x, step, f0):
        """The entries of `sparse_fd_jacobian`'s forward-difference Jacobian of a vectorized ``fun`` at ``x``
        (``step`` per column, ``f0 = fun(x)``), in the pattern's order: the same numbers without building the
        matrix (a solver that factorises it with `shifted_lu` needs none; 0.03-0.04 ms a Jacobian at 80-280
        unknowns)."""
        groups, n_groups = self.groups, self.n_groups
        if not n_groups:
            return np.zeros(0)
        if self._col_index is None or self._col_index.size != x.size:
            self._col_index = np.arange(x.size)
        j = self._col_index
        X = np.repeat(x[:, None], n_groups, axis=1)
        X[j, groups] += step
        h = X[j, groups] - x                         # the step actually taken (rounding)
        df = np.asarray(fun(X), dtype=float) - f0[:, None]
        return df[self.rows, self.entry_group] / h[self.cols]

    def shifted_lu(self, J, shift):
        """SuperLU factors of ``shift * I - J`` for a Jacobian ``J`` on this plan's pattern (as
        `sparse_fd_jacobian` returns it, or its entries alone as `jacobian_data` does) when the pattern
        holds the whole diagonal, else of `shifted`. The fill-reducing column ordering (COLAMD) of the
        first factorisation is kept and the next ones factorise the matrix with its columns in that
        order (``permc_spec="NATURAL"``; the row pivoting is SuperLU's as always): ordering costs about a
        quarter of a factorisation of 516 unknowns and depends on the pattern only (and on the entries
        that are exact zeros, which are dropped as by `shifted`). Returns an object with ``solve`` and
        ``shape``."""
        pat = self.pattern
        if isinstance(J, np.ndarray):            # the entries on this plan's pattern
            same, data = J.size == pat.indices.size, J
        else:
            same = (J.format == "csc" and J.shape == pat.shape and J.indices.size == pat.indices.size
                    and np.array_equal(J.indptr, pat.indptr) and np.array_equal(J.indices, pat.indices))
            data = J.data
        if same and self._diag is None:
            diag = np.flatnonzero(self.rows == self.cols) if pat.shape[0] == pat.shape[1] else np.zeros(0, int)
            self._diag = diag if diag.size == pat.shape[1] else False
        if not same or self._diag is False:
            return splu(shifted(self.matrix(J) if isinstance(J, np.ndarray) else J, shift))
        if self._order is None:
            lu = splu(shifted(self.matrix(data), shift))
            inv = np.argsort(lu.perm_c)          # column j of the ordered matrix is column inv[j]
            counts = np.diff(pat.indptr)[inv]
            indptr = np.concatenate([[0], np.cumsum(counts)]).astype(pat.indptr.dtype)
            take = np.repeat(pat.indptr[inv] - indptr[:-1], counts) + np.arange(indptr[-1])
            is_diag = np.zeros(pat.indices.size, dtype=bool)
            is_diag[self._diag] = True
            self._order = (inv, indptr, pat.indices[take], take, np.flatnonzero(is_diag[take]))
            self._ordered = sp.csc_matrix((np.ones(take.size), self._order[2].copy(), indptr.copy()),
                                          shape=pat.shape)
            return lu
        inv, indptr, indices, take, diag = self._order
        data = -data[take]
        data[diag] += shift
        # the exact zeros dropped, as shifted() does (a third of a dryer's entries can be exact zeros): their
        # positions repeat from one factorisation to the next, so the compacted pattern is kept with them
        zero = data == 0.0
        if zero.any():
            kept = self._kept
            if kept is None or not np.array_equal(kept[0], zero):
                keep = ~zero
                counts = np.zeros(keep.size + 1, dtype=np.intp)
                np.cumsum(keep, out=counts[1:])
                kept = self._kept = (zero, np.flatnonzero(keep), indices[keep], counts[indptr].astype(indptr.dtype))
            data, indices, indptr = data[kept[1]], kept[2], kept[3]
        # a shallow copy of one checked matrix object with its arrays replaced (the constructor's checks cost as
        # much as the small factorisation's own wrapper): its own object per call (threads may share a plan: the
        # copies of a dryer do), the arrays new or never written, the factors SuperLU's own
        A = copy.copy(self._ordered)
        A.data, A.indices, A.indptr = data, indices, indptr
        return _ColumnOrderedLU(splu(A, permc_spec="NATURAL"), inv)


class _ColumnOrderedLU:
    """The factors of a matrix A factorised with its columns reordered (column j of the factorised matrix
    is column ``inv[j]`` of A): ``solve(b)`` solves A x = b."""

    def __init__(self, lu, inv):
        self.lu, self.inv = lu, inv
        self.shape = lu.shape

    def solve(self, b):
        y = self.lu.solve(b)
        x = np.empty_like(y)
        x[self.inv] = y
        return x


def shifted(J, shift) -> sp.csc_matrix:
    """``shift * I - J`` for a square CSC matrix ``J``: from ``J``'s own arrays when its pattern holds the
    whole diagonal (a Jacobian of `sparse_fd_jacobian` with such a pattern; 0.02 ms instead of
    0.36 ms of sparse arithmetic and conversion for 516 unknowns), else by sparse arithmetic. The
    same entries either way (explicit zeros dropped)."""
    J = J.tocsc()
    if J.shape[0] == J.shape[1] and J.has_sorted_indices:
        cols = np.repeat(np.arange(J.shape[1]), np.diff(J.indptr))
        diag = np.flatnonzero(J.indices == cols)
        if diag.size == J.shape[1]:
            data = -J.data
            data[diag] += shift
            A = sp.csc_matrix((data, J.indices.copy(), J.indptr.copy()), shape=J.shape)
            A.eliminate_zeros()      # as the sparse arithmetic does: the same matrix for the LU
            return A
    return (sp.identity(J.shape[0], format="csc") * shift - J).tocsc()


def sparse_fd_jacobian(fun, x, pattern, groups=None, step=None, f0=None, vectorized=False) -> sp.csc_matrix:
    """Forward-difference Jacobian of ``fun`` at ``x`` with the given sparsity.

    Parameters
    ----------
    fun : callable
        ``fun(x) -> ndarray (m,)``.
    x : ndarray, shape (n,)
        Point of evaluation.
    pattern : array_like, sparse matrix (m, n) or FDPlan
        Sparsity pattern (entries outside it are taken as zero), or its `FDPlan` (a pattern
        that is reused: the conversions and groups are done once).
    groups : ndarray of int, optional
        Column groups from `column_groups` (computed if omitted; ignored with a plan).
    step : float or ndarray, optional
        Absolute step per column (default ``sqrt(eps) * max(1, |x|)``).
    f0 : ndarray, optional
        ``fun(x)`` if already known.
    vectorized : bool
        ``fun`` accepts a batch of points as columns, ``fun(X (n, k)) -> (m, k)`` (SciPy's
        ``solve_ivp(vectorized=True)`` convention): all groups are perturbed in one call, which
        for a residual dominated by per-call overhead costs about one evaluation instead of one
        per group. The entries are the same differences as column by column.

    Returns
    -------
    scipy.sparse.csc_matrix, shape (m, n)
    """
    x = np.asarray(x, dtype=float)
    plan = pattern if isinstance(pattern, FDPlan) else FDPlan(pattern, groups)
    pat, groups = plan.pattern, plan.groups
    if step is None:
        step = np.sqrt(np.finfo(float).eps) * np.maximum(1.0, np.abs(x))
    step = np.broadcast_to(np.asarray(step, dtype=float), x.shape)
    f0 = np.asarray(fun(x), dtype=float) if f0 is None else np.asarray(f0, dtype=float)
    rows, cols, entry_group, n_groups = plan.rows, plan.cols, plan.entry_group, plan.n_groups
    if vectorized and n_groups:
        return plan.matrix(plan.jacobian_data(fun, x, step, f0))
    data = np.zeros(rows.size)
    for g in range(n_groups):
        in_g = groups == g
        x1 = x.copy()
        x1[in_g] += step[in_g]
        h = x1 - x                                   # the step actually taken (rounding)
        df = np.asarray(fun(x1), dtype=float) - f0
        sel = entry_group == g
        data[sel] = df[rows[sel]] / h[cols[sel]]
    return sp.csc_matrix((data, pat.indices.copy(), pat.indptr.copy()), shape=pat.shape)
