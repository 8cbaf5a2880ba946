"""Optional compiled kernels (numba, ``pip install 'rotarydryer[fast]'``).

The hot loops of the heat-and-mass residual have a compiled form: the tabulated flight geometry
of every cell (`rotarydryer.geometry._cell_kernel`), the gas properties, the gas-solids
transfer and the shell network (`rotarydryer.properties._kernels`). Each has a NumPy
reference that gives the same numbers to rounding (the shell: the same root to its tolerance;
tested against each other) and that runs whenever numba is not installed, or when
``ROTARYDRYER_JIT=0``. The compiled functions are cached on disk by numba (``cache=True``): the
first use in a fresh installation compiles them (about 8 s); later processes load them (about
0.9 s with numba's import).
"""

from __future__ import annotations

import os
import warnings

__all__ = ["ENV", "disable", "enabled", "kernel"]

#: environment variable: "0", "off", "no" or "false" disables the compiled kernels
ENV = "ROTARYDRYER_JIT"


def _numba():
    if os.environ.get(ENV, "").strip().lower() in ("0", "off", "no", "false"):
        return None
    try:
        import numba
    except ImportError:
        return None
    except Exception as exc:     # installed but unusable here (llvmlite: no executable memory, no library)

        warnings.warn(f"rotarydryer: numba cannot be imported ({type(exc).__name__}: {exc}); using NumPy",
                      RuntimeWarning, stacklevel=2)
        return None
    if getattr(numba.config, "DISABLE_JIT", False):   # NUMBA_DISABLE_JIT=1: njit would return plain Python
        return None
    return numba


_NUMBA = _numba()


def enabled() -> bool:
    """Are compiled kernels in use (numba installed and not disabled by ``ROTARYDRYER_JIT``)?"""
    return _NUMBA is not None


def kernel(fn):
    """``numba.njit(cache=True, nogil=True)`` of ``fn`` when numba is in use, else None (the caller
    then takes its NumPy reference path). Division by zero gives inf or NaN, as in NumPy."""
    if _NUMBA is None:
        return None
    try:
        return _NUMBA.njit(cache=True, nogil=True, error_model="numpy")(fn)
    except RuntimeError:        # no writable cache location (read-only installation): compile per process
        return _NUMBA.njit(nogil=True, error_model="numpy")(fn)


def disable(reason: str):
    """Stop using the compiled kernels in this process (one that failed to compile or run), with a
    warning naming ``reason``; the NumPy references give the same results."""
    global _NUMBA
    if _NUMBA is not None:

        warnings.warn(f"rotarydryer: compiled kernels disabled ({reason}); using NumPy", RuntimeWarning, stacklevel=3)
    _NUMBA = None
