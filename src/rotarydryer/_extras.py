"""Optional dependencies: a clear message naming the extra to install when one is missing.

The core (``pip install rotarydryer``) runs every simulation, RTD and fit. Image analysis needs
``rotarydryer[lab]`` (scikit-image, shapely), the web app ``rotarydryer[app]`` (streamlit), the
Sobol study ``rotarydryer[sensitivity]`` (SALib). ``rotarydryer[fast]`` (numba) adds compiled kernels
that only change the speed (`rotarydryer._jit`).
"""

from __future__ import annotations

import importlib

__all__ = ["MissingExtraError", "require"]


class MissingExtraError(ValueError, ImportError):
    """An optional dependency of a feature is not installed (the message names the extra)."""


def require(module: str, extra: str, feature: str, package: str | None = None):
    """Import and return ``module``; if it is missing raise `MissingExtraError`:
    ``FEATURE needs the optional package PACKAGE: pip install 'rotarydryer[EXTRA]'``."""
    try:
        return importlib.import_module(module)
    except ImportError:
        name = package or module.split(".")[0]
        raise MissingExtraError(f"{feature} needs the optional package {name!r}, which is not installed: "
                                f"pip install 'rotarydryer[{extra}]'") from None
