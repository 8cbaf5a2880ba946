"""DEM bridge and finite-particle correction (issue 15). Run: python benchmarks/bench_dem.py
(prints a Markdown table; targets: corrected holdup profile <= 2x the plain one, deck export < 2 s,
200 dump frames of 5000 particles read and reduced < 10 s)."""

import math
import tempfile
from pathlib import Path

import numpy as np
from _timing import best  # noqa: E402

from rotarydryer.dem.deck import Particles, build_slice, export_deck
from rotarydryer.dem.dumps import read_dump
from rotarydryer.geometry.presets import preset_drum


def profile_ratio(rounds=15, n=20):
    """Best of ``rounds`` interleaved rounds of ``n`` calls each (plain, corrected), per call."""
    drum, _ = preset_drum("mmg_B")
    psi = np.arange(0.0, 360.0, 0.1)
    plain, corr = [], []
    for _ in range(rounds):
        plain.append(best(lambda: [drum.holdup_area(psi, 40.0) for _ in range(n)], repeat=1) / n)
        corr.append(best(lambda: [drum.holdup_area(psi, 40.0, particle_diameter=0.012) for _ in range(n)], repeat=1) / n)
    return min(plain), min(corr)


def export_time(folder):
    drum, _ = preset_drum("ajayi_pilot")
    s = build_slice(drum, Particles(diameter=0.002), rpm=3.5, loading=1.0)
    return best(lambda: export_deck(s, folder / "deck"), repeat=3), s.n_particles


def reduce_time(tmp):
    """Read and reduce (holdup of every flight, packing, repose, airborne) 200 frames x 5000 particles."""
    from rotarydryer.dem.holdup import analyse_run
    from rotarydryer.geometry import FlightedDrum, TwoSectionFlight

    drum = FlightedDrum(0.4, 10, TwoSectionFlight(0.12, 0.12, 90.0, 120.0))
    s = build_slice(drum, Particles(diameter=0.01), rpm=5.0, fill_fraction=0.2, spinup_revolutions=1.0)
    files = export_deck(s, tmp / "reduce")
    st = s.steps()
    (files.folder / "post").mkdir()
    write_dump(files.folder / "post" / "particles.dump", half=s.radius * 1.02 + 0.02, lz=s.length, radius=0.19,
               step0=st["rotation_start"] + 1000, dstep=st["dump_every"], r_particle=0.005)
    return best(lambda: analyse_run(files.folder), repeat=1)


def write_dump(path, n=5000, frames=200, half=0.25, lz=0.04, radius=0.2, step0=1000, dstep=10, r_particle=0.005):
    rng = np.random.default_rng(1)
    with open(path, "w") as fh:
        for f in range(frames):
            r = radius * np.sqrt(rng.random(n))
            a = 2 * math.pi * rng.random(n)
            x, y, z = r * np.cos(a), r * np.sin(a), lz * rng.random(n)
            v = rng.normal(0, 0.1, (n, 3))
            fh.write(f"ITEM: TIMESTEP\n{step0 + dstep * f}\nITEM: NUMBER OF ATOMS\n{n}\nITEM: BOX BOUNDS ff ff pp\n"
                     f"{-half} {half}\n{-half} {half}\n0 {lz}\nITEM: ATOMS id type x y z vx vy vz radius\n")
            rows = np.column_stack([np.arange(1, n + 1), np.ones(n), x, y, z, v, np.full(n, r_particle)])
            np.savetxt(fh, rows, fmt="%d %d %.6g %.6g %.6g %.5g %.5g %.5g %g")


if __name__ == "__main__":
    plain, corr = profile_ratio()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        t_exp, n_exp = export_time(tmp)
        dump = tmp / "particles.dump"
        write_dump(dump)
        size = dump.stat().st_size
        t_read = best(lambda: read_dump(dump), repeat=3)
        t_reduce = reduce_time(tmp)
    print("| benchmark | result | target |")
    print("|---|---|---|")
    print(f"| holdup profile 0-360 deg at 0.1 deg (3600 angles), MMG section B: plain | {plain * 1e3:.2f} ms | - |")
    print(f"| same, with the finite-particle correction (d = 12 mm) | {corr * 1e3:.2f} ms ({corr / plain:.2f}x) | <= 2x |")
    print(f"| deck export (Ajayi pilot drum, 2 mm spheres, {n_exp} particles; STL + deck + json) | {t_exp:.3f} s | < 2 s |")
    print(f"| read 200 dump frames of 5000 particles ({size / 1e6:.0f} MB) | {t_read:.2f} s | < 10 s |")
    print(f"| read and reduce them (`rotarydryer dem holdup`: every flight's holdup, packing, repose, airborne) "
          f"| {t_reduce:.2f} s | - |")
