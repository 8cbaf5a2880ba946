"""Exact flight geometry at surrogate cost: per-drum tables of what the transport models need.

The exact flight model (`FlightedDrum`, Lee (2008) ch. 4) costs
about 20 us per (repose angle, loading) pair: a bisection for the discharge start angle
(Lee (2008) Eq. 4.22) and Gauss-Legendre quadrature of the mass averages (Lee (2008)
Eq. 3.3-3.6) phase by phase. Lee's regressions (Lee (2008) Eq. 4.24-4.28) and Ajayi's
(Ajayi (2011) Eq. 4.25-4.28) exist because gPROMS could not call that geometry. Here the
geometry is instead computed once per drum on a grid and interpolated:

- the cascade (mass-averaged release angle, vertical fall height and free-fall time against
  repose angle ``phi`` and flight loading factor ``f``) as tensor-product cubic splines
  (interpolating, not-a-knot) on a uniform (phi, f) grid; rpm and slope enter analytically
  (passive time Lee (2008) Eq. 3.4 from the release angle; fall height over ``cos(slope)``,
  fall time over ``sqrt(cos(slope))`` and axial step ``h tan(slope)``, as in
  `rotarydryer.geometry.unloading.cascade`);
- the holdups behind the design load and the loading factor (the first-unloading-flight holdup
  ``H0`` and the upper-half flight holdups ``H_i``, Lee (2008) Eq. 4.20-4.22) against
  ``phi`` as cubic splines split at every phase boundary of every flight, so each piece is
  smooth; the design load (Baker / Lee, Ajayi's 1.24 x Baker, Porter, Kelly) and the exact
  piecewise-linear inverse of Eq. 4.22 are then evaluated from them without iteration.

The tables hold Lee's continuum model; the finite-particle correction (``docs/dem.md``) moves the
phase boundaries with the particle size, so a drum with a particle diameter is evaluated directly.

Errors against the exact geometry, checked by ``tests/geometry/test_tabulated.py`` on random
points and on every shipped drum: below 1e-6 of the largest value of each quantity
(a full flight for holdups). Repose angles outside the table (default 10-80 deg) are computed
exactly, so the table never extrapolates. Tables are cached per drum (geometry, convention and
fall-height definition), so every cell and every solver iteration of
a dryer shares one.

On-disk cache (`cache_directory`): the fitted table (the cascade splines' cell polynomials and the
holdup pieces: what costs the 0.5-2 s build) is stored per drum as one ``.npz`` file, so a table
loads in milliseconds without SciPy's interpolation package. Its name is a sha256 of the entry's record (`_entry_meta`: the drum key, the digest of
the code that computes a table, which covers the grid parameters, and `CACHE_FORMAT`); the
file holds that record (``meta``) and a sha256 of the record and of every table array's name,
dtype, shape and bytes (``sha256``), next to the arrays, so data and check are replaced together.
A file is used only if it is a regular ``.npz`` of exactly these arrays with the expected dtypes
and shapes, its record is this entry's, its sha256 matches, its values are finite and its grid is
the drum's; any other file (changed, e.g. values multiplied by 3, non-finite, truncated, not an
archive, another program's or another entry's) is ignored with one `GeometryCacheWarning`
naming it and the reason, and the table is rebuilt and written over it with
`rotarydryer._io.atomic_output` (a temporary file renamed onto it, so concurrent processes
writing the same entry and readers only ever see whole files). The checks cost about 1 ms per
entry (mostly the sha256 of its 0.9 MB). The hash detects accidental and naive changes; it is not
a signature (whoever can write the cache directory can also write a matching hash).
"""

from __future__ import annotations

import functools
import hashlib
import hmac
import io
import json
import math
import os
import stat
import struct
import threading
import warnings
import zipfile
from collections import OrderedDict
from pathlib import Path

import numpy as np

from .. import _jit
from .._io import atomic_output
from .._validation import check_choice, check_range
from . import _cell_kernel as module
from .design_load import DESIGN_LOAD_METHODS, _area_weights, _invert_eq_4_22, _upper_flight_holdups
from .flights import TwoSectionFlight
from .unloading import PASSIVE_TIME_BRANCHES, CascadeSummary, first_unloading_angle

__all__ = ["GeometryCacheWarning", "GeometryTable", "geometry_table", "prune_disk_cache", "cache_limit_bytes"]

#: default table range of the repose angle, deg (outside: exact evaluation)
PHI_RANGE = (10.0, 80.0)
#: grid of the cascade table: intervals in phi per deg and in f over [0, 1]
N_PHI_PER_DEG = 2
N_F = 256
#: points per phase-boundary piece of the holdup splines (at least), and per deg
N_HOLDUP_PER_DEG = 10


def _cell_polynomials(spline, x, y):
    """Power-basis coefficients ``c[i, j, a, b]`` of the bicubic ``spline`` on each grid cell:
    ``spline(x_i + u, y_j + v) = sum_ab c_ab u^a v^b`` (the spline is one cubic per cell; the
    coefficients follow exactly from its values at 4 x 4 points of the closed cell)."""
    nx, ny = x.size - 1, y.size - 1
    vals = spline(np.linspace(x[0], x[-1], 3 * nx + 1), np.linspace(y[0], y[-1], 3 * ny + 1), grid=True)
    ix = 3 * np.arange(nx)[:, None] + np.arange(4)
    iy = 3 * np.arange(ny)[:, None] + np.arange(4)
    w = vals[ix[:, None, :, None], iy[None, :, None, :]]  # (nx, ny, 4, 4)
    ax = np.linalg.inv(np.vander((x[1] - x[0]) * np.arange(4) / 3.0, 4, increasing=True))
    ay = np.linalg.inv(np.vander((y[1] - y[0]) * np.arange(4) / 3.0, 4, increasing=True))
    return np.einsum("ai,xyij,bj->xyab", ax, w, ay)


def _powers(t):
    """``[1, t, t^2, t^3]`` per point, shape (n, 4)."""
    p = np.empty((t.size, 4))
    p[:, 0] = 1.0
    p[:, 1] = t
    np.multiply(t, t, out=p[:, 2])
    np.multiply(p[:, 2], t, out=p[:, 3])
    return p


class _PiecewiseTensorSpline:
    """Interpolating bicubic tensor-product splines of several quantities, one per piece of x
    between ``edges``, each on its own uniform grid ``xs[k]`` times the common uniform ``y``
    (not-a-knot, `scipy.interpolate.RectBivariateSpline`). Stored as one cubic per grid
    cell in the power basis, all quantities of a cell side by side, so a point costs one
    contiguous gather of 16 q coefficients and two Horner passes (no Python loop over pieces)."""

    #: the arrays that are the spline (what the on-disk cache stores; `fitted` makes them, `__init__` takes them)
    ARRAYS = ("edges", "blocks", "cell_off", "x0", "hx", "nx", "y_grid")

    def __init__(self, edges, blocks, cell_off, x0, hx, nx, y_grid):
        self.edges = np.asarray(edges, dtype=float)
        self.blocks = np.ascontiguousarray(blocks, dtype=float)  # (cells, q * 16)
        self.q = self.blocks.shape[1] // 16
        self.cell_off = np.asarray(cell_off, dtype=np.int64)
        self.x0, self.hx, self.nx = np.asarray(x0, float), np.asarray(hx, float), np.asarray(nx, np.int64)
        self.y_grid = np.asarray(y_grid, dtype=float)        # (y0, hy, ny)
        self.y0, self.hy, self.ny = float(y_grid[0]), float(y_grid[1]), int(y_grid[2])

    @classmethod
    def fitted(cls, edges, xs, y, values):
        """The splines of ``values`` (per piece: q arrays on ``xs[k]`` x ``y``), fitted by
        `scipy.interpolate.RectBivariateSpline`."""
        from scipy.interpolate import RectBivariateSpline  # only where a table is built (LAZY)

        blocks, cell_off, gx = [], [], []
        n = 0
        for x, vals in zip(xs, values):
            c = np.stack([_cell_polynomials(RectBivariateSpline(x, y, v, kx=3, ky=3, s=0), x, y) for v in vals],
                         axis=-1)  # (nx, ny, a, b, q)
            blocks.append(np.moveaxis(c, 3, 2).reshape(c.shape[0] * c.shape[1], -1))  # rows (b, a, q)
            cell_off.append(n)
            gx.append((float(x[0]), float(x[1] - x[0]), x.size - 1))
            n += blocks[-1].shape[0]
        x0, hx, nx = (np.array(v) for v in zip(*gx))
        return cls(edges, np.concatenate(blocks), cell_off, x0, hx, nx, (float(y[0]), float(y[1] - y[0]), y.size - 1))

    def arrays(self) -> dict:
        return {k: np.asarray(getattr(self, k)) for k in self.ARRAYS}

    def __call__(self, x, y):
        if self.cell_off.size == 1:
            i = np.minimum(np.maximum(((x - self.x0[0]) * (1.0 / self.hx[0])).astype(np.intp), 0), self.nx[0] - 1)
            u = x - (self.x0[0] + i * self.hx[0])
            cell = i * self.ny
        else:
            k = np.searchsorted(self.edges[1:-1], x, side="right")     # pieces below x (as many as edges <= x)
            x0, hx = self.x0[k], self.hx[k]
            i = np.minimum(np.maximum(((x - x0) / hx).astype(np.intp), 0), self.nx[k] - 1)
            u = x - (x0 + i * hx)
            cell = self.cell_off[k] + i * self.ny
        j = np.minimum(np.maximum(((y - self.y0) * (1.0 / self.hy)).astype(np.intp), 0), self.ny - 1)
        v = y - (self.y0 + j * self.hy)
        blk = self.blocks.take(cell + j, axis=0).reshape(x.size, 4, -1)  # (n, b, a q)
        # sum_b v^b c_b, then sum_a u^a r_a: two batched row-times-matrix products
        r = np.matmul(_powers(v)[:, None, :], blk).reshape(x.size, 4, self.q)
        return np.matmul(_powers(u)[:, None, :], r)[:, 0, :]


class _Breaks:
    """Interval lookup on sorted breakpoints without a binary search: a uniform table of bins
    gives each point the interval of its bin's start, then a vectorised step forward covers the
    (rare) bins that hold a breakpoint."""

    def __init__(self, x, n_bins=16384):
        self.x = np.asarray(x, dtype=float)
        self.lo, self.w = self.x[0], (self.x[-1] - self.x[0]) / n_bins
        starts = self.lo + self.w * np.arange(n_bins + 1)
        self.lut = np.clip(np.searchsorted(self.x, starts, side="right") - 1, 0, self.x.size - 2)
        self.last = self.x.size - 2

    def __call__(self, x):
        b = np.minimum(np.maximum(((x - self.lo) * (1.0 / self.w)).astype(np.intp), 0), self.lut.size - 1)
        i = self.lut[b]
        while True:
            step = (i < self.last) & (x >= self.x[np.minimum(i + 1, self.last + 1)])
            if not step.any():
                return i
            i = i + step


class _Cubic:
    """Cubic pieces with vector values, in `scipy.interpolate.PPoly`'s layout: coefficients ``c``
    (4, intervals, q), highest power first, breakpoints ``x``; ``rows`` the coefficients of each
    interval side by side (one contiguous gather per point, `_ppoly`)."""

    def __init__(self, c, x):
        self.c, self.x = np.asarray(c, dtype=float), np.asarray(x, dtype=float)
        self.rows = np.ascontiguousarray(np.moveaxis(self.c, 1, 0).reshape(self.c.shape[1], -1))


def _ppoly(p, breaks, x):
    """``p(x)`` of a cubic `scipy.interpolate.PPoly` with vector values (Horner, one gather
    of the interval's coefficients, kept contiguous in ``p.rows``)."""
    i = breaks(x)
    c = p.rows.take(i, axis=0).reshape(x.size, 4, -1)  # highest power first
    return np.matmul(_powers(x - p.x[i])[:, None, ::-1], c)[:, 0, :]


def _f_axis(f):
    """The cascade table's loading coordinate ``(2/pi) asin(sqrt(f))`` of loading factors ``f``."""
    return np.arcsin(np.sqrt(f)) * (2.0 / np.pi)


def _phi_grid(a, b):
    """The cascade table's repose angles (deg) on the piece [a, b] (uniform, at least 8 intervals)."""
    return np.linspace(a, b, max(8, int(math.ceil((b - a) * N_PHI_PER_DEG))) + 1)


def _holdup_breaks(drum, lo, hi, convention):
    """Repose angles in (lo, hi) where a holdup behind the design load changes phase
    (psi - phi crosses a phase boundary of Lee (2008) Fig. 4.6-4.9)."""

    c = drum._c
    psi0 = first_unloading_angle(drum, convention)
    n = math.ceil(drum.n_flights / 2) - 1
    psi = psi0 + c.psi_fl * np.arange(0, n + 1)
    offs = np.array([0.0, *c.breaks[1:]])
    b = (psi[:, None] - offs[None, :]).ravel()
    b = np.unique(np.round(b, 12))
    return b[(b > lo) & (b < hi)]


class GeometryTable:
    """Tabulated exact geometry of one drum; see the module docstring.

    Parameters
    ----------
    drum : FlightedDrum
    convention, fall_height : str
        As in `rotarydryer.geometry.unloading.cascade`.
    phi_range : (float, float)
        Repose angles (deg) covered by the tables; outside, the exact geometry is computed.
    """

    def __init__(self, drum, *, convention="root", fall_height="chord", phi_range=PHI_RANGE, _fitted=None):
        self.drum = drum
        self.convention, self.fall_height = convention, fall_height
        lo, hi = (float(v) for v in phi_range)
        self.phi_range = (lo, hi)
        # cascade: (phi, f) grids, rpm = 1 and slope = 0 (both analytic), one per phi piece between the
        # repose angles where the first unloading flight's holdup changes phase (kinks in phi)

        c = drum._c
        psi0 = first_unloading_angle(drum, convention)
        kinks = [psi0 - o for o in c.breaks[1:]]
        self._phi_edges = np.array([lo] + sorted(k for k in kinks if lo < k < hi) + [hi])
        # the table's second axis is s = (2/pi) asin(sqrt(f)): the averages go like sqrt(f) for nearly
        # empty flights and like sqrt(1 - f) for nearly full ones (the first unloading flight starts
        # discharging with dH/dpsi = 0), both smooth in s
        if _fitted is None:     # the exact geometry on the grids, fitted: the costly part (the on-disk cache keeps it)
            self._cascade, coef, brk = self._fit(drum, convention, fall_height, lo, hi)
        else:
            self._cascade = _PiecewiseTensorSpline(*(_fitted[k] for k in _PiecewiseTensorSpline.ARRAYS))
            coef, brk = _fitted["holdup_coef"], _fitted["holdup_breaks"]
        self._holdups = _Cubic(coef, brk)
        self.n_upper = coef.shape[-1] - 1
        # (H0, H0 + 2 sum H_i): what the design-load methods need (Lee (2008) Eq. 4.20)
        self._design = _Cubic(np.stack([coef[..., 0], coef[..., 0] + 2.0 * coef[..., 1:].sum(-1)], axis=-1), brk)
        self._breaks = _Breaks(brk)

    def _fit(self, drum, convention, fall_height, lo, hi):
        """(cascade splines, holdup spline coefficients, their breakpoints) from the exact geometry."""
        from scipy.interpolate import CubicSpline  # only where a table is built (LAZY)

        root_f = np.linspace(0.0, 1.0, N_F + 1)
        f = np.sin(0.5 * np.pi * root_f) ** 2
        xs, vals = [], []
        for a, b in zip(self._phi_edges[:-1], self._phi_edges[1:]):
            phi = _phi_grid(a, b)
            pp, ff = np.meshgrid(phi, f, indexing="ij")
            cs = drum.cascade(pp, ff, rpm=1.0, slope=0.0, fall_height=fall_height, convention=convention)
            xs.append(phi)
            vals.append([cs.mean_release_angle, cs.mean_fall_height, cs.mean_fall_time])
        cascade = _PiecewiseTensorSpline.fitted(self._phi_edges, xs, root_f, vals)
        # holdups H0 and H_i against phi, split at the phase boundaries
        edges = np.concatenate([[lo], _holdup_breaks(drum, lo, hi, convention), [hi]])
        xs, cs_ = [], []
        for a, b in zip(edges[:-1], edges[1:]):
            m = max(8, int(math.ceil((b - a) * N_HOLDUP_PER_DEG)))
            x = np.linspace(a, b, m + 1)
            h0, hi_ = _upper_flight_holdups(drum, x, convention)
            y = np.concatenate([h0[:, None], hi_], axis=1)
            p = CubicSpline(x, y, axis=0, bc_type="not-a-knot")
            xs.append(p.x[:-1])
            cs_.append(p.c)
        return cascade, np.concatenate(cs_, axis=1), np.concatenate(xs + [[hi]])

    def __repr__(self):
        return f"GeometryTable({self.drum!r}, phi {self.phi_range[0]:g}-{self.phi_range[1]:g} deg)"

    def _inside(self, phi):
        return (phi >= self.phi_range[0]) & (phi <= self.phi_range[1])

    # ----------------------------------------------------------------- holdups, design load
    def upper_flight_holdups(self, phi):
        """``(H0, H_i)`` at design (m^2), as `rotarydryer.geometry.design_load._upper_flight_holdups`."""
        phi = np.asarray(phi, dtype=float)
        flat = phi.ravel()
        y = np.empty((flat.size, self.n_upper + 1))
        ins = self._inside(flat)
        if ins.all():
            y[:] = _ppoly(self._holdups, self._breaks, flat)
        else:
            if ins.any():
                y[ins] = _ppoly(self._holdups, self._breaks, flat[ins])
            if (~ins).any():
                h0, hi = _upper_flight_holdups(self.drum, flat[~ins], self.convention)
                y[~ins] = np.concatenate([h0[:, None], hi], axis=1)
        y = y.reshape(phi.shape + (self.n_upper + 1,))
        return y[..., 0], y[..., 1:]

    def design_load_area(self, repose_angle, *, method="lee2008"):
        """Design-load area, m^2 (`rotarydryer.geometry.design_load.design_load_area`)."""
        check_choice("method", method, DESIGN_LOAD_METHODS)
        phi = np.asarray(repose_angle, dtype=float)
        flat = phi.ravel()
        ins = self._inside(flat)
        if ins.all():
            y = _ppoly(self._design, self._breaks, flat)
        else:
            h0, hi = self.upper_flight_holdups(flat)
            y = np.stack([h0, h0 + 2.0 * hi.sum(-1)], axis=-1)
        h0, baker = y[:, 0].reshape(phi.shape), y[:, 1].reshape(phi.shape)  # Lee (2008) Eq. 4.20 = Baker (1988)
        a, b = _area_weights(self.drum.n_flights, method)
        return a * h0 if b == 0.0 else b * baker

    def loading_factor(self, dryer_loading, repose_angle, smoothing=0.0):
        """Flight loading factor (Lee (2008) Eq. 4.22 inverted exactly, as
        `rotarydryer.geometry.design_load.loading_factor`) from tabulated holdups."""

        d, phi = np.broadcast_arrays(np.asarray(dryer_loading, float), np.asarray(repose_angle, float))
        if not np.all(d >= 0.0):
            check_range("dryer_loading", d, 0.0, math.inf, low_inclusive=True)
        h0, hi = self.upper_flight_holdups(phi)
        return _invert_eq_4_22(d, h0, hi, smoothing)

    # ----------------------------------------------------------------- cascade
    def cascade(self, repose_angle, loading_factor=1.0, *, rpm, slope=0.0, passive_time_branch="eq3.4"):
        """Mass-averaged cascade properties (free fall), as `rotarydryer.geometry.unloading.cascade`;
        the discharge start angle and initial holdup are not tabulated (NaN, as in Lee's regressions)."""
        check_choice("passive_time_branch", passive_time_branch, PASSIVE_TIME_BRANCHES)
        if not (isinstance(rpm, (int, float)) and 0.0 < rpm < math.inf):   # plain floats: the solvers' calls
            rpm = check_range("rpm", rpm, 0.0, math.inf, unit="rpm")
        if not (isinstance(slope, (int, float)) and -45.0 < slope < 45.0):
            slope = check_range("slope", slope, -45.0, 45.0, unit="deg")
        rpm, slope = float(rpm), float(slope)
        phi, f = np.broadcast_arrays(np.asarray(repose_angle, float), np.asarray(loading_factor, float))
        shape = phi.shape
        phi, f = phi.ravel(), f.ravel()
        if not np.all((f >= 0.0) & (f <= 1.0)):
            check_range("loading_factor", f, 0.0, 1.0, low_inclusive=True, high_inclusive=True)
        ins = self._inside(phi)
        out = np.empty((phi.size, 3))
        if ins.all():
            out[:] = self._cascade(phi, _f_axis(f))
        else:
            if ins.any():
                out[ins] = self._cascade(phi[ins], _f_axis(f[ins]))
            if (~ins).any():
                ex = self.drum.cascade(phi[~ins], f[~ins], rpm=1.0, slope=0.0, fall_height=self.fall_height,
                                       convention=self.convention)
                out[~ins] = np.stack([ex.mean_release_angle, ex.mean_fall_height, ex.mean_fall_time], axis=-1)
        psi_m, h, t = (out[:, k].reshape(shape) for k in range(3))
        s = math.radians(float(slope))
        cos_s = math.cos(s)
        arc = 2.0 * psi_m - 180.0  # Lee (2008) Eq. 3.4
        omega = 6.0 * float(rpm)
        t_p = arc / omega if passive_time_branch == "eq3.4" else (360.0 - arc) / omega
        start = np.full(shape, np.nan)
        return CascadeSummary(mean_release_angle=psi_m, mean_fall_height=h / cos_s,
                              mean_fall_time=t / math.sqrt(cos_s), passive_time=t_p,
                              discharge_start_angle=start, initial_holdup_area=start.copy(),
                              mean_axial_step=h * math.tan(s))


    # ----------------------------------------------------------------- one pass per cell (compiled)
    def cell_values(self, repose_angle, bulk_density, passive_mass, *, length, fouling=0.0, method="lee2008",
                    smoothing=0.0, rpm, slope=0.0, passive_time_branch="eq3.4", fixed_loading=False):
        """What a flighted cell's coefficients need, in one compiled pass per cell, or None.

        Design load ``rho L A_des(phi) (1 - fouling)`` (kg; Lee (2008) Eq. 4.20-4.21), loading
        factor at the dryer loading ``M_P / M_des`` (Lee (2008) Eq. 4.22 inverted, ``smoothing``
        as in `loading_factor`, clipped to [1e-6, 1]), and the cascade at that loading
        (passive time s, fall height m, fall time s; `cascade`), for 1-D arrays of repose
        angle, bulk density and passive mass (``fixed_loading``: full flights, f = 1). The same
        numbers, to rounding, as `design_load_area`, `loading_factor` and
        `cascade` in turn (their NumPy composition is the reference). None when the
        compiled kernels are off (`rotarydryer._jit`), a repose angle lies outside the
        table, or an input or result is not finite: the caller then composes those methods,
        which check their inputs and name what is wrong."""
        phi = np.asarray(repose_angle, dtype=float)
        if not _jit.enabled() or phi.ndim != 1:
            return None
        # what stays fixed for a law (method, passive-time branch, slope): checked and packed once
        slope = float(slope)
        key = (method, passive_time_branch, slope)
        cache = self.__dict__.setdefault("_kernel_fixed", {})
        try:
            fixed = cache.get(key)
        except TypeError:       # an unhashable choice: named by check_choice below
            fixed = None
        if fixed is None:
            check_choice("method", method, DESIGN_LOAD_METHODS)
            check_choice("passive_time_branch", passive_time_branch, PASSIVE_TIME_BRANCHES)
            if not -45.0 < slope < 45.0:
                return None
            sp = self._cascade
            eq34 = passive_time_branch == "eq3.4"
            fixed = (_area_weights(self.drum.n_flights, method),
                     (self._breaks.x, self._design.rows, self._holdups.rows, self.n_upper, sp.edges,
                      sp.x0.astype(float), sp.hx.astype(float), sp.nx.astype(np.int64), sp.cell_off.astype(np.int64),
                      sp.y0, sp.hy, sp.ny, sp.blocks, 1.0 if eq34 else -1.0, 0.0 if eq34 else 360.0),
                     (math.cos(math.radians(slope)), float(self.phi_range[0]), float(self.phi_range[1])))
            cache[key] = fixed
        (a_h0, a_baker), tables, tail = fixed
        rpm = float(rpm)
        if not 0.0 < rpm < math.inf:
            return None
        n = phi.size
        rho, mp = (a if type(a) is np.ndarray and a.shape == phi.shape and a.dtype == float
                   else np.broadcast_to(np.asarray(a, dtype=float), phi.shape) for a in (bulk_density, passive_mass))
        out = np.empty((5, n))
        try:
            # False: a repose angle outside the table, or an input or result not finite
            fn = module.compiled()
            if fn is None:
                return None
            ok = fn(np.ascontiguousarray(phi), np.ascontiguousarray(rho), np.ascontiguousarray(mp),
                                            float(length), 1.0 - float(fouling), a_h0, a_baker, float(smoothing),
                                            bool(fixed_loading), *tables, 6.0 * rpm, *tail, out)
        except Exception as exc:    # a numba that cannot compile here: the NumPy composition instead
            _jit.disable(f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}")
            return None
        if not ok:
            return None
        return tuple(out)


_cache: OrderedDict = OrderedDict()
_lock = threading.Lock()
#: drums whose tables are kept (least recently used dropped first)
MAX_TABLES = 32
#: environment variable naming the directory of the on-disk table cache; "off" disables it
CACHE_ENV = "ROTARYDRYER_CACHE_DIR"
#: environment variable: the on-disk cache's size limit in MB (default `CACHE_MAX_MB`)
CACHE_MAX_ENV = "ROTARYDRYER_CACHE_MAX_MB"
#: the on-disk cache's default size limit, MB: about 140 drums of 14 MB (a CI run of the tests builds about 60);
#: after a table is written, the least recently used entries beyond it are removed
CACHE_MAX_MB = 2000.0
#: version of the on-disk entry format (part of each entry's key and of its stored record)
CACHE_FORMAT = 3
#: the arrays of an entry's fitted table: dtype and number of dimensions
_TABLE_ARRAYS = {"edges": ("<f8", 1), "blocks": ("<f8", 2), "cell_off": ("<i8", 1), "x0": ("<f8", 1),
                 "hx": ("<f8", 1), "nx": ("<i8", 1), "y_grid": ("<f8", 1), "holdup_coef": ("<f8", 3),
                 "holdup_breaks": ("<f8", 1), "phi_range": ("<f8", 1)}
#: every array of an entry file: the table, its record (``meta``: what it was built from) and the
#: sha256 of both (``sha256``)
_FILE_ARRAYS = frozenset(_TABLE_ARRAYS) | {"meta", "sha256"}
#: larger files are not ours (an entry is about 14 MB: the cascade's spline coefficients) and are not read
_MAX_FILE_BYTES = 64 << 20
#: bad files already reported by this process: (path, inode, size, mtime) -> one warning per file
_warned: set = set()


class GeometryCacheWarning(RuntimeWarning):
    """A file of the on-disk geometry table cache was ignored and the table rebuilt (the file is
    replaced atomically); the message names the file and the reason."""


def cache_directory():
    """Directory of the on-disk table cache, or None when disabled: ``$ROTARYDRYER_CACHE_DIR``
    ("off" disables), else ``$XDG_CACHE_HOME/rotarydryer/geometry`` (``~/.cache/...``)."""

    env = os.environ.get(CACHE_ENV)
    if env is not None:
        return None if env.strip().lower() in ("", "off", "0", "none") else Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "rotarydryer" / "geometry"


@functools.lru_cache(maxsize=1)
def _source_digest() -> str:
    """Digest of the code that computes a table (this module and the exact geometry's): a table
    cached by other code is never used."""

    h = hashlib.sha256()
    here = Path(__file__).parent
    for name in ("tabulated.py", "drum.py", "unloading.py", "design_load.py", "flights.py", "polygon.py"):
        h.update((here / name).read_bytes())
    h.update(repr((PHI_RANGE, N_PHI_PER_DEG, N_F, N_HOLDUP_PER_DEG)).encode())
    return h.hexdigest()[:16]


def cache_limit_bytes() -> int:
    """The on-disk cache's size limit in bytes: ``$ROTARYDRYER_CACHE_MAX_MB`` (a number of MB above 0), else
    `CACHE_MAX_MB`. A value that is not such a number is refused, naming the variable."""
    env = os.environ.get(CACHE_MAX_ENV)
    if env is None or not env.strip():
        return int(CACHE_MAX_MB * 1e6)
    try:
        mb = float(env)
    except ValueError:
        mb = math.nan
    if not (0.0 < mb < 1e12):
        raise ValueError(f"{CACHE_MAX_ENV} = {env!r}: the geometry cache's size limit must be a number of MB in "
                         f"(0, 1e12) (default {CACHE_MAX_MB:g}; {CACHE_ENV}=off turns the disk cache off)")
    return int(mb * 1e6)


def _is_entry_name(name: str) -> bool:
    """An entry file's name (`_disk_path`): 32 hexadecimal digits and ``.npz``; nothing else in the directory is
    ever removed."""
    return len(name) == 36 and name.endswith(".npz") and all(c in "0123456789abcdef" for c in name[:32])


def prune_disk_cache(directory=None, *, limit_bytes: int | None = None, keep=None) -> list[Path]:
    """Remove the least recently used entries (oldest modification time: a load touches its file) of the on-disk
    cache until its entries take at most ``limit_bytes`` (default `cache_limit_bytes`); ``keep`` (a path) is never
    removed. Only entry files are counted and removed (`_is_entry_name`, regular files); errors are ignored (another
    process may prune at the same time). Returns the paths removed."""
    directory = cache_directory() if directory is None else Path(directory)
    if directory is None:
        return []
    limit = cache_limit_bytes() if limit_bytes is None else int(limit_bytes)
    entries = []
    try:
        with os.scandir(directory) as it:
            for e in it:
                if not _is_entry_name(e.name):
                    continue
                try:
                    st = e.stat(follow_symlinks=False)
                except OSError:
                    continue
                if stat.S_ISREG(st.st_mode):
                    entries.append((st.st_mtime_ns, e.name, st.st_size))
    except OSError:
        return []
    total = sum(size for *_, size in entries)
    keep_name = Path(keep).name if keep is not None else None
    removed: list[Path] = []
    for _, name, size in sorted(entries):
        if total <= limit:
            break
        if name == keep_name:
            continue
        path = Path(directory) / name
        try:
            path.unlink()
        except FileNotFoundError:       # removed by another process: no longer counted either
            pass
        except OSError:
            continue
        else:
            removed.append(path)
        total -= size
    return removed


def _entry_meta(key) -> str:
    """The record of what an entry is built from: the drum key (dimensions, convention, fall
    height), the code digest (`_source_digest`, which covers the grid parameters) and the
    entry format. It names the file and is stored in it, so a file of another entry is not ours."""
    return json.dumps({"format": CACHE_FORMAT, "code": _source_digest(), "key": list(key)}, separators=(",", ":"))


def _content_digest(meta: str, arrays) -> str:
    """sha256 of an entry: its record and every table array (name, dtype, shape and bytes)."""
    h = hashlib.sha256(b"rotarydryer.geometry.tabulated\0")
    h.update(meta.encode())
    for name in sorted(_TABLE_ARRAYS):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"\0{name}:{a.dtype.str}:{a.shape}\0".encode())
        h.update(a.data)   # the buffer itself, no copy
    return h.hexdigest()


def _to_arrays(t: GeometryTable) -> dict:
    """The fitted table (the cascade splines and the holdup pieces: what costs the build), as plain arrays."""
    a = t._cascade.arrays()
    a.update(holdup_coef=t._holdups.c, holdup_breaks=t._holdups.x, phi_range=np.array(t.phi_range))
    return {k: np.ascontiguousarray(a[k], dtype=_TABLE_ARRAYS[k][0]) for k in _TABLE_ARRAYS}


def _from_arrays(drum, a, convention, fall_height) -> GeometryTable:
    table = GeometryTable(drum, convention=convention, fall_height=fall_height,
                          phi_range=tuple(float(v) for v in a["phi_range"]), _fitted=a)
    if not np.array_equal(table._phi_edges, a["edges"]):
        raise ValueError("its grid does not fit the drum")
    return table


def _disk_path(key):

    d = cache_directory()
    if d is None:
        return None
    return d / f"{hashlib.sha256(_entry_meta(key).encode()).hexdigest()[:32]}.npz"


def _check_table(f, meta):
    """The table arrays of the open entry ``f``, and None; or None and why the file is not a valid
    entry (wrong arrays, dtypes or shapes, another entry's record, a content hash that does not
    match, non-finite values)."""
    names = set(f.files)
    if names != _FILE_ARRAYS:
        return None, f"not a geometry table of this code (its arrays: {', '.join(sorted(names)) or 'none'})"
    stored_meta, stored_hash = f["meta"], f["sha256"]
    if stored_meta.shape != () or stored_meta.dtype.kind != "U" or str(stored_meta[()]) != meta:
        return None, "not this entry (written for another drum, convention or code version)"
    a = {k: f[k] for k in _TABLE_ARRAYS}
    for k, (dtype, ndim) in _TABLE_ARRAYS.items():
        if a[k].dtype.str != dtype or a[k].ndim != ndim:
            return None, f"array {k!r} is {a[k].dtype.str} with shape {a[k].shape}, not {ndim}-d {dtype}"
    if (stored_hash.shape != () or stored_hash.dtype.kind != "U"
            or not hmac.compare_digest(str(stored_hash[()]), _content_digest(meta, a))):
        return None, "its content does not match its sha256 (changed after it was written)"
    pieces = a["x0"].size
    ny = a["y_grid"][2] if a["y_grid"].size == 3 else -1
    ok = (pieces >= 1 and a["edges"].size == pieces + 1 and a["hx"].size == pieces and a["nx"].size == pieces
          and a["cell_off"].size == pieces and ny == N_F and np.all(a["nx"] >= 1)
          and a["blocks"].shape == (int(np.sum(a["nx"])) * N_F, 3 * 16)
          and a["holdup_coef"].shape[:1] == (4,) and a["holdup_coef"].shape[1] + 1 == a["holdup_breaks"].size
          and a["phi_range"].shape == (2,))
    if not ok:
        return None, ("wrong shapes (" + ", ".join(f"{k} {a[k].shape}" for k in ("edges", "blocks", "nx", "y_grid",
                                                                                  "holdup_coef", "holdup_breaks"))
                      + ")")
    if not all(np.isfinite(v).all() for v in a.values()):
        return None, "it holds non-finite values"
    if tuple(a["phi_range"].tolist()) != PHI_RANGE:
        return None, f"its repose-angle range {a['phi_range'].tolist()} is not the tables' {list(PHI_RANGE)}"
    return a, None


class _StoredArrays(dict):
    """The arrays of an entry by name (``.files`` as `numpy.lib.npyio.NpzFile` has it)."""

    @property
    def files(self):
        return list(self)


def _read_stored_npz(fh):
    """The arrays of the uncompressed ``.npz`` open as ``fh`` (what `numpy.savez` writes), each read by one
    ``readinto`` at its offset in the file into an aligned array of its own: no pass of the zip's CRC-32 (the
    entry's own sha256 checks the content in `_check_table`). `numpy.load` reads a member in 256 kB pieces through
    the zip layer: a 14 MB table took 10-40 ms of CPU, this 3-5 ms. (Arrays mapped in place would be cheaper to
    open but are not aligned to 8 bytes inside a zip member, which made every later gather from them 16x slower.)
    None (the caller then uses `numpy.load`) for anything else: a compressed or encrypted member, a member that is
    not a plain ``.npy`` of version 1 or 2, object arrays, or sizes that do not add up."""
    out = _StoredArrays()
    with zipfile.ZipFile(fh) as zf:
        infos = zf.infolist()
    for info in infos:
        if (info.compress_type != zipfile.ZIP_STORED or info.flag_bits & 0x1 or not info.filename.endswith(".npy")
                or info.compress_size != info.file_size):
            return None
        fh.seek(info.header_offset)
        local = fh.read(30)
        if len(local) != 30 or local[:4] != b"PK\x03\x04":
            return None
        n_name, n_extra = struct.unpack("<HH", local[26:30])
        start = info.header_offset + 30 + n_name + n_extra
        fh.seek(start)
        head = io.BytesIO(fh.read(min(info.file_size, 1 << 16)))
        version = np.lib.format.read_magic(head)
        if version == (1, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_1_0(head)
        elif version == (2, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_2_0(head)
        else:
            return None
        count = math.prod(shape)
        if dtype.hasobject or head.tell() + count * dtype.itemsize != info.file_size:
            return None
        arr = np.empty(count, dtype=dtype)
        fh.seek(start + head.tell())
        if count and fh.readinto(memoryview(arr.view(np.uint8))) != arr.nbytes:
            return None
        out[info.filename[:-4]] = arr.reshape(shape[::-1]).T if fortran else arr.reshape(shape)
    return out


def _load_disk(path, key, drum, convention, fall_height):
    """``(table, None)`` from a valid entry file; ``(None, None)`` when there is none; ``(None,
    reason)`` when the file at ``path`` is not a valid entry (see `_check_table`; also not
    a regular file, too large, not an ``.npz`` archive, truncated or unreadable)."""
    if path is None:
        return None, None
    try:
        st = path.stat()
    except (FileNotFoundError, NotADirectoryError):   # no entry (or no cache directory)
        return None, None
    except OSError as exc:
        return None, f"it cannot be read ({exc.strerror or exc})"
    if not stat.S_ISREG(st.st_mode):
        return None, "it is not a regular file"
    if st.st_size > _MAX_FILE_BYTES:
        return None, f"it is too large for a geometry table ({st.st_size / 1e6:.3g} MB)"
    try:
        with open(path, "rb") as fh:
            if fh.read(4) != b"PK\x03\x04":
                return None, "it is not an .npz archive"
            fh.seek(0)
            stored = _read_stored_npz(fh)
            if stored is not None:
                a, reason = _check_table(stored, _entry_meta(key))
            else:
                fh.seek(0)
                with np.load(fh, allow_pickle=False) as f:
                    a, reason = _check_table(f, _entry_meta(key))
    except FileNotFoundError:   # removed by another process's prune since the stat: no entry
        return None, None
    except Exception as exc:   # noqa: BLE001 - a truncated or damaged archive fails in many ways
        return None, f"it is truncated or unreadable ({type(exc).__name__}: {' '.join(str(exc).split())[:200]})"
    if a is None:
        return None, reason
    try:
        return _from_arrays(drum, a, convention, fall_height), None
    except Exception as exc:   # noqa: BLE001 - whatever a stored grid breaks, the table is rebuilt
        return None, str(exc) if isinstance(exc, ValueError) else f"it cannot be used ({type(exc).__name__}: {exc})"


def _warn_bad_file(path, reason):
    """One `GeometryCacheWarning` per bad file (the same file found again, e.g. when it
    cannot be replaced, is not reported twice by a process)."""
    try:
        st = path.stat()
        ident = (str(path), st.st_ino, st.st_size, st.st_mtime_ns)
    except OSError:
        ident = (str(path), reason)
    with _lock:
        if ident in _warned:
            return
        _warned.add(ident)
    warnings.warn(f"rotarydryer: ignoring the geometry table cache file {str(path)!r}: {reason}; "
                  "the table is rebuilt and the file replaced", GeometryCacheWarning, stacklevel=3)


def _touch(path) -> None:
    """Mark an entry as just used (its modification time: `prune_disk_cache` removes the least recently used
    first); a read-only cache is left as it is."""
    try:
        os.utime(path)
    except OSError:
        pass


def _save_disk(path, table, key, limit=None):
    """Write the table's entry to ``path`` atomically (`rotarydryer._io.atomic_output`: a
    reader, or another process writing the same entry, only ever sees a whole file); a grid with
    non-finite values is not stored."""
    if path is None:
        return
    limit = cache_limit_bytes() if limit is None else limit
    arrays = _to_arrays(table)
    if not all(np.isfinite(v).all() for v in arrays.values()):
        return
    meta = _entry_meta(key)
    try:
        with atomic_output(path) as tmp, open(tmp, "wb") as fh:
            np.savez(fh, meta=np.array(meta), sha256=np.array(_content_digest(meta, arrays)), **arrays)
    except (OSError, ValueError):   # read-only or full disk: the table lives in memory only
        return
    prune_disk_cache(path.parent, limit_bytes=limit, keep=path)


@functools.lru_cache(maxsize=256)
def _flight_text(flight) -> str:
    """The sections of a (frozen, hashable) flight as the key's text, once per flight value: its polygon
    (`FlightedDrum.profile`: a two-section flight converted and checked) cost 0.2 ms each time a study's run
    rebuilt its sections."""
    poly = flight.to_polygon() if isinstance(flight, TwoSectionFlight) else flight
    return ";".join(f"{float(a)!r},{float(b)!r}" for a, b in poly.segments)


def _key(drum, *, convention="root", fall_height="chord") -> tuple:
    """What a table is computed from: the drum's dimensions, its flight (sections as used: a serrated
    tip by its effective length) and held-area computation, the convention and the fall height."""
    try:
        segs = _flight_text(drum.flight)
    except TypeError:       # an unhashable flight: the same text, not remembered
        segs = _flight_text.__wrapped__(drum.flight)
    return (float(drum.radius), int(drum.n_flights), segs, drum.geometry, convention, fall_height)


def geometry_table(drum, *, convention="root", fall_height="chord") -> GeometryTable:
    """The `GeometryTable` of ``drum``, built once and cached (keyed by the drum's
    dimensions, the convention and the fall-height definition): in memory for the process and on
    disk (`cache_directory`; tables of other code versions are never read), so a command
    line run does not pay the 0.5-1 s build of each drum again. An on-disk entry is used only if
    it passes its checks (its record, array shapes, sha256 and finite values); a file that does
    not is rebuilt and replaced, with one `GeometryCacheWarning`."""
    key = _key(drum, convention=convention, fall_height=fall_height)
    with _lock:
        table = _cache.get(key)
        if table is not None:
            _cache.move_to_end(key)
            return table
    path = _disk_path(key)
    limit = cache_limit_bytes() if path is not None else None     # a bad limit is refused before any work
    table, reason = _load_disk(path, key, drum, convention, fall_height)
    if table is None:
        if reason is not None:
            _warn_bad_file(path, reason)
        table = GeometryTable(drum, convention=convention, fall_height=fall_height)
        _save_disk(path, table, key, limit)
    else:
        _touch(path)
    with _lock:
        _cache[key] = table
        while len(_cache) > MAX_TABLES:
            _cache.popitem(last=False)
    return table
