"""Run the doctests of the thermal modules (pytest does not collect doctests by default)."""

import doctest

import pytest

from rotarydryer.thermal import burner, drying, radiation, shell, streams


@pytest.mark.parametrize("module", [burner, drying, radiation, shell, streams], ids=lambda m: m.__name__)
def test_doctests(module):
    result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.failed == 0 and result.attempted > 0
