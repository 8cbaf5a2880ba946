"""Plots of transport results: holdup profile along the dryer and RTD against data.

The one drawing of each figure: `rotarydryer.report.figures.plot_holdup_profile` and
`plot_rtd` (from a saved
[`rotarydryer.results.Results`][rotarydryer.results.Results]) and the functions here (from a live steady state or
tracer RTD) pass their arrays to [`holdup_profile_figure`][rotarydryer.transport.plots.holdup_profile_figure] and [`rtd_figure`][rotarydryer.transport.plots.rtd_figure].

Matplotlib is imported inside the functions (Agg backend when none is chosen).
Views only: nothing here recomputes physics.
"""

from __future__ import annotations

import numpy as np

from .._plotting import pyplot as _plt

__all__ = ["plot_holdup_profile", "plot_rtd", "plot_measured_rtd", "holdup_profile_figure", "rtd_figure"]


def plot_holdup_profile(steady, ax=None, name=None):
    """Holdup per metre (kg/m) along the dryer of a steady state: airborne (curtain),
    flight-borne (up to the design load), kilning bed and unflighted bed; ``name`` (default the
    model's) heads the title, with the state's total holdup.  Returns the figure."""
    m = steady.model
    sections = [(s["name"], s["kind"], s["length"], s["n_cells"]) for s in m.sections]
    return holdup_profile_figure(sections, steady.position, steady.phase, steady.section, steady.masses,
                                 steady.design_load, total_kg=steady.total_holdup,
                                 holdup_over_flow_s=steady.mean_residence_time, name=name or m.name, ax=ax)


def plot_rtd(rtd, measured=None, ax=None, label="model", baseline=0.0):
    """E(t) (1/min) against time (min) of a simulated RTD, with measured points
    ``measured = (t s, signal)`` if given (``baseline`` subtracted, clipped at 0,
    normalised by the integral).  Returns the figure."""
    r = rtd.response
    return rtd_figure(r.time, r.exit_age, rtd.tracer_mean, rtd.tracer_std, measured=measured,
                      baseline=baseline, label=label, ax=ax)


def holdup_profile_figure(sections, position, phase, section, holdup, design_load, *, total_kg,
                          holdup_over_flow_s, name="Holdup profile", ax=None):
    """Holdup per metre (kg/m) along the dryer from per-node arrays.

    ``sections``: ``(name, kind, length m, n_cells)`` in axial order from the feed end;
    ``position`` (m), ``phase`` (active, passive, bed), ``section``, ``holdup`` (kg) and
    ``design_load`` (kg, used on passive nodes) per network node.  Flighted sections show
    the flight-borne holdup up to the design load, the kilning bed (the surplus) and the
    airborne curtain; unflighted sections the bed.  The title gives ``name``, the total
    holdup and H/F.  Returns the figure.
    """
    plt = _plt()
    fig, ax = (ax.figure, ax) if ax is not None else plt.subplots(figsize=(8, 3.6), constrained_layout=True)
    position, phase, section = np.asarray(position, float), np.asarray(phase), np.asarray(section)
    holdup, design_load = np.asarray(holdup, float), np.asarray(design_load, float)
    labelled = set()
    x0 = 0.0
    for sec_name, kind, length, n_cells in sections:
        sec_name, x1 = str(sec_name), x0 + float(length)
        sel = section == sec_name
        step = float(length) / int(n_cells)

        def _line(mask, values, colour, label, style="step"):
            x = position[mask]
            order = np.argsort(x)
            lab = label if label not in labelled else None
            labelled.add(label)
            if style == "step":
                ax.step(x[order], values[order] / step, where="mid", color=colour, label=lab)
            else:
                ax.plot(x[order], values[order] / step, color=colour, label=lab)

        if kind == "flighted":
            p = sel & (phase == "passive")
            a = sel & (phase == "active")
            m, des = holdup[p], design_load[p]
            _line(p, np.minimum(m, des), "C0", "flight-borne")
            _line(p, np.maximum(m - des, 0.0), "C3", "kilning bed")
            _line(a, holdup[a], "C1", "airborne (curtain)")
        else:
            b = sel & (phase == "bed")
            _line(b, holdup[b], "C2", "unflighted bed", style="line")
        ax.axvline(x0, color="0.85", lw=0.8)
        ax.text(0.5 * (x0 + x1), 1.0, sec_name, transform=ax.get_xaxis_transform(), ha="center", va="bottom",
                fontsize=8)
        x0 = x1
    ax.legend(fontsize=8, loc="best")
    ax.set_xlabel("axial position from the feed end (m)")
    ax.set_ylabel("holdup (kg/m)")
    ax.set_title(f"{name}: total {total_kg:,.0f} kg, H/F {holdup_over_flow_s / 60:.2f} min", fontsize=10, pad=14)
    return fig


def rtd_figure(time_s, exit_age_per_s, mean_s, std_s, *, measured=None, baseline=0.0, label="model", ax=None):
    """E(t) (1/min) against time (min) of a simulated tracer curve (legend: ``label``, mean
    and SD), with the measured points ``measured = (t s, signal)`` if given (see
    [`plot_measured_rtd`][rotarydryer.transport.plots.plot_measured_rtd]).  Returns the figure."""
    plt = _plt()
    fig, ax = (ax.figure, ax) if ax is not None else plt.subplots(figsize=(7, 3.6), constrained_layout=True)
    ax.plot(np.asarray(time_s, float) / 60, np.asarray(exit_age_per_s, float) * 60,
            label=f"{label}: mean {mean_s / 60:.2f} min, SD {std_s / 60:.2f} min")
    if measured is not None:
        plot_measured_rtd(ax, measured[0], measured[1], baseline, color="k", ms=3.5)
    ax.set_xlabel("time since injection start (min)")
    ax.set_ylabel("E(t) (1/min)")
    ax.set_title("Residence-time distribution", fontsize=10)
    ax.legend(fontsize=8)
    return fig


def plot_measured_rtd(ax, time_s, signal, baseline=0.0, **style):
    """Measured tracer points on ``ax`` as E(t) (1/min): ``baseline`` (signal units) removed,
    normalised by the area; the legend gives the mean and SD from
    [`rotarydryer.rtd.rtd_moments`][rotarydryer.rtd.rtd_moments] (the same moments as ``rotarydryer rtd``)."""
    from ..rtd import rtd_moments

    t = np.asarray(time_s, float)
    m = rtd_moments(t, signal, baseline=float(baseline))
    e = np.clip(np.asarray(signal, float) - m.baseline, 0.0, None) / m.area
    style.setdefault("ms", 4)
    ax.plot(t / 60, e * 60, "o", label=f"measured: mean {m.mean_s / 60:.2f} min, SD {m.std_s / 60:.2f} min"
            + (f" (baseline {m.baseline:.3g} removed)" if m.baseline else ""), **style)
