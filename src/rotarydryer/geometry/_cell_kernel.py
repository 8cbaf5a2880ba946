"""Compiled form of `rotarydryer.geometry.tabulated.GeometryTable.cell_values` (numba, optional).

One pass per cell through what a flighted cell's coefficients need from its drum's tables: the
design load (Lee (2008) Eq. 4.20-4.21 from the tabulated holdups), the loading factor (Lee (2008)
Eq. 4.22 inverted, with the thermal model's smoothing of its kinks) and the cascade (Lee (2008)
Eq. 3.3-3.6 from the tabulated splines, passive time Lee (2008) Eq. 3.4). The NumPy reference is the
composition of the table's own methods (``GeometryTable.cell_values`` without numba); both give
the same numbers to rounding (``tests/geometry/test_cell_kernel.py``). Plain loops, so the
module imports without numba; it is only called compiled (`rotarydryer._jit`).
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import aot, kernel

#: the functions the kernel calls, by name: compiled with it (`compiled`)
_HELPERS: dict = {}


def _helper(fn):
    """A function the kernel calls: plain Python until `compiled` puts its compiled form in this
    module's namespace (numba resolves the kernel's globals when it compiles it)."""
    _HELPERS[fn.__name__] = fn
    return fn


@_helper
def _interval(x, v):
    """Index i of the interval [x[i], x[i+1]) holding v, clipped to the first and last interval
    (``_Breaks`` of the tabulated module)."""
    i = np.searchsorted(x, v, side="right") - 1
    return min(max(i, 0), x.size - 2)


@_helper
def _inverse_eq_4_22(d, h0, hold, nu, smoothing, r, bp, g, s):
    """Lee (2008) Eq. 4.22 inverted at dryer loading ``d`` for the holdups H0 = ``h0`` and H_i =
    ``hold[1:nu+1]`` (``design_load._invert_eq_4_22`` and ``_smoothed_inverse``, one cell);
    r, bp, g, s: work arrays of nu, nu + 2, nu + 2 and nu + 2 elements."""
    for i in range(nu):             # the ratios, sorted by insertion (few, and nearly in order)
        v = min(max(hold[1 + i] / h0, 0.0), 1.0)
        j = i
        while j > 0 and r[j - 1] > v:
            r[j] = r[j - 1]
            j -= 1
        r[j] = v
    bp[0] = 0.0
    for i in range(nu):
        bp[1 + i] = r[i]
    bp[nu + 1] = 1.0
    # g(b_k) = b_k + 2 (sum_{i<k} r_i + (n - k) b_k), k <= n; g(1) = 1 + 2 sum r
    csum = 0.0
    for k in range(nu + 2):
        below = min(k, nu)
        g[k] = bp[k] + 2.0 * (csum + (nu - below) * bp[k])
        if k < nu:
            csum += r[k]
    if smoothing > 0.0:
        # f(d) through (g_k / g_end, b_k), flat beyond d = 1, as a sum of rounded ramps
        w2 = smoothing * smoothing
        g_end = g[nu + 1]
        last = 0.0
        have = False
        for k in range(nu + 1):
            dd = g[k + 1] / g_end - g[k] / g_end
            if dd > 1e-15:
                last = (bp[k + 1] - bp[k]) / dd
                have = True
            elif not have:
                last = 0.0
            s[k] = last
        s[nu + 1] = 0.0
        x0 = d - g[0] / g_end
        f = s[0] * 0.5 * (x0 + math.sqrt(x0 * x0 + w2))
        for k in range(nu + 1):
            x = d - g[k + 1] / g_end
            f += (s[k + 1] - s[k]) * (0.5 * (x + math.sqrt(x * x + w2)))
        return min(max(f, 0.0), 1.0)
    if d >= 1.0:
        return 1.0
    target = d * g[nu + 1]
    seg = -1
    for k in range(nu + 2):
        if g[k] < target:
            seg += 1
    seg = min(max(seg, 0), nu)
    g0, g1, b0, b1 = g[seg], g[seg + 1], bp[seg], bp[seg + 1]
    f = b0 + (target - g0) * (b1 - b0) / (g1 - g0) if g1 > g0 else b0
    return min(max(f, 0.0), 1.0)


def _cell_values(phi, rho, mp, length, keep, a_h0, a_baker, smoothing, fixed, brk, design_rows, hold_rows, nu,
                 edges, x0, hx, nx, cell_off, y0, hy, ny, blocks, arc_sign, arc_offset, omega, cos_s, phi_lo, phi_hi,
                 out):
    """out[0..4, :] = design load (kg), loading factor, passive time (s), fall height (m), fall time (s);
    ``fixed``: the loading factor is 1 (the section's fixed loading state) instead of Eq. 4.22's.
    Returns False (``out`` incomplete) at the first repose angle outside [phi_lo, phi_hi], bulk density
    or passive mass not finite, or result not finite: the caller then takes the checked NumPy path."""
    r = np.empty(nu)
    bp = np.empty(nu + 2)
    g = np.empty(nu + 2)
    s = np.empty(nu + 2)
    hold = np.empty(nu + 1)
    vals = np.empty(3)
    npieces = x0.size
    sq = math.sqrt(cos_s)
    for n in range(phi.size):
        p = phi[n]
        if not (phi_lo <= p <= phi_hi and math.isfinite(rho[n]) and math.isfinite(mp[n])):
            return False
        # tabulated holdups (cubic pieces, highest power first): design-load areas and H0, H_i
        i = _interval(brk, p)
        t = p - brk[i]
        t2 = t * t
        t3 = t2 * t
        h0 = t3 * design_rows[i, 0] + t2 * design_rows[i, 2] + t * design_rows[i, 4] + design_rows[i, 6]
        baker = t3 * design_rows[i, 1] + t2 * design_rows[i, 3] + t * design_rows[i, 5] + design_rows[i, 7]
        q = nu + 1
        for j in range(q):
            hold[j] = (t3 * hold_rows[i, j] + t2 * hold_rows[i, q + j] + t * hold_rows[i, 2 * q + j]
                       + hold_rows[i, 3 * q + j])
        area = a_h0 * h0 + a_baker * baker
        des = rho[n] * length * area * keep
        if fixed:                   # the fixed loading state: full flights
            f = 1.0
        else:
            d = max(mp[n] / des, 1e-6)
            f = _inverse_eq_4_22(d, hold[0], hold, nu, smoothing, r, bp, g, s)
            f = min(max(f, 1e-6), 1.0)
        # cascade spline at (phi, (2/pi) asin(sqrt(f)))
        y = math.asin(math.sqrt(f)) * (2.0 / math.pi)
        k = 0
        if npieces > 1:
            for e in range(1, edges.size - 1):
                if p >= edges[e]:
                    k += 1
        ci = int((p - x0[0]) * (1.0 / hx[0])) if npieces == 1 else int((p - x0[k]) / hx[k])
        ci = min(max(ci, 0), nx[k] - 1)
        u = p - (x0[k] + ci * hx[k])
        cj = min(max(int((y - y0) * (1.0 / hy)), 0), ny - 1)
        v = y - (y0 + cj * hy)
        row = cell_off[k] + ci * ny + cj
        vals[:] = 0.0
        up = 1.0
        for a in range(4):
            vp = 1.0
            for b in range(4):
                base = b * 12 + a * 3
                c = up * vp
                vals[0] += c * blocks[row, base]
                vals[1] += c * blocks[row, base + 1]
                vals[2] += c * blocks[row, base + 2]
                vp *= v
            up *= u
        arc = 2.0 * vals[0] - 180.0
        out[0, n] = des
        out[1, n] = f
        out[2, n] = (arc_offset + arc_sign * arc) / omega
        out[3, n] = vals[1] / cos_s
        out[4, n] = vals[2] / sq
        for c in range(5):
            if not math.isfinite(out[c, n]):
                return False
    return True


_COMPILED: list = []
#: `_cell_values`'s argument kinds (`rotarydryer._aot`) and what the ahead-of-time module compiles
_KINDS = "aaafffffbammiaaannffimffffffM"
AOT_KERNELS = {"cell_values": (_cell_values, _KINDS)}


def compiled():
    """The compiled `_cell_values` (its helpers compiled first), or None when the kernels are off."""
    if not _COMPILED:
        fn = aot("cell_values", _KINDS)     # the ahead-of-time module's, once built
        if fn is not None:
            _COMPILED.append(fn)
            return fn
        fn = kernel(_cell_values)
        if fn is None:
            return None
        for name, py in _HELPERS.items():
            globals()[name] = kernel(py) or py
        _COMPILED.append(fn)
    return _COMPILED[0]
