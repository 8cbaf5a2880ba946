"""``rotarydryer app``: serve the web app (Streamlit) on this machine.

The module is called ``webapp`` and not ``app``: importing a submodule ``rotarydryer.cli.app``
would replace the Typer object ``rotarydryer.cli.app`` (the console-script entry point).
"""

from __future__ import annotations

import json

import typer

from . import app


@app.command("app")
def run_app(
    port: int = typer.Option(8501, help="TCP port."),
    host: str = typer.Option("127.0.0.1", help="Address to listen on (0.0.0.0: reachable from other machines)."),
    headless: bool = typer.Option(True, "--headless/--browser", help="Do not / do open a browser window."),
    print_command: bool = typer.Option(False, "--print-command", help="Print the server command and exit."),
    as_json: bool = typer.Option(False, "--json", help="With --print-command: print it as a JSON list."),
):
    """Start the web app: flight geometry explorer, transport and RTD, tracer fitting.

    Needs Streamlit: pip install streamlit (or the "app" extra of rotarydryer).

    Examples:
      rotarydryer app                      # http://127.0.0.1:8501
      rotarydryer app --port 8600 --browser
    Exit codes: 0 stopped normally, 2 bad option, 3 Streamlit not installed, else the server's.
    """
    import importlib.util
    import subprocess

    from ..app import streamlit_command

    if not 0 < port < 65536:
        typer.echo(f"error: port = {port} is outside the allowed range [1, 65535]", err=True)
        raise typer.Exit(2)
    cmd = streamlit_command(port, host, headless)
    if print_command:
        typer.echo(json.dumps(cmd) if as_json else " ".join(cmd))
        return
    if importlib.util.find_spec("streamlit") is None:
        typer.echo('error: the web app needs Streamlit: pip install "rotarydryer[app]" (or pip install streamlit)',
                   err=True)
        raise typer.Exit(3)
    typer.echo(f"rotarydryer app on http://{host}:{port} (Ctrl+C to stop)")
    try:
        code = subprocess.call(cmd)
    except KeyboardInterrupt:
        code = 0
    raise typer.Exit(code)
