"""Bad-input corpus for ``rotarydryer lab steps`` (Song's dynamic step method, issue 14 part 5).

Every case runs the real command in an empty working folder (with ``--out res`` inside it where
the case allows) and checks the contract: exit code 2, an ``error:`` line naming the option, the
file and the line, plain numbers, no traceback, nothing written to (or changed in) the folder.
"""

from __future__ import annotations

import pytest

from .conftest import assert_bad, run_cli, snapshot

HEAD = "time_s,feed_kg_min,discharge_kg_min\n"
GOOD = HEAD + "0,0,0\n0,6,0\n60,6,1\n120,6,3\n180,6,5\n240,6,5.9\n240,0,5.9\n300,0,3\n360,0,1\n420,0,0.1\n480,0,0\n"

CASES = [
    # id, file content (None: no file; "DIR": a directory), extra args, fragments of the message
    ("missing-file", None, [], ["rec.csv", "does not exist"]),
    ("directory", "DIR", [], ["rec.csv", "is a directory"]),
    ("empty-file", "", [], ["rec.csv", "empty file", "header"]),
    ("comments-only", "# Song's balance log\n# nothing else\n", [], ["rec.csv", "empty file"]),
    ("numeric-header", "0,0,0\n60,6,1\n120,6,3\n", [], ["rec.csv line 1", "not a header", "time_s"]),
    ("no-time-column", "t,feed_kg_min,discharge_kg_min\n0,0,0\n60,6,1\n120,6,3\n", [],
     ["rec.csv line 1", "no time column", "time_s, time_min, time_h"]),
    ("unknown-time-unit", "time_days,feed_kg_min,discharge_kg_min\n0,0,0\n1,6,1\n2,6,3\n", [],
     ["rec.csv line 1", "no time column", "time_days"]),
    ("no-feed-column", "time_s,inlet,discharge_kg_min\n0,0,0\n60,6,1\n120,6,3\n", [],
     ["rec.csv line 1", "no feed column", "feed_kg_min", "fed_kg"]),
    ("no-discharge-column", "time_s,feed_kg_min,outlet\n0,0,0\n60,6,1\n120,6,3\n", [],
     ["rec.csv line 1", "no discharge column", "discharged_kg"]),
    ("two-feed-columns", "time_s,feed_kg_min,fed_kg,discharge_kg_min\n0,0,0,0\n60,6,6,1\n120,6,12,3\n", [],
     ["rec.csv line 1", "2 feed columns", "feed_kg_min, fed_kg"]),
    ("repeated-column", "time_s,feed_kg_min,discharge_kg_min,note,note\n0,0,0,a,b\n60,6,1,a,b\n120,6,3,a,b\n", [],
     ["rec.csv line 1", "'note' appears twice"]),
    ("text-in-feed", HEAD + "0,0,0\n60,abc,1\n120,6,3\n", [],
     ["rec.csv line 3", "'abc' is not a number in column feed_kg_min"]),
    ("empty-field", HEAD + "0,0,0\n60,6,\n120,6,3\n", [],
     ["rec.csv line 3", "empty field", "discharge_kg_min"]),
    ("nan-discharge", HEAD + "0,0,0\n60,6,nan\n120,6,3\n", [], ["rec.csv line 3", "nan", "NaN or infinite"]),
    ("inf-time", HEAD + "0,0,0\ninf,6,1\n120,6,3\n", [], ["rec.csv line 3", "NaN or infinite"]),
    ("time-goes-back", HEAD + "0,0,0\n60,6,1\n30,6,3\n120,6,4\n", [],
     ["rec.csv line 4", "time 30 is before the previous 60"]),
    ("time-three-times", HEAD + "0,0,0\n60,6,1\n60,6,1\n60,6,2\n120,6,3\n", [],
     ["rec.csv line 5", "appears three times"]),
    ("negative-feed", HEAD + "0,0,0\n60,-1,1\n120,6,3\n", [],
     ["rec.csv line 3", "feed_kg_min = -1 is negative"]),
    ("negative-discharge", HEAD + "0,0,0\n60,6,-0.5\n120,6,3\n", [],
     ["rec.csv line 3", "discharge_kg_min = -0.5 is negative"]),
    ("short-row", HEAD + "0,0,0\n60,6\n120,6,3\n", [], ["rec.csv line 3", "2 columns, expected 3"]),
    ("too-few-rows", HEAD + "0,0,0\n60,6,1\n", [], ["rec.csv", "2 data rows", "at least 3"]),
    ("balance-emptied", "time_min,feed_kg_min,discharged_kg\n0,6,0\n1,6,2\n2,6,7\n3,6,0.5\n4,6,6\n", [],
     ["rec.csv line 5", "discharged_kg = 0.5 falls below the previous 7", "emptied or reset"]),
    ("no-time-span", HEAD + "5,0,0\n5,6,0\n", [], ["rec.csv", "2 data rows"]),
    ("no-step-in-feed", HEAD + "0,6,0\n60,6,3\n120,6,5\n180,6,6\n", [],
     ["rec.csv", "no step in the feed", "give the step times"]),
    ("feed-always-zero", HEAD + "0,0,0\n60,0,0\n120,0,0\n", [], ["rec.csv", "no step in the feed"]),
    ("non-utf8", b"# balance caf\xe9\n" + GOOD.encode(), [], ["rec.csv line 1", "not UTF-8", "0xe9"]),
    ("binary", bytes(range(256)) * 4, [], ["rec.csv line 1", "binary"]),
    ("opt-steps-word", GOOD, ["--steps", "0,later"], ["--steps = '0,later'", "'later' is not a number"]),
    ("opt-steps-nan", GOOD, ["--steps", "0,nan"], ["--steps", "'nan' is not a finite number"]),
    ("opt-steps-decreasing", GOOD, ["--steps", "240,0"], ["--steps = 240, 0 s must increase"]),
    ("opt-steps-outside", GOOD, ["--steps", "0,900"], ["--steps = 0, 900 s", "inside the record", "[0, 480) s"]),
    ("opt-steps-outside-min", "time_min,feed_kg_min,discharge_kg_min\n0,0,0\n0,6,0\n2,6,4\n4,0,4\n8,0,0\n",
     ["--steps", "0,9"], ["--steps = 0, 9 min", "[0, 8) min"]),
    ("opt-plateau-zero", GOOD, ["--plateau", "0"], ["--plateau = 0", "(0, 1]"]),
    ("opt-plateau-big", GOOD, ["--plateau", "1.5"], ["--plateau = 1.5", "(0, 1]"]),
    ("opt-threshold", GOOD, ["--threshold", "1"], ["--threshold = 1", "(0, 1)"]),
    ("opt-tolerance-nan", GOOD, ["--tolerance", "nan"], ["--tolerance = nan", "not a finite number"]),
    ("opt-initial-holdup", GOOD, ["--initial-holdup", "-3"], ["--initial-holdup = -3 kg", "[0, 10000000] kg"]),
]


@pytest.mark.parametrize("case_id, content, extra, fragments", CASES, ids=[c[0] for c in CASES])
def test_lab_steps_bad_input(workdir, case_id, content, extra, fragments):
    p = workdir / "rec.csv"
    if content == "DIR":
        p.mkdir()
    elif isinstance(content, bytes):
        p.write_bytes(content)
    elif content is not None:
        p.write_text(content, encoding="utf-8")
    before = snapshot(workdir)
    res = run_cli(["lab", "steps", "rec.csv", "--out", "res", *extra], cwd=workdir)
    assert_bad(res, *fragments)
    assert "np.float" not in res.output and "array(" not in res.output, res.output
    assert snapshot(workdir) == before, "the failing command changed the working folder"
    assert not (workdir / "res").exists()


def test_out_is_a_file(workdir):
    (workdir / "rec.csv").write_text(GOOD, encoding="utf-8")
    (workdir / "res").write_text("keep me", encoding="utf-8")
    before = snapshot(workdir)
    res = run_cli(["lab", "steps", "rec.csv", "--out", "res"], cwd=workdir)
    assert_bad(res, "--out 'res' is an existing file")
    assert snapshot(workdir) == before


def test_good_record_passes(workdir):
    """The corpus' good record is accepted (so each case fails for its own reason)."""
    (workdir / "rec.csv").write_text(GOOD, encoding="utf-8")
    res = run_cli(["lab", "steps", "rec.csv", "--out", "res"], cwd=workdir)
    assert res.exit_code == 0, res.output
    assert (workdir / "res" / "steps.csv").exists() and (workdir / "res" / "steps.png").exists()
