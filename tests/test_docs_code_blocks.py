"""Every code block of the documentation runs (issue 18).

Collected: README.md and every ``docs/**/*.md`` page, fenced blocks

* ```` ```python ```` - executed with ``exec``; the python blocks of one page share one
  namespace, fresh for each page (pages continue an example from block to block, like a
  notebook: ``d = load_tracer_dataset(...)`` in one block, ``d.moments(...)`` in the next);
* ```` ```bash ```` whose every command is ``rotarydryer ...`` (``&&`` chains, ``\\`` line
  continuations, ``# comments``, ``> file`` redirection; the right side of a ``|`` pipe is
  dropped) - run in-process through ``typer.testing.CliRunner`` on ``rotarydryer.cli.app``.
  Other bash blocks (installs, ``python -m ...``) are not collected.

The blocks of one page run in page order in one temporary working folder (a later block may
use a file an earlier one wrote); running one block alone first runs the earlier ones.

Marker convention, an HTML comment on the line(s) just above the fence (blank lines allowed):

* ``<!-- skip-ci: REASON -->`` - not run in CI (long runs, the web app, a cluster scheduler
  address, placeholder file names such as PHOTO.png, DEM runs); the reason is the skip reason.
* ``<!-- ci-exit-code: N -->`` - a ``rotarydryer`` block that shows an error on purpose: its last
  command must exit with code N (the earlier ones with 0).

Pages that other workers own carry no marker yet; their blocks that cannot run in CI are listed
in ``_EXTERNAL_SKIPS`` below (page, first line of the block) until the page gets its marker.
"""

from __future__ import annotations

import os
import re
import shlex
import time
from dataclasses import dataclass, field
from pathlib import Path

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]

_FENCE = re.compile(r"^(?P<indent>[ \t]*)```(?P<lang>[A-Za-z0-9_+-]*)\s*$")
_SKIP = re.compile(r"^\s*<!--\s*skip-ci:\s*(?P<reason>.+?)\s*-->\s*$")
_EXIT = re.compile(r"^\s*<!--\s*ci-exit-code:\s*(?P<code>\d+)\s*-->\s*$")

# (page relative to the repository, start of the block's first line) -> reason. Only for pages
# whose owner has not added a ``<!-- skip-ci: ... -->`` marker; prefer the marker.
_EXTERNAL_SKIPS: dict[tuple[str, str], str] = {
    ("README.md", "rotarydryer lab rig RUN.csv"): "placeholder file names (RUN.csv, PHOTO.png, series.csv, CURVES.csv)",
    ("docs/lab.md", "from rotarydryer.lab import flight_rig as fr"): "placeholder file name (run.csv)",
    ("docs/lab.md", "from rotarydryer.geometry.presets import preset_drum"): "placeholder file name (photo.png)",
    ("docs/lab.md", "from rotarydryer.lab import design_load_fit as dl"):
        "placeholder data (loading_kg, fuf_area_cm2 are the reader's series)",
    ("docs/sensitivity.md", "# transport only (fast)"): "long run (Sobol study, over 2 min on 2 cores)",
}


@dataclass
class Block:
    page: Path
    line: int                      # 1-based line of the opening fence
    lang: str
    code: str
    skip: str | None = None
    exit_code: int = 0
    commands: list[tuple[list[str], str | None]] = field(default_factory=list)

    @property
    def rel(self) -> str:
        return self.page.relative_to(ROOT).as_posix()

    @property
    def id(self) -> str:
        return f"{self.rel}:{self.line}"


def _rotarydryer_commands(code: str):
    """[(argv after 'rotarydryer', stdout file or None)], or None if any command is not rotarydryer."""
    text = re.sub(r"\\\n", " ", code)
    out = []
    for line in text.splitlines():
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        try:
            tokens = shlex.split(line, comments=True)
        except ValueError:
            return None
        if "|" in tokens:
            tokens = tokens[: tokens.index("|")]
        cmd: list[str] = []
        for tok in [*tokens, "&&"]:
            if tok in ("&&", ";"):
                if not cmd:
                    continue
                if cmd[0] != "rotarydryer":
                    return None
                redirect = None
                if ">" in cmd:
                    i = cmd.index(">")
                    redirect, cmd = cmd[i + 1], cmd[:i]
                out.append((cmd[1:], redirect))
                cmd = []
            else:
                cmd.append(tok)
    return out or None


def _blocks(page: Path) -> list[Block]:
    lines = page.read_text(encoding="utf-8").splitlines()
    blocks, i = [], 0
    while i < len(lines):
        m = _FENCE.match(lines[i])
        if not m or not m["lang"]:
            if m:  # an un-labelled fence: skip to its closing fence
                i += 1
                while i < len(lines) and not _FENCE.match(lines[i]):
                    i += 1
            i += 1
            continue
        indent, lang, start = m["indent"], m["lang"], i
        body = []
        i += 1
        while i < len(lines) and not (_FENCE.match(lines[i]) and not _FENCE.match(lines[i])["lang"]):
            body.append(lines[i][len(indent):] if lines[i].startswith(indent) else lines[i].lstrip())
            i += 1
        i += 1
        skip, exit_code, j = None, 0, start - 1
        while j >= 0 and (not lines[j].strip() or _SKIP.match(lines[j]) or _EXIT.match(lines[j])):
            if s := _SKIP.match(lines[j]):
                skip = s["reason"]
            if e := _EXIT.match(lines[j]):
                exit_code = int(e["code"])
            j -= 1
        code = "\n".join(body) + "\n"
        block = Block(page, start + 1, lang, code, skip, exit_code)
        first = next((ln.strip() for ln in body if ln.strip()), "")
        for (rel, prefix), reason in _EXTERNAL_SKIPS.items():
            if block.rel == rel and first.startswith(prefix) and block.skip is None:
                block.skip = f"{reason} (listed in tests/test_docs_code_blocks.py)"
        if lang == "python":
            blocks.append(block)
        elif lang in ("bash", "sh", "shell"):
            cmds = _rotarydryer_commands(block.code)
            if cmds is not None:
                block.commands = cmds
                blocks.append(block)
            elif block.skip is None:
                pass  # not a rotarydryer block (install, python -m ...): not collected
    return blocks


ALL_BLOCKS = [b for p in PAGES for b in _blocks(p)]
_DONE: dict[str, set[int]] = {}
_NAMESPACES: dict[str, dict] = {}
_WORKDIRS: dict[str, Path] = {}


def _run_block(block: Block, workdir: Path) -> None:
    cwd = os.getcwd()
    os.chdir(workdir)
    try:
        if block.lang == "python":
            namespace = _NAMESPACES.setdefault(block.rel, {"__name__": "__docs__"})
            exec(compile(block.code, block.id, "exec"), namespace)  # noqa: S102 - the docs' own code
            import matplotlib.pyplot as plt

            plt.close("all")
            return
        from typer.testing import CliRunner

        from rotarydryer.cli import app

        runner = CliRunner()
        for k, (argv, redirect) in enumerate(block.commands):
            last = k == len(block.commands) - 1
            result = runner.invoke(app, argv, catch_exceptions=False)
            want = block.exit_code if last else 0
            assert result.exit_code == want, (
                f"{block.id}: `rotarydryer {' '.join(argv)}` exited {result.exit_code} (expected {want})\n"
                f"{result.output[-3000:]}")
            if redirect:
                Path(redirect).write_text(result.stdout)
    finally:
        os.chdir(cwd)


@pytest.mark.parametrize("block", ALL_BLOCKS, ids=lambda b: b.id)
def test_docs_code_block(block: Block, tmp_path_factory):
    if block.skip:
        pytest.skip(block.skip)
    workdir = _WORKDIRS.setdefault(block.rel, tmp_path_factory.mktemp("docs_blocks"))
    done = _DONE.setdefault(block.rel, set())
    for earlier in ALL_BLOCKS:   # blocks of this page above this one that have not run yet
        if earlier.rel == block.rel and earlier.line < block.line and not earlier.skip \
                and earlier.line not in done:
            done.add(earlier.line)
            _run_block(earlier, workdir)
    done.add(block.line)
    t0 = time.perf_counter()
    _run_block(block, workdir)
    elapsed = time.perf_counter() - t0
    assert elapsed < 120, f"{block.id} took {elapsed:.0f} s: mark it <!-- skip-ci: long run -->"


def test_blocks_are_found():
    """The collector sees the docs (a parser regression would silently run nothing)."""
    pages = {b.rel for b in ALL_BLOCKS}
    assert "README.md" in pages and "docs/tutorial.md" in pages
    assert sum(b.lang == "python" for b in ALL_BLOCKS) >= 10
    assert sum(b.lang == "bash" for b in ALL_BLOCKS) >= 10


def test_shell_blocks_quote_their_comparisons():
    """A condition such as ``--such-that product_moisture_kg_kg<=0.12`` written without quotes is a redirection for
    the shell (``<`` reads a file "=0.12"), which these tests, splitting the line themselves, did not see (found by an
    acceptance check on docs/guide/targets.md)."""
    bad = []
    for block in ALL_BLOCKS:
        if block.lang not in ("bash", "sh", "console", "shell"):
            continue
        for k, line in enumerate(block.code.splitlines(), start=1):
            bare = re.sub(r"\"[^\"]*\"|'[^']*'", "", line.split(" #")[0])
            if re.search(r"[<>]=|\w<\w", bare) and not line.lstrip().startswith("#"):
                bad.append(f"{block.id} line {k}: {line.strip()}")
    assert not bad, "unquoted comparisons in shell blocks:\n" + "\n".join(bad)
