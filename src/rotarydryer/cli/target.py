"""``rotarydryer target``: the value of one case input that meets a condition on one output
(e.g. the largest feed rate whose product moisture is at most 0.12)."""

from __future__ import annotations

from typing import Optional

import typer

from .._io import json_text
from ..services.target import run_target
from . import app
from ._common import parse_sets


@app.command("target")
def target_cmd(
    case: str = typer.Argument(..., help="Case name or .toml file."),
    find: str = typer.Option(..., "--find", help="The free input: a case KEY, or KEY=LO,HI with its bounds "
                                                 "(default: 0.25x-4x the case's value, within the key's limits)."),
    such_that: str = typer.Option(..., "--such-that", help="OUTPUT=VALUE, OUTPUT<=VALUE or OUTPUT>=VALUE on a "
                                                           "steady-state output, e.g. product_moisture_kg_kg<=0.12."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Override KEY=VALUE (several allowed)."),
    tol: Optional[float] = typer.Option(None, "--tol", help="Absolute tolerance on the output "
                                                            "(default 1e-4 of the value)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
):
    """Find the value of one case input that meets a target on one steady-state output: the root
    where the output equals the value (Brent's method), or for <= / >= the extreme input of the
    bounds that still meets it (the crossing, else the bound that binds).

    \b
    Examples:
      rotarydryer target ajayi2011_mmg --find operating.feed_rate --such-that product_moisture_kg_kg<=0.12
      rotarydryer target ajayi2011_mmg --find operating.feed_rate=20,40 --such-that product_moisture_kg_kg=0.12 --json

    Exit codes: 0 found, 1 no solution in the bounds (the outputs at both bounds are printed),
    2 bad input or a failed steady state.
    """
    try:
        res = run_target(case, find, such_that, parse_sets(set_), tol)
    except ValueError as exc:
        typer.echo(f"error: {' '.join(str(exc).split())}", err=True)
        raise typer.Exit(2)
    typer.echo(json_text(res.to_dict()) if as_json else res.text())
    if not res.found:
        raise typer.Exit(1)
