"""The DEM calibration campaign of the finite-particle correction (issue 15, docs/dem.md).

    python examples/dem_calibration.py OUT          # write the campaign's LIGGGHTS decks into OUT and
                                                    # print the fit on the shipped reduced runs (fast)
    python examples/dem_calibration.py OUT --run    # also run LIGGGHTS (about an hour on 2 cores),
                                                    # reduce the dumps into src/rotarydryer/data/dem/
                                                    # and fit again (extra options: see
                                                    # python -m rotarydryer.dem.calibrate --help)
"""

import sys

from rotarydryer.dem import calibrate
from rotarydryer.dem.fit import fit_report

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 and not sys.argv[1].startswith("-") else "dem_work"
    extra = [a for a in sys.argv[2:] if a != "--run"]
    if "--run" in sys.argv:
        raise SystemExit(calibrate.main(["--work", out, "--jobs", "2"] + extra))
    calibrate.main(["--work", out, "--export-only"])
    print(f"campaign decks written to {out}/ ({', '.join(r.name for r in calibrate.RUNS)})")
    print(fit_report())
