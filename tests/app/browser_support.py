"""Shared pieces of the browser tests of the web app (Debian chromium + Playwright).

A test module starts with::

    from .browser_support import skip_without_browser
    skip_without_browser()
    from .browser_support import browser, expect, metric, new_page, server  # noqa: F401

``server`` (module scope) serves the app with ``rotarydryer app``'s own command line on a free
port; ``browser`` is a headless Chromium; ``new_page(browser, server, "Page title")`` opens the
app on one page of the sidebar; ``metric(page, label)`` is the shown value of a metric;
``choose(page, label, option)`` picks an option of a selectbox.

``free_port()`` and ``wait_until_serving(url, proc, log)`` need no browser: a test of the server
alone (``test_app_cli_stop.py``) imports them without calling ``skip_without_browser()``.
"""

import os
import socket
import subprocess
import time
import urllib.request
from pathlib import Path

import pytest

CHROMIUM = "/usr/bin/chromium"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--disable-sync", "--no-first-run"]
DOCS_IMG = Path(__file__).resolve().parents[2] / "docs" / "img"
SHOTS = os.environ.get("ROTARYDRYER_SCREENSHOTS") == "1"


def skip_without_browser():
    """Skip the calling test module when Chromium, Playwright or Streamlit is missing."""
    if not os.path.exists(CHROMIUM):
        pytest.skip(f"{CHROMIUM} is absent (apt-get install -y chromium)", allow_module_level=True)
    pytest.importorskip("playwright.sync_api", reason="Playwright for Python is not installed (pip install playwright)")
    pytest.importorskip("streamlit", reason="Streamlit is not installed (pip install streamlit)")
    pytest.importorskip("xarray")


try:
    from playwright.sync_api import expect, sync_playwright
except ImportError:         # the server helpers below serve tests without a browser too
    expect = sync_playwright = None
else:
    # The app recomputes on every change: allow for a busy 2-core CI machine (Playwright's
    # assertions have their own 5 s default, independent of the page timeout).
    expect.set_options(timeout=90_000)

from rotarydryer.app import streamlit_command  # noqa: E402


def free_port() -> int:
    """A TCP port on 127.0.0.1 that is free now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_until_serving(url: str, proc: subprocess.Popen, log: Path, what: str = "streamlit",
                       timeout: float = 90) -> None:
    """Wait until the Streamlit server at ``url`` (started as ``proc``) answers its health check;
    if ``proc`` exits or ``timeout`` seconds pass first, kill it and fail the test with the end of
    its ``log`` (``what`` names it in the message)."""
    deadline = time.monotonic() + timeout
    while True:
        try:
            with urllib.request.urlopen(f"{url}/_stcore/health", timeout=2) as r:
                if r.read().strip() == b"ok":
                    return
        except OSError:
            pass
        if proc.poll() is not None or time.monotonic() > deadline:
            proc.kill()
            pytest.fail(f"{what} did not start (exit {proc.poll()}):\n{Path(log).read_text()[-3000:]}")
        time.sleep(0.3)


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    skip_without_browser()
    port = free_port()
    log = tmp_path_factory.mktemp("app") / "streamlit.log"
    with open(log, "wb") as fh:
        proc = subprocess.Popen(streamlit_command(port), stdout=fh, stderr=subprocess.STDOUT)
    url = f"http://127.0.0.1:{port}"
    try:
        wait_until_serving(url, proc, log)
        yield url
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


@pytest.fixture(scope="module")
def browser():
    skip_without_browser()
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield b
        b.close()


def new_page(browser, server, title: str | None = None, width: int = 1366, height: int = 768):
    """A browser tab on the app (a laptop-sized window), switched to the sidebar page ``title``."""
    page = browser.new_page(viewport={"width": width, "height": height})
    page.set_default_timeout(90_000)
    page.goto(server)
    if title is not None:
        page.locator('[data-testid="stSidebar"]').get_by_text(title, exact=True).click()
    return page


def metric_locator(page, label):
    """The value element of the metric whose label contains ``label`` (for ``expect``)."""
    return page.locator('[data-testid="stMetric"]').filter(has_text=label).locator('[data-testid="stMetricValue"]')


def metric(page, label):
    """The shown value of the metric whose label contains ``label``."""
    return metric_locator(page, label).inner_text()


def enter(box, value):
    """Type ``value`` into an input and press Enter (Streamlit reruns on it)."""
    box.fill(str(value))
    box.press("Enter")


def choose(page, label, option, within=None):
    """Pick ``option`` of the selectbox ``label`` (in ``within``, a locator such as the sidebar;
    default the whole page), again if a rerun of the app closed the list."""
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    scope = page if within is None else within
    # the previous page's widgets may still be on screen for a moment after a page switch (a
    # second selectbox of the same label): wait for the one of this page
    expect(scope.get_by_role("combobox", name=label)).to_have_count(1)
    for _ in range(10):
        scope.get_by_role("combobox", name=label).click()
        try:
            page.get_by_role("option", name=option, exact=True).click(timeout=5_000)
            return
        except PlaywrightTimeout:
            page.keyboard.press("Escape")
    raise AssertionError(f"could not choose {option!r} in {label!r}")
