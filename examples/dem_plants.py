"""What the finite-particle correction means for the plants (issue 15, docs/dem.md).

* MMG Karumba (Ajayi 2011): design load of sections B-D with the correction (the sections' particle
  sizes, Ajayi l.2255) against Baker's geometric design load and Ajayi's 1.24 x Baker;
* Ajayi's pilot drum (filter sand of 300 um in 33 mm flights): the correction against his
  photographed first-unloading-flight areas and design loads (Table 4.11, Table 4.16);
* CSR Invicta (Lee 2008): raw sugar of about 0.85 mm in 0.195 m flights.

Run: python examples/dem_plants.py   (prints Markdown tables)
"""

from __future__ import annotations

import csv
from importlib import resources

from rotarydryer.cases import load_case
from rotarydryer.cases.build import exact_drum, material_of
from rotarydryer.geometry import SURFACE_LAYER_DEFAULT as K
from rotarydryer.geometry.presets import preset_drum


def mmg(x_wet: float = 0.12):
    case = load_case("ajayi2011_mmg")
    mat = material_of(case)
    phi = float(mat.repose_angle(x_wet))
    rows = []
    for s in case.sections:
        if s.kind != "flighted":
            continue
        drum = exact_drum(case.drum.radius, s.n_flights, s.s1, s.s2, s.alpha1, s.alpha2)
        d = s.particle_diameter
        base = float(drum.design_load_area(phi))
        corr = float(drum.design_load_area(phi, particle_diameter=d))
        h0 = drum.holdup_area(90.0, phi)
        h0c = drum.holdup_area(90.0, phi, particle_diameter=d)
        rows.append((s.name, d, d / s.s1, phi, base, corr, corr / base, float(h0c / h0)))
    return rows


def pilot():
    drum, entry = preset_drum("ajayi_pilot")
    d = 300e-6
    rho = {0.4: 1559.0, 0.75: 1560.0, 1.25: 1564.0, 2.1: 1537.0}  # consolidated, Ajayi Table 4.3
    text = resources.files("rotarydryer.data").joinpath("ajayi_design_load_pilot.csv").read_text("utf-8")
    rows = []
    for r in csv.DictReader(line for line in text.splitlines() if not line.startswith("#")):
        phi = float(r["dyn_angle_of_repose_deg"])
        L = entry["length"]
        rb = rho[float(r["fluid_wt_pct"])]
        baker = float(drum.design_load_area(phi)) * rb * L
        corr = float(drum.design_load_area(phi, particle_diameter=d)) * rb * L
        fuf = float(drum.holdup_area(90.0, phi)) * 1e4
        fufc = float(drum.holdup_area(90.0, phi, particle_diameter=d)) * 1e4
        rows.append((r["rpm"], r["fluid_wt_pct"], phi, float(r["design_load_kg"]), baker, corr, 1.24 * baker,
                     float(r["FUF_area_cm2"]), fuf, fufc))
    return rows


def invicta(phi: float = 45.0, d: float = 0.00085):
    drum, _ = preset_drum("invicta")
    base = float(drum.design_load_area(phi))
    corr = float(drum.design_load_area(phi, particle_diameter=d))
    return d, d / drum.flight.s1, phi, base, corr, corr / base


if __name__ == "__main__":
    print(f"surface layer k = {K:g} particle diameters\n")
    print("MMG (x_wet = 0.12 kg/kg, Ajayi Eq. 3.2 repose angle): design load per section, m^2 of cross-section")
    print("| section | d (mm) | d/s1 | phi (deg) | Baker (lee2008) | corrected | corrected / Baker | FUF holdup ratio | Ajayi 1.24 |")
    print("|---|---|---|---|---|---|---|---|---|")
    for n, d, r, phi, b, c, q, f in mmg():
        print(f"| {n} | {d * 1e3:g} | {r:.3f} | {phi:.1f} | {b:.4f} | {c:.4f} | {q:.3f} | {f:.3f} | 1.24 |")
    print("\nAjayi pilot drum, filter sand 300 um (d/s1 = 0.009): design load (kg) and FUF area (cm^2)")
    print("| rpm | fluid wt% | phi | exp. design load | Baker | corrected | 1.24 Baker | exp. FUF | model FUF | corrected FUF |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for row in pilot():
        print("| {} | {} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} |".format(*row))
    d, r, phi, b, c, q = invicta()
    print(f"\nInvicta (raw sugar d = {d * 1e3:g} mm, d/s1 = {r:.4f}, phi = {phi:g}): design load {b:.4f} -> "
          f"{c:.4f} m^2 ({100 * (q - 1):+.2f} %)")
