"""The one way a command writes its --out set (cli._common.written_set): all files or none, and a failed
write is a one-line error naming the option, exit 2."""

from __future__ import annotations

import pytest
import typer

from rotarydryer._io import write_text_atomic
from rotarydryer.cli._common import written_set


def test_a_failed_write_names_the_option_and_keeps_the_previous_set(tmp_path, capsys):
    out = tmp_path / "res"
    with written_set(out):
        write_text_atomic(out / "a.txt", "old a")
        write_text_atomic(out / "b.txt", "old b")
    blocker = tmp_path / "res" / "sub"
    blocker.write_text("a file where the next set wants a folder")
    with pytest.raises(typer.Exit) as exc:
        with written_set(out):
            write_text_atomic(out / "a.txt", "new a")
            write_text_atomic(blocker / "c.txt", "cannot be written")
    assert exc.value.exit_code == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"error: --out {str(out)!r}: ") and "\n" not in err
    assert (out / "a.txt").read_text() == "old a" and (out / "b.txt").read_text() == "old b"


def test_other_errors_pass_through(tmp_path):
    with pytest.raises(KeyError):
        with written_set(tmp_path / "x"):
            raise KeyError("not a write")
    with pytest.raises(typer.Exit) as exc:
        with written_set(tmp_path / "y", option="--save", errors=(ValueError, OSError)):
            raise ValueError("a figure that cannot be drawn")
    assert exc.value.exit_code == 2
