"""One orchestrator for every dryer: ``Simulation(case, overrides)``.

>>> from rotarydryer import Simulation
>>> sim = Simulation("song2003_ottawa")
>>> out = sim.steady_state().summary()             # transport + heat and mass, SI names
>>> [k for k in ("product_moisture_kg_kg", "product_temperature_degC") if k in out]
['product_moisture_kg_kg', 'product_temperature_degC']

The case (any kind: the general ``kind = "dryer"`` schema, or Lee's and Ajayi's plant cases)
becomes a list of [`SectionSpec`][rotarydryer.transport.sections.SectionSpec] ([`rotarydryer.cases.build`][rotarydryer.cases.build]),
from which [`build_sections`][rotarydryer.transport.sections.build_sections] builds the transport network;
the heat-and-mass model ([`ThermalDryer`][rotarydryer.thermal.dryer.ThermalDryer]) rides on the nodes and
edge families of a network built from the same specs with the case's thermal changes (closed
inlet, its own bed discretisation, properties from the computed moisture). Output names carry their unit (``_kg``, ``_kg_s``, ``_s``, ``_degC``, ``_kg_kg``,
``_W``); balances are relative errors.
"""

from __future__ import annotations

import dataclasses
import math
import os
import warnings

import numpy as np

from ._grids import MAX_POINTS, grid_product, parse_grid
from ._threads import single_threaded
from ._validation import check_choice, check_range
from ._workers import check_workers
from .cases import check_time_grid, load_case, load_case_text, measured_rtd, measured_rtd_moments
from .cases.build import (
    FILL_LIMIT,
    build_model,
    check_feasible,
    check_inputs,
    drum_fill_fraction,
    flat_case,
    has_burner,
    model_name,
    network_inputs,
    operating_point,
    takes_as_parameters,
    thermal_enabled,
    thermal_inputs,
    tracer_pulse,
    transport_inputs,
    warn_kiln_cells,
)
from .cases.calibration import same_value
from .executor import Executor, RunFailure, split
from .results import _jsonable, _numbers, add_thermal, fit_measured_rtd, from_transport, output_lines
from .thermal.audit import (
    CondensationWarning,
    SupersaturationWarning,
    condensation_message,
    shell_sections,
    supersaturation_message,
    warn_condensation,
    warn_shell_limit,
    warn_solids_temperature,
    warn_supersaturated_exhaust,
    warn_wet_solids,
)
from .thermal.dryer import DryerError, ThermalDryer, ThermalSettings
from .thermal.plots import plot_thermal_steady_state
from .thermal.schedule import InputSchedule, burner_fuel_rate, load_schedule, simulate_schedule
from .thermal.states import ThermalSteadyState, check_entrainment
from .thermal.studies import perturbed
from .transport.plots import plot_holdup_profile
from .transport.sections import build_sections

__all__ = ["Simulation", "SteadyResult", "build_thermal_dryer", "run_case", "grid_points", "parse_grid",
           "MAX_POINTS", "WARM_DT0", "check_finite", "FillWarning", "BurnerCapacityWarning"]


class FillWarning(UserWarning):
    """A dynamic run whose solids fill the drum beyond the fraction a steady state is refused at."""


class BurnerCapacityWarning(UserWarning):
    """A dynamic run that ends at a gas inlet temperature the case's burner cannot make."""


#: first pseudo-time step (s) of a coupled solve started from a nearby run's state
WARM_DT0 = 1e3


class Simulation:
    """A dryer case ready to solve.

    Parameters
    ----------
    case : str, path or validated case
        Packaged case name (``lee2008_invicta``, ``ajayi2011_mmg``, ``song2003_ottawa``), a
        ``.toml`` file, or a case object from `rotarydryer.cases.load_case`.
    overrides : dict, optional
        ``{"operating.feed_rate": 30.0, ...}`` (the CLI's ``--set``).
    """

    def __init__(self, case, overrides=None):
        if not (isinstance(case, (str, bytes)) or hasattr(case, "__fspath__") or hasattr(case, "kind")):
            raise ValueError(f"case = {case!r}: give a case name (rotarydryer cases), a .toml file or a case object "
                             "(rotarydryer.cases.load_case)")
        if overrides is not None and not isinstance(overrides, dict):
            raise ValueError(f"overrides = {overrides!r}: give a dict of case keys, e.g. {{'operating.feed_rate': 30.0}}")
        bad = [k for k in overrides or () if not isinstance(k, str)]
        if bad:     # {1: 2} failed inside the loader ("'int' object has no attribute 'startswith'")
            raise ValueError(f"overrides: key {bad[0]!r} is not a case key (a text such as 'operating.feed_rate')")
        if isinstance(case, (str, bytes)) or hasattr(case, "__fspath__"):
            self.case_name = str(case)
            #: the overrides the case was loaded with (kept by :meth:`sweep` and :meth:`fit`)
            self.overrides = dict(overrides or {})
            self.case = load_case(str(case), self.overrides)
        else:
            if overrides:
                raise ValueError("overrides need a case name or path (load_case applies them)")
            self.case_name = getattr(getattr(case, "meta", None), "title", "") or "case"
            self.overrides = {}
            self.case = case
        self.kind = self.case.kind
        self._named = isinstance(case, (str, bytes)) or hasattr(case, "__fspath__")   # rebuilt from its name
        self._case_text = None      # the TOML text of a Simulation made by `from_text` (rebuilt from it)
        self._inputs = None         # what the networks are built from (cases.build.transport_inputs)
        self._transport = None
        self._transport_ss = None
        self._dryer = None          # the heat-and-mass model of the case, built once
        self._thermal_ss = None
        self._flat = None           # the case's flat view (cases.build.flat_case), for the next run's comparison

    @classmethod
    def from_text(cls, text: str, name: str = "case", overrides=None) -> Simulation:
        """The Simulation of a case given as TOML text (`rotarydryer.cases.load_case_text`, ``name`` in messages),
        as of a file holding that text: its model is rebuilt from the text where a dynamic run's inputs move what
        its network depends on (an FMU runs the case text it stored at export)."""
        sim = cls(load_case_text(text, name, dict(overrides or {})))
        sim.case_name, sim.overrides = name, dict(overrides or {})
        sim._named, sim._case_text = True, text
        return sim

    def __repr__(self):
        return f"<Simulation {self.case_name} (kind {self.kind!r}, heat and mass {'on' if self.thermal_enabled else 'off'})>"

    def reloadable_name(self, what: str) -> str:
        """The case name or ``.toml`` path that ``what`` (a study that loads the case again for each of its runs:
        a sweep, a target, a fit, a calibration, an energy audit) reloads; ``ValueError`` for a Simulation made from a
        case object or from TOML text, which has neither."""
        if self._named and self._case_text is None:
            return self.case_name
        made = "TOML text (Simulation.from_text)" if self._case_text is not None else "a case object"
        raise ValueError(f"{what} loads the case again for each run, by its name or .toml path: this Simulation "
                         f"({self.case_name!r}) was made from {made}; give the case's name or .toml file "
                         "(Simulation('my_dryer.toml'))")

    @property
    def thermal_enabled(self) -> bool:
        return thermal_enabled(self.case)

    # ------------------------------------------------------------------ transport
    def transport_inputs(self) -> dict:
        """The section specs and operating values the case's networks are built from
        ([`rotarydryer.cases.build.transport_inputs`][rotarydryer.cases.build.transport_inputs]; the case checked), once."""
        if self._inputs is None:
            self._inputs = transport_inputs(self.case)
        return self._inputs

    @property
    def tracer_input(self):
        """The case's tracer pulse ([`TracerInput`][rotarydryer.transport.TracerInput], from its [tracer])."""
        if self._inputs is not None:
            return self._inputs["tracer_input"]
        return tracer_pulse(self.case)

    @property
    def model_name(self) -> str:
        """Name of the case's transport model (its flighted sections' model, e.g. ``lee2008``)."""
        return self.transport_model().name if self._transport is not None else model_name(self.case)

    def transport_model(self):
        """The solids-transport model (TransportModel on the network) of the case."""
        if self._transport is None:
            self._transport = build_model(self.case, self.transport_inputs())
        return self._transport

    def transport_steady_state(self):
        """Steady state of the solids transport; refused (``ValueError`` naming the keys) when the
        case is physically impossible: speed at or above the critical speed, solids filling more
        than `rotarydryer.cases.build.FILL_LIMIT` of the drum (see
        [`rotarydryer.cases.build.check_feasible`][rotarydryer.cases.build.check_feasible])."""
        if self._transport_ss is None:
            self._transport_ss = self.transport_model().steady_state()
        return self._transport_ss

    # ------------------------------------------------------------------ heat and mass
    def thermal_settings(self):
        """[`ThermalSettings`][rotarydryer.thermal.dryer.ThermalSettings] of the case."""
        return thermal_inputs(self.case)["settings"]

    def thermal_dryer(self, settings=None, feed_moisture=None, **overrides):
        """The heat-and-mass model on the case's sections: the transport model's section specs
        with the case's thermal changes (closed inlet, thermal discretisation, properties from the
        computed moisture). ``settings`` replaces the case's ThermalSettings, ``overrides`` set
        fields of them, ``feed_moisture`` (kg/kg wet) replaces the case's. Without arguments this
        is a new model each call; [`dryer`][rotarydryer.simulation.Simulation.dryer] is the Simulation's own, built once."""
        inp = thermal_inputs(self.case)
        st = settings if settings is not None else inp["settings"]
        unknown = sorted(set(overrides) - {f.name for f in dataclasses.fields(ThermalSettings)})
        if unknown:
            raise ValueError(f"unknown ThermalSettings field(s) {', '.join(map(repr, unknown))}; valid: "
                             f"{', '.join(f.name for f in dataclasses.fields(ThermalSettings))}")
        st = dataclasses.replace(st, **overrides)   # a copy: the caller's settings stay as they were
        base = self.transport_inputs()      # the specs alone: no transport-only network is built
        specs = [dataclasses.replace(sp, fouling=st.fouling, **inp["section_changes"].get(sp.name, {}))
                 for sp in base["sections"]]
        model = build_sections(specs, material=inp["material"], feed_rate=base["feed_rate"], rpm=base["rpm"],
                               slope=base["slope"], inlet="danckwerts", name="thermal",
                               tracer_input=base["tracer_input"])
        return ThermalDryer(model, material=inp["material"], feed_rate=base["feed_rate"],
                            feed_moisture=inp["feed_moisture"] if feed_moisture is None else feed_moisture,
                            rpm=base["rpm"], radius=self.case.drum.radius, sections=inp["sections"], settings=st)

    def _reparameterised(self, dryer):
        """``dryer`` (the heat-and-mass model of a case differing from this one in parameter values
        only) with this case's settings, feed rate and speed."""
        check_inputs(self.case)                 # as transport_inputs would (speed, drum, flights)
        settings = thermal_inputs(self.case)["settings"]
        F, rpm, _, _ = operating_point(self.case)
        return dryer.with_parameters(settings=settings, feed_rate=F, rpm=rpm)

    def dryer(self):
        """The case's heat-and-mass model ([`ThermalDryer`][rotarydryer.thermal.dryer.ThermalDryer]), built
        once per Simulation and reused by [`steady_state`][rotarydryer.simulation.Simulation.steady_state], [`dynamics`][rotarydryer.simulation.Simulation.dynamics] and [`results`][rotarydryer.simulation.Simulation.results]
        (do not change it in place: [`rotarydryer.thermal.studies.perturbed`][rotarydryer.thermal.studies.perturbed] makes changed copies)."""
        if self._dryer is None:
            self._dryer = self.thermal_dryer()
            needs = network_inputs(self.case)
            if needs and self._named:
                self._dryer._rebuild = _Rebuild(self.case_name, self.overrides, needs, self._case_text)
        return self._dryer

    # ------------------------------------------------------------------ runs
    @single_threaded()
    def steady_state(self, warm: dict | None = None):
        """Steady state of the whole dryer: transport, and heat and mass where the case has a gas.

        Without heat and mass transfer this is the transport steady state. With it, the coupled
        state, whose fill of the drum is checked ([`rotarydryer.cases.build.check_feasible`][rotarydryer.cases.build.check_feasible]):
        the transport-only model is neither built nor solved unless the coupled solve fails, when
        its feasibility check gives the physical reason where there is one. ``warm``
        ([`SteadyResult.warm_data`][rotarydryer.simulation.SteadyResult.warm_data] of a nearby run: coupled state, transport masses, shell
        temperatures, factorisation) starts the solves when its shapes fit; the state is the same
        steady state, accepted by the same convergence test (the case's cold start is tried when the
        warm one does not converge). When the nearby run's case differs from this one only in
        parameter values ([`rotarydryer.cases.build.takes_as_parameters`][rotarydryer.cases.build.takes_as_parameters]), its heat-and-mass model
        is reused with this case's values: no network is built; else the first of ``warm["models"]`` (other
        runs' Simulations) that does."""
        if warm is not None and not isinstance(warm, dict):
            raise ValueError(f"warm = {warm!r}: give the warm_data() of a nearby run's SteadyResult (a dict) or None")
        warm = warm or {}
        # the nearby run's model, else one of ``warm["models"]`` (other runs' Simulations, e.g. a study's earlier
        # runs on other networks): the first that differs from this case in parameter values only is reused
        for source in (warm.get("simulation"), *warm.get("models", ())):
            if self._dryer is not None or not self.thermal_enabled:
                break
            if source is not None and source._dryer is not None \
                    and takes_as_parameters(source.case, self.case, (source._flat_case(), self._flat_case())):
                self._dryer = self._reparameterised(source._dryer)
        if not self.thermal_enabled:
            masses = warm.get("masses")
            if self._transport_ss is None and masses is not None:
                net = self.transport_model().network
                if np.shape(masses) == (net.n,):
                    net.initial_guess = masses        # Newton from a nearby run's masses
            result = SteadyResult(self, self.transport_steady_state(), None)
            warn_kiln_cells(self.case, result.state)     # the reported state's kilning beds, once a run
            return result
        state = warm.get("state")
        if self._thermal_ss is None and state is not None:
            d = self.dryer()
            if np.shape(state) == (d.n,):
                shell = warm.get("shell")
                if shell is not None and np.shape(shell) == (d.n_gas,):
                    d._shell_outer = np.array(shell)    # Newton's start of the first shell solve
                try:
                    self._thermal_ss = d.steady_state(z0=state, dt0=WARM_DT0, factorization=warm.get("factorization"))
                except ValueError:                  # DryerError: the case's own cold start, on a new model
                    self._dryer = None
        try:
            thermal = self.thermal_steady_state()
        except DryerError:
            self.transport_steady_state()           # an impossible dryer is refused with its physical reason
            raise
        check_feasible(self.case, thermal.transport_state())
        warn_kiln_cells(self.case, thermal.transport_state())
        check_entrainment(thermal)
        warn_shell_limit(thermal)           # a shell hotter than shell.max_temperature: a warning, not an error
        warn_supersaturated_exhaust(thermal)     # an exhaust below its own dew point: a warning
        warn_condensation(thermal)          # a product wetter than the feed: a warning
        warn_solids_temperature(thermal)    # solids above their material's max_temperature: a warning
        warn_wet_solids(thermal)            # wet solids above the boiling point: a warning
        return SteadyResult(self, None, thermal)

    def _flat_case(self) -> dict:
        """The case's flat view, once (a study's next run compares its case with this one)."""
        if self._flat is None:
            self._flat = flat_case(self.case)
        return self._flat

    #: width of the smoothed design-load switch of the start model when the coupled Newton chatters
    START_SMOOTHING = 1e-3

    def thermal_steady_state(self):
        """Coupled steady state of the case's heat-and-mass model. When its Newton iteration
        chatters on the design-load switch min(M_P, M_des) or a kink of the exact loading factor
        (a cell at its design load or where a flight fills, e.g. small feeds), it is restarted from
        the steady state of the same model with the switch smoothed over ten times the case's
        width (at least `START_SMOOTHING` of M_des); the state returned is always that of the
        case's own model, accepted by its own convergence test."""
        if self._thermal_ss is not None:
            return self._thermal_ss
        d = self.dryer()
        try:
            ss = d.steady_state()
        except DryerError as exc:
            w = d.settings.design_load_smoothing
            if exc.reason != "no_steady_state" or w >= 0.01:
                raise
            try:   # continuation in the width: from a 10x wider switch (at least START_SMOOTHING)
                start = self.thermal_dryer(design_load_smoothing=max(self.START_SMOOTHING, 10.0 * w)).steady_state()
                ss = d.steady_state(z0=start.state)
            except DryerError:
                raise exc from None
        self._thermal_ss = ss
        return ss

    def dynamics(self, t_end=7200.0, dt=60.0, **changes):
        """Response from the steady state to new inputs ``changes`` (names of
        `rotarydryer.thermal.studies.INPUTS` or ThermalSettings fields, absolute values)."""
        t_end = float(check_range("t_end", t_end, 0.0, 30 * 86400.0, unit="s"))
        dt = float(check_range("dt", dt, 0.0, t_end, high_inclusive=True, unit="s"))
        if t_end / dt > 100000:
            raise ValueError(f"dt = {dt:g} s: {t_end / dt:.0f} points in {t_end:g} s, at most 100000")
        d = self.dryer()
        ss = self.thermal_steady_state()
        d2 = perturbed(d, **changes) if changes else d
        return d2.simulate(ss.state, t_end, t_eval=np.arange(0.0, t_end + dt / 2, dt))

    def dynamic_start(self, run: str = "a dynamic run", progress=None):
        """The coupled steady state a dynamic run (``run``: its name in the message) starts from; a
        case without a gas is refused, the transport's feasibility (critical speed, fill) checked
        first. ``progress("steady state ...")`` before the solve."""
        if not self.thermal_enabled:
            why = ("has no [gas] block" if self.case.gas is None
                   else "has the heat-and-mass model switched off (thermal.enabled = false)")
            raise ValueError(f"case {self.case_name!r} {why}: {run} needs the heat-and-mass model")
        if progress:
            progress("steady state ...")
        self.transport_steady_state()
        return self.thermal_steady_state()

    def run_schedule(self, schedule=None, t_end=7200.0, dt=60.0, progress=None):
        """Response from the coupled steady state to an input ``schedule`` (an
        [`InputSchedule`][rotarydryer.thermal.schedule.InputSchedule], a .csv/.toml path, or None for
        the case's own inputs), reported every ``dt`` s for ``t_end`` s; the
        [`ScheduleResult`][rotarydryer.thermal.schedule.ScheduleResult] of ``rotarydryer dynamics``."""
        if schedule is not None and not isinstance(schedule, InputSchedule):
            schedule = load_schedule(schedule)
        steady = self.dynamic_start("dynamics", progress)
        step = None
        if progress is not None:
            def step(done, total):
                progress(f"t = {done:.0f} / {total:.0f} s")
        result = simulate_schedule(steady.dryer, steady.state, schedule, t_end, dt, progress=step)
        self._warn_fill(result)
        self._warn_end(result)
        return result

    @staticmethod
    def _warn_end(result) -> None:
        """The warnings `simulate` gives, on a dynamic run's last state with its last inputs: an exhaust below its
        dew point, a product wetted, a gas inlet temperature the case's burner cannot make (found by a check of the
        time-dependent surfaces: a run ending supersaturated, or at 600 degC from a burner that makes 586, said
        nothing)."""
        dr = result.final_dryer
        if dr is None or result.states.shape[1] == 0:
            return
        z = result.states[:, -1]
        try:
            end = ThermalSteadyState(dr, z)
        except (ValueError, ArithmeticError):
            return
        for message, category in ((supersaturation_message(end), SupersaturationWarning),
                                  (condensation_message(end), CondensationWarning)):
            if message:
                warnings.warn(f"at the end of the run (t = {float(result.time_s[-1]):g} s): {message}", category,
                              stacklevel=3)
        if dr.settings.burner is not None:
            try:
                fuel = burner_fuel_rate(dr, z)
                held = result.inputs.get("burner_fuel_rate")
                if held is not None and dr.settings.recycle_fraction and len(held) and \
                        abs(fuel - float(held[-1])) > 5e-3 * max(float(held[-1]), 1e-12):
                    warnings.warn(
                        f"at the end of the run (t = {float(result.time_s[-1]):g} s): the burner burns {fuel:.4g} kg/s "
                        f"for the gas it makes, not the scheduled {float(held[-1]):.4g} kg/s: with exhaust recycle a "
                        "fuel rate becomes a gas inlet temperature at its change, with the exhaust of that moment, and "
                        "the recycled exhaust moves after it (schedule gas_inlet_temperature for a held temperature)",
                        BurnerCapacityWarning, stacklevel=3)
            except ValueError as exc:
                warnings.warn(f"at the end of the run (t = {float(result.time_s[-1]):g} s): {' '.join(str(exc).split())}"
                              " (the run holds the gas inlet temperature the plant's burner cannot make)",
                              BurnerCapacityWarning, stacklevel=3)

    def _warn_fill(self, result) -> None:
        """Warn (`FillWarning`) where a dynamic run's solids fill the drum beyond `FILL_LIMIT`, the limit a
        steady state is refused at: the holdup scaled from the start's fill (found by fuzzing: a schedule's feed of
        500 kg/s put 127 t of sand, about 77 m^3, into a 37.7 m^3 drum without a word)."""
        hold = np.asarray(result.outlets.get("holdup", []), dtype=float)
        if hold.size == 0 or not hold[0] > 0:
            return
        f0 = drum_fill_fraction(self.case, self.steady_state().state)
        i = int(np.argmax(hold))
        peak = f0 * hold[i] / hold[0]
        if math.isfinite(peak) and peak > FILL_LIMIT:
            warnings.warn(f"the solids fill about {peak:.0%} of the drum at t = {result.time_s[i]:g} s ({hold[i]:,.0f} kg "
                          f"against {hold[0]:,.0f} kg at the start, {f0:.1%} full): beyond the {FILL_LIMIT:.0%} at "
                          "which a steady state is refused, where the transport laws do not hold; schedule a smaller "
                          "feed rate or speed change", FillWarning, stacklevel=3)

    def rtd(self, t_end=None, dt=None, method="auto", *, thermal: bool = False):
        """Tracer response with the case's tracer pulse at the solids transport's own steady state (the case's
        assumed moisture profile: the published transport models', `rotarydryer rtd`'s and `validate`'s), or with
        ``thermal=True`` at the coupled heat-and-mass state that [`results`][rotarydryer.simulation.Simulation.results] and
        [`SteadyResult.summary`][rotarydryer.simulation.SteadyResult.summary] report (``rotarydryer rtd --coupled``). ``t_end`` and ``dt`` (s):
        the case's ``[tracer]`` values when not given."""
        tr = self.case.tracer
        if thermal and not self.thermal_enabled:
            raise ValueError(f"thermal = True: case {self.case_name!r} has no heat and mass transfer (thermal.enabled = "
                             "false or no [gas])")
        t_end = tr.t_end if t_end is None else float(check_range("t_end", t_end, 0.0, unit="s"))
        dt = tr.dt if dt is None else float(check_range("dt", dt, 0.0, unit="s"))
        # the case loader's limits on its tracer's time grid, for a grid given here (t_end = 1e7 s at dt = 1 s ran
        # on past a minute, 1e9 s at 1e-3 s asked for 7 TiB; found by an acceptance check)
        check_time_grid(t_end, dt, getattr(tr, "duration", None), "t_end", "dt")
        state = self.steady_state().state if thermal else self.transport_steady_state()
        return state.rtd(self.transport_model().tracer_input, t_end=t_end, dt=dt, method=method)

    def results(self, *, rtd: bool = True, method: str = "auto", fit_rtd: bool = False,
                thermal: bool | None = None):
        """[`rotarydryer.results.Results`][rotarydryer.results.Results] of the case: the steady state (coupled with heat and
        mass where the case has a gas; ``thermal=False`` for the solids transport alone), with
        ``rtd=True`` the case's tracer pulse simulated at that state and its measured curve, with
        ``fit_rtd=True`` the classical RTD models fitted to the measured curve. Every dataset
        (nodes, cells, sections, rtd) and scalar is that one state's."""
        c = self.case
        model = self.transport_model()
        if thermal is None:
            thermal = self.thermal_enabled
        steady = self.steady_state() if thermal else SteadyResult(self, self.transport_steady_state(), None)
        view = steady.state
        r = meas = None
        if rtd:
            r = view.rtd(model.tracer_input, t_end=c.tracer.t_end, dt=c.tracer.dt, method=method)
            meas = measured_rtd(c)
        res = from_transport(c, model, view, r, meas, case_name=self.case_name)
        if meas is not None:
            mm = measured_rtd_moments(c)  # rotarydryer.rtd.rtd_moments with the case's baseline
            res.scalars.update(measured_mean_s=float(mm["mean_s"]), measured_std_s=float(mm["std_s"]),
                               measured_baseline=float(mm["baseline"]))
        if fit_rtd and meas is not None:
            res.datasets["rtd_fits"] = fit_measured_rtd(meas[0], meas[1], c.tracer.duration)
        if steady.thermal is not None:
            add_thermal(res, steady.thermal)
            merged = steady.merged(res.scalars)
            res.scalars = _numbers(merged)
            if merged.get("fuel_rate_error"):     # why the fuel rate is n/a (the report says it)
                res.model_choices["fuel_rate_error"] = " ".join(str(merged["fuel_rate_error"]).split())
            res.model_choices["datasets"] = "coupled heat-and-mass steady state"
        if self.overrides:
            res.model_choices["overrides"] = _jsonable(self.overrides)
        check_finite(res.scalars, self.case_name)
        return res

    def fit(self, dataset, parameters, **kwargs):
        """Fit ``parameters`` (override keys, e.g. ``["transport.backmix"]``) to a measured tracer
        curve: a [`rotarydryer.rtd.TracerData`][rotarydryer.rtd.TracerData] or a shipped dataset name
        (``"lee2008_invicta"``); keyword arguments as
        [`rotarydryer.estimation.cases.fit_case_to_tracer`][rotarydryer.estimation.cases.fit_case_to_tracer], starting from this Simulation's
        overrides (``base_overrides`` adds to them). Returns its ``CaseFit``."""
        from .estimation.cases import fit_case_to_tracer  # estimation builds on Simulation
        from .rtd import load_tracer_dataset

        if isinstance(dataset, str):
            dataset = load_tracer_dataset(dataset)
        base = {**self.overrides, **(kwargs.pop("base_overrides", None) or {})}
        return fit_case_to_tracer(self.reloadable_name("a fit"), dataset, _keys(parameters), base_overrides=base or None,
                                  **kwargs)

    def target(self, find, such_that, bounds=None, **kwargs):
        """The value of the case input ``find`` (e.g. ``"operating.feed_rate"``) in ``bounds`` that
        meets ``such_that`` (e.g. ``"product_moisture_kg_kg<=0.12"``), starting from this
        Simulation's overrides; keyword arguments and the returned ``TargetResult`` as
        `rotarydryer.studies.target.target`."""
        from .studies.target import target  # the target study builds on Simulation

        return target(self, find, such_that, bounds, **kwargs)

    def calibrate(self, parameters, **kwargs):
        """Fit case keys ``parameters`` to several measured responses of many tests at once, from this
        Simulation's case and overrides (keyword arguments as
        `rotarydryer.estimation.calibrate.calibrate`; ``base_overrides`` adds to the overrides).
        Returns its `CaseCalibration` (``.record()``: the
        calibration record)."""
        from .estimation.calibrate import calibrate  # estimation builds on Simulation

        base = {**self.overrides, **(kwargs.pop("base_overrides", None) or {})}
        return calibrate(self.reloadable_name("a calibration"), _keys(parameters), base_overrides=base or None, **kwargs)

    def sweep(self, grid, outputs=None, *, workers: int = 1, scheduler=None, cluster=None, executor=None,
              progress=None):
        """Steady state over a grid of overrides on top of this Simulation's: a list of override
        dicts, or the CLI's form, a dict ``{key: [values]}`` or ``["key=v1,v2", ...]`` (the cartesian
        product). Returns one dict per point: its overrides and [`SteadyResult.summary`][rotarydryer.simulation.SteadyResult.summary]
        (``outputs``: only these names); a point that fails is its overrides and ``error`` (one line).

        The points run through the one executor ([`rotarydryer.executor.Executor`][rotarydryer.executor.Executor]: ``executor``, or one
        of ``workers`` local processes (as ``--workers``: 0 one per core, more than the cores or the points
        capped with a warning), a Dask ``scheduler`` address or a ``cluster`` "local:N"), in
        chunks that depend on the number of points only; in a chunk each point is warm-started from
        the one before it (the same steady state, on the previous point's heat-and-mass model when
        only parameter values differ). Every backend gives the same rows, bit for bit.
        ``progress(n)`` after each chunk of ``n`` points."""
        name = self.reloadable_name("a sweep")
        points = grid_points(grid)
        outputs = _output_names(outputs)
        if executor is not None and not isinstance(executor, Executor):
            raise ValueError(f"executor = {executor!r} is not a rotarydryer.executor.Executor")
        if executor is None:
            # the CLI's checks of --workers (a negative, fractional or text count ran as one worker without a word;
            # found by an acceptance check); its notes (more than the cores or the points: capped) as warnings
            n, notes = check_workers(workers, len(points), scheduler=scheduler or cluster, option="workers")
            for note in notes:
                warnings.warn(note, stacklevel=2)
            executor = Executor(workers=max(1, n), scheduler=scheduler, cluster=cluster)
        ex = executor
        chunks = split(len(points), min_size=SWEEP_MIN_CHUNK, max_size=SWEEP_MAX_CHUNK)
        warm = ((_sweep_warm, (name, {**self.overrides, **points[0]})),) if points else ()
        rows = ex.map_chunks(_sweep_chunk, points, chunks=chunks, args=(name, self.overrides, outputs),
                             warm=warm, progress=progress)
        return [{**ov, "error": r.error} if isinstance(r, RunFailure) else r for ov, r in zip(points, rows)]


#: fewest points of a sweep chunk (`Simulation.sweep`, `rotarydryer.studies.sweep`): a chunk of warm-started
#: coupled runs (about 20 ms each) then costs at least 20 times the dispatch of a Dask task (about 5 ms of CPU;
#: the local pool's is 0.2 ms)
SWEEP_MIN_CHUNK = 5
#: most points of a sweep chunk (a long sweep keeps many chunks to share among workers)
SWEEP_MAX_CHUNK = 32


def _sweep_warm(case_name, overrides: dict) -> None:
    """A worker's warm-up before its first chunk of `Simulation.sweep`: imports, compiled kernels,
    geometry tables, one model built and solved (its errors are the runs' to report)."""
    try:
        Simulation(case_name, overrides).steady_state()
    except (ValueError, ArithmeticError):
        pass


def _keys(parameters) -> list:
    """Case keys to fit as a list: one key given as a text is that key ("transport.backmix" was read one letter at a
    time, "unknown parameter key 't'"; found by an acceptance check)."""
    return [parameters] if isinstance(parameters, str) else list(parameters)


def _output_names(outputs):
    """``outputs`` of a summary or a sweep as a list of names (None: all), or a one-line ValueError."""
    if outputs is None:
        return None
    if isinstance(outputs, (str, bytes)):
        raise ValueError(f"outputs = {outputs!r}: give a list of output names, e.g. [{outputs!r}]")
    try:
        names = list(outputs)
    except TypeError:
        raise ValueError(f"outputs = {outputs!r}: give a list of output names") from None
    wrong = [o for o in names if not isinstance(o, str)]
    if wrong:
        raise ValueError(f"outputs: {wrong[0]!r} is not an output name (a text such as 'product_moisture_kg_kg')")
    return names


def _sweep_chunk(points, case_name, base: dict, outputs):
    """Rows of a chunk of `Simulation.sweep`, in order, each point warm-started from the last converged
    one before it in the chunk (the first cold). Top-level, so that it pickles for worker processes."""
    rows, warm = [], None
    for ov in points:
        try:
            res = Simulation(case_name, {**base, **ov}).steady_state(warm=warm)
        except (ValueError, ArithmeticError) as exc:     # one bad point never ends the sweep
            rows.append({**ov, "error": " ".join(str(exc).split()) or type(exc).__name__})
            continue
        warm = res.warm_data() or warm
        row = dict(ov)
        try:        # a name this run does not give (a typo): one line, not the KeyError's "'name'"
            row.update(res.summary(None if outputs is None else [k for k in outputs if k not in ov]))
        except ValueError as exc:
            rows.append({**ov, "error": " ".join(str(exc).split())})
            continue
        rows.append(row if outputs is None else {**ov, **{k: row[k] for k in outputs}})
    return rows


def check_finite(outputs: dict, case_name: str) -> None:
    """Refuse a run whose numeric outputs are not finite (the mass balance error excepted: it may be
    0/0 for an empty network), naming them."""
    bad = [k for k, v in outputs.items() if isinstance(v, (int, float)) and not isinstance(v, bool)
           and k != "mass_balance_error" and not math.isfinite(v)]
    if bad:
        raise ValueError(f"case {case_name!r}: non-finite results {', '.join(bad)}")


def grid_points(grid) -> list[dict]:
    """Override dicts of a sweep grid: a list of dicts (as given), a dict ``{key: [values]}`` or a
    list of ``"key=v1,v2,..."`` strings (the CLI's ``--grid``): the cartesian product, in order."""
    if isinstance(grid, dict):
        keys = list(grid)
        values = [list(v) if isinstance(v, (list, tuple, np.ndarray)) else [v] for v in grid.values()]
        return grid_product(keys, values, "grid")
    if isinstance(grid, str) or not isinstance(grid, (list, tuple)):
        raise ValueError(f"grid = {grid!r}: give a list of override dicts, a dict {{key: [values]}} or a list of "
                         "'key=v1,v2' strings")
    grid = list(grid)
    if all(isinstance(g, str) for g in grid):
        return parse_grid(grid)
    if not all(isinstance(g, dict) for g in grid):
        raise ValueError("grid: give a list of override dicts, a dict {key: [values]} or 'key=v1,v2' strings")
    return grid


def run_case(case, overrides: dict | None = None, *, rtd: bool = True, method: str = "auto",
             fit_rtd: bool = False, thermal: bool | None = None, applied: dict | None = None):
    """``Simulation(case, overrides).results(...)``: a case name, ``.toml`` path or validated case
    solved into a [`rotarydryer.results.Results`][rotarydryer.results.Results] (see [`Simulation.results`][rotarydryer.simulation.Simulation.results]).
    ``overrides`` need a name or path (the case loader applies them); ``applied``: the overrides a case object
    was loaded with (``load_case(name, applied)``), recorded in the results' provenance."""
    if isinstance(case, (str, os.PathLike)):
        if applied:
            raise ValueError("applied = the overrides a case object was loaded with; with a case name or path "
                             "give them as overrides")
        sim = Simulation(case, overrides)
    else:
        if overrides:
            flat = flat_case(case)
            missing = [k for k, v in overrides.items() if k not in flat or not same_value(flat[k], v)]
            if missing:     # the case object does not hold them: they would be recorded, not applied
                k = missing[0]
                raise ValueError(f"overrides need a case name or path (load_case applies them): this case object has "
                                 f"{k} = {flat.get(k, 'no such key')!r}, not {overrides[k]!r}; a case object loaded "
                                 "with overrides names them with applied=")
            warnings.warn("run_case(case_object, overrides): the overrides a case object was loaded with are named "
                          "with applied= (overrides= with a case object is deprecated)", DeprecationWarning,
                          stacklevel=2)
            applied = {**overrides, **(applied or {})}
        sim = Simulation(case)
        sim.case_name = getattr(getattr(case, "meta", None), "title", "")
        sim.overrides = dict(applied or {})
    return sim.results(rtd=rtd, method=method, fit_rtd=fit_rtd, thermal=thermal)


def build_thermal_dryer(case, settings=None, feed_moisture=None, **overrides):
    """Heat-and-mass model of a validated case: ``Simulation(case).thermal_dryer(...)``."""
    return Simulation(case).thermal_dryer(settings=settings, feed_moisture=feed_moisture, **overrides)


class SteadyResult:
    """Steady state of a [`Simulation`][rotarydryer.simulation.Simulation]: one total holdup, one set of names.

    ``transport``: the transport-only steady state (no gas) or None; ``thermal``: the coupled
    [`ThermalSteadyState`][rotarydryer.thermal.dryer.ThermalSteadyState] or None. With heat and mass transfer
    every holdup, residence time and tracer moment is that of the coupled state (the tracer
    system is built on its flows), so the numbers add up.
    """

    def __init__(self, sim, transport, thermal):
        self.simulation, self.transport, self.thermal = sim, transport, thermal

    def __repr__(self):
        from ._display import short_repr

        out = self.summary()
        keys = ("total_holdup_kg", "mean_residence_time_s", "product_moisture_kg_kg", "gas_outlet_temperature_degC")
        return short_repr("SteadyResult", self.simulation.case_name, [(k, out[k]) for k in keys if k in out])

    def _repr_html_(self):
        from ._display import html_table

        return html_table(self.summary(), caption=f"steady state of {self.simulation.case_name}")

    def plot(self, what: str = "holdup"):
        """The figures ``rotarydryer simulate --out`` writes, from this state: ``"holdup"`` (holdup
        per metre along the dryer, titled with the total), ``"thermal"`` (temperatures, moisture and
        humidity; cases with heat and mass transfer), or ``"all"`` (a dict of both). Returns
        matplotlib figures."""
        check_choice("what", what, ("holdup", "thermal", "all"))
        if what == "thermal" and self.thermal is None:
            raise ValueError("what = 'thermal': the case has no heat and mass transfer (no [gas])")
        figs = {"holdup": plot_holdup_profile(self.state, name=self.simulation.model_name)} \
            if what in ("holdup", "all") else {}
        if what in ("thermal", "all") and self.thermal is not None:
            figs["thermal"] = plot_thermal_steady_state(self.thermal)
        return figs if what == "all" else figs[what]

    def summary_text(self) -> str:
        """[`summary`][rotarydryer.simulation.SteadyResult.summary] as plain text, one output a line (units from the names)."""
        return "\n".join([f"steady state of {self.simulation.case_name}", *output_lines(self.summary())])

    def to_dataframe(self):
        """[`summary`][rotarydryer.simulation.SteadyResult.summary] as a pandas DataFrame (value, unit)."""
        from ._display import outputs_dataframe

        return outputs_dataframe(self.summary())

    @property
    def state(self):
        """The solids of this state as a transport steady state: the coupled one
        ([`ThermalSteadyState.transport_state`][rotarydryer.thermal.states.ThermalSteadyState.transport_state]) with heat and mass, else the transport one.
        Its holdups, section and cell tables and tracer system are what every view shows."""
        return self.thermal.transport_state() if self.thermal is not None else self.transport

    def warm_data(self) -> dict | None:
        """What starts a nearby run ([`Simulation.steady_state`][rotarydryer.simulation.Simulation.steady_state] ``warm``): the coupled state,
        the transport masses, the shell temperatures and the last factorisation; None without heat
        and mass transfer."""
        th = self.thermal
        if th is None:
            return None
        ts = self.simulation._transport_ss
        return dict(state=th.state, masses=None if ts is None else ts.masses,
                    shell=th.dryer._shell_outer, factorization=th.factorization, simulation=self.simulation)

    def to_dict(self) -> dict:
        """[`summary`][rotarydryer.simulation.SteadyResult.summary] with the ``sections`` and ``cells`` tables of [`state`][rotarydryer.simulation.SteadyResult.state] (the
        object ``rotarydryer simulate --json`` prints, less ``case`` and ``parameters``)."""
        out = self.state.to_dict()
        out["model"] = self.simulation.model_name
        out = self.merged(out)
        if self.thermal is not None:      # the transport-only model's total, under its own name
            out["transport_only_total_holdup_kg"] = self.simulation.transport_steady_state().total_holdup
            out["shell_sections"] = shell_sections(self.thermal)    # the shell's loss and temperatures per section
        return out

    def tracer_system(self):
        """Linear tracer system at this state's flows (the coupled one with heat and mass)."""
        return self.state.tracer_system()

    def tracer_moments(self):
        """Analytic moments of the outlet curve for the case's tracer pulse (from the injection start)."""
        return self.tracer_system().moments(self.simulation.tracer_input)

    #: outputs of :meth:`summary` from the tracer system of the state (analytic moments)
    TRACER_OUTPUTS = ("tracer_mean_s", "tracer_std_s", "tracer_skewness", "recovery", "rtd_mean_residence_time_s",
                      "rtd_std_s", "rtd_skewness")

    def summary(self, outputs=None, *, strict: bool = True) -> dict:
        """Outputs named with their unit: holdups, residence time, tracer moments and, with heat
        and mass transfer, [`ThermalSteadyState.summary`][rotarydryer.thermal.states.ThermalSteadyState.summary] (the fuel rate where the case has a
        burner). The transport-only model's total holdup, where wanted, is in [`to_dict`][rotarydryer.simulation.SteadyResult.to_dict]
        (``transport_only_total_holdup_kg``): the summary is this state's alone. ``outputs`` (names):
        the groups that cost a computation (tracer moments, fuel rate, kiln bed, fill fraction, and of
        the heat-and-mass state the heat duties and efficiency, the shell temperatures, the dew point
        and the product at a downstream sensor) are left out unless named; the values of the others
        are the same. A named output this run does not give is a ``ValueError`` naming it and the outputs there
        are (``strict=False``: left out, for a study that records why it is missing)."""
        outputs = _output_names(outputs)
        want = None if outputs is None else set(outputs)
        if self.thermal is not None:
            fuel = has_burner(self.simulation.case) and (want is None or "fuel_rate_kg_s" in want)
            out = self.thermal.summary(with_fuel=fuel, outputs=outputs)
            if want is None or "kiln_bed_holdup_kg" in want:
                out["kiln_bed_holdup_kg"] = self.state.kiln_bed_holdup
        else:
            ss = self.transport
            out = dict(total_holdup_kg=ss.total_holdup, active_holdup_kg=ss.active_holdup,
                       passive_holdup_kg=ss.passive_holdup, bed_holdup_kg=ss.bed_holdup,
                       feed_rate_kg_s=float(self.simulation.transport_model().feed_rate),
                       outlet_flow_kg_s=ss.outlet_flow, mean_residence_time_s=ss.mean_residence_time)
        if want is None or "fill_fraction" in want:
            out["fill_fraction"] = drum_fill_fraction(self.simulation.case, self.state)
        if want is None or want & set(self.TRACER_OUTPUTS):
            ts = self.tracer_system()
            m = ts.moments(self.simulation.tracer_input)
            impulse = ts.moments()
            # analytic moments, named as RTDResult.to_dict names them (the impulse response's with rtd_)
            out.update(tracer_mean_s=m["mean"], tracer_std_s=m["std"], tracer_skewness=m["skewness"],
                       recovery=impulse["recovery"], rtd_mean_residence_time_s=impulse["mean"],
                       rtd_std_s=impulse["std"], rtd_skewness=impulse["skewness"])
        absent = [k for k in outputs or () if k not in out]
        if absent and strict:      # a misspelt name returned the whole summary without a word (found by an acceptance check)
            raise ValueError(f"outputs {absent}: not among this run's outputs ({', '.join(sorted(out))})")
        return out

    def merged(self, transport_outputs: dict) -> dict:
        """``transport_outputs`` (the transport-only model's, e.g. ``SteadyState.to_dict()`` or a
        Results' scalars) overwritten by [`summary`][rotarydryer.simulation.SteadyResult.summary]: one value per name in every view."""
        out = dict(transport_outputs)
        out.update(self.summary())
        return out


#: the schedule inputs (ThermalDryer.rebuilt) -> the case keys they are
_INPUT_KEYS = {"gas_inlet_temperature": "gas.inlet_temperature", "gas_flow": "gas.flow",
               "gas_inlet_humidity": "gas.inlet_humidity", "rpm": "operating.rpm", "feed_rate": "operating.feed_rate"}


class _Rebuild:
    """The heat-and-mass model of a case rebuilt at new values of inputs its network depends on
    (`rotarydryer.thermal.dryer.ThermalDryer.rebuilt`); picklable, the last few models kept."""

    def __init__(self, case_name, overrides, needs, case_text=None):
        self.case_name, self.overrides, self.needs = case_name, dict(overrides), frozenset(needs)
        self.case_text = case_text      # a case given as text (`Simulation.from_text`): rebuilt from it
        self._built: dict = {}

    def __call__(self, values: dict):
        key = tuple(sorted(values.items()))
        if key not in self._built:
            if len(self._built) >= 16:
                self._built.clear()
            ov = {**self.overrides, **{_INPUT_KEYS[k]: float(v) for k, v in values.items()}}
            sim = (Simulation(self.case_name, ov) if self.case_text is None
                   else Simulation.from_text(self.case_text, self.case_name, ov))
            self._built[key] = sim.thermal_dryer()
        return self._built[key]
