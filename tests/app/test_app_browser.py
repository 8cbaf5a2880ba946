"""End-to-end: the web app and the HTML report in a real browser (Debian chromium +
Playwright).  Skips cleanly when /usr/bin/chromium, Playwright or Streamlit is missing.

Set ROTARYDRYER_SCREENSHOTS=1 to refresh docs/img/app.png, app_transport.png and report.png.
"""

import os
import shutil
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

if not os.path.exists(CHROMIUM):
    pytest.skip(f"{CHROMIUM} is absent (apt-get install -y chromium)", allow_module_level=True)
pytest.importorskip("playwright.sync_api", reason="Playwright for Python is not installed (pip install playwright)")
pytest.importorskip("streamlit", reason="Streamlit is not installed (pip install streamlit)")
pytest.importorskip("xarray")

from playwright.sync_api import expect, sync_playwright  # noqa: E402

# The app recomputes on every change: allow for a busy 2-core CI machine (Playwright's
# assertions have their own 5 s default, independent of the page timeout).
expect.set_options(timeout=90_000)

from rotarydryer.app import streamlit_command  # noqa: E402

SHOTS = os.environ.get("ROTARYDRYER_SCREENSHOTS") == "1"


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    port = _free_port()
    log = tmp_path_factory.mktemp("app") / "streamlit.log"
    with open(log, "wb") as fh:
        proc = subprocess.Popen(streamlit_command(port), stdout=fh, stderr=subprocess.STDOUT)
    url = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 90
        while True:
            try:
                with urllib.request.urlopen(f"{url}/_stcore/health", timeout=2) as r:
                    if r.read().strip() == b"ok":
                        break
            except OSError:
                pass
            if proc.poll() is not None or time.monotonic() > deadline:
                pytest.fail(f"streamlit did not start (exit {proc.poll()}):\n{log.read_text()[-3000:]}")
            time.sleep(0.3)
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
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield b
        b.close()


def _metric(page, label):
    box = page.locator('[data-testid="stMetric"]').filter(has_text=label)
    return box.locator('[data-testid="stMetricValue"]').inner_text()


def test_app_geometry_page_updates_in_browser(server, browser):
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    page.set_default_timeout(60_000)
    page.goto(server)
    expect(page.get_by_text("Flight geometry explorer")).to_be_visible()
    expect(page.locator('[data-testid="stMetric"]').filter(has_text="Design load")).to_be_visible()
    before = _metric(page, "Design load (Lee 2008)")
    imgs = page.locator('[data-testid="stImage"] img')
    expect(imgs).to_have_count(2)
    src_before = imgs.first.get_attribute("src")
    box = page.get_by_label("Dynamic repose angle (deg)")
    box.fill("50")
    box.press("Enter")
    metric = page.locator('[data-testid="stMetric"]').filter(has_text="Design load").locator('[data-testid="stMetricValue"]')
    expect(metric).not_to_have_text(before)
    expect(metric).to_have_text("6,786 kg")  # Lee (2008) Table 7.7: 6784 kg at 50 deg
    expect(imgs.first).not_to_have_attribute("src", src_before)
    # the new picture really loaded
    page.wait_for_function("() => [...document.querySelectorAll('[data-testid=stImage] img')]"
                           ".every(i => i.complete && i.naturalWidth > 100)")
    if SHOTS:
        page.wait_for_timeout(500)
        page.screenshot(path=str(DOCS_IMG / "app.png"))
    page.close()


def test_app_transport_page_in_browser(server, browser):
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    page.set_default_timeout(90_000)
    page.goto(server)
    page.get_by_text("Transport and RTD").click()
    expect(page.get_by_text("Solids transport and residence time")).to_be_visible()
    expect(page.locator('[data-testid="stMetric"]').filter(has_text="Total holdup")).to_be_visible()
    expect(page.locator('[data-testid="stMetric"]').filter(has_text="Fitted outlet mean")).to_be_visible()
    before = _metric(page, "Total holdup")
    box = page.get_by_label("Feed rate (kg/s)")
    box.fill("20")
    box.press("Enter")
    metric = page.locator('[data-testid="stMetric"]').filter(has_text="Total holdup").locator('[data-testid="stMetricValue"]')
    expect(metric).not_to_have_text(before)
    assert float(metric.inner_text().split()[0].replace(",", "")) < float(before.split()[0].replace(",", ""))
    # upload a tracer CSV (Lee's Invicta curve) and fit it
    fitted = page.locator('[data-testid="stMetric"]').filter(has_text="Fitted outlet mean").locator(
        '[data-testid="stMetricValue"]')
    fit_before = fitted.inner_text()
    csv_path = Path(__file__).resolve().parents[2] / "src" / "rotarydryer" / "data" / "tracer_lee2008_invicta.csv"
    page.locator('[data-testid="stFileUploader"]').filter(has_text="tracer CSV").locator(
        'input[type="file"]').set_input_files(str(csv_path))
    expect(fitted).not_to_have_text(fit_before)
    from rotarydryer.app.logic import fit_tracer

    expected = fit_tracer(text=csv_path.read_text(), images=False)["moments"]["mean_s"] / 60
    expect(fitted).to_have_text(f"{expected:.2f} min")
    expect(page.get_by_text("Fitting: uploaded file tracer_lee2008_invicta.csv")).to_be_visible()
    if SHOTS:
        page.wait_for_function("() => [...document.querySelectorAll('[data-testid=stImage] img')]"
                               ".every(i => i.complete && i.naturalWidth > 100)")
        page.wait_for_timeout(500)
        page.screenshot(path=str(DOCS_IMG / "app_transport.png"))
    page.close()


def test_app_bad_case_file_shows_readable_error(server, browser, tmp_path):
    from importlib import resources

    text = (resources.files("rotarydryer.cases") / "lee2008_invicta.toml").read_text()
    bad = tmp_path / "bad_case.toml"
    bad.write_text(text.replace("radius = 2.5", "radius = -2.5", 1))
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    page.set_default_timeout(60_000)
    page.goto(server)
    page.get_by_text("Transport and RTD").click()
    expect(page.locator('[data-testid="stMetric"]').filter(has_text="Total holdup")).to_be_visible()
    page.locator('[data-testid="stFileUploader"]').filter(has_text="case file").locator(
        'input[type="file"]').set_input_files(str(bad))
    alert = page.locator('[data-testid="stAlert"]').filter(has_text="drum.radius")
    expect(alert).to_be_visible()
    expect(alert).to_contain_text("-2.5")
    expect(page.get_by_text("Traceback")).to_have_count(0)
    page.close()


def test_report_renders_in_browser(browser, tmp_path):
    from rotarydryer.report.html import write_report

    out = write_report("lee2008_invicta", tmp_path / "report.html", {"geometry.method": "lee2008_regressions"})
    page = browser.new_page(viewport={"width": 1200, "height": 900})
    # no network at all: every resource must be inside the file
    page.route("**/*", lambda route: route.abort() if not route.request.url.startswith("file:") else route.continue_())
    page.goto(out.as_uri())
    n = page.evaluate("() => document.images.length")
    assert n >= 6
    ok = page.evaluate("() => [...document.images].every(i => i.complete && i.naturalWidth > 100)")
    assert ok
    expect(page.get_by_text("Loading state per section")).to_be_visible()
    if SHOTS:
        page.screenshot(path=str(DOCS_IMG / "report.png"))
        shutil.copy(out, tmp_path / "kept.html")
    page.close()
