import pytest

from rotarydryer.cli import app as _cli_app
from rotarydryer.cli import report as _report  # noqa: F401  (registers ``rotarydryer report``)
from rotarydryer.cli import webapp as _webapp  # noqa: F401  (registers ``rotarydryer app``)


@pytest.fixture(scope="session")
def cli():
    return _cli_app
