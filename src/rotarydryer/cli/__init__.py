"""Command-line interface: ``rotarydryer COMMAND ...``.

Each command lives in its own module in this package and registers itself on
`app`; this file only creates the app and imports the command modules.
Heavy libraries (SciPy, Matplotlib) are imported inside the commands so that
``rotarydryer --help`` starts fast.
"""

import contextlib
import functools
import gc
import os
import re
import signal
import sys
import threading
import warnings

from .._startup import defer_numpy_submodules, raise_gc_threshold
from .._threads import command_blas_threads

command_blas_threads()      # before NumPy loads (the commands import it): one BLAS thread, no pool to start
defer_numpy_submodules()    # NumPy's unused submodules are not loaded when SciPy copies its namespace
raise_gc_threshold()        # the imports' half a million objects are not walked 157 times by the collector

import click  # noqa: E402
import typer  # noqa: E402
import typer.core  # noqa: E402

#: the exceptions of the click that typer runs on (typer 0.2x carries its own copy as typer._click)
_CLICK_ERRORS = getattr(getattr(typer.core, "_click", None), "exceptions", None) or click.exceptions


#: a value of the wrong type for an option, in plain words ("--workers 1.5": the type checker's "Input should be a
#: valid integer, unable to parse string as an integer" became "not a valid integer (a whole number)")
_PLAIN_TYPE_MESSAGES = (
    (re.compile(r"Input should be a valid integer(, unable to parse string as an integer)?"),
     "not a valid integer (a whole number)"),
    (re.compile(r"Input should be a valid number(, unable to parse string as a number)?"), "not a valid number"),
)


def _usage_line(exc, given) -> str:
    """A usage error (a bad option value, a missing argument, an unknown command) on one line: click's message,
    the value given where it does not show it, and where to look (``given``: the command line's words)."""
    msg = " ".join(exc.format_message().split()).rstrip(".")
    for generic, plain in _PLAIN_TYPE_MESSAGES:       # the type checker's words for a value of the wrong type
        msg = generic.sub(plain, msg)
    param = getattr(exc, "param", None)
    value = None
    for i, word in enumerate(given):
        for opt in getattr(param, "opts", ()) if param is not None else ():
            if word == opt and i + 1 < len(given):
                value = given[i + 1]
            elif opt.startswith("--") and word.startswith(opt + "="):
                value = word[len(opt) + 1:]
    if value is not None and repr(value) not in msg:
        msg += f" (got {value!r})"
    if getattr(exc, "ctx", None) is not None:
        where = exc.ctx.command_path
    else:       # an option's parser error names no command: the command line's first word is it
        where = "rotarydryer" + (f" {given[0]}" if given and not given[0].startswith("-") else "")
    return f"{msg}; see '{where} --help'"


class _OneLineUsageError(_CLICK_ERRORS.UsageError):
    """A usage error shown as one ``error: ...`` line on stderr (exit code 2), as every other refusal."""

    def __init__(self, text: str, ctx=None):
        super().__init__(text, ctx)
        self.text = text

    def show(self, file=None):
        typer.echo(f"error: {self.text}", err=True)


def _one_line(exc, given):
    if isinstance(exc, _OneLineUsageError) or type(exc).__name__ == "NoArgsIsHelpError":   # the help text
        return exc
    return _OneLineUsageError(_usage_line(exc, given), getattr(exc, "ctx", None))


def _is_path(param) -> bool:
    """Whether a command's parameter takes a file or directory path (``Path`` or ``Optional[Path]``)."""
    ann = getattr(getattr(param, "type_descriptor", None), "annotation", None)
    return ann is not None and "Path" in str(getattr(ann, "__name__", ann))


def _refuse_empty_paths(group, ctx, given: list) -> None:
    """Refuse a path option given an empty value (``--out ''``, ``--out=``) and an empty path argument: ``Path('')``
    is the current directory, so the outputs landed there unasked (or a file option named the directory). The
    tokens after ``--`` are arguments. Other empty values keep their own messages (``new ''``: not a file name)."""
    if not given:
        return
    cmd = group.get_command(ctx, given[0])
    while hasattr(cmd, "commands") and len(given) > 1:       # a sub-group: lab, dem, ...
        given = given[1:]
        sub = cmd.get_command(ctx, given[0])
        if sub is None:
            return
        cmd = sub
    if cmd is None:
        return
    options = {o: p for p in cmd.params if getattr(p, "opts", None) for o in p.opts if o.startswith("-")}
    takes_value = {o for o, p in options.items() if not getattr(p, "is_flag", False) and getattr(p, "nargs", 1) != 0}
    arguments = [p for p in cmd.params if not any(o.startswith("-") for o in getattr(p, "opts", ()) or ())]
    position = 0
    literal = False                     # after "--": every token is an argument
    i = 1
    while i < len(given):
        tok = given[i]
        if not literal and tok == "--":
            literal = True
        elif not literal and tok.startswith("-"):
            name, eq, value = tok.partition("=")
            if eq:
                if name in options and _is_path(options[name]) and not value.strip():
                    raise _OneLineUsageError(f"{name} is empty; give a path (. for the current directory)")
            elif name in takes_value:
                i += 1                  # its value, whatever it is
                if i < len(given) and _is_path(options[name]) and not given[i].strip():
                    raise _OneLineUsageError(f"{name} is empty; give a path (. for the current directory)")
        else:                           # an argument: the command's next one (the last may take many)
            arg = (arguments[position] if position < len(arguments) else
                   arguments[-1] if arguments and getattr(arguments[-1], "nargs", 1) == -1 else None)
            position += 1
            if arg is not None and _is_path(arg) and not tok.strip():
                raise _OneLineUsageError(f"{arg.name.upper()} is empty; give a path (. for the current directory)")
        i += 1


class _Group(typer.core.TyperGroup):
    """The top-level command group: click's usage errors (three lines, "Usage: ...", the option's message
    without the value given) become one ``error: ...`` line naming the option and the value."""

    def make_context(self, info_name, args, parent=None, **extra):
        given = list(args)
        try:
            return super().make_context(info_name, args, parent=parent, **extra)
        except _CLICK_ERRORS.UsageError as exc:
            raise _one_line(exc, given) from None

    def invoke(self, ctx):
        given = [*getattr(ctx, "_protected_args", []), *ctx.args]
        _refuse_empty_paths(self, ctx, given)
        try:
            return super().invoke(ctx)
        except _CLICK_ERRORS.UsageError as exc:
            raise _one_line(exc, given) from None


app = typer.Typer(
    cls=_Group,
    name="rotarydryer",
    help="Flighted rotary dryer simulator: flight geometry, solids transport, drying.",
    no_args_is_help=True,
    add_completion=False,
    # plain click messages: a usage error is "Error: Invalid value for '--feed': ..." on one line
    # (no box drawing that wraps the option name across lines)
    rich_markup_mode=None,
    pretty_exceptions_enable=False,
)



def _version(value: bool):
    if value:
        from .. import __version__

        typer.echo(f"rotarydryer {__version__}")
        raise typer.Exit()


#: ``--debug``: let exceptions through with their traceback (developers)
DEBUG = {"on": bool(os.environ.get("ROTARYDRYER_DEBUG"))}


@app.callback()
def main(
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                 help="Print the version and exit."),
    debug: bool = typer.Option(False, "--debug", help="Show Python tracebacks (for developers)."),
    units: str = typer.Option(None, "--units", metavar="QUANTITY=UNIT,...",
                              help="Display units of the text output, e.g. moisture=kg/kg,mass_flow=t/h,power=MW "
                                   "(also ROTARYDRYER_UNITS or [display] in ~/.config/rotarydryer/config.toml; "
                                   "JSON and CSV stay SI)."),
):
    """Flighted rotary dryer simulator (rotarydryer)."""
    DEBUG["on"] = bool(debug) or bool(os.environ.get("ROTARYDRYER_DEBUG"))
    from .._display import display_units, set_display_units

    try:        # checked once, before any command: a bad choice is refused even where only JSON is printed
        set_display_units(units)
        display_units()
    except ValueError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)


def error_message(exc: BaseException) -> str:
    """One line (or a short block) for the user: what failed, naming the path or key."""
    if isinstance(exc, MemoryError):
        return ("not enough memory for this run: reduce the model size (cells, time grid, sweep points, "
                "image or file size)")
    if isinstance(exc, OSError) and not isinstance(exc, ValueError):
        where = exc.filename if getattr(exc, "filename", None) else None
        reason = exc.strerror or str(exc) or type(exc).__name__
        return f"{where!s}: {reason}" if where else reason
    text = str(exc).strip()
    if isinstance(exc, KeyError):
        text = f"missing key or column {text}"
    if not text:
        text = type(exc).__name__
    return text


#: a number in a warning's text (its values), for telling warnings of one kind apart from their values; not the
#: digits of a name (zone1, dryer2.toml, flight.s1, fit_test4), which tell warnings of one kind apart
_NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d[\d,]*\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?![\w])")


def _warning_printer():
    """A ``warnings.showwarning`` for one command: each warning reaches the user as one ``warning: ...``
    line on stderr (no source location), and the same text once (a case's range warning raised by both
    the transport and the heat-and-mass builds was printed twice). A warning of one kind that repeats with
    other values (a search's or a sweep's runs: `design --check` printed 1 399 lines of one correlation's
    warning) is shown the first time; ``show.summary()``, at the command's end, counts the others."""
    seen: set[str] = set()
    kinds: dict[tuple, list] = {}        # (category, text without its numbers) -> [first text, others]

    def show(message, category, filename, lineno, file=None, line=None):
        text = " ".join(str(message).split())
        if text in seen:
            return
        seen.add(text)
        kind = kinds.setdefault((category, _NUMBER.sub("#", text)), [text, 0])
        if kind[0] != text:
            kind[1] += 1
            return
        typer.echo(f"warning: {text}", err=True)

    def summary():
        for first, others in kinds.values():
            if others:
                head = first if len(first) <= 90 else first[:87].rstrip() + "..."
                typer.echo(f"warning: {others} more like '{head}' with other values (not shown)", err=True)

    show.summary = summary
    return show


def _guard(func):
    """The CLI failure boundary around a command: the project's errors (ValueError and its
    subclasses), OSError, MemoryError and any other exception become ``error: ...`` on stderr
    and exit code 2; no traceback reaches a user unless ``--debug``."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        try:
            with warnings.catch_warnings():
                printer = None if DEBUG["on"] else _warning_printer()
                if printer is not None:
                    warnings.showwarning = printer
                try:
                    out = func(*args, **kwargs)
                except (typer.Exit, click.exceptions.Exit) as done:
                    # the count of the repeats after a command's last line, unless that line is its error
                    if printer is not None and getattr(done, "exit_code", 0) == 0:
                        printer.summary()
                    raise
                if printer is not None:
                    printer.summary()
                return out
        except (typer.Exit, typer.Abort, click.exceptions.ClickException, click.exceptions.Exit,
                click.exceptions.Abort, SystemExit):
            raise
        except KeyboardInterrupt:
            typer.echo("error: interrupted", err=True)
            raise typer.Exit(130)
        except BrokenPipeError:
            # the reader of the output went away (``| head``): stop quietly, as a shell tool would on SIGPIPE
            # (128 + 13); stdout goes to the null device so the interpreter's last flush does not fail again
            with contextlib.suppress(OSError, ValueError):
                os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            raise typer.Exit(141)
        except BaseException as exc:  # noqa: BLE001 - the boundary
            if DEBUG["on"]:
                raise
            if isinstance(exc, (ValueError, OSError, MemoryError, KeyError, OverflowError)):
                msg = error_message(exc)
            else:
                msg = (f"internal error ({type(exc).__name__}: {error_message(exc)}); please report it "
                       "with the command line (rerun with --debug for the traceback)")
            typer.echo(f"error: {msg}", err=True)
            raise typer.Exit(2)

    return wrapper


def _guard_all(typer_app):
    for info in typer_app.registered_commands:
        if info.callback is not None and not getattr(info.callback, "_guarded", False):
            info.callback = _guard(info.callback)
            info.callback._guarded = True
    for group in typer_app.registered_groups:
        if group.typer_instance is not None:
            _guard_all(group.typer_instance)


# Command modules (each registers its commands on ``app`` at import time).
from . import (  # noqa: E402,F401,E501
    audit,
    balance,
    calibrate,
    control,
    correlations,
    dem,
    design,
    dynamics,
    fit,
    flight,
    fmu,
    lab,
    report,
    rtdfit,
    schema,
    sensitivity,
    simulate,
    sweep,
    target,
    validate,
    webapp,
)

_guard_all(app)


def run() -> None:
    """The ``rotarydryer`` console script (and ``python -m rotarydryer``): `app`, then, as the process
    ends, the objects it made are left out of the interpreter's last garbage collections
    (`gc.freeze`). Those walk every object once more after the command has finished: 0.2-0.3 s
    of CPU once the compiled kernels are loaded (a sweep), 10-30 % of a one-off command's
    start-up. The command's files are closed by then; only the process's exit is skipped work. An interrupt
    once the command has ended (its output written) is ignored: it could only cut the exit's clean-up short (a
    sweep's worker pool joined at exit printed a traceback; found by an acceptance check)."""
    try:
        app(prog_name="rotarydryer")
    finally:
        gc.freeze()
        if threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGINT, signal.SIG_IGN)


__all__ = ["app", "error_message", "run"]
