"""Web-app page "Control": PI + feed-forward on a case's dynamic model (``rotarydryer control``).

Sidebar: a case with the heat-and-mass model (built-in or uploaded), the disturbance and the
controller settings; the runs (identification, closed loop, open loop) start with the button.
Shown: controlled and manipulated variables closed vs open loop, IAE, maximum deviation,
settling time, the SIMC tuning.  Bad input gives the CLI's messages
(`rotarydryer.app.logic_control`).
"""

import streamlit as st

from .._display import show, show_delta, unit_of
from ..services.control import describe_feedforward
from . import logic_control as L
from ._runs import Kept
from ._ui import case_picker, heavy, number, plain, progress_box, refuse

#: finished runs of every session (not ``st.cache_data``: the progress bar drawn during a run)
_KEPT = Kept(8)


def _control(case, overrides, kwargs):
    """The run of these inputs: kept, or computed with a progress bar (about 1 s per 4 simulated
    minutes, plus 10-15 s for the steady state and the identification)."""
    key = (case, overrides, kwargs)
    r = _KEPT.get(key)
    if r is not None:
        return r
    open_loop = bool(dict(kwargs).get("open_loop", True))
    with progress_box("Steady state, step-response identification, closed " + ("and open loop" if open_loop else "loop"),
                      lambda m: L.progress_fraction(m, open_loop)) as report:
        with heavy():
            r = L.control_view(case, dict(overrides) or None, progress=report, **dict(kwargs))
    _KEPT.put(key, r)
    return r


@st.cache_data(show_spinner=False, max_entries=16)
def _defaults(case):
    return L.control_defaults(case)


def _opt(side, label, default, key, lo, hi, step, help_text):
    """A number input that may be left to the default (None): a checkbox turns it on."""
    on = side.checkbox(label, value=False, key=f"{key}_on", help=help_text)
    return number(side, f"{label} value", lo, hi, default, step, key=key) if on else None


def _inputs():
    side = st.sidebar
    try:
        cases = L.thermal_cases()
    except Exception as exc:
        refuse("Cases unavailable", exc)
    case, shown = case_picker("control", "ajayi2011_mmg", cases=cases,
                              help_text="cases with the heat-and-mass model ([gas] block)")
    try:
        d = _defaults(case)
    except Exception as exc:
        refuse(f"Case {shown} refused", exc)
    overrides = {}
    if d["tests"]:
        test = side.selectbox("Ajayi test (operating.test)", d["tests"], index=d["tests"].index(d["test"])
                              if d["test"] in d["tests"] else 0, key=f"control_test__{case}")
        overrides["operating.test"] = int(test)
    with side.expander("Disturbance", expanded=True):
        scenarios = list(L.SCENARIO_LABELS)
        scenario = st.selectbox("Scenario", scenarios, key="control_scenario",
                                help="; ".join(f"{k}: {v}" for k, v in L.SCENARIO_LABELS.items()))
        magnitude = number(st, "Magnitude", -0.9, 2.0, 0.2, 0.05, key="control_magnitude",
                                    help=L.SCENARIO_LABELS[scenario])
        duration = number(st, "Simulated time (s)", 60.0, 14400.0, 7200.0, 600.0, key="control_duration",
                                   help="the run takes about 1 s of computing per simulated 4 min")
        step_time = number(st, "Disturbance at (s)", 0.0, 14400.0, 600.0, 60.0, key="control_step_time")
    with side.expander("Controller", expanded=True):
        measured = st.selectbox("Controlled variable", ["product_moisture", "exhaust_temperature"],
                                key="control_measured")
        feedforward = st.selectbox("Feed-forward", ["model", "linear", "off"], key="control_feedforward",
                                   help="model: steady state that holds the setpoint; linear: FOPDT gains")
        feedback = st.checkbox("PI feedback", value=True, key="control_feedback")
        feed_backup = st.checkbox("Reduce the feed when the gas temperature saturates", value=True,
                                  key="control_feed_backup")
        c1, c2 = st.columns(2)
        sample_time = number(c1, "Sample time (s)", 10.0, 3600.0, 60.0, 10.0, key="control_sample_time")
        dead_time = number(c2, "Dead time (s)", 0.0, 7200.0, 120.0, 10.0, key="control_dead_time")
        gas_t_max = number(st, "Highest gas inlet temperature (degC)", 1.0, 600.0, 600.0, 10.0,
                                    key="control_gas_t_max")
        feed_min = number(st, "Lowest feed (fraction of the case's)", 0.01, 1.0, 0.5, 0.05,
                                   key="control_feed_min")
    with side.expander("Tuning (default: SIMC, Skogestad 2003)"):
        kc = _opt(st, "Controller gain Kc", 0.25, "control_kc", -1e6, 1e6, 0.05,
                  "normalised split range, y per y; default SIMC")
        tau_i = _opt(st, "Integral time tau_I (s)", 300.0, "control_tau_i", 0.001, 1e6, 30.0, "default SIMC")
        tau_c = _opt(st, "SIMC closed-loop time constant tau_c (s)", 120.0, "control_tau_c", 0.001, 1e6, 30.0,
                     "default: the dead time")
    with side.expander("Tolerance and product specification"):
        moisture_loop = measured == "product_moisture"
        tolerance = _opt(st, "Tolerance band (kg/kg wet)" if moisture_loop else "Tolerance band (K)",
                         0.005 if moisture_loop else 2.0, f"control_tolerance_{measured}", 1e-6,
                         1.0 if moisture_loop else 100.0, 0.001 if moisture_loop else 0.5,
                         "settling time and time within it; default 0.005 kg/kg or 2 K")
        moisture_max = _opt(st, "Largest product moisture (kg/kg wet)", 0.12, "control_moisture_max", 0.0, 1.0, 0.005,
                            "the fraction of time the product meets it is reported")
        t_low = _opt(st, "Product temperature, low end (degC)", 45.0, "control_t_low", -50.0, 600.0, 1.0,
                     "with the high end: the fraction of time within the band is reported")
        t_high = _opt(st, "Product temperature, high end (degC)", 50.0, "control_t_high", -50.0, 600.0, 1.0,
                      "with the low end")
    open_loop = side.checkbox("Also run the uncontrolled plant", value=True, key="control_open_loop")
    kwargs = dict(scenario=scenario, magnitude=magnitude, duration=duration, step_time=step_time,
                  sample_time=sample_time, dead_time=dead_time, measured=measured, kc=kc, tau_i=tau_i, tau_c=tau_c,
                  feedforward=feedforward, feedback=feedback, feed_backup=feed_backup, gas_t_max=gas_t_max,
                  feed_min_fraction=feed_min, open_loop=open_loop, tolerance=tolerance,
                  product_moisture_max=moisture_max,
                  product_temperature_band=(t_low, t_high) if t_low is not None and t_high is not None else None)
    return case, shown, tuple(sorted(overrides.items())), tuple(sorted(kwargs.items()))


def render():
    st.title("Control: closed loop on the dynamic model")
    st.caption("PI feedback (velocity form, anti-windup, SIMC tuning from identified step responses) and "
               "feed-forward from the measured feed, manipulating the gas inlet temperature and, in split range, "
               "the feed rate; as `rotarydryer control` (docs/design_control.md).")
    case, shown, overrides, kwargs = _inputs()
    if st.button("Run closed and open loop", type="primary", key="control_run"):
        st.session_state["control_args"] = (case, shown, overrides, kwargs)
    if "control_args" not in st.session_state:
        st.info("Choose the case, the disturbance and the controller in the sidebar, then press "
                "**Run closed and open loop** (a 2 h run takes about half a minute).")
        return
    args = st.session_state["control_args"]
    if args != (case, shown, overrides, kwargs):
        st.caption("The inputs changed: press **Run closed and open loop** to run again. Shown: the last run.")
    try:
        r = _control(args[0], args[2], args[3])
    except Exception as exc:
        refuse("Cannot run", exc)
    p, o, t = r["performance"], r["open"], r["tuning"]
    quantity = "moisture" if r["measured"] == "product_moisture" else "temperature"
    unit = show_delta(0.0, quantity).split(" ", 1)[1]      # pp, kg/kg, K or degF (rotarydryer._display)
    t_unit = unit_of("time")

    def settle(x):
        return "never" if x["settling_time_s"] is None else show(x["settling_time_s"], "time", with_unit=False)
    st.caption(plain(f"{args[1]}: setpoint {show(r['setpoint'], quantity)}, disturbance at {r['step_time_s']:g} s; "
                     f"tolerance +-{show_delta(p['tolerance'], quantity)}"))
    c = st.columns(5)
    c[0].metric(f"Peak error, closed ({unit})", show_delta(p["max_abs_deviation"], quantity, with_unit=False),
                help="largest |measured - setpoint| after the disturbance")
    c[1].metric(f"Peak error, open ({unit})", "-" if o is None else show_delta(o["max_abs_deviation"], quantity,
                                                                               with_unit=False))
    c[2].metric(f"Settling, closed ({t_unit})", settle(p),
                help="time after the disturbance until the deviation stays within the tolerance")
    c[3].metric(f"Settling, open ({t_unit})", "-" if o is None else settle(o))
    c[4].metric("Controller gain Kc", f"{t['kc']:.3g}", help=f"{t['rule']}; tau_I = {t['tau_i_s']:.0f} s, "
                                                            f"gain margin {t['gain_margin']:.2f}")
    # the integral of |e| over time, as the CLI gives it: the deviations' display unit times s
    iae = f"IAE closed loop {show_delta(p['iae'], quantity, 4)} s" + (
        "" if o is None else f", open loop {show_delta(o['iae'], quantity, 4)} s") + ". "
    st.markdown(plain(iae + f"Tuning ({t['rule']}): Kc = {t['kc']:.3g}, tau_I = {t['tau_i_s']:.0f} s, gain margin "
                      f"{t['gain_margin']:.2f}, {describe_feedforward(t)}. Manipulated: gas inlet "
                      f"{show(r['ranges']['gas_inlet_temperature_degC'][0], 'temperature', with_unit=False)}-"
                      f"{show(r['ranges']['gas_inlet_temperature_degC'][1], 'temperature')}, feed "
                      f"{show(r['ranges']['feed_rate_kg_s'][0], 'mass_flow', with_unit=False)}-"
                      f"{show(r['ranges']['feed_rate_kg_s'][1], 'mass_flow')}."))
    spec = []
    if "fraction_moisture_within_spec" in p:
        spec.append(f"moisture at most {show(p['product_moisture_max_kg_kg'], 'moisture')} "
                    f"{100 * p['fraction_moisture_within_spec']:.0f} % of the time")
    if "fraction_temperature_within_band" in p:
        lo, hi = p["product_temperature_band_degC"]
        spec.append(f"temperature {show(lo, 'temperature', with_unit=False)}-{show(hi, 'temperature')} "
                    f"{100 * p['fraction_temperature_within_band']:.0f} % of the time")
    st.markdown(plain(f"Within the tolerance {100 * p['fraction_within_tolerance']:.0f} % of the time after the "
                      "disturbance" + (f"; product within specification: {', '.join(spec)}" if spec else "") + "."))
    if t.get("gas_temperature_range_note"):
        st.info(plain(f"Gas range: {t['gas_temperature_range_note']}."))
    for w in r["warnings"]:
        st.warning(plain(w))
    st.image(r["plot"], caption="Controlled variable, product temperature and manipulated variables "
                                "(closed loop solid, open loop dashed)")
    st.download_button("Download the closed-loop series (CSV)", r["csv"], file_name="control.csv",
                       mime="text/csv", key="control_dl")
