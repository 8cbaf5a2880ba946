"""Shared helpers of the bad-input corpus (issue 13).

Every corpus case runs a real command (in-process through the typer app, the same code as the
``rotarydryer`` executable) or a library call, and checks the contract of the failure boundary:
exit code 2, ``error: ...`` naming the key/option/path, no traceback, no output file changed or
left behind. Each case adds its combined output to ``CORPUS_OUTPUTS`` so that a final test can
count tracebacks over all of them.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from typer.testing import CliRunner

from rotarydryer.cli import app

CORPUS_OUTPUTS: list[str] = []
_runner = CliRunner()


def run_cli(args, cwd=None, input=None):
    """Invoke ``rotarydryer ARGS`` in-process (in ``cwd`` when given); returns the click Result
    with ``.output`` (stdout+stderr)."""
    old = os.getcwd()
    if cwd is not None:
        os.chdir(cwd)
    try:
        res = _runner.invoke(app, [str(a) for a in args], input=input)
    finally:
        os.chdir(old)
    CORPUS_OUTPUTS.append(res.output + (repr(res.exception) if res.exception and not isinstance(
        res.exception, SystemExit) else ""))
    return res


def assert_bad(res, *fragments, code=2):
    """Exit ``code`` (2), a one-line-ish ``error:`` message containing every fragment
    (case-insensitive), and no traceback."""
    out = res.output
    assert res.exit_code == code, f"exit {res.exit_code} (expected {code}); output:\n{out}\n{res.exception!r}"
    assert "Traceback" not in out, out
    assert res.exception is None or isinstance(res.exception, SystemExit), repr(res.exception)
    assert "error:" in out.lower(), out
    low = out.lower()
    for f in fragments:
        assert str(f).lower() in low, f"{f!r} not in message:\n{out}"


def snapshot(folder) -> dict:
    """{relative path: (size, mtime_ns, mode)} of every file under ``folder`` (to prove nothing
    changed or was left behind)."""
    folder = Path(folder)
    out = {}
    for p in folder.rglob("*"):
        if p.is_file() or p.is_symlink():
            st = p.lstat()
            out[str(p.relative_to(folder))] = (st.st_size, st.st_mtime_ns, st.st_mode)
    return out


@pytest.fixture
def workdir(tmp_path):
    """An empty working folder; the test asserts that a failing command left it as it was."""
    d = tmp_path / "work"
    d.mkdir()
    return d
