"""Forward step from particle trajectories (``transport.forward_step = "trajectory"``, issue 14 part 1)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from rotarydryer import Simulation
from rotarydryer.cases import load_case
from rotarydryer.correlations import cascade_trajectory, sherritt_curtain_velocity_ratio
from rotarydryer.geometry import FlightedDrum, TwoSectionFlight
from rotarydryer.geometry.lee2008_regressions import Lee2008Regressions
from rotarydryer.transport import lee2008
from rotarydryer.transport.diagnostics import cell_flows
from rotarydryer.transport.forward_step import (
    CurtainGas,
    curtain_velocity_ratio,
    forward_step_table,
    trajectory_forward_step,
)

from .conftest import invicta


def sim(case="lee2008_invicta", **ov):
    ov.setdefault("thermal.enabled", False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return Simulation(case, ov)


def invicta_gas(**kw):
    m = sim(**{"transport.forward_step": "trajectory", "transport.n_cells": 30}).transport_model()
    gas = m.specs[0].gas
    return gas if not kw else CurtainGas(**{**gas.__dict__, **kw})


def test_gas_from_the_case():
    """Superficial velocity of the Invicta [gas] (30.4 kg/s at 100 degC) over pi R^2, particles of
    the material (850 um, 1588 kg/m3)."""
    case = load_case("lee2008_invicta")
    gas = invicta_gas()
    from rotarydryer.properties import humid_air as ha

    Y = float(ha.humidity_from_mass_fraction(case.gas.inlet_humidity))
    rho = float(ha.density(case.gas.inlet_temperature, Y))
    assert gas.gas_velocity == pytest.approx(case.gas.flow / (rho * math.pi * case.drum.radius**2), rel=1e-12)
    assert gas.gas_flow == "counter-current" and gas.particle_diameter == 850e-6
    assert gas.velocity_ratio is None


def test_table_matches_the_trajectory():
    """The tabulated advance is within 5e-4 m of the integrated trajectory over the fall heights
    and curtain velocities of the drum (and exact at u = 0: h tan(theta))."""
    gas = invicta_gas()
    table = forward_step_table(gas, 2.8)
    rng = np.random.default_rng(1)
    h = rng.uniform(0.5, 4.8, 60)
    u = rng.uniform(0.0, gas.gas_velocity, 60)
    ref = cascade_trajectory(h, gas.particle_diameter, gas.particle_density, gas.gas_density, gas.gas_viscosity,
                             gas_velocity=u, gas_flow=gas.gas_flow, inclination=2.8, n_steps=400)
    np.testing.assert_allclose(table(h, u), ref.axial_displacement, atol=5e-4)
    np.testing.assert_allclose(table(h, 0.0), h * math.tan(math.radians(2.8)), rtol=1e-13)


def test_still_gas_gives_lee_zero_gas_step():
    """c_v = 0 (no gas in the curtain): the trajectory step is Lee's C_F^0 = h_m sin(theta)/dL, i.e.
    the fitted model with C_F^G = 1 (Lee (2008) Eq. 3.7)."""
    a = sim(**{"transport.forward_step": "trajectory", "transport.curtain_velocity_ratio": 0.0,
               "transport.backmix": 0.0}).transport_steady_state()
    b = sim(**{"transport.drag_reduction": 1.0, "transport.backmix": 0.0}).transport_steady_state()
    assert a.total_holdup == pytest.approx(b.total_holdup, rel=1e-9)
    np.testing.assert_allclose(a.model.cell_info["C_F"], b.model.cell_info["C_F"], rtol=1e-12)
    np.testing.assert_allclose(a.model.cell_info["C_F_G"], 1.0, rtol=1e-12)


def test_gas_direction():
    """Counter-current gas shortens the step (C_F^G < 1), co-current gas lengthens it (> 1)."""
    gas = invicta_gas(velocity_ratio=0.2)
    h, q = np.array([3.0]), np.array([40.0])
    zero = 3.0 * math.sin(math.radians(2.8))
    back = trajectory_forward_step(gas, 2.8, h, q)["step_m"][0]
    co = trajectory_forward_step(CurtainGas(**{**gas.__dict__, "gas_flow": "co-current"}), 2.8, h, q)["step_m"][0]
    assert back < zero < co


def test_sherritt_reading():
    """c_v = 1.546 h^-0.76 q^-0.86 (Lee (2008) Eq. 2.14 with F = q x 1 m, L = 1 m), clipped to [0, 1]."""
    gas = invicta_gas()
    h, q = np.array([3.0, 0.2, 3.0]), np.array([45.0, 1.6, 0.01])
    cv = curtain_velocity_ratio(gas, h, q)
    want = np.clip(np.asarray(sherritt_curtain_velocity_ratio(h, q, 1.0)), 0.0, 1.0)
    np.testing.assert_allclose(cv, want, rtol=1e-13)
    assert cv[1] == 1.0 and cv[2] == 1.0 and 0 < cv[0] < 0.05


def test_step_independent_of_the_discretisation():
    """The release per metre and h_m do not depend on N: the effective C_F^G is the same for 30 and
    33 cells (constant repose angle)."""
    cfg = [sim(**{"transport.forward_step": "trajectory", "transport.n_cells": n, "transport.backmix": 0.0,
                  "solids.repose_angle": 45.0}).transport_model().cell_info["C_F_G"] for n in (30, 33)]
    np.testing.assert_allclose(cfg[0][0], cfg[1][0], rtol=1e-12)


def test_negative_step_goes_to_backmix():
    """A counter-current gas stronger than the slope (isolated particles, c_v = 1, 10 cells) gives a
    negative advance d: C_F = 0 and C_B = backmix + |d|/dL, mass conserved."""
    m = sim(**{"transport.forward_step": "trajectory", "transport.curtain_velocity_ratio": 1.0,
               "transport.n_cells": 4, "transport.backmix": 0.0, "transport.kiln_time": 9.95}).transport_model()
    ci = m.cell_info
    dl = 12.0 / 4
    assert np.all(ci["forward_step_m"] < 0) and np.all(ci["C_F"] == 0)
    np.testing.assert_allclose(ci["C_B"], -ci["forward_step_m"] / dl, rtol=1e-12)
    ss = m.steady_state()
    assert ss.mass_balance_error < 1e-9
    assert np.all(cell_flows(ss)["net_curtain_kg_s"][:-1] < 0)


def test_step_longer_than_the_cell_names_n_cells():
    with pytest.raises(ValueError, match=r"transport.n_cells = 35 .*trajectory step .*transport.n_cells <= \d+"):
        sim(**{"transport.forward_step": "trajectory"}).transport_steady_state()


def test_errors_name_the_keys():
    with pytest.raises(ValueError, match="transport.forward_step"):
        load_case("lee2008_invicta", {"transport.forward_step": "bogus"})
    with pytest.raises(ValueError, match="transport.curtain_velocity_ratio"):
        load_case("lee2008_invicta", {"transport.curtain_velocity_ratio": 2.0})
    with pytest.raises(ValueError, match=r"\[gas\]"):
        lee2008(geometry=Lee2008Regressions(), forward_step="trajectory", kiln_time=8.69, backmix=0.68,
                drag_reduction=0.48, **invicta(35))
    gas = invicta_gas()
    with pytest.raises(ValueError, match="operating.gas_flow"):
        lee2008(geometry=Lee2008Regressions(), forward_step="trajectory", gas=gas, backmix=0.0, kiln_time=8.69,
                drag_reduction=1.0, gas_flow="co-current", **invicta(30))
    with pytest.raises(ValueError, match="material.particle_diameter"):
        CurtainGas(**{**gas.__dict__, "particle_diameter": -1.0})


def test_fitted_default_unchanged():
    """The default (fitted) model has no trajectory entries and Lee's C_F = C_F^G h_m sin(theta)/dL."""
    m = sim().transport_model()
    assert "C_F_G" not in m.cell_info
    ci = m.cell_info
    cfg = sim().case.transport.drag_reduction      # the case's calibrated C_F^G
    np.testing.assert_allclose(ci["C_F"], cfg * ci["fall_height_m"] * math.sin(math.radians(2.8)) / (12 / 35),
                               rtol=1e-12)


def test_general_schema_and_thermal_model():
    """The general schema: co-current gas lengthens the step (C_F^G > 1) in every flighted cell;
    the coupled heat-and-mass model runs on the same law (inlet-gas table)."""
    s = sim("song2003_ottawa", **{"transport.forward_step": "trajectory"})
    ci = s.transport_model().cell_info
    assert np.all(ci["C_F_G"] > 1)
    s2 = Simulation("song2003_ottawa", {"transport.forward_step": "trajectory"})
    out = s2.steady_state().summary()
    assert out["total_holdup_kg"] == pytest.approx(s2.transport_steady_state().total_holdup, rel=0.5)


def test_exact_drum_mass_average_close_to_step_at_h_m():
    """Using the step at the mass-averaged fall height h_m (as Lee's Eq. 3.7) instead of the
    dH-weighted mean of the steps: within 2 % for Invicta at its curtain velocity."""
    from rotarydryer.geometry.unloading import CascadeDrag, cascade

    gas = invicta_gas()
    drum = FlightedDrum(2.5, 28, TwoSectionFlight(s1=0.195, s2=0.183, alpha1=90.0, alpha2=117.0))
    u_c = 0.0133 * gas.gas_velocity
    drag = CascadeDrag(gas.particle_diameter, gas.particle_density, gas.gas_density, gas.gas_viscosity, u_c,
                       gas.gas_flow)
    c = cascade(drum, 45.0, 1.0, rpm=3.0, slope=2.8, drag=drag)
    at_hm = forward_step_table(gas, 2.8)(c.mean_fall_height * math.cos(math.radians(2.8)), u_c)
    assert float(at_hm) == pytest.approx(float(c.mean_axial_step), rel=0.02)


@pytest.mark.parametrize("c0", [1.0, 1.7, 2.4])
def test_step_factor_and_curtain_coefficient_are_case_keys(c0):
    """Song's two coefficients are parameters of the one forward-step law: with no gas inside the
    curtains (K = 0) the step is c_0 h_m sin(theta) exactly, C_F^G = c_0 in every cell (Song (2003)
    L600-618 reading, docs/song_pilot.md); with Sherritt's K the gas adds to it."""
    ov = {"transport.forward_step": "trajectory", "transport.n_cells": 10, "transport.kiln_time": 9.0,
          "transport.backmix": 0.0, "transport.step_factor": c0}
    still = sim(**ov, **{"transport.curtain_coefficient": 0.0}).transport_model().cell_info
    np.testing.assert_allclose(still["C_F_G"], c0, rtol=1e-12)
    np.testing.assert_allclose(still["curtain_velocity_ratio"], 0.0)
    windy = sim(**ov).transport_model().cell_info       # counter-current Invicta gas: shorter steps
    assert np.all(windy["C_F_G"] < c0) and np.all(windy["curtain_velocity_ratio"] > 0)
    with pytest.raises(ValueError, match=r"transport\.step_factor"):
        load_case("lee2008_invicta", {"transport.step_factor": 0.0})
