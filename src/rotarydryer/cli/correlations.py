"""``rotarydryer mrt``: mean residence time of solids by the published correlations."""

import math
from typing import Optional

import typer

from .._io import json_text
from ..services._options import check_option
from . import app


@app.command("mrt", short_help="Mean residence time by the published correlations.")
def mrt(
    length: float = typer.Option(..., help="Dryer length L, m."),
    diameter: float = typer.Option(..., help="Dryer diameter D, m."),
    slope: float = typer.Option(..., help="Dryer slope s, m/m."),
    rpm: float = typer.Option(..., help="Rotation speed n, rev/min."),
    particle_size: Optional[float] = typer.Option(None, help="Sauter mean particle size, m."),
    gas_mass_flux: Optional[float] = typer.Option(None, help="Gas mass flux G, kg/(m^2 s)."),
    solids_mass_flux: Optional[float] = typer.Option(None, help="Dry-solids mass flux F, kg/(m^2 s)."),
    gas_flow: str = typer.Option("co-current", help="co-current | counter-current."),
    repose_angle: Optional[float] = typer.Option(None, help="Dry angle of repose, deg (Sullivan 1927)."),
    method: Optional[str] = typer.Option(None, help="Evaluate only this method (default: all applicable)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object instead of the table."),
):
    """Mean residence time (s and min) by every correlation the inputs allow (Song 2003 ch. 2 and 4).

    \b
    Example:
      rotarydryer mrt --length 3.05 --diameter 0.305 --slope 0.083 --rpm 5 --particle-size 444e-6 --gas-mass-flux 0.5 --solids-mass-flux 0.7
    """
    import warnings

    from .._validation import check_choice
    from ..correlations import mean_residence_time, mean_residence_time_methods
    from ..correlations.residence_time import MEAN_RESIDENCE_TIME_METHODS, missing_inputs

    try:  # options shared by every method: a wrong one is bad input, not a per-method error
        check_choice("gas_flow", gas_flow, ("co-current", "counter-current"))
        # each given number finite and of its sign (a NaN or negative flux was a per-method row, exit 0, where the
        # other methods did not use it); a method's own validity range stays that method's row
        for opt, v, low, low_inclusive, high, unit in (
                ("--length", length, 0.0, False, math.inf, "m"), ("--diameter", diameter, 0.0, False, math.inf, "m"),
                ("--slope", slope, 0.0, True, math.inf, "m/m"), ("--rpm", rpm, 0.0, False, math.inf, "rev/min"),
                ("--particle-size", particle_size, 0.0, False, math.inf, "m"),
                ("--gas-mass-flux", gas_mass_flux, 0.0, True, math.inf, "kg/(m^2 s)"),
                ("--solids-mass-flux", solids_mass_flux, 0.0, False, math.inf, "kg/(m^2 s)"),
                ("--repose-angle", repose_angle, 0.0, False, 90.0, "deg")):
            if v is not None:
                check_option(opt, v, low, high, unit=unit, low_inclusive=low_inclusive)
        inputs = dict(length=length, diameter=diameter, slope=slope, rpm=rpm, particle_size=particle_size,
                      gas_mass_flux=gas_mass_flux, solids_mass_flux=solids_mass_flux, gas_flow=gas_flow,
                      repose_angle=repose_angle)
        if method:
            check_choice("method", method, MEAN_RESIDENCE_TIME_METHODS)
            missing = missing_inputs(method, **inputs)
            if missing:
                raise ValueError(f"--method {method} needs {', '.join('--' + k.replace('_', '-') for k in missing)}")
    except ValueError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)
    methods = [method] if method else mean_residence_time_methods(**inputs)
    results = {}
    for m in methods:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                tau = mean_residence_time(method=m, **inputs)
                results[m] = {"tau_s": float(tau), "tau_min": float(tau) / 60.0,
                              "warnings": [str(w.message) for w in caught]}
            except ValueError as exc:      # a non-positive tau: its reason, not the Python keyword's hint
                results[m] = {"error": getattr(exc, "summary", str(exc))}
    if as_json:
        typer.echo(json_text(results, indent=2))
    else:
        from .._display import show

        for m, r in results.items():
            if "error" in r:
                typer.echo(f"{m:34s} error: {r['error']}")
                continue
            typer.echo(f"{m:34s} {show(r['tau_s'], 'time'):>12}")     # the display unit of time (--units)
            for w in r["warnings"]:
                typer.echo(f"    warning: {w}")
    if results and all("error" in r for r in results.values()):
        # every correlation refused the input: bad input, said once on stderr naming the option
        said = list(dict.fromkeys(_as_option(r["error"], inputs) for r in results.values()))
        typer.echo(f"error: every correlation refused the input: {'; '.join(said)}", err=True)
        raise typer.Exit(2)


def _as_option(message: str, inputs: dict) -> str:
    """``message`` of a correlation with the input it names first (``slope = 3 m/m ...``) as its option (``--slope``)."""
    name = message.split(" = ", 1)[0]
    return f"--{name.replace('_', '-')}{message[len(name):]}" if name in inputs else message
