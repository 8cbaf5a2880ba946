"""``rotarydryer calibrate``: fit case keys to several measured responses of many tests at once."""

from pathlib import Path
from typing import Optional

import typer

from .._limits import key_unit
from . import app
from ._common import (
    CLUSTER_HELP,
    SCHEDULER_HELP,
    WORKERS_HELP,
    Progress,
    check_out_dir,
    connect_executor,
    parse_sets,
    written_set,
)


@app.command("calibrate", short_help="Calibrate case keys to the measurements of many tests.")
def calibrate_command(
    case: str = typer.Argument(..., help="Built-in case name or a case .toml file."),
    param: list[str] = typer.Option(..., "--param", "-p", help="Case key to fit (repeat); tests.N.FIELD or "
                                    "tests.*.FIELD for a value per test (solids_velocity, dispersion, gas_flow, "
                                    "fouling)."),
    tests: Optional[str] = typer.Option(None, help="Tests ([[tests]] rows) to fit at once, e.g. 2,3,4,5,6 "
                                        "(default all)."),
    response: Optional[list[str]] = typer.Option(None, "--response", "-r", help="Response to fit (repeat): "
                                                 "tracer, mrt, holdup, gas_outlet_temperature, product_moisture, "
                                                 "product_temperature, moisture_profile, product_d50, dust_rate "
                                                 "(default: every one the data have that the parameters move)."),
    sigma: Optional[list[str]] = typer.Option(None, help="Measurement standard deviation RESPONSE=VALUE "
                                              "(repeat; in the response's unit; tracer: of E(t), 1/s)."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Fixed override KEY=VALUE (repeat)."),
    starts: int = typer.Option(1, help="Number of starts (the case values plus sampled ones), 1-100."),
    workers: int = typer.Option(1, help=WORKERS_HELP + " Runs the starts."),
    scheduler: Optional[str] = typer.Option(None, help=SCHEDULER_HELP),
    cluster: Optional[str] = typer.Option(None, help=CLUSTER_HELP),
    profile: bool = typer.Option(False, "--profile", help="Also profile-likelihood 95 % intervals."),
    name: Optional[str] = typer.Option(None, help="Name of the calibration record."),
    out: Optional[Path] = typer.Option(None, help="Directory for calibration.toml (the record), "
                                       "calibration.json and CASE_calibrated.toml (the case with the record)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress lines on stderr."),
):
    """Calibrate case keys to tracer curves, residence times, holdups, exhaust and product
    temperatures and product moisture of one or many tests at once, and write the calibration
    record (values, 95 % intervals, correlation, data and weights, model configuration).

    \b
    Examples:
      rotarydryer calibrate ajayi2011_mmg -p "tests.*.solids_velocity" -p "tests.*.dispersion" --tests 2,4,5,6 -r tracer -r mrt --out cal
      rotarydryer calibrate ajayi2011_mmg -p thermal.area_scale -p "tests.*.gas_flow" -p thermal.discharge_cooling_ntu --tests 2,3,4,5,6

    Several --starts run on --workers local processes or a Dask --cluster local:N / --scheduler, each
    from the case's cold state: the same calibration on every backend.
    """
    from .._io import json_text, write_text_atomic
    from ..estimation import FitError
    from ..services._options import executor_from_options
    from ..services.calibration import parse_sigmas, parse_tests, run_calibration

    try:
        check_out_dir("--out", out)
        base = parse_sets(set_)
        sel = parse_tests(tests)
        sig = parse_sigmas(sigma)
        executor, notes = executor_from_options(workers, max(1, starts), scheduler=scheduler, cluster=cluster)
    except ValueError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)
    for note in notes:
        typer.echo(f"warning: {note}", err=True)
    connect_executor(executor)
    try:
        with Progress("calibrate", quiet=quiet) as bar:
            run = run_calibration(case, param, tests=sel, responses=response or None, base_overrides=base,
                                  sigmas=sig, starts=starts, profile=profile, name=name, executor=executor,
                                  progress=lambda stage, k, n: bar.update(k, n or None, label=stage))
    except (ValueError, FitError) as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)
    cal, text, calibrated = run.calibration, run.record_text, run.calibrated_case_text
    result = run.to_dict()
    if out is not None:
        stem = Path(case).stem
        with written_set(out):                  # all files or none: a failure keeps the previous set
            write_text_atomic(out / "calibration.json", json_text(result, indent=2))
            write_text_atomic(out / f"{stem}_calibrated.toml", calibrated)
            write_text_atomic(out / "calibration.toml", text)
        result["files"] = [str(out / n) for n in ("calibration.toml", "calibration.json", f"{stem}_calibrated.toml")]
    if as_json:
        typer.echo(json_text(result))
        return
    r = cal.fit
    typer.echo(f"calibration of {case}: {len(cal.keys)} parameters, {len(cal.data)} data sets "
               f"({sum(m.y.size for m in cal.data)} values), objective {r.objective:.6g}, "
               f"{r.n_evaluations} evaluations, {cal.seconds:.1f} s")
    w = max(len(k) for k in cal.keys)
    units = {k: key_unit(k) for k in cal.keys}
    wu = max(4, *(len(u) for u in units.values()))
    typer.echo(f"  {'parameter':<{w}}  {'unit':<{wu}}  {'estimate':>12}  {'95% interval':>29}")
    for k in cal.keys:
        p = r.parameters[k]
        lo, hi = (cal.profiles[k].ci_low, cal.profiles[k].ci_high) if cal.profiles.get(k) is not None else \
            (p.ci_low, p.ci_high)
        typer.echo(f"  {k:<{w}}  {units[k]:<{wu}}  {p.value:12.6g}  [{lo:12.6g}, {hi:12.6g}]")
    typer.echo("fit to the data:")
    for row in cal.comparison():
        if row["response"] == "tracer":
            typer.echo(f"  {row['name']:<34} R^2 {row['r_squared']:.4f} ({row['n_points']} points)")
        else:
            typer.echo(f"  {row['name']:<34} measured {row['measured']:.5g}, model {row['model']:.5g} "
                       f"{row['unit']}")
    for msg in r.warnings:
        typer.echo(f"warning: {msg}", err=True)
    if out is None:
        typer.echo("\n# the calibration record (append it to the case file, or give --out):")
        typer.echo(text.rstrip("\n"))
    else:
        typer.echo(f"wrote {', '.join(result['files'])}")
