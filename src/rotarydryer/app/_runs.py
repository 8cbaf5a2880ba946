"""Limits on the web app's heavy runs (no Streamlit here: testable directly).

A heavy run (a model solve, a study, a design search, a closed-loop run, a report or netCDF
download) takes 0.5-60 s of one core and tens of MB; ten browser sessions running at once took
the server from 720 to 876 MB.  Streamlit's fast reruns start a new script run of a session as
soon as a widget changes, while the old run's computation goes on in its thread, so one session
can also pile up runs.  Process-wide, therefore:

- one session runs at most one heavy run at a time: a second request of the same session waits
  up to `SESSION_WAIT_S` seconds for the running one to end (an ordinary widget change
  during a run), then is refused with `RunInProgress` ("a run is already in progress");
  of several waiting requests of a session only the newest runs (the older ones belong to
  replaced script runs and are refused at once);
- at most `MAX_CONCURRENT_RUNS` heavy runs run at once over all sessions; a request waits
  up to `WAIT_S` seconds for a free slot, then is refused with `ServerBusy`.

Both are ``ValueError`` subclasses, so the pages show their message (never a traceback).  The
same thread may nest heavy runs of its session (a cached view calling another): only the outer
one counts.
"""

from __future__ import annotations

import itertools
import os
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["RunInProgress", "ServerBusy", "heavy_run", "MAX_CONCURRENT_RUNS", "WAIT_S", "SESSION_WAIT_S",
           "active_runs", "Kept"]


def _env_int(name: str, default: int, low: int = 1) -> int:
    try:
        return max(low, int(os.environ.get(name, default)))
    except ValueError:
        return default


def _default_slots() -> int:
    from ..services._options import usable_cpus

    return usable_cpus()


#: heavy runs at once over all sessions (default: the usable CPU cores; ``ROTARYDRYER_APP_MAX_RUNS``)
MAX_CONCURRENT_RUNS = _env_int("ROTARYDRYER_APP_MAX_RUNS", _default_slots())
#: seconds a request waits for a free slot before it is refused (``ROTARYDRYER_APP_RUN_WAIT_S``)
WAIT_S = float(_env_int("ROTARYDRYER_APP_RUN_WAIT_S", 30, low=0))
#: seconds a session's request waits for the session's running heavy run to end
#: (``ROTARYDRYER_APP_SESSION_WAIT_S``)
SESSION_WAIT_S = float(_env_int("ROTARYDRYER_APP_SESSION_WAIT_S", 60, low=0))


class RunInProgress(ValueError):
    """This session already has a heavy run in progress."""


class ServerBusy(ValueError):
    """Every slot for heavy runs stayed taken for `WAIT_S` seconds."""


_guard = threading.Condition()
_owners: dict[str, int] = {}        # session id -> thread ident of its running heavy run
_latest: dict[str, int] = {}        # session id -> ticket of its newest request
_tickets = itertools.count(1)
_slots = threading.BoundedSemaphore(MAX_CONCURRENT_RUNS)

_IN_PROGRESS = ("a run is already in progress in this session: wait for it to finish (the page updates when "
                "it is done), then try again")


def active_runs() -> int:
    """Heavy runs in progress now (all sessions)."""
    with _guard:
        return len(_owners)


def _claim(key: str, me: int, session_wait: float) -> int | None:
    """Make this thread the session's runner (its ticket) or see it already is (None: nested)."""
    with _guard:
        if _owners.get(key) == me:
            return None
        ticket = next(_tickets)
        _latest[key] = ticket
        deadline = time.monotonic() + max(0.0, session_wait)
        try:
            while key in _owners:
                left = deadline - time.monotonic()
                if left <= 0 or _latest.get(key) != ticket:
                    raise RunInProgress(_IN_PROGRESS)
                _guard.wait(left)
            if _latest.get(key) != ticket:          # a newer request of this session runs instead
                raise RunInProgress(_IN_PROGRESS)
        except RunInProgress:
            if _latest.get(key) == ticket:
                del _latest[key]
            _guard.notify_all()
            raise
        _owners[key] = me
        return ticket


def _release(key: str, me: int, ticket: int) -> None:
    with _guard:
        if _owners.get(key) == me:
            del _owners[key]
        if _latest.get(key) == ticket:          # no newer request waits: forget the session
            del _latest[key]
        _guard.notify_all()


@contextmanager
def heavy_run(session: str | None, wait: float | None = None, slots: threading.Semaphore | None = None,
              session_wait: float | None = None) -> Iterator[None]:
    """Hold this session's run and one of the process's slots for the ``with`` body.

    ``session``: the Streamlit session id (``None``: no per-session limit, the global bound only).
    Raises `RunInProgress` when the session's running heavy run (in another thread) does not
    end within ``session_wait`` seconds (default `SESSION_WAIT_S`) or a newer request of the
    session came meanwhile, `ServerBusy` when no slot frees within ``wait`` seconds
    (default `WAIT_S`)."""
    me = threading.get_ident()
    key = None if session is None else str(session)
    ticket = None
    if key is not None:
        ticket = _claim(key, me, SESSION_WAIT_S if session_wait is None else float(session_wait))
        if ticket is None:
            yield                               # nested in this session's own run: already counted
            return
    sem = _slots if slots is None else slots
    try:
        if not sem.acquire(timeout=WAIT_S if wait is None else max(0.0, float(wait))):
            raise ServerBusy(f"the server is busy: {MAX_CONCURRENT_RUNS} runs are in progress for other "
                             "visitors; try again in a minute")
        try:
            yield
        finally:
            sem.release()
    finally:
        if key is not None and ticket is not None:
            _release(key, me, ticket)


class Kept:
    """A bounded, thread-safe store of finished heavy runs' results shared by every session (the
    newest ``max_entries``), for the runs that draw a progress bar while they compute: inside an
    ``st.cache_data`` function the bar's calls would be recorded and replayed on a later hit of
    another session (which fails: CacheReplayClosureError), so the page keeps the result here and
    draws the bar only when it computes."""

    def __init__(self, max_entries: int = 8):
        self.max_entries = max(1, int(max_entries))
        self._lock = threading.Lock()
        self._items: dict = {}

    def get(self, key):
        """The kept result of ``key`` (hashable) or None."""
        with self._lock:
            if key not in self._items:
                return None
            value = self._items.pop(key)
            self._items[key] = value        # newest last
            return value

    def put(self, key, value) -> None:
        with self._lock:
            self._items.pop(key, None)
            self._items[key] = value
            while len(self._items) > self.max_entries:
                del self._items[next(iter(self._items))]

    def clear(self) -> None:
        with self._lock:
            self._items.clear()
