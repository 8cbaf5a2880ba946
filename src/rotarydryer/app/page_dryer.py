"""Web-app page "Whole dryer": the coupled heat-and-mass steady state of a shipped or uploaded
case at changed operating variables -> product moisture and temperature, gas outlet, specific
energy, thermal efficiency, fuel rate (cases with a burner), residence time; temperature and
moisture profiles (with the measured plant values where the case has them), the energy
audit (heat duties in the display unit of power, the exhaust's dew point, the shell per
section); downloads (profiles CSV, results netCDF, HTML report). Below, two run
panels on the same case and operating variables: "Target" (the input that meets a target on
an output, ``rotarydryer target``) and "Schedule" (an input schedule from the steady state:
steps, ramps, a burner trip, ``rotarydryer dynamics``); their results are kept in the session
(a rerun shows them again without recomputing; a progress bar is never inside st.cache_data).

Logic: `rotarydryer.app.logic_dryer` and `rotarydryer.app.logic_dryer_runs` (no Streamlit). Errors: the CLI's messages
(`rotarydryer.app._ui.refuse`).
"""

import hashlib

import streamlit as st

from .._display import fmt as fmt_value
from .._display import show, show_delta, show_output, unit_of
from . import logic_dryer, logic_dryer_runs
from ._ui import case_picker, deferred, heavy, number, plain, progress_box, refuse


@st.cache_data(show_spinner=False, max_entries=32)
def _inputs(case, test):
    return logic_dryer.operating_inputs(case, test)


@st.cache_data(show_spinner=False, max_entries=16)
def _tests(case):
    return logic_dryer.plant_tests(case)


@st.cache_data(show_spinner=False, max_entries=32)
def _view(case, overrides):
    with heavy():
        return logic_dryer.dryer_view(case, dict(overrides))


def _stem(case):
    return "uploaded_case" if case.startswith("uploaded_case_") else case


#: the interactive profile charts: (quantity of logic_dryer.profile_rows, y axis title, read-out format)
_PROFILE_CHARTS = [("temperature", "temperature ({})", ".1f"), ("moisture", "solids moisture ({} wet)", ".4g"),
                   ("humidity", "gas humidity ({} dry gas)", ".4g")]


#: colours of the profile series, as in the PNG figure (gas red, solids bed black, passive blue, active cyan)
_SERIES_COLOURS = {"gas": "#d62728", "solids (bed)": "#222222", "solids (passive)": "#1f77b4",
                   "solids (active)": "#17becf"}


def _colour_scale(series):
    """The series' fixed colours (`_SERIES_COLOURS`, others grey: the measured values), the
    same on every chart."""
    import altair as alt

    known = [n for n in _SERIES_COLOURS if n in set(series)]
    names = known + sorted(set(series) - set(known))
    return alt.Scale(domain=names, range=[_SERIES_COLOURS.get(n, "#555555") for n in names])


def _profile_chart(rows, title, fmt):
    """An Altair line chart of one quantity along the dryer (one colour per series, a line per
    section; measured values as squares) with a read-out: pointing at it marks the nearest
    position with a rule and shows the series' values there in a tooltip."""
    import altair as alt
    import pandas as pd

    df = pd.DataFrame(rows)
    hover = alt.selection_point(fields=["position_m"], nearest=True, on="mouseover", clear="mouseout", empty=False)
    x = alt.X("position_m:Q", title="axial position from the feed end (m)")
    base = alt.Chart(df).encode(x=x, y=alt.Y("value:Q", title=title, scale=alt.Scale(zero=False)),
                                color=alt.Color("series:N", title=None, scale=_colour_scale(df["series"]),
                                                legend=alt.Legend(orient="right")))
    lines = base.transform_filter("!datum.measured").mark_line().encode(detail="section:N")
    measured = base.transform_filter("datum.measured").mark_square(size=90, filled=False, strokeWidth=2)
    points = base.mark_circle(size=70).encode(
        opacity=alt.condition(hover, alt.value(1.0), alt.value(0.0)),
        tooltip=[alt.Tooltip("series:N", title="series"), alt.Tooltip("position_m:Q", title="position (m)", format=".2f"),
                 alt.Tooltip("value:Q", title=title, format=fmt)]).add_params(hover)
    rule = alt.Chart(df).mark_rule(color="gray", strokeDash=[4, 3]).encode(x=x).transform_filter(hover)
    return alt.layer(lines, measured, points, rule).properties(height=240).interactive(bind_y=False)


def _fmt(v, spec):
    return "n/a" if v is None else spec.format(v)


def render():
    st.title("Whole dryer")
    case, shown = case_picker("dryer", "ajayi2011_mmg",
                              help_text="any case with a heat and mass transfer model ([gas] or [thermal])")
    try:
        tests = _tests(case)
    except Exception as exc:
        refuse(f"Case {shown} refused", exc)
    test = None
    if tests:
        from .logic import _load

        default = _load(case).operating.test
        test = st.sidebar.selectbox("Plant test", tests,
                                    index=tests.index(default) if default in tests else 0, key=f"dryer_test__{case}",
                                    help="one of the case's [[tests]] rows: it sets the operating point the "
                                         "inputs below start from; the measured values are drawn on the profiles")
    try:
        specs = _inputs(case, test)
    except logic_dryer.NoThermalModel as exc:
        st.info(plain(f"{shown}: {exc}"))
        st.stop()
    except Exception as exc:
        refuse(f"Case {shown} refused", exc)
    overrides = {} if test is None else {"operating.test": int(test)}
    with st.sidebar.expander("Operating variables", expanded=True):
        for s in specs:
            # bounds: the schema's range of the key, containing the case's value (logic_dryer._case_bounds)
            overrides[s["key"]] = number(st, s["label"], s["min"], s["max"], float(s["value"]), float(s["step"]),
                                         format=s["format"], key=f"dryer__{s['key']}__{case}__{test}",
                                         help=f"case key {s['key']} (rotarydryer simulate --set)")
    if test is not None:
        st.sidebar.caption(f"The inputs start at test {test}'s operating point; change one to run off it.")
    try:
        with st.spinner("Solving the coupled heat and mass steady state ..."):
            r = _view(case, tuple(sorted(overrides.items())))
    except logic_dryer.NoThermalModel as exc:
        st.info(plain(f"{shown}: {exc}"))
        st.stop()
    except Exception as exc:
        refuse("Invalid input", exc)
    if r["title"]:
        st.caption(plain(r["title"]))
    for w in r.get("warnings", []):      # what the CLI prints as warnings
        st.warning(plain(w))
    m = r["metrics"]
    c = st.columns(4)
    c[0].metric("Product moisture", show_output("product_moisture_kg_kg", m["product_moisture_kg_kg"]), help="wet basis")
    c[1].metric("Product temperature", show_output("product_temperature_degC", m["product_temperature_degC"]))
    c[2].metric("Gas outlet temperature", show_output("gas_outlet_temperature_degC", m["gas_outlet_temperature_degC"]))
    c[3].metric("Mean residence time", show_output("mean_residence_time_s", m["mean_residence_time_s"]),
                help="holdup / solids outflow (the product, and the dust the gas carries off)")
    c = st.columns(4)
    c[0].metric("Specific energy", show_output("specific_energy_kJ_kg_water", m["specific_energy_kJ_kg_water"]),
                help="heat put into the gas per kg of water evaporated")
    c[1].metric("Thermal efficiency", _fmt(m["thermal_efficiency"], "{:.1%}"),
                help="evaporation x latent heat / heat put into the gas")
    c[2].metric("Evaporation", show_output("evaporation_kg_s", m["evaporation_kg_s"]))
    if r["has_burner"]:
        c[3].metric("Fuel rate", show_output("fuel_rate_kg_s", m["fuel_rate_kg_s"]),
                    help=r["fuel_rate_error"] or "fuel the case's burner needs to heat the gas to its inlet temperature")
    else:
        c[3].metric("Heat input", show_output("heat_input_W", m["heat_input_W"]),
                    help="no burner in this case: heat put into the gas")
    sizes = r.get("size_classes")
    tabs = st.tabs(["Temperature and moisture profiles", "Energy"]
                   + ([f"Model and plant data (test {r['measured']['test']})"] if r["measured"] else [])
                   + (["Particle sizes"] if sizes else []))
    with tabs[0]:
        st.caption("Gas and solids temperature, solids moisture and gas humidity along the dryer"
                   + (f" (squares: measured, test {r['measured']['test']})" if r["measured"] else "")
                   + ". Point at a curve for the values at that position; drag to pan, scroll to zoom.")
        for quantity, title, fmt in _PROFILE_CHARTS:
            rows = [row for row in r["profile_rows"] if row["quantity"] == quantity]
            if rows:
                st.altair_chart(_profile_chart(rows, title.format(unit_of(quantity)), fmt), width="stretch",
                                key=f"dryer_chart_{quantity}")
        st.download_button("Download the profiles figure (PNG)", r["profiles"], file_name=f"{_stem(case)}_profiles.png",
                           mime="image/png", key="dryer_dl_png")
    with tabs[1]:
        power, temp = unit_of("power"), unit_of("temperature")
        st.image(r["waterfall"], caption="Heat duties: where the heat release goes (they add up to it; the last "
                                         "bar, the balance closure, is rounding). Relative to the ambient air and "
                                         "the feed; the exhaust's latent heat is part of the evaporation's heat.")
        st.table({"heat duty": [t["duty"] for t in r["duties"]],
                  power: [fmt_value(t["value"]) for t in r["duties"]],      # already in the display unit
                  "% of release": ["" if t["share_pct"] is None else f"{t['share_pct']:.1f}" for t in r["duties"]]})
        s = r["summary"]
        if s.get("gas_outlet_dew_point_margin_K") is not None:
            st.caption(f"Exhaust dew point {show_output('gas_outlet_dew_point_degC', s['gas_outlet_dew_point_degC'])} "
                       f"at {s['gas_pressure_Pa'] / 1e3:.1f} kPa: the exhaust is "
                       f"{show_delta(abs(s['gas_outlet_dew_point_margin_K']), 'temperature')} "
                       + ("above it" if s["gas_outlet_dew_point_margin_K"] > 0
                          else "below it (condensation in the ducts and filter)"))
        limit = s.get("shell_temperature_limit_degC")
        st.table({"section": [x["section"] for x in r["shell_sections"]],
                  f"shell loss ({power})": [show(x["shell_heat_loss_W"], "power", with_unit=False)
                                            for x in r["shell_sections"]],
                  f"hottest surface ({temp})": [show(x["max_surface_temperature_degC"], "temperature", with_unit=False)
                                                for x in r["shell_sections"]],
                  f"hottest steel ({temp})": [show(x["max_wall_temperature_degC"], "temperature", with_unit=False)
                                              for x in r["shell_sections"]]})
        st.caption("Shell: " + ("no limit set (shell.max_temperature, e.g. 593 degC for mild steel)" if limit is None
                                else f"limit {show_output('shell_temperature_limit_degC', limit)}: "
                                + ("EXCEEDED" if s.get("shell_temperature_limit_exceeded") else "met"))
                   + ". What-if savings (recycle, preheating, insulation): rotarydryer audit.")
    if r["measured"]:
        with tabs[2]:
            st.table(logic_dryer.measured_table(r["summary"], r["measured"]))
            st.caption("Measured: Ajayi (2011) Tables 3.5-3.11 (PI means of the test); the model runs at the "
                       "operating variables in the sidebar.")
    if sizes:
        with tabs[-1]:
            st.caption(plain(f"{len(sizes)} size classes of equal feed mass; product d50 "
                             f"{show_output('product_d50_m', r['summary']['product_d50_m'])}, dust to the exhaust "
                             f"{show_output('dust_rate_kg_s', r['summary']['dust_rate_kg_s'])}"))
            st.table({f"class diameter ({unit_of('particle_size')})": [show(x["diameter_m"], "particle_size",
                                                                               with_unit=False) for x in sizes],
                      "feed fraction": [f"{x['feed_fraction']:.3g}" for x in sizes],
                      "product fraction": [f"{x['product_fraction']:.3g}" for x in sizes],
                      "lost as dust": [f"{100 * x['lost_as_dust']:.3g} %" for x in sizes],
                      "product moisture": ["-" if x["product_moisture_kg_kg"] is None
                                           else show_output("product_moisture_kg_kg", x["product_moisture_kg_kg"])
                                           for x in sizes],
                      "mean residence time": ["-" if x["mean_residence_time_s"] is None
                                              else show_output("mean_residence_time_s", x["mean_residence_time_s"])
                                              for x in sizes]})
            if r.get("size_plot") is not None:
                st.image(r["size_plot"], caption="Cumulative size distributions of the feed, the product and the dust; "
                                                 "each class's product moisture and share lost as dust")
    stem = _stem(case)
    ov = dict(overrides)
    d1, d2, d3 = st.columns(3)
    d1.download_button("Download profiles (CSV)", r["profiles_csv"], file_name=f"{stem}_profiles.csv",
                       mime="text/csv", key="dryer_dl_csv")
    d2.download_button("Download results (netCDF)", deferred(logic_dryer.netcdf_bytes, case, ov),
                       file_name=f"{stem}.nc", mime="application/x-netcdf", key="dryer_dl_nc")
    d3.download_button("Download HTML report", deferred(logic_dryer.report_html, case, ov), file_name=f"{stem}.html",
                       mime="text/html", key="dryer_dl_html")
    st.subheader("Runs on this case")
    t_target, t_sched = st.tabs(["Target: find the input that meets a target",
                                 "Schedule: run an input schedule (steps, ramps, a burner trip)"])
    with t_target:
        _target_panel(case, shown, overrides, r["summary"])
    with t_sched:
        _schedule_panel(case, shown, overrides)


#: default target values of the outputs (when the steady state has none)
_TARGET_DEFAULTS = {"product_moisture_kg_kg": 0.12, "product_temperature_degC": 60.0,
                    "gas_outlet_temperature_degC": 120.0, "gas_outlet_dew_point_margin_K": 20.0,
                    "fill_fraction": 0.1}


def _kept(name, key):
    """The result of the panel ``name`` kept in the session for the inputs ``key`` (or None)."""
    kept = st.session_state.get(f"dryer_{name}_result")
    return kept[1] if kept is not None and kept[0] == key else None


def _guarded_run(what, shown, run):
    """``run()`` inside the panels' failure boundary: its result, or None once the reason is shown
    (no gas: a note; bad input: the refusal; anything else: a generic failure, logged)."""
    try:
        return run()
    except logic_dryer.NoThermalModel as exc:
        st.info(plain(f"{shown}: {exc}; the target and schedule panels need a gas"))
    except ValueError as exc:
        refuse(f"{what} refused", exc, stop=False)
    except Exception as exc:  # noqa: BLE001 - shown as a generic sentence, logged
        refuse(f"{what} failed", exc, stop=False)
    return None


def _keep(name, key, value):
    st.session_state[f"dryer_{name}_result"] = (key, value)


def _target_panel(case, shown, overrides, summary):
    st.caption("One free input varied in its bounds (blank: the default span around the case's value) until "
               "the output meets the condition, at the other operating variables of the sidebar "
               "(rotarydryer target --find KEY=LO,HI --such-that OUTPUT=V).")
    c = st.columns(3)
    find = c[0].selectbox("Free input", logic_dryer_runs.TARGET_INPUTS, key="dryer_target_find")
    lo = c[1].number_input("Lower bound (blank: default)", value=None, format="%.6g", key="dryer_target_lo")
    hi = c[2].number_input("Upper bound (blank: default)", value=None, format="%.6g", key="dryer_target_hi")
    c = st.columns(3)
    output = c[0].selectbox("Output", logic_dryer_runs.TARGET_OUTPUTS, key="dryer_target_output")
    op = c[1].selectbox("Operator", logic_dryer_runs.TARGET_OPERATORS, key="dryer_target_op")
    default = summary.get(output) if isinstance(summary.get(output), float) else None
    value = c[2].number_input("Value", value=float(_TARGET_DEFAULTS.get(output, default or 0.0)),
                              format="%.6g", key=f"dryer_target_value__{output}")
    key = (case, tuple(sorted(overrides.items())), find, lo, hi, output, op, float(value))
    if st.button("Find the input", key="dryer_target_run", type="primary"):
        def run():
            with st.status(f"Finding {find} such that {output}{op}{value:g} ...", expanded=False) as box:
                with heavy():
                    out = logic_dryer_runs.run_target_view(case, dict(overrides), find, lo, hi, output, op, value)
                box.update(label="Target study done", state="complete")
            return out

        res = _guarded_run("Target", shown, run)
        if res is None:
            return
        _keep("target", key, res)
    res = _kept("target", key)
    if res is None:
        return
    if res["found"]:
        u = f" {res['unit']}" if res["unit"] else ""
        m = st.columns(3)
        m[0].metric(res["find"], f"{res['value']:.6g}{u}")
        m[1].metric(res["output_name"], f"{res['output']:.6g}")
        m[2].metric("active", res["active"])
    else:
        st.warning(plain(res["message"]))
    st.code(res["text"], language=None)


def _schedule_chart(rows, quantity, title):
    """An Altair line chart of the schedule's ``quantity`` rows against time (min), with a tooltip
    at the nearest time; drag to pan, scroll to zoom."""
    import altair as alt
    import pandas as pd

    df = pd.DataFrame([r for r in rows if r["quantity"] == quantity])
    t_unit = unit_of("time")
    hover = alt.selection_point(fields=["time"], nearest=True, on="mouseover", clear="mouseout", empty=False)
    x = alt.X("time:Q", title=f"time ({t_unit})")
    base = alt.Chart(df).encode(x=x, y=alt.Y("value:Q", title=title, scale=alt.Scale(zero=False)),
                                color=alt.Color("series:N", title=None, legend=alt.Legend(orient="right")))
    lines = base.mark_line()
    points = base.mark_circle(size=60).encode(
        opacity=alt.condition(hover, alt.value(1.0), alt.value(0.0)),
        tooltip=[alt.Tooltip("series:N", title="series"), alt.Tooltip("time:Q", title=f"time ({t_unit})", format=".1f"),
                 alt.Tooltip("value:Q", title=title, format=".3f")]).add_params(hover)
    rule = alt.Chart(df).mark_rule(color="gray", strokeDash=[4, 3]).encode(x=x).transform_filter(hover)
    return alt.layer(lines, points, rule).properties(height=240).interactive(bind_y=False)


def _schedule_panel(case, shown, overrides):
    st.caption("The dynamic dryer from the steady state of the sidebar's operating variables under an input "
               "schedule (rotarydryer dynamics --schedule). A CSV has a time_s column and one column per "
               "input (gas_inlet_temperature, feed_rate, feed_moisture, rpm, gas_flow, ...).")
    preset = st.selectbox("Schedule", logic_dryer_runs.SCHEDULE_PRESETS, key="dryer_sched_preset")
    csv_bytes = None
    if preset == logic_dryer_runs.CUSTOM_CSV:
        up = st.file_uploader("Schedule CSV", type=["csv"], key="dryer_sched_csv", max_upload_size=1)
        csv_bytes = None if up is None else up.getvalue()
    c = st.columns(2)
    t_end = c[0].number_input("Run time t_end (s)", min_value=60.0, max_value=7 * 86400.0, value=7200.0,
                              step=600.0, format="%.0f", key="dryer_sched_t_end")
    dt = c[1].number_input("Report interval dt (s)", min_value=1.0, max_value=7 * 86400.0, value=60.0,
                           step=10.0, format="%.0f", key="dryer_sched_dt")
    digest = None if csv_bytes is None else hashlib.sha256(csv_bytes).hexdigest()
    key = (case, tuple(sorted(overrides.items())), preset, digest, float(t_end), float(dt))
    if st.button("Run the schedule", key="dryer_sched_run", type="primary"):
        def run():
            with progress_box("Running the schedule", fraction=logic_dryer_runs.schedule_fraction) as report:
                with heavy():
                    return logic_dryer_runs.run_schedule_view(case, dict(overrides), preset, t_end, dt, csv_bytes,
                                                              progress=report)

        res = _guarded_run("Schedule", shown, run)
        if res is None:
            return
        _keep("schedule", key, res)
    res = _kept("schedule", key)
    if res is None:
        return
    st.markdown(f"Product moisture: {show(res['start_moisture_kg_kg'], 'moisture')} wet at the start, maximum "
                f"**{show(res['max_moisture_kg_kg'], 'moisture')}** at {show(res['max_moisture_time_s'], 'time')}, "
                f"{show(res['final_moisture_kg_kg'], 'moisture')} at the end; above the start for "
                f"{show(res['time_above_start_s'], 'time')}.")
    st.altair_chart(_schedule_chart(res["rows"], "moisture", f"product moisture ({unit_of('moisture')} wet)"),
                    width="stretch", key="dryer_sched_chart_moisture")
    st.altair_chart(_schedule_chart(res["rows"], "temperature", f"temperature ({unit_of('temperature')})"),
                    width="stretch", key="dryer_sched_chart_temperature")
    st.download_button("Download the schedule run (CSV)", res["csv"], file_name=f"{_stem(case)}_schedule.csv",
                       mime="text/csv", key="dryer_sched_dl_csv")
