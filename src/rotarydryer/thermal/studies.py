r"""Studies with the thermal dryer model: sensitivity indices, fouling, insulation and fuel, step responses.

* [`relative_index`][rotarydryer.thermal.studies.relative_index] - Ajayi (2011) Eq. 7.1 (after Duchesne et al. 1997):
  $\eta = \dfrac{(\psi-\psi_{ref})/\psi_{ref}}{(\chi-\chi_{ref})/\chi_{ref}}$, outputs ψ =
  product moisture (kg/kg wet) and product temperature **in °C** (as the thesis), inputs χ in
  the thesis's units (°C, kg/kg, rpm, kg/s).
* [`sensitivity_table`][rotarydryer.thermal.studies.sensitivity_table] - Tables 7.1-7.5 of Ajayi (2011): the input changes of l.2364-2366
  (gas inlet T +10 %, gas inlet humidity -30 %, speed -30 %, solids inlet T +30 %, feed -20 %)
  at fouling 0/40/60/80 % (fraction of flight loading capacity lost, see
  [`ThermalSettings`][rotarydryer.thermal.dryer.ThermalSettings]) and the overloaded feed 63.89 kg/s.
* [`fouling_study`][rotarydryer.thermal.studies.fouling_study], [`insulation_study`][rotarydryer.thermal.studies.insulation_study] (Ajayi (2011) Sec. 7.2: lagging, then a lower gas
  inlet temperature for the same product moisture -> fuel saved, with the burner of App. A).
* [`step_response`][rotarydryer.thermal.studies.step_response] and [`fopdt_fit`][rotarydryer.thermal.studies.fopdt_fit] - gain K, dead time θ and time constant τ of a
  first-order-plus-dead-time description (two-point method: θ = t(5 %) , τ = t(63.2 %) - θ,
  times from the step; Seborg et al. 2011 §7.2 use t28/t63 - the 5 % point is used here because
  the responses are S-shaped with a long transport delay).
"""

from __future__ import annotations

import copy

import numpy as np

from .._validation import check_choice, check_range
from .dryer import ThermalDryer, ThermalSteadyState

__all__ = ["relative_index", "INPUTS", "perturbed", "sensitivity_table", "fouling_study", "insulation_study",
           "step_response", "fopdt_fit"]

#: input name -> (attribute holder, attribute, relative change of Ajayi l.2364-2366)
INPUTS = {
    "gas_inlet_temperature": ("settings", "gas_inlet_temperature", +0.10),
    "gas_inlet_humidity": ("settings", "gas_inlet_humidity", -0.30),
    "rotational_speed": ("dryer", "rpm", -0.30),
    "solid_inlet_temperature": ("settings", "solids_inlet_temperature", +0.30),
    "solid_feed_rate": ("dryer", "feed_rate", -0.20),
}


#: the names the case and the input schedules give two of `INPUTS` (``dynamics(feed_rate=3)`` was "unknown input")
INPUT_ALIASES = {"feed_rate": "solid_feed_rate", "rpm": "rotational_speed"}


def relative_index(output, output_ref, input_, input_ref):
    """Relative (steady-state) index η, Ajayi (2011) Eq. 7.1 (dimensionless, vectorised).

    >>> round(float(relative_index(0.12, 0.124, 550.0, 500.0)), 4)
    -0.3226
    """
    y = np.asarray(output, float)
    y0 = check_range("output_ref", output_ref, -np.inf, np.inf)
    u = np.asarray(input_, float)
    u0 = check_range("input_ref", input_ref, -np.inf, np.inf)
    if np.any(y0 == 0) or np.any(u0 == 0) or np.any(u == u0):
        raise ValueError("relative_index: output_ref and input_ref must be non-zero and input_ != input_ref")
    return ((y - y0) / y0) / ((u - u0) / u0)


def _get(dryer, name):
    holder, attr, _ = INPUTS[name]
    return getattr(dryer.settings if holder == "settings" else dryer, attr)


def perturbed(dryer: ThermalDryer, **changes) -> ThermalDryer:
    """A copy of ``dryer`` with inputs changed (names of `INPUTS` or ThermalSettings fields)."""
    settings = copy.copy(dryer.settings)
    values = {}
    for k, v in changes.items():
        k = INPUT_ALIASES.get(k, k)
        if k in INPUTS:
            holder, attr, _ = INPUTS[k]
            try:
                x = float(v)
            except (TypeError, ValueError):     # "could not convert string to float: 'a'" named no input
                raise ValueError(f"{k} = {v!r} is not a number") from None
            if holder == "settings":
                setattr(settings, attr, x)
            else:
                values[attr] = x
        elif hasattr(settings, k):
            setattr(settings, k, v)
        else:
            raise ValueError(f"unknown input {k!r}; use one of {', '.join([*INPUTS, *INPUT_ALIASES])} or a "
                             "ThermalSettings field")
    base = dryer.rebuilt(settings, **values)         # the network rebuilt where it depends on a changed input
    return base.with_parameters(settings=settings, **values)


def sensitivity_table(dryer: ThermalDryer, foulings=(0.0, 0.4, 0.6, 0.8), overload_feed=63.89, inputs=None):
    """Relative indices of product moisture and temperature (°C), Ajayi (2011) Tables 7.1-7.5.

    Returns a list of dicts (input_variable, input_change, solid_feed_kg_s, scaling_pct,
    eta_product_moisture, eta_product_temperature). Steady states are continued from the
    reference state of each row.
    """
    rows = []
    cases = [(f, dryer.feed_rate) for f in foulings] + ([(0.0, overload_feed)] if overload_feed else [])
    for fouling, feed in cases:
        ref_dr = perturbed(dryer, fouling=fouling, solid_feed_rate=feed)
        ref = ref_dr.steady_state()
        for name in (inputs or INPUTS):
            if name == "solid_feed_rate" and feed != dryer.feed_rate:
                continue
            rel = INPUTS[name][2]
            u0 = _get(ref_dr, name)
            d2 = perturbed(ref_dr, **{name: u0 * (1 + rel)})
            ss = d2.steady_state(z0=ref.state, factorization=ref.factorization)    # chord steps from the reference
            rows.append(dict(input_variable=name, input_change=f"{rel:+.0%}", solid_feed_kg_s=feed,
                             scaling_pct=round(100 * fouling),
                             eta_product_moisture=float(relative_index(ss.product_moisture, ref.product_moisture,
                                                                       u0 * (1 + rel), u0)),
                             eta_product_temperature=float(relative_index(ss.product_temperature_degC,
                                                                          ref.product_temperature_degC,
                                                                          u0 * (1 + rel), u0))))
    return rows


def fouling_study(dryer: ThermalDryer, foulings=(0.0, 0.2, 0.4, 0.6, 0.8)):
    """Product moisture/temperature, gas outlet T, holdups and fuel vs fouling (0-80 %): list of dicts."""
    out = []
    z = lu = None
    for f in foulings:
        check_range("fouling", f, 0.0, 0.95, low_inclusive=True, high_inclusive=True)
        ss = perturbed(dryer, fouling=f).steady_state(z0=z, factorization=lu)     # from the last one (chord steps)
        z, lu = ss.state, ss.factorization
        out.append(dict(fouling_pct=100 * f, **ss.summary()))
    return out


def _moisture_at(dryer, t_in, z0):
    return perturbed(dryer, gas_inlet_temperature=t_in).steady_state(z0=z0)


def insulation_study(dryer: ThermalDryer, insulation_thickness=0.1, insulation_conductivity=0.07,
                     reduced_inlet_temperature=350.0):
    """Ajayi (2011) Sec. 7.2: lag the shell, then lower the gas inlet temperature to keep the product moisture.

    Returns a dict with the bare reference, the insulated dryer at the same inlet temperature,
    the insulated dryer at ``reduced_inlet_temperature`` (Ajayi: 350 °C) and at the inlet
    temperature that restores the reference product moisture (found by secant iteration), each
    with its burner fuel rate (kg/s), and the fuel saved (kg/h and %).
    """
    ref = dryer.steady_state()
    ins = perturbed(dryer, insulation_thickness=insulation_thickness,
                    insulation_conductivity=insulation_conductivity)
    same = ins.steady_state(z0=ref.state)
    low = _moisture_at(ins, reduced_inlet_temperature, same.state)
    # secant on the inlet temperature for the reference product moisture
    t0, t1 = dryer.settings.gas_inlet_temperature, reduced_inlet_temperature
    f0 = same.product_moisture - ref.product_moisture
    f1 = low.product_moisture - ref.product_moisture
    ss1, z = low, low.state
    for _ in range(12):
        if abs(f1) < 1e-6 or f1 == f0:
            break
        t2 = float(np.clip(t1 - f1 * (t1 - t0) / (f1 - f0), 150.0, 600.0))
        ss2 = _moisture_at(ins, t2, z)
        t0, f0, t1, f1, ss1, z = t1, f1, t2, ss2.product_moisture - ref.product_moisture, ss2, ss2.state
    fuel_ref = ref.fuel_rate()
    fuel_match = ss1.fuel_rate()
    return dict(reference=ref.summary(), insulated_same_inlet=same.summary(),
                insulated_reduced_inlet=dict(gas_inlet_temperature_degC=reduced_inlet_temperature, **low.summary()),
                insulated_matched=dict(gas_inlet_temperature_degC=t1, **ss1.summary()),
                fuel_saved_kg_h=3600 * (fuel_ref - fuel_match),
                fuel_saved_pct=100 * (fuel_ref - fuel_match) / fuel_ref,
                fuel_saved_reduced_inlet_kg_h=3600 * (fuel_ref - low.fuel_rate()))


def fopdt_fit(time, response, gain_input_change, y0=None, dead_fraction=0.05):
    """Gain, dead time and time constant of a step response (two-point FOPDT method; see module docstring).

    ``response`` sampled at ``time`` (s) from the step at t = 0; returns dict(gain, dead_time_s,
    time_constant_s, final_change). Raises ``ValueError`` if the response has not moved.
    """
    t = np.asarray(time, float)
    y = np.asarray(response, float)
    y0 = y[0] if y0 is None else y0
    dy = y[-1] - y0
    if abs(dy) < 1e-12 * max(1.0, abs(y0)):
        raise ValueError("step response: the output did not change")
    frac = (y - y0) / dy

    def crossing(level):
        i = int(np.argmax(frac >= level))
        if i == 0:
            return t[0]
        return t[i - 1] + (level - frac[i - 1]) * (t[i] - t[i - 1]) / (frac[i] - frac[i - 1])
    theta = crossing(dead_fraction)
    tau = crossing(0.632) - theta
    return dict(gain=dy / gain_input_change, dead_time_s=float(theta), time_constant_s=float(tau),
                final_change=float(dy))


def step_response(dryer: ThermalDryer, steady: ThermalSteadyState, input_name: str, relative_change: float,
                  duration=7200.0, dt=30.0):
    """Step an input at t = 0 from ``steady`` and integrate ``duration`` s (BDF, sparse).

    Returns dict(time, product_moisture, product_temperature_c, gas_outlet_temperature_c, and per output
    the FOPDT fit: gain (output units per input unit), dead time, time constant), plus wall time.
    """
    check_choice("input_name", input_name, INPUTS)
    u0 = _get(dryer, input_name)
    d2 = perturbed(dryer, **{input_name: u0 * (1 + relative_change)})
    t_eval = np.arange(0.0, duration + dt / 2, dt)
    res = d2.simulate(steady.state, duration, t_eval=t_eval)
    du = u0 * relative_change
    out = dict(input=input_name, input_change=du, time=res.time, product_moisture=res.product_moisture,
               product_temperature_c=res.product_temperature_degC,
               gas_outlet_temperature_c=res.gas_outlet_temperature_degC, seconds=res.seconds, nfev=res.nfev)
    for key in ("product_moisture", "product_temperature_c", "gas_outlet_temperature_c"):
        try:
            out[key + "_fopdt"] = fopdt_fit(res.time, out[key], du)
        except ValueError:
            out[key + "_fopdt"] = None
    return out
