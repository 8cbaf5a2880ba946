"""Bad-input corpus for ``rotarydryer dem`` (issue 15): too-large particles, impossible decks, decks
LIGGGHTS rejects, missing LIGGGHTS, dumps from another geometry, files that are not dumps.

Each case runs the real command and checks the contract (exit 2, ``error:`` naming the option or
file, no traceback); the export and holdup cases also check that nothing was written."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from .conftest import assert_bad, run_cli, snapshot

DIMS = ["--radius", "0.1", "--n-flights", "8", "--s1", "0.03", "--s2", "0.025", "--rpm", "12"]
SMALL = ["--settle-time", "0.1", "--spinup", "0.05", "--revolutions", "0.05", "--dump-every", "5"]

EXPORT_CASES = [
    # id, args after "dem export out", fragments
    ("particle-larger-than-quarter-base", DIMS + ["--diameter", "0.01"],
     ["--diameter", "0.01 m", "larger than a quarter of the flight base", "s1 = 0.03 m", "(0, 0.0075] m"]),
    ("case-and-dimensions", ["--case", "lee2008_invicta"] + DIMS, ["either --case", "not both"]),
    ("missing-dimensions", ["--radius", "0.1", "--rpm", "12"], ["missing --n-flights, --s1, --s2"]),
    ("unknown-section", ["--case", "ajayi2011_mmg", "--section", "Z", "--scale", "0.25", "--diameter", "0.002"],
     ["--section = 'Z'", "B, C, D"]),
    ("section-needed", ["--case", "ajayi2011_mmg", "--diameter", "0.002"], ["--section is needed", "B, C, D"]),
    ("above-critical-speed", DIMS[:-2] + ["--rpm", "120", "--diameter", "0.005"],
     ["rpm (--rpm) = 120 rev/min", "critical speed"]),
    ("negative-loading", DIMS + ["--diameter", "0.005", "--loading", "-1"], ["loading (--loading) = -1", "(0, 5]"]),
    ("overlapping-flights", ["--radius", "0.1", "--n-flights", "40", "--s1", "0.03", "--s2", "0.03", "--rpm", "12",
                             "--diameter", "0.005"], ["flights overlap their neighbours"]),
    ("restitution-above-one", DIMS + ["--diameter", "0.005", "--restitution", "1.5"],
     ["restitution (--restitution) = 1.5", "(0, 1)"]),
    ("nan-friction", DIMS + ["--diameter", "0.005", "--friction", "nan"], ["sliding friction (--friction)", "nan"]),
]


@pytest.mark.parametrize("case_id,args,fragments", EXPORT_CASES, ids=[c[0] for c in EXPORT_CASES])
def test_export_bad_input(workdir, case_id, args, fragments):
    before = snapshot(workdir)
    res = run_cli(["dem", "export", "out"] + args, cwd=workdir)
    assert_bad(res, *fragments)
    assert snapshot(workdir) == before, "the failing export wrote something"
    assert not (workdir / "out").exists()


def test_export_of_a_case_with_one_flighted_section_takes_it(workdir):
    """A case of one flighted section needed ``--section`` naming it (found by an acceptance check): it is taken."""
    res = run_cli(["dem", "export", "out", "--case", "song2003_ottawa", "--diameter", "0.002"] + SMALL, cwd=workdir)
    assert res.exit_code == 0, res.output
    assert (workdir / "out" / "in.drum").exists()


@pytest.fixture
def deck_folder(workdir):
    res = run_cli(["dem", "export", "slice"] + DIMS + ["--diameter", "0.006"] + SMALL, cwd=workdir)
    assert res.exit_code == 0, res.output
    return workdir / "slice"


def test_run_without_deck(workdir):
    (workdir / "empty").mkdir()
    before = snapshot(workdir)
    assert_bad(run_cli(["dem", "run", "empty"], cwd=workdir), "'empty' holds no deck", "rotarydryer dem export")
    assert snapshot(workdir) == before


def test_run_without_liggghts(deck_folder, monkeypatch):
    monkeypatch.setenv("ROTARYDRYER_LIGGGHTS", "/nonexistent/liggghts")
    before = snapshot(deck_folder)
    assert_bad(run_cli(["dem", "run", str(deck_folder)]), "LIGGGHTS is not installed", "apt-get install liggghts")
    assert snapshot(deck_folder) == before


def test_run_bad_np(deck_folder):
    assert_bad(run_cli(["dem", "run", str(deck_folder), "--np", "0"]), "np (--np) = 0", "1 to 256")


def test_deck_liggghts_rejects(deck_folder):
    from rotarydryer.dem.run import find_liggghts

    if find_liggghts() is None:
        pytest.skip("LIGGGHTS is not installed (apt-get install liggghts)")
    deck = deck_folder / "in.drum"
    text = deck.read_text().replace("pair_style      gran model hertz", "pair_style      gran model nosuchmodel")
    deck.write_text(text)
    res = run_cli(["dem", "run", str(deck_folder), "--quiet", "--timeout", "60"])
    assert_bad(res, "LIGGGHTS rejected the deck", "in.drum", "pair_style")


def test_holdup_without_dumps(deck_folder):
    before = snapshot(deck_folder)
    assert_bad(run_cli(["dem", "holdup", str(deck_folder)]), "particles.dump", "does not exist", "dem run")
    assert snapshot(deck_folder) == before


def test_holdup_not_a_dump(deck_folder):
    (deck_folder / "post").mkdir(exist_ok=True)
    (deck_folder / "post" / "particles.dump").write_text("time,x,y\n0,1,2\n")
    before = snapshot(deck_folder)
    assert_bad(run_cli(["dem", "holdup", str(deck_folder), "--csv", str(deck_folder / "r.csv")]),
               "particles.dump", "not a LIGGGHTS dump file")
    assert snapshot(deck_folder) == before


def _fake_dump(folder: Path, half: float, lz: float, r: float, steps: int) -> None:
    frames = []
    for k in range(3):
        frames.append(f"ITEM: TIMESTEP\n{steps + k}\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS ff ff pp\n"
                      f"{-half} {half}\n{-half} {half}\n0 {lz}\nITEM: ATOMS id type x y z vx vy vz radius\n"
                      f"1 1 0.0 -0.05 0.01 0 0 0 {r}\n2 1 0.01 -0.05 0.01 0 0 0 {r}\n")
    (folder / "post").mkdir(exist_ok=True)
    (folder / "post" / "particles.dump").write_text("".join(frames))


def test_holdup_dumps_from_another_geometry(deck_folder):
    meta = json.loads((deck_folder / "deck.json").read_text())
    start = meta["derived"]["steps"]["rotation_start"]
    _fake_dump(deck_folder, 0.5, meta["derived"]["slice_length_m"], 0.003, start + 10)  # a 0.5 m box, not 0.104 m
    before = snapshot(deck_folder)
    assert_bad(run_cli(["dem", "holdup", str(deck_folder)]), "comes from another geometry", "R = 0.1 m")
    assert snapshot(deck_folder) == before


def test_holdup_dumps_with_other_particles(deck_folder):
    meta = json.loads((deck_folder / "deck.json").read_text())
    half = 0.1 * 1.02 + 2 * 0.006
    _fake_dump(deck_folder, half, meta["derived"]["slice_length_m"], 0.004, meta["derived"]["steps"]["rotation_start"])
    assert_bad(run_cli(["dem", "holdup", str(deck_folder)]), "another deck", "particle radius 0.004 m", "0.003 m")


def test_holdup_bad_surface_layer(deck_folder):
    assert_bad(run_cli(["dem", "holdup", str(deck_folder), "--surface-layer", "-1"]),
               "--surface-layer (surface_layer) = -1", "[0, 20]")


def test_holdup_not_a_deck_json(workdir):
    (workdir / "run").mkdir()
    (workdir / "run" / "deck.json").write_text('{"format": "something else"}')
    assert_bad(run_cli(["dem", "holdup", "run"], cwd=workdir), "deck.json", "not 'rotarydryer-dem-slice/1'")
