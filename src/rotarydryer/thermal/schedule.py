"""Input schedules for the dynamic dryer: steps, ramps, a trip and restart of any input.

A schedule gives, for some of the dryer's inputs (`SCHEDULE_INPUTS`),
points ``(time s, value)``. Its value at time ``t`` is that of the case until the input's first
point, the points' value from then on, linear between points, held after the last; two points at
one time are a step (the value after it applies from that time on). This is the table of an FMI
co-simulation input (`fmpy.simulate_fmu(input=...)`): [`InputSchedule.signals`][rotarydryer.thermal.schedule.InputSchedule.signals]
writes it, and [`simulate_schedule`][rotarydryer.thermal.schedule.simulate_schedule] applies it as
an FMU importer does: each communication interval of ``dt`` (and each step time) holds the inputs
at its start (zero-order hold), and the integration restarts only where the inputs changed.

Files (``load_schedule``):

- CSV: a ``time_s`` column and one column per input (an empty cell: no point of that input at
  that time); a time written twice is a step.
- TOML: ``[[step]]`` (``input``, ``at_s``, ``value``), ``[[ramp]]`` (``input``, ``from_s``,
  ``to_s``, ``value`` reached at ``to_s``), ``[[trip]]`` (``input``, default the gas inlet
  temperature; ``at_s``, ``duration_s``, ``value`` during the trip, ``restart_s`` the ramp back to
  the value before the trip, 0 = a step back), ``[[point]]`` (``input``, ``at_s``, ``value``).
"""

from __future__ import annotations

import copy
import csv
import dataclasses
import math
import time
import tomllib
from pathlib import Path

import numpy as np

from .. import _jit
from .._io import check_input_file, csv_text
from .._limits import LIMITS, describe_limit
from .._validation import check_range, finite_number
from .burner import combustion_chamber, fuel_rate_for_temperature
from .settings import DryerError
from .states import DynamicResult, ThermalSteadyState, outlets

__all__ = ["SCHEDULE_INPUTS", "input_column", "InputSchedule", "load_schedule", "apply_inputs", "base_inputs", "burner_fuel_rate", "check_applicable", "outlets",
           "DryerIntegrator", "ScheduleResult", "simulate_schedule", "OUTLETS", "OUTLET_NAMES"]

#: schedulable inputs: name -> (case key whose range applies, unit, meaning)
SCHEDULE_INPUTS: dict[str, tuple[str, str, str]] = {
    "gas_inlet_temperature": ("gas.inlet_temperature", "degC", "gas temperature at the drum inlet"),
    "burner_fuel_rate": ("", "kg/s", "fuel of the case's burner (sets the gas inlet temperature)"),
    "feed_rate": ("operating.feed_rate", "kg/s", "wet solids feed"),
    "feed_moisture": ("operating.feed_moisture", "kg/kg wet", "feed moisture"),
    "rpm": ("operating.rpm", "rev/min", "drum speed"),
    "gas_flow": ("gas.flow", "kg/s", "wet gas into the drum"),
    "gas_inlet_humidity": ("gas.inlet_humidity", "kg/kg wet gas", "gas humidity at the drum inlet"),
    "feed_temperature": ("operating.feed_temperature", "degC", "solids feed temperature"),
    "fouling": ("transport.fouling", "", "fouling of the flights (heat-transfer area lost)"),
}

#: the outlet series of a scheduled run and their units
OUTLETS = {"product_moisture": "kg/kg wet", "product_temperature": "degC", "exhaust_temperature": "degC",
           "exhaust_humidity": "kg/kg dry gas", "holdup": "kg"}

#: the names of the outlet series on every surface (CSV, JSON): those of the steady-state summary
#: (`ThermalSteadyState.summary`) for the same quantities
OUTLET_NAMES = {"product_moisture": "product_moisture_kg_kg", "product_temperature": "product_temperature_degC",
                "exhaust_temperature": "gas_outlet_temperature_degC", "exhaust_humidity": "gas_outlet_humidity_kg_kg",
                "holdup": "total_holdup_kg"}

_TOML_EVENTS = ("step", "ramp", "trip", "point")


def _fuel_limit_message(name, value):
    return f"schedule {name}={value!r}: a fuel rate must be a finite number >= 0 kg/s"


@dataclasses.dataclass(frozen=True)
class InputSchedule:
    """Points ``(time_s, value)`` per input name (times non-decreasing; a repeated time is a step).
    ``source``: where it was read from (error messages)."""

    points: dict[str, tuple[tuple[float, float], ...]]
    source: str = "schedule"

    # ------------------------------------------------------------------------------------ readers
    @classmethod
    def from_csv(cls, path) -> InputSchedule:
        """Read a CSV schedule: ``time_s`` and one column per input of `SCHEDULE_INPUTS`."""
        path = Path(path)
        with path.open(newline="", encoding="utf-8-sig") as fh:      # -sig: a spreadsheet's byte-order mark
            reader = csv.reader(fh)
            # (line number in the file, cells) of every row that is not blank or a comment
            numbered = [(reader.line_num, r) for r in reader]
        numbered = [(n, r) for n, r in numbered if r and not r[0].lstrip().startswith("#")]
        rows = [r for _, r in numbered]
        if not rows:
            raise ValueError(f"{path}: empty schedule (a header time_s,<input>,... and rows are needed)")
        # an input's column as dynamics.csv names it (gas_inlet_temperature_degC) is that input: a written run
        # reads back as a schedule
        suffixed = {input_column(k): k for k in SCHEDULE_INPUTS}
        header = [h.strip() for h in rows[0]]
        header = header[:1] + [suffixed.get(h, h) for h in header[1:]]
        if not header or header[0] not in ("time_s", "time"):
            raise ValueError(f"{path}: the first column must be time_s (got {header[0] if header else ''!r})")
        if len(header) < 2:
            raise ValueError(f"{path}: the schedule names no input: give a column per scheduled input after time_s "
                             f"(of {', '.join(SCHEDULE_INPUTS)})")
        dup = sorted({h for h in header if header.count(h) > 1})
        if dup:     # the last column won
            raise ValueError(f"{path}: column {dup[0]!r} appears twice in the header; give each input one column")
        pts: dict[str, list[tuple[float, float]]] = {h: [] for h in header[1:]}
        for line, row in numbered[1:]:
            if len(row) > len(header):
                raise ValueError(f"{path} line {line}: {len(row)} cells for {len(header)} columns")
            t = _number(row[0], f"{path} line {line} time_s")
            for name, cell in zip(header[1:], row[1:]):
                if cell.strip():
                    pts[name].append((t, _number(cell, f"{path} line {line} {name}")))
        if not any(pts.values()):
            raise ValueError(f"{path}: no values under {', '.join(header[1:])}: a schedule needs rows of time_s and "
                             "the inputs' values")
        return cls({k: tuple(v) for k, v in pts.items() if v}, str(path))._checked_names()

    @classmethod
    def from_toml(cls, path) -> InputSchedule:
        """Read a TOML schedule of ``[[step]]``, ``[[ramp]]``, ``[[trip]]`` and ``[[point]]`` tables."""
        path = Path(path)
        try:
            doc = tomllib.loads(path.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise ValueError(f"{path}: not valid TOML: {exc}") from None
        return cls.from_events(doc, str(path))

    @classmethod
    def from_events(cls, doc: dict, source: str = "schedule", base: dict | None = None) -> InputSchedule:
        """A schedule from event tables (as the TOML file: ``{"step": [{...}], "trip": [...]}``).
        The value before a trip or ramp is the previous event's, or the case's (``base``, or
        resolved when the schedule is applied: a ramp or trip from the case's value)."""
        unknown = set(doc) - set(_TOML_EVENTS)
        if unknown:
            raise ValueError(f"{source}: unknown table(s) {sorted(unknown)}; use {', '.join(_TOML_EVENTS)}")
        events = []
        for kind in _TOML_EVENTS:
            if not isinstance(doc.get(kind, []), list):
                raise ValueError(f"{source}: [{kind}] must be written [[{kind}]] (an array of tables, one per event)")
            for i, ev in enumerate(doc.get(kind, [])):
                where = f"{source} [[{kind}]] #{i + 1}"
                if not isinstance(ev, dict):
                    raise ValueError(f"{where}: must be a table")
                allowed = {"step": {"input", "at_s", "value"}, "point": {"input", "at_s", "value"},
                           "ramp": {"input", "from_s", "to_s", "value"},
                           "trip": {"input", "at_s", "duration_s", "value", "restart_s"}}[kind]
                extra = set(ev) - allowed
                if extra:
                    raise ValueError(f"{where}: unknown key(s) {sorted(extra)}; use {', '.join(sorted(allowed))}")
                name = ev.get("input", "gas_inlet_temperature" if kind == "trip" else None)
                if name is None:
                    raise ValueError(f"{where}: input is required (one of {', '.join(SCHEDULE_INPUTS)})")
                need = sorted(allowed - {"input", "restart_s"} - set(ev))
                if need:
                    raise ValueError(f"{where}: missing key(s) {need}")
                t0 = _number(ev.get("at_s", ev.get("from_s")), f"{where} {'at_s' if 'at_s' in ev else 'from_s'}")
                events.append((t0, kind, name, ev, where))
        events.sort(key=lambda e: (e[0], 0 if e[1] in ("point", "step") else 1))   # a point or step before a ramp from it
        pts: dict[str, list[tuple[float, float]]] = {}
        at: dict[tuple[str, float], str] = {}       # (input, time) -> the step or point there
        for t0, kind, name, ev, where in events:
            p = pts.setdefault(name, [])
            if kind in ("step", "point"):
                if (name, t0) in at:
                    raise ValueError(f"{where}: {name} already has {at[name, t0]} at {t0:g} s: one step or point per "
                                     "input and time (the events are taken in time order, not in the file's)")
                at[name, t0] = where.split(" ", 1)[1]         # "[[step]] #1"
            value = _number(ev["value"], f"{where} value")
            before = p[-1][1] if p else (None if base is None else base.get(name))
            if p and t0 < p[-1][0]:
                raise ValueError(f"{where}: starts at {t0:g} s, before the end ({p[-1][0]:g} s) of the "
                                 f"previous event of {name}")
            if kind == "point":
                p.append((t0, value))
            elif kind == "step":
                p += _start(p, t0, before) + [(t0, value)]
            elif kind == "ramp":
                t1 = _number(ev["to_s"], f"{where} to_s")
                if t1 <= t0:
                    raise ValueError(f"{where}: to_s={t1:g} must be after from_s={t0:g}")
                p += _start(p, t0, before) + [(t1, value)]
            else:   # trip
                dur = _number(ev["duration_s"], f"{where} duration_s")
                back = _number(ev.get("restart_s", 0.0), f"{where} restart_s")
                if dur <= 0 or back < 0:
                    raise ValueError(f"{where}: duration_s={dur:g} must be > 0 and restart_s={back:g} >= 0")
                prior = math.nan if before is None else before
                p += _start(p, t0, before) + [(t0, value), (t0 + dur, value)]
                p += [(t0 + dur, prior)] if back == 0 else [(t0 + dur + back, prior)]
        return cls({k: _collapsed(v) for k, v in pts.items()}, source)._checked_names()

    def _checked_names(self) -> InputSchedule:
        for name, p in self.points.items():
            if name not in SCHEDULE_INPUTS:
                raise ValueError(f"{self.source}: unknown input {name!r}; use one of {', '.join(SCHEDULE_INPUTS)}")
            times = [t for t, _ in p]
            if any(b < a for a, b in zip(times, times[1:])):
                raise ValueError(f"{self.source}: the times of {name} must not decrease")
            if sum(1 for a, b in zip(times, times[1:]) if a == b) and any(
                    times.count(t) > 2 for t in set(times)):
                raise ValueError(f"{self.source}: {name} has more than two points at one time (one step per time)")
        if "burner_fuel_rate" in self.points and "gas_inlet_temperature" in self.points:
            raise ValueError(f"{self.source}: schedule either gas_inlet_temperature or burner_fuel_rate, not both "
                             "(the burner's fuel sets the gas inlet temperature)")
        return self

    # ------------------------------------------------------------------------------------ values
    def resolved(self, base: dict) -> InputSchedule:
        """The schedule with a ramp's or trip's 'value before' (NaN until the case is known) set to
        the case's value ``base[name]``."""
        pts = {k: tuple((t, base[k] if math.isnan(v) else v) for t, v in p) for k, p in self.points.items()}
        return InputSchedule(pts, self.source)

    def check(self, base: dict, t_end_s: float, burner: bool = True, length_option: str = "--t-end") -> InputSchedule:
        """Checked against a run: inputs the case has, times in [0, ``t_end_s``], values in their
        ranges (the case key's of `SCHEDULE_INPUTS`). Returns the resolved schedule. ``length_option``: what
        sets the run's length, named in the message of a point after its end."""
        if not burner and "burner_fuel_rate" in self.points:
            raise ValueError(f"{self.source}: burner_fuel_rate needs a case with a [burner] block; schedule "
                             "gas_inlet_temperature instead")
        s = self.resolved(base)
        for name, p in s.points.items():
            key, unit, _ = SCHEDULE_INPUTS[name]
            for t, v in p:
                if not math.isfinite(t) or t < 0 or t > t_end_s:
                    raise ValueError(f"{self.source}: {name} at time {t:g} s is outside the run's time grid "
                                     f"[0, {t_end_s:g}] s (lengthen {length_option} or drop the point)")
                if key:
                    lim = LIMITS[key]
                    low_ok = v > lim.low or (lim.low_inclusive and v == lim.low)
                    high_ok = v < lim.high or (lim.high_inclusive and v == lim.high)
                    if not (math.isfinite(v) and low_ok and high_ok):
                        raise ValueError(f"{self.source}: {name}={v:g} at {t:g} s is outside {key} "
                                         f"{describe_limit(key)}")
                elif not (math.isfinite(v) and v >= 0):
                    raise ValueError(_fuel_limit_message(name, v))
        return s

    def value_at(self, name: str, t: float, base: float, left: bool = False) -> float:
        """Value of ``name`` at ``t`` (after a step there; ``left=True``: before it)."""
        p = self.points.get(name)
        if not p:
            return float(base)
        times = np.array([q[0] for q in p])
        vals = np.array([q[1] for q in p])
        i = int(np.searchsorted(times, t, side="left" if left else "right"))   # points at or before t
        if i == 0:
            return float(base)
        if i == len(times):
            return float(vals[-1])
        t0, t1 = times[i - 1], times[i]
        if t1 == t0 or t == t1:
            return float(vals[i])
        if t == t0:
            return float(vals[i - 1])
        return float(vals[i - 1] + (vals[i] - vals[i - 1]) * (t - t0) / (t1 - t0))

    def inputs_at(self, t: float, base: dict) -> dict:
        """Every scheduled input's value at ``t`` (after a step there)."""
        return {k: self.value_at(k, t, base[k]) for k in self.points}

    def step_times(self, base: dict) -> list[float]:
        """Times > 0 where a scheduled input jumps (a repeated time, or an input's first point
        away from the case's value)."""
        out = set()
        for k, p in self.points.items():
            for t in {q[0] for q in p}:
                if t > 0 and self.value_at(k, t, base[k], left=True) != self.value_at(k, t, base[k]):
                    out.add(float(t))
        return sorted(out)

    def signals(self, base: dict, t_end_s: float):
        """The schedule as an FMI input table: a NumPy structured array with ``time`` and one
        column per scheduled input (a step: two rows at its time), for ``fmpy.simulate_fmu(input=)``. ``base``: the
        case's value of each scheduled input (an FMU's start values: `rotarydryer.fmu.start_values`)."""
        missing = [k for k in self.points if k not in base]
        if missing == ["burner_fuel_rate"]:
            raise ValueError(f"{self.source}: burner_fuel_rate is not an FMU input (the burner's fuel sets the gas "
                             "inlet temperature): schedule gas_inlet_temperature instead")
        if missing:
            raise ValueError(f"{self.source}: signals() needs the case's value of {', '.join(missing)} (scheduled) in "
                             "base, e.g. the FMU's start values: rotarydryer.fmu.start_values('dryer.fmu')")
        s = self.resolved(base)
        names = list(s.points)
        times = sorted({0.0, float(t_end_s), *(t for p in s.points.values() for t, _ in p if t <= t_end_s)})
        steps = set(s.step_times(base))
        rows = []
        for t in times:
            if t in steps:
                rows.append((t, *[s.value_at(k, t, base[k], left=True) for k in names]))
            rows.append((t, *[s.value_at(k, t, base[k]) for k in names]))
        return np.array(rows, dtype=[("time", float)] + [(k, float) for k in names])


def _collapsed(points) -> tuple:
    """Points with each run at one time reduced to its first and last (back-to-back events: the
    value before the first and after the last)."""
    out: list = []
    for q in points:
        if len(out) >= 2 and out[-1][0] == out[-2][0] == q[0]:
            out[-1] = q
        else:
            out.append(q)
    return tuple(out)


def _start(points, t0, before):
    """The point that starts an event at ``t0`` from the value ``before`` (NaN: the case's), none
    when the previous event of the input already ends there (back-to-back events)."""
    if points and points[-1][0] == t0:
        return []
    return [(t0, math.nan if before is None else before)]


def _number(text, where) -> float:
    return finite_number(text, f"{where}:")


def load_schedule(path) -> InputSchedule:
    """A schedule file: ``.csv`` or ``.toml``."""
    if not Path(path).exists():
        raise ValueError(f"--schedule {str(path)!r}: no such file")
    path = check_input_file(path, "--schedule")      # a directory, a device or an unreadable file: said so
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return InputSchedule.from_csv(path)
    if suffix == ".toml":
        return InputSchedule.from_toml(path)
    raise ValueError(f"--schedule {str(path)!r}: a schedule is a .csv or .toml file")


# ---------------------------------------------------------------------------------------------- the plant
def _recycling_state(dryer, z) -> ThermalSteadyState:
    """State ``z`` of a dryer whose burner recycles exhaust (its exhaust is the recycled gas): needed then."""
    if z is None:
        raise ValueError("burner_fuel_rate with gas.recycle_fraction: the state whose exhaust is recycled is needed")
    return ThermalSteadyState(dryer, z)


def _fuel_temperature(dryer, fuel_rate, z=None):
    """Gas inlet temperature (degC) the case's burner makes from ``fuel_rate`` kg/s with the air flows and
    ambient of ``dryer``; with exhaust recycle (``gas.recycle_fraction``), with the recycled exhaust of
    state ``z`` (the chamber balance of `ThermalSteadyState.fuel_rate_at`, inverted by Brent's method)."""
    s = dryer.settings
    b = s.burner
    if s.recycle_fraction:
        from scipy.optimize import brentq

        st = _recycling_state(dryer, z)

        def excess(t):     # fuel the temperature t needs, less the fuel given (the streams alone hotter: none;
            try:           # beyond what the combustion air burns: more than any fuel it takes)
                return st.fuel_rate_at(t) - fuel_rate
            except ValueError as exc:
                if "below the temperature" in str(exc):
                    return -fuel_rate
                if "cannot reach" in str(exc):
                    return 1e3       # kg/s: any fuel it takes is less
                raise
        hi = LIMITS["gas.inlet_temperature"].high
        try:
            if excess(hi) < 0.0:
                raise ValueError(f"burner_fuel_rate = {fuel_rate:g} kg/s heats the gas above gas.inlet_temperature's "
                                 f"limit, {hi:g} degC")
        except ValueError as exc:
            raise ValueError(f"burner_fuel_rate = {fuel_rate:g} kg/s: {' '.join(str(exc).split())}") from None
        return float(brentq(excess, -19.0, hi, xtol=1e-9))
    gas = combustion_chamber(fuel_rate, s.gas_flow * b.combustion_air_share, s.gas_flow * (1 - b.combustion_air_share),
                             air_temperature_c=s.ambient_temperature, air_humidity=dryer.hot_gas_Y, fuel=b.fuel,
                             heat_loss_fraction=b.heat_loss_fraction)
    return float(gas.temperature_c)


def burner_fuel_rate(dryer, z=None, temperature=None) -> float:
    """Fuel rate (kg/s) the case's burner needs for the dryer's gas inlet temperature (or ``temperature``, degC);
    with exhaust recycle (``gas.recycle_fraction``) the burner also heats the recycled exhaust, of state ``z``
    (needed then: `simulate`'s fuel is that of its steady state). ValueError where the burner cannot give it."""
    s = dryer.settings
    b = s.burner
    t = s.gas_inlet_temperature if temperature is None else float(temperature)
    if s.recycle_fraction:
        return _recycling_state(dryer, z).fuel_rate_at(t)
    return float(fuel_rate_for_temperature(t, s.gas_flow * b.combustion_air_share,
                                           s.gas_flow * (1 - b.combustion_air_share),
                                           air_temperature_c=s.ambient_temperature, air_humidity=dryer.hot_gas_Y,
                                           fuel=b.fuel, heat_loss_fraction=b.heat_loss_fraction))


def burner_max_temperature(dryer, z=None, low=None) -> float | None:
    """The hottest gas inlet temperature (degC) the case's burner gives (its maximum fuel rate: the burner's capacity
    or the combustion air's oxygen), at most gas.inlet_temperature's limit; with exhaust recycle, with the exhaust
    of state ``z``. None without a burner. ``low``: a temperature it gives (default the dryer's), the bisection's
    start (to 0.01 K below the limit)."""
    s = dryer.settings
    if s.burner is None:
        return None
    hi = LIMITS["gas.inlet_temperature"].high

    def gives(t):
        try:
            burner_fuel_rate(dryer, z, t)
            return True
        except ValueError:
            return False
    if gives(hi):
        return hi
    lo = s.gas_inlet_temperature if low is None else float(low)
    if not gives(lo):
        return None      # not even the given temperature (the caller's own message names it)
    while hi - lo > 0.01:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if gives(mid) else (lo, mid)
    return lo


def base_inputs(dryer, names=None, z=None) -> dict:
    """The dryer's values of the schedulable inputs ``names`` (all but the fuel when None); ``z``: the state,
    whose exhaust the burner heats with exhaust recycle (`burner_fuel_rate`)."""
    s = dryer.settings
    values = dict(gas_inlet_temperature=s.gas_inlet_temperature, feed_rate=dryer.feed_rate,
                  feed_moisture=dryer.feed_moisture, rpm=dryer.rpm, gas_flow=s.gas_flow,
                  gas_inlet_humidity=s.gas_inlet_humidity, feed_temperature=s.solids_inlet_temperature,
                  fouling=s.fouling)
    if names is not None and "burner_fuel_rate" in names and s.burner is not None:
        if s.recycle_fraction:
            _recycling_state(dryer, z)      # (its own message, not the "no fuel rate" below)
        try:
            values["burner_fuel_rate"] = burner_fuel_rate(dryer, z)
        except ValueError as exc:       # the case's own gas temperature is beyond its burner: no fuel rate to move
            raise ValueError(f"burner_fuel_rate: the case's burner has no fuel rate at its gas.inlet_temperature = "
                             f"{float(s.gas_inlet_temperature):g} degC ({' '.join(str(exc).split())}); schedule the "
                             "gas_inlet_temperature instead, or change [gas.burner] or gas.inlet_temperature") from None
    return {k: float(v) for k, v in values.items() if names is None or k in names}


_SETTING = {"gas_inlet_temperature": "gas_inlet_temperature", "gas_flow": "gas_flow",
            "gas_inlet_humidity": "gas_inlet_humidity", "feed_temperature": "solids_inlet_temperature",
            "fouling": "fouling"}


def apply_inputs(dryer, values: dict, z=None):
    """A copy of ``dryer`` with the schedulable inputs ``values`` (names of `SCHEDULE_INPUTS`); ``z``: the
    state at the change, whose exhaust a recycling burner heats (a fuel rate is converted with it)."""
    settings = copy.copy(dryer.settings)
    for k, v in values.items():
        if k in _SETTING:
            setattr(settings, _SETTING[k], float(v))
    if "burner_fuel_rate" in values:
        moved = dryer.with_parameters(settings=settings)      # the air flows and ambient of the new inputs
        settings.gas_inlet_temperature = _fuel_temperature(moved, float(values["burner_fuel_rate"]), z)
    kw = {k: float(values[k]) for k in ("feed_rate", "rpm", "feed_moisture") if k in values}
    dryer = dryer.rebuilt(settings, **kw)
    try:
        return dryer.with_parameters(settings=settings, **kw)
    except DryerError as exc:
        if "burner_fuel_rate" not in values or not str(exc).startswith("gas too cold to dry"):
            raise
        # the gas temperature is the fuel's: say so in the scheduled input's terms (a burner trip to no fuel
        # leaves air at the ambient, which this model cannot take: it needs a gas that heats the solids)
        raise DryerError(f"burner_fuel_rate = {float(values['burner_fuel_rate']):g} kg/s heats the gas to "
                         f"{settings.gas_inlet_temperature:.4g} degC only, too cold to dry (the feed enters at "
                         f"{settings.solids_inlet_temperature:.4g} degC, or the gas is saturated): the model needs a gas "
                         "that heats the solids, so a full trip is beyond it; schedule a fuel rate that keeps the gas "
                         "above the feed, or a gas_inlet_temperature trip", reason=exc.reason) from None


def check_applicable(dryer, schedule: InputSchedule, z=None) -> None:
    """Every point of a (resolved) ``schedule`` applied alone to ``dryer`` (the case's and the
    material's checks, e.g. a feed wetter than the material's laws allow), before a run starts:
    the error names the schedule, the input, the value and its time. ``z``: the start state (a
    recycling burner's fuel rate is checked with its exhaust)."""
    for name, p in schedule.points.items():
        for t, v in sorted(set(p)):
            try:
                apply_inputs(dryer, {name: v}, z)
            except ValueError as exc:
                raise ValueError(f"{schedule.source}: {name}={v:g} at {t:g} s: {' '.join(str(exc).split())}") from None


# ---------------------------------------------------------------------------------------------- integration
class DryerIntegrator:
    """BDF integration of a dryer advanced from one communication point to the next.

    One BDF solver (`scipy.integrate.BDF`) runs the whole time. `advance` steps it past the point
    and interpolates there (its dense output, as ``solve_ivp`` with ``t_eval``), or with
    ``land=True`` cuts its last step to land on the point (a sampled controller, which changes an
    input at almost every sample). `restart` hands it a dryer with new inputs at the current
    point: a step that passed the point is taken again from where it started, cut to land there
    (the part beyond belonged to the old inputs), and the solver carries on with its order, step
    size, backward differences and Jacobian. The solution has a kink at the point (its derivative
    jumps by f_new - f_old), so the first backward difference takes the jump: the history reads as
    the old solution plus the ramp (t - t_k) (f_new - f_old), whose interpolant has the new
    inputs' slope at t_k and the old solution's curvature; the error control does the rest. A step
    taken again is the step landing ahead would have taken: the run carries on from the same state
    whether the caller knew of the change in advance or not (an FMU's master).

    Measured on a 2 h closed loop of MMG Test 4 (`benchmarks/bench_issue32_control.py`), against a
    restart at order 1 with the backward differences dropped: 1.5x less CPU, and a result 4x
    closer to the same loop integrated at rtol 1e-8 (product moisture 5.8e-6 against
    2.2e-5 kg/kg). A new solver per input change (a `solve_ivp` per sample) paid each time for an
    initial-step search, tiny first steps and a new Jacobian. The shell-loss
    coefficient is lagged as in [`ThermalDryer.simulate`][rotarydryer.thermal.dryer.ThermalDryer.simulate],
    and refreshed at each input change. ``restarts``: solvers started (1 per run); ``changes``:
    input changes taken over; ``nfev``: residuals (the solver's and the kinks')."""

    def __init__(self, dryer, z0, t0=0.0, rtol=1e-5, atol=None, shell_refresh=60.0):
        _jit.long_runs()        # an integration: thousands of residuals, the compiled kernels pay
        self.rtol, self.atol, self.shell_refresh = rtol, atol, shell_refresh
        self.t = float(t0)
        self.z = np.asarray(z0, float).copy()
        self.nfev = 0
        self.restarts = 0
        self.changes = 0
        self._solver = None
        self._refreshed = self.t
        self._kink_fev = 0
        self._last = None
        self.dryer = dryer

    def restart(self, dryer):
        """Carry on from the current state with ``dryer`` (new inputs, the same network)."""
        sol = self._solver
        if sol is not None and sol.t > self.t:      # the last step passed the point: again, landing on it
            self._restore()
            self._step_to(self.t)
            self.z = sol.y.copy()
        z = self.z[:, None]
        f_old = self.dryer.rhs(self.t, z)[:, 0] if sol is not None else None
        self.dryer.unfreeze_shell()
        self.dryer = dryer
        self.changes += 1
        if sol is None:
            return
        dryer.freeze_shell(self.z)
        self._refreshed = self.t
        f_new = dryer.rhs(self.t, z)[:, 0]
        self._kink_fev += 2
        # D[1] = y_n - y_(n-1) takes the jump of the derivative, h (f_new - f_old); the higher backward
        # differences are a ramp's, zero
        sol.D[1] += (f_new - f_old) * (sol.h_abs * sol.direction)
        sol.t_old = None

    def _snapshot(self):
        """What a step changes: the solver's state and the lagged shell loss (restored by `_restore`)."""
        sol = self._solver
        self._last = (sol.t, sol.y, sol.D.copy(), sol.order, sol.h_abs, sol.n_equal_steps, sol.LU, sol.J,
                      None if sol.jac_factor is None else sol.jac_factor.copy(), self._refreshed,
                      self.dryer._shell_ua)

    def _restore(self):
        sol = self._solver
        (sol.t, sol.y, D, sol.order, sol.h_abs, sol.n_equal_steps, sol.LU, sol.J, sol.jac_factor,
         self._refreshed, self.dryer._shell_ua) = self._last
        sol.D[:] = D
        sol.t_old = None

    def _step_to(self, t_next, land=True):
        """Step the solver until it reaches ``t_next`` (``land``: its last step cut to end there)."""
        sol = self._solver
        sol.t_bound, sol.status = (float(t_next) if land else np.inf), "running"
        while sol.t < t_next:
            self._snapshot()
            msg = sol.step()
            if sol.status == "failed":
                self.close()
                raise DryerError(f"dynamic integration failed at t = {sol.t:.6g} s: {msg}", reason="integration",
                                 state=self.z)

    def _fun(self, t, z):
        # vectorized: z (n, k); k = 1 except in the Jacobian's batch of perturbations
        d = self.dryer
        if z.shape[1] == 1 and abs(t - self._refreshed) > self.shell_refresh:
            d.freeze_shell(z[:, 0])
            self._refreshed = t
        return d.rhs(t, z)

    def _start(self):
        from scipy.integrate import BDF

        d = self.dryer
        atol = d._scale() * 1e-7 if self.atol is None else self.atol
        d.freeze_shell(self.z)
        self._refreshed = self.t
        self._solver = BDF(self._fun, self.t, self.z, np.inf, rtol=self.rtol, atol=atol,
                           jac_sparsity=d.sparsity(), vectorized=True)
        self.restarts += 1

    def advance(self, t_next: float, land: bool = False) -> np.ndarray:
        """The state at ``t_next`` (> the current time); ``land``: the solver's last step ends there."""
        if t_next <= self.t:
            return self.z
        if self._solver is None:
            self._start()
        sol = self._solver
        self._step_to(t_next, land)
        self.nfev = sol.nfev + self._kink_fev
        self.z = sol.y.copy() if sol.t == t_next else sol.dense_output()(t_next)
        self.t = float(t_next)
        return self.z

    def close(self):
        self.dryer.unfreeze_shell()
        self._solver = None


@dataclasses.dataclass
class ScheduleResult:
    """A scheduled dynamic run: ``time_s`` (communication points), ``states`` (n x points),
    ``inputs`` (name -> value held over the interval starting at each point; the last point repeats
    the last interval's), ``outlets`` (name of `OUTLETS` -> series), ``restarts`` (integrations
    started: 1, `DryerIntegrator`), ``seconds`` (wall time), ``changes`` (input changes)."""

    time_s: np.ndarray
    states: np.ndarray
    inputs: dict
    outlets: dict
    restarts: int
    seconds: float
    dryer: object = None
    changes: int = 0
    #: the dryer of the last interval's inputs (the one the final state belongs to)
    final_dryer: object = None

    def dynamic_result(self) -> DynamicResult:
        """As a [`DynamicResult`][rotarydryer.thermal.states.DynamicResult] on the base dryer."""
        return DynamicResult(self.dryer, self.time_s, self.states, self.seconds, 0)

    def columns(self) -> dict:
        """Series with unit-suffixed names (CSV columns)."""
        cols = {"time_s": self.time_s}
        for k, v in self.inputs.items():
            cols[input_column(k)] = v
        for k, v in self.outlets.items():
            cols[OUTLET_NAMES[k]] = v
        return cols

    def csv_text(self) -> str:
        """[`columns`][rotarydryer.thermal.schedule.ScheduleResult.columns] as CSV text, a row per point."""
        cols = self.columns()
        return csv_text([{k: float(v[i]) for k, v in cols.items()} for i in range(self.time_s.size)])

    def summary(self) -> dict:
        """Start, final, minimum and maximum (with its time) of every outlet series (unit-suffixed names)."""
        out = {}
        for k, v in self.outlets.items():
            name = OUTLET_NAMES[k]
            i, j = int(np.argmin(v)), int(np.argmax(v))
            out[name] = dict(start=float(v[0]), final=float(v[-1]), min=float(v[i]), min_time_s=float(self.time_s[i]),
                             max=float(v[j]), max_time_s=float(self.time_s[j]))
        return out

    def time_above(self, outlet: str, threshold: float) -> float:
        """Time (s) with ``outlet`` above ``threshold``, from the series linearly interpolated."""
        t, y = self.time_s, self.outlets[outlet] - threshold
        total = 0.0
        for a, b, ya, yb in zip(t[:-1], t[1:], y[:-1], y[1:]):
            if ya > 0 and yb > 0:
                total += b - a
            elif ya > 0 or yb > 0:
                total += (b - a) * max(ya, yb) / abs(yb - ya)
        return float(total)


def _suffix(unit: str) -> str:
    return {"degC": "degC", "kg/s": "kg_s", "kg/kg wet": "kg_kg", "kg/kg wet gas": "kg_kg", "rev/min": "rpm",
            "": ""}[unit]


def input_column(name: str) -> str:
    """The column of a schedulable input in the files (``gas_inlet_temperature_degC``): its name with its unit."""
    return f"{name}_{_suffix(SCHEDULE_INPUTS[name][1])}".rstrip("_")


def simulate_schedule(dryer, z0, schedule: InputSchedule | None, t_end_s: float, dt_s: float = 60.0,
                      rtol: float = 1e-5, progress=None) -> ScheduleResult:
    """Run ``dryer`` from state ``z0`` for ``t_end_s`` s under ``schedule`` (None: the dryer's own
    inputs), reporting every ``dt_s`` s and at each step of an input. Each interval holds the
    inputs at its start (FMI co-simulation semantics); the integration carries on across intervals
    whose inputs did not change. ``progress(done_s, total_s)`` is called after each point."""
    t_end_s = float(check_range("--t-end", t_end_s, 0.0, 30 * 86400.0, low_inclusive=False, unit="s"))
    dt_s = float(check_range("--dt", dt_s, 0.0, t_end_s, low_inclusive=False, unit="s"))
    if t_end_s / dt_s > 100000:
        raise ValueError(f"--dt {dt_s:g} s: {t_end_s / dt_s:.0f} points in {t_end_s:g} s, at most 100000")
    t_start = time.perf_counter()
    schedule = schedule or InputSchedule({})
    names = list(schedule.points)
    base = base_inputs(dryer, names + ["burner_fuel_rate"] if "burner_fuel_rate" in names else None, z0)
    schedule = schedule.check(base, t_end_s, burner=dryer.settings.burner is not None)
    check_applicable(dryer, schedule, z0)
    n = int(math.floor(t_end_s / dt_s + 1e-9))
    grid = sorted({*(k * dt_s for k in range(n + 1) if k * dt_s < t_end_s), t_end_s, *schedule.step_times(base)})
    integ = DryerIntegrator(dryer, z0, rtol=rtol)
    applied = {k: base[k] for k in names}      # the dryer's own values: no restart until one changes
    states = [np.asarray(z0, float).copy()]
    held: dict[str, list[float]] = {k: [] for k in names}
    outs = {k: [v] for k, v in outlets(dryer, z0).items()}
    try:
        for t0, t1 in zip(grid[:-1], grid[1:]):
            u = schedule.inputs_at(t0, base)
            if u != applied:
                try:
                    moved = apply_inputs(dryer, u, integ.z) if u else dryer
                except ValueError as exc:   # inputs that pass one by one (check_applicable) but not together
                    what = ", ".join(f"{k}={v:g}" for k, v in u.items() if v != base[k]) or "the case's inputs"
                    raise ValueError(f"{schedule.source}: {what} at {t0:g} s: {' '.join(str(exc).split())}") from None
                integ.restart(moved)
                applied = u
            for k in names:
                held[k].append(u[k])
            z = integ.advance(t1)
            states.append(z.copy())
            for k, v in outlets(integ.dryer, z).items():
                outs[k].append(v)
            if progress:
                progress(t1, t_end_s)
    finally:
        integ.close()
    for k in names:
        held[k].append(held[k][-1] if held[k] else base[k])
    return ScheduleResult(np.array(grid), np.column_stack(states), {k: np.array(v) for k, v in held.items()},
                          {k: np.array(v) for k, v in outs.items()}, integ.restarts, time.perf_counter() - t_start,
                          dryer, integ.changes, integ.dryer)
