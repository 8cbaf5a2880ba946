"""The command line's start: NumPy's unused submodules load on first use, not when SciPy copies NumPy's
namespace (issue 32 item 4: ``rotarydryer simulate lee2008_invicta --json`` 0.648 -> 0.595 s CPU)."""

import subprocess
import sys

from rotarydryer._startup import DEFERRED_NUMPY_SUBMODULES, GC_YOUNG_THRESHOLD

PROBE = """
import sys
from rotarydryer.cli import app             # installs the deferral before NumPy loads
try:
    app(["simulate", "lee2008_invicta", "--json"], prog_name="rotarydryer")
except SystemExit as exc:
    assert not exc.code, exc.code
print()
print("ran:" + ",".join(n for n in {names!r} if type(sys.modules.get(n)).__name__ != "_LazyModule"))
import numpy
import numpy.ma
from numpy.testing import assert_allclose   # a deferred module loads on first use and works
assert int(numpy.ma.masked_array([1, 2, 3], mask=[0, 1, 0]).sum()) == 4
assert_allclose(numpy.random.default_rng(0).random(2).shape, (2,))
assert numpy.polynomial.Polynomial([1, 2])(1.0) == 3.0
print(type(sys.modules["numpy.ma"]).__name__)
"""


def _run(code):
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return r.stdout.splitlines()


def test_numpys_unused_submodules_are_not_run_by_a_command():
    """`rotarydryer simulate lee2008_invicta --json`: after SciPy's namespace copy and the coupled steady state, the
    two costly deferred submodules have not run (f2py 38 ms, testing 35 ms; SciPy itself uses numpy.random); every
    deferred one works on first use."""
    *_, ran, after = _run(PROBE.format(names=DEFERRED_NUMPY_SUBMODULES))
    ran = ran[4:].split(",")
    assert "numpy.f2py" not in ran and "numpy.testing" not in ran, ran
    assert after == "module"                   # numpy.ma ran on its first attribute access


def test_without_the_command_line_nothing_is_deferred():
    """The library alone (no CLI import) leaves NumPy's imports as they are."""
    out = _run("import sys, rotarydryer, scipy.sparse; print(type(sys.modules['numpy.f2py']).__name__)")
    assert out == ["module"]


HEAVY = ("scipy.stats", "scipy.integrate", "rotarydryer.rtd.fitting", "rotarydryer.estimation", "matplotlib")


def test_a_one_off_simulate_does_not_import_the_fitting_stack():
    """`simulate lee2008_invicta --json` imports neither SciPy's statistics and integrators nor the RTD fits and
    estimation (a schedule reader's input-file check once pulled in `rotarydryer.rtd`, and with it scipy.stats:
    about 0.5 s more at every start)."""
    code = ("import sys\nfrom rotarydryer.cli import app\ntry:\n    app(['simulate', 'lee2008_invicta', '--json'], "
            "prog_name='rotarydryer')\nexcept SystemExit as exc:\n    assert not exc.code, exc.code\nprint()\n"
            f"print(','.join(n for n in {HEAVY!r} if n in sys.modules))")
    loaded = _run(code)[-1]
    assert loaded == "", loaded


def test_a_command_collects_its_young_objects_in_larger_batches():
    """The command line raises the young generation's threshold (700 -> `GC_YOUNG_THRESHOLD`): `simulate
    lee2008_invicta --json` collects a handful of times instead of about 157 (its imports make half a million
    objects); collection stays on, and the library alone keeps Python's thresholds."""
    code = ("import gc, sys\ncounts = [0]\ngc.callbacks.append(lambda phase, info: counts.__setitem__(0, counts[0] + "
            "(phase == 'start')))\nfrom rotarydryer.cli import app\ntry:\n    app(['simulate', 'lee2008_invicta', "
            "'--json'], prog_name='rotarydryer')\nexcept SystemExit as exc:\n    assert not exc.code, exc.code\n"
            "print()\nprint(gc.isenabled(), gc.get_threshold()[0], counts[0])")
    enabled, young, collections = _run(code)[-1].split()
    assert enabled == "True" and int(young) == GC_YOUNG_THRESHOLD
    assert 0 < int(collections) < 20, collections       # 157 with Python's thresholds
    lib = _run("import gc\nbefore = gc.get_threshold()\nimport rotarydryer, rotarydryer.simulation\n"
               "print(gc.get_threshold() == before)")
    assert lib == ["True"]


def test_a_one_off_command_does_not_load_the_process_pool():
    """The executor loads `multiprocessing` and the process pool only when it makes a pool: a one-off simulate
    does not pay for them."""
    code = ("import sys\nfrom rotarydryer.cli import app\ntry:\n    app(['simulate', 'lee2008_invicta', '--json'], "
            "prog_name='rotarydryer')\nexcept SystemExit as exc:\n    assert not exc.code, exc.code\nprint()\n"
            "print(','.join(n for n in ('multiprocessing', 'concurrent.futures.process') if n in sys.modules) or '-')")
    assert _run(code)[-1] == "-"
