"""Result objects of the transport models: steady state and tracer RTD.

Units: kg, s, kg/s; residence times are also given in min where the name says so.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .network import Network, TracerInput, TracerResponse, TracerSystem

__all__ = ["TransportModel", "SteadyState", "RTDResult"]


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
        :mod:`rotarydryer.transport.ajayi`).
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

    def steady_state(self) -> "SteadyState":
        """Solve the steady state (see :meth:`Network.steady_state`)."""
        M = self.network.steady_state()
        return SteadyState(self, M)


class SteadyState:
    """Steady-state holdups and flows of a :class:`TransportModel`."""

    def __init__(self, model: TransportModel, masses: np.ndarray):
        self.model = model
        self.masses = masses
        net = model.network
        self.flows = net.family_flows(masses)
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
        des = self.model.design_load[p]
        return np.where(np.isfinite(des), np.maximum(self.masses[p] - np.nan_to_num(des, nan=np.inf), 0.0), 0.0)

    @property
    def kiln_bed_holdup(self) -> float:
        return float(np.sum(self.kiln_bed))

    @property
    def dryer_loading(self) -> np.ndarray:
        """d_load = M_P / M_P,des per passive node (-), Lee (2008) Section 4.4.2."""
        p = self.phase == "passive"
        return self.masses[p] / self.model.design_load[p]

    @property
    def loading_state(self) -> list:
        """'under', 'design' or 'over' per passive node (relative tolerance 1e-9)."""
        d = self.dryer_loading
        return ["over" if x > 1 + 1e-9 else ("design" if x >= 1 - 1e-9 else "under") for x in d]

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

    # -- tracer ------------------------------------------------------------------------
    def tracer_system(self) -> TracerSystem:
        """Linear tracer system at these flows (inlet: the model's, default the feed nodes)."""
        return self.model.network.tracer_system(self.masses, inlet=self.model.tracer_inlet)

    def rtd(self, tracer_input: TracerInput | None = None, t_end: float = 3600.0, dt: float = 10.0,
            method: str = "auto", simulate: bool = True) -> "RTDResult":
        """Tracer RTD at this steady state: analytic moments and (optionally) the simulated curve."""
        inp = tracer_input or self.model.tracer_input or TracerInput.pulse(1.0, 0.0)
        ts = self.tracer_system()
        mom = ts.moments(inp)
        imp = ts.moments()
        resp = ts.simulate(inp, t_end, dt, method) if simulate else None
        return RTDResult(moments=mom, response=resp, tracer_input=inp, impulse_moments=imp)

    def cell_table(self) -> list:
        """One dict per cell of flighted sections: position, masses, design load, state, repose angle."""
        p = np.where(self.phase == "passive")[0]
        a_of = {(s, c): i for i, (s, c, ph) in enumerate(zip(self.section, self.cell, self.phase)) if ph == "active"}
        info = self.model.cell_info
        kiln, loading, state = self.kiln_bed, self.dryer_loading, self.loading_state  # once, not per row
        rows = []
        for j, i in enumerate(p):
            key = (self.section[i], self.cell[i])
            ai = a_of.get(key)
            row = {
                "section": str(self.section[i]),
                "cell": int(self.cell[i]),
                "position_m": float(self.position[i]),
                "passive_kg": float(self.masses[i]),
                "active_kg": float(self.masses[ai]) if ai is not None else 0.0,
                "design_load_kg": float(self.model.design_load[i]),
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

    def to_dict(self) -> dict:
        """JSON-ready summary.  ``mean_residence_time_s``/``rtd_std_s`` describe the RTD
        (impulse response; mean = holdup/flow for a closed dryer); ``tracer_*`` the
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
