"""Atomic text writes (rotarydryer._io), shared by reports, tracer/rig CSVs, sweeps and solver states."""

import pytest

from rotarydryer._io import write_text_atomic


def test_writes_and_creates_the_directory(tmp_path):
    p = write_text_atomic(tmp_path / "new" / "a.txt", "héllo\n")
    assert p.read_text(encoding="utf-8") == "héllo\n"


def test_failure_midway_leaves_the_old_file_and_no_temporary(tmp_path):
    p = tmp_path / "a.txt"
    p.write_text("old")

    with pytest.raises(TypeError):          # the write itself fails, after the temporary file exists
        write_text_atomic(p, object())
    assert p.read_text() == "old"
    assert [q.name for q in tmp_path.iterdir()] == ["a.txt"]
