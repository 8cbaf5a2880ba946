"""From a validated case to model inputs: the only place that reads case objects.

* [`build_model`][rotarydryer.cases.build.build_model] - the solids-transport model ([`TransportModel`][rotarydryer.transport.TransportModel])
  of any case kind; every kind ends in [`rotarydryer.transport.sections.build_sections`][rotarydryer.transport.sections.build_sections],
  and the model keeps its section specs (``model.specs``);
* [`thermal_inputs`][rotarydryer.cases.build.thermal_inputs] - what the heat-and-mass model adds to those sections: thermal
  settings, per-section heat-transfer data, the material, feed moisture and the changes to the
  transport sections (thermal discretisation, moisture-dependent properties);
* [`check_inputs`][rotarydryer.cases.build.check_inputs] and [`check_feasible`][rotarydryer.cases.build.check_feasible] - physical feasibility of a case, with
  messages that name the case key, its value, the limit and the unit: drum dimensions finite
  and positive, flights that fit the drum, a bulk density of a granular solid, the drum speed
  below the critical speed 42.3/sqrt(D) rev/min ([`rotarydryer.geometry.check_speed`][rotarydryer.geometry.check_speed]; a
  [`CriticalSpeedWarning`][rotarydryer.geometry.CriticalSpeedWarning] above half of it) and, at the steady
  state, a solids fill of at most `FILL_LIMIT` of the drum volume (whole drum and every
  section). [`build_model`][rotarydryer.cases.build.build_model] runs both (the fill check on every steady state of the model).

Models (``transport``, ``thermal``) never import this module; [`rotarydryer.Simulation`][rotarydryer.simulation.Simulation]
and the other entry points do.
"""

from __future__ import annotations

import functools
import math
import warnings

import numpy as np

from rotarydryer.correlations.drag import terminal_velocity
from rotarydryer.geometry import FlightedDrum, PolygonFlight, TwoSectionFlight, check_speed
from rotarydryer.geometry.lee2008_regressions import Lee2008Regressions, invicta_tip_radius
from rotarydryer.properties.humid_air import STANDARD_PRESSURE, saturation_humidity, standard_atmosphere_pressure
from rotarydryer.properties.materials import CALIBRATED_RANGES, load_material
from rotarydryer.properties.psd import from_sieve, lognormal, rosin_rammler
from rotarydryer.properties.solids import PropertyRangeWarning, lee2008_moisture_profile
from rotarydryer.thermal.burner import Burner, FuelOil
from rotarydryer.thermal.settings import SectionThermal, ThermalSettings
from rotarydryer.transport import TracerInput
from rotarydryer.transport.ajayi import AjayiRegressions, check_moisture_scale, eq31_moisture
from rotarydryer.transport.ajayi_predictive import predictive_transport
from rotarydryer.transport.core_variants import add_stagnant_core
from rotarydryer.transport.forward_step import SHERRITT_COEFFICIENT, CurtainGas
from rotarydryer.transport.sections import ExactGeometry, SectionSpec, build_sections

from .._limits import check_key
from .._validation import check_range, fmt_number
from ..published import read_published_csv
from . import PSD_DATASETS, DryerCase
from .calibration import SECTION_DEFAULTS, PredictiveRangeWarning, section_values

#: largest solids fill of the drum volume (whole drum and each section) of a feasible steady state:
#: loaded flighted dryers run at 10-15 %; every shipped case is below 16 % (Invicta 8.9 %, MMG tests
#: 2-6 up to 15.6 % in the unflighted section A, Song 9.3 %)
FILL_LIMIT = 0.30
#: bulk densities a granular solid can have, kg/m^3: above air (1.2) and below osmium (22 590)
BULK_DENSITY_RANGE = (1.0, 23000.0)

__all__ = ["AmbientHumidityWarning", "ambient_humidity", "build_model", "check_inputs", "check_feasible", "FILL_LIMIT", "BULK_DENSITY_RANGE",
           "exact_drum", "section_flight", "transport_coefficients", "lee_parameters", "solids_transport", "ajayi_geometries",
           "test_row", "operating_point", "product_moisture", "fouling_of", "thermal_settings", "settings_from_case",
           "transport_inputs", "tracer_pulse", "model_name", "PARAMETER_KEYS", "changed_keys", "flat_case", "takes_as_parameters", "network_inputs", "thermal_inputs", "thermal_enabled", "has_burner", "burner_of", "material_of", "curtain_gas",
           "site_pressure", "unused_keys", "UnusedKeyWarning", "any_trajectory"]


def exact_drum(radius, n_flights, s1=None, s2=None, alpha1=None, alpha2=None, *, segments=None, vertices=None,
               where="flight", n_flights_key="drum.n_flights"):
    """Exact flight geometry ([`rotarydryer.geometry.FlightedDrum`][rotarydryer.geometry.FlightedDrum]) of a two-section flight
    (``s1``, ``s2``, ``alpha1``, ``alpha2``) or of a polygonal flight (``segments`` or ``vertices``,
    [`rotarydryer.geometry.PolygonFlight`][rotarydryer.geometry.PolygonFlight]).

    A geometry that cannot be built raises ``ValueError`` naming the case keys (``drum.radius``,
    ``n_flights_key``, ``<where>.s1`` ... or ``<where>.segments``) with their values."""

    if segments is not None or vertices is not None:
        key = f"{where}.{'segments' if segments is not None else 'vertices'}"
        try:
            flight = (PolygonFlight(segments, key=key) if segments is not None
                      else PolygonFlight(vertices=vertices, key=key))
            return FlightedDrum(radius=radius, n_flights=n_flights, flight=flight)
        except ValueError as exc:
            raise ValueError(f"flight geometry (drum.radius = {fmt_number(radius)} m, {n_flights_key} = "
                             f"{fmt_number(n_flights)}): {exc}") from None
    try:
        return FlightedDrum(radius=radius, n_flights=n_flights,
                            flight=TwoSectionFlight(s1=s1, s2=s2, alpha1=alpha1, alpha2=alpha2))
    except ValueError as exc:
        keys = (f"drum.radius = {fmt_number(radius)} m, {n_flights_key} = {fmt_number(n_flights)}, "
                f"{where}.s1 = {fmt_number(s1)} m, {where}.s2 = {fmt_number(s2)} m, "
                f"{where}.alpha1 = {fmt_number(alpha1)} deg, {where}.alpha2 = {fmt_number(alpha2)} deg")
        raise ValueError(f"flight geometry ({keys}): {exc}") from None


def section_flight(case, s, where: str) -> tuple[dict, str]:
    """The flight of flighted section ``s`` as keyword arguments of [`exact_drum`][rotarydryer.cases.build.exact_drum] and
    the prefix of its keys: the section's own ``segments``/``vertices``, else its ``s1``..``alpha2`` completed
    from ``[flight]``, else ``[flight]``'s flight."""
    for k in ("segments", "vertices"):
        if getattr(s, k, None) is not None:
            return {k: getattr(s, k)}, where
    fl = getattr(case, "flight", None)
    own = any(getattr(s, k, None) is not None for k in ("s1", "s2", "alpha1", "alpha2"))
    if not own and fl is not None:
        for k in ("segments", "vertices"):
            if getattr(fl, k, None) is not None:
                return {k: getattr(fl, k)}, "flight"
    g = {k: getattr(s, k) if getattr(s, k, None) is not None else getattr(fl, k, None)
         for k in ("s1", "s2", "alpha1", "alpha2")}
    return g, where if getattr(s, "s1", None) is not None else "flight"


def material_of(case):
    """The [`rotarydryer.properties.materials.Material`][rotarydryer.properties.materials.Material] of a case."""

    spec = case.material
    if spec is None:
        raise ValueError("material is missing: name one from the materials library "
                         "(rotarydryer.properties.materials.list_materials()) in [material]")
    d = spec.model_dump()
    return load_material(d["name"] if set(d) == {"name"} else d)


def size_classes_of(case):
    """The feed's [`SizeClasses`][rotarydryer.properties.psd.SizeClasses] of a case's ``[particle_size]``,
    or None (one class of the material's diameter). A class larger than the flights' pocket (the flight
    base s1 of any flighted section) is refused, naming it."""
    ps = case.particle_size
    if ps is None:
        return None
    if ps.dataset is not None:
        rows = read_published_csv("lee_particle_size_distribution.csv")
        col = PSD_DATASETS[ps.dataset]
        sieve = [float(r["sieve_size_micron"]) * 1e-6 for r in rows][::-1]
        passing = [float(r[col]) for r in rows][::-1]
        classes = from_sieve(sieve, passing, ps.classes, source=f"{ps.dataset} (Lee (2008) Table 5.3)")
    elif ps.sieve_m is not None:
        classes = from_sieve(ps.sieve_m, ps.passing_pct, ps.classes)
    elif ps.distribution == "rosin_rammler":
        classes = rosin_rammler(ps.d63, ps.spread, ps.classes)
    else:
        classes = lognormal(ps.d50, ps.sigma_g, ps.classes)
    for i, sec in enumerate(case.sections):
        if sec.kind != "flighted":
            continue
        g, where = section_flight(case, sec, f"sections[{i}]")
        s1 = g.get("s1") if "s1" in g else (g["segments"][0][0] if "segments" in g else None)
        if s1 is not None and classes.edges[-1] >= s1:
            raise ValueError(f"particle_size: the coarsest class reaches {classes.edges[-1]:.4g} m, not smaller than "
                             f"the flight base {where}.s1 = {s1:g} m of section {sec.name!r}: the flights' pocket "
                             "cannot hold such particles")
    return classes


def _tracer_pulse(case, feed_rate):

    tr = case.tracer
    return TracerInput.pulse(tr.fraction * feed_rate * max(tr.duration, 1e-6), tr.duration)


def tracer_pulse(case):
    """The case's tracer pulse ([tracer] fraction of the feed over its duration) at its feed rate."""
    return _tracer_pulse(case, operating_point(case)[0])


def model_name(case) -> str:
    """Name of a case's transport model: its flighted sections' model (lee2008, ajayi2011, ...), or
    "dryer" when they differ."""
    models = flighted_models(case)
    return next(iter(models)) if len(models) == 1 else "dryer"


def build_model(case, inputs: dict | None = None):
    """The [`rotarydryer.transport.TransportModel`][rotarydryer.transport.TransportModel] of a validated case (``inputs``: its
    [`transport_inputs`][rotarydryer.cases.build.transport_inputs], when the caller has them).

    The case is checked first ([`check_inputs`][rotarydryer.cases.build.check_inputs]) and every steady state of the model is
    checked for its fill of the drum ([`check_feasible`][rotarydryer.cases.build.check_feasible])."""
    if not isinstance(case, DryerCase):
        raise ValueError(f"case of type {type(case).__name__} is not supported (load it with "
                         "rotarydryer.cases.load_case)")
    model = _with_core(case, _build_dryer(case, inputs))
    model.checks.append(functools.partial(check_feasible, case))     # picklable, unlike a lambda
    return model


# ---- the operating point -------------------------------------------------------------------
def test_row(case):
    """The [[tests]] row selected by ``operating.test``, or None."""
    t = case.operating.test
    return None if t is None else next(r for r in case.tests if r.test == t)


ROW_OPERATING_KEYS = ("feed_rate", "rpm", "feed_moisture")


def rows_shadowed(case, overrides=None) -> str | None:
    """A sentence naming the [[tests]] rows whose feed rate, speed or feed moisture the case file's
    [operating] overrides (its values win, `operating_point`), or None.

    Keys given in ``overrides`` (``--set operating.rpm``) are the user's choice and not counted. Used where
    a command runs every row (calibrate, validate): a case made with ``rotarydryer new`` gives those keys,
    so each row would silently run at one operating point."""
    given = set(overrides or {})
    o = case.operating
    hits: dict[str, list[int]] = {}
    for k in ROW_OPERATING_KEYS:
        v = getattr(o, k)
        if v is None or f"operating.{k}" in given:
            continue
        tests = [r.test for r in case.tests if getattr(r, k, None) is not None
                 and not math.isclose(float(getattr(r, k)), float(v), rel_tol=1e-9)]
        if tests:
            hits[f"operating.{k} = {fmt_number(v)}"] = tests
    if not hits:
        return None
    tests = sorted({t for ts in hits.values() for t in ts})
    return (f"[[tests]] row{'s' if len(tests) > 1 else ''} {', '.join(map(str, tests))} run at the case's "
            f"{', '.join(hits)}, not at {'their' if len(tests) > 1 else 'its'} own: values in [operating] win over "
            "a row's; delete those keys from [operating] and give operating.test (a case without them runs a row) to run "
            "each test at its row's values")


def _from_test(case, value, field):
    row = test_row(case)
    return value if value is not None or row is None else getattr(row, field)


def test_gas_inlet_temperature(case):
    """The run's gas inlet temperature (degC): the selected [[tests]] row's measured one, as its gas_flow
    (a ``--set gas.inlet_temperature`` clears the rows' values), else ``gas.inlet_temperature``."""
    row = test_row(case)
    if row is not None and row.gas_inlet_temperature is not None:
        return row.gas_inlet_temperature
    return case.gas.inlet_temperature if case.gas is not None else None


def operating_point(case):
    """(feed rate kg/s wet, rpm, feed moisture kg/kg wet, feed temperature degC) of a case: its
    ``operating`` keys, else the values of the selected test."""
    o = case.operating
    return (_from_test(case, o.feed_rate, "feed_rate"), _from_test(case, o.rpm, "rpm"),
            _from_test(case, o.feed_moisture, "feed_moisture"), o.feed_temperature)


def product_moisture(case) -> float:
    """Assumed outlet moisture (kg/kg wet) of the transport-only profile: ``transport.product_moisture``,
    else the selected test's, else the feed moisture (no drying)."""
    x = _from_test(case, case.transport.product_moisture, "product_moisture")
    return operating_point(case)[2] if x is None else x


def moisture_ends(case, material) -> tuple[float, float]:
    """(feed, product) moisture (kg/kg wet) of the transport-only profile, each checked against the
    material's range (the message names the key, and the test when the value is the test's).

    A value wetter than the range is refused (the repose-angle and bulk-density laws do not hold there).
    A value drier than it (a plant's product, measured or predicted, below the range of the material's
    laws) is taken at the range's lower end, with a `PropertyRangeWarning`: the profile only feeds those
    laws, and the coupled model clips its moisture for them the same way (``transport_moisture_clipped``),
    so a test row with a dry product is run, not refused."""
    lo = material.wet_range()[0]
    ends = []
    for key, x in (("operating.feed_moisture", operating_point(case)[2]),
                   ("transport.product_moisture", product_moisture(case))):
        key += _test_text(case, key)
        if x < lo:
            warnings.warn(f"{key} = {x:g} kg/kg wet is below the moisture range of material '{material.name}' "
                          f"(from {lo:g} kg/kg wet): the transport-only moisture profile takes {lo:g} there for the "
                          "repose-angle and bulk-density laws, as the coupled model does (transport_moisture_clipped)",
                          PropertyRangeWarning, stacklevel=2)
            x = lo
        material.check_moisture(key, x)
        ends.append(x)
    return ends[0], ends[1]


def fouling_of(case) -> float:
    """Fraction of the flights' loading capacity lost to scale (Ajayi (2011) Eq. 5.21):
    ``transport.fouling``, else the selected test's, else 0."""
    f = _from_test(case, case.transport.fouling, "fouling")
    return 0.0 if f is None else float(f)


def _test_text(case, key) -> str:
    """`` (the value of test N)`` when the case leaves ``key`` (``"operating.feed_rate"``) to the
    selected test, else ``""``."""
    block, field = key.split(".")
    given = getattr(getattr(case, block), field)
    return f" (the value of test {case.operating.test})" if given is None and test_row(case) is not None else ""


# ---- feasibility ---------------------------------------------------------------------------
def _section_lengths(case):
    """[(key prefix, name, length m)] of the case's sections."""
    return [(f"sections[{k}] ({s.name})", s.name, s.length) for k, s in enumerate(case.sections)]


def _speed_key(case) -> str:
    return f"operating.rpm (test {case.operating.test})" if case.operating.rpm is None else "operating.rpm"


def _feed_text(case, F) -> str:
    """``operating.feed_rate = F kg/s`` (with the test whose value it is)."""
    return f"operating.feed_rate = {fmt_number(F)} kg/s{_test_text(case, 'operating.feed_rate')}"


def check_inputs(case) -> None:
    """Physical checks of a case before any model is built; ``ValueError`` names the key, its
    value, the allowed range and the unit.

    * ``drum.radius``, ``drum.slope`` and the feed rate in their declared ranges
      (`rotarydryer._limits.LIMITS`), section lengths finite and > 0;
    * the drum speed below the critical speed N_c = 42.3/sqrt(D)
      rev/min ([`rotarydryer.geometry.check_speed`][rotarydryer.geometry.check_speed]; a warning above half of it);
    * the material's bulk density at the feed moisture in `BULK_DENSITY_RANGE`;
    * each flight fits the drum: its base shorter than the radius.
    """

    d = case.drum
    R = float(check_key("drum.radius", d.radius))
    check_key("drum.slope", d.slope)
    for prefix, _, L in _section_lengths(case):
        check_range(f"{prefix}.length", L, 0.0, math.inf, unit="m")
    F, rpm, x_in, _ = operating_point(case)
    check_key("operating.feed_rate", F)
    check_speed(_speed_key(case), rpm, R, radius_key="drum.radius")
    mat = material_of(case)
    if x_in > mat.wet_range()[1]:
        # a feed wetter than the material's laws hold for is named as such (the MMG case's feed at 0.99 was refused
        # as a negative bulk density, "material.bulk_density (at the feed moisture) = -1020 kg/m^3"; found by an
        # acceptance check)
        mat.check_moisture("operating.feed_moisture" + _test_text(case, "operating.feed_moisture"), x_in)
    lo, hi = BULK_DENSITY_RANGE
    check_range("material.bulk_density (at the feed moisture)", float(np.asarray(mat.bulk_density(x_in))), lo, hi,
                low_inclusive=True, high_inclusive=True, unit="kg/m^3")
    flights = []
    for k, s in enumerate(case.sections):
        if s.kind == "flighted":
            g, where = section_flight(case, s, f"sections[{k}] ({s.name})")
            if g.get("s1") is None:
                continue        # regressions (no flight dimensions), or a polygonal flight (checked when built)
            flights.append((where, g["s1"]))
    for where, s1 in flights:
        s1 = float(check_range(f"{where}.s1", s1, 0.0, math.inf, unit="m"))
        if s1 >= R:
            raise ValueError(f"{where}.s1 = {fmt_number(s1)} m does not fit drum.radius = {fmt_number(R)} m: "
                             "the flight base must be shorter than the drum radius")


def _bed_density(case):
    """Bulk density (kg/m^3) for unflighted sections when the dryer has no flighted one (then the
    material's at the feed moisture); None: the nearest flighted cell's."""
    if any(s.kind == "flighted" for s in case.sections):
        return None
    _, _, x_in, _ = operating_point(case)
    return float(np.asarray(material_of(case).bulk_density(x_in)))


def _holdup_hint(case) -> str:
    t = case.transport
    models = flighted_models(case)
    if models == {"sheehan2005_model1"}:
        return (f" (or check the material's bulk density, transport.passive_rate = {fmt_number(t.passive_rate)} 1/s, "
                f"transport.kiln_rate = {fmt_number(t.kiln_rate)} 1/s, drum.radius and drum.length)")
    if models and models <= {"lee2008", "sheehan2005_model2"} and t.parameter_source == "predictive":
        return (f" (or raise transport.step_factor = {fmt_number(law_coefficient(case, 'step_factor'))} (the predictive forward step); check "
                "the material's bulk density, drum.radius and the section lengths)")
    if models and models <= {"lee2008", "sheehan2005_model2"}:
        kiln = transport_coefficients(case)["kiln_time"] if t.n_cells is not None else t.kiln_time
        return (f" (or check the material's bulk density, transport.kiln_time = {fmt_number(kiln)} s, drum.radius "
                "and the section lengths)")
    if "ajayi2011" in models:
        if t.parameter_source == "predictive":
            return (f" (or raise transport.velocity_coefficient = {fmt_number(law_coefficient(case, 'velocity_coefficient'))}; "
                    "check drum.radius and the section lengths)")
        u = solids_transport(case)[0]
        u = next(iter(u.values())) if u else None
        return (f" (or raise transport.solids_velocity = {fmt_number(u)} m/s{_test_text(case, 'transport.solids_velocity')}; "
                "check drum.radius and the section lengths)")
    return " (or check transport.kiln_time, transport.solids_velocity, drum.radius and the section lengths)"


def check_feasible(case, steady_state, limit: float = FILL_LIMIT) -> dict:
    """Refuse a steady state whose solids fill more than ``limit`` (`FILL_LIMIT`) of the drum
    volume pi R^2 L, over the whole drum or in any section (bulk volume = holdup / bulk density of
    each cell). The ``ValueError`` names the fill (%), the limit and the keys to change. Returns the
    fill fractions ([`rotarydryer.transport.results.SteadyState.fill_fractions`][rotarydryer.transport.results.SteadyState.fill_fractions])."""
    fills = steady_state.fill_fractions(case.drum.radius, _bed_density(case))
    _check_fill(case, fills, limit)
    if case.transport.parameter_source == "predictive":      # a feasible run: is it inside the calibration?
        warn_predictive_range(case, fills["total"])
    return fills


#: the transport models whose flighted sections kiln their excess at 1/transport.kiln_time (Lee (2008) Eq. 3.9)
KILN_TIME_MODELS = frozenset({"lee2008", "sheehan2005_model2"})


def flighted_models(case) -> set:
    """The transport models of the case's flighted sections (each section's own, else ``transport.model``)."""
    return {s.model or case.transport.model for s in case.sections if s.kind == "flighted"}


#: the kilning beds of a fixed kilning time holding more than this fraction of the holdup warn (`warn_kiln_cells`)
KILN_CELLS_FRACTION = 0.05


class AmbientHumidityWarning(UserWarning):
    """The case's outside air (``shell.ambient_humidity``) holds more vapour than saturated air at its temperature and
    the site's pressure: the model takes saturated outside air."""


class KilnCellsWarning(UserWarning):
    """The kilning beds of ``kiln_law = "fixed"`` hold a notable part of the holdup: their mass grows with the cell
    count (each cell holds its excess over the design load for ``transport.kiln_time``)."""


def _kiln_time_fitted(case) -> bool:
    """Is the case's kilning time fitted with its cell count ([[parameter_sets]] rows, or a calibration record of
    ``transport.kiln_time``, whose configuration names ``transport.n_cells``)?"""
    if getattr(case, "parameter_sets", None):
        return True
    return any("transport.kiln_time" in (rec.values or {}) for rec in getattr(case, "calibrations", None) or ())


def warn_kiln_cells(case, steady_state) -> None:
    """`KilnCellsWarning` where the kilning beds of a fixed kilning time (``transport.kiln_law = "fixed"``, not fitted
    to this dryer: no [[parameter_sets]] nor calibration of ``transport.kiln_time``) hold more than
    `KILN_CELLS_FRACTION` of the holdup: Lee (2008) Eq. 3.9 kilns each cell's excess over the design load at
    1/kiln_time, so the beds hold about n_cells x the excess flow x kiln_time and the holdup and residence time follow
    ``transport.n_cells`` (found by a review: +56 % from 5 to 80 cells on the ``new`` template at a feed over the
    flights' capacity). ``kiln_law = "cascade"`` moves the excess at the cascade speed: the same beds at any cell
    count."""
    t = case.transport
    if t.kiln_law != "fixed" or t.parameter_source == "predictive" or _kiln_time_fitted(case):
        return
    # the laws that kiln at 1/kiln_time (lee2008, sheehan2005_model2); checked first: the kilning beds of a coupled
    # state are evaluated on demand (a study's runs skip them)
    lee = flighted_models(case) & KILN_TIME_MODELS
    if not lee or all(cascade_law(case, m) for m in lee):
        return
    kiln, total = float(steady_state.kiln_bed_holdup), float(steady_state.total_holdup)
    if not (total > 0 and kiln > KILN_CELLS_FRACTION * total):
        return
    kiln_time = transport_coefficients(case)["kiln_time"]
    warnings.warn(f"the kilning beds hold {kiln:,.0f} kg ({100 * kiln / total:.0f} % of the holdup): with "
                  "transport.kiln_law = 'fixed' each flighted cell holds its excess over the flights' design load for "
                  f"transport.kiln_time = {kiln_time:g} s, so this mass, the holdup and the residence time grow with "
                  "the cell count (transport.n_cells); transport.kiln_law = 'cascade' moves the excess at the cascade "
                  "speed, the same at any cell count (or fit kiln_time to this dryer's tracer data at its cell count: "
                  "rotarydryer calibrate)", KilnCellsWarning, stacklevel=3)


def drum_fill_fraction(case, steady_state) -> float:
    """Bulk volume of the solids over the drum volume pi R^2 L (-), as
    [`check_feasible`][rotarydryer.cases.build.check_feasible] measures it (NaN where no bulk density is known)."""
    return float(steady_state.fill_fractions(case.drum.radius, _bed_density(case))["total"])


def _check_fill(case, fills, limit) -> None:
    items = [("total", fills["total"])]
    if len(fills["sections"]) > 1:
        items += list(fills["sections"].items())
    items = [(k, v) for k, v in items if not math.isnan(v)]     # NaN: no bulk density known for a node
    if not items:
        return
    name, worst = max(items, key=lambda kv: kv[1])
    if worst <= limit:
        return
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


#: relative tolerance of a material's ``calibrated_*`` ranges (written to three significant figures)
CALIBRATED_RANGE_RTOL = 5e-3


def predictive_range(case, fill: float) -> list[str]:
    """What of a predictive run lies outside the range its material's coefficients were calibrated on
    (material ``[transport]`` ``calibrated_*``): one phrase per quantity, naming value and range."""
    mat = material_of(case)
    ranges = dict(mat.transport_ranges)
    if not ranges:
        return []
    _, rpm, x_in, _ = operating_point(case)
    omega = 2.0 * math.pi * float(rpm) / 60.0
    values = {"calibrated_rpm": float(rpm), "calibrated_froude": omega**2 * float(case.drum.radius) / 9.80665,
              "calibrated_fill": float(fill), "calibrated_moisture": float(x_in)}
    out = []
    for key, (lo, hi) in ranges.items():
        v = values[key]
        # the material files give the ranges to three figures: the calibration's own point (Invicta's Froude number
        # 0.02516 against [0.0252, 0.0252]) is inside them
        if math.isnan(v) or lo * (1 - CALIBRATED_RANGE_RTOL) - 1e-12 <= v <= hi * (1 + CALIBRATED_RANGE_RTOL) + 1e-12:
            continue
        what, unit = CALIBRATED_RANGES[key]
        u = "" if unit == "-" else " " + unit
        out.append(f"{what} {v:.4g}{u} outside [{lo:g}, {hi:g}]" if hi > lo
                   else f"{what} {v:.4g}{u} where every run of the calibration had {lo:g}{u}")
    return out


def warn_predictive_range(case, fill: float) -> None:
    """`PredictiveRangeWarning` for [`predictive_range`][rotarydryer.cases.build.predictive_range]."""
    out = predictive_range(case, fill)
    if out:
        mat = material_of(case)
        warnings.warn(f"transport.parameter_source = 'predictive': this run is outside the conditions the "
                      f"coefficients of material {mat.name!r} were calibrated at "
                      f"({mat.transport_source or 'its [transport] table'}): "
                      f"{'; '.join(out)}; the prediction is an extrapolation (calibrate on this dryer's data with "
                      "`rotarydryer calibrate`)", PredictiveRangeWarning, stacklevel=3)


# ---- fitted transport coefficients ---------------------------------------------------------
#: kilning time (s), backmix C_B and forward-step drag reduction C_F^G of a case that gives neither
#: the coefficients nor [[parameter_sets]]: physically neutral (no backmix, no drag)
_NEUTRAL_COEFFICIENTS = {"kiln_time": 10.0, "backmix": 0.0, "drag_reduction": 1.0}


def transport_coefficients(case, n_cells=None) -> dict:
    """(kiln_time s, backmix, drag_reduction) of the lee2008-type sections of a case: the explicit
    ``transport.*`` values, else the ``[[parameter_sets]]`` row of ``n_cells`` (default
    ``transport.n_cells``; Lee (2008) Table 7.2 in the Invicta case), else, for a case without
    parameter sets, `_NEUTRAL_COEFFICIENTS`."""
    t = case.transport
    n = t.n_cells if n_cells is None else n_cells
    sets = getattr(case, "parameter_sets", [])
    row = next((p for p in sets if p.n_cells == n), None)
    out = {}
    for key in ("kiln_time", "backmix", "drag_reduction"):
        v = getattr(t, key)
        if v is None and row is None and key == "drag_reduction" and t.forward_step == "trajectory":
            v = 1.0     # unused: the trajectory forward step replaces C_F^G
        if v is None:
            if row is None and sets:
                have = ", ".join(str(p.n_cells) for p in sets)
                raise ValueError(
                    f"transport.n_cells = {n} has no parameter set (the case's [[parameter_sets]] are fitted for "
                    f"n_cells = {have}); set transport.{key} (and the other transport coefficients) explicitly")
            v = getattr(row, key) if row is not None else _NEUTRAL_COEFFICIENTS[key]
        out[key] = v
    out["kiln_law"] = t.kiln_law
    return out


lee_parameters = transport_coefficients


#: the value of a predictive-transport coefficient when neither the case nor its material gives one
_NEUTRAL_LAW = {"step_factor": 1.0, "curtain_coefficient": SHERRITT_COEFFICIENT}


def law_coefficient(case, key: str):
    """A coefficient of the predictive transport law (``step_factor``, ``curtain_coefficient``,
    ``velocity_coefficient``, ``dispersion_coefficient``): ``transport.<key>``, else the material
    class's ([transport] of the material, calibrated under the predictive law: with
    ``transport.parameter_source = "predictive"`` only), else the neutral value (a straight fall,
    Sherritt's constant; None for the bed law's coefficients)."""
    v = getattr(case.transport, key)
    if v is None and case.transport.parameter_source == "predictive":
        v = material_of(case).transport_coefficient(key)
    return _NEUTRAL_LAW.get(key) if v is None else float(v)


def cascade_law(case, model: str) -> bool:
    """Does a flighted section of ``model`` take the predictive cascade law (``transport.parameter_source =
    "predictive"``: every flighted model but Sheehan's Model 1, and Ajayi's sections unless
    ``transport.predictive_flights = "kiln_velocity"``)?"""
    t = case.transport
    if t.parameter_source != "predictive" or model == "sheehan2005_model1":
        return False
    return model != "ajayi2011" or t.predictive_flights == "cascade"


class UnusedKeyWarning(UserWarning):
    """A case key set to a value the case's configuration does not use (`unused_keys`)."""


def unused_keys(case, overrides=()) -> list[str]:
    """A message for each key a case sets that its configuration ignores (a value that would otherwise
    change nothing, silently): ``transport.moisture_scale`` without the Eq. 3.1 moisture profile and
    ``geometry.design_load_factor`` without Ajayi's regressions, when away from their defaults; the fitted
    lee2008 coefficients (``transport.kiln_time``, ``backmix``, ``drag_reduction``) given in ``overrides``
    (this run's ``--set``: a case file may keep them for its per-test mode) where every flighted section
    takes the predictive cascade law, or ``transport.kiln_time`` with ``transport.kiln_law = "cascade"``."""
    t, g = case.transport, case.geometry
    out = []

    def changed(block, name):
        return getattr(block, name) != type(block).model_fields[name].default

    models = flighted_models(case)
    # the predictive law maps the Eq. 3.1 profile (times the scale) onto its velocities and beds, whatever the model
    if changed(t, "moisture_scale") and t.moisture_profile != "ajayi2011_eq3.1" and t.parameter_source != "predictive":
        out.append(f"transport.moisture_scale = {t.moisture_scale:g} has no effect: it scales the "
                   f"transport.moisture_profile = 'ajayi2011_eq3.1' (this case's is {t.moisture_profile!r})")
    if changed(g, "design_load_factor") and g.method != "ajayi2011_regressions":
        out.append(f"geometry.design_load_factor = {g.design_load_factor:g} has no effect: it multiplies the Baker "
                   f"area of geometry.method = 'ajayi2011_regressions' (this case's is {g.method!r}; the exact "
                   "geometry's design_load_method = 'ajayi2011' is 1.24 x Baker, Ajayi (2011) Eq. 4.19)")
    lee_models = models & KILN_TIME_MODELS
    if lee_models and all(cascade_law(case, m) for m in lee_models):
        fitted = [k for k in ("kiln_time", "backmix", "drag_reduction")
                  if getattr(t, k) is not None and f"transport.{k}" in overrides]
        if fitted:
            out.append(f"{', '.join('transport.' + k for k in fitted)} {'has' if len(fitted) == 1 else 'have'} no "
                       "effect: transport.parameter_source = 'predictive' takes the cascade law, nothing fitted to a "
                       "tracer (docs/predictive_transport.md)")
    elif t.kiln_law == "cascade" and t.kiln_time is not None and "transport.kiln_time" in overrides:
        out.append(f"transport.kiln_time = {t.kiln_time:g} s has no effect: transport.kiln_law = 'cascade' kilns the "
                   "excess at the cascade speed")
    # the curtain's keys of the trajectory forward step, given (this run's --set) where no flighted section takes it
    curtain = [k for k in ("step_factor", "curtain_coefficient", "curtain_velocity_ratio")
               if getattr(t, k) is not None and f"transport.{k}" in overrides]
    if curtain and not any_trajectory(case) and t.parameter_source != "predictive":
        out.append(f"{', '.join('transport.' + k for k in curtain)} {'has' if len(curtain) == 1 else 'have'} no effect: "
                   f"{'it sets' if len(curtain) == 1 else 'they set'} the trajectory forward step's curtains (transport.forward_step = 'trajectory'; this "
                   f"case's is {t.forward_step!r})")
    out += _shadowed_by_sections(case, overrides)
    if changed(case.shell, "loss_factor") and case.thermal.mode != "ajayi2011":
        out.append(f"shell.loss_factor = {case.shell.loss_factor:g} has no effect: it is theta_loss of Ajayi's shell "
                   f"loss, thermal.mode = 'ajayi2011' (this case's is {case.thermal.mode!r}: the shell network of "
                   "shell.insulation_thickness and the films)")
    return out


def _shadowed_by_sections(case, overrides) -> list[str]:
    """A message for each case-wide default given in ``overrides`` (this run's ``--set``) that no flighted section
    takes, each setting its own: ``drum.n_flights``, ``transport.n_cells``, ``flight.*`` (a --set drum.n_flights=2 or
    flight.s1=5 on the MMG case changed nothing without a word; found by an acceptance check)."""
    flighted = [s for s in getattr(case, "sections", None) or () if s.kind == "flighted"]
    if not flighted or not overrides:
        return []
    polygon = ("segments", "vertices")

    def own_shape(s):
        return any(getattr(s, k, None) is not None for k in polygon)

    def takes(key, s) -> bool:      # does section s take the case-wide default ``key`` (not one of SECTION_DEFAULTS)?
        block, _, fld = key.partition(".")
        if block == "flight" and fld in polygon:
            return not own_shape(s) and all(getattr(s, k, None) is None for k in ("s1", "s2", "alpha1", "alpha2"))
        if block == "flight" and fld in ("s1", "s2", "alpha1", "alpha2"):
            return not own_shape(s) and getattr(s, fld, None) is None
        return True

    out = []
    for key in overrides:
        if key not in SECTION_DEFAULTS and not key.startswith("flight."):
            continue
        if key == "transport.n_cells" and getattr(case, "parameter_sets", None):
            continue            # it also selects a [[parameter_sets]] row
        if section_values(case, key) is not None if key in SECTION_DEFAULTS else not any(takes(key, s) for s in flighted):
            names = ", ".join(s.name for s in flighted)
            fld = key.partition(".")[2]
            own = "flight" if key.startswith("flight.") else fld
            out.append(f"{key} has no effect: it is the default of the flighted sections, and each of this case's "
                       f"({names}) sets its own {own}; change them in its [[sections]] (a copy of the case to edit: "
                       "rotarydryer new mycase.toml --from CASE)")
    return out


def forward_step_of(case, model: str | None = None) -> str:
    """The forward step of a case's flighted sections of ``model`` (default ``transport.model``):
    ``transport.forward_step``, always "trajectory" under the predictive cascade law (nothing fitted
    to a tracer; [`cascade_law`][rotarydryer.cases.build.cascade_law])."""
    t = case.transport
    return "trajectory" if cascade_law(case, model or t.model) else t.forward_step


def any_trajectory(case) -> bool:
    """Does a flighted section of the case take the trajectory forward step (whose curtain drag the gas sets)?"""
    models = flighted_models(case)
    return any(forward_step_of(case, m) == "trajectory" and m != "sheehan2005_model1" for m in models)


def predictive_lee_coefficients(case) -> dict:
    """The lee2008-type coefficients of ``transport.parameter_source = "predictive"``: the excess
    over the design load at the cascade speed (``kiln_law = "cascade"``), the forward step from
    trajectories (``drag_reduction`` unused; a counter-current gas that turns the step backwards
    carries the solids back), no fitted backmix, and the flights' loading factor 1 (Lee (2008) Eq. 4.22
    with f = 1, as his gPROMS runs: Song's (2003) residence time of dry sand does not change with the
    feed from under- to over-loaded flights, L1363-1367); nothing of ``transport.kiln_time``,
    ``transport.backmix``, ``transport.drag_reduction``, ``transport.loading`` or ``[[parameter_sets]]``
    (fitted to a tracer)."""
    return {"kiln_time": math.inf, "backmix": 0.0, "drag_reduction": 1.0, "kiln_law": "cascade", "loading": "fixed"}


def curtain_gas(case, particle_diameter=None):
    """The [`CurtainGas`][rotarydryer.transport.forward_step.CurtainGas] of a Lee or general case for the
    trajectory forward step: the gas inlet flow, temperature and humidity ([gas]) over the drum
    cross-section, the material's particle size and density, ``transport.curtain_velocity_ratio``."""

    row = test_row(case)
    flow = row.gas_flow if row is not None and row.gas_flow is not None else (
        case.gas.flow if case.gas is not None else None)
    t_in = test_gas_inlet_temperature(case)
    if case.gas is None or flow is None or t_in is None:
        why = ("transport.parameter_source = 'predictive'" if case.transport.parameter_source == "predictive"
               else "transport.forward_step = 'trajectory'")
        raise ValueError(f"{why} needs [gas] (flow, inlet_temperature): the forward step is computed from the "
                         "fall through the gas (give gas.flow = 0 for a drum without gas)")
    mat = material_of(case)
    direction = case.gas.direction
    gas = CurtainGas.at_conditions(gas_mass_flow=flow, temperature_degC=t_in,
                                    humidity=case.gas.inlet_humidity, radius=case.drum.radius, gas_flow=direction,
                                    particle_diameter=particle_diameter or mat.particle_diameter,
                                    particle_density=mat.particle_density,
                                    velocity_ratio=case.transport.curtain_velocity_ratio,
                                    curtain_coefficient=law_coefficient(case, "curtain_coefficient"),
                                    step_factor=law_coefficient(case, "step_factor"), pressure=site_pressure(case))
    if direction == "counter-current" and gas.gas_mass_flow > 0:
        _check_entrainment(case, gas, row)
    return gas


def _check_entrainment(case, gas, row) -> None:
    """Refuse a counter-current gas faster than the terminal velocity of the particles (Lee (2008) Eq.
    6.2-6.3 at a = 0): it would carry them to the feed end instead of letting them fall."""
    vt = float(terminal_velocity(gas.particle_diameter, gas.particle_density, gas.gas_density, gas.gas_viscosity))
    u = gas.gas_velocity
    if u >= vt:
        g_max = vt * gas.gas_density * math.pi * gas.radius**2
        key = f"gas.flow (test {row.test})" if row is not None and row.gas_flow is not None else "gas.flow"
        raise ValueError(f"{key} = {fmt_number(gas.gas_mass_flow)} kg/s gives a counter-current gas velocity of "
                         f"{u:.3g} m/s, above the terminal velocity {vt:.3g} m/s of the particles (d_p = "
                         f"{gas.particle_diameter * 1e6:.4g} um): the gas would entrain them to the feed end; "
                         f"the allowed range is gas.flow < {fmt_number(g_max)} kg/s at this gas temperature")


def _with_core(case, model):
    """The model with the case's near-stagnant core of the passive phase of every cell
    (``transport.core`` = "first_order" or "diffusive", ``core_fraction``, ``core_time``; Lee and
    general cases): [`rotarydryer.transport.core_variants.add_stagnant_core`][rotarydryer.transport.core_variants.add_stagnant_core] (docs/rtd_spread.md)."""
    tr = case.transport
    core = getattr(tr, "core", "none")
    if core == "none":
        return model

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


def _moisture_profile(case, x_in, x_out, pos, length, n):
    """Assumed wet-basis moisture of ``n`` flighted cells at ``pos`` (m) from ``x_in`` to ``x_out``
    (``transport.moisture_profile``): exponential in the wet basis at the cells' centres, or Lee (2008)
    Eq. 7.3, exponential in the dry basis at i/(N-1), i = 0..N-1 (Lee's gPROMS code; a one-section drum)."""
    if case.transport.moisture_profile == "lee2008_eq7.3":

        w = lee2008_moisture_profile(n, x_in / (1.0 - x_in), x_out / (1.0 - x_out))
        return w / (1.0 + w)
    return _exponential_profile(x_in, x_out, pos / length)


# ---- kilning velocity and dispersion -------------------------------------------------------------
#: rolling-bed velocity (m/s) and axial dispersion (m^2/s) of a case that gives neither, nor a test
_NEUTRAL_BED = {"solids_velocity": 0.01, "dispersion": 1e-3}


def solids_transport(case) -> tuple[dict, dict, object]:
    """(u_s per section m/s, D per unflighted section m^2/s, the predictive result or None).

    ``transport.solids_velocity`` / ``transport.dispersion`` when given; else, with
    ``transport.parameter_source = "predictive"``, per-section values from
    `rotarydryer.transport.ajayi_predictive.predictive_transport` at the operating point;
    else the selected test's fitted values (Ajayi (2011) Table 5.2 in the MMG case); else
    `_NEUTRAL_BED`."""
    tr = case.transport
    names = [s.name for s in case.sections]
    pred = None
    if tr.parameter_source == "predictive" and _needs_bed_parameters(case):
        pred = _predictive(case)
        u = tr.solids_velocity if tr.solids_velocity is not None else pred.kiln_velocity_m_s
        D = tr.dispersion if tr.dispersion is not None else pred.dispersion_m2_s
    else:
        u = _from_test(case, tr.solids_velocity, "solids_velocity")
        D = _from_test(case, tr.dispersion, "dispersion")
        row = test_row(case)
        fitted = ", ".join(str(t.test) for t in case.tests if t.solids_velocity is not None and t.dispersion is not None)
        if row is not None and (u is None or D is None) and _needs_bed_parameters(case) and fitted:
            raise ValueError(f"operating.test = {row.test} has no fitted solids velocity and dispersion (the case's "
                             f"[[tests]] fit tests {fitted or 'none'}): set transport.parameter_source = 'predictive', "
                             "or give transport.solids_velocity (m/s) and transport.dispersion (m^2/s)")
        u = _NEUTRAL_BED["solids_velocity"] if u is None else u
        D = _NEUTRAL_BED["dispersion"] if D is None else D
    u_of = dict(u) if isinstance(u, dict) else {n: float(u) for n in names}
    D_of = dict(D) if isinstance(D, dict) else {s.name: float(D) for s in case.sections if s.kind == "unflighted"}
    return u_of, D_of, pred


def _needs_bed_parameters(case) -> bool:
    return any(s.kind == "unflighted" or (s.model or case.transport.model) == "ajayi2011" for s in case.sections)


def _predictive(case):
    """`PredictiveTransport` at the case's operating point."""

    tr = case.transport
    material = material_of(case)
    cu, cd = law_coefficient(case, "velocity_coefficient"), law_coefficient(case, "dispersion_coefficient")
    missing = [f"transport.{k}" for k, v in (("velocity_coefficient", cu), ("dispersion_coefficient", cd)) if v is None]
    if missing:
        raise ValueError(f"transport.parameter_source = 'predictive' needs {' and '.join(missing)} for the "
                         f"unflighted (rolling-bed) sections: give them, or a material whose [transport] table has "
                         f"them (material {material.name!r} has none; docs/predictive_transport.md)")
    F, rpm, _, _ = operating_point(case)
    x_in, x_out = moisture_ends(case, material)
    secs = [dict(name=s.name, kind=s.kind, length=s.length, particle_diameter=s.particle_diameter)
            for s in case.sections]
    return predictive_transport(sections=secs, feed_rate=F, rpm=rpm, slope=case.drum.slope,
                                radius=case.drum.radius, moisture_inlet=x_in, moisture_outlet=x_out,
                                material=material, velocity_coefficient=cu,
                                dispersion_coefficient=cd, law=tr.velocity_law,
                                moisture_scale=tr.moisture_scale)


def ajayi_geometries(case) -> dict:
    """Cell geometry model of each flighted section (``geometry.method``), without fouling."""
    material = material_of(case)
    return {s.name: _section_geometry(case, s, f"sections[{k}] ({s.name})", material)
            for k, s in enumerate(case.sections) if s.kind == "flighted"}


def _section_geometry(case, s, where, material):
    """The cell geometry model of flighted section ``s`` (``geometry.method``)."""

    tr = case.transport
    g, fwhere = section_flight(case, s, where)
    if case.geometry.method == "lee2008_regressions" and "s1" not in g:
        raise ValueError(f"geometry.method = 'lee2008_regressions' is fitted to the Invicta two-section flight; "
                         f"{fwhere} gives a polygonal flight: use geometry.method = 'exact'")
    if case.geometry.method == "ajayi2011_regressions":

        reg = s.regression or {}
        return AjayiRegressions(reg["area"], reg["fall_time"], case.drum.radius, case.geometry.design_load_factor)
    if case.geometry.method == "lee2008_regressions":

        return Lee2008Regressions(tip_radius=invicta_tip_radius(case.drum.radius, *g.values()))
    drum = exact_drum(case.drum.radius, s.n_flights or case.drum.n_flights, **g, where=fwhere,
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
    return ExactGeometry(drum, case.geometry.passive_time_branch, design_load_method=case.geometry.design_load_method,
                         particle_diameter=dp, tabulated=case.geometry.tabulated)


def _flighted_moisture(case, x_in, x_out):
    """{section name: assumed wet-basis moisture of its cells} of the transport-only network
    (``transport.moisture_profile``)."""
    tr = case.transport
    length = sum(s.length for s in case.sections)
    if tr.moisture_profile == "ajayi2011_eq3.1":

        secs = [dict(name=s.name, kind=s.kind, length=s.length, n_cells=s.n_cells or tr.n_cells) for s in case.sections]
        ends = (x_in, x_out) if tr.parameter_source == "predictive" else None
        check_moisture_scale(tr.moisture_scale, secs, material_of(case), ends, key="transport.moisture_scale")
    out, x0 = {}, 0.0
    for s in case.sections:
        if s.kind == "flighted":
            N = s.n_cells or tr.n_cells
            pos = x0 + (np.arange(N) + 0.5) * s.length / N
            if tr.moisture_profile == "ajayi2011_eq3.1":
                out[s.name] = tr.moisture_scale * eq31_moisture(pos, secs, ends)
            else:
                out[s.name] = _moisture_profile(case, x_in, x_out, pos, length, N)
        x0 += s.length
    return out


def _dryer_specs(case: DryerCase, material, bed):
    """The section specs of a case; ``bed`` = [`solids_transport`][rotarydryer.cases.build.solids_transport] of the case."""

    tr = case.transport
    x_in, x_out = moisture_ends(case, material)
    moisture = _flighted_moisture(case, x_in, x_out)
    u_of, D_of, _ = bed
    fouling = fouling_of(case)
    specs = []
    for s in case.sections:
        if s.kind == "unflighted":
            specs.append(SectionSpec(name=s.name, kind="unflighted", length=s.length,
                                     n_cells=s.n_cells or tr.unflighted_cells, velocity=u_of[s.name],
                                     dispersion=D_of[s.name]))
            continue
        where = f"sections[{case.sections.index(s)}] ({s.name})"
        geometry = _section_geometry(case, s, where, material)
        model = s.model or tr.model
        N = s.n_cells or tr.n_cells
        common = dict(name=s.name, kind="flighted", length=s.length, n_cells=N, geometry=geometry,
                      loading=tr.loading, fouling=fouling, passive_time_branch=case.geometry.passive_time_branch,
                      moisture=moisture[s.name])
        if forward_step_of(case, model) == "trajectory" and model != "sheehan2005_model1":   # Model 1: no forward step
            common.update(forward_step="trajectory", gas=curtain_gas(case, s.particle_diameter))
        if model == "ajayi2011" and not cascade_law(case, model):
            specs.append(SectionSpec(kilning="velocity", kiln_velocity=u_of[s.name], **common))
        elif model == "sheehan2005_model1":
            rates = {k: getattr(tr, k) for k in ("passive_rate", "exchange_rate", "return_rate", "kiln_rate")}
            missing = [k for k, v in rates.items() if v is None]
            if missing:
                raise ValueError(f"sections {s.name!r}: model = 'sheehan2005_model1' needs "
                                 f"{', '.join('transport.' + k for k in missing)} (1/s)")
            specs.append(SectionSpec(kilning="empirical", rates={k: float(v) for k, v in rates.items()}, **common))
        else:
            p = (predictive_lee_coefficients(case) if cascade_law(case, model)
                 else transport_coefficients(case, N))
            common["loading"] = p.get("loading", tr.loading)
            if p["backmix"] > 0 and case.gas is not None and case.gas.direction == "co-current":
                raise ValueError(f"transport.backmix = {fmt_number(p['backmix'])} must be 0 for co-current gas "
                                 "flow (gas.direction; Lee (2008) l.2766: no backmixing, drag lengthens the "
                                 "forward step)")
            specs.append(SectionSpec(kilning="excess", kiln_time=float(p["kiln_time"]), kiln_law=p["kiln_law"],
                                     drag_reduction=float(p["drag_reduction"]), backmix=float(p["backmix"]),
                                     backmix_to="active" if model == "sheehan2005_model2" else tr.backmix_to,
                                     **common))
    return specs


def transport_inputs(case) -> dict:
    """What [`rotarydryer.transport.sections.build_sections`][rotarydryer.transport.sections.build_sections] builds a case's network from:
    ``sections`` (the SectionSpecs), ``material``, ``feed_rate``, ``rpm``, ``slope``, ``inlet``,
    ``tracer_input``, ``name`` and ``parameters`` (the model choices recorded with a model; the
    predictive transport's, if any, under ``predictive``). The case is checked first
    ([`check_inputs`][rotarydryer.cases.build.check_inputs]). The heat-and-mass model builds its own network from these without the
    transport-only one ([`rotarydryer.Simulation.thermal_dryer`][rotarydryer.simulation.Simulation.thermal_dryer])."""
    check_inputs(case)
    material = material_of(case)
    F, rpm, _, _ = operating_point(case)
    bed = solids_transport(case)
    specs = _dryer_specs(case, material, bed)
    name = model_name(case)
    params = dict(feed_rate=F, rpm=rpm, slope=case.drum.slope, radius=case.drum.radius, fouling=fouling_of(case),
                  unflighted_inlet=case.transport.unflighted_inlet)
    if case.gas is not None:
        params["gas_direction"] = case.gas.direction
    flighted = [sp for sp in specs if sp.kind == "flighted"]
    if len(flighted) == 1 and flighted[0].kilning == "excess":
        sp = flighted[0]
        params.update(n_cells=sp.n_cells, length=sp.length, kiln_time=sp.kiln_time, backmix=sp.backmix,
                      drag_reduction=sp.drag_reduction, loading=sp.loading, backmix_to=sp.backmix_to)
        if sp.kiln_law == "cascade":
            params.update(kiln_law="cascade", step_factor=law_coefficient(case, "step_factor"),
                          curtain_coefficient=law_coefficient(case, "curtain_coefficient"))
            del params["kiln_time"]
    u_of, D_of, pred = bed if _needs_bed_parameters(case) else ({}, {}, None)
    if u_of:      # one number when every section has the same value (a per-test fit), else per section

        def one(d):
            vals = set(d.values())
            return next(iter(vals)) if len(vals) == 1 and pred is None else dict(d)

        params.update(kiln_velocity=one(u_of), dispersion=one(D_of))
    if case.transport.moisture_profile == "ajayi2011_eq3.1":
        params["moisture_scale"] = case.transport.moisture_scale
    if pred is not None:     # parameter_source = "predictive": what the velocities came from
        params["predictive"] = pred.to_dict()
    return dict(sections=specs, material=material, feed_rate=F, rpm=rpm, slope=case.drum.slope,
                inlet=case.transport.unflighted_inlet, tracer_input=tracer_pulse(case), name=name,
                parameters=params)


def _build_dryer(case: DryerCase, inputs: dict | None = None):

    inp = transport_inputs(case) if inputs is None else inputs
    model = build_sections(**inp)
    unfl = {s["name"]: s["n_cells"] for s in model.sections if s["kind"] == "unflighted"}
    if unfl:
        model.parameters["unflighted_cells"] = unfl
    if "predictive" in model.parameters:      # recorded last, as before
        model.parameters["predictive"] = model.parameters.pop("predictive")
    return model


# ---- parameters a built model takes without a rebuild ----------------------------------------
#: case keys (and key prefixes ending in ".") whose values a built heat-and-mass model takes as new
#: parameters (:meth:`rotarydryer.thermal.dryer.ThermalDryer.with_parameters`): they enter its
#: ThermalSettings, its feed rate or its speed, never its network or section specs
PARAMETER_KEYS = ("operating.feed_rate", "operating.rpm", "operating.feed_temperature", "gas.flow",
                  "gas.inlet_temperature", "gas.inlet_humidity", "gas.leak_air_flow", "gas.burner.",
                  "gas.recycle_fraction", "thermal.area_scale", "thermal.design_load_smoothing",
                  "thermal.discharge_cooling_ntu", "shell.", "site.")
#: of those, the keys the section specs also depend on in some configurations: the operating point
#: (the predictive kilning velocity and dispersion) and the gas (the trajectory forward step's curtains)
_OPERATING_KEYS = ("operating.feed_rate", "operating.rpm")


def _flat(d: dict, prefix: str = "") -> dict:
    out = {}
    for k, v in d.items():
        if isinstance(v, dict) and k != "material":
            out.update(_flat(v, f"{prefix}{k}."))
        else:
            out[f"{prefix}{k}"] = v
    return out


def flat_case(case) -> dict:
    """The case as one flat dict of its keys (`changed_keys`)."""
    d = case.model_dump()
    rows = d.pop("tests", [])
    out = _flat(d)
    for r in rows:       # a [[tests]] row's fields as tests.<test>.<field>
        out.update({f"tests.{r['test']}.{k}": v for k, v in r.items() if k != "test"})
    out["tests"] = sorted(r["test"] for r in rows)
    return out


def changed_keys(old, new, flats=None) -> list[str]:
    """The case keys whose values differ between two validated cases (``sections`` counts as one key,
    a [[tests]] row's fields as ``tests.<test>.<field>``, the material as a whole). ``flats``: the two
    cases' flat views (`flat_case`) where the caller keeps them."""
    a, b = flats if flats is not None else (flat_case(old), flat_case(new))
    return sorted(k for k in set(a) | set(b) if a.get(k, _MISSING) != b.get(k, _MISSING))


#: fields of a [[tests]] row that are parameters of the heat-and-mass model (tests.<test>.<field>)
_TEST_PARAMETER_FIELDS = (".gas_flow", ".gas_inlet_temperature")


_MISSING = object()


def takes_as_parameters(old, new, flats=None) -> bool:
    """Can the heat-and-mass model built for case ``old`` run case ``new`` with new parameter values
    (no rebuild)? True when every changed key is one of `PARAMETER_KEYS` and none of them
    changes the section specs: not the speed (and, with unflighted beds, the feed) with
    ``transport.parameter_source = "predictive"``, not the gas with a trajectory forward step."""
    keys = changed_keys(old, new, flats)
    if not all(k in PARAMETER_KEYS or any(k.startswith(p) for p in PARAMETER_KEYS if p.endswith("."))
               or (k.startswith("tests.") and k.endswith(_TEST_PARAMETER_FIELDS)) for k in keys):
        return False
    if new.transport.parameter_source == "predictive":
        # the cascade law's kilning and the beds' velocity follow the speed; the beds' law the feed
        if "operating.rpm" in keys or (_needs_bed_parameters(new) and "operating.feed_rate" in keys):
            return False
    return not (any_trajectory(new) and any(k.startswith(("gas.", "site.")) for k in keys))


def network_inputs(case) -> frozenset:
    """The inputs of a dynamic run (schedule names) whose change rebuilds the case's transport network, as
    `takes_as_parameters` decides for a steady state: the gas (gas_inlet_temperature, gas_flow,
    gas_inlet_humidity) with a trajectory forward step; the speed (rpm), and with beds the feed (feed_rate),
    with the predictive law."""
    out = set()
    if case.gas is not None and any_trajectory(case):
        out |= {"gas_inlet_temperature", "gas_flow", "gas_inlet_humidity"}
    if case.transport.parameter_source == "predictive":
        out |= {"rpm"} | ({"feed_rate"} if _needs_bed_parameters(case) else set())
    return frozenset(out)


# ---- heat and mass transfer ----------------------------------------------------------------
def thermal_enabled(case) -> bool:
    """Does the case ask for heat and mass transfer?"""
    return bool(case.thermal.enabled)


def _burner_block(case):
    """The case's burner block, or None."""
    return getattr(case.gas, "burner", None) if case.gas is not None else None


def has_burner(case) -> bool:
    """Does the case's gas come from a burner ([gas.burner]; the MMG case's is
    Ajayi's combustion chamber, App. A) whose fuel rate the model can give?"""
    return _burner_block(case) is not None


def burner_of(case):
    """[`Burner`][rotarydryer.thermal.burner.Burner] of the case, or None."""

    b = _burner_block(case)
    if b is None:
        return None
    fuel = FuelOil(water_mass_fraction=b.fuel_water_fraction, sulphur_mass_fraction=b.fuel_sulphur_fraction,
                   carbon_hydrogen_ratio=b.fuel_carbon_hydrogen_ratio, lower_heating_value=b.fuel_lower_heating_value)
    return Burner(combustion_air_share=b.combustion_air_share, heat_loss_fraction=b.heat_loss_fraction, fuel=fuel)


def thermal_settings(case):
    """[`ThermalSettings`][rotarydryer.thermal.dryer.ThermalSettings] of a case: [gas], [shell], [thermal], the
    operating point and the selected test (gas flow and inlet temperature where the case leaves them
    to the test); ``thermal.mode_values`` of the chosen mode replace gas.flow / thermal.area_scale."""

    g, sh, th = case.gas, case.shell, case.thermal
    row = test_row(case)
    flow = row.gas_flow if row is not None and row.gas_flow is not None else (g.flow if g is not None else None)
    t_in = test_gas_inlet_temperature(case)
    if g is None or flow is None or t_in is None:
        raise ValueError("gas is missing: give [gas] flow and inlet_temperature to compute heat and mass transfer")
    area_scale = th.area_scale
    mode_values = th.mode_values.get(th.mode, {})
    flow = mode_values.get("gas.flow", flow)
    area_scale = mode_values.get("thermal.area_scale", area_scale)
    _, _, _, t_feed = operating_point(case)
    kw = dict(mode=th.mode, gas_flow=float(flow), gas_inlet_temperature=float(t_in),
              gas_inlet_humidity=g.inlet_humidity, solids_inlet_temperature=t_feed,
              ambient_temperature=sh.ambient_temperature, ambient_humidity=ambient_humidity(case),
              area_scale=area_scale, scale_thickness=sh.scale_thickness,
              insulation_thickness=sh.insulation_thickness, loss_factor=sh.loss_factor,
              shell_inner_radius=sh.inner_radius, shell_thickness=sh.thickness,
              leak_air_flow=g.leak_air_flow, moisture_coupling=th.moisture_coupling,
              design_load_smoothing=th.design_load_smoothing, gas_direction=g.direction, fouling=fouling_of(case),
              discharge_cooling_ntu=th.discharge_cooling_ntu, kiln_bed_area=th.kiln_bed_area,
              size_classes=size_classes_of(case),
              entrainment=case.particle_size.entrainment if case.particle_size is not None else True,
              recycle_fraction=g.recycle_fraction, shell_max_temperature=sh.max_temperature)
    if th.mode == "ajayi2011":      # the thesis's drum pressure (101045 Pa), in proportion at altitude
        st = ThermalSettings.ajayi2011(**kw)
        st.pressure = st.pressure * (site_pressure(case) / STANDARD_PRESSURE)
        return st
    return ThermalSettings(**kw, pressure=site_pressure(case))


def ambient_humidity(case) -> float:
    """The outside air's humidity the model takes, kg/kg dry air: ``shell.ambient_humidity``, or the saturation
    humidity at ``shell.ambient_temperature`` and the site's pressure where the case's is above it (fog is beyond the
    model; an `AmbientHumidityWarning` says so). A case's ambient temperature is often changed alone (a winter site,
    a study of the weather) under a humidity set for a warmer one: refusing it would refuse most of those runs, and
    air wetter than saturated held vapour in the combustion air's and the shell film's enthalpies that no air holds
    (0.3 kg/kg at -39 degC ran, exit 0, without a word; found by an acceptance check)."""
    sh = case.shell
    y = float(sh.ambient_humidity)
    p = site_pressure(case)
    y_sat = float(saturation_humidity(sh.ambient_temperature, p))
    if y <= y_sat:
        return y
    scale = 10.0 ** (3 - math.floor(math.log10(y_sat)))
    top = math.floor(y_sat * scale) / scale        # 4 digits, rounded down: a value typed from it is not above y_sat
    warnings.warn(f"shell.ambient_humidity = {fmt_number(y)} kg/kg dry air is above the saturation humidity of the "
                  f"outside air at shell.ambient_temperature = {fmt_number(sh.ambient_temperature)} degC and "
                  f"{fmt_number(p / 1e3)} kPa ({y_sat:.6g} kg/kg): the model takes saturated outside air; give "
                  f"shell.ambient_humidity in [0, {top:.4g}]", AmbientHumidityWarning, stacklevel=2)
    return y_sat


def site_pressure(case) -> float:
    """Pressure of the case's site, Pa: the ISO 2533 standard atmosphere at ``site.altitude``
    ([`standard_atmosphere_pressure`][rotarydryer.properties.humid_air.standard_atmosphere_pressure]; 101325 Pa at 0 m). The gas
    properties, the drying (saturation, dew point) and the shell's outside air take it."""
    site = getattr(case, "site", None)
    return float(standard_atmosphere_pressure(0.0 if site is None else site.altitude))


settings_from_case = thermal_settings


def thermal_inputs(case) -> dict:
    """Inputs of the heat-and-mass model of a case: ``settings`` (ThermalSettings), ``sections``
    (name -> SectionThermal), ``material``, ``feed_moisture`` (kg/kg wet) and ``section_changes``
    (name -> SectionSpec fields that differ from the transport model's sections)."""

    core = getattr(case.transport, "core", "none")
    if core != "none":
        raise ValueError(f"transport.core = {core!r} is a transport-only variant (the heat-and-mass model has no "
                         "stagnant core): set thermal.enabled = false for this case (rotarydryer rtd and the "
                         "transport outputs use the core)")
    material = material_of(case)
    _, _, x_in, _ = operating_point(case)
    settings = thermal_settings(case)
    settings.burner = burner_of(case)
    changes = {name: dict(n_cells=n) for name, n in case.thermal.unflighted_cells.items()}
    sec_th = {s.name: SectionThermal(area_factor=s.area_factor, particle_diameter=s.particle_diameter,
                                     shell_temperature=s.shell_temperature) for s in case.sections}
    return dict(settings=settings, sections=sec_th, material=material, feed_moisture=x_in,
                section_changes=changes)
