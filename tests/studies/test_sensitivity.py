"""Global sensitivity study (issue 16 part 4): Sobol indices through the project's runner."""

from __future__ import annotations

import json
import sys
import warnings

import numpy as np
import pytest

pytest.importorskip("SALib")

from rotarydryer.studies.sensitivity import OUTPUTS, plot_sensitivity, require_salib, saltelli_design, sobol_study  # noqa: E402

PI = np.pi
ISHIGAMI = {"x1": (-PI, PI), "x2": (-PI, PI), "x3": (-PI, PI)}
# analytic indices of the Ishigami function (a = 7, b = 0.1), as in SALib's tests
S1_TRUE = {"x1": 0.3139, "x2": 0.4424, "x3": 0.0}
ST_TRUE = {"x1": 0.5576, "x2": 0.4424, "x3": 0.2437}


def ishigami(p):
    from SALib.test_functions import Ishigami

    x = np.array([[p["x1"], p["x2"], p["x3"]]])
    return {"y": float(Ishigami.evaluate(x)[0])}


def test_ishigami_indices_within_confidence():
    res = sobol_study(ishigami, ISHIGAMI, 1024, outputs=["y"], seed=1)
    assert res.n_runs == 1024 * 5 and res.n_failed == 0
    for k in ISHIGAMI:
        v = res.indices["y"][k]
        assert abs(v["S1"] - S1_TRUE[k]) <= 1.5 * v["S1_conf"] + 0.01, (k, v)
        assert abs(v["ST"] - ST_TRUE[k]) <= 1.5 * v["ST_conf"] + 0.01, (k, v)
    d = res.distributions["y"]
    assert d["n"] == res.n_runs and abs(d["mean"] - 3.5) < 0.1      # E[y] = a/2 = 3.5
    assert d["p5"] < d["p50"] < d["p95"] and sum(d["histogram"]["counts"]) == d["n"]
    rows = res.table()
    assert {r["parameter"] for r in rows} == set(ISHIGAMI) and set(rows[0]) >= {"S1", "S1_conf", "ST", "ST_conf"}
    json.dumps(res.to_dict())


def test_failed_runs_are_recorded_and_excluded_by_block():
    def model(p):
        if p["x1"] > 2.5:
            raise ValueError("infeasible point: x1 > 2.5")
        return ishigami(p)

    res = sobol_study(model, ISHIGAMI, 256, outputs=["y"])
    X = saltelli_design(ISHIGAMI, 256)
    expected = int(np.sum(X[:, 0] > 2.5))
    assert res.n_failed == expected > 0
    bad_blocks = (X[:, 0] > 2.5).reshape(-1, 5).any(axis=1)
    assert res.blocks_used["y"] == int((~bad_blocks).sum())
    assert all(np.isfinite(v["S1"]) and np.isfinite(v["ST"]) for v in res.indices["y"].values())
    assert any("runs failed" in n for n in res.notes)
    assert res.failures == [{"error": "infeasible point: x1 > 2.5", "runs": expected}]
    assert res.distributions["y"]["n"] == res.n_runs - expected
    assert sum(1 for r in res.runs_table() if r["error"]) == expected


def test_missing_output_is_skipped_with_a_note():
    res = sobol_study(ishigami, ISHIGAMI, 8, outputs=["y", "fuel_rate_kg_s"])
    assert res.outputs == ["y"] and "fuel_rate_kg_s" not in res.indices
    assert any(n.startswith("fuel_rate_kg_s") for n in res.notes)


def test_bad_arguments():
    with pytest.raises(ValueError, match="LOW = 2 must be below HIGH = 1"):
        sobol_study(ishigami, {"x1": (2, 1)}, 8)
    with pytest.raises(ValueError, match=r"samples = 0 is outside"):
        sobol_study(ishigami, ISHIGAMI, 0)
    with pytest.raises(ValueError, match=r"samples = 1 is outside the allowed range \[2, .*at least 2 blocks"):
        sobol_study(ishigami, ISHIGAMI, 1)      # one block of runs can never give indices
    with pytest.raises(ValueError, match="workers"):
        sobol_study(ishigami, ISHIGAMI, 8, workers=0)


def test_small_real_study_transport_only():
    params = {"operating.rpm": (3.0, 5.0), "operating.feed_rate": (0.05, 0.08)}
    res = sobol_study("song2003_ottawa", params, 4, base_overrides={"thermal.enabled": "false"})
    assert res.seconds < 30 and res.n_runs == 16 and res.n_failed == 0
    assert res.outputs == ["mean_residence_time_s"]
    assert len([n for n in res.notes if "not computed" in n]) == 3
    assert np.all(np.isfinite(res.Y))
    fig = plot_sensitivity(res.to_dict())
    assert fig is not None


def test_warm_start_gives_the_cold_results():
    """Warm starts from the nearest converged state change the path, not the answer."""
    params = {"operating.feed_rate": (39.0, 42.0)}
    warm = sobol_study("ajayi2011_mmg", params, 2, warm_start=True)
    cold = sobol_study("ajayi2011_mmg", params, 2, warm_start=False)
    assert warm.outputs == cold.outputs == list(OUTPUTS)
    np.testing.assert_allclose(warm.Y, cold.Y, rtol=1e-7)


def test_runs_on_another_network_reuse_a_remembered_model(monkeypatch):
    """A row that changes the network (``transport.moisture_scale``) reuses a remembered run's model of that network
    (`_other_models`) instead of building its own: fewer builds, the same outputs bit for bit."""
    from rotarydryer import simulation as sim_mod
    from rotarydryer.studies import sensitivity as sens

    params = sens.check_params({     # the Sobol benchmark's inputs (benchmarks/bench_sensitivity.py)
        "operating.feed_rate": (38.6, 42.7), "operating.rpm": (2.85, 3.15), "gas.flow": (15.4, 17.1),
        "thermal.area_scale": (2.45, 2.75), "gas.inlet_temperature": (480.0, 520.0),
        "transport.moisture_scale": (0.95, 1.05), "operating.feed_temperature": (24.0, 32.0),
        "shell.ambient_temperature": (20.0, 32.0)})
    X = saltelli_design(params, 4, 0)
    builds = []
    build = sim_mod.Simulation.thermal_dryer

    def counted(self, *a, **k):
        builds.append(1)
        return build(self, *a, **k)

    monkeypatch.setattr(sim_mod.Simulation, "thermal_dryer", counted)
    Y, errors, _ = sens._run_chunk("ajayi2011_mmg", {}, list(params), X, list(OUTPUTS))
    reused = len(builds)
    builds.clear()
    monkeypatch.setattr(sens, "OTHER_MODELS", 0)
    Y0, errors0, _ = sens._run_chunk("ajayi2011_mmg", {}, list(params), X, list(OUTPUTS))
    assert not any(errors) and not any(errors0)
    np.testing.assert_array_equal(Y, Y0)
    assert reused < len(builds), (reused, len(builds))


def test_process_pool_matches_serial():
    params = {"operating.rpm": (3.0, 5.0), "operating.feed_rate": (0.05, 0.08)}
    base = {"thermal.enabled": "false"}
    a = sobol_study("song2003_ottawa", params, 4, base_overrides=base, workers=1)
    b = sobol_study("song2003_ottawa", params, 4, base_overrides=base, workers=2)
    np.testing.assert_array_equal(a.Y, b.Y)


def test_salib_missing_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "SALib", None)
    with pytest.raises(ImportError, match=r"rotarydryer\[sensitivity\]"):
        require_salib()


def test_cli_writes_its_files_and_the_report_section(tmp_path):
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    r = CliRunner().invoke(app, ["sensitivity", "song2003_ottawa", "--set", "thermal.enabled=false",
                                 "--param", "operating.rpm=3,5", "--param", "operating.feed_rate=0.05,0.08",
                                 "--samples", "4", "--out", str(tmp_path / "study")])
    assert r.exit_code == 0, r.output
    files = sorted(p.name for p in (tmp_path / "study").iterdir())
    assert files == ["sensitivity.json", "sensitivity.png", "sensitivity_distributions.csv",
                     "sensitivity_indices.csv", "sensitivity_runs.csv"]       # no temporary files left
    data = json.loads((tmp_path / "study" / "sensitivity.json").read_text())
    assert data["kind"] == "sobol_sensitivity" and data["n_runs"] == 16
    assert (tmp_path / "study" / "sensitivity_indices.csv").read_text().startswith(
        "output,parameter,S1,S1_conf,ST,ST_conf\n")
    assert "mean_residence_time_s" in r.output and "note: product_moisture_kg_kg" in r.output
    study = str(tmp_path / "study" / "sensitivity.json")
    r = CliRunner().invoke(app, ["report", "song2003_ottawa", "--set", "thermal.enabled=false", "--set",
                                 "operating.rpm=4", "--sensitivity", study, "-o", str(tmp_path / "r.html")])
    assert r.exit_code == 0, r.output
    text = (tmp_path / "r.html").read_text()
    assert 'id="sensitivity"' in text and "operating.feed_rate" in text
    # a study of another case, or of another base point, is refused (one was shown as the report's dryer's)
    for args, words in ((["lee2008_invicta"], "is a study of case 'song2003_ottawa', this report is of 'lee2008_invicta'"),
                        (["song2003_ottawa"], "thermal.enabled = false in the study, the case value in this report")):
        r = CliRunner().invoke(app, ["report", *args, "--sensitivity", study, "-o", str(tmp_path / "x.html")])
        assert r.exit_code == 2 and words in r.output, r.output
        assert not (tmp_path / "x.html").exists()


def test_cli_without_salib_exit_3(monkeypatch):
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    monkeypatch.setitem(sys.modules, "SALib", None)
    r = CliRunner().invoke(app, ["sensitivity", "song2003_ottawa", "--param", "operating.rpm=3,5"])
    assert r.exit_code == 3 and "rotarydryer[sensitivity]" in r.output


def test_coupled_study_same_indices_on_every_backend():
    """Issue 32: serial, 2 local workers and a Dask LocalCluster of 2 workers run the same chunks
    (warm-start chains included) and give the same runs and Sobol indices, bit for bit."""
    pytest.importorskip("dask.distributed")
    params = {"operating.feed_rate": (39.0, 42.0), "operating.rpm": (2.9, 3.1)}
    base = {"operating.test": 4}
    kw = dict(outputs=["product_moisture_kg_kg", "gas_outlet_temperature_degC"], base_overrides=base,
              num_resamples=20)
    serial = sobol_study("ajayi2011_mmg", params, 4, **kw)
    local = sobol_study("ajayi2011_mmg", params, 4, workers=2, **kw)
    dask = sobol_study("ajayi2011_mmg", params, 4, cluster="local:2", **kw)
    assert serial.n_failed == 0
    for other in (local, dask):
        np.testing.assert_array_equal(other.Y, serial.Y)
        assert other.indices == serial.indices


def test_an_output_that_does_not_vary_has_no_indices_and_says_why(tmp_path):
    """An output with the same value in every run (here a constant) has undefined
    indices: a note naming it, None in the table, an empty cell in the CSV and n/a in the text (before: nan)."""
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    def flat(p):
        return {"y": ishigami(p)["y"], "c": 2.5}
    res = sobol_study(flat, ISHIGAMI, 8, outputs=["y", "c"])
    assert any(n.startswith("c: the same value in every run (2.5, to 1e-09 of it)") for n in res.notes)
    rows = [r for r in res.table() if r["output"] == "c"]
    assert rows and all(r[k] is None for r in rows for k in ("S1", "S1_conf", "ST", "ST_conf"))
    assert all(r["S1"] is not None for r in res.table() if r["output"] == "y")
    # the CLI on a shipped case: the solids transport alone has no fuel rate; the product moisture of the
    # transport-only runs is the feed's (constant): n/a in the text, empty cells in the CSV
    r = CliRunner().invoke(app, ["sensitivity", "song2003_ottawa", "--set", "thermal.enabled=false",
                                 "--param", "operating.rpm=3,5", "--param", "operating.feed_rate=0.05,0.08",
                                 "--samples", "2", "--out", str(tmp_path / "s")])
    assert r.exit_code == 0, r.output
    assert "nan" not in r.output and "nan" not in (tmp_path / "s" / "sensitivity_indices.csv").read_text()


def test_an_output_varying_by_round_off_only_has_no_indices():
    """A product at its moisture floor varied by 4e-18 (the solver's round-off) and its Sobol indices were printed
    as real (ST 1.58; found by fuzzing): such an output is constant, with the note that says so."""
    from rotarydryer.studies import sensitivity as S

    params = {"a": (0.0, 1.0), "b": (0.0, 1.0)}
    X = saltelli_design(params, 8, seed=1)
    y = 0.00049975 + 1e-18 * np.sin(np.arange(len(X)) * 1.7)
    block = len(X) // 8
    ind, n = S._sobol_indices(params, y, block, 1, 50)
    assert n == 8 and all(np.isnan(v["S1"]) and np.isnan(v["ST"]) for v in ind.values())
    ind, _ = S._sobol_indices(params, 1.0 + 0.1 * X[:, 0] + 1e-6 * X[:, 1], block, 1, 50)
    assert ind["a"]["ST"] > 0.5


def test_a_dried_product_varying_by_the_solvers_resolution_of_the_water_has_no_indices():
    """A product dried to 1.8e-7 kg/kg varied by 7.6e-14 kg/kg (4e-7 of it: the solver resolves the water to an
    absolute, not a relative, tolerance) with two tracer inputs it does not depend on, and its indices were printed
    as real (S1 1.007; found by fuzzing). A moisture is constant to 1e-9 of max(it, 1e-3 kg/kg); an output of
    another unit keeps the relative test, and a moisture that does vary keeps its indices."""
    from rotarydryer.studies import sensitivity as S

    params = {"a": (0.0, 1.0), "b": (0.0, 1.0)}
    X = saltelli_design(params, 8, seed=1)
    block = len(X) // 8
    noise = 1.7588e-7 + 7.6e-14 * np.sin(np.arange(len(X)) * 1.7)
    ind, n = S._sobol_indices(params, noise, block, 1, 50, "product_moisture_kg_kg")
    assert n == 8 and all(np.isnan(v["S1"]) and np.isnan(v["ST"]) for v in ind.values())
    ind, _ = S._sobol_indices(params, noise, block, 1, 50, "holdup_kg")
    assert all(np.isfinite(v["ST"]) for v in ind.values())
    ind, _ = S._sobol_indices(params, 1e-5 + 1e-6 * X[:, 0], block, 1, 50, "product_moisture_kg_kg")
    assert ind["a"]["ST"] > 0.5


def test_whole_number_keys_are_refused_up_front():
    """drum.n_flights=12,24 ran every sample at fractions of a flight, all failing (exit 1; found by fuzzing)."""
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    res = CliRunner().invoke(app, ["sensitivity", "lee2008_invicta", "--param", "drum.n_flights=12,24", "--samples", "4",
                                   "-q"])
    assert res.exit_code == 2 and "--param drum.n_flights: the key takes whole numbers" in res.output
    res = CliRunner().invoke(app, ["fit", "lee2008_invicta", "lee2008_invicta", "-p", "transport.n_cells", "-q"])
    assert res.exit_code == 2 and "parameter transport.n_cells: the key takes whole numbers" in res.output


def test_param_and_fit_messages_name_their_options():
    """A --param outside a key's range was reported as a --set, and fit -p of one key twice as "duplicate
    parameter names in [...]" (fuzzing)."""
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    res = CliRunner().invoke(app, ["sensitivity", "lee2008_invicta", "--param", "operating.rpm=-1,2", "--samples", "4",
                                   "-q"])
    assert res.exit_code == 2 and "--param operating.rpm=-1,2: operating.rpm = -1.0" in res.output
    res = CliRunner().invoke(app, ["fit", "lee2008_invicta", "lee2008_invicta", "-p", "transport.kiln_time", "-p",
                                   "transport.kiln_time", "-q"])
    assert res.exit_code == 2 and "duplicate parameter: transport.kiln_time is given twice (-p on the command line)" in res.output


def test_too_few_base_samples_are_warned_about():
    """`sensitivity -n 2` gave S1 = 0.90 +- 518 for a single input, whose S1 = ST = 1 (found by review): a warning says
    such indices are not estimates; 16 and more are not warned about."""
    from rotarydryer.studies.sensitivity import FEW_SAMPLES, check_samples

    with pytest.warns(UserWarning, match=r"--samples = 2: so few base samples give indices that are not estimates"):
        assert check_samples(2, 1) == 2
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert check_samples(FEW_SAMPLES, 1) == FEW_SAMPLES
