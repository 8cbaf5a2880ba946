"""Running an exported deck with LIGGGHTS (``mpirun -np N liggghts`` or plain ``liggghts``)."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

from .._io import stop_process

__all__ = ["find_liggghts", "run_deck", "INSTALL_HINT", "LiggghtsMissing", "LiggghtsFailed"]

INSTALL_HINT = ("LIGGGHTS is not installed (no 'liggghts' or 'lmp_auto' on PATH): install it with "
                "'apt-get install liggghts' (Debian/Ubuntu, LIGGGHTS-PUBLIC 3.8 with Open MPI) or build "
                "LIGGGHTS-PUBLIC 3.8 from https://github.com/CFDEMproject/LIGGGHTS-PUBLIC, or set "
                "ROTARYDRYER_LIGGGHTS to the executable")


class LiggghtsMissing(ValueError):
    """No LIGGGHTS executable."""


class LiggghtsFailed(ValueError):
    """LIGGGHTS stopped with an error (the deck was rejected or the run failed)."""


def find_liggghts() -> str | None:
    """Path of the LIGGGHTS executable: ``$ROTARYDRYER_LIGGGHTS``, else ``liggghts`` or ``lmp_auto`` on PATH."""
    env = os.environ.get("ROTARYDRYER_LIGGGHTS")
    if env:
        return env if (Path(env).is_file() and os.access(env, os.X_OK)) else shutil.which(env)
    for name in ("liggghts", "lmp_auto"):
        p = shutil.which(name)
        if p:
            return p
    return None


def _env() -> dict:
    env = dict(os.environ)
    # Open MPI refuses to start as root without these (containers, CI)
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    env.setdefault("OMPI_MCA_rmaps_base_oversubscribe", "1")
    return env


def _rejected_command(log: Path, deck: Path) -> str:
    """The last command LIGGGHTS read (echoed to the log) and its line in the deck."""
    try:
        lines = [ln.rstrip() for ln in log.read_text("utf-8", "replace").splitlines()]
        deck_lines = [ln.rstrip() for ln in deck.read_text("utf-8", "replace").splitlines()]
    except OSError:
        return ""
    msg = [ln for ln in lines if ln.startswith("ERROR")]
    cmd_lines = {ln.strip(): i + 1 for i, ln in enumerate(deck_lines) if ln.strip() and not ln.startswith("#")}
    last = ""
    for ln in reversed(lines):
        if ln.strip() in cmd_lines:
            last = ln.strip()
            break
    out = []
    if msg:
        out.append(msg[-1])
    if last:
        out.append(f"last command read: line {cmd_lines[last]} of {deck.name}: {last!r}")
    return "; ".join(out)


#: seconds a stopped LIGGGHTS (or mpirun) has to end after a terminate before it is killed
STOP_GRACE_S = 5.0
#: seconds the screen reader has to finish after LIGGGHTS ended (a child it left may hold the output open)
READER_JOIN_S = 10.0


def run_deck(folder, *, np: int = 1, progress: bool = True, label: str | None = None, timeout: float | None = None,
             stream=None) -> dict:
    """Run ``in.drum`` in ``folder`` (written by `rotarydryer.dem.deck.export_deck`).

    ``np > 1`` uses ``mpirun -np N``. Progress (step / total, %) is printed to ``stream``
    (stderr) when ``progress``. Returns ``{"seconds": ..., "steps": ..., "command": [...]}``.
    Raises `LiggghtsMissing` (with how to install it) or `LiggghtsFailed` (naming the
    rejected command of the deck and the log)."""
    folder = Path(folder)
    deck = folder / "in.drum"
    meta = folder / "deck.json"
    if not deck.is_file() or not meta.is_file():
        raise ValueError(f"{str(folder)!r} holds no deck (in.drum and deck.json): write one with rotarydryer dem export")
    if isinstance(np, bool) or int(np) != np or not 1 <= int(np) <= 256:
        raise ValueError(f"np (--np) = {np!r} is outside the allowed range: an integer from 1 to 256")
    exe = find_liggghts()
    if exe is None:
        raise LiggghtsMissing(INSTALL_HINT)
    try:
        total = int(json.loads(meta.read_text("utf-8"))["derived"]["steps"]["total"])
    except (KeyError, ValueError, TypeError):
        total = 0
    cmd = [exe, "-in", "in.drum", "-echo", "log", "-log", "log.liggghts"]
    if int(np) > 1:
        mpirun = shutil.which("mpirun") or shutil.which("mpiexec")
        if mpirun is None:
            raise LiggghtsMissing("mpirun is not installed (needed for --np > 1): install Open MPI "
                                  "('apt-get install openmpi-bin') or run with --np 1")
        cmd = [mpirun, "-np", str(int(np)), "--oversubscribe"] + cmd
    stream = stream or sys.stderr
    name = label or folder.name
    t0 = time.perf_counter()
    step_re = re.compile(rb"^\s*(\d+)\s+\d+\s+[-+0-9.eE]+")
    (folder / "post").mkdir(exist_ok=True)
    with open(folder / "screen.txt", "wb") as screen:
        # in the caller's process group, so that a signal to it (a terminal closed, `timeout`) reaches LIGGGHTS too
        proc = subprocess.Popen(cmd, cwd=folder, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=_env())
        failed: list[BaseException] = []       # what ended the reader (a closed stderr, a full disk)

        def stop():
            stop_process(proc, STOP_GRACE_S)     # mpirun passes the terminate on to its ranks

        def pump():
            # the screen output, read beside the wait: a run that prints nothing for a while is still stopped
            # at its --timeout (a check per printed line overshot it by as long as LIGGGHTS was silent)
            last_pct = -1
            assert proc.stdout is not None
            try:
                for line in proc.stdout:
                    screen.write(line)
                    m = step_re.match(line)
                    if m and total and progress:
                        pct = int(100 * int(m.group(1)) / total)
                        if pct >= last_pct + 5:
                            last_pct = pct
                            el = time.perf_counter() - t0
                            print(f"{name}: step {int(m.group(1))} / {total} ({pct} %, {el:.0f} s)", file=stream,
                                  flush=True)
            except BaseException as exc:    # noqa: BLE001 - handed to the waiting thread, which raises it
                failed.append(exc)
                if proc.poll() is None:     # nobody reads the output any more: LIGGGHTS would block on it
                    stop()

        reader = threading.Thread(target=pump, daemon=True)
        reader.start()
        try:
            try:
                rc = proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                stop()
                raise LiggghtsFailed(f"{name}: LIGGGHTS did not finish within {timeout:g} s (stopped)") from None
        except BaseException:
            if proc.poll() is None:
                stop()
            raise
        finally:
            reader.join(timeout=READER_JOIN_S)
        if failed:
            raise failed[0]
    seconds = time.perf_counter() - t0
    text = (folder / "screen.txt").read_text("utf-8", "replace")
    if rc != 0 or "ERROR" in text or "MPI_ABORT" in text:
        why = _rejected_command(folder / "log.liggghts", deck) or _rejected_command(folder / "screen.txt", deck)
        raise LiggghtsFailed(f"LIGGGHTS rejected the deck in {str(folder)!r} (exit code {rc})"
                             + (f": {why}" if why else "") + f"; see {str(folder / 'log.liggghts')!r}")
    if not (folder / "post" / "particles.dump").is_file():
        raise LiggghtsFailed(f"LIGGGHTS finished but wrote no dump in {str(folder / 'post')!r}; see log.liggghts")
    if progress:
        print(f"{name}: done in {seconds:.0f} s", file=stream, flush=True)
    return {"seconds": seconds, "steps": total, "command": cmd}
