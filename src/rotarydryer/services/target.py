"""Options of ``rotarydryer target`` (and of any front end asking for a target): the study of
:mod:`rotarydryer.studies.target` with its errors naming the command-line options."""

from __future__ import annotations

import math

from ._options import check_option

__all__ = ["run_target", "OPTION_LABELS"]

#: the options a front end's messages name for the study's arguments
OPTION_LABELS = {"find": "--find", "such_that": "--such-that", "bounds": "--find"}


def run_target(case: str, find: str, such_that: str, sets: dict | None = None, tol: float | None = None):
    """:func:`rotarydryer.studies.target.target` of ``case`` with the CLI's options: ``find`` =
    ``KEY`` or ``KEY=LO,HI``, ``such_that`` = ``OUTPUT=V``, ``OUTPUT<=V`` or ``OUTPUT>=V``, ``sets``
    the ``--set`` overrides, ``tol`` the output tolerance. A ``ValueError`` names the option, the
    value and the allowed range."""
    from ..studies.target import target  # the model stack: not at the front end's start-up

    if tol is not None:
        tol = check_option("--tol", tol, 0.0, math.inf)
    return target(case, find, such_that, overrides=sets or None, tol=tol, labels=OPTION_LABELS)
