"""Web-app page "Whole dryer": the coupled heat-and-mass steady state of a shipped or uploaded
case at changed operating variables -> product moisture and temperature, gas outlet, specific
energy, thermal efficiency, fuel rate (cases with a burner), residence time; temperature and
moisture profiles (with the measured plant values where the case has them), the energy
balance waterfall; downloads (profiles CSV, results netCDF, HTML report).

Logic: :mod:`rotarydryer.app.logic_dryer` (no Streamlit). Errors: the CLI's messages
(:func:`rotarydryer.app._ui.refuse`).
"""

import streamlit as st

from . import logic_dryer
from ._ui import case_picker, deferred, heavy, number, plain, refuse


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
        test = st.sidebar.selectbox("Plant test (Ajayi 2011, MMG Karumba)", tests,
                                    index=tests.index(default) if default in tests else 0, key=f"dryer_test__{case}",
                                    help="sets the feed rate, speed, feed moisture and gas inlet temperature of "
                                         "the test; the measured values are drawn on the profiles")
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
        st.sidebar.caption("Feed moisture: the test's (Ajayi Tables 3.5-3.11); change the test to change it.")
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
    m = r["metrics"]
    c = st.columns(4)
    c[0].metric("Product moisture", f"{m['product_moisture_kg_kg']:.4f} kg/kg", help="wet basis")
    c[1].metric("Product temperature", f"{m['product_temperature_degC']:.1f} °C")
    c[2].metric("Gas outlet temperature", f"{m['gas_outlet_temperature_degC']:.1f} °C")
    c[3].metric("Mean residence time", f"{m['mean_residence_time_min']:.2f} min", help="holdup / product flow")
    c = st.columns(4)
    c[0].metric("Specific energy", _fmt(m["specific_energy_kJ_kg_water"], "{:,.0f} kJ/kg"),
                help="heat put into the gas per kg of water evaporated")
    c[1].metric("Thermal efficiency", _fmt(m["thermal_efficiency"], "{:.1%}"),
                help="evaporation x latent heat / heat put into the gas")
    c[2].metric("Evaporation", f"{m['evaporation_kg_s']:.4g} kg/s")
    if r["has_burner"]:
        c[3].metric("Fuel rate", _fmt(m["fuel_rate_kg_h"], "{:,.0f} kg/h"),
                    help=r["fuel_rate_error"] or "fuel the case's burner needs to heat the gas to its inlet temperature")
    else:
        c[3].metric("Heat input", f"{m['heat_input_kW']:,.1f} kW", help="no burner in this case: heat put into the gas")
    tabs = st.tabs(["Temperature and moisture profiles", "Energy balance"]
                   + ([f"Model and plant data (test {r['measured']['test']})"] if r["measured"] else []))
    with tabs[0]:
        st.image(r["profiles"], caption="Gas and solids temperature, solids moisture and gas humidity along the dryer"
                 + (f" (squares: measured, test {r['measured']['test']})" if r["measured"] else ""))
    with tabs[1]:
        st.image(r["waterfall"], caption="Energy balance: streams in (red) and out (blue); enthalpies relative to "
                                         "the model's reference state; the last bar is the closure (in - out)")
        st.table({"stream": [t[0] for t in r["energy_table"]], "direction": [t[1] for t in r["energy_table"]],
                  "kW": [f"{t[2]:,.1f}" for t in r["energy_table"]]})
    if r["measured"]:
        with tabs[2]:
            mm, s = r["measured"], r["summary"]
            st.table({"quantity": ["product moisture (kg/kg wet)", "product temperature (°C)",
                                   "gas outlet temperature (°C)"],
                      "model": [f"{s['product_moisture_kg_kg']:.4f}", f"{s['product_temperature_degC']:.1f}",
                                f"{s['gas_outlet_temperature_degC']:.1f}"],
                      f"measured (test {mm['test']})": [f"{mm.get('moisture_out', float('nan')):.4f}",
                                                        f"{mm.get('product_c', float('nan')):.1f}",
                                                        f"{mm.get('gas_out_c', float('nan')):.1f}"]})
            st.caption("Measured: Ajayi (2011) Tables 3.5-3.11 (PI means of the test); the model runs at the "
                       "operating variables in the sidebar.")
    stem = "uploaded_case" if case.startswith("uploaded_case_") else case
    ov = dict(overrides)
    d1, d2, d3 = st.columns(3)
    d1.download_button("Download profiles (CSV)", r["profiles_csv"], file_name=f"{stem}_profiles.csv",
                       mime="text/csv", key="dryer_dl_csv")
    d2.download_button("Download results (netCDF)", deferred(logic_dryer.netcdf_bytes, case, ov),
                       file_name=f"{stem}.nc", mime="application/x-netcdf", key="dryer_dl_nc")
    d3.download_button("Download HTML report", deferred(logic_dryer.report_html, case, ov), file_name=f"{stem}.html",
                       mime="text/html", key="dryer_dl_html")
