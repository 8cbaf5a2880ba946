"""Vectorised bracketed root finding (Illinois variant of regula falsi) for monotone residuals."""

from __future__ import annotations

import numpy as np


def illinois(func, lo, hi, f_lo=None, f_hi=None, xtol=1e-9, max_iter=100):
    """Roots of ``func`` elementwise in the brackets [lo, hi] (f(lo), f(hi) of opposite sign or zero).

    Illinois modification of regula falsi (Dowell & Jarratt 1971): superlinear, never leaves
    the bracket. Falls back to bisection steps if the secant step stalls. Returns the root array.
    """
    lo = np.array(lo, dtype=float)
    hi = np.array(hi, dtype=float)
    lo, hi = np.broadcast_arrays(lo, hi)
    lo = lo.copy()
    hi = hi.copy()
    f_lo = func(lo) if f_lo is None else np.array(np.broadcast_to(f_lo, lo.shape), dtype=float)
    f_hi = func(hi) if f_hi is None else np.array(np.broadcast_to(f_hi, lo.shape), dtype=float)
    x = np.where(f_lo == 0, lo, hi)
    done = (f_lo == 0) | (f_hi == 0)
    side = np.zeros(lo.shape, dtype=int)
    for _ in range(max_iter):
        denom = f_hi - f_lo
        safe = np.where(denom != 0, denom, 1.0)
        x_new = np.where(denom != 0, (lo * f_hi - hi * f_lo) / safe, 0.5 * (lo + hi))
        bad = ~np.isfinite(x_new) | (x_new < np.minimum(lo, hi)) | (x_new > np.maximum(lo, hi))
        x_new = np.where(bad, 0.5 * (lo + hi), x_new)
        x_prev = x
        x = np.where(done, x, x_new)
        f_x = func(x)
        same_as_lo = np.sign(f_x) == np.sign(f_lo)
        # replace the endpoint with the same sign; halve the other one's value if it is retained twice
        new_lo = np.where(same_as_lo, x, lo)
        new_hi = np.where(same_as_lo, hi, x)
        f_hi = np.where(same_as_lo & (side == 1), 0.5 * f_hi, f_hi)
        f_lo = np.where(~same_as_lo & (side == -1), 0.5 * f_lo, f_lo)
        f_lo = np.where(same_as_lo, f_x, f_lo)
        f_hi = np.where(same_as_lo, f_hi, f_x)
        side = np.where(same_as_lo, 1, -1)
        lo = np.where(done, lo, new_lo)
        hi = np.where(done, hi, new_hi)
        done = done | (f_x == 0) | (np.abs(hi - lo) < xtol) | (np.abs(x - x_prev) < 0.1 * xtol)
        if np.all(done):
            break
    return np.where(np.abs(hi - lo) < xtol, 0.5 * (lo + hi), x)


def newton_from_guess(func, x0, lo, hi, xtol=1e-9, max_iter=12, delta=1e-3):
    """Roots of ``func`` elementwise by Newton's method from a nearby guess ``x0``, kept in [lo, hi].

    ``func`` must accept a stacked argument (2, ...): the point and the point + ``delta`` are
    evaluated in one call (forward-difference slope). Returns the roots once every step is below
    ``xtol``, or once the contraction of the last two steps puts the estimated distance left
    below ``xtol`` / 10 (one evaluation fewer from a nearby guess), or None (no finite slope,
    or not settled in ``max_iter`` steps): then the caller brackets the root (`illinois`).
    From the root of a nearby state it takes 2-3 steps.
    """
    lo = np.asarray(lo, dtype=float)
    hi = np.asarray(hi, dtype=float)
    x = np.clip(np.asarray(x0, dtype=float), lo, hi)
    previous = clipped = None
    for _ in range(max_iter):
        f = func(np.stack([x, x + delta]))
        slope = (f[1] - f[0]) / delta
        if not (np.all(np.isfinite(f)) and np.all(slope != 0)):
            return None
        newton_x = x - f[0] / slope
        x_new = np.clip(newton_x, lo, hi)
        step = np.abs(x_new - x)
        # settled where Newton's own step is below xtol: a step clipped to the bracket is not (an element
        # held at a bound by a step beyond it moves 0 without being a root)
        if np.all(np.abs(newton_x - x) < xtol):
            return x_new
        if previous is not None:
            # the steps contract by r = step / previous step or faster (Newton's method near its
            # root): the distance left from x_new is about step r / (1 - r); estimated below
            # xtol / 10 everywhere (and no step clipped to the bracket, which is no Newton step),
            # x_new is the root to xtol without one more evaluation
            r = step / np.maximum(previous, 1e-300)
            newton = ~(clipped | (x_new == lo) | (x_new == hi))
            if np.all((r < 0.5) & (step * r < 0.05 * xtol) & newton):
                return x_new
        previous = step
        clipped = (x_new == lo) | (x_new == hi)
        x = x_new
    return None
