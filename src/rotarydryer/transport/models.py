r"""Compartment models of flighted rotary dryers built on the network engine.

* [`lee2008`][rotarydryer.transport.models.lee2008] - Lee (2008) Ch. 3 slice model as coded in Appendix I: per cell a
  passive and an active phase; flight discharge capped at the design load
  (Eq. 3.2), active outflow split into forward / return / backmix (Eq. 3.7-3.8),
  kilning of the excess over the design load (Eq. 3.9).  Per-cell coefficients
  come from an injected *cell geometry model* (exact geometry
  ``rotarydryer.geometry.FlightedDrum`` or the surrogates
  [`rotarydryer.geometry.lee2008_regressions.Lee2008Regressions`][rotarydryer.geometry.lee2008_regressions.Lee2008Regressions]).
* [`sheehan2005_model2`][rotarydryer.transport.models.sheehan2005_model2] - Sheehan et al. (2005) "Model 2" (pseudo-physical):
  the same slice structure with backmix into the *previous active* phase.
* [`sheehan2005_model1`][rotarydryer.transport.models.sheehan2005_model1] - Sheehan et al. (2005) "Model 1" (empirical; Lee et
  al.): global transport coefficients, axial transport through the passive phase.

Conventions: SI units (kg, m, s); angles in degrees at the interface.  Errors
name the case-file key of the offending input (e.g. ``transport.n_cells``).
"""

from __future__ import annotations

import math

import numpy as np

from .._limits import check_key
from .._validation import check_choice, check_range, fmt_number
from .network import EdgeFamily, Network, TracerInput
from .results import TransportModel

__all__ = [
    "lee2008",
    "lee2008_repose_profile",
    "sheehan2005_model1",
    "sheehan2005_model2",
    "NetworkBuilder",
]

GAS_FLOWS = ("counter-current", "co-current")


def lee2008_repose_profile(n_cells, moisture_inlet, moisture_outlet):
    r"""Dynamic angle of repose per cell (deg) for the Invicta sugar, Lee (2008) Eq. 7.2-7.3.

    w_i = w_in exp[((i-1)/(N-1)) ln(w_out/w_in)] (Eq. 7.3, exponential moisture
    profile, kg/kg dry) and phi_i = 1222.2 w_i + 34.5 (Eq. 7.2, Britton et al.).
    Lee's code values are 0.02 -> 0.002 kg/kg (Appendix I l.12456, i.e. 58.94 -> 36.94 deg; the
    Invicta case file); the thesis text says "0.2 wt% to 0.02 wt%", a factor 10 lower - the code
    values are the ones that reproduce Ch. 7.
    """
    from ..properties.solids import SOLIDS, lee2008_moisture_profile

    n = int(check_range("transport.n_cells", n_cells, 1, math.inf, low_inclusive=True))
    wi = float(check_range("solids.moisture_inlet", moisture_inlet, 0.0, 1.0, unit="kg/kg"))
    wo = float(check_range("solids.moisture_outlet", moisture_outlet, 0.0, 1.0, unit="kg/kg"))
    slope, intercept = SOLIDS["raw_sugar_lee2008"]["repose"]  # Eq. 7.2, unchecked: the case checks its inputs
    return slope * lee2008_moisture_profile(n, wi, wo) + intercept


def _repeat(value, k):
    """``value`` (a number or k values) as a list of k values."""
    a = np.asarray(value, dtype=float)
    return [float(a)] * k if a.ndim == 0 else list(np.broadcast_to(a, (k,)))


class NetworkBuilder:
    """Accumulates nodes (with section/phase/cell/position labels) and edge families."""

    def __init__(self):
        self.n = 0
        self.families = []
        self.labels = {"section": [], "phase": [], "cell": [], "position": []}
        self.design_load = []
        self.feed = []
        self.guess = []

    def add_nodes(self, section, phase, cells, positions, design_load=None, guess=None):
        cells = np.atleast_1d(cells)
        k = cells.size
        idx = np.arange(self.n, self.n + k)
        self.n += k
        self.labels["section"] += [section] * k
        self.labels["phase"] += [phase] * k
        self.labels["cell"] += list(cells)
        self.labels["position"] += _repeat(positions, k)
        self.design_load += _repeat(np.nan if design_load is None else design_load, k)
        self.feed += [0.0] * k
        self.guess += _repeat(0.0 if guess is None else guess, k)
        return idx

    def add_cell_pairs(self, section, phases, positions):
        """Nodes of ``len(positions)`` cells with two phases each, interleaved (cell 0 phase 0, cell 0
        phase 1, cell 1 phase 0, ...: a banded matrix): the index arrays of each phase. The same nodes
        and labels as `add_nodes` called per cell and phase, in one step."""
        pos = np.asarray(positions, dtype=float).ravel()
        k = pos.size
        first = np.arange(self.n, self.n + 2 * k, 2)
        self.n += 2 * k
        self.labels["section"] += [section] * (2 * k)
        self.labels["phase"] += list(phases) * k
        self.labels["cell"] += np.repeat(np.arange(k), 2).tolist()
        self.labels["position"] += np.repeat(pos, 2).tolist()
        self.design_load += [np.nan] * (2 * k)
        self.feed += [0.0] * (2 * k)
        self.guess += [0.0] * (2 * k)
        return first, first + 1

    def add(self, family: EdgeFamily):
        self.families.append(family)

    def build(self) -> Network:
        return Network(self.n, self.families, np.array(self.feed), labels=self.labels,
                       initial_guess=np.array(self.guess))


def lee2008(*, geometry, n_cells, feed_rate, length, rpm, slope, bulk_density, repose_angle, kiln_time, backmix,
            drag_reduction, passive_time_branch=None, loading="fixed", backmix_to="passive", gas_flow="counter-current",
            tracer_input=None, name="lee2008", section="dryer", forward_step="fitted", gas=None):
    r"""Lee (2008) compartment model of a flighted dryer (one flighted section).

    Per cell i (length dL = L/N) a passive phase P_i (flights + drum floor +
    kilning bed) and an active phase A_i (curtain), both well mixed.  Flows
    (kg/s; Lee (2008) Ch. 3 and Appendix I code):

    * flight discharge P_i -> A_i: M_P/tau_p if M_P <= M_des else M_des/tau_p (Eq. 3.2);
    * kilning P_i -> P_{i+1}: (M_P - M_des)/tau_kiln if M_P > M_des (Eq. 3.9, the
      code's excess form, not the prose's M_P/tau_kiln);
    * active outflow F_a = M_A/tau_a split into forward C_F F_a (A_i -> P_{i+1}),
      return C_R F_a (A_i -> P_i) and backmix C_B F_a (A_i -> P_{i-1};
      A_1 -> P_1 as in the code), with C_F = C_F^G h_m sin(theta)/dL
      (Eq. 3.7-3.8) and C_R = 1 - C_F - C_B;
    * feed into P_1; outlet = forward flow of A_N + kilning of P_N.

    tau_p, tau_a = t_m and h_m come from ``geometry.cascade`` (Eq. 3.3-3.6 exact,
    or Eq. 4.24-4.26 regressions), M_des = rho_b dL A_des(phi) (Eq. 4.20-4.21 /
    Eq. 4.27).

    Parameters
    ----------
    geometry : cell geometry model
        Object with ``cascade``, ``design_load_area`` and ``loading_factor``.
    n_cells : int
        N (-), >= 1.  Lee's nearest-neighbour structure needs C_R >= 0 in every
        cell, i.e. the forward step may not exceed the cell (Invicta: N <= 35 with
        the Table 7.2 parameters); violating it raises ``ValueError`` naming
        ``transport.n_cells`` and the limit.
    feed_rate : float
        Solids feed, kg/s (Invicta 98 t/h = 27.22 kg/s).
    length : float
        Drum length L, m.
    rpm : float
        Drum speed, rev/min.
    slope : float
        Drum slope theta, deg.
    bulk_density : float
        rho_b, kg/m^3 (Lee's code uses 940).
    repose_angle : float or array of n_cells
        Dynamic angle of repose per cell, deg (Lee's Invicta profile: [`lee2008_repose_profile`][rotarydryer.transport.models.lee2008_repose_profile],
        Eq. 7.2-7.3). Every plant quantity is an argument: the Invicta values are case data
        (``rotarydryer.cases.load_case("lee2008_invicta")``).
    kiln_time : float
        tau_kiln, s (> 0; ``math.inf`` disables kilning, then an overloaded dryer
        has no steady state).
    backmix : float
        C_B (-), 0-1; must be 0 for co-current gas.
    drag_reduction : float
        C_F^G (-), >= 0 (< 1 counter-current; may exceed 1 co-current).
    passive_time_branch : str, optional
        Passed to ``geometry.cascade`` ("eq3.4" or "lee2008_ch7"); default: the
        geometry model's default.
    loading : {"fixed", "state"}
        "fixed": f_load = 1 in every cell, as in Lee's gPROMS runs (the clipping
        broke his estimation); "state": f_load from the cell's d_load =
        M_P/M_des via ``geometry.loading_factor`` (Eq. 4.22/4.28) at every
        iteration.
    backmix_to : {"passive", "active"}
        Destination of backmixed solids: previous passive phase (Lee 2008) or
        previous active phase (Sheehan et al. 2005 Model 2; Britton et al. 2006).
    gas_flow : {"counter-current", "co-current"}
    tracer_input : TracerInput, optional
        Default injection for [`SteadyState.rtd`][rotarydryer.transport.results.SteadyState.rtd] (default a 60 s pulse of 1e-4 of the feed,
        as [`build_sections`][rotarydryer.transport.sections.build_sections]).
    forward_step : {"fitted", "trajectory"}
        "fitted": C_F = C_F^G h_m sin(theta)/dL with the fitted ``drag_reduction`` (Lee (2008)
        Eq. 3.7-3.8); "trajectory": C_F = d/dL with d the mean axial advance of a particle
        falling h_m through the gas ``gas`` ([`rotarydryer.transport.forward_step`][rotarydryer.transport.forward_step];
        ``drag_reduction`` unused, a negative d goes to the backmix edge).
    gas : CurtainGas, optional
        Gas stream and particles; required by ``forward_step = "trajectory"``, its direction
        must be ``gas_flow``.
    """
    from .sections import TRAJECTORY_INFO, SectionSpec, build_sections

    check_choice("transport.loading", loading, ("fixed", "state"))
    check_choice("transport.backmix_to", backmix_to, ("passive", "active"))
    check_choice("operating.gas_flow", gas_flow, GAS_FLOWS)
    N = int(check_key("transport.n_cells", n_cells))
    if N != n_cells:
        raise ValueError(f"transport.n_cells = {fmt_number(n_cells)} must be an integer >= 1")
    F = float(check_range("operating.feed_rate", feed_rate, 0.0, math.inf, unit="kg/s"))
    L = float(check_range("drum.length", length, 0.0, math.inf, unit="m"))
    rpm = float(check_range("operating.rpm", rpm, 0.0, math.inf, unit="rev/min"))
    theta = float(check_key("drum.slope", slope))
    rho = float(check_range("solids.bulk_density", bulk_density, 0.0, math.inf, unit="kg/m^3"))
    check_key("transport.kiln_time", kiln_time)
    CB = float(check_key("transport.backmix", backmix))
    CFG = float(check_key("transport.drag_reduction", drag_reduction))
    if gas_flow == "co-current" and CB > 0:
        raise ValueError(
            f"transport.backmix = {fmt_number(CB)} must be 0 for co-current gas flow (Lee (2008) l.2766: "
            "no backmixing, drag lengthens the forward step)"
        )
    check_choice("transport.forward_step", forward_step, ("fitted", "trajectory"))
    if forward_step == "trajectory":
        from .forward_step import CurtainGas

        if not isinstance(gas, CurtainGas):
            raise ValueError("transport.forward_step = 'trajectory' needs the gas stream and the particles "
                             "(give [gas] flow and inlet_temperature, and a [material])")
        if gas.gas_flow != gas_flow:
            raise ValueError(f"gas direction {gas.gas_flow!r} differs from operating.gas_flow = {gas_flow!r}")
    phi = np.broadcast_to(check_range("solids.repose_angle", repose_angle, 0.0, 90.0, unit="deg"), (N,)).copy()
    spec = SectionSpec(name=section, kind="flighted", length=L, n_cells=N, geometry=geometry, kilning="excess",
                       kiln_time=float(kiln_time), drag_reduction=CFG, backmix=CB, backmix_to=backmix_to,
                       loading=loading, passive_time_branch=passive_time_branch, repose_angle=phi,
                       bulk_density=rho, forward_step=forward_step, gas=gas if forward_step == "trajectory" else None)
    params = dict(n_cells=N, feed_rate=F, length=L, rpm=rpm, slope=theta, bulk_density=rho,
                  kiln_time=kiln_time, backmix=CB, drag_reduction=CFG, loading=loading,
                  backmix_to=backmix_to, gas_flow=gas_flow,
                  passive_time_branch=passive_time_branch, geometry=repr(geometry))
    if forward_step == "trajectory":
        params.update(forward_step=forward_step, gas_velocity_m_s=gas.gas_velocity,
                      curtain_velocity_ratio=gas.velocity_ratio)
    model = build_sections([spec], material=None, feed_rate=F, rpm=rpm, slope=theta, tracer_input=tracer_input,
                           name=name, parameters=params)
    ci = model.cell_info
    keys = ("repose_angle_deg", "passive_time_s", "fall_time_s", "fall_height_m", "C_F", "C_R")
    model.cell_info = {k: ci[k] for k in keys + tuple(k for k in TRAJECTORY_INFO if k in ci)}
    return model


def sheehan2005_model2(*, geometry, **kwargs):
    r"""Sheehan, Britton & Schneider (2005) "Model 2" (pseudo-physical), as recovered.

    Recovered (notes lee_models.md Section 4.3): twin tanks per slice with local,
    moisture-dependent coefficients from flight geometry; forward step
    A_i -> P_{i+1} with C_F = C_F^0 C_F^G (Lee Eq. 3.7-3.8, attributed to
    Sheehan); return A_i -> P_i; **backmix A_i -> A_{i-1}** (previous *active*
    tank); flight discharge capped at the design load; kilning proportional to
    the excess over the design load.  Two fitted parameters, most likely C_F^G
    and C_B.

    Not recoverable from the stripped paper, and chosen here: the kilning
    relation ("based on the rotational velocity of the drum and the size of the
    bed") - a constant kilning time ``kiln_time`` (s) on the excess, as in Lee
    (2008) Eq. 3.9; the first cell's backmix - returned to its own passive phase;
    the residence-time sub-model - the injected ``geometry`` (as Lee).  Keyword
    arguments are those of [`lee2008`][rotarydryer.transport.models.lee2008].
    """
    kwargs.setdefault("name", "sheehan2005_model2")
    return lee2008(geometry=geometry, backmix_to="active", **kwargs)


def sheehan2005_model1(*, n_cells, feed_rate, length, passive_rate, exchange_rate,
                       return_rate, kiln_rate, design_load, air_coefficient=0.0, gas_mass_flow=0.0,
                       gas_flow="counter-current", tracer_input=None, section="dryer"):
    r"""Sheehan et al. (2005) "Model 1" (empirical; Lee et al.), as recovered.

    Twin tanks in series with *global* transport coefficients (1/s); every flow is
    a coefficient times the source-tank mass (notes lee_models.md Section 4.2):

    * passive -> next passive: k_PP M_P, with k_PP = k_PP,0 -/+ k_air G
      (``passive_rate`` -/+ ``air_coefficient`` * ``gas_mass_flow``; minus for
      counter-current).  The paper only says an "air flowrate constant" was added
      so that the MRT follows Friedman and Marshall; the linear form and its sign
      convention are **our reading** (not recoverable);
    * passive -> active: k_PA min(M_P, M_des) (fixed at its kilning-point value);
    * active -> passive (same cell): k_AP M_A;
    * kilning passive -> next passive: k_K max(M_P - M_des, 0).

    Parameters
    ----------
    passive_rate, exchange_rate, return_rate, kiln_rate : float
        k_PP,0, k_PA, k_AP, k_K in 1/s (>= 0).  Lee (l.3371) quotes the fitted
        k_AP = 25.4 1/h (every 142 s).
    design_load : float
        Passive design holdup of the whole dryer, kg (split evenly over cells).
    air_coefficient : float
        k_air, 1/kg (1/s per kg/s of gas); gas_mass_flow: G, kg/s.
    """
    check_choice("operating.gas_flow", gas_flow, GAS_FLOWS)
    N = int(check_key("transport.n_cells", n_cells))
    F = float(check_range("operating.feed_rate", feed_rate, 0.0, math.inf, unit="kg/s"))
    L = float(check_range("drum.length", length, 0.0, math.inf, unit="m"))
    kpp0 = float(check_key("transport.passive_rate", passive_rate))
    kpa = float(check_key("transport.exchange_rate", exchange_rate))
    kap = float(check_key("transport.return_rate", return_rate))
    kk = float(check_key("transport.kiln_rate", kiln_rate))
    mdes = float(check_range("transport.design_load", design_load, 0.0, math.inf, unit="kg"))
    kair = float(check_range("transport.air_coefficient", air_coefficient, 0.0, math.inf, low_inclusive=True))
    G = float(check_range("operating.gas_mass_flow", gas_mass_flow, 0.0, math.inf, low_inclusive=True, unit="kg/s"))
    kpp = kpp0 - kair * G if gas_flow == "counter-current" else kpp0 + kair * G
    if kpp < 0:
        raise ValueError(
            f"transport.air_coefficient * operating.gas_mass_flow = {kair * G:.4g} 1/s exceeds "
            f"transport.passive_rate = {kpp0:.4g} 1/s (negative passive transport)"
        )
    des = np.full(N, mdes / N)
    dL = L / N
    pos = (np.arange(N) + 0.5) * dL
    b = NetworkBuilder()
    P = np.empty(N, dtype=np.int64)
    A = np.empty(N, dtype=np.int64)
    for i in range(N):
        P[i] = b.add_nodes(section, "passive", i, pos[i], design_load=des[i], guess=des[i])[0]
        A[i] = b.add_nodes(section, "active", i, pos[i], guess=des[i] * kpa / kap)[0]
    b.feed[P[0]] = F
    nxtP = np.r_[P[1:], -1]
    if kpp > 0:
        b.add(EdgeFamily("passive_forward", P, nxtP, "linear", rate=np.full(N, kpp), section=section))
    b.add(EdgeFamily("discharge", P, A, "capped", rate=np.full(N, kpa), cap=des, section=section))
    b.add(EdgeFamily("return", A, P, "linear", rate=np.full(N, kap), section=section))
    if kk > 0:
        b.add(EdgeFamily("kiln", P, nxtP, "excess", rate=np.full(N, kk), cap=des, section=section))
    net = b.build()
    params = dict(n_cells=N, feed_rate=F, passive_rate=kpp0, exchange_rate=kpa, return_rate=kap,
                  kiln_rate=kk, design_load=mdes, air_coefficient=kair, gas_mass_flow=G, gas_flow=gas_flow)
    return TransportModel(name="sheehan2005_model1", network=net,
                          sections=[dict(name=section, kind="flighted", length=L, n_cells=N)],
                          feed_rate=F, design_load=np.array(b.design_load), cell_info={},
                          tracer_input=tracer_input or TracerInput.pulse(1.0, 0.0), parameters=params)
