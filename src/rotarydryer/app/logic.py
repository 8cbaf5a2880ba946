"""Page logic of the web app: plain functions returning numbers, tables and PNG bytes.

No Streamlit here, so everything is testable directly and cacheable by the page.
Units: SI, angles in deg, speed in rev/min, as in the rest of the package.
"""

from __future__ import annotations

import io
import math

import numpy as np

__all__ = ["presets", "geometry_view", "stage_case_file", "case_defaults", "transport_view", "tracer_sources", "fit_tracer",
           "png"]


def png(fig, dpi: int = 90) -> bytes:
    """PNG bytes of a Matplotlib figure; closes it."""
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    plt.close(fig)
    return buf.getvalue()


def presets() -> dict:
    """Built-in drums (``rotarydryer.geometry.presets``): name -> entry dict."""
    from ..geometry.presets import drum_presets

    return drum_presets()


def geometry_view(radius: float, n_flights: int, s1: float, s2: float, alpha1: float, alpha2: float,
                  repose_angle: float, rpm: float, slope: float, bulk_density: float, length: float,
                  images: bool = True) -> dict:
    """Flight-unloading summary of one drum (Lee (2008) ch. 4) for the geometry page.

    Returns ``{"summary": [(quantity, value, unit)], "design_loads": [(method, m2, kg)],
    "metrics": {...}, "cross_section": png, "profile": png}``.  Raises ``ValueError``
    (naming the argument) on impossible geometry.
    """
    from ..geometry import DESIGN_LOAD_METHODS, FlightedDrum, TwoSectionFlight

    drum = FlightedDrum(radius, int(n_flights), TwoSectionFlight(s1, s2, alpha1, alpha2))
    cs = drum.cascade(repose_angle, 1.0, rpm=rpm, slope=slope)
    tr = drum.transition_angles(repose_angle)
    loads = [(m, float(drum.design_load_area(repose_angle, method=m))) for m in DESIGN_LOAD_METHODS]
    design = dict(loads)["lee2008"] * bulk_density * length
    summary = [
        ("flight-tip radius R_F (Lee (2008) Eq. 4.6)", round(drum.tip_radius, 5), "m"),
        ("flight spacing (Eq. 4.5)", round(drum.flight_spacing, 3), "deg"),
        ("full-flight holdup (Eq. 4.8)", round(drum.full_holdup_area * 1e4, 2), "cm2 per m"),
        ("transition angles psi1-psi5 (Eq. 4.9-4.13)", ", ".join(f"{float(a):.1f}" for a in tr), "deg"),
        ("discharge starts at", round(float(cs.discharge_start_angle), 2), "deg"),
        ("mean release angle (Eq. 3.3)", round(float(cs.mean_release_angle), 2), "deg"),
        ("mean fall height", round(float(cs.mean_fall_height), 4), "m"),
        ("mean fall time (active time)", round(float(cs.mean_fall_time), 4), "s"),
        ("passive time (Eq. 3.4)", round(float(cs.passive_time), 3), "s"),
    ]
    out = {
        "summary": summary,
        "design_loads": [(m, round(a, 5), round(a * bulk_density * length, 1)) for m, a in loads],
        "metrics": {"design_load_kg": design, "mean_fall_height_m": float(cs.mean_fall_height),
                    "passive_time_s": float(cs.passive_time), "mean_fall_time_s": float(cs.mean_fall_time)},
    }
    if images:
        from ..report.plots import draw_cross_section, plot_unloading_profile

        out["cross_section"] = png(draw_cross_section(drum, repose_angle, angle=90.0))
        out["profile"] = png(plot_unloading_profile(drum, repose_angle, rpm))
    return out


def stage_case_file(content: bytes) -> str:
    """Save an uploaded case file (TOML bytes) under a content-addressed name in the
    temporary directory and return its path (so results cache by content); raises
    ``ValueError`` when it is not UTF-8 TOML."""
    import hashlib
    import tempfile
    import tomllib
    from pathlib import Path

    try:
        text = content.decode("utf-8")
        tomllib.loads(text)
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise ValueError(f"not a valid UTF-8 TOML file: {exc}") from None
    d = Path(tempfile.gettempdir()) / "rotarydryer_app_cases"
    d.mkdir(exist_ok=True)
    p = d / f"case_{hashlib.sha256(content).hexdigest()[:16]}.toml"
    if not p.exists():
        p.write_text(text, encoding="utf-8")
    return str(p)


def case_defaults(case: str) -> dict:
    """Feed rate (kg/s), speed (rev/min) and slope (deg) of a built-in case, as used."""
    from ..cases import load_case

    c = load_case(case)
    op = c.operating
    feed, rpm = op.feed_rate, op.rpm
    if hasattr(c, "tests"):  # Ajayi: defaults from the chosen test
        t = next((t for t in c.tests if t.test == op.test), None)
        feed = feed if feed is not None else (t.feed_rate if t else None)
        rpm = rpm if rpm is not None else (t.rpm if t else None)
    return {"feed_rate": float(feed), "rpm": float(rpm), "slope": float(c.drum.slope)}


def transport_view(case: str, feed_rate: float, rpm: float, slope: float, images: bool = True) -> dict:
    """Solids-transport steady state + tracer RTD of a built-in case at a changed operating point
    (heat and mass transfer off: the page's plots and numbers come from one model run).

    Returns ``{"results": Results, "metrics": {...}, "holdup": png, "rtd": png,
    "loading": png}`` (the PNGs only with ``images``)."""
    from ..report.figures import plot_holdup_profile, plot_loading_state, plot_rtd
    from ..results import run_case

    res = run_case(case, {"operating.feed_rate": feed_rate, "operating.rpm": rpm, "drum.slope": slope},
                   thermal=False)
    s = res.scalars
    out = {
        "results": res,
        "metrics": {
            "total_holdup_kg": s["total_holdup_kg"],
            "mean_residence_time_min": s["mean_residence_time_s"] / 60.0,
            "rtd_std_min": s["rtd_std_s"] / 60.0,
            "cells_over": int(s["cells_over"]), "cells_design": int(s["cells_design"]),
            "cells_under": int(s["cells_under"]),
        },
    }
    if images:
        out["holdup"] = png(plot_holdup_profile(res))
        out["rtd"] = png(plot_rtd(res))
        out["loading"] = png(plot_loading_state(res))
    return out


def tracer_sources() -> list[str]:
    """Names of the published tracer curves shipped with the package."""
    from ..rtd import tracer_datasets

    return tracer_datasets()


def fit_tracer(text: str | None = None, dataset: str | None = None, model: str = "tanks_in_series",
               images: bool = True) -> dict:
    """Fit a classical RTD model (``rotarydryer.rtd.fit_tracer_data``) to a tracer CSV
    (text in the tracer-CSV format of :mod:`rotarydryer.rtd.tracer_data`) or to a shipped
    dataset.  Returns ``{"table": [(parameter, value, std_error, ci_low, ci_high)],
    "moments": {...}, "r_squared": float, "plot": png}``."""
    from ..rtd import fit_tracer_data, load_tracer_dataset, parse_tracer_text

    if (text is None) == (dataset is None):
        raise ValueError("give exactly one of text (an uploaded CSV) and dataset (a shipped curve)")
    data = parse_tracer_text(text, "uploaded CSV") if text is not None else load_tracer_dataset(dataset)
    fit = fit_tracer_data(data, model)
    d = fit.to_dict()
    table = [(k, v["value"], v["std_error"], v["ci_low"], v["ci_high"]) for k, v in d["parameters"].items()]
    out = {"table": table, "moments": d["outlet_moments"], "r_squared": d["r_squared"], "model": model,
           "published_mean_min": data.metadata.get("published_mean_min")}
    if images:
        from .._plotting import pyplot as _plt

        plt = _plt()
        fig, ax = plt.subplots(figsize=(7, 3.4), constrained_layout=True)
        t = np.asarray(data.time_s, float)
        ax.plot(t / 60, data.signal, "o", ms=3.5, color="k", label="data")
        tt = np.linspace(t.min(), t.max(), 600)
        ax.plot(tt / 60, fit.predict(tt), label=f"{model}: R2 {d['r_squared']:.3f}")
        ax.set_xlabel(f"time ({data.time_column or 's'} axis shown in min)")
        ax.set_ylabel(f"signal ({data.signal_unit})")
        ax.legend(fontsize=8)
        out["plot"] = png(fig)
    if not all(math.isfinite(r[1]) for r in table):
        raise ValueError("the fit did not converge to finite parameters")
    return out
