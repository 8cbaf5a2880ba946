"""Settings of the heat-and-mass model: the thermal parameters of a dryer ([`ThermalSettings`][rotarydryer.thermal.settings.ThermalSettings]),
the heat-transfer data of a section ([`SectionThermal`][rotarydryer.thermal.settings.SectionThermal]) and the model's error ([`DryerError`][rotarydryer.thermal.settings.DryerError]).

Every plant number is case data ([`rotarydryer.cases.build.thermal_settings`][rotarydryer.cases.build.thermal_settings] fills these from a
case); the defaults here are neutral. [`ThermalSettings.ajayi2011`][rotarydryer.thermal.settings.ThermalSettings.ajayi2011] gives the settings of the
thesis code (Ajayi (2011) App. F).
"""

from __future__ import annotations

import dataclasses
from typing import Optional

import numpy as np

from .._limits import check_key
from .._validation import check_choice, check_range
from ..properties.drying import DryingKinetics
from ..properties.psd import SizeClasses
from . import balances as bal
from .burner import Burner

__all__ = ["DryerError", "SectionThermal", "ThermalSettings", "AJAYI_GAS_FLOW", "SHELL_THICKNESS_RATIO"]

AJAYI_GAS_FLOW = 112675.6688 / 3600.0   # kg/s wet gas, App. F L3225


class DryerError(ValueError):
    """Bad input or no steady state; ``reason`` is a short key, ``state`` the last converged/iterated state."""

    def __init__(self, message, reason="input", state=None):
        super().__init__(message)
        self.reason = reason
        self.state = state


@dataclasses.dataclass
class SectionThermal:
    """Heat-transfer data of one section (case data, not code).

    area_factor : θ_AL (bed) or θ_a (curtain), multiplier on the geometric exposed area (Ajayi
    (2011) l.2278). particle_diameter : m (None = the material's). shell_temperature : °C, fixed
    shell temperature of the ``ajayi2011`` mode (Ajayi's code; None = 100 °C).
    """

    area_factor: float = 1.0
    particle_diameter: Optional[float] = None
    shell_temperature: Optional[float] = None


@dataclasses.dataclass
class ThermalSettings:
    """Thermal parameters of the dryer (SI; temperatures °C).

    gas_flow : wet gas into the dryer, kg/s (required: the case's gas.flow; Ajayi 31.30 kg/s = 112675.7 kg/h, L3225).
    gas_inlet_temperature : °C (required: the case's gas.inlet_temperature; Ajayi 500).
    mode : "physical" | "ajayi2011" (see module docstring).
    gas_inlet_humidity : kg/kg **wet** gas (default 0.01; Ajayi 0.0193, L3227).
    solids_inlet_temperature : °C (default 20; Ajayi 28, L3241). ambient_temperature : °C (default 25; Ajayi 26,
    L3231). The defaults are neutral: the plants' values are case data (rotarydryer.cases.build.thermal_settings).
    area_scale : common multiplier on the sections' area factors (tuned).
    cp_solids, cp_water : J/(kg K) (None = the material's). particle_density : kg/m³ (None = the
    material's). pressure : Pa.
    loss_factor : compatibility mode only (θ_loss = 15; the fixed shell temperatures are section data).
    scale_thickness, scale_conductivity, insulation_thickness, insulation_conductivity : shell
    network of the physical mode (m, W/(m K)).
    shell_inner_radius, shell_thickness : steel shell of the physical mode, m (None: the drum radius,
    and `SHELL_THICKNESS_RATIO` times the inner radius).
    fouling : fraction (0-0.95) of flight loading capacity lost to scale (Ajayi Ch. 5 Eq. 5.21,
    Ch. 7 "scaling 0-80 %"; Test 3 was modelled with 80 %, l.1715): multiplies the design load by (1 - fouling).
    leak_air_flow : ambient air leaking into the drum at the gas inlet end (seals, feed chute), kg/s
    humid air at ambient temperature and ``ambient_humidity`` (kg/kg dry); mixed adiabatically
    with the burner gas before the first stage. 0 = none (Ajayi's assumption).
    kinetics : DryingKinetics (default: the material's; in the ajayi2011 mode with Ajayi's
    mass-transfer basis and Antoine saturation pressure).
    moisture_coupling : transport properties from the computed moisture (True) or the assumed
    transport profile (False, the transport-only model).
    gas_direction : "co-current" | "counter-current".
    design_load_smoothing : width of the smoothed design-load switch min(M_P, M_des), relative
    to M_des (0 = exact, as the transport network; 1e-3 in the MMG case, as before).
    burner : [`Burner`][rotarydryer.thermal.burner.Burner] that makes the gas (None = the gas comes
    from elsewhere, e.g. steam-heated air; no fuel rate).
    kiln_bed_area : physical mode: the passive solids of a flighted cell above its design load (a kiln
    bed on the drum floor: overloaded or fouled flights) exchange with the gas through the active
    layer of the bed, as an unflighted section's bed (Ajayi (2011) Eq. 6.56-6.61); False: no exchange
    (the thesis's model: only curtains and unflighted beds).
    discharge_cooling_ntu : transfer units of the product's cooling by ambient air between the drum
    outlet and a product temperature sensor downstream
    ([`discharge_cooling`][rotarydryer.thermal.streams.discharge_cooling]; 0 = the sensor at the drum outlet).
    size_classes : [`SizeClasses`][rotarydryer.properties.psd.SizeClasses] of the feed (None: one class of
    the material's particle diameter): the solids of every tank are carried per class (module
    `rotarydryer.thermal.dryer`, "Size classes").
    entrainment : with size classes, the gas carries the fines out of the curtains where it is faster
    than their terminal velocity (dust to the exhaust); False: no dust.
    recycle_fraction : fraction r of the exhaust's dry gas returned to the burner, in [0, 1). The drum's
    dry gas flow (``gas_flow`` at ``gas_inlet_humidity``) and its inlet temperature stay: the burner
    heats fresh air (the rest of that flow, at ``gas_inlet_humidity``) and the recycled exhaust (at the
    exhaust's humidity, from its temperature) to the inlet temperature, so the inlet gas is more humid
    and the fuel lower ([`ThermalDryer.inlet_gas`][rotarydryer.thermal.dryer.ThermalDryer.inlet_gas]). 0 = none.
    shell_max_temperature : highest allowed steel wall temperature, degC (None: no limit), e.g. 593
    (mild steel, API 521, as Ajayi (2011) Ch. 7 quotes): reported against the model's hottest wall
    ([`rotarydryer.thermal.audit`][rotarydryer.thermal.audit]); never an error.
    """

    gas_flow: float
    gas_inlet_temperature: float
    mode: str = "physical"
    gas_inlet_humidity: float = 0.01
    solids_inlet_temperature: float = 20.0
    ambient_temperature: float = 25.0
    area_scale: float = 1.0
    particle_density: Optional[float] = None
    cp_solids: Optional[float] = None
    cp_water: float = bal.AJAYI_CP_WATER
    pressure: float = 101325.0
    loss_factor: float = 15.0
    scale_thickness: float = 0.0
    scale_conductivity: float = 1.0
    insulation_thickness: float = 0.0
    insulation_conductivity: float = 0.07
    shell_inner_radius: Optional[float] = None
    shell_thickness: Optional[float] = None
    co2_mole_fraction: float = 0.011
    leak_air_flow: float = 0.0
    ambient_humidity: float = 0.01
    fouling: float = 0.0
    kinetics: Optional[DryingKinetics] = None
    moisture_coupling: bool = True
    gas_direction: str = "co-current"
    design_load_smoothing: float = 0.0
    burner: Optional[Burner] = None
    discharge_cooling_ntu: float = 0.0
    kiln_bed_area: bool = True
    size_classes: Optional[SizeClasses] = None
    entrainment: bool = True
    recycle_fraction: float = 0.0
    shell_max_temperature: Optional[float] = None

    @classmethod
    def ajayi2011(cls, **kw):
        """Compatibility settings reproducing the thesis (Ajayi (2011) App. F process entity)."""
        base = dict(mode="ajayi2011", gas_flow=AJAYI_GAS_FLOW, pressure=101045.0, loss_factor=15.0)
        base.update(kw)
        return cls(**base)

    def validate(self):
        check_choice("thermal.mode", self.mode, ("physical", "ajayi2011"))
        check_choice("gas.direction", self.gas_direction, ("co-current", "counter-current"))
        if self.gas_flow == 0:
            raise ValueError("gas.flow = 0 kg/s: heat and mass transfer needs a gas flow in (0, 1000] kg/s; "
                             "for a run without gas set thermal.enabled = false (solids transport only)")
        # the ranges of the case schema (rotarydryer._limits: one declaration for both)
        for key, value in (("gas.flow", self.gas_flow), ("gas.inlet_temperature", self.gas_inlet_temperature),
                           ("gas.inlet_humidity", self.gas_inlet_humidity),
                           ("operating.feed_temperature", self.solids_inlet_temperature),
                           ("shell.ambient_temperature", self.ambient_temperature),
                           ("thermal.area_scale", self.area_scale), ("thermal.fouling", self.fouling),
                           ("shell.loss_factor", self.loss_factor),
                           ("thermal.discharge_cooling_ntu", self.discharge_cooling_ntu),
                           ("gas.leak_air_flow", self.leak_air_flow), ("shell.ambient_humidity", self.ambient_humidity),
                           ("shell.scale_thickness", self.scale_thickness),
                           ("shell.insulation_thickness", self.insulation_thickness),
                           ("thermal.design_load_smoothing", self.design_load_smoothing),
                           ("gas.recycle_fraction", self.recycle_fraction)):
            check_key(key, value)
        if self.shell_max_temperature is not None:
            check_key("shell.max_temperature", self.shell_max_temperature)
        check_range("pressure", self.pressure, 5e4, 2e5, low_inclusive=True, high_inclusive=True, unit="Pa")
        hot = self.gas_flow * (1.0 - self.gas_inlet_humidity)
        leak = self.leak_air_flow / (1.0 + self.ambient_humidity)
        if self.recycle_fraction > 0 and not self.recycle_fraction * (hot + leak) < hot:
            raise DryerError(
                f"gas.recycle_fraction = {self.recycle_fraction:.10g} returns {self.recycle_fraction * (hot + leak):.4g} "
                f"kg/s of exhaust dry gas, not less than the burner's dry gas {hot:.4g} kg/s (the leak air "
                f"gas.leak_air_flow = {self.leak_air_flow:g} kg/s is in the exhaust too): no fresh air would be left; "
                f"give gas.recycle_fraction below {hot / (hot + leak):.4g}")
        check_range("shell.scale_conductivity", self.scale_conductivity, 0.0, np.inf, unit="W/(m K)")
        check_range("shell.insulation_conductivity", self.insulation_conductivity, 0.0, np.inf, unit="W/(m K)")
        if self.shell_inner_radius is not None:
            check_key("shell.inner_radius", self.shell_inner_radius)
        if self.shell_thickness is not None:
            check_key("shell.thickness", self.shell_thickness)
        check_range("gas.co2_mole_fraction", self.co2_mole_fraction, 0.0, 0.3, low_inclusive=True,
                    high_inclusive=True)
        if self.mode == "ajayi2011" and self.gas_inlet_humidity <= 0:
            raise DryerError("gas.inlet_humidity = 0 with thermal.mode='ajayi2011': Ajayi's h_m divides by the gas "
                             "vapour pressure (Eq. 6.47); use mode='physical' for dry gas")
        return self


#: default steel wall of the shell relative to its inner radius: Ajayi's (2011) 0.05 m at 1.90 m (code
#: l.3870, l.4381); a choice for drums whose wall is not given (4 mm for a 0.3 m pilot drum, 66 mm at 5 m)
SHELL_THICKNESS_RATIO = 0.05 / 1.90
