"""``rotarydryer fmu``: export the dynamic dryer as an FMI 2.0 co-simulation FMU (pythonfmu)."""

from pathlib import Path
from typing import Optional

import typer

from . import app
from ._common import Progress, check_out_file, parse_sets


@app.command("fmu", short_help="Export the dynamic model as an FMI 2.0 FMU.")
def fmu_cmd(
    case: str = typer.Argument(..., help="Case name (ajayi2011_mmg, ...) or a .toml file with a [gas] block."),
    out: Path = typer.Option(Path("dryer.fmu"), "-o", "--out", help="FMU file to write (.fmu)."),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="Override KEY=VALUE, e.g. operating.test=4."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress lines on stderr."),
):
    """Export the case's dynamic coupled model as an FMI 2.0 co-simulation FMU (pythonfmu):
    inputs feed_rate, feed_moisture, gas_inlet_temperature, rpm, gas_flow, gas_inlet_humidity, feed_temperature,
    fouling; outputs product_moisture,
    product_temperature, exhaust_temperature, exhaust_humidity, holdup; it starts from the case's
    steady state. The FMU runs on a Python environment with rotarydryer installed (this one).

    \b
    Example:
      rotarydryer fmu ajayi2011_mmg --set operating.test=4 -o dryer.fmu
    """
    from ..fmu import build_fmu

    check_out_file("-o", out, suffixes=("fmu",))
    if Path(out).suffix.lower() != ".fmu":
        raise ValueError(f"-o {str(out)!r}: the FMU file name must end in .fmu")
    with Progress("fmu", quiet=quiet) as bar:
        path = build_fmu(case, out, parse_sets(set_), progress=bar.message)
    typer.echo(f"FMU written: {path}")
