"""Command-line interface: ``rotarydryer COMMAND ...``.

Each command lives in its own module in this package and registers itself on
:data:`app`; this file only creates the app and imports the command modules.
Heavy libraries (SciPy, Matplotlib) are imported inside the commands so that
``rotarydryer --help`` starts fast.
"""

from __future__ import annotations

import typer

app = typer.Typer(
    name="rotarydryer",
    help="Flighted rotary dryer simulator: flight geometry, solids transport, drying.",
    no_args_is_help=True,
    add_completion=False,
)



def _version(value: bool):
    if value:
        from .. import __version__

        typer.echo(f"rotarydryer {__version__}")
        raise typer.Exit()


@app.callback()
def main(
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                 help="Print the version and exit."),
):
    """Flighted rotary dryer simulator (rotarydryer)."""


# Command modules (each registers its commands on ``app`` at import time).
from . import balance, correlations, fit, flight, lab, report, rtdfit, schema, simulate, sweep, webapp  # noqa: E402,F401

__all__ = ["app"]
