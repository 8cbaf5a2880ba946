"""Streamlit script of the rotarydryer web app (run with ``rotarydryer app``).

Page 1, "Flight geometry": drum presets, repose angle, speed, flight dimensions ->
summary table, design loads, cross-section and unloading profile.
Page 2, "Transport and RTD": a built-in case at a changed feed rate, speed and slope ->
holdups, RTD against data, loading state; download the results (netCDF) and the HTML
report; fit a reference RTD model (tanks in series, axial dispersion, Song's (2003) cells with
dead zones), optionally with a fitted constant background, to a shipped or uploaded tracer CSV.

Visitors' input (docs/app_threat_model.md): uploads are size-limited and kept in memory
only; an uploaded case may name shipped data sets only; every error is caught here and shown
as its message (input errors) or as a generic sentence (anything else; the traceback goes
to the server log), never with a traceback or a file's content.
"""

import streamlit as st

from rotarydryer.app import logic
from rotarydryer.app._ui import plain as _plain
from rotarydryer.app._ui import refuse as _refuse

# no exception types, messages or tracebacks in the browser, even for an error this script
# does not catch (also set on the command line of ``rotarydryer app``)
st.set_option("client.showErrorDetails", "none")
st.set_page_config(page_title="rotarydryer", page_icon=":material/autorenew:", layout="wide")

@st.cache_data(show_spinner=False, max_entries=64)
def _geometry(*args):
    return logic.geometry_view(*args)


@st.cache_data(show_spinner=False, max_entries=16)
def _transport(case, feed, rpm, slope):
    out = logic.transport_view(case, feed, rpm, slope)
    out["scalars"] = dict(out["results"].scalars)
    return out  # the report and the netCDF file are built only when downloaded


def _report_html(res):
    from rotarydryer.report.html import render_report

    return render_report(res)


def _netcdf_bytes(res):
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as d:
        return res.save(Path(d) / "results.nc").read_bytes()


@st.cache_data(show_spinner=False, max_entries=16)
def _fit(text, dataset, model, baseline="none"):
    return logic.fit_tracer(text=text, dataset=dataset, model=model, baseline=baseline)


#: page title -> module of :mod:`rotarydryer.app` with a ``render()`` (None: drawn below)
PAGES = {"Flight geometry": None, "Transport and RTD": None, "Whole dryer": "page_dryer",
         "Studies and sensitivity": "page_studies", "Design": "page_design", "Control": "page_control",
         "Lab data": "page_lab"}
page = st.sidebar.radio("Page", list(PAGES), key="page")
st.sidebar.caption("rotarydryer: flighted rotary dryer simulator. Units: SI, angles in deg.")

if PAGES[page] is not None:
    import importlib

    importlib.import_module(f"rotarydryer.app.{PAGES[page]}").render()

elif page == "Flight geometry":
    st.title("Flight geometry explorer")
    presets = logic.presets()
    name = st.sidebar.selectbox("Drum preset", list(presets), key="preset")
    e = presets[name]
    st.caption(e["description"])
    side = st.sidebar
    repose = side.number_input("Dynamic repose angle (deg)", 10.0, 80.0, 45.0, 0.5, key="repose_angle")
    rpm = side.number_input("Speed (rev/min)", 0.1, 30.0, float(e["rpm"]), 0.1, key=f"rpm__{name}")
    with side.expander("Drum and flight dimensions", expanded=True):
        radius = st.number_input("Drum radius R (m)", 0.05, 10.0, float(e["radius"]), 0.05, key=f"radius__{name}")
        n_flights = st.number_input("Number of flights", 2, 200, int(e["n_flights"]), 1, key=f"n_flights__{name}")
        s1 = st.number_input("Flight base s1 (m)", 0.001, 2.0, float(e["s1"]), 0.005, format="%.3f", key=f"s1__{name}")
        s2 = st.number_input("Flight tip s2 (m)", 0.0, 2.0, float(e["s2"]), 0.005, format="%.3f", key=f"s2__{name}")
        alpha1 = st.number_input("alpha1, base to shell (deg)", 1.0, 179.0, float(e["alpha1"]), 1.0, key=f"alpha1__{name}")
        alpha2 = st.number_input("alpha2, base to tip (deg)", 1.0, 179.0, float(e["alpha2"]), 1.0, key=f"alpha2__{name}")
        slope = st.number_input("Slope (deg)", 0.0, 20.0, float(e["slope"]), 0.1, key=f"slope__{name}")
        rho = st.number_input("Bulk density (kg/m3)", 1.0, 10000.0, float(e["bulk_density"]), 10.0, key=f"rho__{name}")
        length = st.number_input("Length (m)", 0.1, 100.0, float(e["length"]), 0.1, key=f"length__{name}")
    try:
        g = _geometry(radius, int(n_flights), s1, s2, alpha1, alpha2, repose, rpm, slope, rho, length)
    except Exception as exc:
        _refuse("Invalid input", exc)
    m = g["metrics"]
    c1, c2, c3, c4 = st.columns(4)
    c1.metric("Design load (Lee 2008)", f"{m['design_load_kg']:,.0f} kg")
    c2.metric("Mean fall height", f"{m['mean_fall_height_m']:.3f} m")
    c3.metric("Mean fall time", f"{m['mean_fall_time_s']:.3f} s")
    c4.metric("Passive time", f"{m['passive_time_s']:.2f} s")
    left, right = st.columns([1, 1])
    with left:
        st.image(g["cross_section"], caption="Cross-section to scale (flight at 90 deg)")
    with right:
        st.subheader("Summary")
        st.table({"quantity": [r[0] for r in g["summary"]], "value": [str(r[1]) for r in g["summary"]],
                  "unit": [r[2] for r in g["summary"]]})
        st.subheader("Design load")
        st.table({"method": [r[0] for r in g["design_loads"]], "area (m2)": [r[1] for r in g["design_loads"]],
                  "mass (kg)": [f"{r[2]:,.0f}" for r in g["design_loads"]]})
    st.image(g["profile"], caption="Holdup and discharge rate against flight angle")

elif page == "Transport and RTD":
    from rotarydryer.app._ui import case_picker

    st.title("Solids transport and residence time")
    case, shown = case_picker("", default="lee2008_invicta")
    try:
        d = logic.case_defaults(case)
    except Exception as exc:
        _refuse(f"Case {shown} refused", exc)
    feed = st.sidebar.number_input("Feed rate (kg/s)", 0.1, 500.0, d["feed_rate"], 0.5, key=f"feed__{case}")
    rpm = st.sidebar.number_input("Speed (rev/min)", 0.2, 20.0, d["rpm"], 0.1, key=f"trpm__{case}")
    slope = st.sidebar.number_input("Slope (deg)", 0.0, 10.0, d["slope"], 0.1, key=f"tslope__{case}")
    try:
        with st.spinner("Solving the steady state and the tracer pulse ..."):
            r = _transport(case, feed, rpm, slope)
    except Exception as exc:
        _refuse("Invalid input", exc)
    m = r["metrics"]
    c1, c2, c3, c4 = st.columns(4)
    c1.metric("Total holdup", f"{m['total_holdup_kg']:,.0f} kg")
    c2.metric("Mean residence time H/F", f"{m['mean_residence_time_min']:.2f} min")
    c3.metric("RTD standard deviation", f"{m['rtd_std_min']:.2f} min")
    c4.metric("Cells over / design / under", f"{m['cells_over']} / {m['cells_design']} / {m['cells_under']}")
    left, right = st.columns(2)
    left.image(r["holdup"], caption="Holdup profile")
    right.image(r["rtd"], caption="RTD against the measured tracer curve")
    st.image(r["loading"], caption="Loading state per cell")
    d1, d2 = st.columns(2)
    res = r["results"]
    stem = "uploaded_case" if shown != case else case
    d1.download_button("Download results (netCDF)", lambda: _netcdf_bytes(res), file_name=f"{stem}.nc",
                       mime="application/x-netcdf", key="dl_nc")
    d2.download_button("Download HTML report", lambda: _report_html(res), file_name=f"{stem}.html",
                       mime="text/html", key="dl_html")

    st.header("Fit a tracer curve")

    src_col, model_col = st.columns(2)
    sources = logic.tracer_sources()
    source = src_col.selectbox("Published tracer curve", sources, index=sources.index("ajayi2011_test4"),
                               key="tracer_source")
    model = model_col.selectbox("RTD model", list(logic.tracer_models()), key="rtd_model",
                                help="tanks in series, axial dispersion, or Song (2003) Eq. 2.10-2.16 cells: "
                                     "interactive mixers, with dead zones (cholette_cloutier); N scanned")
    fit_background = model_col.checkbox("Fit a constant background (baseline)", value=False, key="rtd_baseline",
                                        help="adds a constant signal b to the model curve, fitted with it "
                                             "(e.g. the lithium background of Ajayi's raw ppm)")
    up = st.file_uploader("... or upload your tracer CSV (columns time_s or time_min, signal; '#' metadata "
                          "lines, see docs/app.md); an uploaded file is fitted instead of the published curve",
                          type=["csv", "txt"], key="tracer_file", max_upload_size=logic.MAX_UPLOAD_MB)
    text = up.getvalue().decode("utf-8", errors="replace") if up is not None else None
    st.caption(_plain(f"Fitting: {'uploaded file ' + up.name if up is not None else 'published curve ' + source}"))
    try:
        f = _fit(text, None if text is not None else source, model, "fit" if fit_background else "none")
    except Exception as exc:
        _refuse("Cannot fit", exc)
    fc1, fc2 = st.columns([1, 1])
    fc1.metric("Fitted outlet mean", f"{f['moments']['mean_s'] / 60:.2f} min",
               help="outlet-curve mean of the fitted model, from the injection start")
    fc1.metric("R squared", f"{f['r_squared']:.4f}")
    if f.get("n_cells") is not None:
        fc1.metric("Number of cells N", f"{f['n_cells']}", help="integer, from a scan of N (Song (2003) l.743)")
    fc1.table({"parameter": [t[0] for t in f["table"]], "value": [f"{t[1]:.5g}" for t in f["table"]],
               "std. error": [f"{t[2]:.3g}" for t in f["table"]],
               "95% CI": [f"{t[3]:.5g} - {t[4]:.5g}" for t in f["table"]]})
    fc2.image(f["plot"], caption="Tracer data and fitted model")
