"""Figures of a heat-and-mass steady state: temperatures, moisture and humidity along the dryer."""

from __future__ import annotations

import numpy as np

from .._plotting import pyplot as _plt

__all__ = ["plot_thermal_profiles", "plot_thermal_steady_state"]


def plot_thermal_profiles(profiles: dict, *, title: str = "", sections=()):
    """Gas and solids temperature (top), solids moisture and gas humidity (bottom) along the
    dryer; returns the figure.

    ``profiles``: arrays ``position``, ``phase`` (bed, passive, active), ``section``,
    ``solids_temperature_degC``, ``moisture_wet`` per tank and ``gas_position``,
    ``gas_temperature_degC``, ``gas_humidity`` per gas stage, as
    :meth:`rotarydryer.thermal.dryer.ThermalSteadyState.profiles` gives them (or
    :func:`thermal_profiles_from_results` from saved results). ``sections``: (name, length m)
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
    the dryer for a :class:`rotarydryer.thermal.dryer.ThermalSteadyState`
    (:func:`plot_thermal_profiles` of ``steady.profiles()``, titled with the product state and
    with the section boundaries). Also importable from :mod:`rotarydryer.report.plots`."""
    title = (f"{steady.dryer.settings.mode} model: product {steady.product_moisture:.3f} kg/kg, "
             f"{steady.product_temperature_degC:.1f} °C; gas out {steady.gas_outlet_temperature_degC:.0f} °C")
    return plot_thermal_profiles(steady.profiles(), title=title,
                                 sections=[(sd["name"], sd["length"]) for sd in steady.dryer.model.sections])
