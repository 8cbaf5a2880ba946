"""``rotarydryer fit``: estimate case parameters from a measured tracer curve."""

from pathlib import Path
from typing import Optional

import typer

from .._limits import key_unit
from .._validation import check_choice
from . import app
from ._common import (
    CLUSTER_HELP,
    SCHEDULER_HELP,
    WORKERS_HELP,
    Progress,
    check_option,
    check_out_dir,
    connect_executor,
    load_tracer,
    parse_sets,
    written_set,
)


@app.command("fit", short_help="Fit case parameters to a tracer curve.")
def fit_command(
    case: str = typer.Argument(..., help="Built-in case name or a case .toml file."),
    data: str = typer.Argument(..., help="Tracer CSV (time_s|time_min|time_h, signal) or a built-in data set name."),
    param: list[str] = typer.Option(..., "--param", "-p", help="Override key to estimate (repeat)."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Fixed override KEY=VALUE (repeat)."),
    starts: int = typer.Option(2, help="Number of starts (the case values plus sampled ones), 1-100."),
    workers: int = typer.Option(1, help=WORKERS_HELP + " Runs the starts."),
    scheduler: Optional[str] = typer.Option(None, help=SCHEDULER_HELP),
    cluster: Optional[str] = typer.Option(None, help=CLUSTER_HELP),
    scale: str = typer.Option("known", help="'known': the signal is E(t); 'fit': raw concentration, unknown scale."),
    method: str = typer.Option("wls", help="wls | ml"),
    baseline: str = typer.Option("none", help="none | fit: fit a constant tracer background (signal unit) "
                                 "as one more parameter ('baseline')."),
    profile: bool = typer.Option(False, "--profile", help="Also profile-likelihood 95 % intervals (each point "
                                 "re-fits the other parameters)."),
    profile_points: Optional[int] = typer.Option(None, help="Grid points of each profile (3-101, default 11; "
                                                 "needs --profile)."),
    out: Optional[Path] = typer.Option(None, help="Directory for fit.png and fit.json (and profile.png)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress lines on stderr."),
):
    """Fit case parameters to a tracer curve, with 95 % confidence intervals.

    \b
    Examples:
      rotarydryer fit lee2008_invicta lee2008_invicta -p transport.kiln_time -p transport.backmix -p transport.drag_reduction --set transport.n_cells=35 --set geometry.method=lee2008_regressions
      rotarydryer fit ajayi2011_mmg ajayi2011_test4 -p transport.solids_velocity -p transport.dispersion --set operating.test=4 --scale fit --baseline fit --profile
    """
    import warnings

    from ..estimation import FitError
    from ..estimation.cases import BASELINE_CHOICES, fit_case_to_tracer, profile_case_fit
    from ..services._options import executor_from_options

    try:
        check_choice("--scale", scale, ("known", "fit"))
        check_choice("--method", method, ("wls", "ml"))
        if baseline not in BASELINE_CHOICES:
            raise ValueError(f"--baseline = {baseline!r} is not one of {', '.join(BASELINE_CHOICES)} (fit: a "
                             "constant tracer background fitted with the case parameters)")
        if profile_points is not None:
            if not profile:
                raise ValueError(f"--profile-points = {profile_points} needs --profile")
            check_option("--profile-points", profile_points, 3, 101, low_inclusive=True, high_inclusive=True)
        check_option("--starts", starts, 1, 100, low_inclusive=True, high_inclusive=True)
        check_out_dir("--out", out)
        base = parse_sets(set_)
        tracer = load_tracer(data)
        executor, notes = executor_from_options(workers, starts, scheduler=scheduler, cluster=cluster)
        for note in notes:
            typer.echo(f"warning: {note}", err=True)
        connect_executor(executor)

        with warnings.catch_warnings(), Progress("start", starts, quiet=quiet) as bar:
            warnings.simplefilter("ignore")
            cf = fit_case_to_tracer(case, tracer, param, base_overrides=base, n_starts=starts, scale=scale,
                                    method=method, baseline=baseline, executor=executor,
                                    progress=lambda k, n, best: bar.update(k, n, f"best objective {best:.6g}"))
            profiles = {}
            if profile:
                profiles = profile_case_fit(cf, n_points=profile_points or 11,
                                            progress=lambda name, k, n: bar.update(k, n, name, label="profile"))
    except (ValueError, FitError) as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)
    r = cf.fit
    result = {
        "case": case,
        "data": data,
        "parameters": {k: {"value": p.value, "std_error": p.std_error, "ci_low": p.ci_low, "ci_high": p.ci_high}
                       for k, p in r.parameters.items()},
        "baseline": baseline,
        "objective": r.objective,
        "r_squared": r.r_squared,
        "n_evaluations": r.n_evaluations,
        "seconds": r.seconds,
        "correlation": r.correlation.tolist(),
        "starts": [{"start": s.start, "objective": s.objective, "success": s.success} for s in r.starts],
        "warnings": r.warnings,
    }
    if profiles:
        from scipy import stats

        for k, pr in profiles.items():
            result["parameters"][k].update(profile_ci_low=pr.ci_low, profile_ci_high=pr.ci_high,
                                           profile_flat=pr.flat, profile_open_low=pr.open_low,
                                           profile_open_high=pr.open_high)
        result["profiles"] = {k: {"values": pr.values.tolist(), "delta": pr.delta.tolist(),
                                  "threshold": float(stats.chi2.ppf(0.95, 1))} for k, pr in profiles.items()}
    if out is not None:
        from .._plotting import pyplot

        plt = pyplot()

        fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True, constrained_layout=True,
                                     gridspec_kw={"height_ratios": [3, 1]})
        t = cf.times / 60.0
        pred = r.predictions["tracer"]
        a1.plot(t, cf.observed * 60, "ko", ms=4, label="measured")
        a1.plot(t, pred * 60, "r-", label="fitted model")
        a1.set_ylabel("E(t) (1/min)")
        a1.legend()
        a2.plot(t, (cf.observed - pred) * 60, "k.")
        a2.axhline(0, color="0.5", lw=0.8)
        a2.set_ylabel("residual")
        a2.set_xlabel("time since injection (min)")
        from .._io import json_text, save_figure, write_text_atomic

        with written_set(out):                  # all files or none: a failure keeps the previous set
            save_figure(fig, out / "fit.png", dpi=110)
            plots = [str(out / "fit.png")]
            if profiles:
                save_figure(_profile_figure(plt, profiles, r), out / "profile.png", dpi=110)
                plots.append(str(out / "profile.png"))
            write_text_atomic(out / "fit.json", json_text(result, indent=2))
        result["plots"] = plots
    if as_json:
        from .._io import json_text

        typer.echo(json_text(result))
        return
    typer.echo(f"fit of {case} to {data}: objective {r.objective:.6g}, R^2 {r.r_squared:.4f}, "
               f"{r.n_evaluations} model evaluations, {r.seconds:.1f} s")
    w = max(len(k) for k in r.parameters)
    units = {k: key_unit(k) for k in r.parameters}
    wu = max(4, *(len(u) for u in units.values()))
    head = f"  {'parameter':<{w}}  {'unit':<{wu}}  {'estimate':>12}  {'95% CI (Wald)':>29}"
    typer.echo(head + (f"  {'95% CI (profile likelihood)':>29}" if profiles else ""))
    for k, p in r.parameters.items():
        line = f"  {k:<{w}}  {units[k]:<{wu}}  {p.value:12.6g}  [{p.ci_low:12.6g}, {p.ci_high:12.6g}]"
        if k in profiles:
            pr = profiles[k]
            line += (f"  [{pr.ci_low:12.6g}{'-' if pr.open_low else ''}, {pr.ci_high:12.6g}"
                     f"{'+' if pr.open_high else ''}]" + (" flat" if pr.flat else ""))
        typer.echo(line)
    if profiles:
        typer.echo("  (profile: where the objective, re-minimised over the others, rises by chi2(0.95, 1) = 3.84; "
                   "'-'/'+': open, no rise within the grid on that side; 'flat': on neither)")
    typer.echo("correlation matrix:")
    for k, row in zip(r.names, r.correlation):
        typer.echo(f"  {k:<{w}}  " + " ".join(f"{x:+.3f}" for x in row))
    for msg in r.warnings:
        typer.echo(f"warning: {msg}", err=True)


def _profile_figure(plt, profiles, r):
    """One panel per parameter: the profile (objective rise, in chi2 units) against its value, with
    the 95 % threshold, the estimate and the Wald interval."""
    from scipy import stats

    crit = float(stats.chi2.ppf(0.95, 1))
    n = len(profiles)
    fig, axes = plt.subplots(1, n, figsize=(3.6 * n, 3.2), constrained_layout=True, squeeze=False)
    for ax, (k, pr) in zip(axes[0], profiles.items()):
        finite = pr.delta[pr.delta < float("inf")]
        top = max(float(finite.max()) if finite.size else crit, 1.5 * crit)
        ax.plot(pr.values, pr.delta.clip(max=top), "k.-", label="profile")
        ax.axhline(crit, color="r", lw=0.8, label="chi2(0.95, 1)")
        p = r.parameters[k]
        ax.axvline(p.value, color="0.4", lw=0.8)
        ax.axvspan(p.ci_low, p.ci_high, color="0.85", label="Wald 95 %")
        ax.set_xlabel(k)
        ax.set_ylabel("objective rise (chi2 units)")
        ax.set_ylim(0, top * 1.05)
    axes[0][0].legend(fontsize=7)
    return fig
