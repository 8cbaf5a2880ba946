"""HTML report: self-contained, correct numbers, CLI behaviour."""

import csv
import json
import re
from importlib import resources

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

pytest.importorskip("xarray")

from rotarydryer.report.html import build_report, render_report, write_report  # noqa: E402
from rotarydryer.results import Results  # noqa: E402

runner = CliRunner()


def _csv(name):
    text = (resources.files("rotarydryer") / "data" / name).read_text()
    return list(csv.DictReader(line for line in text.splitlines() if not line.startswith("#")))


def _design_load_kg(html_text, method="lee2008"):
    m = re.search(rf"<td class=\"l\">{method}</td><td class=\"\">[0-9.]+</td><td class=\"\">([0-9,]+)</td>", html_text)
    assert m, f"no design-load row for {method}"
    return float(m.group(1).replace(",", ""))


def _assert_self_contained(text):
    assert text.startswith("<!DOCTYPE html>")
    assert not re.search(r"(src|href)\s*=\s*[\"'](https?:|//|file:)", text), "external resource"
    assert "<script" not in text and "<link" not in text
    imgs = re.findall(r'<img alt="[^"]*" src="data:image/png;base64,([A-Za-z0-9+/=]+)"', text)
    assert imgs and all(len(i) > 2000 for i in imgs)
    return len(imgs)


def test_drum_report_reproduces_lee_table_7_7_design_load(tmp_path):
    """Lee (2008) Table 7.7: flighted mass (= design load) 6784 kg at a repose angle of 50 deg
    (Invicta, 940 kg/m3, 12 m), read back from the report's design-load table."""
    row = next(r for r in _csv("lee_response_angle_of_repose_holdups.csv") if r["dynamic_angle_of_repose_deg"] == "50")
    out = write_report("invicta", tmp_path / "drum.html", repose_angle=50.0)
    text = out.read_text()
    assert _assert_self_contained(text) == 2  # cross-section + unloading profile
    assert _design_load_kg(text) == pytest.approx(float(row["flighted_mass_kg"]), rel=3e-3)
    assert "repose angle used</td><td class=\"\">50.0 deg" in text


@settings(max_examples=4, deadline=None)
@given(a=st.floats(25, 40), b=st.floats(45, 60))
def test_design_load_in_report_grows_with_repose_angle(a, b):
    low, high = (_design_load_kg(build_report("invicta", repose_angle=x)) for x in (a, b))
    assert high > low


def test_report_cli_case_save_and_reload_identical(cli, tmp_path):
    out, nc = tmp_path / "r.html", tmp_path / "r.nc"
    res = runner.invoke(cli, ["report", "lee2008_invicta", "--set", "geometry.method=lee2008_regressions",
                              "--out", str(out), "--save", str(nc), "--json"])
    assert res.exit_code == 0, res.output
    info = json.loads(res.stdout)
    assert info["report"] == str(out) and info["bytes"] == out.stat().st_size
    text = out.read_text()
    assert _assert_self_contained(text) >= 6
    for sid in ('id="summary"', 'id="holdup"', 'id="rtd"', 'id="loading"', 'id="flight-dryer"', 'id="inputs"',
                'id="validation"'):
        assert sid in text
    assert "against the measured tracer curve" in text and "over-loaded" in text
    loaded = Results.load(nc)
    # the report of the saved result is byte-identical to the one made from the live run
    from rotarydryer.validate import run_validation

    assert render_report(loaded, validation=run_validation(["lee2008_invicta"])) == text
    res2 = runner.invoke(cli, ["report", str(nc), "--out", str(tmp_path / "r2.html")])
    assert res2.exit_code == 0, res2.output
    assert (tmp_path / "r2.html").read_text() == text
    # key results in the report equal the stored scalars
    total = loaded.scalars["total_holdup_kg"]
    assert f"<td class=\"l\">total holdup</td><td class=\"\">{total:,.0f}</td>" in text


def test_report_cli_ajayi_sections(cli, tmp_path):
    out = tmp_path / "a.html"
    res = runner.invoke(cli, ["report", "ajayi2011_mmg", "--set", "operating.test=4", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "report:" in res.output
    text = out.read_text()
    for s in ("B", "C", "D"):
        assert f'id="flight-{s}"' in text
    assert 'id="flight-A"' not in text  # unflighted
    # flights x 3 sections, holdup, RTD, loading state, energy waterfall and thermal profiles (the dryer is
    # drawn once, as the inline SVG of the operating conditions)
    assert _assert_self_contained(text) == 2 * 3 + 3 + 2


@pytest.mark.parametrize("args, expect", [
    (["no_such_thing"], "not a results file"),
    (["lee2008_invicta", "--set", "operating.nope=3"], "operating.nope"),
    (["lee2008_invicta", "--set", "operating.rpm=-1"], "operating.rpm"),
    (["lee2008_invicta", "--set", "rpm"], "KEY=VALUE"),
    (["invicta", "--repose-angle", "95"], "--repose-angle"),
    (["invicta", "--save", "x.nc"], "--save"),
])
def test_report_cli_bad_input(cli, tmp_path, args, expect):
    out = tmp_path / "bad.html"
    res = runner.invoke(cli, ["report", *args, "--out", str(out)])
    assert res.exit_code == 2
    assert expect in res.output
    assert "Traceback" not in res.output
    assert not out.exists()


def test_repose_angle_checked_before_the_case_runs_and_applied_to_every_section(monkeypatch):
    """--repose-angle is handled in one place (resolve_source), for the CLI and build_report."""
    import rotarydryer.simulation as results_module  # the assembler: run_case lives there
    from rotarydryer.report.html import resolve_source

    def _no_run(*args, **kwargs):
        raise AssertionError("the case ran before repose_angle was checked")

    with monkeypatch.context() as m:
        m.setattr(results_module, "run_case", _no_run)
        for bad in (0.0, 90.0, float("nan")):
            with pytest.raises(ValueError, match="repose_angle"):
                build_report("ajayi2011_mmg", repose_angle=bad)
    fake = type("FakeResults", (), {"inputs": {}})()
    seen = []
    monkeypatch.setattr(results_module, "run_case", lambda *a, **k: fake)
    monkeypatch.setattr("rotarydryer.report.figures.case_drums",
                        lambda inputs, res: seen.append(res) or [dict(name="B", repose_angle=41.0)])
    res, drums, _ = resolve_source("ajayi2011_mmg", repose_angle=52)
    assert res is fake and seen == [fake] and drums == [dict(name="B", repose_angle=52.0)]
    assert resolve_source("ajayi2011_mmg")[1] is None  # default: the case's own angles (render_report)


def test_live_and_saved_result_figures_are_one_drawing():
    """transport.plots (live steady state / RTD, the simulate and rtd CLI pictures) and
    report.figures (a Results) draw the holdup profile and the RTD with the same code:
    the same lines, labels and titles."""
    import matplotlib.pyplot as plt
    import numpy as np

    from rotarydryer.cases import build_model, load_case, measured_rtd, measured_rtd_moments
    from rotarydryer.report import figures as rf
    from rotarydryer.results import from_transport
    from rotarydryer.transport import plots as tp

    case = load_case("lee2008_invicta", {"geometry.method": "lee2008_regressions"})
    model = build_model(case)
    ss = model.steady_state()
    rtd = ss.rtd(model.tracer_input, t_end=case.tracer.t_end, dt=case.tracer.dt)
    meas = measured_rtd(case)
    res = from_transport(case, model, ss, rtd, meas)
    baseline = float(measured_rtd_moments(case)["baseline"])
    res.scalars["measured_baseline"] = baseline

    def _content(fig):
        ax = fig.axes[0]
        lines = [(line.get_label(), np.asarray(line.get_xdata(), float).tolist(),
                  np.asarray(line.get_ydata(), float).tolist()) for line in ax.get_lines()]
        legend = [t.get_text() for t in ax.get_legend().get_texts()]
        plt.close(fig)
        return lines, legend, ax.get_title(), ax.get_xlabel(), ax.get_ylabel(), tuple(fig.get_size_inches())

    live, saved = _content(tp.plot_holdup_profile(ss)), _content(rf.plot_holdup_profile(res))
    assert live[0] == saved[0] and live[1] == saved[1] and live[3:] == saved[3:]
    assert live[2].split(":", 1)[1] == saved[2].split(":", 1)[1]  # title: model name vs "Holdup profile"
    assert "airborne (curtain)" in live[1] and "H/F" in live[2]
    assert _content(tp.plot_rtd(rtd, meas, baseline=baseline)) == _content(rf.plot_rtd(res))


def test_report_of_a_new_case_whose_sections_inherit_the_flight(tmp_path, monkeypatch):
    """`rotarydryer new X && rotarydryer report X.toml`: the flighted section takes [flight] and
    drum.n_flights (it crashed formatting the section's own s1, None), and the report shows them."""
    from rotarydryer.cli import app

    monkeypatch.chdir(tmp_path)
    runner = CliRunner()
    assert runner.invoke(app, ["new", "mine"]).exit_code == 0
    r = runner.invoke(app, ["report", "mine.toml", "-o", "mine.html"])
    assert r.exit_code == 0, r.output
    text = (tmp_path / "mine.html").read_text()
    assert re.search(r"section flighted \(11 m\): 18 flights, s1 0\.15 m / s2 0\.1 m, 90 / 120 deg", text)
