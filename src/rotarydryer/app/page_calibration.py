"""Web-app page "Calibration": case keys fitted to the measured responses of a case's tests at once
(``rotarydryer calibrate``).

Sidebar: a case (built-in or uploaded), the tests, the keys to fit and the responses; the run starts
with the button and shows its progress (starts done, model runs so far). Shown: the fitted values
with their units and 95 % intervals, model against measured, and the calibration record and the
calibrated case file to download. Bad input gives the CLI's messages
(`rotarydryer.app.logic_calibration`).
"""

import streamlit as st

from . import logic_calibration as L
from ._runs import Kept
from ._ui import case_picker, heavy, plain, progress_box, refuse

#: finished runs of every session (not ``st.cache_data``: the progress bar drawn during a run)
_KEPT = Kept(8)


def _calibrate(args):
    key = args
    r = _KEPT.get(key)
    if r is not None:
        return r
    case, params, tests, responses, starts = args
    with progress_box("Calibrating: model runs of every test at each step of the fit",
                      lambda m: L.progress_fraction(m, starts)) as report:
        with heavy():
            r = L.calibration_view(case, list(params), list(tests), list(responses), starts, progress=report)
    _KEPT.put(key, r)
    return r


@st.cache_data(show_spinner=False, max_entries=16)
def _defaults(case):
    return L.calibration_defaults(case)


def _inputs():
    side = st.sidebar
    case, shown = case_picker("calibration", "ajayi2011_mmg")
    try:
        d = _defaults(case)
    except Exception as exc:
        refuse(f"Case {shown} refused", exc)
    tests = []
    if d["tests"]:
        tests = side.multiselect("Tests ([[tests]] rows) fitted at once", d["tests"], default=d["tests"],
                                 key=f"calibration_tests__{case}", help="rotarydryer calibrate --tests")
    offered = d["parameters"] or ["thermal.area_scale"]
    params = side.multiselect(f"Case keys to fit (at most {L.MAX_PARAMETERS})", offered, default=offered[:1],
                              key=f"calibration_params__{case}",
                              help="the keys of the case's calibration records; tests.*.FIELD fits one value per "
                                   "test (rotarydryer calibrate -p)")
    extra = side.text_input("Other case keys (comma separated)", "", key=f"calibration_extra__{case}",
                            help="any numeric case key, e.g. thermal.area_scale, gas.flow")
    params += [k.strip() for k in extra.split(",") if k.strip() and k.strip() not in params]
    responses = side.multiselect("Responses (empty: those the data have)", list(L.RESPONSE_LABELS),
                                 format_func=lambda r: L.RESPONSE_LABELS[r], key=f"calibration_responses__{case}")
    starts = int(side.number_input(f"Starts (1-{L.MAX_STARTS})", 1, L.MAX_STARTS, 1, 1, key="calibration_starts",
                                   help="the case's values, then sampled ones (rotarydryer calibrate --starts)"))
    return case, shown, (case, tuple(params), tuple(tests), tuple(responses), starts)


def render():
    st.title("Calibration: fit case keys to the plant data")
    st.caption("Weighted least squares on several measured responses of many tests at once, with 95 % intervals "
               "and the calibration record (values, data, model configuration) to append to the case file; as "
               "`rotarydryer calibrate` (docs/calibration.md).")
    case, shown, args = _inputs()
    if st.button("Run the calibration", type="primary", key="calibration_run"):
        st.session_state["calibration_args"] = (shown, args)
    if "calibration_args" not in st.session_state:
        st.info("Choose the case, the tests, the keys to fit and the responses in the sidebar, then press "
                "**Run the calibration**.")
        return
    shown_run, run_args = st.session_state["calibration_args"]
    if run_args != args:
        st.caption("The inputs changed: press **Run the calibration** to run again. Shown: the last run.")
    try:
        r = _calibrate(run_args)
    except Exception as exc:
        refuse("Cannot calibrate", exc)
    st.caption(plain(f"{shown_run}: objective {r['objective']:.5g}, {r['n_solves']} model runs in "
                     f"{r['seconds']:.1f} s"))
    st.table({"case key": [p["key"] for p in r["parameters"]], "unit": [p["unit"] for p in r["parameters"]],
              "estimate": [f"{p['value']:.5g}" for p in r["parameters"]],
              "95 % interval": [f"{p['ci_low']:.5g} to {p['ci_high']:.5g}" for p in r["parameters"]]})
    rows = r["comparison"]
    st.table({"data set": [c["name"] for c in rows],
              "measured": ["curve" if c["response"] == "tracer" else f"{c['measured']:.5g}" for c in rows],
              "model": [f"R2 {c['r_squared']:.3f}" if c["response"] == "tracer" else f"{c['model']:.5g}"
                        for c in rows],
              "unit": [c["unit"] for c in rows]})
    for w in r["warnings"]:
        st.warning(plain(w))
    st.image(r["plot"], caption="Model against measured after the calibration (numbers: tests)")
    c = st.columns(3)
    c[0].download_button("Calibration record (TOML)", r["record_toml"], file_name="calibration.toml",
                         mime="application/toml", key="calibration_dl_record")
    c[1].download_button("Calibrated case file (TOML)", r["calibrated_case"], file_name="calibrated_case.toml",
                         mime="application/toml", key="calibration_dl_case")
    c[2].download_button("Everything (JSON)", r["json"], file_name="calibration.json", mime="application/json",
                         key="calibration_dl_json")
