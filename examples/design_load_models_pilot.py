"""Compare the design-load models with Ajayi's (2011) pilot-drum measurements.

Ajayi measured the design load of a 0.75 m pilot drum (24 flights) from photographs
(Table 4.11) and compared Porter, Kelly and Baker (Table 4.16, from traced flight areas).
Here every model is evaluated with the exact flight geometry (Lee 2008 ch. 4), the
measured dynamic angles of repose, and the consolidated bulk densities of Table 4.3.

Run: python examples/design_load_models_pilot.py
"""

import numpy as np

from rotarydryer.geometry import DESIGN_LOAD_METHODS, design_load_mass
from rotarydryer.geometry.presets import preset_drum
from rotarydryer.published import read_published_csv

drum, entry = preset_drum("ajayi_pilot")
rho = {float(r["fluid_content_wt_pct"]): float(r["consolidated_bulk_density_kg_m3"])
       for r in read_published_csv("ajayi_pilot_sand_properties.csv")}
rows = read_published_csv("ajayi_design_load_pilot.csv")

for convention in ("tip", "root"):
    print(f"\nfirst unloading flight: {convention} at 9 o'clock")
    print(f"{'rpm':>4} {'fluid%':>6} {'phi':>5} {'measured kg':>12} " + " ".join(f"{m:>11}" for m in DESIGN_LOAD_METHODS))
    dev = {m: [] for m in DESIGN_LOAD_METHODS}
    inside = {m: 0 for m in DESIGN_LOAD_METHODS}
    for r in rows:
        phi, w = float(r["dyn_angle_of_repose_deg"]), float(r["fluid_wt_pct"])
        meas, ci = float(r["design_load_kg"]), float(r["design_load_ci_kg"])
        kg = {m: float(design_load_mass(drum, phi, rho[w], entry["length"], method=m, convention=convention))
              for m in DESIGN_LOAD_METHODS}
        for m in DESIGN_LOAD_METHODS:
            dev[m].append(100 * (kg[m] - meas) / meas)
            inside[m] += abs(kg[m] - meas) <= ci
        print(f"{r['rpm']:>4} {w:6.2f} {phi:5.1f} {meas:6.1f} +-{ci:4.1f} " + " ".join(f"{kg[m]:11.1f}" for m in DESIGN_LOAD_METHODS))
    print("mean deviation %: " + ", ".join(f"{m} {np.mean(v):+.1f} (sd {np.std(v, ddof=1):.1f})" for m, v in dev.items()))
    print("inside the 95% CI: " + ", ".join(f"{m} {inside[m]}/{len(rows)}" for m in DESIGN_LOAD_METHODS))
