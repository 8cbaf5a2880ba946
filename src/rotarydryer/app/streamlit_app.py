"""Streamlit script of the rotarydryer web app (run with ``rotarydryer app``).

The pages are modules of :mod:`rotarydryer.app` with a ``render()`` (:data:`PAGES`): flight
geometry (``page_geometry``), transport and RTD (``page_transport``), whole dryer, studies,
design, control and lab data.  This script draws the sidebar's page choice and calls the chosen
page inside the one failure boundary of the app.

Visitors' input (docs/app_threat_model.md): uploads are size-limited and kept in memory
only; an uploaded case may name shipped data sets only; every error is caught here and shown
as its message (input errors) or as a generic sentence (anything else; the traceback goes
to the server log), never with a traceback or a file's content.
"""

import importlib
import logging

import streamlit as st

from rotarydryer.app import logic
from rotarydryer.app._ui import plain

# no exception types, messages or tracebacks in the browser, even for an error this script
# does not catch (also set on the command line of ``rotarydryer app``)
st.set_option("client.showErrorDetails", "none")
st.set_page_config(page_title="rotarydryer", page_icon=":material/autorenew:", layout="wide")

#: page title -> module of :mod:`rotarydryer.app` with a ``render()``
PAGES = {"Flight geometry": "page_geometry", "Transport and RTD": "page_transport", "Whole dryer": "page_dryer",
         "Studies and sensitivity": "page_studies", "Design": "page_design", "Control": "page_control",
         "Lab data": "page_lab"}
page = st.sidebar.radio("Page", list(PAGES), key="page")
st.sidebar.caption("rotarydryer: flighted rotary dryer simulator. Units: SI, angles in deg.")

# The one failure boundary of every page: an exception a page does not catch itself shows an
# error box with a one-line reason (the message of an input error, else a generic sentence; the
# traceback goes to the server log), never a traceback or a dead page.  st.stop() and st.rerun()
# raise BaseExceptions (not Exception) and pass through.
try:
    importlib.import_module(f"rotarydryer.app.{PAGES[page]}").render()
except Exception as exc:  # noqa: BLE001 - the boundary
    if not isinstance(exc, ValueError) or isinstance(exc, UnicodeError):
        logging.getLogger("rotarydryer.app").error("page %s failed", page, exc_info=exc)
    st.error(plain(f"The page {page} could not be shown: {' '.join(logic.visitor_message(exc).split())}"))
