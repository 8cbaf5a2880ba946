"""Logic of the "Whole dryer" page's two run panels (no Streamlit here): a target (the input that
meets a condition on an output, `rotarydryer.services.target.run_target`) and an input schedule
(steps, ramps, a burner trip: `rotarydryer.Simulation.run_schedule`).

A case is a built-in name or an uploaded file staged by `rotarydryer.app.logic.stage_case_file`;
the target study reads a case by name or path, so an upload is written to a temporary .toml file
for the run only. Errors are ``ValueError`` s with the CLI's messages.
"""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

from .._display import to_display
from .logic import _load, case_label, case_source

__all__ = ["TARGET_INPUTS", "TARGET_OUTPUTS", "TARGET_OPERATORS", "SCHEDULE_PRESETS", "CUSTOM_CSV", "find_spec",
           "run_target_view", "preset_schedule", "run_schedule_view", "schedule_fraction"]

#: free inputs of the target panel (case keys)
TARGET_INPUTS = ["operating.feed_rate", "gas.inlet_temperature", "gas.flow", "operating.rpm",
                 "operating.feed_moisture"]
#: outputs a target may set
TARGET_OUTPUTS = ["product_moisture_kg_kg", "product_temperature_degC", "gas_outlet_temperature_degC",
                  "gas_outlet_dew_point_margin_K", "fill_fraction"]
TARGET_OPERATORS = ["=", "<=", ">="]

TRIP = "Burner trip: gas inlet to 100 degC for 10 min at 10 min"
FEED_STEP = "Feed +10 % step at 10 min"
CUSTOM_CSV = "Custom CSV upload"
SCHEDULE_PRESETS = [TRIP, FEED_STEP, CUSTOM_CSV]
#: bytes of an uploaded schedule CSV
MAX_SCHEDULE_BYTES = 200_000


def _check_thermal(case: str, overrides: dict):
    from .logic_dryer import _check_thermal as check

    c = _load(case, overrides)
    check(c, "this case")
    return c


def find_spec(key: str, lo: float | None = None, hi: float | None = None) -> str:
    """``KEY`` or ``KEY=LO,HI`` (both bounds needed; one alone is refused)."""
    if lo is None and hi is None:
        return key
    if lo is None or hi is None:
        raise ValueError(f"--find {key}: give both bounds (low and high) or neither")
    return f"{key}={lo!r},{hi!r}"


def run_target_view(case: str, overrides: dict, find: str, lo: float | None, hi: float | None, output: str,
                    op: str, value: float, tol: float | None = None) -> dict:
    """The target study: ``{"found", "text", "dict", "value", "unit", "output", "active", "find",
    "message" (the unreachable message, None when found), "notes"}``. ``overrides`` are the page's
    (the free input's own value is dropped: the study varies it)."""
    from ..services.target import run_target, unreachable_message

    if op not in TARGET_OPERATORS:
        raise ValueError(f"--such-that: operator {op!r}; use one of {', '.join(TARGET_OPERATORS)}")
    sets = {k: v for k, v in dict(overrides).items() if k != find}
    _check_thermal(case, sets)
    such_that = f"{output}{op}{float(value)!r}"
    with case_source(case) as src:
        res = run_target(src, find_spec(find, lo, hi), such_that, sets or None, tol)
    res.case = case_label(case)       # not the upload's temporary file
    return {"found": bool(res.found), "text": res.text(), "dict": res.to_dict(), "value": res.value,
            "unit": res.unit, "output": res.output, "active": res.active, "find": res.find,
            "output_name": res.output_name, "such_that": res.such_that,
            "notes": list(getattr(res, "notes", []) or []),
            "message": None if res.found else unreachable_message(res)}


def base_feed(case: str, overrides: dict) -> float:
    """The case's feed rate (kg/s wet) at ``overrides`` (the built dryer's)."""
    from ..simulation import Simulation

    c = _check_thermal(case, overrides)
    return float(Simulation(c).thermal_steady_state().dryer.feed_rate)


def preset_schedule(preset: str, case: str, overrides: dict, csv_bytes: bytes | None = None):
    """The `InputSchedule` of a preset (`SCHEDULE_PRESETS`); `CUSTOM_CSV` reads ``csv_bytes``."""
    from ..thermal.schedule import InputSchedule, load_schedule

    if preset == TRIP:
        return InputSchedule.from_events({"trip": [{"at_s": 600, "duration_s": 600, "value": 100}]}, "burner trip")
    if preset == FEED_STEP:
        feed = base_feed(case, overrides)
        return InputSchedule.from_events({"step": [{"input": "feed_rate", "at_s": 600, "value": 1.1 * feed}]},
                                         "feed step")
    if preset == CUSTOM_CSV:
        if not csv_bytes:
            raise ValueError("upload a schedule CSV (time_s and one column per input) first")
        if len(csv_bytes) > MAX_SCHEDULE_BYTES:
            raise ValueError(f"the schedule file has {len(csv_bytes)} bytes; the limit is {MAX_SCHEDULE_BYTES} bytes")
        try:
            text = bytes(csv_bytes).decode("utf-8-sig")
        except UnicodeDecodeError:
            raise ValueError("the schedule file is not UTF-8 text") from None
        with tempfile.TemporaryDirectory() as d:
            path = Path(d) / "schedule.csv"
            path.write_text(text, encoding="utf-8")
            s = load_schedule(path)
        return type(s)(s.points, "schedule.csv")        # messages name the upload, not the temporary path
    raise ValueError(f"unknown schedule preset {preset!r}; use one of {', '.join(SCHEDULE_PRESETS)}")


def schedule_fraction(message: str) -> float | None:
    """The done fraction of a ``run_schedule`` progress message ``"t = 600 / 7200 s"`` (None: other)."""
    parts = str(message).replace("=", " ").replace("/", " ").split()
    try:
        if parts[0] == "t":
            done, total = float(parts[1]), float(parts[2])
            return done / total if total > 0 else None
    except (IndexError, ValueError):
        pass
    return None


def run_schedule_view(case: str, overrides: dict, preset: str, t_end: float = 7200.0, dt: float = 60.0,
                      csv_bytes: bytes | None = None, progress=None) -> dict:
    """A scheduled run from the steady state: ``{"csv": str, "rows": long-format chart rows
    (time, quantity "moisture"/"temperature", series, value; in the display units of `rotarydryer._display`),
    "summary": ScheduleResult.summary(), "start_moisture_kg_kg", "max_moisture_kg_kg", "max_moisture_time_s",
    "final_moisture_kg_kg", "time_above_start_s", "inputs": names}``."""
    from ..simulation import Simulation

    t_end, dt = float(t_end), float(dt)
    if not (math.isfinite(t_end) and t_end >= 60.0):
        raise ValueError(f"t_end = {t_end:g} s: a run is at least 60 s")
    if not (math.isfinite(dt) and 0 < dt <= t_end):
        raise ValueError(f"dt = {dt:g} s: must be > 0 and at most t_end ({t_end:g} s)")
    if t_end / dt > 2000:
        raise ValueError(f"t_end / dt = {t_end / dt:.0f} report points; at most 2000 (lengthen dt)")
    c = _check_thermal(case, overrides)
    schedule = preset_schedule(preset, case, overrides, csv_bytes)
    res = Simulation(c).run_schedule(schedule, t_end=t_end, dt=dt, progress=progress)
    n = len(res.time_s)
    rows = []
    o = res.outlets
    for i, t in enumerate(res.time_s):       # the chart's values in the display units (_display)
        tm = to_display(t, "time")
        rows.append({"time": tm, "quantity": "moisture", "series": "product moisture",
                     "value": to_display(o["product_moisture"][i], "moisture")})
        rows.append({"time": tm, "quantity": "temperature", "series": "product",
                     "value": to_display(o["product_temperature"][i], "temperature")})
        rows.append({"time": tm, "quantity": "temperature", "series": "exhaust gas",
                     "value": to_display(o["exhaust_temperature"][i], "temperature")})
    s = res.summary()
    pm = s["product_moisture_kg_kg"]
    return {"csv": res.csv_text(), "rows": rows, "summary": s, "inputs": list(res.inputs),
            "max_moisture_kg_kg": pm["max"], "max_moisture_time_s": pm["max_time_s"],
            "start_moisture_kg_kg": pm["start"], "final_moisture_kg_kg": pm["final"],
            "time_above_start_s": res.time_above("product_moisture", pm["start"] + 1e-4),
            "points": n, "seconds": float(res.seconds)}
