"""``rotarydryer design``: size a flighted rotary dryer for a drying duty (or check a plant)."""

import time
from pathlib import Path
from typing import Optional

import typer

from .._display import show
from .._io import json_text
from ..services.design import design_duty, design_limits
from . import app
from ._common import CLUSTER_HELP, SCHEDULER_HELP, WORKERS_HELP, Progress, check_out_dir, connect_executor, written_set


@app.command("design", short_help="Size a dryer for a drying duty (or check a plant).")
def design_cmd(
    duty: Optional[str] = typer.Option(None, help="Preset duty: raw_sugar (20 kg/s, 1.0 -> 0.1 %, air 100 degC, "
                                                  "22 kg/s) | mmg (Ajayi Test 4); the options below override it."),
    material: Optional[str] = typer.Option(None, help="Material of the library (e.g. raw_sugar_lee2008)."),
    feed: Optional[float] = typer.Option(None, help="Wet feed rate, kg/s."),
    moisture_in: Optional[float] = typer.Option(None, help="Feed moisture, kg/kg wet."),
    moisture_out: Optional[float] = typer.Option(None, help="Target product moisture, kg/kg wet."),
    gas_in: Optional[float] = typer.Option(None, help="Gas inlet temperature, degC."),
    gas_flow: Optional[float] = typer.Option(None, help="Gas flow, kg/s wet (omit: from --ntu)."),
    ntu: Optional[float] = typer.Option(None, help="Transfer units when the gas flow is free (Perry: 1.5-2.5)."),
    direction: Optional[str] = typer.Option(None, help="co-current | counter-current."),
    feed_temperature: Optional[float] = typer.Option(None, help="Feed temperature, degC."),
    max_fuel: Optional[float] = typer.Option(None, help="Burner capacity, kg/s fuel oil."),
    objective: str = typer.Option("volume", help="volume | fuel | cost."),
    speed_fraction: float = typer.Option(0.5, help="Largest speed as a fraction of the critical speed."),
    entrainment_fraction: float = typer.Option(1.0, help="Largest gas velocity / particle terminal velocity."),
    gas_velocity_max: float = typer.Option(5.0, help="Largest gas velocity, m/s."),
    fill_max: float = typer.Option(0.15, help="Largest holdup / drum volume."),
    design_load_tolerance: float = typer.Option(0.15, help="Allowed |holdup / design load - 1|."),
    ld_min: float = typer.Option(4.0, help="Smallest length / diameter."),
    ld_max: float = typer.Option(10.0, help="Largest length / diameter."),
    d_min: float = typer.Option(0.5, help="Smallest diameter, m."),
    d_max: float = typer.Option(6.0, help="Largest diameter, m."),
    ua_factor: float = typer.Option(1.0, help="Multiplier on McCormick's Ua (calibrate with --check PLANT)."),
    top: int = typer.Option(8, help="Designs in the ranked table."),
    verify: bool = typer.Option(True, "--verify/--no-verify", help="Run the coupled heat-and-mass model on the best "
                                                                   "design; while it misses the target, lower "
                                                                   "the Ua factor and search again."),
    rounds: int = typer.Option(5, help="Most searches with --verify (each repeats the search with the Ua and holdup "
                                       "factors of the last verification)."),
    check: Optional[str] = typer.Option(None, help="Check a plant instead: its geometry under its own duty vs the "
                                                   "optimum. lee2008_invicta | ajayi2011_mmg (their published "
                                                   "duties) or any dryer case (name or .toml: the duty from its steady "
                                                   "state, or --moisture-out; --set overrides its keys)."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="With --check: override a case key, KEY=VALUE."),
    out: Optional[Path] = typer.Option(None, help="Directory for design.json, design_report.md and "
                                                  "design_cross_section.png."),
    workers: int = typer.Option(1, help=WORKERS_HELP + " Evaluate each generation of the search."),
    scheduler: Optional[str] = typer.Option(None, help=SCHEDULER_HELP),
    cluster: Optional[str] = typer.Option(None, help=CLUSTER_HELP),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress lines on stderr."),
):
    """Find drum diameter, length, slope, speed and flights (number, base and tip lengths, tip
    angle) that dry a duty to its target moisture with the flights at design load, within the
    constraints (critical speed, gas entrainment, fill, flight loading, L/D), minimising the drum
    volume, the fuel per kg of water or a cost proxy (SciPy differential evolution + Nelder-Mead;
    progress on stderr). Prints a ranked table of feasible designs with their binding
    constraints; an infeasible duty is an error naming the blocking constraint.

    Exit codes: 0 done, 1 the design's verification (coupled model) failed or missed the target,
    2 bad input or an infeasible duty.

    \b
    Examples:
      rotarydryer design --duty raw_sugar
      rotarydryer design --duty mmg --ua-factor 1.84 --no-verify --out mmg_design
      rotarydryer design --check ajayi2011_mmg
      rotarydryer new mydryer
      rotarydryer design --check mydryer.toml --moisture-out 0.005
    """
    from .. import design as D
    from ..services._options import executor_from_options

    t0 = time.perf_counter()
    limits = design_limits(objective, speed_fraction, entrainment_fraction, gas_velocity_max, fill_max,
                           design_load_tolerance, ld_min, ld_max, d_min, d_max, ua_factor, top, rounds)
    check_out_dir("--out", out)
    if set_ and check is None:      # it overrides the checked plant's keys; a sizing has no case to set them in
        typer.echo(f"error: --set {set_[0]} needs --check PLANT (it overrides that plant's case keys; a sizing for a "
                   "duty has no case: give the duty's options, e.g. --feed, --moisture-in, --gas-in)", err=True)
        raise typer.Exit(2)
    executor, notes = executor_from_options(workers, 12 * 8, scheduler=scheduler, cluster=cluster)  # a generation: 96
    for note in notes:
        typer.echo(f"warning: {note}", err=True)
    connect_executor(executor)
    with Progress("design", quiet=quiet) as bar:
        return _design(D, t0, limits, bar, duty, material, feed, moisture_in, moisture_out, gas_in, gas_flow,
                       ntu, direction, feed_temperature, max_fuel, objective, top, verify, rounds, check, out, as_json,
                       set_,
                       executor)


def _design(D, t0, limits, bar, duty, material, feed, moisture_in, moisture_out, gas_in, gas_flow, ntu, direction,
            feed_temperature, max_fuel, objective, top, verify, rounds, check, out, as_json, set_=None, executor=None):
    """The body of ``rotarydryer design`` (``bar``: its `Progress`, closed before the results print)."""
    progress = bar.message
    if check is not None:
        from ._common import parse_sets

        res = D.check_plant(check, limits, objective=objective, progress=progress, executor=executor,
                            overrides=parse_sets(set_) or None, moisture_out=moisture_out)
        bar.close()
        res["wall_time_s"] = time.perf_counter() - t0
        if out is not None:
            from .._io import write_text_atomic

            write_text_atomic(out / "plant_check.json", json_text(res, indent=1))
        if as_json:
            typer.echo(json_text(res))
            return
        typer.echo(f"{check}: real geometry D {show(res['real']['diameter_m'], 'length')} x L "
                   f"{show(res['real']['length_m'], 'length')}, "
                   f"{res['real']['n_flights']} flights, {res['real']['rpm']:g} rpm")
        if res["feasible_at_limits"]:
            typer.echo("  feasible at the given limits")
        else:
            typer.echo("  screening rules it violates at the given limits:")
            for k, v in res["violated_at_limits"].items():
                label, value, limit = D.constraint_text(k, v["value"], v["limit"], v["sense"])
                typer.echo(f"    {label}: {value} (limit {limit})")
        typer.echo(f"  calibrated on the plant (Ua factor {res['ua_factor_implied']:.2f}, limits widened to its "
                   f"own values): feasible = {res['feasible_calibrated']}; binding: "
                   f"{', '.join(res['binding_calibrated']) or '-'}")
        o = res["optimum"]
        if o is None:
            typer.echo(f"  optimum for the same duty: none; {'; '.join(res['why'])}")
        else:
            typer.echo(f"  optimum for the same duty: D {o['diameter_m']:.2f} m x L {o['length_m']:.2f} m, "
                       f"{o['n_flights']} flights, {o['rpm']:.2f} rpm; binding: {o['binding']}")
            typer.echo(f"  {objective}: plant / optimum = {res['objective_ratio']:.2f}; why: {'; '.join(res['why'])}")
        for note in res["notes"]:
            typer.echo(f"  note: {note}")
        return

    d = design_duty(duty, material, feed, moisture_in, moisture_out, gas_in, gas_flow, ntu, direction,
                    feed_temperature, max_fuel)
    if verify:
        res, ver = D.design_verified(d, limits, objective=objective, rounds=rounds, progress=progress,
                                     top=top, executor=executor)
    else:
        res, ver = D.design(d, limits, objective=objective, progress=progress, top=top, executor=executor), None
    bar.close()
    summary = dict(res.summary(), table=res.table(top))
    if ver is not None:
        summary["verification"] = ver
    wall = time.perf_counter() - t0
    summary["wall_time_s"] = wall
    if out is not None:
        from .._io import save_figure, write_text_atomic
        from ..geometry import FlightedDrum, TwoSectionFlight
        from ..report.plots import draw_cross_section

        b = res.best
        drum = FlightedDrum(b.diameter_m / 2, b.n_flights, TwoSectionFlight(s1=b.s1_m, s2=b.s2_m, alpha1=90.0,
                                                                             alpha2=b.alpha2_deg))
        files = [out / "design.json", out / "design_report.md", out / "design_cross_section.png"]
        with written_set(out):                  # all files or none: a failure keeps the previous set
            write_text_atomic(files[0], json_text(summary, indent=1))
            write_text_atomic(files[1], _report(d, res, summary))
            fig = draw_cross_section(drum, D._DutyModel(d).repose)
            save_figure(fig, files[2], dpi=100)
        summary["files"] = [str(f) for f in files]
    failed = _verification_failure(summary.get("verification"), d.moisture_out, res.best)
    if as_json:
        typer.echo(json_text(summary))
        if failed:
            typer.echo(f"error: {failed}", err=True)
            raise typer.Exit(1)
        return
    typer.echo(_table_text(d, res, wall))
    ver = summary.get("verification")
    if ver is not None:
        if "error" in ver:
            typer.echo(f"verification (coupled model) failed: {_probe_infeasible(res.best, ver['error'])}")
        else:
            if len(ver["rounds"]) > 1:
                typer.echo("verification rounds (Ua factor, holdup factor -> product moisture, holdup): " + ", ".join(
                    f"{r['ua_factor']:.3g}, {r.get('holdup_factor', 1.0):.3g} -> "
                    f"{show(r.get('product_moisture_kg_kg', float('nan')), 'moisture')}, "
                    f"{show(r.get('total_holdup_kg', float('nan')), 'mass')}"
                    for r in ver["rounds"]))
            typer.echo(f"verification (coupled model, Lee 2008 transport): product moisture "
                       f"{show(ver['product_moisture_kg_kg'], 'moisture')} wet (target {show(d.moisture_out, 'moisture')}: "
                       f"{'met' if ver['target_met'] else 'NOT met'}), exhaust "
                       f"{show(ver['gas_outlet_temperature_degC'], 'temperature')}, holdup "
                       f"{show(ver['total_holdup_kg'], 'mass')}")
            if ver.get("constraints_violated"):
                typer.echo("  the coupled model breaks the screening's limits: " + "; ".join(ver["constraints_violated"]))
            if "next_round_infeasible" in ver:
                typer.echo("  with the Ua lowered to what the coupled model achieves, the next search found no "
                           f"feasible probe: {_search_infeasible(ver['next_round_infeasible'])}")
    if out is not None:
        typer.echo(f"files: {', '.join(summary['files'])}")
    if failed:
        typer.echo(f"error: {failed}", err=True)
        raise typer.Exit(1)


def _probe_text(b) -> str:
    """``probe at D=2.1 m, L=12.3 m, ...``: the design point an optimiser step evaluated."""
    return (f"probe at D={b.diameter_m:.3g} m, L={b.length_m:.3g} m, slope={b.slope_deg:.3g} deg, "
            f"rpm={b.rpm:.3g}, flights={b.n_flights}")


def _probe_infeasible(b, error) -> str:
    """A failure of the model at a design point the search chose, worded as the search's (not as a
    bad input of the user's): ``probe at D=... infeasible: <reason>``."""
    reason = " ".join(str(error).split())
    return f"{_probe_text(b)} infeasible: {reason}" if b is not None else reason


def _search_infeasible(error) -> str:
    """The InfeasibleDuty of a later search round without its 'infeasible duty: ' lead (the duty the
    user gave was feasible in the first round; the lowered Ua factor is the search's own)."""
    text = " ".join(str(error).split())
    return text[len("infeasible duty: "):] if text.startswith("infeasible duty: ") else text


def _verification_failure(ver, target, best=None) -> str:
    """The one-line reason the coupled-model verification of a design failed (it could not run, or
    the design misses the target moisture), or '' (passed, or not verified: --no-verify);
    ``best``: the verified design (its point is named: the failure is the search's, not the input's)."""
    if ver is None:
        return ""
    if "error" in ver:
        msg = f"the design's verification (coupled model) failed: {' '.join(str(ver['error']).split())}"
        return msg + (f" ({_probe_text(best)} infeasible)" if best is not None else "")
    if not ver.get("target_met", True):
        return (f"the design's verification (coupled model) failed: product moisture "
                f"{show(ver.get('product_moisture_kg_kg', float('nan')), 'moisture')} wet misses the target "
                f"{show(target, 'moisture')} "
                f"after {len(ver.get('rounds', []))} round(s) (--rounds"
                + (f"; the closest, round {ver['best_round']}" if ver.get("best_round", 1) != len(ver.get("rounds", []))
                   else "")
                + (f"; a further round: {_search_infeasible(ver['next_round_infeasible'])}"
                   if ver.get("next_round_infeasible") else "")
                + "); the design does not meet the duty")
    if ver.get("constraints_violated"):
        broken = ver["constraints_violated"]
        # the advice of each limit broken (design.verified_violations' phrases), not of the others
        advice = {"exhaust dew-point margin": "a larger --gas-flow or a hotter --gas-in keeps the exhaust above its "
                                              "dew point",
                  "fill": "--fill-max bounds the fill",
                  "flights over-loaded": "--design-load-tolerance widens the flights' accepted loading (the coupled "
                                         "model holds more than the screening's residence time gives)",
                  "flights under-loaded": "--design-load-tolerance widens the flights' accepted loading"}
        tips = [tip for start, tip in advice.items() if any(b.startswith(start) for b in broken)]
        return ("the design's verification (coupled model) failed: the target moisture is met, but the coupled model "
                f"breaks the screening's limits ({'; '.join(broken)}) after "
                f"{len(ver.get('rounds', []))} round(s) (--rounds)" + (f"; {', '.join(tips)}" if tips else ""))
    return ""


def _table_text(d, res, wall):
    lines = [f"duty: {d.material}, {show(d.feed_rate, 'mass_flow')}, {show(d.moisture_in, 'moisture', with_unit=False)} -> "
             f"{show(d.moisture_out, 'moisture')} wet, gas {show(d.gas_inlet_temperature, 'temperature')} {d.direction}; "
             f"objective {res.objective}; "
             f"{res.evaluations} evaluations in {wall:.1f} s",
             f"{'#':>2} {'D m':>5} {'L m':>6} {'slope':>5} {'rpm':>5} {'Nf':>3} {'s1 m':>5} {'s2 m':>5} {'a2':>4} "
             f"{'V m3':>7} {'MJ/kg':>6} {'u m/s':>5} {'fill':>5} {'H/DL':>5}  binding"]
    for r in res.table(len(res.designs)):
        lines.append(f"{r['rank']:>2} {r['diameter_m']:5.2f} {r['length_m']:6.2f} {r['slope_deg']:5.2f} "
                     f"{r['rpm']:5.2f} {r['n_flights']:>3} {r['s1_m']:5.3f} {r['s2_m']:5.3f} {r['alpha2_deg']:4.0f} "
                     f"{r['volume_m3']:7.1f} {r['fuel_per_kg_water_MJ']:6.2f} {r['gas_velocity_m_s']:5.2f} "
                     f"{r['fill_fraction']:5.3f} {r['holdup_over_design_load']:5.2f}  {r['binding']}")
    lines.append(f"binding constraints of the best design: {', '.join(res.best.binding()) or 'none'}")
    return "\n".join(lines)


def _report(d, res, summary):
    from .. import design as D

    b = res.best
    v = b.values
    rows = "\n".join("| {} | {} | {} | {:.1%} |".format(*D.constraint_text(k, c[0], c[1], c[2]), -c[3])
                     for k, c in b.constraints.items())
    return f"""# Dryer design report

Duty: {d.material}, feed {show(d.feed_rate, 'mass_flow')} wet, moisture {show(d.moisture_in, 'moisture', with_unit=False)} ->
{show(d.moisture_out, 'moisture')} wet, gas {show(d.gas_inlet_temperature, 'temperature')} {d.direction}, gas flow
{show(v['gas_flow_kg_s'], 'mass_flow')}.
Objective: {res.objective}. Search: SciPy differential evolution ({res.evaluations} evaluations) + Nelder-Mead.

## Best design

Drum D = {b.diameter_m:.2f} m, L = {b.length_m:.2f} m (L/D {b.length_m / b.diameter_m:.1f}), slope {b.slope_deg:.2f} deg,
{b.rpm:.2f} rpm ({v['speed_over_critical']:.0%} of the critical {v['critical_speed_rpm']:.1f} rpm);
{b.n_flights} two-section flights s1 = {b.s1_m:.3f} m, s2 = {b.s2_m:.3f} m, alpha1 = 90 deg, alpha2 = {b.alpha2_deg:.0f} deg.

Volume {v['volume_m3']:.1f} m3; evaporation {show(v['evaporation_kg_s'], 'mass_flow')}; heat input
{show(v['heat_input_W'], 'power')} ({show(v['heat_input_per_kg_water_J'], 'specific_energy')} water); exhaust
{show(v['gas_outlet_temperature_degC'], 'temperature')}; Ua {v['volumetric_ua_W_m3K']:.0f} W/(m3 K) (McCormick 1962,
Perry Sec. 12); mean residence time {show(v['mean_residence_time_s'], 'time')} (Perry & Green 1984); holdup
{show(v['holdup_kg'], 'mass')}, design load {show(v['design_load_kg'], 'mass')}.

Binding constraints: {', '.join(b.binding()) or 'none'}.

| constraint | value | limit | slack |
|---|---|---|---|
{rows}

{_verification_text(d, summary.get("verification"))}"""


def _verification_text(d, ver) -> str:
    """The report's section on the coupled model's verification of the best design."""
    if ver is None:
        return ("The screening correlations are generic; verify the chosen design with the coupled model\n"
                "(`rotarydryer design` without `--no-verify`, or `rotarydryer new NAME` and `rotarydryer simulate`).\n")
    if "error" in ver:
        return f"## Verification (coupled model)\n\nThe coupled model could not run the design: {' '.join(str(ver['error']).split())}\n"
    margin = ver.get("gas_outlet_dew_point_margin_K")
    rounds = "\n".join(f"| {k + 1} | {r['ua_factor']:.3g} | {r.get('holdup_factor', 1.0):.3g} | "
                       f"{show(r['product_moisture_kg_kg'], 'moisture')} | {show(r['total_holdup_kg'], 'mass')} | "
                       f"{'; '.join(r.get('constraints_violated') or []) or '-'} |"
                       for k, r in enumerate(ver.get("rounds", [])) if "product_moisture_kg_kg" in r)
    broken = "; ".join(ver.get("constraints_violated") or [])
    return f"""## Verification (coupled model, Lee 2008 transport)

Product moisture {show(ver['product_moisture_kg_kg'], 'moisture')} wet (target {show(d.moisture_out, 'moisture')}:
{'met' if ver['target_met'] else 'NOT met'}); exhaust {show(ver['gas_outlet_temperature_degC'], 'temperature')}
(dew-point margin {'n/a' if margin is None else f"{margin:.3g} K"}); product {show(ver['product_temperature_degC'], 'temperature')};
holdup {show(ver['total_holdup_kg'], 'mass')}. Screening limits broken by the coupled model: {broken or 'none'}.

| round | Ua factor | holdup factor | product moisture | holdup | limits broken |
|---|---|---|---|---|---|
{rounds}
"""
