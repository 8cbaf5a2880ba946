"""Web-app page "Flight geometry": drum presets, repose angle, speed, flight dimensions ->
summary table, design loads, cross-section and unloading profile (Lee (2008) ch. 4).

Widget bounds: the dryer schema's range of the matching case key, or the range the geometry
checks allow (`rotarydryer.app.logic.geometry_range`), always containing the preset's
value; a value the model refuses gives its message (`rotarydryer.app._ui.refuse`).
"""

import streamlit as st

from .._display import show, unit_of
from . import logic
from ._ui import PERSIST, metric_row, number, refuse


@st.cache_data(show_spinner=False, max_entries=64)
def _geometry(*args):
    return logic.geometry_view(*args)


@st.cache_data(show_spinner=False, max_entries=64)
def _profile(*args):
    return logic.profile_view(*args)


#: the row of metrics: (label, template of the value, formatted with the view's "metrics")
_METRICS = [("Design load (Lee 2008)", "design_load_kg"),
            ("Mean fall height", "{mean_fall_height_m:.3f} m"),
            ("Mean fall time", "{mean_fall_time_s:.3f} s"),
            ("Passive time", "{passive_time_s:.2f} s")]


def _num(container, label, name, value, step, **kwargs):
    lo, hi = logic.geometry_range(name, value)
    return number(container, label, lo, hi, value, step, **kwargs)


def render():
    st.title("Flight geometry explorer")
    presets = logic.presets()
    name = st.sidebar.selectbox("Drum preset", list(presets), key="preset", persist_state=PERSIST)
    e = presets[name]
    polygon = "s1" not in e             # a polygonal flight (EAD, three-section ...): its shape as the preset's
    st.caption(e["description"])
    side = st.sidebar
    repose = _num(side, "Dynamic repose angle (deg)", "repose_angle", float(e.get("repose_angle", 45.0)), 0.5,
                  key=f"repose_angle__{name}" if polygon else "repose_angle")
    rpm = _num(side, "Speed (rev/min)", "rpm", float(e["rpm"]), 0.1, key=f"rpm__{name}")
    with side.expander("Drum and flight dimensions", expanded=True):
        radius = _num(st, "Drum radius R (m)", "radius", float(e["radius"]), 0.05, key=f"radius__{name}")
        n_flights = _num(st, "Number of flights", "n_flights", int(e["n_flights"]), 1, key=f"n_flights__{name}")
        if not polygon:
            s1 = _num(st, "Flight base s1 (m)", "s1", float(e["s1"]), 0.005, format="%.3f", key=f"s1__{name}")
            s2 = _num(st, "Flight tip s2 (m)", "s2", float(e["s2"]), 0.005, format="%.3f", key=f"s2__{name}")
            alpha1 = _num(st, "alpha1, base to shell (deg)", "alpha1", float(e["alpha1"]), 1.0, key=f"alpha1__{name}")
            alpha2 = _num(st, "alpha2, base to tip (deg)", "alpha2", float(e["alpha2"]), 1.0, key=f"alpha2__{name}")
        slope = _num(st, "Slope (deg)", "slope", float(e["slope"]), 0.1, key=f"slope__{name}")
        rho = _num(st, "Bulk density (kg/m3)", "bulk_density", float(e["bulk_density"]), 10.0, key=f"rho__{name}")
        length = _num(st, "Length (m)", "length", float(e["length"]), 0.1, key=f"length__{name}")
    try:
        if polygon:
            g = _profile(name, radius, int(n_flights), repose, rpm, slope, rho, length)
        else:
            g = _geometry(radius, int(n_flights), s1, s2, alpha1, alpha2, repose, rpm, slope, rho, length)
    except Exception as exc:
        refuse("Invalid input", exc)
    if polygon:
        st.caption("Polygonal flight, sections from the base at the shell to the tip (length m, angle deg: the "
                   "first to the shell, then the bends): "
                   + "; ".join(f"{a:g} m at {b:g} deg" for a, b in g["sections"])
                   + ". To change its shape: `rotarydryer flight --profile FILE.toml` (docs/geometry.md).")
    metric_row(_METRICS, g["metrics"])
    left, right = st.columns([1, 1])
    with left:
        st.image(g["cross_section"], caption="Cross-section to scale (flight at 90 deg)")
    with right:
        st.subheader("Summary")
        st.table({"quantity": [r[0] for r in g["summary"]], "value": [str(r[1]) for r in g["summary"]],
                  "unit": [r[2] for r in g["summary"]]})
        st.subheader("Design load")
        st.table({"method": [r[0] for r in g["design_loads"]], "area (m2)": [r[1] for r in g["design_loads"]],
                  f"mass ({unit_of('mass')})": [show(r[2], "mass", with_unit=False) for r in g["design_loads"]]})
    st.image(g["profile"], caption="Holdup and discharge rate against flight angle")

