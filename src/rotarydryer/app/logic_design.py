"""Logic of the web app's "Design" page: size a dryer for a duty (``rotarydryer design``).

Plain functions (no Streamlit): the duty and the search options are checked by the same
functions as the command line (`rotarydryer.services.design.design_duty`,
`rotarydryer.services.design.design_limits`), so a bad value gives the CLI's message; the
search is `rotarydryer.design.design` (or `design_verified`
with the coupled-model check).  Units: SI, degC, moistures kg/kg wet.
"""

from __future__ import annotations

import re

from ..services.design import design_duty, design_limits
from .logic import png

__all__ = ["DESIGN_PRESETS", "SEARCH_EFFORT", "design_materials", "duty_defaults", "design_view",
           "progress_fraction"]

#: preset duties of ``rotarydryer design --duty``
DESIGN_PRESETS = ("raw_sugar", "mmg")
#: search effort -> (differential-evolution generations, population factor); "full" = the CLI's
SEARCH_EFFORT = {"quick": (20, 8), "full": (60, 12)}


def design_materials() -> list[str]:
    """Names of the library's materials (``rotarydryer.properties.materials``)."""
    from ..properties.materials import list_materials

    return list(list_materials())


def duty_defaults(preset: str) -> dict:
    """The fields of a preset duty (`DESIGN_PRESETS`) as the page's inputs show them."""
    d = design_duty(preset)
    return dict(material=d.material, feed=d.feed_rate, moisture_in=d.moisture_in, moisture_out=d.moisture_out,
                gas_in=d.gas_inlet_temperature, gas_flow=d.gas_flow, ntu=d.ntu, direction=d.direction,
                feed_temperature=d.feed_temperature, max_fuel=d.max_fuel_rate)


def design_view(preset: str | None = "raw_sugar", *, material=None, feed=None, moisture_in=None, moisture_out=None,
                gas_in=None, gas_flow=None, ntu=None, direction=None, feed_temperature=None, max_fuel=None,
                objective="volume", speed_fraction=0.5, entrainment_fraction=1.0, gas_velocity_max=5.0,
                fill_max=0.15, design_load_tolerance=0.15, ld_min=4.0, ld_max=10.0, d_min=0.5, d_max=6.0,
                ua_factor=1.0, effort="quick", verify=False, rounds=5, top=8, images=True, progress=None) -> dict:
    """Size a dryer for a duty, as ``rotarydryer design`` does (same options, same checks).

    ``preset`` (`DESIGN_PRESETS` or None) is overridden by the duty options given;
    ``gas_flow=None`` with ``ntu`` lets the gas flow follow from the energy balance.
    ``effort``: `SEARCH_EFFORT` (``"full"`` is the CLI's search).  Returns
    ``{"best": row dict, "binding": [...], "constraints": [(name, value, sense, limit, slack)],
    "table": ranked rows, "values": {...}, "verification": dict or None, "evaluations": int,
    "seconds": float, "cross_section": png}``.  An infeasible duty raises
    `rotarydryer.design.InfeasibleDuty` (a ``ValueError``) naming the blocking constraint."""
    from .. import design as D

    if effort not in SEARCH_EFFORT:
        raise ValueError(f"effort = {effort!r} is not one of {', '.join(SEARCH_EFFORT)}")
    limits = design_limits(objective, speed_fraction, entrainment_fraction, gas_velocity_max, fill_max,
                           design_load_tolerance, ld_min, ld_max, d_min, d_max, ua_factor, top, rounds)
    duty = design_duty(preset, material, feed, moisture_in, moisture_out, gas_in, gas_flow, ntu, direction,
                       feed_temperature, max_fuel)
    maxiter, popsize = SEARCH_EFFORT[effort]
    if verify:
        res, ver = D.design_verified(duty, limits, objective=objective, rounds=rounds, top=top, maxiter=maxiter,
                                     popsize=popsize, progress=progress)
    else:
        res, ver = D.design(duty, limits, objective=objective, top=top, maxiter=maxiter, popsize=popsize,
                            progress=progress), None
    b = res.best
    out = {
        "best": b.row(),
        "binding": b.binding(),
        "constraints": [(k, c[0], c[2], c[1], -c[3]) for k, c in b.constraints.items()],
        "table": res.table(top),
        "values": dict(b.values),
        "verification": ver,
        "evaluations": res.evaluations,
        "seconds": res.seconds,
        "objective": res.objective,
        "duty": dict(material=duty.material, feed_rate=duty.feed_rate, moisture_in=duty.moisture_in,
                     moisture_out=duty.moisture_out, gas_inlet_temperature=duty.gas_inlet_temperature,
                     direction=duty.direction),
    }
    if images:
        from ..geometry import FlightedDrum, TwoSectionFlight
        from ..report.plots import draw_cross_section

        drum = FlightedDrum(b.diameter_m / 2, b.n_flights, TwoSectionFlight(s1=b.s1_m, s2=b.s2_m, alpha1=90.0,
                                                                             alpha2=b.alpha2_deg))
        out["cross_section"] = png(draw_cross_section(drum, D._DutyModel(duty).repose))
    return out


_GENERATION = re.compile(r"design: generation (\d+)/(\d+)")


def progress_fraction(message: str) -> float | None:
    """The fraction of one search done when `rotarydryer.design.design` reports ``message``:
    the generations 90 %, the local refinement the rest; None for a coupled-model check (with
    ``verify`` each round's search starts again at 0).

    >>> progress_fraction("design: generation 10/20, 90 evaluations, 12 feasible, best volume 101.2")
    0.45
    >>> progress_fraction("design: local refinement (Nelder-Mead)")
    0.9
    """
    text = str(message)
    if text.startswith("design: local refinement"):
        return 0.9
    m = _GENERATION.match(text)
    if m is None:
        return None
    return round(0.9 * min(1.0, int(m.group(1)) / max(int(m.group(2)), 1)), 4)
