"""Run the doctests of the correlation modules (pytest does not collect doctests by default)."""

import doctest

import pytest

import rotarydryer.correlations as corr
from rotarydryer.correlations import drag, heat_transfer, residence_time, trajectory


@pytest.mark.parametrize("module", [corr, residence_time, heat_transfer, drag, trajectory],
                         ids=lambda m: m.__name__)
def test_doctests(module):
    result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.failed == 0
    if module is not corr:
        assert result.attempted > 0


def test_every_public_function_has_a_doctest():
    missing = []
    for module in (residence_time, heat_transfer, drag, trajectory):
        for name in module.__all__:
            obj = getattr(module, name)
            if callable(obj) and not isinstance(obj, type):
                if ">>>" not in (obj.__doc__ or ""):
                    missing.append(f"{module.__name__}.{name}")
    assert not missing, missing
