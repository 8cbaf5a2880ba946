"""Runs after the corpus files of this folder (alphabetical order): no output of any corpus case
contains a traceback (issue 13: ``grep -c Traceback`` over the corpus outputs is 0). With
``ROTARYDRYER_CORPUS_LOG=path`` the outputs are also written there for inspection."""

import os

from .conftest import CORPUS_OUTPUTS


def test_no_traceback_in_any_corpus_output():
    log = os.environ.get("ROTARYDRYER_CORPUS_LOG")
    if log:
        with open(log, "w", encoding="utf-8") as fh:
            fh.write("\n----\n".join(CORPUS_OUTPUTS))
    bad = [o for o in CORPUS_OUTPUTS if "Traceback" in o]
    assert bad == [], bad[:3]
