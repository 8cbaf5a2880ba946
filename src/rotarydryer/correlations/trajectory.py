r"""Trajectory of a particle falling from a flight through a co- or counter-current gas stream.

Coordinates are attached to the inclined drum: *x* along the drum axis,
positive toward the discharge end, and *y* perpendicular to the axis in the
vertical plane, positive downward. With drum inclination θ (degrees at the API)
gravity, reduced by buoyancy, has components

$$
g_x = g \sin\theta\,(1 - \rho_g/\rho_p), \qquad g_y = g \cos\theta\,(1 - \rho_g/\rho_p).
$$

The gas moves along the axis with velocity u (+ co-current, − counter-current).
Newton's law for the particle (Lee 2008 Eqs. 6.2-6.3, drag
$F_D = \tfrac12 C_D \rho_g A |w| w$ on the slip velocity w = v − u) is

$$
\frac{dw}{dt} = g' - \frac{w}{\tau_r}, \qquad
\tau_r = \frac{4 \rho_p d}{3 \rho_g C_D(Re) |w|},
$$

integrated with an exponential (exact for frozen τ_r) midpoint scheme, which is
stable for any step, until the particle has fallen the fall height (measured
perpendicular to the axis, as the flight-geometry chord is). This is the
single-particle drag analysis of Schofield & Glikin (1962) reviewed by Lee
(2008) §2.4 (Eq. 2.9, body stripped in the text) and Song (2003) §2.5, with
the drag correlations of [`rotarydryer.correlations.drag`][rotarydryer.correlations.drag]. Lee and Baker
found isolated-particle drag over-predicts the gas effect on real curtains
(Lee 2008 l.1919-1933; ch. 6 CFD): treat the gas part of the displacement as an
upper bound.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validation import check_choice, check_positive, check_range
from ._common import STANDARD_GRAVITY, as_result
from .drag import _DRAG_METHODS, _drag_kernel, terminal_velocity

__all__ = [
    "CascadeTrajectory",
    "cascade_trajectory",
    "forward_step_without_gas",
    "gas_forward_step_factor",
    "sherritt_curtain_velocity_ratio",
    "cascade_residence_time",
]


@dataclass(frozen=True)
class CascadeTrajectory:
    """Result of [`cascade_trajectory`][rotarydryer.correlations.trajectory.cascade_trajectory] (arrays broadcast over the inputs).

    Attributes
    ----------
    fall_time : float or ndarray
        Time to fall the fall height, s.
    axial_displacement : float or ndarray
        Axial displacement during the fall, m (+ toward the discharge end).
    axial_velocity : float or ndarray
        Axial particle velocity at landing, m/s.
    normal_velocity : float or ndarray
        Velocity perpendicular to the axis at landing, m/s.
    terminal_velocity : float or ndarray
        Still-gas terminal velocity of the particle, m/s.
    """

    fall_time: float | np.ndarray
    axial_displacement: float | np.ndarray
    axial_velocity: float | np.ndarray
    normal_velocity: float | np.ndarray
    terminal_velocity: float | np.ndarray


def forward_step_without_gas(fall_height, inclination):
    r"""Axial displacement of a drag-free particle falling without gas, m.

    $$
    d_0 = h_\perp \tan\theta = h_{vert} \sin\theta
    $$

    Lee (2008) Eq. 3.7 numerator ($d_0 = h_m \sin\theta$ with h_m the
    true vertical height); here the fall height is measured perpendicular to the
    drum axis, h⊥ = h_vert cos θ.

    Parameters
    ----------
    fall_height : array_like
        Fall height perpendicular to the drum axis, m.
    inclination : array_like
        Drum inclination θ, degrees.

    Examples
    --------
    >>> round(forward_step_without_gas(2.0, 2.8), 5)
    0.09782
    """
    h = check_positive("fall_height", fall_height, unit="m")
    th = check_range("inclination", inclination, -45.0, 45.0, unit="deg")
    return as_result(h * np.tan(np.radians(th)))


def cascade_trajectory(fall_height, particle_diameter, particle_density, gas_density, gas_viscosity,
                       gas_velocity=0.0, gas_flow="co-current", inclination=0.0,
                       initial_axial_velocity=0.0, initial_normal_velocity=0.0,
                       method="schiller_naumann_1933", sphericity=None, n_steps=400,
                       gravity=STANDARD_GRAVITY, **drag_kwargs) -> CascadeTrajectory:
    r"""Fall time and axial displacement of a particle released from a flight.

    See the module docstring for the equations. Vectorised: every argument
    except ``gas_flow``, ``method``, ``n_steps`` and ``gravity`` broadcasts.

    Parameters
    ----------
    fall_height : array_like
        Distance fallen perpendicular to the drum axis, m.
    particle_diameter : array_like
        d, m.
    particle_density : array_like
        ρ_p, kg/m³.
    gas_density : array_like
        ρ_g, kg/m³.
    gas_viscosity : array_like
        μ, Pa s.
    gas_velocity : array_like
        Axial gas speed |u| seen by the particle, m/s (≥ 0).
    gas_flow : {"co-current", "counter-current"}
        Co-current gas pushes the particle toward the discharge.
    inclination : array_like
        Drum inclination θ, degrees (positive: the discharge end is lower).
    initial_axial_velocity, initial_normal_velocity : array_like
        Particle velocity at release, m/s (axial + toward discharge, normal + downward).
    method, sphericity, **drag_kwargs
        Drag correlation, as [`rotarydryer.correlations.drag_coefficient`][rotarydryer.correlations.drag_coefficient].
    n_steps : int
        Time steps per characteristic fall time (≥ 50). Default 400 gives
        better than 0.1 % on the fall time.
    gravity : float
        g, m/s².

    Returns
    -------
    CascadeTrajectory

    Examples
    --------
    >>> r = cascade_trajectory(2.0, 850e-6, 1588.0, 1.2, 1.8e-5, gas_velocity=1.0,
    ...                        gas_flow="counter-current", inclination=2.8)
    >>> round(float(r.fall_time), 3), round(float(r.axial_displacement), 4)
    (0.775, -0.2007)
    """
    h = check_positive("fall_height", fall_height, unit="m")
    d = check_positive("particle_diameter", particle_diameter, unit="m")
    rho_p = check_positive("particle_density", particle_density, unit="kg/m3")
    rho_g = check_positive("gas_density", gas_density, unit="kg/m3")
    mu = check_positive("gas_viscosity", gas_viscosity, unit="Pa s")
    ug = check_range("gas_velocity", gas_velocity, 0.0, math.inf, low_inclusive=True, unit="m/s")
    check_choice("gas_flow", gas_flow, ("co-current", "counter-current"))
    theta = np.radians(check_range("inclination", inclination, -45.0, 45.0, high_inclusive=True,
                                   low_inclusive=True, unit="deg"))
    vx0 = check_range("initial_axial_velocity", initial_axial_velocity, unit="m/s")
    vy0 = check_range("initial_normal_velocity", initial_normal_velocity, -50.0, 50.0, unit="m/s")
    check_choice("method", method, _DRAG_METHODS)
    if not (isinstance(n_steps, (int, np.integer)) and n_steps >= 50):
        raise ValueError(f"n_steps = {n_steps!r} must be an integer >= 50")
    g = float(check_positive("gravity", gravity, unit="m/s2"))
    if np.any(rho_p <= rho_g):
        raise ValueError("particle_density must exceed gas_density")

    arrays = np.broadcast_arrays(h, d, rho_p, rho_g, mu, ug, theta, vx0, vy0)
    h, d, rho_p, rho_g, mu, ug, theta, vx0, vy0 = (np.array(a, dtype=float, copy=True).ravel() for a in arrays)
    shape = arrays[0].shape
    sph_flat = None if sphericity is None else np.broadcast_to(np.asarray(sphericity, float), shape).ravel()
    cd_of = _drag_kernel(method, sph_flat, **drag_kwargs)  # checked once here; unchecked in the time loop
    u = ug if gas_flow == "co-current" else -ug
    buoy = 1.0 - rho_g / rho_p
    gx = g * np.sin(theta) * buoy
    gy = g * np.cos(theta) * buoy
    if np.any(gy <= 0):
        raise ValueError("inclination leaves no gravity component perpendicular to the axis")
    vt = np.asarray(terminal_velocity(d, rho_p, rho_g, mu, method=method, sphericity=sph_flat,
                                      gravity=g, **drag_kwargs), float).ravel()
    # Characteristic fall time: the longer of free fall and fall at terminal velocity. (Axial slip
    # slows the vertical fall only while it lasts, i.e. for about one relaxation time.)
    t_free = (np.sqrt(vy0**2 + 2.0 * gy * h) - vy0) / gy
    t_term = h / vt
    dt = np.maximum(t_free, t_term) / n_steps

    u_arr = np.broadcast_to(u, h.shape)

    def relax_time(i, wx_, wy_):
        speed = np.hypot(wx_, wy_)
        re = np.maximum(rho_g[i] * speed * d[i] / mu[i], 1e-12)
        cd = cd_of(re, i)
        # tau_r = 4 rho_p d / (3 rho_g C_D |w|) = 4 rho_p d^2 / (3 mu C_D Re)
        return 4.0 * rho_p[i] * d[i] ** 2 / (3.0 * mu[i] * cd * re)

    def advance(i, wx_, wy_, tau, step):
        """Exact update of slip velocity and position over ``step`` for a frozen relaxation time."""
        e = np.exp(-step / tau)
        one_m = -np.expm1(-step / tau)
        gxi, gyi = gx[i], gy[i]
        wx_n = gxi * tau + (wx_ - gxi * tau) * e
        wy_n = gyi * tau + (wy_ - gyi * tau) * e
        dx = u_arr[i] * step + gxi * tau * step + (wx_ - gxi * tau) * tau * one_m
        dy = gyi * tau * step + (wy_ - gyi * tau) * tau * one_m
        return wx_n, wy_n, dx, dy

    n = h.size
    x = np.zeros(n)
    y = np.zeros(n)
    t = np.zeros(n)
    wx = vx0 - u_arr
    wy = vy0.copy()
    out_t = np.full(n, np.nan)
    out_x = np.full(n, np.nan)
    out_vx = np.full(n, np.nan)
    out_vy = np.full(n, np.nan)
    active = np.ones(n, dtype=bool)
    for _ in range(100 * n_steps):  # hard step budget: never hangs
        idx = np.nonzero(active)[0]
        if idx.size == 0:
            break
        step = dt[idx]
        wxi, wyi = wx[idx], wy[idx]
        # midpoint: relaxation time evaluated at the half-step state
        whx, why, _, _ = advance(idx, wxi, wyi, relax_time(idx, wxi, wyi), 0.5 * step)
        wxn, wyn, dx, dy = advance(idx, wxi, wyi, relax_time(idx, whx, why), step)
        y_new = y[idx] + dy
        landed = y_new >= h[idx]
        if np.any(landed):
            j = idx[landed]
            frac = (h[j] - y[j]) / dy[landed]
            out_t[j] = t[j] + frac * step[landed]
            out_x[j] = x[j] + frac * dx[landed]
            out_vx[j] = wxi[landed] + frac * (wxn[landed] - wxi[landed]) + u_arr[j]
            out_vy[j] = wyi[landed] + frac * (wyn[landed] - wyi[landed])
            active[j] = False
        keep = ~landed
        k = idx[keep]
        x[k] += dx[keep]
        y[k] = y_new[keep]
        t[k] += step[keep]
        wx[k] = wxn[keep]
        wy[k] = wyn[keep]
    if np.any(active):
        raise ValueError("cascade_trajectory: some particles did not land within the step budget "
                         "(gas drag holds them up); check gas_velocity and particle_diameter")

    def shaped(a):
        return as_result(a.reshape(shape))

    return CascadeTrajectory(
        fall_time=shaped(out_t),
        axial_displacement=shaped(out_x),
        axial_velocity=shaped(out_vx),
        normal_velocity=shaped(out_vy),
        terminal_velocity=shaped(vt),
    )


def cascade_residence_time(length, fall_time, flight_time, axial_displacement):
    r"""Mean residence time from the cascade cycle, Schofield & Glikin (1962) structure.

    $$
    \tau = \frac{L}{d_{step}}\,(t_{fall} + t_{flight})
    $$

    Lee (2008) Eq. 2.9 (body stripped; structure from Lee's description,
    l.1064-1100): the number of cascades needed to travel the dryer length times
    the duration of one cascade cycle. Kilning and bouncing are ignored.

    Parameters
    ----------
    length : array_like
        Dryer length L, m.
    fall_time : array_like
        Mean fall time per cascade, s.
    flight_time : array_like
        Mean time carried in a flight per cycle, s.
    axial_displacement : array_like
        Mean forward step per cascade, m (> 0).

    Examples
    --------
    >>> round(cascade_residence_time(3.05, 0.4, 5.0, 0.02), 1)
    823.5
    """
    L = check_positive("length", length, unit="m")
    tf = check_positive("fall_time", fall_time, unit="s")
    tfl = check_range("flight_time", flight_time, 0.0, math.inf, low_inclusive=True, unit="s")
    step = check_positive("axial_displacement", axial_displacement, unit="m")
    return as_result(L / step * (tf + tfl))


def gas_forward_step_factor(fall_height, particle_diameter, particle_density, gas_density, gas_viscosity,
                            gas_velocity, gas_flow="counter-current", inclination=2.8, **kwargs):
    r"""Gas-solids interaction factor on the forward step, $C_F^G$ of Lee (2008) Eq. 3.8, from physics.

    $$
    C_F^G = \frac{x(\text{gas, drag})}{h_\perp \tan\theta}, \qquad C_F = C_F^0\, C_F^G
    $$

    Lee's zero-gas forward coefficient $C_F^0 = h_m \sin\theta/(L/N)$
    (Eq. 3.7) uses the drag-free step; this ratio replaces the fitted
    $C_F^G$ (Lee ch. 7) by the single-particle trajectory of
    [`cascade_trajectory`][rotarydryer.correlations.trajectory.cascade_trajectory]. A value < 0 means the gas carries the particle
    backwards (backmixing, Lee's C_B). Lee's ch. 6 CFD found that dense curtains
    shield most particles from the gas, so this isolated-particle value is an
    upper bound on the gas effect.

    Parameters
    ----------
    fall_height, particle_diameter, particle_density, gas_density, gas_viscosity, gas_velocity, gas_flow
        As [`cascade_trajectory`][rotarydryer.correlations.trajectory.cascade_trajectory].
    inclination : array_like
        Drum inclination θ, degrees (must be non-zero).
    **kwargs
        Passed to [`cascade_trajectory`][rotarydryer.correlations.trajectory.cascade_trajectory].

    Returns
    -------
    float or ndarray
        C_F^G, dimensionless.

    Examples
    --------
    >>> round(gas_forward_step_factor(2.0, 850e-6, 1588.0, 1.2, 1.8e-5, 0.5), 3)
    -0.452
    """
    th = check_range("inclination", inclination, -45.0, 45.0, unit="deg")
    if np.any(th == 0.0):
        raise ValueError("inclination = 0 deg: the drag-free forward step is zero, so C_F^G is undefined")
    r = cascade_trajectory(fall_height, particle_diameter, particle_density, gas_density, gas_viscosity,
                           gas_velocity=gas_velocity, gas_flow=gas_flow, inclination=inclination, **kwargs)
    return as_result(np.asarray(r.axial_displacement) / np.asarray(forward_step_without_gas(fall_height, th)))


def sherritt_curtain_velocity_ratio(fall_height, solids_rate, length):
    r"""Ratio of the gas velocity inside a curtain to the bulk gas velocity, Sherritt et al. (1993).

    $$
    c_v = \frac{U_c}{U_g} = 1.546\, h_f^{-0.76}\, F^{-0.86}\, L^{0.44}
    $$

    Lee (2008) Eq. 2.14 (l.1951-1965), reconstructed from garbled text: the two
    minus signs are assigned to the first two exponents by their position, and
    the meanings of h_f (read as the fall height), F (read as the solids release
    rate) and L (read as a length) and their units are **not** defined in Lee.
    Unverified: no number is printed to check it against. The trajectory forward step
    of the transport models ([`rotarydryer.transport.forward_step`][rotarydryer.transport.forward_step]) reads F as the
    release rate of a curtain L metres long and, a drum's curtain being continuous along
    the axis, evaluates it per metre of drum (F = q x 1 m, L = 1 m; docs/transport.md).

    Parameters
    ----------
    fall_height : array_like
        h_f, m (reading).
    solids_rate : array_like
        F, kg/s (reading).
    length : array_like
        L, m (reading).

    Examples
    --------
    >>> round(sherritt_curtain_velocity_ratio(1.0, 1.0, 1.0), 3)
    1.546
    """
    h = check_positive("fall_height", fall_height, unit="m")
    f = check_positive("solids_rate", solids_rate, unit="kg/s")
    L = check_positive("length", length, unit="m")
    return as_result(1.546 * h**-0.76 * f**-0.86 * L**0.44)
