r"""One builder for any sequence of dryer sections on the sparse transport network.

A dryer is a list of sections in solids-flow order. Each section adds its nodes to one
[`Network`][rotarydryer.transport.network.Network] and joins the next section's entry node:

* **flighted** sections: per cell a passive node P (flights, floor, kilning bed) and an
  active node A (curtain). Flows (Lee (2008) Ch. 3; Ajayi (2011) Eq. 5.17-5.19):

  - discharge P -> A at M_des-capped k_dis min(M_P, M_des) (Lee (2008) Eq. 3.2);
  - active outflow split into forward C_F (A_i -> P_{i+1}), return C_R = 1 - C_F - C_B
    (A_i -> P_i) and backmix C_B (A_i -> P_{i-1}, or A_{i-1} for Sheehan et al. (2005)
    Model 2); C_F = C_F^G h_m sin(theta)/dL (Lee (2008) Eq. 3.7-3.8; C_F^G = 1 and C_B = 0
    in Ajayi's model), or, with ``forward_step = "trajectory"``, C_F = d/dL with d the mean
    axial advance of a particle falling h_m through the gas ([`.forward_step`][rotarydryer.transport.forward_step]; a negative
    d adds -d/dL to the backmix);
  - kilning P_i -> P_{i+1}: on the excess over the design load, (M_P - M_des)/t_kiln (Lee
    (2008) Eq. 3.9, ``kilning="excess"``), or on the whole passive mass at the kilning
    velocity u_s/dL (Ajayi (2011) Eq. 5.19, ``kilning="velocity"``);

  The repose angle and bulk density of each cell come from the **material** at a moisture
  ([`FlightedSectionLaw`][rotarydryer.transport.sections.FlightedSectionLaw]); the transport-only network uses an assumed moisture
  profile, the heat-and-mass model ([`rotarydryer.thermal.dryer`][rotarydryer.thermal.dryer]) the computed one,
  through the same law.
  - or Sheehan et al. (2005) "Model 1" (``kilning="empirical"``): global coefficients (1/s)
    passive -> next passive k_PP M_P, passive -> active k_PA min(M_P, M_des), active -> passive
    k_AP M_A and kilning k_K max(M_P - M_des, 0) (notes lee_models.md Section 4.2), with
    M_des from the geometry and the material as above ([`EmpiricalSectionLaw`][rotarydryer.transport.sections.EmpiricalSectionLaw]);
* **unflighted** sections (rolling bed): axially dispersed plug flow by conservative
  finite volumes (Ajayi (2011) Eq. 5.4-5.14; central differencing where the cell Peclet
  number u dz/D <= 2, upwind otherwise). The first section may have Ajayi's Dirichlet inlet
  (open boundary) or a closed (Danckwerts) inlet.

Every family of a flighted section carries ``family.law`` (the section law) so that a model
that moves the moisture re-evaluates its coefficient and design load; families without a law
have constant coefficients.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _jit
from .._limits import check_key
from .._validation import check_choice, check_range, fmt_number
from . import _step_kernel
from .network import EdgeFamily, Network, TracerInput
from .results import TransportModel

__all__ = ["EmpiricalSectionLaw", "ExactGeometry", "FlightedSectionLaw", "SectionSpec", "build_sections", "unflighted_cells_auto"]


def unflighted_cells_auto(length, velocity, dispersion, minimum=20, maximum=2000):
    """Number of finite volumes so that the cell Peclet number u dz / D <= 1.9 (central scheme)."""
    if dispersion <= 0:
        return maximum
    return int(min(max(math.ceil(velocity * length / (1.9 * dispersion)), minimum), maximum))


@dataclass
class SectionSpec:
    """One section of a dryer (SI, degrees).

    kind : "flighted" | "unflighted". n_cells : cells (flighted) or finite volumes
    (unflighted; None = [`unflighted_cells_auto`][rotarydryer.transport.sections.unflighted_cells_auto]). geometry : cell geometry model
    (``cascade``, ``design_load_area``, ``loading_factor``). kilning : "excess" (Lee),
    "velocity" (Ajayi) or "empirical" (Sheehan et al. (2005) Model 1 with the ``rates``
    ``passive_rate``, ``exchange_rate``, ``return_rate``, ``kiln_rate``, 1/s).
    repose_angle / bulk_density : fixed per-cell values that replace the material laws
    (transport-only studies). moisture : assumed wet-basis moisture per cell (transport-only
    network). fouling : fraction of the design load lost to scale (Ajayi (2011) Eq. 5.21).
    forward_step : "fitted" (C_F = drag_reduction h_m sin(theta)/dL, Lee (2008) Eq. 3.7-3.8) or
    "trajectory" (C_F from the fall through ``gas``, a
    [`CurtainGas`][rotarydryer.transport.forward_step.CurtainGas]; ``drag_reduction`` is then unused).
    kiln_law (``kilning = "excess"``): "fixed" (the excess over the design load leaves a cell at
    1/``kiln_time``, Lee (2008) Eq. 3.9) or "cascade" (it moves at the axial speed of the
    flight-borne solids without gas, c_0 h_m sin(theta)/(t_p + t_a), so
    1/t_kiln = c_0 h_m sin(theta)/((t_p + t_a) dL) per cell; c_0 the trajectory step's
    ``step_factor``, 1 for the fitted step; ``kiln_time`` is then unused).
    """

    name: str
    kind: str
    length: float
    n_cells: int | None = None
    geometry: object = None
    kilning: str = "excess"
    kiln_time: float = math.inf
    kiln_velocity: float = 0.0
    drag_reduction: float = 1.0
    backmix: float = 0.0
    backmix_to: str = "passive"
    loading: str = "state"
    passive_time_branch: str | None = None
    fouling: float = 0.0
    repose_angle: object = None
    bulk_density: object = None
    moisture: object = None
    dispersion: float = 0.0
    velocity: float = 0.0
    rates: dict | None = None
    forward_step: str = "fitted"
    gas: Any = None
    kiln_law: str = "fixed"


class ExactGeometry:
    """Cell geometry of the exact flight model ([`rotarydryer.geometry.FlightedDrum`][rotarydryer.geometry.FlightedDrum]) with a
    chosen design-load method: ``"lee2008"`` (Lee (2008) Eq. 4.20-4.21) or ``"ajayi2011"`` (1.24 x
    Baker, Ajayi (2011) Section 4.5); ``passive_time_branch`` as in ``FlightedDrum.cascade``.

    ``tabulated=True`` (default) evaluates the geometry from the drum's cached
    `rotarydryer.geometry.tabulated.GeometryTable` (within 1e-7 of the direct evaluation,
    at the cost of Lee's regressions); ``False`` computes it directly every call."""

    def __init__(self, drum, passive_time_branch=None, design_load_method="lee2008", particle_diameter=None,
                 tabulated=True):
        check_choice("geometry.design_load_method", design_load_method, ("lee2008", "ajayi2011"))
        self.drum, self.branch, self.design_load_method = drum, passive_time_branch, design_load_method
        #: m; with a diameter the holdup has the finite-particle correction (docs/dem.md), None = Lee's continuum
        self.particle_diameter = particle_diameter
        self._kw = {} if particle_diameter is None else {"particle_diameter": float(particle_diameter)}
        # the tables hold the continuum model: with a particle diameter the geometry is evaluated directly
        self.tabulated = bool(tabulated) and particle_diameter is None
        self._table = None

    def __repr__(self):
        return f"exact({self.drum!r})"

    @property
    def table(self):
        """The drum's `GeometryTable` (built on first use, cached)."""
        if self._table is None:
            from ..geometry.tabulated import geometry_table

            self._table = geometry_table(self.drum)
        return self._table

    def design_load_area(self, phi):
        if self.tabulated:
            return self.table.design_load_area(phi, method=self.design_load_method)
        if self.design_load_method == "lee2008":
            return self.drum.design_load_area(phi, **self._kw)
        return self.drum.design_load_area(phi, method=self.design_load_method, **self._kw)

    def loading_factor(self, d, phi, smoothing=0.0):
        """Flight loading factor (Lee (2008) Eq. 4.22 inverted); ``smoothing`` > 0 rounds its kinks
        over that width of the dryer loading (see ``geometry.design_load._invert_eq_4_22``)."""
        if self.tabulated:
            return self.table.loading_factor(d, phi, smoothing)
        return self.drum.loading_factor(d, phi, smoothing=smoothing, **self._kw)

    def cell_values(self, phi, rho, mp, *, length, fouling, smoothing, rpm, slope=0.0, passive_time_branch=None,
                    fixed_loading=False):
        """Design load, loading factor, passive time, fall height and fall time of cells in one
        compiled pass (`GeometryTable.cell_values`), or None where that does not apply (no
        compiled kernels, a direct evaluation, a repose angle outside the table)."""
        if not self.tabulated:
            return None
        branch = passive_time_branch or self.branch or "eq3.4"
        return self.table.cell_values(phi, rho, mp, length=length, fouling=fouling, method=self.design_load_method,
                                      smoothing=smoothing, rpm=rpm, slope=slope, passive_time_branch=branch,
                                      fixed_loading=fixed_loading)

    def cascade(self, phi, f, *, rpm, slope=0.0, passive_time_branch=None):
        kw = dict(rpm=rpm, slope=slope)
        branch = passive_time_branch or self.branch
        if branch is not None:
            kw["passive_time_branch"] = branch
        if self.tabulated:
            return self.table.cascade(phi, f, **kw)
        return self.drum.cascade(phi, f, **kw, **self._kw)


class FlightedSectionLaw:
    """Per-cell coefficients of one flighted section at a given passive mass and moisture.

    [`evaluate`][rotarydryer.transport.sections.FlightedSectionLaw.evaluate] returns, for every flow family of the section, the coefficient k (1/s)
    and the design load M_des (kg) at wet passive masses ``mp`` and wet-basis moistures ``x``
    of the passive nodes. Repose angle and bulk density follow the material (or the fixed
    values of the spec); M_des = rho_b dL A_des(phi) (1 - fouling) (Lee (2008) Eq. 4.20-4.21;
    Ajayi (2011) Eq. 5.18, 5.21).
    """

    def __init__(self, spec: SectionSpec, material, rpm, slope, P, assumed_moisture):
        self.spec, self.material = spec, material
        self.rpm, self.slope = float(rpm), float(slope)
        self.P = P
        self.assumed_moisture = assumed_moisture
        self.n = P.size
        self.dl = spec.length / self.n
        self.sin_t = math.sin(math.radians(self.slope))
        self._fixed_phi = None if spec.repose_angle is None else np.broadcast_to(
            np.asarray(spec.repose_angle, float), (self.n,)).copy()
        self._fixed_rho = None if spec.bulk_density is None else np.broadcast_to(
            np.asarray(spec.bulk_density, float), (self.n,)).copy()

    def _shape(self, a, cells):
        """Shape of the per-cell values: (n,), a batch (k, n), or that of ``cells`` (a subset)."""
        if cells is not None:
            return np.shape(cells)
        shape = np.shape(a)
        return shape if shape[-1:] == (self.n,) else np.broadcast_shapes(shape, (self.n,))

    def properties(self, x, cells=None):
        """(repose angle deg, bulk density kg/m^3) per cell at wet-basis moisture ``x``; ``cells``:
        the cell index of each element of ``x`` when it holds a subset of the cells (1-D)."""
        fixed_phi, fixed_rho = self._fixed_phi, self._fixed_rho
        if cells is not None:
            fixed_phi = None if fixed_phi is None else fixed_phi[cells]
            fixed_rho = None if fixed_rho is None else fixed_rho[cells]
        phi = np.asarray(fixed_phi if fixed_phi is not None else self.material.repose_angle(x), dtype=float)
        rho = np.asarray(fixed_rho if fixed_rho is not None else self.material.bulk_density(x), dtype=float)
        shape = self._shape(x, cells)           # (n,), a batch (k, n) or a subset
        if phi.shape == shape and rho.shape == shape and fixed_phi is None and fixed_rho is None:
            return phi, rho                     # computed here: new arrays of the right shape
        ones = np.ones(shape)
        return phi * ones, rho * ones

    def design_load(self, phi, rho, fouling=None):
        s = self.spec
        fouling = s.fouling if fouling is None else fouling
        phi = np.asarray(phi, dtype=float)
        key = (phi.shape, phi.tobytes())
        memo = getattr(self, "_area_memo", None)
        if memo is None or memo[0] != key:      # the same repose angles (fixed moisture): the same area
            area = np.array(s.geometry.design_load_area(phi.ravel()), dtype=float).reshape(phi.shape)
            area.setflags(write=False)
            memo = self._area_memo = (key, area)
        return rho * self.dl * memo[1] * (1.0 - fouling)

    def _geometry_cascade(self, phi, f, kw):
        """(t_p, t_a, h_m) of the geometry at repose angles ``phi`` and loading factors ``f`` (same shape),
        memoised on the last call: a transport-only network with a fixed loading evaluates the same cells
        at every state (the trajectory step changes with the release only)."""
        key = (phi.shape, phi.tobytes(), f.tobytes(), tuple(sorted(kw.items())))
        memo = getattr(self, "_cascade_memo", None)
        if memo is None or memo[0] != key:
            c = self.spec.geometry.cascade(phi.ravel(), f.ravel(), **kw)
            shape = phi.shape
            vals = tuple(np.array(v, float).reshape(shape) for v in (c.passive_time, c.mean_fall_time,
                                                                    c.mean_fall_height))
            for v in vals:
                v.setflags(write=False)     # shared by the callers: read-only
            memo = self._cascade_memo = (key, vals)
        return memo[1]

    @property
    def trajectory(self) -> bool:
        """Is the forward step computed from particle trajectories (``forward_step = "trajectory"``)?"""
        return self.spec.forward_step == "trajectory"

    @property
    def release_dependent(self) -> bool:
        """Do the coefficients depend on the flight discharge (Sherritt's curtain velocity ratio)?"""
        return self.trajectory and self.spec.gas.velocity_ratio is None

    def cascade(self, phi, f, rpm=None, flight_mass=None, gas=None):
        """Cycle times, fall height and the forward/return/backmix split C_F, C_R, C_B per cell (Lee
        (2008) Eq. 3.3-3.8). ``flight_mass`` (kg per cell, default f x the design load at the assumed
        moisture) is the mass the flights discharge, used by the trajectory forward step only."""
        kw = dict(rpm=self.rpm if rpm is None else rpm, slope=self.slope)
        if self.spec.passive_time_branch is not None:
            kw["passive_time_branch"] = self.spec.passive_time_branch
        phi = np.asarray(phi, dtype=float)
        shape = np.broadcast_shapes(phi.shape, np.shape(f))     # (n,) or a batch (k, n)
        phi, f = np.broadcast_to(phi, shape), np.broadcast_to(np.asarray(f, dtype=float), shape)
        tp, ta, h = self._geometry_cascade(np.ascontiguousarray(phi), np.ascontiguousarray(f), kw)
        if not self.trajectory:
            return self._fitted_step(tp, ta, h)
        if flight_mass is None:
            flight_mass = np.asarray(f, float) * self._reference_design_load()
        return self._trajectory_step(tp, ta, h, flight_mass, gas)

    def _trajectory_step(self, tp, ta, h, flight_mass, gas=None):
        """The cascade dict of the trajectory forward step from the passive time ``tp``, fall time ``ta``, fall
        height ``h`` and the mass ``flight_mass`` the flights discharge (kg per cell) of each cell (`cascade`)."""
        from .forward_step import trajectory_forward_step

        s = self.spec
        q = np.asarray(flight_mass, float) / tp / self.dl          # release per metre of drum, kg/(s m)
        step = trajectory_forward_step(s.gas if gas is None else gas, self.slope, h, q)
        free = step["step_m"]
        # a step longer than the cell minus backmix is capped there (C_R >= 0): the nearest-neighbour
        # structure (Lee (2008) Fig. 3.4) cannot carry solids further. build_sections refuses a
        # discretisation whose step at the design load does not fit; the cap acts only at lower
        # loadings (sparse curtains of nearly empty flights feel the whole gas velocity)
        far = s.backmix == 0.0          # without a fitted backmix a cascade may reach two cells on
        reach = (2.0 if far else 1.0 - s.backmix) * self.dl
        d = np.minimum(np.maximum(free, -reach), reach)
        xf, xb = np.maximum(d, 0.0) / self.dl, np.maximum(-d, 0.0) / self.dl
        # a uniform curtain over the cell whose particles all advance d: the fraction x = d/dL (< 1) lands
        # in the next cell; for 1 < x <= 2 every particle leaves, 2 - x into the next and x - 1 into the
        # one after (mean advance (2 - x) + 2 (x - 1) = x cells); the same backwards
        CF2, CB2 = np.maximum(xf - 1.0, 0.0), np.maximum(xb - 1.0, 0.0)
        CF = np.where(xf > 1.0, 2.0 - xf, xf)
        CB = s.backmix + np.where(xb > 1.0, 2.0 - xb, xb)
        zero = h * self.sin_t
        cfg = np.divide(d, zero, out=np.full(np.shape(d), np.nan), where=zero > 0)
        out = dict(tp=tp, ta=ta, h=h, CF=CF, CR=1.0 - CF - CB - CF2 - CB2, CB=CB, step=d, step_free=free, CFG=cfg,
                   cv=step["curtain_velocity_ratio"])
        if far:
            out.update(CF2=CF2, CB2=CB2)
        return out

    def _trajectory_rates(self, tp, ta, h, flight_mass):
        """[`rates_of`][rotarydryer.transport.sections.FlightedSectionLaw.rates_of] of `_trajectory_step` (the same numbers to
        rounding) in one compiled pass (`rotarydryer.transport._step_kernel`), or None where it does not apply
        (kernels off, an input or result not finite): the caller then composes the two."""
        fn = _step_kernel.compiled()
        if fn is None:
            return None
        s = self.spec
        gas = s.gas
        far = s.backmix == 0.0
        # the kernel's fixed arguments (the gas's forward-step table, the slope, the cell length): packed once per
        # gas and slope (a law's residual evaluations repeat them; 10 % of Song's steady state was this glue)
        key = (gas, self.slope, self.dl, s.backmix)
        fixed = self.__dict__.get("_step_fixed")
        if fixed is None or fixed[0][0] is not gas or fixed[0][1:] != key[1:]:
            from .forward_step import SHERRITT_EXPONENTS, forward_step_table

            table = forward_step_table(gas, float(self.slope))
            fixed = self._step_fixed = (key, (
                float(self.dl), float(s.backmix), bool(far), math.cos(math.radians(float(self.slope))),
                float(table._tan), -1.0 if gas.velocity_ratio is None else float(gas.velocity_ratio),
                float(gas.curtain_coefficient), *(float(e) for e in SHERRITT_EXPONENTS), float(gas.gas_velocity),
                float(gas.step_factor), table.h, table.u, table.excess))
        shape = np.shape(tp)
        flat = [v.reshape(-1) if type(v) is np.ndarray and v.dtype == float and v.shape == shape and v.flags.c_contiguous
                else np.ascontiguousarray(np.broadcast_to(np.asarray(v, dtype=float), shape)).reshape(-1)
                for v in (tp, ta, h, flight_mass)]
        out = np.empty((len(_step_kernel.ROWS), flat[0].size))
        try:
            ok = fn(*flat, *fixed[1], out)
        except Exception as exc:    # a numba that cannot compile here: the NumPy composition instead
            _jit.disable(f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}")
            return None
        if not ok:
            return None
        rates = {name: out[k].reshape(shape) for k, name in enumerate(_step_kernel.ROWS[:4])}
        if far:
            rates.update(forward_far=out[4].reshape(shape), backmix_far=out[5].reshape(shape))
        rates["kiln"] = self._kiln_rate(tp, ta, h, shape)
        return rates

    def _fitted_step(self, tp, ta, h):
        """The cascade dict of the fitted forward step: C_F = drag_reduction h sin(theta) / dL (Lee
        (2008) Eq. 3.7-3.8), C_B = backmix, C_R = 1 - C_F - C_B."""
        s = self.spec
        CF = self._fitted_forward(h)
        return dict(tp=tp, ta=ta, h=h, CF=CF, CR=1.0 - CF - s.backmix, CB=np.full(np.shape(tp), float(s.backmix)))

    def _fitted_forward(self, h):
        """C_F of the fitted forward step at fall height ``h`` (Lee (2008) Eq. 3.7-3.8)."""
        return self.spec.drag_reduction * h * self.sin_t / self.dl

    def _kernel_applies(self):
        """Can [`ExactGeometry.cell_values`][rotarydryer.transport.sections.ExactGeometry.cell_values] give this law's cells (tabulated exact geometry,
        compiled kernels on)? The trajectory forward step then follows from the cells' cascade (`_trajectory_step`)."""
        g = self.spec.geometry
        return _jit.enabled() and isinstance(g, ExactGeometry) and g.tabulated

    def _compiled(self, mp, phi, rho, rpm, fouling, smoothing):
        """[`evaluate`][rotarydryer.transport.sections.FlightedSectionLaw.evaluate]'s design load, loading factor, passive time, fall height and fall time in
        one compiled pass ([`ExactGeometry.cell_values`][rotarydryer.transport.sections.ExactGeometry.cell_values]), or None where that does not apply (1-D
        arrays; evaluate() has checked `_kernel_applies`)."""
        return self.spec.geometry.cell_values(
            phi, rho, mp, length=self.dl, fouling=self.spec.fouling if fouling is None else fouling,
            smoothing=smoothing, rpm=self.rpm if rpm is None else rpm, slope=self.slope,
            passive_time_branch=self.spec.passive_time_branch, fixed_loading=self.spec.loading == "fixed")

    def _reference_design_load(self):
        """Design load (kg per cell) at the assumed moisture, cached."""
        if getattr(self, "_des_ref", None) is None:
            self._des_ref = self.design_load(*self.properties(self.assumed_moisture))
        return self._des_ref

    def loading_factor(self, mp, des, phi, smoothing=0.0, cells=None):
        """Flight loading factor at passive mass ``mp`` and design load ``des``; ``smoothing`` (> 0,
        the thermal model's ``design_load_smoothing``) rounds the kinks of the exact geometry's."""
        if self.spec.loading == "fixed":
            return np.ones(self._shape(mp, cells))
        d = np.maximum(mp / des, 1e-6)
        phi = np.broadcast_to(phi, d.shape).ravel()
        g = self.spec.geometry
        f = g.loading_factor(d.ravel(), phi, smoothing=smoothing) if smoothing > 0 and isinstance(g, ExactGeometry) \
            else g.loading_factor(d.ravel(), phi)
        return np.minimum(np.maximum(np.asarray(f, dtype=float).reshape(d.shape), 1e-6), 1.0)

    def rates(self, phi, f, rpm=None, flight_mass=None):
        """Coefficients (1/s) of each family at repose angle ``phi`` and loading factor ``f``."""
        return self.rates_of(self.cascade(phi, f, rpm, flight_mass))

    #: the families whose coefficients the curtain's forward step sets (a particle's own with the trajectory step)
    CURTAIN_FAMILIES = ("forward", "return", "backmix", "forward_far", "backmix_far")

    def class_rates(self, mp, x, diameters, rpm=None, fouling=None, smoothing=0.0):
        """The curtain families' coefficients (1/s) of particles of each of ``diameters`` (m) in the cells'
        curtains: ``{family: (..., classes, cells)}``, the trajectory step of each size through the gas
        (the flights' discharge, fall heights and times are the mixture's, at wet passive masses ``mp`` and
        moisture ``x``, as in `evaluate`). Without the trajectory step, None: the fitted step does not
        depend on the particle size."""
        if not self.trajectory or self.spec.gas is None:
            return None
        mp = np.asarray(mp, dtype=float)
        phi, rho = self.properties(x)
        des = self.design_load(phi, rho, fouling)
        f = self.loading_factor(mp, des, phi, smoothing)
        flight_mass = np.minimum(mp, des)
        out: dict = {}
        for d in diameters:
            r = self.rates_of(self.cascade(phi, f, rpm, flight_mass, gas=_with_diameter(self.spec.gas, float(d))))
            for name in self.CURTAIN_FAMILIES:
                if name in r:
                    out.setdefault(name, []).append(np.broadcast_to(r[name], np.shape(phi)))
        return {k: np.stack(v, axis=-2) for k, v in out.items()}

    def _fitted_rates(self, tp, ta, h):
        """[`rates_of`][rotarydryer.transport.sections.FlightedSectionLaw.rates_of] of `_fitted_step` (the same numbers, without the cascade dict)."""
        cf = self._fitted_forward(h)
        return self._rates(tp, ta, cf, float(self.spec.backmix), 1.0 - cf - self.spec.backmix, h)

    def rates_of(self, c):
        """Coefficients (1/s) of each family from a [`cascade`][rotarydryer.transport.sections.FlightedSectionLaw.cascade] result."""
        out = self._rates(c["tp"], c["ta"], c["CF"], c["CB"], c["CR"], c["h"])
        if "CF2" in c:      # the trajectory step's reach into the second cell (cascade)
            out.update(forward_far=c["CF2"] / c["ta"], backmix_far=c["CB2"] / c["ta"])
        return out

    @property
    def step_factor(self) -> float:
        """c_0 of the forward step without gas (the trajectory step's ``step_factor``; 1 for the fitted step)."""
        gas = self.spec.gas
        return float(gas.step_factor) if self.trajectory and gas is not None else 1.0

    def cascade_kiln_rate(self, tp, ta, h):
        """1/t_kiln (1/s) of ``kiln_law = "cascade"``: the excess over the design load moves one cell at the
        axial speed of the flight-borne solids without gas, c_0 h_m sin(theta)/(t_p + t_a) (Lee (2008) Eq.
        3.3-3.8 with C_F^G = c_0; the kilning of Eq. 3.9 tied to the cascade: Song (2003) L1363-1367, the
        residence time of dry sand independent of the feed beyond the flights' capacity)."""
        return self.step_factor * np.asarray(h, float) * self.sin_t / ((np.asarray(tp, float)
                                                                       + np.asarray(ta, float)) * self.dl)

    def _rates(self, tp, ta, cf, cb, cr, h=None):
        """Coefficients (1/s) of each family from the passive and fall times and the forward, backmix
        and return fractions (Lee (2008) Eq. 3.3-3.8); ``h`` the fall height (the cascade kiln law)."""
        out = dict(discharge=1.0 / tp, forward=cf / ta, backmix=cb / ta)
        out["return"] = cr / ta
        out["kiln"] = self._kiln_rate(tp, ta, h, np.shape(tp))
        return out

    def _kiln_rate(self, tp, ta, h, shape):
        """The kilning coefficient (1/s) of cells of ``shape``: the cascade law's (`cascade_kiln_rate`), 1/kiln_time
        (Lee (2008) Eq. 3.9) or the kilning velocity over the cell length."""
        s = self.spec
        if s.kilning == "excess" and s.kiln_law == "cascade":
            rate = self.cascade_kiln_rate(tp, ta, h)
            return rate if rate.shape == shape else rate * np.ones(shape)      # x 1: the same numbers
        return np.full(shape, 1.0 / s.kiln_time) if s.kilning == "excess" else np.full(shape, s.kiln_velocity / self.dl)

    @property
    def cellwise(self) -> bool:
        """Are the coefficients of a cell a function of its own passive mass and moisture only (so a
        subset of the cells can be evaluated alone, ``evaluate(..., cells=...)``)? Yes: the fitted
        step's from the cell's fall height, the trajectory step's from the cell's fall height and its
        own discharge (Sherritt's curtain velocity ratio) in the gas of the drum's inlet conditions."""
        return True

    def evaluate(self, mp, x, rpm=None, fouling=None, smoothing=0.0, cells=None):
        """dict family name -> coefficient (1/s), plus ``"design_load"`` (kg) and the properties,
        at wet passive masses ``mp`` (kg) and wet-basis moisture ``x``; ``rpm`` and ``fouling``
        replace the section's values (studies that change them); ``smoothing``: see
        [`loading_factor`][rotarydryer.transport.sections.FlightedSectionLaw.loading_factor]. ``mp`` (and ``x``) may carry a leading batch axis, shape (k, n): the
        coefficients of k states at once (the heat-and-mass model's finite-difference Jacobian).
        ``cells`` (1-D, [`cellwise`][rotarydryer.transport.sections.FlightedSectionLaw.cellwise] laws only): ``mp`` and ``x`` hold the cells of these indices
        only, one element each (the cells a Jacobian's perturbation changed)."""
        mp = np.asarray(mp, dtype=float)
        phi, rho = self.properties(x, cells)
        shape = mp.shape if mp.shape == phi.shape else np.broadcast_shapes(phi.shape, mp.shape)
        fast = self._compiled(*(a.ravel() if a.shape == shape else np.broadcast_to(a, shape).ravel()
                                for a in (mp, phi, rho)), rpm, fouling, smoothing) if self._kernel_applies() else None
        if fast is not None:        # one compiled pass; a batch (k, n) is passed flat
            des, _, tp, h, ta = (v.reshape(shape) for v in fast)
            if self.trajectory:     # the forward step of the trajectories through the gas from the cells' cascade
                fm = np.minimum(mp, des)
                out = self._trajectory_rates(tp, ta, h, fm)
                if out is None:
                    out = self.rates_of(self._trajectory_step(tp, ta, h, fm))
            else:
                out = self._fitted_rates(tp, ta, h)
            out.update(design_load=des, repose_angle=phi, bulk_density=rho)
            return out
        des = self.design_load(phi, rho, fouling)
        f = self.loading_factor(mp, des, phi, smoothing, cells)
        out = self.rates(phi, f, rpm, np.minimum(mp, des) if self.trajectory else None)
        out.update(design_load=des, repose_angle=phi, bulk_density=rho)
        return out


def _with_diameter(gas, diameter):
    """``gas`` (a frozen `CurtainGas`) with another particle diameter (its forward-step table is cached per gas)."""
    return gas if gas.particle_diameter == diameter else dataclasses.replace(gas, particle_diameter=diameter)


class EmpiricalSectionLaw(FlightedSectionLaw):
    """Sheehan et al. (2005) "Model 1" coefficients of a section: constant k_PP, k_PA, k_AP, k_K
    (1/s, the spec's ``rates``) and the design load from the geometry and the material at the
    moisture (so that a heat-and-mass model moves it with the computed moisture)."""

    NAMES = {"passive_forward": "passive_rate", "discharge": "exchange_rate", "return": "return_rate",
             "kiln": "kiln_rate"}

    def rates(self, phi, f, rpm=None):
        r = self.spec.rates
        return {fam: np.full(np.shape(phi), float(r[key])) for fam, key in self.NAMES.items()}

    def evaluate(self, mp, x, rpm=None, fouling=None, smoothing=0.0, cells=None):
        phi, rho = self.properties(x, cells)
        out = self.rates(phi, None, rpm)
        out.update(design_load=self.design_load(phi, rho, fouling), repose_angle=phi, bulk_density=rho)
        return out


def _check_rates(spec, where):
    r = dict(spec.rates or {})
    need = tuple(EmpiricalSectionLaw.NAMES.values())
    unknown = sorted(set(r) - set(need))
    if unknown:
        raise ValueError(f"{where}: unknown Model 1 rate(s) {', '.join(map(repr, unknown))}; valid: {', '.join(need)}")
    for key in need:
        if key not in r:
            raise ValueError(f"{where}: transport.{key} is missing (1/s); sheehan2005_model1 needs "
                             f"{', '.join('transport.' + k for k in need)}")
        check_key(f"transport.{key}", r[key])
    if r["passive_rate"] == 0 and r["kiln_rate"] == 0:
        raise ValueError(f"{where}: transport.passive_rate = 0 and transport.kiln_rate = 0: no solids leave "
                         "the cells (give one of them > 0)")


class _Coefficients:
    """Transport-only coefficients at the assumed moisture: cached per passive state, with a
    one-sided difference on the side of the current loading branch (the derivative never
    straddles the switch at M_P = M_des)."""

    def __init__(self, law: FlightedSectionLaw, x, des):
        self.law, self.x, self.des = law, x, des
        self._key = None
        self._val = None

    def get(self, M):
        mp = M[self.law.P]
        key = mp.tobytes()
        if key != self._key:
            h = np.where(mp > self.des, 1.0, -1.0) * 1e-7 * self.des
            if self.law.trajectory:
                v0 = self.law.evaluate(mp, self.x)
                v1 = self.law.evaluate(mp + h, self.x)
            else:       # the point and the perturbed point as a batch of two (the same numbers, one call)
                v = self.law.evaluate(np.stack([mp, mp + h]), self.x)
                two = (2, mp.size)
                v0, v1 = {}, {}
                for k in _RATE_NAMES:
                    if k in v:
                        a = v[k] if np.shape(v[k]) == two else np.broadcast_to(v[k], two)
                        v0[k], v1[k] = a[0], a[1]
            self._val = {k: (v0[k], (v1[k] - v0[k]) / h) for k in _RATE_NAMES if k in v0}
            self._key = key
        return self._val

    def rate_fn(self, name):
        fn = lambda M: self.get(M)[name]      # noqa: E731
        fn.source = (self, name)      # the network asks each source once per state (Network._edge_flows)
        return fn


#: values of ``transport.kiln_law`` (SectionSpec.kiln_law)
KILN_LAWS = ("fixed", "cascade")
_RATE_NAMES = ("discharge", "forward", "return", "backmix", "kiln", "forward_far", "backmix_far")
#: cell_info keys of the trajectory forward step (at the design load, transport-only moisture)
TRAJECTORY_INFO = ("C_B", "forward_step_m", "C_F_G", "curtain_velocity_ratio")


#: per-cell coefficients that build_sections reports (cell_info keys and their cascade entries)
_CASCADE_INFO = (("passive_time_s", "tp"), ("fall_time_s", "ta"), ("fall_height_m", "h"), ("C_F", "CF"),
                 ("C_R", "CR")) + tuple(zip(TRAJECTORY_INFO, ("CB", "step", "CFG", "cv")))


def cell_info_at(law: FlightedSectionLaw, moisture, rpm=None) -> tuple[np.ndarray, dict]:
    """Design load (kg per cell) and the per-cell quantities that [`build_sections`][rotarydryer.transport.sections.build_sections] reports
    (moisture, repose angle, bulk density, passive and fall times, fall height, C_F, C_R and the
    trajectory step's), of a section law at wet-basis ``moisture`` per cell: the heat-and-mass
    model's cells at their computed moisture (the transport model reports them at its assumed one).
    The times and fractions are those of a flight at its design load (loading factor 1), as there;
    ``rpm``: the drum speed (default the law's own, that of its build)."""
    x = np.broadcast_to(np.asarray(moisture, dtype=float), (law.n,)).copy()
    phi, rho = (np.broadcast_to(np.asarray(a, dtype=float), (law.n,)) for a in law.properties(x))
    des = np.broadcast_to(np.asarray(law.design_load(phi, rho), dtype=float), (law.n,))
    info = {"moisture_kg_kg": x, "repose_angle_deg": phi, "bulk_density_kg_m3": rho}
    c1 = {} if isinstance(law, EmpiricalSectionLaw) else law.cascade(phi, np.ones(law.n), rpm)
    for key, ck in _CASCADE_INFO:
        info[key] = np.broadcast_to(np.asarray(c1[ck], dtype=float), (law.n,)) if ck in c1 else np.full(law.n, np.nan)
    return des, info


def _check_flighted(spec: SectionSpec, where: str):
    check_choice(f"{where}.kilning", spec.kilning, ("excess", "velocity", "empirical"))
    if spec.kilning == "empirical":
        _check_rates(spec, where)
        return
    check_choice(f"{where}.loading", spec.loading, ("fixed", "state"))
    check_choice(f"{where}.backmix_to", spec.backmix_to, ("passive", "active"))
    check_choice("transport.forward_step", spec.forward_step, ("fitted", "trajectory"))
    if spec.forward_step == "trajectory":
        from .forward_step import CurtainGas

        if not isinstance(spec.gas, CurtainGas):
            raise ValueError(f"{where}: transport.forward_step = 'trajectory' needs the gas stream and the "
                             "particles (give [gas] flow and inlet_temperature, and a [material])")
    check_choice("transport.kiln_law", spec.kiln_law, KILN_LAWS)
    if spec.kilning == "excess" and spec.kiln_law == "fixed":
        check_key("transport.kiln_time", spec.kiln_time)
    if spec.kilning == "velocity":
        check_range("transport.kiln_velocity", spec.kiln_velocity, 0.0, math.inf, unit="m/s")


def build_sections(sections, *, material, feed_rate, rpm, slope, inlet="danckwerts", tracer_input=None,
                   name="dryer", parameters=None) -> TransportModel:
    """Transport model of a dryer made of ``sections`` (list of [`SectionSpec`][rotarydryer.transport.sections.SectionSpec], flow order).

    ``material`` gives repose angle and bulk density versus moisture (used where a section has
    no fixed values). ``inlet`` is the inlet condition of a first unflighted section
    ("ajayi": Dirichlet m(0) = F/u_s with an open dispersive boundary, Ajayi (2011) Eq.
    5.11-5.13; "danckwerts": closed). The model also carries ``specs`` (the sections it was built
    from) and ``cell_length`` (axial extent of each node, m); the families of flighted sections
    carry their [`FlightedSectionLaw`][rotarydryer.transport.sections.FlightedSectionLaw] (``family.law``).
    """
    if not sections:
        raise ValueError("sections = [] is empty: a dryer needs at least one section")
    F = float(check_range("operating.feed_rate", feed_rate, 0.0, math.inf, unit="kg/s"))
    rpm = float(check_range("operating.rpm", rpm, 0.0, math.inf, unit="rev/min"))
    theta = float(check_key("drum.slope", slope))
    check_choice("transport.unflighted_inlet", inlet, ("ajayi", "danckwerts"))
    from .models import NetworkBuilder

    b = NetworkBuilder()
    built = []
    x0 = 0.0
    for k, s in enumerate(sections):
        where = f"sections[{k}] ({s.name})"
        L = float(check_range(f"{where}.length", s.length, 0.0, math.inf, unit="m"))
        if s.kind == "unflighted":
            u = float(check_key("transport.solids_velocity", s.velocity, f"{where}: transport.solids_velocity"))
            D = float(check_key("transport.dispersion", s.dispersion, f"{where}: transport.dispersion"))
            n = int(s.n_cells or unflighted_cells_auto(L, u, D))
            dz = L / n
            pos = x0 + (np.arange(n) + 0.5) * dz
            idx = b.add_nodes(s.name, "bed", np.arange(n), pos, guess=F / u * dz)
            built.append(dict(spec=s, kind="unflighted", n=n, dz=dz, nodes=idx, entry=idx[0]))
        elif s.kind == "flighted":
            _check_flighted(s, where)
            N = s.n_cells
            if N is None or int(N) != N or N < 1:
                raise ValueError(f"{where}.n_cells = {fmt_number(N)}: a flighted section needs an integer n_cells >= 1")
            N = int(N)
            dl = L / N
            pos = x0 + (np.arange(N) + 0.5) * dl
            P, A = b.add_cell_pairs(s.name, ("passive", "active"), pos)     # interleaved P_i, A_i: banded
            built.append(dict(spec=s, kind="flighted", n=N, dl=dl, P=P, A=A, entry=P[0]))
        else:
            raise ValueError(f"{where}.kind = {s.kind!r} is not one of 'flighted', 'unflighted'")
        x0 += L
    feed = np.zeros(b.n)
    guess = np.array(b.guess)
    design_load = np.array(b.design_load)
    info_keys: tuple[str, ...] = ("moisture_kg_kg", "repose_angle_deg", "bulk_density_kg_m3", "passive_time_s", "fall_time_s",
                 "fall_height_m", "C_F", "C_R")
    any_trajectory = any(r["kind"] == "flighted" and r["spec"].forward_step == "trajectory" for r in built)
    if any_trajectory:      # the trajectory forward step per cell (NaN in cells with the fitted one)
        info_keys += TRAJECTORY_INFO
    info: dict[str, list] = {k: [] for k in info_keys}
    families = []
    cell_length = np.zeros(b.n)
    fix_families = {}
    for k, rec in enumerate(built):
        s = rec["spec"]
        nxt = built[k + 1]["entry"] if k + 1 < len(built) else -1
        sec = s.name
        if rec["kind"] == "unflighted":
            n, dz, idx = rec["n"], rec["dz"], rec["nodes"]
            u, D = float(s.velocity), float(s.dispersion)
            if n > 1:
                pe = u * dz / D if D > 0 else math.inf
                if pe <= 2.0:
                    fw, bw = D / dz**2 + u / (2 * dz), D / dz**2 - u / (2 * dz)
                else:
                    fw, bw = D / dz**2 + u / dz, D / dz**2
                families.append(EdgeFamily("bed_forward", idx[:-1], idx[1:], "linear", rate=np.full(n - 1, fw),
                                           section=sec))
                if bw > 0:
                    families.append(EdgeFamily("bed_dispersion", idx[1:], idx[:-1], "linear",
                                               rate=np.full(n - 1, bw), section=sec))
            families.append(EdgeFamily("bed_outflow", idx[-1:], np.array([nxt]), "linear", rate=np.array([u / dz]),
                                       section=sec))
            cell_length[idx] = dz
            continue
        N, P, A = rec["n"], rec["P"], rec["A"]
        nxtP = np.r_[P[1:], nxt]
        prevP = np.r_[P[0], P[:-1]]
        prevA = np.r_[P[0], A[:-1]]        # the first cell's backmix stays in its own passive phase
        x = (np.zeros(N) if s.moisture is None else np.broadcast_to(np.asarray(s.moisture, float), (N,)).copy())
        law = (EmpiricalSectionLaw if s.kilning == "empirical" else FlightedSectionLaw)(s, material, rpm, theta, P, x)
        phi, rho = law.properties(x)
        des = law.design_load(phi, rho)
        if np.any(~np.isfinite(des)) or np.any(des <= 0):
            raise ValueError(f"section {sec}: the geometry model gives a non-positive design load "
                             f"({np.nanmin(des):.4g} kg); check the repose angle / material")
        design_load[P] = des
        if s.kilning == "empirical":
            # Sheehan et al. (2005) Model 1: constant coefficients, capped discharge and kilning excess
            r1 = law.rates(phi, None)
            guess[P] = des
            guess[A] = des * r1["discharge"] / r1["return"]
            fams = [EdgeFamily("discharge", P, A, "capped", rate=r1["discharge"], cap=des, section=sec),
                    EdgeFamily("return", A, P, "linear", rate=r1["return"], section=sec)]
            if s.rates["passive_rate"] > 0:
                fams.append(EdgeFamily("passive_forward", P, nxtP, "linear", rate=r1["passive_forward"], section=sec))
            if s.rates["kiln_rate"] > 0:
                fams.append(EdgeFamily("kiln", P, nxtP, "excess", rate=r1["kiln"], cap=des, section=sec))
            for f in fams:
                f.law = law
            families += fams
            cell_length[P] = cell_length[A] = rec["dl"]
            info["moisture_kg_kg"].append(x)
            info["repose_angle_deg"].append(phi)
            info["bulk_density_kg_m3"].append(rho)
            for key in ("passive_time_s", "fall_time_s", "fall_height_m", "C_F", "C_R") + (
                    TRAJECTORY_INFO if any_trajectory else ()):
                info[key].append(np.full(N, np.nan))
            continue
        if law.trajectory:      # the step at the design load must fit (lower loadings are capped, see cascade)
            c1 = law.cascade(phi, np.ones(N))
            cw = c1
            worst = float(np.min((2.0 if s.backmix == 0.0 else 1.0 - s.backmix)
                                 - np.abs(c1["step_free"]) / rec["dl"]))
        else:
            f_check = [1.0] + ([] if s.loading == "fixed" else [1e-3, 0.25, 0.5, 0.75])
            both = law.cascade(np.broadcast_to(phi, (len(f_check), N)),      # all loadings in one call
                               np.asarray(f_check)[:, None] * np.ones(N))
            rows = [{k: v[i] for k, v in both.items()} for i in range(len(f_check))]
            c1 = rows[0]
            cw = min(rows, key=lambda c: float(np.min(c["CR"])))
            worst = float(np.min(cw["CR"]))
        if worst < 0:
            # the largest N whose forward step fits in the cell at the worst loading
            if law.trajectory:
                step = float(np.max(np.abs(cw["step_free"])))     # m, the trajectory advance
                what = (f"the trajectory step |d| = {step:.4g} m at the design load (transport.forward_step = "
                        f"'trajectory') exceeds {'two cell lengths' if s.backmix == 0.0 else 'the cell length'} "
                        f"{rec['dl']:.4g} m{'' if s.backmix == 0.0 else ' minus backmix'}; with backmix = "
                        f"{s.backmix:g} the")
            else:
                step = s.drag_reduction * float(np.max(cw["h"])) * law.sin_t
                what = ("the forward step C_F^G h_m sin(theta) exceeds the cell length minus backmix; with "
                        f"backmix = {s.backmix:g} and drag_reduction = {s.drag_reduction:g} the")
            span = 2.0 if law.trajectory and s.backmix == 0.0 else 1.0 - s.backmix
            n_max = int(math.floor(span * s.length / step)) if step > 0 else 0
            raise ValueError(
                f"section {sec}: transport.n_cells = {N} makes the return coefficient C_R = 1 - C_F - C_B "
                f"negative (min {worst:.4g}): {what} limit is transport.n_cells <= {n_max} (Lee (2008) Ch. 7: "
                "N <= 35 for Invicta)")
        if np.any(c1["tp"] <= 0) or np.any(c1["ta"] <= 0):
            raise ValueError(f"section {sec}: geometry gives a non-positive passive or fall time; check the "
                             "repose angle")
        r1 = law.rates_of(c1)
        # Newton start: just above the design load where the excess kilns (over-loaded active set),
        # below it where the whole passive mass moves on
        if s.kilning == "excess":
            guess[P] = des * (1 + 1e-6)
            guess[A] = des * c1["ta"] / c1["tp"]
        else:
            guess[P] = 0.8 * des
            guess[A] = 0.8 * des * c1["ta"] / c1["tp"]
        if s.loading == "fixed" and not law.release_dependent:
            mk = lambda key, r1=r1: dict(rate=r1[key])  # noqa: E731
        else:
            cc = _Coefficients(law, x, des)
            mk = lambda key, cc=cc: dict(rate_fn=cc.rate_fn(key), ctrl=P)  # noqa: E731
        fams = [EdgeFamily("discharge", P, A, "capped", cap=des, section=sec, **mk("discharge"))]
        if s.kilning == "excess" and (s.kiln_law == "cascade" or math.isfinite(s.kiln_time)):
            fams.append(EdgeFamily("kiln", P, nxtP, "excess", rate=r1["kiln"], cap=des, section=sec))
        fams.append(EdgeFamily("forward", A, nxtP, "linear", section=sec, **mk("forward")))
        fams.append(EdgeFamily("return", A, P, "linear", section=sec, **mk("return")))
        # a counter-current trajectory step may turn negative at some state: keep the backmix edge
        if s.backmix > 0 or (law.trajectory and s.gas.gas_flow == "counter-current"):
            dst = prevP if s.backmix_to == "passive" else prevA
            fams.append(EdgeFamily("backmix", A, dst, "linear", section=sec, **mk("backmix")))
        if "CF2" in c1:     # the trajectory step's second cell (a step longer than a cell)
            nxt2P = np.r_[P[2:], np.full(min(2, N), nxt)][:N]
            fams.append(EdgeFamily("forward_far", A, nxt2P, "linear", section=sec, **mk("forward_far")))
            if s.gas.gas_flow == "counter-current":
                prev2P = np.r_[P[:1], P[:1], P[:-2]][:N]
                fams.append(EdgeFamily("backmix_far", A, prev2P, "linear", section=sec, **mk("backmix_far")))
        if s.kilning == "velocity":
            fams.append(EdgeFamily("kiln", P, nxtP, "linear", rate=r1["kiln"], section=sec))
        for f in fams:
            f.law = law
            if f.rate_fn is not None:
                fix_families[id(f)] = r1[f.name]
        families += fams
        cell_length[P] = cell_length[A] = rec["dl"]
        info["moisture_kg_kg"].append(x)
        info["repose_angle_deg"].append(phi)
        info["bulk_density_kg_m3"].append(rho)
        for key, ck in (("passive_time_s", "tp"), ("fall_time_s", "ta"), ("fall_height_m", "h"), ("C_F", "CF"),
                        ("C_R", "CR")) + tuple(zip(TRAJECTORY_INFO, ("CB", "step", "CFG", "cv"))
                                               if any_trajectory else ()):
            info[key].append(c1[ck] if ck in c1 else np.full(N, np.nan))
    first = built[0]
    inlet_vec = None
    if first["kind"] == "unflighted" and inlet == "ajayi" and first["spec"].dispersion > 0:
        # Dirichlet m(0) = F/u: inflow F (1 + 2D/(u dz)) - (2D/dz^2) M_1 (open boundary)
        dz, u, D = first["dz"], float(first["spec"].velocity), float(first["spec"].dispersion)
        beta = 2.0 * D / (u * dz)
        feed[first["entry"]] = F * (1.0 + beta)
        families.append(EdgeFamily("inlet_dispersion", np.array([first["entry"]]), np.array([-2]), "linear",
                                   rate=np.array([2.0 * D / dz**2]), section=first["spec"].name))
        inlet_vec = np.zeros(b.n)
        inlet_vec[first["entry"]] = 1.0 + beta
    else:
        feed[first["entry"]] = F
    net = Network(b.n, families, feed, labels=b.labels, initial_guess=guess)
    if fix_families and any(r["kind"] == "flighted" and r["spec"].kilning == "excess" for r in built):
        # start from the steady state with f_load = 1 (piecewise linear, solved exactly)
        fixed = Network(net.n, [EdgeFamily(f.name, f.src, f.dst, f.kind, rate=fix_families.get(id(f), f.rate),
                                           cap=f.cap) for f in net.families], net.feed, initial_guess=guess)
        try:
            net.initial_guess = fixed.steady_state()
        except ValueError:
            pass
    cell_info = {k: np.concatenate(v) if v else np.zeros(0) for k, v in info.items()}
    if tracer_input is None:
        tracer_input = TracerInput.pulse(1e-4 * F * 60.0, 60.0)
    model = TransportModel(
        name=name, network=net,
        sections=[dict(name=r["spec"].name, kind=r["kind"], length=float(r["spec"].length), n_cells=int(r["n"]))
                  for r in built],
        feed_rate=F, design_load=design_load, cell_info=cell_info, tracer_input=tracer_input,
        parameters=dict(parameters or {}))
    model.tracer_inlet = inlet_vec
    model.cell_length = cell_length
    model.specs = list(sections)
    model.material = material
    return model
