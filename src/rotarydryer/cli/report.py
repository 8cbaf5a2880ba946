"""``rotarydryer report``: one self-contained HTML report of a result, a case or a drum."""

import time
from pathlib import Path
from typing import Optional

import typer

from . import app
from ._common import check_out_file, parse_sets


@app.command("report", short_help="Write a self-contained HTML report.")
def report(
    source: str = typer.Argument(..., help="Saved results (.nc), case name (lee2008_invicta, ajayi2011_mmg), "
                                           "case .toml file, or drum preset (invicta, mmg_B, ...)."),
    out: Path = typer.Option(Path("report.html"), "--out", "-o", help="HTML file to write."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Case override KEY=VALUE, e.g. operating.rpm=4."),
    repose_angle: Optional[float] = typer.Option(None, help="Repose angle for the flight pictures, deg "
                                                           "(default: the case's mean per section; 45 for a drum)."),
    save: Optional[Path] = typer.Option(None, help="Also save the results (netCDF, .nc) when SOURCE is a case."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object (path, size, seconds)."),
    sensitivity: Optional[Path] = typer.Option(None, "--sensitivity", help="Include a saved sensitivity study "
                                               "(DIR/sensitivity.json of rotarydryer sensitivity)."),
    audit: Optional[Path] = typer.Option(None, "--audit", help="Include the what-if savings of a saved energy "
                                         "audit (DIR/audit.json of rotarydryer audit --out DIR)."),
):
    """Write a self-contained HTML report (pictures embedded).

    Contents: the dryer (one drawing), flight cross-section and unloading profile, design loads
    and, for cases and results, key results, holdup profile, RTD against data with classical
    model fits, loading state per section and, with heat and mass transfer, the energy audit (heat
    duties in the display unit of power, the exhaust's dew-point margin, the shell against its limit;
    with --audit DIR/audit.json of ``rotarydryer audit --out DIR``, the what-if savings).

    \b
    Examples:
      rotarydryer report lee2008_invicta --out invicta.html
      rotarydryer report ajayi2011_mmg --set operating.test=4 --save test4.nc
      rotarydryer report test4.nc -o test4.html
      rotarydryer report invicta --repose-angle 50

    Exit codes: 0 done, 1 a steady state that did not converge or an internal error, 2 bad input (message on
    stderr).
    """
    from .._io import json_text, output_set
    from ..report.html import (
        case_validation,
        check_saved_audit,
        check_saved_sensitivity,
        load_audit,
        load_sensitivity,
        render_report,
        resolve_source,
        write_html,
    )

    t0 = time.perf_counter()
    try:
        import sys

        check_out_file("--out", out, ("html", "htm"))        # a report is HTML; --save writes netCDF
        if repose_angle is not None:
            from .._validation import check_range

            check_range("--repose-angle", repose_angle, 0.0, 90.0, unit="deg")
        check_out_file("--save", save, ("nc",))
        sens = load_sensitivity(sensitivity) if sensitivity is not None else None
        saved_audit = load_audit(audit) if audit is not None else None
        with typer.progressbar(length=2, label="report", file=sys.stderr,
                               hidden=as_json or not sys.stderr.isatty()) as bar:
            sets = parse_sets(set_)
            results, drums, title = resolve_source(source, sets, repose_angle=repose_angle)
            if saved_audit is not None:
                check_saved_audit(saved_audit, results, audit)
            if sens is not None:
                check_saved_sensitivity(sens, source, sets, sensitivity)
            bar.update(1)
            if save is not None and results is None:
                raise ValueError(f"--save needs a case or results source, got the drum {source!r}")
            html_text = render_report(results, drums=drums, title=title, sensitivity=sens,
                                      validation=case_validation(source, results), audit=saved_audit)
            bar.update(1)
        with output_set():                  # the report and --save: both or neither
            if save is not None:
                results.save(save)
            write_html(html_text, out)
    except Exception as exc:
        from . import DEBUG

        if DEBUG["on"]:  # --debug: the traceback, for developers
            raise
        if isinstance(exc, ValueError):     # a solve that did not converge is the solver's (1), as simulate's
            typer.echo(f"error: {exc}", err=True)
            raise typer.Exit(1 if getattr(exc, "reason", None) in ("no_steady_state", "diverged", "integration")
                             else 2)
        if isinstance(exc, OSError):  # e.g. --out in a missing or read-only directory: bad input
            typer.echo(f"error: {exc}" if "cannot write" in str(exc) else f"error: cannot write {out}: {exc}",
                       err=True)
            raise typer.Exit(2)
        # a bug, not bad input: say so without a traceback
        typer.echo(f"error: internal error ({type(exc).__name__}): {exc}; please report it "
                   "(rerun with --debug for the traceback)", err=True)
        raise typer.Exit(1)
    dt = time.perf_counter() - t0
    info = {"report": str(out), "bytes": out.stat().st_size, "seconds": round(dt, 3), "source": source}
    if save is not None:
        info["results"] = str(save)
    if as_json:
        typer.echo(json_text(info))
    else:
        typer.echo(f"report: {out} ({info['bytes'] / 1e3:,.0f} kB, {dt:.1f} s)"
                   + (f"; results: {save}" if save is not None else ""))
