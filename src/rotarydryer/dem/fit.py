"""Fit of the finite-particle surface layer ``k`` (``delta = k d``) on the DEM runs marked "fit".

``k`` minimises the sum over the fit runs of the squared model-minus-DEM holdup differences (in
% of a full flight) over each run's unloading range, at each run's measured repose angle
(`rotarydryer.dem.holdup.compare`); the held-out runs are only evaluated. Golden-section
search on [0, 6] (the error is smooth and unimodal in k).
"""

from __future__ import annotations

import math
from importlib import resources
from pathlib import Path

import numpy as np

from .deck import ARCHING_MOUTH_DIAMETERS, pocket_mouth_width
from .holdup import DemHoldup, compare, read_reduced_csv

__all__ = ["load_campaign", "fit_surface_layer", "campaign_table", "fit_report", "data_folder"]


def data_folder() -> Path:
    """The shipped reduced DEM runs (``rotarydryer/data/dem``)."""
    return Path(str(resources.files("rotarydryer.data").joinpath("dem")))


#: a run's own dynamic repose angle is used when it rests on at least this many flight surfaces
MIN_REPOSE_SAMPLES = 40


def assign_repose_angles(runs: dict[str, DemHoldup]) -> None:
    """Runs whose repose angle rests on fewer than `MIN_REPOSE_SAMPLES` flight surfaces (pockets
    only a few particles wide) are compared at the angle measured in the run with the same particles
    and Froude number (within 5 %) that has the most surfaces (``extra["repose_angle_used_deg"]`` and
    ``extra["repose_angle_source"]``)."""
    for name, r in runs.items():
        if r.extra.get("repose_angle_samples", 0) >= MIN_REPOSE_SAMPLES:
            continue
        same = [(o.extra.get("repose_angle_samples", 0), n, o) for n, o in runs.items()
                if n != name and o.deck.particles == r.deck.particles
                and abs(o.deck.froude - r.deck.froude) <= 0.05 * r.deck.froude
                and o.extra.get("repose_angle_samples", 0) >= MIN_REPOSE_SAMPLES]
        if same:
            _, n, o = max(same, key=lambda t: t[0])
            r.extra["repose_angle_used_deg"] = o.repose_angle_deg
            r.extra["repose_angle_source"] = n


def load_campaign(folder=None) -> dict[str, DemHoldup]:
    folder = Path(folder) if folder else data_folder()
    def order(p):
        head = p.stem.split("_")[0].lstrip("c")
        return (int(head) if head.isdigit() else 10**9, p.stem)

    runs = {p.stem: read_reduced_csv(p) for p in sorted(folder.glob("*.csv"), key=order)}
    if not runs:
        raise ValueError(f"no reduced DEM runs (*.csv) in {str(folder)!r}")
    assign_repose_angles(runs)
    return runs


def _sse(runs, k):
    tot, n = 0.0, 0
    for r in runs:
        c = compare(r, surface_layer=k)["corrected"]
        tot += c["rms_pct"] ** 2 * c["n_samples"]
        n += c["n_samples"]
    return tot / max(n, 1)


def fit_surface_layer(runs: list[DemHoldup], lo: float = 0.0, hi: float = 6.0, tol: float = 1e-3) -> float:
    """Least-squares ``k`` over ``runs`` (golden-section search on [lo, hi])."""
    if not runs:
        raise ValueError("no DEM runs to fit the surface layer on")
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = lo, hi
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = _sse(runs, c), _sse(runs, d)
    while b - a > tol:
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = _sse(runs, c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = _sse(runs, d)
    return 0.5 * (a + b)


def campaign_table(runs: dict[str, DemHoldup], k: float) -> list[dict]:
    rows = []
    for name, r in runs.items():
        c = compare(r, surface_layer=k)
        rows.append({"run": name, "role": r.extra.get("role", ""),
                     "d_over_s1": r.deck.particles.diameter / r.deck.s1, "froude": r.deck.froude,
                     "mouth_in_d": pocket_mouth_width(r.deck.drum) / r.deck.particles.diameter,
                     "loading": r.loading, "n_particles": r.n_particles, "repose_angle_deg": r.repose_angle_deg,
                     "repose_angle_used_deg": c["dem"]["repose_angle_deg"],
                     "repose_angle_source": r.extra.get("repose_angle_source", "own"),
                     "repose_angle_samples": r.extra.get("repose_angle_samples", 0),
                     "packing_fraction": r.packing_fraction, "airborne_fraction": r.airborne_fraction,
                     "rms_plain_pct": c["plain"]["rms_pct"], "bias_plain_pct": c["plain"]["bias_pct"],
                     "rms_corrected_pct": c["corrected"]["rms_pct"], "bias_corrected_pct": c["corrected"]["bias_pct"],
                     "start_dem_deg": c["dem"]["start_deg"], "start_plain_deg": c["plain"]["start_deg"],
                     "start_corrected_deg": c["corrected"]["start_deg"], "end_dem_deg": c["dem"]["end_deg"],
                     "end_plain_deg": c["plain"]["end_deg"], "end_corrected_deg": c["corrected"]["end_deg"]})
    return rows


def _phi_text(r) -> str:
    own = f"{r['repose_angle_deg']:.1f} ({r['repose_angle_samples']})"
    if r["repose_angle_source"] != "own":
        return f"{own}; used {r['repose_angle_used_deg']:.1f} of {r['repose_angle_source'].split('_')[0]}"
    return own


def _mouth(r: DemHoldup) -> float:
    return pocket_mouth_width(r.deck.drum) / r.deck.particles.diameter


def fit_report(folder=None) -> str:
    """Fit ``k`` on the "fit" runs, (a) all of them (the calibration) and (b) those whose pocket mouth
    is at least `ARCHING_MOUTH_DIAMETERS` wide (narrower mouths arch), and
    tabulate every run at both (Markdown)."""
    runs = load_campaign(folder)
    fit_all = [r for r in runs.values() if r.extra.get("role") == "fit"]
    fit_wide = [r for r in fit_all if _mouth(r) >= ARCHING_MOUTH_DIAMETERS]
    k_all = fit_surface_layer(fit_all)
    k = fit_surface_layer(fit_wide) if fit_wide else k_all
    out = [f"surface layer k = {k_all:.3f} (delta = k d), fitted on all {len(fit_all)} fit runs; k = {k:.3f} when "
           f"fitted on the {len(fit_wide)} fit runs with a pocket mouth >= {ARCHING_MOUTH_DIAMETERS:g} d", ""]
    for kk, title in ((k_all, "at k fitted on all fit runs"), (k, "at k fitted on the wide-mouth fit runs")):
        rows = campaign_table(runs, kk)
        out += [f"### {title} (k = {kk:.3f})", "",
                "| run | role | d/s1 | mouth (d) | Fr | loading | phi_m (deg, surfaces) | RMS plain (%) | bias plain (%) "
                "| RMS corrected (%) | bias corrected (%) | start DEM/plain/corr (deg) | end DEM/plain/corr (deg) |",
                "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in rows:
            out.append(f"| {r['run']} | {r['role']} | {r['d_over_s1']:.3f} | {r['mouth_in_d']:.1f} | {r['froude']:.3f} | "
                       f"{r['loading']:.2f} | {_phi_text(r)} | {r['rms_plain_pct']:.1f} | "
                       f"{r['bias_plain_pct']:+.1f} | {r['rms_corrected_pct']:.1f} | {r['bias_corrected_pct']:+.1f} | "
                       f"{r['start_dem_deg']:.0f}/{r['start_plain_deg']:.0f}/{r['start_corrected_deg']:.0f} | "
                       f"{r['end_dem_deg']:.0f}/{r['end_plain_deg']:.0f}/{r['end_corrected_deg']:.0f} |")
        out.append("")
        wide = ARCHING_MOUTH_DIAMETERS
        for role in ("fit", "held-out"):
            for label, cond in (("", lambda r: True),
                                (f", pocket mouth >= {wide:g} d", lambda r: r["mouth_in_d"] >= wide),
                                (f", pocket mouth < {wide:g} d (arching)", lambda r: r["mouth_in_d"] < wide)):
                sel = [r for r in rows if r["role"] == role and cond(r)]
                if sel:
                    p = float(np.sqrt(np.mean([r["rms_plain_pct"] ** 2 for r in sel])))
                    q = float(np.sqrt(np.mean([r["rms_corrected_pct"] ** 2 for r in sel])))
                    out.append(f"- {role}{label} ({len(sel)} runs): pooled RMS plain {p:.1f} %, corrected {q:.1f} % "
                               "of a full flight")
        out.append("")
    return "\n".join(out)


def runs_markdown(runs: dict[str, DemHoldup]) -> str:
    """The campaign's runs: parameters, particles, steps and wall time (Markdown)."""
    out = ["| run | role | flight (s2/s1, alpha2) | d/s1 | s1/R | mouth (d) | N_F | R (m) | rpm | Fr | loading "
           "| particles | steps (dt) | recorded | wall time | packing | airborne |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, r in runs.items():
        d = r.deck
        st = d.recorded_steps or d.steps()
        wall = r.extra.get("wall_time_s")
        out.append(
            f"| {name} | {r.extra.get('role', '')} | {d.s2 / d.s1:.2g}, {d.alpha2:g} | {d.particles.diameter / d.s1:.3g} | "
            f"{d.s1 / d.radius:.2f} | {_mouth(r):.1f} | {d.n_flights} | {d.radius:.3f} | {d.rpm:.2f} | {d.froude:.3f} | "
            f"{d.loading:g} | {r.n_particles} | {st['total']} ({d.timestep:.2e} s) | {d.record_revolutions:g} rev, "
            f"{r.n_frames} frames | {'-' if wall is None else f'{wall / 60:.1f} min'} | {r.packing_fraction:.3f} | "
            f"{100 * r.airborne_fraction:.1f} % |")
    return "\n".join(out)


if __name__ == "__main__":  # pragma: no cover - python -m rotarydryer.dem.fit [folder]
    import sys

    _runs = load_campaign(sys.argv[1] if len(sys.argv) > 1 else None)
    print(runs_markdown(_runs))
    print()
    print(fit_report(sys.argv[1] if len(sys.argv) > 1 else None))
