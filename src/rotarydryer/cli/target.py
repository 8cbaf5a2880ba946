"""``rotarydryer target``: the value of one case input that meets a condition on one output
(e.g. the largest feed rate whose product moisture is at most 0.12)."""

from typing import Optional

import typer

from .._io import json_text
from ..services.target import run_target, unreachable_message
from . import app
from ._common import parse_sets


@app.command("target", short_help="Input value(s) meeting targets on steady-state outputs, or an optimum.")
def target_cmd(
    case: str = typer.Argument(..., help="Case name or .toml file."),
    find: list[str] = typer.Option(..., "--find", help="A free input: a case KEY, or KEY=LO,HI with its bounds "
                                                       "(default: 0.25x-4x the case's value, within the key's "
                                                       "limits). Repeat for several."),
    such_that: Optional[list[str]] = typer.Option(None, "--such-that", help="OUTPUT=VALUE, OUTPUT<=VALUE or "
                                                  "OUTPUT>=VALUE on a steady-state output, e.g. "
                                                  "product_moisture_kg_kg<=0.12. Repeat for several."),
    maximize: Optional[str] = typer.Option(None, "--maximize", help="Largest value of a free input KEY or an "
                                           "OUTPUT, under the --such-that conditions."),
    minimize: Optional[str] = typer.Option(None, "--minimize", help="Smallest value of a free input KEY or an "
                                           "OUTPUT, under the --such-that conditions."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Override KEY=VALUE (several allowed)."),
    tol: Optional[float] = typer.Option(None, "--tol", help="Absolute tolerance on the outputs "
                                                            "(default 1e-4 of each target value)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
):
    """Find the value of a case input that meets a target on a steady-state output: the root
    where the output equals the value (Brent's method), or for <= / >= the extreme input of the
    bounds that still meets it (the crossing, else the bound that binds). Several equality targets
    with as many free inputs: Newton's method. --maximize/--minimize: the optimum of an input or an
    output with the --such-that conditions as constraints (the binding ones are named).

    \b
    Examples:
      rotarydryer target ajayi2011_mmg --find operating.feed_rate --such-that "product_moisture_kg_kg<=0.12"
      rotarydryer target ajayi2011_mmg --find operating.feed_rate=20,40 --such-that product_moisture_kg_kg=0.12 --json
      rotarydryer target ajayi2011_mmg --find operating.feed_rate=20,60 --maximize operating.feed_rate --such-that "product_moisture_kg_kg<=0.12" --such-that "gas_outlet_dew_point_margin_K>=10"

    Exit codes: 0 found; 1 a steady state failed inside the bounds, or the search for several
    targets stalled; 2 bad input or a target no value in the bounds meets (the outputs at the
    bounds are printed).
    """
    try:
        res = run_target(case, find, such_that, parse_sets(set_), tol, maximize, minimize)
    except ValueError as exc:
        typer.echo(f"error: {' '.join(str(exc).split())}", err=True)
        raise typer.Exit(1 if getattr(exc, "reason", None) == "no_steady_state" else 2)
    typer.echo(json_text(res.to_dict()) if as_json else res.text())
    if not res.found:
        typer.echo(f"error: {unreachable_message(res)}", err=True)
        raise typer.Exit(1 if getattr(res, "kind", "") == "targets" else 2)     # a stalled search: the solver's
