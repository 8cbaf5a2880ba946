"""The wheel installs and runs outside the source tree (docs/tutorial.md, "1. Install").

Slow (about half a minute): builds the wheel with ``python -m build --wheel`` from a copy of the
sources (so that the clone gets no ``build/`` folder), installs it into a fresh virtual
environment and runs ``rotarydryer --version`` and a small ``simulate`` with the installed
command. The build is isolated when the build backend in this environment is older than the
one pyproject.toml requires (it then downloads setuptools and wheel from the package index),
and ``--no-isolation`` otherwise. The fresh environment sees this environment's packages (a
``.pth`` line) for the dependencies, so nothing else is downloaded; it must import
rotarydryer from the wheel, not from the clone.
"""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.slow


def _backend_ok() -> bool:
    """setuptools >= 77 and wheel installed here: the build needs no isolation (no download)."""
    if importlib.util.find_spec("setuptools") is None or importlib.util.find_spec("wheel") is None:
        return False
    import setuptools

    return int(setuptools.__version__.split(".")[0]) >= 77


def _run(cmd, **kw):
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=900, **kw)
    assert proc.returncode == 0, f"{' '.join(map(str, cmd))} failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
    return proc


@pytest.mark.skipif(importlib.util.find_spec("build") is None,
                    reason="the build package is not installed: python -m pip install build")
def test_wheel_builds_installs_and_runs(tmp_path):
    src = tmp_path / "src_copy"
    src.mkdir()
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy2(ROOT / name, src / name)
    shutil.copytree(ROOT / "src", src / "src",
                    ignore=shutil.ignore_patterns("__pycache__", "*.egg-info", "*.pyc"))
    dist = tmp_path / "dist"
    cmd = [sys.executable, "-m", "build", "--wheel", "--outdir", str(dist)]
    if _backend_ok():
        cmd.append("--no-isolation")
    _run([*cmd, str(src)], cwd=src)
    wheels = sorted(dist.glob("rotarydryer-*.whl"))
    assert len(wheels) == 1, wheels

    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", "--without-pip", str(venv)])
    bindir = venv / ("Scripts" if os.name == "nt" else "bin")
    py = bindir / ("python.exe" if os.name == "nt" else "python")
    site_dir = Path(_run([str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"]).stdout.strip())
    # the dependencies from this environment (a plain path: its .pth files, such as the editable
    # install of the clone, are not processed)
    (site_dir / "_deps_from_test_env.pth").write_text(sysconfig.get_paths()["purelib"] + "\n", encoding="utf-8")
    _run([sys.executable, "-m", "pip", "--python", str(py), "install", "--no-deps", "--no-index", str(wheels[0])])

    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["MPLBACKEND"] = "Agg"
    work = tmp_path / "work"
    work.mkdir()
    where = _run([str(py), "-c", "import rotarydryer; print(rotarydryer.__file__)"], cwd=work, env=env).stdout
    assert Path(where.strip()).resolve().is_relative_to(site_dir.resolve()), where   # the wheel, not the clone

    exe = bindir / ("rotarydryer.exe" if os.name == "nt" else "rotarydryer")
    assert exe.is_file(), "the wheel installs no rotarydryer command"
    version = _run([str(exe), "--version"], cwd=work, env=env).stdout
    assert version.startswith("rotarydryer "), version
    out = _run([str(exe), "simulate", "song2003_ottawa", "--json"], cwd=work, env=env).stdout
    summary = json.loads(out)
    assert summary["feed_rate_kg_s"] > 0 and summary["total_holdup_kg"] > 0
