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


def test_output_set_writes_all_files_or_none(tmp_path):
    from rotarydryer._io import output_set

    (tmp_path / "a.txt").write_text("old a")
    with pytest.raises(TypeError):              # the second file fails: the first is not replaced
        with output_set(tmp_path):
            write_text_atomic(tmp_path / "a.txt", "new a")
            write_text_atomic(tmp_path / "b.txt", object())
    assert [q.name for q in tmp_path.iterdir()] == ["a.txt"] and (tmp_path / "a.txt").read_text() == "old a"
    with output_set(tmp_path):
        write_text_atomic(tmp_path / "a.txt", "new a")
        write_text_atomic(tmp_path / "b.txt", "new b")
    assert sorted(q.name for q in tmp_path.iterdir()) == ["a.txt", "b.txt"]
