"""Numbers for the plant manager's report, read from a `rotarydryer.results.Results`:
the operating conditions of the run and the model-versus-measured comparisons (RTD, holdup,
outlet and axial temperatures and moistures), each with its error.

Nothing is recomputed by a model here: the model side is what the Results hold, the measured
side is the case's data (measured tracer curve) or, for the MMG dryer, Ajayi (2011)'s plant
data of the case's test (Tables 3.3 and 3.5-3.14).
"""

from __future__ import annotations

import csv
from importlib import resources

import numpy as np

from .._display import show, unit_of
from ..results import rtd_comparison  # noqa: F401  (the report's comparison; defined with the Results)

__all__ = ["operating_conditions", "rtd_comparison", "thermal_comparison", "holdup_comparison", "MODEL_SOURCES"]

MODEL_SOURCES = {
    "lee2008": "Lee (2008) ch. 3",
    "ajayi2011": "Ajayi (2011) ch. 5",
    "sheehan2005_model1": "Sheehan et al. (2005), Model 1",
    "sheehan2005_model2": "Sheehan et al. (2005), Model 2",
}


def _test_row(inputs: dict) -> dict | None:
    op = inputs.get("operating") or {}
    return next((t for t in inputs.get("tests", []) if t.get("test") == op.get("test")), None)


def run_gas_inlet_temperature(inputs: dict):
    """The gas inlet temperature the run had, degC, or None: the selected [[tests]] row's where it gives one (a
    ``--set gas.inlet_temperature`` clears the rows'), else ``gas.inlet_temperature``, as the case builder takes it
    (`rotarydryer.cases.build.test_gas_inlet_temperature`)."""
    row = _test_row(inputs)
    if row is not None and row.get("gas_inlet_temperature") is not None:
        return row["gas_inlet_temperature"]
    return (inputs.get("gas") or {}).get("inlet_temperature")


def _fmt(v: float) -> str:
    return f"{v:,.0f}" if abs(v) >= 1000 else f"{v:.4g}"


def operating_conditions(results) -> list[tuple[str, str, str]]:
    """``[(quantity, value, unit)]`` of the run: feed, moisture, speed, slope, gas, burner, drum and
    flights, from the case inputs and the stored scalars (what the model was actually run with)."""
    inp, s = results.inputs, results.scalars
    params = results.model_choices.get("parameters", {}) or {}
    drum = inp.get("drum", {}) or {}
    op = inp.get("operating", {}) or {}
    gas = inp.get("gas") or {}
    th = inp.get("thermal") or {}
    test = _test_row(inp)
    rows: list[tuple[str, str, str]] = []
    if test is not None:
        rows.append(("plant test", f"Test {test['test']}", str(test.get("source") or "")))
    feed = s.get("feed_rate_kg_s", params.get("feed_rate", op.get("feed_rate")))
    # in the display units (--units): the summary and the tables after it show the same numbers in them
    if feed is not None:
        rows.append(("wet feed rate", show(float(feed), "mass_flow", with_unit=False)
                     + (f" ({3.6 * float(feed):.4g} t/h)" if unit_of("mass_flow") == "kg/s" else ""),
                     unit_of("mass_flow")))
    x_in = op.get("feed_moisture")
    if x_in is None and test is not None:
        x_in = test.get("feed_moisture")
    if x_in is not None:
        rows.append(("feed moisture", show(float(x_in), "moisture", with_unit=False), f"{unit_of('moisture')} wet basis"))
    t_feed = op.get("feed_temperature")
    if t_feed is not None:
        rows.append(("feed temperature", show(float(t_feed), "temperature", with_unit=False), unit_of("temperature")))
    rpm = params.get("rpm", op.get("rpm"))
    if rpm is not None:
        rows.append(("drum speed", f"{float(rpm):g}", "rev/min"))
    if drum.get("slope") is not None:
        rows.append(("drum slope", f"{float(drum['slope']):g}", "deg"))
    direction = gas.get("direction")
    if direction:
        rows.append(("gas direction", str(direction), "relative to the solids"))
    g_flow = s.get("gas_flow_kg_s", gas.get("flow"))
    if g_flow is not None:
        rows.append(("gas flow", show(float(g_flow), "mass_flow", with_unit=False), f"{unit_of('mass_flow')} wet gas"))
    t_gas = run_gas_inlet_temperature(inp) if th.get("enabled", True) else gas.get("inlet_temperature")
    if t_gas is not None:
        rows.append(("gas inlet temperature", show(float(t_gas), "temperature", with_unit=False), unit_of("temperature")))
    y_gas = gas.get("inlet_humidity")
    if y_gas is not None:
        rows.append(("gas inlet humidity", show(float(y_gas), "humidity", with_unit=False), f"{unit_of('humidity')} wet gas"))
    burner = gas.get("burner")
    if burner is not None:
        fuel = f"fuel oil (C/H {float(burner.get('fuel_carbon_hydrogen_ratio', float('nan'))):g}, " \
               f"S {100 * float(burner.get('fuel_sulphur_fraction', float('nan'))):g} %), Ajayi (2011) App. A"
        rows.append(("burner fuel", fuel, ""))
        if s.get("fuel_rate_kg_s") is not None:
            rows.append(("fuel rate (model)", show(float(s["fuel_rate_kg_s"]), "fuel_flow", with_unit=False),
                         unit_of("fuel_flow")))
    elif direction:
        rows.append(("burner", "none in the case (hot gas supplied)", ""))
    from .drawing import dryer_layout

    lay = dryer_layout(inp)
    rows.append(("drum D x L", f"{show(lay['diameter'], 'length', with_unit=False)} x "
                               f"{show(lay['length'], 'length', with_unit=False)}", unit_of("length")))
    secs = lay["sections"]
    if len(secs) == 1:
        f = inp.get("flight") or {}
        nf = drum.get("n_flights")
        desc = (f"{nf} {'polygonal' if f.get('segments') or f.get('vertices') else 'two-section'} flights"
                if nf else "flighted")
        if f.get("segments"):
            desc += ", sections " + ", ".join(f"{a:g} m / {b:g} deg" for a, b in f["segments"])
        if f.get("s1") is not None:
            desc += f", s1 {f['s1']:g} m / s2 {f['s2']:g} m, {f['alpha1']:g} / {f['alpha2']:g} deg"
        rows.append(("flights", desc, ""))
    else:
        shared = {**(inp.get("flight") or {}), "n_flights": drum.get("n_flights")}   # what sections inherit
        for sec in inp.get("sections", []):
            if sec["kind"] == "flighted":
                g = {k: sec.get(k) if sec.get(k) is not None else shared.get(k)
                     for k in ("n_flights", "s1", "s2", "alpha1", "alpha2")}
                own = any(sec.get(k) is not None for k in ("s1", "s2", "alpha1", "alpha2"))
                segs = sec.get("segments") or (None if own else shared.get("segments"))
                d = f"section {sec['name']} ({sec['length']:g} m): {g['n_flights']} flights"
                if segs:
                    d += ", sections " + ", ".join(f"{a:g} m / {b:g} deg" for a, b in segs)
                elif sec.get("vertices") or (not own and shared.get("vertices")):
                    d += ", polygonal (vertices)"
                elif all(g[k] is not None for k in ("s1", "s2", "alpha1", "alpha2")):
                    d += f", s1 {g['s1']:g} m / s2 {g['s2']:g} m, {g['alpha1']:g} / {g['alpha2']:g} deg"
            else:
                d = f"section {sec['name']} ({sec['length']:g} m): unflighted"
            rows.append(("flights" if sec is inp["sections"][0] else "", d, ""))
    mat = (inp.get("material") or {}).get("name")
    if mat:
        rows.append(("material", str(mat), ""))
    return rows


def _pi(inputs: dict) -> tuple[dict | None, str]:
    """Ajayi's measured means of the case's test, or None and the reason."""
    op, gas, tr = inputs.get("operating") or {}, inputs.get("gas") or {}, inputs.get("transport") or {}
    test = op.get("test")
    if test is None or (inputs.get("tracer") or {}).get("dataset") != "ajayi2011_test{test}":   # the MMG PI data
        return None, ""
    changed = [k for k, v in (("operating.feed_rate", op.get("feed_rate")), ("operating.rpm", op.get("rpm")),
                              ("operating.feed_moisture", op.get("feed_moisture")),
                              ("gas.inlet_temperature", gas.get("inlet_temperature"))) if v is not None]
    if float(tr.get("moisture_scale", 1.0) or 1.0) != 1.0:
        changed.append("transport.moisture_scale")
    if changed:
        return None, (f"The run departs from the conditions of Test {test} ({', '.join(changed)} set), so it is not "
                      "compared with that test's plant data.")
    from ..thermal.consistency import pi_test_conditions
    from ..thermal.dryer import pi_operating_conditions

    d = dict(pi_test_conditions(int(test)))
    raw = pi_operating_conditions(int(test))
    d["holdup_kg"] = float(raw["holdup_exp_kg"]) if raw.get("holdup_exp_kg", "").strip() else float("nan")
    d["test"] = int(test)
    return d, ""


def holdup_comparison(results) -> dict | None:
    """Model total holdup against the measured one (Ajayi (2011) Table 3.14, from the tracer
    test: holdup = feed x measured mean residence time), or None."""
    pi, _ = _pi(results.inputs)
    if pi is None or not np.isfinite(pi["holdup_kg"]):
        return None
    model = float(results.scalars["total_holdup_kg"])
    return dict(model_kg=model, measured_kg=pi["holdup_kg"], error_kg=model - pi["holdup_kg"],
                error_pct=100 * (model / pi["holdup_kg"] - 1), test=pi["test"])


def _axial_moisture_points():
    text = (resources.files("rotarydryer") / "data" / "ajayi_moisture_profile_table3_3.csv").read_text()
    rows = csv.DictReader(line for line in text.splitlines() if not line.startswith("#"))
    return [(float(r["position_m"]), float(r["moisture_kg_per_kg_wet"])) for r in rows]


def _solids_profile(results):
    """(positions m, moisture kg/kg wet) of the solids, the mean over the phases at one position."""
    ts = results.datasets["thermal_solids"]
    x, w = np.asarray(ts.position.values, float), np.asarray(ts.moisture.values, float)
    ux = np.unique(x)
    return ux, np.array([w[x == u].mean() for u in ux])


def thermal_comparison(results) -> dict:
    """Model against measured temperatures and moistures: ``points`` (list of dicts: quantity,
    where, position_m, measured, model, error, unit, source) and per unit (degC, % points) the
    mean absolute and maximum absolute errors; ``reason`` when there are no points."""
    inp, s = results.inputs, results.scalars
    if "thermal_solids" not in results.datasets:
        return dict(points=[], summary={}, reason="The run has no heat and mass transfer results.")
    pi, reason = _pi(inp)
    if pi is None:
        return dict(points=[], summary={}, reason=reason or (
            "No temperatures or moistures were measured on this dryer in the case's source, so the heat and mass "
            "transfer results are predictions that cannot be checked here."))
    lay_len = sum(float(sec["length"]) for sec in inp.get("sections", []))
    direction = (inp.get("operating") or {}).get("gas_flow", "co-current")
    gas_out_at = lay_len if direction == "co-current" else 0.0
    src = f"Ajayi (2011) Tables 3.5-3.11, Test {pi['test']}"
    pts = []

    def add(q, where, x, meas, model, unit, source):
        if np.isfinite(meas) and model is not None:
            pts.append(dict(quantity=q, where=where, position_m=x, measured=float(meas), model=float(model),
                            error=float(model) - float(meas), unit=unit, source=source))

    add("product moisture", "product outlet", lay_len, 100 * pi["moisture_out"],
        100 * s["product_moisture_kg_kg"] if "product_moisture_kg_kg" in s else None, "% points", src)
    # the plant's sensor, as validate and calibrate compare it: the product cooled on its way there where the case
    # has a discharge-cooling NTU (the drum outlet's temperature otherwise)
    sensor = s.get("product_temperature_at_sensor_degC")
    add("product temperature", "product sensor" if sensor is not None else "product outlet", lay_len, pi["product_c"],
        sensor if sensor is not None else s.get("product_temperature_degC"), "degC", src)
    add("gas outlet temperature", "gas outlet", gas_out_at, pi["gas_out_c"], s.get("gas_outlet_temperature_degC"),
        "degC", src)
    ux, wx = _solids_profile(results)
    for x, w in _axial_moisture_points():
        if 0.0 < x <= lay_len:     # x = 0 is the feed, not a prediction
            add("solids moisture", f"{x:g} m from the feed", x, 100 * w, 100 * float(np.interp(x, ux, wx)),
                "% points", "Ajayi (2011) Table 3.3")
    summary = {}
    for unit in ("degC", "% points"):
        errs = [abs(p["error"]) for p in pts if p["unit"] == unit]
        if errs:
            worst = max((p for p in pts if p["unit"] == unit), key=lambda p: abs(p["error"]))
            summary[unit] = dict(n=len(errs), mae=float(np.mean(errs)), max=float(max(errs)),
                                 max_at=f"{worst['quantity']}, {worst['where']}")
    return dict(points=pts, summary=summary, reason="", test=pi["test"], tuned=_tuned_on(inp, pi["test"]))


def _tuned_on(inputs: dict, test: int) -> bool:
    """Is ``test`` the one the built-in MMG case's gas flow and area scale were tuned on (Test 4,
    see the case file) and does the run use those tuned values?"""
    from ..cases import load_case

    tuned = load_case("ajayi2011_mmg")
    run, gas = inputs.get("thermal") or {}, inputs.get("gas") or {}
    return test == 4 and gas.get("flow") == tuned.gas.flow and run.get("area_scale") == tuned.thermal.area_scale
