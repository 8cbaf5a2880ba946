"""The report shows the energy balance of cases with a heat and mass transfer model."""

import re

import pytest

pytest.importorskip("xarray")

from rotarydryer.report.html import build_report  # noqa: E402


def test_ajayi_report_has_energy_balance_section():
    text = build_report("ajayi2011_mmg", {"operating.test": 4})
    section = text[text.index('id="energy"'):]
    assert "energy balance waterfall" in section
    assert "thermal profiles" in section
    # the heat-duty table (kW): the heat input and where it goes (evaporation, heating of solids,
    # shell loss, exhaust), which add up to it
    rows = dict(re.findall(r"<td[^>]*>([a-z ]+ \((?:in|out)\))</td><td[^>]*>([-0-9.,]+)</td>", section))
    kw = {k: float(v.replace(",", "")) for k, v in rows.items()}
    assert set(kw) == {"heat input (in)", "evaporation (out)", "heating of solids (out)", "shell loss (out)",
                       "exhaust (out)"}
    ins = sum(v for k, v in kw.items() if k.endswith("(in)"))
    outs = sum(v for k, v in kw.items() if k.endswith("(out)"))
    assert ins > 5000 and abs(ins - outs) < 0.01 * ins
    words = re.sub(r'src="data:[^"]*"', "", section.split("<h3>Temperature")[0])
    assert "MW" not in words and "(kW)" not in words and "<th class=\"\">kW</th>" in words  # duties in kW


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
    assert res.exit_code == 2 and "cannot write" in res.output and "internal error" not in res.output


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
