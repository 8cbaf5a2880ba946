import pytest

from rotarydryer.cli import app as cli_app

# the report command module registers itself on import (the lead adds it to cli/__init__.py)
from rotarydryer.cli import report as _report_cmd  # noqa: F401


@pytest.fixture(scope="session")
def cli():
    return cli_app
