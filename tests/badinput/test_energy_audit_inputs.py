"""Bad input of the energy audit (issue 34 item 5): the exhaust recycle fraction, the site's altitude,
the shell's temperature limit and the what-if options of ``rotarydryer audit``. Each: exit 2, one
``error:`` line naming the key or option, the value and the allowed range; nothing written."""

from __future__ import annotations

import pytest

from .conftest import assert_bad, run_cli, snapshot

CASES = [
    ("recycle-one", ["simulate", "ajayi2011_mmg", "--set", "gas.recycle_fraction=1"],
     ["gas.recycle_fraction", "'1'", "[0, 1)"]),
    ("recycle-above-one", ["simulate", "ajayi2011_mmg", "--set", "gas.recycle_fraction=1.5"],
     ["gas.recycle_fraction", "1.5", "[0, 1)"]),
    ("recycle-negative", ["simulate", "ajayi2011_mmg", "--set", "gas.recycle_fraction=-0.1"],
     ["gas.recycle_fraction", "-0.1", "[0, 1)"]),
    ("recycle-nan", ["simulate", "ajayi2011_mmg", "--set", "gas.recycle_fraction=nan"],
     ["gas.recycle_fraction", "nan"]),
    ("recycle-leaves-no-fresh-air", ["simulate", "ajayi2011_mmg", "--set", "gas.recycle_fraction=0.9",
                                     "--set", "gas.leak_air_flow=20"],
     ["gas.recycle_fraction = 0.9", "gas.leak_air_flow", "below"]),
    ("altitude-too-high", ["simulate", "ajayi2011_mmg", "--set", "site.altitude=6000"],
     ["site.altitude", "6000", "[-500, 5000] m"]),
    ("altitude-too-low", ["simulate", "ajayi2011_mmg", "--set", "site.altitude=-1000"],
     ["site.altitude", "-1000", "[-500, 5000] m"]),
    ("shell-limit-zero", ["simulate", "ajayi2011_mmg", "--set", "shell.max_temperature=0"],
     ["shell.max_temperature", "'0'", "(0, 1500] degC"]),
    ("shell-limit-negative", ["simulate", "ajayi2011_mmg", "--set", "shell.max_temperature=-5"],
     ["shell.max_temperature", "-5", "(0, 1500] degC"]),
    ("audit-recycle-one", ["audit", "ajayi2011_mmg", "--recycle", "0.1,1"], ["gas.recycle_fraction", "[0, 1)"]),
    ("audit-recycle-word", ["audit", "ajayi2011_mmg", "--recycle", "0.1,half"], ["--recycle", "'half'"]),
    ("audit-preheat-boils", ["audit", "ajayi2011_mmg", "--preheat", "80"], ["--preheat 80", "99 degC"]),
    ("audit-preheat-negative", ["audit", "ajayi2011_mmg", "--preheat", "-5"], ["--preheat -5", "> 0 K"]),
    ("audit-insulation-too-thick", ["audit", "ajayi2011_mmg", "--insulation", "3"],
     ["shell.insulation_thickness", "3", "[0, 2] m"]),
    ("audit-no-gas", ["audit", "song2003_ottawa", "--set", "thermal.enabled=false"], ["heat and mass transfer"]),
]


@pytest.mark.parametrize("name,argv,fragments", CASES, ids=[c[0] for c in CASES])
def test_bad_energy_audit_input(name, argv, fragments, tmp_path):
    before = snapshot(tmp_path)
    res = run_cli([*argv, "--out", str(tmp_path / "out")], cwd=tmp_path)
    assert_bad(res, *fragments)
    errors = [line for line in res.output.splitlines() if line.startswith("error:")]
    assert len(errors) == 1, res.output
    assert snapshot(tmp_path) == before                    # nothing written


def test_library_refuses_a_recycle_of_one_naming_the_key():
    from rotarydryer import Simulation

    with pytest.raises(ValueError, match=r"gas\.recycle_fraction.*\[0, 1\)"):
        Simulation("ajayi2011_mmg", {"gas.recycle_fraction": 1.0})


def test_audit_out_under_a_file_is_refused_before_the_what_ifs(tmp_path):
    (tmp_path / "notes.txt").write_text("x", encoding="utf-8")
    before = snapshot(tmp_path)
    res = run_cli(["audit", "ajayi2011_mmg", "--recycle", "0.2", "--out", "notes.txt/audit"], cwd=tmp_path)
    assert_bad(res, "--out", "notes.txt", "is a file")
    assert "steady state" not in res.output                 # refused up front, nothing computed
    assert snapshot(tmp_path) == before
