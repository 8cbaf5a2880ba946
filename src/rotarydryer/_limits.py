"""The allowed range of every bounded case key: one declaration for the schema and the runtime.

The case schema (`rotarydryer.cases`, ``rotarydryer schema``) takes its pydantic bounds from
`field_bounds`, and the model's own checks (e.g. `rotarydryer.thermal.settings.ThermalSettings.validate`)
call `check_key`, so a value the schema accepts is never refused at run time for its range and
the messages quote the same interval (``docs/errors.md``):

    >>> field_bounds("gas.flow")
    {'ge': 0.0, 'le': 1000.0}
    >>> float(check_key("shell.insulation_thickness", 2.0))
    2.0
    >>> describe_limit("gas.inlet_temperature")
    '(0, 600] degC'

A key's limit is a range of validity of the model or its correlations (or a guard against
nonsense input), documented where the key is declared; the physical feasibility of a whole case
(entrainment, overloaded flights, a burner that cannot reach its set point) is checked where the
model is built, with its reason.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._docblocks import sync_doc_block
from ._validation import _interval, check_range

__all__ = ["Limit", "LIMITS", "MAX_FLIGHTS", "field_bounds", "check_key", "describe_limit", "limits_table", "key_unit",
           "DOC_BEGIN", "DOC_END"]

#: flights per drum or section (the case keys drum.n_flights and sections.n_flights, a flight profile's n_flights,
#: ``rotarydryer flight --n-flights``)
MAX_FLIGHTS = 1000


@dataclass(frozen=True)
class Limit:
    """An interval: ``low``/``high`` (infinite for none), each end closed when its flag is set."""

    low: float = -math.inf
    high: float = math.inf
    low_inclusive: bool = False
    high_inclusive: bool = False
    unit: str = ""

    def field(self) -> dict:
        """pydantic ``Field`` keyword arguments (ge/gt, le/lt) of this interval."""
        out: dict[str, float] = {}
        if math.isfinite(self.low):
            out["ge" if self.low_inclusive else "gt"] = self.low
        if math.isfinite(self.high):
            out["le" if self.high_inclusive else "lt"] = self.high
        return out


def _c(low, high, unit=""):        # closed [low, high]
    return Limit(float(low), float(high), True, True, unit)


def _co(low, high, unit=""):       # [low, high)
    return Limit(float(low), float(high), True, False, unit)


def _oc(low, high, unit=""):       # (low, high]
    return Limit(float(low), float(high), False, True, unit)


def _o(low, high, unit=""):        # (low, high)
    return Limit(float(low), float(high), False, False, unit)


#: the range of each bounded scalar case key (``[[tests]]`` fields use the key they set)
LIMITS: dict[str, Limit] = {
    # drum and operating point
    "drum.radius": _oc(0, 20, "m"),
    "drum.length": _oc(0, 200, "m"),
    "drum.slope": _co(0, 45, "deg"),
    "operating.feed_rate": _oc(0, 1000, "kg/s"),
    # a drum turning slower than 0.1 rev/min does not cascade its solids on any time scale of a run (plants 1-10,
    # lab drums from 0.5): 1e-9 rev/min in a schedule left the dynamics integrating for minutes
    "operating.rpm": _c(0.1, 60, "rev/min"),
    "operating.feed_moisture": _co(0, 1, "kg/kg wet"),
    "operating.feed_temperature": _co(0, 99, "degC"),
    # gas
    "gas.flow": _c(0, 1000, "kg/s"),
    "gas.inlet_temperature": _oc(0, 600, "degC"),
    "gas.inlet_humidity": _co(0, 0.2, "kg/kg wet gas"),
    "gas.leak_air_flow": _c(0, 1000, "kg/s"),
    "gas.feed_temperature": _co(0, 99, "degC"),
    "gas.recycle_fraction": _co(0, 1),
    # site: altitude of the standard atmosphere (rotarydryer.properties.humid_air.standard_atmosphere_pressure),
    # inside the pressure range of the humid-air properties (50-200 kPa: 5000 m gives 54 kPa)
    "site.altitude": _c(-500, 5000, "m"),
    # shell
    "shell.ambient_temperature": _o(-40, 60, "degC"),
    "shell.ambient_humidity": _c(0, 0.3, "kg/kg dry air"),
    "shell.scale_thickness": _c(0, 0.5, "m"),
    "shell.insulation_thickness": _c(0, 2.0, "m"),
    "shell.loss_factor": _c(0, 1000),
    "shell.inner_radius": _oc(0, 20, "m"),
    "shell.thickness": _oc(0, 0.5, "m"),
    "shell.max_temperature": _oc(0, 1500, "degC"),
    # heat-and-mass model
    "thermal.area_scale": _c(0, 100),
    "thermal.design_load_smoothing": _c(0, 0.1),
    "thermal.discharge_cooling_ntu": _c(0, 50),
    "thermal.fouling": _c(0, 0.95),
    # solids transport ([transport], [[parameter_sets]], [[tests]] fits, [geometry]); the runtime checks of
    # rotarydryer.transport (models, sections, forward_step, core_variants, ajayi, ajayi_predictive) read these
    "transport.fouling": _c(0, 0.95),
    "transport.n_cells": _c(1, 100000),
    "particle_size.classes": _c(1, 20),
    "particle_size.d63": Limit(0.0, 0.2, False, True, "m"),
    "particle_size.spread": _c(0.1, 20),
    "particle_size.d50": Limit(0.0, 0.2, False, True, "m"),
    "particle_size.sigma_g": Limit(1.0, 10.0, False, True),
    "transport.unflighted_cells": _c(2, 100000),
    # inf: no kilning (library callers only); below 0.1 s (fits and Lee's parameter sets: 8.7-10 s) the kilning
    # outruns every other flow and 1e-30 s stopped the transport's integration on a step-size error
    "transport.kiln_time": Limit(0.1, math.inf, True, True, "s"),
    "transport.backmix": _c(0, 1),
    "transport.drag_reduction": _co(0, math.inf),
    "transport.curtain_velocity_ratio": _c(0, 1),
    "transport.curtain_coefficient": _co(0, 1e4),
    "transport.step_factor": _o(0, 100),
    "transport.velocity_coefficient": _oc(0, 100),
    "transport.dispersion_coefficient": _c(0, 1e4),
    "transport.core_fraction": _c(0, 10),
    "transport.core_time": _oc(0, 1e6, "s"),
    "transport.passive_rate": _co(0, math.inf, "1/s"),
    "transport.exchange_rate": _o(0, math.inf, "1/s"),
    "transport.return_rate": _o(0, math.inf, "1/s"),
    "transport.kiln_rate": _co(0, math.inf, "1/s"),
    # axial solids velocity of a rolling bed or kilning (fits 0.01-0.03 m/s): 10 m/s is far past any drum; 1e15 m/s
    # overflowed the unflighted section's rates and hung the solve
    "transport.solids_velocity": _oc(0, 10, "m/s"),
    # axial dispersion of unflighted sections (fits 1e-3-2.3e-3 m^2/s): at 100 m^2/s a drum's solids are fully mixed
    # (Peclet number below 1e-2); 1e15 made the transport's matrix singular
    "transport.dispersion": _c(0, 100, "m^2/s"),
    "transport.product_moisture": _co(0, 1, "kg/kg wet"),
    "transport.moisture_scale": _o(0, math.inf),
    "geometry.design_load_factor": _o(0, math.inf),
}


def field_bounds(key: str) -> dict:
    """The pydantic ``Field`` bounds of ``key`` (a key of `LIMITS`)."""
    return LIMITS[key].field()


def check_key(key: str, value: Any, name: str | None = None):
    """``value`` checked against the range of ``key`` (message names ``name`` or the key, the value
    and the interval); returns it as a float array (0-d for a scalar), as
    `rotarydryer._validation.check_range`."""
    lim = LIMITS[key]
    if lim.high == math.inf and lim.high_inclusive and isinstance(value, (int, float)) and value == math.inf:
        return np.asarray(math.inf)       # a closed infinite end (transport.kiln_time = inf: no kilning)
    return check_range(name or key, value, lim.low, lim.high, low_inclusive=lim.low_inclusive,
                       high_inclusive=lim.high_inclusive, unit=lim.unit)


def describe_limit(key: str) -> str:
    """The interval of ``key`` as the error messages print it, e.g. ``'[0, 1000] kg/s'``."""
    lim = LIMITS[key]
    return _interval(lim.low, lim.high, lim.low_inclusive, lim.high_inclusive, lim.unit)


#: markers of the generated table of :data:`LIMITS` in ``docs/errors.md``
DOC_BEGIN, DOC_END = "<!-- limits:begin (generated: python -m rotarydryer._limits --update-docs) -->", \
    "<!-- limits:end -->"


def limits_table() -> str:
    """The Markdown table of every key of `LIMITS` and its allowed range (``docs/errors.md``)."""
    rows = ["| key | allowed range |", "|---|---|"]
    rows += [f"| `{key}` | `{describe_limit(key)}` |" for key in sorted(LIMITS)]
    return "\n".join(rows) + "\n"


def _update_docs(doc) -> str:
    """Rewrite the generated block of ``doc`` (``docs/errors.md``) with `limits_table`."""
    return sync_doc_block(doc, DOC_BEGIN, DOC_END, limits_table(), update=True, script="-m rotarydryer._limits")


if __name__ == "__main__":      # python -m rotarydryer._limits --update-docs [docs/errors.md]
    import sys

    args = sys.argv[1:]
    if not args or args[0] != "--update-docs":
        print(limits_table(), end="")
    else:
        print(_update_docs(args[1] if len(args) > 1 else "docs/errors.md"))


#: units of fitted parameters that are not case keys, and of the [[tests]] fields
_OTHER_UNITS = {"scale": "signal x s", "baseline": "signal", "gas_flow": "kg/s", "fouling": "-"}


def key_unit(name: str) -> str:
    """The unit of a case key or fitted parameter (the tables of ``fit`` and ``calibrate``): a case
    key's (`LIMITS`; ``-`` for a dimensionless key), a ``tests.N.FIELD`` the key FIELD sets, the
    tracer scale or baseline; ``?`` where none is declared.

    >>> key_unit("gas.flow"), key_unit("tests.4.solids_velocity"), key_unit("tests.*.fouling")
    ('kg/s', 'm/s', '-')
    """
    field = name.split(".")[-1]
    for key in (name, f"transport.{field}" if name.startswith("tests.") else None):
        if key in LIMITS:
            return LIMITS[key].unit or "-"
    if field in _OTHER_UNITS:
        return _OTHER_UNITS[field]
    for key, lim in LIMITS.items():      # e.g. a key declared in another block
        if key.endswith("." + field) and lim.unit:
            return lim.unit
    return "?"
