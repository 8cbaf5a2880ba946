"""Built-in drums and flight profiles (data in ``presets.toml`` and ``profiles.toml``, each entry with its source).

``presets.toml`` holds drums with two-section flights (``s1``, ``s2``, ``alpha1``, ``alpha2``);
``profiles.toml`` drums with polygonal flights (``segments`` or ``vertices``,
[`PolygonFlight`][rotarydryer.geometry.flights.PolygonFlight]). A flight-profile file
(``rotarydryer flight --profile file.toml``) is one such entry: see `read_profile`.
"""

from __future__ import annotations

import math
import tomllib
from functools import lru_cache
from importlib import resources
from pathlib import Path

from .._limits import MAX_FLIGHTS
from .._validation import check_range, fmt_number
from .drum import FlightedDrum
from .flights import PolygonFlight, TwoSectionFlight

__all__ = ["drum_presets", "flight_profiles", "builtin_drums", "preset_drum", "read_profile", "profile_flight",
           "PROFILE_KEYS", "DEFAULT_REPOSE_ANGLE"]

#: keys of a flight-profile entry: the flight (``segments`` or ``vertices``), optionally its drum
#: (``radius``, ``n_flights``) and operating defaults, and text
PROFILE_KEYS = {
    "segments": "list of [length m, angle deg] from the root (first angle: base to wall; then interior angles at the bends)",
    "vertices": "list of [x m, y m] in the flight's frame, from the root [0, 0] (x forward along the wall, y inward)",
    "radius": "drum radius, m",
    "n_flights": "number of flights",
    "rpm": "drum speed, rev/min",
    "slope": "drum slope, deg",
    "length": "drum length, m (design loads in kg)",
    "bulk_density": "bulk density, kg/m^3 (design loads in kg)",
    "repose_angle": "dynamic angle of repose the flight was designed for, deg",
    "name": "a name",
    "description": "what the flight is and where its dimensions come from",
    "design": "how the profile was made",
}


#: smallest and largest drum radius of a flight profile or ``rotarydryer flight --radius``, m (a millimetre drum is no
#: drum; at 1e-200 m the pocket's areas underflow to zero)
MIN_RADIUS, MAX_RADIUS = 1e-3, 20.0
#: the repose angle of a built-in drum without a design repose angle of its own, deg
DEFAULT_REPOSE_ANGLE = 45.0


def builtin_drums() -> dict[str, dict]:
    """Every built-in drum, the two-section presets (`drum_presets`) and the polygonal flights' (`flight_profiles`):
    name -> entry (what `preset_drum` builds)."""
    return {**drum_presets(), **flight_profiles()}


@lru_cache(maxsize=1)
def drum_presets() -> dict[str, dict]:
    """All built-in drums with two-section flights: name -> dict of parameters (SI, deg) and a description."""
    text = resources.files("rotarydryer.geometry").joinpath("presets.toml").read_text("utf-8")
    return tomllib.loads(text)


@lru_cache(maxsize=1)
def flight_profiles() -> dict[str, dict]:
    """All built-in drums with polygonal flights: name -> entry (``segments``, drum, operating defaults, source)."""
    text = resources.files("rotarydryer.geometry").joinpath("profiles.toml").read_text("utf-8")
    return tomllib.loads(text)


def profile_flight(entry: dict, where: str = "") -> PolygonFlight:
    """The [`PolygonFlight`][rotarydryer.geometry.flights.PolygonFlight] of a profile entry (``segments`` or ``vertices``);
    messages name the keys with the prefix ``where``."""
    has = [k for k in ("segments", "vertices") if k in entry]
    if len(has) != 1:
        raise ValueError(f"{where}{'segments and vertices are both given' if has else 'segments (or vertices) is missing'}: "
                         "give the flight as segments = [[length_m, angle_deg], ...] or vertices = [[x_m, y_m], ...]")
    k = has[0]
    try:        # the flight's messages name its keys (segments[1], vertices[2], ...): the prefix once, before them
        if k == "segments":
            return PolygonFlight(entry[k], key="segments")
        return PolygonFlight(vertices=entry[k], key="vertices")
    except ValueError as exc:
        raise ValueError(f"{where}{exc}") from None


def preset_drum(name: str) -> tuple[FlightedDrum, dict]:
    """Build the [`FlightedDrum`][rotarydryer.geometry.presets.FlightedDrum] of a preset (`drum_presets` or
    `flight_profiles`); returns ``(drum, entry)``."""
    presets = drum_presets()
    profiles = flight_profiles()
    if name in presets:
        e = presets[name]
        flight = TwoSectionFlight(e["s1"], e["s2"], e["alpha1"], e["alpha2"])
        return FlightedDrum(e["radius"], e["n_flights"], flight), e
    if name in profiles:
        e = profiles[name]
        return FlightedDrum(e["radius"], e["n_flights"], profile_flight(e)), e
    raise ValueError(f"drum = {name!r} is not a built-in drum; choose one of {', '.join([*presets, *profiles])}")


def read_profile(path) -> dict:
    """A flight-profile file (TOML): one entry of `PROFILE_KEYS` (``segments`` or ``vertices`` required;
    ``radius`` and ``n_flights`` optional, taken from the drum it is used with otherwise). Returns the
    entry with its flight checked (``ValueError`` naming the file, the key, the value and the allowed range)."""
    p = Path(path)
    where = f"{p}: "
    try:
        text = p.read_text("utf-8")
    except FileNotFoundError:
        raise ValueError(f"--profile = {str(p)!r}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"--profile = {str(p)!r} cannot be read ({exc})") from None
    try:
        entry = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{where}not valid TOML ({exc})") from None
    if isinstance(entry.get("flight"), dict) and not ({"segments", "vertices"} & set(entry)):
        entry = {**{k: v for k, v in entry.items() if k != "flight"}, **entry["flight"]}   # a [flight] table
    unknown = sorted(set(entry) - set(PROFILE_KEYS))
    if unknown:
        raise ValueError(f"{where}{unknown[0]} is not a key of a flight profile; allowed: {', '.join(PROFILE_KEYS)}")
    out = dict(entry)
    for k, lo, hi, unit in (("radius", MIN_RADIUS, MAX_RADIUS, "m"), ("rpm", 0.0, math.inf, "rev/min"),
                            ("slope", -45.0, 45.0, "deg"), ("length", 0.0, math.inf, "m"),
                            ("bulk_density", 1.0, 23000.0, "kg/m^3"), ("repose_angle", 0.0, 90.0, "deg")):
        if k in entry:
            out[k] = float(check_range(f"{where}{k}", entry[k], lo, hi, low_inclusive=k == "radius",
                                       high_inclusive=k == "radius", unit=unit))
    if "n_flights" in entry:
        n = entry["n_flights"]
        if isinstance(n, bool) or not isinstance(n, int) or not 2 <= n <= MAX_FLIGHTS:
            raise ValueError(f"{where}n_flights = {fmt_number(n) if isinstance(n, (int, float)) else repr(n)} is "
                             f"outside the allowed range: an integer in [2, {MAX_FLIGHTS}]")
    out["flight"] = profile_flight(entry, where)
    return out
