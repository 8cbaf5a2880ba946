"""The one entry point to Matplotlib for the package's plotting code."""

from __future__ import annotations


def pyplot():
    """``matplotlib.pyplot``, imported lazily.

    Selects the non-interactive Agg backend only when no usable backend is active (a script
    or CI run without a display); an interactive session or a notebook keeps its own
    backend. File backends (agg, pdf, svg, cairo) are left alone.
    """
    import matplotlib

    if matplotlib.get_backend().lower() not in ("agg", "pdf", "svg", "cairo") and not matplotlib.is_interactive():
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
