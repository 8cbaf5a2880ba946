"""Flight geometry of the Invicta dryer: transition points, holdup profile, cascade, design load.

Run: python examples/flight_geometry.py [OUTDIR]
"""

import sys
from pathlib import Path

import numpy as np

from rotarydryer.geometry import FlightedDrum, TwoSectionFlight
from rotarydryer.report.plots import draw_cross_section, plot_unloading_profile

drum = FlightedDrum(2.5, 28, TwoSectionFlight(0.195, 0.183, 90.0, 117.0))
print("tip radius %.5f m, tip angle %.4f deg" % (drum.tip_radius, drum.tip_angle))
for phi in (30.0, 60.0):
    print("phi = %g: psi1..psi5 =" % phi, np.round([float(a) for a in drum.transition_angles(phi)], 1))

phi = np.array([30.0, 40.0, 50.0, 55.0])
cs = drum.cascade(phi, rpm=3.0, slope=2.8)
load = drum.design_load_area(phi) * 940 * 12
for row in zip(phi, cs.mean_release_angle, cs.mean_fall_height, cs.mean_fall_time, cs.passive_time, load):
    print("phi %4.0f  psi_m %6.1f deg  h_m %.3f m  t_a %.3f s  t_p %.2f s  design load %6.0f kg" % row)

out = Path(sys.argv[1]) if len(sys.argv) > 1 else None
if out:
    out.mkdir(parents=True, exist_ok=True)
    plot_unloading_profile(drum, 50.0, 3.0).savefig(out / "flight_profile.png", dpi=100)
    draw_cross_section(drum, 50.0).savefig(out / "cross_section.png", dpi=100)
    print("plots in", out)
