"""Why Lee's (2008) model misses the spread of the Invicta RTD, and a variant that does not.

Prints the variance budget of the candidate mechanisms and the comparison of Lee's
model with the stagnant-core variants (fitted parameters from
rotarydryer.studies.invicta_rtd_spread.INVICTA_FITS, produced by ``fit_invicta``); writes
rtd_spread.png and rtd_spread.json into OUTDIR. See docs/rtd_spread.md.

Run: python examples/rtd_spread.py OUTDIR
"""

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # small dense expm: threads only cost time

import json  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from rotarydryer.rtd import fit_rtd_model, pulse_input  # noqa: E402
from rotarydryer.studies.invicta_rtd_spread import (  # noqa: E402
    INVICTA_FITS,
    LOG_FLOOR,
    _response,
    invicta_data,
    invicta_model,
    tail_decay_time,
    tail_power_exponent,
    tail_share,
    truncated_moments,
)

out = Path(sys.argv[1]) if len(sys.argv) > 1 else None
t, y = invicta_data()
eps = LOG_FLOOR * y.max()
_, mean_meas, sd_meas = truncated_moments(t, y)
var_meas = sd_meas**2

print("Measured Invicta RTD (Lee 2008 Fig. 7.1): mean %.2f min, SD %.2f min" % (mean_meas / 60, sd_meas / 60))
for cut in (900, 1200, 1800, 3000):
    frac, m, s = truncated_moments(t, y, cut)
    mass, var = tail_share(t, y, cut)
    print("  after %2.0f min: %4.1f %% of the tracer, %4.1f %% of the variance; curve cut there: SD %.2f min"
          % (cut / 60, 100 * mass, 100 * var, s / 60))
n_pow, rss_pow, rss_exp = tail_power_exponent(t, y, 1400.0)
print("  tail (t > 23 min): e-folding time %.1f min; as a power law E ~ t^%.2f (log-residuals %.2f vs %.2f "
      "for the exponential)" % (tail_decay_time(t, y, 1400.0) / 60, n_pow, rss_pow, rss_exp))

# --------------------------------------------------------------------------- variance budget
rows = []


def lee_sd(values=None, **kw):
    m = invicta_model(values or {}, **kw)
    ss = m.steady_state()
    return ss.rtd(simulate=False).moments, ss


mom0, ss0 = lee_sd()
v0 = mom0["variance"]
print("\nVariance budget (min^2; measured %.1f, Lee Table 7.2 model %.1f):" % (var_meas / 3600, v0 / 3600))
rows.append(("Lee Table 7.2, N = 35, regressions (reference)", mom0["std"], 0.0))
pulse_var = 39.6**2 / 12
rows.append(("39.6 s rectangular tracer pulse (in the reference)", math.sqrt(pulse_var), pulse_var))
for label, kw in [("N = 30 instead of 35 (Table 7.2 row)", dict(n_cells=30)),
                  ("loading factor from the state (under-loading)", dict(overrides={"transport.loading": "state"})),
                  ("exact flight geometry, Table 7.2 parameters", dict(geometry="exact"))]:
    m, ss = lee_sd(**kw)
    rows.append((label, m["std"], m["variance"] - v0))
m, ss = lee_sd(INVICTA_FITS["lee2008_exact"]["values"], geometry="exact")
rows.append(("exact flight geometry, refitted (unit weights)", m["std"], m["variance"] - v0))
# distribution of fall heights: every cascade moves a particle by C_F^G h sin(theta) with h
# anywhere in [0, 2R]; Var(h) <= R^2, n_c cascades per particle (discharge flow / feed)
info = invicta_model({}).cell_info
n_casc = float(np.sum(ss0.flow("discharge"))) / ss0.model.feed_rate
step_var = n_casc * (0.48 * math.sin(math.radians(2.8)) * 2.5) ** 2  # m^2, upper bound
v_axial = 12.0 / mom0["mean"]
rows.append(("fall-height (axial step) distribution, upper bound", math.sqrt(step_var) / v_axial,
             step_var / v_axial**2))
adm = fit_rtd_model(t, y, "dispersion_closed", pulse=pulse_input("rectangular", 39.6))
rows.append(("axial dispersion fitted to the curve (Pe %.0f)" % adm.values["peclet"],
             math.sqrt(adm.outlet_moments.variance_s2), adm.outlet_moments.variance_s2 - v0))
for label, key, cm in [("stagnant core, first order (3 fitted)", "first_order_core", "first_order"),
                       ("stagnant core, diffusive, N = 35 (3 fitted)", "diffusive_core_n35", "diffusive"),
                       ("stagnant core, diffusive, N = 24 (3 fitted)", "diffusive_core", "diffusive")]:
    f = INVICTA_FITS[key]
    e = _response(invicta_model(f["values"], core_model=cm, n_cells=f.get("n_cells", 35)), t, "expm")
    _, _, s = truncated_moments(t, e)
    rows.append((label + ", window", s, s**2 - v0))
for label, sd, dv in rows:
    print("  %-62s SD %5.2f min   dVar %+8.2f min^2" % (label, sd / 60, dv / 3600))
print("  (cascades per particle n_c = %.1f; h_m %.2f-%.2f m)" % (n_casc, info["fall_height_m"].min(),
                                                                  info["fall_height_m"].max()))

# --------------------------------------------------------------------------- model comparison
print("\nSame data; 'unit' = Lee's weights (SSE of E, 1/s^2), 'log' = SSE of log(E + 0.2 % of peak):")
print("%-38s %3s %7s %7s %8s %8s %9s %7s %7s %7s" % ("model", "p", "mean", "SD", "win.mean", "win.SD",
                                                        "SSE unit", "R2", "SSE log", "holdup"))
print("%-38s %3s %7.2f %7.2f %8.2f %8.2f" % ("measured (Lee Table 7.3)", "", 11.08, 6.73, mean_meas / 60, sd_meas / 60))
table = {}
curves = {}
sst = float(np.sum((y - y.mean()) ** 2))
for key in ("lee2008_table7_2", "lee2008", "lee2008_relative", "lee2008_relative_n24", "first_order_core",
            "diffusive_core_unit", "diffusive_core_n35", "diffusive_core"):
    f = INVICTA_FITS[key]
    cm = f.get("core_model", "first_order")
    model = invicta_model(f["values"], core_model=cm, n_cells=f.get("n_cells", 35))
    ss = model.steady_state()
    mom = ss.rtd(simulate=False).moments
    tt = np.arange(0.0, 4470.0, 10.0)
    e_fine = _response(model, tt, "expm")
    e = np.interp(t, tt, e_fine)
    _, wm, ws = truncated_moments(t, e)
    sse = float(np.sum((y - e) ** 2))
    lsse = float(np.sum((np.log(y + eps) - np.log(e + eps)) ** 2))
    table[key] = dict(label=f["label"], n_fitted=f["n_fitted"], n_cells=f.get("n_cells", 35), values=f["values"],
                      mean_min=mom["mean"] / 60,
                      sd_min=mom["std"] / 60, window_mean_min=wm / 60, window_sd_min=ws / 60, sse_unit=sse,
                      r2_unit=1 - sse / sst, sse_log=lsse, holdup_kg=ss.total_holdup)
    curves[key] = e_fine
    print("%-38s %3d %7.2f %7.2f %8.2f %8.2f %9.2e %7.4f %7.2f %6.1ft" % (
        f["label"][:38], f["n_fitted"], mom["mean"] / 60, mom["std"] / 60, wm / 60, ws / 60, sse, 1 - sse / sst, lsse,
        ss.total_holdup / 1000))
print("(mean/SD: analytic, infinite time; win.: the model curve sampled, cut at 74.3 min and normalised like the data)")

if out:
    out.mkdir(parents=True, exist_ok=True)
    (out / "rtd_spread.json").write_text(json.dumps(dict(budget=[dict(mechanism=r[0], sd_min=r[1] / 60,
                                                                      dvar_min2=r[2] / 3600) for r in rows],
                                                         models=table), indent=1, default=float))
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    tt = np.arange(0.0, 4470.0, 10.0) / 60
    styles = {"lee2008_table7_2": ("Lee (2008) Table 7.2", "C1", "--"),
              "lee2008": ("Lee's model refitted (3 p, unit weights)", "C1", "-"),
              "first_order_core": ("+ first-order core (3 p)", "C2", ":"),
              "diffusive_core_n35": ("+ diffusive core, N = 35 (3 p)", "C3", ":"),
              "diffusive_core": ("+ diffusive core, N = 24 (3 p, proposed)", "C3", "-")}
    for ax, log in zip(axes, (False, True)):
        ax.plot(t / 60, y * 60, "ko", ms=4, label="measured (Monro; Lee Fig. 7.1)")
        for key, (lab, c, ls) in styles.items():
            ax.plot(tt, curves[key] * 60, color=c, ls=ls, label=lab)
        ax.set_xlabel("time since injection (min)")
        ax.set_ylabel("E(t) (1/min)")
        if log:
            ax.set_yscale("log")
            ax.set_ylim(1e-4, 0.5)
            ax.set_title("log scale: the tail carries the spread")
        else:
            ax.set_xlim(0, 30)
            ax.set_title("Invicta RTD: SD 6.73 min measured")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "rtd_spread.png", dpi=110)
    print("wrote", out / "rtd_spread.png", "and", out / "rtd_spread.json")
