"""What a command-line process does before NumPy and SciPy load, for a fast one-off command (issue 32).

SciPy's array-API layer (``scipy._lib.array_api_compat.numpy``, imported by ``scipy.sparse``,
``scipy.linalg`` and most of SciPy) copies NumPy's namespace when it loads: it asks ``hasattr`` of
every public name, and NumPy's module ``__getattr__`` then imports each of its lazily loaded
submodules. Five of them are never used by a simulation and cost about 90 ms of CPU together
(measured on 2 cores, NumPy 2.4, SciPy 1.17): ``numpy.f2py`` (38 ms, with ``argparse`` and
``charset_normalizer``), ``numpy.testing`` (35 ms, with ``unittest``), ``numpy.random`` (11 ms),
``numpy.ma`` (8 ms) and ``numpy.polynomial`` (3 ms).

`defer_numpy_submodules` makes the import of those five lazy in this process
([`importlib.util.LazyLoader`](https://docs.python.org/3/library/importlib.html#importlib.util.LazyLoader)):
``import numpy.ma`` gives a module object at once, and its code runs on the first attribute
access (``numpy.ma.masked``, ``from numpy.testing import assert_allclose``). Nothing else changes:
a command that draws a figure (Matplotlib uses ``numpy.ma``) or a fit that draws random starts
loads them when it first uses them. The command line calls it at start; the library does not.

`raise_gc_threshold` makes the cyclic garbage collector's young generation collect every 100 000
net allocations of container objects instead of Python's 700. A one-off command creates about half a
million objects while it imports (modules, classes, pydantic schemas, typing objects), and with the
default thresholds the collector walked them 157 times (143 young, 13 middle and one full collection:
`simulate lee2008_invicta --json` on 2 cores, about 30 ms of its 0.6 s of CPU); with the raised
threshold about 15 times. Collection still happens, so the cycles of a long command (a sweep, a
dynamic run) are freed as before, in larger batches. The command line calls it at start, and each
process of the executor's local pool (`rotarydryer.executor`) once; the library does not change the
collector of the process that imports it.
"""

from __future__ import annotations

import gc
import importlib.machinery
import importlib.util
import sys

__all__ = ["DEFERRED_NUMPY_SUBMODULES", "GC_YOUNG_THRESHOLD", "defer_numpy_submodules", "raise_gc_threshold"]

#: NumPy submodules loaded on first use instead of when SciPy copies NumPy's namespace
DEFERRED_NUMPY_SUBMODULES = ("numpy.f2py", "numpy.testing", "numpy.random", "numpy.ma", "numpy.polynomial")

#: net allocations of container objects between two collections of the young generation in a command's
#: process (Python's default: 700)
GC_YOUNG_THRESHOLD = 100_000


class _LazyFinder:
    """Finds the `DEFERRED_NUMPY_SUBMODULES` with the path finder and wraps their loader lazily (a meta path
    finder by its ``find_spec``; not derived from ``importlib.abc.MetaPathFinder``, whose module loads
    ``importlib.resources``: the executor imports this module)."""

    def __init__(self, names):
        self.names = frozenset(names)

    def find_spec(self, fullname, path=None, target=None):
        if fullname not in self.names:
            return None
        spec = importlib.machinery.PathFinder.find_spec(fullname, path)
        if spec is None or spec.loader is None or not hasattr(spec.loader, "exec_module"):
            return spec
        spec.loader = importlib.util.LazyLoader(spec.loader)
        return spec


def defer_numpy_submodules(names=DEFERRED_NUMPY_SUBMODULES) -> bool:
    """Load ``names`` (NumPy submodules) lazily in this process from now on; a module already imported
    stays as it is. Idempotent; returns True when the finder is (now) installed."""
    if any(isinstance(f, _LazyFinder) for f in sys.meta_path):
        return True
    todo = [n for n in names if n not in sys.modules]
    if not todo:
        return False
    sys.meta_path.insert(0, _LazyFinder(todo))
    return True


def raise_gc_threshold(young: int = GC_YOUNG_THRESHOLD) -> bool:
    """Collect the young generation every ``young`` net allocations in this process (never lowers a
    threshold already higher, keeps the older generations' thresholds); returns True when it changed."""
    first, *older = gc.get_threshold()
    if first == 0 or first >= young:      # 0: collection turned off by whoever runs us
        return False
    gc.set_threshold(young, *older)
    return True
