"""Task: study fouling and insulation (user guide: docs/guide/study_fouling.md).

How much does scale in the flights cost the MMG Karumba zinc-concentrate dryer, and how
much fuel would lagging the shell save at the same product moisture?

Run: python examples/study_fouling.py [OUTDIR]     (about 20 s)
"""

import sys
from pathlib import Path

from rotarydryer.cases import load_case
from rotarydryer.simulation import build_thermal_dryer
from rotarydryer.thermal.studies import fouling_study, insulation_study

dryer = build_thermal_dryer(load_case("ajayi2011_mmg", {"operating.test": 4}))

print("fouling  curtain holdup  product moisture  product T  gas outlet  fuel")
rows = fouling_study(dryer, foulings=(0.0, 0.4, 0.8))
for r in rows:
    print(f"{r['fouling_pct']:5.0f} %  {r['active_holdup_kg']:10.0f} kg  {r['product_moisture_kg_kg']:12.4f}     "
          f"{r['product_temperature_degC']:6.1f} C  {r['gas_outlet_temperature_degC']:7.1f} C  "
          f"{r['fuel_rate_kg_s'] * 3600:5.0f} kg/h")

ins = insulation_study(dryer, insulation_thickness=0.1)
print(f"\ninsulation 0.1 m: shell loss {ins['reference']['shell_heat_loss_W'] / 1e3:.0f} -> "
      f"{ins['insulated_same_inlet']['shell_heat_loss_W'] / 1e3:.0f} kW; same product moisture at a gas inlet of "
      f"{ins['insulated_matched']['gas_inlet_temperature_degC']:.0f} C saves {ins['fuel_saved_kg_h']:.0f} kg/h "
      f"({ins['fuel_saved_pct']:.1f} %)")
low = ins["insulated_reduced_inlet"]
print(f"gas inlet lowered to {low['gas_inlet_temperature_degC']:.0f} C: saves {ins['fuel_saved_reduced_inlet_kg_h']:.0f} kg/h "
      f"but the product leaves at {low['product_moisture_kg_kg']:.3f} kg/kg (reference "
      f"{ins['reference']['product_moisture_kg_kg']:.3f})")

out = Path(sys.argv[1]) if len(sys.argv) > 1 else None
if out:
    import json

    out.mkdir(parents=True, exist_ok=True)
    (out / "fouling.json").write_text(json.dumps({"fouling": rows, "insulation": ins}, indent=1, default=float))
    print("table:", out / "fouling.json")
