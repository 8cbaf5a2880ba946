"""Design load from loading experiments (Ajayi 2011 Appendix D-E): break point of the
first-unloading-flight area against drum loading, with corrected confidence intervals.

Ajayi's raw loading-area points are not published, so each row of his Table 4.11 is mimicked
by synthetic series (break = his design load, plateau = his FUF area, noise and slope set
from his printed CIs; 11 loadings x 5 photographs) and the fit is compared with his design
load and CI over 200 series per row.

Run: python examples/lab_design_load.py [OUTDIR]
"""

import sys
import warnings
from pathlib import Path

import numpy as np

from rotarydryer.lab import design_load_fit as dl

N = 200
print(f"{N} synthetic series per row of Ajayi (2011) Table 4.11")
print(" rpm  wt%  | Ajayi design load | median fit  in his CI | coverage: delta profile corrected App.E"
      " | mean half-width: delta profile")
lines = ["condition,loading_kg,FUF_area_cm2"]
for r in dl.ajayi_table_4_11():
    B, ci = r["design_load_kg"], r["design_load_ci_kg"]
    est, inside, hw = [], 0, {"delta": [], "profile": []}
    cover = dict.fromkeys(dl.CI_METHODS, 0)
    for seed in range(N):
        x, y, truth = dl.mimic_ajayi_series(B, ci, r["FUF_area_cm2"], r["FUF_area_ci_cm2"], seed=seed)
        with warnings.catch_warnings():     # about 1 series in 60 has its break at its last loadings, not
            warnings.simplefilter("ignore", RuntimeWarning)     # significant (a warning): the coverage counts them too
            f = dl.fit_break_point(x, y)
        est.append(f.break_point)
        inside += abs(f.break_point - B) <= ci
        for m, (lo, hi) in f.ci.items():
            cover[m] += lo <= B <= hi
        for m in hw:
            hw[m].append((f.ci[m][1] - f.ci[m][0]) / 2)
        if seed == 0:
            lines += [f"{r['rpm']}rpm_{r['fluid_wt_pct']}pct,{a:.3f},{b:.4f}" for a, b in zip(x, y)]
    c = {m: 100 * v / N for m, v in cover.items()}
    print(f" {r['rpm']:.1f}  {r['fluid_wt_pct']:.2f} | {B:5.1f} +/- {ci:3.1f} kg    | {np.median(est):6.1f} kg  "
          f"{100 * inside / N:5.0f} %  |      {c['delta']:3.0f} %  {c['profile']:3.0f} %  {c['ajayi_corrected']:3.0f} %  "
          f"{c['appendix_e']:3.0f} % |  {np.mean(hw['delta']):4.1f}  {np.mean(hw['profile']):4.1f} kg")

out = Path(sys.argv[1]) if len(sys.argv) > 1 else None
if out:
    out.mkdir(parents=True, exist_ok=True)
    (out / "synthetic_loading_series.csv").write_text("\n".join(lines) + "\n")
    print("one series per row in", out / "synthetic_loading_series.csv",
          "(try: rotarydryer lab design-load", out / "synthetic_loading_series.csv", "--group-column condition)")
