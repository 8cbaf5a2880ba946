"""Web-app page "Lab data" (``rotarydryer lab``): flight-unloading rig signal, drum photograph,
design-load series and Song's step tests, one tab each.

Each tab analyses a built-in example (made by the library; downloadable, to show the format) or
the visitor's upload: kept in memory only and size-limited (docs/app_threat_model.md).  Bad input
gives the CLI's messages (`rotarydryer.app.logic_lab`).
"""

import streamlit as st

from . import logic_lab as L
from ._ui import heavy, log, number, plain
from .logic import MAX_UPLOAD_MB, visitor_message


class _Refused(Exception):
    """Ends one tab after its error is shown (the other tabs still render)."""


def refuse(what, exc):
    """Show why ``what`` failed (as `rotarydryer.app._ui.refuse`) and end this tab only."""
    if not isinstance(exc, ValueError) or isinstance(exc, UnicodeError):
        log.error("%s", what, exc_info=exc)
    st.error(f"{plain(what)}: {plain(visitor_message(exc))}")
    raise _Refused


@st.cache_data(show_spinner=False, max_entries=16)
def _rig(text, name, kwargs):
    with heavy():
        return L.rig_view(text, name, **dict(kwargs))


@st.cache_data(show_spinner=False, max_entries=8)
def _image(content, name, kwargs):
    with heavy():
        return L.image_view(content, name, **dict(kwargs))


@st.cache_data(show_spinner=False, max_entries=16)
def _design_load(text, name, kwargs):
    return L.design_load_view(text, name, **dict(kwargs))


@st.cache_data(show_spinner=False, max_entries=16)
def _steps(text, name, kwargs):
    return L.steps_view(text, name, **dict(kwargs))


def _upload_text(col, label, key, example, example_name):
    """(text or None, shown name) from an optional CSV upload; the example is downloadable."""
    up = col.file_uploader(label, type=["csv", "txt"], key=key, max_upload_size=MAX_UPLOAD_MB)
    col.download_button("Download the example (format)", example, file_name=example_name, mime="text/csv",
                        key=f"{key}_example")
    if up is None:
        return None, "example"
    try:
        return L.decode_upload(up.getvalue(), up.name), up.name
    except Exception as exc:
        refuse(f"File {up.name} refused", exc)


def _rig_tab():
    from ..lab.flight_rig import FILTER_PHASES, RIG_FLIGHTS

    left, right = st.columns([1, 2.2])
    e = L.RIG_EXAMPLE
    text, name = _upload_text(left, "Load-cell CSV: time (s), then load-cell columns (kg), summed",
                              "lab_rig_file", L.rig_example(), "rig_example.csv")
    flights = list(RIG_FLIGHTS)
    flight = left.selectbox("Rig flight (Lee 2008 Table 5.1)", flights, index=flights.index(e["flight"]),
                            key="lab_rig_flight")
    c1, c2 = left.columns(2)
    rpm = number(c1, "Speed (rev/min)", 0.01, 100.0, e["rpm"], 0.5, key="lab_rig_rpm")
    start = number(c2, "Start angle (deg)", 0.0, 359.9, e["start_angle"], 0.5, key="lab_rig_start",
                            help="flight-root angle at the start of unloading, from the images (--start-angle)")
    rho = number(c1, "Bulk density (kg/m3)", 1.0, 20000.0, e["bulk_density"], 10.0, key="lab_rig_rho")
    length = number(c2, "Flight length (m)", 0.01, 100.0, 1.0, 0.1, key="lab_rig_length")
    sd = number(c1, "Repose-angle SD (deg)", 0.0, 45.0, 1.7, 0.1, key="lab_rig_sd",
                         help="band = fitted angle +/- 2 SD (Lee: 1.7 deg from the images); 0: the fit's "
                              "standard error")
    cutoff = number(c2, "FIR cut-off (Hz)", 0.01, 50.0, 1.5, 0.1, key="lab_rig_cutoff",
                             help="1.5 = Lee's code fir1(200, 0.03); 3 = his text")
    phase = left.selectbox("Filter phase", list(FILTER_PHASES), key="lab_rig_phase")
    fit_rho = left.checkbox("Also fit the bulk density", value=False, key="lab_rig_fit_rho")
    kw = dict(flight=flight, rpm=rpm, start_angle=start, bulk_density=rho, length=length, repose_sd=sd,
              cutoff=cutoff, phase=phase, fit_bulk_density=fit_rho)
    with right:
        try:
            r = _rig(text, name, tuple(sorted(kw.items())))
        except Exception as exc:
            refuse("Cannot analyse the rig run", exc)
        lo, hi = r["repose_angle_ci_deg"]
        c = st.columns(4)
        c[0].metric("Repose angle (deg)", f"{r['repose_angle_deg']:.2f}",
                    help=f"fitted; {100 * r['confidence']:g} % CI {lo:.2f} - {hi:.2f} deg")
        c[1].metric("Unloading start (s)", f"{r['unloading_start_s']:.3f}")
        c[2].metric("Mass in band (%)", f"{100 * r['fraction_inside_band_mass']:.1f}",
                    help="mass samples inside Lee's +/- 2 SD band")
        c[3].metric("Rate in band (%)", f"{100 * r['fraction_inside_band_rate']:.1f}",
                    help="discharge-rate samples inside the band")
        st.caption(plain(f"{name}: {r['samples']} samples at {r['sample_rate_hz']:g} Hz; "
                         f"{100 * r['confidence']:g} % CI of the repose angle {lo:.2f} - {hi:.2f} deg; band "
                         f"{r['band_repose_deg'][0]:.1f} - {r['band_repose_deg'][1]:.1f} deg; bulk density "
                         f"{r['bulk_density_kg_m3']:.0f} kg/m3; residual SD {r['residual_sd_kg']:.4f} kg"))
        st.image(r["plot"], caption="Filtered accumulated mass and discharge rate with the model band")


def _image_tab():
    from ..geometry.presets import drum_presets

    left, right = st.columns([1, 2.2])
    up = left.file_uploader(f"Photograph of the drum cross-section (PNG, JPEG, TIFF; at most "
                            f"{L.MAX_LAB_IMAGE_PIXELS / 1e6:g} megapixels)", type=["png", "jpg", "jpeg", "tif", "tiff"],
                            key="lab_image_file", max_upload_size=MAX_UPLOAD_MB)
    example, e = L.image_example()
    content, name = (None, "example photograph") if up is None else (up.getvalue(), up.name)
    if up is None:
        left.caption(plain(f"Example: synthetic photograph of Ajayi's pilot drum at a repose angle of "
                           f"{L.IMAGE_EXAMPLE['repose_angle']:g} deg (true FUF {e['true_fuf_cm2']:.2f} cm2, "
                           f"TP {e['true_tp_cm2']:.1f} cm2)"))
    drums = list(drum_presets())
    drum = left.selectbox("Drum", drums, index=drums.index(e["drum"]), key="lab_image_drum")
    c1, c2 = left.columns(2)
    col = number(c1, "Centre column (px)", 0.0, 1e5, e["centre"][0], 1.0, key="lab_image_col")
    row = number(c2, "Centre row (px)", 0.0, 1e5, e["centre"][1], 1.0, key="lab_image_row")
    px_per_m = number(c1, "Scale (px/m)", 1.0, 1e7, e["px_per_m"], 10.0, key="lab_image_scale")
    ref = number(c2, "Flight 0 root angle (deg)", -360.0, 360.0, e["reference_angle"], 0.5,
                          key="lab_image_ref", help="from the drum bottom in the direction of rotation")
    channel = number(c1, "Colour channel", 0, 3, 0, 1, key="lab_image_channel", help="0 = red (Ajayi)")
    mirror = c2.checkbox("Turns clockwise", value=e["mirror"], key="lab_image_mirror",
                         help="the drum turns clockwise in the picture (Ajayi's did)")
    thr = c1.text_input("Flight-borne threshold", "168,177", key="lab_image_thr", help="'upper,lower', one grey "
                        "level, or 'otsu' (Ajayi: 168,177)")
    athr = c2.text_input("Airborne threshold", "104,120", key="lab_image_athr", help="Ajayi: 104,120, or 'otsu'")
    kw = dict(drum=drum, centre=(col, row), px_per_m=px_per_m, mirror=mirror, reference_angle=ref,
              channel=int(channel), threshold=thr, airborne_threshold=athr)
    with right:
        try:
            with st.spinner("Segmenting the photograph ..."):
                r = _image(content, name, tuple(sorted(kw.items())))
        except Exception as exc:
            refuse("Cannot measure the photograph", exc)
        c = st.columns(4)
        c[0].metric("FUF (cm2)", f"{r['FUF_cm2']:.2f}", help=f"first unloading flight, #{r['fuf_index']}")
        c[1].metric("TP (cm2)", f"{r['TP_cm2']:.1f}", help=f"total passive: UHD {r['UHD_cm2']:.1f} + LHD "
                                                          f"{r['LHD_cm2']:.1f} cm2")
        c[2].metric("Airborne (cm2)", f"{r['airborne_cm2']:.1f}")
        c[3].metric("Airborne (%)", f"{r['airborne_percent']:.2f}", help="of the airborne region")
        a, b = st.columns([1.3, 1])
        a.image(r["annotated"], caption="Segmentation: flight-borne (FUF red), airborne cyan, areas in cm2")
        b.dataframe({"flight": list(range(len(r["flight_areas_cm2"]))),
                     "root angle (deg)": [round(x, 1) for x in r["root_angles_deg"]],
                     "area (cm2)": [round(x, 2) for x in r["flight_areas_cm2"]]}, hide_index=True, height=420)


def _design_load_tab():
    left, right = st.columns([1, 2.2])
    text, name = _upload_text(left, "Design-load table CSV: one row per photograph (loading, FUF area, "
                                    "optional condition)", "lab_dl_file", L.design_load_example(),
                              "design_load_example.csv")
    loading = left.text_input("Loading column", "loading_kg", key="lab_dl_loading")
    area = left.text_input("FUF area column", "FUF_area_cm2", key="lab_dl_area")
    group = left.text_input("Group column (empty: one fit)", "condition", key="lab_dl_group")
    conf = number(left, "Confidence level", 0.5, 0.999, 0.95, 0.01, key="lab_dl_conf")
    kw = dict(loading_column=loading, area_column=area, group_column=group or None, confidence=conf)
    with right:
        try:
            r = _design_load(text, name, tuple(sorted(kw.items())))
        except Exception as exc:
            refuse("Cannot fit the design load", exc)
        fits = r["fits"]
        f0 = fits[0]
        c = st.columns(3)
        c[0].metric("Design load, 1st group", f"{f0['design_load']:.2f}",
                    help=f"{plain(f0['group'])}: break point of the linear-plateau fit (loading unit)")
        c[1].metric("Plateau, 1st group", f"{f0['plateau']:.2f}", help="FUF area unit")
        c[2].metric("Groups fitted", f"{len(fits)}")
        pct = f"{100 * r['confidence']:g} %"
        st.dataframe({"group": [f["group"] for f in fits],
                      "design load": [round(f["design_load"], 2) for f in fits],
                      f"profile {pct} CI": [f"{f['profile_ci'][0]:.2f} - {f['profile_ci'][1]:.2f}" for f in fits],
                      f"delta {pct} CI": [f"{f['delta_ci'][0]:.2f} - {f['delta_ci'][1]:.2f}" for f in fits],
                      "plateau": [round(f["plateau"], 3) for f in fits], "slope": [round(f["slope"], 4) for f in fits],
                      "n": [f["n"] for f in fits],
                      **({"Ajayi Table 4.11": [f["published"] for f in fits]} if "published" in f0 else {})},
                     hide_index=True)
        st.image(r["plot"], caption="FUF area against loading and the linear-plateau fits (Ajayi 2011 App. D)")


def _steps_tab():
    left, right = st.columns([1, 2.2])
    text, name = _upload_text(left, "Step record CSV: time_s|time_min|time_h, feed_kg_s|feed_kg_min|... , "
                                    "discharge_kg_s|...|discharged_kg", "lab_steps_file", L.steps_example(),
                              "steps_example.csv")
    steps = left.text_input("Step times (empty: detected from the feed)", "", key="lab_steps_times",
                            help="comma-separated, in the unit of the time column (steps of speed or gas)")
    c1, c2 = left.columns(2)
    threshold = number(c1, "Detection threshold", 0.001, 0.999, 0.1, 0.05, key="lab_steps_threshold",
                                help="smallest feed change, fraction of the largest feed")
    plateau = number(c2, "Plateau fraction", 0.01, 1.0, 0.2, 0.05, key="lab_steps_plateau")
    tolerance = number(c1, "Steady tolerance", 0.001, 0.999, 0.05, 0.01, key="lab_steps_tolerance")
    h0 = number(c2, "Initial holdup (kg)", 0.0, 1e7, 0.0, 1.0, key="lab_steps_h0")
    kw = dict(step_times=steps or None, threshold=threshold, plateau=plateau, tolerance=tolerance,
              initial_holdup=h0)
    with right:
        try:
            r = _steps(text, name, tuple(sorted(kw.items())))
        except Exception as exc:
            refuse("Cannot analyse the step record", exc)

        def kg(x):
            return "-" if x is None else f"{x:.2f}"
        c = st.columns(4)
        c[0].metric("Holdup H1 (kg)", kg(r["h_up_kg"]), help="after the up-step")
        c[1].metric("Holdup H2 (kg)", kg(r["h_down_kg"]), help="from the down-step")
        c[2].metric("H1 - H2 (%)", "-" if r["up_down_pct"] is None else f"{r['up_down_pct']:+.2f}",
                    help="of their mean (Song: < 3 %)")
        cl = r["closure"]
        c[3].metric("Closure (%)", f"{cl['residual_pct']:.2f}" if cl["applies"] else "n/a",
                    help=cl.get("why") or "residual of the areas; Song Table 4.2: 0.8-4.9 %")
        seg = r["segments"]
        st.dataframe({"from (min)": [round(s["start_s"] / 60, 2) for s in seg],
                      "to (min)": [round(s["end_s"] / 60, 2) for s in seg],
                      "feed (kg/min)": [round(s["feed_end_kg_s"] * 60, 3) for s in seg],
                      "plateau (kg/min)": [round(s["plateau_kg_s"] * 60, 3) for s in seg],
                      "area dH (kg)": [round(s["area_kg"], 3) for s in seg],
                      "H (kg)": [round(s["holdup_kg"], 2) for s in seg],
                      "tau (min)": [None if s["tau_s"] is None else round(s["tau_s"] / 60, 2) for s in seg],
                      "steady": ["yes" if s["steady"] else "NO" for s in seg]}, hide_index=True)
        st.image(r["plot"], caption="Feed and discharge with the area of each interval")


def render():
    st.title("Laboratory data")
    st.caption("Lee (2008) flight-unloading rig, Ajayi (2011) photographs and design-load series, Song (2003) step "
               "tests; as `rotarydryer lab` (docs/lab.md). Each tab shows a built-in example until you upload a "
               "file (kept in memory only, at most 1 MB).")
    tabs = st.tabs(["Rig signal", "Photograph", "Design-load series", "Step tests"])
    for tab, body in zip(tabs, (_rig_tab, _image_tab, _design_load_tab, _steps_tab)):
        with tab:
            try:
                body()
            except _Refused:
                pass
