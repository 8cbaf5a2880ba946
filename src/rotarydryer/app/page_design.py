"""Web-app page "Design": size a flighted rotary dryer for a drying duty (``rotarydryer design``).

Sidebar: a preset duty and its fields, the constraints and the search effort; the search runs
when the button is pressed (a few seconds; "full" is the CLI's search).  Shown: diameter,
length, flights, speed, the binding constraints, every constraint with its slack, the ranked
designs, the drawn cross-section and (optionally) the coupled-model check.  Bad input and an
infeasible duty give the CLI's messages (`rotarydryer.app.logic_design`).
"""

import streamlit as st

from .._display import show
from ..design import constraint_text
from . import logic_design as L
from ._runs import Kept
from ._ui import PERSIST, heavy, number, plain, progress_box, refuse

#: finished searches of every session (not ``st.cache_data``: the progress bar drawn during a search)
_KEPT = Kept(16)


def _design(preset, kwargs):
    """The search of these inputs: kept, or run with a progress bar (quick: 1-5 s; full and the
    coupled-model check: up to a minute)."""
    key = (preset, kwargs)
    r = _KEPT.get(key)
    if r is not None:
        return r
    with progress_box("Differential-evolution search", L.progress_fraction) as report:
        with heavy():
            r = L.design_view(preset, progress=report, **dict(kwargs))
    _KEPT.put(key, r)
    return r


def _inputs():
    side = st.sidebar
    preset = side.selectbox("Preset duty", list(L.DESIGN_PRESETS), key="design_preset", persist_state=PERSIST,
                            help="raw_sugar: 20 kg/s, 1.0 -> 0.1 %, air 100 degC, 22 kg/s; mmg: Ajayi (2011) Test 4. "
                                 "The fields below override it (rotarydryer design --duty ...)")
    d = L.duty_defaults(preset)
    k = f"__{preset}"
    mats = L.design_materials()
    with side.expander("Duty", expanded=True):
        material = st.selectbox("Material", mats, index=mats.index(d["material"]) if d["material"] in mats else 0,
                                key=f"design_material{k}")
        feed = number(st, "Wet feed rate (kg/s)", 0.01, 1000.0, float(d["feed"]), 1.0, key=f"design_feed{k}")
        c1, c2 = st.columns(2)
        moisture_in = number(c1, "Feed moisture (kg/kg wet)", 0.0, 0.95, float(d["moisture_in"]), 0.001,
                                      format="%.4f", key=f"design_min{k}")
        moisture_out = number(c2, "Target moisture (kg/kg wet)", 0.0, 0.95, float(d["moisture_out"]), 0.001,
                                       format="%.4f", key=f"design_mout{k}")
        gas_in = number(st, "Gas inlet temperature (degC)", 0.0, 1000.0, float(d["gas_in"]), 10.0,
                                 key=f"design_gas_in{k}")
        gas_mode = st.radio("Gas flow", ["given", "from NTU"], horizontal=True, key=f"design_gas_mode{k}",
                            help="from NTU: the exhaust temperature from the number of transfer units, the gas "
                                 "flow from the energy balance (--ntu)")
        if gas_mode == "given":
            gas_flow = number(st, "Gas flow (kg/s wet)", 0.01, 1000.0, float(d["gas_flow"] or 20.0), 1.0,
                                       key=f"design_gas_flow{k}")
            ntu = None
        else:
            gas_flow = None
            ntu = number(st, "Transfer units NTU (Perry: 1.5-2.5)", 0.1, 6.0, float(d["ntu"]), 0.1,
                                  key=f"design_ntu{k}")
        dirs = ["counter-current", "co-current"]
        direction = st.radio("Direction", dirs, index=dirs.index(d["direction"]), horizontal=True,
                             key=f"design_direction{k}")
        feed_t = number(st, "Feed temperature (degC)", -20.0, 99.0, float(d["feed_temperature"]), 1.0,
                                 key=f"design_feed_t{k}")
        burner = st.checkbox("Limit the burner (fuel oil)", value=False, key=f"design_burner{k}")
        max_fuel = (number(st, "Burner capacity (kg/s fuel oil)", 0.001, 100.0, 0.5, 0.05,
                                    key=f"design_max_fuel{k}") if burner else None)
    with side.expander("Constraints and objective"):
        objective = st.selectbox("Objective", ["volume", "fuel", "cost"], key="design_objective",
                                 help="drum volume; heat input per kg of water; cost proxy (shell surface^0.6)")
        speed_fraction = number(st, "Largest speed / critical speed", 0.01, 0.99, 0.5, 0.05,
                                         key="design_speed_fraction")
        entrainment = number(st, "Largest gas velocity / terminal velocity", 0.01, 2.0, 1.0, 0.05,
                                      key="design_entrainment")
        u_max = number(st, "Largest gas velocity (m/s)", 0.1, 100.0, 5.0, 0.5, key="design_u_max")
        fill_max = number(st, "Largest fill (holdup / drum volume)", 0.01, 0.5, 0.15, 0.01,
                                   key="design_fill_max")
        dl_tol = number(st, "Design-load tolerance |H/DL - 1|", 0.01, 10.0, 0.15, 0.05, key="design_dl_tol")
        c1, c2 = st.columns(2)
        ld_min = number(c1, "L/D min", 0.5, 50.0, 4.0, 0.5, key="design_ld_min")
        ld_max = number(c2, "L/D max", 0.5, 50.0, 10.0, 0.5, key="design_ld_max")
        d_min = number(c1, "D min (m)", 0.05, 20.0, 0.5, 0.1, key="design_d_min")
        d_max = number(c2, "D max (m)", 0.05, 20.0, 6.0, 0.1, key="design_d_max")
        ua = number(st, "Ua factor (on McCormick's Ua)", 0.01, 100.0, 1.0, 0.1, key="design_ua")
    effort = side.radio("Search", list(L.SEARCH_EFFORT), horizontal=True, key="design_effort",
                        help="quick: 20 generations x population 8 (~1-5 s); full: the CLI's 60 x 12")
    verify = side.checkbox("Check the best design with the coupled model", value=False, key="design_verify",
                           help="runs the heat-and-mass model on the best design; while it misses the target, the "
                                "Ua factor (and, where the coupled holdup breaks the fill or the flights' loading, the "
                                "holdup factor) is corrected and the search repeated (--verify, 5 rounds)")
    kwargs = dict(material=material, feed=feed, moisture_in=moisture_in, moisture_out=moisture_out, gas_in=gas_in,
                  gas_flow=gas_flow, ntu=ntu, direction=direction, feed_temperature=feed_t, max_fuel=max_fuel,
                  objective=objective, speed_fraction=speed_fraction, entrainment_fraction=entrainment,
                  gas_velocity_max=u_max, fill_max=fill_max, design_load_tolerance=dl_tol, ld_min=ld_min,
                  ld_max=ld_max, d_min=d_min, d_max=d_max, ua_factor=ua, effort=effort, verify=verify)
    return preset, tuple(sorted(kwargs.items()))


def render():
    st.title("Size a dryer for a duty")
    st.caption("Differential-evolution search of drum diameter, length, slope, speed and flights under "
               "screening rules (McCormick's Ua, Perry & Green's residence time, exact design load); "
               "as `rotarydryer design` (docs/design_control.md). Screening numbers: verify a chosen design.")
    preset, args = _inputs()
    run = st.button("Size the dryer", type="primary", key="design_run")
    if run:
        st.session_state["design_args"] = (preset, args)
    if "design_args" not in st.session_state:
        st.info("Set the duty and the constraints in the sidebar, then press **Size the dryer**.")
        return
    shown_preset, shown_args = st.session_state["design_args"]
    if (shown_preset, shown_args) != (preset, args):
        st.caption("The inputs changed: press **Size the dryer** to search again. Shown: the last search.")
    try:
        r = _design(shown_preset, shown_args)
    except Exception as exc:
        refuse("No design", exc)
    b = r["best"]
    c = st.columns(5)
    c[0].metric("Diameter D", f"{b['diameter_m']:.2f} m")
    c[1].metric("Length L", f"{b['length_m']:.2f} m", help=f"L/D {b['length_m'] / b['diameter_m']:.1f}")
    c[2].metric("Flights", f"{b['n_flights']}", help=f"s1 {b['s1_m']:.3f} m, s2 {b['s2_m']:.3f} m, "
                                                     f"alpha2 {b['alpha2_deg']:.0f} deg, alpha1 90 deg")
    c[3].metric("Speed", f"{b['rpm']:.2f} rpm", help=f"{b['speed_over_critical']:.0%} of the critical speed")
    c[4].metric("Drum volume", f"{b['volume_m3']:.1f} m3")
    st.markdown(f"**Binding constraints** (slack under 3 %): {plain(', '.join(r['binding']) or 'none')}. "
                f"Slope {b['slope_deg']:.2f} deg; fuel {b['fuel_per_kg_water_MJ']:.2f} MJ/kg water; gas "
                f"{show(b['gas_flow_kg_s'], 'mass_flow')}, exhaust {show(b['gas_outlet_temperature_degC'], 'temperature')}; "
                f"{r['evaluations']} evaluations in {r['seconds']:.1f} s.")
    ver = r.get("verification")
    if ver is not None:
        if "error" in ver:
            st.warning(f"Coupled-model check failed: {plain(ver['error'])}")
        else:
            msg = (f"Coupled model (Lee 2008 transport): product moisture {show(ver['product_moisture_kg_kg'], 'moisture')} "
                   f"wet, target {show(r['duty']['moisture_out'], 'moisture')}: "
                   f"{'met' if ver['target_met'] else 'NOT met'}; exhaust "
                   f"{show(ver['gas_outlet_temperature_degC'], 'temperature')}, holdup {show(ver['total_holdup_kg'], 'mass')}.")
            if ver.get("constraints_violated"):
                msg += " The coupled model breaks the screening's limits: " + "; ".join(ver["constraints_violated"]) + "."
            (st.success if ver["target_met"] and not ver.get("constraints_violated") else st.warning)(msg)
            if "next_round_infeasible" in ver:
                st.caption(plain("With the Ua lowered to what the coupled model achieves: "
                                 + ver["next_round_infeasible"]))
    left, right = st.columns([1, 1])
    left.image(r["cross_section"], caption="Best design: flights at the material's repose angle, to scale")
    with right:
        st.subheader("Constraints of the best design")
        # what each value is, in the display units (design.constraint_text, as the CLI shows them)
        shown = [constraint_text(x[0], x[1], x[3], x[2]) for x in r["constraints"]]
        st.dataframe({"constraint": [c[0] for c in shown], "value": [c[1] for c in shown],
                      "limit": [c[2] for c in shown], "slack": [f"{x[4]:.1%}" for x in r["constraints"]]},
                     hide_index=True)
    st.subheader("Ranked feasible designs")
    cols = ["rank", "diameter_m", "length_m", "slope_deg", "rpm", "n_flights", "s1_m", "s2_m", "alpha2_deg",
            "volume_m3", "fuel_per_kg_water_MJ", "gas_velocity_m_s", "fill_fraction", "holdup_over_design_load",
            "binding"]
    st.dataframe({k: [row[k] if isinstance(row[k], (int, str)) else round(float(row[k]), 3) for row in r["table"]]
                  for k in cols}, hide_index=True)
