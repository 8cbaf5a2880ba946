"""Task: a drying law from lab drying curves (user guide: docs/guide/drying_curves.md).

Fit the thin-layer laws (Lewis, Page, Henderson-Pabis, logarithmic, two-term, Midilli) with
Arrhenius rate constants to the shipped example curves, rank them, compare the recovered law with
the one that generated the data, draw the curves with the chosen law, write the law into a
material file and run Song's pilot dryer with that material.

Run: python examples/drying_curves.py [OUTDIR]     (OUTDIR/drying_curves.png, OUTDIR/my_ore.toml)
"""

import sys
import warnings
from pathlib import Path

from rotarydryer import Simulation
from rotarydryer._io import save_figure
from rotarydryer._plotting import pyplot
from rotarydryer.lab import drying_curves as dc
from rotarydryer.properties.materials import load_material

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(".")
out.mkdir(parents=True, exist_ok=True)

# 1. The curves: three air temperatures, moisture (kg/kg dry) against time (min); see the file's header
curves = dc.load_example()
print(f"{len(curves.ids)} curves at {', '.join(f'{t:g}' for t in curves.air_temperature_degC)} degC, "
      f"{curves.time_s.size} rows")

# 2. All six laws fitted to all curves at once, ranked by AICc
result = dc.fit_models(curves)
print(f"rate constants at T_ref = {result.reference_temperature_K:.2f} K")
for rank, (model, f) in enumerate(result.fits.items(), start=1):
    print(f"{rank}. {model:16s} p {f.n_parameters}  RMSE {f.rmse:.5f}  AICc {f.aicc:8.1f}  "
          f"dAICc {result.delta_aicc(model):6.1f}")

# 3. The chosen law against the one that made the data (dc.EXAMPLE_LAW)
best = result.best_law
truth = {**dc.EXAMPLE_LAW["parameters"], "Ea": dc.EXAMPLE_LAW["activation_energy"]}
estimates = {**best.parameters, "Ea": best.activation_energy}
for name, e in estimates.items():
    print(f"{best.model} {name:3s} {e.value:.5g} {e.unit:6s} 95 % CI [{e.ci_low:.5g}, {e.ci_high:.5g}]  "
          f"true {truth[name]:.5g}")

# 4. The figure: the curves with the chosen law, and its residuals
fig = dc.plot_fit(result)
save_figure(fig, out / "drying_curves.png", dpi=110)
pyplot().close(fig)

# 5. The law as the kinetics of a material (the other properties from a library material)
table = dc.material_table(result, best.model, "ottawa_sand_song2003", name="my_ore")
path = out / "my_ore.toml"
path.write_text(dc.material_toml(table, ["the example's law on Song's sand (examples/drying_curves.py)"]))
material = load_material(str(path))
print(f"material {material.name}: kinetics {material.kinetics.method} / {material.kinetics.model}, "
      f"rate at X = 0.1 kg/kg dry in air at 65 degC: {float(material.kinetics.law_rate(0.1, 65.0)) * 60:.4f} "
      "kg/(kg dry min)")

# 6. Song's pilot dryer with the sand's own kinetics and with the fitted law (feed 10 % wet)
with warnings.catch_warnings():
    warnings.simplefilter("ignore")       # the sand's transport was calibrated on dry sand: an extrapolation
    for label, over in (("sand kinetics", {}), ("fitted law", {f"material.{k}": v for k, v in table.items()})):
        s = Simulation("song2003_ottawa", {"operating.feed_moisture": 0.1, **over}).steady_state().summary()
        print(f"Song's dryer, {label:13s}: product {100 * s['product_moisture_kg_kg']:.2f} % wet, "
              f"gas out {s['gas_outlet_temperature_degC']:.1f} degC")
