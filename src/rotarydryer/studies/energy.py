"""Energy audit of a case and what-if savings (issue 34 item 3), each computed by the coupled model.

"Where does the heat go, and what would recycling part of the exhaust, preheating the feed or
lagging the shell save?"

>>> from rotarydryer.studies.energy import energy_audit
>>> a = energy_audit("ajayi2011_mmg", recycle=[0.2], preheat=[20.0], insulation=[0.1])  # doctest: +SKIP
>>> [round(s.fuel_saved_kg_s * 3600, 1) for s in a.savings]                              # doctest: +SKIP

The base run is the case's coupled steady state; its heat duties (they add up to the heat
release, [`rotarydryer.thermal.audit`][rotarydryer.thermal.audit]), the exhaust's dew point and
the shell's temperatures against ``shell.max_temperature`` come from its summary. Each what-if is
one more coupled steady state of the same case with one change, started from the base state:

- **exhaust recycle** ``gas.recycle_fraction = r``: the drum's dry gas flow and inlet temperature
  stay, the burner heats the fresh air and the recycled exhaust (``ThermalDryer.inlet_gas``);
- **feed preheating** by ``dT`` K: ``operating.feed_temperature`` + dT (below 99 degC). The heat it
  takes, feed x c_p x dT (``preheat_duty_W``), comes from elsewhere (waste heat, e.g. the exhaust):
  the saving is the dryer's;
- **insulation** ``shell.insulation_thickness = t`` m (with the steel's hottest temperature, which
  lagging raises, against the limit).

At a fixed gas inlet temperature a measure also changes the product moisture (a drier product
takes more heat): each what-if reports both, the saving and ``product_moisture_change_kg_kg``.
With ``hold_moisture=True`` each what-if is also solved at the base product moisture, the gas inlet
temperature found by the target solver ([`rotarydryer.studies.target.target`][rotarydryer.studies.target.target]): the saving at
the same product, what an operator's moisture control would give.
"""

from __future__ import annotations

import numbers
import warnings
from dataclasses import dataclass, field

import numpy as np

from .._display import show, show_delta, show_output
from .._limits import check_key
from .._validation import finite_number, fmt_number
from ..cases.build import operating_point
from ..simulation import Simulation
from ..thermal.audit import (
    HEAT_DUTY_LABELS,
    HEAT_DUTY_PARTS,
    CondensationWarning,
    ShellTemperatureWarning,
    SolidsTemperatureWarning,
    SupersaturationWarning,
    WetSolidsWarning,
)
from ..thermal.states import PRODUCT_FLOOR_MOISTURE
from .target import default_tol, target

__all__ = ["energy_audit", "EnergyAudit", "WhatIf", "MEASURES", "parse_values"]

#: the what-if measures: name -> (case key, description)
MEASURES = {"recycle": ("gas.recycle_fraction", "exhaust recycle"),
            "preheat": ("operating.feed_temperature", "feed preheating"),
            "insulation": ("shell.insulation_thickness", "shell insulation")}
#: how far below and above the base gas inlet temperature the held-moisture search looks, K
HOLD_SPAN = (150.0, 60.0)
#: gas inlet temperatures further apart than this (K) giving the base product moisture (within the target's
#: tolerance) leave the held what-if undetermined: a product at its moisture floor (`_hold`)
HOLD_FLAT_K = 1.0
#: the held search's tolerance on the product moisture: this fraction of the what-if's own change of it (or the
#: target's default, if smaller)
HOLD_EFFECT_FRACTION = 0.05
#: a held search needs a tolerance above this fraction of the base moisture (the steady states' own precision)
HOLD_MIN_REL_TOL = 1e-8
#: the held what-if's product moisture, solved again at the temperature found, must equal the base's within this
#: many tolerances of the search (a warm start's path differs from the search's)
HOLD_TOL_FACTOR = 10.0


@dataclass
class WhatIf:
    """One what-if of an energy audit: ``measure`` (a key of `MEASURES`), its ``value`` (recycle
    fraction, preheat K, insulation m), the case ``overrides`` it runs with, and its outputs against
    the base run (savings positive): ``heat_saved_W`` (heat release), ``fuel_saved_kg_s`` (None
    without a burner), ``product_moisture_change_kg_kg``, the run's ``summary``; with a held product
    moisture, ``held`` (the gas inlet temperature found and the savings there) or ``held_error``;
    ``error`` when the steady state failed."""

    measure: str
    value: float
    overrides: dict
    summary: dict | None = None
    heat_saved_W: float | None = None
    fuel_saved_kg_s: float | None = None
    product_moisture_change_kg_kg: float | None = None
    preheat_duty_W: float | None = None
    held: dict | None = None
    held_error: str | None = None
    error: str | None = None
    #: why the what-if cannot be run as the plant is (the case's burner cannot make its gas): no savings then
    infeasible: str | None = None

    @property
    def label(self) -> str:
        """``exhaust recycle 20 %``, ``feed preheating +20 K``, ``shell insulation 0.1 m``."""
        if self.measure == "recycle":
            return f"exhaust recycle {fmt_number(100 * self.value)} %"
        if self.measure == "preheat":
            return f"feed preheating +{fmt_number(self.value)} K"
        return f"shell insulation {fmt_number(self.value)} m"

    def to_dict(self) -> dict:
        keys = ("product_moisture_kg_kg", "gas_outlet_temperature_degC", "gas_outlet_dew_point_margin_K",
                "heat_release_W", "fuel_rate_kg_s", "shell_heat_loss_W", "shell_max_wall_temperature_degC",
                "shell_temperature_limit_exceeded")
        s = self.summary or {}
        return dict(measure=self.measure, value=self.value, label=self.label, overrides=dict(self.overrides),
                    heat_saved_W=self.heat_saved_W, fuel_saved_kg_s=self.fuel_saved_kg_s,
                    product_moisture_change_kg_kg=self.product_moisture_change_kg_kg,
                    preheat_duty_W=self.preheat_duty_W, outputs={k: s.get(k) for k in keys if k in s},
                    held=self.held, held_error=self.held_error, error=self.error, infeasible=self.infeasible)


@dataclass
class EnergyAudit:
    """The audit of one case: the base run's ``summary`` (heat duties, dew point, shell), the
    shell per section (``shell_sections``) and the what-ifs (``savings``)."""

    case: str
    overrides: dict
    summary: dict
    shell_sections: list
    savings: list = field(default_factory=list)
    hold_moisture: bool = False

    def duties(self) -> dict:
        """``{name: W}``: the heat release, the duties that add up to it and the exhaust's latent heat."""
        names = ("heat_release_W", *HEAT_DUTY_PARTS, "heat_duty_exhaust_latent_W")
        return {k: self.summary[k] for k in names}

    def to_dict(self) -> dict:
        """One JSON-ready object (SI, unit-suffixed names): ``kind = "energy_audit"``."""
        s = self.summary
        keys = ("product_moisture_kg_kg", "product_temperature_degC", "gas_outlet_temperature_degC",
                "gas_outlet_humidity_kg_kg", "gas_outlet_dew_point_degC", "gas_outlet_dew_point_margin_K",
                "gas_pressure_Pa", "evaporation_kg_s", "evaporation_temperature_degC", "heat_input_W",
                "fuel_rate_kg_s", "specific_energy_kJ_kg_water", "thermal_efficiency",
                "shell_max_surface_temperature_degC", "shell_max_wall_temperature_degC",
                "shell_temperature_limit_degC", "shell_temperature_limit_exceeded", "energy_balance_error")
        return dict(kind="energy_audit", case=self.case, overrides=dict(self.overrides),
                    heat_duties=self.duties(), duty_parts=list(HEAT_DUTY_PARTS),
                    outputs={k: s.get(k) for k in keys if k in s}, shell_sections=list(self.shell_sections),
                    hold_moisture=self.hold_moisture, savings=[w.to_dict() for w in self.savings])

    def text(self) -> str:
        """The audit as plain text in the display units (`rotarydryer._display`), a line each."""
        return "\n".join(audit_lines(self.to_dict()))


def audit_lines(data: dict) -> list[str]:
    """Text lines of an audit's `EnergyAudit.to_dict` (the CLI's output; also for a saved audit)."""
    out, duties = data["outputs"], data["heat_duties"]
    release = duties["heat_release_W"]
    lines = [f"energy audit of {data['case']}"]
    lines.append("heat duties (they add up to the heat release):")
    w = max(len(HEAT_DUTY_LABELS[k]) for k in duties)
    for k, v in duties.items():
        share = f"{100 * v / release:6.1f} %" if release and k in data["duty_parts"] else ""
        indent = "  " if k == "heat_release_W" else "    "
        lines.append(f"{indent}{HEAT_DUTY_LABELS[k]:<{w}}  {show(v, 'power'):>14}  {share}".rstrip())
    dew, margin = out.get("gas_outlet_dew_point_degC"), out.get("gas_outlet_dew_point_margin_K")
    if dew is not None:
        lines.append(f"exhaust: {show_output('gas_outlet_temperature_degC', out['gas_outlet_temperature_degC'])}, "
                     f"dew point {show(dew, 'temperature')} at {fmt_number(out['gas_pressure_Pa'] / 1e3)} kPa: "
                     f"{show_delta(abs(margin), 'temperature')} "
                     + ("above it" if margin > 0 else "below it - CONDENSATION in the ducts and the bag filter"))
    limit = out.get("shell_temperature_limit_degC")
    lines.append(f"shell: hottest outer surface {show(out['shell_max_surface_temperature_degC'], 'temperature')}, "
                 f"hottest steel {show(out['shell_max_wall_temperature_degC'], 'temperature')}"
                 + ("" if limit is None else f" (limit shell.max_temperature {show(limit, 'temperature')}: "
                    + ("EXCEEDED)" if out.get("shell_temperature_limit_exceeded") else "met)")))
    for r in data["shell_sections"]:
        lines.append(f"  section {r['section']}: loss {show(r['shell_heat_loss_W'], 'power')}, surface up to "
                     f"{show(r['max_surface_temperature_degC'], 'temperature')}, steel up to "
                     f"{show(r['max_wall_temperature_degC'], 'temperature')}")
    if data["savings"]:
        lines.append("what-if (each a coupled steady state; savings positive"
                     + ("; held: at the base product moisture" if data["hold_moisture"] else "") + "):")
    for s in data["savings"]:
        if s["error"]:
            lines.append(f"  {s['label']}: no steady state ({s['error']})")
            continue
        if s.get("infeasible"):
            lines.append(f"  {s['label']}: NOT FEASIBLE, no saving ({s['infeasible']})")
            continue
        text = f"  {s['label']}: heat saved {show(s['heat_saved_W'], 'power')}"
        if s["fuel_saved_kg_s"] is not None:
            text += f", fuel saved {show(s['fuel_saved_kg_s'], 'fuel_flow')}"
        text += f"; product moisture {show_delta(s['product_moisture_change_kg_kg'], 'moisture')}"
        if s["preheat_duty_W"] is not None:
            text += f" (the preheat itself takes {show(s['preheat_duty_W'], 'power')})"
        if s["outputs"].get("shell_temperature_limit_exceeded"):
            text += (f"; the steel reaches {show(s['outputs']['shell_max_wall_temperature_degC'], 'temperature')}, "
                     "above shell.max_temperature")
        lines.append(text)
        if s["held"] is not None:
            h = s["held"]
            held = (f"    held: gas inlet {show(h['gas_inlet_temperature_degC'], 'temperature')}, heat saved "
                    f"{show(h['heat_saved_W'], 'power')}")
            if h["fuel_saved_kg_s"] is not None:
                held += f", fuel saved {show(h['fuel_saved_kg_s'], 'fuel_flow')}"
            lines.append(held)
        elif s["held_error"]:
            lines.append(f"    held: {s['held_error']}")
    return lines


def parse_values(text, label: str) -> list[float]:
    """``"0.1,0.2"`` (or a number or a list) as floats; a bad entry raises ``ValueError`` naming ``label``."""
    if text is None:
        return []
    items = text if isinstance(text, (list, tuple)) else str(text).split(",")
    out = []
    for item in items:
        if isinstance(item, str) and not item.strip():
            continue
        out.append(finite_number(item, f"{label}:", " (give comma-separated values, e.g. 0.1,0.2)"))
    if not out:     # '' or ',' was no what-if at all, exit 0 (found by fuzzing)
        raise ValueError(f"{label} {str(text)!r}: no value; give comma-separated values, e.g. 0.1,0.2")
    return out


def _what_if_overrides(sim: Simulation, measure: str, value: float) -> dict:
    key = MEASURES[measure][0]
    if measure == "preheat":
        if not value > 0:
            raise ValueError(f"--preheat {fmt_number(value)}: the feed temperature rise must be > 0 K")
        t_feed = operating_point(sim.case)[3]
        if not t_feed + value < 99.0:
            raise ValueError(f"--preheat {fmt_number(value)}: the feed would reach {fmt_number(t_feed + value)} degC; "
                             "operating.feed_temperature must stay below 99 degC (the model has no boiling feed)")
        return {key: t_feed + value}
    # the value against its key's range, named as the option the user gave (not as the --set it becomes)
    check_key(key, value, name=f"--{measure} ({key})")
    return {key: value}


def _what_if_values(name: str, values) -> tuple:
    """A what-if's values as a tuple of numbers: one number is one value; a text or another object is refused
    naming the argument (``recycle=0.2`` was "'float' object is not iterable", ``recycle="0.2"`` read one character
    at a time; found by an acceptance check). The values' ranges are the case keys' (checked by the caller)."""
    if isinstance(values, numbers.Real) and not isinstance(values, bool):
        return (values,)
    if isinstance(values, (str, bytes, dict)):
        raise ValueError(f"{name} = {values!r}: give a number or a list of numbers")
    try:        # any sequence or iterable of numbers (a range, a generator, a NumPy array, a pandas Series)
        out = tuple(np.asarray(values, dtype=object).ravel()) if isinstance(values, np.ndarray) else tuple(values)
    except TypeError:
        raise ValueError(f"{name} = {values!r}: give a number or a list of numbers") from None
    wrong = [v for v in out if isinstance(v, bool) or not isinstance(v, numbers.Real)]
    if wrong:
        raise ValueError(f"{name}: {wrong[0]!r} is not a number")
    return out


def energy_audit(case, overrides=None, *, recycle=(), preheat=(), insulation=(), hold_moisture=False,
                 progress=None) -> EnergyAudit:
    """The energy audit of ``case`` (name, ``.toml`` file or `Simulation`) at ``overrides``, with the
    what-ifs: ``recycle`` fractions [0, 1), ``preheat`` feed temperature rises (K), ``insulation``
    thicknesses (m); ``hold_moisture``: each also at the base product moisture (module docstring).
    ``progress(text)`` is called before each steady state. Bad values raise ``ValueError`` naming
    the case key; a what-if whose steady state fails carries its ``error``."""
    if overrides is not None and not isinstance(overrides, dict):
        raise ValueError(f"overrides = {overrides!r}: give a dict of case keys, e.g. {{'gas.flow': 16.0}}")
    recycle, preheat, insulation = (_what_if_values(name, v) for name, v in (("recycle", recycle),
                                                                          ("preheat", preheat),
                                                                          ("insulation", insulation)))
    if isinstance(case, Simulation):
        overrides = {**case.overrides, **(overrides or {})}
        case = case.reloadable_name("an energy audit")
    overrides = dict(overrides or {})
    base_sim = Simulation(case, overrides)
    if not base_sim.thermal_enabled:
        raise ValueError(f"case {case!r} has no heat and mass transfer (thermal.enabled = false or no [gas]): "
                         "an energy audit needs the coupled model")
    plan = [(m, v) for m, values in (("recycle", recycle), ("preheat", preheat), ("insulation", insulation))
            for v in values]
    changes = [(m, v, _what_if_overrides(base_sim, m, v)) for m, v in plan]
    for _, _, ov in changes:       # every value checked before the first run (the case schema's limits)
        Simulation(case, {**overrides, **ov})
    if progress:
        progress("base steady state ...")
    base = base_sim.steady_state()
    s0 = base.summary()
    audit = EnergyAudit(case=str(case), overrides=overrides, summary=s0, shell_sections=base.to_dict()["shell_sections"],
                        hold_moisture=hold_moisture)
    warm = base.warm_data()
    fS = base.thermal.dryer.feed_rate
    cp_feed = None
    for m, v, ov in changes:
        w = WhatIf(measure=m, value=v, overrides=ov)
        audit.savings.append(w)
        if progress:
            progress(f"{w.label} ...")
        try:
            with warnings.catch_warnings():     # a what-if's shell against the limit is in its outputs
                warnings.simplefilter("ignore", ShellTemperatureWarning)
                res = Simulation(case, {**overrides, **ov}).steady_state(warm=warm)
        except ValueError as exc:
            w.error = " ".join(str(exc).split())
            continue
        s = res.summary()
        w.summary = s
        f0, f1 = s0.get("fuel_rate_kg_s"), s.get("fuel_rate_kg_s")
        why = _footing_mismatch(f0, f1, s, s0)
        if why:
            # the base's burner cannot make the what-if's gas (its fuel beyond what its combustion air burns, or a
            # recycle that leaves no dilution air), or the base's own: one heat release would be the gas's heat
            # input instead of the fuel's, another footing than the other's, and the plant cannot run so; no saving
            w.infeasible = why
            if hold_moisture:
                w.held_error = "not run: the what-if is not feasible"
            continue
        w.heat_saved_W = s0["heat_release_W"] - s["heat_release_W"]
        w.fuel_saved_kg_s = None if f0 is None or f1 is None else f0 - f1
        w.product_moisture_change_kg_kg = s["product_moisture_kg_kg"] - s0["product_moisture_kg_kg"]
        if m == "preheat":
            if cp_feed is None:
                st = base.thermal.dryer.settings
                x = base.thermal.dryer.feed_moisture
                cp_feed = (1.0 - x) * st.cp_solids + x * st.cp_water
            w.preheat_duty_W = fS * cp_feed * v
        if hold_moisture:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ShellTemperatureWarning)
                _hold(w, case, overrides, ov, s0, base_sim.thermal_settings().gas_inlet_temperature, progress)
    return audit


def _footing_mismatch(f0, f1, s, s0=None) -> str | None:
    """Why a what-if's summary ``s`` and the base's (fuel rates ``f0``, ``f1``; None where the case's burner cannot
    make the gas) are on different footings (one heat release the fuel's, the other the gas's heat input), or None.
    ``s0``: the base's summary, for its reason when it is the base that the burner cannot make."""
    if (f0 is None) == (f1 is None):
        return None
    if f1 is None:
        why = " ".join(str(s.get("fuel_rate_error") or "the burner cannot make this gas").split())
        return f"the case's burner cannot make the gas of this what-if: {why}"
    why = " ".join(str((s0 or {}).get("fuel_rate_error") or "the burner cannot make the base's gas").split())
    return f"the case's burner cannot make the base run's gas, only this what-if's: {why}"


def _hold(w: WhatIf, case, overrides, ov, s0, t_in, progress) -> None:
    """``w.held``: the what-if at the base product moisture, the gas inlet temperature (base ``t_in``)
    found by the target solver (or ``w.held_error``)."""
    lo, hi = max(t_in - HOLD_SPAN[0], 1.0), min(t_in + HOLD_SPAN[1], 600.0)
    x0 = s0["product_moisture_kg_kg"]
    if not x0 > PRODUCT_FLOOR_MOISTURE:   # the target's tolerance is as large as the moisture itself
        w.held_error = (f"the base product moisture is {show_output('product_moisture_kg_kg', x0)}, below "
                        f"{fmt_number(PRODUCT_FLOOR_MOISTURE)} kg/kg: the product is dried to its floor (the material's "
                        "equilibrium moisture), so holding it does not fix a gas inlet temperature; hold a wetter "
                        "product with rotarydryer target instead")
        return
    # the held search must resolve the what-if's own effect on the moisture: at the target's default tolerance
    # (1e-4 of it) a thinner lagging was "held" 3e-6 kg/kg wetter than the base and reported a saving, a thicker
    # one a cost (found by fuzzing); at a twentieth of the effect the held temperature has the sign it must have
    dx = abs(float(w.product_moisture_change_kg_kg or 0.0))
    tol = min(default_tol("product_moisture_kg_kg", x0), HOLD_EFFECT_FRACTION * dx)
    if not tol > HOLD_MIN_REL_TOL * x0:
        w.held_error = (f"the what-if moves the product moisture by {fmt_number(dx)} kg/kg only, below what the held "
                        f"search resolves ({fmt_number(HOLD_MIN_REL_TOL / HOLD_EFFECT_FRACTION * x0)} kg/kg): the "
                        "product is dried to its floor (the material's equilibrium moisture), or the measure does not "
                        "reach it; holding it does not fix a gas inlet temperature, and the saving at the base "
                        "moisture is that of the run without the hold")
        return
    if progress:
        progress(f"{w.label}, held at the base product moisture ...")
    # the gas inlet temperature is what the hold finds: a --set of it is the base's (t_in), not fixed for the search
    free = {k: v for k, v in {**overrides, **ov}.items() if k != "gas.inlet_temperature"}
    try:
        with warnings.catch_warnings():     # the search's trial runs: ~40 lines of the same warning (found by fuzzing)
            warnings.simplefilter("ignore", SupersaturationWarning)
            warnings.simplefilter("ignore", CondensationWarning)
            warnings.simplefilter("ignore", SolidsTemperatureWarning)
            warnings.simplefilter("ignore", WetSolidsWarning)
            res = target(case, "gas.inlet_temperature", f"product_moisture_kg_kg={x0!r}", (lo, hi), overrides=free,
                         tol=tol)
    except ValueError as exc:
        w.held_error = " ".join(str(exc).split())
        return
    near = [x for x, y, _ in res.points if y is not None and abs(y - x0) <= res.tol]
    if len(near) > 1 and max(near) - min(near) > HOLD_FLAT_K:
        # a product dried to its floor (the material's equilibrium moisture): the same moisture over a range of gas
        # inlet temperatures does not fix one (the target stops at the first it meets, the bracket's end)
        w.held_error = (f"the product moisture is the base's ({show_output('product_moisture_kg_kg', x0)}, to "
                        f"{fmt_number(res.tol)} kg/kg) at every gas inlet temperature from {fmt_number(min(near))} to "
                        f"{fmt_number(max(near))} degC: the product is dried to its floor (the material's equilibrium "
                        "moisture), so holding it does not fix a gas inlet temperature; hold a wetter product with "
                        "rotarydryer target instead")
        return
    if not res.found:
        w.held_error = f"no gas inlet temperature in [{fmt_number(lo)}, {fmt_number(hi)}] degC gives the base product moisture"
        return
    try:
        s = Simulation(case, {**free, "gas.inlet_temperature": res.value}).steady_state().summary()
    except ValueError as exc:       # reported with the what-if, as every failed what-if (not an error of the audit)
        w.held_error = (f"at the gas inlet temperature found, {fmt_number(res.value)} degC: "
                        + " ".join(str(exc).split()))
        return
    if abs(s["product_moisture_kg_kg"] - x0) > HOLD_TOL_FACTOR * res.tol:
        w.held_error = (f"at the gas inlet temperature found, {fmt_number(res.value)} degC, the product moisture is "
                        f"{show_output('product_moisture_kg_kg', s['product_moisture_kg_kg'])}, not the base's "
                        f"{show_output('product_moisture_kg_kg', x0)}")
        return
    f0, f1 = s0.get("fuel_rate_kg_s"), s.get("fuel_rate_kg_s")
    why = _footing_mismatch(f0, f1, s)
    if why:         # the held run's gas (a hotter inlet) beyond the burner: no saving on another footing
        w.held_error = f"at the gas inlet temperature found, {fmt_number(res.value)} degC: {why}"
        return
    w.held = dict(gas_inlet_temperature_degC=float(res.value), product_moisture_kg_kg=s["product_moisture_kg_kg"],
                  heat_release_W=s["heat_release_W"], heat_saved_W=s0["heat_release_W"] - s["heat_release_W"],
                  fuel_saved_kg_s=None if f0 is None or f1 is None else f0 - f1)
