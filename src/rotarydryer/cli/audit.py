"""``rotarydryer audit``: where the heat goes (heat duties), the exhaust's dew point, the shell
against its limit, and what exhaust recycle, feed preheating or insulation would save."""

import sys
from pathlib import Path
from typing import Optional

import typer

from .._io import json_text
from . import app
from ._common import check_out_dir, parse_sets, written_set


@app.command("audit", short_help="Energy audit: heat duties, dew point, shell, what-if savings.")
def audit_cmd(
    case: str = typer.Argument(..., help="Case name or .toml file (with heat and mass transfer)."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Override KEY=VALUE (several allowed)."),
    recycle: Optional[str] = typer.Option(None, "--recycle", help="Exhaust recycle fractions to try, in [0, 1), "
                                          "e.g. 0.1,0.2 (gas.recycle_fraction)."),
    preheat: Optional[str] = typer.Option(None, "--preheat", help="Feed temperature rises to try, K, e.g. 20 "
                                          "(operating.feed_temperature + K)."),
    insulation: Optional[str] = typer.Option(None, "--insulation", help="Shell insulation thicknesses to try, m, "
                                             "e.g. 0.05,0.1 (shell.insulation_thickness)."),
    hold_moisture: bool = typer.Option(False, "--hold-moisture", help="Also solve each what-if at the base "
                                       "product moisture (the gas inlet temperature found by the target solver)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object (SI, unit-suffixed names)."),
    out: Optional[Path] = typer.Option(None, "--out", help="Directory for audit.json and heat_duties.png "
                                       "(the report takes audit.json: rotarydryer report CASE --audit DIR/audit.json)."),
):
    """Energy audit of a case's coupled steady state: the heat duties in the display unit of power
    (burner release, burner loss, evaporation, solids and water heating, shell loss, exhaust sensible,
    air leaks; they add up to the release; the exhaust's latent heat beside them), the exhaust's dew
    point and its margin, the hottest shell surface and steel per section against
    shell.max_temperature, and what-if savings, each a coupled steady state: exhaust recycle, feed
    preheating, shell insulation (fuel and heat saved, the change of the product moisture; with
    --hold-moisture also at the base product moisture).

    \b
    Examples:
      rotarydryer audit ajayi2011_mmg
      rotarydryer audit ajayi2011_mmg --recycle 0.1,0.2 --preheat 20 --insulation 0.1 --hold-moisture
      rotarydryer audit ajayi2011_mmg --set shell.max_temperature=593 --insulation 0.1 --json
      rotarydryer audit ajayi2011_mmg --recycle 0.2 --out audit_out

    Exit codes: 0 done (a what-if without a steady state is reported, not an error); 1 the base
    steady state failed; 2 bad input.
    """
    from ..studies.energy import energy_audit, parse_values

    try:
        check_out_dir("--out", out)         # before the what-ifs, not after them
        kw = dict(recycle=parse_values(recycle, "--recycle"), preheat=parse_values(preheat, "--preheat"),
                  insulation=parse_values(insulation, "--insulation"))
        if hold_moisture and not any(kw.values()):      # it was silently without effect
            raise ValueError("--hold-moisture applies to the what-ifs: give --recycle, --preheat or --insulation")
        show_progress = not as_json and sys.stderr.isatty()
        res = energy_audit(case, parse_sets(set_), hold_moisture=hold_moisture, **kw,
                           progress=(lambda text: typer.echo(text, err=True)) if show_progress else None)
    except ValueError as exc:
        typer.echo(f"error: {' '.join(str(exc).split())}", err=True)
        solver = getattr(exc, "reason", None) in ("no_steady_state", "diverged", "integration")
        raise typer.Exit(1 if solver else 2)
    data = res.to_dict()
    if out is not None:
        from .._display import unit_of
        from .._io import save_figure, write_text_atomic
        from ..report.plots import plot_heat_duties

        files = [out / "audit.json", out / "heat_duties.png"]
        with written_set(out):                  # all files or none
            write_text_atomic(files[0], json_text(data, indent=1))
            save_figure(plot_heat_duties(data["heat_duties"], unit=unit_of("power")), files[1], dpi=120)
        data["files"] = [str(f) for f in files]
    if as_json:
        typer.echo(json_text(data))
        return
    typer.echo(res.text())
    if out is not None:
        typer.echo(f"files: {', '.join(data['files'])}")
