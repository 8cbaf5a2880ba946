"""Page logic of the web app: plain functions returning numbers, tables and PNG bytes.

No Streamlit here, so everything is testable directly and cacheable by the page.
Units: SI, angles in deg, speed in rev/min, as in the rest of the package.

What a visitor may send and what the server may touch: docs/app_threat_model.md.  An
uploaded case file is kept in memory only (`stage_case_file`; never written to disk)
and validated by `rotarydryer.cases.load_case_text`: it may name shipped data sets
only, never a path.
"""

from __future__ import annotations

import hashlib
import io
import math
import tempfile
import threading
import warnings
from collections import OrderedDict
from contextlib import contextmanager
from pathlib import Path

import numpy as np

__all__ = ["presets", "geometry_view", "stage_case_file", "case_defaults", "transport_view", "tracer_sources", "fit_tracer",
           "tracer_models", "TRACER_BASELINES",
           "png", "check_upload_text", "visitor_message", "MAX_CASE_UPLOAD_BYTES", "MAX_TRACER_UPLOAD_BYTES", "MAX_TRACER_ROWS",
           "MAX_UPLOAD_MB", "MAX_STAGED_CASES", "schema_bounds", "input_range", "widen", "geometry_range"]

#: ``server.maxUploadSize`` and the uploaders' ``max_upload_size`` (MB; Streamlit's minimum is 1)
MAX_UPLOAD_MB = 1
#: bytes of an uploaded case file (the shipped cases are < 10 kB)
MAX_CASE_UPLOAD_BYTES = 200_000
#: bytes of an uploaded tracer CSV
MAX_TRACER_UPLOAD_BYTES = 1_000_000
#: data rows of an uploaded tracer CSV
MAX_TRACER_ROWS = 20_000
#: uploaded case files kept in memory (all sessions; least recently used dropped first)
MAX_STAGED_CASES = 32
#: characters of an error message shown to a visitor
MAX_MESSAGE_CHARS = 1500

_UPLOAD_PREFIX = "uploaded_case_"
_staged: OrderedDict[str, str] = OrderedDict()
_staged_lock = threading.Lock()


def visitor_message(exc: BaseException) -> str:
    """The text of an error shown on the page: the message of a ``ValueError`` (the package's
    input errors name the key, the value and what is allowed; they contain the visitor's own
    input only), cut to `MAX_MESSAGE_CHARS`; for any other exception only a generic
    sentence with its type (the details go to the server log, never to the visitor)."""
    if isinstance(exc, ValueError) and not isinstance(exc, UnicodeError):
        msg = str(exc)
        return msg if len(msg) <= MAX_MESSAGE_CHARS else msg[:MAX_MESSAGE_CHARS] + " ..."
    return f"internal error ({type(exc).__name__}); the details are in the server log"


def check_upload_text(text: str, what: str, max_bytes: int, max_rows: int) -> str:
    """An uploaded CSV's text within ``max_bytes`` (UTF-8) and ``max_rows`` data rows (below the
    header; blank and ``#`` lines not counted), else ``ValueError`` naming the limit."""
    size = len(text.encode("utf-8", "replace"))
    if size > max_bytes:
        raise ValueError(f"the {what} has {size} bytes; the limit is {max_bytes} bytes")
    rows = sum(1 for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#"))
    if rows - 1 > max_rows:
        raise ValueError(f"the {what} has {rows - 1} data rows; the limit is {max_rows}")
    return text


def run_warnings(fn, *args, **kwargs):
    """``(fn(*args, **kwargs), [messages])``: the warnings the run gives (the CLI prints them; a page shows them,
    they reached only the server's log: a speed at 98 % of the critical, a run outside a law's calibration, a
    controller's gas its burner cannot make), each once, in order; deprecations and resource warnings left out."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = fn(*args, **kwargs)
    messages = []
    for w in caught:
        if issubclass(w.category, (DeprecationWarning, PendingDeprecationWarning, ResourceWarning)):
            continue
        text = " ".join(str(w.message).split())
        if text not in messages:
            messages.append(text)
    return out, messages


def png(fig, dpi: int = 90) -> bytes:
    """PNG bytes of a Matplotlib figure; closes it."""
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    plt.close(fig)
    return buf.getvalue()


def presets() -> dict:
    """Built-in drums (``rotarydryer.geometry.presets``), two-section and polygonal flights: name -> entry
    dict (a polygonal flight's entry has ``segments`` or ``vertices`` instead of s1, s2, alpha1, alpha2)."""
    from ..geometry.presets import builtin_drums

    return builtin_drums()


def profile_view(name: str, radius: float, n_flights: int, repose_angle: float, rpm: float, slope: float,
                 bulk_density: float, length: float, images: bool = True) -> dict:
    """`geometry_view` of a built-in drum with a polygonal flight (``name``: a `flight_profiles` entry),
    at its own flight shape with ``radius`` and ``n_flights`` (a flight that no longer fits the drum is
    refused naming them), plus ``"sections"``: the flight's [length m, angle deg] from base to tip."""
    from .._validation import fmt_number
    from ..geometry import FlightedDrum
    from ..geometry.presets import flight_profiles, preset_drum

    if name not in flight_profiles():
        raise ValueError(f"drum = {name!r} is not a built-in drum with a polygonal flight; choose one of "
                         f"{', '.join(flight_profiles())}")
    _check_view_inputs(n_flights, bulk_density, length)
    base, _ = preset_drum(name)
    try:
        drum = FlightedDrum(radius, int(n_flights), base.flight)
    except ValueError as exc:
        raise ValueError(f"radius = {fmt_number(radius)} m, n_flights = {int(n_flights)}: {exc}") from None
    out = _drum_view(drum, repose_angle, rpm, slope, bulk_density, length, images)
    out["sections"] = [[float(a), float(b)] for a, b in drum.profile.segments]
    return out


def geometry_view(radius: float, n_flights: int, s1: float, s2: float, alpha1: float, alpha2: float,
                  repose_angle: float, rpm: float, slope: float, bulk_density: float, length: float,
                  images: bool = True) -> dict:
    """Flight-unloading summary of one drum (Lee (2008) ch. 4) for the geometry page.

    Returns ``{"summary": [(quantity, value, unit)], "design_loads": [(method, m2, kg)],
    "metrics": {...}, "cross_section": png, "profile": png}``.  Raises ``ValueError``
    (naming the argument) on impossible geometry.
    """
    from ..geometry import FlightedDrum, TwoSectionFlight

    _check_view_inputs(n_flights, bulk_density, length)
    drum = FlightedDrum(radius, int(n_flights), TwoSectionFlight(s1, s2, alpha1, alpha2))
    return _drum_view(drum, repose_angle, rpm, slope, bulk_density, length, images)


def _check_view_inputs(n_flights, bulk_density, length) -> None:
    """The geometry page's inputs that the drum does not check, before it is built (their own messages)."""
    from .._validation import check_range

    if isinstance(n_flights, bool) or float(n_flights) != int(n_flights):
        raise ValueError(f"n_flights = {n_flights!r} is not a whole number of flights")    # 2.7 became 2 (fuzzing)
    check_range("bulk_density", bulk_density, 0.0, 5000.0, unit="kg/m^3")
    check_range("length", length, 0.0, 200.0, unit="m")


def _drum_view(drum, repose_angle, rpm, slope, bulk_density, length, images):
    """The geometry page's numbers and figures of a built drum (any flight shape; inputs checked by
    `_check_view_inputs`)."""
    from ..geometry import DESIGN_LOAD_METHODS
    from ..geometry.drum import check_speed

    check_speed("rpm", rpm, drum.radius, radius_key="radius", warn=False)     # refuse at/above critical speed
    cs = drum.cascade(repose_angle, 1.0, rpm=rpm, slope=slope)
    tr = drum.transition_angles(repose_angle)
    loads = [(m, float(drum.design_load_area(repose_angle, method=m))) for m in DESIGN_LOAD_METHODS]
    design = dict(loads)["lee2008"] * bulk_density * length
    summary = [
        ("flight-tip radius R_F (Lee (2008) Eq. 4.6)", round(drum.tip_radius, 5), "m"),
        ("flight spacing (Eq. 4.5)", round(drum.flight_spacing, 3), "deg"),
        ("full-flight holdup (Eq. 4.8)", round(drum.full_holdup_area * 1e4, 2), "cm2 per m"),
        ("transition angles psi1-psi5 (Eq. 4.9-4.13)", ", ".join(f"{float(a):.1f}" for a in tr), "deg"),
        ("discharge starts at", round(float(cs.discharge_start_angle), 2), "deg"),
        ("mean release angle (Eq. 3.3)", round(float(cs.mean_release_angle), 2), "deg"),
        ("mean fall height", round(float(cs.mean_fall_height), 4), "m"),
        ("mean fall time (active time)", round(float(cs.mean_fall_time), 4), "s"),
        ("passive time (Eq. 3.4)", round(float(cs.passive_time), 3), "s"),
    ]
    out = {
        "summary": summary,
        "design_loads": [(m, round(a, 5), round(a * bulk_density * length, 1)) for m, a in loads],
        "metrics": {"design_load_kg": design, "mean_fall_height_m": float(cs.mean_fall_height),
                    "passive_time_s": float(cs.passive_time), "mean_fall_time_s": float(cs.mean_fall_time)},
    }
    if images:
        from ..report.plots import draw_cross_section, plot_unloading_profile

        out["cross_section"] = png(draw_cross_section(drum, repose_angle, angle=90.0))
        out["profile"] = png(plot_unloading_profile(drum, repose_angle, rpm))
    return out


def stage_case_file(content: bytes) -> str:
    """Keep an uploaded case file (TOML bytes) in memory and return its content-addressed
    name ``uploaded_case_<sha256 prefix>`` (so results cache by content), which
    `case_defaults` and `transport_view` accept in place of a built-in case.
    Nothing is written to disk; at most `MAX_STAGED_CASES` files are kept.  Raises
    ``ValueError`` when the file is larger than `MAX_CASE_UPLOAD_BYTES`, not UTF-8 or
    not TOML."""
    import tomllib

    content = bytes(content)
    if len(content) > MAX_CASE_UPLOAD_BYTES:
        raise ValueError(f"the case file has {len(content)} bytes; the limit is {MAX_CASE_UPLOAD_BYTES} bytes")
    try:
        text = content.decode("utf-8-sig")     # a leading byte-order mark is dropped
    except UnicodeDecodeError as exc:
        raise ValueError(f"not a valid UTF-8 TOML file: byte 0x{content[exc.start]:02x} at offset {exc.start} "
                         "is not UTF-8") from None
    try:
        tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"not a valid UTF-8 TOML file: {exc}") from None
    except RecursionError:
        raise ValueError("not a valid UTF-8 TOML file: nested too deeply") from None
    key = _UPLOAD_PREFIX + hashlib.sha256(content).hexdigest()[:16]
    with _staged_lock:
        _staged[key] = text
        _staged.move_to_end(key)
        while len(_staged) > MAX_STAGED_CASES:
            _staged.popitem(last=False)
    return key


def _is_upload(case: str) -> bool:
    return isinstance(case, str) and case.startswith(_UPLOAD_PREFIX)


def _load(case: str, overrides: dict | None = None):
    """The validated case of a built-in name or of a staged upload (never a path)."""
    from ..cases import load_case, load_case_text

    if _is_upload(case):
        with _staged_lock:
            text = _staged.get(case)
        if text is None:
            raise ValueError("the uploaded case file is no longer held by the server; upload it again")
        return load_case_text(text, "uploaded case", overrides)
    _check_builtin(case)
    return load_case(case, overrides)


@contextmanager
def case_source(case: str):
    """``with case_source(case) as src:`` a name or path the library's loaders read: a built-in
    name as it is, an uploaded case as a temporary .toml file (removed afterwards)."""
    if not _is_upload(case):
        _load(case)                 # a known built-in name (refuses anything else)
        yield case
        return
    with _staged_lock:
        text = _staged.get(case)
    if text is None:
        raise ValueError("the uploaded case file is no longer held by the server; upload it again")
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "uploaded_case.toml"
        path.write_text(text, encoding="utf-8")
        yield str(path)


def case_label(case: str) -> str:
    """The case as the pages name it: a built-in name as it is, an upload as "uploaded case" (a view ran on a
    temporary file of it, whose path the results would otherwise show)."""
    return "uploaded case" if _is_upload(case) else case


def _check_builtin(case) -> None:
    from ..cases import list_cases

    if case not in list_cases():
        raise ValueError(f"case = {case!r} is not a built-in case ({', '.join(list_cases())}) "
                         "nor an uploaded case file")


def schema_bounds(model, key: str) -> tuple[float | None, float | None]:
    """``(low, high)`` of the override ``key`` (``"section.field"``) in the case schema ``model``
    (a pydantic model class, e.g. ``type(case)``): the field's ``gt``/``ge`` and ``lt``/``le``
    constraints, ``None`` for a side without one (or a key the schema does not have).  An
    excluded end (``gt=0``) is returned as is: a widget may reach it and the model refuses it
    with the CLI's message."""
    import typing

    fields = getattr(model, "model_fields", {})
    parts = key.split(".")
    for i, part in enumerate(parts):
        f = fields.get(part)
        if f is None:
            return None, None
        if i == len(parts) - 1:
            lo = hi = None
            for md in f.metadata:
                for name in ("gt", "ge"):
                    if getattr(md, name, None) is not None:
                        lo = float(getattr(md, name))
                for name in ("lt", "le"):
                    if getattr(md, name, None) is not None:
                        hi = float(getattr(md, name))
            return lo, hi
        ann = f.annotation
        subs = [a for a in (typing.get_args(ann) or (ann,)) if isinstance(a, type) and hasattr(a, "model_fields")]
        if not subs:
            return None, None
        fields = subs[0].model_fields
    return None, None


def widen(low, high, value):
    """Widget bounds ``(low, high)`` widened so that they contain ``value`` (``None``: no bound).
    Integers stay integers (Streamlit wants one type for the bounds and the value)."""
    as_int = isinstance(value, int) and not isinstance(value, bool)
    cast = int if as_int else float
    v = cast(value)
    lo = None if low is None or (isinstance(low, float) and not math.isfinite(low)) else min(cast(low), v)
    hi = None if high is None or (isinstance(high, float) and not math.isfinite(high)) else max(cast(high), v)
    return lo, hi


#: inputs of `geometry_view` -> the case key whose schema range they take (the dryer schema)
_GEOMETRY_KEYS = {"radius": "drum.radius", "n_flights": "drum.n_flights", "s1": "flight.s1", "s2": "flight.s2",
                  "alpha1": "flight.alpha1", "alpha2": "flight.alpha2", "rpm": "operating.rpm",
                  "slope": "drum.slope", "length": "drum.length"}
#: inputs of `geometry_view` the case schema does not hold: the ranges the geometry checks
#: refuse outside (``rotarydryer.geometry.design_load``: repose angle (0, 90) deg, bulk density > 0)
_GEOMETRY_RANGES = {"repose_angle": (0.0, 90.0), "bulk_density": (0.0, None)}


def geometry_range(name: str, value) -> tuple:
    """Widget bounds of the input ``name`` of `geometry_view` at ``value`` (a preset's): the
    dryer schema's range of the matching case key (``drum.radius`` ...) or the range the geometry
    checks allow, widened to contain ``value``."""
    if name in _GEOMETRY_KEYS:
        from ..cases import CASE_MODELS

        lo, hi = schema_bounds(CASE_MODELS["dryer"], _GEOMETRY_KEYS[name])
    else:
        lo, hi = _GEOMETRY_RANGES[name]
    if isinstance(value, int) and not isinstance(value, bool):
        lo = None if lo is None else math.ceil(lo)
        hi = None if hi is None else math.floor(hi)
    return widen(lo, hi, value)


def input_range(case: str, key: str, value: float | None = None) -> tuple[float | None, float | None]:
    """Bounds of a widget for the override ``key`` of ``case`` (a built-in name or a staged upload):
    the schema's range of the key (`schema_bounds`), for ``operating.rpm`` also below the
    critical speed of the case's drum (``rotarydryer.geometry.drum.critical_speed``), for
    ``operating.feed_moisture`` at most the top of the material's validated moisture range, always
    widened to contain ``value`` (default: the case's own value of the key), so that the
    case's value is never outside its widget."""
    from ..cases import valid_override_keys

    c = _load(case)
    if key not in valid_override_keys(type(c)):      # (None, None) before: an unbounded widget for no key
        raise ValueError(f"{key!r} is not a key of case {case!r}")
    lo, hi = schema_bounds(type(c), key)
    if key == "operating.rpm":
        from ..geometry.drum import critical_speed

        try:
            nc = float(critical_speed(float(c.drum.radius)))
            hi = nc if hi is None else min(hi, nc)
        except (AttributeError, TypeError, ValueError):
            pass
    if key == "operating.feed_moisture":      # the material's validated range (its laws hold up to it)
        from ..cases.build import material_of

        try:
            wet_hi = float(material_of(c).wet_range()[1])
            hi = wet_hi if hi is None else min(hi, wet_hi)
        except (AttributeError, TypeError, ValueError):
            pass
    if value is None:
        obj = c
        for part in key.split("."):
            obj = getattr(obj, part, None)
        value = obj
    if value is None or not math.isfinite(float(value)):
        return lo, hi
    return widen(lo, hi, float(value))


def case_defaults(case: str) -> dict:
    """Feed rate (kg/s), speed (rev/min) and slope (deg) of a built-in case (or of an
    uploaded one, see `stage_case_file`), as used."""
    from ..cases.build import operating_point

    c = _load(case)
    feed, rpm, _, _ = operating_point(c)
    return {"feed_rate": float(feed), "rpm": float(rpm), "slope": float(c.drum.slope)}


def transport_view(case: str, feed_rate: float, rpm: float, slope: float, images: bool = True) -> dict:
    """Solids-transport steady state + tracer RTD of a built-in case at a changed operating point
    (heat and mass transfer off: the page's plots and numbers come from one model run).

    Returns ``{"results": Results, "metrics": {...}, "holdup": png, "rtd": png,
    "loading": png}`` (the PNGs only with ``images``)."""
    from ..report.figures import plot_holdup_profile, plot_loading_state, plot_rtd
    from ..simulation import run_case

    overrides = {"operating.feed_rate": feed_rate, "operating.rpm": rpm, "drum.slope": slope}
    if _is_upload(case):
        res = run_case(_load(case, overrides), applied=overrides, thermal=False)
    else:
        _check_builtin(case)  # a built-in name, never a path
        res = run_case(case, overrides, thermal=False)
    s = res.scalars
    out = {
        "results": res,
        "metrics": {
            "total_holdup_kg": s["total_holdup_kg"],
            "mean_residence_time_s": s["mean_residence_time_s"],
            "rtd_std_s": s["rtd_std_s"],
            "cells_over": int(s["cells_over"]), "cells_design": int(s["cells_design"]),
            "cells_under": int(s["cells_under"]),
        },
    }
    if images:
        out["holdup"] = png(plot_holdup_profile(res))
        out["rtd"] = png(plot_rtd(res))
        out["loading"] = png(plot_loading_state(res))
    return out


def tracer_sources() -> list[str]:
    """Names of the published tracer curves shipped with the package."""
    from ..rtd import tracer_datasets

    return tracer_datasets()


def case_tracer_dataset(case: str) -> str:
    """The published tracer curve the tracer fit starts on for ``case``: the case's own shipped
    data set (``tracer.dataset``, ``{test}`` replaced by its ``operating.test``: Ajayi's test 4 for
    the MMG case, Lee's Invicta curve for the Invicta case) when it names one, else the first of
    `tracer_sources` (a case without a tracer data set, or one that names none shipped)."""
    from ..cases import resolve_dataset

    sources = tracer_sources()
    c = _load(case)
    template = getattr(c.tracer, "dataset", None) if getattr(c, "tracer", None) is not None else None
    if template:
        name = resolve_dataset(template, getattr(c.operating, "test", ""))
        if name in sources:
            return name
    return sources[0]


#: ``baseline`` choices of `fit_tracer`: none, or a constant background fitted with the model
TRACER_BASELINES = ("none", "fit")


def tracer_models() -> tuple:
    """Models the tracer-fit page offers (``rotarydryer.rtd.RTD_FIT_MODELS``): tanks in series,
    axial dispersion and Song's (2003) Eq. 2.10-2.16 cells (interactive mixers, with dead zones)."""
    from ..rtd import RTD_FIT_MODELS

    return tuple(RTD_FIT_MODELS)


def fit_tracer(text: str | None = None, dataset: str | None = None, model: str = "tanks_in_series",
               images: bool = True, baseline: str = "none") -> dict:
    """Fit a reference RTD model (``rotarydryer.rtd.fit_tracer_data``; one of `tracer_models`)
    to a tracer CSV (text in the tracer-CSV format of `rotarydryer.rtd.tracer_data`) or to a
    shipped dataset; ``baseline="fit"`` adds a fitted constant background (signal unit, e.g. the
    lithium background of Ajayi's raw ppm).  Returns ``{"table": [(parameter, value, std_error,
    ci_low, ci_high)], "moments": {...}, "r_squared": float, "n_cells": N or None, "plot": png}``."""
    from ..rtd import fit_tracer_data, load_tracer_dataset, parse_tracer_text

    if model not in tracer_models():
        raise ValueError(f"model = {model!r} is not one of {', '.join(tracer_models())}")
    if baseline not in TRACER_BASELINES:
        raise ValueError(f"baseline = {baseline!r} is not one of {', '.join(TRACER_BASELINES)}")
    if (text is None) == (dataset is None):
        raise ValueError("give exactly one of text (an uploaded CSV) and dataset (a shipped curve)")
    if text is not None:
        check_upload_text(text, "tracer CSV", MAX_TRACER_UPLOAD_BYTES, MAX_TRACER_ROWS)
    data = parse_tracer_text(text, "uploaded CSV") if text is not None else load_tracer_dataset(dataset)
    import warnings

    with warnings.catch_warnings():        # identifiability notes are in the result ("warnings")
        warnings.simplefilter("ignore", RuntimeWarning)
        fit = fit_tracer_data(data, model, fit_baseline=baseline == "fit")
    d = fit.to_dict()
    table = [(k, v["value"], v["std_error"], v["ci_low"], v["ci_high"]) for k, v in d["parameters"].items()]
    out = {"table": table, "moments": d["outlet_moments"], "r_squared": d["r_squared"], "model": model,
           "published_mean_min": data.metadata.get("published_mean_min"), "n_cells": d["fixed"].get("n_cells"),
           "baseline": baseline, "warnings": d["warnings"]}
    if images:
        from .._plotting import pyplot as _plt

        plt = _plt()
        fig, ax = plt.subplots(figsize=(7, 3.4), constrained_layout=True)
        t = np.asarray(data.time_s, float)
        ax.plot(t / 60, data.signal, "o", ms=3.5, color="k", label="data")
        tt = np.linspace(t.min(), t.max(), 600)
        ax.plot(tt / 60, fit.predict(tt), label=f"{model}: R2 {d['r_squared']:.3f}")
        ax.set_xlabel(f"time ({data.time_column or 's'} axis shown in min)")
        ax.set_ylabel(f"signal ({data.signal_unit})")
        ax.legend(fontsize=8)
        out["plot"] = png(fig)
    if not all(math.isfinite(r[1]) for r in table):
        raise ValueError("the fit did not converge to finite parameters")
    return out
