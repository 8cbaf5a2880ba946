r"""Closed-loop control of the dynamic coupled dryer model (PI feedback + feed-forward).

The plant is `ThermalDryer`: one BDF integration runs the whole closed loop
([`DryerIntegrator`][rotarydryer.thermal.schedule.DryerIntegrator]), stopping at every sample, where
the controller's new inputs (`perturbed`) take over with the integrator's history kept (no restart
per sample), so the controller sees a sampled, dead-time-delayed measurement of the nonlinear model.

Structure (Ajayi (2011) Ch. 7 targets: product moisture at most 12 % wet basis, product
temperature 45-50 degC; the plant's DCS uses a *feed-forward* on the water to remove):

* **Controlled variable** (measured, sampled every ``sample_time_s``, delayed by
  ``measurement_dead_time_s``): ``product_moisture`` (kg/kg wet) or ``exhaust_temperature``
  (degC).
* **Manipulated variables** in split range: first the gas inlet temperature (burner; the fuel
  rate of the case's burner is reported at every sample), then - when it saturates and
  ``feed_backup`` is on - the solids feed rate is *reduced* (Ajayi (2011) l.2420: "reducing the
  solids feed" as the manipulated variable of scaled or overloaded dryers). The PI output ``v``
  is in units of the controlled variable ("y-equivalent"): each range is normalised by its
  identified steady-state gain, so the loop gain is 1 in either range (gain scheduling).
* **PI** in velocity form (Seborg et al. 2011 Ch. 8, incremental form):
  $\Delta v_k = K_c\,[(e_k-e_{k-1}) + (T_s/\tau_I)\,e_k]$, output clipped to the
  ranges, which is its anti-windup (the stored output never leaves the limits).
* **Feed-forward** from the measured feed moisture (dry basis) and feed rate (Ajayi's DCS logic:
  the water to remove sets the heat demand). ``"model"`` (default): the static feed-forward
  $v_{ff}$ that the steady state of the model itself needs to hold the setpoint at the
  measured disturbance (secant iteration on steady states, cached); ``"linear"``:
  $v_{ff} = -(K_{d,x}\,\Delta X_{feed} + K_{d,F}\,\Delta F_{feed})$ from the FOPDT gains
  (Seborg et al. 2011 Ch. 15, static design). Dynamic compensation (Seborg et al. 2011 Ch. 15: lead-lag and delay)
  is replaced by one delay that matches the times to half response, $\theta+\tau\ln 2$,
  of the disturbance path and of the slowest manipulated path (a lead-lag kicks the
  saturating split range too hard).
* **Tuning**: FOPDT models (gain K, dead time θ, time constant τ) from step responses of the
  dynamic model (as `rotarydryer.thermal.studies.step_response`, with the feed moisture
  and the exhaust temperature added; two-point fit `fopdt_fit`)
  and the SIMC rules of Skogestad (2003),
  "Simple analytic rules for model reduction and PID controller tuning", J. Process Control 13,
  291-309, SIMC PI rule: $K_c = \tau / (K(\tau_c+\theta))$,
  $\tau_I = \min(\tau, 4(\tau_c+\theta))$, with $\tau_c = \theta$ (the "tight but
  robust" choice). Sampling and the measurement dead time are added to θ (half the sample
  time for the zero-order hold, Skogestad 2003 Sec. 3.2).
* **Stability check**: the ultimate loop gain of a FOPDT + PI loop (phase crossover of
  $K_cK(1+1/(j\omega\tau_I))e^{-j\omega\theta}/(1+j\omega\tau)$); settings with
  $K_cK$ beyond it, or of the wrong sign, raise a `ControlWarning`.

Disturbance scenarios: ``feed_moisture_step`` (relative step of the feed moisture, dry basis
by default: +20 % of 0.163 wet = 0.195 would leave the zinc concentrate's validated range),
``feed_rate_step`` (relative), ``fouling_ramp`` (flight loading capacity lost, Ajayi Ch. 7
"scaling", from 0 to ``magnitude`` over the run), ``none``.

Performance figures (after the disturbance): IAE (∫|e| dt), maximum deviation, overshoot
(largest excursion beyond the setpoint on the side opposite to the first peak, % of that peak),
settling time (last time |e| exceeds the tolerance), whether the product moisture stays within
the tolerance band, and the fraction of time within Ajayi's product targets.
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from typing import Optional

import numpy as np

from ._validation import check_choice, check_range
from .thermal.schedule import (
    DryerIntegrator,
    base_inputs,
    burner_fuel_rate,
    burner_max_temperature,
    check_applicable,
    input_column,
    outlets,
)
from .thermal.states import PRODUCT_FLOOR_MOISTURE

__all__ = ["ControlWarning", "check_schedule", "FOPDT", "simc_pi", "pi_ultimate_gain", "check_pi_stability", "PIController",
           "ControlConfig", "identify", "check_scenario", "closed_loop", "ClosedLoopResult", "SCENARIOS",
           "MAX_DURATION_S", "MAX_SAMPLES",
           "AJAYI_TARGETS",
           "performance"]

#: Ajayi (2011) Ch. 7 (l.2362): transportable product moisture limit and MMG product temperature policy
AJAYI_TARGETS = {"product_moisture_max_kg_kg": 0.12, "product_temperature_band_degC": (45.0, 50.0)}
SCENARIOS = ("feed_moisture_step", "feed_rate_step", "fouling_ramp", "none")
#: longest simulated time of one closed- or open-loop run, s (one day). The run rebuilds and integrates
#: the dynamic model every sampling interval (about 0.1-0.25 s of wall time per interval of the MMG
#: dryer), so the former 30 days ran for hours; a dryer with residence times of minutes to an hour
#: settles within hours of a disturbance. ``rotarydryer control --duration`` and the web app's
#: control page check the same bound (:func:`rotarydryer.services.control.check_control_options`).
MAX_DURATION_S = 86400.0
#: most sampling intervals of one run (duration / sample time: one a minute for a day)
MAX_SAMPLES = 1440
MEASURED = ("product_moisture", "exhaust_temperature")
#: units of the identification steps and of the measured outputs (messages)
STEP_UNITS = {"gas_inlet_temperature": "K", "feed_rate": "kg/s", "feed_moisture_dry": "kg/kg dry"}
OUTPUT_UNITS = {"product_moisture": "kg/kg wet", "exhaust_temperature": "degC"}
#: default tolerance band of the controlled variable (0.5 percentage point; 2 K)
TOLERANCE = {"product_moisture": 0.005, "exhaust_temperature": 2.0}


class ControlWarning(UserWarning):
    """Controller settings that make the loop unstable (or act in the wrong direction)."""


@dataclasses.dataclass
class FOPDT:
    """First-order-plus-dead-time model: gain (output per input unit), dead time and time constant, s."""

    gain: float
    dead_time_s: float
    time_constant_s: float

    @classmethod
    def from_fit(cls, fit):
        return cls(float(fit["gain"]), max(float(fit["dead_time_s"]), 0.0), max(float(fit["time_constant_s"]), 1.0))


def simc_pi(model: FOPDT, tau_c_s: Optional[float] = None, extra_dead_time_s: float = 0.0):
    """SIMC PI settings, Skogestad (2003): Kc = τ/(K(τc+θ)), τI = min(τ, 4(τc+θ)).

    ``tau_c_s`` (closed-loop time constant) defaults to θ (Skogestad's recommendation for tight,
    robust control); ``extra_dead_time_s`` (measurement dead time + half the sample time) is
    added to θ. Returns dict(kc, tau_i_s, tau_c_s, theta_s).

    >>> s = simc_pi(FOPDT(2.0, 10.0, 100.0))
    >>> round(s["kc"], 3), s["tau_i_s"]
    (2.5, 80.0)
    """
    if model.gain == 0 or not math.isfinite(model.gain):
        raise ValueError(f"FOPDT gain = {model.gain!r}: the manipulated variable does not move the output")
    theta = max(model.dead_time_s + extra_dead_time_s, 1e-6)
    tc = theta if tau_c_s is None else float(check_range("tau_c_s", tau_c_s, 0.0, math.inf, unit="s"))
    kc = model.time_constant_s / (model.gain * (tc + theta))
    return dict(kc=float(kc), tau_i_s=float(min(model.time_constant_s, 4.0 * (tc + theta))), tau_c_s=float(tc),
                theta_s=float(theta))


def pi_ultimate_gain(model: FOPDT, tau_i_s: float, extra_dead_time_s: float = 0.0) -> float:
    r"""Largest loop gain Kc*K (same sign as K) for which the FOPDT + PI loop is stable.

    Phase of $(1+1/(j\omega\tau_I))e^{-j\omega\theta}/(1+j\omega\tau)$ reaches -180° at
    ω180; the limit is 1/|L(jω180)/(K_cK)| (Nyquist; the loop is open-loop stable)."""
    from scipy.optimize import brentq

    th, tau, ti = model.dead_time_s + extra_dead_time_s, model.time_constant_s, float(tau_i_s)
    if th <= 0:
        return math.inf   # a first-order lag + PI never reaches -180 degrees

    def phase(w):
        return -th * w - math.atan(w * tau) - (math.pi / 2 - math.atan(w * ti)) + math.pi
    lo, hi = 1e-9, 1.0
    while phase(hi) > 0:
        hi *= 2
        if hi > 1e9:
            return math.inf
    w = brentq(phase, lo, hi)
    mag = math.sqrt(1 + 1 / (w * ti) ** 2) / math.sqrt(1 + (w * tau) ** 2)
    return 1.0 / mag


def check_pi_stability(model: FOPDT, kc: float, tau_i_s: float, extra_dead_time_s: float = 0.0, name="PI"):
    """Gain margin of the loop; warns (`ControlWarning`) when Kc*K is of the wrong sign
    (positive feedback) or beyond the ultimate gain (`pi_ultimate_gain`). Returns the gain margin."""
    loop = kc * model.gain
    if loop <= 0:
        warnings.warn(f"{name}: Kc*K = {loop:.3g} <= 0: the controller acts in the wrong direction (positive "
                      f"feedback; Kc must have the sign of the process gain K = {model.gain:.3g})",
                      ControlWarning, stacklevel=2)
        return 0.0
    ku = pi_ultimate_gain(model, tau_i_s, extra_dead_time_s)
    gm = ku / loop
    if gm <= 1.0:
        warnings.warn(f"{name}: unstable loop: Kc*K = {loop:.3g} exceeds the stability limit {ku:.3g} of the "
                      f"FOPDT+PI loop (K = {model.gain:.3g}, theta = {model.dead_time_s + extra_dead_time_s:.0f} s, "
                      f"tau = {model.time_constant_s:.0f} s, tau_I = {tau_i_s:.0f} s; gain margin {gm:.2f} < 1)",
                      ControlWarning, stacklevel=2)
    return float(gm)


class PIController:
    """PI controller in velocity form with output limits (clipping = anti-windup), Seborg et al. 2011 Ch. 8.

    ``step(setpoint, measurement, lo, hi)`` returns the new output; ``lo``/``hi`` may move
    between calls (the room that the feed-forward leaves)."""

    def __init__(self, kc, tau_i_s, sample_time_s, u0=0.0, u_min=-math.inf, u_max=math.inf):
        self.kc = float(kc)
        self.tau_i_s = float(check_range("tau_i_s", tau_i_s, 0.0, math.inf, unit="s"))
        self.ts = float(sample_time_s)
        self.u = float(u0)
        self.u_min, self.u_max = u_min, u_max
        self._e = None

    def step(self, setpoint, measurement, lo=None, hi=None):
        e = float(setpoint) - float(measurement)
        e_prev = e if self._e is None else self._e
        du = self.kc * ((e - e_prev) + self.ts / self.tau_i_s * e)
        lo = self.u_min if lo is None else max(lo, self.u_min)
        hi = self.u_max if hi is None else min(hi, self.u_max)
        self.u = float(np.clip(self.u + du, lo, hi))
        self._e = e
        return self.u


@dataclasses.dataclass
class ControlConfig:
    """Settings of a closed-loop run (SI, degC). ``None`` = from the identification (SIMC)."""

    measured: str = "product_moisture"
    setpoint: Optional[float] = None          # None: the steady state of the case
    sample_time_s: float = 60.0
    measurement_dead_time_s: float = 120.0
    kc: Optional[float] = None                # in y-units per y-unit (normalised split range)
    tau_i_s: Optional[float] = None
    tau_c_s: Optional[float] = None
    feedforward: str = "model"               # "model" (steady-state), "linear" (FOPDT gains) or "off"
    feedback: bool = True
    feed_backup: bool = True                  # reduce the feed when the gas temperature saturates
    gas_temperature_min: Optional[float] = None
    gas_temperature_max: float = 600.0
    feed_min_fraction: float = 0.5
    tolerance: Optional[float] = None
    #: the product's specification (None: not reported): largest moisture (kg/kg wet) and temperature band (degC)
    product_moisture_max: Optional[float] = None
    product_temperature_band: Optional[tuple] = None

    def validate(self, names=None, check=check_range, choose=check_choice):
        """Check every setting (``ValueError`` naming it, the value and the allowed range); the one
        place the settings' ranges live. ``names``: field -> the name to show (the CLI's and the web
        app's option names, `rotarydryer.services.control.check_control_options`), with ``check``
        (as `check_range`) and ``choose`` (as `check_choice`) formatting the messages in their terms."""
        names = names or {}

        def rng(field, value, low, high, **kw):
            check(names.get(field, field), value, low, high, **kw)
        choose(names.get("measured", "measured"), self.measured, MEASURED)
        choose(names.get("feedforward", "feedforward"), self.feedforward, ("model", "linear", "off"))
        rng("sample_time_s", self.sample_time_s, 1.0, 3600.0, low_inclusive=True, high_inclusive=True, unit="s")
        rng("measurement_dead_time_s", self.measurement_dead_time_s, 0.0, 7200.0, low_inclusive=True,
            high_inclusive=True, unit="s")
        rng("gas_temperature_max", self.gas_temperature_max, 0.0, 600.0, high_inclusive=True, unit="degC")
        if self.gas_temperature_min is not None:
            rng("gas_temperature_min", self.gas_temperature_min, 0.0, self.gas_temperature_max, unit="degC")
        rng("feed_min_fraction", self.feed_min_fraction, 0.0, 1.0, high_inclusive=True)
        if self.tau_i_s is not None:
            rng("tau_i_s", self.tau_i_s, 0.0, math.inf, unit="s")
        if self.tau_c_s is not None:
            rng("tau_c_s", self.tau_c_s, 0.0, math.inf, unit="s")
        if self.kc is not None:
            rng("kc", self.kc, -1e6, 1e6)
        moisture = self.measured == "product_moisture"
        if self.tolerance is not None:
            rng("tolerance", self.tolerance, 0.0, 1.0 if moisture else 100.0, unit="kg/kg wet" if moisture else "K")
        if self.product_moisture_max is not None:
            rng("product_moisture_max", self.product_moisture_max, 0.0, 1.0, low_inclusive=True, unit="kg/kg wet")
        if self.product_temperature_band is not None:
            name = names.get("product_temperature_band", "product_temperature_band")
            band = tuple(self.product_temperature_band)
            if len(band) != 2:
                raise ValueError(f"{name} = {self.product_temperature_band!r}: give two temperatures, LOW,HIGH degC")
            for v in band:
                rng("product_temperature_band", v, -50.0, 600.0, low_inclusive=True, high_inclusive=True, unit="degC")
            if not band[0] < band[1]:
                raise ValueError(f"{name} = {band[0]:g},{band[1]:g} degC: the low end must be below the high end")
            self.product_temperature_band = (float(band[0]), float(band[1]))
        if self.setpoint is not None:
            rng("setpoint", self.setpoint, 0.0, 1.0 if moisture else 600.0, unit="kg/kg wet" if moisture else "degC")
        return self


# ---------------------------------------------------------------------------------------------- plant helpers
def _dry_basis(x):
    return x / (1.0 - x)


def _wet_basis(X):
    return X / (1.0 + X)


def plant(dryer, *, gas_inlet_temperature=None, feed_rate=None, feed_moisture=None, fouling=None, **settings):
    """A copy of ``dryer`` with new inputs (gas inlet temperature degC, feed rate kg/s wet, feed
    moisture kg/kg wet, fouling 0-0.95, or other ThermalSettings fields); the checks of
    `perturbed` apply."""
    from .thermal.studies import perturbed

    ch = dict(settings)
    if gas_inlet_temperature is not None:
        ch["gas_inlet_temperature"] = gas_inlet_temperature
    if feed_rate is not None:
        ch["solid_feed_rate"] = feed_rate
    if fouling is not None:
        ch["fouling"] = float(fouling)
    d = perturbed(dryer, **ch)
    if feed_moisture is not None:
        d.feed_moisture = float(feed_moisture)
        d._check_operating_inputs()
    return d


def outputs_of(dryer, z):
    """Measured outputs of state ``z``: product moisture (kg/kg wet) and temperature (degC),
    exhaust temperature (degC) and humidity (kg/kg dry gas), total holdup (kg)
    ([`outlets`][rotarydryer.thermal.schedule.outlets])."""
    return outlets(dryer, z)


def _fuel(dryer, z):
    """Fuel rate (kg/s) of the case's burner for the dryer's gas inlet temperature at state ``z`` (whose exhaust
    a recycling burner heats), None without a burner or where it cannot give that temperature."""
    if dryer.settings.burner is None:
        return None
    try:
        return burner_fuel_rate(dryer, z)
    except ValueError:
        return None


class _FeedRange:
    """The feed range of the split range as the plant's own steady-state map (a static-gain inverse, Hammerstein
    style): the output ``y(F)`` with the gas at the end where the feed backs it up, on ``n`` feed rates from the
    range's lowest to the case's, joined by a monotonic cubic (PCHIP: Fritsch and Carlson (1980)); linear beyond them
    with the end slopes. A controller output ``v`` (y-units) beyond
    the gas range moves the feed to where the steady-state output has moved by ``v``: the loop gain on the feed
    range is that of the design (1 in y-units) wherever the feed is, not the identified gain at the case's feed
    rate. (A drying product's gain to the feed rate rises as the feed falls: 2.5-3.8x from MMG test 4's 40.7 kg/s to
    its half, where the linear range made the default loop oscillate by +-0.5 percentage points.)"""

    def __init__(self, F, y):
        from scipy.interpolate import PchipInterpolator  # (scipy.interpolate: not on the CLI's start path)

        self.F, self.y = np.asarray(F, float), np.asarray(y, float)
        self._curve = PchipInterpolator(self.F, self.y)     # monotonic between the points, as the data are
        d = self._curve.derivative()
        self.slope = (float(d(self.F[0])), float(d(self.F[-1])))
        self.rising = bool(self.y[-1] > self.y[0])

    def output(self, F):
        F = float(F)
        if F < self.F[0]:
            return float(self.y[0] + self.slope[0] * (F - self.F[0]))
        if F > self.F[-1]:
            return float(self.y[-1] + self.slope[1] * (F - self.F[-1]))
        return float(self._curve(F))

    def feed(self, y):
        """The feed rate whose output is ``y`` (the inverse of `output`)."""
        from scipy.optimize import brentq

        y = float(y)
        lo, hi = (self.y[0], self.y[-1]) if self.rising else (self.y[-1], self.y[0])
        if lo <= y <= hi:          # (brentq returns an end where the curve meets y exactly)
            return float(brentq(lambda F: float(self._curve(F)) - y, self.F[0], self.F[-1], xtol=1e-12 * self.F[-1]))
        end = 0 if (y < lo) == self.rising else -1
        slope = self.slope[0 if end == 0 else 1]
        if not slope:       # a flat end (a product at its floor moisture): no feed rate gives y; the farthest that way
            return -math.inf if end == 0 else math.inf
        return float(self.F[end] + (y - self.y[end]) / slope)


def _feed_range(dryer, steady, cv, T_sat, F_lo, F0, n=6):
    """`_FeedRange` of ``dryer`` (output ``cv``, gas inlet ``T_sat`` degC, feed rates ``F_lo``..``F0``), or None where
    a steady state fails or the map is not strictly monotonic (the linear range is then kept)."""
    Fs = np.linspace(F_lo, F0, n)
    ys, z, lu = [], steady.state, getattr(steady, "factorization", None)
    for F in Fs[::-1]:          # from the case's feed down, each from the previous state and its factorisation
        try:
            st = plant(dryer, gas_inlet_temperature=T_sat, feed_rate=float(F)).steady_state(z0=z, factorization=lu)
        except ValueError:
            return None
        z, lu = st.state, st.factorization
        ys.append(outputs_of(st.dryer, st.state)[cv])
    y = np.asarray(ys[::-1])
    d = np.diff(y)
    if not (np.all(d > 0) or np.all(d < 0)) or not np.all(np.isfinite(y)):
        return None
    return _FeedRange(Fs, y)


# ---------------------------------------------------------------------------------------------- identification
def _step(dryer, z0, duration, dt, **change):
    d2 = plant(dryer, **change)
    t_eval = np.arange(0.0, duration + dt / 2, dt)
    res = d2.simulate(z0, duration, t_eval=t_eval)
    ys = {k: [] for k in MEASURED}
    for j in range(res.states.shape[1]):
        o = outputs_of(d2, res.states[:, j])
        for k in MEASURED:
            ys[k].append(o[k])
    return res.time, {k: np.asarray(v) for k, v in ys.items()}


def identify(dryer, steady, duration_s=5400.0, dt_s=60.0, gas_step_degC=30.0, feed_step_fraction=-0.1,
             moisture_step_fraction=0.1, progress=None, measured=None):
    """FOPDT models (per measured output) of the gas inlet temperature, the feed rate and the
    feed moisture (dry basis, kg/kg dry), from step responses of the dynamic model around ``steady``.

    Returns dict input -> output -> `FOPDT` (input names: ``gas_inlet_temperature`` (per K),
    ``feed_rate`` (per kg/s), ``feed_moisture_dry`` (per kg/kg dry)). ``measured`` (an output of `MEASURED`,
    or None for all): the output the loop controls, which must respond to every step (else a ValueError
    saying there is nothing to control); another output that a step does not move is left out."""
    required = MEASURED if measured is None else (measured,)
    from .thermal.studies import fopdt_fit

    z0 = steady.state
    s = dryer.settings
    T0, F0, x0 = s.gas_inlet_temperature, dryer.feed_rate, dryer.feed_moisture
    dT = gas_step_degC if T0 + gas_step_degC <= 600.0 else -gas_step_degC
    X0 = _dry_basis(x0)
    Xs = X0 * (1 + moisture_step_fraction)
    lo, hi = dryer.material.wet_range()
    if _wet_basis(Xs) > hi:
        Xs = X0 * (1 - moisture_step_fraction)
    steps = {"gas_inlet_temperature": (dict(gas_inlet_temperature=T0 + dT), dT),
             "feed_rate": (dict(feed_rate=F0 * (1 + feed_step_fraction)), F0 * feed_step_fraction),
             "feed_moisture_dry": (dict(feed_moisture=_wet_basis(Xs)), Xs - X0)}
    y0 = outputs_of(dryer, z0)
    if "product_moisture" in required and not y0["product_moisture"] > PRODUCT_FLOOR_MOISTURE:
        # a product at the material's floor: its moisture moves by roundings (gains of 1e-10), no loop to tune
        raise ValueError(f"control: the product leaves at {y0['product_moisture']:.3g} kg/kg wet, dried to the "
                         f"material's floor (below {PRODUCT_FLOOR_MOISTURE:g} kg/kg): its moisture does not respond to the "
                         "inputs, there is nothing to control at this operating point; give one where the product "
                         "leaves wetter (a lower gas inlet temperature, a higher feed rate or feed moisture), or "
                         "measure the exhaust (--measured exhaust_temperature)")
    out = {}
    for name, (change, du) in steps.items():
        if progress:
            progress(f"identification: step of {name}")
        t, ys = _step(dryer, z0, duration_s, dt_s, **change)
        out[name] = {}
        for k in MEASURED:
            try:
                out[name][k] = FOPDT.from_fit(fopdt_fit(t, ys[k], du, y0=y0[k]))
            except ValueError:      # an output that a step of this input does not move: no loop to tune on it
                if k not in required:       # not the loop's (an exhaust loop over a product dried to its floor)
                    continue
                raise ValueError(
                    f"control: the {k.replace('_', ' ')} does not respond to a step of the {name.replace('_', ' ')} "
                    f"({du:+.4g} {STEP_UNITS[name]}; it stays at {y0[k]:.6g} {OUTPUT_UNITS[k]} over {duration_s:g} s"
                    + (", the product leaving dry at the material's floor" if k == "product_moisture" else "")
                    + "): there is nothing to control at this operating point; give one where the product leaves "
                      "wetter (a lower gas inlet temperature, a higher feed rate or feed moisture)") from None
    return out


# ---------------------------------------------------------------------------------------------- closed loop
@dataclasses.dataclass
class ClosedLoopResult:
    """Sampled trajectories (arrays over ``time_s``), the settings used and the performance figures."""

    time_s: np.ndarray
    series: dict
    setpoint: float
    measured: str
    tuning: dict
    performance: dict
    scenario: dict
    seconds: float

    def summary(self):
        return dict(measured=self.measured, setpoint=self.setpoint, scenario=self.scenario, tuning=self.tuning,
                    performance=self.performance, wall_time_s=self.seconds)

    def table(self):
        """Rows (dicts) of the sampled series, named with their units."""
        keys = list(self.series)
        return [dict(time_s=float(t), **{k: self.series[k][i] for k in keys}) for i, t in enumerate(self.time_s)]

    def csv_text(self) -> str:
        """The `table` as CSV text (10 significant digits; empty cells for missing values)."""
        rows = self.table()
        keys = list(rows[0])
        lines = [",".join(keys)] + [",".join("" if r[k] is None else f"{float(r[k]):.10g}" for k in keys)
                                    for r in rows]
        return "\n".join(lines) + "\n"


def _disturbance(scenario, magnitude, t, t_step, t_end, base):
    """Feed moisture (wet), feed rate (kg/s) and fouling at time t of a scenario."""
    x, F, f = base["feed_moisture"], base["feed_rate"], base["fouling"]
    if scenario == "feed_moisture_step" and t >= t_step:
        x = _wet_basis(_dry_basis(x) * (1 + magnitude))
    elif scenario == "feed_rate_step" and t >= t_step:
        F = F * (1 + magnitude)
    elif scenario == "fouling_ramp" and t >= t_step:
        f = f + (magnitude - f) * min(1.0, (t - t_step) / max(t_end - t_step, 1.0))
    return x, F, f


#: the plant()/perturbed() names of the schedulable inputs other than feed rate, moisture and fouling
_PLANT_NAMES = {"rpm": "rotational_speed", "gas_flow": "gas_flow", "gas_inlet_humidity": "gas_inlet_humidity",
                "feed_temperature": "solid_inlet_temperature", "gas_inlet_temperature": "gas_inlet_temperature"}


def check_schedule(dryer, schedule, t_end_s, controlled=True):
    """The schedule resolved and checked for a control run; its first change is the disturbance
    time of the performance figures."""
    names = set(schedule.points)
    if "burner_fuel_rate" in names:
        raise ValueError(f"{schedule.source}: control schedules the gas inlet temperature, not burner_fuel_rate "
                         "(the burner's fuel follows from it)")
    if controlled and "gas_inlet_temperature" in names:
        raise ValueError(f"{schedule.source}: gas_inlet_temperature is the controller's manipulated input; schedule "
                         "the disturbances (feed_rate, feed_moisture, fouling, rpm, gas_flow, gas_inlet_humidity, "
                         "feed_temperature), or run the open loop alone")
    base = base_inputs(dryer)
    checked = schedule.check(base, t_end_s, burner=dryer.settings.burner is not None, length_option="--duration")
    check_applicable(dryer, checked)
    starts = []
    for name, p in checked.points.items():      # the start of the first change away from the case's value
        i = next((j for j, (_, v) in enumerate(p) if v != base[name]), None)
        if i is not None:
            starts.append(p[max(i - 1, 0)][0])
    return checked, (min(starts) if starts else 0.0)


def performance(time_s, y, setpoint, t_step, tolerance, product_moisture=None, product_temperature=None,
                moisture_max=None, temperature_band=None, unit=None):
    """IAE (∫|e|dt from the disturbance), maximum |e|, overshoot (%), settling time (s after the
    disturbance, None if |e| ends above the tolerance), within-band flag, the fraction of the samples
    after the disturbance within the tolerance, and within the product's specification when it is
    given (``moisture_max`` kg/kg wet, ``temperature_band`` degC: ``fraction_moisture_within_spec``,
    ``fraction_temperature_within_band``). ``fraction_moisture_at_most_12pct`` and
    ``fraction_temperature_45_50degC`` are Ajayi's (2011) MMG targets, whatever the dryer (kept for
    scripts that read them; give the case's own specification instead). ``unit``: the controlled
    variable's unit, given as ``units`` of the deviations and the IAE."""
    t = np.asarray(time_s, float)
    e = np.asarray(y, float) - setpoint
    m = t >= t_step
    tt, ee = t[m], e[m]
    iae = float(np.trapezoid(np.abs(ee), tt)) if tt.size > 1 else 0.0
    i_pk = int(np.argmax(np.abs(ee))) if ee.size else 0
    peak = float(ee[i_pk]) if ee.size else 0.0
    after = ee[i_pk:]
    opposite = after[np.sign(after) == -np.sign(peak)] if peak != 0 else np.array([])
    overshoot = float(100 * np.max(np.abs(opposite)) / abs(peak)) if opposite.size and peak != 0 else 0.0
    outside = np.nonzero(np.abs(ee) > tolerance)[0]
    if outside.size == 0:
        settling = 0.0
    elif outside[-1] == ee.size - 1:
        settling = None
    else:
        settling = float(tt[outside[-1] + 1] - t_step)
    out = dict(iae=iae, max_abs_deviation=float(np.max(np.abs(ee))) if ee.size else 0.0, peak_deviation=peak,
               overshoot_pct=overshoot, settling_time_s=settling, tolerance=tolerance,
               within_tolerance=bool(outside.size == 0), final_deviation=float(e[-1]),
               fraction_within_tolerance=float(np.mean(np.abs(ee) <= tolerance)) if ee.size else 1.0)
    if unit is not None:    # the deviations' unit (the controlled variable's), and the IAE's (that times s)
        out["units"] = dict(iae=f"{unit} s", max_abs_deviation=unit, peak_deviation=unit, tolerance=unit,
                            final_deviation=unit, overshoot_pct="%", settling_time_s="s")
    if product_moisture is not None:
        pm = np.asarray(product_moisture)[m]
        out["fraction_moisture_at_most_12pct"] = float(np.mean(pm <= AJAYI_TARGETS["product_moisture_max_kg_kg"]
                                                                + 1e-9))
        if moisture_max is not None:
            out["product_moisture_max_kg_kg"] = float(moisture_max)
            out["fraction_moisture_within_spec"] = float(np.mean(pm <= moisture_max + 1e-12)) if pm.size else 1.0
    if product_temperature is not None:
        lo, hi = AJAYI_TARGETS["product_temperature_band_degC"]
        pt = np.asarray(product_temperature)[m]
        out["fraction_temperature_45_50degC"] = float(np.mean((pt >= lo) & (pt <= hi)))
        if temperature_band is not None:
            lo, hi = temperature_band
            out["product_temperature_band_degC"] = [float(lo), float(hi)]
            out["fraction_temperature_within_band"] = float(np.mean((pt >= lo) & (pt <= hi))) if pt.size else 1.0
    return out


def default_gas_temperature_min(gas_inlet_temperature: float, solids_inlet_temperature: float) -> float:
    """Lowest gas inlet temperature of the split range when none is given: 50 K above the feed and at
    most 200 K below the case's gas inlet temperature, but never above that temperature (a dryer
    whose gas enters less than 50 K above the feed, e.g. Lee's 100 degC air on 55 degC sugar, gets
    the point halfway between feed and gas)."""
    t0, ts = float(gas_inlet_temperature), float(solids_inlet_temperature)
    tmin = max(ts + 50.0, t0 - 200.0)
    if tmin > t0:
        tmin = 0.5 * (ts + t0) if t0 > ts else t0
    return max(0.0, min(tmin, t0))


def check_scenario(dryer, scenario, magnitude, t_end_s, t_step_s=0.0):
    """Refuse (``ValueError`` naming the key) a disturbance that takes the plant outside its valid
    inputs (e.g. a feed wetter than the material's range) before any long run."""
    check_choice("scenario", scenario, SCENARIOS)
    base = dict(feed_moisture=dryer.feed_moisture, feed_rate=dryer.feed_rate, fouling=dryer.settings.fouling)
    x, F, f = _disturbance(scenario, magnitude, t_end_s, t_step_s, t_end_s, base)
    if scenario == "feed_moisture_step":
        hi = dryer.material.wet_range()[1]
        if x > hi:      # the disturbance is the caller's magnitude, not the case's feed moisture
            largest = _dry_basis(hi) / _dry_basis(base["feed_moisture"]) - 1.0
            raise ValueError(f"magnitude = {magnitude:g}: feed too wet: the step takes the feed moisture to {x:.4g} kg/kg wet, "
                             f"wetter than material '{dryer.material.name}' allows (<= {hi:.4g} kg/kg wet): at most "
                             f"{largest:+.3g} for this case's feed ({base['feed_moisture']:.4g} kg/kg wet)")
    plant(dryer, feed_moisture=x, feed_rate=F, fouling=f)


def closed_loop(dryer, steady=None, *, scenario="feed_moisture_step", magnitude=0.2, t_end_s=10800.0,
                t_step_s=600.0, config: ControlConfig | None = None, models=None, controlled=True,
                progress=None, schedule=None):
    """Closed-loop (``controlled=True``) or open-loop run of ``dryer`` from ``steady`` (default:
    its steady state) under a disturbance ``scenario`` (`SCENARIOS`; ``magnitude`` relative:
    +0.2 = +20 %; for ``fouling_ramp`` the final fouling fraction), or an input ``schedule``
    ([`InputSchedule`][rotarydryer.thermal.schedule.InputSchedule]: the disturbances feed rate,
    feed moisture, fouling, drum speed, gas flow, gas humidity, feed temperature; the gas inlet
    temperature too in an open-loop run), in place of the scenario.

    ``models``: the result of `identify` (computed when None and needed). Returns a
    `ClosedLoopResult`; warns `ControlWarning` for unstable settings."""
    cfg = (config or ControlConfig()).validate()
    if schedule is None:
        check_choice("scenario", scenario, SCENARIOS)
    check_range("t_end_s", t_end_s, 0.0, MAX_DURATION_S, high_inclusive=True, unit="s")
    if t_end_s / cfg.sample_time_s > MAX_SAMPLES:
        raise ValueError(f"t_end_s / sample_time_s = {t_end_s:g} s / {cfg.sample_time_s:g} s = "
                         f"{t_end_s / cfg.sample_time_s:.6g} sampling intervals; the limit is {MAX_SAMPLES} "
                         "(raise sample_time_s or lower t_end_s)")
    check_range("t_step_s", t_step_s, 0.0, t_end_s, low_inclusive=True, high_inclusive=True, unit="s")
    if schedule is not None:
        schedule, t_step_s = check_schedule(dryer, schedule, t_end_s, controlled)
        scenario, magnitude = "schedule", 0.0
    elif scenario == "fouling_ramp":
        check_range("magnitude", magnitude, 0.0, 0.95, low_inclusive=True, high_inclusive=True,
                    unit="(final fouling fraction)")
    else:
        check_range("magnitude", magnitude, -0.9, 2.0, unit="(relative change)")
    t0 = time.perf_counter()
    if steady is None:
        steady = dryer.steady_state()
    s = dryer.settings
    base = dict(feed_moisture=dryer.feed_moisture, feed_rate=dryer.feed_rate, fouling=s.fouling)
    if schedule is None:
        check_scenario(dryer, scenario, magnitude, t_end_s, t_step_s)
    sched_base = base_inputs(dryer)
    y_ss = outputs_of(dryer, steady.state)
    cv = cfg.measured
    sp = y_ss[cv] if cfg.setpoint is None else float(cfg.setpoint)
    ts = cfg.sample_time_s
    T0, F0 = s.gas_inlet_temperature, dryer.feed_rate
    Tmin = cfg.gas_temperature_min if cfg.gas_temperature_min is not None else default_gas_temperature_min(
        T0, s.solids_inlet_temperature)
    Tmax = cfg.gas_temperature_max
    # the gas range ends where the case's burner does (its capacity or the combustion air's oxygen): MMG test 4's
    # loop held 600 degC for 2 h, which its burner cannot make (586 degC), and called the loop settled
    T_burner = burner_max_temperature(dryer, steady.state) if s.burner is not None else None
    burner_note = None
    if T_burner is not None and T_burner < Tmax and T_burner >= T0:
        burner_note = (f"gas range ends at {T_burner:.1f} degC, the hottest gas the case's burner makes at the start "
                       f"(its maximum fuel rate), below gas_temperature_max = {Tmax:g} degC")
        Tmax = T_burner
    if not Tmin <= T0 <= Tmax:
        which = ("--gas-t-max (gas_temperature_max)" if T0 > Tmax else "--gas-t-min (gas_temperature_min)")
        raise ValueError(f"gas_temperature_min..gas_temperature_max = {Tmin:g}..{Tmax:g} degC must contain the "
                         f"case's gas inlet temperature {T0:g} degC: set {which} so that it does")
    tuning = {}
    if controlled:
        if models is None:
            models = identify(dryer, steady, progress=progress, measured=cv)
        mT, mF, mX = (models["gas_inlet_temperature"][cv], models["feed_rate"][cv], models["feed_moisture_dry"][cv])
        extra = cfg.measurement_dead_time_s + ts / 2
        # normalised ranges: v = K * du (y-units); the slower range sets the tuning (robust)
        norm_T = FOPDT(1.0, mT.dead_time_s, mT.time_constant_s)
        norm_F = FOPDT(1.0, mF.dead_time_s, mF.time_constant_s)
        cands = [simc_pi(norm_T, cfg.tau_c_s, extra)] + ([simc_pi(norm_F, cfg.tau_c_s, extra)]
                                                         if cfg.feed_backup else [])
        simc = min(cands, key=lambda c: c["kc"])
        kc = simc["kc"] if cfg.kc is None else cfg.kc
        ti = simc["tau_i_s"] if cfg.tau_i_s is None else cfg.tau_i_s
        ti_note = None
        if cfg.kc is None and cfg.tau_i_s is None and len(cands) > 1:
            # the smaller gain's integral time may be too short for the other range (a fast gas path's tau_I on a
            # slow feed path: unstable there); the longer of the two keeps both stable (a lower gain and a longer
            # integral time than each range's own SIMC settings)
            def margin(m):
                return pi_ultimate_gain(m, ti, extra) / (kc * m.gain)
            if min(margin(norm_T), margin(norm_F)) <= 1.0:
                ti = max(c["tau_i_s"] for c in cands)
                ti_note = "tau_I of the slower range (the faster range's made the other range's loop unstable)"
        gms = [check_pi_stability(norm_T, kc, ti, extra, name="PI on the gas inlet temperature range")]
        if cfg.feed_backup:
            gms.append(check_pi_stability(norm_F, kc, ti, extra, name="PI on the feed rate range"))
        tuning = dict(rule="SIMC, Skogestad (2003) (tau_c = theta)", kc=kc, tau_i_s=ti,
                      simc_kc=simc["kc"], simc_tau_i_s=simc["tau_i_s"], theta_loop_s=simc["theta_s"],
                      gain_margin=min(gms), **({"tau_i_note": ti_note} if ti_note else {}),
                      fopdt={name: dataclasses.asdict(m) for name, m in
                             (("gas_inlet_temperature", mT), ("feed_rate", mF), ("feed_moisture_dry", mX))},
                      gas_temperature_range_degC=[Tmin, Tmax], feed_min_kg_s=cfg.feed_min_fraction * F0,
                      **({"gas_temperature_range_note": burner_note} if burner_note else {}))
        # y-equivalent ranges of each actuator
        vT = sorted([mT.gain * (Tmin - T0), mT.gain * (Tmax - T0)])
        # the feed range as the plant's steady-state map, with the gas at the end the feed backs up (a feed cut
        # moves y by the sign of -mF.gain: the gas range's end on that side)
        feed_map = None
        if cfg.feed_backup:
            T_sat = T0 + (vT[0] if mF.gain > 0 else vT[1]) / mT.gain
            if progress:
                progress("feed range: steady states along the feed rate")
            feed_map = _feed_range(dryer, steady, cv, T_sat, cfg.feed_min_fraction * F0, F0)
            if feed_map is not None:
                tuning["feed_range_map"] = {"gas_inlet_temperature_degC": T_sat,
                                            "feed_rate_kg_s": feed_map.F.tolist(), cv: feed_map.y.tolist()}
        pi = PIController(kc, ti, ts) if cfg.feedback else None
        # dynamic feed-forward, Seborg et al. (2011) Ch. 15:
        # Gf = -(Kd/Ku) (tau_u s+1)/(tau_d s+1) exp(-(theta_d-theta_u) s); the lead-lag and dead time are
        # replaced by one delay that matches the times to half response, theta + ln2 tau, of the disturbance
        # path and of the slowest manipulated path that acts (a lead-lag kicks the saturating split range too
        # hard). Each measured disturbance has its own path (feed moisture, feed rate), and the ranges that act
        # are those the feed-forward's final value needs: the gas range alone when it suffices, both when the gas
        # saturates. (Before: the feed moisture's path for every disturbance and the slower range always, so
        # that on a dryer with a slow feed path the fast gas range acted up to 1 000 s before the disturbance
        # reached the product, worse than no control.) Scheduled inputs without an identified path (speed, gas
        # flow, ...) enter at once.
        def half_time(m):
            return m.dead_time_s + math.log(2) * m.time_constant_s

        def ff_delays(acting):
            h_u = max(half_time(m) for m in acting)
            return {"feed_moisture": max(0.0, half_time(mX) - h_u), "feed_rate": max(0.0, half_time(mF) - h_u)}

        delays_by_ranges = {"gas": ff_delays([mT]), "gas_and_feed": ff_delays([mT, mF] if cfg.feed_backup else [mT])}
        tuning["feedforward_delay_s"] = delays_by_ranges["gas"]["feed_moisture"]
        tuning["feedforward_delays_s"] = delays_by_ranges
        tuning["feedforward"] = cfg.feedforward
        ff_cache = {}

        def split(v, Fd):
            if not cfg.feed_backup:
                vF = [0.0, 0.0]
            elif feed_map is None:
                vF = sorted([mF.gain * (cfg.feed_min_fraction * F0 - Fd), 0.0])
            else:                                 # in y-units along the plant's own map
                vF = sorted([feed_map.output(cfg.feed_min_fraction * F0) - feed_map.output(Fd), 0.0])
            v_T = float(np.clip(v, vT[0], vT[1]))
            rest = float(np.clip(v - v_T, vF[0], vF[1]))
            if not cfg.feed_backup:
                F_in = Fd
            elif feed_map is None:
                F_in = Fd + rest / mF.gain
            else:
                F_in = Fd if rest == 0.0 else max(cfg.feed_min_fraction * F0,
                                                   min(Fd, feed_map.feed(feed_map.output(Fd) + rest)))
            return T0 + v_T / mT.gain, F_in, vF

        def ff_value(x, Fd, f, extra=()):
            """Feed-forward v for measured feed moisture x and feed rate Fd; ``extra``: the other
            measured (scheduled) inputs, ``((plant name, value), ...)`` - drum speed, gas flow, gas
            humidity, feed temperature - which the model-based feed-forward's steady states take too
            (the linear one has no gains for them)."""
            dX = _dry_basis(x) - _dry_basis(base["feed_moisture"])
            v_lin = -(mX.gain * dX + mF.gain * (Fd - F0))
            if cfg.feedforward != "model" or (abs(dX) < 1e-9 and abs(Fd - F0) < 1e-9 * F0 and not extra):
                return v_lin
            key = (round(x, 9), round(Fd, 9), extra)
            if key not in ff_cache:   # steady-state (model-based) feed-forward: Brent on v for the setpoint
                if progress:
                    progress(f"feed-forward: steady state for feed moisture {x:.4g}, feed rate {Fd:.4g} kg/s")
                zs, lu = steady.state, getattr(steady, "factorization", None)

                def g(v):       # each steady state from the last one's state and factorisation (chord steps)
                    nonlocal zs, lu
                    T_in, F_in, _ = split(v, Fd)
                    st = plant(dryer, gas_inlet_temperature=T_in, feed_rate=F_in, feed_moisture=x,
                               fouling=base["fouling"], **dict(extra)).steady_state(z0=zs, factorization=lu)
                    zs, lu = st.state, st.factorization
                    return outputs_of(st.dryer, st.state)[cv] - sp
                tol = 0.05 * (cfg.tolerance or TOLERANCE[cv])
                vF_d = split(0.0, Fd)[2]
                lo_all, hi_all = vT[0] + vF_d[0], vT[1] + vF_d[1]
                try:
                    # bracket the root between no action (v = 0) and the linear estimate, widened up to
                    # the actuators' range; then Brent's method (the map saturates where the split range
                    # does, so a secant can run off a flat stretch)
                    g_lin = g(v_lin)
                    if abs(g_lin) < tol:
                        ff_cache[key] = v_lin
                    else:
                        g_0 = g_lin if v_lin == 0.0 else g(0.0)
                        # a disturbance without a linear gain (a scheduled gas flow, speed...): v is a shift
                        # in y-units, so -(y - setpoint) is the first-order guess
                        b = v_lin if v_lin != 0.0 else -g_0
                        gb = g_lin if v_lin != 0.0 else g(b)
                        a, ga = 0.0, g_0
                        limit = (hi_all if b > 0 else lo_all)
                        while ga * gb > 0.0 and 0.0 < abs(b) < abs(limit):
                            a, ga, b = b, gb, float(np.clip(2.0 * b, min(limit, 0.0), max(limit, 0.0)))
                            gb = g(b)
                        if ga * gb > 0.0:   # out of range: the actuators' limit
                            ff_cache[key] = b
                        else:
                            from scipy.optimize import brentq

                            ff_cache[key] = brentq(g, min(a, b), max(a, b), xtol=1e-3 * abs(b) + 1e-12, maxiter=30)
                except ValueError:   # no steady state at these inputs: fall back to the linear feed-forward
                    ff_cache[key] = v_lin
            return ff_cache[key]
    n = int(round(t_end_s / ts))
    delay_n = int(round(cfg.measurement_dead_time_s / ts))
    meas_buf, ff_buf = [], []
    z = np.asarray(steady.state, float)
    rec = {k: [] for k in ("product_moisture_kg_kg", "product_temperature_degC", "exhaust_temperature_degC",
                           "exhaust_humidity_kg_kg", "holdup_kg", "measured", "gas_inlet_temperature_degC",
                           "feed_rate_kg_s", "feed_moisture_kg_kg", "fouling", "fuel_rate_kg_s", "controller_output",
                           # the feed the disturbance brings (feed_rate_kg_s is the feed after the controller's backup)
                           "feed_rate_disturbance_kg_s")}
    # the schedule's other inputs (gas flow, speed, feed temperature, gas humidity): one column each, as dynamics.csv
    # names them (the files showed none of them)
    sched_cols = {} if schedule is None else {
        name: input_column(name) for name in schedule.points
        if name not in ("feed_moisture", "feed_rate", "fouling", "gas_inlet_temperature")}
    rec.update({col: [] for col in sched_cols.values()})
    times = []
    # a copy of the dryer (caches cleared: the run does not depend on what the caller solved before)
    d_cur = plant(dryer, gas_inlet_temperature=T0, feed_rate=F0, feed_moisture=base["feed_moisture"],
                  fouling=base["fouling"])
    integ = DryerIntegrator(d_cur, z)    # one integration, continued across the samples
    last_applied = (T0, F0, base["feed_moisture"], base["fouling"], ())
    fuel_of = {}    # the burner's fuel rate depends on the gas inputs only (a root solve, 3 ms each)
    v_fb = 0.0
    for k in range(n + 1):
        t = k * ts
        extra = {}
        if schedule is None:
            x, Fd, f = _disturbance(scenario, magnitude, t, t_step_s, t_end_s, base)
        else:
            u = schedule.inputs_at(t, sched_base)
            for name, col in sched_cols.items():
                rec[col].append(u[name])
            x, Fd, f = u.pop("feed_moisture", base["feed_moisture"]), u.pop("feed_rate", F0), u.pop("fouling", base["fouling"])
            extra = {_PLANT_NAMES[k]: v for k, v in u.items() if k != "gas_inlet_temperature"}
            T_sched = u.get("gas_inlet_temperature", T0)
        y = outputs_of(d_cur, z)
        meas_buf.append(y[cv])
        ym = meas_buf[max(0, len(meas_buf) - 1 - delay_n)]
        T_in, F_in, v = (T0 if schedule is None else T_sched), Fd, 0.0
        if controlled:
            v_ff = 0.0
            if cfg.feedforward != "off":
                ff_buf.append((x, Fd))
                ex = tuple(sorted((k, round(float(v), 12)) for k, v in extra.items()))
                v_end = ff_value(x, Fd, f, ex)      # what the disturbance will need: which ranges act
                dl = delays_by_ranges["gas" if vT[0] <= v_end <= vT[1] else "gas_and_feed"]

                def seen(delay_s, i):       # the disturbance i (0 feed moisture, 1 feed rate) delay_s ago
                    return ff_buf[max(0, len(ff_buf) - 1 - int(round(delay_s / ts)))][i]
                v_ff = ff_value(seen(dl["feed_moisture"], 0), seen(dl["feed_rate"], 1), f, ex)
            vF = split(0.0, Fd)[2]
            lo, hi = vT[0] + vF[0], vT[1] + vF[1]
            if pi is not None:
                v_fb = pi.step(sp, ym, lo - v_ff, hi - v_ff)
            v = float(np.clip(v_fb + v_ff, lo, hi))
            # split range: the gas temperature first, the rest by the feed rate
            T_in, F_in, _ = split(v, Fd)
        applied = (T_in, F_in, x, f, tuple(sorted(extra.items())))
        if applied != last_applied:       # the same inputs: the integration carries on as it is
            d_cur = plant(dryer, gas_inlet_temperature=T_in, feed_rate=F_in, feed_moisture=x, fouling=f, **extra)
            integ.restart(d_cur)
            last_applied = applied
        times.append(t)
        gas_key = (T_in, tuple(sorted((name, val) for name, val in extra.items()
                                      if name not in ("rotational_speed", "solid_inlet_temperature"))))
        if d_cur.settings.recycle_fraction or gas_key not in fuel_of:    # recycled exhaust: the state's, no cache
            fuel_of[gas_key] = _fuel(d_cur, z)
        for key, val in (("product_moisture_kg_kg", y["product_moisture"]),
                         ("product_temperature_degC", y["product_temperature"]),
                         ("exhaust_temperature_degC", y["exhaust_temperature"]),
                         ("exhaust_humidity_kg_kg", y["exhaust_humidity"]), ("holdup_kg", y["holdup"]),
                         ("measured", ym), ("gas_inlet_temperature_degC", T_in), ("feed_rate_kg_s", F_in),
                         ("feed_moisture_kg_kg", x), ("fouling", f), ("fuel_rate_kg_s", fuel_of[gas_key]),
                         ("controller_output", v), ("feed_rate_disturbance_kg_s", Fd)):
            rec[key].append(val)
        if k == n:
            break
        if progress and k % 10 == 0:
            progress(f"{'closed' if controlled else 'open'} loop: t = {t:.0f} / {t_end_s:.0f} s, "
                     f"{cv} = {y[cv]:.4g}")
        z = integ.advance(t + ts, land=controlled)     # a controller changes an input at almost every sample
    integ.close()
    if s.burner is not None:        # samples whose gas the burner cannot make (a schedule, recycled exhaust)
        short = [t for t, fuel in zip(times, rec["fuel_rate_kg_s"]) if fuel is None]
        if short:
            tuning["burner_short"] = dict(samples=len(short), first_s=short[0], last_s=short[-1],
                                          max_gas_inlet_temperature_degC=max(
                                              T for T, fuel in zip(rec["gas_inlet_temperature_degC"],
                                                                   rec["fuel_rate_kg_s"]) if fuel is None))
    # the measurement's dead time as applied: whole samples
    tuning["dead_time_applied_s"] = delay_n * ts
    series = {k: np.asarray(v, dtype=float if k != "fuel_rate_kg_s" else object) for k, v in rec.items()}
    tol = cfg.tolerance if cfg.tolerance is not None else TOLERANCE[cv]
    yk = "product_moisture_kg_kg" if cv == "product_moisture" else "exhaust_temperature_degC"
    perf = performance(times, series[yk], sp, t_step_s, tol, series["product_moisture_kg_kg"],
                       series["product_temperature_degC"], moisture_max=cfg.product_moisture_max,
                       temperature_band=cfg.product_temperature_band,
                       unit="kg/kg wet" if cv == "product_moisture" else "K")
    return ClosedLoopResult(np.asarray(times), series, sp, cv, tuning, perf,
                            dict(name=scenario, magnitude=magnitude, t_step_s=t_step_s, t_end_s=t_end_s,
                                 controlled=controlled), time.perf_counter() - t0)


def plot(closed: ClosedLoopResult, open_: ClosedLoopResult | None = None):
    """Figure: controlled variable (with setpoint and tolerance band), product temperature, and
    the manipulated variables (gas inlet temperature, feed rate), closed vs open loop."""
    from ._plotting import pyplot

    plt = pyplot()

    fig, ax = plt.subplots(4, 1, figsize=(8, 10), sharex=True)
    h = closed.time_s / 3600
    yk = "product_moisture_kg_kg" if closed.measured == "product_moisture" else "exhaust_temperature_degC"
    scale = 100 if closed.measured == "product_moisture" else 1
    unit = "product moisture, % wet" if scale == 100 else "exhaust temperature, degC"
    ax[0].plot(h, scale * closed.series[yk], label="closed loop")
    if open_ is not None:
        ax[0].plot(open_.time_s / 3600, scale * open_.series[yk], "--", label="open loop")
    sp, tol = closed.setpoint, closed.performance["tolerance"]
    ax[0].axhline(scale * sp, color="k", lw=0.8, label="setpoint")
    ax[0].axhspan(scale * (sp - tol), scale * (sp + tol), color="g", alpha=0.1, label="tolerance")
    ax[0].set_ylabel(unit)
    ax[0].legend(fontsize=8)
    ax[1].plot(h, closed.series["product_temperature_degC"], label="closed loop")
    if open_ is not None:
        ax[1].plot(open_.time_s / 3600, open_.series["product_temperature_degC"], "--", label="open loop")
    band = closed.performance.get("product_temperature_band_degC")     # the case's, when given
    if band is not None:
        ax[1].axhspan(*band, color="orange", alpha=0.1, label=f"specification {band[0]:g}-{band[1]:g} degC")
    ax[1].set_ylabel("product T, degC")
    ax[1].legend(fontsize=8)
    ax[2].step(h, closed.series["gas_inlet_temperature_degC"], where="post")
    ax[2].set_ylabel("gas inlet T, degC")
    ax[3].step(h, closed.series["feed_rate_kg_s"], where="post", label="manipulated feed")
    ax[3].set_ylabel("feed rate, kg/s")
    ax[3].set_xlabel("time, h")
    fig.tight_layout()
    return fig

