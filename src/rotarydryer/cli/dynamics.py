"""``rotarydryer dynamics``: the dynamic response of a dryer from its steady state under an input
schedule (steps, ramps, a burner trip and restart of any input)."""

from pathlib import Path
from typing import Optional

import typer

from .._display import show, show_output
from .._io import json_text
from ..services.dynamics import dynamics_summary, parse_above, run_dynamics
from . import app
from ._common import Progress, check_out_dir, parse_sets, written_set


def _progress_printer(bar: Progress):
    """The run's progress messages through the one progress style (`Progress`), a line per tenth
    of the simulated time where stderr is not a terminal."""
    if bar.quiet:
        return None
    last = [-1]

    def show(msg: str):
        if msg.startswith("t = "):      # one line per tenth of the run
            try:
                done, total = (float(x) for x in msg[4:-2].split(" / "))
                tenth = int(10 * done / total) if total > 0 else 10
            except ValueError:
                tenth = -2
            if tenth == last[0] and not bar.tty:
                return
            last[0] = tenth
        bar.message(f"dynamics: {msg}")
    return show


@app.command("dynamics", short_help="Dynamic response to an input schedule: steps, ramps, a burner trip.")
def dynamics_cmd(
    case: str = typer.Argument(..., help="Case name or .toml file (with a [gas] block)."),
    schedule: Optional[Path] = typer.Option(None, "--schedule", help="Input schedule, .csv (time_s and one column "
                                            "per input) or .toml ([[step]], [[ramp]], [[trip]], [[point]]); "
                                            "without it the case's own inputs."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Override KEY=VALUE (several allowed)."),
    t_end: float = typer.Option(7200.0, "--t-end", help="Simulated time, s."),
    dt: float = typer.Option(60.0, "--dt", help="Reporting (communication) interval, s; inputs are held over each."),
    above: Optional[str] = typer.Option(None, "--above", help="OUTLET=VALUE: also report the time the outlet "
                                        "spends above VALUE, e.g. product_moisture=0.13."),
    out: Optional[Path] = typer.Option(None, "--out", help="Directory for dynamics.csv, dynamics.json and "
                                       "dynamics.png."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object (the summary)."),
    quiet: bool = typer.Option(False, "--quiet", help="No progress lines on stderr."),
):
    """Simulate the coupled heat-and-mass model from the case's steady state under an input
    schedule: gas inlet temperature or burner fuel, feed rate, feed moisture, drum speed, gas
    flow, gas humidity, feed temperature, fouling. Each interval of --dt (and each step of an
    input) holds the inputs at its start, as an FMU importer does (the FMU of `rotarydryer fmu`
    driven with the same schedule gives the same series).

    \b
    Examples:
      rotarydryer dynamics ajayi2011_mmg --set operating.test=4 --t-end 3600
      rotarydryer dynamics ajayi2011_mmg --set operating.test=4 --schedule trip.toml --above product_moisture=0.13 --out trip

    \b
    A burner trip, trip.toml:
      [[trip]]
      input = "gas_inlet_temperature"
      at_s = 600
      duration_s = 600
      value = 100
    """
    from ..simulation import Simulation

    threshold = parse_above(above)
    check_out_dir("--out", out)
    sim = Simulation(case, parse_sets(set_))
    with Progress("dynamics", quiet=quiet) as bar:
        result = run_dynamics(sim, schedule, t_end=t_end, dt=dt, progress=_progress_printer(bar))
    summary = dynamics_summary(result, case, threshold)
    if out is not None:
        from .._io import save_figure, write_text_atomic
        from ..thermal.plots import plot_schedule_result

        cols = result.columns()
        files = [out / "dynamics.csv", out / "dynamics.json", out / "dynamics.png"]
        with written_set(out):                   # all files or none
            write_text_atomic(files[0], result.csv_text())
            write_text_atomic(files[1], json_text(dict(summary, series={k: list(map(float, v)) for k, v in cols.items()}),
                                                  indent=1))
            save_figure(plot_schedule_result(result, title=f"{case}: {schedule.name if schedule else 'case inputs'}"),
                        files[2], dpi=110)
        summary["files"] = [str(f) for f in files]
    if as_json:
        typer.echo(json_text(summary))
        return
    src = schedule.name if schedule else "the case's own inputs"
    typer.echo(f"{case}: {summary['t_end_s']:g} s from the steady state, {src} "
               f"({', '.join(summary['scheduled_inputs']) or 'no input changed'}); {summary['points']} points, "
               f"{summary['integrations']} integration(s), {summary['input_changes']} input change(s), "
               f"{summary['seconds']:.1f} s")
    for name, s in summary["outlets"].items():
        typer.echo(f"  {name:<26} start {show_output(name, s['start'])}, final {show_output(name, s['final'])}, "
                   f"max {show_output(name, s['max'])} at {show(s['max_time_s'], 'time')}, "
                   f"min {show_output(name, s['min'])} at {show(s['min_time_s'], 'time')}")
    if threshold is not None:
        ta = summary["time_above"]
        from ..thermal.schedule import OUTLET_NAMES

        printed = OUTLET_NAMES.get(ta["outlet"], ta["outlet"])     # as the rows above name it, in their unit
        typer.echo(f"  {printed} above {show_output(printed, ta['threshold'])}: {show(ta['seconds'], 'time')}")
    if out is not None:
        typer.echo(f"files: {', '.join(summary['files'])}")
