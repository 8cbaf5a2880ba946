"""Shared front-end logic: the option checks and runners used by both the command line
(`rotarydryer.cli`) and the web app (`rotarydryer.app`).

A bad value raises ``ValueError`` with a one-line message naming the option, the value and the
allowed range (``--rpm = -2 rev/min is outside the allowed range; allowed: (0, 100] rev/min``), so
both front ends show the same text.  Nothing here prints (progress, where there is any, goes to a
``progress=None`` callback) and nothing imports typer, click, streamlit, `rotarydryer.cli` or
`rotarydryer.app`: the front ends import this layer, never each other.  Heavy libraries
(SciPy, Matplotlib, the lab extras) are imported inside the functions, so importing a module of
this package is cheap.

- `rotarydryer.services.control`: ``rotarydryer control`` / the Control page
- `rotarydryer.services.design`: ``rotarydryer design`` / the Design page
- `rotarydryer.services.lab`: ``rotarydryer lab ...`` / the Lab data page
"""
