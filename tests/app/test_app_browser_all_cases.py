"""End-to-end: every page of the web app with every shipped case (and a `rotarydryer new`
template uploaded) in a real browser (Debian chromium + Playwright): each page shows its
results, no error box, no exception, no traceback. One server and one tab (about 2-3 min).
Skips cleanly when /usr/bin/chromium, Playwright or Streamlit is missing."""

import re

import pytest
from typer.testing import CliRunner

from .browser_support import skip_without_browser

skip_without_browser()
from rotarydryer.app import PAGES as APP_PAGES  # noqa: E402

from .browser_support import browser, choose, expect, new_page, server  # noqa: E402,F401

SHIPPED = ["ajayi2011_mmg", "lee2008_invicta", "song2003_ottawa"]
#: page -> (label of its case selectbox or None, text shown once the page has its results)
PAGES = {
    "Flight geometry": (None, "Design load (Lee 2008)"),
    "Transport and RTD": ("Built-in case", "Total holdup"),
    "Whole dryer": ("Built-in case", "Product moisture"),
    "Studies and sensitivity": ("Built-in case", "Global sensitivity"),
    "Design": (None, "Size the dryer"),
    "Control": ("Built-in case", "Run closed and open loop"),
    "Lab data": (None, "Repose angle (deg)"),
}
#: texts of the app's error boxes (pages' refusals and the failure boundary)
ERRORS = ("could not be shown", "internal error", "refused", "Invalid input", "Cannot ", "No design", "Traceback")


def _check(page, where, ready):
    page.wait_for_timeout(300)        # the rerun starts (the status widget shows "Running ...")
    page.wait_for_function("() => !document.querySelector('[data-testid=stStatusWidgetRunningIcon]')"
                           " && !document.querySelector('[data-testid=stSpinner]')")
    expect(page.get_by_text(ready, exact=False).first).to_be_visible()
    expect(page.locator('[data-testid="stException"]')).to_have_count(0)
    alerts = page.locator('[data-testid="stAlert"]')
    texts = [alerts.nth(i).inner_text() for i in range(alerts.count())]
    bad = [t for t in texts if any(e in t for e in ERRORS)]
    assert not bad, (where, bad)
    assert "Traceback" not in page.content(), where


@pytest.fixture(scope="module")
def template(tmp_path_factory):
    from rotarydryer.cli import app

    path = tmp_path_factory.mktemp("new") / "mydryer.toml"
    res = CliRunner().invoke(app, ["new", "mydryer", "--out", str(path)])
    assert res.exit_code == 0, res.output
    return path


@pytest.mark.slow
def test_every_page_with_every_case_in_browser(server, browser, template):
    page = new_page(browser, server)
    sidebar = page.locator('[data-testid="stSidebar"]')
    for title, (case_label, ready) in PAGES.items():
        sidebar.get_by_text(title, exact=True).click()
        url = APP_PAGES[title][1]          # the page's own address (the landing page: the root)
        expect(page).to_have_url(re.compile(rf"/{'' if title == next(iter(APP_PAGES)) else url}/?$"))
        if case_label is None:
            _check(page, title, ready)
            continue
        for case in SHIPPED:
            choose(page, case_label, case, within=sidebar)
            expect(sidebar.get_by_role("combobox", name=case_label)).to_have_value(case)
            _check(page, (title, case), ready)
        uploader = sidebar.locator('[data-testid="stFileUploader"]').filter(has_text="case file")
        uploader.locator('input[type="file"]').set_input_files(str(template))
        expect(page.get_by_text("Case file: mydryer.toml")).to_be_visible()
        _check(page, (title, "template"), ready)
        # the next page has its own uploader (its own widget key): it starts on the built-in cases
    page.close()
