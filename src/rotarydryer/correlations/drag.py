r"""Single-particle drag coefficients and terminal velocity (Lee 2008 ch. 2 and 6).

Drag force (Lee 2008 Eq. 6.3): $F_D = \tfrac12 C_D \rho A v^2$ with
$Re = \rho v d/\mu$ (Lee 2008 l.1858-1870). All functions are vectorised
over their array arguments.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from .._validation import check_choice, check_positive, check_range
from ._common import STANDARD_GRAVITY, as_result, warn_outside

__all__ = [
    "reynolds_number",
    "stokes_drag",
    "schiller_naumann_1933",
    "haider_levenspiel_1989",
    "modified_schiller_naumann",
    "lee_2008",
    "drag_coefficient",
    "drag_coefficient_methods",
    "terminal_velocity",
]


def _re(reynolds):
    return check_positive("reynolds", reynolds)


def reynolds_number(velocity, diameter, density, viscosity):
    r"""Particle Reynolds number $Re = \rho |v| d/\mu$ (Lee 2008 l.1870).

    Parameters
    ----------
    velocity : array_like
        Slip velocity between particle and fluid, m/s (sign ignored).
    diameter : array_like
        Particle diameter (characteristic length), m.
    density : array_like
        Fluid density, kg/m³.
    viscosity : array_like
        Fluid dynamic viscosity, Pa s.

    Examples
    --------
    >>> round(reynolds_number(1.0, 850e-6, 1.2, 1.8e-5), 3)
    56.667
    """
    v = check_range("velocity", velocity, unit="m/s")
    d = check_positive("diameter", diameter, unit="m")
    rho = check_positive("density", density, unit="kg/m3")
    mu = check_positive("viscosity", viscosity, unit="Pa s")
    return as_result(rho * np.abs(v) * d / mu)


# Unchecked C_D kernels: each formula exists only here. The public functions below check
# their inputs and warn outside the fitted ranges, then call these; iterations call them
# through _drag_kernel (inputs checked once, no per-step checks or warnings).


def _cd_stokes(re):
    return 24.0 / re


def _cd_schiller_naumann(re):
    return np.where(re <= 1000.0, 24.0 / re * (1.0 + 0.15 * re**0.687), 0.44)


def _cd_haider_levenspiel(re, phi, c):
    a = np.exp(2.3288 - 6.4581 * phi + 2.4486 * phi**2)
    b = 0.0964 + 0.5565 * phi
    cc = np.exp(4.905 - 13.8944 * phi + 18.4222 * phi**2 - 10.2599 * phi**3)
    d = np.exp(1.4681 + c * phi - 20.7322 * phi**2 + 15.8855 * phi**3)
    return 24.0 / re * (1.0 + a * re**b) + cc * re / (re + d)


def _cd_lee_2008(re, a):
    return a / re * (1.0 + 0.004 * re**0.9968)


def _haider_levenspiel_params(sphericity, coefficient="published"):
    """Checked (phi, c) of [`haider_levenspiel_1989`][rotarydryer.correlations.drag.haider_levenspiel_1989]."""
    phi = check_range("sphericity", sphericity, 0.0, 1.0, high_inclusive=True)
    check_choice("coefficient", coefficient, ("published", "lee_2008_print"))
    return phi, (12.5584 if coefficient == "published" else 12.5284)


def _lee_2008_params(prefactor=24.0):
    """Checked numerator a of [`lee_2008`][rotarydryer.correlations.drag.lee_2008]."""
    return check_positive("prefactor", prefactor)


def stokes_drag(reynolds):
    r"""Stokes drag coefficient of a sphere, $C_D = 24/Re$ (creeping flow, Re < 0.1).

    Examples
    --------
    >>> stokes_drag(0.01)
    2400.0
    """
    re = _re(reynolds)
    warn_outside("reynolds", re, 0.0, 0.1, source="Stokes' law (creeping flow)")
    return as_result(_cd_stokes(re))


def schiller_naumann_1933(reynolds):
    r"""Drag coefficient of a sphere, Schiller & Naumann (1933).

    $$
    C_D = \frac{24}{Re}\left(1 + 0.15\,Re^{0.687}\right) \quad (Re \le 1000), \qquad C_D = 0.44 \quad (Re > 1000)
    $$

    Lee (2008) Eq. 2.13 (body stripped in the extracted text; this is the
    standard form, the one CFX uses in Lee's ch. 6 CFD, Eq. 6.15). The upper
    limit Re ≈ 2×10⁵ (drag crisis) is from general literature; beyond it a
    CorrelationRangeWarning is issued.

    Parameters
    ----------
    reynolds : array_like
        Particle Reynolds number, > 0.

    Returns
    -------
    float or ndarray
        C_D, dimensionless.

    Examples
    --------
    >>> round(schiller_naumann_1933(100.0), 4)
    1.0917
    """
    re = _re(reynolds)
    warn_outside("reynolds", re, 0.0, 2.0e5, source="Schiller & Naumann (1933)")
    return as_result(_cd_schiller_naumann(re))


def haider_levenspiel_1989(reynolds, sphericity, coefficient="published"):
    r"""Drag coefficient of a non-spherical particle, Haider & Levenspiel (1989).

    $$
    C_D = \frac{24}{Re}\left[1 + e^{2.3288 - 6.4581\phi + 2.4486\phi^2} Re^{0.0964 + 0.5565\phi}\right]
    + \frac{Re\, e^{4.905 - 13.8944\phi + 18.4222\phi^2 - 10.2599\phi^3}}
    {Re + e^{1.4681 + 12.5584\phi - 20.7322\phi^2 + 15.8855\phi^3}}
    $$

    Lee (2008) Eq. 6.1 (l.8028-8072). φ is the sphericity: surface of the
    volume-equivalent sphere / actual surface.

    Parameters
    ----------
    reynolds : array_like
        Re based on the volume-equivalent sphere diameter, > 0.
    sphericity : array_like
        φ, in (0, 1].
    coefficient : {"published", "lee_2008_print"}
        Lee prints 12.5284 for the φ coefficient of the last exponent; Haider &
        Levenspiel (1989) publish 12.5584. ``"published"`` (default) uses
        12.5584 (the thesis value is taken as a transcription error);
        ``"lee_2008_print"`` uses 12.5284. The difference is < 1 % in C_D.

    Returns
    -------
    float or ndarray
        C_D.

    Notes
    -----
    Fitted range (Haider & Levenspiel 1989, general literature): Re < 2.6×10⁵,
    φ ≥ 0.026; outside it a CorrelationRangeWarning is issued.

    Lee (2008) §6.2.4 reports a best-fit sphericity φ ≈ 0.4 for sugar crystals,
    but at φ = 0.4 this correlation gives C_D ≈ 4.5 on Re = 70-300, far *above*
    Schiller-Naumann, while Lee's data lie below it; that statement cannot be
    reconciled with Eq. 6.1 as printed (either coefficient variant).

    Examples
    --------
    >>> round(haider_levenspiel_1989(100.0, 0.846), 4)
    1.1671
    """
    re = _re(reynolds)
    phi, c = _haider_levenspiel_params(sphericity, coefficient)
    warn_outside("reynolds", re, 0.0, 2.6e5, source="Haider & Levenspiel (1989)")
    warn_outside("sphericity", phi, 0.026, 1.0, source="Haider & Levenspiel (1989)")
    return as_result(_cd_haider_levenspiel(re, phi, c))


def modified_schiller_naumann(reynolds, a, b, n):
    r"""General Schiller-Naumann form $C_D = (a/Re)(1 + b\,Re^{n})$, Lee (2008) Eq. 6.5.

    Parameters
    ----------
    reynolds : array_like
        Re, > 0.
    a, b, n : array_like
        Fitted constants (Schiller-Naumann: 24, 0.15, 0.687).

    Examples
    --------
    >>> round(modified_schiller_naumann(100.0, 24.0, 0.15, 0.687), 4)
    1.0917
    """
    re = _re(reynolds)
    a = check_positive("a", a)
    b = check_range("b", b, 0.0, math.inf, low_inclusive=True)
    n = check_range("n", n, 0.0, 2.0, low_inclusive=True)
    return as_result(a / re * (1.0 + b * re**n))


def lee_2008(reynolds, prefactor=24.0):
    r"""Drag coefficient of a falling raw-sugar crystal, Lee (2008) Eq. 6.6 ("modified Schiller-Naumann").

    $$
    C_D = \frac{a}{Re}\left(1 + 0.004\,Re^{0.9968}\right), \qquad a = 24 \text{ (assumed)}
    $$

    **Reading of the garbled equation.** The extracted text, identical at
    l.8284, l.8381 and l.11345 of the thesis, is ``( )0.9968 / 1 0.004Re /
    ReDC = +``: three numbers for the three constants (a, b, n) of Eq. 6.5.
    The layout (0.9968 on the superscript line with the parenthesis glyphs,
    "1 0.004Re" inside the parentheses, Re in the denominator) reads as
    b = 0.004 and n = 0.9968; the numerator a is not visible. It is taken as
    24, the Schiller-Naumann value the equation is said to modify, and left
    selectable as ``prefactor``.

    This reading is **not consistent** with Lee's other statements: with a = 24
    the curve lies 3-4 times below Schiller-Naumann on Re = 70-300, whereas the
    text says spheres over-predict the crystal drag by "up to 40 %" and reports
    an rms error of 0.26 for Schiller-Naumann. A numerator a ≈ 60 would
    reproduce that rms (0.26) but not the Haider-Levenspiel rms (0.51); no
    single a fits both, so the true constant cannot be recovered from the text.
    Use with care, and prefer [`schiller_naumann_1933`][rotarydryer.correlations.drag.schiller_naumann_1933] (which Lee's own CFD
    uses) until the original figure is checked.

    Parameters
    ----------
    reynolds : array_like
        Re based on the crystal's point-to-point length, > 0. Fitted range
        Re = 70-300 (Lee 2008 §6.2.4); outside it a CorrelationRangeWarning.
    prefactor : float
        The numerator a (see above), default 24.

    Returns
    -------
    float or ndarray
        C_D.

    Examples
    --------
    >>> round(lee_2008(100.0), 4)
    0.3346
    """
    re = _re(reynolds)
    a = _lee_2008_params(prefactor)
    warn_outside("reynolds", re, 70.0, 300.0, source="Lee (2008) Eq. 6.6 (sugar crystals)")
    return as_result(_cd_lee_2008(re, a))


_DRAG_METHODS: dict[str, tuple[Callable[..., Any], tuple[str, ...]]] = {
    "schiller_naumann_1933": (schiller_naumann_1933, ()),
    "haider_levenspiel_1989": (haider_levenspiel_1989, ("sphericity",)),
    "lee_2008": (lee_2008, ()),
    "stokes": (stokes_drag, ()),
}


def drag_coefficient_methods(reynolds=None, sphericity=None) -> list[str]:
    """List the drag correlations applicable to the given inputs.

    Haider-Levenspiel needs a sphericity; Stokes is listed only when every Re
    is below 0.1; Lee (2008) only when every Re lies in its fitted range 70-300.

    Examples
    --------
    >>> drag_coefficient_methods(100.0)
    ['schiller_naumann_1933', 'lee_2008']
    >>> drag_coefficient_methods(100.0, sphericity=0.8)
    ['schiller_naumann_1933', 'haider_levenspiel_1989', 'lee_2008']
    """
    out = ["schiller_naumann_1933"]
    if sphericity is not None:
        out.append("haider_levenspiel_1989")
    if reynolds is not None:
        re = np.asarray(reynolds, float)
        if np.all((re >= 70.0) & (re <= 300.0)):
            out.append("lee_2008")
        if np.all(re < 0.1):
            out.append("stokes")
    else:
        out += ["lee_2008", "stokes"]
    return out


def drag_coefficient(reynolds, method: str = "schiller_naumann_1933", sphericity=None, **kwargs):
    """Drag coefficient C_D of a single particle by the chosen correlation.

    Parameters
    ----------
    reynolds : array_like
        Particle Reynolds number, > 0.
    method : {"schiller_naumann_1933", "haider_levenspiel_1989", "lee_2008", "stokes"}
    sphericity : array_like, optional
        Needed by Haider-Levenspiel.
    **kwargs
        ``coefficient`` (Haider-Levenspiel), ``prefactor`` (Lee 2008).

    Examples
    --------
    >>> round(drag_coefficient(100.0, "haider_levenspiel_1989", sphericity=1.0), 4)
    1.1483
    """
    check_choice("method", method, _DRAG_METHODS)
    if method == "haider_levenspiel_1989":
        if sphericity is None:
            raise ValueError("drag_coefficient(method='haider_levenspiel_1989') needs sphericity")
        return haider_levenspiel_1989(reynolds, sphericity, **kwargs)
    func = _DRAG_METHODS[method][0]
    return func(reynolds, **kwargs)


def _drag_kernel(method, sphericity=None, **kwargs):
    """Check a drag correlation and its parameters once, as [`drag_coefficient`][rotarydryer.correlations.drag.drag_coefficient] does
    (same errors), and return ``cd(re, index)``: C_D of the float array ``re`` from the
    unchecked kernel, without input checks or range warnings, for use inside iterations.

    ``re`` must be > 0 (the caller's business). ``sphericity`` (Haider-Levenspiel) is a
    scalar or a flat array; ``index`` selects the elements of a flat array that ``re``
    belongs to (ignored otherwise).
    """
    check_choice("method", method, _DRAG_METHODS)
    if method == "haider_levenspiel_1989":
        if sphericity is None:
            raise ValueError("drag_coefficient(method='haider_levenspiel_1989') needs sphericity")
        _no_other_kwargs(method, kwargs, ("coefficient",))
        phi, c = _haider_levenspiel_params(sphericity, **kwargs)
        if phi.ndim == 0:
            return lambda re, index=None: _cd_haider_levenspiel(re, phi, c)
        return lambda re, index: _cd_haider_levenspiel(re, phi[index], c)
    if method == "lee_2008":
        _no_other_kwargs(method, kwargs, ("prefactor",))
        a = _lee_2008_params(**kwargs)
        return lambda re, index=None: _cd_lee_2008(re, a)
    _no_other_kwargs(method, kwargs, ())
    kernel = _cd_stokes if method == "stokes" else _cd_schiller_naumann
    return lambda re, index=None: kernel(re)


def _no_other_kwargs(method, kwargs, allowed):
    """TypeError for a keyword argument the correlation does not take (as calling it would)."""
    for k in kwargs:
        if k not in allowed:
            raise TypeError(f"{method}() got an unexpected keyword argument {k!r}")


def terminal_velocity(particle_diameter, particle_density, gas_density, gas_viscosity,
                      method: str = "schiller_naumann_1933", sphericity=None, gravity=STANDARD_GRAVITY, **kwargs):
    r"""Terminal settling velocity of a single particle, m/s.

    Solves the steady force balance (Lee 2008 Eq. 6.2 with a = 0 and Eq. 6.3)

    $$
    C_D(Re)\, Re^2 = \frac43\, Ar, \qquad Ar = \frac{g\, d^3 \rho_g (\rho_p - \rho_g)}{\mu^2},
    \qquad v_t = \frac{Re\, \mu}{\rho_g d}
    $$

    for Re by a vectorised safeguarded Newton iteration in log Re (bounded
    number of iterations; it never hangs). Where the drag law has a jump
    (Schiller-Naumann at Re = 1000, 0.4 %), the root is the jump point.

    Parameters
    ----------
    particle_diameter : array_like
        d, m.
    particle_density : array_like
        ρ_p, kg/m³ (must exceed the gas density).
    gas_density : array_like
        ρ_g, kg/m³.
    gas_viscosity : array_like
        μ, Pa s.
    method, sphericity, **kwargs
        Drag correlation, as [`drag_coefficient`][rotarydryer.correlations.drag.drag_coefficient].
    gravity : float
        g, m/s².

    Returns
    -------
    float or ndarray
        v_t, m/s.

    Examples
    --------
    >>> round(terminal_velocity(850e-6, 1588.0, 1.2, 1.8e-5), 3)
    4.485
    """
    d = check_positive("particle_diameter", particle_diameter, unit="m")
    rho_p = check_positive("particle_density", particle_density, unit="kg/m3")
    rho_g = check_positive("gas_density", gas_density, unit="kg/m3")
    mu = check_positive("gas_viscosity", gas_viscosity, unit="Pa s")
    g = check_positive("gravity", gravity, unit="m/s2")
    if np.any(rho_p <= rho_g):
        raise ValueError("particle_density must exceed gas_density for a particle to settle")
    check_choice("method", method, _DRAG_METHODS)
    d, rho_p, rho_g, mu = np.broadcast_arrays(d, rho_p, rho_g, mu)
    ar = g * d**3 * rho_g * (rho_p - rho_g) / mu**2
    target = np.log(4.0 / 3.0 * ar)
    # Initial guess: explicit approximation of Haider & Levenspiel (1989) for spheres,
    # u* = [18/d*^2 + 0.591/d*^0.5]^-1 with d* = Ar^(1/3), Re = u* d* (within a few %).
    if method == "stokes":
        re = ar / 18.0
    else:
        dstar = np.cbrt(ar)
        re = dstar / (18.0 / dstar**2 + 0.591 / np.sqrt(dstar))
    x = np.log(np.maximum(re, 1e-300))
    # Bracket: C_D > 0.01 for every method here (upper bound on Re); C_D < 1e4 * 24/Re (lower bound).
    lo = np.log(np.minimum(1e-12, ar / 18.0 * 1e-4))
    hi = np.log(np.maximum(ar / 18.0, np.sqrt(4.0 / 3.0 * ar / 0.01))) + 1.0
    x, lo, hi, target = (np.array(a, dtype=float).ravel() for a in np.broadcast_arrays(x, lo, hi, target))
    sph_all = None if sphericity is None else np.broadcast_to(np.asarray(sphericity, float), d.shape).ravel()
    cd = _drag_kernel(method, sph_all, **kwargs)
    active = np.arange(x.size)
    f_prev = np.full(x.size, np.inf)
    for _ in range(300):  # hard iteration budget: never hangs
        xa, la, ha, ta = x[active], lo[active], hi[active], target[active]
        f = np.log(cd(np.exp(xa), active)) + 2.0 * xa - ta
        la = np.where(f < 0, xa, la)
        ha = np.where(f > 0, xa, ha)
        done = (np.abs(f) < 1e-10) | (ha - la < 1e-10)
        h = 1e-6
        fp = (np.log(cd(np.exp(xa + h), active)) + 2.0 * (xa + h) - ta - f) / h
        xn = xa - f / np.where(fp > 0.1, fp, 0.1)
        # bisect when Newton leaves the bracket or stops halving the residual (this guarantees
        # convergence where the drag law has a jump and Newton would oscillate across it)
        stalled = np.abs(f) > 0.5 * f_prev[active]
        outside = (xn <= la) | (xn >= ha) | stalled
        xn = np.where(outside, 0.5 * (la + ha), xn)
        x[active] = np.where(done, xa, xn)
        lo[active], hi[active] = la, ha
        f_prev[active] = np.abs(f)
        active = active[~done]
        if active.size == 0:
            break
    else:
        raise ValueError("terminal_velocity: the force balance did not converge; check the inputs")
    x = x.reshape(d.shape)
    re = np.exp(x)
    return as_result(re * mu / (rho_g * d))
