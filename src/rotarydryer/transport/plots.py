"""Plots of transport results: holdup profile along the dryer and RTD against data.

Matplotlib is imported inside the functions (Agg backend when none is chosen).
Views only: nothing here recomputes physics.
"""

from __future__ import annotations

import numpy as np

from .._plotting import pyplot as _plt

__all__ = ["plot_holdup_profile", "plot_rtd", "plot_measured_rtd"]


def plot_holdup_profile(steady, ax=None):
    """Holdup per metre (kg/m) along the dryer: active, flight-borne (up to the design
    load), kilning bed and unflighted bed.  Returns the figure."""
    plt = _plt()
    fig, ax = (ax.figure, ax) if ax is not None else plt.subplots(figsize=(8, 4))
    m = steady.model
    x0 = 0.0
    for sec in m.sections:
        sel = steady.section == sec["name"]
        dz = sec["length"] / sec["n_cells"]
        if sec["kind"] == "flighted":
            p = np.where(sel & (steady.phase == "passive"))[0]
            a = np.where(sel & (steady.phase == "active"))[0]
            des = m.design_load[p]
            flighted = np.minimum(steady.masses[p], des)
            kiln = np.maximum(steady.masses[p] - des, 0.0)
            x = x0 + (np.arange(p.size) + 0.5) * dz
            ax.step(x, flighted / dz, where="mid", color="C0", label="flight-borne")
            ax.step(x, kiln / dz, where="mid", color="C3", label="kilning bed")
            ax.step(x, steady.masses[a] / dz, where="mid", color="C1", label="active (curtain)")
        else:
            b = np.where(sel & (steady.phase == "bed"))[0]
            x = x0 + (np.arange(b.size) + 0.5) * dz
            ax.plot(x, steady.masses[b] / dz, color="C2", label="unflighted bed")
        ax.axvline(x0, color="0.8", lw=0.8)
        x0 += sec["length"]
    h, lab = ax.get_legend_handles_labels()
    uniq = dict(zip(lab, h))
    ax.legend(uniq.values(), uniq.keys(), fontsize=8)
    ax.set_xlabel("axial position from the feed end (m)")
    ax.set_ylabel("holdup (kg/m)")
    ax.set_title(f"{m.name}: total {steady.total_holdup:,.0f} kg, MRT {steady.mean_residence_time / 60:.2f} min")
    fig.tight_layout()
    return fig


def plot_rtd(rtd, measured=None, ax=None, label="model", baseline=0.0):
    """E(t) (1/min) against time (min) of a simulated RTD, with measured points
    ``measured = (t s, signal)`` if given (``baseline`` subtracted, clipped at 0,
    normalised by the integral).  Returns the figure."""
    plt = _plt()
    fig, ax = (ax.figure, ax) if ax is not None else plt.subplots(figsize=(7, 4))
    r = rtd.response
    ax.plot(r.time / 60, r.exit_age * 60, label=f"{label}: mean {rtd.tracer_mean / 60:.2f} min, "
                                               f"SD {rtd.tracer_std / 60:.2f} min")
    if measured is not None:
        plot_measured_rtd(ax, measured[0], measured[1], baseline)
    ax.set_xlabel("time since injection start (min)")
    ax.set_ylabel("E(t) (1/min)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def plot_measured_rtd(ax, time_s, signal, baseline=0.0, **style):
    """Measured tracer points on ``ax`` as E(t) (1/min): ``baseline`` (signal units) removed,
    normalised by the area; the legend gives the mean and SD from
    :func:`rotarydryer.rtd.rtd_moments` (the same moments as ``rotarydryer rtd``)."""
    from ..rtd import rtd_moments

    t = np.asarray(time_s, float)
    m = rtd_moments(t, signal, baseline=float(baseline))
    e = np.clip(np.asarray(signal, float) - m.baseline, 0.0, None) / m.area
    style.setdefault("ms", 4)
    ax.plot(t / 60, e * 60, "o", label=f"measured: mean {m.mean_s / 60:.2f} min, SD {m.std_s / 60:.2f} min"
            + (f" (baseline {m.baseline:.3g} removed)" if m.baseline else ""), **style)
