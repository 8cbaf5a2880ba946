"""Every command's ``--help``: examples kept verbatim (one command per line, Click's ``\\b``
marker), a short help that reads whole, and examples that copy and run.

The examples run in a temporary working directory (``tmp_path``), in their order within the
command (a later example may use an earlier one's output). Long-running commands are in the
``slow`` test; examples that need an optional program or the user's own data are skipped with
the reason.
"""

from __future__ import annotations

import importlib.util
import shlex
import shutil

import pytest
import typer.main
from typer.testing import CliRunner

from rotarydryer.cli import app

runner = CliRunner()

#: commands whose help lives in files edited elsewhere (reported, not fixed here)
#: files an example reads, written by the help text itself (its "A ..., NAME:" block): the test writes them
_HELP_FILES = ("trip.toml", "moisture.toml", "three_section.toml", "my_tolerances.toml")

#: commands whose examples take more than a few seconds (the ``slow`` test)
_SLOW = {("audit",), ("calibrate",), ("design",), ("fit",), ("sensitivity",), ("sweep",), ("report",), ("validate",),
         ("control",), ("target",), ("fmu",), ("dynamics",)}


def _commands(group, path: tuple = ()) -> list[tuple[tuple, object]]:
    out = []
    for name in sorted(group.commands):
        cmd = group.commands[name]
        if hasattr(cmd, "commands"):  # a group (typer may bring its own Click classes)
            out += _commands(cmd, (*path, name))
        else:
            out.append(((*path, name), cmd))
    return out


ROOT = typer.main.get_command(app)
COMMANDS = _commands(ROOT)


def _help(path: tuple) -> str:
    res = runner.invoke(app, [*path, "--help"], env={"COLUMNS": "80"})
    assert res.exit_code == 0, res.output
    return res.output


def _examples(path: tuple) -> list[str]:
    """The example command lines of ``rotarydryer PATH --help`` (lines starting ``rotarydryer ``)."""
    return [line.strip() for line in _help(path).splitlines() if line.strip().startswith("rotarydryer ")]


def _ids(items):
    return [" ".join(p) for p, _ in items]


def _write_help_files(path: tuple, folder):
    """The example input files a help text shows (a ``NAME:`` line ending a heading, then its
    indented lines), written into ``folder``."""
    lines = _help(path).splitlines()
    for i, line in enumerate(lines):
        name = next((f for f in _HELP_FILES if line.rstrip().endswith(f", {f}:")), None)
        if name is None:
            continue
        body = []
        for nxt in lines[i + 1:]:
            if not nxt.startswith("    "):
                break
            body.append(nxt.strip())
        (folder / name).write_text("\n".join(body) + "\n", encoding="utf-8")


@pytest.mark.parametrize(("path", "cmd"), COMMANDS, ids=_ids(COMMANDS))
def test_examples_are_kept_one_command_per_line(path, cmd):
    text = _help(path)
    doc = [line.strip() for line in (cmd.help or "").splitlines()]
    written = [line for line in doc if line.startswith("rotarydryer ")]
    shown = _examples(path)
    problems = []
    if "Example" in (cmd.help or "") and not written:
        problems.append("an Examples block without a `rotarydryer ...` line of its own")
    for line in text.splitlines():
        if "Example" in line and "rotarydryer " in line:
            problems.append(f"example run into its heading: {line.strip()!r}")
    if shown != written:
        problems.append(f"examples rewrapped: written {written}, shown {shown}")
    for line in shown:     # copy-and-paste into a shell: no unquoted redirection, pipe or separator
        lex = shlex.shlex(line, posix=True, punctuation_chars=True)
        lex.whitespace_split = True
        lex.commenters = "#"
        bad = [tok for tok in lex if tok and set(tok) <= set("<>|&;()")]
        if bad:
            problems.append(f"{line!r}: unquoted shell operator {bad[0]!r} (quote the argument)")
    assert not problems, problems


@pytest.mark.parametrize(("path", "cmd"), COMMANDS, ids=_ids(COMMANDS))
def test_short_help_reads_whole(path, cmd):
    short = cmd.get_short_help_str(limit=60)  # the room `rotarydryer --help` gives at 80 columns
    assert not short.endswith("..."), short
    assert short.endswith("."), short


def test_group_listings_are_not_cut():
    for path in [(), *{p[:1] for p, _ in COMMANDS if len(p) > 1}]:
        for line in _help(path).split("Commands:")[-1].splitlines():
            if line.rstrip().endswith("..."):
                pytest.fail(f"`rotarydryer {' '.join(path)} --help` cuts a summary: {line.strip()!r}")


def _skip_reason(argv: list[str], ran: set) -> str:
    """Why an example cannot run here ('' = it can)."""
    if argv[0] == "app" and "--print-command" not in argv:
        return "starts the web server (runs until stopped)"
    if argv[0] == "lab":
        return f"needs the user's measurement file {argv[2]!r}"
    if argv[:2] == ["dem", "run"] and shutil.which("liggghts") is None:
        return "LIGGGHTS is not installed"
    if argv[:2] == ["dem", "run"] and not any(r.startswith("dem export") for r in ran):
        return "needs the deck of `rotarydryer dem export` (a slice of the user's drum)"
    if argv[:2] == ["dem", "holdup"] and not any(r.startswith("dem run") for r in ran):
        return "needs the dumps of `rotarydryer dem run`"
    for module, what in (("pythonfmu", "fmu"), ("SALib", "sensitivity"), ("streamlit", "app")):
        if argv[0] == what and importlib.util.find_spec(module) is None and "--print-command" not in argv:
            return f"optional extra {module} is not installed"
    if "--scheduler" in argv:
        return "needs a Dask cluster"
    return ""


def _run_examples(path: tuple, tmp_path, monkeypatch):
    examples = _examples(path)
    if not examples:
        pytest.skip(f"`rotarydryer {' '.join(path)}` has no example")
    monkeypatch.chdir(tmp_path)
    _write_help_files(path, tmp_path)
    ran: set = set()
    skipped = []
    for line in examples:
        argv = shlex.split(line, comments=True)[1:]
        why = _skip_reason(argv, ran)
        if why:
            skipped.append(f"{line}: {why}")
            continue
        res = runner.invoke(app, argv)
        assert res.exit_code == 0, f"{line}\n{res.output}"
        ran.add(" ".join(argv))
    if skipped and not ran:
        pytest.skip("; ".join(skipped))


FAST = [(p, c) for p, c in COMMANDS if p[:1] not in {s[:1] for s in _SLOW}]
SLOW = [(p, c) for p, c in COMMANDS if p[:1] in {s[:1] for s in _SLOW}]


@pytest.mark.parametrize(("path", "cmd"), FAST, ids=_ids(FAST))
def test_fast_examples_run(path, cmd, tmp_path, monkeypatch):
    _run_examples(path, tmp_path, monkeypatch)


@pytest.mark.slow
@pytest.mark.parametrize(("path", "cmd"), SLOW, ids=_ids(SLOW))
def test_slow_examples_run(path, cmd, tmp_path, monkeypatch):
    _run_examples(path, tmp_path, monkeypatch)
