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


FEED = 98000 / 3600


def invicta(n_cells=35, **changes):
    """The Invicta plant inputs of ``lee2008()`` (Lee (2008) Appendix I code, as the shipped case
    file): feed, drum, bulk density, the Eq. 7.2-7.3 repose profile and Lee's 39.6 s tracer pulse;
    plant numbers are not defaults of the library function."""
    from rotarydryer.transport import TracerInput, lee2008_repose_profile

    out = dict(n_cells=n_cells, feed_rate=FEED, length=12.0, rpm=3.0, slope=2.8, bulk_density=940.0,
               repose_angle=lee2008_repose_profile(n_cells, 0.02, 0.002),
               tracer_input=TracerInput.pulse(3.683e-4 * 39.6 * FEED, 39.6))
    out.update(changes)
    return out
