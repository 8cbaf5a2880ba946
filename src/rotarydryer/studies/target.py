"""Targets (issue 31 item 1): the value of one case input that meets a condition on one output.

"What feed rate can my dryer take before the product is too wet?"

>>> from rotarydryer.studies.target import target
>>> res = target("ajayi2011_mmg", "operating.feed_rate", "product_moisture_kg_kg<=0.12")  # doctest: +SKIP
>>> round(res.value, 1), res.active                                                    # doctest: +SKIP
(29.8, 'target met with equality')

One free input (a numeric case key, e.g. ``operating.feed_rate``, ``gas.inlet_temperature``,
``gas.flow``, ``operating.rpm``) is varied in ``bounds = (lo, hi)``; every evaluation is the
steady state ``Simulation(case, {**overrides, key: x}).steady_state().summary()[output]``, started
from the previous evaluation's state and on its heat-and-mass model where only parameter values
change (as `rotarydryer.simulation.Simulation.sweep`).

The condition is on one output of `summary`:

- ``output = value``: the input where the output equals the value (Brent's method,
  `scipy.optimize.brentq`, on the sign change between the bounds); no sign change is
  "no solution in [lo, hi]".
- ``output <= value`` or ``output >= value``: the extreme input of the bounds that still meets it,
  the end of the part of ``[lo, hi]`` that meets it toward which the output approaches the value
  (e.g. the largest feed rate whose product moisture is at most 0.12, the lowest inlet temperature
  that still dries to 0.12). The output is assumed to cross the value at most once in the bounds
  (monotone over the bracket): when it crosses, the answer is the crossing (the same root as the
  equality); when the whole bracket meets it, the bound on the side of the larger (``<=``) or smaller
  (``>=``) output binds; when neither bound meets it, there is no solution, and the result names the
  bound that comes closest.

A steady state that fails at a bound (infeasible fill, no coupled steady state) moves that bound
toward the other one (at most `SHRINK_STEPS` times, halving the distance, then `BISECT_STEPS`
bisections back toward the failed bound, so that little of the bracket is given away), and the result
says so in ``notes``; a failure inside the bracket during the root search is an error naming the
input value and the reason. The output tolerance ``tol`` (absolute, in the output's unit) ends
the search when ``|output - value| <= tol``.
"""

from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq, minimize

from .._display import UNIT_QUANTITIES, UNITS, quantity_of, show_output, unit_of
from .._limits import LIMITS
from .._validation import finite_number, fmt_number
from ..cases import discrete_kind, load_case, valid_override_keys
from ..cases.build import test_row
from ..simulation import Simulation

__all__ = ["target", "TargetResult", "solve_targets", "optimum", "TargetSetResult", "TargetError", "parse_such_that", "parse_find", "default_bounds", "check_bounds",
           "OPERATORS", "SHRINK_STEPS", "BISECT_STEPS", "DEFAULT_SPAN"]

#: the conditions a target may put on its output
OPERATORS = ("=", "<=", ">=")
#: halvings of the distance to the other bound tried when the steady state fails at a bound
SHRINK_STEPS = 5
#: bisections between the first point that solves and the last that does not, after a failed bound (`_usable_end`)
BISECT_STEPS = 6
#: default bracket around the case's value: (lo factor, hi factor)
DEFAULT_SPAN = (0.25, 4.0)
#: most steady states of one target (bounds, shrinking and the root search) or one Newton solve
MAX_EVALUATIONS = 80
#: most steady states of one SLSQP optimum (finite-difference gradients: about n + 2 per iteration)
OPTIMUM_EVALUATIONS = 300

class TargetError(ValueError):
    """A target that cannot be answered: ``reason`` ``"no_steady_state"`` (a steady state failed
    inside the bounds: the solver's answer, exit code 1) or ``"unreachable"`` / ``"bad_input"``
    (exit code 2)."""

    def __init__(self, message, reason="bad_input"):
        super().__init__(message)
        self.reason = reason


_LABELS = {"find": "find", "such_that": "such_that", "bounds": "bounds", "objective": "objective"}
_SUCH_THAT = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*(<=|>=|==|=)\s*(\S.*?)\s*$")


@dataclass
class TargetResult:
    """A target's answer.

    ``value``: the input (``find``, in its SI unit) that meets the condition (None without a
    solution); ``output``: the output there; ``active``: ``"target met with equality"``,
    ``"bound lo binds"`` / ``"bound hi binds"`` (the whole bracket meets an inequality) or
    ``"no solution in [lo, hi]"``; ``outputs_at_bounds``: the output at ``lo`` and ``hi`` (after
    any shrinking, ``bounds``); ``points``: every evaluation ``(input, output or None, error)``.
    """

    case: str
    find: str
    output_name: str
    operator: str
    target_value: float
    bounds: tuple
    value: float | None
    output: float | None
    active: str
    evaluations: int
    outputs_at_bounds: dict
    tol: float
    closest: str | None = None
    unit: str = ""
    notes: list = field(default_factory=list)
    points: list = field(default_factory=list)

    @property
    def found(self) -> bool:
        """Does a value of the input meet the condition?"""
        return self.value is not None

    @property
    def such_that(self) -> str:
        """The condition as written on the command line, e.g. ``product_moisture_kg_kg<=0.12``."""
        return f"{self.output_name}{self.operator}{fmt_number(self.target_value)}"

    def to_dict(self) -> dict:
        """One JSON-ready object: the input under its case key, the output under its name (with its
        unit suffix), the bounds and the outputs there."""
        lo, hi = self.bounds
        return {"case": self.case, "find": self.find, "unit": self.unit, "such_that": self.such_that,
                self.find: self.value, self.output_name: self.output, "active": self.active,
                "found": self.found, "closest_bound": self.closest, "evaluations": self.evaluations,
                "tol": self.tol, "bounds": [lo, hi],
                "outputs_at_bounds": {"lo": {self.find: lo, self.output_name: self.outputs_at_bounds["lo"]},
                                      "hi": {self.find: hi, self.output_name: self.outputs_at_bounds["hi"]}},
                "notes": list(self.notes)}

    def text(self) -> str:
        """Plain text of the answer, a line each (the input in the display unit of its quantity where ``--units``
        chose another than the key's own)."""
        num, u = _key_shown(self.unit)
        lo, hi = self.bounds
        ylo, yhi = self.outputs_at_bounds["lo"], self.outputs_at_bounds["hi"]
        lines = [f"target of {self.case}: {self.find} such that {self.such_that}",
                 f"bounds: [{num(lo)}, {num(hi)}]{u}; {self.output_name} = {_shown(ylo, self.output_name)} at lo, "
                 f"{_shown(yhi, self.output_name)} at hi"]
        if self.found:
            lines.append(f"{self.find} = {num(self.value)}{u} ({self.active}); "
                         f"{self.output_name} = {_shown(self.output, self.output_name)}")
        else:
            lines.append(f"{self.active}: {self.output_name} {self.operator} {fmt_number(self.target_value)} "
                         f"is met nowhere; bound {self.closest} comes closest ({self.output_name} = "
                         f"{_shown(self.outputs_at_bounds[self.closest], self.output_name)})")
        lines += [f"note: {n}" for n in self.notes]
        lines.append(f"{self.evaluations} steady states")
        return "\n".join(lines)


def _key_shown(unit: str):
    """(number formatter, " unit") of a case key's values in text: the key's own unit and `fmt_number`, or, where
    ``--units`` shows the key's quantity in another unit (``temperature=degF``), that unit (6 figures)."""
    q, f = UNIT_QUANTITIES.get(unit or "", (None, 1.0))
    if q is None or unit_of(q) == unit:
        return fmt_number, (f" {unit}" if unit else "")
    scale, offset = UNITS[q][unit_of(q)]
    return (lambda v: fmt_number(float(v) * f * scale + offset)), f" {unit_of(q)}"


#: absolute floor of the default output tolerance by quantity (SI, the output names' units): a target of
#: 0 (a dew-point margin of 0 K, 0 degC) is met within these; elsewhere 1e-4 of the value is larger
ABSOLUTE_TOL = {"temperature": 1e-3, "temperature_difference": 1e-3, "moisture": 1e-7, "humidity": 1e-7,
                "mass_flow": 1e-6, "fuel_flow": 1e-7, "mass": 1e-3, "power": 1.0, "time": 1e-2, "length": 1e-6,
                "specific_energy": 1.0}
#: the floor of a dimensionless output (a fraction, an efficiency)
ABSOLUTE_TOL_DIMENSIONLESS = 1e-9


def default_tol(name: str, value: float) -> float:
    """The default tolerance of a target ``name = value``: ``1e-4 * |value|``, at least the absolute
    floor of the output's quantity (`ABSOLUTE_TOL`, by its unit suffix)."""
    q = quantity_of(name)
    floor = ABSOLUTE_TOL_DIMENSIONLESS if q is None else ABSOLUTE_TOL.get(q[0], ABSOLUTE_TOL_DIMENSIONLESS) / q[1]
    return max(1e-4 * abs(float(value)), floor)


def _shown(y, name: str | None = None) -> str:
    """An output's value as named (SI, by its unit suffix) and, where the display unit of its quantity
    differs, in that unit too: ``0.12 (12 %)``."""
    if y is None:
        return "n/a"
    text = fmt_number(y)
    q = quantity_of(name) if name else None
    if q is not None and (q[1] != 1.0 or UNITS[q[0]][unit_of(q[0])] != (1.0, 0.0)):
        text += f" ({show_output(name, y)})"
    return text


def parse_such_that(text, label: str = "such_that") -> tuple[str, str, float]:
    """``"product_moisture_kg_kg<=0.12"`` -> ``("product_moisture_kg_kg", "<=", 0.12)`` (``==`` is
    ``=``); a tuple ``(name, op, value)`` passes checked. ``ValueError`` naming ``label``."""
    form = "expected OUTPUT=VALUE, OUTPUT<=VALUE or OUTPUT>=VALUE, e.g. product_moisture_kg_kg<=0.12"
    if isinstance(text, (tuple, list)):
        if len(text) != 3:
            raise ValueError(f"{label} = {text!r}: {form}")
        name, op, value = text
    else:
        m = _SUCH_THAT.match(str(text))
        if m is None:
            raise ValueError(f"{label} = {str(text)!r}: {form}")
        name, op, value = m.groups()
    op = "=" if op == "==" else op
    if op not in OPERATORS:
        raise ValueError(f"{label} = {text!r}: the operator {op!r} is not one of {', '.join(OPERATORS)}")
    v = finite_number(value, f"{label} = {str(text)!r}: the value", f"; {form}")
    floor = next((f for suffix, f in _OUTPUT_FLOORS if str(name).endswith(suffix)), None)
    if floor is not None and op in ("=", "<=") and v < floor[0]:
        # no run can reach it: refused before the search (it solved five steady states, then "not reached"; found by
        # review)
        raise ValueError(f"{label} = {str(text)!r}: {name} {op} {fmt_number(v)} cannot be met, {floor[1]}; give a "
                         f"value of at least {fmt_number(floor[0])}")
    return str(name), op, v


#: (output name suffix, (lowest value any run can give, why)) of `parse_such_that`'s up-front check
_OUTPUT_FLOORS = (("_kg_kg", (0.0, "a moisture or humidity is never negative")),
                  ("_kg_s", (0.0, "a flow is never negative")), ("_kg", (0.0, "a mass is never negative")),
                  ("_s", (0.0, "a time is never negative")), ("_degC", (-273.15, "below absolute zero")))


def parse_find(text, label: str = "find") -> tuple[str, tuple | None]:
    """``"operating.feed_rate=20,40"`` -> ``("operating.feed_rate", (20.0, 40.0))``;
    ``"operating.feed_rate"`` -> ``(key, None)`` (the default bracket). ``ValueError`` naming ``label``."""
    form = "expected KEY or KEY=LO,HI, e.g. operating.feed_rate=10,60"
    key, eq, rest = str(text).partition("=")
    key = key.strip()
    if not key or " " in key:
        raise ValueError(f"{label} = {str(text)!r}: {form}")
    if not eq:
        return key, None
    parts = [p.strip() for p in rest.split(",")]
    if len(parts) != 2:
        raise ValueError(f"{label} = {str(text)!r}: {form}")
    try:
        lo, hi = float(parts[0]), float(parts[1])
    except ValueError:
        raise ValueError(f"{label} = {str(text)!r}: the bounds {rest.strip()!r} are not two numbers; {form}") from None
    return key, (lo, hi)


def _limit_text(key) -> str:
    lim = LIMITS[key]
    u = f" {lim.unit}" if lim.unit else ""
    return f"{'[' if lim.low_inclusive else '('}{fmt_number(lim.low)}, {fmt_number(lim.high)}" \
           f"{']' if lim.high_inclusive else ')'}{u}"


def check_bounds(key: str, bounds, label: str = "find") -> tuple[float, float]:
    """``(lo, hi)`` of ``key`` as floats: finite, ``lo < hi``, both inside the key's schema limit
    (`rotarydryer._limits.LIMITS`, where declared); else ``ValueError`` naming ``label``,
    the values and the allowed range."""
    try:
        lo, hi = (float(b) for b in bounds)
    except (TypeError, ValueError):
        raise ValueError(f"{label} {key}: bounds {bounds!r} are not two numbers (LO, HI)") from None
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ValueError(f"{label} {key}={fmt_number(lo)},{fmt_number(hi)}: the bounds are not finite numbers")
    if lo >= hi:
        where = f" (allowed range {_limit_text(key)})" if key in LIMITS else ""
        raise ValueError(f"{label} {key}={fmt_number(lo)},{fmt_number(hi)}: need LO < HI{where}")
    lim = LIMITS.get(key)
    if lim is not None:
        for name, v in (("LO", lo), ("HI", hi)):
            ok = (v >= lim.low if lim.low_inclusive else v > lim.low) and \
                 (v <= lim.high if lim.high_inclusive else v < lim.high)
            if not ok:
                raise ValueError(f"{label} {key}={fmt_number(lo)},{fmt_number(hi)}: {name} = {fmt_number(v)} "
                                 f"is outside the allowed range {_limit_text(key)}")
    return lo, hi


def case_value(case, key: str):
    """The value of case key ``key`` in the validated ``case`` (the selected [[tests]] row's where
    the case takes it from there: feed rate, speed, gas flow and inlet temperature), or None."""
    node = case
    for part in key.split("."):
        node = getattr(node, part, None)
        if node is None:
            break
    section, _, fld = key.rpartition(".")
    row = test_row(case) if getattr(getattr(case, "operating", None), "test", None) is not None else None
    if row is not None:
        from_row = getattr(row, fld, None)
        if from_row is None and section:
            from_row = getattr(row, f"{section.split('.')[-1]}_{fld}", None)
        if from_row is not None and (node is None or section == "gas"):
            node = from_row           # the row's gas flow and inlet temperature replace the case's
    if isinstance(node, bool) or not isinstance(node, (int, float)):
        return None
    return float(node)


def default_bounds(case, key: str, label: str = "find") -> tuple[float, float]:
    """`DEFAULT_SPAN` times the case's value of ``key``, clipped to the key's schema limit."""
    v = case_value(case, key)
    if v is None or not math.isfinite(v) or v <= 0:
        raise ValueError(f"{label} {key}: the case has no positive value of {key} to bracket "
                         f"({'none' if v is None else fmt_number(v)}); give bounds, e.g. {key}=LO,HI")
    lo, hi = DEFAULT_SPAN[0] * v, DEFAULT_SPAN[1] * v
    lim = LIMITS.get(key)
    if lim is not None:
        span = hi - lo
        if lo < lim.low or (lo == lim.low and not lim.low_inclusive):
            lo = lim.low if lim.low_inclusive else lim.low + 1e-6 * span
        if hi > lim.high or (hi == lim.high and not lim.high_inclusive):
            hi = lim.high if lim.high_inclusive else lim.high - 1e-6 * span
    return lo, hi


class _Found(Exception):
    """The root search met the output tolerance at ``x``."""

    def __init__(self, x, y):
        super().__init__(x)
        self.x, self.y = x, y


class _Failed(Exception):
    def __init__(self, x, reason):
        super().__init__(reason)
        self.x, self.reason = x, reason


def target(case, find, such_that, bounds=None, *, overrides=None, tol=None, labels=None,
           _evaluator=None) -> TargetResult:
    """The value of the case input ``find`` in ``bounds`` that meets ``such_that`` (module docstring).

    Parameters
    ----------
    case : str, path or Simulation
        Case name or ``.toml`` file (a `Simulation` of one: its
        case and overrides).
    find : str
        The free input, a numeric case key (``"operating.feed_rate"``); ``"KEY=LO,HI"`` gives the
        bounds too.
    such_that : str or (name, op, value)
        ``"product_moisture_kg_kg=0.12"``, ``"...<=0.12"`` or ``"...>=0.12"``.
    bounds : (lo, hi), optional
        Bracket of the input (SI); default `DEFAULT_SPAN` times the case's value, clipped to
        the key's schema limit.
    overrides : dict, optional
        Further case overrides (``--set``), applied at every evaluation.
    tol : float, optional
        Absolute tolerance on the output; default `default_tol` (``1e-4 * |value|``, at least an
        absolute floor of the output's quantity: 1e-3 K, 1e-7 kg/kg ...).
    labels : dict, optional
        Names of ``find``, ``such_that`` and ``bounds`` in the error messages (the CLI's options).

    Returns
    -------
    TargetResult
    """
    lab = {**_LABELS, **(labels or {})}
    if isinstance(case, Simulation):
        overrides = {**case.overrides, **(overrides or {})}
        case = case.reloadable_name("a target")
    case_name = str(case)
    overrides = dict(overrides or {})
    key, given = parse_find(find, lab["find"])
    if bounds is not None and given is not None:
        raise ValueError(f"{lab['find']} = {find!r}: bounds given twice (in {lab['find']} and {lab['bounds']})")
    bounds = given if bounds is None else bounds
    name, op, y_target = parse_such_that(such_that, lab["such_that"])
    if key in overrides:
        raise ValueError(f"{lab['find']} {key}: the key is also set as an override ({key}={overrides[key]}); "
                         "the free input cannot be fixed")
    base = load_case(case_name, overrides)         # names an unknown case or a bad override
    _check_free_input(base, key, lab["find"])
    lo, hi = default_bounds(base, key, lab["find"]) if bounds is None else check_bounds(key, bounds, lab["find"])
    tol = default_tol(name, y_target) if tol is None else float(tol)
    if not (math.isfinite(tol) and tol > 0):
        raise ValueError(f"tol = {tol!r} is not a positive number")
    unit = LIMITS[key].unit if key in LIMITS else ""

    ev = _evaluator
    if ev is None:
        ev = _Evaluator(case_name, overrides, [name], f"{lab['such_that']} = {str(such_that)!r}",
                        budget_message=f"target {key} such that {name}{op}{fmt_number(y_target)}: no answer in "
                                       f"{MAX_EVALUATIONS} steady states")
    first = len(ev.points)      # an evaluator shared with other searches: this search's steady states follow

    def evaluate(x):
        ys, reason = ev({key: float(x)})
        return (None, reason) if ys is None else (ys[name], "")

    notes: list[str] = []
    def crossed(ya, yb):        # the output meets the value between two points that solve
        return (ya - y_target) * (yb - y_target) <= 0

    lo, hi = _usable_end(evaluate, lo, hi, "lo", key, unit, notes, lab["find"], crossed)
    hi, lo = _usable_end(evaluate, hi, lo, "hi", key, unit, notes, lab["find"], crossed)
    ylo, yhi = evaluate(lo)[0], evaluate(hi)[0]

    def meets(y):
        return y <= y_target + tol if op == "<=" else y >= y_target - tol if op == ">=" else abs(y - y_target) <= tol

    result = dict(case=case_name, find=key, output_name=name, operator=op, target_value=y_target, bounds=(lo, hi),
                  outputs_at_bounds={"lo": ylo, "hi": yhi}, tol=tol, unit=unit, notes=notes)

    def answer(**kw) -> TargetResult:
        if _evaluator is None:      # a search of its own: its answer's warnings (a shared one's caller says them)
            ev.replay_warnings(None if kw.get("value") is None else {key: kw["value"]}, notes)
        # (input, output or None, error) of every steady state of this search, in order
        points = [(at, y[name] if isinstance(y, dict) else y, err) for at, y, err in ev.points[first:]]
        return TargetResult(evaluations=len(points), points=points, **kw, **result)

    glo, ghi = ylo - y_target, yhi - y_target
    if abs(glo) <= tol or abs(ghi) <= tol or glo * ghi < 0:
        if abs(glo) <= tol or abs(ghi) <= tol:
            x, y = (lo, ylo) if abs(glo) <= abs(ghi) else (hi, yhi)
            if op == "=":
                # met at the bracket's end: an output flat there (a product at its moisture floor over a range of gas
                # temperatures) meets it over a range, and this end is one answer of many (found by fuzzing: 600 degC,
                # the bound, "met with equality")
                mid = 0.5 * (lo + hi)
                ym, _ = evaluate(mid)
                if ym is not None and abs(ym - y_target) <= tol:
                    notes.append(f"{name} meets {fmt_number(y_target)} (within tol = {fmt_number(tol)}) at the bracket's "
                                 f"end {fmt_number(x)} and at its middle {fmt_number(mid)} too: it is flat there (e.g. a "
                                 "product dried to its floor), so the value is one of a range; give other bounds or "
                                 "another target")
        else:
            x, y = _root(evaluate, lo, hi, y_target, tol, key, unit, lab["find"])
            if abs(y - y_target) > tol:
                notes.append(f"{name} = {fmt_number(y)} at the end of the root search, not within tol = "
                             f"{fmt_number(tol)} of {fmt_number(y_target)} (a jump of the output?)")
        both = op != "=" and meets(ylo) and meets(yhi)
        if both:               # at a bound within tol, the whole bracket meeting it: that bound binds
            side = "lo" if x == lo else "hi"
            return answer(value=x, output=y, active=f"bound {side} binds")
        return answer(value=x, output=y, active="target met with equality")
    # no crossing in the bracket
    worse = "hi" if (yhi > ylo) == (op == "<=") else "lo"     # the side where the output nears the value
    if op != "=" and meets(ylo) and meets(yhi):
        x, y = (lo, ylo) if worse == "lo" else (hi, yhi)
        return answer(value=x, output=y, active=f"bound {worse} binds")
    # neither bound meets it: the output need not be monotone (under-loaded flights whose curtains thin as the feed
    # falls; a size class blown out): a look inside, at the case's own value and the quarter points
    own = case_value(base, key)
    own = float(own) if isinstance(own, (int, float)) and not isinstance(own, bool) else None
    probes = sorted({x for x in (own, lo + 0.25 * (hi - lo), lo + 0.5 * (hi - lo), lo + 0.75 * (hi - lo))
                     if x is not None and lo < x < hi})
    prev_x, prev_g, seen = lo, glo, []
    for i, x in enumerate(probes):
        y, _ = evaluate(x)
        if y is None:
            continue
        g = y - y_target
        seen.append(f"{fmt_number(y)} at {fmt_number(x)}")
        if abs(g) <= tol or g * prev_g < 0:
            xr, yr = (x, y) if abs(g) <= tol else _root(evaluate, prev_x, x, y_target, tol, key, unit, lab["find"])
            # where it stops meeting the value again: between the next probes (or the last one and hi)
            later = [(x, g)] + [(p, yp - y_target) for p in probes[i + 1:]
                                if (yp := evaluate(p)[0]) is not None] + [(hi, ghi)]
            back = next(((a, b) for (a, ga), (b, gb) in zip(later, later[1:]) if ga * gb < 0), None)
            other = ""
            if back is not None:
                xb, _ = _root(evaluate, back[0], back[1], y_target, tol, key, unit, lab["find"])
                other = f" and again at {fmt_number(xb)}"
            notes.append(f"{name} is not monotone in {key} over [{fmt_number(lo)}, {fmt_number(hi)}]: it meets "
                         f"{fmt_number(y_target)} inside though at neither bound ({fmt_number(ylo)} and "
                         f"{fmt_number(yhi)}; {', '.join(seen)}): it crosses the value at {fmt_number(xr)}{other}; "
                         "this answer is the first crossing: give bounds around the one wanted")
            return answer(value=xr, output=yr, active="target met with equality")
        prev_x, prev_g = x, g
    if seen:
        notes.append(f"{name} inside the bracket: {', '.join(seen)}")
    closest = "lo" if abs(glo) <= abs(ghi) else "hi"
    return answer(value=None, output=None, active=f"no solution in [{fmt_number(lo)}, {fmt_number(hi)}]",
                  closest=closest)


def _usable_end(evaluate, end, other, side, key, unit, notes, label, crossed=None):
    """``(end, other)`` with ``end`` moved toward ``other`` until its steady state solves: halving the distance
    until a point solves, then bisecting between it and the last point that did not (BISECT_STEPS times), so
    that the bracket keeps all but 1/2^BISECT_STEPS of the failed half (a halving alone can give away most of
    the range, the answer with it). No bisection where ``crossed(y at the point, y at other)``: the answer lies
    between them already (near the edge of a dryer's steady states each failed solve costs a march: a target on
    a user dryer took 4 of them, 5 minutes, to move a bound the answer was far from)."""
    y, reason = evaluate(end)
    x = end
    k = 0
    while y is None and k < SHRINK_STEPS:
        k += 1
        bad, x = x, other + 0.5 * (x - other)
        y, _ = evaluate(x)
    if y is not None and x != end and crossed is not None:
        y_other = evaluate(other)[0]
        if y_other is not None and crossed(y, y_other):
            notes.append(f"bound {side} moved from {fmt_number(end)} to {fmt_number(x)}{f' {unit}' if unit else ''}: "
                         f"no steady state at {fmt_number(end)} ({reason}); the answer lies inside")
            return x, other
    if y is not None and x != end:
        for _ in range(BISECT_STEPS):
            mid = 0.5 * (x + bad)
            if evaluate(mid)[0] is None:
                bad = mid
            else:
                x = mid
    u = f" {unit}" if unit else ""
    if y is None:
        raise TargetError(f"{label} {key}: no steady state at the bound {side} = {fmt_number(end)}{u} nor at "
                          f"{k} points toward {fmt_number(other)} ({reason}); give narrower bounds", "no_steady_state")
    if x != end:
        notes.append(f"bound {side} moved from {fmt_number(end)} to {fmt_number(x)}{u}: no steady state at "
                     f"{fmt_number(end)} ({reason})")
    return x, other


def _root(evaluate, lo, hi, y_target, tol, key, unit, label):
    """(input, output) where the output equals ``y_target`` within ``tol`` (Brent on ``[lo, hi]``)."""
    def g(x):
        y, reason = evaluate(x)
        if y is None:
            raise _Failed(x, reason)
        if abs(y - y_target) <= tol:
            raise _Found(x, y)
        return y - y_target

    try:
        x = brentq(g, lo, hi, xtol=1e-10 * max(abs(lo), abs(hi), 1e-300), rtol=1e-12, maxiter=60)
    except _Found as hit:
        return float(hit.x), float(hit.y)
    except _Failed as bad:
        u = f" {unit}" if unit else ""
        raise TargetError(f"{label} {key}: no steady state at {fmt_number(bad.x)}{u} inside the bracket "
                          f"[{fmt_number(lo)}, {fmt_number(hi)}] ({bad.reason}); give bounds on one side of it",
                          "no_steady_state") from None
    y, reason = evaluate(x)
    if y is None:
        raise TargetError(f"{label} {key}: no steady state at {fmt_number(x)} ({reason})", "no_steady_state")
    return float(x), float(y)


# ---------------------------------------------------------------------------------------------- several targets
@dataclass
class TargetSetResult:
    """The answer of several targets ([`solve_targets`][rotarydryer.studies.target.solve_targets]) or of an
    optimum ([`optimum`][rotarydryer.studies.target.optimum]).

    ``values``: input key -> value (SI); ``outputs``: output name -> value there (every output a
    condition or the objective names); ``conditions``: one dict per condition (``such_that``,
    ``output``, ``met``, ``active``: an inequality holding with equality within its tolerance, or an
    equality); ``active_bounds``: input key -> ``"lo"``/``"hi"`` where an input sits on a bound."""

    case: str
    kind: str
    values: dict
    outputs: dict
    conditions: list
    active_bounds: dict
    bounds: dict
    evaluations: int
    found: bool
    objective: str | None = None
    sense: str | None = None
    notes: list = field(default_factory=list)

    def to_dict(self) -> dict:
        return {"case": self.case, "kind": self.kind, "found": self.found, "objective": self.objective,
                "sense": self.sense, **{k: v for k, v in self.values.items()}, "values": dict(self.values),
                "outputs": dict(self.outputs), "conditions": list(self.conditions),
                "active_bounds": dict(self.active_bounds), "bounds": {k: list(v) for k, v in self.bounds.items()},
                "evaluations": self.evaluations, "notes": list(self.notes)}

    def text(self) -> str:
        head = (f"{self.sense} {self.objective}" if self.objective else "targets") + f" of {self.case}"
        lines = [head + ("" if self.found else ": no solution in the bounds")]
        for k, v in self.values.items():
            lo, hi = self.bounds[k]
            u = LIMITS[k].unit if k in LIMITS else ""
            side = self.active_bounds.get(k)
            lines.append(f"  {k} = {fmt_number(v)}{' ' + u if u else ''} in [{fmt_number(lo)}, {fmt_number(hi)}]"
                         + (f" (bound {side} binds)" if side else ""))
        for c in self.conditions:
            state = "active" if c["active"] else ("met" if c["met"] else "NOT met")
            lines.append(f"  {c['such_that']}: {c['output_name']} = {_shown(c['output'], c['output_name'])} ({state})")
        lines += [f"note: {n}" for n in self.notes]
        lines.append(f"{self.evaluations} steady states")
        return "\n".join(lines)


class _Evaluator:
    """Steady-state outputs at input values (dict key -> x), cached, warm-started from the last run."""

    def __init__(self, case_name, overrides, names, such_that_label, budget_message=None, budget=MAX_EVALUATIONS,
                 name_labels=None):
        self.case_name, self.overrides, self.names, self.label = case_name, overrides, names, such_that_label
        self.name_labels = name_labels or {}     # the option naming an output, where not the conditions' (an objective)
        self.budget = budget
        self.budget_message = budget_message or f"no answer in {budget} steady states (the study's budget)"
        self.cache: dict = {}
        self.warm = None
        self.count = 0
        #: every steady state in order: (the input's value for one input, else the values dict;
        #: the output for one name, else the outputs dict, None where it failed; the error or "")
        self.points: list = []
        #: the warnings of each steady state, by its key (`replay_warnings`)
        self.warned: dict = {}

    @staticmethod
    def key_of(values: dict) -> tuple:
        return tuple(sorted((k, float(v)) for k, v in values.items()))

    def replay_warnings(self, values: dict | None, notes: list) -> None:
        """Issue again the warnings of the steady state at ``values`` (the answer's; None: no answer), and add
        to ``notes`` how many of the search's other steady states warned (a point the search passed on its
        way, below a dew point or outside a range, is not the answer: its warnings are not repeated)."""
        key = None if values is None else self.key_of(values)
        for message, category in self.warned.get(key, []):
            warnings.warn(message, category, stacklevel=3)
        n = sum(1 for k, w in self.warned.items() if w and k != key)
        if n:
            notes.append(f"{n} other steady state{'s' if n > 1 else ''} of the search warned (not shown: the "
                         "points the search passed are not the answer; the answer's warnings are)")

    def __call__(self, values: dict):
        key = self.key_of(values)
        if key in self.cache:
            return self.cache[key]
        if self.count >= self.budget:
            raise TargetError(self.budget_message, "unreachable")
        self.count += 1
        at = float(next(iter(values.values()))) if len(values) == 1 else dict(values)
        try:
            sim = Simulation(self.case_name, {**self.overrides, **values})    # the case's own warnings pass
            # the steady state's warnings (an exhaust below its dew point...) belong to this point: kept, and
            # shown for the answer's point only (`replay_warnings`), not for every point the search passed
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                try:
                    res = sim.steady_state(warm=self.warm)
                    out = res.summary()
                finally:
                    self.warned[key] = [(w.message, w.category) for w in caught]
        except (ValueError, ArithmeticError) as exc:
            self.cache[key] = (None, " ".join(str(exc).split()) or type(exc).__name__)
            self.points.append((at, None, self.cache[key][1]))
            return self.cache[key]
        self.warm = res.warm_data() or self.warm
        ys = {}
        for name in self.names:
            y = out.get(name)
            if name not in out or isinstance(y, bool) or not isinstance(y, (int, float)):
                numeric = sorted(k for k, v in out.items() if isinstance(v, (int, float)) and not isinstance(v, bool))
                what = "is not an output of the case" if name not in out else "is not a number in this run"
                raise TargetError(f"{self.name_labels.get(name, self.label)}: {name!r} {what}; outputs: {', '.join(numeric)}")
            ys[name] = float(y)
        self.cache[key] = (ys, "")
        self.points.append((at, ys[self.names[0]] if len(self.names) == 1 else dict(ys), ""))
        return self.cache[key]


def _check_free_input(base, key: str, label: str) -> None:
    """A free input is a key of the case that takes a continuous number (``TargetError`` naming it otherwise: a
    whole-number key such as drum.n_flights was tried at 5.5 flights, a text key had "no positive value")."""
    if key not in valid_override_keys(type(base)):
        raise TargetError(f"{label} {key!r}: not a key of the case; numeric keys with limits: "
                          f"{', '.join(sorted(LIMITS))}")
    what = discrete_kind(type(base), key)
    if what is not None:
        raise TargetError(f"{label} {key}: the key takes {what}; a target needs a continuous input (run the values "
                          f"you want to compare with `rotarydryer sweep --grid {key}=...`)")


def _prepare(case, finds, such_thats, overrides, tol, labels, need):
    lab = {**_LABELS, **(labels or {})}
    if isinstance(case, Simulation):
        overrides = {**case.overrides, **(overrides or {})}
        case = case.reloadable_name("a target")
    case_name, overrides = str(case), dict(overrides or {})
    finds = [finds] if isinstance(finds, str) else list(finds)
    one = isinstance(such_thats, str) or (isinstance(such_thats, tuple) and len(such_thats) == 3
                                          and isinstance(such_thats[0], str) and such_thats[1] in OPERATORS + ("==",))
    such_thats = [such_thats] if one else list(such_thats or [])
    if not finds:
        raise TargetError(f"{lab['find']}: give at least one free input")
    base = load_case(case_name, overrides)
    keys, bounds = [], {}
    for f in finds:
        key, given = parse_find(f, lab["find"])
        if key in keys:
            raise TargetError(f"{lab['find']} {key}: the same free input given twice")
        if key in overrides:
            raise TargetError(f"{lab['find']} {key}: the key is also set as an override ({key}={overrides[key]}); "
                              "the free input cannot be fixed")
        _check_free_input(base, key, lab["find"])
        bounds[key] = default_bounds(base, key, lab["find"]) if given is None else check_bounds(key, given, lab["find"])
        keys.append(key)
    conds = [parse_such_that(s, lab["such_that"]) for s in such_thats]
    seen: dict = {}
    for name, op, v in conds:
        if op == "=" and name in seen and seen[name] != v:
            raise TargetError(f"{lab['such_that']}: conflicting targets {name}={fmt_number(seen[name])} and "
                              f"{name}={fmt_number(v)} (one output cannot take two values)")
        if op == "=":
            seen[name] = v
    if need == "square":
        if len(conds) != len(keys):
            raise TargetError(f"{len(keys)} free input(s) ({lab['find']}) for {len(conds)} target(s) "
                              f"({lab['such_that']}): several targets need as many free inputs; for a maximum or "
                              "minimum under conditions use --maximize/--minimize")
        if any(op != "=" for _, op, _ in conds):
            raise TargetError(f"{lab['such_that']}: several targets are equalities OUTPUT=VALUE; inequalities are the "
                              "conditions of --maximize/--minimize")
    tols = [default_tol(name, v) if tol is None else float(tol) for name, _, v in conds]
    if any(not (math.isfinite(t) and t > 0) for t in tols):
        raise TargetError(f"tol = {tol!r} is not a positive number")
    start = {}
    for k in keys:
        v = case_value(base, k)
        lo, hi = bounds[k]
        start[k] = 0.5 * (lo + hi) if v is None or not lo <= v <= hi else v
    return lab, case_name, overrides, keys, bounds, conds, tols, start


def _conditions(conds, tols, ys):
    out = []
    for (name, op, v), t in zip(conds, tols):
        y = None if ys is None else ys[name]
        met = y is not None and (y <= v + t if op == "<=" else y >= v - t if op == ">=" else abs(y - v) <= t)
        out.append(dict(such_that=f"{name}{op}{fmt_number(v)}", output_name=name, output=y, met=bool(met),
                        active=bool(y is not None and abs(y - v) <= t)))
    return out


def _at_bounds(values, bounds):
    sides = {}
    for k, x in values.items():
        lo, hi = bounds[k]
        span = hi - lo
        if x <= lo + 1e-9 * span:
            sides[k] = "lo"
        elif x >= hi - 1e-9 * span:
            sides[k] = "hi"
    return sides


def solve_targets(case, finds, such_thats, *, overrides=None, tol=None, labels=None,
                  max_iterations=25) -> TargetSetResult:
    """The values of as many free inputs as equality targets (``finds`` = ``["operating.feed_rate",
    "gas.inlet_temperature=400,600"]``, ``such_thats`` = ``["product_moisture_kg_kg=0.12",
    "gas_outlet_temperature_degC=130"]``): Newton's method on the steady states, the Jacobian by
    forward differences (1e-4 of each bracket) at every iterate, steps kept inside the bounds and
    halved until the scaled residual falls (a damped Newton). One free input is
    [`target`][rotarydryer.studies.target.target]'s bracketing search. ``TargetError`` when the targets
    conflict, the Jacobian is singular (a target does not depend on the inputs) or no point in the
    bounds meets them."""

    lab, case_name, overrides, keys, bounds, conds, tols, start = _prepare(case, finds, such_thats, overrides, tol,
                                                                            labels, "square")
    names = [c[0] for c in conds]
    ev = _Evaluator(case_name, overrides, names, lab["such_that"])
    lo = np.array([bounds[k][0] for k in keys])
    span = np.array([bounds[k][1] - bounds[k][0] for k in keys])
    target_v = np.array([c[2] for c in conds])
    tol_v = np.array(tols)
    scale = np.maximum(np.abs(target_v), 1e4 * tol_v)

    def at(u):
        vals = {k: float(lo[i] + span[i] * u[i]) for i, k in enumerate(keys)}
        ys, reason = ev(vals)
        if ys is None:
            return vals, None, reason
        return vals, np.array([ys[n] for n in names]), ""

    u = np.array([(start[k] - lo[i]) / span[i] for i, k in enumerate(keys)])
    vals, y, reason = at(u)
    if y is None:
        raise TargetError(f"{lab['find']}: no steady state at the start {_fmt_values(vals)} ({reason})", "no_steady_state")
    notes: list[str] = []
    for _ in range(max_iterations):
        r = (y - target_v) / scale
        if np.all(np.abs(y - target_v) <= tol_v):
            break
        h = 1e-4
        J = np.empty((len(names), len(keys)))
        for j in range(len(keys)):
            du = h if u[j] + h <= 1 else -h
            uj = u.copy()
            uj[j] += du
            _, yj, reason = at(uj)
            if yj is None:
                raise TargetError(f"{lab['find']}: no steady state near {_fmt_values(vals)} ({reason})", "no_steady_state")
            J[:, j] = (yj - y) / scale / du
        if not np.all(np.isfinite(J)) or np.linalg.matrix_rank(J, tol=1e-10 * max(1.0, np.abs(J).max())) < len(keys):
            dead = [names[i] for i in range(len(names)) if np.all(np.abs(J[i]) < 1e-12)]
            # a local slope: an output flat at this point (a product dried to its floor) may move elsewhere
            why = (f"{', '.join(dead)} does not change with the free inputs at {_fmt_values(vals)} (flat there: "
                   "e.g. a product dried to its floor)") if dead else \
                "the targets are not independent (two of them move together)"
            raise TargetError(f"{lab['such_that']}: conflicting or redundant targets: {why}; change the free inputs "
                              f"({lab['find']}), their start or the targets, or solve one target at a time",
                              "bad_input")
        step = np.linalg.solve(J, -r)
        # projected Newton (Bertsekas (1982) SIAM J. Control Optim. 20, 221): an input at its bound that the
        # step would push outside stays there, and the others take the least-squares step with it fixed
        # (clipping the full step instead bends its direction, and the line search can stall on it)
        out = ((u <= 0.0) & (step < 0.0)) | ((u >= 1.0) & (step > 0.0))
        if np.any(out) and not np.all(out):
            step = np.zeros_like(step)
            step[~out] = np.linalg.lstsq(J[:, ~out], -r, rcond=None)[0]
        lam, accepted = 1.0, False
        for _half in range(8):
            un = np.clip(u + lam * step, 0.0, 1.0)
            vn, yn, reason = at(un)
            if yn is not None and np.linalg.norm((yn - target_v) / scale) < np.linalg.norm(r):
                u, vals, y, accepted = un, vn, yn, True
                break
            lam *= 0.5
        if not accepted:
            break
    found = bool(np.all(np.abs(y - target_v) <= tol_v))
    ys = {n: float(v) for n, v in zip(names, y)}
    if not found:
        notes.append("Newton's method stalled: the targets are not met at the closest point found (shown); a "
                     "local search from one start, it does not prove that the bounds hold no answer")
    ev.replay_warnings(vals, notes)
    return TargetSetResult(case=case_name, kind="targets", values=vals, outputs=ys, conditions=_conditions(conds, tols, ys),
                           active_bounds=_at_bounds(vals, bounds), bounds=bounds, evaluations=ev.count, found=found,
                           notes=notes)


def _fmt_values(vals):
    return ", ".join(f"{k}={fmt_number(v)}" for k, v in vals.items())


def optimum(case, finds, objective, such_thats=(), *, sense="max", overrides=None, tol=None,
            labels=None) -> TargetSetResult:
    """The largest (``sense="max"``) or smallest (``"min"``) ``objective`` (a free input's key or an
    output name) over the free inputs ``finds`` in their bounds, subject to the conditions
    ``such_thats`` (``<=``, ``>=`` or ``=`` on outputs), e.g. the largest feed rate with
    ``product_moisture_kg_kg<=0.12`` and ``gas_outlet_dew_point_margin_K>=10``.

    One free input and an objective that is that input: each condition's crossing by
    [`target`][rotarydryer.studies.target.target] (Brent on the steady states; each output taken
    monotone over the bounds, as there), the feasible intervals intersected, and the end of the
    intersection in the objective's direction returned, with the conditions that bind there.
    Otherwise SLSQP (`scipy.optimize.minimize`) on the inputs scaled to their bounds, finite-
    difference gradients of 1e-4 of each bracket, started from the case's values."""

    if sense not in ("max", "min"):
        raise TargetError(f"sense = {sense!r}: use max or min")
    lab, case_name, overrides, keys, bounds, conds, tols, start = _prepare(case, finds, such_thats, overrides, tol,
                                                                            labels, "any")
    objective = str(objective).strip()
    if objective not in keys and objective in valid_override_keys(type(load_case(case_name, overrides or None))):
        raise TargetError(f"{lab['objective']} {objective}: a case key that is not a free input of this target "
                          f"({lab['find']} {', '.join(keys)}): give it as a {lab['find']} too, or optimise an output")
    names = list(dict.fromkeys([c[0] for c in conds] + ([] if objective in keys else [objective])))
    if len(keys) == 1 and objective == keys[0]:
        return _optimum_1d(case_name, overrides, keys[0], bounds[keys[0]], conds, tols, sense, lab)
    ev = _Evaluator(case_name, overrides, names, lab["such_that"], budget=OPTIMUM_EVALUATIONS,
                    name_labels={} if objective in keys or objective in [c[0] for c in conds]
                    else {objective: lab["objective"]})
    lo = np.array([bounds[k][0] for k in keys])
    span = np.array([bounds[k][1] - bounds[k][0] for k in keys])
    sign = -1.0 if sense == "max" else 1.0
    def values(u):
        return {k: float(lo[i] + span[i] * np.clip(u[i], 0, 1)) for i, k in enumerate(keys)}

    def outputs(u, strict=True):
        ys, reason = ev(values(u))
        if ys is None and not strict:
            return None
        if ys is None:
            raise TargetError(f"{lab['find']}: no steady state at {_fmt_values(values(u))} ({reason})", "no_steady_state")
        return ys

    y0 = None

    def f(u):
        nonlocal y0
        if objective in keys:
            v = values(u)[objective]
        else:
            ys = outputs(u, strict=False)
            if ys is None:            # no steady state at a probe: a poor objective, the step is retried shorter
                return 1e3
            v = ys[objective]
        y0 = abs(v) if y0 is None else y0
        return sign * v / max(y0, 1e-12)

    cons = []
    for (name, op, v), t in zip(conds, tols):
        s = max(abs(v), 1e4 * t)
        if op == "=":
            cons.append({"type": "eq", "fun": lambda u, n=name, v=v, s=s: _scaled(outputs(u, False), n, v, s, 1.0)})
        else:
            sg = 1.0 if op == ">=" else -1.0
            cons.append({"type": "ineq", "fun": lambda u, n=name, v=v, s=s, sg=sg: _scaled(outputs(u, False), n, v,
                                                                                           s, sg)})
    u0 = np.array([(start[k] - lo[i]) / span[i] for i, k in enumerate(keys)])
    notes: list[str] = []
    try:
        res = minimize(f, u0, method="SLSQP", bounds=[(0.0, 1.0)] * len(keys), constraints=cons,
                       options={"eps": 1e-4, "maxiter": 40, "ftol": 1e-8})
        x_best = res.x
        if not res.success:
            notes.append(f"SLSQP: {res.message}")
    except TargetError as exc:     # a probe without a steady state (or the budget): the best point met so far
        x_best = _best_feasible(ev, keys, lo, span, objective, sign, conds, tols)
        if x_best is None:
            raise
        notes.append(f"SLSQP stopped ({' '.join(str(exc).split())}); the best point evaluated that meets the "
                     "conditions is shown")
    vals = values(x_best)
    ys = outputs(x_best)
    conditions = _conditions(conds, tols, ys)
    found = bool(all(c["met"] for c in conditions))
    outs = {n: ys[n] for n in names}
    ev.replay_warnings(vals, notes)
    return TargetSetResult(case=case_name, kind="optimum", values=vals, outputs=outs, conditions=conditions,
                           active_bounds=_at_bounds(vals, bounds), bounds=bounds, evaluations=ev.count, found=found,
                           objective=objective, sense=sense, notes=notes)


def _scaled(ys, name, value, scale, sign):
    """A condition as SLSQP's constraint function (>= 0 met); a point without a steady state
    counts as violating it (-1)."""
    return -1.0 if ys is None else sign * (ys[name] - value) / scale


def _best_feasible(ev, keys, lo, span, objective, sign, conds, tols):
    """Scaled inputs of the best evaluated point that meets every condition (None: none does)."""

    best, best_f = None, math.inf
    for key, (ys, _) in ev.cache.items():
        if ys is None:
            continue
        x = dict(key)
        if not all(c["met"] for c in _conditions(conds, tols, ys)):
            continue
        fv = sign * (x[objective] if objective in x else ys[objective])
        if fv < best_f:
            best, best_f = np.array([(x[k] - lo[i]) / span[i] for i, k in enumerate(keys)]), fv
    return best


def _optimum_1d(case_name, overrides, key, bounds, conds, tols, sense, lab):
    """One input maximised or minimised under conditions on outputs (see `optimum`)."""
    lo, hi = bounds
    feasible = [lo, hi]
    binding: list[str] = []
    notes: list[str] = []
    # one evaluator for every condition's search and the answer: each steady state once (the bounds are
    # every search's), each warm-started from the last, the answer too
    ev = _Evaluator(case_name, overrides, list(dict.fromkeys(c[0] for c in conds)), lab["such_that"],
                    budget=MAX_EVALUATIONS * len(conds) + 1)
    for (name, op, v), t in zip(conds, tols):
        r = target(case_name, f"{key}={lo!r},{hi!r}", (name, op, v), overrides=overrides, tol=t, labels=lab,
                   _evaluator=ev)
        notes += [n for n in r.notes if n not in notes]       # a moved bound is every search's
        if r.value is None:
            raise TargetError(f"{lab['such_that']} {r.such_that}: met nowhere for {key} in [{fmt_number(lo)}, "
                              f"{fmt_number(hi)}] ({name} = {_shown(r.outputs_at_bounds['lo'])} at lo, "
                              f"{_shown(r.outputs_at_bounds['hi'])} at hi)", "unreachable")
        ylo = r.outputs_at_bounds["lo"]
        meets_lo = ylo is not None and (ylo <= v + t if op == "<=" else ylo >= v - t if op == ">=" else abs(ylo - v) <= t)
        if op == "=":
            interval = (r.value, r.value)
        elif r.active.startswith("bound"):
            interval = (r.bounds[0], r.bounds[1])           # the whole (usable) bracket meets it
        elif meets_lo:
            interval = (r.bounds[0], r.value)
        else:
            interval = (r.value, r.bounds[1])
        feasible = [max(feasible[0], interval[0]), min(feasible[1], interval[1])]
    if feasible[0] > feasible[1] + 1e-12 * (hi - lo):
        raise TargetError(f"{lab['such_that']}: the conditions exclude each other for {key} in [{fmt_number(lo)}, "
                          f"{fmt_number(hi)}] (no value meets them all)", "unreachable")
    x = feasible[1] if sense == "max" else feasible[0]
    ys, reason = ev({key: x})
    evaluations = ev.count
    if ys is None:
        raise TargetError(f"{lab['find']}: no steady state at {key}={fmt_number(x)} ({reason})", "no_steady_state")
    conditions = _conditions(conds, tols, ys)
    binding = [c["such_that"] for c in conditions if c["active"]]
    if binding:
        notes.append(f"binding: {', '.join(binding)}")
    ev.replay_warnings({key: x}, notes)
    return TargetSetResult(case=case_name, kind="optimum", values={key: x}, outputs=ys, conditions=conditions,
                           active_bounds=_at_bounds({key: x}, {key: bounds}), bounds={key: bounds},
                           evaluations=evaluations, found=all(c["met"] for c in conditions), objective=key,
                           sense=sense, notes=notes)
