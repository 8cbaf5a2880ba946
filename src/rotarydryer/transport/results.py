"""Result objects of the transport models: steady state and tracer RTD.

Units: kg, s, kg/s; residence times are also given in min where the name says so.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._validation import fmt_number
from .network import Network, TracerInput, TracerResponse, TracerSystem

__all__ = ["TransportModel", "SteadyState", "RTDResult", "RTDWindowWarning", "RECOVERY_TOLERANCE"]

#: a simulated tracer curve that recovers less than (analytic recovery - this) is truncated
RECOVERY_TOLERANCE = 1e-6


class RTDWindowWarning(UserWarning):
    """The simulated tracer curve does not represent the RTD: its time window (``t_end``, a case's
    ``tracer.t_end``) ends before the tracer has left the dryer, or its step (``dt``,
    ``tracer.dt``) is too coarse, so its recovery or mean is off the analytic one."""


@dataclass
class TransportModel:
    """A built transport model: the sparse network plus what is needed to report it.

    Attributes
    ----------
    name : str
        Model name (``"lee2008"``, ``"sheehan2005_model1"`` ...).
    network : Network
    sections : list of dict
        One dict per section: name, kind ("flighted"/"unflighted"), length (m), n_cells.
    feed_rate : float
        Solids feed, kg/s.
    design_load : (n_nodes,) kg
        Design load of passive nodes (NaN elsewhere).
    cell_info : dict of per-passive-node arrays (repose angle, cycle times, coefficients)
    tracer_input : TracerInput, optional
        Default tracer injection of the case.
    parameters : dict
        The model inputs, for the record.
    tracer_inlet : (n_nodes,) array, optional
        Where injected tracer enters (default: feed nodes in proportion to feed; an
        open Dirichlet inlet admits more than the nominal amount, see
        [`rotarydryer.transport.ajayi`][rotarydryer.transport.ajayi]).
    """

    name: str
    network: Network
    sections: list
    feed_rate: float
    design_load: np.ndarray
    cell_info: dict = field(default_factory=dict)
    tracer_input: TracerInput | None = None
    parameters: dict = field(default_factory=dict)
    tracer_inlet: np.ndarray | None = None
    #: feasibility checks ``check(steady_state)`` run on every steady state (raise ``ValueError``);
    #: :func:`rotarydryer.cases.build.build_model` adds the fill-fraction check of the case
    checks: list = field(default_factory=list)
    #: what :func:`rotarydryer.transport.sections.build_sections` attaches: the length of each node's
    #: cell (m), the section specs and the material (None / empty for models built otherwise)
    cell_length: np.ndarray | None = None
    specs: list = field(default_factory=list)
    material: Any = None

    def steady_state(self) -> SteadyState:
        """Solve the steady state (see [`Network.steady_state`][rotarydryer.transport.network.Network.steady_state]) and run `checks`."""
        M = self.network.steady_state()
        ss = SteadyState(self, M)
        for check in self.checks:
            check(ss)
        return ss

    def node_bulk_density(self, bed_density=None) -> np.ndarray:
        """Bulk density (kg/m^3) of every node: the cell's (the section law at the assumed
        moisture, or the fixed value) for flighted sections; ``bed_density`` (kg/m^3) for the
        nodes of unflighted sections, default the nearest flighted cell's."""
        net = self.network
        lab = net.labels
        sec, cell = np.asarray(lab["section"]), np.asarray(lab["cell"])
        pos = np.asarray(lab["position"], dtype=float)
        rho = np.full(net.n, np.nan)
        seen = set()
        for f in net.families:
            law = getattr(f, "law", None)
            if law is None or id(law) in seen:
                continue
            seen.add(id(law))
            _, r = law.properties(law.assumed_moisture)
            for P, rr in zip(law.P, np.asarray(r, dtype=float)):
                rho[(sec == sec[P]) & (cell == cell[P])] = rr
        bed = np.isnan(rho)
        if bed.any():
            if bed_density is not None:
                rho[bed] = float(bed_density)
            elif (~bed).any():
                known = np.where(~bed)[0]
                near = known[np.argmin(np.abs(pos[bed][:, None] - pos[known][None, :]), axis=1)]
                rho[bed] = rho[near]
        return rho


class SteadyState:
    """Steady-state holdups and flows of a [`TransportModel`][rotarydryer.transport.results.TransportModel]."""

    def __init__(self, model: TransportModel, masses: np.ndarray, *, flows=None, design_load=None, cell_info=None):
        self.model = model
        self.masses = masses
        net = model.network
        #: edge flows per family (kg/s); a coupled state (heat and mass) passes its own
        self.flows = net.family_flows(masses) if flows is None else flows
        #: design load per node (kg, NaN off the passive nodes) and per-cell coefficients of this state:
        #: the model's (assumed moisture) unless a coupled state passes those at its computed moisture
        self.design_load = np.asarray(model.design_load if design_load is None else design_load, dtype=float)
        self.cell_info = model.cell_info if cell_info is None else cell_info
        lab = net.labels
        self.phase = np.asarray(lab["phase"])
        self.section = np.asarray(lab["section"])
        self.cell = np.asarray(lab["cell"])
        self.position = np.asarray(lab["position"], dtype=float)

    # -- holdups -----------------------------------------------------------------------
    def _sum(self, mask):
        return float(np.sum(self.masses[mask]))

    @property
    def total_holdup(self) -> float:
        """Total solids holdup, kg."""
        return float(np.sum(self.masses))

    @property
    def active_holdup(self) -> float:
        """Airborne (curtain) solids, kg."""
        return self._sum(self.phase == "active")

    @property
    def passive_holdup(self) -> float:
        """Flight- and drum-borne solids in flighted sections incl. the kilning bed, kg."""
        return self._sum(self.phase == "passive")

    @property
    def bed_holdup(self) -> float:
        """Solids in unflighted sections (rolling bed), kg."""
        return self._sum(self.phase == "bed")

    @property
    def kiln_bed(self) -> np.ndarray:
        """Per passive node: mass above the design load (kilning bed), kg."""
        p = self.phase == "passive"
        des = self.design_load[p]
        return np.where(np.isfinite(des), np.maximum(self.masses[p] - np.nan_to_num(des, nan=np.inf), 0.0), 0.0)

    @property
    def kiln_bed_holdup(self) -> float:
        return float(np.sum(self.kiln_bed))

    @property
    def dryer_loading(self) -> np.ndarray:
        """d_load = M_P / M_P,des per passive node (-), Lee (2008) Section 4.4.2."""
        p = self.phase == "passive"
        return self.masses[p] / self.design_load[p]

    @property
    def loading_state(self) -> list:
        """'under', 'design' or 'over' per passive node (relative tolerance 1e-9)."""
        d = self.dryer_loading
        return ["over" if x > 1 + 1e-9 else ("design" if x >= 1 - 1e-9 else "under") for x in d]

    def loading_counts(self) -> dict:
        """Flighted cells over, at and under their design load: ``cells_over``, ``cells_design``,
        ``cells_under`` (floats, as the Results scalars hold them)."""
        states = self.loading_state
        return {f"cells_{k}": float(states.count(k)) for k in ("over", "design", "under")}

    def section_holdups(self) -> dict:
        """{section: {"active": kg, "passive": kg, "bed": kg, "total": kg}}."""
        out = {}
        for s in self.model.sections:
            m = self.section == s["name"]
            out[s["name"]] = {
                "active_kg": self._sum(m & (self.phase == "active")),
                "passive_kg": self._sum(m & (self.phase == "passive")),
                "bed_kg": self._sum(m & (self.phase == "bed")),
                "total_kg": self._sum(m),
            }
        return out

    # -- flows -------------------------------------------------------------------------
    def flow(self, name: str, section: str | None = None) -> np.ndarray:
        """Concatenated flows (kg/s) of all edge families called ``name`` (optionally one section)."""
        parts = [F for f, F in zip(self.model.network.families, self.flows)
                 if f.name == name and (section is None or f.section == section)]
        return np.concatenate(parts) if parts else np.zeros(0)

    @property
    def outlet_flow(self) -> float:
        """Solids leaving through the outlet, kg/s."""
        return self.model.network.boundary_flow(self.masses, -1, self.flows)

    @property
    def mass_balance_error(self) -> float:
        """|feed - outlet - boundary losses| / feed (-)."""
        net = self.model.network
        f = float(net.feed.sum())
        return abs(f - self.outlet_flow - net.boundary_flow(self.masses, -2, self.flows)) / f

    @property
    def mean_residence_time(self) -> float:
        """Holdup / throughput, s (Lee (2008) Eq. 2.2)."""
        return self.total_holdup / self.outlet_flow

    # -- volume ------------------------------------------------------------------------
    def solids_volume(self, bed_density=None) -> np.ndarray:
        """Bulk volume of the solids of every node, m^3 (mass / bulk density,
        [`TransportModel.node_bulk_density`][rotarydryer.transport.results.TransportModel.node_bulk_density])."""
        return self.masses / self.model.node_bulk_density(bed_density)

    def fill_fractions(self, radius: float, bed_density=None) -> dict:
        """Fraction of the drum volume (pi R^2 L, ``radius`` R in m) the solids fill: ``"total"``
        (whole drum) and ``"sections"`` ({name: fraction}); with the volumes (m^3), holdups (kg)
        and lengths (m) behind them (``"detail"``: name -> dict)."""
        V = self.solids_volume(bed_density)
        area = math.pi * float(radius) ** 2
        out, detail = {}, {}
        Ltot = Vtot = 0.0
        for s in self.model.sections:
            m = self.section == s["name"]
            L = float(s["length"])
            v = float(np.sum(V[m]))
            out[s["name"]] = v / (area * L)
            detail[s["name"]] = dict(volume_m3=v, drum_volume_m3=area * L, holdup_kg=self._sum(m), length_m=L)
            Ltot += L
            Vtot += v
        detail["total"] = dict(volume_m3=Vtot, drum_volume_m3=area * Ltot, holdup_kg=self.total_holdup,
                               length_m=Ltot)
        return {"total": Vtot / (area * Ltot), "sections": out, "detail": detail}

    # -- tracer ------------------------------------------------------------------------
    def tracer_system(self) -> TracerSystem:
        """Linear tracer system at these flows (inlet: the model's, default the feed nodes)."""
        return self.model.network.tracer_system(self.masses, inlet=self.model.tracer_inlet)

    def rtd(self, tracer_input: TracerInput | None = None, t_end: float = 3600.0, dt: float = 10.0,
            method: str = "auto", simulate: bool = True, check_window: bool = True) -> RTDResult:
        """Tracer RTD at this steady state: analytic moments and (optionally) the simulated curve.

        With ``check_window`` an [`RTDWindowWarning`][rotarydryer.transport.results.RTDWindowWarning] says when the simulated curve does not
        represent the RTD (window ``t_end`` too short: recovery below the analytic one by more than
        `RECOVERY_TOLERANCE`; or ``dt`` too coarse: mean off the analytic one); callers that
        want a truncated curve on purpose (fits on the data's time span) pass False."""
        inp = tracer_input or self.model.tracer_input or TracerInput.pulse(1.0, 0.0)
        ts = self.tracer_system()
        mom = ts.moments(inp)
        imp = ts.moments()
        resp = ts.simulate(inp, t_end, dt, method) if simulate else None
        res = RTDResult(moments=mom, response=resp, tracer_input=inp, impulse_moments=imp)
        if resp is not None and check_window:
            res.check_window(stacklevel=3)
        return res

    def cell_table(self) -> list:
        """One dict per cell, in node order along the dryer: every cell of the flighted sections
        (position, passive and active masses, design load, loading state, repose angle and the
        per-cell coefficients) and every finite volume of the unflighted ones (``kind`` =
        "unflighted": its rolling-bed mass, NaN for the flight quantities). ``holdup_kg`` is the
        cell's whole holdup, so the rows add up to [`total_holdup`][rotarydryer.transport.results.SteadyState.total_holdup]."""
        a_of = {(s, c): i for i, (s, c, ph) in enumerate(zip(self.section, self.cell, self.phase)) if ph == "active"}
        info = self.cell_info
        kiln, loading, state = self.kiln_bed, self.dryer_loading, self.loading_state  # once, not per row
        j_of = {int(i): j for j, i in enumerate(np.where(self.phase == "passive")[0])}
        whole: dict = {}     # every node of a cell (passive, active, a stagnant core's layers)
        for sec, c, mass in zip(self.section, self.cell, self.masses):
            whole[(sec, c)] = whole.get((sec, c), 0.0) + float(mass)
        rows = []
        nan = float("nan")
        for i in np.where((self.phase == "passive") | (self.phase == "bed"))[0]:
            key = (self.section[i], self.cell[i])
            j = j_of.get(int(i))
            if j is None:       # a finite volume of an unflighted section
                row = {"section": str(self.section[i]), "cell": int(self.cell[i]), "kind": "unflighted",
                       "position_m": float(self.position[i]), "passive_kg": 0.0, "active_kg": 0.0,
                       "bed_kg": float(self.masses[i]), "holdup_kg": whole[key],
                       "design_load_kg": nan, "kiln_bed_kg": 0.0, "dryer_loading": nan, "state": "unflighted"}
                for k in info:
                    row[k] = nan
                rows.append(row)
                continue
            ai = a_of.get(key)
            active = float(self.masses[ai]) if ai is not None else 0.0
            row = {
                "section": str(self.section[i]),
                "cell": int(self.cell[i]),
                "kind": "flighted",
                "position_m": float(self.position[i]),
                "passive_kg": float(self.masses[i]),
                "active_kg": active,
                "bed_kg": 0.0,
                "holdup_kg": whole[key],
                "design_load_kg": float(self.design_load[i]),
                "kiln_bed_kg": float(kiln[j]),
                "dryer_loading": float(loading[j]),
                "state": state[j],
            }
            for k, v in info.items():
                row[k] = float(np.asarray(v)[j])
            rows.append(row)
        return rows

    def to_dict(self) -> dict:
        """JSON-ready summary."""
        return {
            "model": self.model.name,
            "feed_rate_kg_s": float(self.model.feed_rate),
            "outlet_flow_kg_s": self.outlet_flow,
            "total_holdup_kg": self.total_holdup,
            "active_holdup_kg": self.active_holdup,
            "passive_holdup_kg": self.passive_holdup,
            "bed_holdup_kg": self.bed_holdup,
            "kiln_bed_holdup_kg": self.kiln_bed_holdup,
            "mean_residence_time_s": self.mean_residence_time,
            "mass_balance_error": self.mass_balance_error,
            "sections": self.section_holdups(),
            "cells": self.cell_table(),
        }


@dataclass
class RTDResult:
    """Tracer RTD: analytic moments (s) and the simulated response.

    Attributes
    ----------
    moments : dict
        Analytic moments of the outlet response to ``tracer_input``, times from the
        injection start (recovery, mean, variance, std, skewness).  These are what
        tracer experiments and Lee (2008) Table 7.3 / Ajayi (2011) Table 5.4 report.
    impulse_moments : dict
        Moments of the impulse response: the residence-time distribution itself
        (mean = holdup / throughput for a closed dryer).
    response : TracerResponse or None
    tracer_input : TracerInput
    """

    moments: dict
    response: TracerResponse | None
    tracer_input: TracerInput
    impulse_moments: dict | None = None

    @property
    def mean_residence_time(self) -> float:
        """Mean of the RTD (impulse response), s."""
        return (self.impulse_moments or self.moments)["mean"]

    @property
    def std(self) -> float:
        """Standard deviation of the RTD (impulse response), s."""
        return (self.impulse_moments or self.moments)["std"]

    @property
    def tracer_mean(self) -> float:
        """Mean of the outlet tracer curve from the injection start, s."""
        return self.moments["mean"]

    @property
    def tracer_std(self) -> float:
        """Standard deviation of the outlet tracer curve, s."""
        return self.moments["std"]

    def window_problem(self) -> str | None:
        """Why the simulated curve misrepresents the analytic RTD, or None: its recovery is below
        the analytic one by more than `RECOVERY_TOLERANCE` (the window ``t_end`` ends before
        the tracer has left), or its mean is off the analytic mean by more than 1 % of the SD and
        0.1 % of the mean (the step ``dt`` is too coarse). A recovery lost with a window past the tracer
        mean + 10 SD and a step above a tenth of the SD is the coarse step's."""
        if self.response is None:
            return None
        sm = self.response.moments()
        an_rec, an_mean, an_std = self.moments["recovery"], self.moments["mean"], self.moments["std"]
        t_end = float(self.response.time[-1])
        dt = float(self.response.time[1] - self.response.time[0]) if self.response.time.size > 1 else t_end
        imp = self.impulse_moments or self.moments
        short = not (sm["recovery"] >= an_rec - RECOVERY_TOLERANCE)
        off = abs(sm["mean"] - an_mean) if np.isfinite(sm["mean"]) else math.inf
        mean_off = not (off <= max(1e-2 * an_std, 1e-3 * an_mean))
        if not (short or mean_off):
            return None
        need = an_mean + 10.0 * an_std
        head = (f"the simulated tracer curve (t_end = {fmt_number(t_end)} s, dt = {fmt_number(dt)} s; "
                f"tracer.t_end and tracer.dt in a case) recovers {sm['recovery']:.6g} of the injected tracer "
                f"(analytic {an_rec:.6g}) with mean {sm['mean']:.4g} s (analytic {an_mean:.4g} s)")
        if short and (t_end < need or dt <= max(an_std / 10.0, 1e-3)):   # not a coarse step's lost recovery
            return (f"{head}: the window ends before the tracer has left the dryer (mean residence time "
                    f"{imp['mean']:.4g} s, SD {imp['std']:.3g} s); its moments are not the RTD's. Simulate to "
                    f"t_end >= about {math.ceil(need / 60.0) * 60:.0f} s (tracer mean + 10 SD), or use the analytic "
                    "moments")
        return (f"{head}: the step is too coarse for this RTD (SD {an_std:.3g} s); use dt <= about "
                f"{max(an_std / 10.0, 1e-3):.3g} s (a tenth of the SD), or the analytic moments")

    def check_window(self, stacklevel: int = 2) -> bool:
        """Warn ([`RTDWindowWarning`][rotarydryer.transport.results.RTDWindowWarning]) when [`window_problem`][rotarydryer.transport.results.RTDResult.window_problem] finds one; returns True if
        the curve is fine."""
        msg = self.window_problem()
        if msg is not None:
            warnings.warn(msg, RTDWindowWarning, stacklevel=stacklevel + 1)
            return False
        return True

    def to_dict(self) -> dict:
        """JSON-ready summary.  ``mean_residence_time_s``/``rtd_std_s`` describe the RTD
        (impulse response; its mean is holdup/flow for a closed dryer, to the discretisation of an
        unflighted section's dispersive inlet: MMG test 4 882.5 against 884.0 s); ``tracer_*`` the
        response to the injected pulse, from the injection start (compare with
        published tracer moments)."""
        imp = self.impulse_moments or self.moments
        d = {
            "mean_residence_time_s": imp["mean"],
            "rtd_std_s": imp["std"],
            "rtd_skewness": imp["skewness"],
            "recovery": imp["recovery"],
            "tracer_mean_s": self.moments["mean"],
            "tracer_std_s": self.moments["std"],
            "tracer_skewness": self.moments["skewness"],
            "tracer_mass_kg": self.tracer_input.mass,
        }
        if self.response is not None:
            sm = self.response.moments()
            d.update({
                "simulated_mean_s": sm["mean"],
                "simulated_std_s": sm["std"],
                "simulated_recovery": sm["recovery"],
                "simulation_method": self.response.method,
                "simulation_t_end_s": float(self.response.time[-1]),
            })
        return d
