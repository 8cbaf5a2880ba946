"""Cascade trajectories: limits, symmetry, comparison with an ODE solver."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotarydryer.correlations import (
    cascade_residence_time,
    cascade_trajectory,
    forward_step_without_gas,
    schiller_naumann_1933,
    terminal_velocity,
)

G = 9.80665
SUGAR = dict(particle_diameter=850e-6, particle_density=1588.0, gas_density=1.2, gas_viscosity=1.8e-5)


def test_drag_free_limit():
    """A heavy particle in a very light gas falls freely: t = sqrt(2h/(g cos th)), step = h tan th (Lee Eq. 3.7)."""
    r = cascade_trajectory(2.0, 5e-3, 8000.0, 1e-4, 1.8e-5, inclination=3.0)
    assert r.fall_time == pytest.approx(math.sqrt(2 * 2.0 / (G * math.cos(math.radians(3.0)))), rel=1e-3)
    assert r.axial_displacement == pytest.approx(forward_step_without_gas(2.0, 3.0), rel=2e-3)


def test_terminal_limit():
    """A fine particle reaches terminal velocity quickly: fall time ~ h / v_t."""
    vt = terminal_velocity(50e-6, 1588.0, 1.2, 1.8e-5)
    r = cascade_trajectory(1.0, 50e-6, 1588.0, 1.2, 1.8e-5)
    assert r.fall_time == pytest.approx(1.0 / vt, rel=0.01)
    assert r.normal_velocity == pytest.approx(vt, rel=1e-3)


def test_gas_direction_and_symmetry():
    none = cascade_trajectory(2.0, **SUGAR, inclination=0.0)
    co = cascade_trajectory(2.0, **SUGAR, gas_velocity=1.0, gas_flow="co-current")
    counter = cascade_trajectory(2.0, **SUGAR, gas_velocity=1.0, gas_flow="counter-current")
    assert none.axial_displacement == pytest.approx(0.0, abs=1e-12)
    assert co.axial_displacement > 0 > counter.axial_displacement
    assert co.axial_displacement == pytest.approx(-counter.axial_displacement, rel=1e-9)
    assert co.fall_time == pytest.approx(counter.fall_time, rel=1e-9)
    # axial drag also slows the vertical fall
    assert co.fall_time > none.fall_time


def _reference(h, d, rho_p, rho_g, mu, u, theta_deg):
    th = math.radians(theta_deg)
    b = 1 - rho_g / rho_p
    gx, gy = G * math.sin(th) * b, G * math.cos(th) * b

    def rhs(t, s):
        x, y, vx, vy = s
        wx, wy = vx - u, vy
        w = math.hypot(wx, wy)
        re = max(rho_g * w * d / mu, 1e-12)
        k = 3 * rho_g * schiller_naumann_1933(re) * w / (4 * rho_p * d)
        return [vx, vy, gx - k * wx, gy - k * wy]

    ev = lambda t, s: s[1] - h  # noqa: E731
    ev.terminal = True
    sol = solve_ivp(rhs, (0, 100), [0, 0, 0, 0], events=ev, rtol=1e-10, atol=1e-12, method="DOP853")
    return sol.t_events[0][0], sol.y_events[0][0][0]


@pytest.mark.parametrize("u, theta", [(1.5, 2.8), (-1.0, 2.8), (3.0, 0.0)])
def test_matches_ode_solver(u, theta):
    t_ref, x_ref = _reference(2.0, 850e-6, 1588.0, 1.2, 1.8e-5, u, theta)
    r = cascade_trajectory(2.0, **SUGAR, gas_velocity=abs(u),
                           gas_flow="co-current" if u >= 0 else "counter-current", inclination=theta)
    assert r.fall_time == pytest.approx(t_ref, rel=2e-3)
    assert r.axial_displacement == pytest.approx(x_ref, rel=5e-3)


def test_vectorised_matches_scalar():
    heights = np.array([0.5, 1.0, 2.0])
    gas = np.array([0.0, 1.0, 2.0])
    r = cascade_trajectory(heights, **SUGAR, gas_velocity=gas, inclination=2.8)
    for i in range(3):
        s = cascade_trajectory(float(heights[i]), **SUGAR, gas_velocity=float(gas[i]), inclination=2.8)
        assert r.fall_time[i] == pytest.approx(s.fall_time, rel=1e-12)
        assert r.axial_displacement[i] == pytest.approx(s.axial_displacement, rel=1e-12)


def test_errors():
    with pytest.raises(ValueError, match="fall_height"):
        cascade_trajectory(0.0, **SUGAR)
    with pytest.raises(ValueError, match="gas_flow"):
        cascade_trajectory(1.0, **SUGAR, gas_flow="up")
    with pytest.raises(ValueError, match="n_steps"):
        cascade_trajectory(1.0, **SUGAR, n_steps=3)
    with pytest.raises(ValueError, match="particle_density"):
        cascade_trajectory(1.0, 1e-3, 1.0, 1.2, 1.8e-5)


def test_fine_particle_follows_the_gas():
    """A 20 um particle relaxes to the gas velocity within ms: it drifts at u and settles at v_t."""
    still = cascade_trajectory(2.0, 20e-6, 1588.0, 1.2, 1.8e-5, gas_velocity=0.0)
    windy = cascade_trajectory(2.0, 20e-6, 1588.0, 1.2, 1.8e-5, gas_velocity=5.0, n_steps=50)
    assert windy.fall_time == pytest.approx(still.fall_time, rel=1e-3)
    assert windy.axial_displacement == pytest.approx(5.0 * windy.fall_time, rel=1e-3)
    assert windy.axial_velocity == pytest.approx(5.0, rel=1e-6)


def test_cascade_residence_time():
    assert cascade_residence_time(3.05, 0.4, 5.0, 0.02) == pytest.approx(3.05 / 0.02 * 5.4)


def test_gas_forward_step_factor():
    from rotarydryer.correlations import gas_forward_step_factor

    # drag-free, no gas: the factor is 1 (Lee Eq. 3.7 step recovered)
    assert gas_forward_step_factor(2.0, 5e-3, 8000.0, 1e-4, 1.8e-5, 0.0, inclination=3.0) == pytest.approx(1.0,
                                                                                                         rel=2e-3)
    u = np.array([0.0, 0.25, 0.5, 1.0])
    f = gas_forward_step_factor(2.0, **SUGAR, gas_velocity=u, gas_flow="counter-current")
    assert np.all(np.diff(f) < 0) and f[0] < 1.0  # drag alone shortens the step; counter-current gas reverses it
    co = gas_forward_step_factor(2.0, **SUGAR, gas_velocity=u, gas_flow="co-current")
    assert np.all(np.diff(co) > 0)
    with pytest.raises(ValueError, match="inclination"):
        gas_forward_step_factor(2.0, **SUGAR, gas_velocity=1.0, inclination=0.0)


def test_sherritt_curtain_velocity_ratio():
    from rotarydryer.correlations import sherritt_curtain_velocity_ratio

    assert sherritt_curtain_velocity_ratio(2.0, 3.0, 4.0) == pytest.approx(1.546 * 2**-0.76 * 3**-0.86 * 4**0.44)
    assert sherritt_curtain_velocity_ratio(2.0, 3.0, 4.0) < sherritt_curtain_velocity_ratio(1.0, 3.0, 4.0)
    with pytest.raises(ValueError, match="solids_rate"):
        sherritt_curtain_velocity_ratio(1.0, -1.0, 1.0)
