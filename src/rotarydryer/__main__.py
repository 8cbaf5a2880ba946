"""``python -m rotarydryer``: the command line."""

from .cli import run

run()
