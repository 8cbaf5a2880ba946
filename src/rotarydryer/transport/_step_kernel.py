"""Compiled form of the trajectory forward step's coefficients (numba, optional).

One pass per cell from a flighted cell's cascade (passive time t_p, fall time t_a, fall height h_m) and the mass
its flights discharge to its curtain coefficients: the release per metre of drum, Sherritt's curtain velocity
ratio (Lee (2008) Eq. 2.14), the advance of the trajectories through the gas (the bilinear interpolation of the
section's `rotarydryer.transport.forward_step.ForwardStepTable`), its cap at the reach of the nearest-neighbour
structure and the split into C_F, C_B, C_R and the second-cell fractions (Lee (2008) Eq. 3.3-3.8), divided by the
passive and fall times. The NumPy reference is `FlightedSectionLaw._trajectory_step` followed by
`FlightedSectionLaw.rates_of`; both give the same numbers to rounding (``tests/transport/test_step_kernel.py``).
Plain loops, so the module imports without numba; it is only called compiled (`rotarydryer._jit`).
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import aot, kernel

#: the functions the kernel calls (`rotarydryer._aot` compiles them with it): none
_HELPERS: dict = {}
#: the rows of the kernel's output, in order
ROWS = ("discharge", "forward", "backmix", "return", "forward_far", "backmix_far", "cv")


def _trajectory_rates(tp, ta, h, flight_mass, dl, backmix, far, cos_s, tan_s, velocity_ratio, coefficient,
                      exponent_h, exponent_q, gas_velocity, step_factor, h_grid, u_grid, excess, out):
    """Per cell (1-D inputs of one length): the rows of `ROWS` into ``out`` (7, n). ``velocity_ratio`` < 0:
    Sherritt's c_v = min(1, K h^a q^b) clipped to [0, 1] (K ``coefficient``, a, b the exponents), else that
    fixed ratio. False where an input or a result is not finite (the caller takes the NumPy reference)."""
    nh, nu = h_grid.size, u_grid.size
    h_top, u_top = h_grid[nh - 1], u_grid[nu - 1]
    reach = (2.0 if far else 1.0 - backmix) * dl
    for c in range(tp.size):
        q = flight_mass[c] / tp[c] / dl
        hc = h[c]
        if velocity_ratio >= 0.0:
            cv = velocity_ratio
        else:
            cv = min(1.0, coefficient * max(hc, 1e-9) ** exponent_h * max(q, 1e-12) ** exponent_q)
            cv = min(max(cv, 0.0), 1.0)
        # the table's bilinear interpolation (ForwardStepTable.__call__) at the perpendicular fall height
        hp0 = hc * cos_s
        hp = min(max(hp0, 0.0), h_top)
        u = min(max(cv * gas_velocity, 0.0), u_top)
        i = min(max(np.searchsorted(h_grid, hp) - 1, 0), nh - 2)
        j = min(max(np.searchsorted(u_grid, u) - 1, 0), nu - 2)
        a = (hp - h_grid[i]) / (h_grid[i + 1] - h_grid[i])
        b = (u - u_grid[j]) / (u_grid[j + 1] - u_grid[j])
        ex = ((1 - a) * (1 - b) * excess[i, j] + a * (1 - b) * excess[i + 1, j]
              + (1 - a) * b * excess[i, j + 1] + a * b * excess[i + 1, j + 1])
        free = hp * tan_s + ex
        if step_factor != 1.0:
            free = free + (step_factor - 1.0) * hp0 * tan_s     # the landing's own advance, c_0 h_m sin(theta)
        d = min(max(free, -reach), reach)
        xf = max(d, 0.0) / dl
        xb = max(-d, 0.0) / dl
        cf2 = max(xf - 1.0, 0.0)
        cb2 = max(xb - 1.0, 0.0)
        cf = 2.0 - xf if xf > 1.0 else xf
        cb = backmix + (2.0 - xb if xb > 1.0 else xb)
        cr = 1.0 - cf - cb - cf2 - cb2
        t = ta[c]
        out[0, c] = 1.0 / tp[c]
        out[1, c] = cf / t
        out[2, c] = cb / t
        out[3, c] = cr / t
        out[4, c] = cf2 / t
        out[5, c] = cb2 / t
        out[6, c] = cv
        for r in range(7):
            if not math.isfinite(out[r, c]):
                return False
    return True


_COMPILED: list = []
#: `_trajectory_rates`'s argument kinds (`rotarydryer._aot`) and what the ahead-of-time module compiles
_KINDS = "aaaaffbffffffffaamM"
AOT_KERNELS = {"trajectory_rates": (_trajectory_rates, _KINDS)}


def compiled():
    """The compiled `_trajectory_rates`, or None when the kernels are off."""
    if not _COMPILED:
        fn = aot("trajectory_rates", _KINDS)     # the ahead-of-time module's, once built
        if fn is None:
            fn = kernel(_trajectory_rates)
        if fn is None:
            return None
        _COMPILED.append(fn)
    return _COMPILED[0]
