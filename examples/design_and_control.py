"""Task: size a raw-sugar dryer for a duty, and hold the MMG dryer's product moisture in closed loop
(docs/design_control.md).

1. Design: 20 kg/s raw sugar, 1.0 -> 0.1 % wet basis, counter-current air at 100 degC; the drum
   of least volume within the constraints (critical speed, entrainment, fill, design load, L/D),
   with its binding constraints.
2. Control: MMG Test 4, +20 % feed moisture (dry basis); PI (SIMC) + feed-forward on the gas
   inlet temperature and the feed rate vs the uncontrolled dryer (a short run: 1 h, 120 s samples).

Run: python examples/design_and_control.py [OUTDIR]
"""

import sys
from pathlib import Path

from rotarydryer import Simulation
from rotarydryer import control as C
from rotarydryer import design as D

# 1. design
res = D.design(D.raw_sugar_duty(), objective="volume", maxiter=30)
b = res.best
print(f"raw sugar: D {b.diameter_m:.2f} m x L {b.length_m:.2f} m, slope {b.slope_deg:.2f} deg, {b.rpm:.2f} rpm, "
      f"{b.n_flights} flights (s1 {b.s1_m:.3f} m, s2 {b.s2_m:.3f} m, alpha2 {b.alpha2_deg:.0f} deg)")
print(f"  volume {b.values['volume_m3']:.1f} m3, binding: {', '.join(b.binding()) or 'none'} "
      f"({res.evaluations} evaluations, {res.seconds:.1f} s)")

# 2. control
dryer = Simulation("ajayi2011_mmg", {"operating.test": 4}).thermal_dryer()
steady = dryer.steady_state()
models = C.identify(dryer, steady, duration_s=3600.0)
cfg = C.ControlConfig(sample_time_s=120.0)
kw = dict(scenario="feed_moisture_step", magnitude=0.2, t_end_s=3600.0, t_step_s=240.0, models=models, config=cfg)
closed = C.closed_loop(dryer, steady, **kw)
opened = C.closed_loop(dryer, steady, controlled=False, **kw)
for name, r in (("closed loop", closed), ("open loop", opened)):
    p = r.performance
    print(f"{name}: max |deviation| {100 * p['max_abs_deviation']:.2f} percentage points, IAE {p['iae']:.3g}")
print(f"tuning: Kc {closed.tuning['kc']:.3g}, tau_I {closed.tuning['tau_i_s']:.0f} s "
      f"(gain margin {closed.tuning['gain_margin']:.2f})")

if len(sys.argv) > 1:
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    C.plot(closed, opened).savefig(out / "closed_loop.png", dpi=80)
    print("picture:", out / "closed_loop.png")
