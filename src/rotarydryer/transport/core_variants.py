r"""Stagnant-core variants of the transport models (mobile-immobile exchange).

Lee's (2008) fitted slice model matches the mean of the Invicta tracer curve but not its
standard deviation; ``docs/rtd_spread.md`` explains why (a slowly decaying tail that a
chain of fast well-mixed cells cannot produce) and the study
`rotarydryer.studies.invicta_rtd_spread` fits the variants below to the data.

This module holds the pure model code:

* [`add_stagnant_core`][rotarydryer.transport.core_variants.add_stagnant_core] / [`lee2008_stagnant_core`][rotarydryer.transport.core_variants.lee2008_stagnant_core]: Lee's model plus a
  *near-stagnant core* of the passive phase in every cell (mobile-immobile exchange),
  either one well-mixed core (``core_model="first_order"``, mean stay t_c) or a
  slab renewed by diffusion from the surface (``"diffusive"``, t_D = d^2/D), both with
  the core mass as a fraction of the mobile passive mass, ``core_fraction`` (beta).
  The DEM remark quoted by Lee (2008) Section 7.1.2 (l.10404-10412, Jones et al.) is the
  physical basis: a kilning bed holds a bulk with negligible axial velocity that
  exchanges with a thin fast surface layer;
* [`stagnant_core_moments`][rotarydryer.transport.core_variants.stagnant_core_moments], [`diffusive_core_equivalent_time`][rotarydryer.transport.core_variants.diffusive_core_equivalent_time]: exact moments
  of a passive tank with a core (compound Poisson sojourns), used in the tests;
* [`slowest_time_constant`][rotarydryer.transport.core_variants.slowest_time_constant] of a built model (tail e-folding time, s).

Units: SI (kg, s, kg/s).
"""

from __future__ import annotations

import math

import numpy as np

from .._limits import check_key
from .._validation import check_choice, check_range, fmt_number
from .models import lee2008
from .network import EdgeFamily, Network
from .results import TransportModel

__all__ = [
    "CORE_MODELS",
    "core_layer_widths",
    "diffusive_core_equivalent_time",
    "add_stagnant_core",
    "lee2008_stagnant_core",
    "stagnant_core_moments",
    "slowest_time_constant",
]


# ----------------------------------------------------------------------------- the variant
CORE_MODELS = ("first_order", "diffusive")


def core_layer_widths(n_layers: int, layer_ratio: float = 1.0) -> np.ndarray:
    """Relative thicknesses (sum 1) of the finite volumes of a diffusive core, from
    the surface down, growing geometrically by ``layer_ratio`` (1-3; 1 = uniform) so
    that the fast exchange near the surface is resolved. The surface layer must be
    at least 1e-4 of the depth.

    Note: when the surface exchange flow 2 beta M_P / (t_D w_0) exceeds the feed by many
    decades, the engine's steady-state tolerance is set by the rounding of those flows (its
    floor, `Network.FLOW_ROUNDING` times the gross flow through a node) rather than by
    1e-13 of the feed; such a core is in equilibrium with its cell anyway (t_D far below the
    residence time)."""
    n = int(check_range("n_layers", n_layers, 1, 200, low_inclusive=True, high_inclusive=True))
    r = float(check_range("layer_ratio", layer_ratio, 1.0, 3.0, low_inclusive=True, high_inclusive=True))
    w = r ** np.arange(n)
    w = w / w.sum()
    if w[0] < 1e-4:
        raise ValueError(
            f"n_layers = {n} with layer_ratio = {r:g} makes the surface layer {w[0]:.3g} of the core depth "
            "(allowed >= 1e-4: the exchange rates would span too many decades); use fewer layers or a smaller ratio"
        )
    return w


def diffusive_core_equivalent_time(core_time, n_layers: int = 10, layer_ratio: float = 1.5):
    r"""First-order-equivalent stay t_eq (s) of a discretised diffusive core: the t_c of
    a first-order core with the same added variance 2 beta t_eq E[T_P].

    t_eq = t_D sum_i r_i B_i^2 over the surface and the layer interfaces, with r_i the
    distance (fraction of the depth) between the centres the interface joins (w_0/2 at
    the surface) and B_i the mass fraction below it; the continuous slab gives
    t_D int_0^1 (1 - z)^2 dz = t_D / 3 (second-order term of its transfer function
    tanh(sqrt(s t_D))/sqrt(s t_D) = 1 - s t_D/3 + ...). Broadcasts over core_time."""
    td = check_range("core_time", core_time, 0.0, math.inf, unit="s")
    w = core_layer_widths(n_layers, layer_ratio)
    below = 1.0 - np.r_[0.0, np.cumsum(w)[:-1]]  # mass fraction below each interface
    dist = np.r_[w[0] / 2, (w[:-1] + w[1:]) / 2]
    return td * float(np.sum(dist * below**2))


def add_stagnant_core(model: TransportModel, core_fraction, core_time, *, core_model: str = "first_order",
                      n_layers: int = 10, layer_ratio: float = 1.5, phase: str = "passive",
                      name: str | None = None) -> TransportModel:
    r"""Add a near-stagnant core to every node of ``phase`` (mobile-immobile exchange).

    For each node P of the given phase a core node C is added with two linear flows

    * P -> C: (beta / t_c) M_P   (``core_in``)
    * C -> P: M_C / t_c          (``core_out``)

    so that at steady state M_C = beta M_P exactly and the other flows of the
    model are unchanged (the core neither feeds the kilning nor the flights
    directly: only mass that has returned to P moves on). A particle in P enters
    the core at rate beta/t_c (1/s) and stays there an exponential time of mean
    t_c; the core adds beta T_P to the mean residence time (T_P = time spent in
    P) and 2 beta t_c E[T_P] to the variance when the visits are rare
    ([`stagnant_core_moments`][rotarydryer.transport.core_variants.stagnant_core_moments]). This is the classical mobile-immobile
    ("dead-zone") model of chromatography and of Villermaux's RTD analysis, applied to
    the kilning bed of a flighted drum as suggested by the DEM picture that Lee
    (2008) quotes (Section 7.1.2, l.10404: "the bulk of the material exists in a
    passive phase with negligible axial velocity, whilst most of the axial
    transport occurs in a thin active layer on the surface").

    ``core_model = "diffusive"`` replaces the well-mixed core by a slab of depth d
    into which material is mixed by (shear-induced) diffusion from the surface: the
    exchange is fast near the surface and slow at depth, so one pair (beta,
    t_D = d^2/D_core) gives a *spectrum* of exchange times instead of one. The slab
    is discretised in ``n_layers`` finite volumes of relative thickness w_k
    ([`core_layer_widths`][rotarydryer.transport.core_variants.core_layer_widths], growing by ``layer_ratio`` from the surface; masses
    beta M_P w_k); the surface exchange (half a layer) carries
    Q_0 = 2 beta M_P / (t_D w_0) each way and the interface between layers k, k+1
    Q_k = 2 beta M_P / (t_D (w_k + w_{k+1})) (kg/s), no flux at the bottom. The
    mean added time is again beta T_P; the variance equals that of a first-order core
    with t_c = t_D / 3 (slab with one open face), but the tail is heavier. This
    is the diffusive dead-zone model (Coats & Smith's capacitance model is the
    first-order limit); the physical basis is that the near-stagnant bulk of a
    rolling bed is only renewed from the sheared surface layer above it.

    Parameters
    ----------
    model : TransportModel
        A built model (e.g. [`rotarydryer.transport.lee2008`][rotarydryer.transport.lee2008]).
    core_fraction : float
        beta = M_C / M_P (-), in [0, 10]. 0 returns the model unchanged (same
        network object).
    core_time : float
        s, in (0, 1e6]: t_c, mean duration of one stay in the core ("first_order"),
        or t_D = d^2 / D_core, the diffusion time across the core ("diffusive").
    core_model : {"first_order", "diffusive"}
    n_layers, layer_ratio : int, float
        Finite volumes of the diffusive core (1-200) and their thickness ratio
        (1-3); default 10 layers growing by 1.5 (surface layer 0.9 % of the depth;
        the Invicta E(t) changes by < 1 % of its peak against 40 uniform layers, see
        tests); ignored for "first_order".
    phase : str
        Phase label of the nodes that get a core (default "passive").
    name : str, optional
        Name of the new model (default ``model.name + "+core"``).
    """
    beta = float(check_key("transport.core_fraction", core_fraction, "core_fraction"))
    tc = float(check_key("transport.core_time", core_time, "core_time"))
    net = model.network
    ph = np.asarray(net.labels.get("phase", []))
    P = np.where(ph == phase)[0]
    if P.size == 0:
        raise ValueError(f"phase = {phase!r} matches no node of model {model.name!r}")
    if beta == 0.0:
        return model
    if beta / tc == 0.0:  # the exchange rate underflows: the core would never be entered or left
        raise ValueError(f"core_fraction = {fmt_number(beta)} is too small for core_time = {fmt_number(tc)} s: "
                         "the exchange rate "
                         "core_fraction/core_time underflows to 0; use 0 (no core) or a normal number")
    check_choice("core_model", core_model, CORE_MODELS)
    nl = 1
    if core_model == "diffusive":
        nl = int(check_range("n_layers", n_layers, 1, 200, low_inclusive=True, high_inclusive=True))
        if nl != n_layers:
            raise ValueError(f"n_layers = {fmt_number(n_layers)} must be an integer in [1, 200]")
        check_range("layer_ratio", layer_ratio, 1.0, 3.0, low_inclusive=True, high_inclusive=True)
    n0 = net.n
    m = P.size
    # layer k of the core of node P[j] is node n0 + k*m + j
    C = n0 + np.arange(nl * m).reshape(nl, m)
    labels = {k: list(v) + ([v[i] for i in P] * nl if k != "phase" else ["core"] * (nl * m))
              for k, v in net.labels.items()}
    wl = core_layer_widths(nl, layer_ratio) if core_model == "diffusive" else np.ones(1)
    guess = None
    if net.initial_guess is not None:
        g = np.asarray(net.initial_guess, dtype=float)
        guess = np.r_[g, (beta * wl[:, None] * g[P][None, :]).ravel()]
    if core_model == "first_order":
        fams = [EdgeFamily("core_in", P, C[0], "linear", rate=np.full(m, beta / tc), section="core"),
                EdgeFamily("core_out", C[0], P, "linear", rate=np.full(m, 1.0 / tc), section="core")]
    else:
        w = core_layer_widths(nl, layer_ratio)
        fams = [EdgeFamily("core_in", P, C[0], "linear", rate=np.full(m, 2.0 * beta / (tc * w[0])), section="core"),
                EdgeFamily("core_out", C[0], P, "linear", rate=np.full(m, 2.0 / (tc * w[0] ** 2)), section="core")]
        if nl > 1:
            g = 2.0 / (tc * (w[:-1] + w[1:]))  # interface conductance / (beta M_P), 1/s
            up, down = C[:-1].ravel(), C[1:].ravel()
            fams += [EdgeFamily("core_down", up, down, "linear", rate=np.repeat(g / w[:-1], m), section="core"),
                     EdgeFamily("core_up", down, up, "linear", rate=np.repeat(g / w[1:], m), section="core")]
    fams = list(net.families) + fams
    feed = np.r_[net.feed, np.zeros(nl * m)]
    new = Network(n0 + nl * m, fams, feed, labels=labels, initial_guess=guess)
    inlet = None if model.tracer_inlet is None else np.r_[model.tracer_inlet, np.zeros(nl * m)]
    info = dict(model.cell_info)
    params = dict(model.parameters, core_fraction=beta, core_time=tc, core_model=core_model,
                  n_layers=nl, layer_ratio=float(layer_ratio), core_phase=phase)
    out = TransportModel(name=name or f"{model.name}+core", network=new, sections=model.sections,
                         feed_rate=model.feed_rate, design_load=np.r_[model.design_load, np.full(nl * m, np.nan)],
                         cell_info=info, tracer_input=model.tracer_input, parameters=params, tracer_inlet=inlet,
                         checks=list(model.checks))
    # what the section builder attaches (rotarydryer.transport.sections.build_sections): the core nodes
    # lie in their cell (its axial extent); the section specs and material are the mobile model's
    for attr in ("specs", "material"):
        if hasattr(model, attr):
            setattr(out, attr, getattr(model, attr))
    if model.cell_length is not None:
        cl = np.asarray(model.cell_length, dtype=np.float64)
        out.cell_length = np.r_[cl, np.tile(cl[P], nl)]
    return out


def lee2008_stagnant_core(*, geometry, core_fraction, core_time, **lee_kwargs) -> TransportModel:
    r"""Lee (2008) slice model ([`rotarydryer.transport.lee2008`][rotarydryer.transport.lee2008]) with a near-stagnant
    core in the passive phase of every cell ([`add_stagnant_core`][rotarydryer.transport.core_variants.add_stagnant_core]).

    ``core_fraction`` beta (-) = core mass / mobile passive mass of the cell (flights
    + moving kilning bed), ``core_time`` t_c or t_D (s); ``core_model``, ``n_layers``,
    ``layer_ratio`` as [`add_stagnant_core`][rotarydryer.transport.core_variants.add_stagnant_core]; other keywords as ``lee2008``
    (kiln_time, backmix, drag_reduction, n_cells, ...)."""

    name = lee_kwargs.pop("name", "lee2008_stagnant_core")
    core_kw = {k: lee_kwargs.pop(k) for k in ("core_model", "n_layers", "layer_ratio") if k in lee_kwargs}
    return add_stagnant_core(lee2008(geometry=geometry, **lee_kwargs), core_fraction, core_time, name=name,
                             **core_kw)


def stagnant_core_moments(mobile_mean, mobile_variance, core_fraction, core_time):
    r"""Mean (s) and variance (s^2) of the residence time with a stagnant core, for a
    mobile residence time spent entirely in the exchanging phase.

    With T the mobile time (mean m, variance v), visits to the core form a Poisson
    process of rate beta/t_c during T, each lasting Exp(t_c) (compound Poisson):

        mean = (1 + beta) m,    variance = (1 + beta)^2 v + 2 beta t_c m.

    The first term is the stretching of the mobile time, the second the spread of
    the core sojourns. For a network where only part of the time is spent in the
    exchanging phase (Lee's active phase has no core) these are bounds/estimates,
    with m replaced by the mean time spent in that phase (holdup / flow).
    All arguments broadcast (NumPy); mobile_mean, core_time > 0; mobile_variance,
    core_fraction >= 0.
    """
    m = check_range("mobile_mean", mobile_mean, 0.0, math.inf, unit="s")
    v = check_range("mobile_variance", mobile_variance, 0.0, math.inf, low_inclusive=True, unit="s^2")
    b = check_range("core_fraction", core_fraction, 0.0, math.inf, low_inclusive=True)
    tc = check_range("core_time", core_time, 0.0, math.inf, unit="s")
    return (1.0 + b) * m, (1.0 + b) ** 2 * v + 2.0 * b * tc * m


def slowest_time_constant(steady_state) -> float:
    """-1/Re(lambda_max) of the tracer matrix at a steady state, s: the e-folding time of
    the far tail of the model RTD (dense eigenvalues; networks up to 2000 nodes)."""
    ts = steady_state.tracer_system()
    if ts.n > 2000:
        raise ValueError(f"network has {ts.n} nodes; slowest_time_constant is dense (limit 2000)")
    lam = np.linalg.eigvals(ts.K.toarray())
    return -1.0 / float(np.max(lam.real))

