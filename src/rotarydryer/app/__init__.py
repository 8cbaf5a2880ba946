"""Web app (Streamlit): flight geometry explorer, transport + RTD of a built-in case,
tracer-curve fitting.

Start it with ``rotarydryer app`` (or ``streamlit run`` on `script_path`).  The
page logic lives in `rotarydryer.app.logic` (plain functions, testable without
Streamlit); `rotarydryer.app.streamlit_app` is the Streamlit script.

Why Streamlit: its ``streamlit.testing.v1.AppTest`` harness runs the script headless in
the test process (set widget values, read metrics, tables and images) with no browser
and no server, which keeps the logic tests fast and deterministic; the app is a plain
top-to-bottom script with no callbacks or JavaScript.  Its cost is install weight
(Streamlit pulls pyarrow, pandas, altair, tornado...: about 300 MB installed), which is
why it is an optional extra (``pip install rotarydryer[app]``) and imported only when
the app runs.  Panel and NiceGUI are lighter to install but their headless harnesses are
asynchronous or need a running server.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["PAGES", "script_path", "streamlit_command"]

#: page title -> (module of `rotarydryer.app` with a ``render()``, URL path = file of
#: `rotarydryer.app.entries`, icon); the first is the landing page (served at /, its URL path
#: too).  `rotarydryer.app.streamlit_app` makes one ``st.Page`` of each.
PAGES = {"Flight geometry": ("page_geometry", "geometry", ":material/donut_large:"),
         "Transport and RTD": ("page_transport", "transport", ":material/conveyor_belt:"),
         "Whole dryer": ("page_dryer", "whole_dryer", ":material/local_fire_department:"),
         "Studies and sensitivity": ("page_studies", "studies", ":material/query_stats:"),
         "Design": ("page_design", "design", ":material/architecture:"),
         "Control": ("page_control", "control", ":material/tune:"),
         "Calibration": ("page_calibration", "calibration", ":material/straighten:"),
         "Lab data": ("page_lab", "lab", ":material/science:")}


def script_path() -> Path:
    """Path of the Streamlit script."""
    return Path(__file__).with_name("streamlit_app.py")


def streamlit_command(port: int = 8501, host: str = "127.0.0.1", headless: bool = True) -> list[str]:
    """The command line that serves the app (``python -m streamlit run ...``).

    Hardening (docs/app_threat_model.md): ``client.showErrorDetails = none`` (no exception
    text or traceback in the browser), ``server.maxUploadSize = 1`` MB (uploads; the page
    checks tighter byte limits), no file watcher, no run-on-save."""
    import sys

    from .logic import MAX_UPLOAD_MB

    return [sys.executable, "-m", "streamlit", "run", str(script_path()),
            "--server.port", str(int(port)), "--server.address", host,
            "--server.headless", "true" if headless else "false",
            "--browser.gatherUsageStats", "false", "--server.fileWatcherType", "none",
            "--global.developmentMode", "false", "--client.toolbarMode", "minimal",
            "--client.showErrorDetails", "none", "--server.maxUploadSize", str(MAX_UPLOAD_MB),
            "--server.runOnSave", "false"]
