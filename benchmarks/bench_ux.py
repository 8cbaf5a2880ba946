"""User-experience benchmarks: results I/O, HTML report, CLI wall times (never fail on timing).

Run: python -m pytest benchmarks/bench_ux.py --benchmark-only -q
Targets (issue 7): ``rotarydryer simulate`` on a built-in case < 1.5 s wall time from the
shell including start-up; report generation < 5 s.

The CLI benchmarks start a fresh interpreter per round and register every command module
(the lead's cli/__init__.py does that), so start-up cost of all modules is included.
"""

import subprocess
import sys

import pytest

pytest.importorskip("xarray")

from rotarydryer.report.html import build_report, render_report  # noqa: E402
from rotarydryer.results import Results, run_case  # noqa: E402

REG = {"geometry.method": "lee2008_regressions"}
_MODULES = ["simulate", "report", "webapp", "schema", "sweep"]
_LAUNCH = ("import importlib, sys\n"
           "from rotarydryer.cli import app\n"
           f"for m in {_MODULES!r}:\n"
           "    try: importlib.import_module('rotarydryer.cli.' + m)\n"
           "    except ImportError: pass\n"
           "sys.argv[0] = 'rotarydryer'\n"
           "app()\n")


def _cli(*args):
    r = subprocess.run([sys.executable, "-c", _LAUNCH, *args], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r.stdout


@pytest.fixture(scope="module")
def lee():
    return run_case("lee2008_invicta", REG)


@pytest.fixture(scope="module")
def ajayi():
    return run_case("ajayi2011_mmg")


def test_results_save(benchmark, lee, tmp_path):
    benchmark(lee.save, tmp_path / "lee.nc")


def test_results_load(benchmark, lee, tmp_path):
    p = lee.save(tmp_path / "lee.nc")
    back = benchmark(Results.load, p)
    assert back == lee


@pytest.mark.parametrize("name", ["lee", "ajayi"])
def test_render_report_from_results(benchmark, name, request):
    res = request.getfixturevalue(name)
    html = benchmark.pedantic(render_report, args=(res,), rounds=3, iterations=1)
    assert html.count("<img") >= 6


def test_report_of_drum_preset(benchmark):
    benchmark.pedantic(build_report, args=("invicta",), rounds=3, iterations=1)


@pytest.mark.parametrize("case", ["lee2008_invicta", "ajayi2011_mmg"])
def test_cli_report_wall(benchmark, case, tmp_path):
    """Shell wall time of ``rotarydryer report CASE --out r.html`` (start-up + run + report)."""
    benchmark.pedantic(_cli, args=("report", case, "--out", str(tmp_path / "r.html")), rounds=3, iterations=1)


@pytest.mark.parametrize("case", ["lee2008_invicta", "ajayi2011_mmg"])
def test_cli_simulate_wall(benchmark, case):
    """Shell wall time of ``rotarydryer simulate CASE`` with every command module registered."""
    try:
        import rotarydryer.cli.simulate  # noqa: F401
    except ImportError:
        pytest.skip("rotarydryer.cli.simulate not present")
    out = benchmark.pedantic(_cli, args=("simulate", case), rounds=5, iterations=1)
    assert "holdup" in out


def test_cli_help_wall(benchmark):
    out = benchmark.pedantic(_cli, args=("--help",), rounds=5, iterations=1)
    assert "report" in out and "sweep" in out
