"""``python -m rotarydryer.cli``: the command line."""

from . import app

app(prog_name="rotarydryer")
