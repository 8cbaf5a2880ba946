"""``rotarydryer app``: serve the web app (Streamlit) on this machine.

The module is called ``webapp`` and not ``app``: importing a submodule ``rotarydryer.cli.app``
would replace the Typer object ``rotarydryer.cli.app`` (the console-script entry point).
"""

import typer

from .._io import json_text, stop_process
from . import app


@app.command("app", short_help="Start the web app (Streamlit).")
def run_app(
    port: int = typer.Option(8501, help="TCP port."),
    host: str = typer.Option("127.0.0.1", help="Address to listen on (0.0.0.0: reachable from other machines)."),
    headless: bool = typer.Option(True, "--headless/--browser", help="Do not / do open a browser window."),
    print_command: bool = typer.Option(False, "--print-command", help="Print the server command and exit."),
    as_json: bool = typer.Option(False, "--json", help="With --print-command: print it as a JSON list."),
):
    """Start the web app: flight geometry explorer, transport and RTD, tracer fitting.

    Needs Streamlit: pip install streamlit (or the "app" extra of rotarydryer).

    \b
    Examples:
      rotarydryer app                      # http://127.0.0.1:8501
      rotarydryer app --port 8600 --browser
      rotarydryer app --print-command

    Stopping it (Ctrl+C, SIGTERM, SIGHUP) stops the server.
    Exit codes: 0 stopped normally, 2 bad option, 3 Streamlit not installed, else the server's
    (128 + N when signal N ended it).
    """
    import importlib.util

    from ..app import streamlit_command

    if not 0 < port < 65536:
        typer.echo(f"error: port = {port} is outside the allowed range [1, 65535]", err=True)
        raise typer.Exit(2)
    cmd = streamlit_command(port, host, headless)
    if print_command:
        typer.echo(json_text(cmd) if as_json else " ".join(cmd))
        return
    if importlib.util.find_spec("streamlit") is None:
        typer.echo('error: the web app needs Streamlit: pip install "rotarydryer[app]" (or pip install streamlit)',
                   err=True)
        raise typer.Exit(3)
    typer.echo(f"rotarydryer app on http://{host}:{port} (Ctrl+C to stop)")
    raise typer.Exit(serve(cmd))


#: seconds the server gets to stop after a forwarded signal before it is killed
STOP_TIMEOUT_S = 10.0


def serve(cmd: list[str]) -> int:
    """Run the server command ``cmd`` as a child process and return its exit code (128 + N when
    a signal N ended it).

    SIGTERM, SIGINT and SIGHUP sent to this process are forwarded to the server, so stopping
    ``rotarydryer app`` (Ctrl+C, ``kill``, a service manager) stops the server too; when this
    process leaves for any other reason the server is terminated (killed after
    `STOP_TIMEOUT_S` s). Only the main thread can install signal handlers; elsewhere the
    signals are not forwarded (the clean-up still runs)."""
    import signal
    import subprocess
    import threading

    proc = subprocess.Popen(cmd)

    def forward(signum, frame):
        if proc.poll() is None:
            try:
                proc.send_signal(signum)
            except OSError:  # already gone
                pass

    names = ("SIGTERM", "SIGINT", "SIGHUP")
    previous = {}
    if threading.current_thread() is threading.main_thread():
        for name in names:
            sig = getattr(signal, name, None)
            if sig is not None:
                previous[sig] = signal.signal(sig, forward)
    try:
        while True:
            try:
                code = proc.wait()
                break
            except KeyboardInterrupt:  # SIGINT without our handler (not the main thread)
                forward(signal.SIGINT, None)
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        if proc.poll() is None:
            stop_process(proc, STOP_TIMEOUT_S)
    if code < 0:                          # ended by a signal: the shell's convention
        return 128 - code
    return code
