"""``rotarydryer fit``: estimate case parameters from a measured tracer curve."""

from __future__ import annotations

import json
from pathlib import Path
from typing import List, Optional

import typer

from . import app
from ._common import load_tracer, parse_sets


@app.command("fit")
def fit_command(
    case: str = typer.Argument(..., help="Built-in case name or a case .toml file."),
    data: str = typer.Argument(..., help="Tracer CSV (time_s|time_min|time_h, signal) or a built-in data set name."),
    param: List[str] = typer.Option(..., "--param", "-p", help="Override key to estimate (repeat)."),
    set_: Optional[List[str]] = typer.Option(None, "--set", help="Fixed override KEY=VALUE (repeat)."),
    starts: int = typer.Option(2, help="Number of starts (the case values plus sampled ones)."),
    scale: str = typer.Option("known", help="'known': the signal is E(t); 'fit': raw concentration, unknown scale."),
    method: str = typer.Option("wls", help="wls | ml"),
    out: Optional[Path] = typer.Option(None, help="Directory for fit.png and fit.json."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
):
    """Fit case parameters to a tracer curve, with 95 % confidence intervals.

    Example: rotarydryer fit lee2008_invicta lee2008_invicta -p transport.kiln_time
    -p transport.backmix -p transport.drag_reduction --set transport.n_cells=35
    --set geometry.method=lee2008_regressions
    """
    import warnings

    from ..estimation import FitError
    from ..estimation.cases import fit_case_to_tracer

    try:
        base = parse_sets(set_)
        tracer = load_tracer(data)

        def progress(k, n, best):
            typer.echo(f"start {k}/{n} done, best objective {best:.6g}", err=True)

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            cf = fit_case_to_tracer(case, tracer, param, base_overrides=base, n_starts=starts, scale=scale,
                                    method=method, progress=progress)
    except (ValueError, FitError) as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)
    r = cf.fit
    result = {
        "case": case,
        "data": data,
        "parameters": {k: {"value": p.value, "std_error": p.std_error, "ci_low": p.ci_low, "ci_high": p.ci_high}
                       for k, p in r.parameters.items()},
        "objective": r.objective,
        "r_squared": r.r_squared,
        "n_evaluations": r.n_evaluations,
        "seconds": r.seconds,
        "correlation": r.correlation.tolist(),
        "starts": [{"start": s.start, "objective": s.objective, "success": s.success} for s in r.starts],
        "warnings": r.warnings,
    }
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

        try:
            save_figure(fig, out / "fit.png", dpi=110)
            write_text_atomic(out / "fit.json", json_text(result, indent=2))
        except OSError as exc:
            typer.echo(f"error: --out {str(out)!r}: {exc}", err=True)
            raise typer.Exit(2)
        result["plots"] = [str(out / "fit.png")]
    if as_json:
        from .._io import json_text

        typer.echo(json_text(result))
        return
    typer.echo(f"fit of {case} to {data}: objective {r.objective:.6g}, R^2 {r.r_squared:.4f}, "
               f"{r.n_evaluations} model evaluations, {r.seconds:.1f} s")
    w = max(len(k) for k in r.parameters)
    typer.echo(f"  {'parameter':<{w}}  {'estimate':>12}  {'95% CI':>27}")
    for k, p in r.parameters.items():
        typer.echo(f"  {k:<{w}}  {p.value:12.6g}  [{p.ci_low:12.6g}, {p.ci_high:12.6g}]")
    typer.echo("correlation matrix:")
    for k, row in zip(r.names, r.correlation):
        typer.echo(f"  {k:<{w}}  " + " ".join(f"{x:+.3f}" for x in row))
    for msg in r.warnings:
        typer.echo(f"warning: {msg}")
