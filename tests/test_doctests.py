"""Doctests of every public module are collected (issue 18).

pytest does not collect doctests by default (no ``--doctest-modules`` in pyproject: it would
import every module, including the Streamlit app). This test finds every module of the package
whose source contains ``>>>`` and runs ``doctest.testmod`` on it, except the modules that
other test files already run (listed in ``ELSEWHERE``, so that no doctest runs twice) and the
ones in ``SKIP`` with the reason.
"""

from __future__ import annotations

import doctest
import importlib
import pkgutil
from pathlib import Path

import pytest

import rotarydryer

SRC = Path(rotarydryer.__file__).resolve().parent

# already run by tests/correlations/test_corr_doctests.py, tests/thermal/test_thermal_doctests.py,
# tests/thermal/test_balances.py and tests/properties/test_humid_air_properties.py
ELSEWHERE = {
    "rotarydryer.correlations", "rotarydryer.correlations.drag", "rotarydryer.correlations.heat_transfer",
    "rotarydryer.correlations.residence_time", "rotarydryer.correlations.trajectory",
    "rotarydryer.thermal.burner", "rotarydryer.thermal.drying", "rotarydryer.properties.drying", "rotarydryer.thermal.radiation",
    "rotarydryer.thermal.shell", "rotarydryer.thermal.streams", "rotarydryer.thermal.balances",
    "rotarydryer.properties.humid_air", "rotarydryer.properties.water", "rotarydryer.properties.combustion",
}
# module -> reason
SKIP: dict[str, str] = {
    "rotarydryer.app.streamlit_app": "Streamlit script: importing it runs the app",
}


def _modules_with_doctests() -> list[str]:
    names = []
    for info in pkgutil.walk_packages([str(SRC)], prefix="rotarydryer."):
        path = SRC.joinpath(*info.name.split(".")[1:])
        file = path / "__init__.py" if info.ispkg else path.with_suffix(".py")
        if file.is_file() and ">>>" in file.read_text(encoding="utf-8") and info.name not in ELSEWHERE:
            names.append(info.name)
    return sorted(names)


MODULES = _modules_with_doctests()


@pytest.mark.parametrize("name", MODULES)
def test_module_doctests(name):
    if name in SKIP:
        pytest.skip(SKIP[name])
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS, verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} doctests of {name} failed"
    assert result.attempted > 0


def test_doctest_modules_found():
    assert "rotarydryer.simulation" in MODULES and "rotarydryer.geometry.drum" in MODULES
