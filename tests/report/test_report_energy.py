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
    # the balance table lists inputs and outputs whose difference is the tiny closure
    rows = dict(re.findall(r"<td[^>]*>([a-z ]+ \((?:in|out)\))</td><td[^>]*>([-0-9.]+)</td>", section))
    ins = sum(float(v) for k, v in rows.items() if k.endswith("(in)"))
    outs = sum(float(v) for k, v in rows.items() if k.endswith("(out)"))
    assert ins > 5 and abs(ins - outs) < 0.01 * ins


def test_lee_report_has_no_energy_section():
    text = build_report("lee2008_invicta")
    assert 'id="energy"' not in text
