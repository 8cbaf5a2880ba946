"""Streamlit helpers shared by the pages of the web app (imported only inside the app).

Visitors' input (docs/app_threat_model.md): every error is shown as its message (input
errors, the same one-line messages as the CLI) or a generic sentence (anything else; the
traceback goes to the server log), never with a traceback or a file's content.
"""

from __future__ import annotations

import logging
import re
import time
from contextlib import contextmanager
from typing import Literal

import streamlit as st

from .._display import display_units, show_output
from . import logic

log = logging.getLogger("rotarydryer.app")

#: ``persist_state`` of the pages' main widgets: their values survive a visit to another page
#: (``st.navigation`` drops the state of the widgets a page switch does not draw otherwise)
PERSIST: Literal["session"] = "session"


def plain(text: str) -> str:
    """Markdown-escaped text (shown literally; one line per line)."""
    return re.sub(r"([\\`*\[\]<>$~#|])", r"\\\1", str(text)).replace("\n", "  \n")


def refuse(what: str, exc: BaseException, stop: bool = True):
    """Show why ``what`` failed (a one-line-per-problem message, no traceback) and stop
    (``stop=False``: carry on with the rest of the page)."""
    if not isinstance(exc, ValueError) or isinstance(exc, UnicodeError):
        log.error("%s", what, exc_info=exc)
    st.error(f"{plain(what)}: {plain(logic.visitor_message(exc))}")
    if stop:
        st.stop()


def case_picker(prefix: str, default: str = "ajayi2011_mmg", cases: list[str] | None = None,
                help_text: str | None = None) -> tuple[str, str]:
    """Sidebar choice of a built-in case or an uploaded case file (kept in memory only).

    ``prefix`` makes the widget keys unique per page (``f"{prefix}_case"``,
    ``f"{prefix}_case_file"``; an empty prefix: ``"case"`` and ``"case_file"``).  Returns
    ``(case, shown)``: the name to pass to the logic functions (a built-in name or the staged
    key of an upload) and the name to show (they differ only for an upload).  The choice of a
    built-in case is kept when the visitor goes to another page and back (``persist_state``)."""
    from rotarydryer.cases import list_cases

    names = list(cases) if cases is not None else list_cases()
    case = st.sidebar.selectbox("Built-in case", names, index=names.index(default) if default in names else 0,
                                key=f"{prefix}_case" if prefix else "case", help=help_text, persist_state=PERSIST)
    upload = st.sidebar.file_uploader("... or upload a case file (TOML; `rotarydryer new NAME` writes a template; "
                                      "it may name shipped data sets only)", type=["toml"],
                                      key=f"{prefix}_case_file" if prefix else "case_file",
                                      max_upload_size=logic.MAX_UPLOAD_MB)
    shown = case
    if upload is not None:
        shown = upload.name
        try:
            case = logic.stage_case_file(upload.getvalue())
        except Exception as exc:
            refuse(f"Case file {shown} refused", exc)
        st.caption(f"Case file: {plain(shown)}")
    return case, shown


def session_id() -> str | None:
    """The Streamlit session id of the running script (None outside a script run)."""
    try:
        from streamlit.runtime.scriptrunner import get_script_run_ctx

        ctx = get_script_run_ctx(suppress_warning=True)
    except Exception:  # noqa: BLE001 - no context: no per-session limit
        return None
    return None if ctx is None else str(ctx.session_id)


def heavy(session: str | None = None):
    """``with heavy():`` around a heavy computation (`rotarydryer.app._runs`): one at a time
    per session, a bounded number at once over all sessions; the refusals are ``ValueError``\\ s
    that `refuse` shows as their message."""
    from ._runs import heavy_run

    return heavy_run(session if session is not None else session_id())


def deferred(func, *args):
    """A download button's deferred ``data`` callable: ``func(*args)`` as a heavy run of this
    session (the session id is taken now; the callable runs outside the script thread).  An error
    is logged and the download holds a one-line text instead of the file."""
    sid = session_id()

    def call():
        try:
            with heavy(sid):
                return func(*args)
        except Exception as exc:  # noqa: BLE001 - a download has no page to show it on
            if not isinstance(exc, ValueError) or isinstance(exc, UnicodeError):
                log.error("download failed", exc_info=exc)
            return f"error: {logic.visitor_message(exc)}\n".encode()

    return call


def number(container, label: str, low, high, value, step=None, **kwargs):
    """``container.number_input`` whose bounds (``None``: unbounded) always contain ``value``:
    a preset's, a case's or an upload's value never makes the widget raise.  A keyed input keeps
    its value over a visit to another page (`PERSIST`)."""
    lo, hi = logic.widen(low, high, value)
    if kwargs.get("key") is not None:
        kwargs.setdefault("persist_state", PERSIST)
    v = int(value) if isinstance(value, int) and not isinstance(value, bool) else float(value)
    return container.number_input(label, lo, hi, v, step, **kwargs)


def case_number(container, label: str, case: str, case_key: str, value, step=None, **kwargs):
    """A number input for the override ``case_key`` of ``case`` at ``value``: its bounds are the
    schema's range of the key (and the case's drum for the speed), widened to contain ``value``
    (`rotarydryer.app.logic.input_range`); ``kwargs`` go to ``number_input`` (``key`` ...)."""
    lo, hi = logic.input_range(case, case_key, float(value))
    return number(container, label, lo, hi, float(value), step, **kwargs)


def metric_row(spec: list[tuple[str, str]], values: dict) -> None:
    """One row of metrics across the page: a column for each ``(label, what)`` of ``spec``: an
    output name of ``values`` (shown in its display unit, `rotarydryer._display.show_output`), or a
    template with braces, ``template.format(**values)``."""
    for col, (label, what) in zip(st.columns(len(spec)), spec):
        col.metric(label, what.format(**values) if "{" in what else show_output(what, values[what]))


@contextmanager
def progress_box(label: str, fraction=None):
    """``with progress_box("Running ...") as report:`` around a run that takes more than a couple
    of seconds: an open ``st.status`` box with a progress bar.  ``report(message, done=None)``
    (a service's ``progress=`` callback) shows ``message`` under the bar and moves the bar to
    ``done`` (0-1) or, without it, to ``fraction(message)`` (None: the bar stays).  When the run
    ends the box closes with the time it took (or is marked failed: the page shows why); a
    rerun that interrupts the run (a widget changed meanwhile) leaves it to the next script run."""
    box = st.status(label, expanded=True)
    bar = box.progress(0.0, text="starting ...")
    shown = [0.0]
    t0 = time.monotonic()

    def report(message, done=None):
        f = done if done is not None else (fraction(message) if fraction is not None else None)
        if f is not None:
            shown[0] = min(1.0, max(0.0, float(f)))
        bar.progress(shown[0], text=plain(" ".join(str(message).split())))

    try:
        yield report
    except Exception:
        box.update(label=f"{label} failed", state="error", expanded=False)
        raise
    bar.progress(1.0, text="done")
    box.update(label=f"{label} done in {time.monotonic() - t0:.0f} s", state="complete", expanded=False)


def display_note() -> str:
    """The display units of the text (``moisture %, fuel kg/h, ...``; ``ROTARYDRYER_UNITS`` or the
    config file's ``[display]``, `rotarydryer._display`), for the sidebar."""
    u = display_units()
    return ", ".join(f"{q.replace('_', ' ')} {u[q]}" for q in ("moisture", "temperature", "mass_flow", "fuel_flow",
                                                              "power", "time"))
