import csv
from importlib import resources

import pytest

from rotarydryer.geometry.lee2008_regressions import Lee2008Regressions


def read_csv(name):
    text = (resources.files("rotarydryer") / "data" / name).read_text()
    lines = [ln for ln in text.splitlines() if not ln.startswith("#")]
    return list(csv.DictReader(lines))


@pytest.fixture(scope="session")
def regressions():
    return Lee2008Regressions()


@pytest.fixture(scope="session")
def table_7_2():
    return {int(r["N"]): dict(kiln_time=float(r["t_kiln_s"]), backmix=float(r["C_B"]),
                              drag_reduction=float(r["C_F_G"]))
            for r in read_csv("lee_parameter_estimates.csv")}
