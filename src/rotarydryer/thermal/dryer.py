r"""The whole dryer: transport + moisture + energy of solids and gas, steady state and dynamics.

Model (Ajayi (2011) Ch. 5-6, generalised to any sequence of sections; notes ajayi_energy.md §1):

* **Solids tanks**: unflighted slices (rolling-bed finite volumes) and, per flighted
  cell, a passive (flight/floor-borne) and an active (airborne curtain) tank. Each tank has
  dry solids S (kg), water W (kg) and temperature T (°C) as states. The wet-solids flows are
  those of the transport model ([`rotarydryer.transport.ajayi`][rotarydryer.transport.ajayi], Ajayi (2011)
  Eq. 5.1-5.3, 5.17-5.19; bed: dispersed plug flow Eq. 5.9 by finite volumes, closed
  (Danckwerts) inlet so that every balance closes) and carry the composition and enthalpy of
  their source tank (Eq. 6.1-6.4, 6.8-6.11). Differences from the thesis, chosen for
  conservation: dry solids and water are balanced separately (Ajayi's wet-mass balance
  Eq. 5.1 does not subtract evaporation, notes §5.12 item 7); the design-load cap
  min(m_p, m_des) may be smoothed (``design_load_smoothing``, 0.1 % of m_des in the MMG case).
* **Transport coupled to moisture**: the solids states ride on the nodes of the dryer's
  transport network ([`rotarydryer.transport.sections.build_sections`][rotarydryer.transport.sections.build_sections]: any sequence of
  flighted and unflighted sections), whose edge families give the flows. A family of a
  flighted section re-evaluates its coefficient and design load through the section law at
  the *computed* passive moisture: repose angle and bulk density come from the material
  ([`rotarydryer.properties.materials`][rotarydryer.properties.materials]), as in Ajayi's code (L3608-3618). Outside the
  material's moisture range the moisture is clipped for the transport properties only and
  the steady state reports ``transport_moisture_clipped``. ``moisture_coupling=False`` uses
  the transport model's assumed profile instead (the transport-only model).
* **Gas**: one well-mixed stage per bed slice / flighted cell, plug flow along the drum,
  co- or counter-current; states T_g (°C) and Y (kg/kg dry gas); the dry-gas flow is
  constant. Gas exchanges heat and water only with the active layer (bed slices) and the
  curtain (active tanks), Ajayi (2011) §6.1; passive tanks exchange nothing (Ajayi's
  assumption). Shell heat loss from the gas (Eq. 6.50-6.55). For dynamics the gas has a
  small holdup (freeboard volume at 250 °C), i.e. it is quasi-steady as in Ajayi's
  algebraic gas model but solved by the same stiff integrator.
* **Modes** (the sources disagree, notes §2.2 and §8):

  ``"physical"`` (default)
      physical humid-air enthalpies, WSGG gas radiation, shell loss with the shell
      temperature solved ([`rotarydryer.thermal.shell.shell_heat_loss`][rotarydryer.thermal.shell.shell_heat_loss]), Chilton-Colburn
      on a concentration basis; the gas flow is a parameter (tuned on Test 4, see
      ``cases/ajayi2011_mmg.toml`` [thermal]) and the fuel rate follows from the burner.
  ``"ajayi2011"`` (compatibility)
      Ajayi's enthalpies with c_p,v in kJ/(kg K) as coded, black-gas radiation,
      Ajayi's h_m with the vapour partial pressure (Eq. 6.47) and Antoine P_sat, gas flow
      112675.6688 kg/h, fixed shell temperatures with loss factor θ_loss = 15 (Eq. 6.50).
      Its balances close in Ajayi's own enthalpy accounting; the steady state also reports
      the energy balance re-evaluated with physical enthalpies
      (``physical_energy_balance_error``), which does not close - the inconsistency of the
      thesis.

* **Solvers**: steady state by pseudo-transient continuation (implicit Euler on the dynamic
  model with a growing time step, started from the transport steady state and a linear
  temperature/moisture guess, ending in Newton steps) with a sparse finite-difference
  Jacobian (column grouping) and sparse LU; dynamics by ``solve_ivp`` BDF with the Jacobian
  sparsity pattern. The residual takes a batch of states (``rhs(t, Z)``, Z of shape (n, k)), so
  each finite-difference Jacobian perturbs all its column groups in one call (about one residual
  evaluation instead of 15 for MMG); the shell temperatures of the previous shell solve start the
  next one (Newton, same root). Chord steps on a kept Newton factorisation (a nearby run's, in a
  study or sweep) carry Broyden's secant corrections of the steps taken on it (Kelley (1995)
  Alg. 7.3.1): 8 % fewer residuals per warm-started MMG run; the root is the same. Each step
  moves no temperature or humidity more than STEP_RADIUS times its scale (a fixed bound along the
  step's direction; far from the root Newton's steps on the gas overshoot), and the pseudo-time
  step does not grow while the bound binds; where the continuation
  still fails, a transient march at a loose tolerance (MARCH_RTOL) reaches the root's basin and
  Newton finishes from there.
* **Compiled cell balance**: with the compiled kernels on, the residual of a dryer of one size class
  in the physical mode is one compiled pass over its edges, tanks and stages
  (`rotarydryer.properties._kernels`, `ThermalDryer._rhs_compiled`); the section laws, the rolling
  beds' bulk density, the shell loss and a recycling burner's inlet gas are evaluated first, as by the
  NumPy form (`ThermalDryer._rhs`), which stays the definition (the same residual to rounding; bit for
  bit on the shipped cases) and serves the other configurations.

Bad input raises [`DryerError`][rotarydryer.thermal.dryer.DryerError] (a ``ValueError``) saying which and why; solver failures
keep the last iterate on ``exc.state``.
"""

from __future__ import annotations

import copy
import dataclasses
import logging
import math
import time
import warnings

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu, spsolve

from .. import _jit
from .._sparse_fd import FDPlan, column_groups
from .._validation import check_range
from ..correlations.drag import terminal_velocity
from ..geometry.drum import check_speed
from ..properties import _kernels
from ..properties import humid_air as ha
from ..properties import water as _water
from ..properties.psd import single_class
from . import balances as bal
from . import radiation as rad
from .consistency import pi_operating_conditions  # noqa: F401  (re-exported)
from .settings import AJAYI_GAS_FLOW, SHELL_THICKNESS_RATIO, DryerError, SectionThermal, ThermalSettings
from .shell import _shell_loss_compiled, ajayi2011_heat_loss, shell_heat_loss
from .states import (  # noqa: F401  (re-exported)
    DUST_REFUSE_FRACTION,
    CoupledTransportState,
    DynamicResult,
    ThermalSteadyState,
    dust_share,
)

__all__ = ["DryerError", "SectionThermal", "ThermalSettings", "ThermalDryer", "ThermalSteadyState", "DynamicResult",
           "AJAYI_GAS_FLOW", "pi_operating_conditions"]
# the settings (settings.py), the states (states.py) and the plant data (consistency.py) are re-exported
# here, where they were defined before the module was split by role

_log = logging.getLogger(__name__)

#: a step whose residual falls below this fraction of the last keeps the factorisation (chord step)
CHORD_RATIO = 0.01
#: ... with size classes, whose Jacobian costs about C times more residuals (its colour groups grow as the
#: classes: every class of a tank shares the mixture's flows): a chord step pays sooner (MMG with 5 classes:
#: 10 iterations instead of 8, 0.10 s instead of 0.14 s, the same state to the tolerance)
CHORD_RATIO_CLASSES = 0.1
#: tolerance of the transport-only steady state that starts the coupled solve (relative to the feed;
#: a start needs no more: the coupled Newton steps correct far larger differences)
START_TOLERANCE = 1e-10
#: chord steps with a nearby steady state's factorisation continue while the residual falls at least this much
#: per step (with the secant corrections a threefold fall pays against a new Jacobian, about 2.6 residuals and an
#: LU: on 80 warm-started MMG runs of the Sobol benchmark's inputs 768 residuals and 21 Jacobians instead of 738
#: and 86 at 0.1, the value from before the secant corrections; Invicta and Song warm starts cost the same)
BORROWED_RATIO = 0.3

#: secant (Broyden) corrections kept on one factorisation before the chord steps start afresh
BROYDEN_MEMORY = 8
#: ... on a factorisation of I/dt - J with dt at least this (s): a Newton matrix (1/dt far below the slowest
#: rate of the dryer, about 1e-4 1/s); on a smaller pseudo-time step the secant updates would undo the
#: damping of the pseudo-transient continuation
BROYDEN_MIN_DT = 1e6
#: a secant correction whose denominator 1 - <s_n, z>/<s_n, s_n> is smaller than this is not taken
BROYDEN_MIN_DENOMINATOR = 0.1

#: column groups of the Jacobian patterns met so far (pattern bytes -> groups), oldest dropped first
_GROUPS_CACHE: dict = {}


#: virtual solids mass (kg per kg/s of feed) giving an empty tank a temperature (ThermalDryer._rhs)
EMPTY_TANK_MASS = 1e-10
#: below this solids mass (kg per kg/s of feed) a tank's temperature residual counts in
#: proportion to its heat capacity (ThermalDryer._residual_norm)
EMPTY_TANK_MASS_NORM = 1e-6
#: ... in the test that accepts a steady state (not in the one that steers the pseudo-time step): a tank
#: holding less than a millisecond of the feed (the fines of a dusty dryer, nearly all carried off) has a
#: temperature that no output depends on, and whose rate Newton cannot resolve to 1e-11 K/s through the
#: kinks of a bone-dry product (a 4e-10 kg tank stalled a user dryer at 3.5e-7 after 300 iterations)
EMPTY_TANK_MASS_ACCEPT = 1e-3
#: gas within this many K of the ambient (and below it): the shell loss is linear in T_g - T_amb with
#: the network's conductance at the band's edge (ThermalDryer.physical_shell_loss)
SHELL_LINEAR_BAND_K = 1.0
#: transient march's stops (multiples of the start's solids residence time), at each of which Newton is tried
#: again, where pseudo-transient continuation from the start fails (ThermalDryer.steady_state)
MARCH_HORIZONS = (3.0, 10.0)
#: residual calls a march may take (to each stop): a march that needs more is given up, not waited for (a user dryer of
#: fine size classes losing most of its feed as dust marched for over 10 minutes); the largest march of 279 random user
#: dryers took 1 343, those of random size-class dryers (`bench_issue32_user_dryers.py --classes`) up to 9 024 (4 000
#: before 2026-12-06 gave up on seven of them, each of which Newton then solved from the march's end in 1-195 steps)
MARCH_MAX_CALLS = 12000
#: a pseudo-transient step is refused (the pseudo-time step cut fourfold) where the scaled residual grows by
#: more than this, once the pseudo-time step is above the starting one (not while it is at or below it, the
#: phase where the step radius binds included)
ACCEPT_GROWTH = 10.0
#: before a step the growth test refuses, the gas's own Newton step from it (`ThermalDryer._gas_corrected`) is tried:
#: the gas stages hold seconds of flow, so a step that moves the solids leaves the gas behind and the largest
#: residual is a gas humidity's; with the gas caught up the step may pass. Song's pilot dryer: 16 -> 9 iterations,
#: 14 -> 7 factorisations (four fourfold cuts of the pseudo-time step gone); of 279 random valid dryers, 5.6 % fewer
#: iterations in all (benchmarks/RESULTS.md, issue 32); tried on every step, or on every step whose residual rose,
#: it cost MMG and Invicta three to four times the iterations. Not with size classes: of 80 random dryers with
#: classes it took 41 % more CPU in all and failed three instead of one. A dryer of one class with entrainment takes it
#: as without (it solves as the same dryer while the gas carries nothing off: tests/thermal/test_size_classes.py)
GAS_CORRECTION = True
#: largest scaled change of a temperature or humidity in one pseudo-transient step (scale: 100 K, 0.05
#: kg/kg; ThermalDryer._scale): a longer step is shortened along its direction. Far from the steady state
#: Newton's steps on the gas overshoot (humidities from 0 to 0.8 kg/kg and back); near it the steps are far
#: shorter, so the converged state is the same. While it binds the pseudo-time step does not grow. Of 279
#: random valid dryers, 277 converge without the transient march instead of 244 (benchmarks/RESULTS.md, issue 32)
STEP_RADIUS = 2.0
#: relative tolerance of the transient march towards the steady state (it only has to reach the root's basin;
#: the Newton steps after it converge to the same tolerance): 1e-3, 2.8x cheaper than 1e-5 on the dryers
#: that need it, with the same states after Newton
MARCH_RTOL = 1e-3
#: a solve that ends without meeting the residual test (its iterations spent, or stalled) is accepted where its
#: scaled residual is below this many times the tolerance and its water and energy balances close to BALANCE_ACCEPT
ACCEPT_AFTER_MAX_ITER = 1e3
#: ... the water and energy balance errors of an accepted solve at most (and of a failed one that is refused as
#: entrained, `ThermalDryer._refuse_if_entrained`)
BALANCE_ACCEPT = 1e-6
#: the smallest feed, as a share of the gas flow, the coupled solver resolves: below it the solids' heat and water
#: flows vanish beside the gas's (the MMG dryer fed 1e-6 kg/s, 7e-8 of its 14.4 kg/s of gas, stalled with overflows
#: after 24 s; 1e-5 kg/s converges; the `new` template fed 1e-6 kg/s, 2.5e-7 of its gas, converges)
MIN_FEED_TO_GAS = 1e-7
#: ... and ends early where its residual has not fallen below STALL_FACTOR x its lowest for this many iterations
#: while that lowest is already acceptable: a Newton iteration stalled on a kink (a bone-dry tank's moisture at
#: the dry guard's corner) by a few times the tolerance took the last 100-250 of its 300 iterations to end where it
#: was (seconds with size classes)
STALL_ITERATIONS = 30
STALL_FACTOR = 0.5
#: a failed solve of a dryer recycling exhaust names the recycle where its last iterate's gas humidity reached this
#: fraction of the humid-air range's top (ThermalDryer._with_recycle_hint)
RECYCLE_HINT_HUMIDITY = 0.9
#: a converged state whose water or energy balance is open by more than this is polished
#: (ThermalDryer._polished)
BALANCE_POLISH = 1e-10


#: the shell's inner radius allowed, as fractions of the drum radius (`ThermalDryer._check_shell`): wide, since a
#: case that gives its shell (the MMG case's 1.90 m, Ajayi's code) keeps it under a --set drum.radius
SHELL_RADIUS_RANGE = (0.5, 2.0)


def _near_ambient(q_edge, Tg, ambient):
    """Shell loss ``q_edge`` (W per stage, evaluated at max(T_g, T_amb + band)) continued linearly
    below the band's edge: q = q_edge (T_g - T_amb) / band, zero at the ambient and a gain below
    it. The correlations of the shell network (natural convection, radiation) hold for a shell
    warmer than the surroundings; near and below the ambient their conductance at the edge stands
    for both directions of the heat flow."""
    dT = np.asarray(Tg, dtype=float) - ambient
    if dT.size and isinstance(q_edge, np.ndarray) and q_edge.shape == dT.shape and dT.min() >= SHELL_LINEAR_BAND_K:
        return q_edge
    return np.where(dT < SHELL_LINEAR_BAND_K, q_edge * dT / SHELL_LINEAR_BAND_K, q_edge)


def _flat64(*arrays) -> bool:
    """Are these the compiled step kernels' arrays (float64, one dimension, C-contiguous)?"""
    return all(a.dtype == np.float64 and a.ndim == 1 and a.flags.c_contiguous for a in arrays)


def _broyden_step(steps: list, z: np.ndarray):
    """The chord step ``z`` = M^-1 f on a kept factorisation M, corrected by Broyden's secant updates of
    the full steps ``steps`` s_0..s_n taken on it (scaled variables): Kelley (1995) Alg. 7.3.1 (brsol,
    Broyden's good method with the inverse updates stored as the steps). Superlinear where the chord
    steps converge linearly (a study's run from a nearby run's factorisation); the root is the same.
    None where the last denominator is too small (the caller takes the plain chord step)."""
    z = z.copy()
    for a, b in zip(steps[:-1], steps[1:]):
        z += b * (np.dot(a, z) / np.dot(a, a))
    last = steps[-1]
    denom = 1.0 - np.dot(last, z) / np.dot(last, last)
    if not np.isfinite(denom) or abs(denom) < BROYDEN_MIN_DENOMINATOR:
        return None
    return z / denom


def _scatter_rows(index, weights, n, flat_index):
    """``np.bincount(index, w, n)`` along the last axis of each of several weight arrays ``w`` of one
    shape ((e,) or a batch (k, e)): the sums over edges into nodes, as one bincount of them stacked, in
    the same order (so the same rounding) for every row. ``flat_index(rows)``: the index of each weight
    in the stacked rows (rows x n bins), ``index`` offset by row (cached by the caller). One row each (a single
    state of one class, the solvers' usual call): a bincount per array, the same sums without the stacking."""
    if index.size and weights[0].size == index.size:
        return [np.bincount(index, w.reshape(-1), n).reshape(w.shape[:-1] + (n,)) for w in weights]
    w = np.stack(weights)
    if not index.size:      # no edge ends here
        return np.zeros(w.shape[:-1] + (n,))
    rows = w.size // index.size
    out = np.bincount(flat_index(rows), w.reshape(-1), rows * n)
    return out.reshape(w.shape[:-1] + (n,))


def _filled(base, shape):
    """A new array of ``shape`` holding the last single state's values ``base`` in every row (the
    Jacobian batches overwrite the pairs their perturbations changed; cheaper than np.broadcast_to
    and a copy)."""
    a = np.empty(shape)
    a[...] = base
    return a


#: a size class holding less than this many seconds of its dry feed in a tank: all but emptied there by the gas
#: (named in a failed solve's error, `ThermalDryer._where_unsolved`)
TRACE_CLASS_HOLDUP = 1e-3


def _smooth_min(a, b, eps):
    """min(a, b), smoothed over ``eps`` (exact for eps = 0)."""
    if not np.asarray(eps).any():        # every width 0 (a scalar or an array of widths)
        return np.minimum(a, b)
    return 0.5 * (a + b - np.sqrt((a - b) ** 2 + eps**2))


def _hinted(failure: DryerError, hint: str) -> DryerError:
    """``failure`` with ``hint`` (a likely cause) after its message: the same reason, state and cause."""
    out = DryerError(str(failure) + hint, reason=failure.reason, state=failure.state)
    out.__cause__ = failure.__cause__
    return out


class ThermalDryer:
    """Heat and mass transfer on the nodes of a dryer's transport network.

    Parameters
    ----------
    model : TransportModel
        Built by [`rotarydryer.transport.sections.build_sections`][rotarydryer.transport.sections.build_sections] (any sequence of
        flighted and unflighted sections; closed inlet). Its nodes carry the solids states,
        its edge families the flows; the families of flighted sections re-evaluate their
        coefficients and design loads at the computed moisture through their section law.
    material : Material
        Repose angle, bulk density, heat capacity, particle density and size, drying kinetics,
        and the moisture range where they hold ([`rotarydryer.properties.materials`][rotarydryer.properties.materials]).
    feed_rate : wet solids, kg/s. feed_moisture : kg/kg wet (inside the material's range).
    rpm : rev/min. radius : drum radius, m.
    sections : dict section name -> [`SectionThermal`][rotarydryer.thermal.dryer.SectionThermal] (missing: defaults).
    settings : [`ThermalSettings`][rotarydryer.thermal.dryer.ThermalSettings].
    """

    def __init__(self, model, *, material, feed_rate, feed_moisture, rpm, radius, sections=None,
                 settings: ThermalSettings):
        self.model = model
        self.material = material
        self.settings = self._completed(settings.validate())      # a copy: the caller's settings stay as they are
        self.feed_rate, self.feed_moisture, self.rpm = feed_rate, feed_moisture, rpm
        self.radius = float(check_range("drum.radius", radius, 0.0, 20.0, unit="m"))
        self._check_operating_inputs()
        self.section_thermal = {k: (v if isinstance(v, SectionThermal) else SectionThermal(**v))
                                for k, v in (sections or {}).items()}
        self._check_gas_can_dry()
        self._check_shell()
        self._layout()

    def _completed(self, s: ThermalSettings) -> ThermalSettings:
        """``s`` with what it leaves to the material filled in: the drying kinetics (in the ajayi2011
        mode on Ajayi's mass-transfer basis with Antoine's saturation pressure), the solids' heat
        capacity and particle density."""
        kin = s.kinetics
        if kin is None:
            kin = self.material.kinetics
            if s.mode == "ajayi2011":
                kin = dataclasses.replace(kin, basis="ajayi2011", saturation_method="antoine_ajayi2011")
        return dataclasses.replace(
            s, kinetics=kin,
            cp_solids=float(self.material.heat_capacity) if s.cp_solids is None else s.cp_solids,
            particle_density=float(self.material.particle_density) if s.particle_density is None else s.particle_density)

    def _check_shell(self):
        """The scale layer fits inside the shell (checked when the dryer is built and when a study
        changes its settings, [`rotarydryer.thermal.studies.perturbed`][rotarydryer.thermal.studies.perturbed])."""
        s = self.settings
        if s.shell_inner_radius is not None:
            # the steel shell is the drum's wall: its inner radius near the drum radius (the MMG case's 1.90 m at a
            # 1.95 m drum, Ajayi's code); a 0.01 m shell on a 1 m drum ran with a 24x smaller shell loss (found by an
            # acceptance check); the MMG case's shell with drum.radius from 0.95 to 3.8 m runs
            lo, hi = SHELL_RADIUS_RANGE
            r = float(s.shell_inner_radius)
            if not lo * self.radius <= r <= hi * self.radius:
                raise ValueError(f"shell.inner_radius = {r:g} m is outside the allowed range [{lo * self.radius:.4g}, "
                                 f"{hi * self.radius:.4g}] m ({lo:g} to {hi:g} x drum.radius = {self.radius:g} m: the "
                                 "steel shell is the drum's wall; without shell.inner_radius it is the drum radius)")
        if s.mode == "physical" and not s.scale_thickness < 0.5 * self.shell_inner_radius:
            raise ValueError(f"shell.scale_thickness = {s.scale_thickness:g} m must be below half the shell inner "
                             f"radius ({0.5 * self.shell_inner_radius:g} m)")

    @property
    def shell_inner_radius(self) -> float:
        """Inner radius of the steel shell, m: ``settings.shell_inner_radius``, or the drum radius."""
        r = self.settings.shell_inner_radius
        return self.radius if r is None else float(r)

    @property
    def shell_thickness(self) -> float:
        """Steel wall of the shell, m: ``settings.shell_thickness``, or `SHELL_THICKNESS_RATIO` times
        the inner radius."""
        d = self.settings.shell_thickness
        return SHELL_THICKNESS_RATIO * self.shell_inner_radius if d is None else float(d)

    def _check_operating_inputs(self):
        """Check (and convert) the inputs a study may change: feed rate, feed moisture, speed."""
        self.feed_rate = float(check_range("operating.feed_rate", self.feed_rate, 0.0, 1000.0, unit="kg/s"))
        fm = float(check_range("operating.feed_moisture", self.feed_moisture, 0.0, 1.0, low_inclusive=True,
                               unit="kg/kg wet"))
        lo, hi = self.material.wet_range()
        if fm > hi:
            raise DryerError(
                f"feed too wet: operating.feed_moisture = {fm:g} kg/kg wet exceeds the range of material "
                f"'{self.material.name}' (<= {hi:.4g} kg/kg wet): its repose-angle and bulk-density laws and the "
                f"design-load model are not valid above it", reason="feed_too_wet")
        self.feed_moisture = fm
        self.rpm = float(check_range("operating.rpm", self.rpm, 0.0, 60.0, unit="rev/min"))
        # at or above the drum's critical speed the solids ride round with the wall (the case checks it when it
        # is built, a study's or dynamic run's new speed here)
        check_speed("operating.rpm", self.rpm, self.radius, warn=False)

    # ------------------------------------------------------------------ layout
    def _check_gas_can_dry(self):
        s = self.settings
        y = s.gas_inlet_humidity / (1.0 - s.gas_inlet_humidity)
        if s.gas_inlet_temperature <= s.solids_inlet_temperature:
            raise DryerError(
                f"gas too cold to dry: gas.inlet_temperature = "
                f"{s.gas_inlet_temperature:g} degC is not above "
                f"the solids inlet temperature {s.solids_inlet_temperature:g} degC: the model needs the gas to be the "
                f"heat source (a feed as warm as the gas would dry, if at all, on its own heat, as in a cooler); give "
                f"gas.inlet_temperature above {s.solids_inlet_temperature:g} degC", reason="gas_too_cold")
        rh = float(ha.relative_humidity(min(s.gas_inlet_temperature, 600.0), min(y, 0.3), s.pressure))
        if rh >= 1.0:
            raise DryerError(f"gas too cold to dry: the inlet gas is saturated (gas.inlet_humidity = "
                             f"{s.gas_inlet_humidity:g} kg/kg wet gas at gas.inlet_temperature = "
                             f"{s.gas_inlet_temperature:g} degC: relative humidity {rh:.2f})", reason="gas_too_cold")
        t_in, y_in = min(s.gas_inlet_temperature, 600.0), min(y, ha.Y_MAX)
        if self.feed_moisture > 0 and bool(ha.wet_bulb_below(t_in, y_in, 0.0, s.pressure)):
            wb = float(ha.wet_bulb_temperature(t_in, y_in, s.pressure))       # for the message
            if wb < 0.0:
                raise DryerError(
                    f"gas too cold to dry: gas.inlet_temperature = {s.gas_inlet_temperature:g} degC with "
                    f"gas.inlet_humidity = {s.gas_inlet_humidity:g} kg/kg wet gas has a wet-bulb temperature of "
                    f"{wb:.3g} degC: the wet feed would cool below freezing, which the model does not represent "
                    "(no ice); raise gas.inlet_temperature", reason="gas_too_cold")

    def _layout(self):
        """Nodes, families and gas stages from the transport model (no layout of its own)."""
        s = self.settings
        net = self.model.network
        lab = net.labels
        phase = np.asarray(lab["phase"])
        self.n_tanks = net.n
        self.kind = np.select([phase == "bed", phase == "passive"], [0, 1], 2)
        self.tank_section = np.asarray(lab["section"])
        self.position = np.asarray(lab["position"], dtype=float)
        feed_nodes = np.flatnonzero(net.feed > 0)
        if feed_nodes.size != 1 or any(f.name == "inlet_dispersion" for f in net.families):
            raise DryerError("the heat-and-mass model needs a closed solids inlet (one feed node)")
        self.entry = int(feed_nodes[0])
        self.families = net.families
        self._outlet_families = [f for f in self.families if np.any(f.dst < 0)]
        self.laws = []
        self._law_cache = {}
        self._law_base = {}      # id(law) -> (mp, xp, rpm, fouling, values, smoothing) of the last single state
        for f in self.families:
            if f.law is not None and all(f.law is not x for x in self.laws):
                self.laws.append(f.law)
        self.length = float(sum(sec["length"] for sec in self.model.sections))
        # gas stages: one per bed finite volume and per flighted cell (coupled to its curtain), in axial order
        gas_tank = np.flatnonzero(self.kind != 1)
        gas_tank = gas_tank[np.argsort(self.position[gas_tank], kind="stable")]
        self.gas_tank = gas_tank
        self.n_gas = gas_tank.size
        self.seglen = self.model.cell_length
        self.gas_len = self.seglen[gas_tank]
        self.gas_section = self.tank_section[gas_tank]
        self.gas_position = self.position[gas_tank]
        st = [self.section_thermal.get(name, SectionThermal()) for name in self.gas_section]
        self.gas_theta = np.array([x.area_factor for x in st], dtype=float)
        self.gas_dp = np.array([x.particle_diameter if x.particle_diameter is not None
                                else self.material.particle_diameter for x in st], dtype=float)
        self.shell_T = np.array([x.shell_temperature if x.shell_temperature is not None else 100.0 for x in st])
        self.is_bed_stage = self.kind[gas_tank] == 0
        # the gas stage nearest each tank (same section where it has one): the anchor of an empty tank's
        # temperature (_rhs: EMPTY_TANK_MASS)
        near = np.abs(self.position[:, None] - self.gas_position[None, :]) + 1e6 * (
            np.asarray(self.tank_section)[:, None] != np.asarray(self.gas_section)[None, :])
        self._tank_stage = np.argmin(near, axis=1) if self.n_gas else np.zeros(self.n_tanks, dtype=int)
        # kiln bed: the passive solids of a flighted cell above its design load roll on the drum floor;
        # their active layer exchanges with the gas of the cell's stage (the curtain's), with the
        # bed-surface area of Ajayi (2011) Eq. 6.56-6.61 (kiln_bed_area = true)
        stage_of = {(self.tank_section[t], float(self.position[t])): i for i, t in enumerate(gas_tank)}
        self._kiln_plan = []
        for law in self.laws:
            stages = np.array([stage_of.get((self.tank_section[p], float(self.position[p])), -1) for p in law.P])
            if np.all(stages >= 0):
                self._kiln_plan.append((law, stages))
        # gas holdup (kg dry gas) of each stage: freeboard at 250 degC
        rho = float(ha.density(250.0, 0.05, s.pressure)) / 1.05
        self.gas_holdup = rho * math.pi * self.radius**2 * self.gas_len
        co = s.gas_direction == "co-current"
        self.gas_order = np.arange(self.n_gas) if co else np.arange(self.n_gas)[::-1]
        up = np.empty(self.n_gas, dtype=int)
        up[self.gas_order[0]] = -1
        up[self.gas_order[1:]] = self.gas_order[:-1]
        self.gas_up = up
        self.gas_outlet_stage = int(self.gas_order[-1])
        self._beam_length = rad.mean_beam_length(2 * self.radius)   # gas radiation to the solids
        self._pattern = None
        self._pattern_recycle = False    # the pattern holds the recycle's entries (sparsity)
        self._groups = None
        self._shell_ua = None
        self._shell_outer = None     # outer shell temperatures of the last shell solve (a warm start)
        self._shell_slope = None     # (those temperatures, their Newton slopes) of a compiled solve
        self._shell_memo = None      # (inputs, heat loss) of the last exact shell evaluation
        self._floor_memo = None      # (inputs, lowest admissible gas temperature) (_gas_temperature_floor)
        self._transfer_base = None   # (inputs, outputs) of the last single-state gas-solids transfer
        self._edge_base = None       # (k, caps, law evaluations) of the last single state's edges (flows)
        self._batch_values = None    # (m, law -> the cells a batch changed and their values) (_edge_values_batch)
        self._cells = None           # (settings key, kinetics, plan) of the compiled cell balance (_cell_plan)
        self._inlet_h = None
        self._clipped = False
        self._plans = {}             # family set -> edges end to end (_edge_plan)
        self._flat = {}              # stacked bincount indices (_flat_index)
        self._layout_classes()
        self.n = 3 * self.n_classes * self.n_tanks + 2 * self.n_gas

    def _layout_classes(self):
        """The size classes ([`SizeClasses`][rotarydryer.properties.psd.SizeClasses] of the settings, or
        one of the material's diameter): their diameter at each gas stage (a section's own particle
        diameter shifts every class by its ratio to the material's: the size change along the dryer
        that Ajayi (2011) l.1571 observed), their share of the feed, and - with entrainment - each
        class's terminal velocity at the inlet gas (module docstring, "Size classes")."""
        s = self.settings
        d_mat = float(self.material.particle_diameter)
        sc = s.size_classes
        if sc is None:
            sc = single_class(d_mat, "the material's particle diameter")
        self.size_classes = sc
        self.n_classes = sc.n
        self.class_diameter = np.asarray(sc.diameters, dtype=float)
        self.class_feed = np.asarray(sc.fractions, dtype=float)
        # (classes, stages): one class of the material's diameter gives gas_dp itself (ratio 1)
        self.class_dp = self.gas_dp[None, :] * (self.class_diameter / d_mat)[:, None]
        self.dusty = bool(s.entrainment and s.size_classes is not None)      # one class too (it was n > 1: silently none)
        self._dust_plan = None
        if self.dusty:
            self._layout_dust()
        # the trajectory step's laws: each class's own curtain coefficients (its diameter in the section)
        self._class_laws = []
        if sc.n > 1:
            slices = self._edge_plan(self.families)[-1]
            for law in self.laws:
                if getattr(law, "trajectory", False) and law.spec.gas is not None:
                    sec = self.section_thermal.get(law.spec.name, SectionThermal())
                    d_sec = sec.particle_diameter if sec.particle_diameter is not None else d_mat
                    fams = [(f.name, edges) for f, (edges, _) in zip(self.families, slices)
                            if f.law is law and f.name in law.CURTAIN_FAMILIES]
                    self._class_laws.append((law, self.class_diameter * (d_sec / d_mat), fams))

    def _layout_dust(self):
        """What the dust needs, fixed by the network: the curtain (active) tanks of the flighted sections,
        their gas stage, the edges leaving them, and each class's terminal velocity at each stage (its
        diameter there; gas density and viscosity at the inlet gas, Lee (2008) Eq. 6.2-6.3)."""
        s = self.settings
        src = self._edge_plan(self.families)[0]
        stage_of = np.full(self.n_tanks, -1)
        stage_of[self.gas_tank] = np.arange(self.n_gas)
        active = np.flatnonzero((self.kind == 2) & (stage_of >= 0))
        tank_pos = np.full(self.n_tanks, -1)
        tank_pos[active] = np.arange(active.size)
        out_edges = np.flatnonzero(tank_pos[src] >= 0)        # the curtains' outflows (forward, return, backmix)
        y_in = min(max(self.gas_inlet_Y, 0.0), ha.Y_MAX)
        t_in = min(s.gas_inlet_temperature, ha.T_MAX_C)
        rho_g = float(ha.density(t_in, y_in, s.pressure))
        mu_g = float(ha.viscosity(t_in, y_in))
        dp = self.class_dp[:, stage_of[active]]                    # (classes, curtains)
        u_t = terminal_velocity(dp, s.particle_density, rho_g, mu_g)
        self._dust_plan = (active, stage_of[active], out_edges, tank_pos[src[out_edges]], np.asarray(u_t, float))
        # the gas's free cross-section at each curtain: the drum's less the solids of its section (bed, flights
        # and curtains at the transport start, at the feed's bulk density, per metre of the section; a choice:
        # the mean over the section, fixed by the layout)
        vol = self._transport_holdup() / float(self.material.bulk_density(self.feed_moisture))
        drum = math.pi * self.radius**2
        length = {sec["name"]: float(sec["length"]) for sec in self.model.sections}
        solids = {sec: float(vol[self.tank_section == sec].sum()) / length[sec] for sec in set(self.tank_section[active])}
        self._dust_area = np.array([max(drum - solids[sec], 0.5 * drum) for sec in self.tank_section[active]])
        self._dust_edges = {}        # id(src) -> (src, src + dust sources, dst + dust edges)
        self._dust_sum = np.zeros((out_edges.size, active.size))
        self._dust_sum[np.arange(out_edges.size), tank_pos[src[out_edges]]] = 1.0
        self._refuse_all_entrained()

    def _refuse_all_entrained(self):
        """Refuse, before any solve, a dryer whose gas would carry away at least half of even the coarsest
        class's curtain in every flighted cell at the slowest the gas can be (its inlet humidity, cooled to
        the coldest of the feed, the inlet gas and the ambient air): each cascade then loses half of what
        is left and nothing reaches the discharge (`dust_fraction`)."""
        s = self.settings
        t_lo = min(s.solids_inlet_temperature, s.gas_inlet_temperature, s.ambient_temperature)
        n = self._dust_plan[0].size
        e = self.dust_fraction(np.full(self.n_gas, t_lo), np.full(self.n_gas, max(self.gas_inlet_Y, 0.0)))
        if n and float(np.min(e[-1])) >= 0.5:
            u_t = float(np.max(self._dust_plan[-1][-1]))
            y = min(max(self.gas_inlet_Y, 0.0), ha.Y_MAX)
            u_g = self.dry_gas_flow * (1.0 + y) / (float(ha.density(t_lo, y, s.pressure)) * float(self._dust_area.max()))
            raise DryerError(
                f"entrainment: at gas.flow = {s.gas_flow:g} kg/s the gas moves at {u_g:.3g} m/s or more, above twice "
                f"the terminal velocity of the coarsest size class ({self.class_diameter[-1] * 1e6:.0f} um: "
                f"{u_t:.3g} m/s): the whole feed would leave as dust and nothing is left as a product; lower "
                "gas.flow or give a coarser particle_size", reason="entrained")

    def dust_fraction(self, Tg, Y):
        """Share of each class's curtain the gas carries away as dust, per curtain tank (..., classes,
        curtains): 0 where the local gas velocity u_g (through the free cross-section, `_layout_dust`) is at
        most the class's terminal velocity
        u_t (the elutriation criterion: a particle is carried when the gas is faster than it settles,
        Kunii & Levenspiel (1991) Ch. 7), then s^2/(1 + s^2) with s = u_g/u_t - 1: smooth at u_t (the
        Newton solver's Jacobian is continuous), a half at twice u_t, all of it as u_g >> u_t (a choice:
        no source gives this share for a curtain). u_g at the stage's gas temperature and humidity; u_t at
        the inlet gas (`_layout_dust`)."""
        active, stages, _, _, u_t = self._dust_plan
        s = self.settings
        tg = np.minimum(np.maximum(Tg[..., stages], ha.T_MIN_C), ha.T_MAX_C)
        y = np.minimum(np.maximum(Y[..., stages], 0.0), ha.Y_MAX)
        u_g = self.dry_gas_flow * (1.0 + y) / (ha.density(tg, y, s.pressure) * self._dust_area)
        x = np.minimum(np.maximum(u_g[..., None, :] / u_t - 1.0, 0.0), 1e100) ** 2      # 1e200: a share of 1, no overflow
        return x / (1.0 + x)

    def _dusty_flows(self, src, dst, F, Tg, Y):
        """The flows with the dust: each curtain's outflows of class c keep (1 - e_c) and a dust edge to
        the exhaust (dst = -3) takes e_c of them (`dust_fraction`), after the network's edges."""
        active, _, out_edges, pos, _ = self._dust_plan
        e = self.dust_fraction(Tg, Y)                                   # (..., classes, curtains)
        F = F.copy()
        lost = F[..., out_edges] * e[..., pos]
        F[..., out_edges] -= lost
        dust = lost @ self._dust_sum                                  # per curtain: the sum of its edges' losses
        hit = self._dust_edges.get(id(src))
        if hit is None or hit[0] is not src:       # the same arrays every call: `_flat_index` caches by them
            hit = self._dust_edges[id(src)] = (src, np.concatenate([src, active]),
                                                np.concatenate([dst, np.full(active.size, -3)]))
        return hit[1], hit[2], np.concatenate([F, dust], axis=-1)

    # ------------------------------------------------------------------ state helpers
    def split_classes(self, z):
        """(S, W, T, T_g, Y) of state(s) ``z``: the solids per class and tank, shape (..., classes, tanks)
        (views into ``z``), the gas per stage."""
        nt, ng, c = self.n_tanks, self.n_gas, self.n_classes
        k = c * nt
        lead = z.shape[:-1]
        return (z[..., :k].reshape(lead + (c, nt)), z[..., k:2 * k].reshape(lead + (c, nt)),
                z[..., 2 * k:3 * k].reshape(lead + (c, nt)), z[..., 3 * k:3 * k + ng], z[..., 3 * k + ng:])

    def split(self, z):
        """(S, W, T, T_g, Y) of state(s) ``z``, the solids of each tank as one mixture (the sums of the
        classes' dry solids and water, the temperature of their enthalpy): per tank (..., tanks)."""
        S, W, T, Tg, Y = self.split_classes(z)
        if self.n_classes == 1:
            return S[..., 0, :], W[..., 0, :], T[..., 0, :], Tg, Y
        s = self.settings
        C = S * s.cp_solids + W * s.cp_water
        Ct = C.sum(axis=-2)
        Tm = np.where(Ct > 0, (C * T).sum(axis=-2) / np.where(Ct > 0, Ct, 1.0), T.mean(axis=-2))
        return S.sum(axis=-2), W.sum(axis=-2), Tm, Tg, Y

    def class_sum(self, x):
        """The sum over the size classes (axis -2) of ``x`` (..., classes, n): a view of the one class
        where there is one (the default model pays no reduction)."""
        return x[..., 0, :] if self.n_classes == 1 else x.sum(axis=-2)

    @property
    def hot_gas_Y(self):
        """Humidity of the burner gas, kg/kg dry gas."""
        s = self.settings
        return s.gas_inlet_humidity / (1.0 - s.gas_inlet_humidity)

    @property
    def _flows_in(self):
        s = self.settings
        hot = s.gas_flow * (1.0 - s.gas_inlet_humidity)
        leak = s.leak_air_flow / (1.0 + s.ambient_humidity)
        return hot, leak

    @property
    def dry_gas_flow(self):
        """Dry gas through the drum (burner gas + leak air), kg/s."""
        hot, leak = self._flows_in
        return hot + leak

    @property
    def gas_inlet_Y(self):
        """Humidity of the gas entering the first stage (the burner gas mixed with the leak air), kg/kg dry
        gas, without exhaust recycle (with it: [`inlet_gas`][rotarydryer.thermal.dryer.ThermalDryer.inlet_gas])."""
        hot, leak = self._flows_in
        return (hot * self.hot_gas_Y + leak * self.settings.ambient_humidity) / (hot + leak)

    def gas_inlet_enthalpy(self, method=None):
        """Enthalpy of the entering gas (burner gas + leak air mixed adiabatically), J/kg dry gas."""
        s = self.settings
        method = method or s.mode
        hot, leak = self._flows_in
        h = hot * float(bal.gas_enthalpy(s.gas_inlet_temperature, self.hot_gas_Y, method))
        if leak > 0:
            h += leak * float(bal.gas_enthalpy(s.ambient_temperature, s.ambient_humidity, method))
        return h / (hot + leak)

    def _inlet_enthalpy(self):
        """[`gas_inlet_enthalpy`][rotarydryer.thermal.dryer.ThermalDryer.gas_inlet_enthalpy] of the current settings, re-evaluated only when they change."""
        s = self.settings
        key = (s.mode, s.gas_flow, s.gas_inlet_temperature, s.gas_inlet_humidity, s.leak_air_flow,
               s.ambient_temperature, s.ambient_humidity)
        if self._inlet_h is None or self._inlet_h[0] != key:
            self._inlet_h = (key, self.gas_inlet_enthalpy(),
                             float(bal.gas_enthalpy(s.gas_inlet_temperature, self.hot_gas_Y, s.mode)))
        return self._inlet_h[1]

    def inlet_gas(self, Y):
        """(humidity kg/kg dry gas, enthalpy J/kg dry gas) of the gas entering the first stage, at the
        stages' gas humidities ``Y`` ((n_gas,) or a batch (k, n_gas): then arrays (k,)).

        The burner gas (dry flow ``hot``) mixed adiabatically with the leak air (``leak``): without
        recycle, [`gas_inlet_Y`][rotarydryer.thermal.dryer.ThermalDryer.gas_inlet_Y] and
        [`gas_inlet_enthalpy`][rotarydryer.thermal.dryer.ThermalDryer.gas_inlet_enthalpy], whatever ``Y``. With
        ``recycle_fraction`` r the burner heats fresh air (hot - r F_d, at the burner gas's humidity Y_h)
        and the fraction r of the exhaust (r F_d, F_d = hot + leak, at the outlet stage's humidity Y_out)
        to the inlet temperature T_in; the enthalpy being linear in the humidity,
        Y_in = Y_in,0 + r (Y_out - Y_h) and h_in = h_in,0 + r (h(T_in, Y_out) - h(T_in, Y_h))."""
        r = self.settings.recycle_fraction
        h0 = self._inlet_enthalpy()
        if r == 0:
            return self.gas_inlet_Y, h0
        s = self.settings
        y_out = np.asarray(Y, dtype=float)[..., self.gas_outlet_stage]
        h_recycled = bal._gas_enthalpy(s.gas_inlet_temperature, y_out, s.mode)     # at the inlet temperature
        return self.gas_inlet_Y + r * (y_out - self.hot_gas_Y), h0 + r * (h_recycled - self._inlet_h[2])

    def flows(self, S, W, T, families=None, gas=None):
        """Wet-solids edge flows per size class: (src, dst, flow kg/s) with the flows (..., classes,
        edges), incl. the outlet edges (dst = -1) and, with entrainment, the dust edges (dst = -3).

        The network's families with their flow rules, on each tank's solids as one mixture: a family of
        a flighted section takes its coefficient and design load from the section law at the passive
        mixture's moisture (computed, or the assumed transport profile when ``moisture_coupling`` is
        off), and a capped or excess flow min(M, M_des) is the mixture's. A class moves with its share of
        the source tank's solids; the curtains' forward step is the class's own (trajectory step) and the
        gas carries part of a fine class's curtain away (`_dust`). ``families``: only these (default
        all). S, W, T are per class, (..., classes, tanks), with an optional leading batch axis; ``gas``:
        (T_g, Y) of the stages, which set the dust's share (without it: no dust)."""
        everything = families is None
        families = self.families if everything else families
        s = self.settings
        mc = S + W
        m = mc.sum(axis=-2)
        W = W.sum(axis=-2)
        # all edges end to end: one gather, one coefficient array, one smoothed cap for the capped and
        # excess edges (the same operations per edge as family by family)
        src, dst, capped, excess, in_ce, slices = self._edge_plan(families)
        k, cap = self._edge_coefficients(W, m, None if everything else families)
        ms = m[..., src]
        b = ms
        if in_ce.size:
            sm = _smooth_min(ms[..., in_ce], cap, s.design_load_smoothing * cap)
            b = ms.copy()
            b[..., capped[0]] = sm[..., capped[1]]
            b[..., excess[0]] = ms[..., excess[0]] - sm[..., excess[1]]
        # each class its share of the source's mixture (a single class: share 1 exactly, F = k b)
        F = (k * b)[..., None, :] * (mc[..., src] / np.maximum(ms, 1e-300)[..., None, :])
        if everything and self._class_laws:      # the curtains' forward step of each class's own size
            for (law, diameters, fams), (mp, xp) in zip(self._class_laws,
                                                        self._passive(W, m, [c[0] for c in self._class_laws])[0]):
                rates = law.class_rates(mp, xp, diameters, rpm=self.rpm, fouling=s.fouling,
                                        smoothing=s.design_load_smoothing)
                for name, edges in fams:
                    F[..., :, edges] = rates[name] * mc[..., :, src[edges]]
        if self.dusty and everything and gas is not None:
            return self._dusty_flows(src, dst, F, *gas)
        return src, dst, F

    def _edge_coefficients(self, W, m, families=None):
        """(k, cap): the coefficient of every edge of ``families`` (default all) end to end (`_edge_plan`) and the
        design load of each capped or excess edge, at the tanks' mixtures ``W``, ``m`` ((tanks,) or a batch
        (k, tanks)): the section laws at the passive nodes' masses and moisture (`_law_values`; a batch of all
        families re-evaluates only the cells it changed, `_edge_values_batch`), the fixed rates and caps of the
        families without a law. A single state of all families is remembered for the batches that follow."""
        everything = families is None
        families = self.families if everything else families
        s = self.settings
        src, _, _, _, in_ce, slices = self._edge_plan(families)
        batch = self._edge_values_batch(W, m) if everything and m.ndim == 2 else None
        if batch is not None:
            return batch
        coef = {}
        laws = self.laws if everything else list({id(f.law): f.law for f in families if f.law is not None}.values())
        passive, clipped = self._passive(W, m, laws)
        for law, (mp, xp) in zip(laws, passive):
            coef[id(law)] = self._law_values(law, mp, xp, s.fouling)
        lead = m.shape[:-1]
        k = np.empty(lead + src.shape)
        cap = np.empty(lead + in_ce.shape)
        for f, (edges, caps) in zip(families, slices):
            k[..., edges] = f.rate if f.law is None else coef[id(f.law)][f.name]
            if caps is not None:
                cap[..., caps] = f.cap if f.law is None else coef[id(f.law)]["design_load"]
        if everything and m.ndim == 1:
            self._clipped = clipped      # reported by the steady state (transport_moisture_clipped)
            # the edge values of this state and the law evaluations they came from (_edge_values_batch)
            self._edge_base = (k, cap, [self._law_base.get(id(law)) for law in self.laws])
        return k, cap

    def _passive(self, W, m, laws):
        """Per law (its passive nodes' wet masses, their wet-basis moisture clipped to the material's
        range, or the assumed transport profile without ``moisture_coupling``), and whether a moisture
        was clipped: the passive nodes of all ``laws`` in one pass (the same numbers as law by law)."""
        if not laws:
            return [], False
        if not self.settings.moisture_coupling:
            return [(m[..., law.P], law.assumed_moisture) for law in laws], False
        key = ("passive", "all") if laws is self.laws else ("passive",) + tuple(id(law) for law in laws)
        plan = self._plans.get(key)
        if plan is None:
            bounds = np.cumsum([0] + [law.P.size for law in laws])
            plan = self._plans[key] = (np.concatenate([law.P for law in laws]),
                                       [slice(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:])])
        P, slices = plan
        lo, hi = self.material.wet_range()
        mp = m[..., P]
        xp = W[..., P] / np.maximum(mp, 1e-12)
        clipped = bool((xp < lo).any() or (xp > hi).any())
        xp = np.minimum(np.maximum(xp, lo), hi)
        return [(mp[..., sl], xp[..., sl]) for sl in slices], clipped

    def _edge_values_batch(self, W, m):
        """Coefficients and caps of every edge (k, e) for a batch of states (k, n), or None: the last
        single state's edge values with only the (state, cell) pairs re-evaluated whose passive mass or
        moisture differs from it (a Jacobian's perturbations move a few cells of each state; the same
        numbers as evaluating every law on the whole batch and filling family by family). None where
        that does not apply (no single state evaluated since, a law that couples its cells, changed
        settings): [`flows`][rotarydryer.thermal.dryer.ThermalDryer.flows] then evaluates the laws on the whole batch."""
        self._batch_values = None
        base = self._edge_base
        if base is None:
            return None
        k0, cap0, law_bases = base
        s = self.settings
        smooth = s.design_load_smoothing
        per_law = self._edge_plan_laws()
        for law, law_base in zip(self.laws, law_bases):
            if law_base is None or self._law_base.get(id(law)) is not law_base or not law.cellwise \
                    or law_base[2] != self.rpm or law_base[3] != s.fouling or law_base[5] != smooth:
                return None
        k = cap = None
        passive, _ = self._passive(W, m, self.laws)
        changed_values = {}
        for law, law_base, (mp, xp) in zip(self.laws, law_bases, passive):
            mb, xb = law_base[0], law_base[1]
            if s.moisture_coupling:
                changed = (mp != mb) | (xp != xb)
            else:
                if not (xp is xb or np.array_equal(xp, xb)):
                    return None
                changed = mp != mb
            rows, cells = np.nonzero(changed)
            if not rows.size:
                continue
            x = xp[rows, cells] if s.moisture_coupling else np.broadcast_to(np.asarray(xp, dtype=float), (law.n,))[cells]
            v = law.evaluate(mp[rows, cells], x, rpm=self.rpm, fouling=s.fouling, smoothing=smooth, cells=cells)
            changed_values[id(law)] = (rows, cells, v)
            if k is None:
                k, cap = _filled(k0, (m.shape[0], k0.size)), _filled(cap0, (m.shape[0], cap0.size))
            for name, e0, c0 in per_law[id(law)]:
                k[rows, e0 + cells] = v[name]
                if c0 is not None:
                    cap[rows, c0 + cells] = v["design_load"]
        if k is None:
            k, cap = _filled(k0, (m.shape[0], k0.size)), _filled(cap0, (m.shape[0], cap0.size))
        self._batch_values = (m, changed_values)      # what the kiln beds of this batch take (`_kiln_inputs`)
        return k, cap

    def _edge_plan_laws(self):
        """Per section law: (family name, its first edge, its first capped or excess edge or None) of each
        of its families in `_edge_plan` of all families (edge j of a family is the law's cell j)."""
        plan = self._plans.get("laws")
        if plan is None:
            slices = self._edge_plan(self.families)[-1]
            plan = {id(law): [] for law in self.laws}
            for f, (edges, caps) in zip(self.families, slices):
                if f.law is not None:
                    plan[id(f.law)].append((f.name, edges.start, None if caps is None else caps.start))
            self._plans["laws"] = plan
        return plan

    def _edge_plan(self, families):
        """The edges of ``families`` end to end (fixed by the network, built once per family set):
        src, dst, then (edge index, index among the capped and excess edges) of the capped and of
        the excess edges, the edge index of each capped or excess edge, and per family its slice
        of the edges and of the capped and excess edges (None when linear)."""
        key = tuple(id(f) for f in families)
        plan = self._plans.get(key)
        if plan is None:
            kind = np.concatenate([np.full(f.src.size, f.kind) for f in families])
            ce = np.flatnonzero(kind != "linear")
            pos = np.full(kind.size, -1)
            pos[ce] = np.arange(ce.size)
            cap_e, exc_e = np.flatnonzero(kind == "capped"), np.flatnonzero(kind == "excess")
            slices, a, c = [], 0, 0
            for f in families:
                n = f.src.size
                slices.append((slice(a, a + n), None if f.kind == "linear" else slice(c, c + n)))
                a, c = a + n, c + (0 if f.kind == "linear" else n)
            plan = (np.concatenate([f.src for f in families]), np.concatenate([f.dst for f in families]),
                    (cap_e, pos[cap_e]), (exc_e, pos[exc_e]), ce, slices)
            self._plans[key] = plan
        return plan

    def _law_values(self, law, mp, xp, fouling):
        """``law.evaluate`` at (mp, xp), remembered for the last two distinct inputs of each law.

        The finite-difference Jacobian perturbs groups of unknowns; most groups leave a given
        section's passive masses and moisture unchanged (temperatures, gas, other sections), so
        its coefficients are those of the base state: exact reuse, the same numbers. A batch (k, n)
        is evaluated whole (a Jacobian's batch normally takes `_edge_values_batch` instead)."""
        if mp.ndim == 2:
            return law.evaluate(mp, xp, rpm=self.rpm, fouling=fouling, smoothing=self.settings.design_load_smoothing)
        cache = self._law_cache.setdefault(id(law), [])
        smooth = self.settings.design_load_smoothing
        key = (mp.tobytes(), xp.tobytes() if isinstance(xp, np.ndarray) else repr(xp), self.rpm, fouling, smooth)
        for k, v in cache:
            if k == key:
                self._law_base[id(law)] = (mp, xp, self.rpm, fouling, v, smooth)
                return v
        v = law.evaluate(mp, xp, rpm=self.rpm, fouling=fouling, smoothing=smooth)
        cache.insert(0, (key, v))
        del cache[2:]
        self._law_base[id(law)] = (mp, xp, self.rpm, fouling, v, smooth)
        return v

    def _kiln_bed_area(self, W, m):
        """Gas-exposed area (m^2) per gas stage of the kiln beds of the flighted cells: the passive
        mass above the design load, max(M_P - M_des, 0) smoothed over the case's design-load width,
        as a rolling bed's active layer ([`rotarydryer.thermal.balances.active_layer_area`][rotarydryer.thermal.balances.active_layer_area]).
        ``W``, ``m``: the tanks' mixtures (..., tanks)."""
        s = self.settings
        out = np.zeros(m.shape[:-1] + (self.n_gas,))
        passive, _ = self._passive(W, m, [law for law, _ in self._kiln_plan])
        for (law, stages), (mp, xp) in zip(self._kiln_plan, passive):
            base = self._law_base.get(id(law)) if mp.ndim == 1 else None
            if (base is not None and base[2] == self.rpm and base[3] == s.fouling and np.array_equal(base[0], mp)
                    and np.array_equal(base[1], xp)):
                # the flows of this state evaluated the law at the same passive masses: its design load
                des, rho = base[4]["design_load"], base[4]["bulk_density"]
            else:
                xw = np.broadcast_to(xp, mp.shape)
                phi, rho = law.properties(xw)           # the design load alone (not the law's coefficients)
                des = law.design_load(phi, rho, s.fouling)
            eps = max(s.design_load_smoothing, 1e-3) * np.maximum(des, 1e-9)
            excess = np.maximum(mp - _smooth_min(mp, des, eps), 0.0)
            out[..., stages] += bal.active_layer_area(excess, rho, self.gas_len[stages],
                                                      self.radius, self.gas_dp[stages],
                                                      s.area_scale * self.gas_theta[stages], s.particle_density)
        return out

    def _kiln_inputs(self, W, m):
        """(design load kg, bulk density kg/m^3) of the passive node of each kiln stage (`_kiln_plan`'s laws end to
        end), (J,) for a single state and (k, J) for a batch, at the tanks' mixtures ``W``, ``m``: the values of the
        section laws' last evaluation at these states (`_edge_coefficients`, called first with the same ``m``; a
        batch's unchanged cells those of the last single state), else evaluated here as by `_kiln_bed_area`."""
        s = self.settings
        stash = self._batch_values if m.ndim == 2 else None
        fresh = stash is not None and stash[0] is m
        passive = None
        des, rho = [], []
        for i, (law, _) in enumerate(self._kiln_plan):
            base = self._law_base.get(id(law))
            if m.ndim == 1 and base is not None:        # evaluated by `_edge_coefficients` at this state
                des.append(base[4]["design_load"])
                rho.append(base[4]["bulk_density"])
            elif fresh and base is not None:
                d = _filled(base[4]["design_load"], (m.shape[0], law.P.size))
                r = _filled(base[4]["bulk_density"], (m.shape[0], law.P.size))
                hit = stash[1].get(id(law))
                if hit is not None:
                    rows, cells, v = hit
                    d[rows, cells] = v["design_load"]
                    r[rows, cells] = v["bulk_density"]
                des.append(d)
                rho.append(r)
            else:
                if passive is None:
                    passive, _ = self._passive(W, m, [x for x, _ in self._kiln_plan])
                mp, xp = passive[i]
                phi, r = law.properties(np.broadcast_to(xp, mp.shape))
                des.append(law.design_load(phi, r, s.fouling))
                rho.append(r)
        return np.concatenate(des, axis=-1), np.concatenate(rho, axis=-1)

    def _bed_stage_area(self, W, m):
        """Gas-exposed area (m^2) of the rolling beds' active layers, per bed stage (..., bed stages), at the tanks'
        mixtures ``W``, ``m`` (..., tanks): [`rotarydryer.thermal.balances.active_layer_area`][rotarydryer.thermal.balances.active_layer_area] at the bulk density of
        the bed's wet-basis moisture (clipped to 0-0.3)."""
        s = self.settings
        bed = self.is_bed_stage
        tb = self.gas_tank[bed]
        xw = np.minimum(np.maximum(W[..., tb] / np.maximum(m[..., tb], 1e-12), 0.0), 0.3)
        return bal.active_layer_area(m[..., tb], self.material.bulk_density(xw), self.gas_len[bed], self.radius,
                                     self.gas_dp[bed], s.area_scale * self.gas_theta[bed], s.particle_density)

    def _transfer(self, S, W, T, Tg, Y):
        """Gas -> solids transfer per size class and gas stage: (area, R_w, Q_conv, Q_rad), each
        (..., classes, stages), [`rotarydryer.thermal.balances.stage_transfer`][rotarydryer.thermal.balances.stage_transfer] on each class's own
        moisture, temperature and diameter. A curtain's area is each class's own (Ajayi (2011) Eq. 6.63,
        m_c / d_c); a rolling bed's (and a kiln bed's) area is the mixture's, shared by the classes in
        proportion to their surface, m_c / d_c (a single class: the whole)."""
        s = self.settings
        one = self.n_classes == 1
        mc = S + W
        m, Wt = self.class_sum(mc), self.class_sum(W)
        X = W / np.maximum(S, 1e-12)
        tk = self.gas_tank
        dp = self.class_dp
        shape = S.shape[:-1] + (self.n_gas,)
        area = np.empty(shape)
        bed = self.is_bed_stage
        surface = None
        if not one:
            surface = mc[..., tk] / dp                  # each class's share of a bed's surface: m_c / d_c
            surface = surface / surface.sum(axis=-2, keepdims=True)
        if bed.any():
            a_bed = self._bed_stage_area(Wt, m)
            area[..., bed] = a_bed[..., None, :] if one else a_bed[..., None, :] * surface[..., bed]
        act = ~bed
        area[..., act] = bal.curtain_area(mc[..., tk[act]], dp[:, act], s.area_scale * self.gas_theta[act],
                                          s.particle_density)
        if s.kiln_bed_area and s.mode == "physical" and self._kiln_plan:
            kiln = self._kiln_bed_area(Wt, m)[..., None, :]
            area = area + (kiln if one else kiln * surface)
        fg = self._wet_gas_flow(Y)[0][..., None, :]
        tg, y = Tg[..., None, :], Y[..., None, :]
        if not one:                  # one class: (..., 1, stages) is the shape already
            fg, tg, y = (np.broadcast_to(v, shape) for v in (fg, tg, y))
        xs, ts = X[..., tk], T[..., tk]
        # the transfer of a stage depends on that stage's inputs only: a batch (the Jacobian's perturbed
        # states) evaluates only the (state, class, stage) triples whose inputs differ from the last single state
        base = self._transfer_base
        key = (s.kinetics, s.mode, s.pressure, s.co2_mole_fraction, self.radius, self.dry_gas_flow)
        if S.ndim == 3 and base is not None and base[2] == key and base[0][0].shape == area.shape[1:]:
            changed = np.zeros(area.shape, dtype=bool)
            for now, then in zip((area, xs, ts, tg, y), base[0]):
                changed |= now != then
            rows, cls, st = np.nonzero(changed)
            out = [_filled(b, area.shape) for b in base[1]]
            if rows.size:
                sub = bal._stage_transfer(area[rows, cls, st], xs[rows, cls, st], ts[rows, cls, st], tg[rows, cls, st],
                                          y[rows, cls, st], fg[rows, cls, st], dp[cls, st], self.radius, s.kinetics,
                                          s.mode, s.pressure, s.co2_mole_fraction, 0.9, 2e-3, self._beam_length)
                for a, v in zip(out, sub):
                    a[rows, cls, st] = v
            return (area, *out)
        # unchecked kernel of bal.stage_transfer: the inputs are clipped there, the parameters checked at construction
        rw, qc, qr = (np.reshape(v, shape) for v in bal._stage_transfer(
            area, xs, ts, tg, y, fg, np.broadcast_to(dp, shape), self.radius, s.kinetics, s.mode, s.pressure,
            s.co2_mole_fraction, 0.9, 2e-3, self._beam_length))
        if S.ndim == 2:
            self._transfer_base = ((area.copy(), xs, ts, np.array(tg), np.array(y)),
                                   (rw.copy(), qc.copy(), qr.copy()), key)
        return area, rw, qc, qr

    def _wet_gas_flow(self, Y):
        """(wet gas flow kg/s, humidity kg/kg) per stage at the humidity clipped to its physical range, as the
        transfer's and the shell's properties take it: an integrator's trial state may carry a humidity below -1,
        whose unclipped flow is negative (a NaN Reynolds number and a NaN coefficient)."""
        yc = np.minimum(np.maximum(Y, 0.0), ha.Y_MAX)
        return self.dry_gas_flow * (1.0 + yc), yc

    def _upstream_gas_temperature(self, Tg):
        """The temperature of the gas entering each stage (..., stages): its upstream stage's, the inlet's at the first."""
        up = self.gas_up
        return np.where(up >= 0, Tg[..., np.maximum(up, 0)], self.settings.gas_inlet_temperature)

    def _shell_loss(self, Tg, Y, Tg_up=None):
        """Shell heat loss per stage (W): the lagged coefficient while frozen, else exact (``Tg_up``, the upstream
        gas temperatures, computed when not given)."""
        s = self.settings
        if self._shell_ua is not None:   # lagged coefficient Q = UA (T_g - T_amb), refreshed by the solvers
            return self._shell_ua * (Tg - s.ambient_temperature)
        return self._shell_loss_exact(Tg, Y, self._upstream_gas_temperature(Tg) if Tg_up is None else Tg_up)

    def _shell_loss_exact(self, Tg, Y, Tg_up):
        # the last exact evaluation is remembered: the convergence test and the steady state's
        # balances evaluate the same converged state
        key = (Tg.tobytes(), Y.tobytes(), np.asarray(Tg_up).tobytes(), self._settings_key())
        if self._shell_memo is not None and self._shell_memo[0] == key:
            return self._shell_memo[1]
        q = self._shell_loss_exact_eval(Tg, Y, Tg_up)
        self._shell_memo = (key, q)
        return q

    def _settings_key(self):
        s = self.settings
        return (s.mode, s.gas_flow, s.gas_inlet_humidity, s.leak_air_flow, s.ambient_humidity, s.ambient_temperature,
                s.loss_factor, s.pressure, s.co2_mole_fraction, s.scale_thickness, s.scale_conductivity,
                s.insulation_thickness, s.insulation_conductivity, self.shell_inner_radius, self.shell_thickness)

    def _shell_loss_exact_eval(self, Tg, Y, Tg_up):
        s = self.settings
        if s.mode == "ajayi2011":
            fg = self._wet_gas_flow(Y)[0]
            # inside the ranges ajayi2011_heat_loss accepts, [0, 600) and (0, 600) degC: a solver's trial state at a
            # clip's bound (600 or 0 exactly) was refused there as if it were the user's input (found by fuzzing)
            top = np.nextafter(600.0, 0.0)
            tg = np.minimum(np.maximum(Tg, s.ambient_temperature + SHELL_LINEAR_BAND_K), top)
            q = ajayi2011_heat_loss(tg, fg, self.shell_T, self.gas_len, s.ambient_temperature, s.loss_factor,
                                    np.minimum(np.maximum(Tg_up, 1e-6), top))
            return _near_ambient(q, Tg, s.ambient_temperature)
        return self.physical_shell_loss(Tg, Y)

    def physical_shell_loss(self, Tg, Y):
        """Shell heat loss per gas stage (W) of the solved shell network (shell temperature solved,
        scale and insulation layers) at gas temperatures ``Tg`` and humidities ``Y``; within
        SHELL_LINEAR_BAND_K of the ambient and below it, the network's conductance at the band's
        edge times (T_g - T_amb): a gas colder than the surroundings gains heat through the shell."""
        return _near_ambient(self._shell_network_loss(Tg, Y), Tg, self.settings.ambient_temperature)

    def _shell_network_loss(self, Tg, Y):
        s = self.settings
        tg = np.minimum(np.maximum(Tg, s.ambient_temperature + SHELL_LINEAR_BAND_K), 600.0)
        # the shell temperatures of the previous solve start Newton's method (same root to 1e-9 K)
        guess = self._shell_outer if self._shell_outer is not None and self._shell_outer.shape == tg.shape else None
        slope = self._shell_slope if guess is not None and self._shell_slope is not None and \
            self._shell_slope[0] is guess else None
        fg, yc = self._wet_gas_flow(Y)
        args = (tg, fg, self.gas_len, s.ambient_temperature)
        kw = dict(gas_humidity=yc, co2_mole_fraction=s.co2_mole_fraction,
                  inner_radius=self.shell_inner_radius, shell_thickness=self.shell_thickness,
                  scale_thickness=s.scale_thickness, scale_conductivity=s.scale_conductivity,
                  insulation_thickness=s.insulation_thickness, insulation_conductivity=s.insulation_conductivity,
                  pressure=s.pressure, ambient_humidity=s.ambient_humidity, outer_guess=guess)
        fast = _shell_loss_compiled(*args, **kw, slope_guess=None if slope is None else slope[1])
        if fast is not None:     # one compiled pass (else None: the NumPy network)
            self._shell_outer = fast[1]
            self._shell_slope = (fast[1], fast[2])     # the slopes of these temperatures' Newton iterations
            return fast[0]
        r = shell_heat_loss(*args, **kw, _trusted=True)
        self._shell_outer = np.asarray(r.outer_surface_temperature_c, dtype=float)
        return r.heat_loss

    def _solids_streams(self, z, families=None):
        """(S, W, T, Tg, Y, src, dst, F, frac_s, frac_w, h_wet): the state on the nearest physical
        state (trial states of the solvers may leave the physical domain; conservation is
        unaffected at physical states), the edge flows and what each flow carries, per size class
        (solids arrays (..., classes, tanks), flows (..., classes, edges))."""
        if not np.isfinite(z).all():
            raise DryerError("state became non-finite (solver diverged)", reason="diverged", state=z)
        s = self.settings
        S, W, T, Tg, Y = self.split_classes(z)
        S = np.maximum(S, 1e-15 * self.feed_rate)
        W = np.maximum(W, 0.0)
        T = np.minimum(np.maximum(T, -20.0), self._solids_temperature_ceiling())
        m = S + W
        src, dst, F = self.flows(S, W, T, families, gas=(Tg, Y))
        ms = np.maximum(m[..., src], 1e-12)
        frac_s = S[..., src] / ms
        frac_w = W[..., src] / ms
        h_wet = (s.cp_solids * frac_s + s.cp_water * frac_w) * T[..., src]
        return S, W, T, Tg, Y, src, dst, F, frac_s, frac_w, h_wet

    def _solids_temperature_ceiling(self):
        """Upper clip of the solids temperature on the nearest physical state, degC: above the hottest
        gas (+50 K) a trial state is unphysical. (A fixed 300 degC ceiling made solids hotter than it
        invisible to their own balance: a hot over-dried dryer had no restoring heat flow and no
        steady state.)"""
        return max(300.0, self.settings.gas_inlet_temperature + 50.0)

    def product_stream(self, z):
        """Dry solids (kg/s), water (kg/s) and enthalpy (W) leaving with the product at state ``z``
        (solids flows only: no heat-transfer or shell terms)."""
        *_, dst, F, frac_s, frac_w, h_wet = self._solids_streams(z, self._outlet_families)
        out = dst == -1
        return float(np.sum((F * frac_s)[..., out])), float(np.sum((F * frac_w)[..., out])), \
            float(np.sum((F * h_wet)[..., out]))

    def terms(self, z, products=True):
        """All balance terms at state ``z`` (dict of arrays, W and kg/s); ``products``: with the product
        stream's dry solids, water and enthalpy (``product_S``, ``product_W``, ``product_H``), and with
        size classes per class too (``product_S_c``, ... (classes,)) and the dust's (``dust_S``, ``dust_W``,
        ``dust_H``; 0 without entrainment). The solids per class are ``Sc``, ``Wc``, ``Tc`` (..., classes,
        tanks), the transfer per class ``rw_c``, ``qc_c``, ``qr_c``, ``area_c``, ``hv_c`` (..., classes,
        stages); ``S``, ``W``, ``T``, ``rw``, ``qc``, ``qr``, ``area`` are the tanks' mixtures and the stages'
        sums (`split`)."""
        s = self.settings
        S, W, T, Tg, Y, src, dst, F, frac_s, frac_w, h_wet = self._solids_streams(z)
        nt = self.n_tanks
        inner, di, out = self._inner_edges()
        Fs, Fw, Fh = F * frac_s, F * frac_w, F * h_wet
        # solids, water and enthalpy into and out of the tanks: two stacked bincounts (_scatter_rows)
        inS, inW, inH = _scatter_rows(di, [x[..., inner] for x in (Fs, Fw, Fh)], nt,
                                      lambda rows: self._flat_index(di, rows, nt))
        outS, outW, outH = _scatter_rows(src, [Fs, Fw, Fh], nt, lambda rows: self._flat_index(src, rows, nt))
        fS, fW = self.feed_rate * (1 - self.feed_moisture), self.feed_rate * self.feed_moisture
        share = self.class_feed
        inS[..., self.entry] += fS * share
        inW[..., self.entry] += fW * share
        inH[..., self.entry] += (fS * s.cp_solids + fW * s.cp_water) * s.solids_inlet_temperature * share
        area, rw, qc, qr = self._transfer(S, W, T, Tg, Y)
        Ts_c = T[..., self.gas_tank]
        hv = bal._vapour_source_enthalpy(Ts_c, s.mode)
        up = self.gas_up
        Tg_up = self._upstream_gas_temperature(Tg)
        Y_in, h_in = self.inlet_gas(Y)      # the gas entering the first stage (with recycle: of this state)
        Y_up = np.where(up >= 0, Y[..., np.maximum(up, 0)], Y_in if np.ndim(Y_in) == 0 else Y_in[..., None])
        qloss = self._shell_loss(Tg, Y, Tg_up)
        Sm, Wm, Tm, _, _ = self.split(z) if self.n_classes > 1 else (S[..., 0, :], W[..., 0, :], T[..., 0, :], 0, 0)
        d = dict(Sc=S, Wc=W, Tc=T, S=Sm, W=Wm, T=Tm, Tg=Tg, Y=Y, inS=inS, inW=inW, inH=inH, outS=outS, outW=outW,
                 outH=outH, area_c=area, rw_c=rw, qc_c=qc, qr_c=qr, hv_c=hv, area=self.class_sum(area),
                 rw=self.class_sum(rw), qc=self.class_sum(qc), qr=self.class_sum(qr), qloss=qloss, Tg_up=Tg_up,
                 Y_up=Y_up, Y_in=Y_in, h_in=h_in, src=src, dst=dst, Fc=F, F=self.class_sum(F))
        if products:
            for name, mask in (("product", dst == -1), ("dust", dst == -3)):
                if name == "dust" and not self.dusty:
                    per = [np.zeros(F.shape[:-1]) for _ in range(3)]
                else:
                    per = [np.sum(x[..., mask], axis=-1) for x in (Fs, Fw, Fh)]       # (..., classes)
                tot = [x[..., 0] if self.n_classes == 1 else x.sum(axis=-1) for x in per]
                if F.ndim == 2:
                    tot = [float(x) for x in tot]
                d.update({f"{name}_S": tot[0], f"{name}_W": tot[1], f"{name}_H": tot[2],
                          f"{name}_S_c": per[0], f"{name}_W_c": per[1], f"{name}_H_c": per[2]})
        return d

    def _inner_edges(self):
        """(mask of the edges that end in a tank, their destination tanks, mask of the outlet edges) of all
        families and, with entrainment, the dust edges after them (fixed by the network)."""
        plan = self._plans.get("inner")
        if plan is None:
            dst = self._edge_plan(self.families)[1]
            if self.dusty:
                dst = np.concatenate([dst, np.full(self._dust_plan[0].size, -3)])
            inner = dst >= 0
            plan = self._plans["inner"] = (inner, dst[inner], ~inner)
        return plan

    def _flat_index(self, index, rows, n):
        """``index`` offset by n per row for ``rows`` stacked rows (`_scatter_rows`), cached for the
        network's own index arrays."""
        key = (id(index), rows, n)
        hit = self._flat.get(key)
        if hit is None or hit[0] is not index:
            if len(self._flat) > 32:        # a few batch sizes per dryer in practice
                self._flat.clear()
            hit = self._flat[key] = (index, (np.arange(rows)[:, None] * n + index).ravel())
        return hit[1]

    def freeze_shell(self, z):
        """Evaluate the shell-loss network exactly at ``z`` and use it as a lagged UA coefficient
        (W/K per stage) until `unfreeze_shell`; the physical network solves the shell
        temperature iteratively, which would dominate every residual evaluation."""
        self._shell_ua = None
        *_, Tg, Y = self.split_classes(z)
        Tg_up = self._upstream_gas_temperature(Tg)
        q = self._shell_loss_exact(Tg, Y, Tg_up)
        dT = Tg - self.settings.ambient_temperature
        # the loss is linear in dT inside the band (_near_ambient): its coefficient there is exact
        # at any dT, also at dT = 0 and below (a gas colder than the surroundings gains heat)
        band = dT < SHELL_LINEAR_BAND_K
        if np.any(band):
            edge = np.where(band, self.settings.ambient_temperature + SHELL_LINEAR_BAND_K, Tg)
            q_edge = self._shell_loss_exact_eval(edge, Y, Tg_up)
            self._shell_ua = np.where(band, q_edge / SHELL_LINEAR_BAND_K, q / np.where(band, 1.0, dT))
        else:
            self._shell_ua = q / dT

    def _refreeze_shell(self, z, f):
        """Freeze the shell loss at ``z`` and return ``f`` (the residual at z with the previous
        coefficient, or unfrozen) corrected to the new coefficient: only the gas temperature
        rows change, by the change of the loss over M_g c_s ([`rhs`][rotarydryer.thermal.dryer.ThermalDryer.rhs])."""
        old = self._shell_ua
        self.freeze_shell(z)
        if old is None:
            return self.rhs(0.0, z)
        *_, Tg, Y = self.split_classes(z)
        s = self.settings
        dq = (self._shell_ua - old) * (Tg - s.ambient_temperature)
        f = f.copy()
        k, ng = 3 * self.n_classes * self.n_tanks, self.n_gas
        f[k:k + ng] -= dq / (self.gas_holdup * bal._gas_heat_capacity(Tg, Y, s.mode))
        return f

    def unfreeze_shell(self):
        self._shell_ua = None

    def with_parameters(self, settings=None, feed_rate=None, rpm=None, feed_moisture=None):
        """A copy of this dryer on the same network with new parameter values: ``settings`` (a whole
        [`ThermalSettings`][rotarydryer.thermal.dryer.ThermalSettings]), the wet feed rate (kg/s), the drum speed (rev/min), the feed moisture
        (kg/kg wet); checked as at construction, caches cleared. The network, the section laws and the
        layout are shared (nothing is rebuilt): a study's or sweep's run re-evaluates the coefficients
        at its own values ([`rotarydryer.thermal.studies.perturbed`][rotarydryer.thermal.studies.perturbed], [`rotarydryer.Simulation.steady_state`][rotarydryer.simulation.Simulation.steady_state])."""
        d = copy.copy(self)
        d.settings = copy.copy(self.settings) if settings is None else self._completed(settings)
        for name, value in (("feed_rate", feed_rate), ("rpm", rpm), ("feed_moisture", feed_moisture)):
            if value is not None:
                setattr(d, name, value)
        d.settings.validate()
        d._check_operating_inputs()  # the same checks as when the dryer was built
        d._check_shell()
        d._reset_caches()
        d._check_gas_can_dry()
        if d.dusty:
            d._layout_dust()         # terminal velocities at the new inlet gas; the up-front refusal
        return d

    def rebuilt(self, settings=None, feed_rate=None, rpm=None, **_):
        """This dryer, or its model rebuilt (``self._rebuild``, set by the Simulation that built it) where
        the new ``settings`` and values (those of `with_parameters`; others ignored) change an input that the
        transport network itself depends on (`rotarydryer.cases.build.network_inputs`): the curtains' gas drag of a trajectory
        forward step, the speed (and the beds' feed) of a predictive law. `with_parameters` re-evaluates the
        coefficients on the same network, which holds them at the case's values: a dynamic run's step of the
        gas temperature on Song's pilot drum settled 35 % off the steady state there. The rebuilt model has
        the same tanks and stages (its state continues the run's); it has the other inputs of the case."""
        hook = getattr(self, "_rebuild", None)
        if hook is None:
            return self

        def inputs(st, feed, speed):     # the schedule names of the inputs a network may depend on
            return {"gas_inlet_temperature": st.gas_inlet_temperature, "gas_flow": st.gas_flow,
                    "gas_inlet_humidity": st.gas_inlet_humidity, "rpm": speed, "feed_rate": feed}
        current = inputs(self.settings, self.feed_rate, self.rpm)
        new = inputs(self.settings if settings is None else settings, self.feed_rate if feed_rate is None else feed_rate,
                     self.rpm if rpm is None else rpm)
        moved = {k: float(v) for k, v in new.items() if k in hook.needs and float(v) != float(current[k])}
        if not moved:
            return self
        d = hook(moved)
        if d.n != self.n:
            raise DryerError(f"the inputs {', '.join(sorted(moved))} change the model's layout ({self.n} -> {d.n} "
                             "unknowns): a dynamic run cannot continue its state on it", reason="input")
        return d

    def _reset_caches(self):
        """Forget what was remembered for the previous inputs (after a study changed them in place)."""
        self._shell_ua = None
        self._shell_memo = None
        self._floor_memo = None
        self._transfer_base = None
        self._edge_base = None
        self._batch_values = None
        self._law_cache = {}
        self._law_base = {}

    def rhs(self, t, z):
        """Time derivatives of the state (S, W kg/s; T, T_g K/s; Y 1/s).

        ``z`` of shape (n,) or a batch of states as columns, (n, k) (SciPy's ``vectorized``
        convention, used by the finite-difference Jacobians): the result has the same shape; every
        column equals the single evaluation (the same operations element by element)."""
        z = np.asarray(z, dtype=float)
        if z.ndim == 2:
            if z.shape[1] == 1:
                return self._rhs(z[:, 0])[:, None]
            return self._rhs(np.ascontiguousarray(z.T)).T
        return self._rhs(z)

    def _cell_plan(self):
        """What the compiled cell balance (`rotarydryer.properties._kernels._cell_balance_loop`) needs that the
        network and the layout fix (edges, capped and excess edges, stages, tanks), or None where it does not apply:
        kernels off, size classes or entrainment, the compatibility mode, kinetics the compiled transfer does not
        take (`rotarydryer.thermal.balances._transfer_kernel_parameters`). Then `_rhs` takes the NumPy form."""
        s = self.settings
        key = (s.mode, id(s.kinetics), s.pressure, s.co2_mole_fraction, self.radius, self.n_classes, self.dusty,
               _jit.enabled())
        hit = self._cells       # this dryer's own (copies made by `with_parameters` rebind it, not share it)
        if hit is not None and hit[0] == key and hit[1] is s.kinetics:
            return hit[2]
        plan = None
        if (self.n_classes == 1 and not self.dusty and not self._class_laws and s.mode == "physical"
                and _kernels.compiled("cells") is not None):
            params = bal._transfer_kernel_parameters(s.kinetics, self.radius, s.pressure, s.co2_mole_fraction, 0.9,
                                                     2e-3, self._beam_length)
            if params is not None:
                src, dst, capped, excess, in_ce, _ = self._edge_plan(self.families)
                i64 = np.int64
                ce_excess = np.zeros(in_ce.size, dtype=i64)
                ce_excess[excess[1]] = 1
                plan = dict(
                    src=np.ascontiguousarray(src, dtype=i64), dst=np.ascontiguousarray(dst, dtype=i64),
                    ce_edge=np.ascontiguousarray(in_ce, dtype=i64), ce_excess=ce_excess,
                    gas_tank=np.ascontiguousarray(self.gas_tank, dtype=i64),
                    tank_stage=np.ascontiguousarray(self._tank_stage, dtype=i64),
                    gas_up=np.ascontiguousarray(self.gas_up, dtype=i64),
                    is_bed=np.ascontiguousarray(self.is_bed_stage, dtype=i64),
                    dp=np.ascontiguousarray(self.class_dp[0], dtype=float),
                    holdup=np.ascontiguousarray(self.gas_holdup, dtype=float),
                    transfer=params, coefficients=(ha._KERNEL_COEFFICIENTS, rad._KERNEL_COEFFICIENTS,
                                                   _water._PSAT_COEFFICIENTS),
                    no_base=np.zeros((12, self.n_gas)), no_kiln=np.zeros((1, 0)),
                    kiln_tank=np.concatenate([np.zeros(0, dtype=i64)] + [np.asarray(law.P, dtype=i64)
                                                                          for law, _ in self._kiln_plan]),
                    kiln_stage=np.concatenate([np.zeros(0, dtype=i64)] + [np.asarray(st, dtype=i64)
                                                                           for _, st in self._kiln_plan]),
                    gas_len=np.ascontiguousarray(self.gas_len, dtype=float))
        self._cells = (key, s.kinetics, plan)
        return plan

    def _rhs_compiled(self, z):
        """`_rhs` in one compiled pass over the tanks and stages (`_cell_plan`), or None where it does not apply
        or the kernel declined (solids at the boiling point: the NumPy form names it). The section laws, the kiln
        and rolling-bed areas, the shell loss and the inlet gas are evaluated here first, as by the NumPy form
        (with what they remember for the next call); the same numbers to rounding."""
        plan = self._cell_plan()
        if plan is None:
            return None
        if not np.isfinite(z).all():
            raise DryerError("state became non-finite (solver diverged)", reason="diverged", state=z)
        s = self.settings
        nt, ng = self.n_tanks, self.n_gas
        single = z.ndim == 1
        Z = np.ascontiguousarray(z[None, :] if single else z)
        rows = Z.shape[0]
        S = np.maximum(Z[:, :nt], 1e-15 * self.feed_rate)
        W = np.maximum(Z[:, nt:2 * nt], 0.0)
        m = S + W
        Tg, Y = Z[:, 3 * nt:3 * nt + ng], Z[:, 3 * nt + ng:]
        if single:
            W, m, Tg, Y = W[0], m[0], Tg[0], Y[0]
        k, cap = self._edge_coefficients(W, m)
        kiln = bool(s.kiln_bed_area and s.mode == "physical" and self._kiln_plan)
        kiln_des, kiln_rho = self._kiln_inputs(W, m) if kiln else (plan["no_kiln"], plan["no_kiln"])
        a_bed = np.zeros((rows, ng))         # the rolling beds' areas at their stages (the kernel reads no other)
        if self.is_bed_stage.any():
            a_bed[:, self.is_bed_stage] = self._bed_stage_area(W, m)
        qloss = self._shell_loss(Tg, Y)
        y_in, h_in = self.inlet_gas(Y)
        base = self._transfer_base
        use_base = False
        tkey = (s.kinetics, s.mode, s.pressure, s.co2_mole_fraction, self.radius, self.dry_gas_flow)
        if not single and base is not None and len(base) > 3 and base[2] == tkey:     # a base of this path's
            use_base = True
            b = base[3]
        else:
            b = plan["no_base"]
        feed_s, feed_w = self.feed_rate * (1 - self.feed_moisture), self.feed_rate * self.feed_moisture
        share = float(self.class_feed[0])
        p = _kernels.pack_cells(nt, ng, self.entry, feed_s * share, feed_w * share,
                                (feed_s * s.cp_solids + feed_w * s.cp_water) * s.solids_inlet_temperature * share,
                                s.cp_solids, s.cp_water, 1e-15 * self.feed_rate, self._solids_temperature_ceiling(),
                                s.design_load_smoothing, s.particle_density, self.dry_gas_flow,
                                (EMPTY_TANK_MASS * self.feed_rate * s.cp_solids) * share, ha.Y_MAX, use_base, kiln,
                                self.radius)

        def rows2(x):
            x = np.asarray(x, dtype=float)
            return np.ascontiguousarray(x.reshape(rows, -1))

        def per_row(x):
            a = np.asarray(x, dtype=float)
            if a.ndim == 0:     # one value for every row (a single state's inlet gas): no broadcast view to copy
                return np.full(rows, a)
            return np.ascontiguousarray(np.broadcast_to(a, (rows,)))

        dz = np.empty((rows, self.n))
        rec = np.empty((12, ng))
        q, cx, cy = plan["transfer"]
        ok = _kernels.call("cells", Z, rows2(k), rows2(cap), rows2(a_bed), rows2(kiln_des), rows2(kiln_rho),
                           rows2(qloss), per_row(y_in), per_row(h_in), plan["src"], plan["dst"], plan["ce_edge"],
                           plan["ce_excess"], plan["gas_tank"], plan["tank_stage"], plan["gas_up"], plan["is_bed"],
                           plan["kiln_tank"], plan["kiln_stage"], plan["dp"],
                           np.ascontiguousarray(s.area_scale * self.gas_theta, dtype=float), plan["holdup"],
                           plan["gas_len"], bal._SEG_GRID, bal._THETA_GRID, p, q, cx, cy, *plan["coefficients"], b, dz,
                           rec)
        if not ok:
            return None
        if single:
            # the transfer of this state: the base of the batches that follow (`_transfer`'s record, the same form)
            self._transfer_base = (tuple(rec[i:i + 1] for i in range(5)), tuple(rec[i:i + 1] for i in range(5, 8)),
                                   tkey, rec)
            return dz[0]
        return dz

    def _rhs(self, z):
        """[`rhs`][rotarydryer.thermal.dryer.ThermalDryer.rhs] of one state (n,) or of a batch with the states as rows, (k, n)."""
        fast = self._rhs_compiled(z)
        if fast is not None:
            return fast
        s = self.settings
        d = self.terms(z, products=False)
        S, W, T, Tg, Y = d["Sc"], d["Wc"], d["Tc"], d["Tg"], d["Y"]
        nt = self.n_tanks
        tk = self.gas_tank
        rw, hv = d["rw_c"], d["hv_c"]
        rw_t, qh_t = _scatter_rows(tk, [rw, d["qc_c"] + d["qr_c"] - rw * hv], nt,
                                   lambda rows: self._flat_index(tk, rows, nt))
        dS = d["inS"] - d["outS"]
        dW = d["inW"] - d["outW"] - rw_t
        dU = d["inH"] - d["outH"] + qh_t
        # an empty tank (a cell the cascade overshoots, S -> 0) has no temperature of its own: a virtual
        # heat capacity of EMPTY_TANK_MASS x (the class's share of the) feed rate x 1 s exchanging with the
        # nearest gas stage at a 1 s time constant defines it (the gas temperature); it fades as (virtual/
        # actual heat capacity)^2, so in a tank holding solids its heat flow moves no reported number
        ce = (EMPTY_TANK_MASS * self.feed_rate * s.cp_solids) * self.class_feed[:, None]
        C = S * s.cp_solids + W * s.cp_water
        ce = ce / (1.0 + (C / ce) ** 2)          # fades as (ce/C)^2 once the tank holds solids
        C = C + ce
        dT = (dU - T * (s.cp_solids * dS + s.cp_water * dW) + ce * (Tg[..., None, self._tank_stage] - T)) / C
        Fd = self.dry_gas_flow
        Mg = self.gas_holdup
        rw_g = d["rw"]
        dYm = Fd * (d["Y_up"] - Y) + rw_g
        h, h_wetter = bal._gas_enthalpy_pair(Tg, Y, 1e-4, s.mode)
        h_up = h[..., np.maximum(self.gas_up, 0)]       # the upstream stage's enthalpy (elementwise identical)
        h_up[..., self.gas_order[0]] = d["h_in"]
        dH = Fd * (h_up - h) + self.class_sum(rw * hv) - d["qc"] - d["qr"] - d["qloss"]
        cs = bal._gas_heat_capacity(Tg, Y, s.mode)
        dhdY = (h_wetter - h) / 1e-4
        dY = dYm / Mg
        dTg = (dH / Mg - dhdY * dY) / cs
        lead = dS.shape[:-2]
        return np.concatenate([dS.reshape(lead + (-1,)), dW.reshape(lead + (-1,)), dT.reshape(lead + (-1,)), dTg, dY],
                              axis=-1)

    # ------------------------------------------------------------------ jacobian
    def sparsity(self):
        """Jacobian sparsity pattern (csr, n x n) from the network's edge families and gas stages, per size
        class: a class's flow on an edge depends on its own solids at the source and, where the flow or its
        coefficient is the mixture's (a capped or excess flow min(M, M_des), a section law at the passive
        mixture's mass and moisture), on every class there; a tank's classes depend on each other (the
        bed's area shared by surface) and on the gas of their stage, which depends on them all (with exhaust recycle, the inlet stage's gas reads the outlet stage's humidity)."""
        recycle = self.settings.recycle_fraction > 0
        if self._pattern is not None and self._pattern_recycle == recycle:
            return self._pattern
        nt, ng, nc = self.n_tanks, self.n_gas, self.n_classes
        kk = nc * nt
        own_a, own_b = [], []                  # edge node pairs, class by class
        mix_a, mix_b = [], []                  # edge node pairs, every class with every class
        ctrl_a, ctrl_b = [], []                # a node and the control node of its flows' law
        for f in self.families:
            inside = f.dst >= 0
            pairs = (own_a, own_b) if f.kind == "linear" and f.law is None else (mix_a, mix_b)
            # a flow k(control) b(M_src) (EdgeFamily) moves its source's balances (the diagonal, below) and its
            # destination's: the destination's rows take the source's columns, not the other way round
            pairs[0].append(f.dst[inside])
            pairs[1].append(f.src[inside])
            law = f.law
            if law is not None:      # the coefficient depends on the control (passive) node's mass and moisture
                ctrl = np.broadcast_to(law.P, f.src.shape)
                for node in (f.src, f.dst):
                    ok = node >= 0
                    ctrl_a.append(node[ok])
                    ctrl_b.append(ctrl[ok])
        rows, cols = [], []

        def tank_links(ta, tb, classes, variables):
            # the (row, column) variable pairs ``variables`` (0 S, 1 W, 2 T) of every class pair of each distinct
            # node pair (the families list a pair many times)
            # the distinct pairs, sorted (np.unique's result; it imports numpy.ma, 16 ms of a one-off command)
            pair = np.sort(np.asarray(ta, dtype=np.int64) * nt + tb)
            pair = pair[np.concatenate(([True], pair[1:] != pair[:-1]))] if pair.size else pair
            ta, tb = pair // nt, pair % nt
            var_i, var_j = (np.asarray(v)[:, None, None] for v in zip(*variables))
            c1, c2 = (np.asarray(c)[None, :, None] for c in zip(*classes))
            rows.append((var_i * kk + c1 * nt + ta).ravel())
            cols.append((var_j * kk + c2 * nt + tb).ravel())
        same = [(c, c) for c in range(nc)]
        every = [(c1, c2) for c1 in range(nc) for c2 in range(nc)]
        # a tank's S, W, T depend on its own S, W, T (drying, its heat capacity); a flow's mass and water follow its
        # source's S and W (and its law's control node's), never a temperature, and the heat it carries its source's
        # T: a destination's rows take the source's S and W columns, and its T the source's T; the control node's
        # S and W columns go to the rows of its flows' ends. Until 2026-12-07 every linked pair took all nine
        # (S, W, T) x (S, W, T) entries both ways: Song's colour groups 27 -> 17 (a Jacobian 27 -> 17 batched
        # residuals), MMG's 15 -> 14, Invicta's 18; of 150 states (the start and the steady state of 72 random
        # dryers, 12 of them with size classes, and the three shipped ones) no nonzero entry of a dense
        # finite-difference Jacobian that the old pattern held is outside this one (tests/thermal/test_solver_reuse.py)
        full = [(i, j) for i in range(3) for j in range(3)]
        mass = [(i, j) for i in range(3) for j in range(2)]
        linked = [*mass, (2, 2)]
        tank_links(np.arange(nt), np.arange(nt), every if nc > 1 else same, full)
        if own_a:
            tank_links(np.concatenate(own_a), np.concatenate(own_b), same, linked)
        if mix_a:
            tank_links(np.concatenate(mix_a), np.concatenate(mix_b), every, linked)
        if ctrl_a:
            tank_links(np.concatenate(ctrl_a), np.concatenate(ctrl_b), every, mass)
        k = np.arange(ng)
        tk = self.gas_tank
        gvars = [3 * kk + k, 3 * kk + ng + k]
        tvars = [v * kk + c * nt + tk for v in range(3) for c in range(nc)]
        for g in gvars:
            for h in gvars:
                rows.append(g), cols.append(h)
            for t in tvars:
                rows += [g, t]
                cols += [t, g]
        for law, stages in self._kiln_plan:      # a kiln bed's area: the passive node's mass and moisture
            act = tk[stages]
            for col in [v * kk + c * nt + law.P for v in (0, 1) for c in range(nc)]:
                for row in [3 * kk + stages, 3 * kk + ng + stages] + [v * kk + c * nt + act for v in range(3)
                                                                      for c in range(nc)]:
                    rows.append(row), cols.append(col)
        has_up = self.gas_up >= 0
        for g in gvars:
            for h in (3 * kk + self.gas_up[has_up], 3 * kk + ng + self.gas_up[has_up]):
                rows.append(g[has_up]), cols.append(h)
        if self.dusty:      # a curtain's outflows keep 1 - e(gas of the curtain's stage): their destinations too
            active, stages, out_edges, pos, _ = self._dust_plan
            src_all, dst_all = self._edge_plan(self.families)[:2]
            dst_t = dst_all[out_edges]
            inside = dst_t >= 0
            for g in (3 * kk + stages[pos][inside], 3 * kk + ng + stages[pos][inside]):
                for v in range(3):
                    for c in range(nc):
                        rows.append(v * kk + c * nt + dst_t[inside]), cols.append(g)
        if nc > 1:          # an empty tank's temperature anchor: the nearest stage's gas (every tank)
            for c in range(nc):
                rows.append(2 * kk + c * nt + np.arange(nt)), cols.append(3 * kk + self._tank_stage)
        if recycle:      # the inlet gas's humidity and enthalpy follow the exhaust humidity (inlet_gas)
            first = self.gas_order[0]
            rows.append(np.array([3 * kk + first, 3 * kk + ng + first]))
            cols.append(np.full(2, 3 * kk + ng + self.gas_outlet_stage))
        r, c = np.concatenate(rows), np.concatenate(cols)
        pat = sp.csr_matrix((np.ones(r.size), (r, c)), shape=(self.n, self.n))
        pat.data[:] = 1.0
        pat.sort_indices()
        # the greedy grouping loops over the columns in Python: reuse it for the same pattern (the
        # runs of a study or a sweep build one dryer each, all with the same network)
        key = (self.n, pat.indptr.tobytes(), pat.indices.tobytes())
        groups = _GROUPS_CACHE.get(key)
        if groups is None:
            groups = column_groups(pat)
            _GROUPS_CACHE[key] = groups
            while len(_GROUPS_CACHE) > 16:
                _GROUPS_CACHE.pop(next(iter(_GROUPS_CACHE)))
        self._pattern = pat
        self._pattern_recycle = recycle
        self._groups = groups
        self._fd_plan = FDPlan(pat, groups)
        return pat

    def jacobian(self, z, f0=None):
        """The forward-difference Jacobian of `rhs` at ``z`` on the dryer's sparsity pattern (CSC; ``f0`` = rhs(0, z)
        where known)."""
        self.sparsity()
        return self._fd_plan.matrix(self._jacobian_data(z, f0))

    def _jacobian_data(self, z, f0=None):
        """`jacobian`'s entries in its pattern's order (`FDPlan.jacobian_data`), the matrix not built."""
        self.sparsity()
        z = np.asarray(z, dtype=float)
        if f0 is None:
            f0 = self.rhs(0.0, z)
        floor = self._scale() * 1e-8
        # the masses' floor follows the feed, not the residual scale's 1 kg floor: a dryer fed grams per hour
        # holds milligrams of water, which a step of 2e-9 kg would overshoot hundreds of times (its Newton
        # then converged linearly and stalled); the same for any feed above 0.1 kg/s
        k2 = 2 * self.n_classes * self.n_tanks
        floor[:k2] *= min(1.0, self.feed_rate * 10.0)
        if self.n_classes > 1:      # a class's tanks may hold traces only (the fines a curtain loses as dust): a
            k = 2 * self.n_classes * self.n_tanks       # step of its own size for their solids and water
            floor[:k] *= 1e-6
        step = np.maximum(np.abs(z) * 1e-7, floor)
        return self._fd_plan.jacobian_data(lambda x: self.rhs(0.0, x), z, step, np.asarray(f0, dtype=float))

    def _scale(self):
        """The residual scale of each state (kg, kg, K, K, kg/kg per s: the steady-state test's), read-only; kept for
        the feed rate it was made for (a solve asks for it at every Jacobian)."""
        k, ng = self.n_classes * self.n_tanks, self.n_gas
        key = (self.feed_rate, k, ng)
        memo = getattr(self, "_scale_memo", None)
        if memo is not None and memo[0] == key:
            return memo[1]
        msc = np.maximum(self.feed_rate * 10.0, 1.0)
        sc = np.concatenate([np.full(k, msc), np.full(k, msc * 0.2), np.full(k, 100.0), np.full(ng, 100.0),
                             np.full(ng, 0.05)])
        sc.flags.writeable = False
        self._scale_memo = (key, sc)
        return sc

    # ------------------------------------------------------------------ initial guess
    def _transport_start(self):
        """The transport model's steady holdups per tank at this dryer's feed rate, kg: the network's own
        steady state (its coefficients are fixed), solved once for every dryer on it (a study's or a
        sweep's runs share the network, ThermalDryer.with_parameters)."""
        net = self.model.network
        start = getattr(net, "_thermal_start", None)
        if start is None:
            try:
                start = net.steady_state(tol=START_TOLERANCE)
            except ValueError as exc:
                raise DryerError(f"no transport steady state for the start: {exc}", reason="no_steady_state") from exc
            start.setflags(write=False)
            net._thermal_start = start
        return start * (self.feed_rate / max(self.model.feed_rate, 1e-300))

    def _transport_holdup(self):
        """The transport model's steady holdups per tank at this dryer's own feed rate, kg: the network's
        steady state with its feed scaled to this dryer's (a dryer from `with_parameters` shares the network
        built at another feed rate, and the holdups of a loading-dependent law are not proportional to the
        feed). What a quantity of the model (not only the start) takes from the transport holdup uses this,
        so that a dryer built at a feed rate and one moved to it are the same model. Cached on the network
        per feed rate."""
        net = self.model.network
        ratio = self.feed_rate / max(self.model.feed_rate, 1e-300)
        if ratio == 1.0:
            return self._transport_start()
        cache = net.__dict__.setdefault("_thermal_holdups", {})
        if ratio not in cache:
            base_feed = net.feed
            guess = net.initial_guess
            try:
                net.feed = base_feed * ratio
                net.initial_guess = self._transport_start()
                m = net.steady_state(tol=START_TOLERANCE)
            except ValueError as exc:
                raise DryerError(f"no transport steady state at the feed rate {self.feed_rate:g} kg/s: {exc}",
                                 reason="no_steady_state") from exc
            finally:
                net.feed, net.initial_guess = base_feed, guess
            m.setflags(write=False)
            if len(cache) > 64:
                cache.clear()
            cache[ratio] = m
        return cache[ratio]

    def initial_state(self, dust_out=True):
        """Transport-only steady holdups (assumed moisture profile), linear solids/gas temperature guesses; with
        entrainment, each class's holdups with the dust taken out (`_dusty_start`; ``dust_out=False``: the feed's
        share of every tank, the basis of `_with_dust_hint`'s estimate)."""
        s = self.settings
        m = self._transport_start()
        x = np.interp(self.position, [0, self.length], [self.feed_moisture, max(self.feed_moisture - 0.04,
                                                                               0.5 * self.feed_moisture)])
        S = np.maximum(m * (1 - x), 1e-6 * self.feed_rate)
        W = m * x
        T = np.interp(self.position, [0, 0.3 * self.length, self.length],
                      [s.solids_inlet_temperature, 40.0, 45.0])
        share = self.class_feed[:, None]        # every class in the tanks as in the feed
        S, W = S * share, W * share
        gp = self.gas_position if s.gas_direction == "co-current" else self.length - self.gas_position
        Tout = max(s.solids_inlet_temperature + 20.0, 0.3 * s.gas_inlet_temperature)
        Tg = np.interp(gp, [0, self.length], [s.gas_inlet_temperature, Tout])
        Y = np.interp(gp, [0, self.length], [self.gas_inlet_Y, self.gas_inlet_Y + 0.05])
        T = np.tile(T, (self.n_classes, 1))
        if self.dusty and dust_out:
            S, W = self._dusty_start(S, W, T, Tg, Y)
        return np.concatenate([S.ravel(), W.ravel(), T.ravel(), Tg, Y])

    def _dusty_start(self, S, W, T, Tg, Y):
        """The start's holdups per class (classes, tanks) with the dust taken out: each class's flows linear in
        its own holdup at the coefficients of the start's mixture (every edge's flow per kg of its source, the
        dust edges' too, at the start's gas), and that linear network's steady state for the class's share of
        the feed, one sparse solve per class; W keeps the start's moisture profile. Without it the fines start
        with the feed's share of every tank, which the gas then has to empty: the pseudo-transient solve of a
        dryer whose fines leave as dust stalled there and the transient march took minutes (20 classes, 174 s)."""
        src, dst, F = self.flows(S, W, T, gas=(Tg, Y))
        mc = S + W
        nt, keep = self.n_tanks, dst >= 0
        feed = np.zeros(nt)
        feed[self.entry] = 1.0
        x = W / np.maximum(mc, 1e-300)
        for c in range(self.n_classes):
            rate = F[c] / np.maximum(mc[c, src], 1e-300)           # kg/s per kg of the source's class c
            out = np.bincount(src, weights=rate, minlength=nt)
            a = sp.csc_matrix((rate[keep], (dst[keep], src[keep])), shape=(nt, nt)) - sp.diags(out, format="csc")
            try:
                with warnings.catch_warnings():     # a singular network (a class with no way out): NaN, kept as it was
                    warnings.simplefilter("ignore")
                    m = spsolve(a, -feed * (self.feed_rate * float(self.class_feed[c])))
            except (RuntimeError, ValueError):
                continue
            if not np.all(np.isfinite(m)):
                continue
            m = np.maximum(m, 0.0)
            S[c] = np.maximum(m * (1.0 - x[c]), 1e-6 * self.feed_rate * float(self.class_feed[c]))
            W[c] = m * x[c]
        return S, W

    # ------------------------------------------------------------------ steady state
    def steady_state(self, z0=None, max_iter=300, tol=1e-11, dt0=20.0, verbose=None, factorization=None,
                     progress=None, march=True):
        """Coupled steady state by pseudo-transient continuation + Newton (module docstring); where
        that fails (and ``march``), a transient march (BDF with error control at MARCH_RTOL, [`simulate`][rotarydryer.thermal.dryer.ThermalDryer.simulate]) from the same
        start to the first of MARCH_HORIZONS solids residence times, then Newton again from the marched state;
        where that fails too, the march carries on to the next horizon (a march that stalls is not repeated).

        Converged when the scaled residual max |f_i|/scale_i < ``tol`` (1/s) and the balances
        close; raises [`DryerError`][rotarydryer.thermal.dryer.DryerError] (reason ``"no_steady_state"``) with ``state`` = last iterate
        of the first attempt. The other arguments are those of `_pseudo_transient`.
        """
        self._refuse_unresolved_feed()
        try:
            return self._polished(self._pseudo_transient(z0, max_iter, tol, dt0, verbose, factorization, progress),
                                  tol, dt0)
        except DryerError as exc:
            if exc.reason != "no_steady_state" or exc.state is None:
                raise
            self._refuse_if_entrained(exc)      # a march would end at the same refusal
            if not march:
                raise
            first = exc
        z = self.initial_state() if z0 is None else np.array(z0, dtype=float)
        mrt = float(np.sum(z[:2 * self.n_classes * self.n_tanks])) / max(self.feed_rate, 1e-300)
        marched_s = 0.0
        for horizon in MARCH_HORIZONS:      # each march carries on from where the last one ended
            t_end = max(horizon * mrt, 60.0)
            try:
                marched = self.simulate(z, t_end - marched_s, rtol=MARCH_RTOL, atol=self._scale() * (MARCH_RTOL * 1e-2),
                                        max_calls=MARCH_MAX_CALLS)
                z = np.asarray(marched.states, dtype=float)[:, -1]
            except (RuntimeError, ValueError, FloatingPointError):     # DryerError is a ValueError
                break           # the integration stalled (or failed): a longer one from the same state would too
            marched_s = t_end
            try:
                ss = self._pseudo_transient(self._projected(z), max_iter, tol, dt0, None, None, progress)
            except (RuntimeError, ValueError, FloatingPointError):
                continue
            ss = self._polished(ss, tol, dt0)
            ss.marched_s = marched_s
            return ss
        first = self._with_recycle_hint(first)
        raise self._with_dust_hint(first) if self.dusty else first

    def _refuse_unresolved_feed(self):
        """Refuse, before the solve, a feed below `MIN_FEED_TO_GAS` of the gas flow (reason ``"input"``, exit 2): a
        steady state the solver cannot resolve, not a dryer's operating point (it ended as "no steady state" after
        up to 25 s, exit 1)."""
        g = float(self.settings.gas_flow)
        if g > 0.0 and self.feed_rate < MIN_FEED_TO_GAS * g:
            raise DryerError(f"operating.feed_rate = {self.feed_rate:.3g} kg/s is below {MIN_FEED_TO_GAS:g} of gas.flow = "
                             f"{g:.4g} kg/s: the solids' heat and water flows vanish beside the gas's, below what the "
                             f"coupled solver resolves; give a feed of at least {MIN_FEED_TO_GAS * g:.2g} kg/s (or less "
                             "gas)", reason="input")

    def _refuse_if_entrained(self, failure):
        """Raise the entrainment refusal (reason ``"entrained"``, `check_entrainment`'s) for a failed solve of a
        dusty dryer whose last iterate closes its water and energy balances (to the acceptance test's BALANCE_ACCEPT)
        and loses more than DUST_REFUSE_FRACTION of the feed as dust there: the gas carries off nearly the whole
        feed, and the residual left is that of the traces it leaves in the tanks (user dryers stalled on the
        temperatures of classes holding 1e-15 to 1e-11 kg, their balances closed to 1e-9 and 100.0 % of the
        feed in the dust). A converged state of that kind gets the same refusal; a failure with its balances
        open is left to `_with_dust_hint` (its iterate's dust share is not the dryer's)."""
        st = failure.state
        if not self.dusty or not isinstance(st, ThermalSteadyState) or max(st.water_balance_error,
                                                                           st.energy_balance_error) > BALANCE_ACCEPT:
            return
        lost = dust_share(st)
        if lost > DUST_REFUSE_FRACTION:
            raise DryerError(f"entrainment: {lost:.1%} of the feed leaves as dust with the exhaust at gas.flow = "
                             f"{self.settings.gas_flow:g} kg/s: nothing is left as a product (the solver's last iterate, "
                             "its water and energy balances closed; the traces the gas leaves in the tanks were not "
                             "resolved); lower gas.flow or give a coarser particle_size", reason="entrained",
                             state=st) from None

    def _with_recycle_hint(self, failure):
        """A failed solve of a dryer that recycles exhaust (``gas.recycle_fraction``), with the recycle named as the
        likely cause where the last iterate ran the gas humidity up to the top of the humid-air range: only the
        fraction 1 - r of the gas leaves, and it has to carry out all the water evaporated (a template dryer holds
        0.40 kg/kg in its exhaust at r = 0.9; at 0.99 no humid air can carry its water)."""
        r = self.settings.recycle_fraction
        z = getattr(failure.state, "state", None)
        if not r or z is None:
            return failure
        Y = self.split_classes(np.asarray(z, dtype=float))[4]
        if not float(np.max(Y)) >= RECYCLE_HINT_HUMIDITY * ha.Y_MAX:
            return failure
        hint = (f"; the recycled exhaust is the likely cause: with gas.recycle_fraction = {r:.10g} only {1 - r:.3g} of "
                f"the gas leaves the loop and carries out all the water evaporated; the iterations ran the gas "
                f"humidity up to the top of the humid-air range ({ha.Y_MAX:g} kg/kg): lower gas.recycle_fraction")
        return _hinted(failure, hint)

    def _with_dust_hint(self, failure):
        """A failed solve of a dryer with dust, with the dust named as the likely cause where the gas carries
        the curtains off much faster than the feed refills them: at the solver's start (the transport holdups,
        the gas cooling along the drum as `initial_state` guesses) or, failing that, at its last iterate (a gas
        that the iterations made wetter, and so faster, carried off every class of a feed whose finest class
        alone went at the start). A class whose curtains lose r times its feed rate per second keeps about
        exp(-r) of it through the drum's cascades (each cascade keeps 1 - e, and r sums e over them); where
        that leaves less than 1 - DUST_REFUSE_FRACTION of the feed, most or all of it leaves as dust, a state
        without a product that the solver may not settle (converged runs of that kind are refused by
        `check_entrainment`). A hint, not a refusal: neither state is the dryer's (the start's gas is a guess,
        hotter and so faster than a wet feed's drum; the last iterate did not converge), and the up-front
        refusal (`_refuse_all_entrained`) takes the coldest gas to be certain."""
        ng, k = self.n_gas, 3 * self.n_classes * self.n_tanks
        feed = self.feed_rate * (1.0 - self.feed_moisture) * self.class_feed

        def carried_off(z):     # (rate per class's feed, share of the feed lost) at state z, or None
            try:
                rate = np.asarray(self.terms(np.asarray(z, dtype=float))["dust_S_c"], float) / np.maximum(feed, 1e-300)
            except (ValueError, FloatingPointError):
                return None
            lost = float(np.sum(self.class_feed * -np.expm1(-rate)))
            return (rate, lost) if lost > DUST_REFUSE_FRACTION and np.all(np.isfinite(rate)) else None
        last = getattr(failure.state, "state", None)
        # the curtains of the feed's share of the transport holdups: the loss per pass, r, the estimate sums (the
        # solver's start has the dust taken out already, `_dusty_start`)
        found = next(((where, z, dust) for where, z in (("at the solver's start", self.initial_state(dust_out=False)),
                                                        ("at the solver's last iterate", last))
                      if z is not None and (dust := carried_off(z)) is not None), None)    # the first that shows it
        if found is None:
            return failure
        where, z, (rate, lost) = found
        hint = (f"; the dust is the likely cause: {where} (the gas cooling from "
                f"{self.settings.gas_inlet_temperature:.4g} to {float(np.min(z[k:k + ng])):.4g} degC) the gas carries the "
                f"curtains' solids off at {float(np.min(rate)):.3g} to {float(np.max(rate)):.3g} times each size class's "
                f"feed rate, enough to take most or all of the feed (about {lost:.1%} at that gas) with the exhaust: "
                f"lower gas.flow (now {self.settings.gas_flow:g} kg/s) or give a coarser particle_size")
        return _hinted(failure, hint)

    def _polished(self, ss, tol, dt0):
        """``ss``, or where its water or energy balance is open by more than BALANCE_POLISH (the
        residual test met at a state a little off the root), the state a few Newton steps further
        with a hundredfold tighter residual test."""
        if max(ss.water_balance_error, ss.energy_balance_error) <= BALANCE_POLISH:
            return ss
        try:
            better = self._pseudo_transient(ss.state, 20, tol * 1e-2, dt0 * 1e6, None, ss.factorization, None)
        except DryerError:
            return ss
        better.iterations += ss.iterations
        return better

    def _pseudo_transient(self, z0=None, max_iter=300, tol=1e-11, dt0=20.0, verbose=None, factorization=None,
                          progress=None):
        """Coupled steady state by pseudo-transient continuation + Newton (module docstring).

        Converged when the scaled residual max |f_i|/scale_i < ``tol`` (1/s) and the balances
        close; raises [`DryerError`][rotarydryer.thermal.dryer.DryerError] (reason ``"no_steady_state"``) with ``state`` = last iterate.
        ``factorization``: the `ThermalSteadyState.factorization` of a nearby steady state
        (same network, e.g. the previous run of a study, with ``z0`` its state): chord steps with
        it while the residual falls at least fourfold per step, then the solver's own Jacobians.
        The converged state is the same; only the path changes. ``progress(iteration, scaled
        residual, pseudo-time step s)`` is called after each step (``verbose=True``, deprecated,
        logs them at INFO level on this module's logger).
        """
        if verbose is not None:       # deprecated (it printed): the library never prints
            warnings.warn("ThermalDryer.steady_state(verbose=...) is deprecated: pass progress=callable(iteration, "
                          "scaled residual, pseudo-time step)", DeprecationWarning, stacklevel=2)
            if verbose and progress is None:
                def progress(it, norm, dt):
                    _log.info("iteration %d: scaled residual %.3g, pseudo-time step %.3g s", it, norm, dt)
        t0 = time.perf_counter()
        z = self.initial_state() if z0 is None else np.array(z0, dtype=float)
        sc = self._scale()
        self.freeze_shell(z)
        f = self.rhs(0.0, z)          # the frozen shell loss equals the exact one at z
        norm = self._residual_norm(f, z, sc)
        dt = dt0
        J = lu = None                 # Jacobian at z (shell frozen at z; its entries) and the factorised I/dt - J
        borrowed = factorization is not None and factorization.shape == (self.n, self.n)
        if borrowed:
            J, lu = "borrowed", factorization
        it = 0
        best, best_it = norm, 0       # the lowest residual so far and its iteration (STALL_ITERATIONS)
        steps: list = []              # the full steps taken on this factorisation (Broyden's s_j), scaled
        newton = False                # the factorisation's pseudo-time step is a Newton matrix's
        for it in range(1, max_iter + 1):
            if J is None:
                J = self._jacobian_data(z, f)
                lu = None
            if lu is None:
                steps = []
                try:
                    lu = self._fd_plan.shifted_lu(J, 1.0 / dt)     # I/dt - J (the first one's column order)
                except RuntimeError:
                    dt *= 0.2
                    continue
                newton = dt >= BROYDEN_MIN_DT
            dz = lu.solve(f)
            secant = bool(steps) and (newton or borrowed)
            if secant:
                corrected = _broyden_step(steps, dz / sc)
                if corrected is None:       # the plain chord step
                    steps, secant = [], False
                else:
                    dz = corrected * sc
            dz, shortened = self._radius_step(dz, sc)
            zn = self._bounded_step(z, dz)
            ok = self._admissible(zn)
            fn, nn = None, np.inf
            if ok:
                try:
                    fn = self.rhs(0.0, zn)
                    nn = self._residual_norm(fn, zn, sc)
                except DryerError:
                    ok = False
            if secant and (not ok or not np.isfinite(nn) or nn > norm):
                steps = []                # the secant-corrected step did not help: a plain chord step instead
                continue
            if borrowed and (not ok or not np.isfinite(nn) or nn > norm):
                J = lu = None         # the nearby factorisation does not fit: the solver's own Jacobian
                borrowed = False
                continue
            if (GAS_CORRECTION and ok and nn > ACCEPT_GROWTH * norm and dt > dt0 and not borrowed
                    and self.n_classes == 1):
                # the growth test would refuse the step: the gas caught up with it first (GAS_CORRECTION); a
                # step so changed is not a full step of this factorisation (no secant memory, no longer dt)
                got = self._gas_corrected(J, zn, fn, sc)
                if got is not None and got[2] < nn:
                    zn, fn, nn = got
                    shortened = True
            if not ok or not np.isfinite(nn) or (nn > ACCEPT_GROWTH * norm and dt > dt0):
                dt *= 0.25            # the same state: only the pseudo-time step changes, J stays
                lu = None
                if dt < 1e-6:
                    break
                continue
            # a full step (no component held back by the bounds or the step radius) continues the secant
            # corrections of the chord steps on this factorisation; a shortened step starts them afresh
            if len(steps) < BROYDEN_MEMORY and not shortened and np.array_equal(zn, z + dz):
                steps.append((zn - z) / sc)
            else:
                steps = []
            # the shell coefficient refreshed at the new state: f is then the exact residual there
            # (the frozen loss equals the exact one at the state it was frozen at)
            z, f = zn, self._refreeze_shell(zn, fn)
            nn = self._residual_norm(f, z, sc)
            ratio = nn / max(norm, 1e-300)
            # switched evolution relaxation (Mulder & Van Leer (1985); Kelley & Keyes (1998)): the pseudo-time
            # step grows as the residual falls (here by a further 1.5 a step, at most tenfold); while the step
            # radius binds, it may shrink but not grow (a longer step of the same matrix would be cut again,
            # and the matrix of a longer pseudo-time step is Newton's, whose direction far from the root is
            # what overshoots)
            change = min(max(1.0 / max(ratio, 1e-300), 0.5), 10.0)
            dt = min(dt * (min(change, 1.0) if shortened else change * 1.5), 1e12)
            norm = nn
            if progress is not None:
                progress(it, norm, dt)
            if norm < tol or self._residual_norm(f, z, sc, EMPTY_TANK_MASS_ACCEPT) < tol:
                break
            if norm < STALL_FACTOR * best:
                best, best_it = norm, it
            elif it - best_it >= STALL_ITERATIONS and best < tol * ACCEPT_AFTER_MAX_ITER:
                break       # stalled where the last iterations would end: the same test decides, now
            # converging fast (the residual fell 100-fold): keep the factorisation for a chord step
            # instead of a new Jacobian (the fixed point f = 0 is the same for any pseudo-time
            # step); a step that falls less recomputes it
            if borrowed:
                if not ratio < BORROWED_RATIO:
                    J, borrowed = None, False
            elif not ratio < (CHORD_RATIO if self.n_classes == 1 else CHORD_RATIO_CLASSES):
                J = None
        self.unfreeze_shell()
        norm = min(norm, self._residual_norm(f, z, sc, EMPTY_TANK_MASS_ACCEPT))
        ss = ThermalSteadyState(self, z, iterations=it, residual=norm, seconds=time.perf_counter() - t0)
        ss.factorization = lu
        if (norm >= tol * ACCEPT_AFTER_MAX_ITER or ss.water_balance_error > BALANCE_ACCEPT
                or ss.energy_balance_error > BALANCE_ACCEPT):
            raise DryerError(f"no steady state reached: scaled residual {norm:.3g} after {it} iterations "
                             f"(water balance error {ss.water_balance_error:.2g}, energy {ss.energy_balance_error:.2g}); "
                             f"{self._where_unsolved(f, z, sc)}", reason="no_steady_state", state=ss)
        return ss

    def _gas_corrected(self, J, zn, fn, sc):
        """(state, residual, scaled residual norm) after one Newton step of the gas alone from ``zn``, the solids
        held: the gas temperatures and humidities solve J_gg dz_g = -f_g(zn) on the gas block of the Jacobian
        ``J`` (the solver's current one's entries: of the iterate the step left or, after chord steps, an earlier one), the step
        bounded as any other (`_radius_step`,
        `_bounded_step`). A nonlinear elimination of the fast states (Lanzkron, Rose & Wilkes (1996)) taken once,
        where a step would be refused (GAS_CORRECTION). None where the block is singular or the state is not
        admissible."""
        k = 3 * self.n_classes * self.n_tanks
        try:
            M = self._fd_plan.matrix(J) if isinstance(J, np.ndarray) else J     # its entries, or the matrix
            dg = splu(M[k:, k:].tocsc()).solve(-fn[k:])
        except RuntimeError:        # a singular gas block
            return None
        if not np.all(np.isfinite(dg)):
            return None
        dz = np.zeros_like(zn)
        dz[k:] = dg
        dz, _ = self._radius_step(dz, sc)
        zc = self._bounded_step(zn, dz)
        if not self._admissible(zc):
            return None
        try:
            fc = self.rhs(0.0, zc)
        except DryerError:
            return None
        return zc, fc, self._residual_norm(fc, zc, sc)

    def _where_unsolved(self, f, z, sc) -> str:
        """Where a failed solve's largest scaled residual (`_residual_norm`'s weighting) sits, one phrase for
        its error: the state (a class's dry solids, water or temperature in a tank, or the gas at a stage)
        and its place; for a size class the gas has all but emptied there (less than `TRACE_CLASS_HOLDUP`
        seconds of that class's dry feed), that, and the keys that avoid solving for it."""
        c, nt = self.n_classes, self.n_tanks
        k = c * nt
        i = int(np.argmax(self._scaled_residuals(f, z, sc)))
        if i >= 3 * k:
            g = (i - 3 * k) % self.n_gas
            what = "temperature" if i < 3 * k + self.n_gas else "humidity"
            return (f"the largest residual is the gas {what} at stage {g + 1} of {self.n_gas} "
                    f"({self.gas_section[g]}, {float(self.gas_position[g]):.2f} m)")
        block, j = divmod(i, k)
        cls, tank = divmod(j, nt)
        what = ("dry solids", "water", "temperature")[block]
        of = f" of size class {cls + 1} of {c} ({float(self.class_diameter[cls]) * 1e6:.0f} um)" if c > 1 else ""
        text = (f"the largest residual is the solids {what}{of} in tank {tank + 1} of {nt} "
                f"({self.tank_section[tank]}, {float(self.position[tank]):.2f} m)")
        held = float(z[cls * nt + tank])
        dry_feed = self.feed_rate * (1.0 - self.feed_moisture) * float(self.class_feed[cls])
        if c > 1 and held < TRACE_CLASS_HOLDUP * dry_feed:
            text += (f", where the gas has carried off nearly all of that class ({held:.2g} kg held): a class the gas "
                     "empties is hard to resolve; fewer or coarser classes (particle_size.classes, particle_size.d50 "
                     "or the sieve analysis) or less gas (gas.flow) avoid it")
        return text

    def _residual_norm(self, f, z, sc, empty=EMPTY_TANK_MASS_NORM):
        """Scaled residual max |f_i|/scale_i of the steady-state test (`_scaled_residuals`; in one compiled pass where
        the kernels are in use, `rotarydryer.properties._kernels._step_norm_loop`: the same number)."""
        if _flat64(f, z, sc) and _kernels.compiled("step_norm") is not None:
            s = self.settings
            out = np.empty(1)
            p = np.array((self.n_classes * self.n_tanks, s.cp_solids, s.cp_water, empty * self.feed_rate * s.cp_solids))
            if _kernels.call("step_norm", f, z, sc, p, out):
                return float(out[0])
        return float(np.max(self._scaled_residuals(f, z, sc, empty)))

    def _scaled_residuals(self, f, z, sc, empty=EMPTY_TANK_MASS_NORM):
        """|f_i|/scale_i of the steady-state test, the temperature rate of a tank weighted by its heat
        capacity up to ``empty`` x feed rate x 1 s of solids (EMPTY_TANK_MASS_NORM; the heat-flow
        residual, W, of a nearly empty tank is what its balance can resolve; its K/s is a ratio of two
        vanishing numbers). At any tank holding solids the test is the plain one."""
        r = np.abs(f) / sc
        k = self.n_classes * self.n_tanks
        S, W = z[:k], z[k:2 * k]
        s = self.settings
        c_floor = empty * self.feed_rate * s.cp_solids      # of the whole feed, for every class
        w = np.minimum(1.0, np.maximum(S * s.cp_solids + W * s.cp_water, 0.0) / c_floor)
        r[2 * k:3 * k] *= w
        return r

    def _radius_step(self, dz, sc):
        """(``dz`` shortened along its direction so that no temperature or humidity moves more than
        STEP_RADIUS times its scale, whether it was shortened): a fixed bound on the pseudo-transient
        step in the scaled largest-component norm (the masses are bounded by `_bounded_step`)."""
        k = 2 * self.n_classes * self.n_tanks
        if _flat64(dz, sc) and _kernels.compiled("step_radius") is not None:   # the same numbers, compiled
            out, big = np.empty_like(dz), np.empty(1)
            if _kernels.call("step_radius", dz, sc, np.array((k, STEP_RADIUS)), out, big):
                return (out, True) if big[0] > STEP_RADIUS else (dz, False)
        big = float(np.max(np.abs(dz[k:]) / sc[k:]))
        return (dz * (STEP_RADIUS / big), True) if big > STEP_RADIUS else (dz, False)

    def _bounded_step(self, z, dz):
        """``z + dz`` with the dry solids, the water, the temperatures and the gas humidity kept inside
        their admissible range by a fraction-to-boundary rule (interior-point practice, Nocedal & Wright
        (2006) Eq. 19.9, per component): a component the Newton step would take below zero (or past
        its bound) moves to a fifth of its distance instead; the humidity is projected onto zero
        (zero is admissible: a dry gas over a dry feed). The water may go half the admissibility
        margin, 5e-10 of the feed, below zero: a bone-dry product's steady state can hold W a
        rounding below zero, which the balances read as zero. Elsewhere the step is Newton's own, so the converged state is the same. A steady state
        with an empty tank (a cell the cascade overshoots) or a dry product lies on that boundary: the
        iterates approach it geometrically instead of stalling on rejected steps."""
        if _flat64(z, dz) and _kernels.compiled("step_bounded") is not None:    # the same operations, compiled
            zn = np.empty_like(z)
            if _kernels.call("step_bounded", z, dz, self._step_parameters(0.5e-9 * self.feed_rate), zn):
                return zn
        zn = z + dz
        S, W, T, Tg, Y = self.split_classes(z)
        Sn, Wn, Tn, Tgn, Yn = self.split_classes(zn)
        np.maximum(Sn, 0.2 * S, out=Sn)
        np.maximum(Wn, np.minimum(0.2 * W, W) - 0.5e-9 * self.feed_rate, out=Wn)
        np.maximum(Yn, 0.0, out=Yn)      # a humidity may reach zero (dry gas, nothing evaporates)
        # the temperatures and the humidity's top the same way, towards the bounds of _admissible
        lo_t, hi_t, lo_g, hi_g, hi_y = self._state_bounds()
        np.minimum(Yn, np.maximum(hi_y - 0.2 * (hi_y - Y), Y), out=Yn)
        np.maximum(Tn, np.minimum(lo_t + 0.2 * (T - lo_t), T), out=Tn)
        np.minimum(Tn, np.maximum(hi_t - 0.2 * (hi_t - T), T), out=Tn)
        np.maximum(Tgn, np.minimum(lo_g + 0.2 * (Tg - lo_g), Tg), out=Tgn)
        np.minimum(Tgn, np.maximum(hi_g - 0.2 * (hi_g - Tg), Tg), out=Tgn)
        return zn

    def _state_bounds(self):
        """(solids T low, high, gas T low, high, humidity high) of `_admissible`, each a
        rounding inside (degC, kg/kg)."""
        s = self.settings
        eps = 1e-9
        return (-5.0 + eps, max(150.0, s.gas_inlet_temperature + 5.0) - eps, self._gas_temperature_floor() + eps,
                650.0 - eps, ha.Y_MAX * (1 - eps))

    def _gas_temperature_floor(self):
        """Lowest admissible gas temperature, degC: 30 K below the coldest of the ambient (leaks,
        shell), the feed and the inlet gas's wet-bulb temperature (a hot, dry gas evaporating water
        from a warm feed cools towards its adiabatic saturation temperature, below both), and inside
        the humid-air range. The margin is wide: the drying laws cool wet solids, and the gas with
        them, below the inlet gas's wet bulb (16 K below in a sampled Invicta case); the bound only
        keeps the iterates physical (`_bounded_step`)."""
        s = self.settings
        key = (s.ambient_temperature, s.solids_inlet_temperature, s.gas_inlet_temperature, self.gas_inlet_Y, s.pressure)
        if self._floor_memo is None or self._floor_memo[0] != key:
            t_gas, y_gas = min(s.gas_inlet_temperature, ha.T_MAX_C), min(max(self.gas_inlet_Y, 0.0), ha.Y_MAX)
            cold = min(s.ambient_temperature, s.solids_inlet_temperature)
            try:
                if cold <= t_gas and not ha.wet_bulb_below(t_gas, y_gas, cold, s.pressure):
                    wb = cold       # the wet bulb is not the coldest: one evaluation of its balance, not its root
                else:
                    wb = float(ha.wet_bulb_temperature(t_gas, y_gas, s.pressure))
            except ValueError:
                wb = ha.T_MIN_C
            self._floor_memo = (key, max(ha.T_MIN_C + 1.0, min(s.ambient_temperature, s.solids_inlet_temperature, wb) - 30.0))
        return self._floor_memo[1]

    def _projected(self, z):
        """``z`` moved into the admissible states (`_admissible`): a marched state, whose integration at a loose
        tolerance leaves the traces of a fine class a rounding below zero (the tanks its curtains empty into
        the exhaust), starts Newton from the nearest admissible one (a copy; the others unchanged)."""
        z = np.array(z, dtype=float)
        S, W, T, Tg, Y = self.split_classes(z)
        lo_t, hi_t, lo_g, hi_g, hi_y = self._state_bounds()
        margin = 1e-6        # K and kg/kg inside the bounds
        np.maximum(S, EMPTY_TANK_MASS * 1e-3 * self.feed_rate, out=S)
        np.maximum(W, 0.0, out=W)
        np.clip(T, lo_t + margin, hi_t - margin, out=T)
        np.clip(Tg, lo_g + margin, hi_g - margin, out=Tg)
        np.clip(Y, 0.0, hi_y - margin, out=Y)
        return z

    def _step_parameters(self, water):
        """(tanks x classes, gas stages, `_state_bounds`, ``water``) of the compiled step kernels
        (`rotarydryer.properties._kernels._step_bounded_loop`, `_step_admissible_loop`)."""
        return np.array((self.n_classes * self.n_tanks, self.n_gas, *self._state_bounds(), water))

    def _admissible(self, z):
        if _flat64(z) and _kernels.compiled("step_admissible") is not None:    # the same tests, compiled
            out = np.empty(1)
            if _kernels.call("step_admissible", z, self._step_parameters(-1e-9 * self.feed_rate), out):
                return bool(out[0])
        S, W, T, Tg, Y = self.split_classes(z)
        # the extremes against the bounds (a NaN fails every comparison, as with np.all)
        lo_t, hi_t, lo_g, hi_g, hi_y = self._state_bounds()
        return bool(S.min() > 0 and W.min() > -1e-9 * self.feed_rate and T.min() > lo_t and T.max() < hi_t
                    and Tg.min() > lo_g and Tg.max() < hi_g and Y.min() > -1e-6 and Y.max() < hi_y)

    # ------------------------------------------------------------------ dynamics
    def simulate(self, z0, t_end, t_eval=None, rtol=1e-5, atol=None, max_step=np.inf, shell_refresh=60.0,
                 max_calls=None):
        """Integrate from state ``z0`` for ``t_end`` s with BDF and the sparse Jacobian pattern.

        The shell-loss coefficient UA is lagged: re-evaluated exactly every ``shell_refresh`` s
        of simulated time (the shell network's own dynamics are not modelled). ``max_calls``: at most
        that many residual calls (the steady state's transient march), else
        [`DryerError`][rotarydryer.thermal.dryer.DryerError] (reason ``"integration"``)."""
        from scipy.integrate import solve_ivp

        _jit.long_runs()        # an integration: thousands of residuals, the compiled kernels pay
        t0 = time.perf_counter()
        if atol is None:
            atol = self._scale() * 1e-7
        z0 = np.asarray(z0, dtype=float)
        self.freeze_shell(z0)
        last = [0.0]

        calls = [0]

        def fun(t, z):      # vectorized: z (n, k); k = 1 except in the Jacobian's batch of perturbations
            calls[0] += 1
            if max_calls is not None and calls[0] > max_calls:
                raise DryerError(f"the integration did not reach t = {float(t_end):.4g} s within {max_calls} residual "
                                 f"evaluations (at t = {float(t):.4g} s)", reason="integration", state=z[:, 0])
            if z.shape[1] == 1 and abs(t - last[0]) > shell_refresh:
                self.freeze_shell(z[:, 0])
                last[0] = t
            return self.rhs(t, z)
        try:
            sol = solve_ivp(fun, (0.0, float(t_end)), z0, method="BDF", t_eval=t_eval, rtol=rtol, atol=atol,
                            jac_sparsity=self.sparsity(), max_step=max_step, vectorized=True)
        finally:
            self.unfreeze_shell()
        if not sol.success:
            raise DryerError(f"dynamic integration failed: {sol.message}", reason="integration", state=z0)
        return DynamicResult(self, sol.t, sol.y, time.perf_counter() - t0, sol.nfev)
