"""Streamlit script of the rotarydryer web app (run with ``rotarydryer app``).

The pages are modules of `rotarydryer.app` with a ``render()`` (`rotarydryer.app.PAGES`): flight
geometry (``page_geometry``), transport and RTD (``page_transport``), whole dryer, studies,
design, control, calibration and lab data.  Each page has its own address (``st.navigation`` with one
``st.Page`` per page: /transport, /whole_dryer, /studies, /design, /control, /calibration, /lab; the flight
geometry, the landing page, at /), so a page can be bookmarked or linked and the browser's Back
and Forward buttons move between pages.  The page files are in `rotarydryer.app.entries`
(one line each: the page module's ``render()``).  This script draws the navigation and the
sidebar's shared caption and runs the chosen page inside the one failure boundary of the app.
The session (its state, its kept results) is the same on every page; a page's widgets keep
their values when the visitor comes back to it (``persist_state="session"`` on the main ones).

Visitors' input (docs/app_threat_model.md): uploads are size-limited and kept in memory
only; an uploaded case may name shipped data sets only; every error is caught here and shown
as its message (input errors) or as a generic sentence (anything else; the traceback goes
to the server log), never with a traceback or a file's content.
"""

import logging
from pathlib import Path

import streamlit as st

from rotarydryer import _jit
from rotarydryer.app import PAGES, logic
from rotarydryer.app._ui import display_note, plain

# no exception types, messages or tracebacks in the browser, even for an error this script
# does not catch (also set on the command line of ``rotarydryer app``)
st.set_option("client.showErrorDetails", "none")
st.set_page_config(page_title="rotarydryer", page_icon=":material/autorenew:", layout="wide")

ENTRIES = Path(__file__).with_name("entries")
_jit.long_runs()        # a server: many runs in one process, the compiled kernels pay (rotarydryer._jit)

page = st.navigation([st.Page(ENTRIES / f"{url}.py", title=title, url_path=url, icon=icon, default=i == 0)
                      for i, (title, (_, url, icon)) in enumerate(PAGES.items())])
st.sidebar.caption(f"rotarydryer: flighted rotary dryer simulator. Display units: {display_note()}; angles in deg.")

# The one failure boundary of every page: an exception a page does not catch itself shows an
# error box with a one-line reason (the message of an input error, else a generic sentence; the
# traceback goes to the server log), never a traceback or a dead page.  st.stop() and st.rerun()
# raise BaseExceptions (not Exception) and pass through.
try:
    page.run()
except Exception as exc:  # noqa: BLE001 - the boundary
    if not isinstance(exc, ValueError) or isinstance(exc, UnicodeError):
        logging.getLogger("rotarydryer.app").error("page %s failed", page.title, exc_info=exc)
    st.error(plain(f"The page {page.title} could not be shown: {' '.join(logic.visitor_message(exc).split())}"))
