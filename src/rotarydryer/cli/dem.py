"""``rotarydryer dem export|run|holdup``: LIGGGHTS slices of a flighted drum and their flight holdup."""

from pathlib import Path
from typing import Optional

import typer

from . import app

dem_app = typer.Typer(short_help="DEM (LIGGGHTS 3.8) slices of a flighted drum.",
                      help="DEM (LIGGGHTS 3.8) slices of a flighted drum: export a deck, run it, read the "
                           "flight holdup from its dumps and compare it with the geometric model.",
                      no_args_is_help=True)
app.add_typer(dem_app, name="dem")


def _case_drum(case_name: str, section: Optional[str]):
    """(drum, rpm, particle diameter or None, description) of a case (and section)."""
    from ..cases import load_case
    from ..cases.build import exact_drum, material_of, operating_point, section_flight

    case = load_case(case_name)
    _, rpm, _, _ = operating_point(case)
    secs = [s for s in (getattr(case, "sections", None) or []) if s.kind == "flighted"]
    d_p = None
    if secs:
        names = [s.name for s in secs]
        if section is None and len(names) == 1:     # the one flighted section (it was asked for; found by a check)
            section = names[0]
        if section is None:
            raise ValueError(f"--section is needed for case {case_name!r}: one of its flighted sections "
                             f"{', '.join(names)}")
        sec = next((s for s in secs if s.name == section), None)
        if sec is None:
            raise ValueError(f"--section = {section!r} is not a flighted section of case {case_name!r}; "
                             f"choose one of {', '.join(names)}")
        nf = sec.n_flights or getattr(case.drum, "n_flights", None)
        where = f"sections[{case.sections.index(sec)}] ({sec.name})"
        g, fwhere = section_flight(case, sec, where)
        drum = exact_drum(case.drum.radius, nf, **g, where=fwhere, n_flights_key=f"{where}.n_flights")
        d_p = sec.particle_diameter
        desc = f"case {case_name}, section {sec.name}"
    else:
        if section is not None:
            raise ValueError(f"--section = {section!r}: case {case_name!r} has no sections")
        f = case.flight
        drum = exact_drum(case.drum.radius, case.drum.n_flights, f.s1, f.s2, f.alpha1, f.alpha2)
        desc = f"case {case_name}"
    if d_p is None:
        try:
            d_p = getattr(material_of(case), "particle_diameter", None)
        except ValueError:
            d_p = None
    return drum, float(rpm), d_p, desc


@dem_app.command("export", short_help="Write a LIGGGHTS deck for a thin slice of a drum.")
def export(
    out: Path = typer.Argument(..., help="Folder for the deck (in.drum, shell.stl, flights.stl, deck.json)."),
    case: Optional[str] = typer.Option(None, help="Take drum, flights and speed from this case (name or .toml)."),
    section: Optional[str] = typer.Option(None, help="Flighted section of the case (sectioned cases; default: its one flighted section, if it has one)."),
    radius: Optional[float] = typer.Option(None, help="Drum radius, m (without --case)."),
    n_flights: Optional[int] = typer.Option(None, help="Number of flights (without --case)."),
    s1: Optional[float] = typer.Option(None, help="Flight base, m."),
    s2: Optional[float] = typer.Option(None, help="Flight tip, m."),
    alpha1: float = typer.Option(90.0, help="Base-to-wall angle, deg."),
    alpha2: float = typer.Option(120.0, help="Base-to-tip angle, deg."),
    profile: Optional[Path] = typer.Option(None, help="Flight-profile file (TOML) of a flight of any shape (segments or "
                                           "vertices; radius and n_flights from it or --radius --n-flights), instead "
                                           "of --s1 --s2 --alpha1 --alpha2."),
    rpm: Optional[float] = typer.Option(None, help="Drum speed, rev/min (default the case's)."),
    scale: float = typer.Option(1.0, help="Scale the case's drum and flights by this factor (the speed keeps the "
                                            "Froude number: rpm / sqrt(scale))."),
    diameter: Optional[float] = typer.Option(None, help="Particle diameter, m (default the case's, else 0.01)."),
    density: float = typer.Option(2500.0, help="Particle (solid) density, kg/m^3."),
    friction: float = typer.Option(0.5, help="Sliding friction coefficient."),
    rolling_friction: float = typer.Option(0.1, help="Rolling friction coefficient (cdt model)."),
    restitution: float = typer.Option(0.5, help="Coefficient of restitution."),
    youngs_modulus: float = typer.Option(5.0e6, help="Young's modulus, Pa (soft particles: a few MPa)."),
    poisson_ratio: float = typer.Option(0.3, help="Poisson ratio."),
    wall_friction: Optional[float] = typer.Option(None, help="Wall sliding friction (default --friction)."),
    wall_rolling_friction: Optional[float] = typer.Option(None, help="Wall rolling friction, 0-1 (cdt model; default "
                                                                     "--rolling-friction)."),
    loading: Optional[float] = typer.Option(None, help="Dryer loading: particles for this multiple of the design load."),
    fill: Optional[float] = typer.Option(None, help="Bulk fill fraction of the drum cross-section (instead of --loading)."),
    layers: float = typer.Option(4.0, help="Slice thickness in particle diameters (periodic)."),
    settle_time: float = typer.Option(0.6, help="Settling time before rotation, s."),
    spinup: float = typer.Option(1.0, help="Revolutions turned before recording (>= 1: every flight refilled by "
                                                "the turning bed)."),
    revolutions: float = typer.Option(0.5, help="Revolutions recorded."),
    dump_every: float = typer.Option(1.0, help="Dump interval, deg of drum rotation."),
    timestep_fraction: float = typer.Option(0.2, help="Time step as a fraction of the Rayleigh time."),
    seed: int = typer.Option(0, help="Random seed (made a prime > 10000 for LIGGGHTS)."),
    as_json: bool = typer.Option(False, "--json", help="Print the deck description as JSON."),
):
    """Write a runnable LIGGGHTS 3.8 deck for a thin periodic slice of a flighted drum.

    \b
    Examples:
      rotarydryer dem export slice/ --radius 0.2 --n-flights 10 --s1 0.05 --s2 0.05 --rpm 6.7 --diameter 0.01 --loading 1
      rotarydryer dem run slice/
      rotarydryer dem holdup slice/ --plot holdup.png
    """
    import math

    from .._io import json_text
    from .._validation import check_range, fmt_number
    from ..dem.deck import Particles, build_slice, export_deck
    from ..geometry import FlightedDrum, PolygonFlight, TwoSectionFlight
    from ..geometry.presets import read_profile

    check_range("--scale (scale)", scale, 0.0, 100.0)
    for key, v in (("--layers (layers)", layers), ("--settle-time (settle_time)", settle_time),
                   ("--spinup (spinup)", spinup), ("--revolutions (revolutions)", revolutions),
                   ("--dump-every (dump_every)", dump_every)):
        lo, hi = {"--spinup (spinup)": (0.0, 20.0), "--revolutions (revolutions)": (0.0, 20.0),
                  "--dump-every (dump_every)": (0.0, 360.0), "--settle-time (settle_time)": (0.0, 100.0),
                  "--layers (layers)": (1.0, 100.0)}[key]
        check_range(key, v, lo, hi, low_inclusive=key.startswith("--spinup") or key.startswith("--layers"),
                    high_inclusive=True)
    check_range("--timestep-fraction (timestep_fraction)", timestep_fraction, 0.0, 0.5, high_inclusive=True)
    dims = dict(radius=radius, n_flights=n_flights, s1=s1, s2=s2)
    if case is None:        # a case's options without a case were ignored (found by fuzzing)
        for opt, given in (("--section", section is not None), ("--scale", scale != 1.0)):
            if given:
                raise ValueError(f"{opt} applies to --case: give --case, or the drum and flights themselves")
    if profile is not None:
        if case is not None or s1 is not None or s2 is not None:
            raise ValueError("--profile gives the flight: not with --case or --s1 --s2")
        prof = read_profile(profile)
        R_ = radius if radius is not None else prof.get("radius")
        N_ = n_flights if n_flights is not None else prof.get("n_flights")
        if R_ is None or N_ is None:
            raise ValueError(f"{profile}: radius and n_flights are not in the profile: give --radius and --n-flights")
        check_range("--radius (radius)", R_, 0.0, 20.0, unit="m")
        if N_ < 2 or N_ > 400:
            raise ValueError(f"--n-flights (n_flights) = {N_} is outside the allowed range: an integer from 2 to 400")
        try:
            drum = FlightedDrum(R_, N_, prof["flight"])
        except ValueError as exc:       # named as `rotarydryer flight --profile` names it
            raise ValueError(f"{profile} (radius = {fmt_number(R_)} m, n_flights = {N_}): {exc}") from None
        rpm_ = rpm if rpm is not None else prof.get("rpm")
        if rpm_ is None:
            raise ValueError("--rpm is needed (rev/min): the profile gives no rpm")
        d = 0.01 if diameter is None else diameter
        desc = f"profile {profile}"
    elif case is not None:
        if any(v is not None for v in dims.values()):
            raise ValueError("give either --case (and --section) or the dimensions --radius --n-flights --s1 --s2, not both")
        drum, rpm_case, d_case, desc = _case_drum(case, section)
        if scale != 1.0:
            f = drum.flight
            scaled = (TwoSectionFlight(f.s1 * scale, f.s2 * scale, f.alpha1, f.alpha2) if isinstance(f, TwoSectionFlight)
                      else PolygonFlight([(a * scale, b) for a, b in f.segments]))
            drum = FlightedDrum(drum.radius * scale, drum.n_flights, scaled)
            rpm_case = rpm_case / math.sqrt(scale)
            desc += f", scaled x{scale:g}"
        rpm_ = rpm if rpm is not None else rpm_case
        d = diameter if diameter is not None else (d_case if d_case is not None else 0.01)
    else:
        missing = [f"--{k.replace('_', '-')}" for k, v in dims.items() if v is None]
        if missing:
            raise ValueError(f"give --case or the drum dimensions; missing {', '.join(missing)}")
        check_range("--radius (radius)", radius, 0.0, 20.0, unit="m")
        check_range("--s1 (s1)", s1, 0.0, 20.0, unit="m")
        check_range("--s2 (s2)", s2, 0.0, 20.0, low_inclusive=True, unit="m")
        check_range("--alpha1 (alpha1)", alpha1, 0.0, 180.0, unit="deg")
        check_range("--alpha2 (alpha2)", alpha2, 0.0, 180.0, high_inclusive=True, unit="deg")    # 180: straight on
        if n_flights < 2 or n_flights > 400:
            raise ValueError(f"--n-flights (n_flights) = {n_flights} is outside the allowed range: an integer from 2 to 400")
        drum = FlightedDrum(radius, n_flights, TwoSectionFlight(s1, s2, alpha1, alpha2))
        if rpm is None:
            raise ValueError("--rpm is needed with explicit dimensions (rev/min)")
        rpm_ = rpm
        d = 0.01 if diameter is None else diameter
        desc = "cli dimensions"
    check_range("--rpm (rpm)", rpm_, 0.0, 1000.0, unit="rev/min")
    p = Particles(diameter=d, density=density, friction=friction, rolling_friction=rolling_friction,
                  restitution=restitution, youngs_modulus=youngs_modulus, poisson_ratio=poisson_ratio,
                  wall_friction=wall_friction, wall_rolling_friction=wall_rolling_friction)
    if loading is None and fill is None:
        loading = 1.0
    s = build_slice(drum, p, rpm=rpm_, loading=loading, fill_fraction=fill, n_layers=layers,
                    settle_time=settle_time, spinup_revolutions=spinup, record_revolutions=revolutions,
                    dump_every_deg=dump_every, timestep_fraction=timestep_fraction, seed=seed, source=desc)
    files = export_deck(s, out)
    if as_json:
        typer.echo(json_text(s.to_dict(), indent=1))
        return
    st = s.steps()
    typer.echo(f"deck written to {files.folder}/ (in.drum, shell.stl, flights.stl, deck.json): {s.n_particles} "
               f"particles of {d:g} m (d/s1 = {d / drum.flight.s1:.3g}), R = {drum.radius:g} m, {drum.n_flights} flights, "
               f"{rpm_:.4g} rev/min (Froude {s.froude:.3g}), {st['total']} steps of {s.timestep:.3g} s, "
               f"{st['record'] // st['dump_every']} frames")
    typer.echo(f"run it: rotarydryer dem run {files.folder} --np 2")


@dem_app.command("run", short_help="Run a deck with LIGGGHTS.")
def run(
    folder: Path = typer.Argument(..., help="Deck folder written by rotarydryer dem export."),
    np_: int = typer.Option(1, "--np", help="MPI ranks (mpirun -np N); 1 runs plain liggghts."),
    quiet: bool = typer.Option(False, "--quiet", help="No progress lines."),
    timeout: Optional[float] = typer.Option(None, help="Stop after this many seconds."),
):
    """Run a deck with LIGGGHTS (progress on stderr); dumps go to FOLDER/post/.

    \b
    Example:
      rotarydryer dem run slice/ --np 4
    """
    from ..dem.run import run_deck

    if timeout is not None:
        from .._validation import check_range

        check_range("--timeout (timeout)", timeout, 0.0, 1e7, unit="s")
    from ..services._options import usable_cpus

    cpus = usable_cpus()
    if not isinstance(np_, bool) and isinstance(np_, int) and cpus < np_ <= 256:
        typer.echo(f"warning: --np = {np_} is more than the {cpus} usable CPU cores; using {cpus}", err=True)
        np_ = cpus
    info = run_deck(folder, np=np_, progress=not quiet, timeout=timeout)
    typer.echo(f"LIGGGHTS finished in {info['seconds']:.1f} s; dumps in {Path(folder) / 'post'}/; "
               f"next: rotarydryer dem holdup {folder}")


@dem_app.command("holdup", short_help="Flight holdup from DEM dumps vs the geometric model.")
def holdup(
    folder: Path = typer.Argument(..., help="Run folder (deck.json and post/particles.dump)."),
    csv: Optional[Path] = typer.Option(None, help="Write the reduced profile (CSV with the deck in its header)."),
    plot: Optional[Path] = typer.Option(None, help="Plot DEM and geometric model (PNG)."),
    surface_layer: Optional[float] = typer.Option(None, help="Surface layer k of the correction (default the calibrated one)."),
    every: int = typer.Option(1, help="Use every N-th dump frame."),
    repose_angle: Optional[float] = typer.Option(None, help="Compare at this repose angle, deg (default the measured one)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
):
    """Flight holdup versus flight angle from the dumps, packing fraction, dynamic repose angle,
    airborne fraction; RMS and bias of the geometric model (plain and corrected) in % of a full flight.

    \b
    Example:
      rotarydryer dem holdup slice/ --csv holdup.csv --plot holdup.png
    """
    from .._io import json_text, output_set
    from .._validation import check_range
    from ..dem.holdup import analyse_run, compare, plot_comparison, write_reduced_csv

    if every < 1 or every > 10000:
        raise ValueError(f"--every (every) = {every} is outside the allowed range: an integer from 1 to 10000")
    if surface_layer is not None:
        check_range("--surface-layer (surface_layer)", surface_layer, 0.0, 20.0, low_inclusive=True, high_inclusive=True)
    if repose_angle is not None:
        check_range("--repose-angle (repose_angle)", repose_angle, 0.0, 90.0, unit="deg")
    res = analyse_run(folder, every=every)
    c = compare(res, surface_layer=surface_layer, repose_angle=repose_angle)
    with output_set():                  # --csv and --plot: both or neither
        if csv is not None:
            write_reduced_csv(res, csv)
        if plot is not None:
            plot_comparison(res, plot, surface_layer=surface_layer, repose_angle=repose_angle)
    out = {"n_particles": res.n_particles, "n_frames": res.n_frames, "packing_fraction": res.packing_fraction,
           "repose_angle_deg": res.repose_angle_deg, "repose_angle_iqr_deg": res.repose_angle_iqr_deg,
           "repose_angle_samples": res.extra.get("repose_angle_samples", 0),
           "airborne_fraction": res.airborne_fraction, "full_holdup_area_m2": res.full_area,
           "liggghts_version": res.liggghts_version, "comparison": c,
           "samples": {"frame": res.frame, "flight": res.flight, "psi_deg": res.psi_deg,
                       "holdup_area_m2": res.holdup_area_m2, "holdup_fraction": res.holdup_area_m2 / res.full_area}}
    if as_json:
        typer.echo(json_text(out))
        return
    typer.echo(f"{res.n_particles} particles, {res.n_frames} frames (LIGGGHTS {res.liggghts_version})")
    typer.echo(f"packing fraction of the bulk  {res.packing_fraction:.3f}")
    n_rep = res.extra.get("repose_angle_samples", 0)
    typer.echo(f"dynamic repose angle          {res.repose_angle_deg:.1f} deg (IQR {res.repose_angle_iqr_deg:.1f}, "
               f"{n_rep} flight surfaces)" + ("" if repose_angle is None else f"; compared at {repose_angle:g} deg"))
    if n_rep < 40 and repose_angle is None:
        typer.echo("warning: fewer than 40 flight surfaces: the measured repose angle is uncertain (pockets only a "
                   "few particles wide); give --repose-angle from a larger slice of the same particles", err=True)
    typer.echo(f"airborne fraction             {100 * res.airborne_fraction:.1f} %")
    if c["dem"]["n_flights_tracked"] == 0:
        typer.echo("warning: no flight filled by the turning bed was recorded (each flight must go down the empty "
                   "side and through the bottom after the drum starts turning): export with --spinup 1", err=True)
    typer.echo(f"flights compared              {c['dem']['n_flights_tracked']} (up to a root angle of "
               f"{c['last_angle_deg']:.0f} deg); DEM unloading starts {c['dem']['start_deg']:.0f}, "
               f"ends {c['dem']['end_deg']:.0f} deg")
    for name in ("plain", "corrected"):
        m = c[name]
        typer.echo(f"{name:9s} model: RMS {m['rms_pct']:.1f} %, bias {m['bias_pct']:+.1f} % of a full flight; "
                   f"start {m['start_deg']:.0f}, end {m['end_deg']:.0f} deg")
