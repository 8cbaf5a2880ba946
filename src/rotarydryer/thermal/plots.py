"""Figures of a heat-and-mass steady state: temperatures, moisture and humidity along the dryer."""

from __future__ import annotations

import numpy as np

from .._plotting import pyplot as _plt
from .schedule import OUTLETS, SCHEDULE_INPUTS

__all__ = ["plot_thermal_profiles", "plot_thermal_steady_state", "plot_schedule_result"]


def plot_thermal_profiles(profiles: dict, *, title: str = "", sections=()):
    """Gas and solids temperature (top), solids moisture and gas humidity (bottom) along the
    dryer; returns the figure.

    ``profiles``: arrays ``position``, ``phase`` (bed, passive, active), ``section``,
    ``solids_temperature_degC``, ``moisture_wet`` per tank and ``gas_position``,
    ``gas_temperature_degC``, ``gas_humidity`` per gas stage, as
    `rotarydryer.thermal.dryer.ThermalSteadyState.profiles` gives them (or
    `thermal_profiles_from_results` from saved results). ``sections``: (name, length m)
    pairs in order, drawn as boundaries.
    """
    plt = _plt()
    p = profiles
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    kinds = np.asarray(p["phase"])
    sec_of = np.asarray(p["section"])
    a1.plot(p["gas_position"], p["gas_temperature_degC"], "r-", label="gas")
    for ph, st in (("bed", "k-"), ("passive", "b-"), ("active", "c--")):
        m = kinds == ph
        if not np.any(m):
            continue
        if ph == "bed":  # one line per unflighted section
            first = np.unique(sec_of[m])[0]
            for sec in np.unique(sec_of[m]):
                mm = m & (sec_of == sec)
                label = "solids (unflighted bed)" if sec == first else None
                a1.plot(p["position"][mm], p["solids_temperature_degC"][mm], st, label=label)
                a2.plot(p["position"][mm], p["moisture_wet"][mm], st, label=label)
        else:
            a1.plot(p["position"][m], p["solids_temperature_degC"][m], st, label=f"solids ({ph})")
            a2.plot(p["position"][m], p["moisture_wet"][m], st, label=f"solids ({ph})")
    a1.set_ylabel("temperature (°C)")
    if title:
        a1.set_title(title)
    a1.legend(fontsize=8)
    a2.set_ylabel("solids moisture (kg/kg wet)")
    ax2 = a2.twinx()
    ax2.plot(p["gas_position"], p["gas_humidity"], "r:", label="gas humidity")
    ax2.set_ylabel("gas humidity (kg/kg dry gas)", color="r")
    a2.set_xlabel("axial position (m)")
    a2.legend(fontsize=8, loc="upper center")
    x0 = 0.0
    for name, length in sections:
        for a in (a1, a2):
            a.axvline(x0, color="0.8", lw=0.8)
        a1.text(x0 + 0.1, a1.get_ylim()[1] * 0.95, str(name), fontsize=9)
        x0 += float(length)
    fig.tight_layout()
    return fig


def plot_thermal_steady_state(steady):
    """Figure: gas and solids temperature (top) and solids moisture / gas humidity (bottom) along
    the dryer for a `rotarydryer.thermal.dryer.ThermalSteadyState`
    (`plot_thermal_profiles` of ``steady.profiles()``, titled with the product state and
    with the section boundaries). Also importable from `rotarydryer.report.plots`."""
    title = (f"{steady.dryer.settings.mode} model: product {steady.product_moisture:.3f} kg/kg, "
             f"{steady.product_temperature_degC:.1f} °C; gas out {steady.gas_outlet_temperature_degC:.0f} °C")
    return plot_thermal_profiles(steady.profiles(), title=title,
                                 sections=[(sd["name"], sd["length"]) for sd in steady.dryer.model.sections])


def plot_schedule_result(result, *, title: str = ""):
    """Figure of a scheduled dynamic run
    ([`ScheduleResult`][rotarydryer.thermal.schedule.ScheduleResult]): the scheduled inputs (held
    over each interval, drawn as steps) above the product moisture, product and exhaust
    temperatures versus time (min)."""
    plt = _plt()
    t_min = np.asarray(result.time_s) / 60.0
    n_in = max(1, len(result.inputs))
    fig, axes = plt.subplots(n_in + 2, 1, figsize=(8.0, 2.0 * (n_in + 2)), sharex=True)
    for ax, (name, values) in zip(axes[:n_in], result.inputs.items()):
        ax.step(t_min, values, where="post", color="tab:red")
        ax.set_ylabel(f"{name}\n{SCHEDULE_INPUTS[name][1]}", fontsize=8)
    if not result.inputs:
        axes[0].text(0.5, 0.5, "no scheduled input (the case's own)", ha="center", va="center",
                     transform=axes[0].transAxes)
    ax = axes[n_in]
    ax.plot(t_min, 100.0 * np.asarray(result.outlets["product_moisture"]), color="tab:blue")
    ax.set_ylabel("product moisture\n% wet basis", fontsize=8)
    ax = axes[n_in + 1]
    ax.plot(t_min, result.outlets["product_temperature"], label="product")
    ax.plot(t_min, result.outlets["exhaust_temperature"], label="exhaust gas")
    ax.set_ylabel(f"temperature\n{OUTLETS['product_temperature']}", fontsize=8)
    ax.legend(fontsize=8)
    ax.set_xlabel("time, min")
    if title:
        axes[0].set_title(title)
    fig.tight_layout()
    return fig


def cumulative_passing(edges, fractions, diameters):
    """``(sizes m, % passing)`` of classes (edges, masses, medians): the points of
    `rotarydryer.properties.psd.percentile_diameter`'s curve, for a plot."""
    e = np.asarray(edges, float)
    w = np.asarray(fractions, float)
    total = float(w.sum())
    if total <= 0:
        return np.array([]), np.array([])
    cum = np.concatenate([[0.0], np.cumsum(w) / total])
    x = np.empty(2 * w.size + 1)
    y = np.empty_like(x)
    x[0::2], y[0::2] = e, cum
    x[1::2], y[1::2] = np.asarray(diameters, float), 0.5 * (cum[:-1] + cum[1:])
    return x, 100.0 * y


def plot_size_distributions(steady, *, title: str = ""):
    """Feed, product and dust size distributions of a steady state with size classes
    (`plot_size_classes`)."""
    dr = steady.dryer
    rows = steady.size_class_table()
    d = steady.terms
    return plot_size_classes(dr.size_classes.edges, dr.size_classes.diameters, dr.class_feed,
                             np.atleast_1d(d["product_S_c"]), np.atleast_1d(d["dust_S_c"]),
                             [r["product_moisture_kg_kg"] for r in rows], [r["lost_as_dust"] for r in rows], title=title)


def plot_size_classes(edges, diameters, feed, product, dust, moisture, lost, *, title: str = ""):
    """Feed, product and dust size distributions (cumulative mass % passing against size, log axis;
    class masses on the feed's class ``edges`` with their median ``diameters``, m) and each class's
    product moisture (kg/kg wet, None where it has no product) and share lost as dust (-)."""
    plt = _plt()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 3.8), constrained_layout=True)
    for label, w, style in (("feed", feed, "k-"), ("product", product, "b-"), ("dust", dust, "r--")):
        x, y = cumulative_passing(edges, w, diameters)
        if x.size:
            a1.plot(x * 1e6, y, style, label=label)
    a1.set_xscale("log")
    a1.set_xlabel("particle size (um)")
    a1.set_ylabel("cumulative mass passing (%)")
    a1.set_ylim(0, 100)
    a1.grid(alpha=0.3, which="both")
    a1.legend(fontsize=8)
    dia = np.asarray(diameters, float) * 1e6
    a2.plot(dia, [np.nan if m is None else 100 * m for m in moisture], "bo-")
    a2.set_xscale("log")
    a2.set_xlabel("class diameter (um)")
    a2.set_ylabel("product moisture (% wet)", color="b")
    a3 = a2.twinx()
    a3.plot(dia, 100 * np.asarray(lost, float), "rs--")
    a3.set_ylabel("lost as dust (% of the class)", color="r")
    a3.set_ylim(-2, 102)
    a2.grid(alpha=0.3, which="both")
    for ax in (a1, a2):
        plain_log_ticks(ax)
    if title:
        fig.suptitle(title, fontsize=10)
    return fig


def plain_log_ticks(ax) -> None:
    """Label a log x axis with plain numbers (150, 200, 300) rather than powers of ten; the minor
    ticks only where the axis spans less than a decade (call after plotting)."""
    from matplotlib.ticker import FuncFormatter, NullFormatter

    fmt = FuncFormatter(lambda v, _pos: f"{v:g}")
    lo, hi = ax.get_xlim()
    ax.xaxis.set_major_formatter(fmt)
    ax.xaxis.set_minor_formatter(fmt if 0 < lo and hi < 10 * lo else NullFormatter())
