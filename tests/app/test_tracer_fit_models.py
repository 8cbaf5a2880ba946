"""The app's tracer-fit page logic with Song's (2003) cell models and the fitted background
(issue 14 part 6): ``logic.tracer_models``, ``logic.fit_tracer(model=..., baseline=...)``, and the
page's widgets (Streamlit AppTest)."""

import pytest

pytest.importorskip("streamlit")

from rotarydryer.app import logic  # noqa: E402
from rotarydryer.rtd import RTD_FIT_MODELS  # noqa: E402


def test_page_offers_every_fit_model():
    assert logic.tracer_models() == RTD_FIT_MODELS
    assert {"interactive_mixers", "cholette_cloutier"} <= set(logic.tracer_models())
    assert logic.TRACER_BASELINES == ("none", "fit")


def test_cell_model_with_background_on_a_shipped_curve():
    plain = logic.fit_tracer(dataset="ajayi2011_test4", model="interactive_mixers", images=False)
    bg = logic.fit_tracer(dataset="ajayi2011_test4", model="interactive_mixers", baseline="fit", images=False)
    names = [row[0] for row in bg["table"]]
    assert names == ["conductance_per_s", "scale", "baseline"]
    assert [row[0] for row in plain["table"]] == ["conductance_per_s", "scale"]
    assert isinstance(bg["n_cells"], int) and bg["n_cells"] >= 1
    b = dict((row[0], row[1]) for row in bg["table"])["baseline"]
    assert 0.1 < b < 2.0                              # Ajayi's lithium background, ppm
    assert bg["r_squared"] > plain["r_squared"]
    assert bg["baseline"] == "fit" and isinstance(bg["warnings"], list)
    tis = logic.fit_tracer(dataset="ajayi2011_test4", images=False)
    assert tis["n_cells"] is None


def test_dead_zone_model_on_the_invicta_curve_with_plot():
    out = logic.fit_tracer(dataset="lee2008_invicta", model="cholette_cloutier")
    assert [row[0] for row in out["table"]] == ["conductance_per_s", "active_fraction", "exchange_ratio"]
    assert out["r_squared"] > 0.98
    assert out["plot"][:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("kwargs,fragment", [(dict(model="cholette"), "model = 'cholette'"),
                                             (dict(model=""), "model"),
                                             (dict(baseline="yes"), "baseline = 'yes'"),
                                             (dict(baseline="leading"), "baseline")])
def test_bad_model_or_baseline_is_refused(kwargs, fragment):
    with pytest.raises(ValueError, match=fragment):
        logic.fit_tracer(dataset="ajayi2011_test4", images=False, **kwargs)


def test_page_widgets_choose_the_model_and_the_background():
    from .apptest_support import open_app

    at = open_app("Transport and RTD", timeout=300)
    at.selectbox(key="rtd_model").set_value("interactive_mixers").run()
    at.checkbox(key="rtd_baseline").check().run()
    assert not at.exception and not at.error
    labels = [m.label for m in at.metric]
    assert "Number of cells N" in labels
