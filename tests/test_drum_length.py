"""``drum.length`` of a sectioned case (issue 27): optional, and when given it must equal the sum of
the sections' lengths; a disagreement names both keys and where the value came from."""

from importlib import resources

import pytest
from typer.testing import CliRunner

from rotarydryer.cases import load_case
from rotarydryer.cli import app

TEMPLATE = resources.files("rotarydryer.cases") / "templates" / "dryer.toml"


@pytest.mark.parametrize("case", ["ajayi2011_mmg", str(TEMPLATE)])
def test_a_length_that_matches_the_sections_loads(case):
    total = sum(s.length for s in load_case(case).sections)
    c = load_case(case, {"drum.length": total})
    assert c.drum.length == total


@pytest.mark.parametrize("case", ["ajayi2011_mmg", str(TEMPLATE)])
def test_a_length_that_disagrees_names_both_keys(case):
    with pytest.raises(ValueError) as err:
        load_case(case, {"drum.length": 99.0})
    msg = str(err.value)
    assert "--set drum.length: drum.length = 99 m disagrees" in msg
    assert "sections[0].length = " in msg


def test_a_file_that_sets_the_length_twice_points_at_the_line(tmp_path):
    text = TEMPLATE.read_text("utf-8")
    assert "[drum]\n" in text
    path = tmp_path / "twice.toml"
    path.write_text(text.replace("[drum]\n", "[drum]\nlength = 5.0\n", 1))
    line = path.read_text().splitlines().index("length = 5.0") + 1
    r = CliRunner().invoke(app, ["simulate", str(path)])
    assert r.exit_code == 2
    assert f"twice.toml:{line}: drum.length = 5 m disagrees with the sections' lengths" in r.output
    assert "Traceback" not in r.output
