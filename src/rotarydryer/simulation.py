"""One orchestrator for every dryer: ``Simulation(case, overrides)``.

>>> from rotarydryer import Simulation
>>> sim = Simulation("song2003_ottawa")
>>> out = sim.steady_state().summary()             # transport + heat and mass, SI names
>>> sorted(k for k in out if k.startswith("product_"))[:2]
['product_moisture_kg_kg', 'product_rate_kg_s']

The case (any kind: the general ``kind = "dryer"`` schema, or Lee's and Ajayi's plant cases)
becomes a list of :class:`~rotarydryer.transport.sections.SectionSpec`; the transport network
is built once by :func:`~rotarydryer.transport.sections.build_sections`; the heat-and-mass
model (:class:`~rotarydryer.thermal.dryer.ThermalDryer`) rides on the same network's nodes and
edge families. Output names carry their unit (``_kg``, ``_kg_s``, ``_s``, ``_degC``, ``_kg_kg``,
``_W``); balances are relative errors.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

__all__ = ["Simulation", "SteadyResult"]


def _exponential_profile(x_in, x_out, frac):
    """Moisture along the dryer (fraction 0..1 of its length), exponential as Lee (2008) Eq. 7.3
    when both ends are > 0, else linear."""
    if x_in > 0 and x_out > 0:
        return x_in * np.exp(frac * math.log(x_out / x_in))
    return x_in + (x_out - x_in) * frac


class Simulation:
    """A dryer case ready to solve.

    Parameters
    ----------
    case : str, path or validated case
        Packaged case name (``lee2008_invicta``, ``ajayi2011_mmg``, ``song2003_ottawa``), a
        ``.toml`` file, or a case object from :func:`rotarydryer.cases.load_case`.
    overrides : dict, optional
        ``{"operating.feed_rate": 30.0, ...}`` (the CLI's ``--set``).
    """

    def __init__(self, case, overrides=None):
        from .cases import load_case

        if isinstance(case, (str, bytes)) or hasattr(case, "__fspath__"):
            self.case_name = str(case)
            self.case = load_case(str(case), overrides or {})
        else:
            if overrides:
                raise ValueError("overrides need a case name or path (load_case applies them)")
            self.case_name = getattr(getattr(case, "meta", None), "title", "") or "case"
            self.case = case
        self.kind = self.case.kind
        self._transport = None
        self._transport_ss = None

    # ------------------------------------------------------------------ inputs
    @property
    def material(self):
        from .cases import _material_of

        return _material_of(self.case)

    @property
    def thermal_enabled(self) -> bool:
        c = self.case
        if self.kind == "lee2008":
            return bool(c.thermal.enabled and c.gas is not None and c.material is not None)
        return bool(getattr(c.thermal, "enabled", True))

    def _operating(self):
        """(feed rate kg/s wet, rpm, feed moisture kg/kg wet, feed temperature degC)."""
        c = self.case
        if self.kind == "ajayi2011":
            from .transport.ajayi import case_test_inputs

            inp = case_test_inputs(c)
            return inp["feed_rate"], inp["rpm"], inp["test"].moisture_inlet, c.thermal.solids_inlet_temperature
        if self.kind == "lee2008":
            mat = self.material
            w_in = c.solids.moisture_inlet
            x_in = w_in / (1 + w_in) if mat.moisture_basis == "dry" else w_in
            t_in = getattr(c.gas, "feed_temperature", None)
            return c.operating.feed_rate, c.operating.rpm, x_in, 20.0 if t_in is None else t_in
        o = c.operating
        return o.feed_rate, o.rpm, o.feed_moisture, o.feed_temperature

    def _specs(self, thermal=False):
        """Section specs of the case; ``thermal``: the network the heat-and-mass model rides on."""
        from .transport.sections import SectionSpec

        c = self.case
        if self.kind == "ajayi2011":
            from .transport.ajayi import case_geometries, case_test_inputs, mmg_moisture_profile

            inp = case_test_inputs(c)
            geoms = case_geometries(c)
            fouling = c.transport.fouling if c.transport.fouling is not None else (0.8 if inp["test"].scaled else 0.0)
            if thermal and c.thermal.fouling is not None:
                fouling = c.thermal.fouling
            specs, x0 = [], 0.0
            for s in c.sections:
                if s.kind == "unflighted":
                    n = (c.thermal.unflighted_cells.get(s.name, max(4, int(math.ceil(s.length / 0.3))))
                         if thermal else c.transport.unflighted_cells)
                    specs.append(SectionSpec(name=s.name, kind="unflighted", length=s.length, n_cells=n,
                                             velocity=inp["kiln_velocity"], dispersion=inp["dispersion"]))
                else:
                    pos = x0 + (np.arange(s.n_cells) + 0.5) * s.length / s.n_cells
                    specs.append(SectionSpec(name=s.name, kind="flighted", length=s.length, n_cells=s.n_cells,
                                             geometry=geoms[s.name], kilning="velocity",
                                             kiln_velocity=inp["kiln_velocity"], loading="state", fouling=fouling,
                                             moisture=mmg_moisture_profile(pos, c.solids.moisture_scale)))
                x0 += s.length
            return specs
        if self.kind == "lee2008":
            from .cases import _exact_drum, lee_parameters
            from .geometry.lee2008_regressions import Lee2008Regressions, invicta_tip_radius
            from .transport.models import lee2008_repose_profile

            d, fl, s = c.drum, c.flight, c.solids
            geometry = (_exact_drum(d.radius, d.n_flights, fl.s1, fl.s2, fl.alpha1, fl.alpha2)
                        if c.geometry.method == "exact" else
                        Lee2008Regressions(tip_radius=invicta_tip_radius(d.radius, fl.s1, fl.s2, fl.alpha1, fl.alpha2)))
            p = lee_parameters(c)
            N = c.transport.n_cells
            kw = dict(name="dryer", kind="flighted", length=d.length, n_cells=N, geometry=geometry, kilning="excess",
                      kiln_time=p["kiln_time"], drag_reduction=p["drag_reduction"], backmix=p["backmix"],
                      backmix_to="active" if c.transport.model == "sheehan2005_model2" else c.transport.backmix_to,
                      loading=c.transport.loading, passive_time_branch=c.geometry.passive_time_branch)
            if thermal:
                mat = self.material
                w = _exponential_profile(s.moisture_inlet, s.moisture_outlet, np.arange(N) / max(N - 1, 1))
                kw["moisture"] = w / (1 + w) if mat.moisture_basis == "dry" else w
                if s.repose_angle is not None:
                    kw["repose_angle"] = s.repose_angle
                kw["bulk_density"] = s.bulk_density
            else:
                kw["repose_angle"] = (s.repose_angle if s.repose_angle is not None else
                                      lee2008_repose_profile(N, s.moisture_inlet, s.moisture_outlet))
                kw["bulk_density"] = s.bulk_density
            return [SectionSpec(**kw)]
        return self._general_specs()

    def _general_specs(self):
        from .cases import _exact_drum
        from .transport.ajayi import _ExactAdapter
        from .transport.sections import SectionSpec

        c = self.case
        tr = c.transport
        mat = self.material
        F, rpm, x_in, _ = self._operating()
        mat.check_moisture("operating.feed_moisture", x_in)
        x_out = x_in if tr.product_moisture is None else tr.product_moisture
        mat.check_moisture("transport.product_moisture", x_out)
        length = sum(s.length for s in c.sections)
        specs, x0 = [], 0.0
        for i, s in enumerate(c.sections):
            if s.kind == "unflighted":
                specs.append(SectionSpec(name=s.name, kind="unflighted", length=s.length,
                                         n_cells=s.n_cells or tr.unflighted_cells, velocity=tr.solids_velocity,
                                         dispersion=tr.dispersion))
            else:
                g = {k: getattr(s, k) if getattr(s, k) is not None else getattr(c.flight, k, None)
                     for k in ("s1", "s2", "alpha1", "alpha2")}
                drum = _exact_drum(c.drum.radius, s.n_flights or c.drum.n_flights, **g)
                model = s.model or tr.model
                geometry = _ExactAdapter(drum, c.geometry.passive_time_branch) \
                    if c.geometry.design_load_method == "ajayi2011" else _LeeExact(drum, c.geometry.passive_time_branch)
                N = s.n_cells or tr.n_cells
                pos = x0 + (np.arange(N) + 0.5) * s.length / N
                common = dict(name=s.name, kind="flighted", length=s.length, n_cells=N, geometry=geometry,
                              loading=tr.loading, fouling=tr.fouling,
                              moisture=_exponential_profile(x_in, x_out, pos / length))
                if model == "ajayi2011":
                    specs.append(SectionSpec(kilning="velocity", kiln_velocity=tr.solids_velocity, **common))
                else:
                    specs.append(SectionSpec(kilning="excess", kiln_time=tr.kiln_time, drag_reduction=tr.drag_reduction,
                                             backmix=tr.backmix,
                                             backmix_to="active" if model == "sheehan2005_model2" else "passive",
                                             **common))
            x0 += s.length
        return specs

    # ------------------------------------------------------------------ transport
    def transport_model(self):
        """The solids-transport model (TransportModel on the network) of the case."""
        if self._transport is None:
            if self.kind == "dryer":
                from .transport import TracerInput
                from .transport.sections import build_sections

                c = self.case
                F, rpm, _, _ = self._operating()
                tr = c.tracer
                self._transport = build_sections(
                    self._general_specs(), material=self.material, feed_rate=F, rpm=rpm, slope=c.drum.slope,
                    inlet="danckwerts", tracer_input=TracerInput.pulse(tr.fraction * F * max(tr.duration, 1e-6),
                                                                       tr.duration),
                    name="dryer", parameters=dict(feed_rate=F, rpm=rpm, slope=c.drum.slope))
            else:
                from .cases import build_model

                self._transport = build_model(self.case)
        return self._transport

    def transport_steady_state(self):
        if self._transport_ss is None:
            self._transport_ss = self.transport_model().steady_state()
        return self._transport_ss

    # ------------------------------------------------------------------ heat and mass
    def thermal_settings(self):
        """:class:`~rotarydryer.thermal.dryer.ThermalSettings` of the case."""
        from .thermal.dryer import ThermalSettings, settings_from_case

        c = self.case
        if self.kind == "ajayi2011":
            st = settings_from_case(c)
            st.gas_direction = c.operating.gas_flow
            return st
        if c.gas is None:
            raise ValueError("gas is missing: give [gas] flow and inlet_temperature to compute heat and mass transfer")
        g, sh, th = c.gas, c.shell, c.thermal
        _, _, _, t_feed = self._operating()
        kw = dict(mode=th.mode, gas_flow=g.flow, gas_inlet_temperature=g.inlet_temperature,
                  gas_inlet_humidity=g.inlet_humidity, solids_inlet_temperature=t_feed,
                  ambient_temperature=sh.ambient_temperature, ambient_humidity=sh.ambient_humidity,
                  area_scale=th.area_scale, scale_thickness=sh.scale_thickness,
                  insulation_thickness=sh.insulation_thickness, loss_factor=sh.loss_factor,
                  leak_air_flow=g.leak_air_flow, moisture_coupling=th.moisture_coupling,
                  design_load_smoothing=th.design_load_smoothing, gas_direction=g.direction)
        if self.kind == "dryer":
            kw["fouling"] = c.transport.fouling
        return ThermalSettings.ajayi2011(**kw) if th.mode == "ajayi2011" else ThermalSettings(**kw)

    def thermal_dryer(self, settings=None, feed_moisture=None, **overrides):
        """The heat-and-mass model on the case's network (closed inlet, the case's thermal cells)."""
        from .thermal.dryer import SectionThermal, ThermalDryer, ThermalSettings
        from .transport.sections import build_sections

        c = self.case
        st = settings if settings is not None else self.thermal_settings()
        unknown = sorted(set(overrides) - {f.name for f in dataclasses.fields(ThermalSettings)})
        if unknown:
            raise ValueError(f"unknown ThermalSettings field(s) {', '.join(map(repr, unknown))}; valid: "
                             f"{', '.join(f.name for f in dataclasses.fields(ThermalSettings))}")
        st = dataclasses.replace(st, **overrides)
        F, rpm, x_in, _ = self._operating()
        if feed_moisture is not None:
            x_in = feed_moisture
        specs = self._specs(thermal=True)
        for sp in specs:
            sp.fouling = st.fouling
        mat = self.material
        if self.kind == "ajayi2011" and st.mode != "ajayi2011" and x_in is not None:
            pass
        model = build_sections(specs, material=mat, feed_rate=F, rpm=rpm, slope=c.drum.slope, inlet="danckwerts",
                               name="thermal")
        sec_th = {}
        for s in getattr(c, "sections", []) if self.kind != "lee2008" else []:
            sec_th[s.name] = SectionThermal(area_factor=getattr(s, "area_factor", 1.0),
                                            particle_diameter=getattr(s, "particle_diameter", None),
                                            shell_temperature=getattr(s, "shell_temperature", None))
        radius = c.drum.radius
        return ThermalDryer(model, material=mat, feed_rate=F, feed_moisture=x_in, rpm=rpm, radius=radius,
                            sections=sec_th, settings=st)

    # ------------------------------------------------------------------ runs
    def steady_state(self):
        """Steady state of the whole dryer: transport, and heat and mass where the case has a gas."""
        thermal = None
        if self.thermal_enabled:
            thermal = self.thermal_dryer().steady_state()
        return SteadyResult(self, self.transport_steady_state() if thermal is None else None, thermal)

    def dynamics(self, t_end=7200.0, dt=60.0, **changes):
        """Step response from the steady state: ``changes`` are inputs of
        :data:`rotarydryer.thermal.studies.INPUTS` (absolute new values)."""
        from .thermal.studies import perturbed

        d = self.thermal_dryer()
        ss = d.steady_state()
        d2 = perturbed(d, **changes) if changes else d
        return d2.simulate(ss.state, t_end, t_eval=np.arange(0.0, t_end + dt / 2, dt))

    def rtd(self, t_end=None, dt=None, method="auto"):
        """Tracer response at the (transport) steady state with the case's tracer pulse."""
        tr = self.case.tracer
        return self.transport_steady_state().rtd(self.transport_model().tracer_input, t_end=t_end or tr.t_end,
                                                 dt=dt or tr.dt, method=method)

    def results(self):
        """:class:`rotarydryer.results.Results` of the case (transport, RTD, heat and mass)."""
        from .results import run_case

        return run_case(self.case, name=self.case_name)

    def fit(self, dataset, parameters, **kwargs):
        """Fit ``parameters`` (override keys) to a dataset (:func:`rotarydryer.estimation.fit_case`)."""
        from .estimation.cases import fit_case

        return fit_case(self.case_name, dataset, parameters, **kwargs)

    def sweep(self, grid, outputs=None):
        """Steady state over a grid of overrides: list of dicts (``grid``: list of override dicts)."""
        rows = []
        for ov in grid:
            sim = Simulation(self.case_name, ov)
            row = dict(ov)
            row.update(sim.steady_state().summary())
            rows.append({k: row[k] for k in (outputs or row)})
        return rows


class _LeeExact:
    """Exact FlightedDrum with Lee's design load (Lee (2008) Eq. 4.20-4.21)."""

    def __init__(self, drum, branch):
        self.drum, self.branch = drum, branch

    def __repr__(self):
        return f"exact({self.drum!r})"

    def design_load_area(self, phi):
        return self.drum.design_load_area(phi)

    def loading_factor(self, d, phi):
        return self.drum.loading_factor(d, phi)

    def cascade(self, phi, f, *, rpm, slope=0.0, passive_time_branch=None):
        kw = dict(rpm=rpm, slope=slope)
        b = passive_time_branch or self.branch
        if b is not None:
            kw["passive_time_branch"] = b
        return self.drum.cascade(phi, f, **kw)


class SteadyResult:
    """Steady state of a :class:`Simulation`: one total holdup, one set of names.

    ``transport``: the transport-only steady state (no gas) or None; ``thermal``: the coupled
    :class:`~rotarydryer.thermal.dryer.ThermalSteadyState` or None. With heat and mass transfer
    every holdup, residence time and tracer moment is that of the coupled state (the tracer
    system is built on its flows), so the numbers add up.
    """

    def __init__(self, sim, transport, thermal):
        self.simulation, self.transport, self.thermal = sim, transport, thermal

    def tracer_moments(self):
        tr = self.simulation.transport_model().tracer_input
        if self.thermal is not None:
            return self.thermal.tracer_system().moments(tr)
        return self.transport.tracer_system().moments(tr)

    def summary(self) -> dict:
        m = self.tracer_moments()
        out = {}
        if self.thermal is not None:
            th = self.thermal
            kind = th.dryer.kind
            hold = th.holdup
            prod = float(th.product_rate)
            out.update(
                total_holdup_kg=float(np.sum(hold)), active_holdup_kg=float(np.sum(hold[kind == 2])),
                passive_holdup_kg=float(np.sum(hold[kind == 1])), bed_holdup_kg=float(np.sum(hold[kind == 0])),
                feed_rate_kg_s=th.dryer.feed_rate, product_rate_kg_s=prod,
                mean_residence_time_s=float(np.sum(hold)) / prod)
            s = th.summary(with_fuel=False)
            out.update(
                product_moisture_kg_kg=s["product_moisture"], product_temperature_degC=s["product_temperature_C"],
                gas_outlet_temperature_degC=s["gas_outlet_temperature_C"],
                gas_outlet_humidity_kg_kg=s["gas_outlet_humidity"], evaporation_kg_s=s["evaporation_kg_s"],
                shell_heat_loss_W=s["shell_heat_loss_W"], gas_flow_kg_s=s["gas_flow_kg_s"],
                energy_balance_error=s["energy_balance_error"], water_balance_error=s["water_balance_error"],
                solids_balance_error=float(th.solids_balance_error),
                physical_energy_balance_error=s["physical_energy_balance_error"],
                transport_moisture_clipped=s["transport_moisture_clipped"], thermal_mode=s["mode"],
                solver_iterations=s["solver_iterations"])
        else:
            ss = self.transport
            out.update(total_holdup_kg=ss.total_holdup, active_holdup_kg=ss.active_holdup,
                       passive_holdup_kg=ss.passive_holdup, bed_holdup_kg=ss.bed_holdup,
                       feed_rate_kg_s=float(self.simulation.transport_model().feed_rate),
                       product_rate_kg_s=ss.outlet_flow, mean_residence_time_s=ss.mean_residence_time)
        out.update(tracer_mean_s=m["mean"], tracer_std_s=m["std"], tracer_recovery=m["recovery"])
        return out
