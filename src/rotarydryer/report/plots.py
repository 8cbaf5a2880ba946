"""Plots of the flight geometry: unloading profile and drum cross-section.

Import cost: Matplotlib is imported inside the functions, with the non-interactive
Agg backend when no backend has been chosen.
"""

from __future__ import annotations

import numpy as np

from .._display import UNITS, fmt, unit_of
from .._plotting import pyplot as _plt
from ..geometry import FlightedDrum, first_unloading_angle
from ..thermal.audit import HEAT_DUTY_LABELS, HEAT_DUTY_PARTS
from ..thermal.plots import plot_thermal_profiles, plot_thermal_steady_state

__all__ = ["plot_unloading_profile", "draw_cross_section", "draw_flight_conventions", "plot_energy_waterfall",
           "plot_heat_duties", "plot_thermal_profiles", "thermal_profiles_from_results", "plot_thermal_steady_state"]




def plot_unloading_profile(drum: FlightedDrum, repose_angle: float, rpm: float, *, ax=None,
                           convention: str = "root"):
    """Holdup (m^2 per m of flight) and discharge rate versus root angle; returns the figure.

    Shows the transition angles psi1..psi5 (Lee (2008) Eq. 4.9-4.13) and the first
    unloading flight position.
    """

    plt = _plt()
    psi = np.arange(0.0, 360.0, 0.1)
    hold = drum.holdup_area(psi, repose_angle)
    rate = drum.discharge_rate(psi, repose_angle, rpm)
    if ax is None:
        fig, ax = plt.subplots(figsize=(7.5, 4.2), constrained_layout=True)
    else:
        fig = ax.figure
    ax.plot(psi, hold * 1e4, color="tab:blue", label="holdup")
    ax.set_xlabel("flight root angle psi from drum bottom (deg)")
    ax.set_ylabel("holdup per m of flight (cm$^2$)", color="tab:blue")
    ax2 = ax.twinx()
    ax2.plot(psi, rate * 1e4, color="tab:red", label="discharge rate")
    ax2.set_ylabel("discharge rate per m of flight (cm$^2$/s)", color="tab:red")
    for k, a in enumerate(drum.transition_angles(repose_angle), start=1):
        ax.axvline(float(a), color="0.6", lw=0.8, ls=":")
        ax.text(float(a), ax.get_ylim()[1] * 0.97, f"$\\psi_{k}$", ha="center", va="top", fontsize=8)
    ax.axvline(first_unloading_angle(drum, convention), color="k", lw=0.8, ls="--")
    ax.set_xlim(0, 360)
    ax.set_title(f"Flight unloading, repose angle {repose_angle:g} deg, {rpm:g} rpm")
    return fig


def draw_cross_section(drum: FlightedDrum, repose_angle: float, *, angle: float = 90.0, ax=None,
                       show_curtain: bool = True, annotate: bool = True):
    """Drum cross-section drawn to scale: flights, held solids and curtains; returns the figure.

    ``angle`` (deg) is the root angle of the reference flight; the others follow at the
    flight spacing. The drum turns anticlockwise; psi is measured from the bottom.
    Each flight is drawn with the most it can hold at its angle (Lee (2008) H_max(psi));
    flights in the lower half are buried in the bed and full. Curtains fall vertically
    from discharging tips (tip above the horizontal) to the flight-tip circle.
    """
    from matplotlib.patches import Circle, Polygon

    plt = _plt()
    if ax is None:
        fig, ax = plt.subplots(figsize=(6, 6), constrained_layout=True)
    else:
        fig = ax.figure
    R, RF = drum.radius, drum.tip_radius
    ax.add_patch(Circle((0, 0), R, fill=False, lw=2, color="k"))
    ax.add_patch(Circle((0, 0), RF, fill=False, lw=0.6, ls="--", color="0.5"))
    psi5 = float(drum.transition_angles(repose_angle).psi5)
    rates = []
    for j in range(drum.n_flights):
        psi = (angle + j * drum.flight_spacing) % 360.0
        held = drum.held_polygon(psi, repose_angle)
        if len(held) >= 3:
            ax.add_patch(Polygon(held, closed=True, fc="#d9a441", ec="#8a6416", lw=0.4))
        pts = drum.flight_outline(psi)
        ax.plot(pts[:, 0], pts[:, 1], color="#333333", lw=1.6, solid_capstyle="round")
        tip_angle = psi + drum.tip_angle
        if show_curtain and 90.0 < tip_angle < 270.0 and psi < psi5:
            rates.append((pts[-1], float(drum.discharge_rate(psi, repose_angle, 1.0))))
    if rates:
        top = max(r for _, r in rates) or 1.0
        for tip, r in rates:
            if r <= 0:
                continue
            x = tip[0]
            y_end = -np.sqrt(max(RF**2 - x**2, 0.0))
            ax.plot([x, x], [tip[1], y_end], color="#b8862d", lw=0.5 + 3.0 * r / top, alpha=0.55)
    if annotate:
        ax.annotate("", xy=(R * 1.12 * np.cos(np.radians(-60)), R * 1.12 * np.sin(np.radians(-60))),
                    xytext=(R * 1.12 * np.cos(np.radians(-100)), R * 1.12 * np.sin(np.radians(-100))),
                    arrowprops=dict(arrowstyle="->", connectionstyle="arc3,rad=0.25", color="k"))
        ax.text(0, -R * 1.22, "rotation (psi from the bottom)", ha="center", fontsize=8)
        ref = drum.flight_outline(angle % 360.0)
        ax.annotate(f"psi = {angle % 360:g} deg", xy=ref[0], xytext=(ref[0] * 1.08), fontsize=8,
                    ha="left" if ref[0][0] >= 0 else "right")
    lim = R * 1.3
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")
    ax.set_axis_off()
    ax.set_title(
        f"R = {R:g} m, {drum.n_flights} flights, repose angle {repose_angle:g} deg", fontsize=10
    )
    return fig


def draw_flight_conventions(drum: FlightedDrum, repose_angle: float = 45.0, *, psi: float = 120.0, ax=None):
    """Close-up of one flight with the conventions of `rotarydryer.geometry` labelled.

    Shows root, bend and tip, ``s1``, ``s2``, ``alpha1`` (inside the pocket), ``alpha2``,
    the material surface at the repose angle through the tip and the held solids.
    """
    from matplotlib.patches import Polygon

    plt = _plt()
    if ax is None:
        fig, ax = plt.subplots(figsize=(6, 5), constrained_layout=True)
    else:
        fig = ax.figure
    R = drum.radius
    held = drum.held_polygon(psi, repose_angle, 400)
    if len(held) >= 3:
        ax.add_patch(Polygon(held, fc="#d9a441", ec="#8a6416"))
    for j in (-1, 0, 1):
        pts = drum.flight_outline(psi + j * drum.flight_spacing)
        ax.plot(pts[:, 0], pts[:, 1], "k-", lw=2)
    a = np.radians(np.linspace(psi - 1.6 * drum.flight_spacing, psi + 2.0 * drum.flight_spacing, 200))
    ax.plot(R * np.sin(a), -R * np.cos(a), "k-", lw=3)
    ax.plot(drum.tip_radius * np.sin(a), -drum.tip_radius * np.cos(a), "--", color="0.5", lw=0.8)
    root, bend, tip = drum.flight_outline(psi)
    scale = max(np.linalg.norm(bend - root), 1e-9)
    inward = -root / np.linalg.norm(root)
    forward = np.array([np.cos(np.radians(psi)), np.sin(np.radians(psi))])
    kw = dict(fontsize=9, ha="center", va="center")
    ax.text(*(root - 0.45 * scale * inward), "root\n(angle psi)", **kw)
    ax.text(*(bend + 0.35 * scale * inward - 0.35 * scale * forward), "bend", **kw)
    ax.text(*(tip + 0.45 * scale * inward), "tip\n(psi + psi_ft)", **kw)
    ax.text(*(0.5 * (root + bend) - 0.3 * scale * forward), "s1", color="b", **kw)
    ax.text(*(0.5 * (bend + tip) + 0.25 * scale * inward - 0.1 * scale * forward), "s2", color="b", **kw)
    ax.text(*(root + 0.25 * scale * inward + 0.45 * scale * forward), "alpha1", color="b", fontsize=8,
            ha="left", va="center")
    ax.text(*(bend + 0.25 * scale * forward + 0.05 * scale * inward), "alpha2", color="b", fontsize=8,
            ha="left", va="center")
    u = np.array([np.cos(np.radians(repose_angle)), np.sin(np.radians(repose_angle))])
    seg = np.array([tip - 0.6 * scale * u, tip + 2.5 * scale * u])
    ax.plot(seg[:, 0], seg[:, 1], "r--", lw=1)
    ax.text(*(tip + 2.5 * scale * u), f" surface at the repose angle ({repose_angle:g} deg)", color="r",
            fontsize=8, ha="left", va="bottom")
    ax.annotate("", xy=root + 2.5 * scale * forward, xytext=root + 1.2 * scale * forward,
                arrowprops=dict(arrowstyle="->", color="k"))
    ax.text(*(root + 2.6 * scale * forward), "rotation", fontsize=8, ha="left")
    span = 4.0 * scale
    c = 0.5 * (root + tip)
    ax.set_xlim(c[0] - span, c[0] + span)
    ax.set_ylim(c[1] - span, c[1] + span)
    ax.set_aspect("equal")
    ax.set_axis_off()
    ax.set_title("psi: root angle from the drum bottom; the drum turns anticlockwise;\n"
                 "the pocket faces the direction of rotation; dashed: flight-tip circle", fontsize=9)
    return fig


def plot_energy_waterfall(terms: dict, *, ax=None, title: str = "Energy balance", unit: str | None = None):
    """Waterfall of an energy balance, MW (kW below 1 MW of input; ``unit`` "W", "kW" or "MW" fixes
    it): inputs stacked up, outputs stepped down.

    ``terms = {"in": {name: W}, "out": {name: W}}`` (e.g.
    ``ThermalSteadyState.energy_terms_w``). The last bar is the closure (in - out), which is
    zero when the balance closes.
    """
    plt = _plt()
    if ax is None:
        fig, ax = plt.subplots(figsize=(7.5, 3.8), constrained_layout=True)
    else:
        fig = ax.figure
    # MW for plants, kW below 1 MW of input (a pilot drum's terms would all read 0.00 MW)
    total_in = sum(terms["in"].values())
    if unit is None:
        unit = "MW" if total_in >= 1e6 else "kW"
    scales = {"MW": 1e6, "kW": 1e3, "W": 1.0}
    if unit not in scales:
        raise ValueError(f"unit = {unit!r}: give 'MW', 'kW' or 'W'")
    scale = scales[unit]
    names, bottoms, heights, colours = [], [], [], []
    level = 0.0
    for name, w in terms["in"].items():
        names.append(name)
        bottoms.append(level)
        heights.append(w / scale)
        colours.append("#c0392b")
        level += w / scale
    for name, w in terms["out"].items():
        level -= w / scale
        names.append(name)
        bottoms.append(level)
        heights.append(w / scale)
        colours.append("#2e86c1")
    names.append("closure (in - out)")
    bottoms.append(0.0)
    heights.append(level)
    colours.append("#7f8c8d")
    x = np.arange(len(names))
    ax.bar(x, heights, bottom=bottoms, color=colours, edgecolor="k", linewidth=0.5)
    for xi, b, h in zip(x, bottoms, heights):
        ax.text(xi, b + h + 0.01 * max(1e-9, max(bottoms) + max(heights)), f"{h:,.0f}" if abs(h) >= 100 else f"{h:.2f}", ha="center", va="bottom",
                fontsize=8)
    ax.set_xticks(x, names, rotation=20, ha="right")
    ax.set_ylabel(unit)
    ax.set_title(title)
    return fig


def plot_heat_duties(duties: dict, *, ax=None, title: str = "Heat duties", unit: str | None = None):
    """Waterfall of the energy audit's heat duties ([`rotarydryer.thermal.audit.heat_duties`][rotarydryer.thermal.audit.heat_duties],
    ``{name: W}``) in ``unit`` (a display unit of power, default the chosen one, `rotarydryer._display`):
    the heat release, then each duty of `rotarydryer.thermal.audit.HEAT_DUTY_PARTS` stepping down to
    zero (the last, the balance closure, is rounding); the exhaust's latent heat (part of the
    evaporation's heat, not a step) is written in the title."""
    plt = _plt()
    u = unit or unit_of("power")
    scale = UNITS["power"][u][0]
    if ax is None:
        fig, ax = plt.subplots(figsize=(7.5, 3.8), constrained_layout=True)
    else:
        fig = ax.figure
    names = [HEAT_DUTY_LABELS["heat_release_W"]]
    bottoms, heights, colours = [0.0], [duties["heat_release_W"] * scale], ["#c0392b"]
    level = heights[0]
    for k in HEAT_DUTY_PARTS:
        v = duties[k] * scale
        level -= v
        names.append(HEAT_DUTY_LABELS[k])
        bottoms.append(level)
        heights.append(v)
        colours.append("#7f8c8d" if k == "heat_duty_closure_W" else "#2e86c1")
    x = np.arange(len(names))
    ax.bar(x, heights, bottom=bottoms, color=colours, edgecolor="k", linewidth=0.5)
    top = max(b + h for b, h in zip(bottoms, heights))
    for xi, b, h in zip(x, bottoms, heights):
        ax.text(xi, max(b, b + h) + 0.01 * top, fmt(h, 3), ha="center", va="bottom", fontsize=8)
    ax.set_xticks(x, names, rotation=25, ha="right")
    ax.set_ylabel(u)
    latent = duties.get("heat_duty_exhaust_latent_W")
    ax.set_title(title if latent is None else f"{title} (exhaust latent heat {fmt(latent * scale, 3)} {u}, "
                                              "part of the evaporation)", fontsize=10)
    return fig


def thermal_profiles_from_results(results) -> dict:
    """The ``profiles`` arrays of `plot_thermal_profiles` from a
    `rotarydryer.results.Results` with thermal datasets."""
    sol, gas = results.datasets["thermal_solids"], results.datasets["thermal_gas"]
    return dict(position=sol.position.values, phase=sol.phase.values, section=sol.section.values,
                solids_temperature_degC=sol.temperature.values, moisture_wet=sol.moisture.values,
                gas_position=gas.position.values, gas_temperature_degC=gas.temperature.values,
                gas_humidity=gas.humidity.values)
