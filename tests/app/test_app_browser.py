"""End-to-end: the web app and the HTML report in a real browser (Debian chromium +
Playwright).  Skips cleanly when /usr/bin/chromium, Playwright or Streamlit is missing.

Set ROTARYDRYER_SCREENSHOTS=1 to refresh docs/img/app.png, app_transport.png and report.png.
"""

import shutil
from pathlib import Path

from .browser_support import skip_without_browser

skip_without_browser()
from .browser_support import DOCS_IMG, SHOTS, browser, enter, expect, metric_locator, server  # noqa: E402,F401
from .browser_support import metric as _metric  # noqa: E402


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
    enter(box, "50")
    metric = metric_locator(page, "Design load")
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
    box = page.get_by_role("spinbutton", name="Feed rate (kg/s)")
    enter(box, "20")
    metric = metric_locator(page, "Total holdup")
    expect(metric).not_to_have_text(before)
    assert float(metric.inner_text().split()[0].replace(",", "")) < float(before.split()[0].replace(",", ""))
    # the tracer fit starts on the case's own data set (Invicta case: Lee's Invicta curve)
    expect(page.get_by_text("Fitting: published curve lee2008_invicta")).to_be_visible()
    # upload a tracer CSV (Ajayi's test 2) and fit it
    fitted = page.locator('[data-testid="stMetric"]').filter(has_text="Fitted outlet mean").locator(
        '[data-testid="stMetricValue"]')
    fit_before = fitted.inner_text()
    csv_path = Path(__file__).resolve().parents[2] / "src" / "rotarydryer" / "data" / "tracer_ajayi2011_test2.csv"
    page.locator('[data-testid="stFileUploader"]').filter(has_text="tracer CSV").locator(
        'input[type="file"]').set_input_files(str(csv_path))
    expect(page.get_by_text("Fitting: uploaded file tracer_ajayi2011_test2.csv")).to_be_visible()
    expect(fitted).not_to_have_text(fit_before)
    from rotarydryer.app.logic import fit_tracer

    expected = fit_tracer(text=csv_path.read_text(), images=False)["moments"]["mean_s"] / 60
    expect(fitted).to_have_text(f"{expected:.2f} min")
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
