"""Logic of the web app's "Control" page: closed loop on the dynamic model (``rotarydryer control``).

Plain functions (no Streamlit): the options are checked by the same function as the command line
(`rotarydryer.services.control.check_control_options`), so a bad value gives the CLI's message;
the runs are `rotarydryer.control.identify` and `rotarydryer.control.closed_loop`
(closed loop, and the uncontrolled plant for comparison).  A case is a built-in name or an
uploaded case file staged in memory (`rotarydryer.app.logic.stage_case_file`).
"""

from __future__ import annotations

import re

from ..services.control import check_control_options, run_control
from .logic import _load, png, run_warnings

__all__ = ["thermal_cases", "control_defaults", "control_view", "progress_fraction", "SCENARIO_LABELS"]

#: scenario -> what ``magnitude`` means (shown on the page)
SCENARIO_LABELS = {
    "feed_moisture_step": "relative step of the feed moisture (dry basis; +0.2 = +20 %)",
    "feed_rate_step": "relative step of the feed rate (+0.2 = +20 %)",
    "fouling_ramp": "final fouling fraction of the flights' loading capacity (ramp from the step time)",
    "none": "no disturbance (magnitude unused)",
}


def thermal_cases() -> list[str]:
    """Built-in cases with the heat-and-mass model (control needs it)."""
    from ..cases import list_cases
    from ..simulation import Simulation

    return [c for c in list_cases() if Simulation(c).thermal_enabled]


def control_defaults(case: str, overrides: dict | None = None) -> dict:
    """The case's operating point as used (feed rate kg/s, feed moisture kg/kg wet), its Ajayi
    tests (list, empty for other cases) and the chosen test."""
    c = _load(case, overrides)
    tests = [int(t.test) for t in getattr(c, "tests", [])]
    return {"tests": tests, "test": getattr(c.operating, "test", None)}


def control_view(case: str = "ajayi2011_mmg", overrides: dict | None = None, *, scenario="feed_moisture_step",
                 magnitude=0.2, duration=7200.0, step_time=None, sample_time=60.0, dead_time=120.0,
                 measured="product_moisture", setpoint=None, kc=None, tau_i=None, tau_c=None, feedforward="model",
                 feedback=True, feed_backup=True, gas_t_max=600.0, gas_t_min=None, feed_min_fraction=0.5,
                 open_loop=True, images=True, progress=None, tolerance=None, product_moisture_max=None,
                 product_temperature_band=None) -> dict:
    """Closed-loop run of a case's dynamic model under a disturbance, as ``rotarydryer control``.

    Returns ``{"closed": summary dict, "open": performance dict or None, "tuning": {...},
    "series": {...}, "time_s": [...], "ranges": {...}, "csv": text, "plot": png}``.  ``progress``:
    called with a message at each stage (steady state, each identification step, every 10 samples
    of the closed and the open loop; `progress_fraction` turns one into a fraction done)."""
    from .. import control as C
    from ..simulation import Simulation

    step_time = check_control_options(scenario, magnitude, duration, step_time, sample_time, dead_time, measured,
                                      setpoint, kc, tau_i, tau_c, feedforward, gas_t_max, gas_t_min,
                                      feed_min_fraction, tolerance, product_moisture_max, product_temperature_band)
    # every warning of the run, as the CLI prints them (the page showed the controller's own only: a case's
    # calibration range, a burner short of the loop's gas were the server log's)
    (closed, opened), notes = run_warnings(
        lambda: run_control(Simulation(_load(case, overrides)), case, scenario=scenario, magnitude=magnitude,
                            duration=duration, step_time=step_time, sample_time=sample_time, dead_time=dead_time,
                            measured=measured, setpoint=setpoint, kc=kc, tau_i=tau_i, tau_c=tau_c,
                            feedforward=feedforward, feedback=feedback, feed_backup=feed_backup, gas_t_max=gas_t_max,
                            gas_t_min=gas_t_min, feed_min_fraction=feed_min_fraction, open_loop=open_loop,
                            progress=progress, tolerance=tolerance, product_moisture_max=product_moisture_max,
                            product_temperature_band=product_temperature_band))
    s = closed.series
    out = {
        "closed": closed.summary(),
        "performance": closed.performance,
        "open": opened.performance if opened is not None else None,
        "tuning": closed.tuning,
        "setpoint": closed.setpoint,
        "measured": measured,
        "step_time_s": step_time,
        "time_s": [float(t) for t in closed.time_s],
        "series": {k: [float(v) for v in s[k]] for k in ("product_moisture_kg_kg", "product_temperature_degC",
                                                        "exhaust_temperature_degC", "gas_inlet_temperature_degC",
                                                        "feed_rate_kg_s")},
        "ranges": {"gas_inlet_temperature_degC": (float(min(s["gas_inlet_temperature_degC"])),
                                                  float(max(s["gas_inlet_temperature_degC"]))),
                   "feed_rate_kg_s": (float(min(s["feed_rate_kg_s"])), float(max(s["feed_rate_kg_s"])))},
        "warnings": notes,
        "csv": closed.csv_text(),
    }
    if images:
        fig = C.plot(closed, opened)
        fig.set_size_inches(10.5, 7.5)   # readable on a laptop screen (the CLI's figure is 8 x 10 in)
        fig.tight_layout()
        out["plot"] = png(fig)
    return out


#: identification steps of `rotarydryer.control.identify`, in their order
_ID_STEPS = ("gas_inlet_temperature", "feed_rate", "feed_moisture_dry")
_LOOP = re.compile(r"(closed|open) loop: t = ([0-9.eE+-]+) / ([0-9.eE+-]+) s")


def progress_fraction(message: str, open_loop: bool = True) -> float | None:
    """The fraction of a control run done when the run reports ``message`` (its ``progress``
    callback), from the measured shares of a 2 h MMG run (about 35 s: the steady state 1/3,
    identification 1/10, the closed loop and the open loop 1/4 each); None for a message
    that tells no stage (the feed-forward's steady states).

    >>> progress_fraction("closed loop: t = 3600 / 7200 s, product_moisture = 0.13")
    0.575
    >>> progress_fraction("open loop: t = 7200 / 7200 s, product_moisture = 0.13")
    1.0
    """
    text = str(message)
    if text.startswith("steady state"):
        return 0.0
    if text.startswith("identification: step of "):
        name = text.rsplit(" ", 1)[-1]
        return round(0.35 + 0.03 * (_ID_STEPS.index(name) if name in _ID_STEPS else 0), 4)
    m = _LOOP.match(text)
    if m is None:
        return None
    done = min(1.0, max(0.0, float(m.group(2)) / max(float(m.group(3)), 1e-9)))
    if not open_loop:
        return round(0.45 + 0.55 * done, 4)
    return round((0.45 if m.group(1) == "closed" else 0.75) + 0.25 * done, 4)
