"""Bounds on the resource options (issue "Reliability under hostile and ordinary input", part A).

Every option that sets how much work or how many processes, files or bytes a command makes is
refused (exit 2, one ``error:`` line naming the option, the value and the bound) or clamped with a
``warning:`` naming the option and the bound; a refused input returns at once and leaves nothing
behind."""

from __future__ import annotations

import time

import pytest

from rotarydryer import _workers
from rotarydryer.services import _options
from rotarydryer.services._options import check_scheduler, check_workers

from .conftest import assert_bad, run_cli, snapshot

FAST = ["--set", "thermal.enabled=false", "--no-rtd"]
DIMS = ["--radius", "0.2", "--n-flights", "10", "--s1", "0.05", "--s2", "0.05", "--rpm", "6.7"]


# ------------------------------------------------------------------------------ --workers
def test_check_workers_clamps_to_cpus_and_runs(monkeypatch):
    monkeypatch.setattr(_workers, "usable_cpus", lambda: 2)       # where check_workers reads it
    n, notes = check_workers(50, 2)
    assert n == 2 and len(notes) == 1 and "--workers = 50" in notes[0] and "2 usable CPU cores" in notes[0]
    n, notes = check_workers(100000, 1)
    # one warning with the number used (it gave "using 2", then "using 1"; found by review)
    assert n == 1 and notes == ["--workers = 100000 is more than the 2 usable CPU cores and the 1 runs; using 1"]
    assert check_workers(0, 10) == (2, [])           # 0: one per core, no warning
    assert check_workers(1, 10) == (1, [])
    n, notes = check_workers(2, 1)
    assert n == 1 and notes == ["--workers = 2 is more than the 1 runs; using 1"]
    # the range as the option takes it: above the cores is taken (capped, with a warning), so not [0, 2] (-1 was
    # "outside [0, 2]" while 1000 ran on 2; found by an acceptance check)
    with pytest.raises(ValueError, match=r"--workers = -1 is outside the allowed range \[0, inf\) \(0: one per core; "
                                         r"more than the 2 usable CPU cores run as 2, with a warning\)"):
        check_workers(-1, 10)
    with pytest.raises(ValueError, match=r"--jobs = 1.5 is not a whole number in the allowed range \[0, inf\)"):
        check_workers(1.5, 10, option="--jobs")
    # a Dask cluster has its own workers: no clamp to the local cores, never a warning
    assert check_workers(64, 100, scheduler="tcp://h:8786") == (64, [])


def test_sweep_workers_clamped_with_warning():
    t0 = time.perf_counter()
    res = run_cli(["sweep", "song2003_ottawa", "--grid", "operating.rpm=4", *FAST, "--workers", "100000"])
    assert time.perf_counter() - t0 < 30
    assert res.exit_code == 0, res.output
    assert "warning: --workers = 100000 is more than the" in res.output and "usable CPU cores" in res.output
    assert "Traceback" not in res.output


@pytest.mark.parametrize("cmd", [
    ["sweep", "song2003_ottawa", "--grid", "operating.rpm=3,4", *FAST],
    ["sensitivity", "song2003_ottawa", "--set", "thermal.enabled=false", "--param", "operating.rpm=3,5",
     "--samples", "4"],
], ids=["sweep", "sensitivity"])
def test_negative_workers_refused(cmd):
    assert_bad(run_cli([*cmd, "--workers", "-1"]), "--workers = -1", "allowed range [0,")


# ------------------------------------------------------------------------------ --scheduler
SCHEDULERS = [
    ("inproc", "inproc://", ["--scheduler", "inproc://", "not a scheduler address", "tcp://HOST:PORT"]),
    ("no-port", "tcp://host", ["--scheduler", "tcp://host", "tcp://HOST:PORT"]),
    ("port-out-of-range", "tcp://h:99999", ["--scheduler", "99999", "1-65535"]),
    ("port-word", "tcp://h:port", ["--scheduler", "'port'", "1-65535"]),
    ("empty", "", ["--scheduler", "''"]),
    ("udp", "udp://h:8786", ["--scheduler", "udp://", "not supported"]),
]


@pytest.mark.parametrize("value,fragments", [c[1:] for c in SCHEDULERS], ids=[c[0] for c in SCHEDULERS])
@pytest.mark.parametrize("cmd", [
    ["sweep", "song2003_ottawa", "--grid", "operating.rpm=3,4", *FAST],
    ["sensitivity", "song2003_ottawa", "--set", "thermal.enabled=false", "--param", "operating.rpm=3,5",
     "--samples", "4"],
], ids=["sweep", "sensitivity"])
def test_bad_scheduler_refused_at_once(cmd, value, fragments):
    t0 = time.perf_counter()
    res = run_cli([*cmd, "--scheduler", value])
    assert time.perf_counter() - t0 < 30
    assert_bad(res, *fragments)
    assert len([ln for ln in res.output.splitlines() if ln.startswith("error:")]) == 1


def test_scheduler_forms_accepted():
    for a in ("tcp://10.0.0.5:8786", "tls://cluster:8786", "cluster:8786", "tcp://[::1]:8786", None):
        assert check_scheduler(a) == a


# ------------------------------------------------------------------------------ dem export
DEM = [
    ("seed-huge", ["--diameter", "0.01", "--seed", "99999999999999999999"],
     ["--seed", "99999999999999999999", "0 to 2000000000"]),
    ("seed-negative", ["--diameter", "0.01", "--seed", "-1"], ["--seed", "-1", "0 to 2000000000"]),
    ("diameter-tiny", ["--diameter", "1e-6"], ["--diameter", "1e-06", "200000 particles", "--diameter >="]),
    ("dump-every-below-a-step", ["--diameter", "0.01", "--dump-every", "1e-9"],
     ["--dump-every", "1e-09", "allowed range [0.00"]),
    ("dump-volume", ["--diameter", "0.01", "--revolutions", "20", "--dump-every", "0.01"],
     ["--dump-every", "dump rows", "10000000"]),
    ("facets", ["--diameter", "2e-6", "--loading", "1e-6"], ["--diameter", "facets", "400000"]),
]


@pytest.mark.parametrize("args,fragments", [c[1:] for c in DEM], ids=[c[0] for c in DEM])
def test_dem_export_refused_leaves_no_deck(workdir, args, fragments):
    t0 = time.perf_counter()
    res = run_cli(["dem", "export", "deck", *DIMS, *args], cwd=workdir)
    assert time.perf_counter() - t0 < 30
    assert_bad(res, *fragments)
    assert snapshot(workdir) == {} and not (workdir / "deck").exists()


def test_dem_export_library_bounds():
    from rotarydryer.dem.deck import MAX_PARTICLES, Particles, build_slice
    from rotarydryer.geometry import FlightedDrum, TwoSectionFlight

    drum = FlightedDrum(0.2, 10, TwoSectionFlight(0.05, 0.05, 90.0, 120.0))
    with pytest.raises(ValueError, match=f"the limit is {MAX_PARTICLES} particles"):
        build_slice(drum, Particles(diameter=1e-4), rpm=6.7, loading=1.0)
    with pytest.raises(ValueError, match="seed"):
        build_slice(drum, Particles(diameter=0.008), rpm=6.7, loading=1.0, seed=2**40)
    s = build_slice(drum, Particles(diameter=0.008), rpm=6.7, loading=1.0, seed=2_000_000_000)
    from rotarydryer.dem.deck import _prime_seed

    t0 = time.perf_counter()
    assert _prime_seed(s.seed) > 10000 and time.perf_counter() - t0 < 2


# ------------------------------------------------------------------------------ sensitivity
SENS = ["sensitivity", "song2003_ottawa", "--set", "thermal.enabled=false", "--param", "operating.rpm=3,5"]


@pytest.mark.parametrize("n,near", [("3", "use 2 or 4"), ("100", "use 64 or 128"), ("7", "use 4 or 8")])
def test_sensitivity_samples_not_power_of_two_refused(n, near):
    assert_bad(run_cli([*SENS, "-n", n]), f"--samples = {n}", "not a power of 2", near)


@pytest.mark.parametrize("seed", ["-1", "4294967296"])
def test_sensitivity_seed_names_option(seed):
    assert_bad(run_cli([*SENS, "-n", "4", "--seed", seed]), f"--seed = {seed}", "0 to 4294967295")


# ------------------------------------------------------------------------------ lab steps
HEAD = "time_s,feed_kg_min,discharge_kg_min\n"


@pytest.mark.parametrize("text,fragments", [
    (HEAD + "0,0,0\n0,1e300,0\n60,1e300,1e299\n120,1e300,3e299\n180,0,0\n",
     ["rec.csv line 3", "feed_kg_min = 1e+300", "[0, 600000]", "10000 kg/s"]),
    (HEAD + "0,0,0\n60,6,1e300\n120,6,3\n", ["rec.csv line 3", "discharge_kg_min = 1e+300", "[0, 600000]"]),
    ("time_s,fed_kg,discharged_kg\n0,0,0\n60,1e300,0\n120,2e300,1\n", ["line 3", "fed_kg = 1e+300", "1000000000 kg"]),
    (HEAD + "0,0,0\n1e300,6,1\n2e300,6,3\n", ["rec.csv line 3", "time_s = 1e+300", "1000000000]"]),
], ids=["feed", "discharge", "cumulative", "time"])
def test_lab_steps_overflowing_values_refused(workdir, text, fragments):
    (workdir / "rec.csv").write_text(text)
    before = snapshot(workdir)
    assert_bad(run_cli(["lab", "steps", "rec.csv", "--out", "res"], cwd=workdir), *fragments)
    assert snapshot(workdir) == before


# ------------------------------------------------------------------------------ new
@pytest.mark.parametrize("name", ["..", ".", "", ".toml", "..toml", ".hidden", "a/", "-x", "x."])
def test_new_refuses_names_that_are_not_plain_file_names(workdir, name):
    res = run_cli(["new", "--", name], cwd=workdir)
    assert_bad(res, "case_name", "not a plain file name")
    assert snapshot(workdir) == {}


@pytest.mark.parametrize("out", ["sub", "nosub/", "x.txt"])
def test_new_out_must_be_a_toml_file(workdir, out):
    (workdir / "sub").mkdir()
    res = run_cli(["new", "mine", "--out", out], cwd=workdir)
    assert_bad(res, "--out", "NAME.toml")
    assert snapshot(workdir) == {}


def test_new_plain_names_still_written(workdir):
    res = run_cli(["new", "plant.v2"], cwd=workdir)
    assert res.exit_code == 0, res.output
    assert (workdir / "plant.v2.toml").is_file()


# ------------------------------------------------------------------------------ other counts
def test_fit_starts_bounded():
    t0 = time.perf_counter()
    res = run_cli(["fit", "lee2008_invicta", "lee2008_invicta", "-p", "transport.backmix", "--starts", "100000"])
    assert time.perf_counter() - t0 < 30
    assert_bad(res, "--starts = 100000", "[1, 100]")


def test_dem_run_np_clamped_to_cpus(monkeypatch, tmp_path):
    """--np above the usable cores is clamped with a warning before LIGGGHTS is started."""
    from rotarydryer.dem import run as dem_run

    seen = {}

    def fake_run_deck(folder, *, np=1, progress=True, timeout=None, **kw):
        seen["np"] = np
        return {"seconds": 0.0}

    monkeypatch.setattr(_options, "usable_cpus", lambda: 2)
    monkeypatch.setattr(dem_run, "run_deck", fake_run_deck)
    res = run_cli(["dem", "run", str(tmp_path), "--np", "64"])
    assert res.exit_code == 0, res.output
    assert seen["np"] == 2 and "warning: --np = 64 is more than the 2 usable CPU cores; using 2" in res.output


# ------------------------------------------------------------------------------ BOM
def test_case_file_with_utf8_bom_is_read(workdir):
    from importlib import resources

    text = (resources.files("rotarydryer.cases") / "song2003_ottawa.toml").read_text("utf-8")
    (workdir / "bom.toml").write_bytes(b"\xef\xbb\xbf" + text.encode("utf-8"))
    res = run_cli(["simulate", "bom.toml", "--set", "thermal.enabled=false"], cwd=workdir)
    assert res.exit_code == 0, res.output
    assert "not valid TOML" not in res.output and "total holdup" in res.output


def test_material_file_with_utf8_bom_is_read(tmp_path):
    from importlib import resources

    from rotarydryer.properties.materials import list_materials, load_material

    name = list_materials()[0]
    text = (resources.files("rotarydryer.data") / "materials" / f"{name}.toml").read_text("utf-8")
    p = tmp_path / "m.toml"
    p.write_bytes(b"\xef\xbb\xbf" + text.encode("utf-8"))
    assert load_material(str(p)) is not None


# ------------------------------------------------------------------------------ control --duration
def test_control_duration_bounded_to_what_runs_in_bounded_time():
    """``control --duration`` once allowed 30 days: each loop rebuilds and integrates the model every
    sampling interval (~0.1-0.25 s each), so that ran for hours (and was then refused by the loop's own
    open bound). Now at most one day and MAX_SAMPLES intervals, refused at once naming the option and
    the bound; the library loop checks the same bounds."""
    from rotarydryer import control as C
    from rotarydryer.services.control import check_control_options

    assert C.MAX_DURATION_S == 86400.0 and C.MAX_SAMPLES == 1440
    assert check_control_options(duration=C.MAX_DURATION_S) == 600.0       # the bound itself is allowed
    for args, fragments in ((["--duration", "2592000"], ["--duration = 2592000", "(0, 86400] s"]),
                            (["--duration", "86401"], ["--duration = 86401", "(0, 86400] s"]),
                            (["--duration", "7200", "--sample-time", "1"],
                             ["--duration = 7200", "--sample-time = 1", "the limit is 1440"])):
        t0 = time.perf_counter()
        res = run_cli(["control", "ajayi2011_mmg", *args])
        assert time.perf_counter() - t0 < 30
        assert_bad(res, *fragments)
        assert len([ln for ln in res.output.splitlines() if ln.startswith("error:")]) == 1, res.output
    # the library loop: the same bounds, before any model work (no dryer needed to refuse)
    with pytest.raises(ValueError, match=r"t_end_s = 2592000 s is outside the allowed range \(0, 86400\] s"):
        C.closed_loop(None, None, t_end_s=2592000.0)
    with pytest.raises(ValueError, match="the limit is 1440"):
        C.closed_loop(None, None, t_end_s=7200.0, config=C.ControlConfig(sample_time_s=1.0))


def test_control_duration_bound_documented():
    from pathlib import Path

    text = (Path(__file__).parents[2] / "docs" / "errors.md").read_text(encoding="utf-8")
    assert "--duration" in text and "86400 s" in text and "1440 sampling intervals" in text


# ------------------------------------------------------------------------------ --cluster, and the options together
EXECUTOR_COMMANDS = {
    "sweep": ["sweep", "song2003_ottawa", "--grid", "operating.rpm=3,4", *FAST],
    "sensitivity": ["sensitivity", "song2003_ottawa", "--set", "thermal.enabled=false", "--param", "operating.rpm=3,5",
                    "--samples", "4"],
    "calibrate": ["calibrate", "ajayi2011_mmg", "-p", "thermal.area_scale", "--tests", "4", "--starts", "2"],
    "fit": ["fit", "ajayi2011_mmg", "ajayi2011_test4", "-p", "transport.solids_velocity", "--set", "operating.test=4",
            "--scale", "fit"],
    "design": ["design", "--duty", "raw_sugar", "--no-verify"],
}
EXECUTOR_BAD = [
    ("cluster-zero", ["--cluster", "local:0"], ["--cluster", "local:0", "allowed range [1,"]),
    ("cluster-word", ["--cluster", "foo"], ["--cluster", "'foo'", "local:N"]),
    ("both", ["--cluster", "local:2", "--scheduler", "tcp://127.0.0.1:8786"], ["--scheduler", "--cluster", "not both"]),
    ("workers-negative", ["--workers", "-1"], ["--workers = -1", "allowed range [0, inf)"]),
    # the type checker's words ("Input should be a valid integer, unable to parse string as an integer") in plain ones
    ("workers-fraction", ["--workers", "1.5"], ["--workers", "not a valid integer (a whole number)", "'1.5'"]),
]


@pytest.mark.parametrize("extra,fragments", [c[1:] for c in EXECUTOR_BAD], ids=[c[0] for c in EXECUTOR_BAD])
@pytest.mark.parametrize("cmd", list(EXECUTOR_COMMANDS.values()), ids=list(EXECUTOR_COMMANDS))
def test_bad_executor_options_refused_at_once(tmp_path, cmd, extra, fragments):
    t0 = time.perf_counter()
    res = run_cli([*cmd, *extra, "--out", str(tmp_path / "out")] if cmd[0] != "sweep" else [*cmd, *extra])
    assert time.perf_counter() - t0 < 30
    assert_bad(res, *fragments)
    assert len([ln for ln in res.output.splitlines() if ln.startswith("error:")]) == 1
    assert not (tmp_path / "out").exists()


def test_cluster_above_the_cores_is_clamped_with_a_warning(monkeypatch):
    from rotarydryer.services._options import check_cluster

    monkeypatch.setattr(_workers, "usable_cpus", lambda: 2)       # where check_cluster reads it
    assert check_cluster("local:2") == (2, [])
    n, notes = check_cluster("local:64")
    assert n == 2 and "--cluster = local:64 is more than the 2 usable CPU cores; using local:2" in notes[0]
    assert check_cluster(None) == (None, [])


# ------------------------------------------------------------------------------ values that hung or broke a solve
@pytest.mark.parametrize("key, value, fragments", [
    ("transport.solids_velocity", "1e15", ["transport.solids_velocity", "(0, 10] m/s"]),      # hung the solve
    ("transport.dispersion", "1e30", ["transport.dispersion", "[0, 100] m^2/s"]),             # a singular matrix
    ("transport.kiln_time", "1e-30", ["transport.kiln_time", "[0.1, inf] s"]),                # a step-size error
    ("operating.rpm", "1e-9", ["operating.rpm", "[0.1, 60] rev/min"]),
])
def test_values_past_any_drum_are_refused_at_once(key, value, fragments):
    """Found by fuzzing the CLI on the `rotarydryer new` template: these values were inside their keys' ranges and
    hung the solve (120 s and more) or ended in an internal error; the ranges now stop short of them."""
    t0 = time.perf_counter()
    assert_bad(run_cli(["simulate", "ajayi2011_mmg", "--set", f"{key}={value}", "--json"]), *fragments)
    assert time.perf_counter() - t0 < 30


def test_a_schedule_that_all_but_stops_the_drum_is_refused(workdir):
    """rpm = 1e-9 rev/min at 600 s in a dynamics schedule left the integration running for minutes."""
    path = workdir / "s.csv"
    path.write_text("time_s,rpm\n0,4\n600,1e-9\n")
    t0 = time.perf_counter()
    assert_bad(run_cli(["dynamics", "ajayi2011_mmg", "--quiet", "--schedule", str(path)]),
               "s.csv", "rpm=1e-09 at 600 s", "operating.rpm [0.1, 60] rev/min")
    assert time.perf_counter() - t0 < 30


def test_a_tracer_pulse_longer_than_the_record_is_refused():
    """tracer.duration = 1e30 s printed a tracer mean of 1e28 min (the pulse simulated as fed to the end; fuzzing)."""
    assert_bad(run_cli(["rtd", "song2003_ottawa", "--set", "tracer.duration=1e30"]),
               "tracer.duration = 1e+30 s must be shorter than tracer.t_end", "allowed: [0,")
