"""Drum photographs (Ajayi 2011 ch. 4): render a synthetic cross-section of the pilot drum from the
exact flight geometry, segment it with Ajayi's thresholds and measure the area in every flight.

Run: python examples/lab_images.py [OUTDIR]
"""

import sys
from pathlib import Path

from rotarydryer.geometry.presets import preset_drum
from rotarydryer.lab import images as im

drum, _ = preset_drum("ajayi_pilot")  # Ajayi (2011) Table 4.2: D 0.75 m, 24 flights
px_per_m = 2 * 950 / 0.75  # Appendix C scale: 25.33 px/cm
syn = im.render_cross_section(drum, 46.7, reference_angle=91.0, px_per_m=px_per_m, flight_thickness=0.002,
                              noise_sd=10.0, seed=1, mirror=True)  # his drum turned clockwise in the photos
m = im.measure(syn.image, drum, syn.calibration, reference_angle=91.0)  # thresholds 168/177, 104/120
k = m.fuf_index
print(f"image {syn.image.shape[1]} x {syn.image.shape[0]} px at {px_per_m / 100:.2f} px/cm")
print(f"FUF (flight {k}, root {m.root_angles[k]:.1f} deg): measured {m.fuf_area * 1e4:.2f} cm2, "
      f"true {syn.flight_areas[k] * 1e4:.2f} cm2, geometric model {syn.model_areas[k] * 1e4:.2f} cm2")
big = syn.flight_areas > 2e-4
err = 100 * (m.flight_areas[big] / syn.flight_areas[big] - 1)
print(f"{big.sum()} flights holding > 2 cm2: errors {err.min():+.2f} % to {err.max():+.2f} %")
print(f"TP {m.total_passive * 1e4:.1f} cm2 (true {syn.flight_areas.sum() * 1e4:.1f}), airborne "
      f"{m.airborne * 1e4:.1f} cm2 (true {syn.airborne_area * 1e4:.1f}), {100 * m.airborne_fraction:.1f} % of the region")

out = Path(sys.argv[1]) if len(sys.argv) > 1 else None
if out:
    from skimage import io

    out.mkdir(parents=True, exist_ok=True)
    io.imsave(out / "synthetic_photo.png", syn.image, check_contrast=False)
    im.annotate(syn.image, m, out / "annotated.png", dpi=150)
    print("files in", out)
