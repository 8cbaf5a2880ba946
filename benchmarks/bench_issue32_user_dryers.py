"""Issue 32 item 2 (globalisation): coupled steady states of random valid user dryers.

Dryers made from the `rotarydryer new` template with random drum, flight, operating, material, transport
and gas values inside engineering ranges (seeded; the flighted section's length too), as a user's own
plant would be. Each dryer's steady state from its start: converged by the pseudo-transient continuation
alone, or after the transient march (the fallback), or not at all; iterations, CPU time
(``time.process_time``, one BLAS thread, compiled kernels). Cases the schema or the model refuses up front
(a moisture outside the material's range, a cell count the forward step overshoots, an over-full drum)
are counted apart, as are those the solve refuses because the gas carries the whole feed off (reason "entrained"). Run with the tree to measure and with ``PYTHONPATH=OLD_CHECKOUT/src`` for the "before"
side, in one session:

    python benchmarks/bench_issue32_user_dryers.py [--seeds 1,2] [--n 140]
    PYTHONPATH=/tmp/before/src python benchmarks/bench_issue32_user_dryers.py

Never a pass/fail test: the machine is shared; the counts do not depend on it.
"""

from __future__ import annotations

import argparse
import math
import os
import random
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits
from typer.testing import CliRunner

import rotarydryer
from rotarydryer import Simulation, _jit
from rotarydryer.cli import app
from rotarydryer.properties.materials import list_materials, load_material

#: feed moisture ranges (kg/kg wet) of the library's materials: the range each material's laws hold for
MATERIAL_MOISTURE = {name: load_material(name).wet_range() for name in list_materials()}


def sample(rng: random.Random) -> tuple[dict, float]:
    """(case overrides, flighted section length m) of one random dryer."""
    def u(a, b):
        return rng.uniform(a, b)

    def lu(a, b):
        return math.exp(rng.uniform(math.log(a), math.log(b)))
    radius = u(0.6, 2.5)
    s1 = u(0.06, 0.18) * radius
    material = rng.choice(sorted(MATERIAL_MOISTURE))
    ov = {"drum.radius": radius, "drum.slope": u(1, 5), "drum.n_flights": rng.randint(10, 30), "flight.s1": s1,
          "flight.s2": rng.choice([0.0, u(0.3, 1.0) * s1]), "flight.alpha2": u(100, 150),
          "operating.feed_rate": lu(0.5, 30) * radius**2, "operating.rpm": u(1.5, 7),
          "operating.feed_moisture": u(*MATERIAL_MOISTURE[material]), "operating.feed_temperature": u(5, 60),
          "material.name": material, "transport.model": rng.choice(["lee2008", "sheehan2005_model2", "ajayi2011"]),
          "gas.direction": rng.choice(["co-current", "counter-current"]), "gas.flow": lu(1, 20) * radius**2,
          "gas.inlet_temperature": u(90, 600), "gas.inlet_humidity": u(0.005, 0.08),
          "shell.insulation_thickness": rng.choice([0.0, u(0.02, 0.1)])}
    return ov, u(4, 25)


def sample_classes(rng: random.Random) -> dict:
    """Size-class overrides of one random dryer (``--classes``): a log-normal feed (median 0.1-3 mm, geometric
    spread 1.3-3) in 2-8 equal-mass classes, or a shipped sieve analysis; the gas carries the fines off
    (entrainment) in three dryers of four."""
    ps = {"particle_size.classes": rng.randint(2, 8), "particle_size.entrainment": rng.random() < 0.75}
    if rng.random() < 0.3:
        ps["particle_size.dataset"] = rng.choice(["lee2008_filter_sand", "lee2008_zeolite", "lee2008_fine_river_sand"])
    else:
        ps.update({"particle_size.distribution": "lognormal",
                   "particle_size.d50": math.exp(rng.uniform(math.log(1e-4), math.log(3e-3))),
                   "particle_size.sigma_g": rng.uniform(1.3, 3.0)})
    return ps


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--n", type=int, default=140, help="dryers per seed")
    ap.add_argument("--list", action="store_true", help="print the dryers that needed the march or failed")
    ap.add_argument("--classes", action="store_true", help="size classes too (`sample_classes`): a fine feed the gas "
                                                           "partly carries off")
    a = ap.parse_args()
    warnings.simplefilter("ignore")
    _jit.long_runs()
    tmp = tempfile.TemporaryDirectory()
    folder = Path(tmp.name)
    res = CliRunner().invoke(app, ["new", "mydryer", "--out", str(folder / "mydryer.toml")])
    assert res.exit_code == 0, res.output
    template = (folder / "mydryer.toml").read_text()
    assert "length = 11.0" in template
    rows, refused, entrained = [], 0, 0
    with threadpool_limits(1):
        for seed in (int(s) for s in a.seeds.split(",")):
            rng = random.Random(seed)
            for i in range(a.n):
                ov, length = sample(rng)
                if a.classes:
                    ov.update(sample_classes(rng))
                path = folder / f"d{seed}_{i}.toml"
                path.write_text(template.replace("length = 11.0", f"length = {length:.3f}"))
                try:
                    dryer = Simulation(str(path), ov).dryer()
                except ValueError:     # refused up front, with its reason (schema or model)
                    refused += 1
                    continue
                t = time.process_time()
                # (CPU s, iterations, marched or failed, converged)
                try:
                    ss = dryer.steady_state()
                    rows.append((time.process_time() - t, ss.iterations, float(ss.marched_s or 0.0) > 0, True))
                except (ValueError, RuntimeError, FloatingPointError) as exc:
                    if getattr(exc, "reason", None) == "entrained":     # the whole feed as dust: refused, with it
                        entrained += 1
                        if a.list:
                            print(f"seed {seed} dryer {i}: refused by the solve (entrained); {ov}", flush=True)
                        continue
                    rows.append((time.process_time() - t, 0, True, False))
                if a.list and rows[-1][2]:
                    print(f"seed {seed} dryer {i}: {'marched' if rows[-1][3] else 'failed'}; flighted length "
                          f"{length:.3f} m; {ov}", flush=True)
    tmp.cleanup()
    cpu = np.array([r[0] for r in rows])
    it = np.array([r[1] for r in rows if r[3] and not r[2]] or [0])
    marched = sum(1 for r in rows if r[2] and r[3])
    failed = sum(1 for r in rows if not r[3])
    print(f"{rotarydryer.__file__}: load {os.getloadavg()[0]:.2f}; {len(rows)} dryers solved ({refused} refused up "
          f"front, {entrained} by the solve: the whole feed as dust): {len(rows) - marched - failed} by continuation alone, {marched} after the march, {failed} "
          f"not; iterations (continuation alone) median {np.median(it):.0f}, 90th percentile "
          f"{np.percentile(it, 90):.0f}, largest {it.max()}; CPU per dryer median {np.median(cpu) * 1e3:.0f} ms, "
          f"90th percentile {np.percentile(cpu, 90) * 1e3:.0f} ms, largest {cpu.max():.2f} s, all {cpu.sum():.1f} s",
          flush=True)


if __name__ == "__main__":
    main()
