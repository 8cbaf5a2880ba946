"""States of the heat-and-mass model: a converged steady state ([`ThermalSteadyState`][rotarydryer.thermal.states.ThermalSteadyState]), the
same state seen as a transport steady state ([`CoupledTransportState`][rotarydryer.thermal.states.CoupledTransportState]) and a dynamic run
([`DynamicResult`][rotarydryer.thermal.states.DynamicResult]). Temperatures in degC, names ending in ``_degC``."""

from __future__ import annotations

import warnings
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from .._display import html_table, outputs_dataframe, short_repr
from ..properties.humid_air import dew_point
from ..properties.psd import percentile_diameter
from ..transport.network import TracerSystem, tracer_system_from_flows
from ..transport.results import SteadyState
from ..transport.sections import cell_info_at
from . import audit
from . import balances as bal
from .burner import fuel_rate_for_temperature, fuel_rate_with_recycle
from .settings import DryerError
from .streams import discharge_cooling

if TYPE_CHECKING:
    from .dryer import ThermalDryer

__all__ = ["ThermalSteadyState", "CoupledTransportState", "DynamicResult", "fuel_rate_note", "outlets",
           "EntrainmentWarning", "check_entrainment", "dust_share", "DUST_WARN_FRACTION", "DUST_REFUSE_FRACTION",
           "PRODUCT_FLOOR_MOISTURE"]

#: a steady state losing more than this share of the feed's dry solids as dust is reported (a warning)
DUST_WARN_FRACTION = 0.5
#: ... and refused beyond this share: nothing left to call a product
DUST_REFUSE_FRACTION = 0.99
#: a product drier than this (kg/kg wet) is dried to its floor (the material's equilibrium moisture): its moisture
#: does not respond to the inputs, so a product-moisture loop has nothing to control and holding it in an audit's
#: what-if fixes no gas inlet temperature (found by fuzzing: gains of 1e-10 tuned, a hold at 1.8e-7 kg/kg)
PRODUCT_FLOOR_MOISTURE = 1e-5


class EntrainmentWarning(UserWarning):
    """Most of the feed, or a whole size class, leaves the dryer as dust with the exhaust gas."""


def dust_share(thermal, rows=None) -> float:
    """The share of the feed's dry solids that leaves as dust (``rows``: `ThermalSteadyState.size_class_table`, if
    at hand): the one figure of the entrainment warning, simulate's text and the report."""
    rows = thermal.size_class_table() if rows is None else rows
    return sum(r["lost_as_dust"] * r["feed_fraction"] for r in rows)


def check_entrainment(thermal) -> None:
    """Warn (`EntrainmentWarning`) where a steady state loses more than `DUST_WARN_FRACTION` of the feed
    or a whole size class as dust, and refuse (``ValueError``) one losing more than
    `DUST_REFUSE_FRACTION`: each message names the classes, the gas flow and the keys to change."""
    dr = thermal.dryer
    if not dr.dusty:
        return
    rows = thermal.size_class_table()
    lost = dust_share(thermal, rows)
    gone = [f"{r['diameter_m'] * 1e6:.0f} um" for r in rows if r["lost_as_dust"] > 0.999]
    g = dr.settings.gas_flow
    if lost > DUST_REFUSE_FRACTION:
        raise DryerError(f"entrainment: {lost:.1%} of the feed leaves as dust with the exhaust at gas.flow = {g:g} "
                         "kg/s: nothing is left as a product; lower gas.flow or give a coarser particle_size",
                         reason="entrained", state=thermal)
    if lost > DUST_WARN_FRACTION:
        warnings.warn(f"entrainment: {lost:.1%} of the feed leaves as dust with the exhaust at gas.flow = {g:g} kg/s "
                      f"(size classes {', '.join(gone) or 'partly'}); lower gas.flow or give a coarser particle_size",
                      EntrainmentWarning, stacklevel=3)
    elif gone:
        warnings.warn(f"entrainment: the size class(es) {', '.join(gone)} leave(s) entirely as dust at gas.flow = "
                      f"{g:g} kg/s", EntrainmentWarning, stacklevel=3)


def fuel_rate_note(summary: dict) -> str:
    """One line saying why a run has no fuel rate although its case has a burner (the burner cannot
    reach the set gas inlet temperature) and what was simulated instead, or '' when it has one
    (``summary``: [`ThermalSteadyState.summary`][rotarydryer.thermal.states.ThermalSteadyState.summary], or any dict with ``fuel_rate_error``). The
    steady state is still valid for the set temperature: the gas the burner cannot deliver."""
    err = summary.get("fuel_rate_error")
    if not err:
        return ""
    return (f"{' '.join(str(err).split())}; simulated with the set gas inlet temperature anyway (a gas this "
            "burner cannot deliver): fuel rate n/a")

class _Renamed:
    """A deprecated attribute name that reads the new one with a ``DeprecationWarning`` naming it
    (issue 27: ``_degC`` on every public temperature)."""

    def __init__(self, new: str):
        self.new = new

    def __set_name__(self, owner, name):
        self.old = name

    def __get__(self, obj, owner=None):
        if obj is None:
            return self
        warnings.warn(f"{type(obj).__name__}.{self.old} is deprecated: use .{self.new}", DeprecationWarning,
                      stacklevel=2)
        return getattr(obj, self.new)


class _RenamedKeys(dict):
    """A dict whose old key names still read, with a ``DeprecationWarning`` naming the new one."""

    def __init__(self, data, renamed):
        super().__init__(data)
        self._renamed = dict(renamed)

    def __missing__(self, key):
        if key in self._renamed:
            warnings.warn(f"profiles key {key!r} is deprecated: use {self._renamed[key]!r}", DeprecationWarning,
                          stacklevel=2)
            return self[self._renamed[key]]
        raise KeyError(key)


#: old profile keys -> the names with the unit suffixes of every other output
_PROFILE_RENAMED = {"solids_temperature_c": "solids_temperature_degC", "gas_temperature_c": "gas_temperature_degC",
                    "shell_loss_w": "shell_loss_W"}


class ThermalSteadyState:
    """A converged steady state: profiles, outlet values and balances (SI, °C: names end in ``_degC``)."""

    solids_temperature_c = _Renamed("solids_temperature_degC")
    gas_temperature_c = _Renamed("gas_temperature_degC")
    gas_outlet_temperature_c = _Renamed("gas_outlet_temperature_degC")
    product_temperature_c = _Renamed("product_temperature_degC")

    def __init__(self, dryer: ThermalDryer, z, iterations=0, residual=0.0, seconds=0.0):
        self.dryer = dryer
        self.state = np.asarray(z, dtype=float)
        #: the solver's last factorisation of I/dt - J (an object with ``solve(b)`` and ``shape``: SciPy's
        #: SuperLU or its column-ordered form, :meth:`rotarydryer._sparse_fd.FDPlan.shifted_lu`), a start for
        #: nearby solves
        self.factorization = None
        self.iterations = iterations
        #: simulated seconds of the transient march that preceded Newton (0: Newton from the start)
        self.marched_s = 0.0
        self.residual = float(residual)
        self.seconds = seconds
        s = dryer.settings
        d = dryer.terms(self.state)
        self.terms = d
        self.transport_moisture_clipped = bool(dryer._clipped)
        S, W, T, Tg, Y = d["S"], d["W"], d["T"], d["Tg"], d["Y"]
        self.solids_temperature_degC = T
        self.moisture_wet = W / (S + W)
        self.holdup = S + W
        self.gas_temperature_degC = Tg
        self.gas_humidity = Y
        Fd = dryer.dry_gas_flow
        k = dryer.gas_outlet_stage
        self.gas_outlet_temperature_degC = float(Tg[k])
        self.gas_outlet_humidity = float(Y[k])
        pS, pW, pH = d["product_S"], d["product_W"], d["product_H"]
        dS, dW, dH = d["dust_S"], d["dust_W"], d["dust_H"]
        #: dust carried to the exhaust, kg/s wet (size classes with entrainment; else 0)
        self.dust_rate = dS + dW
        self.product_rate = pS + pW
        if not float(pS) > 1e-12 * dryer.feed_rate:     # a product of no solids has no moisture or temperature
            raise DryerError(
                f"entrainment: at gas.flow = {s.gas_flow:g} kg/s the steady state leaves no product: the gas carries "
                "the whole feed off as dust; lower gas.flow or give a coarser particle_size", reason="entrained")
        self.product_moisture = pW / (pS + pW)
        self.product_temperature_degC = pH / (pS * s.cp_solids + pW * s.cp_water)
        self.evaporation_rate = float(np.sum(d["rw"]))
        self.shell_heat_loss_w = float(np.sum(d["qloss"]))
        fS, fW = dryer.feed_rate * (1 - dryer.feed_moisture), dryer.feed_rate * dryer.feed_moisture
        # the drum's balances: the gas entering its first stage (with exhaust recycle, of this state)
        Yin, h_in = d["Y_in"], d["h_in"]
        w_in = fW + Fd * Yin
        w_out = pW + dW + Fd * Y[k]
        # relative to the water in; a bone-dry feed in dry gas: to 1e-9 of the mass flows
        self.water_balance_error = abs(w_in - w_out) / max(w_in, 1e-9 * (dryer.feed_rate + Fd))
        self.solids_balance_error = abs(fS - pS - dS) / fS
        hs_in = (fS * s.cp_solids + fW * s.cp_water) * s.solids_inlet_temperature
        # the solver's states are checked (the unchecked enthalpy; the inlet's remembered per settings)
        hg_in = Fd * h_in
        hg_out = Fd * float(bal._gas_enthalpy(Tg[k], Y[k], s.mode))
        e_in = hs_in + hg_in
        e_out = pH + dH + hg_out + self.shell_heat_loss_w
        self.energy_in_w = e_in
        # relative to the energy in; a dryer whose streams all enter near the reference 0 degC: to
        # their heat capacity flow x 100 K (the solver's temperature scale, ThermalDryer._scale)
        e_ref = max(abs(e_in), (fS * s.cp_solids + fW * s.cp_water + Fd * 1006.0) * 100.0)
        self.energy_balance_error = abs(e_in - e_out) / e_ref
        #: energy streams of the balance, W (enthalpies relative to the model's reference state)
        self.energy_terms_w = {
            "in": {"hot gas": float(hg_in), "wet feed": float(hs_in)},
            "out": {"exhaust gas": float(hg_out), "product": float(pH), "shell loss": float(self.shell_heat_loss_w)},
        }
        if dryer.dusty:
            self.energy_terms_w["out"]["dust"] = float(dH)
        # the same streams with physical enthalpies (closes only in the physical mode)
        if s.mode == "physical":
            hg_in_p, hg_out_p = hg_in, hg_out
            self.physical_shell_loss_w = self.shell_heat_loss_w
        else:   # and the shell network (shell temperature solved) at the same gas temperatures
            hg_in_p = Fd * dryer.gas_inlet_enthalpy("physical")
            if s.recycle_fraction:      # the recycled exhaust at the inlet temperature (ThermalDryer.inlet_gas)
                hg_in_p += Fd * s.recycle_fraction * float(
                    bal._gas_enthalpy(s.gas_inlet_temperature, Y[k], "physical")
                    - bal._gas_enthalpy(s.gas_inlet_temperature, dryer.hot_gas_Y, "physical"))
            hg_out_p = Fd * float(bal._gas_enthalpy(Tg[k], Y[k], "physical"))
            self.physical_shell_loss_w = float(np.sum(dryer.physical_shell_loss(Tg, Y)))
        e_in_p = hs_in + hg_in_p
        # its magnitude, as energy_balance_error's (one balance read +1.8e-15 there and -1.8e-15 here; found by an
        # acceptance check); which way it misses: physical_implied_shell_loss_w against the shell loss
        self.physical_energy_balance_error = abs(e_in_p - (pH + dH + hg_out_p + self.physical_shell_loss_w)) / max(
            abs(e_in_p), e_ref)
        self.physical_implied_shell_loss_w = e_in_p - pH - dH - hg_out_p
        self.gas_heat_duty_w = hg_in - hg_out

    @property
    def total_holdup(self):
        return float(np.sum(self.holdup))

    @property
    def mean_residence_time(self) -> float:
        """Mean residence time of the solids, s: dry holdup over the dry solids leaving (product and dust), Little's
        law on the solids the tracer follows (Lee (2008) Eq. 2.2 with drying), the mean of the tracer's impulse
        response. The water held in the drum leaves mostly by evaporation, not with the product: the wet holdup
        over the wet product counted it as solids (+12 % on a wet counter-current dryer)."""
        d = self.terms
        out = float(np.sum(d["product_S"])) + float(np.sum(d["dust_S"]))
        return float(np.sum(d["S"])) / out if out > 0 else float("inf")

    def transport_state(self):
        """This state as a transport steady state ([`CoupledTransportState`][rotarydryer.thermal.states.CoupledTransportState]) on the
        heat-and-mass model's network: the coupled holdups and flows, the design loads and per-cell
        coefficients at the computed moisture. Its totals, section holdups, cell table and tracer
        moments are this state's, so every view (``simulate --json`` ``sections``/``cells``, the
        holdup plot, Results, the report) shows one number per quantity."""
        if getattr(self, "_transport_state", None) is None:
            dr, d = self.dryer, self.terms
            m = d["S"] + d["W"]
            sizes = [f.src.size for f in dr.families]         # the network's edges (the dust edges after them)
            flows = np.split(np.asarray(d["F"], dtype=float)[:sum(sizes)], np.cumsum(sizes)[:-1])
            self._transport_state = CoupledTransportState(self, dr.model, m, flows=flows)
        return self._transport_state

    def _cells_at_state(self):
        """(design load per node, kg; per-cell coefficients of the passive nodes) at this state's moisture
        and the run's speed (`transport_state`; evaluated when a view asks for them: the fill check of a
        study's run does not)."""
        dr, d = self.dryer, self.terms
        model = dr.model
        m = d["S"] + d["W"]
        design = np.array(model.design_load, dtype=float)
        per_node = {k: np.full(m.size, np.nan) for k in model.cell_info}
        passive, _ = dr._passive(d["W"], m, dr.laws)
        for law, (_, xp) in zip(dr.laws, passive):
            des, info = cell_info_at(law, xp, dr.rpm)   # at this run's speed
            design[law.P] = des
            for k in per_node:
                if k in info:
                    per_node[k][law.P] = info[k]
        p = np.asarray(model.network.labels["phase"]) == "passive"
        return design, {k: v[p] for k, v in per_node.items()}

    def tracer_system(self, size_class: int | None = None):
        """Linear tracer system at the coupled steady flows (wet solids; tracer follows the solids),
        so RTD moments agree with the holdups of this state; ``size_class``: a tracer of that class's size
        (its own holdups and flows; the part the gas carries away as dust is lost to the product's curve).
        With size classes and no ``size_class``, the feed's tracer: on particles of every size in the feed's
        proportions, each class's system side by side (one block each), fed its share. Where nothing leaves as
        dust its mean is within a fraction of a percent of a tracer spread over each tank's mixture (0.2 % in
        Song's drum with five sand classes: the classes move and dry at their own rates); where the gas carries
        fines off, their tracer leaves with them (spread over the mixture, it passed from the fines to the
        coarse product, whose curve then came 15 % early against its own class's)."""

        if size_class is None and self.dryer.n_classes > 1:
            systems = [self.tracer_system(c) for c in range(self.dryer.n_classes)]
            return TracerSystem(sp.block_diag([t.K for t in systems], format="csc"),
                                np.concatenate([t.outlet for t in systems]),
                                np.concatenate([w * t.inlet for w, t in zip(self.dryer.class_feed, systems)]))
        d = self.terms
        inlet = np.zeros(d["S"].size)
        inlet[self.dryer.entry] = 1.0
        if size_class is None:
            return tracer_system_from_flows(d["S"] + d["W"], d["src"], d["dst"], d["F"], inlet)
        c = int(size_class)
        return tracer_system_from_flows(d["Sc"][c] + d["Wc"][c], d["src"], d["dst"], d["Fc"][c], inlet)

    def fuel_rate(self, fuel_heat_loss_fraction=None):
        """Fuel rate (kg/s) that the case's burner (``ThermalSettings.burner``, Ajayi (2011) App. A
        combustion chamber) needs to heat this gas flow to the inlet temperature (air at ambient,
        humidity of the gas). ``fuel_heat_loss_fraction`` replaces the burner's. Raises
        [`DryerError`][rotarydryer.thermal.settings.DryerError] if the case has no burner or it cannot reach the set temperature."""

        s = self.dryer.settings
        try:
            return self.fuel_rate_at(s.gas_inlet_temperature, fuel_heat_loss_fraction)
        except DryerError:          # no burner: its own reason
            raise
        except ValueError as exc:
            why = str(exc)
            if why.startswith("burner cannot reach target_temperature_c") and ": " in why:
                why = why.split(": ", 1)[1]        # the set temperature is named once, below
            raise DryerError(f"burner cannot reach the set gas inlet temperature {s.gas_inlet_temperature:g} degC: "
                             f"{why}", reason="burner", state=self) from exc

    def fuel_rate_at(self, gas_inlet_temperature, fuel_heat_loss_fraction=None) -> float:
        """Fuel rate (kg/s) of the case's burner for a gas inlet temperature (degC), the air and any
        recycled exhaust of this state (``ValueError`` where the burner cannot give it): `fuel_rate`'s
        chamber balance at another temperature; the recycled exhaust (``gas.recycle_fraction``) is this
        state's, so a dynamic run converts a fuel rate with the exhaust of the moment."""
        dr = self.dryer
        s = dr.settings
        b = s.burner
        if b is None:
            raise DryerError("the case has no burner ([gas.burner] combustion_air_share, fuel): no fuel rate",
                             reason="no_burner", state=self)
        loss = b.heat_loss_fraction if fuel_heat_loss_fraction is None else fuel_heat_loss_fraction
        air = s.gas_flow
        if s.recycle_fraction:
            # fresh air (the combustion air and the rest as dilution air) and the recycled exhaust
            hot, leak = dr._flows_in
            back = s.recycle_fraction * (hot + leak)
            fresh = (hot - back) * (1.0 + dr.hot_gas_Y)
            y = self.gas_outlet_humidity
            dilution = fresh - air * b.combustion_air_share
            if 0.0 > dilution >= -1e-12 * air:      # recycle = 1 - combustion air share: no dilution air, not -2e-16
                dilution = 0.0
            return float(fuel_rate_with_recycle(
                gas_inlet_temperature, air * b.combustion_air_share, dilution,
                back * (1.0 + y), self.gas_outlet_temperature_degC, y, air_temperature_c=s.ambient_temperature,
                air_humidity=dr.hot_gas_Y, fuel=b.fuel, heat_loss_fraction=loss))
        return float(fuel_rate_for_temperature(gas_inlet_temperature, air * b.combustion_air_share,
                                               air * (1 - b.combustion_air_share),
                                               air_temperature_c=s.ambient_temperature,
                                               air_humidity=dr.hot_gas_Y, fuel=b.fuel, heat_loss_fraction=loss))

    def profiles(self):
        """Axial profiles: dict of arrays (position m, phase, section, solids moisture wet, T and holdup per tank; gas
        position, T, Y, evaporation, shell loss and transfer area per gas stage), named with their units (the old
        ``_c``/``_w`` names still read, deprecated)."""
        dr = self.dryer
        return _RenamedKeys(dict(
            position=dr.position, phase=np.array(["bed", "passive", "active"])[dr.kind], section=dr.tank_section,
            solids_temperature_degC=self.solids_temperature_degC, moisture_wet=self.moisture_wet, holdup_kg=self.holdup,
            gas_position=dr.gas_position, gas_temperature_degC=self.gas_temperature_degC, gas_humidity=self.gas_humidity,
            evaporation_kg_s=self.terms["rw"], shell_loss_W=self.terms["qloss"], area_m2=self.terms["area"]),
            _PROFILE_RENAMED)

    def solids_moisture_at(self, positions_m):
        """Wet-basis moisture (kg/kg) of the solids on the flights and in the beds (the airborne curtains
        left out) at axial positions (m from the feed end), interpolated along the drum and clamped at
        its ends: what samples taken along a stopped dryer hold (Ajayi (2011) Table 3.3, l.802)."""
        p = self.profiles()
        solids = np.asarray(p["phase"]) != "active"
        pos, w = np.asarray(p["position"], float)[solids], np.asarray(p["moisture_wet"], float)[solids]
        order = np.argsort(pos, kind="stable")
        return np.interp(np.asarray(positions_m, float), pos[order], w[order])

    def __repr__(self):

        return short_repr("ThermalSteadyState", self.dryer.model.name, [
            ("product moisture kg/kg", float(self.product_moisture)),
            ("product degC", float(self.product_temperature_degC)),
            ("gas out degC", self.gas_outlet_temperature_degC), ("holdup kg", self.total_holdup),
            ("energy balance error", float(self.energy_balance_error))])

    def _repr_html_(self):

        return html_table(self.summary(with_fuel=False), caption=f"heat-and-mass steady state ({self.dryer.model.name})")

    def to_dataframe(self):
        """Named outputs ([`summary`][rotarydryer.thermal.states.ThermalSteadyState.summary]) as a pandas DataFrame (value, unit)."""

        return outputs_dataframe(self.summary(with_fuel=False))

    @property
    def product_d50(self) -> float:
        """Mass-median diameter of the product (m): its class masses on the feed's class edges
        ([`percentile_diameter`][rotarydryer.properties.psd.percentile_diameter]); one class: its diameter."""
        dr = self.dryer
        sc = dr.size_classes
        return percentile_diameter(sc.edges, np.atleast_1d(self.terms["product_S_c"]), 0.5, sc.diameters)

    def size_class_table(self) -> list[dict]:
        """One row per size class: its diameter at the feed (m), its mass fraction of the feed, of the
        product and of the dust (dry solids), its share of the feed lost as dust, its product moisture
        (kg/kg wet), its holdup (kg) and its mean residence time: dry holdup over the class's dry feed (s;
        what a tracer of its size would show, the lost part included), and the mean of its product's residence
        time distribution (``rtd_mean_s``: the impulse response at the product outlet of a tracer of its size,
        `tracer_system`)."""
        dr, d = self.dryer, self.terms
        pS, pW = np.atleast_1d(d["product_S_c"]), np.atleast_1d(d["product_W_c"])
        dS = np.atleast_1d(d["dust_S_c"])
        fS = dr.feed_rate * (1.0 - dr.feed_moisture) * dr.class_feed
        hold = (d["Sc"] + d["Wc"]).sum(axis=-1)
        dry = d["Sc"].sum(axis=-1)
        rows = []
        for c in range(dr.n_classes):
            flow = pS[c] + pW[c]
            rows.append(dict(size_class=c, diameter_m=float(dr.class_diameter[c]), feed_fraction=float(dr.class_feed[c]),
                             product_fraction=float(pS[c] / max(pS.sum(), 1e-300)),
                             dust_fraction=float(dS[c] / dS.sum()) if dS.sum() > 0 else 0.0,
                             # a share: at most 1 (a class all carried off read 1.000000000000001 by rounding)
                             lost_as_dust=min(float(dS[c] / fS[c]), 1.0) if fS[c] > 0 else 0.0,
                             product_moisture_kg_kg=float(pW[c] / flow) if flow > 0 else None,
                             holdup_kg=float(hold[c]), mean_residence_time_s=float(dry[c] / fS[c]) if fS[c] > 0 else None,
                             rtd_mean_s=self._class_rtd_mean(c) if flow > 0 else None))
        return rows

    def _class_rtd_mean(self, c: int) -> float | None:
        m = self.tracer_system(c).moments()
        return float(m["mean"]) if m["recovery"] > 1e-9 and np.isfinite(m["mean"]) else None

    @property
    def heat_input_w(self):
        """Heat put into the drying gas (W): the entering gas's enthalpy above that of the same gas
        at ambient temperature (what a burner or heater supplies to it), mode-consistent. With exhaust
        recycle (``recycle_fraction`` r): the fresh air (dry flow hot - r F_d) heated from ambient
        and the recycled exhaust (r F_d, at the exhaust humidity) from the exhaust temperature, both
        to the inlet temperature. Computed once per state (a summary asks for it seven times)."""
        q = getattr(self, "_heat_input", None)
        if q is None:
            q = self._heat_input = self._heat_input_of_gas()
        return q

    def _heat_input_of_gas(self):
        dr = self.dryer
        s = dr.settings
        hot, leak = dr._flows_in
        mode = s.mode
        dh = float(bal.gas_enthalpy(s.gas_inlet_temperature, dr.hot_gas_Y, mode)) - float(
            bal.gas_enthalpy(s.ambient_temperature, dr.hot_gas_Y, mode))
        r = s.recycle_fraction
        if r == 0:
            return hot * dh
        back = r * (hot + leak)             # the recycled exhaust, kg/s dry gas
        y, t = self.gas_outlet_humidity, self.gas_outlet_temperature_degC
        return (hot - back) * dh + back * float(bal.gas_enthalpy(s.gas_inlet_temperature, y, mode)
                                                - bal.gas_enthalpy(t, y, mode))

    @property
    def thermal_efficiency(self):
        """Heat that evaporated water (the evaporation duty ``heat_duty_evaporation_W``: each stage's
        evaporation x the latent heat at the temperature of its solids, [`rotarydryer.thermal.audit`][rotarydryer.thermal.audit])
        over [`heat_input_w`][rotarydryer.thermal.states.ThermalSteadyState.heat_input_w] (-); the usual dryer efficiency (Kemp, Handbook of
        Industrial Drying, 'energy efficiency'). (Before the energy audit it took the latent heat at
        the product temperature for all the water: MMG Test 4 0.484, now 0.486.)"""

        q = self.heat_input_w
        if q <= 0:
            return float("nan")
        return self.heat_duties_w()["heat_duty_evaporation_W"] / q

    def _burner_fuel_rate(self):
        """The case's burner's fuel rate (kg/s), or None (no burner, or it cannot reach the set point)."""
        if self.dryer.settings.burner is None:
            return None
        try:
            return self.fuel_rate()
        except DryerError:
            return None

    def heat_duties_w(self) -> dict:
        """Heat duties of this state, W ([`rotarydryer.thermal.audit.heat_duties`][rotarydryer.thermal.audit.heat_duties]): ``heat_release_W``
        (fuel x LHV of the case's burner, else the heat put into the gas) and the duties that add up
        to it (`rotarydryer.thermal.audit.HEAT_DUTY_PARTS`), with ``heat_duty_exhaust_latent_W``."""
        if getattr(self, "_duties", None) is None:
            self._duties = audit.heat_duties(self, self._burner_fuel_rate())
        return dict(self._duties)

    def shell_profile(self) -> dict:
        """Shell per gas stage: loss, outer surface and hottest wall temperatures
        ([`rotarydryer.thermal.audit.shell_profile`][rotarydryer.thermal.audit.shell_profile]; computed once)."""
        if getattr(self, "_shell_profile", None) is None:
            self._shell_profile = audit.shell_profile(self)
        return self._shell_profile

    def summary(self, with_fuel=True, outputs=None):
        """Outputs of the state, named with their unit (the names of ``simulate --json``, sweeps,
        Results and the report). Balance errors are relative; ``thermal_mode`` the model mode. The
        energy audit's heat duties (``heat_release_W``, ``heat_duty_*_W``; they add up to the release),
        the shell's hottest surface and wall against ``shell.max_temperature`` and the gas pressure
        (the site's) are in every summary ([`rotarydryer.thermal.audit`][rotarydryer.thermal.audit]).
        ``outputs`` (names; None: all): the groups that cost a computation - the heat duties and the
        efficiency, the shell temperatures, the dew point, the product at a sensor downstream - are
        left out unless one of their names is wanted (a study's many runs); every value is the same."""
        want = None if outputs is None else set(outputs)

        def wanted(*names):
            return want is None or not want.isdisjoint(names)

        kind, hold = self.dryer.kind, self.holdup
        y_out = float(self.gas_outlet_humidity)
        dew = None
        try:        # None for a gas too dry for the saturation curve's range (dew point below about -60 degC)
            if y_out > 0 and wanted("gas_outlet_dew_point_degC", "gas_outlet_dew_point_margin_K"):
                dew = float(dew_point(y_out, self.dryer.settings.pressure))
        except ValueError:
            dew = None
        # no water removed (a dry feed, or humid gas condensing on cold solids): undefined; above 1 (the evaporation
        # duty beyond the heat put into the gas: a warm feed's own heat pays for part of it) the ratio is no
        # efficiency either: undefined
        efficiency = None
        if wanted("thermal_efficiency") and self.evaporation_rate > 1e-12 and np.isfinite(self.thermal_efficiency) \
                and self.thermal_efficiency <= 1.0:
            efficiency = self.thermal_efficiency
        out = dict(
            thermal_mode=self.dryer.settings.mode,
            total_holdup_kg=self.total_holdup, active_holdup_kg=float(np.sum(hold[kind == 2])),
            passive_holdup_kg=float(np.sum(hold[kind == 1])), bed_holdup_kg=float(np.sum(hold[kind == 0])),
            feed_rate_kg_s=self.dryer.feed_rate, outlet_flow_kg_s=float(self.product_rate),
            # dry holdup over every dry solids outflow (Little's law): the product and, with size classes, the dust
            # the gas carries off
            mean_residence_time_s=self.mean_residence_time,
            product_moisture_kg_kg=float(self.product_moisture),
            product_temperature_degC=float(self.product_temperature_degC),
            gas_outlet_temperature_degC=self.gas_outlet_temperature_degC,
            gas_outlet_humidity_kg_kg=self.gas_outlet_humidity,
            gas_outlet_dew_point_degC=dew,
            # how far the exhaust is above its dew point (condensation in the ducts and bag filter below 0)
            gas_outlet_dew_point_margin_K=None if dew is None else self.gas_outlet_temperature_degC - dew,
            evaporation_kg_s=self.evaporation_rate,
            heat_input_W=self.heat_input_w,
            # undefined without water removed, or without heat put into the gas (a gas at or below the ambient
            # reference: the water then dries on the feed's own heat and the dryer's, not the gas's)
            specific_energy_kJ_kg_water=(self.heat_input_w / self.evaporation_rate / 1e3
                                         if self.evaporation_rate > 1e-12 and self.heat_input_w > 0 else None),
            thermal_efficiency=efficiency,
            shell_heat_loss_W=self.shell_heat_loss_w,
            gas_flow_kg_s=self.dryer.settings.gas_flow,
            energy_balance_error=float(self.energy_balance_error),
            water_balance_error=float(self.water_balance_error),
            solids_balance_error=float(self.solids_balance_error),
            # wet solids: feed = product + evaporation (the transport model's mass balance, with drying)
            mass_balance_error=abs(self.dryer.feed_rate - float(self.product_rate) - self.evaporation_rate
                                   - float(self.dust_rate)) / self.dryer.feed_rate,
            dust_rate_kg_s=float(self.dust_rate),
            product_d50_m=self.product_d50,
            physical_energy_balance_error=float(self.physical_energy_balance_error),
            physical_shell_loss_W=float(self.physical_shell_loss_w),
            transport_moisture_clipped=self.transport_moisture_clipped,
            solver_iterations=self.iterations, solver_time_s=self.seconds,
        )
        if want is not None:        # not computed: absent (None would read as undefined)
            for group in (("gas_outlet_dew_point_degC", "gas_outlet_dew_point_margin_K"), ("thermal_efficiency",)):
                if not wanted(*group):
                    for name in group:
                        del out[name]
        # the energy audit (rotarydryer.thermal.audit): heat duties, the shell against its limit
        if wanted(*(k for k in audit.DUTY_KEYS if k not in out)):     # shell_heat_loss_W is there already
            out.update(self.heat_duties_w())
        if wanted("evaporation_temperature_degC"):
            out["evaporation_temperature_degC"] = audit.evaporation_temperature(self)
        if wanted(*audit.SHELL_KEYS):
            out.update(audit.shell_temperatures(self))
        out["gas_pressure_Pa"] = float(self.dryer.settings.pressure)
        st = self.dryer.settings
        if st.discharge_cooling_ntu > 0 and wanted("product_temperature_at_sensor_degC",
                                                   "product_moisture_at_sensor_kg_kg"):
            # what a sensor downstream of the drum outlet reads
            t_s, x_s = discharge_cooling(self.product_temperature_degC, self.product_moisture, st.discharge_cooling_ntu,
                                         st.ambient_temperature, st.ambient_humidity, st.cp_solids, st.cp_water)
            out["product_temperature_at_sensor_degC"] = float(t_s)
            out["product_moisture_at_sensor_kg_kg"] = float(x_s)
        if with_fuel:
            try:
                out["fuel_rate_kg_s"] = self.fuel_rate()
            except DryerError as exc:
                out["fuel_rate_kg_s"] = None
                out["fuel_rate_error"] = str(exc)
        return out


class CoupledTransportState(SteadyState):
    """A coupled steady state seen as a transport [`SteadyState`][rotarydryer.transport.results.SteadyState]
    ([`ThermalSteadyState.transport_state`][rotarydryer.thermal.states.ThermalSteadyState.transport_state]): wet-solids holdups and flows of the heat-and-mass
    model, its tracer system, and the mass balance with the evaporation."""

    def __init__(self, thermal: ThermalSteadyState, model, masses, **kw):
        super().__init__(model, masses, **kw)
        self.thermal = thermal
        # the design loads and per-cell coefficients are the coupled state's, at its computed moisture (not
        # the model's, which the base class set): evaluated on first use (the fill check does not ask)
        del self.design_load, self.cell_info

    @cached_property
    def _cells(self) -> tuple:
        return self.thermal._cells_at_state()

    # (mypy reads a cached_property as read-only; it is an attribute, writable as the base class's)
    @cached_property
    def design_load(self) -> np.ndarray:  # type: ignore[override]
        return self._cells[0]

    @cached_property
    def cell_info(self) -> dict:  # type: ignore[override]
        return self._cells[1]

    @property
    def mass_balance_error(self) -> float:
        """|feed - product - evaporation| / feed (-), wet solids."""
        th = self.thermal
        F = th.dryer.feed_rate
        return abs(F - float(th.product_rate) - th.evaporation_rate) / F

    @property
    def mean_residence_time(self) -> float:
        """The solids' mean residence time, s: dry holdup / dry outflow
        ([`ThermalSteadyState.mean_residence_time`][rotarydryer.thermal.states.ThermalSteadyState.mean_residence_time])."""
        return self.thermal.mean_residence_time

    def tracer_system(self):
        return self.thermal.tracer_system()


def outlets(dryer, z) -> dict:
    """Outlet values of state ``z``: product moisture (kg/kg wet) and temperature (degC), exhaust
    temperature (degC) and humidity (kg/kg dry gas), total holdup (kg)."""
    s = dryer.settings
    pS, pW, pH = dryer.product_stream(z)
    S, W, T, Tg, Y = dryer.split(z)
    k = dryer.gas_outlet_stage
    return dict(product_moisture=float(pW / (pS + pW)),
                product_temperature=float(pH / (pS * s.cp_solids + pW * s.cp_water)),
                exhaust_temperature=float(Tg[k]), exhaust_humidity=float(Y[k]),
                holdup=float(np.sum(S + W)))


class DynamicResult:
    """Trajectory of a dynamic simulation: ``time_s``, ``states`` (n x nt) and outlet series
    (``product_moisture_kg_kg``, ``product_temperature_degC``, ``gas_outlet_temperature_degC``; ``time`` and
    ``product_moisture`` are the same arrays under their older names)."""

    product_temperature_c = _Renamed("product_temperature_degC")
    gas_outlet_temperature_c = _Renamed("gas_outlet_temperature_degC")

    @property
    def time_s(self):
        """The output times, s (the array ``time``)."""
        return self.time

    @property
    def product_moisture_kg_kg(self):
        """The product moisture at each output time, kg/kg wet (the array ``product_moisture``)."""
        return self.product_moisture

    def __repr__(self):

        return short_repr("DynamicResult", "", [("t_end s", float(self.time[-1])), ("points", self.time.size),
                                                ("final product moisture kg/kg", float(self.product_moisture[-1])),
                                                ("solve s", self.seconds)])

    def to_dataframe(self):
        """Outlet series versus time (s) as a pandas DataFrame."""
        import pandas as pd

        return pd.DataFrame({"product_moisture_kg_kg": self.product_moisture,
                             "product_temperature_degC": self.product_temperature_degC,
                             "gas_outlet_temperature_degC": self.gas_outlet_temperature_degC},
                            index=pd.Index(self.time, name="time_s"))

    def __init__(self, dryer, t, y, seconds, nfev):
        self.dryer, self.time, self.states, self.seconds, self.nfev = dryer, t, y, seconds, nfev
        o = [outlets(dryer, y[:, j]) for j in range(y.shape[1])]
        self.product_moisture = np.array([v["product_moisture"] for v in o])
        self.product_temperature_degC = np.array([v["product_temperature"] for v in o])
        self.gas_outlet_temperature_degC = np.array([v["exhaust_temperature"] for v in o])
