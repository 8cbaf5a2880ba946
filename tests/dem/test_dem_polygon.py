"""The DEM bridge for flights of any shape (issue 34 item 1): polygon decks, the holdup reduction on their
pockets, and the shipped LIGGGHTS slices of a three-section and an EAD flight against the exact polygon
holdup with the finite-particle correction (no refit), within the correction's held-out accuracy."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from rotarydryer.cli import app
from rotarydryer.dem.calibrate import POLYGON_RUNS, polygon_deck
from rotarydryer.dem.deck import Particles, SliceDeck, build_slice, export_deck, facet_count, flight_facets
from rotarydryer.dem.fit import campaign_table, data_folder, load_campaign
from rotarydryer.dem.holdup import analyse_run, compare, read_reduced_csv
from rotarydryer.geometry import FlightedDrum, PolygonFlight
from rotarydryer.geometry import drum as drum_mod

from .test_dem import _synthetic_run

THREE = [(0.06, 90.0), (0.03, 135.0), (0.027, 135.0)]


@pytest.fixture(scope="module")
def poly_drum():
    return FlightedDrum(0.25, 8, PolygonFlight(THREE))


def test_polygon_deck_exports_every_section(tmp_path, poly_drum):
    s = build_slice(poly_drum, Particles(diameter=0.01), rpm=8.0, loading=1.0)
    assert s.segments == [[a, b] for a, b in THREE]
    files = export_deck(s, tmp_path / "deck")
    meta = json.loads(files.meta.read_text())
    assert meta["segments"] == [[a, b] for a, b in THREE]
    assert "sections (0.06 m, 90 deg), (0.03 m, 135 deg), (0.027 m, 135 deg)" in files.input.read_text()
    facet = s.facet_size * 0.01
    fl = flight_facets(poly_drum, s.length, facet)
    outline = [poly_drum.flight_outline(i * poly_drum.flight_spacing) for i in range(poly_drum.n_flights)]
    assert fl.shape[0] == sum(2 * math.ceil(np.linalg.norm(o[k + 1] - o[k]) / facet)
                              for o in outline for k in range(len(o) - 1))
    shell = 2 * max(48, math.ceil(2 * math.pi * 0.25 / facet))
    assert abs(facet_count(s) - shell - fl.shape[0]) <= 2 * poly_drum.n_flights * len(THREE)   # the size check's count
    # every facet lies on a flight section of the drum at angle 0
    segs = [(o[k], o[k + 1]) for o in outline for k in range(len(o) - 1)]
    pts = fl[:, :, :2].reshape(-1, 2)
    dist = np.min([np.abs(np.cross(b - a, pts - a)) / np.linalg.norm(b - a) for a, b in segs], axis=0)
    assert dist.max() < 1e-9
    back = SliceDeck.from_dict(json.loads(json.dumps(s.to_dict())))
    assert back.drum.profile.segments == poly_drum.profile.segments and back.drum.geometry == "polygon"


def test_two_section_deck_json_unchanged(tmp_path):
    from rotarydryer.geometry import TwoSectionFlight

    s = build_slice(FlightedDrum(0.2, 10, TwoSectionFlight(0.05, 0.05, 90.0, 120.0)), Particles(diameter=0.01),
                    rpm=6.0, fill_fraction=0.1)
    assert "segments" not in s.to_dict()


def test_dem_export_profile_cli(tmp_path):
    prof = tmp_path / "f.toml"
    prof.write_text("segments = [[0.06, 90.0], [0.03, 135.0], [0.027, 135.0]]\nradius = 0.25\nn_flights = 8\n")
    res = CliRunner().invoke(app, ["dem", "export", str(tmp_path / "deck"), "--profile", str(prof), "--rpm", "8",
                                   "--diameter", "0.01", "--json"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.output)["segments"] == [[a, b] for a, b in THREE]
    res = CliRunner().invoke(app, ["dem", "export", str(tmp_path / "d2"), "--profile", str(prof), "--s1", "0.1"])
    assert res.exit_code == 2 and "--profile" in res.output


def test_reduction_on_synthetic_polygon_dumps(tmp_path, poly_drum):
    folder, _ = _synthetic_run(tmp_path, FlightedDrum(0.3, 8, PolygonFlight([(0.07, 90.0), (0.035, 135.0),
                                                                             (0.03, 135.0)])))
    res = analyse_run(folder)
    assert res.deck.drum.geometry == "polygon"
    c = compare(res, repose_angle=35.0, steady=False)
    assert c["plain"]["rms_pct"] < 6.0


# ------------------------------------------------------------------ shipped LIGGGHTS slices
def _polygon_runs():
    folder = data_folder() / "polygon"
    return {p.stem: read_reduced_csv(p) for p in sorted(folder.glob("*.csv"))}


def test_polygon_runs_are_the_declared_decks():
    runs = _polygon_runs()
    assert {r.name for r in POLYGON_RUNS} == set(runs)
    for r in POLYGON_RUNS:
        shipped = runs[r.name].deck
        made = polygon_deck(r)
        assert shipped.segments == made.segments and shipped.n_particles == made.n_particles
        assert shipped.seed == made.seed and runs[r.name].liggghts_version.startswith("LIGGGHTS")
        assert shipped.particles.wall_mu == made.particles.wall_mu
        assert shipped.particles.wall_rolling_mu == made.particles.wall_rolling_mu


def _held_out():
    """Pooled and worst corrected RMS (% of a full flight) of the two-section campaign's held-out runs."""
    held = [r for r in campaign_table(load_campaign(), drum_mod.SURFACE_LAYER) if r["role"] == "held-out"]
    rms = [r["rms_corrected_pct"] for r in held]
    return math.sqrt(sum(v * v for v in rms) / len(rms)), max(rms)


def _rms(shape):
    """Corrected RMS (% of a full flight) of every slice of this flight shape with the campaign's
    particle-wall contact (p7 and p9, the EAD slices at another wall contact, are diagnostics of it)."""
    runs = _polygon_runs()
    out = {}
    for r in POLYGON_RUNS:
        if r.shape == shape and r.wall_friction is None and r.wall_rolling_friction is None:
            res = runs[r.name]
            assert res.deck.drum.geometry == "polygon" and res.deck.drum.profile.n_segments >= 3
            c = compare(res)
            assert c["corrected"]["n_samples"] > 200
            assert c["corrected"]["rms_pct"] < c["plain"]["rms_pct"]      # the correction helps on every run
            out[r.name] = c["corrected"]["rms_pct"]
    assert len(out) >= 2
    return out


def test_three_section_runs_within_the_held_out_accuracy():
    """The exact polygon holdup with the finite-particle correction (k fitted on two-section flights only)
    matches the three-section slices better than the two-section held-out pool (docs/dem.md)."""
    pool, _ = _held_out()
    rms = _rms("3S")
    assert max(rms.values()) <= pool, (rms, pool)


@pytest.mark.xfail(strict=True, reason="known miss (docs/dem.md): EAD runs 5.2 % (p2), 4.3 % (p4), 4.6 % (p5) "
                                       "and 5.0 % (p6) of a full flight, the worst two-section held-out run "
                                       "5.0 %, pooled 4.8 % against 3.7 %")
def test_ead_runs_within_the_held_out_accuracy():
    pool, worst = _held_out()
    rms = _rms("EAD")
    assert max(rms.values()) <= worst and math.sqrt(sum(v * v for v in rms.values()) / len(rms)) <= pool, rms


def test_ead_runs_figures():
    """The EAD slices' figures as documented (a regression guard on the miss above)."""
    rms = _rms("EAD")
    assert rms["p4_EAD_d020_over2_highFr"] == pytest.approx(4.26, abs=0.01)
    assert rms["p2_EAD_d020_over_highFr"] == pytest.approx(5.17, abs=0.01)
    # the same drums at the three-section runs' particle scale (d/s1 = 0.125): the miss does not come from
    # the particles' size at the edge of the calibration range
    assert rms["p5_EAD_d0125_over_highFr"] == pytest.approx(4.56, abs=0.01)
    assert rms["p6_EAD_d0125_over2_highFr"] == pytest.approx(4.98, abs=0.01)


def test_ead_miss_is_not_the_flights_wall_friction():
    """p7 is p4 with a particle-wall friction of 1.0 (45 deg, above the repose angle: no sliding on the
    flight): the EAD miss stays, with its shape (the model over-holding late, the DEM flight empty first),
    so the sliding of the last layer on the flight does not explain it (docs/dem.md); p8, a shorter last
    section, shows the same late over-prediction."""
    runs = _polygon_runs()
    base, rough = runs["p4_EAD_d020_over2_highFr"], runs["p7_EAD_d020_over2_highFr_wall1"]
    assert rough.deck.particles.wall_mu == 1.0 and base.deck.particles.wall_mu == 0.5
    pool, _ = _held_out()
    c4, c7 = compare(base), compare(rough)
    assert c7["corrected"]["rms_pct"] == pytest.approx(4.64, abs=0.01)
    assert abs(c7["corrected"]["rms_pct"] - c4["corrected"]["rms_pct"]) < 0.5 and c7["corrected"]["rms_pct"] > pool
    assert c7["dem"]["end_deg"] < c7["corrected"]["end_deg"] - 2.0
    c8 = compare(runs["p8_EADshort_d020_over2_highFr"])
    assert runs["p8_EADshort_d020_over2_highFr"].deck.drum.profile.segments[-1][0] == pytest.approx(2.4 * 0.05)
    assert c8["corrected"]["rms_pct"] == pytest.approx(3.94, abs=0.01)
    assert c8["dem"]["end_deg"] < c8["corrected"]["end_deg"] - 2.0


def test_ead_late_holdup_follows_the_particle_wall_contact():
    """p9 is p7 with a particle-wall rolling friction of 1.0 too (the spheres can neither slide nor roll on
    the flight): the DEM flight then keeps a layer on its long last section to 188 deg, 21 deg after p7's
    and 18 deg after the model's end, where p4 and p7 (the spheres free to roll on the flight) empty 2-4 deg
    before it. The EAD flight's late holdup is set by the particle-wall contact, which the continuum model
    (one repose angle from the tip) does not describe (docs/dem.md)."""
    runs = _polygon_runs()
    rough, sticky = runs["p7_EAD_d020_over2_highFr_wall1"], runs["p9_EAD_d020_over2_highFr_wall1_roll1"]
    assert sticky.deck.particles.wall_rolling_mu == 1.0 and rough.deck.particles.wall_rolling_mu == 0.1
    assert sticky.deck.particles.wall_mu == rough.deck.particles.wall_mu == 1.0
    c7, c9 = compare(rough), compare(sticky)
    assert c9["corrected"]["rms_pct"] == pytest.approx(5.62, abs=0.01)
    assert c9["corrected"]["bias_pct"] < -3.0 < c7["corrected"]["bias_pct"]     # the model now holds less
    assert c9["dem"]["end_deg"] > c9["corrected"]["end_deg"] + 15.0
    assert c9["dem"]["end_deg"] > c7["dem"]["end_deg"] + 15.0
