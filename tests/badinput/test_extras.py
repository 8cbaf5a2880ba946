"""Lean install (issue 18 part 5): a command whose optional dependency is missing names the extra.

The missing package is simulated by blocking its import (``sys.modules[name] = None``)."""

import sys

import pytest

from rotarydryer._extras import MissingExtraError, require

from .conftest import assert_bad, run_cli, snapshot
from .test_lab_and_data import photo_png  # noqa: F401 - the synthetic drum photograph fixture


def test_require_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "skimage", None)
    with pytest.raises(MissingExtraError, match=r"pip install 'rotarydryer\[lab\]'"):
        require("skimage", "lab", "image analysis", "scikit-image")
    assert require("json", "x", "y").dumps([1]) == "[1]"


@pytest.mark.parametrize("blocked", ["skimage"])      # shapely: only for rendering synthetic photographs
def test_lab_image_without_its_extra(monkeypatch, tmp_path, workdir, photo_png, blocked):  # noqa: F811
    p = tmp_path / "photo.png"
    p.write_bytes(photo_png)
    for name in [m for m in sys.modules if m == blocked or m.startswith(blocked + ".")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, blocked, None)
    before = snapshot(workdir)
    res = run_cli(["lab", "image", p, "--centre", "163,163", "--px-per-m", "400", "--mirror"], cwd=workdir)
    assert_bad(res, "rotarydryer[lab]")
    assert snapshot(workdir) == before


def test_core_commands_do_not_import_the_lab_extra():
    """simulate, rtd and fit import neither scikit-image nor shapely (checked in a fresh interpreter)."""
    import subprocess

    code = ("import sys\n"
            "from typer.testing import CliRunner\n"
            "from rotarydryer.cli import app\n"
            "r = CliRunner().invoke(app, ['simulate', 'song2003_ottawa', '--set', 'thermal.enabled=false', '--json'])\n"
            "assert r.exit_code == 0, r.output\n"
            "r = CliRunner().invoke(app, ['rtd', 'song2003_ottawa', '--json'])\n"
            "assert r.exit_code == 0, r.output\n"
            "bad = sorted(m for m in sys.modules if m.split('.')[0] in ('skimage', 'shapely', 'streamlit', 'SALib'))\n"
            "assert not bad, bad\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]
