r"""Size a flighted rotary dryer for a drying duty (issue 17, part 1).

From a `Duty` (material, wet feed rate, inlet and target outlet moisture, gas inlet
temperature and gas flow or a number of transfer units, burner limit) `design` searches
drum diameter and length (as L/D), slope, speed and flights (number, base length s1, tip length
s2, tip angle alpha2; base angle 90 deg) with SciPy's ``differential_evolution`` (integer flight
count), the drum at least as long as the drying requirement, minimising drum volume, fuel per kg of water
evaporated, or a cost proxy, under the constraints the engineer sets:

* **drying** - the heat to the solids (evaporation at the wet-bulb temperature, vapour and solids
  heating) is transferred with the volumetric coefficient of McCormick (1962), Perry's Chemical
  Engineers' Handbook (Sec. 12, rotary dryers; 0.5 G^0.67/D in Btu/(h ft3 F), in SI):
  $Ua = 237\,G^{0.67}/D$ W/(m^3 K) (G gas mass velocity kg/(m^2 s), D m) over the log-mean
  difference of gas and wet-bulb temperature: $V = Q/(Ua\,\Delta T_{lm})$, so the length is $L = 4V/(\pi D^2)$;
  without a gas flow, the exhaust temperature follows from ``ntu`` (Perry: economical rotary
  dryers have 1.5-2.5 transfer units), $T_{out} = T_{wb} + (T_{in}-T_{wb})e^{-NTU}$,
  and the gas flow from the energy balance (with the shell loss);
* **speed** below ``speed_fraction_max`` of the critical speed $N_c = 42.3/\sqrt{D}$
  (`rotarydryer.geometry.drum.critical_speed`);
* **gas velocity** (either end, free area) below ``entrainment_fraction`` times the terminal
  velocity of the material's particles (`rotarydryer.correlations.drag.terminal_velocity`)
  and below ``gas_velocity_max`` (dust carry-over; 5 m/s, Ajayi (2011) l.1922: 3-5 m/s);
* **fill**: holdup (mean residence time of Perry & Green (1984), Friedman & Marshall,
  `rotarydryer.correlations.residence_time.perry_green_1984`, times the solids flow) at most
  ``fill_max`` of the drum volume (Perry: 10-15 %);
* **flights at design load**: holdup / design load (exact flight geometry,
  `rotarydryer.geometry.FlightedDrum.design_load_area`, Lee 2008 Ch. 4) within
  1 +- ``design_load_tolerance`` (under-loaded flights waste curtain, over-loaded ones kiln);
* **L/D** within ``length_to_diameter`` (Perry: 4-10), diameter within ``diameter_range``;
* **exhaust** at least 10 K above its dew point; **burner**: fuel rate at most ``max_fuel_rate``.

The result ranks the feasible designs and names the binding constraints (slack below 3 %); an
infeasible duty raises `InfeasibleDuty` (a ``ValueError``) naming the blocking constraint.
`check_plant` applies the same screening to a shipped plant's real geometry and duty and
says how far it is from the optimum. `verify` runs the coupled heat-and-mass model
(`rotarydryer.Simulation`) on a design.
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from typing import Optional

import numpy as np

from ._validation import check_choice, check_range
from .correlations import CorrelationRangeWarning
from .executor import Executor, RunFailure

__all__ = ["Duty", "Limits", "Design", "DesignResult", "InfeasibleDuty", "design", "evaluate", "check_plant",
           "verify", "design_verified", "verified_violations", "OBJECTIVES", "raw_sugar_duty", "mmg_duty"]

OBJECTIVES = ("volume", "fuel", "cost")
#: fuel oil lower heating value, J/kg (Ajayi (2011) App. A: LHV 41.6 MJ/kg)
FUEL_LHV = 41.6e6
BINDING_SLACK = 0.03
_VARS = ("diameter_m", "length_to_diameter", "slope_deg", "speed_fraction", "n_flights", "s1_fraction", "s2_ratio",
         "alpha2_deg")


class InfeasibleDuty(ValueError):
    """No design meets the duty within the constraints; ``constraint`` names the blocking one."""

    def __init__(self, message, constraint=None):
        super().__init__(message)
        self.constraint = constraint


@dataclasses.dataclass
class Duty:
    """A drying duty (SI, degC; moistures kg/kg wet)."""

    material: str
    feed_rate: float
    moisture_in: float
    moisture_out: float
    gas_inlet_temperature: float
    gas_flow: Optional[float] = None          # kg/s wet; None: from ``ntu`` and the energy balance
    ntu: float = 2.0
    direction: str = "counter-current"
    feed_temperature: float = 25.0
    product_temperature: Optional[float] = None   # None: wet-bulb + 10 K (at least the feed temperature)
    gas_inlet_humidity: float = 0.01          # kg/kg dry gas
    ambient_temperature: float = 25.0
    shell_u: float = 6.0                      # W/(m2 K), bare shell to ambient
    max_fuel_rate: Optional[float] = None     # kg/s fuel oil (burner capacity)
    pressure: float = 101325.0                # Pa, the site's (a case's altitude: `plant_from_case`)

    def validate(self):
        from .properties.materials import load_material

        check_range("feed_rate", self.feed_rate, 0.0, 1000.0, unit="kg/s")
        check_range("moisture_in", self.moisture_in, 0.0, 0.95, unit="kg/kg wet")
        check_range("moisture_out", self.moisture_out, 0.0, 0.95, low_inclusive=True, unit="kg/kg wet")
        if self.moisture_out >= self.moisture_in:
            raise ValueError(f"moisture_out = {self.moisture_out:g} must be below moisture_in = "
                             f"{self.moisture_in:g} kg/kg wet: the duty must dry")
        check_range("feed_temperature", self.feed_temperature, -20.0, 99.0, unit="degC")
        check_range("gas_inlet_temperature", self.gas_inlet_temperature, -20.0, 1000.0, unit="degC")
        if not self.gas_inlet_temperature > self.feed_temperature:
            raise ValueError(f"gas_inlet_temperature = {self.gas_inlet_temperature:g} degC must be above "
                             f"feed_temperature = {self.feed_temperature:g} degC: the gas must heat the feed")
        if self.gas_flow is not None:
            check_range("gas_flow", self.gas_flow, 0.0, 1000.0, unit="kg/s")
        check_range("ntu", self.ntu, 0.1, 6.0, high_inclusive=True)
        check_choice("direction", self.direction, ("co-current", "counter-current"))
        check_range("gas_inlet_humidity", self.gas_inlet_humidity, 0.0, 0.3, low_inclusive=True,
                    unit="kg/kg dry gas")
        check_range("shell_u", self.shell_u, 0.0, 100.0, low_inclusive=True, unit="W/(m2 K)")
        if self.max_fuel_rate is not None:
            check_range("max_fuel_rate", self.max_fuel_rate, 0.0, 100.0, unit="kg/s")
        check_range("pressure", self.pressure, 30e3, 120e3, high_inclusive=True, unit="Pa")
        self._material = load_material(self.material)
        return self


@dataclasses.dataclass
class Limits:
    """Constraints and search bounds of the design."""

    speed_fraction_max: float = 0.5           # of the critical speed (rotarydryer.geometry.drum warns above 0.5)
    entrainment_fraction: float = 1.0         # of the particles' terminal velocity
    fill_max: float = 0.15                    # holdup / drum volume
    design_load_tolerance: float = 0.15       # |holdup / design load - 1|
    length_to_diameter: tuple = (4.0, 10.0)
    diameter_range: tuple = (0.5, 6.0)        # m
    slope_range: tuple = (0.5, 5.0)           # deg
    flights_range: tuple = (8, 60)
    dew_point_margin: float = 10.0            # K
    peripheral_speed_max: float = 1.0         # m/s (a choice: the shipped plants run at 0.6-0.8 m/s)
    ua_factor: float = 1.0                    # multiplier on McCormick's Ua (calibrate with check_plant)
    holdup_factor: float = 1.0                # multiplier on Perry & Green's residence time (design_verified sets it
                                              # to the coupled model's holdup over the screening's)
    gas_velocity_max: float = 5.0             # m/s, dust carry-over (Ajayi (2011) l.1922: 3-5 m/s in MMG)

    def validate(self):
        check_range("speed_fraction_max", self.speed_fraction_max, 0.0, 1.0)
        check_range("entrainment_fraction", self.entrainment_fraction, 0.0, 2.0, high_inclusive=True)
        check_range("fill_max", self.fill_max, 0.0, 0.5, high_inclusive=True)
        check_range("peripheral_speed_max", self.peripheral_speed_max, 0.0, 10.0, unit="m/s")
        check_range("ua_factor", self.ua_factor, 0.0, 100.0)
        check_range("holdup_factor", self.holdup_factor, 0.0, 100.0)
        check_range("gas_velocity_max", self.gas_velocity_max, 0.0, 100.0, unit="m/s")
        check_range("design_load_tolerance", self.design_load_tolerance, 0.0, 10.0, high_inclusive=True)
        lo, hi = self.length_to_diameter
        check_range("length_to_diameter", lo, 0.5, 50.0, high_inclusive=True)
        check_range("length_to_diameter", hi, lo, 50.0, low_inclusive=True, high_inclusive=True)
        lo, hi = self.diameter_range
        check_range("diameter_range", lo, 0.05, 20.0, high_inclusive=True, unit="m")
        check_range("diameter_range", hi, lo, 20.0, low_inclusive=True, high_inclusive=True, unit="m")
        return self


@dataclasses.dataclass
class Design:
    """One drum: geometry, operating point, derived quantities and constraint values."""

    diameter_m: float
    length_m: float
    slope_deg: float
    rpm: float
    n_flights: int
    s1_m: float
    s2_m: float
    alpha2_deg: float
    values: dict
    constraints: dict          # name -> (value, limit, sense "<=" / ">=", normalised violation g (<= 0 ok))
    objective: float = math.nan

    @property
    def feasible(self):
        return all(c[3] <= 1e-9 for c in self.constraints.values())

    def binding(self, slack=BINDING_SLACK):
        return [k for k, c in self.constraints.items() if -slack <= c[3] <= 1e-9]

    def row(self):
        v = self.values
        return dict(diameter_m=self.diameter_m, length_m=self.length_m, slope_deg=self.slope_deg, rpm=self.rpm,
                    n_flights=self.n_flights, s1_m=self.s1_m, s2_m=self.s2_m, alpha1_deg=90.0,
                    alpha2_deg=self.alpha2_deg, volume_m3=v["volume_m3"],
                    fuel_per_kg_water_MJ=v["heat_input_per_kg_water_J"] / 1e6, cost_index=v["cost_index"],
                    gas_flow_kg_s=v["gas_flow_kg_s"], gas_outlet_temperature_degC=v["gas_outlet_temperature_degC"],
                    gas_velocity_m_s=v["gas_velocity_m_s"], terminal_velocity_m_s=v["terminal_velocity_m_s"],
                    fill_fraction=v["fill_fraction"], holdup_over_design_load=v["holdup_over_design_load"],
                    speed_over_critical=v["speed_over_critical"], mean_residence_time_s=v["mean_residence_time_s"],
                    fuel_rate_kg_s=v["fuel_rate_kg_s"], objective=self.objective,
                    binding=", ".join(self.binding()) or "-")


# ------------------------------------------------------------------------------------------- duty physics
def _gas_props(T, Y, pressure=101325.0):
    from .properties import humid_air as ha

    return float(ha.density(T, Y, pressure)), float(ha.viscosity(T, Y))


def _wet_bulb(T, Y, pressure=101325.0):
    """Adiabatic-saturation temperature, degC (h(T, Y) = h(T_s, Y_sat(T_s)) at ``pressure`` Pa)."""
    from scipy.optimize import brentq

    from .properties import humid_air as ha
    from .properties.water import saturation_pressure

    h = float(ha.enthalpy(T, Y))

    def f(ts):
        pv = float(saturation_pressure(ts))
        ys = min(0.621945 * pv / max(pressure - pv, 1e-9), 0.3)    # saturated humidity (model range <= 0.3)
        return float(ha.enthalpy(ts, ys)) - h
    hi = min(T, 71.0)                                       # Y_sat(71 degC) ~ 0.3 kg/kg
    return float(brentq(f, 0.0, hi)) if f(hi) > 0 else hi


class _DutyModel:
    """Geometry-independent parts of the duty, precomputed once."""

    def __init__(self, duty: Duty):
        from .correlations.drag import terminal_velocity
        from .properties import humid_air as ha
        from .properties.water import latent_heat, vapour_heat_capacity

        self.duty = d = duty
        m = d._material
        self.material = m
        lo, hi = m.wet_range()
        self.S = d.feed_rate * (1 - d.moisture_in)
        self.X_in, self.X_out = d.moisture_in / (1 - d.moisture_in), d.moisture_out / (1 - d.moisture_out)
        self.E = self.S * (self.X_in - self.X_out)
        self.F_out = self.S * (1 + self.X_out)
        self.x_mean = float(np.clip(0.5 * (d.moisture_in + d.moisture_out), lo, hi))
        self.repose = float(m.repose_angle(self.x_mean))
        self.rho_b = float(m.bulk_density(self.x_mean))
        self.T_wb = _wet_bulb(d.gas_inlet_temperature, d.gas_inlet_humidity, d.pressure)
        self.T_p = (d.product_temperature if d.product_temperature is not None
                    else max(self.T_wb + 10.0, d.feed_temperature))
        self.lam = float(latent_heat(self.T_wb))
        self.cp_v = float(vapour_heat_capacity(0.5 * (self.T_wb + d.gas_inlet_temperature)))
        self.cp_w = m.water_heat_capacity
        self.cp_s = m.heat_capacity
        self.cp_h = float(ha.humid_heat(0.5 * (d.gas_inlet_temperature + self.T_wb), d.gas_inlet_humidity))
        dp = m.particle_diameter
        self.dp = dp
        self._vt = {}
        self.Q_solids = (self.S * self.cp_s + self.S * self.X_out * self.cp_w) * (self.T_p - d.feed_temperature)
        self.h_in = float(ha.enthalpy(d.gas_inlet_temperature, d.gas_inlet_humidity))
        self.h_amb = float(ha.enthalpy(d.ambient_temperature, d.gas_inlet_humidity))
        self._terminal = terminal_velocity

    def q_evap(self, T_out):
        return self.E * (self.cp_w * (self.T_wb - self.duty.feed_temperature) + self.lam
                         + self.cp_v * (T_out - self.T_wb))

    def terminal(self, T, Y):
        key = (round(T, 1), round(Y, 4))
        if key not in self._vt:
            rho, mu = _gas_props(T, Y, self.duty.pressure)
            self._vt[key] = (float(self._terminal(self.dp, self.material.particle_density, rho, mu)), rho)
        return self._vt[key]

    def gas(self, shell_loss):
        """(dry gas flow kg/s, exhaust T degC) closing the energy balance with ``shell_loss`` W."""
        from scipy.optimize import brentq

        d = self.duty
        Tin = d.gas_inlet_temperature
        if d.gas_flow is None:
            T_out = self.T_wb + (Tin - self.T_wb) * math.exp(-d.ntu)
            G = (self.q_evap(T_out) + self.Q_solids + shell_loss) / (self.cp_h * (Tin - T_out))
            return G, T_out
        G = d.gas_flow / (1 + d.gas_inlet_humidity)

        def f(T):
            return G * self.cp_h * (Tin - T) - self.q_evap(T) - self.Q_solids - shell_loss
        lo = -50.0
        if f(lo) < 0:   # not even cooling the gas to -50 degC supplies the duty
            return G, -math.inf
        return G, float(brentq(f, lo, Tin))


#: the unit of each screening constraint's value and limit (a ratio: "-")
CONSTRAINT_UNITS = {"gas heat capacity": "-", "drying length": "m", "exhaust dew point": "degC",
                    "critical speed": "-", "peripheral speed": "m/s", "gas entrainment": "m/s", "gas velocity": "m/s",
                    "L/D max": "-", "L/D min": "-", "diameter max": "m", "residence time correlation": "-",
                    "fill": "-", "flight geometry": "-", "flights over-loaded": "-", "flights under-loaded": "-",
                    "burner capacity": "kg/s"}


#: what each constraint's value is, where its name says what it guards instead (the text surfaces' label)
CONSTRAINT_LABELS = {"exhaust dew point": "exhaust temperature against its dew point + margin"}


def constraint_text(name: str, value: float, limit: float, sense: str) -> tuple[str, str, str]:
    """(label, value, limit) of a screening constraint for a person: the label of what the value is
    (`CONSTRAINT_LABELS`: "exhaust dew point" compares the exhaust temperature) and the value and limit in the display
    units (``--units``; a ratio or a velocity as a number with its unit)."""
    from ._display import UNIT_QUANTITIES, fmt, show

    unit = CONSTRAINT_UNITS.get(name, "-")
    q, f = UNIT_QUANTITIES.get(unit, (None, 1.0))
    if q is not None:
        shown = show(value * f, q), show(limit * f, q)
    else:
        shown = tuple(fmt(x) + ("" if unit == "-" else f" {unit}") for x in (value, limit))
    return CONSTRAINT_LABELS.get(name, name), shown[0], f"{sense} {shown[1]}"


def _constraint(value, limit, sense):
    g = (value - limit) / max(abs(limit), 1e-12) if sense == "<=" else (limit - value) / max(abs(limit), 1e-12)
    return (float(value), float(limit), sense, float(g))


def evaluate(dm: _DutyModel, limits: Limits, diameter_m, slope_deg, rpm, n_flights, s1_m, s2_m, alpha2_deg,
             length_m=None, objective="volume") -> Design:
    """Constraint values and objectives of one geometry for the duty (``length_m`` None: the
    length the drying requirement needs)."""
    from .correlations.residence_time import perry_green_1984
    from .geometry import FlightedDrum, TwoSectionFlight
    from .geometry.drum import critical_speed
    from .properties import humid_air as ha

    d = dm.duty
    D = float(diameter_m)
    R = D / 2
    A = math.pi * D**2 / 4
    Tin = d.gas_inlet_temperature
    cons = {}
    vals = {}
    # energy balance <-> length (shell loss depends on the length): fixed point
    L = float(length_m) if length_m is not None else 4.0 * D
    fill_guess = 0.1
    for _ in range(4):
        shell_loss = d.shell_u * math.pi * D * L * (0.5 * (Tin + dm.T_wb) - d.ambient_temperature)
        G, T_out = dm.gas(shell_loss)
        if not math.isfinite(T_out):
            break
        A_free = A * (1 - fill_guess)
        G_flux = G * (1 + d.gas_inlet_humidity) / A_free
        Ua = limits.ua_factor * 237.0 * G_flux**0.67 / D    # McCormick (1962), Perry Sec. 12
        dT1, dT2 = Tin - dm.T_wb, max(T_out - dm.T_wb, 1e-3)
        dTlm = (dT1 - dT2) / math.log(dT1 / dT2) if abs(dT1 - dT2) > 1e-9 else dT1
        Q_solids = dm.q_evap(T_out) + dm.Q_solids
        L_req = Q_solids / (Ua * dTlm) / A
        if length_m is None:
            L = L_req
    vals["shell_loss_W"] = shell_loss
    if not math.isfinite(T_out):
        cons["gas heat capacity"] = _constraint(0.0, 1.0, ">=")
        return Design(D, L, slope_deg, rpm, int(n_flights), s1_m, s2_m, alpha2_deg,
                      dict(volume_m3=A * L, heat_input_per_kg_water_J=math.inf, cost_index=math.inf), cons, math.inf)
    Y_out = d.gas_inlet_humidity + dm.E / G
    cons["drying length"] = _constraint(L, L_req, ">=")
    dew = float(ha.dew_point(min(Y_out, 0.3), d.pressure))
    cons["exhaust dew point"] = _constraint(T_out, dew + limits.dew_point_margin, ">=")
    nc = critical_speed(R)
    cons["critical speed"] = _constraint(rpm / nc, limits.speed_fraction_max, "<=")
    cons["peripheral speed"] = _constraint(math.pi * D * rpm / 60.0, limits.peripheral_speed_max, "<=")
    # gas velocity at either end vs entrainment
    u_max_ratio, u_show, vt_show = 0.0, 0.0, 0.0
    for T, Y in ((Tin, d.gas_inlet_humidity), (T_out, Y_out)):
        vt, rho = dm.terminal(T, Y)
        u = G * (1 + Y) / rho / A_free
        if u / vt > u_max_ratio:
            u_max_ratio, u_show, vt_show = u / vt, u, vt
    cons["gas entrainment"] = _constraint(u_show, limits.entrainment_fraction * vt_show, "<=")
    u_hot = max(G * (1 + Y) / dm.terminal(T, Y)[1] / A_free for T, Y in ((Tin, d.gas_inlet_humidity), (T_out, Y_out)))
    cons["gas velocity"] = _constraint(u_hot, limits.gas_velocity_max, "<=")
    lo, hi = limits.length_to_diameter
    cons["L/D max"] = _constraint(L / D, hi, "<=")
    cons["L/D min"] = _constraint(L / D, lo, ">=")
    cons["diameter max"] = _constraint(D, limits.diameter_range[1], "<=")
    # residence time, holdup, fill, design load
    G_flux = G * (1 + d.gas_inlet_humidity) / A_free
    S_flux = d.feed_rate / A
    rt = dict(length=L, diameter=D, slope=math.tan(math.radians(slope_deg)), rpm=rpm, particle_size=dm.dp,
              solids_mass_flux=S_flux, gas_flow=d.direction, allow_nonpositive=True)
    try:
        with warnings.catch_warnings():     # a non-positive residence time is the constraint below, not a warning
            warnings.simplefilter("ignore", CorrelationRangeWarning)         # for each of a search's thousands of drums
            tau = float(perry_green_1984(gas_mass_flux=G_flux, **rt))
            tau_no_gas = float(perry_green_1984(gas_mass_flux=0.0, **rt))
    except ValueError:
        tau, tau_no_gas = math.nan, math.nan
    # Friedman-Marshall's co-current gas term is linear in the gas flux: where it exceeds the geometric
    # term the correlation gives no residence time at all (a fast co-current gas on fine solids); such a
    # design is outside the correlation, and says so, instead of screening a drum with no holdup
    share = tau / tau_no_gas if math.isfinite(tau) and tau_no_gas > 0 else math.nan
    cons["residence time correlation"] = (share, 0.0, ">=", -share if math.isfinite(share) else 1.0)
    # outside the correlation the holdup, fill and flight loading are void: the search screens them at a 1e-6 s
    # residence time as ever (its penalties steer it), and the values report them as none (null), not as numbers
    void = not math.isfinite(tau) or tau <= 0
    if void:
        tau = 1e-6
    else:
        tau *= limits.holdup_factor
    H = tau * 0.5 * (d.feed_rate + dm.F_out)
    fill = H / (dm.rho_b * A * L)
    fill_guess = min(fill, 0.5)
    cons["fill"] = _constraint(fill, limits.fill_max, "<=")
    try:
        drum = FlightedDrum(R, int(n_flights), TwoSectionFlight(s1=s1_m, s2=s2_m, alpha1=90.0, alpha2=alpha2_deg))
        DL = float(drum.design_load_area(dm.repose)) * dm.rho_b * L
        ratio = H / DL if DL > 0 else math.inf
        cons["flight geometry"] = _constraint(0.0, 1.0, "<=")
    except (ValueError, ZeroDivisionError):
        DL, ratio = math.nan, math.inf
        cons["flight geometry"] = _constraint(2.0, 1.0, "<=")
    if math.isfinite(ratio):
        cons["flights over-loaded"] = _constraint(ratio, 1 + limits.design_load_tolerance, "<=")
        cons["flights under-loaded"] = _constraint(ratio, max(1 - limits.design_load_tolerance, 1e-6), ">=")
    heat_in = G * (dm.h_in - dm.h_amb)
    fuel = heat_in / FUEL_LHV
    if d.max_fuel_rate is not None:
        cons["burner capacity"] = _constraint(fuel, d.max_fuel_rate, "<=")
    vals.update(volume_m3=A * L, length_required_m=L_req, heat_input_W=heat_in,
                heat_input_per_kg_water_J=heat_in / dm.E, fuel_rate_kg_s=fuel,
                cost_index=(math.pi * D * L + 2 * A) ** 0.6,
                gas_flow_kg_s=G * (1 + d.gas_inlet_humidity), gas_outlet_temperature_degC=T_out,
                gas_outlet_humidity_kg_kg=Y_out, gas_velocity_m_s=u_show, terminal_velocity_m_s=vt_show,
                volumetric_ua_W_m3K=Ua, mean_residence_time_s=tau, holdup_kg=H, design_load_kg=DL,
                fill_fraction=fill, holdup_over_design_load=ratio, speed_over_critical=rpm / nc,
                critical_speed_rpm=nc, evaporation_kg_s=dm.E, wet_bulb_degC=dm.T_wb, product_temperature_degC=dm.T_p)
    if void:
        vals.update(mean_residence_time_s=math.nan, holdup_kg=math.nan, fill_fraction=math.nan,
                    holdup_over_design_load=math.nan)
    obj = {"volume": vals["volume_m3"], "fuel": vals["heat_input_per_kg_water_J"] / 1e6,
           "cost": vals["cost_index"]}[objective]
    return Design(D, L, float(slope_deg), float(rpm), int(n_flights), float(s1_m), float(s2_m), float(alpha2_deg),
                  vals, cons, float(obj))


# ------------------------------------------------------------------------------------------- search
@dataclasses.dataclass
class DesignResult:
    duty: Duty
    objective: str
    designs: list           # feasible, best first
    best: Design
    seconds: float
    evaluations: int

    def table(self, n=10):
        return [dict(rank=i + 1, **d.row()) for i, d in enumerate(self.designs[:n])]

    def summary(self):
        b = self.best
        return dict(objective=self.objective, best=b.row(), binding_constraints=b.binding(),
                    constraints={k: dict(value=c[0], limit=c[1], sense=c[2], slack=-c[3])
                                 for k, c in b.constraints.items()},
                    values=b.values, n_feasible=len(self.designs), evaluations=self.evaluations,
                    wall_time_s=self.seconds)


def _decode(x, limits, dm):
    from .geometry.drum import critical_speed

    D, ld, slope, phi, n, s1f, s2r, a2 = x
    R = D / 2
    return dict(diameter_m=float(D), length_m=float(ld * D), slope_deg=float(slope), rpm=float(phi * critical_speed(R)),
                n_flights=int(round(n)), s1_m=float(s1f * R), s2_m=float(s2r * s1f * R), alpha2_deg=float(a2))


class _Objective:
    """The search's objective of a parameter vector (a class, so that it pickles for worker processes):
    ``score(x)`` -> (value minimised, evaluated design or None, total constraint violation)."""

    def __init__(self, dm: _DutyModel, limits: Limits, objective: str):
        self.dm, self.limits, self.objective = dm, limits, objective

    def score(self, x):
        try:
            des = evaluate(self.dm, self.limits, objective=self.objective, **_decode(x, self.limits, self.dm))
        except (ValueError, ZeroDivisionError, OverflowError):
            return 1e9, None, math.inf
        viol = sum(max(0.0, c[3]) for c in des.constraints.values())
        if viol <= 1e-9:
            return math.log(des.objective), des, 0.0
        return 50.0 + 100.0 * viol, des, viol

    def __call__(self, x):
        return self.score(x)[0]


def _score(x, objective: _Objective):
    """One evaluation of a population (top-level, for the executor)."""
    return objective.score(x)


def design(duty: Duty, limits: Limits | None = None, objective="volume", maxiter=60, popsize=12, seed=1,
           progress=None, top=10, executor=None, check_limits=True) -> DesignResult:
    """Search the geometry that meets ``duty`` at the least ``objective`` (`OBJECTIVES`).

    ``check_limits``: check ``limits`` against the ranges a user may give (`Limits.validate`); False for
    limits widened to a plant's own values (`check_plant`), which may lie beyond them.

    Each generation's population is evaluated through ``executor`` (`rotarydryer.executor.Executor`,
    default serial) as SciPy's ``workers`` map; the results come back in population order, so the
    search is the same for a seed on every backend.

    Raises `InfeasibleDuty` naming the constraint that blocks the least-infeasible design."""
    from scipy.optimize import differential_evolution

    duty.validate()
    limits = limits or Limits()
    if check_limits:
        limits.validate()
    check_choice("objective", objective, OBJECTIVES)
    t0 = time.perf_counter()
    dm = _DutyModel(duty)
    bounds = [limits.diameter_range, limits.length_to_diameter, limits.slope_range,
              (0.05, min(0.95, 1.2 * limits.speed_fraction_max)),
              limits.flights_range, (0.04, 0.25), (0.0, 1.2), (100.0, 170.0)]
    archive = []
    least = [None, math.inf]
    count = [0]
    scorer = _Objective(dm, limits, objective)
    ex = executor or Executor()

    def record(result):
        value, des, viol = result
        count[0] += 1
        if des is not None and viol <= 1e-9:
            archive.append(des)
        elif des is not None and viol < least[1]:
            least[0], least[1] = des, viol
        return value

    def f(x):
        return record(scorer.score(x))

    def population(func, xs):
        """SciPy's map over a generation (``func`` is its wrapper of the objective, ``scorer``): the
        scores through the executor, in population order, the designs kept here."""
        xs = [np.asarray(x, dtype=float) for x in xs]
        # independent evaluations: the chunking does not change the results
        out = ex.map(_score, xs, args=(scorer,), chunks=ex.independent_chunks(len(xs)))
        return [record((1e9, None, math.inf) if isinstance(r, RunFailure) else r) for r in out]

    it = [0]

    def cb(xk, convergence=None):
        it[0] += 1
        if progress and it[0] % 5 == 0:
            # no feasible design yet: said so (it printed "best volume nan"; found by an acceptance check)
            best = (f"best {objective} {min(d.objective for d in archive):.4g}" if archive
                    else "no feasible design yet")
            progress(f"design: generation {it[0]}/{maxiter}, {count[0]} evaluations, {len(archive)} feasible, {best}")
    differential_evolution(scorer, bounds, integrality=[False, False, False, False, True, False, False, False],
                           maxiter=maxiter, popsize=popsize, seed=seed, polish=False, tol=1e-7, callback=cb,
                           updating="deferred", workers=population)
    if archive:   # local refinement of the best (Nelder-Mead on the continuous variables, flights fixed)
        from scipy.optimize import minimize

        b = min(archive, key=lambda d: d.objective)
        from .geometry.drum import critical_speed

        R = b.diameter_m / 2
        x0 = np.array([b.diameter_m, b.length_m / b.diameter_m, b.slope_deg, b.rpm / critical_speed(R), b.n_flights,
                       b.s1_m / R, b.s2_m / b.s1_m if b.s1_m > 0 else 0.0, b.alpha2_deg])
        lo_b = np.array([bb[0] for bb in bounds], float)
        hi_b = np.array([bb[1] for bb in bounds], float)
        cont = [0, 1, 2, 3, 5, 6, 7]

        def g(xc):
            x = x0.copy()
            x[cont] = np.clip(xc, lo_b[cont], hi_b[cont])
            return f(x)
        if progress:
            progress("design: local refinement (Nelder-Mead)")
        minimize(g, x0[cont], method="Nelder-Mead", options=dict(maxiter=300, xatol=1e-4, fatol=1e-6))
    if not archive:
        des = least[0]
        if des is None:
            raise InfeasibleDuty("infeasible duty: no geometry could be evaluated", None)
        worst = max(des.constraints.items(), key=lambda kv: kv[1][3])
        name, (v, lim, sense, g) = worst
        others = [k for k, c in des.constraints.items() if c[3] > 1e-9 and k != name]
        label, shown, limit = constraint_text(name, v, lim, sense)
        raise InfeasibleDuty(
            f"infeasible duty: no design meets it within the constraints; blocking constraint '{name}'"
            + ("" if label == name else f" ({label})")
            + f": {shown} {'>' if sense == '<=' else '<'} limit {limit[len(sense) + 1:]} in the least-infeasible design "
            f"(D = {des.diameter_m:.2f} m, L = {des.length_m:.1f} m)"
            + (f"; also violated: {', '.join(others)}" if others else "")
            + f". {_advice(name)}", name)
    archive.sort(key=lambda d: d.objective)
    ranked, seen = [], set()
    for dsg in archive:   # distinct designs (diameter to 5 cm, flight count)
        key = (round(dsg.diameter_m / 0.05), dsg.n_flights)
        if key in seen:
            continue
        seen.add(key)
        ranked.append(dsg)
        if len(ranked) >= top:
            break
    return DesignResult(duty, objective, ranked, ranked[0], time.perf_counter() - t0, count[0])


def _advice(name):
    return {"gas entrainment": "Lower the gas flow (higher inlet temperature), allow a larger diameter, or accept "
                               "entrainment (--entrainment-fraction).",
            "gas velocity": "Allow a larger diameter (--d-max) or a higher gas velocity (--gas-velocity-max).",
            "L/D max": "Allow a longer drum (--ld-max) or a larger diameter.",
            "diameter max": "Allow a larger diameter (--d-max) or split the duty over parallel dryers.",
            "exhaust dew point": "Raise the gas inlet temperature or the gas flow: the exhaust would condense.",
            "gas heat capacity": "The gas flow cannot carry the heat: raise the gas flow or inlet temperature.",
            "burner capacity": "Raise the burner capacity (--max-fuel) or lower the duty.",
            "fill": "Allow a higher fill (--fill-max) or a larger drum.",
            "residence time correlation": "The co-current gas term of Friedman-Marshall's residence time (Perry & "
                                          "Green (1984)) exceeds its geometric term: lower the gas flow (a hotter "
                                          "gas), widen the drum, or run the gas counter-current.",
            }.get(name, "Relax this constraint or change the duty.")


# ------------------------------------------------------------------------------------------- shipped plants
def raw_sugar_duty(**kw):
    """Issue 17's new raw-sugar dryer: 20 kg/s wet, 1.0 -> 0.1 % (wet basis), counter-current air
    at 100 degC (steam-coil heated, as the Invicta case), 22 kg/s (the Invicta case's 30.4 kg/s
    scaled to the feed), feed at 55 degC."""
    base = dict(material="raw_sugar_lee2008", feed_rate=20.0, moisture_in=0.010, moisture_out=0.001,
                gas_inlet_temperature=100.0, gas_flow=22.0, direction="counter-current", feed_temperature=55.0,
                gas_inlet_humidity=0.013)
    base.update(kw)
    return Duty(**base)


def mmg_duty(**kw):
    """The MMG Karumba duty (Ajayi (2011) Test 4, Table 6.1): 40.67 kg/s zinc concentrate
    16.3 -> 12.4 % wet, co-current burner gas 500 degC, 16.25 kg/s, feed 28 degC."""
    base = dict(material="zinc_concentrate_ajayi2011", feed_rate=40.666667, moisture_in=0.163, moisture_out=0.124,
                gas_inlet_temperature=500.0, gas_flow=16.25, direction="co-current", feed_temperature=28.0,
                gas_inlet_humidity=0.0193 / (1 - 0.0193), ambient_temperature=26.0)
    base.update(kw)
    return Duty(**base)


PLANTS = {
    # geometry: Lee (2008) Invicta 5 m x 12 m, 28 flights (case lee2008_invicta); duty as raw_sugar_duty
    # with the case's feed and moisture (0.02 -> 0.002 kg/kg, Lee code l.12456) and its chosen 30.4 kg/s air
    "lee2008_invicta": (dict(diameter_m=5.0, length_m=12.0, slope_deg=2.8, rpm=3.0, n_flights=28, s1_m=0.195,
                             s2_m=0.183, alpha2_deg=117.0),
                        lambda: raw_sugar_duty(feed_rate=27.222, moisture_in=0.02 / 1.02, moisture_out=0.002 / 1.002,
                                               gas_flow=30.4)),
    # Ajayi (2011) Table 3.2: 3.9 m x 22.2 m, 4 deg, 3 rpm, 30 flights (section D flights)
    "ajayi2011_mmg": (dict(diameter_m=3.9, length_m=22.2, slope_deg=4.0, rpm=3.0, n_flights=30, s1_m=0.12,
                           s2_m=0.21, alpha2_deg=130.0), mmg_duty),
}


#: the product moisture a duty taken from a case's own steady state aims at when that product leaves
#: (nearly) bone-dry: the screening's drying length diverges towards zero moisture
CASE_DUTY_MOISTURE_FLOOR = 1e-4


def plant_from_case(case, overrides=None, moisture_out=None):
    """``(geometry, duty, notes)`` of any dryer case for `check_plant`: the drum and the flights of its
    longest flighted section (two-section flights: the screening's flight model), the total drum
    length, the case's speed, slope, feed, gas and site, and as the duty's product moisture
    ``moisture_out`` (kg/kg wet) or, by default, the product moisture of the case's own steady state
    (at least `CASE_DUTY_MOISTURE_FLOOR`). ValueError naming what the screening cannot represent."""
    from .geometry.flights import TwoSectionFlight
    from .simulation import Simulation

    try:
        sim = Simulation(case, overrides or None)
        d = sim.thermal_dryer()
    except ValueError as exc:       # named by the option that gave the case
        raise ValueError(str(exc).replace(f"case = {case!r}", f"--check = {case!r}", 1)) from None
    st = d.settings
    flighted = [law for law in getattr(d, "laws", ()) if getattr(getattr(law, "spec", None), "geometry", None)
                is not None and hasattr(law.spec.geometry, "drum")]
    if not flighted:
        raise ValueError(f"--check {case}: the case has no flighted section; the screening sizes flighted drums")
    main = max(flighted, key=lambda law: law.spec.length)
    drum = main.spec.geometry.drum
    if not isinstance(drum.flight, TwoSectionFlight):
        raise ValueError(f"--check {case}: section {main.spec.name!r} has a {type(drum.flight).__name__}; the "
                         "screening models two-section flights (s1, s2, alpha2) only")
    notes = []
    if len({(law.spec.geometry.drum.n_flights, law.spec.geometry.drum.flight) for law in flighted}) > 1:
        notes.append(f"the flighted sections differ: the screening takes section {main.spec.name!r}'s flights "
                     "(the longest) for the whole drum")
    if abs(drum.flight.alpha1 - 90.0) > 1e-9:
        notes.append(f"the flight base stands at {drum.flight.alpha1:g} deg to the shell; the screening takes it radial")
    unflighted = d.length - sum(law.spec.length for law in flighted)
    if unflighted > 1e-9:
        notes.append(f"{unflighted:g} m of the {d.length:g} m drum are unflighted; the screening takes the whole "
                     "length as flighted")
    if moisture_out is None:
        summary = sim.steady_state().summary()
        x = float(summary["product_moisture_kg_kg"])
        moisture_out = max(x, CASE_DUTY_MOISTURE_FLOOR)
        if x < CASE_DUTY_MOISTURE_FLOOR:
            notes.append(f"the case's product leaves at {x:.3g} kg/kg: the duty aims at {CASE_DUTY_MOISTURE_FLOOR:g} "
                         "kg/kg wet (give --moisture-out to choose)")
        gas_flow = float(summary["gas_flow_kg_s"])
    else:
        gas_flow = float(st.gas_flow)
    slope = float(getattr(sim.case.drum, "slope", None) or math.degrees(math.asin(main.sin_t)))
    geom = dict(diameter_m=2.0 * float(d.radius), length_m=float(d.length), slope_deg=slope, rpm=float(d.rpm),
                n_flights=int(drum.n_flights), s1_m=float(drum.flight.s1), s2_m=float(drum.flight.s2),
                alpha2_deg=float(drum.flight.alpha2))
    duty = Duty(material=str(getattr(d.material, "name", d.material)), feed_rate=float(d.feed_rate),
                moisture_in=float(d.feed_moisture), moisture_out=float(moisture_out),
                gas_inlet_temperature=float(st.gas_inlet_temperature), gas_flow=gas_flow,
                direction=str(st.gas_direction), feed_temperature=float(st.solids_inlet_temperature),
                gas_inlet_humidity=float(d.gas_inlet_Y), ambient_temperature=float(st.ambient_temperature),
                pressure=float(st.pressure))
    return geom, duty, notes


#: the screening rules that rest on the residence-time correlation's holdup (void where it does not hold)
VOID_OUTSIDE_CORRELATION = ("fill", "flights over-loaded", "flights under-loaded")


def _widened(limit: float, own: float) -> float:
    """A limit widened to a plant's own value (with 0.1 % room); the limit where that value is void (none)."""
    return max(limit, 1.001 * own) if math.isfinite(own) else limit


def check_plant(name, limits: Limits | None = None, objective="volume", progress=None, overrides=None,
                moisture_out=None, **search):
    """A plant's real geometry under its own duty: a shipped plant of `PLANTS` (its published duty), or any
    dryer case (a name or a .toml file: `plant_from_case`, with ``overrides`` and ``moisture_out``).

    1. The screening rules at ``limits``: which the real plant violates (the correlations are
       generic: McCormick's Ua, Perry & Green's residence time).
    2. Calibrated on the plant: the Ua factor its length implies (required / real length) and
       the limits widened to the plant's own L/D, loading, fill and speed, so that the real
       geometry is feasible; the optimum of the same duty under these limits, and the ratio of
       the plant's objective to it (how far from the optimum) with the reasons.
    Returns a dict."""
    notes: list = []
    if name in PLANTS and not overrides and moisture_out is None:
        geom, duty_fn = PLANTS[name]
        duty = duty_fn().validate()
    else:
        geom, duty, notes = plant_from_case(name, overrides, moisture_out)
        duty = duty.validate()
    limits = (limits or Limits()).validate()
    dm = _DutyModel(duty)
    raw = evaluate(dm, limits, objective=objective, **geom)
    # outside the residence-time correlation the fill and flight loading are void: not listed as violated
    void = raw.constraints["residence time correlation"][3] > 1e-9
    violated = {k: dict(value=c[0], limit=c[1], sense=c[2], unit=CONSTRAINT_UNITS.get(k, "-"))
                for k, c in raw.constraints.items() if c[3] > 1e-9 and not (void and k in VOID_OUTSIDE_CORRELATION)}
    v = raw.values
    ua = limits.ua_factor * max(1.0, v["length_required_m"] / raw.length_m) * 1.001
    ld = raw.length_m / raw.diameter_m
    cal = dataclasses.replace(
        limits, ua_factor=ua,
        length_to_diameter=(min(limits.length_to_diameter[0], ld), max(limits.length_to_diameter[1], ld)),
        design_load_tolerance=_widened(limits.design_load_tolerance, abs(v["holdup_over_design_load"] - 1)),
        fill_max=_widened(limits.fill_max, v["fill_fraction"]),
        speed_fraction_max=max(limits.speed_fraction_max, 1.001 * v["speed_over_critical"]),
        gas_velocity_max=max(limits.gas_velocity_max, 1.001 * v["gas_velocity_m_s"]),
        peripheral_speed_max=max(limits.peripheral_speed_max, 1.001 * math.pi * raw.diameter_m * raw.rpm / 60),
        diameter_range=(min(limits.diameter_range[0], raw.diameter_m), max(limits.diameter_range[1], raw.diameter_m)),
    )       # not `validate`d: the plant's own values may lie beyond the ranges a user may give (a drum loaded to
    # 21 x its design load was refused as "design_load_tolerance = 20.46 is outside the allowed range", an option
    # the user had not given); each is a user's validated limit or the plant's own finite value
    real = evaluate(dm, cal, objective=objective, **geom)
    # the same names as simulate's outputs, other numbers: the screening's, which the notes say
    notes = [*notes, "the real row's values (fuel rate, gas outlet temperature, residence time, holdup, fill) are the "
             "screening correlations' at the plant's geometry and duty, as the optimum's, not the coupled model's: "
             "`rotarydryer simulate` gives the plant's own (the fuel rate there includes the burner's losses)"]
    out = dict(plant=name, geometry=geom, duty=dataclasses.asdict(duty), feasible_at_limits=raw.feasible,
               model="screening correlations (rotarydryer.design)",
               violated_at_limits=violated, ua_factor_implied=ua,
               calibrated_limits=dataclasses.asdict(cal), feasible_calibrated=real.feasible,
               binding_calibrated=real.binding(), real=real.row(), objective=objective, notes=notes)
    try:
        opt = design(duty, cal, objective=objective, progress=progress, check_limits=False, **search)
    except InfeasibleDuty as exc:
        # no geometry meets the duty even at the plant's own limits (the plant itself breaks a rule the
        # calibration does not widen, e.g. its exhaust's dew point): the plant's check stands, without an optimum
        return dict(out, optimum=None, optimum_binding=None, objective_ratio=None,
                    why=[f"no optimum: {' '.join(str(exc).split())}"])
    return dict(out, optimum=opt.best.row(), optimum_binding=opt.best.binding(),
                objective_ratio=real.objective / opt.best.objective, why=_why(real, opt.best, cal))


def _why(real: Design, best: Design, limits: Limits):
    out = []
    rv, bv = real.values, best.values
    if real.length_m > 1.05 * rv["length_required_m"]:
        out.append(f"the drum is {real.length_m / rv['length_required_m']:.2f} x longer than drying needs "
                   f"(Perry/McCormick Ua)")
    rt = real.constraints.get("residence time correlation")
    if rt is not None and rt[3] > 1e-9:
        out.append("Friedman-Marshall's residence time does not hold for this plant (its co-current gas term exceeds "
                   "the geometric term): the screening's holdup, fill and flight loading are void here")
    elif rv["holdup_over_design_load"] < 1 - 0.15:
        out.append(f"flights under-loaded (holdup/design load {rv['holdup_over_design_load']:.2f})")
    elif rv["holdup_over_design_load"] > 1.15:
        out.append(f"flights over-loaded (holdup/design load {rv['holdup_over_design_load']:.2f}): kilning")
    if rv["gas_velocity_m_s"] < 0.5 * bv["gas_velocity_m_s"]:
        out.append(f"gas velocity {rv['gas_velocity_m_s']:.2f} m/s vs {bv['gas_velocity_m_s']:.2f} m/s at the "
                   f"optimum: a wider drum than entrainment requires")
    if best.diameter_m < 0.9 * real.diameter_m:
        out.append(f"the optimum is narrower (D {best.diameter_m:.2f} vs {real.diameter_m:.2f} m; binding: "
                   f"{', '.join(best.binding()) or '-'})")
    return out or ["close to the optimum"]


def verify(design: Design, duty: Duty, n_cells=20):
    """Coupled heat-and-mass steady state (`rotarydryer.Simulation`, general dryer case,
    Lee (2008) transport) of a design: dict of its summary (product moisture etc.). The excess over the
    flights' design load kilns at the cascade speed (``kiln_law = "cascade"``): a fixed kilning time would
    give beds, and a holdup, that grow with ``n_cells`` (a design has no tracer data to fit it to)."""
    from .cases import DryerCase
    from .simulation import Simulation

    case = DryerCase.model_validate({
        "kind": "dryer",
        "drum": {"radius": design.diameter_m / 2, "slope": design.slope_deg, "n_flights": design.n_flights},
        "flight": {"s1": design.s1_m, "s2": design.s2_m, "alpha1": 90.0, "alpha2": design.alpha2_deg},
        "operating": {"feed_rate": duty.feed_rate, "rpm": design.rpm, "feed_moisture": duty.moisture_in,
                      "feed_temperature": duty.feed_temperature},
        "material": {"name": duty.material},
        "transport": {"model": "lee2008", "n_cells": n_cells, "kiln_law": "cascade"},
        "sections": [{"name": "drum", "kind": "flighted", "length": design.length_m}],
        "gas": {"direction": duty.direction, "flow": design.values["gas_flow_kg_s"],
                "inlet_temperature": duty.gas_inlet_temperature,
                "inlet_humidity": duty.gas_inlet_humidity / (1 + duty.gas_inlet_humidity)},
    })
    return Simulation(case).steady_state().summary()


def _geometry(b: Design) -> tuple:
    return (b.diameter_m, b.length_m, b.slope_deg, b.rpm, b.n_flights, b.s1_m, b.s2_m, b.alpha2_deg)


def verified_violations(summary: dict, best: Design, dm: _DutyModel, limits: Limits) -> list[str]:
    """The screening's limits that the coupled model's steady state ``summary`` of design ``best`` breaks,
    one phrase each: the exhaust's dew-point margin (`Limits.dew_point_margin`), the fill (holdup over the
    drum volume at the screening's bulk density, `Limits.fill_max`) and the flights' loading (holdup over
    the screening's design load, `Limits.design_load_tolerance` above 1). The screening held them on its
    own estimates (McCormick's Ua, Perry and Green's residence time); the coupled model may disagree."""
    out = []
    margin = summary.get("gas_outlet_dew_point_margin_K")
    if margin is not None and margin < limits.dew_point_margin:
        out.append(f"exhaust dew-point margin {margin:.3g} K (limit {limits.dew_point_margin:g} K)")
    volume = math.pi * best.diameter_m**2 / 4 * best.length_m
    fill = summary["total_holdup_kg"] / (dm.rho_b * volume)
    if fill > limits.fill_max:
        out.append(f"fill {fill:.3g} (limit {limits.fill_max:g})")
    dl = best.values.get("design_load_kg")
    if dl and math.isfinite(dl) and summary["total_holdup_kg"] / dl > 1 + limits.design_load_tolerance:
        out.append(f"flights over-loaded: holdup / design load {summary['total_holdup_kg'] / dl:.3g} "
                   f"(limit {1 + limits.design_load_tolerance:g})")
    return out


def design_verified(duty: Duty, limits: Limits | None = None, objective="volume", rounds=5, progress=None, **search):
    """`design`, then `verify` of the best design with the coupled model; while the
    coupled model misses the target product moisture, the Ua factor is lowered by the
    evaporation shortfall (required / achieved evaporation, to the power 1.5) and the search
    repeated (at most ``rounds`` searches). Returns (DesignResult, verification dict with the
    rounds' history).

    The coupled model's own numbers are also held to the screening's limits that it computes
    (`verified_violations`): the exhaust's dew-point margin, the fill and the flights' loading. A
    design that meets the target moisture but breaks one of them (``constraints_violated``) is not
    verified; where it over-dries (the coupled drum evaporates more than the duty needs, so the gas
    leaves colder than screened), the Ua factor is raised by the same rule and the search repeated
    (a shorter drum); where the fill or the flights' loading is broken, the screening's residence time
    is scaled by the coupled model's holdup over the screening's (``Limits.holdup_factor``: Perry and
    Green's correlation knows neither the flights nor the coupled model's transport law) and the search
    repeated. Every repeated round carries both factors of the last verification. The round returned: the
    first verified one, else the closest (target met first, then no limit broken, then the driest product)."""
    limits = (limits or Limits()).validate()
    duty.validate()
    dm = _DutyModel(duty)
    history = []
    res = None
    designs = []        # the design of each round; history[k] is its verification (a failed one ends the search)

    def closest():
        """The closest verified round: the target met first, then no limit broken, then the driest product
        (a later, larger drum may dry worse: the search's Ua factor is a model of the shortfall, not a
        guarantee)."""
        k = min(range(len(designs)), key=lambda i: (not history[i]["target_met"], bool(history[i]["constraints_violated"]),
                                                    history[i]["product_moisture_kg_kg"]))
        return designs[k], dict(history[k], best_round=k + 1)

    for k in range(int(rounds)):
        try:
            res = design(duty, limits, objective=objective, progress=progress, **search)
        except InfeasibleDuty as exc:
            if res is None:
                raise
            # the coupled model needs more than the constraints allow: keep the closest design, say why
            best, entry = closest()
            return best, dict(entry, rounds=history, next_round_infeasible=str(exc),
                              blocking_constraint=exc.constraint)
        if designs and _geometry(res.best) == _geometry(designs[-1].best):
            # the new Ua factor did not move the search (the objective, not the drying, sets the drum): the same
            # verification again
            best, entry = closest()
            return best, dict(entry, rounds=history)
        if progress:
            progress(f"verification {k + 1}: coupled heat-and-mass steady state of the best design")
        try:
            v = verify(res.best, duty)
        except ValueError as exc:
            history.append(dict(ua_factor=limits.ua_factor, error=str(exc)))
            return res, dict(error=str(exc), rounds=history)
        xp = v["product_moisture_kg_kg"]
        met = bool(xp <= duty.moisture_out * 1.0001)
        e_ach = dm.S * (dm.X_in - xp / (1 - xp))
        entry = dict(ua_factor=limits.ua_factor, holdup_factor=limits.holdup_factor, product_moisture_kg_kg=xp,
                     evaporation_kg_s=e_ach,
                     product_temperature_degC=v["product_temperature_degC"],
                     gas_outlet_temperature_degC=v["gas_outlet_temperature_degC"],
                     total_holdup_kg=v["total_holdup_kg"], target_met=met,
                     gas_outlet_dew_point_margin_K=v.get("gas_outlet_dew_point_margin_K"),
                     constraints_violated=verified_violations(v, res.best, dm, limits),
                     diameter_m=res.best.diameter_m, length_m=res.best.length_m)
        history.append(entry)
        designs.append(res)
        over_dried = e_ach > dm.E * 1.0001
        if met and not entry["constraints_violated"]:
            return res, dict(entry, rounds=history)
        screened = res.best.values.get("holdup_kg", math.nan)
        holdup_off = (any(c.startswith(("fill ", "flights over-loaded")) for c in entry["constraints_violated"])
                      and math.isfinite(screened) and screened > 0 and v["total_holdup_kg"] > 0)
        if k == rounds - 1 or (met and not over_dried and not holdup_off):   # nothing a new search would mend
            best, entry = closest()
            return best, dict(entry, rounds=history)
        shortfall = dm.E / max(e_ach, 1e-3 * dm.E)
        hf = limits.holdup_factor
        if math.isfinite(screened) and screened > 0 and v["total_holdup_kg"] > 0:
            hf = min(max(hf * v["total_holdup_kg"] / screened, 1e-3), 99.0)     # inside Limits.validate's (0, 100)
        limits = dataclasses.replace(limits, ua_factor=limits.ua_factor / shortfall**1.5, holdup_factor=hf)

