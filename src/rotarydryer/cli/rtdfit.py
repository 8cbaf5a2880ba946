"""``rotarydryer rtd-moments`` and ``rotarydryer rtd-fit``: measured tracer curves.

DATA is a tracer CSV file (format in `rotarydryer.rtd.tracer_data`) or the
name of a shipped data set (``lee2008_invicta``, ``ajayi2011_test1`` ... ``6``).
"""

import math
from pathlib import Path
from typing import Optional

import typer

from .._io import json_text
from . import app
from ._common import check_option, check_out_dir, load_tracer

_BASELINES = ("none", "leading", "trailing", "linear")
_TAILS = ("none", "exponential", "auto")
#: rotarydryer.rtd.RTD_FIT_MODELS (kept literal: the command modules import light; a test checks it)
_MODELS = ("tanks_in_series", "dispersion_closed", "dispersion_open", "interactive_mixers", "cholette_cloutier")
_CELL_MODELS = ("interactive_mixers", "cholette_cloutier")
_MAX_CELLS = 5000   # rotarydryer.rtd.fitting.MAX_SCAN_CELLS


def _baseline(value: str, allow_fit: bool = False):
    """``--baseline``: a method name or a finite number (signal unit); ``fit`` (rtd-fit only):
    a constant background fitted with the model."""
    v = value.strip().lower()
    if v == "fit":
        if not allow_fit:
            raise ValueError(f"--baseline = {value!r}: a fitted background is an option of rtd-fit (and fit); "
                             f"rtd-moments takes one of {', '.join(_BASELINES)} or a number (signal unit)")
        return v
    if v in _BASELINES:
        return v
    try:
        float(v)
    except ValueError:
        choices = ", ".join(_BASELINES + (("fit",) if allow_fit else ()))
        raise ValueError(f"--baseline = {value!r} is not one of {choices} or a number "
                         "(signal unit)") from None
    return check_option("--baseline", v)


def _named(data: str, func, *args, **kwargs):
    """``func(*args, **kwargs)``; a ValueError gets the data file or data-set name in front."""
    try:
        return func(*args, **kwargs)
    except ValueError as exc:
        text = str(exc)
        if text.startswith(str(data)):
            raise
        raise ValueError(f"{data}: {text}") from None


def _choice(option: str, value: str, choices) -> str:
    if value not in choices:
        raise ValueError(f"{option} = {value!r} is not one of {', '.join(choices)}")
    return value


#: the library's argument names in its messages -> this command's options (the library names its arguments)
_OPTION_WORDS = (("tail_points = ", "--tail-points = "), (": baseline = ", ": --baseline = "),
                 ("give baseline_window_s or a numeric baseline", "give a numeric --baseline (signal unit)"))


def _as_options(message: str) -> str:
    for word, option in _OPTION_WORDS:
        message = message.replace(word, option)
    return message


@app.command("rtd-moments", short_help="Moments of a measured tracer curve.")
def rtd_moments_cmd(
    data: str = typer.Argument(..., help="Tracer CSV file or shipped data-set name."),
    baseline: str = typer.Option("none", help="none | leading | trailing | linear | a number (signal unit)."),
    tail: str = typer.Option("none", help="none (report only) | exponential | auto (extrapolate if truncated)."),
    tail_points: int = typer.Option(5, help="Samples used for the exponential tail fit."),
    time_origin_s: Optional[float] = typer.Option(None, help="Injection start, s (default: file metadata or 0)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
):
    """Moments of a measured tracer curve: mean, SD, skewness, recovery, tail report.

    \b
    Example:
      rotarydryer rtd-moments lee2008_invicta --json
    """
    from ..rtd._datafile import fmt

    try:
        b = _baseline(baseline)
        _choice("--tail", tail, _TAILS)
        check_option("--tail-points", tail_points, 2, 10_000, low_inclusive=True, high_inclusive=True)
        if time_origin_s is not None:
            check_option("--time-origin-s", time_origin_s, unit="s")
        d = load_tracer(data)
        kw = dict(baseline=b, tail=tail, tail_points=tail_points)
        if time_origin_s is not None:
            if time_origin_s >= d.time_s[-1]:
                raise ValueError(
                    f"--time-origin-s = {fmt(time_origin_s)} s is at or after the last sample of {data} "
                    f"({fmt(d.time_s[-1])} s); the tracer injection must start before the data end"
                )
            kw["time_origin_s"] = time_origin_s
        m = _named(data, d.moments, **kw)
    except ValueError as exc:
        typer.echo(f"error: {_as_options(str(exc))}", err=True)
        raise typer.Exit(2) from None
    # the curve's moments are the tracer's, from the injection start; with the file's pulse (its metadata) the RTD's
    # are those less the pulse's (moments of a convolution add): the mean residence time of `rotarydryer rtd`
    pulse = d.pulse()
    tau = m.mean_s - pulse.mean_s
    sd = math.sqrt(max(m.std_s**2 - pulse.variance_s2, 0.0))
    out = m.to_dict()
    out.update(
        data=str(data),
        source=d.metadata.get("source"),
        signal_unit=d.signal_unit,
        tracer_mean_s=m.mean_s,
        tracer_std_s=m.std_s,
        pulse_kind=str(d.metadata.get("pulse_kind", "dirac")),
        pulse_duration_s=(0.0 if str(d.metadata.get("pulse_kind", "dirac")) == "dirac"
                          else float(d.metadata.get("pulse_duration_s", 0.0))),
        mean_residence_time_s=tau,
        rtd_std_s=sd,
    )
    if pulse.mean_s > 0 and as_json:    # the key's meaning changed (2026-12-06): said to the scripts that read it
        typer.echo(f"warning: mean_residence_time_s and rtd_std_s are the RTD's, the {out['pulse_kind']} pulse's "
                   f"moments taken off ({pulse.mean_s:g} s off the mean); the curve's own mean from the injection "
                   "start, which mean_residence_time_s was before, is tracer_mean_s (and mean_s)", err=True)
    if as_json:
        typer.echo(json_text(out))
        return
    typer.echo(f"{data}: {m.n_points} points, t = {m.first_time_s:g} .. {m.last_time_s:g} s after injection")
    if pulse.mean_s > 0 or pulse.variance_s2 > 0:
        typer.echo(f"  tracer curve mean    {m.mean_s:10.1f} s  = {m.mean_min:8.3f} min (from the injection start)")
        typer.echo(f"  standard deviation   {m.std_s:10.1f} s  = {m.std_min:8.3f} min")
        typer.echo(f"  mean residence time  {tau:10.1f} s  = {tau / 60:8.3f} min, SD {sd / 60:.3f} min (the "
                   f"{out['pulse_kind']} pulse of {out['pulse_duration_s']:g} s taken off)")
    else:
        typer.echo(f"  mean residence time  {m.mean_s:10.1f} s  = {m.mean_min:8.3f} min")
        typer.echo(f"  standard deviation   {m.std_s:10.1f} s  = {m.std_min:8.3f} min")
    typer.echo(f"  skewness (m3/sd^3)   {m.skewness:10.3f}")
    typer.echo(f"  area                 {m.area:10.4g} ({d.signal_unit or 'signal'} x s)")
    if m.recovery is not None:
        typer.echo(f"  recovery             {m.recovery:10.3f}")
    typer.echo(f"  baseline             {m.baseline:10.4g} ({m.baseline_method})")
    typer.echo(
        f"  tail: last/peak = {m.tail_end_fraction_of_peak:.4f}, truncated = {m.tail_truncated}, "
        f"extrapolated = {m.tail_extrapolated} ({100 * m.extrapolated_area_fraction:.2f} % of area)"
    )


@app.command("rtd-fit", short_help="Fit a reference RTD model to a tracer curve.")
def rtd_fit_cmd(
    data: str = typer.Argument(..., help="Tracer CSV file or shipped data-set name."),
    model: str = typer.Option("tanks_in_series", help="tanks_in_series | dispersion_closed | dispersion_open | "
                              "interactive_mixers | cholette_cloutier (Song (2003) Eq. 2.10-2.16)."),
    delay: bool = typer.Option(False, "--delay", help="Fit a dead time (s)."),
    scale: Optional[bool] = typer.Option(
        None, "--scale/--no-scale", help="Fit an unknown scale (default: only for non-normalised signals)."
    ),
    pulse_s: Optional[float] = typer.Option(
        None, help="Rectangular input duration, s (default: file metadata; 0 = Dirac)."
    ),
    baseline: str = typer.Option("none", help="Subtract a baseline first: none | leading | trailing | a number; "
                                 "or 'fit': fit a constant background (signal unit) with the model."),
    n_cells: Optional[int] = typer.Option(None, help="Cell models: number of cells N (integer; default: scanned)."),
    n_starts: int = typer.Option(1, help="Number of starts (the best is kept)."),
    out: Optional[Path] = typer.Option(None, help="Directory for rtd_fit.png (data, model, residuals)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
):
    """Fit a reference RTD model by least squares, with 95 % intervals: tanks in series, axial
    dispersion, or Song's (2003) Eq. 2.10-2.16 cells (interactive mixers; with dead zones,
    cholette_cloutier); optionally with a fitted constant background (--baseline fit).

    \b
    Examples:
      rotarydryer rtd-fit lee2008_invicta --model dispersion_open --delay --json
      rotarydryer rtd-fit ajayi2011_test4 --model interactive_mixers --baseline fit
    """
    import numpy as np

    from ..rtd import TracerData, fit_tracer_data, pulse_input, subtract_baseline
    from ..rtd._datafile import fmt

    try:
        _choice("--model", model, _MODELS)
        b = _baseline(baseline, allow_fit=True)
        if n_cells is not None:
            if model not in _CELL_MODELS:
                raise ValueError(f"--n-cells = {n_cells} applies only to --model {' or '.join(_CELL_MODELS)} "
                                 f"(got --model {model})")
            check_option("--n-cells", n_cells, 1, _MAX_CELLS, low_inclusive=True, high_inclusive=True)
        check_option("--n-starts", n_starts, 1, 1000, low_inclusive=True, high_inclusive=True)
        if pulse_s is not None:
            check_option("--pulse-s", pulse_s, 0.0, low_inclusive=True, unit="s")
        check_out_dir("--out", out)
        d = load_tracer(data)
        if pulse_s is not None and pulse_s >= d.time_s[-1] - d.time_origin_s:
            raise ValueError(
                f"--pulse-s = {fmt(pulse_s)} s is not shorter than the record of {data} "
                f"({fmt(d.time_s[-1] - d.time_origin_s)} s after the injection start)"
            )
        if b not in ("none", "fit"):
            y, _ = _named(data, subtract_baseline, d.time_s, d.signal, b)
            d = TracerData(d.time_s, y, d.metadata, d.time_column, d.extra_columns, d.path)
        kw = dict(model=model, fit_delay=delay, n_starts=n_starts, fit_baseline=b == "fit", n_cells=n_cells)
        if scale is not None:
            kw["fit_scale"] = scale
        if pulse_s is not None:
            kw["pulse"] = pulse_input("dirac") if pulse_s == 0 else pulse_input("rectangular", pulse_s)
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            f = _named(data, fit_tracer_data, d, **kw)
    except ValueError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2) from None
    res = f.to_dict()
    res["data"] = str(data)
    if out is not None:
        from .._io import save_figure
        from .._plotting import pyplot

        plt = pyplot()

        t0 = d.time_origin_s
        tt = np.linspace(d.time_s[0], d.time_s[-1], 2000)
        ydata = (d.rate_factor or 1.0) * d.signal
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
        a1.plot((d.time_s - t0) / 60, ydata, "o", label="data")
        a1.plot((tt - t0) / 60, f.predict(tt), "-", label=f"{model} fit")
        a1.set_ylabel("signal (1/s)" if "scale" in f.fixed else "signal")
        a1.legend()
        a2.plot((d.time_s - t0) / 60, -f.residuals, "o")
        a2.axhline(0, color="k", lw=0.5)
        a2.set_xlabel("time since injection (min)")
        a2.set_ylabel("data - model")
        fig.tight_layout()
        save_figure(fig, out / "rtd_fit.png", dpi=120)  # atomic; closes the figure
        res["plot"] = str(out / "rtd_fit.png")
    if as_json:
        typer.echo(json_text(res))
        return
    typer.echo(f"{model} fit to {data}: {f.n_points} points, {f.n_evaluations} model evaluations")
    if "n_cells" in f.fixed:
        how = ("given (--n-cells)" if n_cells is not None
               else f"integer scan, {len(f.n_cells_scan)} values of N fitted")
        typer.echo(f"  number of cells N = {f.fixed['n_cells']} ({how})")
    typer.echo(f"  objective (SSR) {f.objective:.6g}   R^2 {f.r_squared:.5f}")
    typer.echo(f"  {'parameter':24s} {'value':>12s} {'std error':>12s} {'95 % CI':>28s}")
    for k in f.parameter_names:
        typer.echo(
            f"  {k:24s} {f.values[k]:12.5g} {f.std_errors[k]:12.3g}   [{f.ci_low[k]:11.5g}, {f.ci_high[k]:11.5g}]"
        )
    typer.echo("  correlation matrix:")
    for k, row in zip(f.parameter_names, np.asarray(f.correlation), strict=True):
        typer.echo(f"  {k:24s} " + " ".join(f"{x:7.3f}" for x in row))
    om = f.outlet_moments
    typer.echo(f"  fitted outlet curve: mean {om.mean_s / 60:.3f} min, SD {om.std_s / 60:.3f} min")
    for w in f.warnings:
        typer.echo(f"  warning: {w}")
