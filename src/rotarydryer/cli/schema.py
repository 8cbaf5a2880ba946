"""``rotarydryer schema``, ``rotarydryer cases``, ``rotarydryer new``: case-file tooling."""

from pathlib import Path
from typing import Optional

import typer

from .._io import json_text
from . import app


def case_schema(kind: Optional[str] = None) -> dict:
    """JSON Schema (draft 2020-12, from the pydantic models in `rotarydryer.cases`) of
    all case kinds (discriminated by ``kind``) or of one kind."""
    from typing import Annotated, Union

    from pydantic import Field, TypeAdapter

    from ..cases import CASE_MODELS as kinds
    if kind is not None:
        if kind not in kinds:
            raise ValueError(f"--kind = {kind!r} is not one of {', '.join(map(repr, kinds))}")
        schema = kinds[kind].model_json_schema()
    else:
        schema = TypeAdapter(Annotated[Union[tuple(kinds.values())], Field(discriminator="kind")]).json_schema()
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema.setdefault("title", "rotarydryer case file")
    schema["description"] = ("rotarydryer case file (TOML). Units: SI (m, kg, s, kg/s), angles in deg, "
                             "speed in rev/min; each field's description gives its unit.")
    return schema


@app.command("schema", short_help="Print the JSON Schema of case files.")
def schema(
    kind: Optional[str] = typer.Option(None, help="Only this case kind: dryer | lee2008 | ajayi2011 (default: all)."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="Write to this file instead of stdout."),
):
    """Print the JSON Schema of case files (for editors and validators).

    \b
    Examples:
      rotarydryer schema -o case.schema.json
      rotarydryer schema --kind lee2008 -o lee.schema.json
    """
    try:
        text = json_text(case_schema(kind), indent=1)
    except ValueError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)
    if out is None:
        typer.echo(text)
    else:
        from .._io import write_text_atomic

        try:
            write_text_atomic(out, text + "\n")
        except OSError as exc:
            typer.echo(f"error: --out {exc}", err=True)
            raise typer.Exit(2)
        typer.echo(f"schema: {out}")


@app.command("cases", short_help="List the built-in cases (name, kind, title).")
def cases(as_json: bool = typer.Option(False, "--json", help="Print a JSON list.")):
    """List the built-in cases (name, kind, title).

    \b
    Example:
      rotarydryer cases
    """
    import tomllib
    from importlib import resources

    from ..cases import list_cases

    rows = []
    for name in list_cases():
        raw = tomllib.loads((resources.files("rotarydryer.cases") / f"{name}.toml").read_text())
        rows.append({"name": name, "kind": raw.get("kind", ""), "title": raw.get("meta", {}).get("title", "")})
    if as_json:
        typer.echo(json_text(rows))
        return
    w = max(len(r["name"]) for r in rows)
    for r in rows:
        typer.echo(f"{r['name']:<{w}}  {r['kind']:<10s} {r['title']}")


@app.command("new", short_help="Write an annotated case template.")
def new(
    case_name: str = typer.Argument(..., help="Name of the new case (file CASE_NAME.toml)."),
    base: str = typer.Option("template", "--from", help="'template' (a commented general dryer) or a built-in case (see `rotarydryer cases`)."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="File to write (default ./CASE_NAME.toml)."),
    force: bool = typer.Option(False, help="Overwrite an existing file."),
):
    """Write an annotated case template and check that it loads.

    The template is a copy of a built-in case with its unit comments and citations.

    \b
    Examples:
      rotarydryer new mydryer                       # the commented general template
      rotarydryer new plant2 --from ajayi2011_mmg
      rotarydryer simulate mydryer.toml --set operating.rpm=4

    Exit codes: 0 written, 2 the file exists (use --force), a bad name or base.
    """
    import re
    from importlib import resources

    from ..cases import list_cases, load_case

    stem = case_name[:-5] if case_name.lower().endswith(".toml") else case_name
    if not re.fullmatch(r"[A-Za-z0-9_][A-Za-z0-9_.\-]*", stem) or stem.endswith("."):
        typer.echo(f"error: case_name = {case_name!r} is not a plain file name: it must start with a letter, digit "
                   "or '_', may contain only letters, digits, '_', '-', '.', and must not end with '.' "
                   "(e.g. mydryer; give a folder with --out)", err=True)
        raise typer.Exit(2)
    if base != "template" and base not in list_cases():
        typer.echo(f"error: --from {base!r} is not 'template' nor a built-in case ({', '.join(list_cases())})",
                   err=True)
        raise typer.Exit(2)
    if case_name.lower().endswith(".toml"):     # `rotarydryer new mine.toml` writes mine.toml, not mine.toml.toml
        case_name = case_name[:-5]
    path = out if out is not None else Path(f"{case_name}.toml")
    if out is not None and (path.is_dir() or path.suffix.lower() != ".toml" or path.name.startswith(".")):
        # a folder: the case's name in it; anything else (x3.json, /dev/null): a .toml beside it
        example = (Path(out) / (case_name + ".toml") if path.is_dir()
                   else Path(out).parent / ((Path(out).stem.lstrip(".") or case_name) + ".toml"))
        typer.echo(f"error: --out {str(out)!r} is not a case file name: give a file NAME.toml (e.g. "
                   f"{str(example)!r})", err=True)
        raise typer.Exit(2)
    if path.exists() and not force:
        typer.echo(f"error: {path} exists (use --force to overwrite)", err=True)
        raise typer.Exit(2)
    src = ("templates/dryer.toml" if base == "template" else f"{base}.toml")
    text = (resources.files("rotarydryer.cases") / src).read_text()
    header = (f"# Case {case_name!r}: template written by `rotarydryer new` from the built-in case {base!r}.\n"
              "# Edit the values below (units in the comments; SI, angles in deg, speed in rev/min).\n"
              "# Validate and run:  rotarydryer simulate " + str(path) + "\n"
              "# Every field, its unit and allowed range:  rotarydryer schema\n"
              "# The [meta] citations refer to the base case: replace them with your sources.\n\n")
    m = re.search(r'(?m)^title = "(.*)"$', text)
    title = f"{case_name} (from {base})"
    text = re.sub(r'(?m)^title = ".*"$', f'title = "{title}"', text, count=1)
    if m is not None and "[[calibrations]]" in text:   # the base's calibrations, now of this copy of its dryer
        text = text.replace(f'case = "{m.group(1)}"', f'case = "{title}"')
        header += ("# The [[calibrations]] were fitted to the base case's plant data: once you change the dryer,\n"
                   "# refit them to your own data with `rotarydryer calibrate` (docs/calibration.md).\n\n")
    from .._io import write_text_atomic

    try:
        write_text_atomic(path, header + text)
    except OSError as exc:
        typer.echo(f"error: --out: {exc}", err=True)
        raise typer.Exit(2)
    try:
        load_case(str(path))
    except ValueError as exc:  # pragma: no cover - the packaged cases are valid
        typer.echo(f"error: the template does not validate: {exc}", err=True)
        raise typer.Exit(2)
    typer.echo(f"case template: {path}")
