r"""Energy audit of a coupled steady state: where the heat goes, the exhaust's dew point, the shell.

**Heat duties** ([`heat_duties`][rotarydryer.thermal.audit.heat_duties]), W, at a converged
[`ThermalSteadyState`][rotarydryer.thermal.states.ThermalSteadyState]. They add up to the **heat
release** ``heat_release_W``: the fuel's heat, fuel rate x lower heating value, where the case has a
burner whose fuel rate the model gives; else the heat put into the gas (``heat_input_W``). The
reference is the site's ambient air (``shell.ambient_temperature``; its humidity for the leak air)
and the feed's temperature for the solids, so that the identity is exact in the model's own
enthalpies (those of its mode, ``thermal.mode``), term by term:

``heat_duty_burner_loss_W``
    release - heat input: the chamber's wall loss (``gas.burner.heat_loss_fraction``) and what the
    combustion products hold beyond the model's humid-air gas at the same temperature (their CO2
    and the water formed, the fuel's mass; about 2.5 % of the release for the MMG burner). 0
    without a burner.
``heat_duty_evaporation_W``
    $\sum_i R_{w,i}\,\lambda(T_{s,i})$: each stage's evaporation rate times the latent heat at the
    temperature of the solids it evaporates from (the model's latent heat $h_v(T_s) - c_{p,w}T_s$,
    [`rotarydryer.thermal.balances.vapour_source_enthalpy`][rotarydryer.thermal.balances.vapour_source_enthalpy]; Ajayi (2011) Eq. 6.4, 6.7).
``heat_duty_solids_heating_W``
    the dry solids from the feed to the product temperature, $S\,c_{p,s}(T_p - T_f)$.
``heat_duty_water_heating_W``
    the liquid water: the water that stays, from the feed to the product temperature, and the
    water evaporated, from the feed temperature to the temperature it evaporates at.
``shell_heat_loss_W``
    through the shell (per section: [`shell_sections`][rotarydryer.thermal.audit.shell_sections]).
``heat_duty_exhaust_sensible_W``
    the exhaust that leaves the plant (with recycle r, the fraction 1 - r): its dry gas and the
    vapour the fresh gas brought above ambient, and the evaporated water's vapour from the
    temperature it evaporated at to the exhaust temperature.
``heat_duty_leak_air_W``
    the leak air (``gas.leak_air_flow``) heated from ambient to the exhaust temperature.
``heat_duty_closure_W``
    release minus the terms above: the balance residual of the converged state (below 1e-9 of the
    release; the steady-state test polishes the balances to 1e-10).

``heat_duty_dust_W``
    the dust (fines the gas carries out of the curtains, a case with ``[particle_size]``): its
    solids and water from the feed temperature to the temperature they leave their curtains at
    (0 without dust).

Reported beside them, not added (it is part of the evaporation's heat, carried out by the exhaust):
``heat_duty_exhaust_latent_W``, the latent heat of the evaporated water at ambient temperature,
$\dot m_{evap}(h_v(T_{amb}) - c_{p,w}T_{amb})$ - at most what a condenser cooling the exhaust to
ambient would recover.

Why the identity holds: the gas enthalpy of both modes is linear in the humidity,
$h(T, Y) = h_a(T) + Y h_v(T)$, so the exhaust splits exactly into its dry gas, the vapour it
brought and the water evaporated; with the steady state's water and energy balances the terms
above add up to the heat input (derivation in ``docs/guide/energy_audit.md``).

**Shell** ([`shell_profile`][rotarydryer.thermal.audit.shell_profile]): the outer surface
temperature (what an infrared gun reads) and the hottest steel temperature (the steel's inside
face, under the scale layer) per gas stage, from the shell network the model solves
([`rotarydryer.thermal.shell.shell_heat_loss`][rotarydryer.thermal.shell.shell_heat_loss]; the fixed shell temperatures of the
``ajayi2011`` mode there). A case's ``shell.max_temperature`` (e.g. 593 degC, the mild-steel limit
of API 521 that Ajayi (2011) Ch. 7 quotes for an insulated shell) is compared with the hottest wall:
a `ShellTemperatureWarning`, never an error.
"""

from __future__ import annotations

import math
import warnings
from typing import TYPE_CHECKING

import numpy as np

from ..properties import water
from ..properties.humid_air import dew_point
from . import balances as bal
from .shell import shell_heat_loss

if TYPE_CHECKING:
    from .states import ThermalSteadyState

__all__ = ["HEAT_DUTY_PARTS", "HEAT_DUTY_LABELS", "ShellTemperatureWarning", "heat_duties", "shell_profile",
           "shell_sections", "shell_temperatures", "shell_limit_message", "warn_shell_limit",
           "SupersaturationWarning", "supersaturation_message", "warn_supersaturated_exhaust", "CondensationWarning",
           "condensation_message", "warn_condensation", "SolidsTemperatureWarning", "solids_temperature_message",
           "warn_solids_temperature", "WetSolidsWarning", "wet_solids_message", "warn_wet_solids"]

#: the heat duties that add up to ``heat_release_W`` (summary names, W), in the order of a waterfall
HEAT_DUTY_PARTS = ("heat_duty_burner_loss_W", "heat_duty_evaporation_W", "heat_duty_solids_heating_W",
                   "heat_duty_water_heating_W", "heat_duty_dust_W", "shell_heat_loss_W", "heat_duty_exhaust_sensible_W",
                   "heat_duty_leak_air_W", "heat_duty_closure_W")

#: every key of `heat_duties`
DUTY_KEYS = ("heat_release_W", *HEAT_DUTY_PARTS, "heat_duty_exhaust_latent_W")
#: every key of `shell_temperatures`
SHELL_KEYS = ("shell_max_surface_temperature_degC", "shell_max_wall_temperature_degC", "shell_temperature_limit_degC",
              "shell_temperature_limit_exceeded")

#: short labels of the duties for the tables and figures of the text surfaces
HEAT_DUTY_LABELS = {
    "heat_release_W": "heat release",
    "heat_duty_burner_loss_W": "burner loss",
    "heat_duty_evaporation_W": "evaporation",
    "heat_duty_solids_heating_W": "solids heating",
    "heat_duty_water_heating_W": "water heating",
    "heat_duty_dust_W": "dust",
    "shell_heat_loss_W": "shell loss",
    "heat_duty_exhaust_sensible_W": "exhaust (sensible)",
    "heat_duty_leak_air_W": "air leaks",
    "heat_duty_closure_W": "balance closure",
    "heat_duty_exhaust_latent_W": "exhaust latent heat (part of evaporation)",
}


class ShellTemperatureWarning(UserWarning):
    """The model's hottest shell wall is above the case's ``shell.max_temperature``."""


class CondensationWarning(UserWarning):
    """The steady state's solids take up more water than they lose: the product leaves wetter than the feed."""


class SolidsTemperatureWarning(UserWarning):
    """The steady state's solids are hotter than their material's ``max_temperature`` (it melts, decomposes or
    reacts there): the material's data do not hold."""


class WetSolidsWarning(UserWarning):
    """The steady state's solids hold water above its boiling point: the drying law (a thin-layer law fitted below it)
    evaporates less than the heat the solids take would boil off, which the model does not describe."""


class SupersaturationWarning(UserWarning):
    """The exhaust leaves the drum below its own dew point: a supersaturated gas, which the model does not
    represent (no condensation in the gas)."""


def heat_duties(steady: ThermalSteadyState, fuel_rate: float | None = None) -> dict:
    """The heat duties of a converged steady state (module docstring), W: ``heat_release_W``, the
    parts `HEAT_DUTY_PARTS` (which add up to it) and ``heat_duty_exhaust_latent_W``.

    ``fuel_rate`` (kg/s) of the case's burner: the release is fuel rate x LHV; None (no burner, or a
    burner that cannot reach the set temperature): the release is the heat put into the gas."""
    dr = steady.dryer
    s = dr.settings
    d = steady.terms
    mode = s.mode
    hot, leak = dr._flows_in
    r = s.recycle_fraction
    back = r * (hot + leak)                  # recycled exhaust, kg/s dry gas (0 without recycle)
    fresh = hot - back                       # fresh air through the burner, kg/s dry gas
    ta, tf = s.ambient_temperature, s.solids_inlet_temperature
    k = dr.gas_outlet_stage
    t_out = float(d["Tg"][k])
    yh, ya = dr.hot_gas_Y, s.ambient_humidity

    def h(t, y):
        return float(bal._gas_enthalpy(t, y, mode))

    q_in = float(steady.heat_input_w)
    b = s.burner
    release = q_in if fuel_rate is None or b is None else float(fuel_rate) * b.fuel.lhv
    # solids: dry solids and the water they keep, from the feed to the product temperature
    cps, cpw = s.cp_solids, s.cp_water
    assert cps is not None          # the material's, filled in when the dryer was built
    pS, pW = float(d["product_S"]), float(d["product_W"])
    tp = float(steady.product_temperature_degC)
    dS, dW, dH = float(d["dust_S"]), float(d["dust_W"]), float(d["dust_H"])
    # evaporation per gas stage and size class at the temperature of the class's solids there (the
    # model's vapour enthalpy hv)
    rw = np.asarray(d["rw_c"], dtype=float)
    ts = np.asarray(d["Tc"], dtype=float)[..., dr.gas_tank]
    hv = np.asarray(d["hv_c"], dtype=float)
    vapour_out = h(t_out, 1.0) - h(t_out, 0.0)      # h_v(T_out): the gas enthalpy is linear in Y
    evaporation = float(np.sum(rw * (hv - cpw * ts)))
    parts = {
        "heat_duty_burner_loss_W": release - q_in,
        "heat_duty_evaporation_W": evaporation,
        "heat_duty_solids_heating_W": pS * cps * (tp - tf),
        "heat_duty_water_heating_W": pW * cpw * (tp - tf) + float(np.sum(rw * cpw * (ts - tf))),
        "heat_duty_dust_W": dH - (dS * cps + dW * cpw) * tf,
        "shell_heat_loss_W": float(np.sum(d["qloss"])),
        "heat_duty_exhaust_sensible_W": fresh * (h(t_out, yh) - h(ta, yh)) + float(np.sum(rw * (vapour_out - hv))),
        "heat_duty_leak_air_W": leak * (h(t_out, ya) - h(ta, ya)),
    }
    parts["heat_duty_closure_W"] = release - math.fsum(parts.values())
    out = {"heat_release_W": release, **parts}
    evaporated = float(np.sum(rw))
    out["heat_duty_exhaust_latent_W"] = evaporated * (h(ta, 1.0) - h(ta, 0.0) - cpw * ta)
    return out


def evaporation_temperature(steady: ThermalSteadyState) -> float | None:
    """Mean temperature of the solids water evaporates from, degC, weighted by each stage's evaporation
    where water evaporates (None where nothing does). Stages where the solids take water up (a cold feed
    under humid gas) are left out: weighted by the net rate, their negative weights put the mean outside
    the solids' own temperatures (197 degC under a 186 degC inlet gas)."""
    d = steady.terms
    rw = np.maximum(np.asarray(d["rw"], dtype=float), 0.0)
    total = float(np.sum(rw))
    if not total > 1e-12 * steady.dryer.feed_rate:
        return None
    return float(np.sum(rw * np.asarray(d["T"], dtype=float)[steady.dryer.gas_tank]) / total)


def shell_profile(steady: ThermalSteadyState) -> dict:
    """Per gas stage (arrays): ``section``, ``position_m``, ``length_m``, ``shell_heat_loss_W`` (the
    model's), ``surface_temperature_degC`` (outer surface: the lagging's where the shell is insulated)
    and ``wall_temperature_degC`` (the steel's hottest face, its inside, under the scale). Physical
    mode: the shell network at the stage's gas temperature and humidity (at the edge of the
    near-ambient band, 1 K above ambient, for gas colder than that); ``ajayi2011`` mode: the fixed
    shell temperatures of the sections (Ajayi's code)."""
    dr = steady.dryer
    s = dr.settings
    d = steady.terms
    tg, y = np.asarray(d["Tg"], dtype=float), np.asarray(d["Y"], dtype=float)
    if s.mode == "ajayi2011":
        surface = wall = np.asarray(dr.shell_T, dtype=float).copy()
    else:
        band = 1.0      # ThermalDryer's SHELL_LINEAR_BAND_K (the loss is linear in T_g - T_amb below it)
        r = shell_heat_loss(np.clip(tg, s.ambient_temperature + band, 600.0), dr.dry_gas_flow * (1.0 + y), dr.gas_len,
                            s.ambient_temperature, gas_humidity=np.clip(y, 0.0, 1.0),
                            co2_mole_fraction=s.co2_mole_fraction, inner_radius=dr.shell_inner_radius,
                            shell_thickness=dr.shell_thickness, scale_thickness=s.scale_thickness,
                            scale_conductivity=s.scale_conductivity, insulation_thickness=s.insulation_thickness,
                            insulation_conductivity=s.insulation_conductivity, pressure=s.pressure,
                            ambient_humidity=s.ambient_humidity, outer_guess=dr._shell_outer,
                            _trusted=True)     # the model's own call (its settings checked once; any gas state)
        surface = np.asarray(r.outer_surface_temperature_c, dtype=float)
        wall = np.asarray(r.inner_surface_temperature_c, dtype=float)
        if s.scale_thickness > 0:       # the steel's inside face lies under the scale layer
            ri = dr.shell_inner_radius
            r_scale = math.log(ri / (ri - s.scale_thickness)) / (2.0 * math.pi * s.scale_conductivity)
            wall = wall - np.asarray(r.heat_loss_per_length, dtype=float) * r_scale
    return dict(section=np.asarray(dr.gas_section), position_m=np.asarray(dr.gas_position, dtype=float),
                length_m=np.asarray(dr.gas_len, dtype=float), shell_heat_loss_W=np.asarray(d["qloss"], dtype=float),
                surface_temperature_degC=surface, wall_temperature_degC=wall)


def shell_sections(steady: ThermalSteadyState) -> list[dict]:
    """One row per section (in the order along the drum): ``section``, ``length_m``,
    ``shell_heat_loss_W``, ``max_surface_temperature_degC``, ``max_wall_temperature_degC``."""
    p = steady.shell_profile()
    names = list(dict.fromkeys(str(x) for x in p["section"]))
    # each section's own length, as the sections table gives it (its stages' lengths summed read 1.0000000000000002
    # for 1 m; found by an acceptance check)
    given = {str(sec.get("name")): float(sec["length"]) for sec in steady.dryer.model.sections
             if isinstance(sec, dict) and "length" in sec}
    rows = []
    for name in names:
        m = np.asarray([str(x) == name for x in p["section"]])
        rows.append(dict(section=name, length_m=given.get(name, float(np.sum(p["length_m"][m]))),
                         shell_heat_loss_W=float(np.sum(p["shell_heat_loss_W"][m])),
                         max_surface_temperature_degC=float(np.max(p["surface_temperature_degC"][m])),
                         max_wall_temperature_degC=float(np.max(p["wall_temperature_degC"][m]))))
    return rows


def shell_temperatures(steady: ThermalSteadyState) -> dict:
    """The shell's summary outputs: ``shell_max_surface_temperature_degC``,
    ``shell_max_wall_temperature_degC``, the case's limit ``shell_temperature_limit_degC`` (None: none)
    and ``shell_temperature_limit_exceeded`` (None without a limit)."""
    p = steady.shell_profile()
    limit = steady.dryer.settings.shell_max_temperature
    wall = float(np.max(p["wall_temperature_degC"]))
    return dict(shell_max_surface_temperature_degC=float(np.max(p["surface_temperature_degC"])),
                shell_max_wall_temperature_degC=wall, shell_temperature_limit_degC=limit,
                shell_temperature_limit_exceeded=None if limit is None else bool(wall > limit))


def shell_limit_message(steady: ThermalSteadyState) -> str | None:
    """One line when the hottest wall exceeds ``shell.max_temperature`` (where, by how much), else None."""
    limit = steady.dryer.settings.shell_max_temperature
    if limit is None:
        return None
    p = steady.shell_profile()
    i = int(np.argmax(p["wall_temperature_degC"]))
    wall = float(p["wall_temperature_degC"][i])
    if not wall > limit:
        return None
    return (f"the shell wall reaches {wall:.1f} degC in section {p['section'][i]} ({p['position_m'][i]:.3g} m from the "
            f"feed end), above shell.max_temperature = {limit:g} degC (steel strength; Ajayi (2011) Ch. 7 quotes "
            "593 degC for mild steel): less insulation, a lower gas inlet temperature or another steel")


def warn_shell_limit(steady: ThermalSteadyState) -> None:
    """A `ShellTemperatureWarning` when `shell_limit_message` has one."""
    _warn(shell_limit_message(steady), ShellTemperatureWarning)


def supersaturation_message(steady: ThermalSteadyState) -> str | None:
    """Why the steady state's exhaust is not physical, or None: it leaves below its own dew point (the gas in the
    drum supersaturated; the model carries the water as vapour whatever its temperature, and its balances hold,
    but a real gas would condense it, in the drum or the ducts)."""
    y, t = float(steady.gas_outlet_humidity), float(steady.gas_outlet_temperature_degC)
    if not y > 0:
        return None
    try:
        dew = float(dew_point(y, steady.dryer.settings.pressure))
    except ValueError:              # a gas too dry for the saturation curve's range
        return None
    if t >= dew:
        return None
    return (f"the exhaust leaves at {t:.4g} degC, {dew - t:.3g} K below its own dew point {dew:.4g} degC: the gas in "
            "the drum is supersaturated, which the model does not represent (no condensation in the gas); its balances "
            "hold, the gas state does not: raise gas.inlet_temperature or gas.flow, or lower operating.feed_rate")


def condensation_message(steady: ThermalSteadyState) -> str | None:
    """Why the steady state wets its solids, or None: the gas gives the solids more water than it takes (a net
    evaporation below zero, beyond 1e-6 of the feed), so the product leaves wetter than the feed: a feed colder
    than the gas's dew point that the gas does not warm in time. A valid steady state, not a dryer's."""
    dr = steady.dryer
    e = float(steady.evaporation_rate)
    if not e < -1e-6 * dr.feed_rate:
        return None
    x_in, x_out = float(dr.feed_moisture), float(steady.product_moisture)
    return (f"the drum condenses water onto the solids: net evaporation {e:.4g} kg/s, the product leaves at {100 * x_out:.4g} % "
            f"moisture (wet basis) against {100 * x_in:.4g} % in the feed; the gas (its dew point above the cold solids) "
            "wets them before it warms them: raise gas.inlet_temperature or operating.feed_temperature, or lower "
            "gas.inlet_humidity")


def _warn(msg: str | None, category: type[Warning]) -> None:
    """``msg`` as a ``category`` warning at the caller of the ``warn_*`` function, when there is one."""
    if msg:
        warnings.warn(msg, category, stacklevel=3)


def warn_condensation(steady: ThermalSteadyState) -> None:
    """A `CondensationWarning` when `condensation_message` has one."""
    _warn(condensation_message(steady), CondensationWarning)


def warn_supersaturated_exhaust(steady: ThermalSteadyState) -> None:
    """A `SupersaturationWarning` when `supersaturation_message` has one."""
    _warn(supersaturation_message(steady), SupersaturationWarning)


#: a tank counts in `solids_temperature_message` when it holds at least this many seconds of the feed (an emptied
#: cell's temperature is the gas's, `ThermalDryer._rhs`'s virtual heat capacity)
HOT_SOLIDS_MIN_HOLDUP_S = 1e-3


def _hottest_held(steady: ThermalSteadyState, where) -> int | None:
    """The index of the hottest tank among those selected by ``where`` (a mask over the tanks) that hold solids (at
    least `HOT_SOLIDS_MIN_HOLDUP_S` of the feed), or None."""
    held = where & (np.asarray(steady.holdup, dtype=float) >= HOT_SOLIDS_MIN_HOLDUP_S * steady.dryer.feed_rate)
    if not held.any():
        return None
    T = np.asarray(steady.solids_temperature_degC, dtype=float)
    return int(np.flatnonzero(held)[np.argmax(T[held])])


def solids_temperature_message(steady: ThermalSteadyState) -> str | None:
    """Why the steady state's solids leave their material's data, or None: the hottest tank holding solids (at
    least `HOT_SOLIDS_MIN_HOLDUP_S` of the feed) is above the material's ``max_temperature`` (None: no limit)."""
    dr = steady.dryer
    m = dr.material
    limit = getattr(m, "max_temperature", None)
    if limit is None:
        return None
    T = np.asarray(steady.solids_temperature_degC, dtype=float)
    i = _hottest_held(steady, np.ones(T.shape, dtype=bool))
    if i is None:
        return None
    hottest = float(T[i])
    if not hottest > limit:
        return None
    why = f" ({m.max_temperature_source})" if m.max_temperature_source else ""
    return (f"the solids reach {hottest:.4g} degC in section {dr.tank_section[i]} ({float(dr.position[i]):.3g} m from "
            f"the feed end; the product leaves at {float(steady.product_temperature_degC):.4g} degC), above "
            f"material.max_temperature = {limit:g} degC of '{m.name}'{why}: the material's data do not hold there; "
            "lower gas.inlet_temperature or gas.flow, or raise operating.feed_rate")


def warn_solids_temperature(steady: ThermalSteadyState) -> None:
    """A `SolidsTemperatureWarning` when `solids_temperature_message` has one."""
    _warn(solids_temperature_message(steady), SolidsTemperatureWarning)


#: dry-basis moisture (kg/kg) above which solids count as wet in `wet_solids_message`: the transfer's dry guard
#: (`rotarydryer.thermal.balances.stage_transfer`), below which the model stops evaporating the last traces
WET_SOLIDS_MOISTURE = 2e-3
#: K above the boiling point before solids count as boiling (the steady state's temperatures to rounding)
BOILING_MARGIN_K = 1.0


def wet_solids_message(steady: ThermalSteadyState) -> str | None:
    """Why the steady state's wet solids leave the model, or None: a tank holding solids (at least
    `HOT_SOLIDS_MIN_HOLDUP_S` of the feed) with free water (dry basis above `WET_SOLIDS_MOISTURE` and the law's
    critical moisture) is hotter than water boils at the drum's pressure (by `BOILING_MARGIN_K`). Its water would
    boil off with the heat the solids take; the drying law evaluates a slower evaporation there (a thin-layer law's
    rate does not rise at the boiling point; a surface law's stops at its ceiling's), so the solids heat past it, wet."""
    dr = steady.dryer
    s = dr.settings
    boil = float(water.saturation_temperature(float(s.pressure)))
    T = np.asarray(steady.solids_temperature_degC, dtype=float)
    x = np.asarray(steady.moisture_wet, dtype=float)
    X = x / np.maximum(1.0 - x, 1e-12)
    # free water: above the law's critical moisture, where it has one (below it, a falling rate's water held in the
    # solids may be hotter than the boiling point; a thin-layer law has none)
    wet = max(WET_SOLIDS_MOISTURE, float(getattr(s.kinetics, "critical_moisture", None) or 0.0))
    i = _hottest_held(steady, (X > wet) & (T > boil + BOILING_MARGIN_K))
    if i is None:
        return None
    pm, pt = float(steady.product_moisture), float(steady.product_temperature_degC)
    law = getattr(s.kinetics, "method", "")
    return (f"wet solids above the boiling point: {100 * float(x[i]):.3g} % moisture (wet basis) at {float(T[i]):.4g} degC "
            f"in section {dr.tank_section[i]} ({float(dr.position[i]):.3g} m from the feed end; the product leaves at "
            f"{100 * pm:.3g} % and {pt:.4g} degC), where water boils at {boil:.4g} degC: the drying law "
            f"(kinetics.method = {law!r}) evaporates less than the heat the solids take would boil off, which the "
            "model does not describe; check the law's temperature range (a thin-layer law fitted below the boiling "
            "point), or lower gas.inlet_temperature")


def warn_wet_solids(steady: ThermalSteadyState) -> None:
    """A `WetSolidsWarning` when `wet_solids_message` has one."""
    _warn(wet_solids_message(steady), WetSolidsWarning)
