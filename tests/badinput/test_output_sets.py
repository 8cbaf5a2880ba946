"""Outputs as a set, and no leftover temporary files (issue "Reliability under hostile and ordinary
input").

* ``rotarydryer._io.output_set``: the files of one result replace the previous ones only when all
  of them are complete; a full disk on the n-th file (simulated by making the n-th flush raise
  ENOSPC), an exception or Ctrl-C leaves the previous set byte for byte (same inode: not even
  rewritten) and no new or temporary file;
* a run killed mid-write (``kill -9``) leaves ``.NAME.rdtmp-<host>-<pid>-<random>.tmp``; the next
  write into that folder removes it, but never a live run's temporary file nor a file of another
  pattern;
* the last state of a failed heat-and-mass solve goes to ``--diagnostics FILE`` or ``--out DIR``,
  never into the working directory unasked.
"""

from __future__ import annotations

import errno
import json
import os
import re
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

import rotarydryer._io as io_mod
from rotarydryer._io import (
    OutputError,
    atomic_output,
    output_set,
    remove_stale_temps,
    save_figure,
    temp_name,
    write_bytes_atomic,
    write_text_atomic,
)
from rotarydryer.cli._common import check_out_dir

from .conftest import assert_bad, run_cli, snapshot

FAST = ["--set", "thermal.enabled=false"]      # song2003_ottawa transport only: a fraction of a second
TMP_RE = re.compile(r"\..*\.rdtmp-[0-9a-f]{8}-[0-9]+-[0-9a-f]{8}\.tmp", re.DOTALL)


def _state(folder) -> dict:
    """{name: (bytes, inode, mode)} of every entry of ``folder`` (hidden ones included)."""
    out = {}
    for p in sorted(Path(folder).rglob("*")):
        if p.is_file():
            st = p.stat()
            out[str(p.relative_to(folder))] = (p.read_bytes(), st.st_ino, stat.S_IMODE(st.st_mode))
    return out


def _temps(folder) -> list:
    return [p.name for p in Path(folder).rglob("*") if p.name.endswith(".tmp")]


def _fail_nth_flush(monkeypatch, n, exc=None):
    """Make the ``n``-th completed file (1-based) fail as on a full disk."""
    real = io_mod._flush_to_disk
    calls = {"n": 0}

    def flush(tmp, mode):
        calls["n"] += 1
        if calls["n"] == n:
            raise exc if exc is not None else OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real(tmp, mode)

    monkeypatch.setattr(io_mod, "_flush_to_disk", flush)
    return calls


def _old_set(folder: Path) -> dict:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "a.json").write_text('{"run": 1}')
    (folder / "b.csv").write_text("x\n1\n")
    (folder / "b.csv").chmod(0o640)
    (folder / "keep.png").write_bytes(b"old plot")
    return _state(folder)


def _write_new_set(folder: Path):
    write_text_atomic(folder / "a.json", '{"run": 2}')
    write_text_atomic(folder / "b.csv", "x\n2\n")
    write_bytes_atomic(folder / "c.png", b"new plot")


# ---- the set writer -------------------------------------------------------------------------
@pytest.mark.parametrize("n", [1, 2, 3])
def test_full_disk_on_any_file_keeps_the_previous_set(tmp_path, monkeypatch, n):
    before = _old_set(tmp_path)
    _fail_nth_flush(monkeypatch, n)
    with pytest.raises(OutputError, match="No space left on device"):
        with output_set(tmp_path):
            _write_new_set(tmp_path)
    assert _state(tmp_path) == before          # same bytes, same inodes: nothing replaced, c.png not made
    assert _temps(tmp_path) == []


@pytest.mark.parametrize("exc", [RuntimeError("bug in a plot"), KeyboardInterrupt()])
def test_exception_or_ctrl_c_after_two_files_keeps_the_previous_set(tmp_path, exc):
    before = _old_set(tmp_path)
    with pytest.raises(type(exc)):
        with output_set(tmp_path):
            write_text_atomic(tmp_path / "a.json", '{"run": 2}')
            write_bytes_atomic(tmp_path / "c.png", b"new")
            raise exc
    assert _state(tmp_path) == before and _temps(tmp_path) == []


def test_failed_rename_puts_back_the_files_already_renamed(tmp_path, monkeypatch):
    before = _old_set(tmp_path)
    real = os.replace
    calls = {"n": 0}

    def replace(src, dst):
        if TMP_RE.fullmatch(Path(src).name):
            calls["n"] += 1
            if calls["n"] == 3:                 # a.json and b.csv renamed, c.png fails
                raise OSError(errno.EIO, os.strerror(errno.EIO))
        real(src, dst)

    monkeypatch.setattr(io_mod.os, "replace", replace)
    with pytest.raises(OutputError, match="c.png"):
        with output_set(tmp_path):
            _write_new_set(tmp_path)
    monkeypatch.setattr(io_mod.os, "replace", real)
    assert calls["n"] >= 3
    assert _state(tmp_path) == before           # the renamed ones put back from their hard-link backups
    assert _temps(tmp_path) == []


def test_complete_set_replaces_and_keeps_the_files_it_does_not_write(tmp_path):
    before = _old_set(tmp_path)
    with output_set(tmp_path) as s:
        _write_new_set(tmp_path)
        assert not (tmp_path / "c.png").exists() and (tmp_path / "a.json").read_text() == '{"run": 1}'
    assert s.committed and [p.name for p in s.files] == ["a.json", "b.csv", "c.png"]
    after = _state(tmp_path)
    assert after["a.json"][0] == b'{"run": 2}' and after["c.png"][0] == b"new plot"
    assert after["b.csv"][2] == 0o640                      # permissions kept
    assert after["keep.png"] == before["keep.png"]         # not in the new set: kept as it was
    assert _temps(tmp_path) == []


def test_set_follows_symlinks_and_refuses_directories(tmp_path):
    real = tmp_path / "real.json"
    real.write_text("old")
    (tmp_path / "link.json").symlink_to(real)
    (tmp_path / "d.png").mkdir()
    with pytest.raises(OutputError, match="it is a directory"):
        with output_set(tmp_path):
            write_text_atomic(tmp_path / "link.json", "new")
            write_bytes_atomic(tmp_path / "d.png", b"x")
    assert real.read_text() == "old" and _temps(tmp_path) == []
    with output_set(tmp_path):
        write_text_atomic(tmp_path / "link.json", "new")
    assert (tmp_path / "link.json").is_symlink() and real.read_text() == "new"


def test_nested_set_joins_the_outer_one(tmp_path, monkeypatch):
    before = _old_set(tmp_path)
    _fail_nth_flush(monkeypatch, 3)
    with pytest.raises(OutputError):
        with output_set(tmp_path):
            with output_set(tmp_path):          # e.g. lab's helper inside a command's set
                write_text_atomic(tmp_path / "a.json", "inner")
            write_text_atomic(tmp_path / "b.csv", "outer")
            write_bytes_atomic(tmp_path / "c.png", b"fails")
    assert _state(tmp_path) == before


def test_without_a_set_each_file_is_written_at_once(tmp_path, monkeypatch):
    _old_set(tmp_path)
    _fail_nth_flush(monkeypatch, 2)
    write_text_atomic(tmp_path / "a.json", "new")
    with pytest.raises(OutputError):
        write_text_atomic(tmp_path / "b.csv", "new")
    assert (tmp_path / "a.json").read_text() == "new" and (tmp_path / "b.csv").read_text() == "x\n1\n"


def test_figure_and_library_writers_join_the_set(tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    before = _old_set(tmp_path)
    _fail_nth_flush(monkeypatch, 3)
    with pytest.raises(OutputError):
        with output_set(tmp_path):
            save_figure(plt.figure(), tmp_path / "keep.png", dpi=20)
            with atomic_output(tmp_path / "a.json") as tmp:     # any library writing a path
                Path(tmp).write_text("lib")
            write_text_atomic(tmp_path / "b.csv", "new")
    assert _state(tmp_path) == before and _temps(tmp_path) == []


# ---- temporary files: names and leftovers of killed runs --------------------------------------
def _dead_pid() -> int:
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def _named(name: str, pid: int, host: str | None = None) -> str:
    t = temp_name(name)
    t = re.sub(r"-[0-9]+-([0-9a-f]{8})\.tmp$", rf"-{pid}-\1.tmp", t)
    if host is not None:
        t = re.sub(r"\.rdtmp-[0-9a-f]{8}-", f".rdtmp-{host}-", t)
    return t


def test_temporary_name_is_recognisable_and_short_enough(tmp_path):
    seen = []
    with atomic_output(tmp_path / "steady_state.json") as tmp:
        seen.append(Path(tmp).name)
        Path(tmp).write_text("{}")
    assert TMP_RE.fullmatch(seen[0]) and seen[0].startswith(".steady_state.json.rdtmp-")
    assert f"-{os.getpid()}-" in seen[0]
    long = "é" * 120 + ".json"                       # 245 bytes: at the file-name limit with the suffix
    write_text_atomic(tmp_path / long, "x")
    assert (tmp_path / long).read_text() == "x" and _temps(tmp_path) == []
    assert len(os.fsencode(temp_name(long))) <= 255


def test_stale_temporary_of_a_dead_run_is_removed_at_the_next_write(tmp_path):
    stale = tmp_path / _named("steady_state.json", _dead_pid())
    stale.write_bytes(b"\0" * 265_000)
    write_text_atomic(tmp_path / "other.json", "{}")
    assert not stale.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["other.json"]


def test_live_runs_and_foreign_files_are_never_removed(tmp_path):
    live = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        keep = [
            _named("a.json", live.pid),                         # a live concurrent run
            _named("b.json", os.getpid()),                      # this process
            _named("c.json", _dead_pid(), host="0123abcd"),     # another host, recent
            ".d.json.k3j4h5x_.tmp",                             # tempfile.mkstemp style: not ours
            ".e.json.rdtmp-zz.tmp", "notes.tmp", "f.rdtmp-1-2.tmp",
        ]
        for name in keep:
            (tmp_path / name).write_text("keep")
        old_foreign = tmp_path / _named("g.json", 1234, host="0123abcd")
        old_foreign.write_text("old")
        two_days = time.time() - 2 * 86400
        os.utime(old_foreign, (two_days, two_days))
        target = tmp_path / "precious.txt"
        target.write_text("data")
        link = tmp_path / _named("h.json", _dead_pid())
        link.symlink_to(target)                                 # our pattern, but not a regular file
        write_text_atomic(tmp_path / "out.json", "{}")
        names = {p.name for p in tmp_path.iterdir()}
        assert set(keep) <= names and link.name in names and target.read_text() == "data"
        assert old_foreign.name not in names
    finally:
        live.kill()
        live.wait()


def test_remove_stale_temps_reports_what_it_removed(tmp_path):
    a = tmp_path / _named("x.json", _dead_pid())
    a.write_text("")
    assert remove_stale_temps(tmp_path) == [a] and remove_stale_temps(tmp_path) == []
    assert remove_stale_temps(tmp_path / "missing") == []


def test_kill_9_mid_write_then_the_next_run_cleans_up(tmp_path, workdir):
    """A real ``kill -9`` while the JSON is being written leaves its temporary file; the next
    ``simulate --out`` into the folder removes it."""
    out = tmp_path / "out"
    out.mkdir()
    code = ("import os, signal, pathlib\nfrom rotarydryer._io import atomic_output\n"
            f"with atomic_output({str(out / 'steady_state.json')!r}) as tmp:\n"
            "    pathlib.Path(tmp).write_bytes(b'x' * 265000)\n"
            "    os.kill(os.getpid(), signal.SIGKILL)\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True)
    assert r.returncode == -signal.SIGKILL
    left = _temps(out)
    assert len(left) == 1 and TMP_RE.fullmatch(left[0]), left
    res = run_cli(["simulate", "song2003_ottawa", *FAST, "--out", out], cwd=workdir)
    assert res.exit_code == 0, res.output
    assert _temps(out) == [] and sorted(p.name for p in out.iterdir()) == ["holdup_profile.png", "steady_state.json"]


# ---- commands: a full disk on the last file keeps the previous set ----------------------------
def _steps_csv(folder: Path) -> Path:
    import numpy as np

    t = np.arange(0.0, 6002.0, 2.0)
    feed = np.where(t < 2000.0, 0.1, 0.0)
    up = 0.1 * (1 - np.exp(-np.minimum(t, 2000.0) / 300.0))
    dis = np.where(t < 2000.0, up, 0.1 * (1 - np.exp(-2000.0 / 300.0)) * np.exp(-(t - 2000.0) / 300.0))
    p = folder / "run.csv"
    p.write_text("time_s,feed_kg_min,discharge_kg_min\n" + "".join(f"{a},{b * 60},{c * 60}\n" for a, b, c in
                                                                  zip(t, feed, dis)))
    return p


DEM = ["--radius", "0.1", "--n-flights", "8", "--s1", "0.03", "--s2", "0.025", "--rpm", "12", "--diameter", "0.006",
       "--settle-time", "0.1", "--spinup", "0.05", "--revolutions", "0.05", "--dump-every", "5"]
COMMANDS = {     # id: (argv with {out} and {data}, number of files of the set; None: as the first run wrote)
    "simulate": (["simulate", "song2003_ottawa", *FAST, "--out", "{out}"], 2),
    "rtd": (["rtd", "song2003_ottawa", *FAST, "--out", "{out}"], 3),
    "flight": (["flight", "--drum", "invicta", "--repose-angle", "50", "--out", "{out}"], 2),
    "lab steps": (["lab", "steps", "{data}", "--out", "{out}"], 2),
    "lab rig": (["lab", "rig", "{rig}", "--rpm", "2", "--start-angle", "93.5", "--bulk-density", "1474",
                 "--repose-angle", "39.6", "--repose-sd", "1.7", "--out", "{out}"], 2),
    "dem export": (["dem", "export", "{out}", *DEM], 4),
    "report --save": (["report", "song2003_ottawa", *FAST, "-o", "{out}/r.html", "--save", "{out}/r.nc"], 2),
    "validate": (["validate", "song2003_ottawa", "--out", "{out}"], 2),
    "sensitivity": (["sensitivity", "song2003_ottawa", *FAST, "--param", "operating.rpm=3,5", "--samples", "4",
                     "--out", "{out}"], None),
    "design": (["design", "--duty", "raw_sugar", "--no-verify", "--out", "{out}"], None),
    "control": (["control", "ajayi2011_mmg", "--set", "operating.test=4", "--duration", "600", "--step-time", "0",
                 "--sample-time", "120", "--no-open-loop", "--out", "{out}"], None),
    "fit": (["fit", "ajayi2011_mmg", "ajayi2011_test4", "-p", "transport.dispersion", "--set", "operating.test=4",
             "--scale", "fit", "--starts", "1", "--out", "{out}"], None),
}


@pytest.mark.parametrize("cmd", list(COMMANDS))
def test_command_full_disk_on_the_last_file_keeps_the_previous_set(tmp_path, workdir, monkeypatch, cmd):
    argv, n_files = COMMANDS[cmd]
    out = tmp_path / "out"
    out.mkdir()                                  # report --save needs an existing folder
    data, rig = _steps_csv(tmp_path), tmp_path / "rig.csv"
    if cmd == "lab rig":
        from rotarydryer.lab import flight_rig as fr

        fr.write_rig_csv(rig, fr.synthetic_run(fr.rig_drum("alternative"), 39.6, rpm=2.0, start_angle=93.5,
                                               bulk_density=1474.0, seed=1))
    argv = [a.replace("{out}", str(out)).replace("{data}", str(data)).replace("{rig}", str(rig)) for a in argv]
    res = run_cli(argv, cwd=workdir)
    assert res.exit_code in (0, 1), res.output          # validate: 1 when a check fails
    before = _state(out)
    if n_files is None:                                 # the command's own set: at least two files
        n_files = len(before)
        assert n_files >= 2, sorted(before)
    assert len(before) == n_files, sorted(before)
    calls = _fail_nth_flush(monkeypatch, n_files)
    res = run_cli(argv, cwd=workdir)
    assert calls["n"] == n_files, calls
    assert_bad(res, "No space left on device")
    assert _state(out) == before, "a file of the previous set was replaced or one was added"
    assert _temps(out) == [] and snapshot(workdir) == {}


def test_simulate_second_run_replaces_the_whole_set(tmp_path, workdir):
    out = tmp_path / "out"
    assert run_cli(["simulate", "song2003_ottawa", *FAST, "--out", out], cwd=workdir).exit_code == 0
    before = _state(out)
    res = run_cli(["simulate", "song2003_ottawa", *FAST, "--out", out], cwd=workdir)
    assert res.exit_code == 0, res.output
    after = _state(out)
    assert set(after) == set(before) and all(after[k][1] != before[k][1] for k in after)
    assert json.loads(after["steady_state.json"][0])["case"] == "song2003_ottawa" and _temps(out) == []


# ---- diagnostics of a failed heat-and-mass solve -----------------------------------------------
@pytest.fixture
def unreachable(monkeypatch):
    from rotarydryer.thermal import dryer as dryer_mod

    original = dryer_mod.ThermalDryer.steady_state

    def capped(self, z0=None, **kw):           # two iterations: the solver cannot get there
        return original(self, z0=z0, max_iter=2, march=False)

    monkeypatch.setattr(dryer_mod.ThermalDryer, "steady_state", capped)


def test_failed_solve_writes_nothing_into_the_working_directory(workdir, unreachable):
    res = run_cli(["simulate", "ajayi2011_mmg"], cwd=workdir)
    assert res.exit_code == 1, res.output
    assert "no steady state reached" in res.output and "--diagnostics" in res.output
    assert snapshot(workdir) == {}


def test_failed_solve_diagnostics_go_to_the_named_file(tmp_path, workdir, unreachable):
    diag = tmp_path / "diag" / "last.json"
    out = tmp_path / "out"
    res = run_cli(["simulate", "ajayi2011_mmg", "--diagnostics", diag, "--out", out], cwd=workdir)
    assert res.exit_code == 1, res.output
    assert f"saved to {diag}" in " ".join(res.output.split())
    assert json.loads(diag.read_text())["reason"] == "no_steady_state"
    assert snapshot(workdir) == {} and not (out / "thermal_last_state.json").exists()
    assert _temps(diag.parent) == []


def test_diagnostics_option_that_is_a_directory_is_refused_before_the_run(tmp_path, workdir):
    res = run_cli(["simulate", "ajayi2011_mmg", "--diagnostics", tmp_path], cwd=workdir)
    assert_bad(res, "--diagnostics", "directory")
    assert snapshot(workdir) == {}


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs Linux's /proc, where no directory can be made")
def test_an_output_directory_that_cannot_be_made_is_refused_before_the_work(tmp_path):
    """`design --out /proc/d` ran its whole search (about 10 s) before saying it could not write there (found by
    fuzzing): the place is probed up front, and a writable one is left as it was."""
    res = run_cli(["design", "--material", "ottawa_sand_song2003", "--feed", "2.5", "--moisture-in", "0.06",
                   "--moisture-out", "0.001", "--gas-in", "250", "--no-verify", "--out", "/proc/rotarydryer_d"],
                  cwd=tmp_path)
    assert_bad(res, "--out '/proc/rotarydryer_d': cannot write in '/proc'")
    assert "design" not in res.stdout            # refused before the search: nothing of it printed
    check_out_dir("--out", tmp_path / "new" / "sub")
    assert list(tmp_path.iterdir()) == []        # the probe removed, nothing made


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs Linux's /proc, where no file can be made")
def test_an_output_file_that_cannot_be_written_is_refused_before_the_work(tmp_path):
    """`report CASE -o /proc/x.html` ran the whole report (7 s) before saying it could not write there (found by
    review): the folder is probed up front, as an output directory's is, and a writable one is left as it was."""
    from rotarydryer.cli._common import check_out_file

    res = run_cli(["report", "lee2008_invicta", "-o", "/proc/rotarydryer_x.html"], cwd=tmp_path)
    assert_bad(res, "--out '/proc/rotarydryer_x.html': cannot write in '/proc'")
    assert "report:" not in res.stdout
    check_out_file("--out", tmp_path / "new" / "r.html", ("html",))
    assert list(tmp_path.iterdir()) == []        # the probe removed, nothing made
