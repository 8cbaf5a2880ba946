"""Optional compiled kernels (numba, ``pip install 'rotarydryer[fast]'``), for the runs that pay for them.

The hot loops of the heat-and-mass residual have a compiled form: the tabulated flight geometry
of every cell (`rotarydryer.geometry._cell_kernel`), the gas properties, the gas-solids
transfer, the shell network and the cell balance of a dryer of one size class
(`rotarydryer.properties._kernels`). Each has a NumPy
reference that gives the same numbers to rounding (the shell: the same root to its tolerance;
tested against each other) and that runs whenever the compiled kernels are not in use.

The compiled kernels come from one of two places:

* the **ahead-of-time module** (`rotarydryer._aot`): built once per installation in the background,
  started by the first long run (15-60 s of one core; it needs numba and a C compiler), then loaded
  by any process in about a millisecond, without numba;
* **numba's JIT** with its disk cache (``cache=True``), until that module is there or where it
  cannot be built: the first use compiles (about 8 s), later processes load them in 0.5-0.9 s
  (numba's import and first dispatch), which a one-off steady state (0.1-0.3 s of solving) does
  not win back.

``ROTARYDRYER_JIT`` chooses:

* ``auto`` (default): the compiled kernels serve the **long runs** - a process that declares one
  (`long_runs`: sweeps, sensitivity studies, dynamics, control, design searches, fits and
  calibrations, validation, the executor's workers, the web app) loads them (or starts the
  module's build and takes the JIT meanwhile); a
  one-off command (``simulate``, ``rtd``, ``report``) uses the ahead-of-time module when it is
  built and NumPy otherwise, and never imports numba;
* ``1`` / ``on``: always;
* ``0`` / ``off``: never.

numba is imported only when a kernel is first needed and the ahead-of-time module is not
there, never at import time.
"""

from __future__ import annotations

import os
import warnings

from . import _aot

__all__ = ["ENV", "aot", "available", "disable", "enabled", "kernel", "long_runs", "mode"]

#: environment variable: "auto" (default), "1"/"on" (always) or "0"/"off" (never)
ENV = "ROTARYDRYER_JIT"

_OFF = ("0", "off", "no", "false")
_ON = ("1", "on", "yes", "true")

_NUMBA = None          # the numba module once imported (None: not yet, or not usable)
_TRIED = False         # numba's import attempted in this process
_DISABLED = False      # a kernel failed to compile or run here: NumPy for the rest of the process
_LONG = False          # this process declared long runs (the auto mode uses the kernels then)


def mode() -> str:
    """``"auto"``, ``"on"`` or ``"off"`` from ``ROTARYDRYER_JIT`` (anything else: auto)."""
    v = os.environ.get(ENV, "").strip().lower()
    return "off" if v in _OFF else "on" if v in _ON else "auto"


_STATE: dict = {}      # (_LONG, _DISABLED) -> enabled(): a residual asks once per kernel call


def _numba():
    """numba, imported on the first call (None: not installed, unusable, or NUMBA_DISABLE_JIT=1)."""
    global _NUMBA, _TRIED
    if _TRIED:
        return _NUMBA
    _TRIED = True
    try:
        import numba  # start-up: 0.2-0.6 s; only for the runs that use the kernels
    except ImportError:
        return None
    except Exception as exc:     # installed but unusable here (llvmlite: no executable memory, no library)
        warnings.warn(f"rotarydryer: numba cannot be imported ({type(exc).__name__}: {exc}); using NumPy",
                      RuntimeWarning, stacklevel=3)
        return None
    if getattr(numba.config, "DISABLE_JIT", False):   # NUMBA_DISABLE_JIT=1: njit would return plain Python
        return None
    _NUMBA = numba
    return _NUMBA


def long_runs() -> None:
    """Declare that this process runs long work (many solves or a long integration): in the auto
    mode the compiled kernels are used from now on. Sticky for the process."""
    global _LONG
    _LONG = True


def available() -> bool:
    """Could the compiled kernels be used here (numba installed and usable, not ``ROTARYDRYER_JIT=0``)?
    Imports numba."""
    return mode() != "off" and not _DISABLED and _numba() is not None


def enabled() -> bool:
    """Are compiled kernels in use now: ``ROTARYDRYER_JIT=1``, or the auto mode after `long_runs`,
    with numba available? The answer is remembered for the process's declarations (`long_runs`,
    `disable`): a residual asks once per kernel call, thousands of times a second, so
    ``ROTARYDRYER_JIT`` is read when a process first asks (set it before the process starts)."""
    key = (_LONG, _DISABLED)
    hit = _STATE.get(key)
    if hit is None:
        m = mode()
        if m == "off" or _DISABLED or os.environ.get("NUMBA_DISABLE_JIT", "0").strip() not in ("", "0"):
            hit = False     # NUMBA_DISABLE_JIT=1: numba's own switch (to debug the kernels as Python) too
        elif m == "auto" and not _LONG:     # a one-off run: only kernels that cost nothing to load
            hit = _aot.module() is not None
        else:
            hit = _aot.module(build=True) is not None or _numba() is not None
        _STATE[key] = hit
    return hit


def kernel(fn):
    """``numba.njit(cache=True, nogil=True)`` of ``fn`` when the kernels are in use, else None (the caller
    then takes its NumPy reference path). Division by zero gives inf or NaN, as in NumPy."""
    if not enabled() or _numba() is None:
        return None
    try:
        return _NUMBA.njit(cache=True, nogil=True, error_model="numpy")(fn)
    except RuntimeError:        # no writable cache location (read-only installation): compile per process
        return _NUMBA.njit(nogil=True, error_model="numpy")(fn)


def aot(name: str, kinds: str):
    """Kernel ``name`` from the ahead-of-time module (`rotarydryer._aot`) when the kernels are in use
    and that module is built, else None (the caller then takes numba's JIT, `kernel`)."""
    if not enabled():
        return None
    return _aot.function(name, kinds)


def disable(reason: str):
    """Stop using the compiled kernels in this process (one that failed to compile or run), with a
    warning naming ``reason``; the NumPy references give the same results."""
    global _DISABLED
    if not _DISABLED and (_NUMBA is not None or _aot.module() is not None):
        warnings.warn(f"rotarydryer: compiled kernels disabled ({reason}); using NumPy", RuntimeWarning, stacklevel=3)
    _DISABLED = True
