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
change (as :meth:`rotarydryer.simulation.Simulation.sweep`).

The condition is on one output of :meth:`~rotarydryer.simulation.SteadyResult.summary`:

- ``output = value``: the input where the output equals the value (Brent's method,
  :func:`scipy.optimize.brentq`, on the sign change between the bounds); no sign change is
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
toward the other one (at most :data:`SHRINK_STEPS` times, halving the distance), and the result
says so in ``notes``; a failure inside the bracket during the root search is an error naming the
input value and the reason. The output tolerance ``tol`` (absolute, in the output's unit) ends
the search when ``|output - value| <= tol``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

from scipy.optimize import brentq

from .._limits import LIMITS
from .._validation import fmt_number
from ..cases import load_case, valid_override_keys
from ..cases.build import test_row
from ..simulation import Simulation

__all__ = ["target", "TargetResult", "parse_such_that", "parse_find", "default_bounds", "check_bounds",
           "OPERATORS", "SHRINK_STEPS", "DEFAULT_SPAN"]

#: the conditions a target may put on its output
OPERATORS = ("=", "<=", ">=")
#: halvings of the distance to the other bound tried when the steady state fails at a bound
SHRINK_STEPS = 5
#: default bracket around the case's value: (lo factor, hi factor)
DEFAULT_SPAN = (0.25, 4.0)
#: most steady states of one target (bounds, shrinking and the root search)
MAX_EVALUATIONS = 80

_LABELS = {"find": "find", "such_that": "such_that", "bounds": "bounds"}
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
        """Plain text of the answer, a line each."""
        u = f" {self.unit}" if self.unit else ""
        lo, hi = self.bounds
        ylo, yhi = self.outputs_at_bounds["lo"], self.outputs_at_bounds["hi"]
        lines = [f"target of {self.case}: {self.find} such that {self.such_that}",
                 f"bounds: [{fmt_number(lo)}, {fmt_number(hi)}]{u}; {self.output_name} = {_shown(ylo)} at lo, "
                 f"{_shown(yhi)} at hi"]
        if self.found:
            lines.append(f"{self.find} = {fmt_number(self.value)}{u} ({self.active}); "
                         f"{self.output_name} = {_shown(self.output)}")
        else:
            lines.append(f"{self.active}: {self.output_name} {self.operator} {fmt_number(self.target_value)} "
                         f"is met nowhere; bound {self.closest} comes closest ({self.output_name} = "
                         f"{_shown(self.outputs_at_bounds[self.closest])})")
        lines += [f"note: {n}" for n in self.notes]
        lines.append(f"{self.evaluations} steady states")
        return "\n".join(lines)


def _shown(y) -> str:
    return "n/a" if y is None else fmt_number(y)


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
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{label} = {str(text)!r}: the value {str(value)!r} is not a number; {form}") from None
    if not math.isfinite(v):
        raise ValueError(f"{label} = {str(text)!r}: the value is not a finite number; {form}")
    return str(name), op, v


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
    (:data:`rotarydryer._limits.LIMITS`, where declared); else ``ValueError`` naming ``label``,
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
    """:data:`DEFAULT_SPAN` times the case's value of ``key``, clipped to the key's schema limit."""
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


def target(case, find, such_that, bounds=None, *, overrides=None, tol=None, labels=None) -> TargetResult:
    """The value of the case input ``find`` in ``bounds`` that meets ``such_that`` (module docstring).

    Parameters
    ----------
    case : str, path or Simulation
        Case name or ``.toml`` file (a :class:`~rotarydryer.simulation.Simulation` of one: its
        case and overrides).
    find : str
        The free input, a numeric case key (``"operating.feed_rate"``); ``"KEY=LO,HI"`` gives the
        bounds too.
    such_that : str or (name, op, value)
        ``"product_moisture_kg_kg=0.12"``, ``"...<=0.12"`` or ``"...>=0.12"``.
    bounds : (lo, hi), optional
        Bracket of the input (SI); default :data:`DEFAULT_SPAN` times the case's value, clipped to
        the key's schema limit.
    overrides : dict, optional
        Further case overrides (``--set``), applied at every evaluation.
    tol : float, optional
        Absolute tolerance on the output; default ``1e-4 * |value|`` (at least 1e-9).
    labels : dict, optional
        Names of ``find``, ``such_that`` and ``bounds`` in the error messages (the CLI's options).

    Returns
    -------
    TargetResult
    """
    lab = {**_LABELS, **(labels or {})}
    if isinstance(case, Simulation):
        overrides = {**case.overrides, **(overrides or {})}
        case = case.case_name
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
    if key not in valid_override_keys(type(base)):
        raise ValueError(f"{lab['find']} {key!r}: not a key of the case; numeric keys with limits: "
                         f"{', '.join(sorted(LIMITS))}")
    lo, hi = default_bounds(base, key, lab["find"]) if bounds is None else check_bounds(key, bounds, lab["find"])
    tol = 1e-4 * max(abs(y_target), 1e-5) if tol is None else float(tol)
    if not (math.isfinite(tol) and tol > 0):
        raise ValueError(f"tol = {tol!r} is not a positive number")
    unit = LIMITS[key].unit if key in LIMITS else ""

    points: list = []
    cache: dict = {}
    warm = [None]

    def evaluate(x):
        x = float(x)
        if x in cache:
            return cache[x]
        if len(points) >= MAX_EVALUATIONS:
            raise ValueError(f"target {key} such that {name}{op}{fmt_number(y_target)}: no answer in "
                             f"{MAX_EVALUATIONS} steady states")
        try:
            res = Simulation(case_name, {**overrides, key: x}).steady_state(warm=warm[0])
            out = res.summary()
        except (ValueError, ArithmeticError) as exc:
            reason = " ".join(str(exc).split()) or type(exc).__name__
            points.append((x, None, reason))
            cache[x] = (None, reason)
            return cache[x]
        warm[0] = res.warm_data() or warm[0]
        y = out.get(name)
        if name not in out or isinstance(y, bool) or not isinstance(y, (int, float)):
            numeric = sorted(k for k, v in out.items() if isinstance(v, (int, float)) and not isinstance(v, bool))
            what = "is not an output of the case" if name not in out else "is not a number in this run"
            raise ValueError(f"{lab['such_that']} = {str(such_that)!r}: {name!r} {what}; "
                             f"outputs: {', '.join(numeric)}")
        points.append((x, float(y), ""))
        cache[x] = (float(y), "")
        return cache[x]

    notes: list[str] = []
    lo, hi = _usable_end(evaluate, lo, hi, "lo", key, unit, notes, lab["find"])
    hi, lo = _usable_end(evaluate, hi, lo, "hi", key, unit, notes, lab["find"])
    ylo, yhi = evaluate(lo)[0], evaluate(hi)[0]

    def meets(y):
        return y <= y_target + tol if op == "<=" else y >= y_target - tol if op == ">=" else abs(y - y_target) <= tol

    result = dict(case=case_name, find=key, output_name=name, operator=op, target_value=y_target, bounds=(lo, hi),
                  outputs_at_bounds={"lo": ylo, "hi": yhi}, tol=tol, unit=unit, notes=notes, points=points)
    glo, ghi = ylo - y_target, yhi - y_target
    if abs(glo) <= tol or abs(ghi) <= tol or glo * ghi < 0:
        if abs(glo) <= tol or abs(ghi) <= tol:
            x, y = (lo, ylo) if abs(glo) <= abs(ghi) else (hi, yhi)
        else:
            x, y = _root(evaluate, lo, hi, y_target, tol, key, unit, lab["find"])
            if abs(y - y_target) > tol:
                notes.append(f"{name} = {fmt_number(y)} at the end of the root search, not within tol = "
                             f"{fmt_number(tol)} of {fmt_number(y_target)} (a jump of the output?)")
        both = op != "=" and meets(ylo) and meets(yhi)
        if both:               # at a bound within tol, the whole bracket meeting it: that bound binds
            side = "lo" if x == lo else "hi"
            return TargetResult(value=x, output=y, active=f"bound {side} binds", evaluations=len(points),
                                **result)
        return TargetResult(value=x, output=y, active="target met with equality", evaluations=len(points), **result)
    # no crossing in the bracket
    worse = "hi" if (yhi > ylo) == (op == "<=") else "lo"     # the side where the output nears the value
    if op != "=" and meets(ylo) and meets(yhi):
        x, y = (lo, ylo) if worse == "lo" else (hi, yhi)
        return TargetResult(value=x, output=y, active=f"bound {worse} binds", evaluations=len(points), **result)
    closest = "lo" if abs(glo) <= abs(ghi) else "hi"
    return TargetResult(value=None, output=None, active=f"no solution in [{fmt_number(lo)}, {fmt_number(hi)}]",
                        closest=closest, evaluations=len(points), **result)


def _usable_end(evaluate, end, other, side, key, unit, notes, label):
    """``(end, other)`` with ``end`` moved toward ``other`` until its steady state solves."""
    y, reason = evaluate(end)
    x = end
    k = 0
    while y is None and k < SHRINK_STEPS:
        k += 1
        x = other + 0.5 * (x - other)
        y, _ = evaluate(x)
    u = f" {unit}" if unit else ""
    if y is None:
        raise ValueError(f"{label} {key}: no steady state at the bound {side} = {fmt_number(end)}{u} nor at "
                         f"{k} points toward {fmt_number(other)} ({reason}); give narrower bounds")
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
        raise ValueError(f"{label} {key}: no steady state at {fmt_number(bad.x)}{u} inside the bracket "
                         f"[{fmt_number(lo)}, {fmt_number(hi)}] ({bad.reason}); give bounds on one side of it") from None
    y, reason = evaluate(x)
    if y is None:
        raise ValueError(f"{label} {key}: no steady state at {fmt_number(x)} ({reason})")
    return float(x), float(y)
