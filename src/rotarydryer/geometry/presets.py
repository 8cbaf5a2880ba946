"""Built-in drums (data in ``presets.toml``, each entry with its source)."""

from __future__ import annotations

import tomllib
from functools import lru_cache
from importlib import resources

from .drum import FlightedDrum
from .flights import TwoSectionFlight

__all__ = ["drum_presets", "preset_drum"]


@lru_cache(maxsize=1)
def drum_presets() -> dict[str, dict]:
    """All built-in drum entries: name -> dict of parameters (SI, deg) and a description."""
    text = resources.files("rotarydryer.geometry").joinpath("presets.toml").read_text("utf-8")
    return tomllib.loads(text)


def preset_drum(name: str) -> tuple[FlightedDrum, dict]:
    """Build the [`FlightedDrum`][rotarydryer.geometry.presets.FlightedDrum] of a preset; returns ``(drum, entry)``."""
    presets = drum_presets()
    if name not in presets:
        raise ValueError(f"drum = {name!r} is not a built-in drum; choose one of {', '.join(presets)}")
    e = presets[name]
    flight = TwoSectionFlight(e["s1"], e["s2"], e["alpha1"], e["alpha2"])
    return FlightedDrum(e["radius"], e["n_flights"], flight), e
