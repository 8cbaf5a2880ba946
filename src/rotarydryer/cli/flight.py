"""``rotarydryer flight``: unloading summary and pictures for one drum and flight."""

import math
from pathlib import Path
from typing import Optional

import typer

from .._io import json_text
from .._limits import MAX_FLIGHTS
from . import app
from ._common import written_set

#: bulk densities a granular solid can have, kg/m^3 (as rotarydryer.cases.build.BULK_DENSITY_RANGE)
_BULK_DENSITY_RANGE = (1.0, 23000.0)


def _opt(param: str) -> str:
    """How messages name an option: ``--repose-angle (repose_angle)``, the option and the parameter
    it sets (the name of the library argument and, with a unit suffix, of the --json field)."""
    return f"--{param.replace('_', '-')} ({param})"


def _check_options(dims, *, repose_angle, rpm, slope, loading_factor, bulk_density, length, angle):
    """Every number option finite and in its range; the message names the option, its value,
    the allowed range and the unit."""
    from .._validation import check_range
    from ..geometry.presets import MAX_RADIUS, MIN_RADIUS

    inf = float("inf")
    ranges = dict(radius=(MIN_RADIUS, MAX_RADIUS, True, True, "m"), s1=(0.0, inf, False, False, "m"),
                  s2=(0.0, inf, True, False, "m"), alpha1=(0.0, 180.0, False, False, "deg"),
                  alpha2=(0.0, 180.0, False, True, "deg"))
    for key, (lo, hi, li, hi_in, unit) in ranges.items():
        if dims[key] is not None:
            check_range(_opt(key), dims[key], lo, hi, low_inclusive=li, high_inclusive=hi_in, unit=unit)
    if dims["n_flights"] is not None and not 2 <= dims["n_flights"] <= MAX_FLIGHTS:
        raise ValueError(f"{_opt('n_flights')} = {dims['n_flights']} is outside the allowed range [2, {MAX_FLIGHTS}]")
    if repose_angle is not None:
        check_range(_opt("repose_angle"), repose_angle, 0.0, 90.0, unit="deg")
    if rpm is not None:
        check_range(_opt("rpm"), rpm, 0.0, inf, unit="rev/min")
    if slope is not None:
        check_range(_opt("slope"), slope, 0.0, 45.0, low_inclusive=True, unit="deg")
    check_range(_opt("loading_factor"), loading_factor, 0.0, 1.0, low_inclusive=True, high_inclusive=True)
    if bulk_density is not None:
        lo, hi = _BULK_DENSITY_RANGE
        check_range(_opt("bulk_density"), bulk_density, lo, hi, low_inclusive=True, high_inclusive=True, unit="kg/m^3")
    if length is not None:
        check_range(_opt("length"), length, 0.0, inf, unit="m")
    check_range(_opt("angle"), angle, unit="deg")


@app.command("flight", short_help="Flight-unloading summary of a drum (Lee 2008).")
def flight(
    drum: str = typer.Option("invicta", help="Built-in drum (see --list-drums); explicit dimensions below override it."),
    radius: Optional[float] = typer.Option(None, help="Drum radius R, m."),
    n_flights: Optional[int] = typer.Option(None, help="Number of flights N_F."),
    s1: Optional[float] = typer.Option(None, help="Flight base length, m."),
    s2: Optional[float] = typer.Option(None, help="Flight tip length, m (0: straight flight)."),
    alpha1: Optional[float] = typer.Option(None, help="Base-to-wall angle inside the pocket, deg (90 = radial)."),
    alpha2: Optional[float] = typer.Option(None, help="Base-to-tip interior angle, deg."),
    repose_angle: Optional[float] = typer.Option(None, help="Dynamic angle of repose, deg (default: the profile's or "
                                                 "the drum's design repose angle where it has one, else 45)."),
    rpm: Optional[float] = typer.Option(None, help="Drum speed, rev/min (default: the drum's)."),
    slope: Optional[float] = typer.Option(None, help="Drum slope, deg (default: the drum's)."),
    loading_factor: float = typer.Option(1.0, help="Flight loading factor f_load in [0, 1]."),
    fall_height: str = typer.Option("chord", help="Fall-height definition: chord | eq3.5 | ajayi2011."),
    passive_branch: str = typer.Option("eq3.4", help="Passive-time branch: eq3.4 | lee2008_ch7."),
    convention: str = typer.Option("root", help="First-unloading-flight convention: root | tip (at 90 deg)."),
    bulk_density: Optional[float] = typer.Option(None, help="Bulk density, kg/m^3, for design loads in kg."),
    length: Optional[float] = typer.Option(None, help="Drum length, m, for design loads in kg."),
    angle: float = typer.Option(90.0, help="Root angle of the reference flight in the drawing, deg."),
    profile: Optional[Path] = typer.Option(None, help="Flight-profile file (TOML): a flight of any shape as segments = "
                                           "[[length_m, angle_deg], ...] or vertices = [[x_m, y_m], ...], optionally "
                                           "radius and n_flights (else the --drum's); see docs/guide/design_flights.md."),
    out: Optional[Path] = typer.Option(None, help="Directory for the plots (flight_profile.png, cross_section.png)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object instead of the table."),
    list_drums: bool = typer.Option(False, "--list-drums", help="List the built-in drums and exit."),
):
    """Flight-unloading summary (Lee 2008 ch. 4) for a drum: geometry, transition angles,
    mass-averaged cascade, cycle times and design loads; optionally save plots.

    A flight of any shape (straight sections from the root to the tip, each [length m, angle deg]:
    the base-to-wall angle, then the interior angle at each bend) is given by a flight-profile file
    (radius and n_flights optional, else the --drum's; docs/guide/design_flights.md).

    \b
    Example:
      rotarydryer flight --drum invicta --repose-angle 50 --out out/
      rotarydryer flight --profile three_section.toml --repose-angle 40 --out out/

    \b
    A three-section flight, three_section.toml:
      segments = [[0.195, 90.0], [0.10, 135.0], [0.09, 135.0]]
      radius = 2.5
      n_flights = 28
    """
    from .._validation import check_choice, fmt_number
    from ..geometry import DESIGN_LOAD_METHODS, FlightedDrum, TwoSectionFlight, check_speed, curtain_distribution
    from ..geometry.presets import DEFAULT_REPOSE_ANGLE, drum_presets, flight_profiles, preset_drum, read_profile
    from ..geometry.unloading import DESIGN_CONVENTIONS, FALL_HEIGHT_DEFINITIONS, PASSIVE_TIME_BRANCHES

    if list_drums:
        for name, e in drum_presets().items():
            typer.echo(f"{name:22s} {e['description']}")
        for name, e in flight_profiles().items():
            typer.echo(f"{name:22s} {e['description']}")
        raise typer.Exit(0)
    try:
        for option, value, allowed in (("--fall-height", fall_height, FALL_HEIGHT_DEFINITIONS),
                                       ("--passive-branch", passive_branch, PASSIVE_TIME_BRANCHES),
                                       ("--convention", convention, DESIGN_CONVENTIONS)):
            check_choice(option, value, allowed)
        base, entry = preset_drum(drum)
        dims = dict(radius=radius, n_flights=n_flights, s1=s1, s2=s2, alpha1=alpha1, alpha2=alpha2)
        _check_options(dims, repose_angle=repose_angle, rpm=rpm, slope=slope, loading_factor=loading_factor,
                       bulk_density=bulk_density, length=length, angle=angle)
        two = {k: v for k, v in dims.items() if k in ("s1", "s2", "alpha1", "alpha2") and v is not None}
        if profile is not None:
            if two:
                raise ValueError(f"--profile and {', '.join('--' + k for k in two)}: give the flight either as a profile "
                                 "file or as the two-section dimensions --s1 --s2 --alpha1 --alpha2, not both")
            prof = read_profile(profile)
            # the profile's operating values (and its design repose angle) stand in for the drum's
            entry = {**{k: v for k, v in entry.items() if k != "repose_angle"},
                     **{k: v for k, v in prof.items() if k in ("rpm", "slope", "length", "bulk_density", "repose_angle")}}
            R_ = radius if radius is not None else prof.get("radius", base.radius)
            N_ = n_flights if n_flights is not None else prof.get("n_flights", base.n_flights)
            try:
                d = FlightedDrum(R_, N_, prof["flight"])
            except ValueError as exc:
                raise ValueError(f"{profile} (radius = {fmt_number(R_)} m, n_flights = {N_}): {exc}") from None
        elif any(v is not None for v in dims.values()):
            if two and "s1" not in entry and len(two) < 4:
                raise ValueError(f"the {drum!r} drum has a polygonal flight: give all of --s1 --s2 --alpha1 --alpha2 "
                                 "(or --profile) to change it")
            if two or "s1" in entry:
                fl = TwoSectionFlight(*(two[k] if k in two else entry[k] for k in ("s1", "s2", "alpha1", "alpha2")))
            else:
                fl = base.flight
            p = {k: (v if v is not None else getattr(base, k)) for k, v in dims.items() if k in ("radius", "n_flights")}
            try:
                d = FlightedDrum(p["radius"], p["n_flights"], fl)
            except ValueError as exc:
                given = ", ".join(f"--{k.replace('_', '-')} {fmt_number(v)}"
                                  for k, v in dims.items() if v is not None)
                raise ValueError(f"{given} (with the {drum!r} drum's other dimensions): {exc}") from None
        else:
            d = base
        rpm_ = entry["rpm"] if rpm is None else rpm
        slope_ = entry["slope"] if slope is None else slope
        rho = entry["bulk_density"] if bulk_density is None else bulk_density
        ell = entry["length"] if length is None else length
        repose_angle = float(entry.get("repose_angle", DEFAULT_REPOSE_ANGLE)) if repose_angle is None else repose_angle

        def key(name):      # where a value without its option came from: the profile file's key or the drum's
            has = profile is not None and name in prof
            return f"{profile}: {name}" if has else f"the {drum!r} drum's {name}"
        check_speed(_opt("rpm") if rpm is not None else key("rpm"), rpm_, d.radius,
                    radius_key=_opt("radius") if radius is not None else key("radius"))
        cs = d.cascade(repose_angle, loading_factor, rpm=rpm_, slope=slope_, fall_height=fall_height,
                       passive_time_branch=passive_branch, convention=convention)
        tr = d.transition_angles(repose_angle)
        loads = {m: float(d.design_load_area(repose_angle, method=m, convention=convention)) for m in DESIGN_LOAD_METHODS}
        curtain = curtain_distribution(d, repose_angle, loading_factor, convention=convention)
    except ValueError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)
    psi5 = float(tr.psi5)
    # the drum the numbers are of: the preset, a profile file, or the preset with the dimensions given (its speed,
    # slope, length and bulk density stand in for those not given; "invicta" alone was reported for a drum of the
    # user's own dimensions, found by fuzzing)
    given = [f"--{k.replace('_', '-')}" for k, v in dims.items() if v is not None]
    drum_label = (str(profile) if profile is not None
                  else f"{drum} with {', '.join(given)} given" if given else drum)
    result = {
        "drum": drum_label,
        "radius_m": d.radius,
        "n_flights": d.n_flights,
        "flight_sections": [[float(a), float(b)] for a, b in d.profile.segments],
        "geometry": d.geometry,
        "tip_radius_m": d.tip_radius,
        "tip_angle_deg": d.tip_angle,
        "flight_spacing_deg": d.flight_spacing,
        "full_flight_holdup_m2": d.full_holdup_area,
        "repose_angle_deg": repose_angle,
        "rpm": rpm_,
        "slope_deg": slope_,
        "loading_factor": loading_factor,
        "transition_angles_deg": [float(a) for a in tr],
        "unloading_events_deg": [repose_angle + o for o in d.unloading_events],
        "final_discharge_angle_deg": psi5,
        "final_discharge_tip_angle_deg": psi5 + d.tip_angle,
        "curtain": curtain.to_dict(),
        "discharge_start_angle_deg": float(cs.discharge_start_angle),
        "mean_release_angle_deg": float(cs.mean_release_angle),
        "mean_fall_height_m": float(cs.mean_fall_height),
        "mean_fall_time_s": float(cs.mean_fall_time),
        "passive_time_s": float(cs.passive_time),
        "fall_height_definition": fall_height,
        "passive_time_branch": passive_branch,
        "design_convention": convention,
        "bulk_density_kg_m3": rho,
        "length_m": ell,
        "design_load_area_m2": loads,
        "design_load_kg": {m: a * rho * ell for m, a in loads.items()},
    }
    if out is not None:
        from .._io import check_output_target, save_figure
        from ..report.plots import draw_cross_section, plot_unloading_profile

        files = [out / "flight_profile.png", out / "cross_section.png"]
        for f in files:                     # refuse a bad --out before drawing anything
            check_output_target(f)
        fig = plot_unloading_profile(d, repose_angle, rpm_, convention=convention)
        fig2 = draw_cross_section(d, repose_angle, angle=angle)
        with written_set(out):                  # both files or neither: a failure keeps the previous set
            save_figure(fig, files[0], dpi=120)
            save_figure(fig2, files[1], dpi=120)
        result["plots"] = [str(f) for f in files]
    if as_json:
        typer.echo(json_text(result))
        return
    from .._display import show

    def length(v):      # lengths and masses in the display units (--units length=mm, mass=t); the flight's
        return show(v, "length", 6)     # seconds-scale times stay in s (the default time unit, min, is a residence time's)

    sections = ", ".join(f"{length(a)} at {b:g} deg" for a, b in d.profile.segments)
    rows = [
        ("drum", f"{drum_label}: R = {length(d.radius)}, {d.n_flights} flights"),
        (f"flight ({d.profile.n_segments} section{'s' if d.profile.n_segments > 1 else ''}, {d.geometry})", sections),
        ("flight-tip radius R_F (Eq. 4.6)", length(d.tip_radius)),
        ("tip angle psi_ft (Eq. 4.7)", f"{d.tip_angle:.4f} deg"),
        ("flight spacing psi_fl (Eq. 4.5)", f"{d.flight_spacing:.4f} deg"),
        ("full-flight holdup (Eq. 4.8)", f"{d.full_holdup_area * 1e4:.2f} cm2 per m"),
        ("transition angles psi1-5 (Eq. 4.9-4.13)", ", ".join(f"{float(a):.1f}" for a in tr) + " deg"),
        ("discharge into curtain starts at", f"{float(cs.discharge_start_angle):.1f} deg"),
        ("final discharge angle psi5 (root / tip)", f"{psi5:.1f} / {psi5 + d.tip_angle:.1f} deg"),
        # an empty flight (loading factor 0) releases nothing: no curtain to describe
        ("curtain: span across the drum", f"{'+' if curtain.span_m[0] >= 0 else ''}{length(curtain.span_m[0])} to "
                                           f"{'+' if curtain.span_m[1] >= 0 else ''}{length(curtain.span_m[1])} from the axis"
         if all(math.isfinite(float(v)) for v in curtain.span_m) else "none (the flight releases nothing)"),
        ("curtain: CV per degree / across span", f"{curtain.cv_per_degree:.3f} / {curtain.cv_across_span:.3f}"
         if math.isfinite(curtain.cv_per_degree) and math.isfinite(curtain.cv_across_span) else "-"),
        ("mean release angle psi_m (Eq. 3.3)", f"{float(cs.mean_release_angle):.1f} deg"),
        (f"mean fall height h_m ({fall_height})", length(float(cs.mean_fall_height))),
        ("mean fall time = active time", f"{float(cs.mean_fall_time):.3f} s"),
        (f"passive time ({passive_branch})", f"{float(cs.passive_time):.2f} s"),
    ]
    for m, a in loads.items():
        rows.append((f"design load {m} ({convention})", f"{a:.4f} m2 = {show(a * rho * ell, 'mass')}"))
    w = max(len(k) for k, _ in rows)
    typer.echo(f"Flight unloading, repose angle {repose_angle:g} deg, {rpm_:g} rpm, slope {slope_:g} deg, "
               f"rho_b {rho:g} kg/m3, L {length(ell)}")
    for k, v in rows:
        typer.echo(f"  {k:<{w}}  {v}")
    if out is not None:
        typer.echo(f"plots: {', '.join(result['plots'])}")
