"""End-to-end: the "Whole dryer" and "Studies and sensitivity" pages in a real browser (Debian
chromium + Playwright) on a laptop-sized window (1366 x 768). Skips cleanly when
/usr/bin/chromium, Playwright or Streamlit is missing.

Set ROTARYDRYER_SCREENSHOTS=1 to refresh docs/img/app_dryer.png and app_studies.png.
"""

import pytest

from .browser_support import skip_without_browser

skip_without_browser()
pytest.importorskip("SALib")
from rotarydryer._display import show_output  # noqa: E402

from .browser_support import DOCS_IMG, SHOTS, browser, choose, enter, expect, metric, new_page, server  # noqa: E402,F401
from .browser_support import metric_locator as _value  # noqa: E402


def _images_loaded(page):
    page.wait_for_function("() => [...document.querySelectorAll('[data-testid=stImage] img')]"
                           ".every(i => i.complete && i.naturalWidth > 100)")


def test_whole_dryer_page_in_browser(server, browser):
    page = new_page(browser, server, "Whole dryer")
    expect(page.get_by_role("heading", name="Whole dryer")).to_be_visible()
    from rotarydryer.simulation import Simulation

    x0 = Simulation("ajayi2011_mmg").steady_state().summary()["product_moisture_kg_kg"]
    moisture = _value(page, "Product moisture")
    expect(moisture).to_have_text(show_output("product_moisture_kg_kg", x0))     # in its display unit, %
    assert show_output("product_moisture_kg_kg", x0).endswith(" %")             # Ajayi (2011) test 4: 12.4 % measured
    expect(_value(page, "Fuel rate")).to_be_visible()
    gas_before = metric(page, "Gas outlet temperature")
    imgs = page.locator('[data-testid="stImage"] img')
    expect(imgs).to_have_count(1)                                   # the energy waterfall
    charts = page.locator('[data-testid="stVegaLiteChart"]')        # the interactive profiles
    expect(charts).to_have_count(3)
    expect(charts.first.locator("canvas, svg").first).to_be_visible()
    src_before = imgs.first.get_attribute("src")
    box = page.get_by_role("spinbutton", name="Feed rate (kg/s wet)")
    enter(box, "50")
    expect(moisture).not_to_have_text(f"{x0:.4f} kg/kg")
    assert float(moisture.inner_text().split()[0]) > x0         # more feed, same gas: wetter product
    expect(_value(page, "Gas outlet temperature")).not_to_have_text(gas_before)
    expect(imgs.first).not_to_have_attribute("src", src_before)
    _images_loaded(page)
    # metrics and the two figures side by side fit a laptop screen's width
    width = page.evaluate("() => document.documentElement.scrollWidth")
    assert width <= 1366
    # a bad value: the CLI's one-line message, no traceback
    enter(box, "0")
    alert = page.locator('[data-testid="stAlert"]')
    expect(alert).to_contain_text("operating.feed_rate")
    expect(alert).to_contain_text("greater than 0")
    assert "Traceback" not in page.content()
    if SHOTS:
        enter(box, "40.667")
        expect(alert).to_have_count(0)
        _images_loaded(page)
        page.wait_for_timeout(500)
        page.screenshot(path=str(DOCS_IMG / "app_dryer.png"))
    page.close()


def test_studies_page_in_browser(server, browser):
    page = new_page(browser, server, "Studies and sensitivity")
    expect(page.get_by_text("What-if: one input")).to_be_visible()
    imgs = page.locator('[data-testid="stImage"] img')
    expect(imgs).to_have_count(1)
    src_before = imgs.first.get_attribute("src")
    points = page.get_by_role("spinbutton", name="Points (2-15)")
    enter(points, "3")
    expect(imgs.first).not_to_have_attribute("src", src_before)
    # the sensitivity study runs on the button: 4 samples x (2 inputs + 2) = 16 runs
    choose(page, "Base samples N", "4")
    expect(page.get_by_text("16 runs (limit 96)")).to_be_visible()
    run = page.get_by_role("button", name="Run the sensitivity study")
    expect(run).to_have_count(1)           # a rerun may show the previous run's button a moment longer
    run.click()
    runs = _value(page, "Runs (failed)")
    expect(runs).to_have_text("16 (0)")
    expect(imgs).to_have_count(3)          # what-if plot, Sobol figures of 2 + 2 outputs
    # changing an input changes the result: 8 samples -> 32 runs
    choose(page, "Base samples N", "8")
    expect(page.get_by_text("32 runs (limit 96)")).to_be_visible()
    expect(run).to_have_count(1)
    run.click()
    expect(runs).to_have_text("32 (0)")
    _images_loaded(page)
    assert "Traceback" not in page.content()
    if SHOTS:
        page.get_by_text("What-if: one input").scroll_into_view_if_needed()
        page.wait_for_timeout(500)
        page.screenshot(path=str(DOCS_IMG / "app_studies.png"), full_page=False)
    page.close()
