"""Options and analyses of ``rotarydryer lab rig|image|design-load|steps|drying`` and of the web app's
Lab data page (flight-unloading rig runs, drum photographs, design-load fits, Song's step tests,
thin-layer drying laws from drying curves)."""

from __future__ import annotations

import re
import warnings

import numpy as np

from .._validation import finite_number
from ._options import check_option

__all__ = ["check_rig_options", "rig_analysis", "image_options", "measure_image", "design_load_fits",
           "check_steps_options", "steps_analysis", "check_drying_options", "drying_analysis"]


def _pair(text: str, name: str):
    """'otsu', '168' or '168,177' -> 'otsu', 168.0 or (168.0, 177.0) grey levels in [0, 255]."""
    t = text.strip().lower()
    if t == "otsu":
        return "otsu"
    try:
        vals = [float(v) for v in t.split(",")]
    except ValueError:
        raise ValueError(f"{name} = {text!r} must be 'otsu', a grey level or 'upper,lower' (0 .. 255)") from None
    if len(vals) not in (1, 2):
        raise ValueError(f"{name} = {text!r} must be 'otsu', a grey level or 'upper,lower' (0 .. 255)")
    for v in vals:
        check_option(name, v, 0, 255, low_inclusive=True, high_inclusive=True, unit="(grey level)")
    return vals[0] if len(vals) == 1 else tuple(vals)


def _choice(option: str, value: str, choices) -> str:
    if value not in choices:
        raise ValueError(f"{option} = {value!r} is not one of {', '.join(choices)}")
    return value


def _centre(text: str):
    """``--centre 'column,row'`` (px) -> (column, row) floats."""
    parts = text.split(",")
    if len(parts) != 2:
        raise ValueError(f"--centre = {text!r} must be 'column,row' in px (two numbers, e.g. 970,970)")
    out = []
    for part, what in zip(parts, ("column", "row")):
        try:
            v = float(part)
        except ValueError:
            raise ValueError(f"--centre = {text!r}: the {what} {part.strip()!r} is not a number "
                             "(expected 'column,row' in px, e.g. 970,970)") from None
        out.append(check_option(f"--centre {what}", v, unit="px"))
    return tuple(out)


def check_rig_options(flight="alternative", rpm=2.0, start_angle=90.0, bulk_density=1474.0, length=1.0,
                      repose_angle=None, repose_sd=0.0, cutoff=1.5, phase="zero"):
    """Check the options of ``rotarydryer lab rig`` (``ValueError`` naming the option; the web app
    calls this too, for the same messages)."""
    from ..lab import flight_rig as fr

    _choice("--flight", flight, tuple(fr.RIG_FLIGHTS))
    _choice("--phase", phase, fr.FILTER_PHASES)
    check_option("--rpm", rpm, 0, 100, high_inclusive=True, unit="rev/min")
    check_option("--start-angle", start_angle, 0, 360, low_inclusive=True, unit="deg")
    check_option("--bulk-density", bulk_density, 0, 20000, high_inclusive=True, unit="kg/m^3")
    check_option("--length", length, 0, 100, high_inclusive=True, unit="m")
    if repose_angle is not None:
        check_option("--repose-angle", repose_angle, 0, 90, unit="deg")
    check_option("--repose-sd", repose_sd, 0, 45, low_inclusive=True, high_inclusive=True, unit="deg")
    check_option("--cutoff", cutoff, 0, unit="Hz")


def rig_analysis(run, name, flight="alternative", rpm=2.0, start_angle=90.0, bulk_density=1474.0, length=1.0,
                 repose_angle=None, repose_sd=0.0, cutoff=1.5, phase="zero", fit_bulk_density=False):
    """Repose-angle fit and band analysis of a rig run as ``rotarydryer lab rig`` does them
    (``name`` names the record in the messages): returns ``(RigFit, RigAnalysis)``."""
    from ..lab import flight_rig as fr

    if cutoff >= run.sample_rate / 2:
        raise ValueError(f"--cutoff = {cutoff:g} Hz must be below half the sampling rate of {name} "
                         f"({run.sample_rate / 2:g} Hz)")
    drum = fr.rig_drum(flight)
    phi_hi = repose_angle if repose_angle is not None else 89.5
    psi5 = float(drum.transition_angles(phi_hi).psi5)
    if start_angle >= psi5:
        raise ValueError(
            f"--start-angle = {start_angle:g} deg is past the end of unloading of the {flight} flight "
            f"({psi5:.1f} deg at a repose angle of {phi_hi:g} deg): the flight holds no solids there"
        )
    caught: list = []
    try:
        with warnings.catch_warnings(record=True) as caught:        # said after the analysis, unless it is refused
            warnings.simplefilter("always")
            f = fr.fit_repose_angle(run, drum, rpm=rpm, start_angle=start_angle, bulk_density=bulk_density,
                                    length=length, fit_bulk_density=fit_bulk_density, cutoff=cutoff)
        rho = f.params["bulk_density"]
        sd = repose_sd if (repose_angle is not None or repose_sd > 0) else f.stderr["repose_angle"]
        phi = float(f.repose_angle)
        at_bound = min(phi - fr.RIG_REPOSE_BOUNDS[0], fr.RIG_REPOSE_BOUNDS[1] - phi) < 1e-3
        if not sd < 90.0 or (repose_angle is None and at_bound):
            # infinite, or a fitted interval wider than the angle's range (was "repose_sd = 925 deg is outside the
            # allowed range", an option the user had not given), or an angle at the end of its search (0.5 deg
            # "fitted" at 100 rev/min, with a -35 to 36 deg interval, exit 0; found by fuzzing)
            why = (f"its standard error is {sd:.3g} deg" if not sd < 90.0 else
                   f"the fit ends at the bound of its search, {phi:.3g} deg")
            raise ValueError(f"the record does not determine the repose angle ({why}): the unloading model does not "
                             "describe it, so there is no model band to compare it with; check --start-angle, "
                             "--flight, --rpm and the record's columns (time, load cells in kg), or give "
                             "--repose-angle and --repose-sd")
        with warnings.catch_warnings(record=True) as later:
            warnings.simplefilter("always")
            a = fr.analyse_run(run, drum, rpm=rpm, start_angle=start_angle, bulk_density=rho, length=length,
                               repose_angle=repose_angle if repose_angle is not None else f.repose_angle,
                               repose_sd=sd, cutoff=cutoff, phase=phase, fit=False)
    except ValueError as exc:
        # the one-line error alone: the fit's warnings before it repeated what it says (found by fuzzing)
        raise ValueError(f"{name}: {exc}") from None
    for w in [*caught, *later]:
        warnings.warn(w.message, w.category, stacklevel=2)
    return f, a


def image_options(centre, drum="ajayi_pilot", px_per_m=None, known_length_px=None, known_length_m=None, mirror=False,
                  reference_angle=90.0, channel=0, threshold="168,177", airborne_threshold="104,120",
                  smooth_sigma=0.0):
    """Check the options of ``rotarydryer lab image`` (``ValueError`` naming the option; the web app
    calls this too, for the same messages): returns ``(drum, calibration, scale option name,
    threshold, airborne threshold)``."""
    from ..geometry.presets import preset_drum
    from ..lab import images as im

    c = _centre(centre)
    try:
        d, _ = preset_drum(drum)
    except ValueError as exc:
        raise ValueError(f"--drum: {exc}") from None
    if px_per_m is None:
        if known_length_px is None or known_length_m is None:
            raise ValueError("give --px-per-m, or --known-length-px with --known-length-m")
        check_option("--known-length-px", known_length_px, 0, 1e6, high_inclusive=True, unit="px")
        check_option("--known-length-m", known_length_m, 0, 100, high_inclusive=True, unit="m")
        scale_name = "--known-length-px/--known-length-m"
        cal = im.ImageCalibration.from_known_length(c, known_length_px, known_length_m, mirror=mirror)
    else:
        if known_length_px is not None or known_length_m is not None:
            # both scales: --px-per-m won silently (found by fuzzing)
            raise ValueError("give --px-per-m, or --known-length-px with --known-length-m, not both")
        check_option("--px-per-m", px_per_m, 0, 1e7, high_inclusive=True, unit="px/m")
        scale_name = "--px-per-m"
        cal = im.ImageCalibration(c, px_per_m, mirror=mirror)
    check_option("--reference-angle", reference_angle, -360, 360, low_inclusive=True, high_inclusive=True,
                 unit="deg")
    check_option("--channel", channel, 0, 3, low_inclusive=True, high_inclusive=True)
    thr = _pair(threshold, "--threshold")
    athr = _pair(airborne_threshold, "--airborne-threshold")
    check_option("--smooth-sigma", smooth_sigma, 0, 100, low_inclusive=True, unit="px")     # the library's [0, 100)
    return d, cal, scale_name, thr, athr


def measure_image(img, name, d, cal, scale_name, reference_angle=90.0, channel=0, threshold="168,177",
                  airborne_threshold="104,120", smooth_sigma=0.0):
    """Measure a photograph (an array from `rotarydryer.lab.images.load_image`) as
    ``rotarydryer lab image`` does, after `image_options` (``name`` names it in messages)."""
    from ..lab import images as im

    nch = 1 if img.ndim == 2 else img.shape[2]
    if channel >= nch:
        raise ValueError(f"--channel = {channel} is not a channel of {name} ({nch} channel"
                         f"{'s' if nch > 1 else ''}: 0 .. {nch - 1})")
    im.check_drum_in_image(img.shape, d, cal, image_name=name, centre_name="--centre", scale_name=scale_name)
    return im.measure(img, d, cal, reference_angle=reference_angle, channel=channel,
                      threshold=threshold, airborne_threshold=airborne_threshold, smooth_sigma=smooth_sigma)


def design_load_fits(groups: dict, name: str, grouped: bool, confidence: float = 0.95) -> dict:
    """Break-point fits per group of a design-load table as ``rotarydryer lab design-load`` does
    them (``name`` names the table in the messages; the web app calls this too)."""
    from ..lab import design_load_fit as dl

    check_option("--confidence", confidence, 0, 1)
    fits = {}
    for g, pts in groups.items():
        x, y = zip(*pts)
        try:
            fits[g] = dl.fit_break_point(x, y, confidence=confidence)
        except ValueError as exc:
            where = f"group {g!r} of {name}" if grouped else name
            raise ValueError(f"{where}: {exc}") from None
    return fits


def _step_times(text: str, factor: float):
    """``--steps '0,37'`` (in the record's time unit) -> step times in s."""
    hint = " (give the step times in the unit of the record's time column, separated by commas, e.g. 0,37)"
    return [finite_number(part.strip(), f"--steps = {text!r}:", hint) * factor for part in text.split(",")]


def check_steps_options(threshold=0.1, plateau=0.2, tolerance=0.05, initial_holdup=0.0):
    """Check the options of ``rotarydryer lab steps`` (``ValueError`` naming the option; the web app
    calls this too, for the same messages)."""
    check_option("--threshold", threshold, 0, 1, unit="(fraction of the largest feed)")
    check_option("--plateau", plateau, 0, 1, high_inclusive=True, unit="(fraction of an interval)")
    check_option("--tolerance", tolerance, 0, 1, unit="(fraction of the largest feed)")
    check_option("--initial-holdup", initial_holdup, 0, 1e7, low_inclusive=True, high_inclusive=True, unit="kg")


def steps_analysis(rec, name, step_times=None, threshold=0.1, plateau=0.2, tolerance=0.05, initial_holdup=0.0):
    """Song's step method on a record as ``rotarydryer lab steps`` applies it (``step_times``: the
    ``--steps`` text, in the unit of the time column; ``name`` names the record in messages)."""
    from ..lab import steps as sm

    factor = sm.TIME_COLUMNS[rec.columns["time"]]
    times = None
    if step_times is not None:
        times = _step_times(step_times, factor)
        unit = rec.columns["time"].split("_", 1)[1]
        shown = ", ".join(f"{x / factor:g}" for x in times)
        if any(b <= a for a, b in zip(times, times[1:])):
            raise ValueError(f"--steps = {shown} {unit} must increase")
        t0, t1 = float(rec.time[0]), float(rec.time[-1])
        if times[0] < t0 or times[-1] >= t1:
            raise ValueError(f"--steps = {shown} {unit} must lie inside the record of {name} "
                             f"[{t0 / factor:g}, {t1 / factor:g}) {unit}")
    a = sm.analyse_steps(rec, times, threshold=threshold, plateau=plateau, tolerance=tolerance,
                         initial_holdup=initial_holdup)
    return a


def check_drying_options(model=None, equilibrium_moisture=None, reference_temperature=None, material_out=None,
                         base_material=None, material_name=None, particle_diameter=None):
    """Check the options of ``rotarydryer lab drying`` before any file is read (``ValueError`` naming
    the option, the value and the allowed range)."""
    from ..properties.materials import list_materials
    from ..properties.thin_layer import MODELS

    if model is not None:
        _choice("--model", model, tuple(MODELS))
    if equilibrium_moisture is not None:
        check_option("--equilibrium-moisture", equilibrium_moisture, 0, 50, low_inclusive=True, unit="kg/kg dry")
    if reference_temperature is not None:
        check_option("--reference-temperature", reference_temperature, 0, 400, low_inclusive=True,
                     high_inclusive=True, unit="degC")
    if particle_diameter is not None:
        check_option("--particle-diameter", particle_diameter, 0, 0.2, unit="m")
    extra = [o for o, v in (("--base-material", base_material), ("--material-name", material_name),
                            ("--particle-diameter", particle_diameter)) if v is not None]
    if material_out is None:
        if extra:
            raise ValueError(f"{extra[0]} is given without --material-out; it describes the material file to write")
        return
    if not str(material_out).lower().endswith(".toml"):
        raise ValueError(f"--material-out {str(material_out)!r} is not a .toml file name (e.g. my_material.toml)")
    names = list_materials()
    if base_material is None:
        raise ValueError("--material-out needs --base-material NAME: the library material whose repose angle, bulk "
                         f"density, heat capacity and particle data the new material takes ({', '.join(names)})")
    _choice("--base-material", base_material, tuple(names))
    if material_name is not None:
        if not re.fullmatch(r"[A-Za-z0-9_][A-Za-z0-9_.\-]{0,99}", material_name):
            raise ValueError(f"--material-name = {material_name!r} is not a plain name (letters, digits, '_', '-', "
                             "'.', at most 100 characters)")
        if material_name in names:
            raise ValueError(f"--material-name = {material_name!r} is a library material; give the new material its "
                             "own name")


#: drying curves whose every weighing after time 0 has a moisture ratio below this resolve no drying
DRYING_RESOLVED_MR = 0.01


def drying_analysis(curves, model=None, reference_temperature=None):
    """The thin-layer laws fitted to ``curves`` as ``rotarydryer lab drying`` fits them: returns
    ``(DryingFit, chosen law name)``: ``model`` (``--model``, which must be one that could be fitted),
    else the lowest AICc among the fits that are drying laws."""
    from ..lab import drying_curves as dc

    t_ref = None if reference_temperature is None else float(reference_temperature) + 273.15
    after = curves.moisture_ratio[curves.time_s > 0]
    if after.size and float(np.max(after)) < DRYING_RESOLVED_MR:
        # every law then fits to rounding, R^2 is undefined and the rate constant is any fast one (found by fuzzing)
        raise ValueError(f"{curves.name}: every weighing after time 0 is already at equilibrium (moisture ratio at most "
                         f"{float(np.max(after)):.2g}): the curves do not resolve the drying, and no rate constant "
                         "follows from them; weigh sooner after the start")
    result = dc.fit_models(curves, reference_temperature_K=t_ref)
    if model is not None:
        if model not in result.fits:
            raise ValueError(f"--model = {model!r} could not be fitted to {curves.name}: {result.skipped[model]}")
        return result, model
    if result.best_law is None:
        why = "; ".join(f"{m}: {f.law_problem}" for m, f in result.fits.items())
        raise ValueError(f"{curves.name}: no fitted law is a drying law ({why})")
    return result, result.best_law.model
