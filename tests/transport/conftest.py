import pytest

from rotarydryer.geometry.lee2008_regressions import Lee2008Regressions
from rotarydryer.published import read_published_csv as read_csv  # noqa: F401  (imported by the tests)


@pytest.fixture(scope="session")
def regressions():
    return Lee2008Regressions()


@pytest.fixture(scope="session")
def table_7_2():
    return {int(r["N"]): dict(kiln_time=float(r["t_kiln_s"]), backmix=float(r["C_B"]),
                              drag_reduction=float(r["C_F_G"]))
            for r in read_csv("lee_parameter_estimates.csv")}
