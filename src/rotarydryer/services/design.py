"""Duty and search options of ``rotarydryer design`` and of the web app's Design page."""

from __future__ import annotations

from ._options import check_option

__all__ = ["design_limits", "design_duty"]

_PRESETS = ("raw_sugar", "mmg")


def design_limits(objective="volume", speed_fraction=0.5, entrainment_fraction=1.0, gas_velocity_max=5.0,
                  fill_max=0.15, design_load_tolerance=0.15, ld_min=4.0, ld_max=10.0, d_min=0.5, d_max=6.0,
                  ua_factor=1.0, top=8, rounds=5):
    """The checked search options of ``rotarydryer design`` as `rotarydryer.design.Limits`
    (``ValueError`` naming the option; the web app calls this too, for the same messages)."""
    from .. import design as D

    if objective not in D.OBJECTIVES:
        raise ValueError(f"--objective = {objective!r} is not one of {', '.join(D.OBJECTIVES)}")
    check_option("--speed-fraction", speed_fraction, 0.0, 1.0)
    check_option("--entrainment-fraction", entrainment_fraction, 0.0, 2.0, high_inclusive=True)
    check_option("--gas-velocity-max", gas_velocity_max, 0.0, 100.0, unit="m/s")
    check_option("--fill-max", fill_max, 0.0, 0.5, high_inclusive=True)
    check_option("--design-load-tolerance", design_load_tolerance, 0.0, 10.0, high_inclusive=True)
    check_option("--ld-min", ld_min, 0.5, 50.0, high_inclusive=True)
    check_option("--ld-max", ld_max, ld_min, 50.0, low_inclusive=True, high_inclusive=True)
    check_option("--d-min", d_min, 0.05, 20.0, high_inclusive=True, unit="m")
    check_option("--d-max", d_max, d_min, 20.0, low_inclusive=True, high_inclusive=True, unit="m")
    check_option("--ua-factor", ua_factor, 0.0, 100.0)
    check_option("--top", top, 1, 100, low_inclusive=True, high_inclusive=True)
    check_option("--rounds", rounds, 1, 10, low_inclusive=True, high_inclusive=True)
    return D.Limits(speed_fraction_max=speed_fraction, entrainment_fraction=entrainment_fraction,
                    gas_velocity_max=gas_velocity_max, fill_max=fill_max,
                    design_load_tolerance=design_load_tolerance, length_to_diameter=(ld_min, ld_max),
                    diameter_range=(d_min, d_max), ua_factor=ua_factor).validate()


def design_duty(duty=None, material=None, feed=None, moisture_in=None, moisture_out=None, gas_in=None,
                gas_flow=None, ntu=None, direction=None, feed_temperature=None, max_fuel=None):
    """The validated `rotarydryer.design.Duty` of ``rotarydryer design``'s duty options (a
    preset overridden by the options given; ``ValueError`` naming the option; the web app calls
    this too, for the same messages)."""
    from .. import design as D

    presets = {"raw_sugar": D.raw_sugar_duty, "mmg": D.mmg_duty}
    if duty is not None and duty not in presets:
        raise ValueError(f"--duty = {duty!r} is not one of {', '.join(_PRESETS)}")
    given = {k: v for k, v in dict(material=material, feed_rate=feed, moisture_in=moisture_in,
                                   moisture_out=moisture_out, gas_inlet_temperature=gas_in, gas_flow=gas_flow,
                                   ntu=ntu, direction=direction, feed_temperature=feed_temperature,
                                   max_fuel_rate=max_fuel).items() if v is not None}
    if ntu is not None and gas_flow is not None:
        raise ValueError(f"--gas-flow = {gas_flow:g} kg/s and --ntu = {ntu:g}: give one (the gas flow fixes the transfer "
                         "units; --ntu sizes the gas flow when it is free)")
    if ntu is not None:
        given["gas_flow"] = None
    names = {"material": "--material", "feed_rate": "--feed", "moisture_in": "--moisture-in",
             "moisture_out": "--moisture-out", "gas_inlet_temperature": "--gas-in", "gas_flow": "--gas-flow",
             "ntu": "--ntu", "direction": "--direction", "feed_temperature": "--feed-temperature",
             "max_fuel_rate": "--max-fuel"}
    if duty is None:
        need = [names[k] for k in ("material", "feed_rate", "moisture_in", "moisture_out", "gas_inlet_temperature")
                if k not in given]
        if need:
            raise ValueError("missing " + ", ".join(need) + " (or give --duty raw_sugar|mmg)")
        d = D.Duty(**given)
    else:
        d = presets[duty](**given)
    try:
        d.validate()
    except ValueError as exc:   # name the option, not the field
        msg = str(exc)
        for k, opt in names.items():
            msg = msg.replace(k + " =", opt + " =")
        raise ValueError(msg) from None
    return d
