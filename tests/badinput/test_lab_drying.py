"""Bad-input corpus for ``rotarydryer lab drying`` (thin-layer drying laws from drying curves, issue 34).

Every case runs the real command in an empty working folder with ``--out res`` and
``--material-out mat.toml`` where the case allows, and checks the contract: exit code 2, an ``error:``
line naming the file and line or the option, the value and the allowed range, no traceback,
nothing written to (or changed in) the folder.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotarydryer.properties import thin_layer as tl

from .conftest import assert_bad, run_cli, snapshot

HEAD = "time_min,moisture_kg_kg_dry,air_temperature_degC\n"
ROWS = "0,0.30,50\n10,0.22,50\n20,0.16,50\n30,0.12,50\n0,0.30,70\n10,0.18,70\n20,0.11,70\n30,0.07,70\n"
GOOD = HEAD + ROWS
OUT = ["--out", "res", "--material-out", "mat.toml", "--base-material", "ottawa_sand_song2003"]

CASES = [
    # id, file content (None: no file; "DIR": a directory), extra args, fragments of the message
    ("missing-file", None, [], ["curves.csv", "does not exist"]),
    ("directory", "DIR", [], ["curves.csv", "is a directory"]),
    ("empty-file", "", [], ["curves.csv", "empty file", "header"]),
    ("comments-only", "# lab log\n# nothing\n", [], ["curves.csv", "empty file"]),
    ("header-only", HEAD, [], ["curves.csv", "no data rows"]),
    ("numeric-header", "0,0.3,50\n10,0.2,50\n", [], ["curves.csv line 1", "not a header", "time_min"]),
    ("no-time-column", "t,moisture_kg_kg_dry,air_temperature_degC\n0,0.3,50\n", [],
     ["curves.csv line 1", "no time column", "time_s, time_min, time_h"]),
    ("unknown-time-unit", "time_days,moisture_kg_kg_dry,air_temperature_degC\n0,0.3,50\n", [],
     ["curves.csv line 1", "no time column", "time_days"]),
    ("no-moisture-column", "time_min,moisture,air_temperature_degC\n0,0.3,50\n", [],
     ["curves.csv line 1", "no moisture column", "moisture_kg_kg_dry, moisture_kg_kg_wet"]),
    ("two-moisture-columns", "time_min,moisture_kg_kg_dry,moisture_kg_kg_wet,air_temperature_degC\n0,0.3,0.23,50\n",
     [], ["curves.csv line 1", "2 moisture columns"]),
    ("no-temperature-column", "time_min,moisture_kg_kg_dry,air_temp\n0,0.3,50\n", [],
     ["curves.csv line 1", "no temperature column", "air_temperature_degC"]),
    ("repeated-column", "time_min,moisture_kg_kg_dry,air_temperature_degC,note,note\n0,0.3,50,a,b\n", [],
     ["curves.csv line 1", "'note' appears twice"]),
    ("text-in-moisture", HEAD + "0,0.30,50\n10,abc,50\n20,0.16,50\n", [],
     ["curves.csv line 3", "'abc' is not a number in column moisture_kg_kg_dry"]),
    ("empty-field", HEAD + "0,0.30,50\n10,,50\n20,0.16,50\n", [],
     ["curves.csv line 3", "empty field", "moisture_kg_kg_dry"]),
    ("nan-temperature", HEAD + "0,0.30,50\n10,0.2,nan\n20,0.16,50\n", [],
     ["curves.csv line 3", "NaN or infinite"]),
    ("negative-time", HEAD + "0,0.30,50\n-10,0.2,50\n20,0.16,50\n", [],
     ["curves.csv line 3", "time_min = -10 is outside the allowed range [0,"]),
    ("wet-moisture-above-1", "time_min,moisture_kg_kg_wet,air_temperature_degC\n0,1.2,50\n10,0.2,50\n20,0.1,50\n", [],
     ["curves.csv line 2", "moisture_kg_kg_wet = 1.2 is outside the allowed range [0, 1) kg/kg wet"]),
    ("wet-moisture-1", "time_min,moisture_kg_kg_wet,air_temperature_degC\n0,1,50\n10,0.2,50\n20,0.1,50\n", [],
     ["curves.csv line 2", "moisture_kg_kg_wet = 1 is outside the allowed range [0, 1)"]),
    ("negative-moisture", HEAD + "0,0.30,50\n10,-0.1,50\n20,0.16,50\n", [],
     ["curves.csv line 3", "moisture_kg_kg_dry = -0.1 is outside the allowed range [0, 50) kg/kg dry"]),
    ("air-too-hot", HEAD + "0,0.30,500\n10,0.2,500\n20,0.16,500\n", [],
     ["curves.csv line 2", "air_temperature_degC = 500 is outside the allowed range [0, 400] degC"]),
    ("rising-moisture", HEAD + "0,0.30,50\n10,0.20,50\n20,0.26,50\n30,0.12,50\n", [],
     ["curves.csv line 4", "the moisture rises to 0.26 kg/kg dry after 0.2", "at most 0.05"]),
    ("below-equilibrium", HEAD + "0,0.30,50\n10,0.20,50\n20,0.01,50\n", ["--equilibrium-moisture", "0.05"],
     ["curves.csv line 4", "below its equilibrium moisture 0.05"]),
    ("curve-not-at-zero", HEAD + "5,0.30,50\n10,0.20,50\n20,0.16,50\n", [],
     ["curves.csv line 2", "starts at time 300 s", "initial moisture at time 0"]),
    ("time-not-increasing", HEAD + "0,0.30,50\n20,0.20,50\n10,0.16,50\n", [],
     ["curves.csv line 4", "time 600 s of curve '50' is not after the previous 1200 s"]),
    ("temperature-drifts", "time_min,moisture_kg_kg_dry,air_temperature_degC,curve\n0,0.3,50,A\n10,0.2,55,A\n20,0.1,50,A\n",
     [], ["curves.csv line 3", "air_temperature_degC = 55 differs from the first row of curve 'A' (50) by more than 2"]),
    ("equilibrium-varies", "time_min,moisture_kg_kg_dry,air_temperature_degC,equilibrium_moisture_kg_kg_dry\n"
     "0,0.3,50,0.01\n10,0.2,50,0.02\n20,0.1,50,0.01\n", [], ["curves.csv line 3", "equilibrium moisture 0.02", "one value per curve"]),
    ("equilibrium-twice", "time_min,moisture_kg_kg_dry,air_temperature_degC,equilibrium_moisture_kg_kg_dry\n"
     "0,0.3,50,0.01\n10,0.2,50,0.01\n20,0.1,50,0.01\n", ["--equilibrium-moisture", "0.01"],
     ["curves.csv line 1", "equilibrium column", "give one"]),
    ("nothing-to-dry", HEAD + "0,0.30,50\n10,0.28,50\n20,0.27,50\n", ["--equilibrium-moisture", "0.3"],
     ["curves.csv line 2", "initial moisture 0.3 kg/kg dry of curve '50' is not above its equilibrium moisture 0.3"]),
    ("too-few-rows", HEAD + "0,0.30,50\n10,0.20,50\n", [],
     ["curves.csv", "curve '50' has 2 rows", "at least 3"]),
    ("empty-curve-label", "time_min,moisture_kg_kg_dry,air_temperature_degC,curve\n0,0.3,50,A\n10,0.2,50,\n", [],
     ["curves.csv line 3", "empty field in column curve"]),
    ("short-row", HEAD + "0,0.30,50\n10,0.20\n20,0.16,50\n", [], ["curves.csv line 3", "2 columns, expected 3"]),
    ("fewer-points-than-parameters", HEAD + "0,0.30,50\n10,0.20,50\n20,0.15,50\n0,0.30,70\n10,0.18,70\n20,0.12,70\n",
     ["--model", "midilli"], ["--model = 'midilli' could not be fitted", "4 points after time 0 for 5 parameters"]),
    ("non-utf8", b"# caf\xe9\n" + GOOD.encode(), [], ["curves.csv line 1", "not UTF-8", "0xe9"]),
    ("binary", bytes(range(256)) * 4, [], ["curves.csv line 1", "binary"]),
    ("opt-model", GOOD, ["--model", "weibull"], ["--model = 'weibull' is not one of lewis, page"]),
    ("opt-equilibrium", GOOD, ["--equilibrium-moisture", "-1"],
     ["--equilibrium-moisture = -1 kg/kg dry is outside the allowed range", "[0, 50)"]),
    ("opt-reference-temperature", GOOD, ["--reference-temperature", "900"],
     ["--reference-temperature = 900 degC is outside the allowed range", "[0, 400]"]),
    ("opt-particle-diameter", GOOD, ["--particle-diameter", "0"], ["--particle-diameter = 0 m", "(0, 0.2)"]),
    ("opt-base-material", GOOD, ["--base-material", "granite"], ["--base-material = 'granite' is not one of"]),
    ("opt-material-name", GOOD, ["--material-name", "raw_sugar_lee2008"],
     ["--material-name = 'raw_sugar_lee2008' is a library material"]),
    ("opt-material-name-path", GOOD, ["--material-name", "../x"], ["--material-name = '../x' is not a plain name"]),
]


def _write(workdir, content):
    p = workdir / "curves.csv"
    if content == "DIR":
        p.mkdir()
    elif isinstance(content, bytes):
        p.write_bytes(content)
    elif content is not None:
        p.write_text(content, encoding="utf-8")


@pytest.mark.parametrize("case_id, content, extra, fragments", CASES, ids=[c[0] for c in CASES])
def test_lab_drying_bad_input(workdir, case_id, content, extra, fragments):
    _write(workdir, content)
    before = snapshot(workdir)
    args = OUT if "--base-material" not in extra else ["--out", "res", "--material-out", "mat.toml"]
    res = run_cli(["lab", "drying", "curves.csv", *args, *extra], cwd=workdir)
    assert_bad(res, *fragments)
    assert len([ln for ln in res.output.splitlines() if ln.strip()]) == 1, res.output
    assert "np.float" not in res.output and "array(" not in res.output, res.output
    assert snapshot(workdir) == before, "the failing command changed the working folder"
    assert not (workdir / "res").exists() and not (workdir / "mat.toml").exists()


@pytest.mark.parametrize("extra, fragments", [
    (["--material-out", "mat.toml"], ["--material-out needs --base-material NAME"]),
    (["--material-out", "mat.txt", "--base-material", "ottawa_sand_song2003"], ["--material-out 'mat.txt' is not a .toml"]),
    (["--base-material", "ottawa_sand_song2003"], ["--base-material is given without --material-out"]),
    (["--material-out", "curves.toml", "--base-material", "ottawa_sand_song2003"], ["is the drying-curve file itself"]),
    (["--out", "afile"], ["--out 'afile' is an existing file"]),
])
def test_lab_drying_bad_options(workdir, extra, fragments):
    (workdir / "curves.toml").write_text(GOOD, encoding="utf-8")   # a CSV under a .toml name, for the self-overwrite case
    (workdir / "afile").write_text("keep me", encoding="utf-8")
    before = snapshot(workdir)
    res = run_cli(["lab", "drying", "curves.toml", *extra], cwd=workdir)
    assert_bad(res, *fragments)
    assert snapshot(workdir) == before


def test_law_that_is_not_a_drying_law_writes_nothing(workdir):
    """A Midilli fit with b > 0 (moisture rising at long times) is reported but not written as a material."""
    rows = ["time_s,moisture_kg_kg_dry,air_temperature_degC"]
    t = np.arange(0, 61, 5) * 60.0
    rows += [f"{ti:g},{0.3 * m:.6f},60" for ti, m in zip(t, tl._mr("midilli", t, {"a": 1.0, "k": 5e-3, "n": 0.75, "b": 2e-5}))]
    (workdir / "curves.csv").write_text("\n".join(rows) + "\n", encoding="utf-8")
    before = snapshot(workdir)
    res = run_cli(["lab", "drying", "curves.csv", "--model", "midilli", *OUT], cwd=workdir)
    assert_bad(res, "the midilli law cannot be written as a material", "material.kinetics.parameters.b",
               "b > 0 makes the moisture rise")
    assert snapshot(workdir) == before


def test_good_curves_pass(workdir):
    """The corpus' good file is accepted (so each case fails for its own reason)."""
    (workdir / "curves.csv").write_text(GOOD, encoding="utf-8")
    res = run_cli(["lab", "drying", "curves.csv", *OUT], cwd=workdir)
    assert res.exit_code == 0, res.output
    assert (workdir / "res" / "drying_fit.png").exists() and (workdir / "mat.toml").exists()
