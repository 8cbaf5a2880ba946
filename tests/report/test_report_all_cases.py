"""``rotarydryer report`` on every shipped case and on the ``rotarydryer new`` template (through
:func:`rotarydryer.report.html.write_report`, what the command runs: the case, the report, its
validation section), and the command's ``--debug``: an internal error shows its traceback."""

import re
import subprocess
import sys
import textwrap

import pytest
from typer.testing import CliRunner

pytest.importorskip("xarray")

from rotarydryer.cases import list_cases  # noqa: E402
from rotarydryer.cli import app  # noqa: E402

runner = CliRunner()


@pytest.fixture(scope="module")
def template(tmp_path_factory):
    path = tmp_path_factory.mktemp("new") / "mydryer.toml"
    res = runner.invoke(app, ["new", "mydryer", "--out", str(path)])
    assert res.exit_code == 0, res.output
    return path


def _visible_text(html: str) -> str:
    """The report without its embedded pictures (base64 data may spell 'nan')."""
    return re.sub(r"data:[a-z]+/[a-z+.-]+;base64,[A-Za-z0-9+/=]+", "", html)


@pytest.mark.slow
@pytest.mark.parametrize("source", ["template", *list_cases()])
def test_report_of_every_case(source, template, tmp_path):
    from rotarydryer.report.html import write_report

    src = str(template) if source == "template" else source
    out = write_report(src, tmp_path / "report.html")
    assert out.is_file() and out.stat().st_size > 50_000
    text = _visible_text(out.read_text(encoding="utf-8"))
    assert "<html" in text and "</html>" in text
    for bad in ("internal error", "Traceback"):
        assert bad not in text, (source, bad)
    hits = [text[max(0, m.start() - 80):m.end() + 40] for m in re.finditer(r"(?i)\bnan\b", text)]
    assert not hits, (source, hits[:3])


def _boom_script(out, debug: bool) -> str:
    return textwrap.dedent(f"""
        import rotarydryer.report.html as h

        def boom(*args, **kwargs):
            raise RuntimeError("boom in render_report")

        h.render_report = boom
        from rotarydryer.cli import app
        app({["--debug"] if debug else []!r} + ["report", "invicta", "-o", {str(out)!r}])
    """)


def test_internal_error_is_one_line_without_debug(tmp_path, monkeypatch):
    import rotarydryer.report.html as h

    def boom(*args, **kwargs):
        raise RuntimeError("boom in render_report")

    monkeypatch.setattr(h, "render_report", boom)
    res = runner.invoke(app, ["report", "invicta", "-o", str(tmp_path / "r.html")])
    assert res.exit_code == 1
    assert "internal error (RuntimeError)" in res.output and "--debug" in res.output
    assert "Traceback" not in res.output
    assert not (tmp_path / "r.html").exists()


def test_debug_shows_the_traceback_of_an_internal_error(tmp_path):
    p = subprocess.run([sys.executable, "-c", _boom_script(tmp_path / "r.html", debug=True)], capture_output=True,
                       text=True, timeout=120)
    assert p.returncode != 0
    assert "Traceback (most recent call last)" in p.stderr, p.stderr[-2000:]
    assert "RuntimeError: boom in render_report" in p.stderr
