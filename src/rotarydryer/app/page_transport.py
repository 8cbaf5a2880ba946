"""Web-app page "Transport and RTD": a built-in or uploaded case at a changed feed rate, speed
and slope -> holdups, RTD against data, loading state; download the results (netCDF) and the
HTML report; fit a reference RTD model (tanks in series, axial dispersion, Song's (2003) cells
with dead zones), optionally with a fitted constant background, to a shipped or uploaded tracer CSV.

Widget bounds: the case schema's range of each key (the speed also below the critical speed of
the case's drum), always containing the case's value (`rotarydryer.app.logic.input_range`).
The model runs are heavy runs (`rotarydryer.app._runs`).
"""

import math

import streamlit as st

from .._display import show
from . import logic
from ._ui import PERSIST, case_number, case_picker, deferred, heavy, metric_row, plain, refuse


@st.cache_data(show_spinner=False, max_entries=16)
def _transport(case, feed, rpm, slope):
    with heavy():
        out = logic.transport_view(case, feed, rpm, slope)
    out["scalars"] = dict(out["results"].scalars)
    return out  # the report and the netCDF file are built only when downloaded


#: the row of metrics: (label, output name of the view's "metrics" or a template of them)
_METRICS = [("Total holdup", "total_holdup_kg"),
            ("Mean residence time H/F", "mean_residence_time_s"),
            ("RTD standard deviation", "rtd_std_s"),
            ("Cells over / design / under", "{cells_over} / {cells_design} / {cells_under}")]


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
    with heavy():
        return logic.fit_tracer(text=text, dataset=dataset, model=model, baseline=baseline)


def _step(value):
    """A widget step of about a tenth of ``value`` rounded to 1, 2 or 5 x 10^k (0.01 kg/s for a
    pilot drum's 0.08 kg/s, 5 kg/s for a plant's 40 kg/s)."""
    v = abs(float(value)) / 10 or 0.1
    k = 10 ** math.floor(math.log10(v))
    return float(next(m * k for m in (1, 2, 5, 10) if m * k >= v * 0.999))


def render():
    side = st.sidebar
    st.title("Solids transport and residence time")
    st.caption("The solids transport alone, at the case's assumed moisture profile (as `rotarydryer rtd`): the Whole "
               "dryer page gives the coupled heat-and-mass state's holdup and residence times, which follow the "
               "computed moisture.")
    case, shown = case_picker("", default="lee2008_invicta")
    try:
        d = logic.case_defaults(case)
    except Exception as exc:
        refuse(f"Case {shown} refused", exc)
    feed = case_number(side, "Feed rate (kg/s)", case, "operating.feed_rate", d["feed_rate"], _step(d["feed_rate"]),
                       format="%.4g", key=f"feed__{case}", help="case key operating.feed_rate")
    rpm = case_number(side, "Speed (rev/min)", case, "operating.rpm", d["rpm"], 0.1, key=f"trpm__{case}",
                      help="case key operating.rpm; below the critical speed of the case's drum")
    slope = case_number(side, "Slope (deg)", case, "drum.slope", d["slope"], 0.1, key=f"tslope__{case}",
                        help="case key drum.slope")
    try:
        with st.spinner("Solving the steady state and the tracer pulse ..."):
            r = _transport(case, feed, rpm, slope)
    except Exception as exc:
        refuse("Invalid input", exc)
    metric_row(_METRICS, r["metrics"])
    left, right = st.columns(2)
    left.image(r["holdup"], caption="Holdup profile")
    right.image(r["rtd"], caption="RTD against the measured tracer curve")
    st.image(r["loading"], caption="Loading state per cell")
    d1, d2 = st.columns(2)
    res = r["results"]
    stem = "uploaded_case" if shown != case else case
    d1.download_button("Download results (netCDF)", deferred(_netcdf_bytes, res), file_name=f"{stem}.nc",
                       mime="application/x-netcdf", key="dl_nc")
    d2.download_button("Download HTML report", deferred(_report_html, res), file_name=f"{stem}.html",
                       mime="text/html", key="dl_html")

    st.header("Fit a tracer curve")

    src_col, model_col = st.columns(2)
    sources = logic.tracer_sources()
    try:
        own = logic.case_tracer_dataset(case)
    except Exception:  # noqa: BLE001 - the case loaded above; any trouble here: the first curve
        own = sources[0]
    # keyed by the case: the default follows the case chosen in the sidebar (its own data set)
    source = src_col.selectbox("Published tracer curve", sources, index=sources.index(own),
                               key=f"tracer_source__{case}", persist_state=PERSIST,
                               help="default: the tracer data set of the case (tracer.dataset), else the first")
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
    st.caption(plain(f"Fitting: {'uploaded file ' + up.name if up is not None else 'published curve ' + source}"))
    try:
        f = _fit(text, None if text is not None else source, model, "fit" if fit_background else "none")
    except Exception as exc:
        refuse("Cannot fit", exc)
    fc1, fc2 = st.columns([1, 1])
    fc1.metric("Fitted outlet mean", show(f['moments']['mean_s'], "time"),
               help="outlet-curve mean of the fitted model, from the injection start")
    fc1.metric("R squared", f"{f['r_squared']:.4f}")
    if f.get("n_cells") is not None:
        fc1.metric("Number of cells N", f"{f['n_cells']}", help="integer, from a scan of N (Song (2003) l.743)")
    fc1.table({"parameter": [t[0] for t in f["table"]], "value": [f"{t[1]:.5g}" for t in f["table"]],
               "std. error": [f"{t[2]:.3g}" for t in f["table"]],
               "95% CI": [f"{t[3]:.5g} - {t[4]:.5g}" for t in f["table"]]})
    fc2.image(f["plot"], caption="Tracer data and fitted model")
    for w in f.get("warnings", []):      # the fit's identifiability notes, as rtd-fit prints them
        st.warning(plain(w))
