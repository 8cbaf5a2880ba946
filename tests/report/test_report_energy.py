"""The report shows the energy balance of cases with a heat and mass transfer model."""

import re

import pytest

pytest.importorskip("xarray")

from rotarydryer.report.html import build_report  # noqa: E402


def test_ajayi_report_has_the_energy_audit():
    """Issue 34: the report's energy audit shows the model's heat duties (they add up to the release), the
    exhaust's dew-point margin and the shell per section, in the display units."""
    from rotarydryer.simulation import Simulation
    from rotarydryer.thermal.audit import HEAT_DUTY_LABELS, HEAT_DUTY_PARTS

    text = build_report("ajayi2011_mmg", {"operating.test": 4})
    section = text[text.index('id="energy"'):]
    assert "energy audit waterfall" in section and "thermal profiles" in section
    rows = dict(re.findall(r'<td class="l">\s*([a-z() ]+)</td><td class="">([-0-9.,e+]+)</td>', section))
    kw = {k.strip(): float(v.replace(",", "")) for k, v in rows.items()}
    s = Simulation("ajayi2011_mmg", {"operating.test": 4}).steady_state().summary()
    # the same numbers as the summary (kW, 4 significant digits) and they add up to the release
    for k in ("heat_release_W", *HEAT_DUTY_PARTS):
        if abs(s[k]) > 1e3:
            assert kw[HEAT_DUTY_LABELS[k]] == pytest.approx(s[k] / 1e3, rel=1e-3), k
    parts = sum(kw[HEAT_DUTY_LABELS[k]] for k in HEAT_DUTY_PARTS)
    assert parts == pytest.approx(kw[HEAT_DUTY_LABELS["heat_release_W"]], rel=1e-3)
    assert "Exhaust dew point:" in section and f"{s['gas_outlet_dew_point_margin_K']:.1f} K above it" in section
    assert "<h4>Shell</h4>" in section and "no limit set" in section
    words = re.sub(r'src="data:[^"]*"', "", section.split("<h3>Temperature")[0])
    assert "MW" not in words and '<th class="">kW</th>' in words  # duties in the display unit (kW)


def test_report_shows_the_saved_audits_savings(tmp_path):
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    r = CliRunner().invoke(app, ["audit", "ajayi2011_mmg", "--recycle", "0.2", "--out", str(tmp_path / "a")])
    assert r.exit_code == 0, r.output
    out = tmp_path / "r.html"
    r = CliRunner().invoke(app, ["report", "ajayi2011_mmg", "--audit", str(tmp_path / "a" / "audit.json"),
                                 "--set", "shell.max_temperature=200", "--out", str(out)])
    assert r.exit_code == 0, r.output
    text = out.read_text(encoding="utf-8")
    assert "What-if savings" in text and "exhaust recycle 20 %" in text and "<b>exceeded</b>" in text
    bad = CliRunner().invoke(app, ["report", "ajayi2011_mmg", "--audit", str(out), "--out", str(tmp_path / "x.html")])
    assert bad.exit_code == 2 and "not a JSON file" in bad.output and not (tmp_path / "x.html").exists()
    # another operating point's audit (another case's was shown as this dryer's savings; found by fuzzing)
    other = CliRunner().invoke(app, ["report", "ajayi2011_mmg", "--set", "operating.test=2", "--audit",
                                     str(tmp_path / "a" / "audit.json"), "--out", str(tmp_path / "y.html")])
    assert other.exit_code == 2 and "is of another dryer or operating point" in other.output
    assert not (tmp_path / "y.html").exists()
    # a changed feed leaves a burner's heat release as it was: the other duties tell (a 2.5 kg/s report showed the
    # savings of a 4 kg/s audit)
    feed = CliRunner().invoke(app, ["report", "ajayi2011_mmg", "--set", "operating.feed_rate=25", "--audit",
                                    str(tmp_path / "a" / "audit.json"), "--out", str(tmp_path / "y.html")])
    assert feed.exit_code == 2 and "is of another dryer or operating point" in feed.output, feed.output
    assert not (tmp_path / "y.html").exists()
    pdf = CliRunner().invoke(app, ["report", "ajayi2011_mmg", "--out", str(tmp_path / "r.pdf")])
    assert pdf.exit_code == 2 and "unknown file type '.pdf'; use one of .html, .htm" in pdf.output


def test_lee_report_has_an_energy_section():
    """Issue 12: the Invicta dryer gets heat and mass transfer (counter-current raw sugar)."""
    text = build_report("lee2008_invicta")
    assert 'id="energy"' in text
    assert "coupled transport, heat and mass steady state" in text   # which model the key results are


def test_measured_rtd_legend_uses_the_case_baseline():
    """The report's measured-RTD moments are those of `rotarydryer rtd` (rtd_moments with the
    case's baseline): Ajayi test 4 has a lithium background (SD 1.53 min, not 6.2)."""
    from rotarydryer.cases import load_case, measured_rtd_moments
    from rotarydryer.report.figures import plot_rtd
    from rotarydryer.simulation import run_case

    res = run_case("ajayi2011_mmg", {"operating.test": 4}, thermal=False)
    mm = measured_rtd_moments(load_case("ajayi2011_mmg", {"operating.test": 4}))
    assert res.scalars["measured_std_s"] == pytest.approx(mm["std_s"])
    legend = [t.get_text() for t in plot_rtd(res).axes[0].get_legend().get_texts()]
    assert f"SD {mm['std_s'] / 60:.2f} min" in legend[1] and mm["std_s"] / 60 < 3.0


def test_report_cli_unwritable_out_is_bad_input(tmp_path):
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    res = CliRunner().invoke(app, ["report", "invicta", "--out", str(tmp_path)])  # a directory
    assert res.exit_code == 2 and "is a directory; give a file name" in res.output and "out.html" in res.output
    assert "internal error" not in res.output


def test_waterfall_unit_follows_the_size_of_the_dryer():
    """MW for a plant, kW for a pilot drum (whose terms would otherwise all read 0.00 MW)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rotarydryer.report.plots import plot_energy_waterfall

    for total, unit, label in ((8.2e6, "MW", "8.20"), (2.5e4, "kW", "25.00")):
        fig = plot_energy_waterfall({"in": {"gas": total}, "out": {"evaporation": 0.6 * total, "exhaust": 0.4 * total}})
        ax = fig.axes[0]
        assert ax.get_ylabel() == unit
        assert label in [t.get_text() for t in ax.texts]
        plt.close(fig)
