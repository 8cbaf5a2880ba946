"""Malformed case files: one readable message per problem, with the file line; exit code 2."""

import pytest
from typer.testing import CliRunner

from rotarydryer.cases import load_case
from rotarydryer.cli import app

BAD = """kind = "lee2008"

[drum]
radius = "big"
length = -12.0
slope = 2.8
n_flights = 28
colour = "red"

[operating]
feed_rate = 27.2
rpm = 3.0
"""


def test_every_problem_reported_with_its_line(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(BAD)
    with pytest.raises(ValueError) as err:
        load_case(str(path))
    msg = str(err.value)
    assert "7 problems" in msg
    assert f"{path}:4: drum.radius = 'big'" in msg  # wrong type
    assert f"{path}:5: drum.length = -12.0" in msg and "greater than 0" in msg  # out of range
    assert f"{path}:8: drum.colour is not a known field" in msg  # unknown key
    assert "flight is missing" in msg  # missing section


def test_cli_exit_code_and_no_traceback(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(BAD)
    res = CliRunner().invoke(app, ["simulate", str(path)])
    assert res.exit_code == 2
    assert "Traceback" not in res.output
    assert res.output.count("\n") >= 7


def test_override_problem_names_the_set_option():
    with pytest.raises(ValueError, match=r"--set transport.n_cells"):
        load_case("lee2008_invicta", {"transport.n_cells": -3})


def test_invalid_toml_syntax(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("kind = \n[drum")
    with pytest.raises(ValueError, match="not valid TOML"):
        load_case(str(path))


def _mmg_variant(tmp_path, old, new):
    from importlib import resources

    text = (resources.files("rotarydryer.cases") / "ajayi2011_mmg.toml").read_text()
    assert old in text
    path = tmp_path / "mmg.toml"
    path.write_text(text.replace(old, new, 1))
    return str(path)


def test_incomplete_flighted_section_named(tmp_path):
    """A flighted Ajayi section without n_cells, regression coefficients or flight dimensions is
    reported with its index and field (it used to fail later with a raw TypeError / KeyError)."""
    path = _mmg_variant(tmp_path, "n_cells = 8\n", "")
    with pytest.raises(ValueError, match=r"sections\[1\] \(B\)\.n_cells is missing"):
        load_case(path, {"operating.test": 4})
    thesis = {"operating.test": 4, "geometry.method": "ajayi2011_regressions"}
    path = _mmg_variant(tmp_path, "regression.area = ", "regression.areas = ")
    load_case(path, {"operating.test": 4})  # the exact geometry (default) does not need the regressions
    with pytest.raises(ValueError, match=r"regression\.area = None.*7 coefficients"):
        load_case(path, thesis)
    path = _mmg_variant(tmp_path, "s1 = 0.12\n", "")
    load_case(path, thesis)  # the regressions do not need s1
    with pytest.raises(ValueError, match=r"sections\[1\] \(B\)\.s1 is missing"):
        load_case(path, {"operating.test": 4})
