"""End-to-end: every page of the web app has its own address (``st.navigation``) in a real
browser (Debian chromium + Playwright): a page opened directly by its URL shows its own title
and widgets (not the landing page's), the navigation links change the URL, and the browser's
Back button returns to the previous page with the other page's widgets gone.  Skips cleanly
when /usr/bin/chromium, Playwright or Streamlit is missing."""

import re

from .browser_support import skip_without_browser

skip_without_browser()
from rotarydryer.app import PAGES  # noqa: E402

from .browser_support import browser, expect, server  # noqa: E402,F401

TRANSPORT = "Solids transport and residence time"
CONTROL = "Control: closed loop on the dynamic model"


def _heading(page, text):
    return page.get_by_role("heading", name=text)


def _at(url_path):
    return re.compile(rf"/{url_path}/?(\?.*)?$")


def test_pages_open_by_url_and_back_returns(server, browser):
    assert PAGES["Transport and RTD"][1] == "transport" and PAGES["Control"][1] == "control"
    page = browser.new_page(viewport={"width": 1366, "height": 768})
    page.set_default_timeout(90_000)
    # a page opened by its address: its own heading and widget, not the landing page's
    page.goto(f"{server}/transport")
    expect(_heading(page, TRANSPORT)).to_be_visible()
    expect(page.get_by_role("spinbutton", name="Feed rate (kg/s)")).to_be_visible()
    expect(_heading(page, "Flight geometry explorer")).to_have_count(0)
    page.goto(f"{server}/control")
    expect(_heading(page, CONTROL)).to_be_visible()
    expect(page.get_by_role("button", name="Run closed and open loop")).to_be_visible()
    expect(_heading(page, TRANSPORT)).to_have_count(0)
    # Back: the previous page again, the other page's widgets gone
    page.go_back()
    expect(page).to_have_url(_at("transport"))
    expect(_heading(page, TRANSPORT)).to_be_visible()
    expect(page.get_by_role("spinbutton", name="Feed rate (kg/s)")).to_be_visible()
    expect(_heading(page, CONTROL)).to_have_count(0)
    expect(page.get_by_role("button", name="Run closed and open loop")).to_have_count(0)
    # a navigation link in the sidebar changes the address; Back returns within the session
    page.locator('[data-testid="stSidebarNav"]').get_by_text("Lab data", exact=True).click()
    expect(page).to_have_url(_at("lab"))
    expect(_heading(page, "Laboratory data")).to_be_visible()
    expect(_heading(page, TRANSPORT)).to_have_count(0)
    page.go_back()
    expect(page).to_have_url(_at("transport"))
    expect(_heading(page, TRANSPORT)).to_be_visible()
    expect(_heading(page, "Laboratory data")).to_have_count(0)
    # the landing page is at the root
    page.goto(server)
    expect(_heading(page, "Flight geometry explorer")).to_be_visible()
    assert "Traceback" not in page.content()
    page.close()
