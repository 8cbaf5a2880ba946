"""Measured tracer-data CSV format: loader, validation, shipped data sets."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.published import read_published_csv
from rotarydryer.rtd import load_tracer_csv, load_tracer_dataset, parse_tracer_text, tracer_datasets, write_tracer_csv

GOOD = """# source: test data
# signal_unit: ppm
# tracer_mass_kg: 0.3
# feed_rate_kg_s: 40
a free comment line without key
time_min,signal,note
0,0.0,a
1,1.0,b
2,3.0,c
3,1.0,d
4,0.5,e
5,0.0,f
"""


def test_parse_metadata_units_and_extra_columns(tmp_path):
    text = GOOD.replace("a free comment", "# a free comment")
    p = tmp_path / "x.csv"
    p.write_text(text)
    d = load_tracer_csv(p)
    np.testing.assert_allclose(d.time_s, 60.0 * np.arange(6))
    assert d.metadata["source"] == "test data"
    assert d.metadata["tracer_mass_kg"] == 0.3 and d.metadata["signal_unit"] == "ppm"
    assert "free comment" in d.metadata["comment"]
    assert d.extra_columns["note"] == list("abcdef")
    assert d.time_column == "time_min" and d.path == str(p)
    # expected area for 100 % recovery: mass / (feed * 1e-6) in ppm*s
    assert d.expected_area() == pytest.approx(0.3 / (40 * 1e-6))


@pytest.mark.parametrize("col,factor", [("time_s", 1.0), ("time_min", 60.0), ("time_h", 3600.0)])
def test_time_units(col, factor):
    d = parse_tracer_text(f"{col},signal\n" + "".join(f"{i},{i % 3}\n" for i in range(6)))
    np.testing.assert_allclose(d.time_s, factor * np.arange(6))


def test_write_and_load_round_trip(tmp_path):
    t = np.linspace(0, 3600, 37)
    y = np.exp(-((t - 900) ** 2) / 2e5)
    p = tmp_path / "r.csv"
    write_tracer_csv(p, t, y, {"source": "round trip", "signal_unit": "1/h"}, time_unit="min")
    d = load_tracer_csv(p)
    np.testing.assert_allclose(d.time_s, t, rtol=1e-15)
    np.testing.assert_array_equal(d.signal, y)
    assert d.metadata["signal_unit"] == "1/h"


BAD = [
    ("time_s,signal\n0,1\n1,nan\n2,1\n3,1\n4,1\n", r"line 3: signal = 'nan' is NaN"),
    ("time_s,signal\n0,1\n1,-0.5\n2,1\n3,1\n4,1\n", r"line 3: negative signal"),
    ("time_s,signal\n0,1\n2,1\n1,1\n3,1\n4,1\n", r"line 4: unsorted time"),
    ("time_s,signal\n0,1\n1,1\n1,2\n3,1\n4,1\n", r"line 4: duplicate time"),
    ("time_s,signal\n0,1\n1,1\n2,1\n3,1\n", r"too few points \(4\)"),
    ("t,signal\n0,1\n1,1\n2,1\n3,1\n4,1\n", r"missing time column"),
    ("time_days,signal\n0,1\n1,1\n2,1\n3,1\n4,1\n", r"'time_days', which is not a known unit"),
    ("time_s,conc\n0,1\n1,1\n2,1\n3,1\n4,1\n", r"missing 'signal' column"),
    ("time_s,signal\n0,1\n1,abc\n2,1\n3,1\n4,1\n", r"'abc' is not a number"),
    ("time_s,time_min,signal\n0,0,1\n1,1,1\n2,2,1\n3,3,1\n4,4,1\n", r"more than one time column"),
    ("# only: metadata\n", r"no header"),
]


@pytest.mark.parametrize("text,match", BAD)
def test_validation_errors_name_the_problem(text, match):
    with pytest.raises(ValueError, match=match):
        parse_tracer_text(text, name="bad.csv")


def test_missing_file():
    with pytest.raises(ValueError, match="does not exist"):
        load_tracer_csv("/nonexistent/tracer.csv")


def test_shipped_datasets_load_and_keep_source():
    names = tracer_datasets()
    assert "lee2008_invicta" in names and {f"ajayi2011_test{k}" for k in range(1, 7)} <= set(names)
    for n in names:
        d = load_tracer_dataset(n)
        assert d.metadata["source"].startswith(("Lee (2008)", "Ajayi (2011)"))
        assert d.time_s.size >= 5 and np.all(d.signal >= 0)
    with pytest.raises(ValueError, match="is not one of"):
        load_tracer_dataset("nope")


def test_shipped_ajayi_test4_matches_published_table():
    # the shipped curve equals the gPROMS estimation data (Ajayi (2011) App. F)
    d = load_tracer_dataset("ajayi2011_test4")
    assert d.time_s.size == 42
    assert d.signal[np.argmax(d.signal)] == 51.7 and d.time_s[np.argmax(d.signal)] == 15.5 * 60
    row = next(r for r in read_published_csv("ajayi_rtd_tests_summary.csv") if r["test"] == "4")
    assert float(d.metadata["published_mean_min"]) == float(row["MRT_measured_min"])
    assert float(d.metadata["feed_rate_kg_s"]) == pytest.approx(float(row["feed_kg_wet_min"]) / 60, abs=1e-4)


def test_lee_dataset_time_origin_and_pulse():
    d = load_tracer_dataset("lee2008_invicta")
    p = d.pulse()
    assert p.kind == "rectangular" and p.duration_s == 39.6
    assert d.time_s.size == 32 and d.time_s[-1] - d.time_origin_s == 4460.0


def test_write_rejects_mismatched_lengths(tmp_path):
    with pytest.raises(ValueError, match="equal length"):
        write_tracer_csv(tmp_path / "x.csv", [0.0, 1.0, 2.0], [1.0, 2.0])


@settings(max_examples=30, deadline=None)
@given(
    dt=st.lists(st.floats(1e-3, 1e4), min_size=4, max_size=30),
    unit=st.sampled_from(["s", "min", "h"]),
    seed=st.integers(0, 1000),
)
def test_round_trip_property(tmp_path_factory, dt, unit, seed):
    t = np.cumsum([0.0, *dt])
    y = np.random.default_rng(seed).uniform(0, 10, t.size)
    p = tmp_path_factory.mktemp("rt") / "d.csv"
    write_tracer_csv(p, t, y, {"source": "property"}, time_unit=unit)
    d = load_tracer_csv(p)
    np.testing.assert_allclose(d.time_s, t, rtol=1e-12, atol=1e-9)
    np.testing.assert_array_equal(d.signal, y)


def test_a_pulse_of_zero_duration_is_a_dirac_pulse():
    """`# pulse_duration_s: 0` was refused ("must be > 0 s") though `rtd-fit --pulse-s 0` means a Dirac pulse."""
    body = "time_s,signal\n" + "".join(f"{i},{i % 3}\n" for i in range(6))
    d = parse_tracer_text("# pulse_kind: dirac\n# pulse_duration_s: 0\n" + body)
    assert d.pulse().kind == "dirac"
    assert parse_tracer_text("# pulse_duration_s: 0\n" + body).pulse().kind == "dirac"
    with pytest.raises(ValueError, match=r"pulse_duration_s = 0 s with pulse_kind = 'rectangular'"):
        parse_tracer_text("# pulse_kind: rectangular\n# pulse_duration_s: 0\n" + body, name="p.csv")
    with pytest.raises(ValueError, match=r"must be > 0 s \(0 s: a Dirac pulse\)"):
        parse_tracer_text("# pulse_duration_s: -5\n" + body, name="p.csv")
