"""A case's flights of any shape (issue 34 item 1): ``[flight] segments`` / ``vertices`` and per section."""

import re
from pathlib import Path

import pytest

from rotarydryer.cases import load_case
from rotarydryer.cases.build import ajayi_geometries
from rotarydryer.simulation import Simulation

TEMPLATE = Path(__file__).resolve().parents[1] / "src" / "rotarydryer" / "cases" / "templates" / "dryer.toml"
THREE = "segments = [[0.15, 90.0], [0.06, 150.0], [0.05, 150.0]]"


def _case(tmp_path, flight_block, section_extra=""):
    text = TEMPLATE.read_text()
    text = re.sub(r"\[flight\].*?\n\n", f"[flight]\n{flight_block}\n\n", text, count=1, flags=re.S)
    if section_extra:
        text = text.replace('name = "flighted"\nkind = "flighted"', f'name = "flighted"\nkind = "flighted"\n{section_extra}')
    p = tmp_path / "poly.toml"
    p.write_text(text)
    return p


def test_flight_segments_run_a_dryer(tmp_path):
    p = _case(tmp_path, THREE)
    case = load_case(str(p))
    g = ajayi_geometries(case)["flighted"]
    assert g.drum.geometry == "polygon" and g.drum.profile.n_segments == 3
    s = Simulation(str(p)).steady_state().summary()
    assert s["total_holdup_kg"] > 0


def test_section_vertices_override_the_flight(tmp_path):
    p = _case(tmp_path, "s1 = 0.15\ns2 = 0.10\nalpha1 = 90.0\nalpha2 = 120.0",
              "vertices = [[0.0, 0.0], [0.0, 0.15], [0.05, 0.2], [0.1, 0.2]]")
    drum = ajayi_geometries(load_case(str(p)))["flighted"].drum
    assert drum.profile.n_segments == 3 and drum.geometry == "polygon"


@pytest.mark.parametrize("flight,section,words", [
    (THREE + "\ns1 = 0.1", "", ["flight", "segments and s1"]),
    ("segments = [[0.15, 90.0], [0.1, 20.0], [0.1, 20.0]]", "", ["flight.segments", "intersects itself"]),
    ("segments = [[0.15, 90.0], [-0.1, 150.0]]", "", ["flight.segments"]),
    ("segments = [[0.6, 90.0], [0.6, 150.0], [0.5, 150.0]]", "", ["flight.segments", "centre"]),
    (THREE, "s1 = 0.2", ["sections[1] (flighted).s2 is missing"]),
    # the schema's bounds with their interval (found by fuzzing: "Input should be a finite number" alone)
    ("segments = [[0.15, 90.0], [nan, 150.0]]", "", ["flight.segments.1.0 = nan", "allowed range (0, 100] m"]),
    ("segments = [[0.15, 90.0], [0.1, 360.0]]", "", ["flight.segments.1.1 = 360.0", "allowed range (0, 360) deg"]),
    ("vertices = [[0.0, 0.0], [0.0, 150.0]]", "", ["flight.vertices.1.1 = 150.0", "allowed range [-100, 100] m"]),
])
def test_bad_polygon_flights_name_the_key(tmp_path, flight, section, words):
    p = _case(tmp_path, flight, section)
    with pytest.raises(ValueError) as exc:
        case = load_case(str(p))
        ajayi_geometries(case)
    msg = str(exc.value)
    assert all(w in msg for w in words), msg


def test_regressions_refuse_a_polygonal_flight(tmp_path):
    p = _case(tmp_path, THREE)
    with pytest.raises(ValueError, match="lee2008_regressions"):
        ajayi_geometries(load_case(str(p), {"geometry.method": "lee2008_regressions"}))


def test_report_draws_polygonal_flights(tmp_path):
    from rotarydryer.report.figures import case_drums

    drums = case_drums(load_case(str(_case(tmp_path, THREE))).model_dump())
    assert [d["drum"].geometry for d in drums] == ["polygon"]


def test_a_flight_set_one_way_replaces_the_files_other_way():
    """``--set flight.segments=[...]`` on a case whose file gives s1..alpha2 was refused as "both given" (it took four
    more ``--set flight.s1=none`` ...); found by an acceptance check. The override's way replaces the file's; the same
    flight as a polyline gives the same state; both ways given by the overrides are refused."""
    base = Simulation("lee2008_invicta").steady_state().summary()
    f = load_case("lee2008_invicta").flight
    seg = [[f.s1, f.alpha1], [f.s2, f.alpha2]]
    case = load_case("lee2008_invicta", {"flight.segments": seg})
    assert case.flight.s1 is None and case.flight.segments is not None
    poly = Simulation("lee2008_invicta", {"flight.segments": seg}).steady_state().summary()
    assert poly["total_holdup_kg"] == pytest.approx(base["total_holdup_kg"], rel=1e-12)
    # both ways given by the overrides themselves: refused, naming them
    with pytest.raises(ValueError, match="segments and s1, s2, alpha1, alpha2 are both given"):
        load_case("lee2008_invicta", {"flight.segments": seg, "flight.s1": f.s1, "flight.s2": f.s2,
                                      "flight.alpha1": f.alpha1, "flight.alpha2": f.alpha2})


def test_a_bad_flight_list_given_by_set_is_blamed_on_the_set_option():
    """A bad item of ``--set flight.segments=[...]`` was named as the case file's line of [flight]."""
    with pytest.raises(ValueError, match=r"--set flight.segments: flight.segments.1.0 = 0.0: .*greater than 0"):
        load_case("lee2008_invicta", {"flight.segments": "[[0.15, 90.0], [0.0, 120.0]]"})


def test_one_two_section_key_on_a_polygonal_case_is_named_as_both_given(tmp_path):
    """One of s1..alpha2 by --set on a case whose file gives a polygonal flight stays a conflict named by its --set
    (a review found it had removed the file's segments and blamed the file for the missing s2, alpha1, alpha2); all
    four replace the polygon."""
    p = str(_case(tmp_path, THREE))
    assert load_case(p).flight.segments is not None
    with pytest.raises(ValueError, match=r"--set flight.s1: flight: segments and s1 are both given"):
        load_case(p, {"flight.s1": 0.1})
    four = load_case(p, {"flight.s1": 0.15, "flight.s2": 0.1, "flight.alpha1": 90.0, "flight.alpha2": 120.0})
    assert four.flight.segments is None and four.flight.s1 == 0.15
