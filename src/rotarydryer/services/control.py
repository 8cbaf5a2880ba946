"""Options and runs of ``rotarydryer control`` and of the web app's Control page (closed loop,
PI + feed-forward, on a dryer's dynamic model)."""

from __future__ import annotations

import warnings

import numpy as np

from ._options import check_option

__all__ = ["check_control_options", "run_control", "describe_feedforward"]

#: `rotarydryer.control.ControlConfig` field -> the option of ``rotarydryer control`` (and the web app) that sets it
OPTION_NAMES = {"measured": "--measured", "setpoint": "--setpoint", "sample_time_s": "--sample-time",
                "measurement_dead_time_s": "--dead-time", "kc": "--kc", "tau_i_s": "--tau-i", "tau_c_s": "--tau-c",
                "feedforward": "--feedforward", "gas_temperature_min": "--gas-t-min", "gas_temperature_max": "--gas-t-max",
                "feed_min_fraction": "--feed-min-fraction", "tolerance": "--tolerance",
                "product_moisture_max": "--product-moisture-max", "product_temperature_band": "--product-temperature-band"}


def _choose(option, value, allowed):
    if value not in allowed:
        raise ValueError(f"{option} = {value!r} is not one of {', '.join(allowed)}")
    return value


def check_control_options(scenario="feed_moisture_step", magnitude=0.2, duration=10800.0, step_time=None,
                          sample_time=60.0, dead_time=120.0, measured="product_moisture", setpoint=None, kc=None,
                          tau_i=None, tau_c=None, feedforward="model", gas_t_max=600.0, gas_t_min=None,
                          feed_min_fraction=0.5, tolerance=None, product_moisture_max=None,
                          product_temperature_band=None):
    """Check the options of ``rotarydryer control`` (``ValueError`` naming the option; the web app
    calls this too, for the same messages); returns the step time (default 600 s or the duration)."""
    from .. import control as C

    # --duration: at most C.MAX_DURATION_S (one day) and C.MAX_SAMPLES sampling intervals, the bounds of
    # C.closed_loop: a run costs ~0.1-0.25 s of wall time per interval, so 30 days ran for hours
    check_option("--duration", duration, 0.0, C.MAX_DURATION_S, unit="s", high_inclusive=True)
    # the loop's settings: their ranges live in C.ControlConfig.validate, shown here by option name
    C.ControlConfig(measured=measured, setpoint=setpoint, sample_time_s=sample_time, measurement_dead_time_s=dead_time,
                    kc=kc, tau_i_s=tau_i, tau_c_s=tau_c, feedforward=feedforward, gas_temperature_min=gas_t_min,
                    gas_temperature_max=gas_t_max, feed_min_fraction=feed_min_fraction, tolerance=tolerance,
                    product_moisture_max=product_moisture_max, product_temperature_band=product_temperature_band,
                    ).validate(names=OPTION_NAMES, check=check_option, choose=_choose)
    if duration / sample_time > C.MAX_SAMPLES:
        raise ValueError(f"--duration = {duration:g} s with --sample-time = {sample_time:g} s makes "
                         f"{duration / sample_time:.6g} sampling intervals; the limit is {C.MAX_SAMPLES} (raise "
                         f"--sample-time to at least {duration / C.MAX_SAMPLES:.3g} s or lower --duration to at most "
                         f"{C.MAX_SAMPLES * sample_time:g} s)")
    if step_time is None:
        step_time = min(600.0, duration)
    check_option("--step-time", step_time, 0.0, duration, unit="s", low_inclusive=True, high_inclusive=True)
    if sample_time > duration:
        raise ValueError(f"--sample-time = {sample_time:g} s is longer than --duration = {duration:g} s")
    _choose("--scenario", scenario, C.SCENARIOS)
    if scenario == "fouling_ramp":
        check_option("--magnitude", magnitude, 0.0, 0.95, low_inclusive=True, high_inclusive=True,
                     unit="(final fouling fraction)")
    else:
        check_option("--magnitude", magnitude, -0.9, 2.0, unit="(relative change)")
    return step_time


def parse_band(text):
    """``"45,50"`` -> (45.0, 50.0) for ``--product-temperature-band`` (None passes through)."""
    if text is None:
        return None
    parts = [p.strip() for p in str(text).split(",")]
    try:
        if len(parts) != 2:
            raise ValueError
        return float(parts[0]), float(parts[1])
    except ValueError:
        raise ValueError(f"--product-temperature-band = {text!r}: give two temperatures LOW,HIGH in degC, "
                         "e.g. 45,50") from None


#: a closed loop whose IAE exceeds this many times the open loop's (and that leaves its tolerance band) is
#: reported as worse than no control (`run_control`)
WORSE_THAN_OPEN = 2.0


def run_control(sim, case, *, scenario, magnitude, duration, step_time, sample_time, dead_time, measured, setpoint,
                kc, tau_i, tau_c, feedforward, feedback, feed_backup, gas_t_max, gas_t_min, feed_min_fraction,
                open_loop, progress=None, schedule=None, tolerance=None, product_moisture_max=None,
                product_temperature_band=None):
    """The runs of ``rotarydryer control`` (and of the web app's control page) on ``sim``, a
    `Simulation` of ``case``, with options already checked by
    `check_control_options`: steady state, FOPDT models, the closed loop and, with
    ``open_loop``, the uncontrolled plant; ``schedule`` (an
    [`InputSchedule`][rotarydryer.thermal.schedule.InputSchedule] or a .csv/.toml path) replaces the
    scenario; ``tolerance`` (the controlled variable's band, default `rotarydryer.control.TOLERANCE`),
    ``product_moisture_max`` and ``product_temperature_band``: the product's specification, reported as
    the fraction of time within it. Returns ``(closed, opened or None)``."""
    from .. import control as C

    steady = sim.dynamic_start("control", progress)
    dryer = steady.dryer
    if measured == "product_moisture" and setpoint is not None and not setpoint < dryer.feed_moisture:
        raise ValueError(f"--setpoint = {setpoint:g} kg/kg wet is at or above the feed moisture {dryer.feed_moisture:g} "
                         f"kg/kg wet: a dryer's product is drier than its feed; the allowed range is [0, "
                         f"{dryer.feed_moisture:g}) kg/kg wet")
    cfg = C.ControlConfig(measured=measured, setpoint=setpoint, sample_time_s=sample_time,
                          measurement_dead_time_s=dead_time, kc=kc, tau_i_s=tau_i, tau_c_s=tau_c,
                          feedforward=feedforward, feedback=feedback, feed_backup=feed_backup,
                          gas_temperature_min=gas_t_min, gas_temperature_max=gas_t_max,
                          feed_min_fraction=feed_min_fraction, tolerance=tolerance,
                          product_moisture_max=product_moisture_max,
                          product_temperature_band=product_temperature_band).validate()
    from ..thermal.schedule import InputSchedule, load_schedule  # the model stack: not at the CLI's start-up

    if schedule is not None and not isinstance(schedule, InputSchedule):
        schedule = load_schedule(schedule)
    kw = dict(scenario=scenario, magnitude=magnitude, t_end_s=duration, t_step_s=step_time, config=cfg,
              progress=progress, schedule=schedule)
    if schedule is None:
        try:
            C.check_scenario(dryer, scenario, magnitude, duration, step_time)
        except ValueError as exc:           # the option's name, as the other options' messages
            raise ValueError(("--" + str(exc)) if str(exc).startswith("magnitude = ") else str(exc)) from None
    else:       # the schedule's own checks before the identification runs
        C.check_schedule(dryer, schedule, duration, True)
    models = C.identify(dryer, steady, progress=progress, measured=cfg.measured)
    closed = C.closed_loop(dryer, steady, models=models, **kw)
    cycling = limit_cycle(closed)
    out_of_reach = None if cycling else setpoint_out_of_reach(closed, feed_backup)
    for message in (cycling, out_of_reach):
        if message:
            warnings.warn(message, C.ControlWarning, stacklevel=2)
    opened = C.closed_loop(dryer, steady, models=models, controlled=False, **kw) if open_loop else None
    if opened is not None:
        c_iae, o_iae = closed.performance["iae"], opened.performance["iae"]
        if c_iae > WORSE_THAN_OPEN * o_iae and closed.performance["max_abs_deviation"] > closed.performance["tolerance"]:
            warnings.warn(f"the closed loop did worse than no control (IAE {c_iae:.3g} against {o_iae:.3g} in open loop): "
                          "the process models identified at the case's point do not hold where the loop went (near a "
                          "product's moisture floor the gain to the gas temperature collapses, and the loop cycles); "
                          "a larger --tau-c detunes it, or measure the exhaust (--measured exhaust_temperature)",
                          C.ControlWarning, stacklevel=2)
    return closed, opened


#: samples at the end of a closed loop over which saturated manipulated inputs make its setpoint out of reach
SATURATED_SAMPLES = 5
#: swings of the gas inlet temperature from one limit of its range to the other that make a closed loop a limit cycle
CYCLE_SWINGS = 3


def limit_cycle(closed) -> str | None:
    """Why a closed loop's gas inlet temperature swung between the two limits of its range, where it did so at least
    CYCLE_SWINGS times (each swing from one limit to the other, samples between them not counted): the loop cycles,
    which the process models identified at the case's point do not foresee (near a product's moisture floor the
    product moisture's gain to the gas temperature collapses and its response is far from linear). None otherwise.
    A cycling loop is not a setpoint out of reach: at its end the inputs may sit at a limit between two swings."""
    s, t = closed.series, closed.tuning
    gas = np.asarray(s["gas_inlet_temperature_degC"], dtype=float)
    time = np.asarray(closed.time_s, dtype=float)
    lo, hi = (float(v) for v in t["gas_temperature_range_degC"])
    if not hi > lo or gas.size < 2:
        return None
    near = 1e-6 * max(abs(lo), abs(hi), 1.0)
    side = np.where(np.abs(gas - lo) <= near, -1, np.where(np.abs(gas - hi) <= near, 1, 0))
    at = np.flatnonzero(side != 0)
    if at.size < 2:
        return None
    change = at[1:][side[at][1:] != side[at][:-1]]         # the samples where the input reached the other limit
    if change.size < CYCLE_SWINGS:
        return None
    unit = "K" if closed.measured == "exhaust_temperature" else "kg/kg"
    return (f"the loop cycles: the gas inlet temperature swung {change.size} times between the limits of its range "
            f"({lo:.4g} and {hi:.4g} degC) from t = {time[change[0]] / 60:.0f} min, and the controlled output with it "
            f"(max |e| {closed.performance['max_abs_deviation']:.3g} {unit}); the process models identified at the case's "
            "point do not hold where the loop goes (near a product's moisture floor the gain to the gas temperature "
            "collapses): a larger --tau-c detunes the loop, a setpoint further from the floor or --measured "
            "exhaust_temperature avoids it")


def setpoint_out_of_reach(closed, feed_backup: bool) -> str | None:
    """Why a closed loop ended off its setpoint, where it did because its manipulated inputs sat at their limits
    for its last SATURATED_SAMPLES samples (the gas inlet temperature at a bound of its range and, with the feed
    backup, the feed rate at its lowest or at the case's): the setpoint is out of their reach. None otherwise
    (a run that ends within its tolerance, or still moving its inputs)."""
    perf = closed.performance
    if perf["within_tolerance"]:
        return None
    s, t = closed.series, closed.tuning
    gas = [float(v) for v in s["gas_inlet_temperature_degC"][-SATURATED_SAMPLES:]]
    feed = [float(v) for v in s["feed_rate_kg_s"][-SATURATED_SAMPLES:]]
    lo, hi = (float(v) for v in t["gas_temperature_range_degC"])
    fmin, fcase = float(t["feed_min_kg_s"]), float(s["feed_rate_kg_s"][0])
    if len(gas) < SATURATED_SAMPLES:
        return None

    def at(values, bound):
        return all(abs(v - bound) <= 1e-6 * max(abs(bound), 1.0) for v in values)
    gas_at = "upper" if at(gas, hi) else "lower" if at(gas, lo) else None
    if gas_at is None:
        return None
    why = "--gas-t-min" if gas_at == "lower" else (
        "the case's burner's hottest gas" if t.get("gas_temperature_range_note") else "--gas-t-max")
    said = [f"the gas inlet temperature sat at its {gas_at} limit, {gas[-1]:.4g} degC ({why})"]
    if feed_backup:
        if at(feed, fmin):
            said.append(f"the feed rate at its lowest, {feed[-1]:.4g} kg/s (--feed-min-fraction)")
        elif at(feed, fcase):
            said.append(f"the feed rate at the case's, {feed[-1]:.4g} kg/s")
        else:
            return None
    name = closed.measured if isinstance(closed.measured, str) else "the measured output"
    return (f"the setpoint is out of reach of the manipulated inputs: over the last {SATURATED_SAMPLES} samples "
            f"{' and '.join(said)}, and {name} ended {perf['final_deviation']:+.4g} off its setpoint "
            f"{closed.setpoint:.4g}: widen the inputs' ranges or choose a setpoint the dryer can reach")


def describe_feedforward(tuning: dict) -> str:
    """The feed-forward of a `ClosedLoopResult.tuning` in words, for the text surfaces: its kind and the delays
    of each measured disturbance on the gas range, and when the feed range acts too."""
    kind = tuning.get("feedforward", "off")
    d = tuning.get("feedforward_delays_s")
    if kind == "off" or not d:
        return f"feed-forward {kind}"
    g, b = d["gas"], d["gas_and_feed"]
    out = (f"feed-forward {kind} (delays: feed moisture {g['feed_moisture']:.0f} s, feed rate {g['feed_rate']:.0f} s "
           "on the gas range")
    if b != g:
        out += f"; {b['feed_moisture']:.0f} s and {b['feed_rate']:.0f} s when the feed range acts too"
    return out + ")"
