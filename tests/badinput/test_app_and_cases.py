"""Bad case files from outside and the web app (issue 13; docs/app_threat_model.md).

Every bad case file is checked twice: through the library (``load_case_text`` raises a
``ValueError`` naming the key and the value) and through the real command
(``rotarydryer simulate FILE.toml --json``: exit 2, ``error:`` naming the key, no traceback,
nothing written). The web app is driven through Streamlit's ``AppTest``: an uploaded case naming
a path or a format string is refused with a clear message, and no server file content, exception
text or traceback reaches the page.
"""

from __future__ import annotations

import os
import re
import tempfile
from importlib import resources

import pytest

from rotarydryer.cases import MAX_CASE_BYTES, load_case_text, measured_files

from .conftest import CORPUS_OUTPUTS, assert_bad, run_cli, snapshot

LEE = (resources.files("rotarydryer.cases") / "lee2008_invicta.toml").read_text("utf-8")
MMG = (resources.files("rotarydryer.cases") / "ajayi2011_mmg.toml").read_text("utf-8")
SONG = (resources.files("rotarydryer.cases") / "song2003_ottawa.toml").read_text("utf-8")
#: an old-format file with Lee's Table 7.2 as [[parameter_sets]] (the shipped case holds them as calibration records)
LEE_OLD = (__import__("pathlib").Path(__file__).parents[1] / "data" / "legacy" / "lee2008_invicta.toml").read_text("utf-8")
BASES = {"lee": LEE, "mmg": MMG, "song": SONG, "lee_old": LEE_OLD}
DATA_DIR = str(resources.files("rotarydryer.data"))


def _edit(text: str, table: str, key: str, value: str) -> str:
    """Set ``key = value`` (raw TOML) in ``[table]`` (``sections.1``: the second ``[[sections]]``),
    replacing the key's line or adding it under the header."""
    lines = text.splitlines()
    name, _, idx = table.partition(".")
    if idx.isdigit():
        heads = [i for i, ln in enumerate(lines) if ln.strip() == f"[[{name}]]"]
        start = heads[int(idx)]
    else:
        start = next(i for i, ln in enumerate(lines) if ln.split("#")[0].strip() in (f"[{table}]", f"[[{table}]]"))
    end = next((i for i in range(start + 1, len(lines)) if lines[i].lstrip().startswith("[")), len(lines))
    for i in range(start + 1, end):
        if re.match(rf"\s*{re.escape(key)}\s*=", lines[i]):
            lines[i] = f"{key} = {value}"
            break
    else:
        lines.insert(start + 1, f"{key} = {value}")
    return "\n".join(lines) + "\n"


def _set(base, table, key, value):
    return lambda: _edit(BASES[base], table, key, value)


def _text(base, old, new):
    def make():
        assert old in BASES[base]
        return BASES[base].replace(old, new, 1)
    return make


def _many_sections(n):
    extra = "".join(f'\n[[sections]]\nname = "s{i}"\nkind = "flighted"\nlength = 0.1\nn_cells = 1\n'
                    for i in range(n))
    return lambda: SONG + extra


# (id, case text factory, fragments the message must contain)
CASES = [
    # --- tracer.measured: shipped data sets only, never a path ----------------------------
    ("measured-dotdot", _set("lee", "tracer", "measured", '"../../etc/passwd"'),
     ["tracer.measured", "'../../etc/passwd'", "not a shipped data set", "allowed", "tracer_lee2008_invicta.csv"]),
    ("measured-dotdot-csv", _set("lee", "tracer", "measured", '"../../some/file.csv"'),
     ["tracer.measured", "../../some/file.csv", "not a shipped data set"]),
    ("measured-absolute", _set("lee", "tracer", "measured", '"/etc/passwd"'),
     ["tracer.measured", "/etc/passwd", "paths are refused"]),
    ("measured-dev-zero", _set("lee", "tracer", "measured", '"/dev/zero"'),
     ["tracer.measured", "/dev/zero", "not a shipped data set"]),
    ("measured-backslash", _set("lee", "tracer", "measured", r"'..\..\windows\win.ini'"),
     ["tracer.measured", "windows", "paths are refused"]),
    ("measured-subfolder", _set("lee", "tracer", "measured", '"materials/raw_sugar_lee2008.toml"'),
     ["tracer.measured", "materials/raw_sugar_lee2008.toml", "not a shipped data set"]),
    ("measured-home", _set("lee", "tracer", "measured", '"~/.ssh/id_rsa"'),
     ["tracer.measured", "~/.ssh/id_rsa", "paths are refused"]),
    ("measured-url", _set("lee", "tracer", "measured", '"file:///etc/passwd"'),
     ["tracer.measured", "file:///etc/passwd", "paths are refused"]),
    ("measured-dot-slash", _set("lee", "tracer", "measured", '"./tracer_lee2008_invicta.csv"'),
     ["tracer.measured", "./tracer_lee2008_invicta.csv", "not a shipped data set"]),
    ("measured-nul", _set("lee", "tracer", "measured", r'"tracer_lee2008_invicta.csv\u0000.txt"'),
     ["tracer.measured", "not a shipped data set"]),
    ("measured-other-shipped-file", _set("lee", "tracer", "measured", '"lee_material_properties.csv"'),
     ["tracer.measured", "lee_material_properties.csv", "not a shipped data set", "allowed"]),
    ("measured-shipped-case-file", _set("lee", "tracer", "measured", '"../cases/lee2008_invicta.toml"'),
     ["tracer.measured", "../cases/lee2008_invicta.toml", "not a shipped data set"]),
    ("measured-empty", _set("lee", "tracer", "measured", '""'), ["tracer.measured", "''", "not a shipped data set"]),
    ("measured-5000-chars", _set("lee", "tracer", "measured", '"' + "a" * 5000 + '"'),
     ["tracer.measured", "at most 200 characters"]),
    ("measured-number", _set("lee", "tracer", "measured", "42"), ["tracer.measured", "42", "valid string"]),
    # --- tracer.dataset: a shipped data set, {test} replaced as text ----------------------
    ("dataset-format-mro", _set("mmg", "tracer", "dataset", '"{test.__class__.__mro__}"'),
     ["tracer.dataset", "{test.__class__.__mro__}", "not a shipped data set", "allowed", "ajayi2011_test4"]),
    ("dataset-format-globals", _set("mmg", "tracer", "dataset", '"{test.__init__.__globals__}"'),
     ["tracer.dataset", "__globals__", "not a shipped data set"]),
    ("dataset-format-positional", _set("mmg", "tracer", "dataset", '"ajayi2011_test{0}"'),
     ["tracer.dataset", "ajayi2011_test{0}", "not a shipped data set"]),
    ("dataset-format-width", _set("mmg", "tracer", "dataset", '"ajayi2011_test{test:>999999999}"'),
     ["tracer.dataset", "{test:>999999999}", "not a shipped data set"]),
    ("dataset-path", _set("mmg", "tracer", "dataset", '"../../etc/passwd"'),
     ["tracer.dataset", "../../etc/passwd", "not a shipped data set"]),
    ("dataset-unknown", _set("mmg", "tracer", "dataset", '"ajayi2011_test9"'),
     ["tracer.dataset", "ajayi2011_test9", "not a shipped data set", "allowed"]),
    ("dataset-template-unknown", _set("mmg", "tracer", "dataset", '"lee2008_{test}"'),
     ["tracer.dataset", "lee2008_{test}", "lee2008_4", "not a shipped data set"]),
    ("dataset-placeholder-without-test", _set("lee", "tracer", "dataset", '"ajayi2011_test{test}"'),
     ["tracer.dataset", "ajayi2011_test{test}", "not a shipped data set"]),
    # --- material: a library name, never a file -------------------------------------------
    ("material-absolute-path", _set("lee", "material", "name", '"/etc/evil.toml"'),
     ["material.name", "/etc/evil.toml", "not a material of the library", "raw_sugar_lee2008"]),
    ("material-relative-path", _set("mmg", "material", "name", '"../../../secret.toml"'),
     ["material.name", "../../../secret.toml", "not a material of the library"]),
    ("material-unknown", _set("song", "material", "name", '"cheese"'), ["material.name", "cheese", "allowed"]),
    # --- file format ----------------------------------------------------------------------
    ("kind-unknown", _text("lee", 'kind = "dryer"', 'kind = "rocket"'), ["kind", "rocket", "dryer"]),
    ("kind-missing", _text("lee", 'kind = "dryer"', ""), ["kind", "none", "dryer"]),
    ("kind-number", _text("lee", 'kind = "dryer"', "kind = 3"), ["kind", "3", "dryer"]),
    ("not-toml", lambda: "radius = = 3\n", ["not valid toml"]),
    ("deeply-nested-toml", lambda: "a = " + "[" * 50_000 + "]" * 50_000 + "\n", ["not valid toml", "nested"]),
    ("empty-file", lambda: "", ["kind", "none"]),
    ("unknown-key", _set("lee", "drum", "colour", '"red"'), ["drum.colour", "not a known field"]),
    ("unknown-table", lambda: LEE + "\n[rocket]\nfuel = 1\n", ["rocket", "not a known field"]),
    # --- time grid --------------------------------------------------------------------------
    ("dt-too-fine", _set("lee", "tracer", "dt", "1e-6"),
     ["tracer.t_end", "3600.0", "tracer.dt", "1e-06", "limit is 200000"]),
    ("t-end-huge", _set("mmg", "tracer", "t_end", "1e12"), ["tracer.t_end", "1000000000000.0", "limit is 200000"]),
    ("dryer-dt-too-fine", _set("song", "tracer", "dt", "1e-5"), ["tracer.t_end", "tracer.dt", "1e-05", "200000"]),
    ("dt-above-t-end", _set("lee", "tracer", "dt", "7200.0"), ["tracer.t_end", "tracer.dt", "7200.0", "larger"]),
    ("dt-zero", _set("lee", "tracer", "dt", "0.0"), ["tracer.dt", "0.0", "greater than 0"]),
    ("dt-nan", _set("lee", "tracer", "dt", "nan"), ["tracer.dt", "nan", "finite"]),
    ("t-end-inf", _set("lee", "tracer", "t_end", "inf"), ["tracer.t_end", "inf", "finite"]),
    ("measured-offset-nan", _set("lee", "tracer", "measured_offset", "nan"),
     ["tracer.measured_offset", "nan", "finite"]),
    # --- cells ------------------------------------------------------------------------------
    ("n-cells-million", _set("lee", "transport", "n_cells", "1000000"),
     ["transport.n_cells", "1000000", "less than or equal to 100000"]),
    ("n-cells-zero", _set("lee", "transport", "n_cells", "0"), ["transport.n_cells", "0", "greater than or equal to 1"]),
    ("n-cells-negative", _set("song", "transport", "n_cells", "-5"), ["transport.n_cells", "-5"]),
    ("n-cells-fraction", _set("lee", "transport", "n_cells", "3.5"), ["transport.n_cells", "3.5", "integer"]),
    ("parameter-set-n-cells-huge", _set("lee_old", "parameter_sets.0", "n_cells", "1000000000"),
     ["parameter_sets.0.n_cells", "1000000000"]),
    ("section-n-cells-huge", _set("mmg", "sections.1", "n_cells", "10000000"),
     ["sections.1.n_cells", "10000000", "100000"]),
    ("sections-total-cells", lambda: _edit(_edit(MMG, "sections.1", "n_cells", "60000"), "sections.2", "n_cells",
                                           "60000"),
     ["sections", "cells in all", "limit is 100000"]),
    ("unflighted-cells-huge", _set("mmg", "transport", "unflighted_cells", "10000000"),
     ["transport.unflighted_cells", "10000000"]),
    ("thermal-unflighted-cells-huge", _set("mmg", "thermal", "unflighted_cells", "{A = 1000000, E = 24}"),
     ["thermal.unflighted_cells.a", "1000000"]),
    ("dryer-total-cells", lambda: _edit(SONG, "transport", "n_cells", "90000")
     + '\n[[sections]]\nname = "second"\nkind = "flighted"\nlength = 1.0\nn_cells = 50000\n',
     ["sections", "140000 cells in all", "limit is 100000"]),
    ("sections-1001", _many_sections(1001), ["sections", "at most 1000"]),
    # --- drum, flights, operating -------------------------------------------------------------
    ("radius-negative", _set("lee", "drum", "radius", "-2.5"), ["drum.radius", "-2.5", "greater than 0"]),
    ("radius-nan", _set("lee", "drum", "radius", "nan"), ["drum.radius", "nan", "finite"]),
    ("radius-inf", _set("mmg", "drum", "radius", "inf"), ["drum.radius", "inf", "finite"]),
    ("radius-huge", _set("lee", "drum", "radius", "1e6"), ["drum.radius", "1000000.0", "less than or equal to 20"]),
    ("length-zero", _set("lee", "drum", "length", "0.0"), ["drum.length", "0.0", "greater than 0"]),
    ("length-huge", _set("lee", "drum", "length", "1e9"), ["drum.length", "1000000000.0", "200"]),
    ("section-length-huge", _set("mmg", "sections.0", "length", "1e9"), ["sections.0.length", "1000000000.0"]),
    ("slope-45", _set("lee", "drum", "slope", "45.0"), ["drum.slope", "45.0", "less than 45"]),
    ("slope-negative", _set("song", "drum", "slope", "-1.0"), ["drum.slope", "-1.0"]),
    ("n-flights-million", _set("lee", "drum", "n_flights", "1000000"), ["drum.n_flights", "1000000", "1000"]),
    ("n-flights-one", _set("lee", "drum", "n_flights", "1"), ["drum.n_flights", "1", "greater than or equal to 2"]),
    ("rpm-zero", _set("lee", "operating", "rpm", "0.0"), ["operating.rpm", "0.0", "greater than or equal to 0.1"]),
    ("rpm-61", _set("song", "operating", "rpm", "61.0"), ["operating.rpm", "61.0", "60"]),
    ("rpm-word", _set("lee", "operating", "rpm", '"fast"'), ["operating.rpm", "fast"]),
    ("feed-negative", _set("lee", "operating", "feed_rate", "-1.0"), ["operating.feed_rate", "-1.0"]),
    ("feed-nan", _set("song", "operating", "feed_rate", "nan"), ["operating.feed_rate", "nan", "finite"]),
    ("moisture-above-one", _set("lee", "operating", "feed_moisture", "1.5"), ["operating.feed_moisture", "1.5"]),
    ("ajayi-test-7", _set("mmg", "operating", "test", "7"), ["operating.test", "7", "6"]),
]

assert len({c[0] for c in CASES}) == len(CASES) >= 45


@pytest.mark.parametrize("make, fragments", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_bad_case_library(make, fragments):
    with pytest.raises(ValueError) as err:
        load_case_text(make(), "upload.toml")
    msg = str(err.value)
    for f in fragments:
        assert f.lower() in msg.lower(), f"{f!r} not in:\n{msg}"
    assert len(msg) < 4000  # no file dumps


@pytest.mark.parametrize("make, fragments", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_bad_case_cli(make, fragments, workdir):
    (workdir / "case.toml").write_text(make(), encoding="utf-8")
    before = snapshot(workdir)
    res = run_cli(["simulate", "case.toml", "--json"], cwd=workdir)
    assert_bad(res, *fragments)
    assert snapshot(workdir) == before


# --- bytes that are not text, or too many of them -------------------------------------------
BYTE_CASES = [
    ("non-utf8", b'kind = "lee2008"\n# \xff\xfe caf\xe9\n', ["not utf-8", "0xff"]),
    ("utf16-bom", '\ufeffkind = "lee2008"\n'.encode("utf-16"), ["not utf-8", "0xff"]),
    ("larger-than-limit", b"# " + b"x" * (MAX_CASE_BYTES + 10) + b"\n", ["larger than the limit", str(MAX_CASE_BYTES)]),
]


@pytest.mark.parametrize("content, fragments", [c[1:] for c in BYTE_CASES], ids=[c[0] for c in BYTE_CASES])
def test_bad_case_bytes(content, fragments, workdir):
    with pytest.raises(ValueError) as err:
        load_case_text(content, "upload.toml")
    for f in fragments:
        assert f.lower() in str(err.value).lower()
    (workdir / "case.toml").write_bytes(content)
    before = snapshot(workdir)
    assert_bad(run_cli(["simulate", "case.toml", "--json"], cwd=workdir), "case.toml", *fragments)
    assert snapshot(workdir) == before


def test_device_named_toml_is_refused(workdir):
    """A case path that is not a regular file (here /dev/zero behind a .toml name) is never read."""
    link = workdir / "zero.toml"
    try:
        os.symlink("/dev/zero", link)
    except (OSError, NotImplementedError):
        pytest.skip("no symlinks or no /dev/zero")
    before = snapshot(workdir)
    assert_bad(run_cli(["simulate", "zero.toml", "--json"], cwd=workdir), "zero.toml", "not a regular file")
    assert snapshot(workdir) == before


def test_override_names_a_path():
    """The same rule holds for --set overrides (CLI) and every other loader."""
    from rotarydryer.cases import load_case

    with pytest.raises(ValueError, match=r"--set tracer\.measured: tracer\.measured = '/etc/passwd' is not a shipped"):
        load_case("lee2008_invicta", {"tracer.measured": "/etc/passwd"})
    with pytest.raises(ValueError, match=r"tracer\.dataset = '\{test\.__class__\}' is not a shipped data set"):
        load_case("ajayi2011_mmg", {"tracer.dataset": "{test.__class__}"})


def test_measured_rtd_refuses_a_path_in_a_case_built_in_code():
    """measured_rtd checks the name again before reading (a case built with model_construct)."""
    from rotarydryer.cases import load_case, measured_rtd

    case = load_case("lee2008_invicta", {"tracer.dataset": None})
    bad = case.model_copy(update={"tracer": case.tracer.model_copy(update={"measured": "../../../etc/passwd"})})
    with pytest.raises(ValueError, match="not a shipped data set"):
        measured_rtd(bad)
    assert measured_rtd(case) is not None  # the shipped CSV itself still loads
    assert "lee_rtd_invicta_tracer.csv" in measured_files()


# --- the web app ------------------------------------------------------------------------------
try:
    from streamlit.testing.v1 import AppTest
except ImportError:  # the "app" extra is not installed
    AppTest = None

from rotarydryer.app import PAGES, logic, script_path, streamlit_command  # noqa: E402

needs_streamlit = pytest.mark.skipif(AppTest is None, reason="Streamlit is not installed")

SECRET = "SECRET-SERVER-CONTENT-7f3a"


def _page_text(at) -> str:
    """Everything the page shows (every element's protobuf text)."""
    def walk(node):
        out = [str(node.proto)] if getattr(node, "proto", None) is not None else []
        for child in getattr(node, "children", {}).values():
            out += walk(child)
        return out
    text = "\n".join(walk(at._tree))
    CORPUS_OUTPUTS.append(text)
    return text


def _errors(at) -> str:
    return "\n".join(e.value for e in at.error).replace("\\", "")  # the page escapes Markdown


@pytest.fixture()
def transport_page():
    at = AppTest.from_file(str(script_path()), default_timeout=120)
    at.run()
    at.switch_page(f"entries/{PAGES['Transport and RTD'][1]}.py").run()   # its navigation link
    assert not at.exception and not at.error
    return at


def _upload(at, name, content: bytes):
    at.sidebar.file_uploader(key="case_file").set_value((name, content, "application/toml")).run()
    assert not at.exception, [e.value for e in at.exception]
    return at


@pytest.fixture()
def secret_csv(tmp_path):
    """A tracer CSV outside the shipped data, in the format measured_rtd reads."""
    p = tmp_path / "secret.csv"
    p.write_text(f"# {SECRET}\ntime_s,signal_per_h\n0,{len(SECRET)}\n10,1\n20,0\n", encoding="utf-8")
    return p


@needs_streamlit
@pytest.mark.parametrize("how", ["relative", "absolute", "etc-passwd", "dev-zero"])
def test_app_refuses_uploaded_case_naming_a_path(transport_page, secret_csv, how):
    value = {"relative": os.path.relpath(secret_csv, DATA_DIR), "absolute": str(secret_csv),
             "etc-passwd": "../../etc/passwd", "dev-zero": "/dev/zero"}[how]
    text = _edit(LEE, "tracer", "measured", repr(value))
    at = _upload(transport_page, "evil.toml", text.encode())
    errors = _errors(at)
    assert "Case evil.toml refused" in errors
    for f in ("tracer.measured", value, "is not a shipped data set", "allowed: ", "tracer_lee2008_invicta.csv"):
        assert f in errors, (f, errors)
    page = _page_text(at)
    assert SECRET not in page and "root:" not in page and "Traceback" not in page
    assert not at.metric  # no results from the refused case


@needs_streamlit
def test_app_refuses_format_string_dataset(transport_page):
    text = _edit(MMG, "tracer", "dataset", '"{test.__class__.__mro__}"')
    at = _upload(transport_page, "fmt.toml", text.encode())
    errors = _errors(at)
    for f in ("tracer.dataset", "{test.__class__.__mro__}", "not a shipped data set", "ajayi2011_test4"):
        assert f in errors, (f, errors)
    page = _page_text(at)
    assert "<class" not in page and "object" not in page  # never evaluated
    assert not at.metric


@needs_streamlit
@pytest.mark.parametrize("name, content, fragment", [
    ("non-utf8", b'kind = "lee2008"\n\xff\xfe\n', "not a valid UTF-8 TOML file"),
    ("not-toml", b"radius = = 3", "not a valid UTF-8 TOML file"),
    ("too-large", b"#" * (logic.MAX_CASE_UPLOAD_BYTES + 1), f"limit is {logic.MAX_CASE_UPLOAD_BYTES} bytes"),
    ("material-path", _edit(LEE, "material", "name", '"/etc/evil.toml"').encode(), "not a material of the library"),
    ("huge-time-grid", _edit(LEE, "tracer", "dt", "1e-9").encode(), "limit is 200000"),
], ids=lambda v: v if isinstance(v, str) and len(v) < 20 else "")
def test_app_refuses_bad_upload(transport_page, name, content, fragment):
    at = _upload(transport_page, f"{name}.toml", content)
    assert fragment in _errors(at)
    assert "Traceback" not in _page_text(at) and not at.metric


@needs_streamlit
def test_app_hides_unexpected_errors(transport_page, monkeypatch):
    """A non-input error (a bug) shows a generic sentence: no message text, no traceback."""
    def boom(*a, **k):
        raise RuntimeError(f"{SECRET} from /etc/shadow")

    monkeypatch.setattr(logic, "case_defaults", boom)
    at = _upload(transport_page, "ok.toml", LEE.encode())
    assert "internal error (RuntimeError)" in _errors(at)
    page = _page_text(at)
    assert SECRET not in page and "/etc/shadow" not in page and "Traceback" not in page


@needs_streamlit
def test_app_tracer_csv_too_many_rows(transport_page):
    rows = "".join(f"{i},{i % 7}\n" for i in range(logic.MAX_TRACER_ROWS + 5))
    at = transport_page
    at.file_uploader(key="tracer_file").set_value(("big.csv", ("time_s,signal\n" + rows).encode(), "text/csv")).run()
    assert not at.exception
    assert f"limit is {logic.MAX_TRACER_ROWS}" in _errors(at)


def test_upload_writes_nothing(tmp_path, monkeypatch):
    """Uploaded cases stay in memory (bounded); nothing is staged in the temporary folder."""
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    keys = [logic.stage_case_file(_edit(LEE, "operating", "rpm", f"{3 + i / 10}").encode())
            for i in range(logic.MAX_STAGED_CASES + 3)]
    assert logic.case_defaults(keys[-1])["rpm"] == pytest.approx(3 + (logic.MAX_STAGED_CASES + 2) / 10)
    assert list(tmp_path.iterdir()) == []
    assert len(logic._staged) <= logic.MAX_STAGED_CASES
    with pytest.raises(ValueError, match="no longer held"):
        logic.case_defaults(keys[0])  # the oldest was dropped
    with pytest.raises(ValueError, match="not a built-in case"):
        logic.case_defaults("/etc/passwd")


def test_server_command_hides_error_details():
    cmd = streamlit_command(8765)
    assert cmd[cmd.index("--client.showErrorDetails") + 1] == "none"
    assert cmd[cmd.index("--server.maxUploadSize") + 1] == str(logic.MAX_UPLOAD_MB) == "1"
