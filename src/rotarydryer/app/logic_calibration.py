"""Logic of the web app's "Calibration" page: case keys fitted to the measured responses of a
case's tests at once (``rotarydryer calibrate``).

Plain functions (no Streamlit): the run is `rotarydryer.services.calibration.run_calibration`,
the one the command line calls, so a bad choice gives the CLI's message; a case is a built-in
name or an uploaded case file staged in memory (`rotarydryer.app.logic.stage_case_file`).
"""

from __future__ import annotations

import re

import numpy as np

from .._io import json_text
from .._limits import key_unit
from ..services.calibration import RESPONSES, case_text, run_calibration
from .logic import _load, case_label, case_source, png

__all__ = ["MAX_PARAMETERS", "MAX_STARTS", "calibration_defaults", "calibration_view", "progress_fraction",
           "RESPONSE_LABELS"]

#: most parameters of one calibration on the page (each adds model runs to every evaluation)
MAX_PARAMETERS = 4
#: most starts of one calibration on the page (rotarydryer calibrate takes up to 100)
MAX_STARTS = 4

#: response -> label on the page
RESPONSE_LABELS = {"tracer": "tracer curves (E(t))", "mrt": "mean residence times", "holdup": "holdups",
                   "gas_outlet_temperature": "exhaust gas temperatures", "product_moisture": "product moistures",
                   "product_temperature": "product temperatures", "moisture_profile": "moisture profiles",
                   "product_d50": "product d50 (size classes)", "dust_rate": "dust rates (size classes)"}


def calibration_defaults(case: str, overrides: dict | None = None) -> dict:
    """What the page offers for a case: ``{"tests": [...], "parameters": [...]}``: the case's
    ``[[tests]]`` rows and the keys its calibration records hold (a per-test key ``tests.N.FIELD`` as
    ``tests.*.FIELD``), in the order of the records."""
    c = _load(case, overrides)
    keys: list[str] = []
    for rec in c.calibrations:
        for k in rec.values:
            k = re.sub(r"^tests\.\d+\.", "tests.*.", k)
            if k not in keys:
                keys.append(k)
    return {"tests": [int(t.test) for t in c.tests], "parameters": keys}


def _check_choice(name: str, values, limit: int) -> list:
    values = list(values or [])
    if not values:
        raise ValueError(f"{name}: choose at least one")
    if len(values) > limit:
        raise ValueError(f"{name}: {len(values)} chosen; at most {limit} on this page (rotarydryer calibrate has "
                         "no such limit)")
    return values


def calibration_view(case: str, parameters, tests=None, responses=None, starts: int = 1, overrides=None,
                     images: bool = True, progress=None) -> dict:
    """Calibrate ``parameters`` of ``case`` to the measured ``responses`` of ``tests`` (None: every
    test, every response the data have), as ``rotarydryer calibrate``.

    Returns ``{"parameters": [{key, unit, value, ci_low, ci_high}], "comparison": rows of
    `CaseCalibration.comparison`, "record_toml": str, "calibrated_case": str, "json": str,
    "objective", "n_solves", "seconds", "warnings": [...], "plot": png (model against measured)}``.
    ``progress(message)`` after each model run and each start."""
    parameters = _check_choice("parameters", parameters, MAX_PARAMETERS)
    if isinstance(starts, bool) or not float(starts).is_integer() or not 1 <= int(starts) <= MAX_STARTS:
        raise ValueError(f"starts = {starts!r} is outside the allowed range [1, {MAX_STARTS}] on this page")
    for r in responses or []:
        if r not in RESPONSES:
            raise ValueError(f"response {r!r} is not one of {', '.join(RESPONSES)}")

    def report(stage, k, n):
        if progress is not None:
            progress(f"{stage} {k}/{n}" if n else f"{stage} {k}")

    with case_source(case) as source:     # an upload as a temporary file, removed afterwards
        run = run_calibration(source, parameters, tests=list(tests) if tests else None,
                              responses=list(responses or []), base_overrides=dict(overrides or {}),
                              starts=int(starts), progress=report, source_text=case_text(source))
        data = run.to_dict()
    data["case"] = case_label(case)       # not the upload's temporary file
    cal = run.calibration
    fit = cal.fit
    rows = []
    for k in cal.keys:
        p = fit.parameters[k]
        rows.append({"key": k, "unit": key_unit(k), "value": float(p.value), "ci_low": float(p.ci_low),
                     "ci_high": float(p.ci_high)})
    out = {"parameters": rows, "comparison": cal.comparison(), "record_toml": run.record_text,
           "calibrated_case": run.calibrated_case_text, "json": json_text(data, indent=1),
           "objective": float(fit.objective), "n_solves": int(cal.n_solves), "seconds": float(cal.seconds),
           "warnings": list(fit.warnings)}
    if images:
        out["plot"] = png(_parity_figure(cal.comparison()))
    return out


def _parity_figure(rows):
    """Model against measured, one panel per response (the tracer curves as R^2 in the title)."""
    from .._plotting import pyplot

    plt = pyplot()
    points = [r for r in rows if r["response"] != "tracer"]
    by: dict[str, list] = {}
    for r in points:
        by.setdefault(r["response"], []).append(r)
    n = max(1, len(by))
    fig, axes = plt.subplots(1, n, figsize=(3.6 * n, 3.4), squeeze=False, constrained_layout=True)
    for ax, (resp, rs) in zip(axes[0], by.items()):
        x = np.array([r["measured"] for r in rs], float)
        y = np.array([r["model"] for r in rs], float)
        lo, hi = float(min(x.min(), y.min())), float(max(x.max(), y.max()))
        pad = 0.05 * (hi - lo or abs(hi) or 1.0)
        ax.plot([lo - pad, hi + pad], [lo - pad, hi + pad], "k--", lw=0.8)
        ax.plot(x, y, "o", ms=6)
        for r, xi, yi in zip(rs, x, y):
            if r["test"] is not None:
                ax.annotate(str(r["test"]), (xi, yi), textcoords="offset points", xytext=(4, 3), fontsize=7)
        unit = rs[0]["unit"]
        ax.set_title(RESPONSE_LABELS.get(resp, resp), fontsize=9)
        ax.set_xlabel(f"measured ({unit})", fontsize=8)
        ax.set_ylabel(f"model ({unit})", fontsize=8)
        ax.tick_params(labelsize=8)
        ax.grid(alpha=0.3)
    tracer = [r for r in rows if r["response"] == "tracer"]
    if tracer:
        fig.suptitle("tracer curves: " + ", ".join(f"test {r['test']} R2 {r['r_squared']:.3f}" for r in tracer),
                     fontsize=9)
    if not by:
        axes[0][0].set_axis_off()
    return fig


_STAGE = re.compile(r"(start|profile) (\d+)/(\d+)")


def progress_fraction(message: str, starts: int = 1) -> float | None:
    """The fraction of a calibration done when it reports ``message``: the starts, one by one
    (model runs inside a start leave the bar where it is: their count is not known beforehand).

    >>> progress_fraction("start 1/2"), progress_fraction("model run 7")
    (0.5, None)
    """
    m = _STAGE.match(str(message))
    if m is None or m.group(1) != "start":
        return None
    return round(min(1.0, int(m.group(2)) / max(int(m.group(3)), 1)), 4)
