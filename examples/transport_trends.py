"""Task: predict Lee's drag factor from particle trajectories, and see how MRT and holdup move.

Produces the tables of docs/transport.md "Forward step from trajectories" and "Trends" (issue 14
parts 1 and 3) and checks that the docs still show them (numbers within their printed digits).

Run: python examples/transport_trends.py [OUTDIR]     (about 30 s)
"""

from __future__ import annotations

import math
import re
import sys
import warnings
from importlib import resources
from pathlib import Path

import numpy as np

from rotarydryer import Simulation
from rotarydryer.cases import load_case, measured_rtd_moments
from rotarydryer.correlations import perry_green_1984, sherritt_curtain_velocity_ratio, song_2003_appendix_a
from rotarydryer.published import read_published_csv
from rotarydryer.transport.diagnostics import cell_flows, holdup_parts
from rotarydryer.transport.forward_step import CurtainGas, trajectory_forward_step

warnings.simplefilter("ignore")      # critical-speed and correlation-range warnings of the sweeps
TEMPLATE = str(resources.files("rotarydryer.cases") / "templates" / "dryer.toml")


def steady(case="lee2008_invicta", **ov):
    # the fitted coefficients and the chosen forward step of each model (Song's case is predictive by
    # default; the predictive law's trends: docs/predictive_transport.md)
    ov.setdefault("transport.parameter_source", "per_test")
    if case != "ajayi2011_mmg":
        ov.setdefault("thermal.enabled", False)
    else:   # Ajayi's thesis model (regression geometry), whose feed independence the table states
        ov.setdefault("geometry.method", "ajayi2011_regressions")
    return Simulation(case, ov).transport_steady_state()


def table(head, rows):
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    return "\n".join(lines + ["| " + " | ".join(str(c) for c in r) + " |" for r in rows])


# ---- 1. effective C_F^G at Invicta ------------------------------------------------------------
def invicta_step():
    lee = {int(r["N"]): float(r["C_F_G"]) for r in read_published_csv("lee_parameter_estimates.csv")}
    rows = [["Lee (2008) Table 7.2, fitted", "-", "-", "-", "-",
             ", ".join(f"{v:.2f} (N = {n})" for n, v in sorted(lee.items())), "-"]]
    for geo in ("lee2008_regressions", "exact"):
        # the step does not depend on N (local release per metre; h_m per cell): one N shown
        m = Simulation("lee2008_invicta", {"thermal.enabled": False, "geometry.method": geo, "transport.n_cells": 35,
                                           "transport.forward_step": "trajectory", "transport.backmix": 0.0,
                                           "transport.kiln_time": 8.69}).transport_model()
        ci, gas = m.cell_info, m.specs[0].gas
        cfg, cv = ci["C_F_G"], ci["curtain_velocity_ratio"]
        rows.append([f"trajectory, {geo}", f"{np.mean(ci['fall_height_m']):.3f}", f"{np.mean(ci['forward_step_m']):.4f}",
                     f"{np.mean(cv):.4f}", f"{np.mean(cv) * gas.gas_velocity:.3f}", f"{np.mean(cfg):.3f}",
                     f"{cfg.min():.3f}-{cfg.max():.3f}"])
    case = load_case("lee2008_invicta")
    return (f"u_g = {gas.gas_velocity:.3f} m/s ({case.gas.flow:g} kg/s at {case.gas.inlet_temperature:g} degC over "
            f"pi R^2), particles {gas.particle_diameter * 1e6:.0f} um at {gas.particle_density:g} kg/m3\n\n"
            + table(["Invicta", "h_m (m, mean)", "step d (m, mean)", "c_v (mean)", "U_c (m/s)", "C_F^G (mean)",
                     "min-max over cells"], rows))


def invicta_readings():
    """C_F^G of the mid cell (exact geometry, N = 35) for readings of Sherritt's Eq. 2.14 and fixed c_v."""
    m = Simulation("lee2008_invicta", {"thermal.enabled": False, "transport.n_cells": 35, "transport.backmix": 0.0,
                                       "transport.kiln_time": 9.0, "transport.forward_step": "trajectory"}
                   ).transport_model()
    gas, ci, i = m.specs[0].gas, m.cell_info, 17
    h, tp, dl = ci["fall_height_m"][i], ci["passive_time_s"][i], 12.0 / 35
    des = float(np.asarray(m.design_load)[np.asarray(m.network.labels["phase"]) == "passive"][i])
    q = des / tp / dl
    zero = h * math.sin(math.radians(2.8))
    rf = 2.22789

    def cfg(cv):
        g = CurtainGas(**{**gas.__dict__, "velocity_ratio": float(min(max(cv, 0.0), 1.0))})
        return float(trajectory_forward_step(g, 2.8, np.array([h]), np.array([q]))["step_m"][0]) / zero

    readings = [
        ("Sherritt, F = q x 1 m, L = 1 m (chosen: local)", float(sherritt_curtain_velocity_ratio(h, q, 1.0))),
        ("Sherritt, F = q L, L = drum length 12 m", float(sherritt_curtain_velocity_ratio(h, q * 12.0, 12.0))),
        ("Sherritt, F = one cell's release, L = curtain width 2 R_F", float(sherritt_curtain_velocity_ratio(h, q * dl, 2 * rf))),
    ] + [(f"fixed c_v = {c:g}", c) for c in (0.0, 0.05, 0.1, 0.2, 0.5, 1.0)]
    rows = [[name, f"{min(cv, 1.0):.4f}", f"{min(cv, 1.0) * gas.gas_velocity:.3f}", f"{cfg(cv):.3f}"]
            for name, cv in readings]
    # the c_v that reproduces each of Lee's fitted values (bisection; C_F^G falls with c_v)
    lee = {int(r["N"]): float(r["C_F_G"]) for r in read_published_csv("lee_parameter_estimates.csv")}
    for N, target in sorted(lee.items()):
        lo, hi = 0.0, 1.0
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if cfg(mid) > target else (lo, mid)
        rows.append([f"c_v matching Lee's C_F^G = {target:.2f} (N = {N})", f"{lo:.4f}", f"{lo * gas.gas_velocity:.3f}",
                     f"{target:.3f}"])
    return (f"Mid cell (exact geometry): h_m = {h:.3f} m, release q = {q:.1f} kg/(s m), u_g = {gas.gas_velocity:.3f} m/s\n\n"
            + table(["curtain velocity ratio", "c_v", "U_c (m/s)", "C_F^G"], rows))


def invicta_results():
    t73 = {r["rtd"]: r for r in read_published_csv("lee_rtd_moments.csv")}
    meas = measured_rtd_moments(load_case("lee2008_invicta"))
    rows = [["measured (Monro; Table 7.3 experiment)", "-", "-",
             f"{meas['mean_s'] / 60:.2f} ({t73['Experiment']['mean_residence_time_min']})",
             f"{meas['std_s'] / 60:.2f} ({t73['Experiment']['standard_deviation_min']})"]]
    variants = [("lee2008_regressions", 35, "fitted", None), ("lee2008_regressions", 30, "fitted", None),
                ("lee2008_regressions", 30, "trajectory", None), ("lee2008_regressions", 31, "trajectory", None),
                ("exact", 33, "trajectory", None), ("lee2008_regressions", 35, "trajectory", 0.0),
                ("exact", 35, "trajectory", 0.0)]
    for geo, N, fs, cb in variants:
        ov = {"geometry.method": geo, "transport.n_cells": N, "transport.forward_step": fs}
        lee = load_case("lee2008_invicta", {"geometry.method": "lee2008_regressions", "transport.n_cells": N}).transport
        ov.update({"transport.kiln_time": lee.kiln_time, "transport.backmix": lee.backmix,     # Lee's Table 7.2
                   "transport.drag_reduction": lee.drag_reduction})
        if cb is not None:
            ov["transport.backmix"] = cb
        s = Simulation("lee2008_invicta", {"thermal.enabled": False, **ov})
        ss = s.transport_steady_state()
        r = ss.rtd(s.transport_model().tracer_input, simulate=False)
        ref = t73.get(f"Model N={N}") if fs == "fitted" else None
        label = f"{fs}, {geo}, N = {N}, Lee's t_kiln" + (", C_B = 0" if cb == 0.0 else ", C_B")
        rows.append([label, f"{ss.total_holdup:,.0f}", f"{ss.mean_residence_time / 60:.2f}",
                     f"{r.tracer_mean / 60:.2f}" + (f" ({ref['mean_residence_time_min']})" if ref else ""),
                     f"{r.tracer_std / 60:.2f}" + (f" ({ref['standard_deviation_min']})" if ref else "")])
    return table(["Invicta", "holdup (kg)", "holdup/feed (min)", "tracer mean (min) (Table 7.3)",
                  "tracer SD (min) (Table 7.3)"], rows)


# ---- 2. trends -----------------------------------------------------------------------------------
def invicta_speed_flows():
    rows = []
    for rpm in (1.5, 3.0, 5.0):
        ss = steady(**{"operating.rpm": rpm})
        c = cell_flows(ss)
        i = 17
        p = holdup_parts(ss)
        nob = steady(**{"operating.rpm": rpm, "transport.backmix": 0.0}).mean_residence_time
        k0 = load_case("lee2008_invicta").transport.kiln_time      # the case's (calibrated at 3 rpm)
        kt = steady(**{"operating.rpm": rpm, "transport.kiln_time": k0 * 3.0 / rpm}).mean_residence_time
        rows.append([f"{rpm:g}", f"{c['passive_time_s'][i]:.2f}", f"{c['discharge_kg_s'][i]:.1f}",
                     f"{c['forward_kg_s'][i]:.1f}", f"{c['backmix_kg_s'][i]:.1f}", f"{c['net_curtain_kg_s'][i]:.1f}",
                     f"{c['kiln_kg_s'][i]:.1f}", f"{c['kiln_bed_kg'][i]:.0f}", f"{p['flights_kg']:,.0f}",
                     f"{p['kiln_bed_kg']:,.0f}", f"{p['curtain_kg']:,.0f}", f"{ss.mean_residence_time:.0f}",
                     f"{nob:.0f}", f"{kt:.0f}"])
    return table(["rpm", "t_p (s)", "discharge", "forward", "backmix", "net curtain", "kiln", "kiln bed (kg)",
                  "flights (kg)", "kiln beds (kg)", "curtains (kg)", "MRT (s)", "MRT, C_B = 0 (s)",
                  "MRT, t_kiln x 3/rpm (s)"], rows)


SWEEPS = {  # case: (rpm, slope, gas key and values, feed)
    "lee2008_invicta": ((2.0, 3.0, 4.5), (2.0, 2.8, 3.3), ("gas.flow", (15.2, 30.4, 45.6)), (19.0, 27.2222, 35.0)),
    "song2003_ottawa": ((3.0, 5.0, 8.0), (3.83, 4.745, 6.68), ("gas.flow", (0.1, 0.182, 0.22)), (0.06, 0.0835, 0.12)),
    "template": ((3.0, 4.0, 6.0), (2.0, 3.0, 4.0), ("gas.flow", (2.0, 4.0, 6.0)), (1.75, 2.5, 3.25)),
    "ajayi2011_mmg": ((2.5, 3.0, 4.0), (3.0, 4.0, 5.0), ("gas.flow", (10.0, 16.25, 25.0)),
                      (30.0, 40.666667, 50.0)),
}
MODEL1 = {"transport.passive_rate": 0.002, "transport.exchange_rate": 0.2, "transport.return_rate": 2.0,
          "transport.kiln_rate": 0.1}


def trend_rows():
    setups = [("lee2008_invicta", m, "fitted", {}) for m in ("lee2008", "sheehan2005_model2")]
    setups += [("lee2008_invicta", m, "trajectory", {"transport.n_cells": 30}) for m in ("lee2008", "sheehan2005_model2")]
    setups += [("ajayi2011_mmg", "ajayi2011", "fitted", {})]
    for case in ("song2003_ottawa", "template"):
        setups += [(case, m, fs, {}) for m in ("lee2008", "sheehan2005_model2", "ajayi2011") for fs in ("fitted", "trajectory")]
        setups.append((case, "sheehan2005_model1", "fitted", MODEL1))
    rows = []
    for case, model, fs, extra in setups:
        rpm, slope, (gkey, gas), feed = SWEEPS[case]
        base = {"transport.model": model, **extra}
        if case != "ajayi2011_mmg":
            base["transport.forward_step"] = fs
        f = TEMPLATE if case == "template" else case
        cells = []
        for key, vals in (("operating.rpm", rpm), ("drum.slope", slope), (gkey, gas), ("operating.feed_rate", feed)):
            t = [steady(f, **{**base, key: v}).mean_residence_time for v in vals]
            cells.append(" / ".join(f"{x:.0f}" for x in t))
        rows.append([case, model, fs] + cells)
    return table(["case", "model", "forward step", "speed low/base/high: MRT (s)", "slope", "gas flow", "feed"], rows)


def song_elasticities():
    """d ln(tau)/d ln(x) at the Song case's point: Song's runs, Perry & Green, the models."""
    d = song_2003_appendix_a()
    tau, n, s, G, F = d["mean_residence_time"], d["rpm"], d["slope"], d["gas_mass_flux"], d["solids_feed_rate"]
    sel = {"speed": ((G == 0) & np.isclose(s, 0.083), n), "slope": ((G == 0) & (n == 5), s),
           "gas flow": ((n == 5) & np.isclose(s, 0.083) & (G > 0), G),
           "feed (with gas)": ((n == 5) & np.isclose(s, 0.083) & (G > 0), F)}
    data = {k: float(np.polyfit(np.log(x[m]), np.log(tau[m]), 1)[0]) for k, (m, x) in sel.items()}
    area = math.pi * 0.305**2 / 4
    pt = dict(rpm=5.0, slope=0.083, gas=0.182, feed=0.0835)

    def pg(**kw):
        v = {**pt, **kw}
        return float(perry_green_1984(3.05, 0.305, v["slope"], v["rpm"], 444e-6, v["gas"] / area, v["feed"] / area,
                                      "co-current", allow_nonpositive=True))
    keys = {"speed": ("rpm", "operating.rpm", 5.0, 6.0), "slope": ("slope", "drum.slope", 0.083, 0.0996),
            "gas flow": ("gas", "gas.flow", 0.182, 0.2184), "feed (with gas)": ("feed", "operating.feed_rate", 0.0835, 0.1002)}
    rows = []
    for name, (pk, ck, x0, x1) in keys.items():
        r = math.log(x1 / x0)
        pgv = math.log(pg(**{pk: x1}) / pg(**{pk: x0})) / r
        cv = (lambda x: math.degrees(math.atan(x))) if pk == "slope" else (lambda x: x)
        mod = []
        for fs in ("fitted", "trajectory"):
            t0 = steady("song2003_ottawa", **{"transport.forward_step": fs, ck: cv(x0)}).mean_residence_time
            t1 = steady("song2003_ottawa", **{"transport.forward_step": fs, ck: cv(x1)}).mean_residence_time
            mod.append(math.log(t1 / t0) / r)
        rows.append([name, f"{data[name]:.2f}", f"{pgv:.2f}", f"{mod[0]:.2f}", f"{mod[1]:.2f}"])
    return table(["elasticity d ln(MRT)/d ln(x)", "Song's runs (App. A)", "Perry & Green at the case point",
                  "song2003_ottawa, lee2008 fitted", "lee2008 trajectory"], rows)


SECTIONS = {"step-invicta": invicta_step, "step-readings": invicta_readings, "step-results": invicta_results,
            "trends-speed-flows": invicta_speed_flows, "trends-summary": trend_rows,
            "trends-song": song_elasticities}

_NUM = re.compile(r"-?\d[\d,]*\.?\d*(?:e-?\d+)?")


def _numbers(text):
    return [(float(m.replace(",", "")), len(m.split(".")[1]) if "." in m else 0) for m in _NUM.findall(text)]


def check_docs(tables, doc):
    """Each table's numbers equal those between ``<!-- name -->`` markers of the docs, within the
    printed digits (one unit of the last decimal, or 0.2 %)."""
    text = doc.read_text(encoding="utf-8")
    bad = []
    for name, got in tables.items():
        m = re.search(rf"<!-- {name} -->\n(.*?)\n<!-- /{name} -->", text, flags=re.S)
        if m is None:
            bad.append(f"{name}: no <!-- {name} --> block in {doc.name}")
            continue
        a, b = _numbers(m.group(1)), _numbers(got)
        if len(a) != len(b) or any(abs(x - y) > max(10.0**-max(da, db), 2e-3 * abs(y)) for (x, da), (y, db) in zip(a, b)):
            bad.append(f"{name}: the table in {doc.name} differs from this script's output")
    return bad


if __name__ == "__main__":
    tables = {name: fn() for name, fn in SECTIONS.items()}
    for name, t in tables.items():
        print(f"<!-- {name} -->\n{t}\n<!-- /{name} -->\n")
    if len(sys.argv) > 1:
        out = Path(sys.argv[1])
        out.mkdir(parents=True, exist_ok=True)
        (out / "transport_trends.md").write_text("\n\n".join(tables.values()) + "\n", encoding="utf-8")
    doc = Path(__file__).resolve().parents[1] / "docs" / "transport.md"
    if doc.exists():
        problems = check_docs(tables, doc)
        if problems:
            sys.exit("\n".join(problems) + "\n(update docs/transport.md with this script's output)")
