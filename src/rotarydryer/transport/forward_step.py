r"""Forward step of a cascade from particle trajectories (``transport.forward_step = "trajectory"``).

Lee (2008) Eq. 3.7-3.8 split the curtain of cell i into forward, return and backmix parts
with C_F = C_F^G h_m sin(theta)/dL, where C_F^G is *fitted* (Table 7.2). Here the mean axial
advance of a cascade, d, comes from the fall of a particle through the axial gas stream
([`rotarydryer.correlations.cascade_trajectory`][rotarydryer.correlations.cascade_trajectory]: drag, buoyancy, slope; Lee (2008) §2.7,
the Schofield & Glikin analysis of Eq. 2.9) and C_F = d/dL; the effective drag factor is
C_F^G = d/(h_m sin(theta)) (1 without gas: a particle falling from rest through still gas
moves on a straight line, d = h_perp tan(theta) = h_m sin(theta)).

Readings chosen (see docs/transport.md "Forward step from trajectories"):

* **gas velocity**: superficial, the gas mass flow over the whole drum cross-section,
  u_g = G/(rho_g pi R^2) (the basis of the MRT correlations and of Song's 2.6 m/s), at the
  gas inlet conditions of the case (the transport-only model has no gas temperature
  profile);
* **curtain**: particles inside a curtain feel the reduced velocity U_c = c_v U_g of
  Sherritt et al. (Lee (2008) Eq. 2.14), c_v = 1.546 h_f^-0.76 F^-0.86 L^0.44, read as h_f the
  fall height (m), F the solids release rate (kg/s) of a curtain L metres long; the curtain
  of a drum is continuous along the axis, so F = q L with q the local release rate per metre
  of drum (flight discharge of the cell / cell length, kg/(s m)) and L = 1 m: a local law,
  independent of the number of cells and of the drum length. c_v is clipped to [0, 1] (the
  gas inside a curtain is never faster than the bulk). ``velocity_ratio`` replaces c_v by a
  fixed value (1: isolated particles in the bulk gas, Lee's upper bound);
* **fall height**: the cell's mass-averaged fall height h_m (Lee (2008) Eq. 3.7 uses h_m;
  the advance is nearly linear in h, docs give the dH-weighted check);
* **sign**: a negative advance (counter-current gas stronger than the slope) is carried by
  the backmix edge (cell i -> i-1) so that the mean displacement per fall stays d.

The advance is tabulated once per gas/particle/slope on a (fall height, gas velocity) grid
and interpolated bilinearly (error below 2e-4 m on the shipped cases); a steady state then
costs no trajectory integration.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .._limits import check_key
from .._validation import check_choice, check_range

__all__ = ["CurtainGas", "ForwardStepTable", "forward_step_table", "curtain_velocity_ratio", "sherritt_form",
           "trajectory_forward_step", "FORWARD_STEPS", "SHERRITT_COEFFICIENT", "SHERRITT_EXPONENTS"]

#: values of ``transport.forward_step``
FORWARD_STEPS = ("fitted", "trajectory")
GAS_FLOWS = ("co-current", "counter-current")
#: Sherritt's constant of Lee (2008) Eq. 2.14, c_v = 1.546 h^-0.76 F^-0.86 L^0.44 (read with F = q x 1 m, L = 1 m)
SHERRITT_COEFFICIENT = 1.546
#: exponents of h (m) and q (kg/(s m)) in Lee (2008) Eq. 2.14, as printed
SHERRITT_EXPONENTS = (-0.76, -0.86)


def sherritt_form(fall_height, release_rate_per_length, coefficient=SHERRITT_COEFFICIENT):
    r"""c_v = min(1, K h^-0.76 q^-0.86): the gas velocity inside a curtain over the bulk gas velocity in
    Sherritt's form (Lee (2008) Eq. 2.14), h the fall height (m), q the release per metre of drum
    (kg/(s m)), K Sherritt's 1.546 or a fitted value (Song's pilot: ``transport.curtain_coefficient``).
    Unchecked kernel (vectorised; the callers check their inputs)."""
    a, b = SHERRITT_EXPONENTS
    return np.minimum(1.0, coefficient * np.asarray(fall_height, float)**a
                      * np.asarray(release_rate_per_length, float)**b)


@dataclass(frozen=True)
class CurtainGas:
    """Gas stream and particles seen by the curtains of a flighted section (SI).

    Attributes
    ----------
    gas_mass_flow : float
        G, kg/s of (wet) gas through the drum.
    gas_density, gas_viscosity : float
        kg/m^3 and Pa s, at the gas conditions chosen by the caller.
    radius : float
        Drum radius R, m (free cross-section pi R^2; fall heights up to 2R are tabulated).
    gas_flow : {"co-current", "counter-current"}
    particle_diameter, particle_density : float
        m and kg/m^3 (of the material).
    velocity_ratio : float or None
        Fixed c_v = U_c/U_g in [0, 1]; None: Sherritt's Lee (2008) Eq. 2.14.
    method : str
        Drag correlation ([`rotarydryer.correlations.drag_coefficient`][rotarydryer.correlations.drag_coefficient]).
    curtain_coefficient : float
        K of [`sherritt_form`][rotarydryer.transport.forward_step.sherritt_form] (default Sherritt's 1.546).
    step_factor : float
        c_0, the advance of a cascade without gas over the drag-free fall h_m sin(theta) (1: a straight
        fall; > 1: bouncing and rolling where the particles land, Song (2003) L600-618). The step is
        d = c_0 h_m sin(theta) + (the extra advance of the fall through the gas).
    """

    gas_mass_flow: float
    gas_density: float
    gas_viscosity: float
    radius: float
    gas_flow: str
    particle_diameter: float
    particle_density: float
    velocity_ratio: float | None = None
    method: str = "schiller_naumann_1933"
    curtain_coefficient: float = SHERRITT_COEFFICIENT
    step_factor: float = 1.0

    def __post_init__(self):
        check_range("gas.flow", self.gas_mass_flow, 0.0, math.inf, low_inclusive=True, unit="kg/s")
        check_range("gas density", self.gas_density, 0.0, math.inf, unit="kg/m^3")
        check_range("gas viscosity", self.gas_viscosity, 0.0, math.inf, unit="Pa s")
        check_range("drum.radius", self.radius, 0.0, math.inf, unit="m")
        check_choice("gas direction", self.gas_flow, GAS_FLOWS)
        check_range("material.particle_diameter", self.particle_diameter, 0.0, math.inf, unit="m")
        check_range("material.particle_density", self.particle_density, self.gas_density, math.inf, unit="kg/m^3")
        if self.velocity_ratio is not None:
            check_key("transport.curtain_velocity_ratio", self.velocity_ratio)
        check_key("transport.curtain_coefficient", self.curtain_coefficient)
        check_key("transport.step_factor", self.step_factor)

    @classmethod
    def at_conditions(cls, *, gas_mass_flow, temperature_degC, humidity, radius, gas_flow, particle_diameter,
                      particle_density, velocity_ratio=None, method="schiller_naumann_1933",
                      curtain_coefficient=SHERRITT_COEFFICIENT, step_factor=1.0, pressure=101325.0):
        """From the gas flow (kg/s wet), temperature (degC), water mass fraction (kg/kg wet gas) and
        pressure (Pa; the site's, a case's ``site.altitude``): density (ideal gas) and viscosity
        (Wilke) of humid air, [`rotarydryer.properties.humid_air`][rotarydryer.properties.humid_air]."""
        from ..properties import humid_air as ha

        t = float(check_range("gas.inlet_temperature", temperature_degC, 0.0, 600.0, low_inclusive=True,
                              high_inclusive=True, unit="degC"))
        y = float(check_key("gas.inlet_humidity", humidity))
        Y = float(ha.humidity_from_mass_fraction(y))
        return cls(gas_mass_flow=float(gas_mass_flow), gas_density=float(ha.density(t, Y, pressure)),
                   gas_viscosity=float(ha.viscosity(t, Y)), radius=float(radius), gas_flow=gas_flow,
                   particle_diameter=float(particle_diameter), particle_density=float(particle_density),
                   velocity_ratio=None if velocity_ratio is None else float(velocity_ratio), method=method,
                   curtain_coefficient=float(curtain_coefficient), step_factor=float(step_factor))

    @property
    def gas_velocity(self) -> float:
        """Superficial axial gas velocity u_g = G/(rho_g pi R^2), m/s."""
        return self.gas_mass_flow / (self.gas_density * math.pi * self.radius**2)


class ForwardStepTable:
    """Axial advance (m) of a particle falling a height h (perpendicular to the drum axis, m)
    through gas of axial speed u (m/s), tabulated on [0, h_max] x [0, u_max] and interpolated
    bilinearly; exact (h tan(theta)) at u = 0. Build with [`forward_step_table`][rotarydryer.transport.forward_step.forward_step_table]."""

    def __init__(self, gas: CurtainGas, slope: float, n_height: int = 33, n_velocity: int = 17, n_steps: int = 50):
        from ..correlations.trajectory import cascade_trajectory

        self.gas, self.slope = gas, float(slope)
        self.h = np.linspace(0.0, 2.0 * gas.radius, n_height)
        u_max = gas.gas_velocity if gas.velocity_ratio is None else gas.gas_velocity * gas.velocity_ratio
        self.u = np.linspace(0.0, max(u_max, 1e-9), n_velocity)
        self._tan = math.tan(math.radians(self.slope))
        H, U = np.meshgrid(self.h[1:], self.u, indexing="ij")
        if u_max > 0:
            r = cascade_trajectory(H, gas.particle_diameter, gas.particle_density, gas.gas_density, gas.gas_viscosity,
                                   gas_velocity=U, gas_flow=gas.gas_flow, inclination=self.slope, method=gas.method,
                                   n_steps=n_steps)
            x = np.asarray(r.axial_displacement, float).reshape(H.shape)
            t = np.asarray(r.fall_time, float).reshape(H.shape)
        else:
            x = H * self._tan
            t = np.full_like(H, np.nan)
        # store the gas-induced part x - h tan(theta): zero at u = 0 and at h = 0 (exact there)
        self.excess = np.vstack([np.zeros((1, self.u.size)), x - H * self._tan])
        self.excess[:, 0] = 0.0
        self.fall_time = np.vstack([np.zeros((1, self.u.size)), t])

    def __call__(self, fall_height, gas_velocity):
        """Advance (m, + toward the discharge) at perpendicular fall heights and gas speeds (arrays)."""
        h = np.minimum(np.maximum(np.asarray(fall_height, float), 0.0), self.h[-1])
        u = np.minimum(np.maximum(np.asarray(gas_velocity, float), 0.0), self.u[-1])
        i = np.minimum(np.maximum(np.searchsorted(self.h, h) - 1, 0), self.h.size - 2)
        j = np.minimum(np.maximum(np.searchsorted(self.u, u) - 1, 0), self.u.size - 2)
        a = (h - self.h[i]) / (self.h[i + 1] - self.h[i])
        b = (u - self.u[j]) / (self.u[j + 1] - self.u[j])
        e = self.excess
        ex = ((1 - a) * (1 - b) * e[i, j] + a * (1 - b) * e[i + 1, j]
              + (1 - a) * b * e[i, j + 1] + a * b * e[i + 1, j + 1])
        return h * self._tan + ex


@lru_cache(maxsize=64)
def forward_step_table(gas: CurtainGas, slope: float) -> ForwardStepTable:
    """The (cached) [`ForwardStepTable`][rotarydryer.transport.forward_step.ForwardStepTable] of a gas/particle set and a drum slope (deg)."""
    return ForwardStepTable(gas, float(slope))


def curtain_velocity_ratio(gas: CurtainGas, fall_height, release_rate_per_length):
    """c_v = U_c/U_g of the curtains, in [0, 1]: ``gas.velocity_ratio`` when fixed, else Sherritt's
    Lee (2008) Eq. 2.14 with F = q x 1 m and L = 1 m (module docstring): [`sherritt_form`][rotarydryer.transport.forward_step.sherritt_form],
    K h^-0.76 q^-0.86 with K = ``gas.curtain_coefficient``, h in m, q in kg/(s m)."""
    h = np.maximum(np.asarray(fall_height, float), 1e-9)
    q = np.asarray(release_rate_per_length, float)
    if gas.velocity_ratio is not None:
        return np.full(np.broadcast(h, q).shape, float(gas.velocity_ratio))
    return np.minimum(np.maximum(sherritt_form(h, np.maximum(q, 1e-12), gas.curtain_coefficient), 0.0), 1.0)


def trajectory_forward_step(gas: CurtainGas, slope, fall_height, release_rate_per_length):
    """Mean axial advance of a cascade per cell.

    Parameters
    ----------
    gas : CurtainGas
    slope : float
        Drum slope theta, deg.
    fall_height : array_like
        Mass-averaged *vertical* fall height h_m of each cell, m (Lee (2008) Eq. 3.5); the
        trajectory falls h_m cos(theta) perpendicular to the axis.
    release_rate_per_length : array_like
        Flight discharge into the curtain per metre of drum, kg/(s m).

    Returns
    -------
    dict with ``step_m`` (advance, m, + toward the discharge), ``curtain_velocity_ratio`` (c_v)
    and ``curtain_gas_velocity_m_s`` (U_c).

    Examples
    --------
    Invicta's gas (30.4 kg/s at 100 degC, counter-current) and sugar; a cell with h_m = 3 m
    releasing 90 kg/(s m): C_F^G = 0.1365/(3 sin 2.8 deg) = 0.93.

    >>> g = CurtainGas.at_conditions(gas_mass_flow=30.4, temperature_degC=100.0, humidity=0.0128, radius=2.5,
    ...                              gas_flow="counter-current", particle_diameter=850e-6, particle_density=1588.0)
    >>> round(g.gas_velocity, 3)
    1.65
    >>> r = trajectory_forward_step(g, 2.8, [3.0], [90.0])
    >>> round(float(r["curtain_velocity_ratio"][0]), 4), round(float(r["step_m"][0]), 4)
    (0.014, 0.1365)
    """
    table = forward_step_table(gas, float(slope))
    h_perp = np.asarray(fall_height, float) * math.cos(math.radians(float(slope)))
    cv = curtain_velocity_ratio(gas, fall_height, release_rate_per_length)
    uc = cv * gas.gas_velocity
    step = table(h_perp, uc)
    if gas.step_factor != 1.0:      # the landing's own advance: c_0 h_m sin(theta) instead of the straight fall's
        step = step + (gas.step_factor - 1.0) * h_perp * table._tan
    return dict(step_m=step, curtain_velocity_ratio=cv, curtain_gas_velocity_m_s=uc)
