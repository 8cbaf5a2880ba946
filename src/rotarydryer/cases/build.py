"""From a validated case to model inputs: the only place that reads case objects.

* :func:`build_model` - the solids-transport model (:class:`~rotarydryer.transport.TransportModel`)
  of any case kind; every kind ends in :func:`rotarydryer.transport.sections.build_sections`,
  and the model keeps its section specs (``model.specs``);
* :func:`thermal_inputs` - what the heat-and-mass model adds to those sections: thermal
  settings, per-section heat-transfer data, the material, feed moisture and the changes to the
  transport sections (thermal discretisation, moisture-dependent properties);
* :func:`check_inputs` and :func:`check_feasible` - physical feasibility of a case, with
  messages that name the case key, its value, the limit and the unit: drum dimensions finite
  and positive, flights that fit the drum, a bulk density of a granular solid, the drum speed
  below the critical speed 42.3/sqrt(D) rev/min (:func:`rotarydryer.geometry.check_speed`; a
  :class:`~rotarydryer.geometry.CriticalSpeedWarning` above half of it) and, at the steady
  state, a solids fill of at most :data:`FILL_LIMIT` of the drum volume (whole drum and every
  section). :func:`build_model` runs both (the fill check on every steady state of the model).

Models (``transport``, ``thermal``) never import this module; :class:`rotarydryer.Simulation`
and the other entry points do.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .._validation import check_range, fmt_number
from . import AjayiCase, DryerCase, LeeCase

#: largest solids fill of the drum volume (whole drum and each section) of a feasible steady state:
#: loaded flighted dryers run at 10-15 %; every shipped case is below 16 % (Invicta 8.9 %, MMG tests
#: 2-6 up to 15.6 % in the unflighted section A, Song 9.3 %)
FILL_LIMIT = 0.30
#: bulk densities a granular solid can have, kg/m^3: above air (1.2) and below osmium (22 590)
BULK_DENSITY_RANGE = (1.0, 23000.0)

__all__ = ["build_model", "check_inputs", "check_feasible", "FILL_LIMIT", "BULK_DENSITY_RANGE",
           "exact_drum", "lee_parameters", "ajayi_test_inputs", "ajayi_geometries",
           "settings_from_case", "thermal_inputs", "thermal_enabled", "has_burner", "burner_of", "material_of",
           "operating_point", "curtain_gas"]


def exact_drum(radius, n_flights, s1, s2, alpha1, alpha2, *, where="flight", n_flights_key="drum.n_flights"):
    """Exact flight geometry (:class:`rotarydryer.geometry.FlightedDrum`) of a two-section flight.

    A geometry that cannot be built raises ``ValueError`` naming the case keys (``drum.radius``,
    ``n_flights_key``, ``<where>.s1`` ...) with their values."""
    from rotarydryer.geometry import FlightedDrum, TwoSectionFlight

    try:
        return FlightedDrum(radius=radius, n_flights=n_flights,
                            flight=TwoSectionFlight(s1=s1, s2=s2, alpha1=alpha1, alpha2=alpha2))
    except ValueError as exc:
        keys = (f"drum.radius = {fmt_number(radius)} m, {n_flights_key} = {fmt_number(n_flights)}, "
                f"{where}.s1 = {fmt_number(s1)} m, {where}.s2 = {fmt_number(s2)} m, "
                f"{where}.alpha1 = {fmt_number(alpha1)} deg, {where}.alpha2 = {fmt_number(alpha2)} deg")
        raise ValueError(f"flight geometry ({keys}): {exc}") from None


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
    """The :class:`rotarydryer.transport.TransportModel` of a validated case (any kind).

    The case is checked first (:func:`check_inputs`) and every steady state of the model is
    checked for its fill of the drum (:func:`check_feasible`)."""
    if not isinstance(case, (LeeCase, AjayiCase, DryerCase)):
        raise ValueError(f"case of type {type(case).__name__} is not supported")
    check_inputs(case)
    if isinstance(case, LeeCase):
        model = _build_lee(case)
    elif isinstance(case, AjayiCase):
        model = _build_ajayi(case)
    else:
        model = _build_dryer(case)
    model = _with_core(case, model)
    model.checks.append(functools.partial(check_feasible, case))     # picklable, unlike a lambda
    return model


# ---- feasibility ---------------------------------------------------------------------------
def _section_lengths(case):
    """[(key prefix, name, length m)] of the case's sections (Lee: one drum)."""
    if isinstance(case, LeeCase):
        return [("drum", "dryer", case.drum.length)]
    return [(f"sections[{k}] ({s.name})", s.name, s.length) for k, s in enumerate(case.sections)]


def _speed_key(case) -> str:
    if isinstance(case, AjayiCase) and case.operating.rpm is None:
        return f"operating.rpm (test {case.operating.test})"
    return "operating.rpm"


def _feed_text(case, F) -> str:
    """``operating.feed_rate = F kg/s`` (with the test whose value it is, for Ajayi's cases)."""
    if isinstance(case, AjayiCase) and case.operating.feed_rate is None:
        return f"operating.feed_rate = {fmt_number(F)} kg/s (the value of test {case.operating.test})"
    return f"operating.feed_rate = {fmt_number(F)} kg/s"


def check_inputs(case) -> None:
    """Physical checks of a case before any model is built; ``ValueError`` names the key, its
    value, the allowed range and the unit.

    * ``drum.radius``, ``drum.length`` / section lengths finite and > 0, ``drum.slope`` in [0, 45) deg;
    * the feed rate finite and > 0; the drum speed below the critical speed N_c = 42.3/sqrt(D)
      rev/min (:func:`rotarydryer.geometry.check_speed`; a warning above half of it);
    * Lee's ``solids.bulk_density`` in :data:`BULK_DENSITY_RANGE`; ``solids.repose_angle`` in (0, 90);
    * each flight fits the drum: its base shorter than the radius.
    """
    from rotarydryer.geometry import check_speed

    d = case.drum
    R = float(check_range("drum.radius", d.radius, 0.0, math.inf, unit="m"))
    check_range("drum.slope", d.slope, 0.0, 45.0, low_inclusive=True, unit="deg")
    for prefix, _, L in _section_lengths(case):
        check_range(f"{prefix}.length", L, 0.0, math.inf, unit="m")
    F, rpm, _, _ = operating_point(case)
    check_range("operating.feed_rate", F, 0.0, math.inf, unit="kg/s")
    check_speed(_speed_key(case), rpm, R, radius_key="drum.radius")
    flights = []
    if isinstance(case, LeeCase):
        lo, hi = BULK_DENSITY_RANGE
        check_range("solids.bulk_density", case.solids.bulk_density, lo, hi, low_inclusive=True,
                    high_inclusive=True, unit="kg/m^3")
        if case.solids.repose_angle is not None:
            check_range("solids.repose_angle", case.solids.repose_angle, 0.0, 90.0, unit="deg")
        flights.append(("flight", case.flight.s1))
    elif isinstance(case, AjayiCase):
        flights += [(f"sections[{k}] ({s.name})", s.s1) for k, s in enumerate(case.sections)
                    if s.kind == "flighted" and s.s1 is not None]
    else:
        for k, s in enumerate(case.sections):
            if s.kind == "flighted":
                own = getattr(s, "s1", None)
                flights.append((f"sections[{k}] ({s.name})" if own is not None else "flight",
                                own if own is not None else case.flight.s1))
    for where, s1 in flights:
        s1 = float(check_range(f"{where}.s1", s1, 0.0, math.inf, unit="m"))
        if s1 >= R:
            raise ValueError(f"{where}.s1 = {fmt_number(s1)} m does not fit drum.radius = {fmt_number(R)} m: "
                             "the flight base must be shorter than the drum radius")


def _bed_density(case):
    """Bulk density (kg/m^3) for unflighted sections when the dryer has no flighted one (then the
    material's at the feed moisture); None: the nearest flighted cell's."""
    if isinstance(case, LeeCase) or any(s.kind == "flighted" for s in case.sections):
        return None
    _, _, x_in, _ = operating_point(case)
    return float(np.asarray(material_of(case).bulk_density(x_in)))


def _holdup_hint(case) -> str:
    if isinstance(case, LeeCase) and case.transport.model == "sheehan2005_model1":
        t = case.transport
        return (f" (or check solids.bulk_density = {fmt_number(case.solids.bulk_density)} kg/m^3, "
                f"transport.passive_rate = {fmt_number(t.passive_rate)} 1/s, transport.kiln_rate = "
                f"{fmt_number(t.kiln_rate)} 1/s, drum.radius and drum.length)")
    if isinstance(case, LeeCase):
        t = case.transport
        kiln = t.kiln_time if t.kiln_time is not None else lee_parameters(case)["kiln_time"]
        return (f" (or check solids.bulk_density = {fmt_number(case.solids.bulk_density)} kg/m^3, "
                f"transport.kiln_time = {fmt_number(kiln)} s, drum.radius and drum.length)")
    if isinstance(case, AjayiCase):
        u = ajayi_test_inputs(case)["kiln_velocity"]
        if isinstance(u, dict):     # parameter_source = "predictive": one velocity per section
            return (f" (or raise transport.velocity_coefficient = {fmt_number(case.transport.velocity_coefficient)}; "
                    "check drum.radius and the section lengths)")
        return (f" (or raise transport.kiln_velocity = {fmt_number(u)} m/s; check drum.radius and the "
                "section lengths)")
    return " (or check transport.kiln_time, transport.solids_velocity, drum.radius and the section lengths)"


def check_feasible(case, steady_state, limit: float = FILL_LIMIT) -> dict:
    """Refuse a steady state whose solids fill more than ``limit`` (:data:`FILL_LIMIT`) of the drum
    volume pi R^2 L, over the whole drum or in any section (bulk volume = holdup / bulk density of
    each cell). The ``ValueError`` names the fill (%), the limit and the keys to change. Returns the
    fill fractions (:meth:`rotarydryer.transport.results.SteadyState.fill_fractions`)."""
    fills = steady_state.fill_fractions(case.drum.radius, _bed_density(case))
    items = [("total", fills["total"])]
    if len(fills["sections"]) > 1:
        items += list(fills["sections"].items())
    items = [(k, v) for k, v in items if not math.isnan(v)]     # NaN: no bulk density known for a node
    if not items:
        return fills
    name, worst = max(items, key=lambda kv: kv[1])
    if worst <= limit:
        return fills
    det = fills["detail"][name]
    where = ("the drum volume" if name == "total"
             else f"the drum volume of section {name} ({det['length_m']:g} m long)")
    rho = det["holdup_kg"] / det["volume_m3"] if det["volume_m3"] > 0 else float("nan")
    F, _, _, _ = operating_point(case)
    raise ValueError(
        f"solids fill {100 * worst:.3g} % of {where} ({det['holdup_kg']:,.0f} kg of solids at "
        f"{rho:.4g} kg/m^3 take {det['volume_m3']:.3g} m^3 of {det['drum_volume_m3']:.3g} m^3); the limit is "
        f"{100 * limit:.0f} % (loaded dryers run at 10-15 %): reduce {_feed_text(case, F)}"
        + _holdup_hint(case))


# ---- Lee (2008) Invicta ------------------------------------------------------------------
def lee_parameters(case: LeeCase) -> dict:
    """(kiln_time, backmix, drag_reduction) for the case: explicit values, else the
    Table 7.2 row for ``transport.n_cells``."""
    t = case.transport
    row = next((p for p in case.parameter_sets if p.n_cells == t.n_cells), None)
    out = {}
    for key in ("kiln_time", "backmix", "drag_reduction"):
        v = getattr(t, key)
        if v is None and row is None and key == "drag_reduction" and t.forward_step == "trajectory":
            v = 1.0     # unused: the trajectory forward step replaces C_F^G
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


def curtain_gas(case, particle_diameter=None):
    """The :class:`~rotarydryer.transport.forward_step.CurtainGas` of a Lee or general case for the
    trajectory forward step: the gas inlet flow, temperature and humidity ([gas]) over the drum
    cross-section, the material's particle size and density, ``transport.curtain_velocity_ratio``."""
    from rotarydryer.transport.forward_step import CurtainGas

    if case.gas is None:
        raise ValueError("transport.forward_step = 'trajectory' needs [gas] (flow, inlet_temperature): the "
                         "forward step is computed from the fall through the gas")
    mat = material_of(case)
    direction = case.operating.gas_flow if isinstance(case, LeeCase) else case.gas.direction
    return CurtainGas.at_conditions(gas_mass_flow=case.gas.flow, temperature_degC=case.gas.inlet_temperature,
                                    humidity=case.gas.inlet_humidity, radius=case.drum.radius, gas_flow=direction,
                                    particle_diameter=particle_diameter or mat.particle_diameter,
                                    particle_density=mat.particle_density,
                                    velocity_ratio=case.transport.curtain_velocity_ratio)


def _build_lee(case: LeeCase):
    from rotarydryer.geometry.lee2008_regressions import Lee2008Regressions, invicta_tip_radius
    from rotarydryer.transport import lee2008, lee2008_repose_profile

    _check_lee_moisture(case)
    d, fl = case.drum, case.flight
    if case.geometry.method == "exact":
        from rotarydryer.transport.sections import ExactGeometry

        geometry = ExactGeometry(exact_drum(d.radius, d.n_flights, fl.s1, fl.s2, fl.alpha1, fl.alpha2, where="flight"),
                                 tabulated=case.geometry.tabulated)
    else:
        geometry = Lee2008Regressions(tip_radius=invicta_tip_radius(d.radius, fl.s1, fl.s2, fl.alpha1, fl.alpha2))
    if case.transport.model == "sheehan2005_model1":
        return _build_lee_model1(case, geometry)
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
    if case.transport.forward_step == "trajectory":
        kwargs.update(forward_step="trajectory", gas=curtain_gas(case))
    if case.transport.model == "sheehan2005_model2":
        kwargs["backmix_to"] = "active"
    return lee2008(**kwargs)


def _build_lee_model1(case: LeeCase, geometry):
    """Sheehan et al. (2005) Model 1 (notes lee_models.md Section 4.2) on Lee's drum: one flighted
    section of ``transport.n_cells`` cells with the case's global rates ``transport.passive_rate``,
    ``exchange_rate``, ``return_rate``, ``kiln_rate`` (1/s) and the design load of the case's geometry
    and repose-angle profile (``SectionSpec(kilning="empirical")`` of rotarydryer.transport.sections)."""
    from rotarydryer.transport import lee2008_repose_profile
    from rotarydryer.transport.sections import SectionSpec, build_sections

    d, t, s = case.drum, case.transport, case.solids
    N, F, rpm = t.n_cells, case.operating.feed_rate, case.operating.rpm
    phi = s.repose_angle if s.repose_angle is not None else lee2008_repose_profile(N, s.moisture_inlet, s.moisture_outlet)
    rates = {k: float(getattr(t, k)) for k in ("passive_rate", "exchange_rate", "return_rate", "kiln_rate")}
    spec = SectionSpec(name="dryer", kind="flighted", length=d.length, n_cells=N, geometry=geometry,
                       kilning="empirical", rates=rates, loading=t.loading,
                       passive_time_branch=case.geometry.passive_time_branch,
                       repose_angle=np.broadcast_to(np.asarray(phi, float), (N,)).copy(),
                       bulk_density=s.bulk_density)
    params = dict(n_cells=N, feed_rate=F, length=d.length, rpm=rpm, slope=d.slope, bulk_density=s.bulk_density,
                  gas_flow=case.operating.gas_flow, geometry=repr(geometry), **rates)
    return build_sections([spec], material=None, feed_rate=F, rpm=rpm, slope=d.slope,
                          tracer_input=_tracer_pulse(case, F), name="sheehan2005_model1", parameters=params)


def _with_core(case, model):
    """The model with the case's near-stagnant core of the passive phase of every cell
    (``transport.core`` = "first_order" or "diffusive", ``core_fraction``, ``core_time``; Lee and
    general cases): :func:`rotarydryer.transport.core_variants.add_stagnant_core` (docs/rtd_spread.md)."""
    tr = case.transport
    core = getattr(tr, "core", "none")
    if core == "none":
        return model
    from rotarydryer.transport.core_variants import add_stagnant_core

    try:
        return add_stagnant_core(model, tr.core_fraction, tr.core_time, core_model=core,
                                 name=f"{model.name}+{core}_core")
    except ValueError as exc:
        raise ValueError(f"transport.core = {core!r} (transport.core_fraction = {fmt_number(tr.core_fraction)}, "
                         f"transport.core_time = {fmt_number(tr.core_time)} s): {exc}") from None


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
    (m^2/s): case overrides first, else the test's Table 5.2 values
    (``transport.parameter_source = "per_test"``) or, with ``"predictive"``, per-section dicts from
    :func:`rotarydryer.transport.ajayi_predictive.predictive_transport` at the test's feed, speed and
    moisture (then also ``predictive`` and ``moisture_ends``, the test's inlet/product moisture)."""
    test = next((t for t in case.tests if t.test == case.operating.test), None)
    if test is None:
        raise ValueError(f"operating.test = {case.operating.test} is not in the case's tests "
                         f"({', '.join(str(t.test) for t in case.tests)})")
    tr = case.transport
    out = dict(test=test, feed_rate=case.operating.feed_rate or test.feed_rate,
               rpm=case.operating.rpm or test.rpm,
               kiln_velocity=tr.solids_velocity or tr.kiln_velocity or test.kiln_velocity,
               dispersion=tr.dispersion if tr.dispersion is not None else test.dispersion)
    if tr.parameter_source == "predictive":
        pred = _ajayi_predictive(case, test, out["feed_rate"], out["rpm"])
        out.update(predictive=pred, moisture_ends=(test.moisture_inlet, test.moisture_outlet))
        if not (tr.solids_velocity or tr.kiln_velocity):
            out["kiln_velocity"] = pred.kiln_velocity_m_s
        if tr.dispersion is None:
            out["dispersion"] = pred.dispersion_m2_s
    elif out["kiln_velocity"] is None or out["dispersion"] is None:
        fitted = ", ".join(str(t.test) for t in case.tests if t.kiln_velocity is not None and t.dispersion is not None)
        raise ValueError(f"operating.test = {test.test} has no fitted solids velocity and dispersion (Ajayi (2011) "
                         f"Table 5.2 fits tests {fitted}): set transport.parameter_source = 'predictive', or give "
                         "transport.solids_velocity (m/s) and transport.dispersion (m^2/s)")
    return out


def _ajayi_predictive(case: AjayiCase, test, feed_rate, rpm):
    """:class:`~rotarydryer.transport.ajayi_predictive.PredictiveTransport` of the selected test."""
    from rotarydryer.transport.ajayi_predictive import predictive_transport

    tr = case.transport
    missing = [f"transport.{k}" for k in ("velocity_coefficient", "dispersion_coefficient") if getattr(tr, k) is None]
    if missing:
        raise ValueError(f"transport.parameter_source = 'predictive' needs {' and '.join(missing)} (the calibrated "
                         "values are in the packaged ajayi2011_mmg.toml; docs/mmg_cross_test.md)")
    material = material_of(case)
    for key in ("moisture_inlet", "moisture_outlet"):
        material.check_moisture(f"tests (test {test.test}).{key}", getattr(test, key))
    secs = [dict(name=s.name, kind=s.kind, length=s.length, particle_diameter=s.particle_diameter)
            for s in case.sections]
    return predictive_transport(sections=secs, feed_rate=feed_rate, rpm=rpm, slope=case.drum.slope,
                                radius=case.drum.radius, moisture_inlet=test.moisture_inlet,
                                moisture_outlet=test.moisture_outlet, material=material,
                                velocity_coefficient=tr.velocity_coefficient,
                                dispersion_coefficient=tr.dispersion_coefficient, law=tr.velocity_law,
                                moisture_scale=case.solids.moisture_scale)


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
            where = f"sections[{case.sections.index(s)}] ({s.name})"
            drum = exact_drum(case.drum.radius, s.n_flights, s.s1, s.s2, s.alpha1, s.alpha2, where=where,
                              n_flights_key=f"{where}.n_flights")
            geoms[s.name] = ExactGeometry(drum, case.geometry.passive_time_branch, design_load_method="ajayi2011",
                                          tabulated=case.geometry.tabulated)
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
    model = ajayi2011(sections=secs, feed_rate=F, rpm=inp["rpm"], slope=case.drum.slope, radius=case.drum.radius,
                      kiln_velocity=inp["kiln_velocity"], dispersion=inp["dispersion"],
                      geometries=ajayi_geometries(case), fouling=_ajayi_fouling(case, inp["test"]),
                      moisture_scale=case.solids.moisture_scale, inlet=tr.unflighted_inlet,
                      unflighted_cells=tr.unflighted_cells, tracer_input=_tracer_pulse(case, F),
                      gas_flow=case.operating.gas_flow, material=material_of(case),
                      moisture_ends=inp.get("moisture_ends"))
    if "predictive" in inp:     # parameter_source = "predictive": what the velocities came from
        model.parameters["predictive"] = inp["predictive"].to_dict()
    return model


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
            where = f"sections[{case.sections.index(s)}] ({s.name})"
            drum = exact_drum(case.drum.radius, s.n_flights or case.drum.n_flights, **g,
                              where=where if s.s1 is not None else "flight",
                              n_flights_key=f"{where}.n_flights" if s.n_flights else "drum.n_flights")
            dp = None
            if case.geometry.finite_particle:
                if tr.loading != "fixed":
                    raise ValueError("geometry.finite_particle = true needs transport.loading = 'fixed' for now: with "
                                     "the corrected holdup the state-dependent loading factor is not smooth enough "
                                     "for the steady-state Newton solver (docs/dem.md)")
                dp = s.particle_diameter or getattr(material, "particle_diameter", None)
                if dp is None:
                    raise ValueError(f"geometry.finite_particle = true needs a particle diameter: give "
                                     f"{where}.particle_diameter or material.particle_diameter (m)")
                if dp > 0.25 * drum.flight.s1:
                    raise ValueError(f"geometry.finite_particle: particle diameter {dp:g} m is larger than a quarter "
                                     f"of the flight base s1 = {drum.flight.s1:g} m ({where}); the correction holds "
                                     "for d/s1 <= 0.25 (docs/dem.md)")
            geometry = ExactGeometry(drum, case.geometry.passive_time_branch,
                                     design_load_method=case.geometry.design_load_method, particle_diameter=dp,
                                     tabulated=case.geometry.tabulated)
            model = s.model or tr.model
            N = s.n_cells or tr.n_cells
            pos = x0 + (np.arange(N) + 0.5) * s.length / N
            common = dict(name=s.name, kind="flighted", length=s.length, n_cells=N, geometry=geometry,
                          loading=tr.loading, fouling=tr.fouling,
                          moisture=_exponential_profile(x_in, x_out, pos / length))
            if tr.forward_step == "trajectory" and model != "sheehan2005_model1":   # Model 1 has no forward step
                common.update(forward_step="trajectory", gas=curtain_gas(case, s.particle_diameter))
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
              shell_inner_radius=sh.inner_radius, shell_thickness=sh.thickness,
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

    core = getattr(case.transport, "core", "none")
    if core != "none":
        raise ValueError(f"transport.core = {core!r} is a transport-only variant (the heat-and-mass model has no "
                         "stagnant core): set thermal.enabled = false for this case (rotarydryer rtd and the "
                         "transport outputs use the core)")
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
