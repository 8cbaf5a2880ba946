"""Every command's ``--json`` is strict JSON: written through `rotarydryer._io.json_text` (NaN and inf as null)."""

import json
import re
from pathlib import Path

from typer.testing import CliRunner

import rotarydryer.cli.lab  # noqa: F401  (registers the sub-app)
from rotarydryer.cli import app

CLI = Path(__file__).resolve().parents[2] / "src" / "rotarydryer" / "cli"


def test_no_command_writes_json_by_json_dumps():
    """json.dumps writes NaN as the bare word NaN (not JSON): `lab design-load --json` and `rtd-fit --json` did
    (found by fuzzing). The commands write through json_text."""
    hits = [f"{p.name}:{i}" for p in sorted(CLI.glob("*.py"))
            for i, line in enumerate(p.read_text().splitlines(), 1) if re.search(r"\bjson\.dumps\(", line)]
    assert not hits, hits


def test_design_load_json_with_an_undefined_interval_is_strict(tmp_path):
    """Two photographs before the break: the 'ajayi_corrected' and 'appendix_e' intervals are undefined (NaN); the
    --json output has null there, and parses as strict JSON."""
    rows = [(77.6193, 217.7314), (118.8693, 217.7314), (110.7263, 217.7314), (52.2438, 217.7314),
            (43.7317, 190.8684), (90.8537, 217.7314), (108.3501, 217.7314), (121.2596, 217.7314)]
    p = tmp_path / "dl.csv"
    p.write_text("loading_kg,FUF_area_cm2\n" + "".join(f"{a},{b}\n" for a, b in rows))
    res = CliRunner().invoke(app, ["lab", "design-load", str(p), "--json"])
    assert res.exit_code == 0, res.output
    text = res.output[res.output.index("{"):]

    def refuse(c):
        raise AssertionError(f"non-JSON constant {c}")

    out = json.loads(text.splitlines()[0] if text.count("\n") > 1 else text, parse_constant=refuse)
    assert "null" in text
    assert out["confidence"] == 0.95


def test_simulate_json_records_the_gas_direction_under_its_own_name():
    """`parameters.gas_flow` held the gas *direction* ("co-current"), next to the numeric gas_flow_kg_s (found by
    fuzzing): the record is `parameters.gas_direction`, and the only gas flow is the number in kg/s."""
    res = CliRunner().invoke(app, ["simulate", "lee2008_invicta", "--json"])
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout)
    assert d["parameters"]["gas_direction"] == "counter-current" and "gas_flow" not in d["parameters"]
    assert d["gas_flow_kg_s"] > 0
