"""``rotarydryer validate``: the cases against their measured and published numbers."""

from pathlib import Path
from typing import Optional

import typer

from .._io import json_text
from . import app
from ._common import Progress, check_out_dir, parse_sets


def _one_line(exc: BaseException) -> str:
    """A multi-line message (e.g. a case's list of problems) on one line."""
    parts = [p.strip() for p in str(exc).strip().splitlines() if p.strip()]
    return " ".join(parts) if parts else type(exc).__name__


@app.command("validate", short_help="Compare cases with measured and published numbers.")
def validate(
    cases: Optional[list[str]] = typer.Argument(None, metavar="CASE",
                                               help="Case names or .toml files (default: every shipped case)."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Override KEY=VALUE on top of every item's own "
                                             "overrides, e.g. thermal.area_scale=2.6."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    out: Optional[Path] = typer.Option(None, help="Directory for validation.json and validation.md."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress lines on stderr."),
    tolerances: Optional[Path] = typer.Option(None, "--tolerances", help="Your own tolerances (TOML): "
                                              "[defaults.<quantity>] tables with tolerance, kind and reason replace "
                                              "the shipped ones (rotarydryer/data/validation.toml) for the items "
                                              "derived from the cases' data."),
):
    """Compare cases with every measured or published number they have, each against a tolerance
    written beforehand (rotarydryer/data/validation.toml: tolerance, kind, reason, source).

    Prints item, measured, model, error, tolerance and status; known misses are listed with their
    figure and reason and do not fail the run.

    Exit codes: 0 every item within its tolerance (known misses aside), 1 an item outside it,
    2 bad input (unknown case, bad --set key or value, bad --out).

    \b
    Example:
      rotarydryer validate ajayi2011_mmg --out validation/
      rotarydryer validate lee2008_invicta --json
      rotarydryer validate song2003_ottawa --tolerances my_tolerances.toml

    \b
    Your own product-moisture tolerance, my_tolerances.toml:
      [defaults.product_moisture]
      tolerance = 0.3
      kind = "relative"
      reason = "our grab samples: 30 % of the measured moisture"
      source = "plant laboratory"
    """
    from ..validate import run_validation

    try:
        sets = parse_sets(set_)
        check_out_dir("--out", out)
        with Progress("validate", quiet=quiet) as bar:
            report = run_validation(cases or None, sets, progress=bar.message, tolerances=tolerances)
    except ValueError as exc:
        typer.echo(f"error: {_one_line(exc)}", err=True)
        raise typer.Exit(2)
    result = report.to_dict()
    if out is not None:
        from .._io import output_set, write_text_atomic

        files = [out / "validation.json", out / "validation.md"]
        try:
            with output_set(out):               # both files or neither: a failure keeps the previous set
                write_text_atomic(files[0], json_text(result, indent=1))
                write_text_atomic(files[1], report.markdown())
        except OSError as exc:
            typer.echo(f"error: --out {out}: {exc}", err=True)
            raise typer.Exit(2)
        result["files"] = [str(f) for f in files]
    if as_json:
        typer.echo(json_text(result))
    else:
        typer.echo(report.text())
        if out is not None:
            typer.echo(f"files: {', '.join(result['files'])}")
    raise typer.Exit(0 if report.passed else 1)
