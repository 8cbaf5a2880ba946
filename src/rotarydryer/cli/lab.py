"""``rotarydryer lab``: laboratory data tools (flight-unloading rig, photographs, design-load fits, step
tests, drying curves)."""

import math
from pathlib import Path
from typing import Optional

import typer

from .._io import json_text
from ..services.lab import (
    check_drying_options,
    check_rig_options,
    check_steps_options,
    design_load_fits,
    drying_analysis,
    image_options,
    measure_image,
    rig_analysis,
    steps_analysis,
)
from . import app
from ._common import check_option, check_out_dir, check_out_file

lab_app = typer.Typer(
    name="lab",
    short_help="Laboratory data: rig runs, photographs, design loads, drying.",
    help="Laboratory data: flight-unloading rig runs (Lee 2008 ch. 5), drum photographs and "
    "design-load break-point fits (Ajayi 2011 ch. 4), step tests (Song 2003 ch. 4) and thin-layer "
    "drying laws from lab drying curves.",
    no_args_is_help=True,
)
app.add_typer(lab_app, name="lab")


def _fail(exc: Exception):
    typer.echo(f"error: {exc}", err=True)
    raise typer.Exit(2)


@lab_app.command("rig", short_help="Analyse one flight-unloading rig run.")
def rig(
    run_csv: Path = typer.Argument(..., help="Load-cell CSV: time (s), then one or more load-cell columns (kg), summed."),
    flight: str = typer.Option("alternative", help="Rig flight (Lee 2008 Table 5.1): alternative | half_scale | full_scale | lee_code."),
    rpm: float = typer.Option(..., help="Rotation speed, rev/min."),
    start_angle: float = typer.Option(..., help="Flight-root angle at the start of unloading, deg (from the images; 0 = base pointing down)."),
    bulk_density: float = typer.Option(..., help="Bulk density, kg/m^3 (Lee used the consolidated value)."),
    length: float = typer.Option(1.0, help="Flight section length, m."),
    repose_angle: Optional[float] = typer.Option(None, help="Measured mean dynamic repose angle, deg, for the band (default: fitted)."),
    repose_sd: float = typer.Option(0.0, help="SD of the measured repose angle, deg; band = mean +/- 2 SD (default without --repose-angle: the fit's standard error)."),
    cutoff: float = typer.Option(1.5, help="FIR cut-off, Hz (1.5 = Lee's code fir1(200,0.03); 3 = his text)."),
    phase: str = typer.Option("zero", help="Filter phase: zero (delay-corrected) | filtfilt | causal (Lee, uncorrected)."),
    fit_bulk_density: bool = typer.Option(False, help="Also fit the bulk density."),
    out: Optional[Path] = typer.Option(None, help="Directory for rig.png and rig_aligned.csv."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
):
    """Analyse one flight-unloading rig run: filter, discharge rate, start of unloading, repose-angle
    fit with its CI, and Lee's +/- 2 SD band comparison.

    \b
    Example:
      rotarydryer lab rig run.csv --rpm 2 --start-angle 93.5 --bulk-density 1474 --repose-sd 1.7
    """
    from ..lab import flight_rig as fr

    try:
        check_rig_options(flight, rpm, start_angle, bulk_density, length, repose_angle, repose_sd, cutoff, phase)
        check_out_dir("--out", out)
        run = fr.read_rig_csv(run_csv)
        f, a = rig_analysis(run, str(run_csv), flight, rpm, start_angle, bulk_density, length, repose_angle,
                            repose_sd, cutoff, phase, fit_bulk_density)
        rho = f.params["bulk_density"]
    except (ValueError, OSError) as exc:
        _fail(exc)
    res = {
        "file": str(run_csv),
        "samples": int(run.time.size),
        "sample_rate_hz": run.sample_rate,
        "filter": {"numtaps": fr.LEE_NUMTAPS, "cutoff_hz": cutoff, "phase": phase},
        "unloading_start_s": a.start_time,
        "repose_angle_deg": f.repose_angle,
        "repose_angle_ci_deg": list(f.repose_angle_ci),
        "confidence": f.confidence,
        # the fitted parameters with the unit in each name (as every other output) and their standard errors
        "fit": _with_units(f.params),
        "fit_stderr": _with_units(f.stderr),
        # deprecated (December 2026): the same numbers without units in their names; a warning names the new keys
        "params": f.params,
        "stderr": f.stderr,
        "residual_sd_kg": f.residual_sd,
        "residual_ar1": f.ar1,
        "band_repose_deg": [a.band.repose_low, a.band.repose_high],
        "fraction_inside_band_mass": a.inside_mass,
        "fraction_inside_band_rate": a.inside_rate,
    }
    if out is not None:
        res["outputs"] = _write_rig_outputs(fr, a, run_csv, out)
    if as_json:
        typer.echo(json_text(res))
        typer.echo("warning: the JSON keys 'params' and 'stderr' are deprecated (their names carry no unit) and will "
                   "be removed: use 'fit' and 'fit_stderr' (" + ", ".join(_with_units(f.params)) + ")", err=True)
        return
    lo, hi = f.repose_angle_ci
    typer.echo(f"rig run {run_csv}: {run.time.size} samples at {run.sample_rate:g} Hz, flight {flight}, {rpm:g} rpm")
    typer.echo(f"  FIR filter: {fr.LEE_NUMTAPS} taps, cut-off {cutoff:g} Hz, {phase} phase")
    typer.echo(f"  start of unloading          {a.start_time:.3f} s")
    typer.echo(f"  fitted repose angle         {f.repose_angle:.2f} deg  ({100 * f.confidence:g} % CI {lo:.2f} - {hi:.2f})")
    if fit_bulk_density:
        blo, bhi = f.ci["bulk_density"]
        typer.echo(f"  fitted bulk density         {rho:.0f} kg/m3  (CI {blo:.0f} - {bhi:.0f})")
    typer.echo(f"  residual SD                 {f.residual_sd:.4f} kg (lag-1 autocorrelation {f.ar1:.2f})")
    typer.echo(f"  band (repose {a.band.repose_low:.1f}-{a.band.repose_high:.1f} deg): "
               f"{100 * a.inside_mass:.1f} % of mass and {100 * a.inside_rate:.1f} % of rate samples inside")
    if out is not None:
        typer.echo(f"  outputs: {', '.join(res['outputs'])}")


def _write_rig_outputs(fr, a, run_csv, out: Path) -> list:
    """rig.png and rig_aligned.csv in ``out``, rendered in memory first and written as one set
    (`rotarydryer._io.output_set`): if either write fails, the previous pair is kept."""
    import io

    from .._io import output_set, write_bytes_atomic, write_text_atomic
    from .._plotting import pyplot

    fig = fr.plot_analysis(a)
    buf = io.BytesIO()
    try:
        fig.savefig(buf, format="png", dpi=110)
    finally:
        pyplot().close(fig)
    lines = [f"# rotarydryer lab rig {run_csv}: aligned at unloading start {a.start_time:.4f} s",
             "time_s,mass_kg,rate_kg_s,model_mass_kg,band_low_kg,band_high_kg"]
    lines += [",".join(f"{v:.6g}" for v in row)
              for row in zip(a.time, a.mass, a.rate, a.band.mass_mean, a.band.mass_low, a.band.mass_high)]
    png, csv_path = out / "rig.png", out / "rig_aligned.csv"
    with output_set(out):
        write_bytes_atomic(png, buf.getvalue())
        write_text_atomic(csv_path, "\n".join(lines) + "\n")
    return [str(png), str(csv_path)]


@lab_app.command("image", short_help="Measure solids areas in a drum photograph.")
def image(
    photo: Path = typer.Argument(..., help="Photograph of the drum cross-section (PNG, JPEG, TIFF)."),
    drum: str = typer.Option("ajayi_pilot", help="Built-in drum (rotarydryer flight --list-drums)."),
    centre: str = typer.Option(..., help="Drum centre in the image, 'column,row' px."),
    px_per_m: Optional[float] = typer.Option(None, help="Pixel scale, px/m."),
    known_length_px: Optional[float] = typer.Option(None, help="A known length in the image, px (e.g. the drum diameter)."),
    known_length_m: Optional[float] = typer.Option(None, help="That length in m (e.g. 0.75 for Ajayi's drum)."),
    reference_angle: float = typer.Option(90.0, help="Root angle of one flight (flight 0), deg from the drum bottom in the direction of rotation."),
    mirror: bool = typer.Option(False, help="The drum turns clockwise in the picture (Ajayi's did)."),
    channel: int = typer.Option(0, help="Colour channel to threshold (0 = red, as Ajayi's Appendix C)."),
    threshold: str = typer.Option("168,177", help="Flight-borne solids threshold: 'upper,lower' half, a number, or 'otsu' (Ajayi: 168,177)."),
    airborne_threshold: str = typer.Option("104,120", help="Airborne solids threshold (Ajayi: 104,120) or 'otsu'."),
    smooth_sigma: float = typer.Option(0.0, help="Gaussian smoothing before thresholding, px."),
    out: Optional[Path] = typer.Option(None, help="Annotated PNG to write."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
):
    """Measure flight-borne (per flight, FUF, UHD, LHD, TP) and airborne solids areas in a photograph
    (Ajayi 2011 section 4.3); optionally write an annotated image to check the segmentation.

    \b
    Example:
      rotarydryer lab image photo.png --centre 970,970 --known-length-px 1900 --known-length-m 0.75 --mirror --out checked.png
    """
    from ..lab import images as im

    try:
        d, cal, scale_name, thr, athr = image_options(centre, drum, px_per_m, known_length_px, known_length_m,
                                                      mirror, reference_angle, channel, threshold,
                                                      airborne_threshold, smooth_sigma)
        check_out_file("--out", out, ("png", "jpg", "jpeg", "tif", "tiff", "pdf", "svg"))
        if out is not None and out.exists() and photo.exists() and out.resolve() == photo.resolve():
            raise ValueError(f"--out {str(out)!r} is the photograph itself; give another file name")
        img = im.load_image(photo)
        m = measure_image(img, str(photo), d, cal, scale_name, reference_angle, channel, thr, athr, smooth_sigma)
    except (ValueError, OSError) as exc:
        _fail(exc)
    res = {"file": str(photo), "drum": drum, **m.as_dict()}
    if out is not None:
        from .._plotting import pyplot

        pyplot().close(im.annotate(img, m, out))  # written atomically
        res["annotated"] = str(out)
    if as_json:
        typer.echo(json_text(res))
        return
    typer.echo(f"photo {photo}: {img.shape[1]} x {img.shape[0]} px, {cal.px_per_m:.1f} px/m, drum {drum}")
    typer.echo(f"  first unloading flight (#{m.fuf_index}, root {m.root_angles[m.fuf_index]:.1f} deg)  {res['FUF_cm2']:.2f} cm2")
    typer.echo(f"  upper half UHD  {res['UHD_cm2']:.2f} cm2   lower half LHD  {res['LHD_cm2']:.2f} cm2   TP  {res['TP_cm2']:.2f} cm2")
    typer.echo(f"  airborne        {res['airborne_cm2']:.2f} cm2 ({res['airborne_percent']:.2f} % of the airborne region)")
    typer.echo("  per flight (cm2): " + " ".join(f"{a:.2f}" for a in res["flight_areas_cm2"]))
    if out is not None:
        typer.echo(f"  annotated image: {out}")


@lab_app.command("design-load", short_help="Design load from FUF area against loading.")
def design_load(
    table: Path = typer.Argument(..., help="CSV with one row per photograph: loading and FUF area columns."),
    loading_column: str = typer.Option("loading_kg", help="Column with the drum loading, kg."),
    area_column: str = typer.Option("FUF_area_cm2", help="Column with the first-unloading-flight area."),
    group_column: Optional[str] = typer.Option(None, help="Column naming the condition; one fit per group."),
    confidence: float = typer.Option(0.95, help="Confidence level."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
):
    """Design load = break point of a linear-plateau fit of FUF area against loading (Ajayi 2011
    Appendix D), with delta-method, profile-likelihood and corrected Appendix E intervals.

    \b
    Example:
      rotarydryer lab design-load loading_series.csv --group-column condition
    """
    try:
        check_option("--confidence", confidence, 0, 1)
        groups = _read_design_table(table, loading_column, area_column, group_column)
        fits = design_load_fits(groups, str(table), group_column is not None, confidence)
    except (ValueError, OSError) as exc:
        _fail(exc)
    res = {
        g: {
            "design_load": f.break_point, "slope": f.slope, "plateau": f.plateau, "plateau_ci": list(f.plateau_ci),
            "n": f.n, "n_left": f.n_left, "n_right": f.n_right, "residual_sd": f.residual_sd,
            "ci": {m: list(v) for m, v in f.ci.items()}, "stderr": f.stderr,
            "profile_closed": list(f.profile_closed),
        }
        for g, f in fits.items()
    }
    if as_json:
        # the fits are in the units of the table's columns: named here, from the columns' names
        lu, au = _column_unit(loading_column), _column_unit(area_column)
        units = {"design_load": lu, "ci": lu, "stderr": f"{lu} (design_load)", "plateau": au, "plateau_ci": au,
                 "residual_sd": au, "slope": f"{au} per {lu}"}
        typer.echo(json_text({"confidence": confidence, "units": units, "fits": res}))
        return
    typer.echo(f"design load = break point of {area_column} vs {loading_column} (right slope 0), "
               f"{100 * confidence:g} % intervals")
    for g, f in fits.items():
        typer.echo(f"  {g}: design load {f.break_point:.2f}  plateau {f.plateau:.3f}  slope {f.slope:.4f}  n {f.n}")
        for m, (lo, hi) in f.ci.items():
            if math.isfinite(lo) and math.isfinite(hi):
                typer.echo(f"      {m:16s} {lo:8.2f} - {hi:8.2f}  (+/- {(hi - lo) / 2:.2f})")
            else:       # a method that does not apply to this fit (its warning says why): no "nan" in the table
                typer.echo(f"      {m:16s} {'not available':>19s}")


#: units a design-load table's column name may end with (``loading_kg``, ``FUF_area_cm2``)
_COLUMN_UNITS = frozenset({"kg", "g", "t", "lb", "m2", "cm2", "mm2", "in2", "ft2", "px", "pixels", "pct", "percent"})


def _column_unit(column: str) -> str:
    """The unit a CSV column's name ends with (``loading_kg``: kg, ``FUF_area_cm2``: cm2; one of `_COLUMN_UNITS`),
    else the column's name (the fits are in its units, whatever they are: ``FUF_area`` is not in "area")."""
    head, sep, tail = column.rpartition("_")
    if sep and head and tail.lower() in _COLUMN_UNITS:
        return tail
    return f"units of column {column!r}"


#: a rig fit's parameter names (`rotarydryer.lab.flight_rig.RigFit`) with their units, as the JSON gives them
_RIG_UNITS = {"repose_angle": "repose_angle_deg", "mass_offset": "mass_offset_kg", "start_time": "start_time_s",
              "bulk_density": "bulk_density_kg_m3"}


def _with_units(values: dict) -> dict:
    """A rig fit's ``params`` or ``stderr`` with the unit in each name (`_RIG_UNITS`)."""
    return {_RIG_UNITS.get(k, k): v for k, v in values.items()}


def _read_design_table(table: Path, loading_column: str, area_column: str, group_column) -> dict:
    """{group: [(loading, area), ...]} from a design-load CSV, read line by line (UTF-8, at most
    200 000 rows); errors name the file, the line and the column
    (`rotarydryer.lab.design_load_fit.read_design_rows`)."""
    from ..lab.design_load_fit import read_design_rows
    from ..rtd._datafile import data_lines

    return read_design_rows(data_lines(table, "design-load table"), str(table), loading_column, area_column,
                            group_column)


@lab_app.command("steps", short_help="Holdup by Song's dynamic step method.")
def steps(
    data: Path = typer.Argument(..., help="CSV record: time_s|time_min|time_h, feed_kg_s|feed_kg_min|feed_kg_h|fed_kg, discharge_kg_s|discharge_kg_min|discharge_kg_h|discharged_kg."),
    step_times: Optional[str] = typer.Option(None, "--steps", help="Step times, comma-separated, in the unit of the time column (default: detected from the feed; give them for speed or gas steps)."),
    threshold: float = typer.Option(0.1, help="Step detection: smallest feed change, fraction of the largest feed (0-1)."),
    plateau: float = typer.Option(0.2, help="Fraction of each interval, at its end, averaged for the plateau discharge (0-1]."),
    tolerance: float = typer.Option(0.05, help="An interval is steady when its plateau discharge differs from its feed by less than this fraction of the largest feed (0-1)."),
    initial_holdup: float = typer.Option(0.0, help="Holdup at the start of the record, kg (Song: 0, an empty dryer)."),
    out: Optional[Path] = typer.Option(None, help="Directory for steps.csv (one row per interval) and steps.png."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
):
    """Song's (2003) dynamic step method: holdup after each feed step from the area between the feed
    and discharge records, mean residence time tau = H/F (Eq. 4.1), up/down agreement H1 = H2 and the
    closure of a record that starts and ends empty (Table 4.2), reconciled.

    \b
    Example:
      rotarydryer lab steps steps_run.csv --out results
    """
    from ..lab import steps as sm

    try:
        check_steps_options(threshold, plateau, tolerance, initial_holdup)
        check_out_dir("--out", out)
        rec = sm.read_step_csv(data)
        a = steps_analysis(rec, str(data), step_times, threshold, plateau, tolerance, initial_holdup)
        outputs = _write_steps_outputs(sm, rec, a, out) if out is not None else None
    except (ValueError, OSError) as exc:
        _fail(exc)
    res = {"columns": rec.columns, "samples": int(rec.time.size), **a.as_dict()}
    if outputs is not None:
        res["outputs"] = outputs
    if as_json:

        typer.echo(json_text(res))
        return
    t_unit = rec.columns["time"].split("_", 1)[1]
    factor = sm.TIME_COLUMNS[rec.columns["time"]]
    typer.echo(f"step record {data}: {rec.time.size} samples over {(rec.time[-1] - rec.time[0]) / 60:.2f} min "
               f"({', '.join(rec.columns.values())})")
    how = "given" if step_times is not None else f"detected: feed changes > {threshold:g} of the largest feed"
    typer.echo(f"  steps at {', '.join(f'{s / factor:g}' for s in a.steps_s)} {t_unit} ({how})")
    typer.echo("  #   from - to (min)     feed   plateau (kg/min)   area dH (kg)   H (kg)   H rec. (kg)   tau (min)  steady")
    for k, sg in enumerate(a.segments, start=1):
        hr = "" if sg["holdup_reconciled_kg"] is None else f"{sg['holdup_reconciled_kg']:.2f}"
        tau = "-" if sg["tau_s"] is None else f"{sg['tau_s'] / 60:.2f}"
        typer.echo(f"  {k:<3d} {sg['start_s'] / 60:7.2f} - {sg['end_s'] / 60:<8.2f} {sg['feed_end_kg_s'] * 60:7.3f} "
                   f"{sg['plateau_kg_s'] * 60:8.3f}        {sg['area_kg']:10.3f}   {sg['holdup_kg']:7.2f}   {hr:>10s}"
                   f"   {tau:>9s}  {'yes' if sg['steady'] else 'NO'}")
    if a.h_up_kg is not None or a.h_down_kg is not None:
        parts = []
        if a.h_up_kg is not None:
            parts.append(f"up-step H1 = {a.h_up_kg:.2f} kg")
        if a.h_down_kg is not None:
            parts.append(f"down-step H2 = {a.h_down_kg:.2f} kg")
        if a.up_down_pct is not None:
            parts.append(f"H1 - H2 = {a.up_down_pct:+.2f} % of their mean (Song: < 3 %)")
        elif a.h_up_kg is not None and a.h_down_kg is not None:
            parts.append("not compared: the up-step and the down-step are at different feeds")
        typer.echo("  " + ", ".join(parts))
    c = a.closure
    if c["applies"]:
        typer.echo(f"  closure: residual {c['residual_kg']:+.3f} kg = {c['residual_pct']:.2f} % of the areas "
                   "(Song Table 4.2: 0.8-4.9 %), removed in proportion to each area (H rec.)")
    else:
        typer.echo(f"  closure not applicable: {c['why']}")
    if not all(sg["steady"] for sg in a.segments):
        typer.echo("  warning: an interval marked NO did not reach a steady discharge; its holdup is not the "
                   "steady-state holdup (lengthen the step)")
    if outputs is not None:
        typer.echo(f"  outputs: {', '.join(outputs)}")


def _write_steps_outputs(sm, rec, a, out: Path) -> list:
    """steps.png and steps.csv in ``out``, rendered in memory first and written as one set
    (`rotarydryer._io.output_set`): if either write fails, the previous pair is kept."""
    import io

    from .._io import output_set, write_bytes_atomic, write_text_atomic
    from .._plotting import pyplot

    fig = sm.plot_steps(rec, a)
    buf = io.BytesIO()
    try:
        fig.savefig(buf, format="png", dpi=110)
    finally:
        pyplot().close(fig)
    png, csv_path = out / "steps.png", out / "steps.csv"
    table = sm.segment_table(a)
    with output_set(out):
        write_bytes_atomic(png, buf.getvalue())
        write_text_atomic(csv_path, table)
    return [str(png), str(csv_path)]


@lab_app.command("drying", short_help="Thin-layer drying laws from lab drying curves.")
def drying(
    curves_csv: Path = typer.Argument(..., help="CSV: time_s|time_min|time_h, moisture_kg_kg_dry|moisture_kg_kg_wet, air_temperature_degC; optional curve and equilibrium_moisture_kg_kg_dry|_wet."),
    model: Optional[str] = typer.Option(None, help="Law to plot and write: lewis | page | henderson_pabis | logarithmic | two_term | midilli (default: the lowest AICc of the drying laws)."),
    equilibrium_moisture: Optional[float] = typer.Option(None, help="X_e of every curve, kg/kg dry, for a file without an equilibrium column (default 0)."),
    reference_temperature: Optional[float] = typer.Option(None, help="Temperature of the fitted rate constants, degC (default: the mean of the curves')."),
    out: Optional[Path] = typer.Option(None, help="Directory for drying_fit.png (curves and law) and drying_models.csv (the ranking)."),
    material_out: Optional[Path] = typer.Option(None, help="Material file to write (.toml): the law as the kinetics of a copy of --base-material."),
    base_material: Optional[str] = typer.Option(None, help="Library material whose other properties the new material takes (with --material-out)."),
    material_name: Optional[str] = typer.Option(None, help="Name of the new material (default BASE_MODEL)."),
    particle_diameter: Optional[float] = typer.Option(None, help="Particle diameter of the lab sample, m (default the base material's)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
):
    """Fit the thin-layer laws (Lewis, Page, Henderson-Pabis, logarithmic, two-term, Midilli) with
    Arrhenius rate constants to all drying curves at once, rank them (AICc; AIC, BIC, RMSE, R^2),
    give 95 % intervals, and write the chosen law into a material file the dryer model reads.

    \b
    Example:
      rotarydryer lab drying curves.csv --out results --material-out my_ore.toml --base-material ottawa_sand_song2003
    """
    from .._io import output_set, write_bytes_atomic, write_text_atomic
    from ..lab import drying_curves as dc

    try:
        check_drying_options(model, equilibrium_moisture, reference_temperature, material_out, base_material,
                             material_name, particle_diameter)
        check_out_dir("--out", out)
        check_out_file("--material-out", material_out, ("toml",))
        if material_out is not None and material_out.exists() and curves_csv.exists() and \
                material_out.resolve() == curves_csv.resolve():
            raise ValueError(f"--material-out {str(material_out)!r} is the drying-curve file itself; give another name")
        curves = dc.read_drying_csv(curves_csv, equilibrium_moisture)
        result, chosen = drying_analysis(curves, model, reference_temperature)
        table = text = None
        if material_out is not None:
            table = dc.material_table(result, chosen, str(base_material), name=material_name,
                                      particle_diameter=particle_diameter)
            text = dc.material_toml(table, _material_header(curves_csv, chosen, material_out))
        files = _drying_files(dc, result, chosen) if out is not None else {}
        written = []
        if files or text is not None:
            with output_set(out):
                for fname, data in files.items():
                    write_bytes_atomic(out / fname, data)   # type: ignore[operator]
                    written.append(str(out / fname))       # type: ignore[operator]
                if text is not None:
                    write_text_atomic(material_out, text)
    except (ValueError, OSError) as exc:
        _fail(exc)
    res = result.as_dict()
    res["chosen"] = chosen
    if written:
        res["outputs"] = written
    if material_out is not None:
        res["material_file"] = str(material_out)
        res["material_name"] = table["name"]     # type: ignore[index]
    if as_json:
        typer.echo(json_text(res))
        return
    _print_drying(curves, result, chosen, written, material_out, table)


def _material_header(curves_csv: Path, model: str, material_out: Path) -> list:
    return [f"Material written by `rotarydryer lab drying {curves_csv.name}`: the {model} thin-layer law fitted to",
            "those drying curves as the kinetics of a copy of the base library material (see [material.kinetics]).",
            f"Python: rotarydryer.properties.materials.load_material({str(material_out)!r}).",
            "In a case file: replace the case's [material] block (and its sub-tables) by the tables below.",
            ""]


def _drying_files(dc, result, chosen) -> dict:
    """{file name: bytes} of ``--out``: the figure of the chosen law and the ranking table."""
    import io

    from .._io import csv_text
    from .._plotting import pyplot

    fig = dc.plot_fit(result, chosen)
    buf = io.BytesIO()
    try:
        fig.savefig(buf, format="png", dpi=110)
    finally:
        pyplot().close(fig)
    rows = []
    for i, (m, f) in enumerate(result.fits.items()):
        row = {"rank": i + 1, "model": m, "n_parameters": f.n_parameters, "n_points": f.n_points, "sse": f.sse,
               "rmse": f.rmse, "r_squared": f.r_squared, "aic": f.aic, "aicc": f.aicc, "bic": f.bic,
               "delta_aicc": result.delta_aicc(m), "akaike_weight": result.akaike_weight(m),
               "activation_energy_J_mol": f.activation_energy_value}
        for k, e in f.parameters.items():
            row[k] = e.value
        # one column per parameter name serves every law: each row says its own parameters' units (Page's k is in
        # 1/s^n, Lewis's in 1/s; the two-term b has none, Midilli's is in 1/s)
        row["parameter_units"] = "; ".join(f"{k}: {e.unit or '-'}" for k, e in f.parameters.items())
        rows.append(row)
    keys = list(dict.fromkeys(k for r in rows for k in r))
    # an undefined criterion (AICc with n <= p + 2, and its difference) is an empty field, as null in the JSON
    table = csv_text([{k: ("" if isinstance(v := r.get(k, ""), float) and not math.isfinite(v) else v) for k in keys}
                      for r in rows])
    return {"drying_fit.png": buf.getvalue(), "drying_models.csv": table.encode("utf-8")}


def _print_drying(curves, result, chosen, written, material_out, table) -> None:
    from ..properties.thin_layer import MODELS

    temps = ", ".join(f"{t:g}" for t in curves.air_temperature_degC)
    typer.echo(f"drying curves {curves.name}: {len(curves.ids)} curves at {temps} degC, {curves.time_s.size} rows "
               f"({int((curves.time_s > 0).sum())} fitted after time 0)")
    typer.echo(f"  moisture ratio MR = (X - X_e)/(X_0 - X_e); rate constants at T_ref = "
               f"{result.reference_temperature_K:.2f} K ({result.reference_temperature_K - 273.15:.2f} degC)"
               + (", Arrhenius" if curves.n_temperatures > 1 else ", one air temperature: no temperature dependence"))
    crit = result.criterion       # AICc, or AIC where no law has enough points for AICc
    typer.echo(f"  rank  model              p    RMSE      R^2       AIC      AICc       BIC  {'d' + crit:>6s}  weight")
    for i, (m, f) in enumerate(result.fits.items(), start=1):
        finite = f.aicc != float("inf")
        aicc = f"{f.aicc:9.1f}" if finite else "        -"
        d = result.delta_aicc(m)
        delta = f"{d:6.2f}" if d != float("inf") else "     -"
        r2 = f"{f.r_squared:8.5f}" if math.isfinite(f.r_squared) else "       -"     # undefined: no spread to explain
        typer.echo(f"  {i:<4d}  {m:<17s} {f.n_parameters:2d}  {f.rmse:8.5f}  {r2}  {f.aic:8.1f} {aicc}"
                   f"  {f.bic:8.1f}  {delta}  {result.akaike_weight(m):6.3f}")
    for m, why in result.skipped.items():
        typer.echo(f"  skipped {m}: {why}")
    f = result.fits[chosen]
    for m, g in result.fits.items():
        if g.law_problem is not None:
            typer.echo(f"  not a drying law, not chosen: {m} ({g.law_problem})")
    how = (f"lowest {crit}" if chosen == result.best.model else "--model" if result.best_law is None
           or chosen != result.best_law.model else f"lowest {crit} of the drying laws")
    if crit == "AIC":
        how += f"; no law has an AICc with {int((curves.time_s > 0).sum())} points after time 0"
    typer.echo(f"  chosen: {chosen} ({how}), {MODELS[chosen].equation}; 95 % intervals:")
    for k, e in f.parameters.items():
        typer.echo(f"    {k:4s} = {e.value:.5g} {e.unit:6s} [{e.ci_low:.5g}, {e.ci_high:.5g}]")
    if f.activation_energy is not None:
        e = f.activation_energy
        typer.echo(f"    Ea   = {e.value / 1e3:.4g} kJ/mol [{e.ci_low / 1e3:.4g}, {e.ci_high / 1e3:.4g}]")
    for note in f.notes:
        typer.echo(f"  note: {note}")
    if written:
        typer.echo(f"  outputs: {', '.join(written)}")
    if material_out is not None:
        typer.echo(f"  material {table['name']!r} written to {material_out} (kinetics method thin_layer, model "
                   f"{chosen}); use it in a case in place of the [material] block")
