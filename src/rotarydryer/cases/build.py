"""From a validated case to model inputs: the only place that reads case objects.

* :func:`build_model` - the solids-transport model (:class:`~rotarydryer.transport.TransportModel`)
  of any case kind; every kind ends in :func:`rotarydryer.transport.sections.build_sections`,
  and the model keeps its section specs (``model.specs``);
* :func:`thermal_inputs` - what the heat-and-mass model adds to those sections: thermal
  settings, per-section heat-transfer data, the material, feed moisture and the changes to the
  transport sections (thermal discretisation, moisture-dependent properties).

Models (``transport``, ``thermal``) never import this module; :class:`rotarydryer.Simulation`
and the other entry points do.
"""

from __future__ import annotations

import math

import numpy as np

from . import AjayiCase, DryerCase, LeeCase

__all__ = ["build_model", "exact_drum", "lee_parameters", "ajayi_test_inputs", "ajayi_geometries",
           "settings_from_case", "thermal_inputs", "thermal_enabled", "has_burner", "burner_of", "material_of",
           "operating_point"]


def exact_drum(radius, n_flights, s1, s2, alpha1, alpha2):
    """Exact flight geometry (:class:`rotarydryer.geometry.FlightedDrum`) of a two-section flight."""
    from rotarydryer.geometry import FlightedDrum, TwoSectionFlight

    return FlightedDrum(radius=radius, n_flights=n_flights,
                        flight=TwoSectionFlight(s1=s1, s2=s2, alpha1=alpha1, alpha2=alpha2))


def material_of(case):
    """The :class:`rotarydryer.properties.materials.Material` of a case."""
    from rotarydryer.properties.materials import load_material

    spec = case.material
    if spec is None:
        raise ValueError("material is missing: name one from the materials library "
                         "(rotarydryer.properties.materials.list_materials()) in [material]")
    d = spec.model_dump()
    return load_material(d["name"] if set(d) == {"name"} else d)


def _tracer_pulse(case, feed_rate):
    from rotarydryer.transport import TracerInput

    tr = case.tracer
    return TracerInput.pulse(tr.fraction * feed_rate * max(tr.duration, 1e-6), tr.duration)


def build_model(case):
    """The :class:`rotarydryer.transport.TransportModel` of a validated case (any kind)."""
    if isinstance(case, LeeCase):
        return _build_lee(case)
    if isinstance(case, AjayiCase):
        return _build_ajayi(case)
    if isinstance(case, DryerCase):
        return _build_dryer(case)
    raise ValueError(f"case of type {type(case).__name__} is not supported")


# ---- Lee (2008) Invicta ------------------------------------------------------------------
def lee_parameters(case: LeeCase) -> dict:
    """(kiln_time, backmix, drag_reduction) for the case: explicit values, else the
    Table 7.2 row for ``transport.n_cells``."""
    t = case.transport
    row = next((p for p in case.parameter_sets if p.n_cells == t.n_cells), None)
    out = {}
    for key in ("kiln_time", "backmix", "drag_reduction"):
        v = getattr(t, key)
        if v is None:
            if row is None:
                have = ", ".join(str(p.n_cells) for p in case.parameter_sets)
                raise ValueError(
                    f"transport.n_cells = {t.n_cells} has no Table 7.2 parameter set (available: {have}); "
                    f"set transport.{key} (and the other transport coefficients) explicitly"
                )
            v = getattr(row, key)
        out[key] = v
    return out


def _check_lee_moisture(case: LeeCase):
    """Lee's moistures w (kg water per kg dry solids, Eq. 7.3; Appendix I l.12456) inside the range
    of the case's material, when it names one."""
    if case.material is not None:
        mat = material_of(case)
        for key in ("moisture_inlet", "moisture_outlet"):
            mat.check_moisture(f"solids.{key}", getattr(case.solids, key), basis="dry")


def _build_lee(case: LeeCase):
    from rotarydryer.geometry.lee2008_regressions import Lee2008Regressions, invicta_tip_radius
    from rotarydryer.transport import lee2008, lee2008_repose_profile

    _check_lee_moisture(case)
    d, fl = case.drum, case.flight
    if case.geometry.method == "exact":
        geometry = exact_drum(d.radius, d.n_flights, fl.s1, fl.s2, fl.alpha1, fl.alpha2)
    else:
        geometry = Lee2008Regressions(tip_radius=invicta_tip_radius(d.radius, fl.s1, fl.s2, fl.alpha1, fl.alpha2))
    p = lee_parameters(case)
    N = case.transport.n_cells
    s = case.solids
    phi = s.repose_angle if s.repose_angle is not None else lee2008_repose_profile(N, s.moisture_inlet, s.moisture_outlet)
    F = case.operating.feed_rate
    kwargs = dict(
        geometry=geometry, n_cells=N, feed_rate=F, length=d.length, rpm=case.operating.rpm, slope=d.slope,
        bulk_density=s.bulk_density, repose_angle=phi, kiln_time=p["kiln_time"], backmix=p["backmix"],
        drag_reduction=p["drag_reduction"], passive_time_branch=case.geometry.passive_time_branch,
        loading=case.transport.loading, backmix_to=case.transport.backmix_to,
        gas_flow=case.operating.gas_flow, tracer_input=_tracer_pulse(case, F), name=case.transport.model,
    )
    if case.transport.model == "sheehan2005_model2":
        kwargs["backmix_to"] = "active"
    return lee2008(**kwargs)


def _exponential_profile(x_in, x_out, frac):
    """Moisture along the dryer (fraction 0..1 of its length), exponential as Lee (2008) Eq. 7.3
    when both ends are > 0, else linear."""
    if x_in > 0 and x_out > 0:
        return x_in * np.exp(frac * math.log(x_out / x_in))
    return x_in + (x_out - x_in) * frac


# ---- Ajayi (2011) MMG --------------------------------------------------------------------
def ajayi_test_inputs(case: AjayiCase) -> dict:
    """Per-test inputs of an ``AjayiCase``: the selected test row (``test``), feed rate
    ``feed_rate`` (kg/s), ``rpm``, solids velocity ``kiln_velocity`` (m/s) and ``dispersion``
    (m^2/s): case overrides first, else the test's Table 5.2 values."""
    test = next((t for t in case.tests if t.test == case.operating.test), None)
    if test is None:
        raise ValueError(f"operating.test = {case.operating.test} is not in the case's tests "
                         f"({', '.join(str(t.test) for t in case.tests)})")
    tr = case.transport
    return dict(test=test, feed_rate=case.operating.feed_rate or test.feed_rate,
                rpm=case.operating.rpm or test.rpm,
                kiln_velocity=tr.solids_velocity or tr.kiln_velocity or test.kiln_velocity,
                dispersion=tr.dispersion if tr.dispersion is not None else test.dispersion)


def ajayi_geometries(case: AjayiCase) -> dict:
    """Cell geometry model of each flighted section (Ajayi's regressions or the exact flight
    geometry with Ajayi's design load, per ``geometry.method``), without fouling."""
    from rotarydryer.transport.ajayi import AjayiRegressions
    from rotarydryer.transport.sections import ExactGeometry

    geoms = {}
    for s in case.sections:
        if s.kind != "flighted":
            continue
        if case.geometry.method == "ajayi2011_regressions":
            reg = s.regression or {}
            geoms[s.name] = AjayiRegressions(reg["area"], reg["fall_time"], case.drum.radius,
                                             case.transport.design_load_factor)
        else:
            drum = exact_drum(case.drum.radius, s.n_flights, s.s1, s.s2, s.alpha1, s.alpha2)
            geoms[s.name] = ExactGeometry(drum, case.geometry.passive_time_branch, design_load_method="ajayi2011")
    return geoms


def _ajayi_fouling(case: AjayiCase, test) -> float:
    """Transport fouling: the case's, else 0.8 for tests marked 'Scaled' (Ajayi (2011) l.1715)."""
    fouling = case.transport.fouling
    return fouling if fouling is not None else (0.8 if test.scaled else 0.0)


def _build_ajayi(case: AjayiCase):
    from rotarydryer.transport.ajayi import ajayi2011

    inp = ajayi_test_inputs(case)
    F = inp["feed_rate"]
    tr = case.transport
    secs = [dict(name=s.name, kind=s.kind, length=s.length, n_cells=s.n_cells) for s in case.sections]
    return ajayi2011(sections=secs, feed_rate=F, rpm=inp["rpm"], slope=case.drum.slope, radius=case.drum.radius,
                     kiln_velocity=inp["kiln_velocity"], dispersion=inp["dispersion"],
                     geometries=ajayi_geometries(case), fouling=_ajayi_fouling(case, inp["test"]),
                     moisture_scale=case.solids.moisture_scale, inlet=tr.unflighted_inlet,
                     unflighted_cells=tr.unflighted_cells, tracer_input=_tracer_pulse(case, F),
                     gas_flow=case.operating.gas_flow, material=material_of(case))


def settings_from_case(case: AjayiCase):
    """ThermalSettings of an ``AjayiCase``: its ``thermal`` section and the selected test's PI data
    (gas inlet temperature; Test 3 'Scaled' -> fouling 0.8, Ajayi l.1715). A test's own ``gas_flow``
    ([[tests]], kg/s wet) replaces ``thermal.gas_flow`` in the physical mode."""
    from rotarydryer.thermal.dryer import ThermalSettings, pi_operating_conditions

    raw = case.thermal.model_dump()
    mode = raw.pop("mode", "physical")
    raw.pop("burner", None)          # built by burner_of (thermal_inputs)
    raw = {k: v for k, v in raw.items() if v is not None}
    fields = {k: v for k, v in raw.items() if k in ThermalSettings.__dataclass_fields__}
    if mode == "ajayi2011":
        fields.pop("gas_flow", None)
        fields.pop("area_scale", None)
        st = ThermalSettings.ajayi2011(**fields)
    else:
        st = ThermalSettings(**fields)
    pi = pi_operating_conditions(case.operating.test)
    test = next((t for t in case.tests if t.test == case.operating.test), None)
    if mode != "ajayi2011" and getattr(test, "gas_flow", None) is not None:
        st.gas_flow = float(test.gas_flow)      # the test's own gas flow, when the case knows it
    if "gas_inlet_temperature" not in raw:
        st.gas_inlet_temperature = float(pi["gas_inlet_T_C"])
    if "fouling" not in raw:
        # one physical quantity: the transport case's fouling when set, else 0.8 for 'Scaled' tests
        if case.transport.fouling is not None:
            st.fouling = float(case.transport.fouling)
        elif pi["internal_condition"].strip().lower() == "scaled":
            st.fouling = 0.8
    st.gas_direction = case.operating.gas_flow
    return st


# ---- the general schema --------------------------------------------------------------------
def operating_point(case):
    """(feed rate kg/s wet, rpm, feed moisture kg/kg wet, feed temperature degC) of a case."""
    if isinstance(case, AjayiCase):
        inp = ajayi_test_inputs(case)
        return inp["feed_rate"], inp["rpm"], inp["test"].moisture_inlet, case.thermal.solids_inlet_temperature
    if isinstance(case, LeeCase):
        _check_lee_moisture(case)
        w_in = case.solids.moisture_inlet
        x_in = w_in / (1 + w_in)
        t_in = getattr(case.gas, "feed_temperature", None)
        return case.operating.feed_rate, case.operating.rpm, x_in, 20.0 if t_in is None else t_in
    o = case.operating
    return o.feed_rate, o.rpm, o.feed_moisture, o.feed_temperature


def _dryer_specs(case: DryerCase, material):
    from rotarydryer.transport.sections import ExactGeometry, SectionSpec

    tr = case.transport
    _, _, x_in, _ = operating_point(case)
    material.check_moisture("operating.feed_moisture", x_in)
    x_out = x_in if tr.product_moisture is None else tr.product_moisture
    material.check_moisture("transport.product_moisture", x_out)
    length = sum(s.length for s in case.sections)
    specs, x0 = [], 0.0
    for s in case.sections:
        if s.kind == "unflighted":
            specs.append(SectionSpec(name=s.name, kind="unflighted", length=s.length,
                                     n_cells=s.n_cells or tr.unflighted_cells, velocity=tr.solids_velocity,
                                     dispersion=tr.dispersion))
        else:
            g = {k: getattr(s, k) if getattr(s, k) is not None else getattr(case.flight, k)
                 for k in ("s1", "s2", "alpha1", "alpha2")}
            drum = exact_drum(case.drum.radius, s.n_flights or case.drum.n_flights, **g)
            geometry = ExactGeometry(drum, case.geometry.passive_time_branch,
                                     design_load_method=case.geometry.design_load_method)
            model = s.model or tr.model
            N = s.n_cells or tr.n_cells
            pos = x0 + (np.arange(N) + 0.5) * s.length / N
            common = dict(name=s.name, kind="flighted", length=s.length, n_cells=N, geometry=geometry,
                          loading=tr.loading, fouling=tr.fouling,
                          moisture=_exponential_profile(x_in, x_out, pos / length))
            if model == "ajayi2011":
                specs.append(SectionSpec(kilning="velocity", kiln_velocity=tr.solids_velocity, **common))
            elif model == "sheehan2005_model1":
                rates = {k: getattr(tr, k) for k in ("passive_rate", "exchange_rate", "return_rate", "kiln_rate")}
                missing = [k for k, v in rates.items() if v is None]
                if missing:
                    raise ValueError(f"sections {s.name!r}: model = 'sheehan2005_model1' needs "
                                     f"{', '.join('transport.' + k for k in missing)} (1/s)")
                specs.append(SectionSpec(kilning="empirical", rates=rates, **common))
            else:
                specs.append(SectionSpec(kilning="excess", kiln_time=tr.kiln_time, drag_reduction=tr.drag_reduction,
                                         backmix=tr.backmix,
                                         backmix_to="active" if model == "sheehan2005_model2" else "passive",
                                         **common))
        x0 += s.length
    return specs


def _build_dryer(case: DryerCase):
    from rotarydryer.transport.sections import build_sections

    material = material_of(case)
    F, rpm, _, _ = operating_point(case)
    return build_sections(_dryer_specs(case, material), material=material, feed_rate=F, rpm=rpm,
                          slope=case.drum.slope, inlet="danckwerts", tracer_input=_tracer_pulse(case, F),
                          name="dryer", parameters=dict(feed_rate=F, rpm=rpm, slope=case.drum.slope))


# ---- heat and mass transfer ----------------------------------------------------------------
def thermal_enabled(case) -> bool:
    """Does the case ask for heat and mass transfer (and give what it needs)?"""
    if isinstance(case, LeeCase):
        return bool(case.thermal.enabled and case.gas is not None and case.material is not None)
    return bool(case.thermal.enabled)


def _burner_block(case):
    """The case's burner block, or None."""
    if isinstance(case, AjayiCase):
        return case.thermal.burner
    return getattr(case.gas, "burner", None) if case.gas is not None else None


def has_burner(case) -> bool:
    """Does the case's gas come from a burner ([gas.burner], or the MMG case's [thermal.burner]:
    Ajayi's combustion chamber, App. A) whose fuel rate the model can give?"""
    return _burner_block(case) is not None


def burner_of(case):
    """:class:`~rotarydryer.thermal.burner.Burner` of the case, or None."""
    from rotarydryer.thermal.burner import Burner, FuelOil

    b = _burner_block(case)
    if b is None:
        return None
    fuel = FuelOil(water_mass_fraction=b.fuel_water_fraction, sulphur_mass_fraction=b.fuel_sulphur_fraction,
                   carbon_hydrogen_ratio=b.fuel_carbon_hydrogen_ratio, lower_heating_value=b.fuel_lower_heating_value)
    return Burner(combustion_air_share=b.combustion_air_share, heat_loss_fraction=b.heat_loss_fraction, fuel=fuel)


def _general_settings(case):
    from rotarydryer.thermal.dryer import ThermalSettings

    if case.gas is None:
        raise ValueError("gas is missing: give [gas] flow and inlet_temperature to compute heat and mass transfer")
    g, sh, th = case.gas, case.shell, case.thermal
    _, _, _, t_feed = operating_point(case)
    kw = dict(mode=th.mode, gas_flow=g.flow, gas_inlet_temperature=g.inlet_temperature,
              gas_inlet_humidity=g.inlet_humidity, solids_inlet_temperature=t_feed,
              ambient_temperature=sh.ambient_temperature, ambient_humidity=sh.ambient_humidity,
              area_scale=th.area_scale, scale_thickness=sh.scale_thickness,
              insulation_thickness=sh.insulation_thickness, loss_factor=sh.loss_factor,
              leak_air_flow=g.leak_air_flow, moisture_coupling=th.moisture_coupling,
              design_load_smoothing=th.design_load_smoothing, gas_direction=g.direction)
    if isinstance(case, DryerCase):
        kw["fouling"] = case.transport.fouling
    return ThermalSettings.ajayi2011(**kw) if th.mode == "ajayi2011" else ThermalSettings(**kw)


def thermal_inputs(case) -> dict:
    """Inputs of the heat-and-mass model of a case: ``settings`` (ThermalSettings), ``sections``
    (name -> SectionThermal), ``material``, ``feed_moisture`` (kg/kg wet) and ``section_changes``
    (name -> SectionSpec fields that differ from the transport model's sections)."""
    from rotarydryer.thermal.dryer import SectionThermal

    material = material_of(case)
    _, _, x_in, _ = operating_point(case)
    changes = {}
    sec_th = {}
    if isinstance(case, AjayiCase):
        settings = settings_from_case(case)
        for s in case.sections:
            if s.kind == "unflighted":     # the thermal model's bed discretisation (case data)
                changes[s.name] = dict(n_cells=case.thermal.unflighted_cells.get(
                    s.name, max(4, int(math.ceil(s.length / 0.3)))))
    else:
        settings = _general_settings(case)
    settings.burner = burner_of(case)
    if isinstance(case, LeeCase):
        # repose angle from the computed moisture (Lee (2008) Eq. 7.2 through the material) unless the
        # case fixes it; the Eq. 7.3 exponential profile is the start and the transport-only moisture
        s, N = case.solids, case.transport.n_cells
        w = _exponential_profile(s.moisture_inlet, s.moisture_outlet, np.arange(N) / max(N - 1, 1))
        changes["dryer"] = dict(repose_angle=s.repose_angle, moisture=w / (1 + w))
    else:
        for s in case.sections:
            sec_th[s.name] = SectionThermal(area_factor=s.area_factor, particle_diameter=s.particle_diameter,
                                            shell_temperature=s.shell_temperature)
    return dict(settings=settings, sections=sec_th, material=material, feed_moisture=x_in,
                section_changes=changes)
