"""Figures drawn from a `rotarydryer.results.Results` (no physics recomputed) and
the geometry of a case.

Matplotlib is imported inside the functions (Agg backend when none is chosen).
"""

from __future__ import annotations

import numpy as np

from .plots import _plt

__all__ = ["case_drums", "plot_holdup_profile", "plot_rtd", "plot_loading_state", "draw_dryer_side_view"]

STATE_COLOURS = {"under": "#4c9be8", "design": "#3aa655", "over": "#d9534f"}


def case_drums(inputs: dict, results=None) -> list[dict]:
    """Flighted sections of a case (the ``inputs`` dict of a Results, or ``case.model_dump()``)
    as dicts: name, drum (FlightedDrum), length (m), bulk_density (kg/m3), repose_angle (deg),
    rpm (rev/min), slope (deg).

    The repose angle and bulk density are the section means of the per-cell values of
    ``results`` when available (they vary with moisture along the dryer), else the
    case's constant values, else 45 deg and 1000 kg/m3 (shown as such in the report).
    """
    from ..geometry import FlightedDrum, PolygonFlight, TwoSectionFlight

    cells = results.flighted_cells if results is not None else None
    params = (results.model_choices.get("parameters", {}) if results is not None else {})

    def _mean(section, var, default):
        if cells is None or var not in cells:
            return default
        sel = cells["section"].values == section
        return float(np.mean(cells[var].values[sel])) if np.any(sel) else default

    out = []
    d, op = inputs["drum"], inputs.get("operating", {})
    shared = {**(inputs.get("flight") or {}), "n_flights": d.get("n_flights")}     # what sections inherit
    rpm = params.get("rpm") or op.get("rpm")
    if rpm is None:
        test = next((t for t in inputs.get("tests", []) if t["test"] == op.get("test")), None)
        rpm = test["rpm"] if test else 3.0
    for sec in inputs.get("sections", []):
        if sec["kind"] != "flighted":
            continue
        nf = sec.get("n_flights") or shared.get("n_flights")
        own = any(sec.get(k) is not None for k in ("s1", "s2", "alpha1", "alpha2"))
        poly = next(((k, src[k]) for src in ((sec,) if own else (sec, shared)) for k in ("segments", "vertices")
                     if src.get(k) is not None), None)
        if poly is not None and nf is not None:      # a flight of any shape (segments or vertices)
            flight = (PolygonFlight(poly[1]) if poly[0] == "segments" else PolygonFlight(vertices=poly[1]))
            drum = FlightedDrum(d["radius"], nf, flight)
        else:
            g = {k: sec.get(k) if sec.get(k) is not None else shared.get(k)
                 for k in ("n_flights", "s1", "s2", "alpha1", "alpha2")}
            if any(v is None for v in g.values()):
                continue        # no flight dimensions (regression geometry only)
            drum = FlightedDrum(d["radius"], g["n_flights"], TwoSectionFlight(g["s1"], g["s2"], g["alpha1"], g["alpha2"]))
        out.append(dict(name=sec["name"], drum=drum, length=sec["length"], slope=d["slope"], rpm=rpm,
                        bulk_density=_mean(sec["name"], "bulk_density", 1000.0),
                        repose_angle=_mean(sec["name"], "repose_angle", 45.0)))
    return out


def _axial_sections(results):
    secs = results.sections
    x0, out = 0.0, []
    for name, kind, length in zip(secs.section.values, secs.kind.values, secs.length.values):
        out.append((str(name), str(kind), x0, x0 + float(length)))
        x0 += float(length)
    return out


def plot_holdup_profile(results, ax=None):
    """Holdup per metre (kg/m) along the dryer from a Results: airborne, flight-borne (up to
    the design load), kilning bed, unflighted bed.  Returns the figure (drawn by
    `rotarydryer.transport.plots.holdup_profile_figure`)."""
    from ..transport.plots import holdup_profile_figure

    nodes, secs, s = results.nodes, results.sections, results.scalars
    sections = list(zip(secs.section.values, secs.kind.values, secs.length.values, secs.n_cells.values))
    return holdup_profile_figure(sections, nodes.position.values, nodes.phase.values, nodes.section.values,
                                 nodes.holdup.values, nodes.design_load.values, total_kg=s["total_holdup_kg"],
                                 holdup_over_flow_s=s["mean_residence_time_s"], ax=ax)


def plot_rtd(results, ax=None):
    """Simulated E(t) (1/min) against time (min) with the measured curve, normalised by its
    trapezoidal integral, when the Results hold one.  Returns the figure (or None without RTD;
    drawn by `rotarydryer.transport.plots.rtd_figure`)."""
    if results.rtd is None:
        return None
    from ..transport.plots import rtd_figure

    r, s, m = results.rtd, results.scalars, results.rtd_measured
    return rtd_figure(r.time.values, r.exit_age.values, s.get("tracer_mean_s", s.get("simulated_mean_s", np.nan)),
                      s.get("tracer_std_s", s.get("rtd_std_s", np.nan)),
                      measured=None if m is None else (m.time.values, m.signal.values),
                      baseline=s.get("measured_baseline", 0.0), ax=ax)


def plot_loading_state(results, ax=None):
    """Dryer loading M_P/M_P,des per flighted cell (Lee (2008) Section 4.4.2), coloured by
    loading state (under, design, over).  Returns the figure (None without flighted cells)."""
    cells = results.flighted_cells
    if cells is None:
        return None
    plt = _plt()
    fig, ax = (ax.figure, ax) if ax is not None else plt.subplots(figsize=(8, 2.8), constrained_layout=True)
    x = cells.position.values
    d = cells.dryer_loading.values
    st = cells.state.values
    width = np.min(np.diff(np.sort(x))) * 0.9 if x.size > 1 else 0.5
    for state, colour in STATE_COLOURS.items():
        sel = st == state
        if np.any(sel):
            ax.bar(x[sel], d[sel], width=width, color=colour, label=f"{state} ({int(sel.sum())} cells)")
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    for _name, _kind, x0, _x1 in _axial_sections(results):
        ax.axvline(x0, color="0.85", lw=0.8)
    ax.set_xlabel("axial position from the feed end (m)")
    ax.set_ylabel("dryer loading (-)")
    ax.set_title("Loading state per cell (1 = design load)", fontsize=10)
    ax.legend(fontsize=8, loc="upper right")
    return fig


def draw_dryer_side_view(results=None, *, inputs: dict | None = None, ax=None):
    """The dryer drawn to scale from the side: shell, sections (flighted/unflighted), flights
    as lines along the shell, curtains in flighted sections, the slope and feed/discharge
    ends.  Uses the sections of ``results`` or, without results, of ``inputs`` (Lee cases:
    one flighted section).  Returns the figure."""
    plt = _plt()
    inputs = inputs if inputs is not None else results.inputs
    if results is not None and results.sections is not None:
        secs = [(n, k, a, b) for n, k, a, b in _axial_sections(results)]
    elif inputs.get("sections"):
        secs, x0 = [], 0.0
        for s in inputs["sections"]:
            secs.append((s["name"], s["kind"], x0, x0 + s["length"]))
            x0 += s["length"]
    else:
        secs = [("dryer", "flighted", 0.0, float(inputs["drum"]["length"]))]
    R = float(inputs["drum"]["radius"])
    slope = np.radians(float(inputs["drum"].get("slope", 0.0)))
    L = secs[-1][3]
    fig, ax = (ax.figure, ax) if ax is not None else plt.subplots(
        figsize=(7.0, float(np.clip(7.0 * (3.2 * R + L * np.sin(slope)) / (1.4 * L) + 0.5, 1.8, 5.0))),
        constrained_layout=True)
    c, s = np.cos(-slope), np.sin(-slope)

    def tr(x, y):
        x, y = np.asarray(x, float), np.asarray(y, float)
        return x * c - y * s, x * s + y * c

    from matplotlib.patches import Polygon

    for name, kind, x0, x1 in secs:
        face = "#f3e3c3" if kind == "flighted" else "#e6e6e6"
        ax.add_patch(Polygon(np.c_[tr([x0, x1, x1, x0], [-R, -R, R, R])], closed=True, fc=face, ec="k", lw=1))
        xm = 0.5 * (x0 + x1)
        ax.text(*tr(xm, R * 1.12), name, ha="center", va="bottom", fontsize=8,
                rotation=-np.degrees(slope))
        if kind == "flighted":
            for y in np.linspace(-0.85 * R, 0.85 * R, 7):
                ax.plot(*tr([x0 + 0.02 * (x1 - x0), x1 - 0.02 * (x1 - x0)], [y, y]), color="#8a6416", lw=0.6)
            n_curt = max(2, int((x1 - x0) / (0.6 * R)))
            for xc in np.linspace(x0, x1, n_curt + 2)[1:-1]:
                xa, ya = tr(xc, 0.8 * R)
                ax.plot([xa, xa], [ya, ya - 1.5 * R], color="#b8862d", lw=2.2, alpha=0.45)
        else:
            ax.add_patch(Polygon(np.c_[tr([x0, x1, x1, x0], [-R, -R, -0.7 * R, -0.7 * R])], closed=True,
                                 fc="#d9a441", ec="none", alpha=0.8))
    ax.annotate("feed", xy=tr(0, 0), xytext=tr(-0.12 * L, 0), ha="center", va="bottom", fontsize=9,
                arrowprops=dict(arrowstyle="->"))
    ax.annotate("", xy=tr(1.12 * L, 0), xytext=tr(L, 0), arrowprops=dict(arrowstyle="->"))
    ax.text(*tr(1.08 * L, 0.12 * R), "discharge", ha="center", va="bottom", fontsize=9)
    ax.set_aspect("equal")
    ax.set_xlim(-0.2 * L, 1.2 * L)
    ax.set_ylim(-R * 1.6 - L * np.sin(slope), R * 1.6)
    ax.set_axis_off()
    ax.set_title(f"Dryer to scale: L = {L:g} m, D = {2 * R:g} m, slope {np.degrees(slope):g} deg "
                 "(flighted sections shaded; flights and curtains schematic)", fontsize=9)
    return fig
