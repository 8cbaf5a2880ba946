"""The compiled kernels ahead of time (`rotarydryer._aot`): built once, loaded without numba, the same
numbers as numba's JIT, arguments checked, and a build that cannot happen falls back to the JIT."""

import importlib.util
import os
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from rotarydryer import _aot, _jit

HAVE_BUILD = importlib.util.find_spec("numba") is not None and shutil.which("cc") is not None

RUN = """
import json, sys
from rotarydryer import _jit
_jit.long_runs()
from rotarydryer.simulation import Simulation
from rotarydryer.properties import _kernels
s = Simulation("ajayi2011_mmg", {"operating.test": 4}).steady_state().summary()
print(json.dumps({"numba": "numba" in sys.modules, "x": s["product_moisture_kg_kg"], "t": s["gas_outlet_temperature_degC"],
                  "aot": all(getattr(f, "aot", False) for f in _kernels._compiled.values()), "n": len(_kernels._compiled)}))
"""


def _run(env):
    r = subprocess.run([sys.executable, "-c", RUN], capture_output=True, text=True, env={**os.environ, **env})
    assert r.returncode == 0, r.stderr
    import json

    return json.loads(r.stdout.strip().splitlines()[-1])


@pytest.fixture
def fresh_state(monkeypatch):
    """This process's decisions forgotten (and restored after the test)."""
    monkeypatch.setattr(_aot, "_STATE", {})
    monkeypatch.setattr(_jit, "_STATE", {})


@pytest.mark.slow
@pytest.mark.skipif(not HAVE_BUILD, reason="numba or a C compiler missing: the ahead-of-time module cannot be built")
def test_built_once_then_loaded_without_numba(tmp_path):
    """A long run in an empty kernel directory starts the module's build in the background and goes on with
    numba's JIT; the next process loads the module without importing numba; they give the same numbers
    (rounding: the same machine code, bar the CPU target)."""
    import time

    env = {_aot.DIR_ENV: str(tmp_path), "ROTARYDRYER_JIT": "auto"}
    first = _run(env)
    assert first["numba"] and not first["aot"] and first["n"] >= 4
    deadline = time.monotonic() + 600
    while not [p for p in tmp_path.iterdir() if p.suffix in (".so", ".failed")] and time.monotonic() < deadline:
        time.sleep(1.0)
    assert not list(tmp_path.glob("*.failed")), [p.read_text() for p in tmp_path.glob("*.failed")]
    built = [p.name for p in tmp_path.iterdir() if p.suffix == ".so"]
    assert len(built) == 1 and built[0].startswith("_rotarydryer_kernels_"), list(tmp_path.iterdir())
    second = _run(env)
    assert second["aot"] and not second["numba"]
    jit = _run({_aot.DIR_ENV: "off", "ROTARYDRYER_JIT": "auto"})
    assert jit["numba"] and not jit["aot"]
    numpy_path = _run({"ROTARYDRYER_JIT": "0"})
    assert second["n"] >= 4
    for other in (second, jit, numpy_path):
        assert other["x"] == pytest.approx(first["x"], rel=1e-9)
        assert other["t"] == pytest.approx(first["t"], abs=1e-9)
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".build-")]     # the build's files removed


@pytest.mark.skipif(not HAVE_BUILD, reason="numba or a C compiler missing")
def test_one_off_run_uses_a_built_module_and_never_builds(tmp_path):
    """A one-off run (no `long_runs`) in an empty directory stays on NumPy and builds nothing."""
    code = ("from rotarydryer import _jit, _aot; from rotarydryer.simulation import Simulation; "
            "Simulation('ajayi2011_mmg', {'operating.test': 4}).steady_state(); import sys; "
            "print(_jit.enabled(), 'numba' in sys.modules)")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       env={**os.environ, _aot.DIR_ENV: str(tmp_path), "ROTARYDRYER_JIT": "auto"})
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["False", "False"]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(importlib.util.find_spec("numba") is None, reason="numba missing: no build is attempted")
def test_a_failed_build_is_remembered_and_the_jit_serves(tmp_path, monkeypatch, fresh_state):
    """No compiler (a build that fails): one warning naming the reason, a marker so that later processes
    do not try again, and numba's JIT (or NumPy) instead; the marker's process does not build again."""
    monkeypatch.setenv(_aot.DIR_ENV, str(tmp_path))
    calls = []
    monkeypatch.setattr(_aot, "build", lambda where, name: calls.append(name) or "no C compiler found")
    with pytest.warns(RuntimeWarning, match="could not be built ahead of time .no C compiler found.*JIT"):
        assert _aot.build_now() is None
    markers = list(tmp_path.glob("*.failed"))
    assert len(markers) == 1 and "no C compiler" in markers[0].read_text()
    monkeypatch.setattr(_aot, "_STATE", {})
    started = []
    monkeypatch.setattr(_aot, "_start_background", lambda *a: started.append(a))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _aot.build_now() is None              # the marker: no second attempt, no second warning
        monkeypatch.setattr(_aot, "_STATE", {})
        assert _aot.module(build=True) is None       # nor a background build
    assert len(calls) == 1 and not started


def test_a_damaged_module_falls_back_with_a_warning(tmp_path, monkeypatch, fresh_state):
    monkeypatch.setenv(_aot.DIR_ENV, str(tmp_path))
    _, _, ext, _, _ = _aot._paths()
    ext.write_bytes(b"not an extension module")
    with pytest.warns(RuntimeWarning, match="cannot be loaded"):
        assert _aot.module(build=True) is None


def test_directory_off_disables(monkeypatch, fresh_state):
    monkeypatch.setenv(_aot.DIR_ENV, "off")
    assert _aot.kernel_directory() is None
    assert _aot.module(build=True) is None


@pytest.mark.skipif(importlib.util.find_spec("numba") is None, reason="numba missing: no build is attempted")
def test_an_unwritable_directory_is_named(tmp_path, monkeypatch, fresh_state):
    blocker = tmp_path / "file"
    blocker.write_text("")
    monkeypatch.setenv(_aot.DIR_ENV, str(blocker / "kernels"))
    with pytest.warns(RuntimeWarning, match="not writable"):
        assert _aot.build_now() is None
    monkeypatch.setattr(_aot, "_STATE", {})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _aot.module(build=True) is None       # a long run goes on with the JIT, silently


def test_arguments_are_checked_before_the_compiled_code():
    """The extension's functions trust their arguments (a scalar for an array crashes the process);
    the wrapper refuses anything but the declared kinds with TypeError."""
    seen = []
    fn = _aot._guarded(lambda *a: seen.append(a) or True, "demo", "aofbnfm")
    good = (np.zeros(3), np.zeros(3), 1, 0, np.arange(3, dtype=np.int64), 2.5, np.zeros((2, 2)))
    assert fn(*good)
    assert [type(x) for x in seen[0][2:4]] == [float, bool]
    readonly = np.zeros(3)
    readonly.flags.writeable = False
    bad = {
        "a scalar for an array": (1.0, *good[1:]),
        "an int array for a float one": (np.arange(3), *good[1:]),
        "a strided array": (np.zeros(6)[::2], *good[1:]),
        "a read-only output": (good[0], readonly, *good[2:]),
        "2-D for 1-D": (np.zeros((3, 1)), *good[1:]),
        "a float array for an int one": (*good[:4], np.zeros(3), *good[5:]),
        "an array for a float": (*good[:2], np.zeros(2), *good[3:]),
        "too few": good[:-1],
    }
    for what, args in bad.items():
        with pytest.raises(TypeError, match="kernel demo"):
            fn(*args)
        assert len(seen) == 1, what
    ro_input = (readonly, *good[1:])        # a read-only input is fine
    assert fn(*ro_input) and len(seen) == 2


def test_every_kernel_declares_its_argument_kinds():
    import inspect

    from rotarydryer.geometry import _cell_kernel
    from rotarydryer.properties import _kernels
    from rotarydryer.transport import _step_kernel

    assert _aot.KERNEL_MODULES == tuple(m.__name__ for m in (_kernels, _cell_kernel, _step_kernel))
    for mod in (_kernels, _cell_kernel, _step_kernel):
        for name, (fn, kinds) in mod.AOT_KERNELS.items():
            assert len(inspect.signature(fn).parameters) == len(kinds), name
            assert set(kinds) <= _aot.KINDS, name


def test_modules_of_other_sources_unused_for_a_month_are_removed(tmp_path):
    import time

    old, recent, mine = (tmp_path / f"_rotarydryer_kernels_{x}.so" for x in ("aaaa", "bbbb", "cccc"))
    for p in (old, recent, mine):
        p.write_bytes(b"")
    month = time.time() - (_aot.STALE_DAYS + 1) * 86400
    os.utime(old, (month, month))
    os.utime(mine, (month, month))
    _aot._prune(tmp_path, "_rotarydryer_kernels_cccc")
    assert sorted(p.name for p in tmp_path.iterdir()) == [recent.name, mine.name]


@pytest.mark.skipif(importlib.util.find_spec("numba") is None, reason="numba missing: no build is attempted")
def test_a_passing_failure_leaves_no_marker(tmp_path, monkeypatch, fresh_state):
    """A build killed (out of memory) or over its time is tried again by a later run: no marker."""
    monkeypatch.setenv(_aot.DIR_ENV, str(tmp_path))
    monkeypatch.setattr(_aot, "build", lambda where, name: _aot.TransientBuildFailure("stopped by signal 9"))
    with pytest.warns(RuntimeWarning, match="stopped by signal 9"):
        assert _aot.build_now() is None
    assert not list(tmp_path.glob("*.failed"))


def test_a_module_others_can_write_is_not_loaded(tmp_path, monkeypatch, fresh_state):
    if not hasattr(os, "getuid"):
        pytest.skip("no file owners here")
    monkeypatch.setenv(_aot.DIR_ENV, str(tmp_path))
    _, _, ext, _, _ = _aot._paths()
    ext.write_bytes(b"")
    ext.chmod(0o666)
    with pytest.warns(RuntimeWarning, match="others can write it"):
        assert _aot.module(build=True) is None


def test_the_build_gets_neither_numbas_settings_nor_warnings_as_errors(monkeypatch):
    monkeypatch.setenv("NUMBA_OPT", "0")
    monkeypatch.setenv("NUMBA_DISABLE_JIT", "1")
    monkeypatch.setenv("PYTHONWARNINGS", "error")
    env = _aot._child_env()
    assert not [k for k in env if k.startswith("NUMBA_")] and "PYTHONWARNINGS" not in env
    assert env["PYTHONPATH"].split(os.pathsep)[0] == str(Path(_aot.__file__).resolve().parent.parent)
