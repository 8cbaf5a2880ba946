"""Calibrations as data: fitted values tied to the model configuration and the data they came from.

A case's ``[[calibrations]]`` entries (`CalibrationRecord`) hold fitted values of case keys,
their 95 % intervals and correlation, the data sets (with their weights) they were fitted to, the
model configuration they hold for (``configuration``: case keys and their values, e.g.
``"geometry.method" = "exact"``), the software version and the date. A thesis's published
estimates are a record too, with the thesis's configuration (Ajayi (2011) Table 5.2 under
``geometry.method = "ajayi2011_regressions"``; Lee (2008) Table 7.2 under ``lee2008_regressions``).

When a case is loaded, the records that set the same keys form a group, and of each group one
record applies, whole: the one whose configuration the run has (after the ``--set`` overrides; of
several, the last in the file, so that an appended calibration supersedes). A key given as an
override keeps the override. When no record of a group matches, the closest one (fewest differing
configuration keys) is used and a `CalibrationWarning` names the keys that differ and
``rotarydryer calibrate``: the run is outside the configuration its coefficients were fitted in.
A record fitted under the other transport law (its ``transport.parameter_source`` differs from the
run's) is never used: its values are coefficients of a law the run does not evaluate.
A record's ``case`` (the meta.title of the case it was fitted for) must be the case's, and its
``format`` the one this version reads.

Keys of a record's ``values``: any override key (``thermal.area_scale``) or a field of one
``[[tests]]`` row, ``tests.<test>.<field>`` (``tests.4.solids_velocity``).
"""

import math
import warnings
from collections.abc import Mapping
from typing import Any, Optional, Union

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

__all__ = ["CalibrationRecord", "CalibrationData", "CalibrationWarning", "apply_calibrations", "applied_calibrations",
           "configuration_value", "NONE_VALUE", "select_calibrations", "PredictiveRangeWarning", "TEST_KEY_PREFIX", "record_problems"]

#: prefix of a record value that sets a field of one [[tests]] row: tests.<test>.<field>
TEST_KEY_PREFIX = "tests."
#: fields of a [[tests]] row a calibration may set (fitted or unmeasured inputs of that test)
TEST_FIELDS = ("solids_velocity", "dispersion", "gas_flow", "fouling")

_ConfigValue = Union[bool, int, float, str, None]


class CalibrationWarning(UserWarning):
    """A run uses calibrated values outside the model configuration they were fitted in."""


class PredictiveRangeWarning(CalibrationWarning):
    """A predictive-law run outside the operating range its coefficients were calibrated on (speed,
    Froude number, fill, feed moisture: the material's ``[transport]`` ``calibrated_*`` ranges)."""


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, defer_build=True)


class CalibrationData(_Strict):
    """One data set a calibration was fitted to, with its weight (1/sigma^2 of each point)."""
    name: str = Field(min_length=1, max_length=200, description="data set, e.g. 'ajayi2011_test4' or 'test4.gas_outlet_temperature'")
    response: str = Field(default="", max_length=200, description="what was compared: tracer E(t), mrt, gas_outlet_temperature, ...")
    sigma: Optional[float] = Field(default=None, gt=0, description="measurement standard deviation (the response's unit)")
    unit: str = Field(default="", max_length=40)
    n_points: Optional[int] = Field(default=None, ge=1)
    source: str = Field(default="", max_length=400)


class Correlation(_Strict):
    keys: list[str] = Field(max_length=200)
    matrix: list[list[float]]

    @model_validator(mode="after")
    def _square(self):
        n = len(self.keys)
        if len(self.matrix) != n or any(len(r) != n for r in self.matrix):
            raise ValueError(f"correlation.matrix must be {n} x {n} (one row and column per key of correlation.keys)")
        return self


class CalibrationRecord(_Strict):
    """A calibration: values of case keys fitted to named data, in a stated model configuration."""
    format: int = Field(default=1, description="version of the record format (this software reads 1)")
    name: str = Field(min_length=1, max_length=200)
    case: str = Field(default="", max_length=400, description="the case it was fitted for (its meta.title)")
    description: str = Field(default="", max_length=2000)
    configuration: dict[str, _ConfigValue] = Field(default={}, max_length=50, description="case keys and the values "
                                                   "the calibration holds for (e.g. geometry.method = 'exact')")
    values: dict[str, Union[bool, float, str]] = Field(min_length=1, max_length=1000, description="fitted values of case keys "
                                     "(tests.<test>.<field> for a [[tests]] row)")
    held: list[str] = Field(default=[], max_length=1000, description="keys of values that were not fitted but held "
                            "at the run's value (those of the calibration this one supersedes): a record applies "
                            "whole, so it carries every key of its group")
    intervals: dict[str, list[float]] = Field(default={}, max_length=1000, description="95 % interval [low, high] of values")
    interval_method: str = Field(default="", max_length=100, description="wald | profile | published")
    correlation: Optional[Correlation] = None
    data: list[CalibrationData] = Field(default=[], max_length=1000)
    method: str = Field(default="", max_length=200, description="estimator (e.g. weighted least squares)")
    objective: Optional[float] = Field(default=None, ge=0)
    n_evaluations: Optional[int] = Field(default=None, ge=0)
    software_version: str = Field(default="", max_length=50)
    date: str = Field(default="", max_length=40)
    source: str = Field(default="", max_length=1000, description="who fitted it: this software, or the publication")

    @field_validator("intervals")
    @classmethod
    def _pairs(cls, v):
        for k, iv in v.items():
            if len(iv) != 2 or not (math.isfinite(iv[0]) and math.isfinite(iv[1])) or iv[0] > iv[1]:
                raise ValueError(f"intervals.{k} = {iv!r} must be [low, high] with low <= high")
        return v

    @field_validator("format")
    @classmethod
    def _format(cls, v):
        if v != 1:
            raise ValueError(f"calibration record format {v} is not the format 1 this version of rotarydryer reads")
        return v

    @model_validator(mode="after")
    def _consistent(self):
        extra = sorted(set(self.intervals) - set(self.values))
        if extra:
            raise ValueError(f"intervals of {', '.join(extra)} but no value of them in values")
        extra = sorted(set(self.held) - set(self.values))
        if extra:
            raise ValueError(f"held keys {', '.join(extra)} are not keys of values")
        if self.correlation is not None:
            extra = sorted(set(self.correlation.keys) - set(self.values))
            if extra:
                raise ValueError(f"correlation.keys {', '.join(extra)} are not keys of values")
        return self


def _split_test_key(key: str) -> tuple[int, str] | None:
    """(test, field) of ``tests.<test>.<field>``, None for another key."""
    if not key.startswith(TEST_KEY_PREFIX):
        return None
    parts = key.split(".")
    if len(parts) != 3 or not parts[1].lstrip("-").isdigit():
        raise ValueError(f"calibration key {key!r} must be tests.<test number>.<field>")
    return int(parts[1]), parts[2]


def record_problems(record: CalibrationRecord, valid_keys, tests: list, where: str, title: str = "") -> list[str]:
    """What in ``record`` does not fit the case: another case's record, keys it cannot have, tests it
    does not have."""
    problems = []
    if record.case and title and record.case != title:
        problems.append(f"{where}: a calibration of case {record.case!r}, not of this case ({title!r})")
    numbers = {t.get("test") if isinstance(t, dict) else getattr(t, "test", None) for t in tests}
    for key in record.values:
        tk = _split_test_key(key)
        if tk is not None:
            test, fld = tk
            if fld not in TEST_FIELDS:
                problems.append(f"{where}.values: {key!r}: a calibration sets {', '.join(TEST_FIELDS)} of a "
                                "[[tests]] row")
            elif test not in numbers:
                problems.append(f"{where}.values: {key!r}: the case has no [[tests]] row test = {test} "
                                f"(tests: {', '.join(str(n) for n in sorted(x for x in numbers if x is not None)) or 'none'})")
        elif key not in valid_keys and not key.startswith("material."):
            problems.append(f"{where}.values: {key!r} is not a key of this case")
    for key in record.configuration:
        if key not in valid_keys and not key.startswith("material."):
            problems.append(f"{where}.configuration: {key!r} is not a key of this case")
    return problems


def _get(raw: dict, key: str, defaults) -> Any:
    node: Any = raw
    for part in key.split("."):
        if not isinstance(node, dict) or part not in node:
            return defaults(key)
        node = node[part]
    return node


def configuration_value(raw: dict, key: str, defaults) -> Any:
    """The run's value of configuration key ``key`` in the raw case ``raw`` (the schema default
    ``defaults(key)`` where the file does not give it)."""
    return _get(raw, key, defaults)


def _coerced(have, want):
    """A --set value (text, before validation) read as the type of the record's value."""
    if not isinstance(have, str) or isinstance(want, str) or want is None:
        return have
    text = have.strip().lower()
    if isinstance(want, bool):
        return {"true": True, "false": False}.get(text, have)
    try:
        value = float(text)
    except ValueError:
        return have
    return int(value) if isinstance(want, int) and value.is_integer() else value


def _is_none(v) -> bool:
    """A configuration value standing for a key left at None: None, or in a record (TOML has no null) "none"
    (NONE_VALUE, what records are written with), "null" or "" (records written before)."""
    return v is None or (isinstance(v, str) and v.strip().lower() in ("", "none", "null"))


def same_value(held, given) -> bool:
    """Does a validated case's value ``held`` equal ``given`` (an override, a --set text read as ``held``'s type;
    numbers to 1e-12)?"""
    return _same(_coerced(given, held), held)


def _same(a, b) -> bool:
    if _is_none(a) or _is_none(b):
        return _is_none(a) and _is_none(b)
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return math.isclose(float(a), float(b), rel_tol=1e-12, abs_tol=0.0)
    return a == b


#: how a record writes a configuration key left at None (TOML has no null); "" and "null" read the same
NONE_VALUE = "none"
#: configuration keys that only matter under the predictive law (ignored in a run without it)
PREDICTIVE_ONLY = ("transport.predictive_flights",)


#: case-wide defaults of the flighted sections: the section's own key of the same name replaces each
SECTION_DEFAULTS = {"transport.n_cells": "n_cells", "drum.n_flights": "n_flights"}


def section_values(doc, key: str) -> list | None:
    """The values of ``key``, a case-wide default of the flighted sections (`SECTION_DEFAULTS`), that every flighted
    section of ``doc`` (a case document, a validated case's ``model_dump()`` or the validated case itself) sets for
    itself; None where one takes the default (or the key is not such a default): the run then uses the key. The one
    statement of that rule: a calibration record's configuration (`_shadowed`) and the unused-key warning of a
    ``--set`` (`rotarydryer.cases.build`) both read it."""
    own = SECTION_DEFAULTS.get(key)
    if not own:
        return None
    mapping = isinstance(doc, Mapping)
    sections = doc.get("sections") if mapping else getattr(doc, "sections", None)
    if not isinstance(sections, (list, tuple)):
        return None

    def get(s, name, default=None):
        return s.get(name, default) if isinstance(s, Mapping) else getattr(s, name, default)

    flighted = [s for s in sections if (isinstance(s, Mapping) or not mapping) and get(s, "kind", "flighted") == "flighted"]
    if not flighted or any(get(s, own) is None for s in flighted):
        return None
    return [get(s, own) for s in flighted]


def _shadowed(raw: dict, key: str, want) -> bool:
    """Does a record's configuration value ``want`` of ``key`` not differ from the run ``raw``, the key being a
    case-wide default every flighted section replaces (`section_values`)? So where the record holds it unset (the
    MMG case's records; its sections B, C, D set their own n_cells) or at every section's own value; a record fitted
    at another value (a section that took it then) still differs."""
    values = section_values(raw, key)
    return values is not None and (_is_none(want) or all(_same(_coerced(v, want), want) for v in values))


def _differences(record: CalibrationRecord, raw: dict, defaults) -> list[tuple[str, Any, Any]]:
    out = []
    predictive = configuration_value(raw, LAW_KEY, defaults) == "predictive"
    for key, want in record.configuration.items():
        if key in PREDICTIVE_ONLY and not predictive:
            continue
        if _shadowed(raw, key, want):
            continue
        have = _coerced(configuration_value(raw, key, defaults), want)
        if not _same(have, want):
            out.append((key, want, have))
    return out


def _set(raw: dict, key: str, value) -> None:
    """Write ``value`` at ``key`` of ``raw``, copying the nested tables it passes (the parsed
    document is shared between loads)."""
    tk = _split_test_key(key)
    if tk is not None:
        test, fld = tk
        rows = [dict(r) if isinstance(r, dict) else r for r in raw.get("tests", [])]
        for r in rows:
            if isinstance(r, dict) and r.get("test") == test:
                r[fld] = value
        raw["tests"] = rows
        return
    *path, fld = key.split(".")
    node = raw
    for part in path:
        nxt = node.get(part)
        nxt = node[part] = dict(nxt) if isinstance(nxt, dict) else {}
        node = nxt
    node[fld] = value


def _fmt(v) -> str:
    if _is_none(v):
        return "none (unset)"
    return repr(v) if isinstance(v, str) else str(v)


def _groups(records: list[CalibrationRecord]) -> list[list[int]]:
    """Indices of the records that set overlapping keys (connected components), in file order: one
    record of each group applies."""
    parent = list(range(len(records)))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    owner: dict[str, int] = {}
    for i, r in enumerate(records):
        for k in r.values:
            if k in owner:
                parent[root(i)] = root(owner[k])
            else:
                owner[k] = i
    out: dict[int, list[int]] = {}
    for i in range(len(records)):
        out.setdefault(root(i), []).append(i)
    return list(out.values())


#: the configuration key that selects the transport law: a record fitted under the other law is not used
LAW_KEY = "transport.parameter_source"


def select_calibrations(records: list[CalibrationRecord], raw: dict, defaults):
    """[(record, differences)] of the records that apply to the run ``raw``: of each group of records
    setting the same keys, the one whose configuration the run has, else the closest (fewest
    differing keys); of equals the last in the file (a record appended later supersedes) with its differences [(key, calibrated value, run value)]."""
    diffs = [_differences(r, raw, defaults) for r in records]
    chosen = []
    for group in _groups(records):
        # a record of the other transport law (transport.parameter_source) holds values this run does not use
        group = [i for i in group if not any(k == LAW_KEY for k, _, _ in diffs[i])]
        if not group:
            continue
        best = min(group, key=lambda i: (len(diffs[i]), -i))
        chosen.append((records[best], diffs[best]))
    return chosen


def applied_calibrations(case, defaults) -> list[CalibrationRecord]:
    """The records of a validated ``case`` that apply to it (`select_calibrations` on its values):
    one of each group of records setting overlapping keys. ``defaults(key)``: a key's schema default."""
    raw = case.model_dump()
    return [rec for rec, _ in select_calibrations(list(case.calibrations), raw, defaults)]


def apply_calibrations(raw: dict, overrides: dict | None, defaults, shown: str, file_raw: dict | None = None,
                       records: list[CalibrationRecord] | None = None, pending: list[str] | None = None) -> list[str]:
    """Write the values of the case's calibrations into ``raw`` (a loaded case document with its
    overrides applied): of each group of records that set the same keys, the one whose
    configuration the run has (the last of several), else the closest one with a `CalibrationWarning` naming the
    keys that differ. A record applies whole; keys in ``overrides`` keep their override. Returns the
    names of the records applied. ``defaults(key)`` gives a key's schema default. With ``file_raw``
    (the document without the overrides), a group whose record the overrides change (e.g. --set
    geometry.method selects the thesis's calibration) is named in a `CalibrationWarning` too:
    the run's coefficients are then not the case's default calibration. ``records``: the validated
    records of ``raw["calibrations"]`` (the case loader checks them once per parsed document). ``pending``: a
    list that receives the `CalibrationWarning` texts instead of their being issued (the case loader issues them
    once the case has validated: a value the schema refuses gets its refusal alone)."""
    def warn(text: str) -> None:
        if pending is None:
            warnings.warn(text, CalibrationWarning, stacklevel=5)      # the caller of apply_calibrations's caller
        else:
            pending.append(text)

    if records is None:
        records = [CalibrationRecord.model_validate(r) for r in raw.get("calibrations") or []]
    given = set(overrides or {})
    used = []
    origin: dict[str, str] = {}
    chosen = select_calibrations(records, raw, defaults)
    if file_raw is not None and given:
        default = {id(r): r for r, _ in select_calibrations(records, file_raw, defaults)}
        groups = _groups(records)
        for rec, diff in chosen:
            if diff or id(rec) in default:
                continue
            group = next(g for g in groups if any(records[i] is rec for i in g))
            was = next((records[i] for i in group if id(records[i]) in default), None)
            if was is None:         # the default run uses no record of this group (another transport law)
                continue
            keys = sorted({k for r in (rec, was) for k in r.configuration
                           if not _same(_coerced(configuration_value(raw, k, defaults), r.configuration[k]),
                                        _coerced(configuration_value(file_raw, k, defaults), r.configuration[k]))})
            if LAW_KEY in keys or any(k in PREDICTIVE_ONLY for k in keys):
                continue        # another transport law chosen: its own record is the one to use
            want = {**was.configuration, **rec.configuration}
            runs = ", ".join(f"{k} = {_fmt(_coerced(configuration_value(raw, k, defaults), want[k]))}" for k in keys)
            warn(f"{shown}: {runs} (set) selects the calibration {rec.name!r} of that configuration in place of the "
                 f"case's default {was.name!r}: the run's {', '.join(list(rec.values)[:3])}"
                 f"{' ...' if len(rec.values) > 3 else ''} are that calibration's")
    for rec, diff in chosen:
        keys = [k for k in rec.values if k not in given]
        if not keys:        # this run's overrides set every value of the record: it applies nothing, says nothing
            continue
        for key in keys:
            _set(raw, key, rec.values[key])
            origin[key] = rec.name
        used.append(rec.name)
        if diff:
            held = ", ".join(f"{k} = {_fmt(w)}" for k, w, _ in diff)
            runs = ", ".join(f"{k} = {_fmt(h)}" for k, _, h in diff)
            shown_keys = ", ".join(keys[:3]) + (f" and {len(keys) - 3} more" if len(keys) > 3 else "")
            warn(f"{shown}: calibration {rec.name!r} was fitted with {held}; this run has {runs}: its values "
                 f"({shown_keys}) may not reproduce the data they were fitted to (refit them for this configuration "
                 "with `rotarydryer calibrate`)")
    raw["__calibrated__"] = origin       # key -> record name, for the messages of the case's validation
    return used
