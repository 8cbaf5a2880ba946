"""The project's DEM calibration and validation campaign (issue 15) and its regeneration.

Twelve periodic slices (4 particle diameters thick) of small flighted drums filled with 10 mm soft
spheres span d/s1 = 0.0625-0.2, two flight shapes (``A``: a Lee-rig-like flight, s2 = s1, 90/120
deg; ``B``: an MMG-like flight with a long tip, s2 = 1.5 s1, 90/135 deg), under- and over-loaded
drums (loading 0.6-2.0 of the geometric design load at 35 deg) and two Froude numbers (0.01
and 0.025, the range of Ajayi's pilot drum to the Invicta and MMG dryers). The drum radius is
a few flight bases (s1/R = 0.20-0.40) so that a few thousand particles fill it. Runs ``fit`` are
used to calibrate the finite-particle correction, the others are held out.

Regenerate (needs LIGGGHTS; about an hour on two cores):

    python -m rotarydryer.dem.calibrate --work dem_work --np 1 --jobs 2
    python examples/dem_calibration.py dem_work --run          (the same)

This exports every deck into ``dem_work/<run>/``, runs it, reduces the dumps to
``src/rotarydryer/data/dem/<run>.csv`` (``--data`` to write elsewhere) and prints the fit.

Polygonal flights (issue 34): nine more slices, ``POLYGON_RUNS``, of flights that are not two-section
flights (a three-section flight and the equal-angular-distribution flight of the presets, their
sections in proportion to the base), validate the exact polygon holdup with the finite-particle
correction fitted above (no refit); three of them ("diagnostic") test causes proposed for the EAD
flight's miss (docs/dem.md). They are reduced to ``src/rotarydryer/data/dem/polygon/``, apart
from the calibration campaign:

    python -m rotarydryer.dem.calibrate --polygon --work dem_work --np 1 --jobs 2
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path

__all__ = ["CampaignRun", "RUNS", "campaign_deck", "PolygonRun", "POLYGON_RUNS", "POLYGON_SHAPES", "polygon_deck",
           "main"]

D = 0.01  # m, particle diameter of the campaign
FROUDE = {"low": 0.01, "high": 0.025}
SHAPES = {"A": (1.0, 90.0, 120.0), "B": (1.5, 90.0, 135.0)}  # s2/s1, alpha1, alpha2


@dataclass(frozen=True)
class CampaignRun:
    name: str
    s1_in_d: float
    s1_over_R: float
    n_flights: int
    shape: str
    loading: float
    froude: str
    role: str  # "fit" or "held-out"
    spinup_revolutions: float = 1.0
    record_revolutions: float = 0.5


RUNS = (
    CampaignRun("c1_A_d020_over_lowFr", 5, 0.25, 10, "A", 1.3, "low", "fit"),
    CampaignRun("c2_B_d0125_under_highFr", 8, 0.25, 8, "B", 0.7, "high", "held-out"),
    CampaignRun("c3_B_d0167_over_highFr", 6, 0.25, 10, "B", 1.3, "high", "fit"),
    CampaignRun("c4_A_d0083_under_highFr", 12, 0.35, 10, "A", 0.7, "high", "held-out"),
    CampaignRun("c5_A_d010_over_lowFr", 10, 0.35, 10, "A", 1.2, "low", "fit"),
    CampaignRun("c6_A_d0071_under_highFr", 14, 0.40, 8, "A", 0.6, "high", "held-out"),
    CampaignRun("c7_A_d0125_over2_highFr", 8, 0.30, 10, "A", 2.0, "high", "held-out"),
    CampaignRun("c8_B_d0111_over_lowFr", 9, 0.25, 8, "B", 1.6, "low", "fit"),
    CampaignRun("c9_A_d00625_design_highFr", 16, 0.30, 8, "A", 1.0, "high", "held-out"),
    CampaignRun("c10_A_d0167_over_highFr_wide", 6, 0.22, 8, "A", 1.5, "high", "fit"),
    CampaignRun("c11_B_d0143_over_highFr_wide", 7, 0.22, 8, "B", 1.4, "high", "held-out"),
    CampaignRun("c12_A_d0167_over_lowFr_wide", 6, 0.20, 8, "A", 1.2, "low", "held-out"),
)


def campaign_deck(run: CampaignRun):
    """The `SliceDeck` of a campaign run."""
    from ..geometry import FlightedDrum, TwoSectionFlight
    from .deck import Particles, build_slice

    s1 = run.s1_in_d * D
    R = s1 / run.s1_over_R
    k2, a1, a2 = SHAPES[run.shape]
    drum = FlightedDrum(R, run.n_flights, TwoSectionFlight(s1, k2 * s1, a1, a2))
    fr = FROUDE[run.froude]
    rpm = math.sqrt(fr * 9.81 / R) * 60.0 / (2.0 * math.pi)
    return build_slice(drum, Particles(diameter=D), rpm=rpm, loading=run.loading, settle_time=0.6,
                       spinup_revolutions=run.spinup_revolutions, record_revolutions=run.record_revolutions, dump_every_deg=1.0,
                       timestep_fraction=0.2, source=f"campaign {run.name} ({run.role})")


#: flight shapes of the polygon runs: (length / base length, angle deg) per section, from the root
POLYGON_SHAPES = {
    # the three-section preset's shape (presets.toml: invicta_three_section): radial base, two 45 deg bends
    "3S": ((1.0, 90.0), (0.5, 135.0), (0.45, 135.0)),
    # the equal-angular-distribution preset's shape (profiles.toml: invicta_ead), lengths over its 0.068 m base
    "EAD": ((1.0, 90.0), (0.04 / 0.068, 170.0), (0.04 / 0.068, 154.5), (0.24 / 0.068, 170.0)),
    # the EAD flight with a shorter last section (2.4 bases instead of 3.53; p8, after the EAD miss); its middle
    # sections as run, 0.588 bases (the EAD preset's 0.04 / 0.068 = 0.5882 rounded)
    "EAD-short": ((1.0, 90.0), (0.588, 170.0), (0.588, 154.5), (2.4, 170.0)),
}


@dataclass(frozen=True)
class PolygonRun:
    name: str
    shape: str
    s1_in_d: float
    radius: float
    n_flights: int
    loading: float
    froude: str
    seed: int = 5778
    role: str = "validation"
    #: particle-wall sliding friction (-); None: the particles' own (0.5, 26.6 deg)
    wall_friction: float | None = None
    #: particle-wall rolling friction (-); None: the particles' own (0.1)
    wall_rolling_friction: float | None = None
    spinup_revolutions: float = 1.0
    record_revolutions: float = 0.5


POLYGON_RUNS = (
    PolygonRun("p1_3S_d0125_over_highFr", "3S", 8, 0.32, 8, 1.3, "high"),
    PolygonRun("p2_EAD_d020_over_highFr", "EAD", 5, 0.40, 8, 1.3, "high"),
    PolygonRun("p3_3S_d0125_over2_highFr", "3S", 8, 0.32, 8, 2.0, "high"),
    PolygonRun("p4_EAD_d020_over2_highFr", "EAD", 5, 0.40, 8, 2.0, "high"),
    # the EAD drums of p2 and p4 at the three-section runs' particle scale (d/s1 = 0.125, inside the
    # calibration's range; p2 and p4 are at its edge, 0.2)
    PolygonRun("p5_EAD_d0125_over_highFr", "EAD", 8, 0.64, 8, 1.3, "high"),
    PolygonRun("p6_EAD_d0125_over2_highFr", "EAD", 8, 0.64, 8, 2.0, "high"),
    # two slices that test the candidate cause of the EAD miss (docs/dem.md): p4 with a particle-wall friction
    # of 1.0 (45 deg, above the repose angle: no sliding on the flight), and the EAD flight with a shorter
    # last section (a flight shape of its own)
    PolygonRun("p7_EAD_d020_over2_highFr_wall1", "EAD", 5, 0.40, 8, 2.0, "high", wall_friction=1.0,
               role="diagnostic"),
    PolygonRun("p8_EADshort_d020_over2_highFr", "EAD-short", 5, 0.40, 8, 2.0, "high", role="diagnostic"),
    # p7 with the particle-wall rolling friction of 1.0 too: the spheres can neither slide nor roll on the
    # flight (p7's spheres could still roll on it, at the CDT rolling friction of 0.1)
    PolygonRun("p9_EAD_d020_over2_highFr_wall1_roll1", "EAD", 5, 0.40, 8, 2.0, "high", wall_friction=1.0,
               wall_rolling_friction=1.0, role="diagnostic"),
)


def polygon_deck(run: PolygonRun):
    """The `SliceDeck` of a polygon run."""
    from ..geometry import FlightedDrum, PolygonFlight
    from .deck import Particles, build_slice

    s1 = run.s1_in_d * D
    flight = PolygonFlight([(k * s1, a) for k, a in POLYGON_SHAPES[run.shape]])
    drum = FlightedDrum(run.radius, run.n_flights, flight)
    fr = FROUDE[run.froude]
    rpm = math.sqrt(fr * 9.81 / run.radius) * 60.0 / (2.0 * math.pi)
    return build_slice(drum, Particles(diameter=D, wall_friction=run.wall_friction,
                                          wall_rolling_friction=run.wall_rolling_friction), rpm=rpm, loading=run.loading,
                       settle_time=0.6,
                       spinup_revolutions=run.spinup_revolutions, record_revolutions=run.record_revolutions,
                       dump_every_deg=1.0, timestep_fraction=0.2, seed=run.seed,
                       source=f"polygon run {run.name} ({run.role}; python -m rotarydryer.dem.calibrate --polygon)")


def _run_one(name: str, work: str, np: int) -> dict:
    """LIGGGHTS on one run's deck (top-level, for the executor's worker processes)."""
    from .run import run_deck

    return run_deck(Path(work) / name, np=np, progress=True, label=name)


class _BatchError(Exception):
    """A bad option of the batch: one line on stderr, exit code 2 (`main`)."""


class _Parser(argparse.ArgumentParser):
    """argparse with a usage error as one ``error: ...`` line (its usage block and program name read as a crash
    beside the project's other commands; found by an acceptance check)."""

    def error(self, message):       # noqa: D401 - argparse's hook
        raise _BatchError(f"{message}; see 'python -m rotarydryer.dem.calibrate --help'")


def main(argv=None):
    """The batch (exit code 0; 2 and one ``error: ...`` line on stderr for a bad option or an unreachable cluster).
    A warning is one ``warning: ...`` line on stderr, each text once."""
    seen: set = set()

    def show(message, category, filename, lineno, file=None, line=None):
        text = " ".join(str(message).split())
        if text not in seen:
            seen.add(text)
            print(f"warning: {text}", file=sys.stderr)

    with warnings.catch_warnings():
        warnings.showwarning = show
        try:
            return _main(argv)
        except _BatchError as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2


def _main(argv=None):
    ap = _Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--work", default="dem_work", help="folder for the decks and dumps")
    ap.add_argument("--data", default=None, help="folder for the reduced CSVs (default: the package data)")
    ap.add_argument("--np", type=int, default=1, help="MPI ranks per run")
    ap.add_argument("--jobs", type=int, default=1, help="runs at the same time (local worker processes; 0: one per "
                    "core)")
    ap.add_argument("--scheduler", default=None, help="run on a Dask scheduler, e.g. tcp://10.0.0.5:8786 (LIGGGHTS and "
                    "the work folder must be there too)")
    ap.add_argument("--cluster", default=None, help="local:N: a Dask LocalCluster of N worker processes here")
    ap.add_argument("--only", nargs="*", default=None, help="run names (default all)")
    ap.add_argument("--reduce-only", action="store_true", help="do not run LIGGGHTS, reduce existing dumps")
    ap.add_argument("--export-only", action="store_true", help="only write the decks")
    ap.add_argument("--plots", default=None, help="folder for one comparison plot per run (PNG)")
    ap.add_argument("--polygon", action="store_true", help="the polygonal-flight runs (POLYGON_RUNS) instead")
    a = ap.parse_args(argv)
    from .._workers import executor_from_options, usable_cpus
    from ..executor import RunFailure
    from .deck import export_deck
    from .holdup import analyse_run, write_reduced_csv

    # the two-section campaign, or the polygonal flights' validation slices (no fit): the same pipeline
    runs_all, deck_of = (POLYGON_RUNS, polygon_deck) if a.polygon else (RUNS, campaign_deck)
    names = [r.name for r in runs_all]
    unknown = [n for n in (a.only or ()) if n not in names]
    if unknown:         # a misspelt run name ran nothing of it without a word
        raise _BatchError(f"--only {unknown[0]}: no such run of the {'polygon' if a.polygon else 'calibration'} "
                          f"campaign; runs: {', '.join(names)}")
    if a.only is not None and not a.only:
        raise _BatchError(f"--only: no run named; runs: {', '.join(names)}")
    runs = [r for r in runs_all if not a.only or r.name in a.only]
    cpus = usable_cpus()
    if not 1 <= a.np <= 256:         # as `rotarydryer dem run --np` (more than the cores: a warning, as there)
        raise _BatchError(f"--np = {a.np} is outside the allowed range [1, 256] (MPI ranks per run; more than the "
                          f"{cpus} usable CPU cores run as {cpus}, with a warning)")
    if a.np > cpus and not a.scheduler:     # a cluster's machines have their own cores
        print(f"warning: --np = {a.np} is more than the {cpus} usable CPU cores; using {cpus}", file=sys.stderr)
        a.np = cpus
    # the option checks of every many-run command, whatever runs (a bad address refused at once, not after the
    # connection's wait: "--scheduler nonsense" took 21 s; --jobs -1 or 1000 ran without a word)
    try:
        executor, notes = executor_from_options(a.jobs, len(runs), scheduler=a.scheduler, cluster=a.cluster,
                                                workers_option="--jobs")
    except (ValueError, ImportError) as exc:
        raise _BatchError(str(exc)) from None
    running = not (a.reduce_only or a.export_only)
    if running:
        for note in notes:
            print(f"warning: {note}", file=sys.stderr)
        try:
            executor.connect()
        except (ValueError, ImportError) as exc:
            raise _BatchError(str(exc)) from None

    work = Path(a.work)
    data = Path(a.data) if a.data else Path(__file__).resolve().parents[1] / "data" / "dem"
    if a.polygon and not a.data:
        data = data / "polygon"
    for r in runs:
        if not a.reduce_only:
            export_deck(deck_of(r), work / r.name)
    if a.export_only:
        return 0
    if running:     # one run per chunk through the executor: a failed run is reported, the others go on
        done = executor.map(_run_one, [r.name for r in runs], args=(str(work), a.np), chunks=1)
        for r, res in zip(runs, done):
            if isinstance(res, RunFailure):
                print(f"{r.name}: LIGGGHTS run failed ({res.error})")
    for r in runs:
        try:
            res = analyse_run(work / r.name)
        except ValueError as exc:
            print(f"{r.name}: skipped ({exc})")
            continue
        write_reduced_csv(res, data / f"{r.name}.csv", role=r.role)
        print(f"{r.name}: {res.summary_line()}")
    if a.polygon:
        return 0
    if a.plots:
        from .fit import load_campaign
        from .holdup import plot_comparison

        for name, res in load_campaign(data).items():
            plot_comparison(res, Path(a.plots) / f"dem_{name.split('_')[0]}.png",
                            title=f"{name} ({res.extra.get('role', '')})")
    from .fit import fit_report

    print(fit_report(data))
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
