"""Output writes (issue 13): atomic files that keep their permissions, refuse directories, devices
and FIFOs, leave no temporary file on any failure (read-only folder, full disk), and a CLI
failure boundary that never shows a traceback."""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
import uuid
from pathlib import Path

import pytest

from rotarydryer._io import OutputError, atomic_output, json_text, save_figure, write_bytes_atomic, write_text_atomic

from .conftest import assert_bad, run_cli, snapshot

FAST = ["--set", "thermal.enabled=false"]      # song2003_ottawa transport only: a fraction of a second


def _tmp_left(folder) -> list:
    return [p.name for p in Path(folder).rglob("*.tmp")]


# ---- the atomic writer ------------------------------------------------------------------------
def test_new_file_gets_umask_permissions(tmp_path):
    old = os.umask(0o022)
    try:
        p = write_text_atomic(tmp_path / "a.json", "{}")
    finally:
        os.umask(old)
    assert stat.S_IMODE(p.stat().st_mode) == 0o644


def test_existing_file_keeps_its_permissions(tmp_path):
    p = tmp_path / "a.txt"
    p.write_text("old")
    p.chmod(0o640)
    write_text_atomic(p, "new")
    assert p.read_text() == "new" and stat.S_IMODE(p.stat().st_mode) == 0o640


def test_symlink_is_followed_and_kept(tmp_path):
    real = tmp_path / "real.txt"
    real.write_text("old")
    link = tmp_path / "link.txt"
    link.symlink_to(real)
    write_text_atomic(link, "new")
    assert link.is_symlink() and real.read_text() == "new"


def test_failure_in_the_writer_leaves_the_old_file_and_no_temporary(tmp_path):
    p = tmp_path / "keep.txt"
    p.write_text("precious")
    with pytest.raises(RuntimeError):
        with atomic_output(p) as tmp:
            Path(tmp).write_text("half")
            raise RuntimeError("killed midway")
    assert p.read_text() == "precious" and _tmp_left(tmp_path) == []


@pytest.mark.parametrize("kind", ["directory", "fifo", "device"])
def test_refuses_directories_fifos_and_devices(tmp_path, kind):
    if kind == "directory":
        target = tmp_path / "d"
        target.mkdir()
    elif kind == "fifo":
        target = tmp_path / "f"
        os.mkfifo(target)
    else:
        target = Path("/dev/null")
    with pytest.raises(OutputError, match=f"(?i)it is a {kind}"):
        write_bytes_atomic(target, b"x")
    assert _tmp_left(tmp_path) == []
    if kind == "device":
        assert Path("/dev/null").is_char_device()


def test_json_text_is_strict_json():
    import numpy as np

    text = json_text({"a": float("nan"), "b": [1.0, float("inf")], "c": np.float64(2.5), "d": np.array([1, 2])})
    assert json.loads(text) == {"a": None, "b": [1.0, None], "c": 2.5, "d": [1, 2]}


def test_save_figure_is_atomic_and_closes(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure()
    p = save_figure(fig, tmp_path / "x.png", dpi=50)
    assert p.read_bytes()[:4] == b"\x89PNG" and not plt.fignum_exists(fig.number)


# ---- CLI: every output path that cannot be written ------------------------------------------
def _commands(out):
    """(id, argv) of every command with an output file or folder, writing to ``out``."""
    return [
        ("simulate", ["simulate", "song2003_ottawa", *FAST, "--out", out]),
        ("rtd", ["rtd", "lee2008_invicta", "--set", "geometry.method=lee2008_regressions", "--out", out]),
        ("new", ["new", "mine", "-o", f"{out}/mine.toml"]),
        ("schema", ["schema", "-o", f"{out}/schema.json"]),
        ("report", ["report", "song2003_ottawa", *FAST, "-o", f"{out}/r.html"]),
        ("sweep", ["sweep", "song2003_ottawa", *FAST, "--grid", "operating.rpm=4,5", "--no-rtd",
                   "-o", f"{out}/s.csv"]),
    ]


def _file_blocker(tmp_path):
    """A path under a regular file: no folder can be made there, whoever runs the test."""
    f = tmp_path / "a_file"
    f.write_text("x")
    return f / "sub"


@pytest.mark.parametrize("cmd", [c[0] for c in _commands("X")])
def test_output_under_a_file_is_a_clear_error(tmp_path, workdir, cmd):
    out = _file_blocker(tmp_path)
    argv = dict(_commands(str(out)))[cmd]
    before = snapshot(tmp_path)
    res = run_cli(argv, cwd=workdir)
    assert_bad(res, str(tmp_path / "a_file"))
    assert snapshot(tmp_path) == before


@pytest.mark.parametrize("cmd", ["simulate", "rtd"])
def test_output_folder_that_is_a_file(tmp_path, workdir, cmd):
    f = tmp_path / "out"
    f.write_text("not a folder")
    argv = dict(_commands(str(f)))[cmd]
    res = run_cli(argv, cwd=workdir)
    assert_bad(res, "out")
    assert f.read_text() == "not a folder"


def test_new_onto_a_directory_is_refused(tmp_path, workdir):
    d = tmp_path / "d.toml"
    d.mkdir()
    res = run_cli(["new", "x", "-o", d, "--force"], cwd=workdir)
    assert_bad(res, "directory")
    assert d.is_dir() and list(d.iterdir()) == []


def test_report_onto_a_fifo_is_refused(tmp_path, workdir):
    f = tmp_path / "r.html"
    os.mkfifo(f)
    res = run_cli(["report", "song2003_ottawa", *FAST, "-o", f], cwd=workdir)
    assert_bad(res, "fifo")
    assert stat.S_ISFIFO(f.stat().st_mode) and _tmp_left(tmp_path) == []


def test_saved_report_is_readable_by_colleagues(tmp_path, workdir):
    old = os.umask(0o022)
    try:
        res = run_cli(["report", "song2003_ottawa", *FAST, "-o", tmp_path / "r.html"], cwd=workdir)
    finally:
        os.umask(old)
    assert res.exit_code == 0, res.output
    assert stat.S_IMODE((tmp_path / "r.html").stat().st_mode) == 0o644


# ---- mounts: read-only folder and full disk (tmpfs) ------------------------------------------
def _mount(folder: Path, options: str):
    folder.mkdir(parents=True, exist_ok=True)
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(folder)], capture_output=True, text=True)
    if r.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here ({r.stderr.strip() or 'mount failed'}): needs root / CAP_SYS_ADMIN")


def _umount(folder: Path):
    subprocess.run(["umount", "-l", str(folder)], capture_output=True)


def _mounted(tmp_path, prefix, options):
    d = tmp_path / f"{prefix}_{uuid.uuid4().hex[:6]}"
    _mount(d, options)
    yield d
    _umount(d)


@pytest.fixture
def readonly(tmp_path):
    yield from _mounted(tmp_path, "ro", "size=1m,ro")


@pytest.fixture
def small_disk(tmp_path):
    yield from _mounted(tmp_path, "full", "size=2m")


@pytest.mark.parametrize("cmd", [c[0] for c in _commands("X")])
def test_read_only_output_folder(readonly, workdir, cmd):
    argv = dict(_commands(str(readonly)))[cmd]
    res = run_cli(argv, cwd=workdir)
    assert_bad(res, str(readonly))
    assert list(readonly.iterdir()) == [] and snapshot(workdir) == {}


def test_sweep_keeps_its_rows_when_the_write_fails(tmp_path, workdir, monkeypatch):
    """The output folder passes the early check, then the disk fails: the rows go to stdout."""
    import rotarydryer._io as io_mod

    def broken(path, text, **kw):
        raise OutputError(f"cannot write {str(path)!r}: No space left on device")

    monkeypatch.setattr(io_mod, "write_text_atomic", broken)
    res = run_cli(["sweep", "song2003_ottawa", *FAST, "--grid", "operating.rpm=4,5", "--no-rtd",
                   "-o", tmp_path / "s.csv"], cwd=workdir)
    assert_bad(res, "No space left", "printed to stdout")
    assert res.output.count("\n4,") + res.output.count("\n5,") + res.output.count("\n4.0") >= 0
    assert "operating.rpm" in res.output and "total_holdup_kg" in res.output


def _fill(folder: Path, leave: int):
    """Fill the file system of ``folder`` until ``leave`` bytes remain."""
    import shutil

    free = shutil.disk_usage(folder).free
    with open(folder / "filler", "wb") as fh:
        try:
            fh.write(b"\0" * max(free - leave, 0))
        except OSError:
            pass


def test_full_disk_keeps_the_previous_results(small_disk, workdir):
    """simulate --out onto a full disk: the previous steady_state.json stays intact, no temporary."""
    res = run_cli(["simulate", "song2003_ottawa", *FAST, "--out", small_disk], cwd=workdir)
    assert res.exit_code == 0, res.output
    good = (small_disk / "steady_state.json").read_bytes()
    json.loads(good)
    for p in small_disk.glob("*.png"):
        p.unlink()
    _fill(small_disk, 2048)
    res = run_cli(["simulate", "song2003_ottawa", "--set", "thermal.enabled=false", "--set",
                   "operating.rpm=5", "--out", small_disk], cwd=workdir)
    assert_bad(res, "No space left on device")
    assert (small_disk / "steady_state.json").read_bytes() == good
    assert _tmp_left(small_disk) == []


def test_full_disk_netcdf_is_refused_without_a_crash(small_disk):
    """Results.save (HDF5) onto a nearly full disk, in a separate process: exit 2 and a message,
    not a crash (h5py on a full disk can kill the process); the previous file stays, no temporary."""
    prev = small_disk / "old.nc"
    code = ("from rotarydryer.simulation import run_case; run_case('song2003_ottawa', "
            f"{{'thermal.enabled': False}}).save({str(prev)!r})")
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True)
    before = prev.read_bytes()
    _fill(small_disk, 16384)
    r = subprocess.run([sys.executable, "-m", "rotarydryer.cli", "report", "song2003_ottawa", "--set",
                        "thermal.enabled=false", "--save", str(prev), "-o", str(small_disk.parent / "r.html")],
                       capture_output=True, text=True)
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert "Traceback" not in r.stderr and "No space left" in r.stderr, r.stderr
    assert prev.read_bytes() == before and _tmp_left(small_disk) == []


# ---- the failure boundary ---------------------------------------------------------------------
def test_unexpected_exception_is_an_error_line_not_a_traceback(monkeypatch, workdir):
    import rotarydryer.simulation as sim_mod

    def boom(self):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(sim_mod.Simulation, "transport_model", boom)
    res = run_cli(["simulate", "song2003_ottawa"], cwd=workdir)
    assert_bad(res, "internal error", "ZeroDivisionError", "--debug")


def test_memory_error_is_an_error_line(monkeypatch, workdir):
    import rotarydryer.simulation as sim_mod

    def boom(self):
        raise MemoryError()

    monkeypatch.setattr(sim_mod.Simulation, "transport_model", boom)
    res = run_cli(["simulate", "song2003_ottawa"], cwd=workdir)
    assert_bad(res, "not enough memory")


def test_debug_shows_the_traceback(monkeypatch, workdir):
    import rotarydryer.simulation as sim_mod

    def boom(self):
        raise ZeroDivisionError("x")

    monkeypatch.setattr(sim_mod.Simulation, "transport_model", boom)
    res = run_cli(["--debug", "simulate", "song2003_ottawa"], cwd=workdir)
    assert isinstance(res.exception, ZeroDivisionError)
    from rotarydryer.cli import DEBUG

    DEBUG["on"] = False
