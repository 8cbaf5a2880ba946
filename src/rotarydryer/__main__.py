"""``python -m rotarydryer``: the command line."""

from .cli import app

app(prog_name="rotarydryer")
