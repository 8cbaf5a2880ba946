"""``rotarydryer simulate`` and ``rotarydryer rtd``: solids transport of a case."""

from pathlib import Path
from typing import Optional

import typer

from .._io import json_text
from . import app
from ._common import check_out_file, parse_sets, written_set


def _save_last_thermal_state(exc, out, diagnostics=None) -> Optional[str]:
    """Write the last iterate of a failed thermal steady state (``DryerError.state``) to the file
    ``diagnostics`` or, without it, to ``thermal_last_state.json`` in ``out``; never into the
    working directory unasked. Returns the line telling the user where it went (or how to get
    it), or None when the error has no solver state."""
    import numpy as np

    from .._io import write_text_atomic

    state = getattr(exc, "state", None)
    if state is None or not hasattr(state, "profiles"):
        return None
    if diagnostics is None and out is None:
        return ("the solver's last state was not saved: rerun with --diagnostics FILE.json "
                "(or --out DIR) to save it")
    target = Path(diagnostics) if diagnostics is not None else Path(out) / "thermal_last_state.json"
    record = {"error": str(exc), "reason": exc.reason, "summary": state.summary(with_fuel=False),
              "profiles": {k: np.asarray(v).tolist() for k, v in state.profiles().items()},
              "state_vector": np.asarray(state.state).tolist()}
    try:
        return f"last solver state saved to {write_text_atomic(target, json_text(record, indent=1, default=float))}"
    except OSError as exc2:
        return f"the solver's last state could not be saved: {exc2}"


@app.command("simulate", short_help="Steady state of a dryer: transport, heat and mass.")
def simulate(
    case: str = typer.Argument(..., help="Case name (lee2008_invicta, ajayi2011_mmg) or a .toml file."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Override KEY=VALUE, e.g. transport.n_cells=33."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    out: Optional[Path] = typer.Option(None, help="Directory for steady_state.json and holdup_profile.png."),
    diagnostics: Optional[Path] = typer.Option(None, "--diagnostics", help="File for the solver's last state "
                                               "(JSON) when the heat and mass steady state fails (default with "
                                               "--out: DIR/thermal_last_state.json; without either: not saved)."),
):
    """Steady state of a dryer: solids transport (holdup per phase and section, loading state
    per cell, flows, tracer moments) and, for every case with a [gas] block, heat and mass
    transfer (product moisture and temperature, gas outlet, evaporation, shell loss, balances;
    fuel rate where the case has a burner). Outputs are named with their unit.

    \b
    Example:
      rotarydryer simulate lee2008_invicta --set geometry.method=lee2008_regressions
    """
    from ..simulation import Simulation
    from ..thermal.states import dust_share

    try:
        check_out_file("--diagnostics", diagnostics)
        sim = Simulation(case, parse_sets(set_))
        model = sim.transport_model()
        ss = sim.transport_steady_state()
    except ValueError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)
    thermal = None
    try:
        steady = sim.steady_state()
        thermal = steady.thermal
    except ValueError as exc:
        typer.echo(f"error: heat and mass transfer: {exc}", err=True)
        saved = _save_last_thermal_state(exc, out, diagnostics)
        if saved is not None:
            typer.echo(saved, err=True)
        solver_failed = getattr(exc, "reason", None) in ("no_steady_state", "diverged", "integration")
        raise typer.Exit(1 if solver_failed else 2)
    ss = steady.state        # the one state every output shows (the coupled one with heat and mass)
    result = steady.to_dict()
    for key in ("sections", "cells", "shell_sections"):   # keep the JSON's order: tables, then case and parameters
        if key in result:
            result[key] = result.pop(key)
    result.update({"case": case, "parameters": model.parameters})
    thermal_on = thermal is not None
    # [particle_size] (one class with entrainment too: its dust and d50 are shown)
    classes = thermal_on and (thermal.dryer.n_classes > 1 or thermal.dryer.dusty)
    if classes:           # [particle_size]: a row per size class
        result["size_classes"] = thermal.size_class_table()
    if out is not None:
        from .._io import save_figure, write_text_atomic
        from ..report.plots import plot_thermal_steady_state
        from ..transport.plots import plot_holdup_profile

        files = [out / "steady_state.json", out / "holdup_profile.png"]
        with written_set(out):                  # all files or none: a failure keeps the previous set
            write_text_atomic(files[0], json_text(result, indent=1))
            save_figure(plot_holdup_profile(ss, name=model.name), files[1], dpi=120)
            if thermal is not None:
                files.append(out / "thermal_profiles.png")
                save_figure(plot_thermal_steady_state(thermal), files[2], dpi=120)
            if classes:
                from ..thermal.plots import plot_size_distributions

                files.append(out / "size_distributions.png")
                save_figure(plot_size_distributions(thermal, title=case), files[-1], dpi=120)
        result["files"] = [str(f) for f in files]
    if as_json:
        typer.echo(json_text(result))
        from ..thermal.states import fuel_rate_note

        note = fuel_rate_note(result)
        if note:        # on stderr, as the text output's (the JSON holds fuel_rate_error; found by an acceptance check)
            typer.echo(f"warning: {note}", err=True)
        return
    from .._display import fmt_error, show, show_output

    typer.echo(f"{case}: {model.name}, feed {show(result['feed_rate_kg_s'], 'mass_flow')}"
               + (" (transport, heat and mass)" if thermal_on else " (solids transport only)"))
    rows = [
        ("total holdup", show_output("total_holdup_kg", result["total_holdup_kg"])),
        ("  active (curtain)", show_output("active_holdup_kg", result["active_holdup_kg"])),
        ("  passive (flights + floor)", show_output("passive_holdup_kg", result["passive_holdup_kg"])),
        ("  unflighted bed", show_output("bed_holdup_kg", result["bed_holdup_kg"])),
        ("outlet flow", show_output("outlet_flow_kg_s", result["outlet_flow_kg_s"])),
        ("mean residence time H/F", show_output("mean_residence_time_s", result["mean_residence_time_s"])
         # dry holdup over the dry solids leaving: with dust, both outlets; the product's own is its RTD's mean
         + (f" (product and dust; the product's RTD mean {show(result['rtd_mean_residence_time_s'], 'time')})"
            if (result.get("dust_rate_kg_s") or 0.0) > 0 else "")),
        ("tracer mean / SD", f"{show(result['tracer_mean_s'], 'time', with_unit=False)} / "
                             f"{show(result['tracer_std_s'], 'time')}"),
    ]
    if not thermal_on:
        rows.append(("mass balance error", f"{fmt_error(ss.mass_balance_error)} (relative)"))
    for name, h in ss.section_holdups().items():
        rows.append((f"section {name}", show(h["total_kg"], "mass")))
    if thermal is not None:
        rows += [
            ("product moisture", f"{show_output('product_moisture_kg_kg', result['product_moisture_kg_kg'])} wet basis"),
            ("product temperature", show_output("product_temperature_degC", result["product_temperature_degC"])),
            ("gas outlet temperature", show_output("gas_outlet_temperature_degC", result["gas_outlet_temperature_degC"])),
            ("evaporation", show_output("evaporation_kg_s", result["evaporation_kg_s"])),
            ("shell heat loss", show_output("shell_heat_loss_W", result["shell_heat_loss_W"])),
            ("energy / water balance error", f"{fmt_error(result['energy_balance_error'])} / "
                                              f"{fmt_error(result['water_balance_error'])} (relative)"),
        ]
        if classes:
            rows += [("product d50", f"{show_output('product_d50_m', result['product_d50_m'])} "
                                     f"({thermal.dryer.n_classes} size classes)"),
                     # the share of the feed's solids, as the entrainment warning gives it (the dust rate with its
                     # water over the wet feed was a second, smaller share of one quantity)
                     ("dust to the exhaust", f"{show_output('dust_rate_kg_s', result['dust_rate_kg_s'])} wet "
                                             f"({dust_share(thermal):.1%} of the feed's dry solids)")]
        rows += _audit_rows(result)
        if "fuel_rate_kg_s" in result:      # cases with a burner
            rows.append(("fuel rate", "n/a (the burner cannot reach the set point: see the warning below)"
                         if result["fuel_rate_kg_s"] is None else show_output("fuel_rate_kg_s", result["fuel_rate_kg_s"])))
    states = ss.loading_state
    rows.append(("cells over / design / under", f"{states.count('over')} / {states.count('design')} / "
                                            f"{states.count('under')}"))
    w = max(len(k) for k, _ in rows)
    for k, v in rows:
        typer.echo(f"  {k:<{w}}  {v}")
    from ..thermal.states import fuel_rate_note

    note = fuel_rate_note(result)
    if note:        # a valid steady state of the set gas temperature, which the burner cannot deliver: exit 0
        typer.echo(f"warning: {note}", err=True)
    if out is not None:
        typer.echo(f"files: {', '.join(result['files'])}")


def _audit_rows(result: dict) -> list[tuple[str, str]]:
    """The energy audit's rows of the text output: the heat duties (display unit of power, share of
    the release), the exhaust's dew-point margin and the hottest shell against its limit."""
    from .._display import show, show_delta, show_output
    from ..thermal.audit import HEAT_DUTY_LABELS, HEAT_DUTY_PARTS

    release = result["heat_release_W"]
    rows = [("heat release" + (" (fuel x LHV)" if result.get("fuel_rate_kg_s") else " (heat put into the gas)"),
             show_output("heat_release_W", release))]
    for k in HEAT_DUTY_PARTS:
        share = f" ({100 * result[k] / release:.1f} %)" if release else ""
        rows.append((f"  {HEAT_DUTY_LABELS[k]}", show_output(k, result[k]) + share))
    rows.append(("  (exhaust latent heat)", show_output("heat_duty_exhaust_latent_W", result["heat_duty_exhaust_latent_W"])
                 + " - part of the evaporation's heat"))
    margin = result.get("gas_outlet_dew_point_margin_K")
    if margin is not None:
        rows.append(("exhaust dew point / margin", f"{show(result['gas_outlet_dew_point_degC'], 'temperature')} / "
                     f"{show_delta(margin, 'temperature')}" + ("" if margin > 0 else " (condensation)")))
    limit = result.get("shell_temperature_limit_degC")
    rows.append(("hottest shell surface / steel", f"{show(result['shell_max_surface_temperature_degC'], 'temperature')} / "
                 f"{show(result['shell_max_wall_temperature_degC'], 'temperature')}"
                 + ("" if limit is None else f" (limit {show(limit, 'temperature')}: "
                    + ("exceeded)" if result.get("shell_temperature_limit_exceeded") else "met)"))))
    return rows


@app.command("rtd", short_help="Simulated tracer pulse (RTD) at the steady state.")
def rtd(
    case: str = typer.Argument(..., help="Case name or .toml file."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Override KEY=VALUE."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    out: Optional[Path] = typer.Option(None, help="Directory for rtd.csv, rtd.json and rtd.png."),
    method: str = typer.Option("auto", help="Tracer integrator: auto | expm | bdf2 | ivp."),
    coupled_state: bool = typer.Option(False, "--coupled", help="The coupled heat-and-mass steady state that "
                                       "simulate, report and sweep report, instead of the solids transport's own "
                                       "(cases with a gas)."),
):
    """Tracer pulse at the steady state: E(t), mean, SD, recovery; plot against the
    case's measured RTD when it has one. The state is the solids transport's own, at the
    case's assumed moisture profile (the published transport models' and `validate`'s);
    --coupled: the coupled heat-and-mass state `simulate` reports, for a case with a gas.

    \b
    Example:
      rotarydryer rtd lee2008_invicta --set geometry.method=lee2008_regressions --out out/
    """
    from ..simulation import Simulation

    try:
        from .._validation import check_choice
        from ..cases import measured_rtd
        from ..transport.network import RTD_METHODS

        check_choice("--method", method, RTD_METHODS)     # named as the option, before the run
        sim = Simulation(case, parse_sets(set_))
        c, model = sim.case, sim.transport_model()
        if coupled_state and not sim.thermal_enabled:
            raise ValueError(f"--coupled: case {case!r} has no heat and mass transfer (thermal.enabled = false or no "
                             "[gas]): its steady state is the solids transport's")
        coupled = coupled_state
        ss = sim.transport_steady_state() if not coupled else None
        meas = measured_rtd(c)
    except ValueError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)
    try:
        if coupled:         # the state simulate reports (the same holdups, residence times and tracer moments)
            ss = sim.steady_state().state
        res = ss.rtd(model.tracer_input, t_end=c.tracer.t_end, dt=c.tracer.dt, method=method)
    except ValueError as exc:
        typer.echo(f"error: {'heat and mass transfer: ' if coupled else ''}{exc}", err=True)
        solver_failed = getattr(exc, "reason", None) in ("no_steady_state", "diverged", "integration")
        raise typer.Exit(1 if solver_failed else 2)
    result = res.to_dict()
    result.update({
        "case": case,
        "model": model.name,
        # the solids transport's own steady state (the case's assumed moisture profile), as `validate`'s tracer items
        # and the transport calibrations; with a gas, `simulate`, `report` and `sweep` report the coupled
        # heat-and-mass state's holdups and residence times instead, which --coupled gives here
        "steady_state": "coupled heat-and-mass state" if coupled else "solids transport alone" + (
            " (simulate: the coupled heat-and-mass state)" if sim.thermal_enabled else ""),
        "total_holdup_kg": ss.total_holdup,
        "active_holdup_kg": ss.active_holdup,
        "passive_holdup_kg": ss.passive_holdup,
        "bed_holdup_kg": ss.bed_holdup,
        "outlet_flow_kg_s": ss.outlet_flow,
        "holdup_over_flow_s": ss.mean_residence_time,
    })
    if meas is not None:
        from ..cases import measured_rtd_moments

        mm = measured_rtd_moments(c)
        result["measured_mean_s"] = float(mm["mean_s"])
        result["measured_std_s"] = float(mm["std_s"])
        result["measured_baseline"] = mm["baseline"]
        result["measured_baseline_method"] = mm["baseline_method"]
    if out is not None:
        import io

        import numpy as np

        from .._io import save_figure, write_text_atomic
        from ..transport.plots import plot_rtd

        r = res.response
        width = float(np.diff(model.tracer_input.breakpoints)[0]) if len(model.tracer_input.rates) == 1 else 0.0
        # the curve through the case's pulse (its metadata: rtd-moments and rtd-fit take the pulse off)
        meta = [f"# source: rotarydryer rtd {case}: the model's tracer curve through the case's pulse "
                f"(E_per_s: its exit age, 1/s; mean {result['tracer_mean_s']:.6g} s from the injection start)",
                f"# time_origin_s: {float(model.tracer_input.breakpoints[0]):.9g}"]
        if width > 1e-3:
            meta += ["# pulse_kind: rectangular", f"# pulse_duration_s: {width:.9g}"]
        buf = io.StringIO()
        np.savetxt(buf, np.c_[r.time, r.exit_age, r.cumulative], delimiter=",",
                   header="\n".join(meta + ["time_s,E_per_s,F"]), comments="")
        with written_set(out):                  # all files or none: a failure keeps the previous set
            write_text_atomic(out / "rtd.csv", buf.getvalue())
            write_text_atomic(out / "rtd.json", json_text(result, indent=1))
            save_figure(plot_rtd(res, meas, baseline=result.get("measured_baseline", 0.0)), out / "rtd.png", dpi=120)
        result["files"] = [str(out / f) for f in ("rtd.csv", "rtd.json", "rtd.png")]
    if as_json:
        typer.echo(json_text(result))
        return
    from .._display import show

    def t(key):     # a time of the result in its display unit (--units time=s, min or h)
        return show(result[key], "time")

    typer.echo(f"{case}: {model.name} tracer RTD ({res.response.method}, dt {show(c.tracer.dt, 'time')})")
    if coupled:
        typer.echo("  (the coupled heat-and-mass steady state, as `simulate` reports it)")
    elif sim.thermal_enabled:
        typer.echo("  (the solids transport's own steady state, at the case's assumed moisture profile; `simulate` "
                   "gives the coupled heat-and-mass state's holdup and residence times: rtd --coupled)")
    if getattr(c, "particle_size", None) is not None:
        typer.echo("  (the solids as one mixture: the size classes and the dust the gas carries off are in `simulate`'s "
                   "per-class table, with each class's RTD mean)")
    typer.echo(f"  mean residence time  {t('mean_residence_time_s')} (the RTD's mean; holdup/flow "
               f"{t('holdup_over_flow_s')}), SD {t('rtd_std_s')}")
    typer.echo(f"  tracer curve         mean {t('tracer_mean_s')} (analytic), {t('simulated_mean_s')} (simulated), "
               f"SD {t('tracer_std_s')}, from injection start")
    typer.echo(f"  recovery             {result['recovery']:.6f} (analytic), {result['simulated_recovery']:.6f} "
               f"(simulated to {show(c.tracer.t_end, 'time')})")
    if meas is not None:
        typer.echo(f"  measured             mean {t('measured_mean_s')}, SD {t('measured_std_s')}")
    if out is not None:
        typer.echo(f"files: {', '.join(result['files'])}")
