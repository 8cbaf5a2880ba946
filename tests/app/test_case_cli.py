"""``rotarydryer schema``, ``cases``, ``new``."""

import json

import pytest
from typer.testing import CliRunner

from rotarydryer.cases import list_cases, load_case
from rotarydryer.cli import app as cli
from rotarydryer.cli import schema as _schema  # noqa: F401  (registers the commands)

runner = CliRunner()


def test_schema_covers_both_kinds(tmp_path):
    res = runner.invoke(cli, ["schema"])
    assert res.exit_code == 0, res.output
    s = json.loads(res.output)
    assert s["$schema"].endswith("2020-12/schema")
    defs = s["$defs"]
    assert {"LeeCase", "AjayiCase"} <= set(defs)
    assert defs["Drum"]["properties"]["radius"]["exclusiveMinimum"] == 0
    assert defs["LeeOperating"]["properties"]["rpm"]["maximum"] == 60
    assert s["discriminator"]["propertyName"] == "kind"
    res = runner.invoke(cli, ["schema", "--kind", "lee2008", "-o", str(tmp_path / "lee.json")])
    assert res.exit_code == 0
    assert json.loads((tmp_path / "lee.json").read_text())["title"] == "LeeCase"
    res = runner.invoke(cli, ["schema", "--kind", "nope"])
    assert res.exit_code == 2 and "kind" in res.output


def test_schema_validates_packaged_cases():
    jsonschema = pytest.importorskip("jsonschema")
    import tomllib
    from importlib import resources

    s = json.loads(runner.invoke(cli, ["schema"]).output)
    for name in list_cases():
        raw = tomllib.loads((resources.files("rotarydryer.cases") / f"{name}.toml").read_text())
        jsonschema.validate(raw, s)
    bad = dict(raw, drum={**raw["drum"], "radius": -1.0})
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(bad, s)


def test_cases_lists_builtins():
    res = runner.invoke(cli, ["cases", "--json"])
    assert res.exit_code == 0
    rows = json.loads(res.output)
    assert [r["name"] for r in rows] == list_cases()
    assert all(r["kind"] in ("dryer", "lee2008", "ajayi2011") and r["title"] for r in rows)
    res = runner.invoke(cli, ["cases"])
    assert "lee2008_invicta" in res.output and "ajayi2011_mmg" in res.output


@pytest.mark.parametrize("base", ["lee2008_invicta", "ajayi2011_mmg"])
def test_new_writes_a_loadable_template(tmp_path, base):
    p = tmp_path / "mine.toml"
    res = runner.invoke(cli, ["new", "mine", "--from", base, "-o", str(p)])
    assert res.exit_code == 0, res.output
    text = p.read_text()
    assert text.startswith("# Case 'mine'") and "# m" in text  # unit comments kept
    case = load_case(str(p))
    assert case.meta.title == f"mine (from {base})"
    mine, shipped = case.model_dump(exclude={"meta"}), load_case(base).model_dump(exclude={"meta"})
    assert [r["case"] for r in mine["calibrations"]] == [f"mine (from {base})"] * len(mine["calibrations"])
    for d in (mine, shipped):            # the base's calibrations, now named for the copy
        d["calibrations"] = [{k: v for k, v in r.items() if k != "case"} for r in d["calibrations"]]
    assert mine == shipped
    res = runner.invoke(cli, ["new", "mine", "-o", str(p)])
    assert res.exit_code == 2 and "exists" in res.output
    assert runner.invoke(cli, ["new", "mine", "-o", str(p), "--force"]).exit_code == 0


def test_new_with_a_toml_name_writes_that_file(tmp_path, monkeypatch):
    """`rotarydryer new mine.toml` writes mine.toml (not mine.toml.toml), titled "mine"."""
    monkeypatch.chdir(tmp_path)
    res = runner.invoke(cli, ["new", "mine.toml"])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "mine.toml").exists() and not (tmp_path / "mine.toml.toml").exists()
    assert 'title = "mine (from template)"' in (tmp_path / "mine.toml").read_text()


def test_new_bad_arguments(tmp_path):
    assert runner.invoke(cli, ["new", "bad/name"]).exit_code == 2
    res = runner.invoke(cli, ["new", "x", "--from", "nope", "-o", str(tmp_path / "x.toml")])
    assert res.exit_code == 2 and "nope" in res.output
