"""Helpers shared by the AppTest tests (Streamlit's headless harness): open the app on a page,
switch pages, read a metric as a number, the image URLs. Import after
``pytest.importorskip("streamlit")``."""

import re

from streamlit.testing.v1 import AppTest

from rotarydryer.app import PAGES, script_path


def goto(at, title):
    """Switch ``at`` (run at least once) to the page ``title`` (``st.navigation``: the page's
    file in :mod:`rotarydryer.app.entries`, as a click on its navigation link) and run it."""
    return at.switch_page(f"entries/{PAGES[title][1]}.py").run()


def open_app(page=None, timeout=120, no_error=False):
    """The app, run once and switched to ``page``; no exception (and with ``no_error``, no error box)."""
    at = AppTest.from_file(str(script_path()), default_timeout=timeout)
    at.run()
    if page is not None:
        goto(at, page)
    assert not at.exception, [e.value for e in at.exception]
    if no_error:
        assert not at.error, [e.value for e in at.error]
    return at


def metric_number(at, label):
    """The number at the start of the metric ``label``'s value."""
    m = next(m for m in at.metric if m.label == label)
    return float(re.sub(r"[^0-9.\-]", "", m.value.split()[0]))


def image_urls(at):
    return [i.proto.imgs[0].url for i in at.image]
