"""``rotarydryer control``: closed-loop run (PI + feed-forward) of a dryer's dynamic model."""

from pathlib import Path
from typing import Optional

import typer

from .._display import show, show_delta
from .._io import json_text
from ..services.control import check_control_options, describe_feedforward, parse_band, run_control
from . import app
from ._common import Progress, check_out_dir, parse_sets, written_set


@app.command("control", short_help="Closed-loop run (PI + feed-forward) under a disturbance or a schedule.")
def control(
    ctx: typer.Context,
    case: str = typer.Argument(..., help="Case name (ajayi2011_mmg, ...) or a .toml file with a [gas] block."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Override KEY=VALUE, e.g. operating.test=4."),
    scenario: str = typer.Option("feed_moisture_step", help="feed_moisture_step | feed_rate_step | fouling_ramp "
                                                              "| none."),
    magnitude: float = typer.Option(0.2, help="Disturbance: relative step (+0.2 = +20 %; feed moisture on the dry "
                                              "basis), or the final fouling fraction of fouling_ramp."),
    duration: float = typer.Option(10800.0, help="Simulated time, s: at most 86400 (one day) and 1440 sampling "
                                                 "intervals (--duration / --sample-time)."),
    step_time: Optional[float] = typer.Option(None, help="Time of the disturbance (start of the ramp), s; "
                                                          "default 600 s or --duration if shorter."),
    sample_time: float = typer.Option(60.0, help="Sampling interval of measurement and controller, s."),
    dead_time: float = typer.Option(120.0, help="Measurement dead time (analyser), s."),
    measured: str = typer.Option("product_moisture", help="Controlled variable: product_moisture | "
                                                          "exhaust_temperature."),
    setpoint: Optional[float] = typer.Option(None, help="Setpoint (kg/kg wet or degC); default the steady state."),
    kc: Optional[float] = typer.Option(None, help="Controller gain (normalised split range, y per y); "
                                                  "default SIMC."),
    tau_i: Optional[float] = typer.Option(None, help="Integral time, s; default SIMC."),
    tau_c: Optional[float] = typer.Option(None, help="SIMC closed-loop time constant, s (default = dead time)."),
    feedforward: str = typer.Option("model", help="model (steady-state) | linear (FOPDT gains) | off."),
    feedback: bool = typer.Option(True, "--feedback/--no-feedback", help="PI feedback on/off."),
    feed_backup: bool = typer.Option(True, "--feed-backup/--no-feed-backup",
                                     help="Reduce the feed when the gas temperature saturates (split range)."),
    gas_t_max: float = typer.Option(600.0, help="Upper limit of the gas inlet temperature, degC."),
    gas_t_min: Optional[float] = typer.Option(None, help="Lower limit of the gas inlet temperature, degC."),
    feed_min_fraction: float = typer.Option(0.5, help="Lowest feed rate, fraction of the case's feed."),
    tolerance: Optional[float] = typer.Option(None, help="Band of the controlled variable for the settling time "
                                              "and the time within it (kg/kg wet or K; default 0.005 or 2)."),
    product_moisture_max: Optional[float] = typer.Option(None, help="Product specification: largest moisture, "
                                                         "kg/kg wet (reports the fraction of time within it)."),
    product_temperature_band: Optional[str] = typer.Option(None, metavar="LOW,HIGH",
                                                           help="Product specification: temperature band, degC "
                                                                "(reports the fraction of time within it)."),
    schedule: Optional[Path] = typer.Option(None, "--schedule", help="Disturbance schedule (.csv or .toml, the "
                                            "format of the dynamics command) in place of --scenario."),
    open_loop: bool = typer.Option(True, "--open-loop/--no-open-loop", help="Also run the uncontrolled plant."),
    out: Optional[Path] = typer.Option(None, help="Directory for control.json, control.csv and control.png."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress lines on stderr."),
):
    """Closed-loop simulation of the dynamic coupled model under a disturbance: PI feedback
    (velocity form, anti-windup, SIMC tuning from identified FOPDT step-response models,
    Skogestad 2003) and feed-forward from the measured feed moisture and feed rate (Ajayi 2011
    Ch. 7), manipulating the gas inlet temperature and, in split range, the feed rate. Prints
    IAE, maximum deviation, overshoot and settling time, closed vs open loop; progress on stderr (--quiet: none).

    \b
    Examples:
      rotarydryer control ajayi2011_mmg --set operating.test=4 --duration 7200 --out ctrl
      rotarydryer control ajayi2011_mmg --set operating.test=4 --duration 3600 --schedule moisture.toml

    \b
    A feed moisture step, moisture.toml:
      [[step]]
      input = "feed_moisture"
      at_s = 600
      value = 0.17
    """
    from .. import control as C
    from ..simulation import Simulation

    if schedule is not None:
        # the schedule is the disturbance: the scenario's options given with it were ignored (found by fuzzing)
        given = [f"--{n.replace('_', '-')}" for n in ("scenario", "magnitude", "step_time")
                 if getattr(ctx.get_parameter_source(n), "name", "") == "COMMANDLINE"]
        if given:
            typer.echo(f"error: --schedule and {', '.join(given)}: the schedule is the disturbance; give one or the "
                       "other", err=True)
            raise typer.Exit(2)
    try:
        band = parse_band(product_temperature_band)
    except ValueError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)
    step_time = check_control_options(scenario, magnitude, duration, step_time, sample_time, dead_time, measured,
                                      setpoint, kc, tau_i, tau_c, feedforward, gas_t_max, gas_t_min,
                                      feed_min_fraction, tolerance, product_moisture_max, band)
    check_out_dir("--out", out)

    with Progress("control", quiet=quiet) as bar:
        closed, opened = run_control(Simulation(case, parse_sets(set_)), case, scenario=scenario, magnitude=magnitude,
                                     duration=duration, step_time=step_time, sample_time=sample_time,
                                     dead_time=dead_time, measured=measured, setpoint=setpoint, kc=kc, tau_i=tau_i,
                                     tau_c=tau_c, feedforward=feedforward, feedback=feedback, feed_backup=feed_backup,
                                     gas_t_max=gas_t_max, gas_t_min=gas_t_min, feed_min_fraction=feed_min_fraction,
                                     open_loop=open_loop, progress=bar.message, schedule=schedule,
                                     tolerance=tolerance, product_moisture_max=product_moisture_max,
                                     product_temperature_band=band)
    result = dict(case=case, closed_loop=closed.summary(),
                  open_loop=opened.summary()["performance"] if opened is not None else None)
    if out is not None:
        from .._io import save_figure, write_text_atomic

        files = [out / "control.json", out / "control.csv", out / "control.png"]
        with written_set(out):                  # all files or none: a failure keeps the previous set
            write_text_atomic(files[0], json_text(dict(result, series={k: list(v) for k, v in closed.series.items()},
                                                       time_s=list(closed.time_s)), indent=1))
            write_text_atomic(files[1], closed.csv_text())
            save_figure(C.plot(closed, opened), files[2], dpi=110)
        result["files"] = [str(f) for f in files]
    if as_json:
        typer.echo(json_text(result))
        return
    cp = closed.performance
    quantity = "moisture" if measured == "product_moisture" else "temperature"
    t = closed.tuning
    step_time = closed.scenario["t_step_s"]
    if schedule is not None:
        what = f"schedule {schedule.name} at t = {show(step_time, 'time')}"
    elif scenario == "none":
        what = "no disturbance"
    else:
        what = f"{scenario} ({magnitude:+g}) at t = {show(step_time, 'time')}"
    applied = t.get("dead_time_applied_s", dead_time)
    typer.echo(f"{case}: {what}, {measured} setpoint "
               f"{show(closed.setpoint, quantity)}, sample {sample_time:g} s, dead time {applied:g} s"
               + (f" (--dead-time {dead_time:g} s in whole samples)" if abs(applied - dead_time) > 1e-9 else ""))
    typer.echo(f"  tuning ({t['rule']}): Kc = {t['kc']:.3g}, tau_I = {t['tau_i_s']:.0f} s, "
               f"gain margin {t['gain_margin']:.2f}, {describe_feedforward(t)}")
    for name, p in (("closed loop", cp), ("open loop", opened.performance if opened is not None else None)):
        if p is None:
            continue
        st = "never" if p["settling_time_s"] is None else show(p["settling_time_s"], "time")
        # the IAE, the integral of |e| over time: the deviations' display unit times s (pp s, K s, degF s)
        typer.echo(f"  {name:<11}  max |e| {show_delta(p['max_abs_deviation'], quantity)}, "
                   f"IAE {show_delta(p['iae'], quantity, 4)} s, "
                   f"overshoot {p['overshoot_pct']:.0f} %, settling {st}, within +-{show_delta(p['tolerance'], quantity)}: "
                   f"{'yes' if p['within_tolerance'] else 'no'} ({100 * p['fraction_within_tolerance']:.0f} % of the time)")
        spec = [f"moisture <= {show(p['product_moisture_max_kg_kg'], 'moisture')} "
                f"{100 * p['fraction_moisture_within_spec']:.0f} %"] if "fraction_moisture_within_spec" in p else []
        if "fraction_temperature_within_band" in p:
            lo, hi = p["product_temperature_band_degC"]
            spec.append(f"temperature {show(lo, 'temperature', with_unit=False)}-{show(hi, 'temperature')} "
                        f"{100 * p['fraction_temperature_within_band']:.0f} %")
        if spec:
            typer.echo(f"  {'':<11}  product within specification (of the time after the disturbance): "
                       + ", ".join(spec))
    s = closed.series
    typer.echo(f"  manipulated: gas inlet T {show(min(s['gas_inlet_temperature_degC']), 'temperature', with_unit=False)}-"
               f"{show(max(s['gas_inlet_temperature_degC']), 'temperature')}, feed "
               f"{show(min(s['feed_rate_kg_s']), 'mass_flow', with_unit=False)}-{show(max(s['feed_rate_kg_s']), 'mass_flow')}")
    if t.get("gas_temperature_range_note"):
        typer.echo(f"  note: {t['gas_temperature_range_note']}")
    short = t.get("burner_short")
    if short:
        typer.echo(f"warning: the case's burner cannot make the gas inlet temperature at {short['samples']} samples "
                   f"(t = {show(short['first_s'], 'time')} to {show(short['last_s'], 'time')}, up to "
                   f"{show(short['max_gas_inlet_temperature_degC'], 'temperature')}; fuel rate n/a there): the plant "
                   "cannot run those inputs", err=True)
    if out is not None:
        typer.echo(f"files: {', '.join(result['files'])}")
