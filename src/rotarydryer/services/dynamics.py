"""Runs of ``rotarydryer dynamics`` (and of any front end driving the dynamic dryer with an input
schedule): the case's steady state, then
[`simulate_schedule`][rotarydryer.thermal.schedule.simulate_schedule]."""

from __future__ import annotations

import math

from ._options import check_option

__all__ = ["run_dynamics", "parse_above", "dynamics_summary"]

#: longest run, s (30 days), and most reporting points of one run
MAX_T_END_S = 30 * 86400.0
MAX_POINTS = 100000


def parse_above(text: str | None):
    """``--above OUTLET=VALUE`` (e.g. ``product_moisture=0.13``) -> (outlet, value) or None."""
    if not text:
        return None
    name, sep, value = text.partition("=")
    from ..thermal.schedule import OUTLET_NAMES, OUTLETS  # the model stack: not at the CLI's start-up

    # the names the command prints (gas_outlet_temperature_degC, total_holdup_kg) or the short ones
    by_printed = {v: k for k, v in OUTLET_NAMES.items()}
    name = name.strip()
    name = by_printed.get(name, name.removesuffix("_kg_kg").removesuffix("_degC").removesuffix("_kg"))
    if not sep or name not in OUTLETS:
        raise ValueError(f"--above {text!r}: write OUTLET=VALUE with OUTLET one of "
                         f"{', '.join(OUTLET_NAMES.values())} (or {', '.join(OUTLETS)})")
    try:
        v = float(value)
    except ValueError:
        raise ValueError(f"--above {text!r}: {value.strip()!r} is not a number") from None
    if not math.isfinite(v):
        raise ValueError(f"--above {text!r}: the value must be finite")
    return name, v


def run_dynamics(sim, schedule=None, *, t_end: float = 7200.0, dt: float = 60.0, progress=None):
    """The dynamic response of ``sim`` (a [`Simulation`][rotarydryer.simulation.Simulation] with a gas) from
    its coupled steady state under ``schedule`` (an [`InputSchedule`][rotarydryer.thermal.schedule.InputSchedule],
    a .csv/.toml path, or None for the case's own inputs), reported every ``dt`` s for ``t_end``
    s. Returns the [`ScheduleResult`][rotarydryer.thermal.schedule.ScheduleResult]."""
    check_option("--t-end", t_end, 0.0, MAX_T_END_S, unit="s", high_inclusive=True)
    check_option("--dt", dt, 0.0, t_end, unit="s", high_inclusive=True)
    if t_end / dt > MAX_POINTS:
        raise ValueError(f"--t-end {t_end:g} s with --dt {dt:g} s makes {t_end / dt:.0f} points; at most "
                         f"{MAX_POINTS} (raise --dt to at least {t_end / MAX_POINTS:.3g} s)")
    return sim.run_schedule(schedule, t_end=t_end, dt=dt, progress=progress)


def dynamics_summary(result, case: str, above=None) -> dict:
    """The JSON summary of a run: the scheduled inputs, every outlet's start, final, minimum and
    maximum, the run's cost and, with ``above`` = (outlet, value), the time above that value."""
    out = dict(case=case, t_end_s=float(result.time_s[-1]), points=int(result.time_s.size),
               scheduled_inputs=sorted(result.inputs), integrations=result.restarts, input_changes=result.changes,
               seconds=round(result.seconds, 3), outlets=result.summary())
    if above is not None:
        name, value = above
        out["time_above"] = dict(outlet=name, threshold=value, seconds=result.time_above(name, value))
    return out
