"""End-to-end: the "Design", "Control" and "Lab data" pages of the web app in a real browser
(Debian chromium + Playwright) at a laptop size (1366 x 768): change an input, see the result
change, never a traceback.  Skips cleanly when /usr/bin/chromium, Playwright or Streamlit is
missing."""

from .browser_support import skip_without_browser

skip_without_browser()
from .browser_support import browser, enter, expect, metric, new_page, server  # noqa: E402,F401
from .browser_support import metric_locator as _value  # noqa: E402


def _set(page, label, value):
    box = page.get_by_label(label, exact=True)
    enter(box, value)


def _click_button(page, name):
    """Click the one button ``name`` (a rerun may show the previous run's button a moment longer)."""
    button = page.get_by_role("button", name=name)
    expect(button).to_have_count(1)
    button.click()


def _no_traceback(page):
    assert "Traceback" not in page.content()
    expect(page.locator('[data-testid="stException"]')).to_have_count(0)


def test_design_page_in_browser(server, browser):
    page = new_page(browser, server, "Design")
    expect(page.get_by_text("Size a dryer for a duty")).to_be_visible()
    _click_button(page, "Size the dryer")
    d = _value(page, "Diameter D")
    expect(d).to_be_visible()
    before = d.inner_text()
    _set(page, "Gas flow (kg/s wet)", 40)
    expect(page.get_by_text("The inputs changed")).to_be_visible()
    _click_button(page, "Size the dryer")
    expect(d).not_to_have_text(before)
    assert float(metric(page, "Diameter D").split()[0]) > float(before.split()[0])  # more gas: wider (entrainment)
    _no_traceback(page)
    page.close()


def test_control_page_in_browser(server, browser):
    page = new_page(browser, server, "Control")
    expect(page.get_by_text("Control: closed loop on the dynamic model")).to_be_visible()
    _set(page, "Simulated time (s)", 1200)
    _set(page, "Sample time (s)", 120)
    _click_button(page, "Run closed and open loop")
    closed = _value(page, "Peak error, closed (pp)")
    expect(closed).to_be_visible()
    before = closed.inner_text()
    expect(_value(page, "Peak error, open (pp)")).to_be_visible()
    _set(page, "Magnitude", 0.1)
    _click_button(page, "Run closed and open loop")
    expect(closed).not_to_have_text(before)
    expect(page.locator('[data-testid="stImage"] img')).to_have_count(1)
    _no_traceback(page)
    page.close()


def test_lab_page_in_browser(server, browser):
    page = new_page(browser, server, "Lab data")
    expect(page.get_by_text("Laboratory data")).to_be_visible()
    inside = _value(page, "Mass in band (%)")
    expect(inside).to_be_visible()
    expect(_value(page, "Repose angle (deg)")).to_have_text("39.60")      # the synthetic run's 39.6 deg
    before = inside.inner_text()
    _set(page, "Repose-angle SD (deg)", 0.5)
    expect(inside).not_to_have_text(before)
    # the step-test tab: Song's run 2 simulated, then a given initial holdup
    page.get_by_role("tab", name="Step tests").click()
    h2 = _value(page, "Closure (%)")
    expect(h2).to_be_visible()
    before = h2.inner_text()
    _set(page, "Initial holdup (kg)", 1)
    expect(h2).not_to_have_text(before)
    _no_traceback(page)
    page.close()
