"""Run every ```python block of docs/rtd.md in one namespace (examples must not rot)."""

import re
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[1] / "docs" / "rtd.md"


@pytest.mark.skipif(not DOC.exists(), reason="docs/rtd.md not present")
def test_rtd_doc_examples_run(capsys):
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), flags=re.S)
    assert len(blocks) >= 6
    ns: dict = {}
    for b in blocks:
        exec(compile(b, str(DOC), "exec"), ns)
    out = capsys.readouterr().out
    assert "mean 11.08 min, SD 6.73 min" in out
