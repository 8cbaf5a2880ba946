"""Logic of the "Whole dryer" page: plain functions returning numbers, tables and PNG bytes.

No Streamlit here (testable directly, cached by the page) and no physics: every number comes
from `rotarydryer.simulation.Simulation` (the coupled heat-and-mass steady state,
``ThermalSteadyState``) and every figure from `rotarydryer.report.plots`. Inputs go to the
model as the case's own override keys (``--set`` of the CLI), so bad values are refused with
the CLI's messages (the case schema and the model's checks). A case is a built-in name or an
uploaded file staged by `rotarydryer.app.logic.stage_case_file` (never a path).
"""

from __future__ import annotations

import csv
import io
import math

import numpy as np

from .._display import show_output, to_display
from .logic import _load, png, run_warnings

__all__ = ["NoThermalModel", "operating_inputs", "study_inputs", "plant_tests", "dryer_view", "results_of",
           "report_html", "netcdf_bytes", "duty_table"]


class NoThermalModel(ValueError):
    """The case has no heat-and-mass model (``thermal.enabled = false`` or no gas)."""


def _spec(key, label, unit, value, lo, hi, step, fmt="%.3f", integer=False):
    """One input: the case's override key, a label with its unit, the case's value and the
    widget bounds (the schema's inclusive bounds; an excluded end such as 0 stays enterable so
    that the model refuses it with the CLI's message)."""
    return {"key": key, "label": f"{label} ({unit})" if unit else label, "unit": unit,
            "value": None if value is None else (int(value) if integer else float(value)),
            "min": lo, "max": hi, "step": step, "format": "%d" if integer else fmt, "integer": integer}


def _kind_keys(case) -> dict:
    """Override keys of the main operating variables (one schema: the same keys for every case)."""
    return {"gas_inlet_temperature": "gas.inlet_temperature", "gas_flow": "gas.flow",
            "feed_temperature": "operating.feed_temperature", "area_scale": "thermal.area_scale",
            "gas_inlet_humidity": "gas.inlet_humidity", "insulation_thickness": "shell.insulation_thickness",
            "feed_moisture": "operating.feed_moisture"}


def _has_thermal(c) -> bool:
    from ..simulation import Simulation

    try:
        return Simulation(c).thermal_enabled and c.gas is not None
    except ValueError:
        return False


def _check_thermal(c, shown: str = "the case"):
    if not _has_thermal(c):
        raise NoThermalModel(f"{shown} has no heat and mass transfer model (thermal.enabled = false, or no [gas] "
                             "block with flow and inlet_temperature): this page needs one; the Transport and RTD "
                             "page shows its solids transport")


def plant_tests(case: str) -> list[int]:
    """Plant tests a case can run (Ajayi's MMG tests with fitted transport parameters, or every
    test with ``transport.parameter_source = 'predictive'``); [] for other kinds."""
    c = _load(case)
    predictive = c.transport.parameter_source == "predictive"
    return [t.test for t in c.tests if predictive or t.solids_velocity is not None]


def operating_inputs(case: str, test: int | None = None) -> list[dict]:
    """The main operating variables of a case (feed rate, speed, feed moisture, feed temperature,
    gas inlet temperature, gas flow) as input specs: ``key`` (override key of the case's schema),
    ``label``, ``value`` (the case's, at plant test ``test`` for Ajayi's MMG case), widget bounds
    ``min``/``max``/``step``. Raises `NoThermalModel` for a case without heat and mass
    transfer. Ajayi's feed moisture is the test's (no override key): change the test."""
    from ..cases.build import operating_point

    c = _load(case, {"operating.test": test} if test is not None else None)
    _check_thermal(c, "this case")
    from ..simulation import Simulation

    st = Simulation(c).thermal_settings()
    feed, rpm, x_in, t_feed = operating_point(c)
    k = _kind_keys(c)
    out = [_spec("operating.feed_rate", "Feed rate", "kg/s wet", feed, None, None, _step(feed), "%.4g"),
           _spec("operating.rpm", "Speed", "rev/min", rpm, None, None, 0.1, "%.2f")]
    if k["feed_moisture"] is not None:
        out.append(_spec("operating.feed_moisture", "Feed moisture", "kg/kg wet", x_in, None, None, 0.005, "%.4f"))
    out += [_spec(k["feed_temperature"], "Feed temperature", "degC", t_feed, None, None, 1.0, "%.1f"),
            _spec(k["gas_inlet_temperature"], "Gas inlet temperature", "degC", st.gas_inlet_temperature, None, None,
                  5.0, "%.1f"),
            _spec(k["gas_flow"], "Gas flow", "kg/s wet", st.gas_flow, None, None, _step(st.gas_flow), "%.4g")]
    return _case_bounds(c, out)


def _step(value) -> float:
    """A widget step of about a tenth of ``value``, rounded to 1, 2 or 5 x 10^k."""
    v = abs(float(value or 0.0)) / 10 or 0.1
    k = 10 ** math.floor(math.log10(v))
    return float(next(m * k for m in (1, 2, 5, 10) if m * k >= v * 0.999))


def _case_bounds(c, specs: list[dict]) -> list[dict]:
    """Fill the widget bounds ``min``/``max`` of ``specs`` from the case schema's range of each key
    (`rotarydryer.app.logic.schema_bounds`; the speed also below the critical speed of the
    case's drum), widened to contain the case's value: no fixed limits, and the case's value is
    always inside its widget (None: no bound on that side)."""
    from ..geometry.drum import critical_speed
    from .logic import schema_bounds, widen

    for s in specs:
        lo, hi = schema_bounds(type(c), s["key"])
        if s["key"] == "operating.rpm":
            try:
                nc = float(critical_speed(float(c.drum.radius)))
                hi = nc if hi is None else min(hi, nc)
            except (AttributeError, TypeError, ValueError):
                pass
        if s["value"] is not None:
            lo, hi = widen(lo, hi, s["value"])
        s["min"], s["max"] = lo, hi
    return specs


def study_inputs(case: str) -> list[dict]:
    """Inputs a study may vary on a case: `operating_inputs` plus model parameters (drum
    slope, area scale, gas inlet humidity, insulation thickness), each with a default study
    range ``low``/``high`` around the case's value (within the widget bounds)."""
    c = _load(case)
    specs = operating_inputs(case)
    k = _kind_keys(c)
    st = _settings(c)
    specs += _case_bounds(c, [
        _spec("drum.slope", "Drum slope", "deg", c.drum.slope, None, None, 0.1, "%.2f"),
        _spec(k["area_scale"], "Area scale (transfer area multiplier)", "-", st.area_scale, None, None, 0.1, "%.3f"),
        _spec(k["gas_inlet_humidity"], "Gas inlet humidity", "kg/kg wet gas", st.gas_inlet_humidity, None, None,
              0.001, "%.4f"),
        _spec(k["insulation_thickness"], "Shell insulation thickness", "m", st.insulation_thickness, None, None,
              0.01, "%.3f")])
    for s in specs:
        v = s["value"]
        if v is None or v == 0:
            lo, hi = 0.0, {"m": 0.1}.get(s["unit"], 1.0)
        else:
            rel = 0.1 if s["unit"] == "degC" else 0.15
            lo, hi = v * (1 - rel), v * (1 + rel)
        lo = lo if s["min"] is None else max(lo, s["min"])
        hi = hi if s["max"] is None else min(hi, s["max"])
        s["low"], s["high"] = float(f"{lo:.4g}"), float(f"{hi:.4g}")
    return specs


def _settings(c):
    from ..simulation import Simulation

    return Simulation(c).thermal_settings()


def _steady(case: str, overrides: dict):
    """``(validated case, Simulation, SteadyResult)`` at ``overrides`` (the schema's, then the
    model's checks: ValueErrors with the CLI's messages)."""
    from ..simulation import Simulation

    c = _load(case, overrides)
    _check_thermal(c, "this case")
    sim = Simulation(c)
    return c, sim, sim.steady_state()


def duty_table(summary: dict) -> list[dict]:
    """The energy audit's heat duties of a steady state's ``summary`` (`rotarydryer.thermal.audit`): one
    row per duty, ``{"duty": label, "name": summary name, "value": in the display unit of power,
    "share_pct": % of the release (None for the release and the exhaust's latent heat, which is part of
    the evaporation's heat), "part": whether it is one of the duties that add up to the release}``."""
    from ..thermal.audit import HEAT_DUTY_LABELS, HEAT_DUTY_PARTS

    release = summary["heat_release_W"]
    rows = []
    for k in ("heat_release_W", *HEAT_DUTY_PARTS, "heat_duty_exhaust_latent_W"):
        part = k in HEAT_DUTY_PARTS
        rows.append({"duty": HEAT_DUTY_LABELS[k], "name": k, "value": to_display(summary[k], "power"),
                     "share_pct": 100.0 * summary[k] / release if part and release else None, "part": part})
    return rows


def _measured(c) -> dict | None:
    """Measured plant values of the case's operating point (Ajayi's MMG tests, Tables 3.5-3.11)."""
    if c.operating.test is None or c.tracer.dataset != "ajayi2011_test{test}":   # the MMG PI data set
        return None
    from ..thermal.consistency import pi_test_conditions

    m = pi_test_conditions(c.operating.test)
    return {"test": int(c.operating.test), **{k: v for k, v in m.items() if isinstance(v, float)}}


def measured_table(summary: dict, measured: dict) -> dict:
    """The model against the plant's measured means (`_measured`) as table columns: product moisture, product
    temperature (the model's at the plant's sensor where the case has a discharge-cooling NTU, as `validate` and the
    report compare it) and gas outlet temperature, shown in their display units."""
    sensor = summary.get("product_temperature_at_sensor_degC") is not None
    t_name = "product_temperature_at_sensor_degC" if sensor else "product_temperature_degC"
    names = ("product_moisture_kg_kg", t_name, "gas_outlet_temperature_degC")
    plant = (measured.get("moisture_out", float("nan")), measured.get("product_c", float("nan")),
             measured.get("gas_out_c", float("nan")))
    return {"quantity": ["product moisture (wet)", "product temperature" + (" at the sensor" if sensor else ""),
                         "gas outlet temperature"],
            "model": [show_output(n, summary[n]) for n in names],
            f"measured (test {measured['test']})": [show_output(n, v) for n, v in zip(names, plant)]}


def _profiles_figure(th, measured, sensor_c=None):
    from ..report.plots import plot_thermal_steady_state

    fig = plot_thermal_steady_state(th)
    if not measured:
        return fig
    a1, a2 = fig.axes[0], fig.axes[1]
    p = th.profiles()
    x0, x1 = float(np.min(p["position"])), float(np.max(p["position"]))
    co = th.dryer.settings.gas_direction == "co-current"
    g_in, g_out = (x0, x1) if co else (x1, x0)
    lab = f"measured (test {measured['test']})"
    pts = [(a1, g_in, measured.get("gas_in_c"), "rs"), (a1, g_out, measured.get("gas_out_c"), "rs"),
           (a1, x1, measured.get("product_c"), "ks"), (a2, x0, measured.get("moisture_in"), "ks"),
           (a2, x1, measured.get("moisture_out"), "ks")]
    for ax, x, y, style in pts:
        if y is not None and math.isfinite(y):
            ax.plot([x], [y], style, ms=7, mfc="none", mew=1.5, label=lab if ax is a1 and style == "ks" else None)
    if sensor_c is not None and math.isfinite(sensor_c):    # the plant's product temperature is a sensor's
        a1.plot([x1], [sensor_c], "b^", ms=7, mfc="none", mew=1.5, label="model at the product sensor")
    a1.legend(fontsize=8)
    a2.legend(fontsize=8, loc="upper center")
    return fig


def _profiles_csv(th) -> str:
    """The profiles download: one row per solids tank (the whole drum), then one per gas stage with the stage's
    evaporation and shell loss (per gas stage: zipped with the tanks, the evaporation cut the solids table at the
    number of stages, half of MMG's drum, and sat on other tanks' rows)."""
    p = th.profiles()
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["position_m", "phase", "section", "solids_temperature_degC", "moisture_kg_kg_wet", "holdup_kg"])
    for row in zip(p["position"], p["phase"], p["section"], p["solids_temperature_degC"], p["moisture_wet"],
                   p["holdup_kg"], strict=True):
        w.writerow([repr(float(row[0])), row[1], row[2], *(repr(float(v)) for v in row[3:])])
    w.writerow([])
    w.writerow(["gas_position_m", "gas_temperature_degC", "gas_humidity_kg_kg_dry", "evaporation_kg_s", "shell_loss_W"])
    for row in zip(p["gas_position"], p["gas_temperature_degC"], p["gas_humidity"], p["evaporation_kg_s"],
                   p["shell_loss_W"], strict=True):
        w.writerow([repr(float(v)) for v in row])
    return buf.getvalue()


def profile_rows(profiles: dict, measured: dict | None = None, co_current: bool = True,
                 sensor_c: float | None = None) -> list[dict]:
    """The axial profiles of ``profiles`` (``ThermalSteadyState.profiles()``) as long-format rows
    for an interactive chart: ``{"quantity": "temperature" | "moisture" | "humidity", "series",
    "section", "position_m", "value" (in its display unit, `rotarydryer._display`), "measured": bool}`` (gas temperature and humidity per gas
    stage; solids temperature and moisture per tank, one series per phase: bed, passive, active);
    with ``measured`` (`_measured`), the plant's values at the ends as in the PNG figure (gas
    in and out, product temperature, feed and product moisture); ``sensor_c``: the model's product temperature at the
    plant's sensor (a case with a discharge-cooling NTU), the series the measured product temperature compares with."""
    p = profiles
    rows = []

    def add(quantity, series, section, x, y, meas=False):
        y = to_display(y, quantity)         # the display unit of the quantity (rotarydryer._display)
        if math.isfinite(y):
            rows.append({"quantity": quantity, "series": series, "section": str(section),
                         "position_m": float(x), "value": y, "measured": meas})

    for x, t, w in zip(p["gas_position"], p["gas_temperature_degC"], p["gas_humidity"]):
        add("temperature", "gas", "", x, t)
        add("humidity", "gas", "", x, w)
    for x, ph, sec, t, m in zip(p["position"], p["phase"], p["section"], p["solids_temperature_degC"],
                                p["moisture_wet"]):
        add("temperature", f"solids ({ph})", sec, x, t)
        add("moisture", f"solids ({ph})", sec, x, m)
    if measured:
        x0, x1 = float(np.min(p["position"])), float(np.max(p["position"]))
        g_in, g_out = (x0, x1) if co_current else (x1, x0)
        lab = f"measured (test {measured['test']})"
        for quantity, x, key in (("temperature", g_in, "gas_in_c"), ("temperature", g_out, "gas_out_c"),
                                 ("temperature", x1, "product_c"), ("moisture", x0, "moisture_in"),
                                 ("moisture", x1, "moisture_out")):
            if measured.get(key) is not None:
                add(quantity, lab, "", x, measured[key], meas=True)
        if sensor_c is not None:
            add("temperature", "model at the product sensor", "", x1, sensor_c)
    return rows


def dryer_view(case: str, overrides: dict | None = None, images: bool = True) -> dict:
    """Coupled steady state of the whole dryer at ``overrides`` (override keys, e.g. those of
    `operating_inputs`).

    Returns ``{"summary": SteadyResult.summary(), "metrics": {...}, "duties": rows of `duty_table` (the
    energy audit's heat duties in the display unit of power), "shell_sections": the shell per section
    (loss W, hottest surface and steel degC), "measured": {...} or None, "has_burner": bool,
    "profiles_csv": str, "profiles": png, "waterfall": png (the heat duties), "profile_rows": rows
    for an interactive chart (`profile_rows`)}``. Raises ``ValueError`` with the CLI's message on a
    bad value and `NoThermalModel` for a case without heat and mass transfer."""
    from ..cases.build import has_burner
    from ..report.plots import plot_heat_duties
    from ..thermal.audit import shell_sections

    overrides = dict(overrides or {})
    (c, sim, steady), notes = run_warnings(_steady, case, overrides)
    th = steady.thermal
    s = steady.summary()
    burner = has_burner(c)
    measured = _measured(c)
    metrics = {k: s.get(k) for k in ("product_moisture_kg_kg", "product_temperature_degC", "gas_outlet_temperature_degC",
                                      "specific_energy_kJ_kg_water", "thermal_efficiency", "mean_residence_time_s",
                                      "evaporation_kg_s", "heat_input_W", "fuel_rate_kg_s")}
    out = {"summary": s, "metrics": metrics, "duties": duty_table(s), "shell_sections": shell_sections(th),
           "measured": measured, "has_burner": burner, "warnings": notes,
           "fuel_rate_error": s.get("fuel_rate_error"), "profiles_csv": _profiles_csv(th),
           "title": getattr(c.meta, "title", "") or "",
           "profile_rows": profile_rows(th.profiles(), measured, th.dryer.settings.gas_direction == "co-current",
                                        s.get("product_temperature_at_sensor_degC"))}
    if th.dryer.n_classes > 1:        # [particle_size]: a row per size class and the distributions
        out["size_classes"] = th.size_class_table()
        if images:
            from ..thermal.plots import plot_size_distributions

            out["size_plot"] = png(plot_size_distributions(th), dpi=100)
    if images:
        # drawn at about the width of the page's main area on a laptop (900 px): shown unscaled
        out["profiles"] = png(_profiles_figure(th, out["measured"], s.get("product_temperature_at_sensor_degC")),
                              dpi=100)
        out["waterfall"] = png(plot_heat_duties(s), dpi=110)
    return out


def results_of(case: str, overrides: dict | None = None):
    """`rotarydryer.results.Results` of the case at ``overrides`` (transport, tracer RTD
    and the coupled heat and mass steady state): what the downloads hold."""
    from ..simulation import run_case

    c = _load(case, dict(overrides or {}))
    _check_thermal(c, "this case")
    res = run_case(c, applied=dict(overrides or {}) or None)
    if not str(case).startswith("uploaded_case_"):
        res.case_name = case
    return res


def report_html(case: str, overrides: dict | None = None) -> str:
    """The HTML report (``rotarydryer report``) of the case at ``overrides``."""
    from ..report.html import render_report

    return render_report(results_of(case, overrides))


def netcdf_bytes(case: str, overrides: dict | None = None) -> bytes:
    """The results of the case at ``overrides`` as a netCDF file (bytes)."""
    import tempfile
    from pathlib import Path

    res = results_of(case, overrides)
    with tempfile.TemporaryDirectory() as d:
        return res.save(Path(d) / "results.nc").read_bytes()
