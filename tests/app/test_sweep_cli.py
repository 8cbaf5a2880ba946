"""``rotarydryer sweep``: grids, lists, local processes, errors."""

import csv
import io
import json
import sys

import pytest
from typer.testing import CliRunner

pytest.importorskip("xarray")

from rotarydryer.cli import app as cli  # noqa: E402
from rotarydryer.cli import sweep as sweep_mod  # noqa: E402
from rotarydryer.simulation import run_case  # noqa: E402

runner = CliRunner()
REG = ["--set", "geometry.method=lee2008_regressions"]


def test_grid_matches_single_runs_and_is_ordered(tmp_path):
    out = tmp_path / "t.csv"
    res = runner.invoke(cli, ["sweep", "lee2008_invicta", *REG, "--grid", "operating.rpm=2,3",
                              "--grid", "operating.feed_rate=20,27.2", "--no-rtd", "-o", str(out)])
    assert res.exit_code == 0, res.output
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    assert [(r["operating.rpm"], r["operating.feed_rate"]) for r in rows] == [
        ("2", "20"), ("2", "27.2"), ("3", "20"), ("3", "27.2")]
    single = run_case("lee2008_invicta", {"geometry.method": "lee2008_regressions", "operating.rpm": 3,
                                          "operating.feed_rate": 27.2}, rtd=False)
    # each point starts from the previous one (issue 27): the same steady state to the solver's tolerance
    assert float(rows[3]["total_holdup_kg"]) == pytest.approx(single.scalars["total_holdup_kg"], rel=1e-9)
    # the first point has no warm start: exact (repr floats through the CSV)
    first = run_case("lee2008_invicta", {"geometry.method": "lee2008_regressions", "operating.rpm": 2,
                                         "operating.feed_rate": 20}, rtd=False)
    assert float(rows[0]["total_holdup_kg"]) == first.scalars["total_holdup_kg"]
    for r in rows:  # conservation in every run
        assert float(r["mass_balance_error"]) < 1e-9
    # more feed -> more holdup at each speed
    assert float(rows[1]["total_holdup_kg"]) > float(rows[0]["total_holdup_kg"])


def test_list_with_processes_and_failed_point(tmp_path):
    runs = tmp_path / "runs.csv"
    runs.write_text("# Ajayi tests\noperating.test\n2\n4\n7\n")
    res = runner.invoke(cli, ["sweep", "ajayi2011_mmg", "--list", str(runs), "--workers", "2", "--json"])
    assert res.exit_code == 1  # test 7 does not exist
    rows = json.loads(res.stdout)
    assert [r["operating.test"] for r in rows] == [2, 4, 7]     # numbers, as the case reads them
    assert rows[0]["error"] == "" and rows[1]["error"] == ""
    assert "operating.test" in rows[2]["error"]
    assert rows[1]["total_holdup_kg"] == pytest.approx(run_case("ajayi2011_mmg", {"operating.test": 4}).scalars["total_holdup_kg"])


@pytest.mark.parametrize("args, expect", [
    ([], "nothing to run"),
    (["--grid", "operating.rpm"], "KEY=V1"),
    (["--grid", "operating.nope=1,2"], "operating.nope"),
    (["--grid", "operating.rpm=1", "--workers", "-1"], "workers"),
])
def test_bad_input(args, expect):
    res = runner.invoke(cli, ["sweep", "lee2008_invicta", *args])
    assert res.exit_code == 2 and expect in res.output


def test_dask_missing_gives_exit_3(monkeypatch):
    monkeypatch.setitem(sys.modules, "dask.distributed", None)  # import fails as when not installed
    res = runner.invoke(cli, ["sweep", "lee2008_invicta", *REG, "--grid", "operating.rpm=2,3", "--no-rtd",
                              "--scheduler", "tcp://127.0.0.1:1"])
    assert res.exit_code == 3 and "dask" in res.output


def test_parse_grid_product():
    pts = sweep_mod.parse_grid(["a.b=1,2,3", "c.d=x,y"])
    assert len(pts) == 6 and pts[0] == {"a.b": "1", "c.d": "x"} and pts[-1] == {"a.b": "3", "c.d": "y"}


def test_dask_scheduler_gives_same_table():
    """The Dask path (an in-process LocalCluster behind --scheduler) gives the serial table, text for text."""
    distributed = pytest.importorskip("dask.distributed")
    args = ["sweep", "lee2008_invicta", *REG, "--grid", "operating.rpm=2,3,4", "--no-rtd"]
    local = runner.invoke(cli, args).stdout
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster:
        res = runner.invoke(cli, [*args, "--scheduler", cluster.scheduler_address])
    assert res.exit_code == 0, res.output
    assert res.stdout == local


MMG_GRID = ["sweep", "ajayi2011_mmg", "--set", "operating.test=4", "--grid", "operating.feed_rate=38,40,42,44",
            "--grid", "operating.rpm=2.9,3.0,3.1"]


def test_serial_local_pool_and_dask_cluster_give_the_same_csv(tmp_path):
    """Issue 32: a coupled sweep (12 points, 2 chunks) gives the same CSV text serially, on 2 local
    worker processes and on a Dask LocalCluster of 2 worker processes; a failed point is a row."""
    pytest.importorskip("dask.distributed")
    tables = {}
    for name, extra in (("serial", []), ("local", ["--workers", "2"]), ("dask", ["--cluster", "local:2"])):
        out = tmp_path / f"{name}.csv"
        res = runner.invoke(cli, [*MMG_GRID, "-o", str(out), "-q", *extra])
        assert res.exit_code == 0, res.output
        tables[name] = out.read_text()
    assert tables["local"] == tables["serial"] and tables["dask"] == tables["serial"]
    rows = list(csv.DictReader(io.StringIO(tables["serial"])))
    assert len(rows) == 12 and all(r["error"] == "" for r in rows)


def test_a_failing_point_is_a_row_on_every_backend(tmp_path):
    runs = tmp_path / "runs.csv"
    runs.write_text("operating.test,operating.rpm\n" + "".join(f"4,{r}\n" for r in (2.9, 3.0, 3.1, 3.2, 3.3))
                    + "4,-1\n" + "".join(f"4,{r}\n" for r in (2.8, 2.7, 2.6, 2.5)))
    want = runner.invoke(cli, ["sweep", "ajayi2011_mmg", "--list", str(runs), "-q"])
    got = runner.invoke(cli, ["sweep", "ajayi2011_mmg", "--list", str(runs), "-q", "--workers", "2"])
    assert want.exit_code == got.exit_code == 1
    assert got.stdout == want.stdout
    rows = list(csv.DictReader(io.StringIO(got.stdout)))
    assert [bool(r["error"]) for r in rows] == [False] * 5 + [True] + [False] * 4
    assert "operating.rpm" in rows[5]["error"]


@pytest.mark.parametrize("args, fragments", [
    (["--cluster", "local:0"], ["--cluster", "local:0", "allowed range [1,"]),
    (["--cluster", "foo"], ["--cluster", "'foo'", "local:N"]),
    (["--cluster", "local:2", "--scheduler", "tcp://127.0.0.1:8786"], ["--scheduler", "--cluster", "not both"]),
    (["--workers", "-1"], ["--workers = -1", "allowed range [0,"]),
])
def test_bad_executor_options_exit_2(args, fragments):
    res = runner.invoke(cli, ["sweep", "lee2008_invicta", *REG, "--grid", "operating.rpm=2,3", "--no-rtd", *args])
    assert res.exit_code == 2, res.output
    errors = [ln for ln in res.output.splitlines() if ln.startswith("error:")]
    assert len(errors) == 1 and all(f in errors[0] for f in fragments), res.output


def test_unreachable_scheduler_exit_2_nothing_written(tmp_path, monkeypatch):
    pytest.importorskip("dask.distributed")
    from rotarydryer import executor

    monkeypatch.setattr(executor, "CONNECT_TIMEOUT_S", 1.0)
    out = tmp_path / "t.csv"
    res = runner.invoke(cli, ["sweep", "lee2008_invicta", *REG, "--grid", "operating.rpm=2,3", "--no-rtd",
                              "--scheduler", "tcp://127.0.0.1:1", "-o", str(out)])
    assert res.exit_code == 2 and "--scheduler = 'tcp://127.0.0.1:1'" in res.output and not out.exists()


@pytest.mark.parametrize("rows, grid, expect", [
    # a ragged row: "internal error (AttributeError ...)" (found by fuzzing)
    ("operating.feed_rate,operating.rpm\n2,3,4\n", None, "line 2: 3 value(s) for the header's 2 column(s)"),
    ("operating.rpm,operating.rpm\n2,3\n", None, "the header names 'operating.rpm' twice"),
    # the same key twice: the second --grid overwrote the first's values in every combination
    (None, ["operating.rpm=2,3", "operating.rpm=4"], "--grid operating.rpm is given twice"),
    (None, ["operating.rpm=2,,4"], "an empty value between commas"),
    # a value that is no number: it was reported as a --set (found by review)
    ("operating.rpm,operating.feed_rate\n3,27\n4,abc\n", None, "line 3: operating.feed_rate = 'abc' is not a number"),
])
def test_malformed_lists_and_grids_are_refused(tmp_path, rows, grid, expect):
    args = ["sweep", "lee2008_invicta", "--no-rtd", "-q"]
    if rows is not None:
        p = tmp_path / "runs.csv"
        p.write_text(rows)
        args += ["--list", str(p)]
    for g in grid or []:
        args += ["--grid", g]
    res = runner.invoke(cli, args)
    assert res.exit_code == 2 and expect in res.output and "internal error" not in res.output, res.output


def test_a_key_in_set_and_in_the_sweep_is_refused(tmp_path):
    """The sweep sets a swept key per run: a --set of the same key was silently overridden (exit 0)."""
    res = runner.invoke(cli, ["sweep", "lee2008_invicta", "--grid", "operating.rpm=2,4", "--set", "operating.rpm=3",
                              "-q", "--no-rtd"])
    assert res.exit_code == 2 and "operating.rpm given by --set and by --grid" in res.output, res.output
    runs = tmp_path / "runs.csv"
    runs.write_text("operating.rpm\n2\n4\n")
    res = runner.invoke(cli, ["sweep", "lee2008_invicta", "--list", str(runs), "--set", "operating.rpm=3", "-q"])
    assert res.exit_code == 2 and "by --list" in res.output, res.output


def test_every_run_refused_the_same_way_by_the_set_is_bad_input():
    """A --set that makes the case invalid whatever the swept values (backmix with co-current gas) failed every run
    with the same message and exit 1 (some runs failed); it is the set-up that is wrong: exit 2 with the message once
    (the table still printed). Runs refused for their own swept value stay exit 1."""
    res = runner.invoke(cli, ["sweep", "lee2008_invicta", "--grid", "operating.rpm=2,4", "--set", "transport.backmix=0.15",
                              "--set", "gas.direction=co-current", "-q", "--no-rtd"])
    assert res.exit_code == 2, res.output
    assert "every run failed the same way, whatever the swept values: transport.backmix = 0.15 must be 0" in res.output
    assert res.stdout.count("must be 0 for co-current") == 2         # the table: both rows
    # the same refusal for every run, but naming a swept key (the runs' own values): some runs failed, exit 1
    res = runner.invoke(cli, ["sweep", "lee2008_invicta", "--grid", "gas.direction=co-current,co-current", "--set",
                              "transport.backmix=0.15", "-q", "--no-rtd"])
    assert res.exit_code == 1 and "2 of 2 runs failed" in res.output, res.output


def test_no_rtd_leaves_the_tracer_moments_out():
    """--no-rtd had no visible effect (the tracer moments are the steady state's analytic ones, computed anyway):
    it now leaves the tracer columns out; the other columns are the same numbers."""
    args = ["sweep", "lee2008_invicta", "--grid", "operating.rpm=2,3", "-q", "--json"]
    assert [r["operating.rpm"] for r in json.loads(runner.invoke(cli, args).stdout)] == [2, 3]
    with_rtd, without = (json.loads(runner.invoke(cli, args + flag).stdout) for flag in ([], ["--no-rtd"]))
    for a, b in zip(with_rtd, without):
        assert "tracer_mean_s" in a and "rtd_std_s" in a and "tracer_mean_s" not in b and "rtd_std_s" not in b
        assert {k: v for k, v in a.items() if k not in ("tracer_mean_s", "rtd_std_s")} == b


def test_a_feed_in_size_classes_adds_the_dust_and_d50_columns():
    """A sweep over the gas flow of a feed in size classes: the dust rate grows with the gas, the columns only in
    a size-class table (a single-class case's CSV keeps its columns)."""
    args = ["sweep", "song2003_ottawa", "--set", "particle_size.dataset=lee2008_fine_river_sand", "--grid",
            "gas.flow=0.04,0.08", "-q", "--json"]
    res = runner.invoke(cli, args)
    assert res.exit_code == 0, res.output
    rows = json.loads(res.stdout)
    assert rows[1]["dust_rate_kg_s"] > rows[0]["dust_rate_kg_s"] >= 0.0
    assert 1e-5 < rows[0]["product_d50_m"] < 1e-3
    single = json.loads(runner.invoke(cli, ["sweep", "song2003_ottawa", "--grid", "gas.flow=0.04", "-q",
                                            "--json"]).stdout)
    assert "dust_rate_kg_s" not in single[0] and "product_d50_m" not in single[0]
