"""``rotarydryer sensitivity``: Sobol indices and output distributions of a case (issue 16)."""

from pathlib import Path
from typing import Optional

import typer

from .._display import UNITS, quantity_of, split_unit, unit_of
from . import app
from ._common import CLUSTER_HELP, SCHEDULER_HELP, WORKERS_HELP

#: output names a study may ask for (``--output``)
KNOWN_OUTPUTS = ("product_moisture_kg_kg", "product_temperature_degC", "gas_outlet_temperature_degC",
                 "gas_outlet_humidity_kg_kg", "evaporation_kg_s", "fuel_rate_kg_s", "shell_heat_loss_W",
                 "mean_residence_time_s", "total_holdup_kg", "active_holdup_kg", "passive_holdup_kg",
                 "bed_holdup_kg", "outlet_flow_kg_s", "tracer_mean_s", "tracer_std_s", "rtd_std_s",
                 "rtd_mean_residence_time_s",
                 # size classes, the exhaust's dew point and the energy audit (simulate and target give them; found
                 # by fuzzing: "not a known output")
                 "dust_rate_kg_s", "product_d50_m", "gas_outlet_dew_point_degC", "gas_outlet_dew_point_margin_K",
                 "heat_release_W", "specific_energy_kJ_kg_water", "thermal_efficiency")


def _text_table(res) -> str:
    lines = [f"Sobol indices ({res.n_runs} runs, {res.n_failed} failed; +- {100 * 0.95:.0f} % CI half-width)",
             f"{'output':<30} {'parameter':<32} {'S1':>8} {'+-':>7} {'ST':>8} {'+-':>7}"]
    def cell(v, width):
        return f"{'n/a':>{width}}" if v is None else f"{v:{width}.3f}"
    for r in res.table():
        lines.append(f"{r['output']:<30} {r['parameter']:<32} {cell(r['S1'], 8)} {cell(r['S1_conf'], 7)} "
                     f"{cell(r['ST'], 8)} {cell(r['ST_conf'], 7)}")
    lines += ["", f"{'output':<30} {'n':>6} {'mean':>11} {'sd':>11} {'p5':>11} {'p50':>11} {'p95':>11}  unit"]
    for d in res.distribution_table():
        if d.get("n"):
            # in the display unit of the output's quantity (--units; the JSON and CSV stay SI, named by their suffix)
            q = quantity_of(d["output"])
            unit, f, offset, scale = "-", 1.0, 0.0, 1.0
            if q is not None:
                quantity, f = q
                unit = unit_of(quantity)
                scale, offset = UNITS[quantity][unit]
            v = {k: d[k] * f * scale + offset for k in ("mean", "p5", "p50", "p95")}
            sd = d["sd"] * f * scale       # a spread has no offset (degC -> degF)
            # the name without its SI suffix where the values are in another unit ("fuel_rate_kg_s ... kg/h" read as
            # two units for one number; found by review)
            name = split_unit(d["output"])[0] if q is not None else d["output"]
            lines.append(f"{name:<30} {d['n']:6d} {v['mean']:11.5g} {sd:11.5g} "
                         f"{v['p5']:11.5g} {v['p50']:11.5g} {v['p95']:11.5g}  {unit}")
    return "\n".join(lines) + "\n"


@app.command("sensitivity", short_help="Sobol sensitivity indices of a case.")
def sensitivity(
    case: str = typer.Argument(..., help="Case name or .toml file."),
    param: Optional[list[str]] = typer.Option(None, "--param", help="Uncertain input KEY=LOW,HIGH (uniform); repeat."),
    samples: str = typer.Option("64", "--samples", "-n", help="Base samples N (runs: N x (inputs + 2)); a power of 2."),
    output: Optional[list[str]] = typer.Option(None, "--output", help="Output name (repeat); default: product "
                                               "moisture, gas outlet temperature, fuel rate, mean residence time."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Override KEY=VALUE applied to every run."),
    workers: int = typer.Option(1, help=WORKERS_HELP),
    scheduler: Optional[str] = typer.Option(None, help=SCHEDULER_HELP),
    cluster: Optional[str] = typer.Option(None, help=CLUSTER_HELP),
    seed: int = typer.Option(0, help="Seed of the scrambled Sobol' sequence and the bootstrap."),
    warm_start: bool = typer.Option(True, "--warm-start/--cold-start",
                                    help="Start each coupled steady state from the nearest converged run."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="Folder for sensitivity.json, the CSV tables "
                                                                "and sensitivity.png."),
    as_json: bool = typer.Option(False, "--json", help="Print the result as one JSON object."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress lines on stderr."),
):
    """Global sensitivity (Sobol first- and total-order indices with 95 % confidence intervals)
    and Monte Carlo output distributions of a case.

    \b
    Examples:
      rotarydryer sensitivity lee2008_invicta --set thermal.enabled=false --param operating.rpm=2,4 --param operating.feed_rate=20,30 --samples 64
      rotarydryer sensitivity ajayi2011_mmg --param operating.feed_rate=3,4 --param transport.kiln_time=5,10 --samples 32 --workers 0 --out study/
      rotarydryer report ajayi2011_mmg --sensitivity study/sensitivity.json

    Failed runs (infeasible points) are recorded and left out of the indices block-wise. The runs go
    serially, on --workers local processes, on a Dask --cluster local:N or a --scheduler; every
    backend gives the same indices.
    Exit codes: 0 done, 1 every run failed, 2 bad input, 3 SALib or Dask not installed.
    """
    from .._io import csv_text, json_text, save_figure, write_text_atomic
    from ..services._options import executor_from_options
    from ..studies import sensitivity as sens
    from ._common import Progress, check_out_dir, connect_executor, parse_sets, written_set

    try:
        sens.require_salib()
    except ImportError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(3)
    try:
        base = parse_sets(set_)
        params = sens.check_params([sens.parse_param(p) for p in (param or [])])
        both = [k for k in params if k in base]
        if both:        # the runs took the --param range and dropped the --set, which the output still recorded
            raise ValueError(f"{', '.join(both)} given by --set and by --param: a varied key takes its values from "
                             "its range; drop the --set")
        n_samples = sens.check_samples(samples, len(params))
        sens.check_seed(seed)
        outputs = list(dict.fromkeys(output)) if output else list(sens.OUTPUTS)
        for o in outputs:
            if o not in KNOWN_OUTPUTS:
                raise ValueError(f"--output {o!r} is not a known output; choose from {', '.join(KNOWN_OUTPUTS)}")
        executor, worker_notes = executor_from_options(workers, n_samples * (len(params) + 2), scheduler=scheduler,
                                                       cluster=cluster)
        check_out_dir("--out", out)
        sens._check_case(case, base, params)          # unknown case or key, a range the schema refuses
    except (ValueError, OSError) as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)
    for note in worker_notes:
        typer.echo(f"warning: {note}", err=True)
    connect_executor(executor)          # an unreachable scheduler: refused before any run
    n_runs = n_samples * (len(params) + 2)
    with Progress("run", n_runs, quiet=quiet) as bar:
        res = sens.sobol_study(case, params, n_samples, outputs, executor=executor, base_overrides=base, seed=seed,
                               warm_start=warm_start, progress=bar.advance)
    data = res.to_dict()
    if out is not None:
        out = Path(out)
        with written_set(out, errors=(ValueError, OSError)):    # all files or none: the previous set kept
            write_text_atomic(out / "sensitivity.json", json_text(data, indent=1))
            write_text_atomic(out / "sensitivity_indices.csv", csv_text(res.table()))
            write_text_atomic(out / "sensitivity_distributions.csv", csv_text(res.distribution_table()))
            write_text_atomic(out / "sensitivity_runs.csv", csv_text(res.runs_table()))
            save_figure(sens.plot_sensitivity(data), out / "sensitivity.png", dpi=110)
    if as_json:
        typer.echo(json_text(data))
    else:
        typer.echo(_text_table(res), nl=False)
        if out is not None:
            typer.echo(f"results: {out}/sensitivity.json, sensitivity_indices.csv, sensitivity_distributions.csv, "
                       f"sensitivity_runs.csv, sensitivity.png ({res.seconds:.1f} s, {res.runs_per_second:.1f} runs/s)")
    for note in res.notes:
        typer.echo(f"note: {note}", err=True)
    if res.n_failed == res.n_runs:
        typer.echo(f"error: all {res.n_runs} runs failed; first: {res.failures[0]['error'] if res.failures else ''}",
                   err=True)
        raise typer.Exit(1)
