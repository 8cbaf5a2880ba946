"""Flight-unloading rig (Lee 2008 ch. 5): synthetic run, FIR filter, start of unloading,
repose-angle fit with a CI, and Lee's +/- 2 SD band.

Run: python examples/lab_rig.py [OUTDIR]
"""

import sys
from pathlib import Path

from rotarydryer.lab import flight_rig as fr

drum = fr.rig_drum("alternative")  # Lee (2008) Table 5.1: s1 0.15 m, s2 0.18 m, 100 deg, flat back
phi, sd = 39.6, 1.7  # Table 5.5, experiment 6 (Alternative flight, filter sand, 2 rpm)
rho = 1474.0  # Table 5.2, consolidated bulk density of filter sand, kg/m3
run = fr.synthetic_run(drum, phi, rpm=2.0, start_angle=93.5, bulk_density=rho, seed=6,
                       noise_sd=0.1, noise_correlation=0.5)
print(f"synthetic run: {run.time.size} samples at {run.sample_rate:g} Hz, true start 2.000 s, true angle {phi} deg")
for cutoff in (fr.LEE_CUTOFF_CODE, fr.LEE_CUTOFF_TEXT):
    for phase in ("zero", "causal"):
        ts = fr.detect_unloading_start(run.time, run.mass, cutoff=cutoff, phase=phase)
        lee = fr.detect_unloading_start(run.time, run.mass, cutoff=cutoff, phase=phase, method="lee2008")
        print(f"  FIR {cutoff:g} Hz, {phase:6s}: start {ts:.3f} s (hinge fit), {lee:.3f} s (Lee's first-positive-rate rule)")
fit = fr.fit_repose_angle(run, drum, rpm=2.0, start_angle=93.5, bulk_density=rho)
lo, hi = fit.repose_angle_ci
print(f"fitted repose angle {fit.repose_angle:.2f} deg, 95 % CI {lo:.2f}-{hi:.2f} "
      f"(residual SD {fit.residual_sd:.3f} kg, lag-1 autocorrelation {fit.ar1:.2f})")
a = fr.analyse_run(run, drum, rpm=2.0, start_angle=93.5, bulk_density=rho, repose_angle=phi, repose_sd=sd, fit=False)
print(f"Lee's criterion, band {a.band.repose_low:.1f}-{a.band.repose_high:.1f} deg: "
      f"{100 * a.inside_mass:.1f} % of mass samples, {100 * a.inside_rate:.1f} % of rate samples inside")

out = Path(sys.argv[1]) if len(sys.argv) > 1 else None
if out:
    out.mkdir(parents=True, exist_ok=True)
    fr.write_rig_csv(out / "synthetic_run.csv", run, comment="synthetic rig run, Alternative flight, 2 rpm")
    fr.plot_analysis(a).savefig(out / "rig_band.png", dpi=100)
    print("files in", out)
