"""Web-app page "Studies and sensitivity" on a shipped or uploaded case:

- what-if: the whole-dryer steady state over a range of one input (product moisture, gas
  outlet temperature, fuel rate, residence time ... against it), recomputed on every change;
- global sensitivity: Sobol first- and total-order indices and the Monte Carlo output
  distributions for a few uniform inputs (SALib, ``rotarydryer.studies.sensitivity``), run
  on a button press.

Both are capped (points, runs) so that a study stays well under a minute; the limits are
in the widgets. Logic: `rotarydryer.app.logic_studies` (no Streamlit).
"""

import streamlit as st

from . import logic_dryer, logic_studies
from ._runs import Kept
from ._ui import case_picker, heavy, plain, progress_box, refuse


@st.cache_data(show_spinner=False, max_entries=16)
def _specs(case):
    return logic_studies.study_inputs(case)


#: finished what-if studies of every session (not ``st.cache_data``: the progress bar drawn meanwhile)
_WHATIF = Kept(32)


def _whatif(case, key, low, high, points):
    """The what-if study of these inputs: kept, or solved with a progress bar (0.3-1 s a point)."""
    sig = (case, key, low, high, points)
    w = _WHATIF.get(sig)
    if w is not None:
        return w
    with progress_box(f"Solving {points} steady states") as report:
        with heavy():
            w = logic_studies.whatif_view(case, key, low, high, points,
                                          progress=lambda done, n: report(f"{done} of {n} steady states solved",
                                                                          done / max(n, 1)))
    _WHATIF.put(sig, w)
    return w


def _sensitivity(case, params, samples, seed, progress=None):
    """The study of these inputs, kept in the session (not ``st.cache_data``: the progress bar's
    calls inside a cached function would be recorded and fail to replay on a later hit)."""
    sig = (case, params, samples, seed)
    kept = st.session_state.get("studies_sens_result")
    if kept is not None and kept[0] == sig:
        return kept[1]
    with heavy():
        r = logic_studies.sensitivity_view(case, dict(params), samples, seed, progress=progress)
    st.session_state["studies_sens_result"] = (sig, r)
    return r


def _rows_table(rows, key, outs):
    table = {key: [f"{r[key]:.5g}" for r in rows]}
    for name, label in outs:
        title, scale, offset = logic_studies.display_column(name, label)
        table[title] = ["-" if r.get(name) is None else f"{r[name] * scale + offset:.5g}" for r in rows]
    if any(r["error"] for r in rows):
        table["error"] = [r["error"] for r in rows]
    return table


def _whatif_section(case, specs, by_key):
    st.header("What-if: one input")
    st.caption("The whole-dryer steady state at evenly spaced values of one input; the other inputs stay at the "
               "case's values. Recomputed on every change.")
    keys = list(by_key)
    cols = st.columns([2.2, 1, 1, 1])
    key = cols[0].selectbox("Input", keys, index=0, format_func=lambda k: f"{by_key[k]['label']} ({k})",
                            key=f"studies_whatif_input__{case}")
    s = by_key[key]
    low = cols[1].number_input("From", value=float(s["low"]), step=float(s["step"]), format=s["format"],
                               key=f"studies_low__{case}__{key}")
    high = cols[2].number_input("To", value=float(s["high"]), step=float(s["step"]), format=s["format"],
                                key=f"studies_high__{case}__{key}")
    points = cols[3].number_input(f"Points (2-{logic_studies.MAX_POINTS})", 2, logic_studies.MAX_POINTS, 5, 1,
                                  key="studies_points",
                                  help=f"at most {logic_studies.MAX_POINTS} points (about 0.3-1 s each); "
                                       "rotarydryer sweep has no limit")
    try:
        w = _whatif(case, key, float(low), float(high), int(points))
    except Exception as exc:
        refuse("What-if study refused", exc, stop=False)
        return
    st.image(w["plot"], caption=f"Outputs against {w['label']}")
    if w["failed"]:
        st.warning(f"{w['failed']} of {len(w['rows'])} points could not be solved (see the error column).")
    with st.expander("Table of the points"):
        st.table(_rows_table(w["rows"], key, w["outputs"]))
    st.download_button("Download the what-if table (CSV)", w["csv"], file_name="whatif.csv", mime="text/csv",
                       key="studies_dl_whatif")


def _sensitivity_section(case, specs, by_key):
    st.header("Global sensitivity (Sobol indices, Monte Carlo)")
    st.caption("Uniform inputs on the ranges below; Saltelli's design of samples x (inputs + 2) runs "
               f"(at most {logic_studies.MAX_RUNS} on this page, about 0.25-1 s each); indices with 95 % bootstrap "
               "intervals. Small samples give wide intervals: for a real study run `rotarydryer sensitivity`.")
    keys = list(by_key)
    default = [k for k in keys if by_key[k]["label"].startswith(("Feed rate", "Gas inlet temperature"))][:2]
    chosen = st.multiselect(f"Uncertain inputs (1-{logic_studies.MAX_PARAMS})", keys, default=default,
                            format_func=lambda k: by_key[k]["label"], max_selections=logic_studies.MAX_PARAMS,
                            key=f"studies_sens_inputs__{case}")
    params = {}
    for k in chosen:
        s = by_key[k]
        c1, c2, c3 = st.columns([2.2, 1, 1])
        c1.markdown(f"{plain(s['label'])}  \n`{k}`")
        lo = c2.number_input("Low", value=float(s["low"]), step=float(s["step"]), format=s["format"],
                             key=f"studies_sens_low__{case}__{k}")
        hi = c3.number_input("High", value=float(s["high"]), step=float(s["step"]), format=s["format"],
                             key=f"studies_sens_high__{case}__{k}")
        params[k] = (float(lo), float(hi))
    c1, c2, c3 = st.columns([1, 1, 2])
    samples = c1.selectbox("Base samples N", logic_studies.SAMPLE_CHOICES, index=1, key="studies_samples",
                           help=f"runs = N x (inputs + 2), at most {logic_studies.MAX_RUNS} on this page")
    seed = c2.number_input("Seed", 0, 2**31 - 1, 0, 1, key="studies_seed")
    runs = int(samples) * (len(params) + 2)
    c3.caption(f"{runs} runs (limit {logic_studies.MAX_RUNS})")
    sig = (case, tuple(params.items()), int(samples), int(seed))
    if c3.button("Run the sensitivity study", key="studies_run", type="primary"):
        st.session_state["studies_sens_sig"] = sig
    if st.session_state.get("studies_sens_sig") != sig:
        if st.session_state.get("studies_sens_sig") is not None:
            st.caption("The inputs changed: press the button to run the study again.")
        return
    bar = st.progress(0.0, text=f"{runs} runs ...")
    done = [0]

    def tick(n):
        done[0] += n
        bar.progress(min(1.0, done[0] / max(runs, 1)), text=f"{done[0]} of {runs} runs")

    try:
        r = _sensitivity(case, tuple(params.items()), int(samples), int(seed), progress=tick)
    except Exception as exc:
        bar.empty()
        refuse("Sensitivity study refused", exc, stop=False)
        return
    bar.empty()
    st.metric("Runs (failed)", f"{r['n_runs']} ({r['n_failed']})", help=f"{r['seconds']:.1f} s")
    st.table({"output": [t["output"] for t in r["table"]], "input": [t["parameter"] for t in r["table"]],
              "S1 (first order)": [f"{t['S1']:.3f} ± {t['S1_conf']:.3f}" for t in r["table"]],
              "ST (total order)": [f"{t['ST']:.3f} ± {t['ST_conf']:.3f}" for t in r["table"]]})
    for img in r["plots"]:
        st.image(img, caption="Sobol indices (bars, 95 % intervals) and the output distribution over the runs "
                              "(histogram; lines: 5th, 50th, 95th percentiles)")
    st.table({"output": [d["output"] for d in r["distributions"]],
              "mean": [f"{d.get('mean', float('nan')):.5g}" for d in r["distributions"]],
              "sd": [f"{d.get('sd', float('nan')):.3g}" for d in r["distributions"]],
              "p5 - p95": [f"{d.get('p5', float('nan')):.5g} - {d.get('p95', float('nan')):.5g}"
                           for d in r["distributions"]]})
    for note in r["notes"]:
        st.caption(plain(f"note: {note}"))
    st.download_button("Download the runs (CSV)", r["runs_csv"], file_name="sensitivity_runs.csv", mime="text/csv",
                       key="studies_dl_runs")


def render():
    st.title("Studies and sensitivity")
    case, shown = case_picker("studies", "ajayi2011_mmg",
                              help_text="any case with a heat and mass transfer model; the studies run at its "
                                        "operating point")
    try:
        specs = _specs(case)
    except logic_dryer.NoThermalModel as exc:
        st.info(plain(f"{shown}: {exc}"))
        st.stop()
    except Exception as exc:
        refuse(f"Case {shown} refused", exc)
    by_key = {s["key"]: s for s in specs}
    _whatif_section(case, specs, by_key)
    _sensitivity_section(case, specs, by_key)
