"""One orchestrator for every dryer: ``Simulation(case, overrides)``.

>>> from rotarydryer import Simulation
>>> sim = Simulation("song2003_ottawa")
>>> out = sim.steady_state().summary()             # transport + heat and mass, SI names
>>> sorted(k for k in out if k.startswith("product_"))[:2]
['product_moisture_kg_kg', 'product_temperature_degC']

The case (any kind: the general ``kind = "dryer"`` schema, or Lee's and Ajayi's plant cases)
becomes a list of :class:`~rotarydryer.transport.sections.SectionSpec` (:mod:`rotarydryer.cases.build`),
from which :func:`~rotarydryer.transport.sections.build_sections` builds the transport network;
the heat-and-mass model (:class:`~rotarydryer.thermal.dryer.ThermalDryer`) rides on the nodes and
edge families of a network built from the same specs with the case's thermal changes (closed
inlet, its own bed discretisation, properties from the computed moisture). Output names carry their unit (``_kg``, ``_kg_s``, ``_s``, ``_degC``, ``_kg_kg``,
``_W``); balances are relative errors.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ._threads import single_threaded

__all__ = ["Simulation", "SteadyResult", "build_thermal_dryer"]


class Simulation:
    """A dryer case ready to solve.

    Parameters
    ----------
    case : str, path or validated case
        Packaged case name (``lee2008_invicta``, ``ajayi2011_mmg``, ``song2003_ottawa``), a
        ``.toml`` file, or a case object from :func:`rotarydryer.cases.load_case`.
    overrides : dict, optional
        ``{"operating.feed_rate": 30.0, ...}`` (the CLI's ``--set``).
    """

    def __init__(self, case, overrides=None):
        from .cases import load_case

        if isinstance(case, (str, bytes)) or hasattr(case, "__fspath__"):
            self.case_name = str(case)
            self.case = load_case(str(case), overrides or {})
        else:
            if overrides:
                raise ValueError("overrides need a case name or path (load_case applies them)")
            self.case_name = getattr(getattr(case, "meta", None), "title", "") or "case"
            self.case = case
        self.kind = self.case.kind
        self._transport = None
        self._transport_ss = None

    def __repr__(self):
        return f"<Simulation {self.case_name} (kind {self.kind!r}, heat and mass {'on' if self.thermal_enabled else 'off'})>"

    @property
    def thermal_enabled(self) -> bool:
        from .cases.build import thermal_enabled

        return thermal_enabled(self.case)

    # ------------------------------------------------------------------ transport
    def transport_model(self):
        """The solids-transport model (TransportModel on the network) of the case."""
        if self._transport is None:
            from .cases.build import build_model

            self._transport = build_model(self.case)
        return self._transport

    def transport_steady_state(self):
        """Steady state of the solids transport; refused (``ValueError`` naming the keys) when the
        case is physically impossible: speed at or above the critical speed, solids filling more
        than :data:`rotarydryer.cases.build.FILL_LIMIT` of the drum (see
        :func:`rotarydryer.cases.build.check_feasible`)."""
        if self._transport_ss is None:
            self._transport_ss = self.transport_model().steady_state()
        return self._transport_ss

    # ------------------------------------------------------------------ heat and mass
    def thermal_settings(self):
        """:class:`~rotarydryer.thermal.dryer.ThermalSettings` of the case."""
        from .cases.build import thermal_inputs

        return thermal_inputs(self.case)["settings"]

    def thermal_dryer(self, settings=None, feed_moisture=None, **overrides):
        """The heat-and-mass model on the case's sections: the transport model's section specs
        with the case's thermal changes (closed inlet, thermal discretisation, properties from the
        computed moisture). ``settings`` replaces the case's ThermalSettings, ``overrides`` set
        fields of them, ``feed_moisture`` (kg/kg wet) replaces the case's."""
        from .cases.build import thermal_inputs
        from .thermal.dryer import ThermalDryer, ThermalSettings
        from .transport.sections import build_sections

        inp = thermal_inputs(self.case)
        st = settings if settings is not None else inp["settings"]
        unknown = sorted(set(overrides) - {f.name for f in dataclasses.fields(ThermalSettings)})
        if unknown:
            raise ValueError(f"unknown ThermalSettings field(s) {', '.join(map(repr, unknown))}; valid: "
                             f"{', '.join(f.name for f in dataclasses.fields(ThermalSettings))}")
        st = dataclasses.replace(st, **overrides)   # a copy: the caller's settings stay as they were
        base = self.transport_model()
        p = base.parameters
        specs = [dataclasses.replace(sp, fouling=st.fouling, **inp["section_changes"].get(sp.name, {}))
                 for sp in base.specs]
        model = build_sections(specs, material=inp["material"], feed_rate=base.feed_rate, rpm=p["rpm"],
                               slope=p["slope"], inlet="danckwerts", name="thermal")
        return ThermalDryer(model, material=inp["material"], feed_rate=base.feed_rate,
                            feed_moisture=inp["feed_moisture"] if feed_moisture is None else feed_moisture,
                            rpm=p["rpm"], radius=self.case.drum.radius, sections=inp["sections"], settings=st)

    # ------------------------------------------------------------------ runs
    @single_threaded()
    def steady_state(self):
        """Steady state of the whole dryer: transport, and heat and mass where the case has a gas.

        The transport steady state is solved (and checked for feasibility) first in either case."""
        transport = self.transport_steady_state()
        if self.thermal_enabled:
            return SteadyResult(self, None, self.thermal_steady_state())
        return SteadyResult(self, transport, None)

    #: width of the smoothed design-load switch of the start model when the coupled Newton chatters
    START_SMOOTHING = 1e-3

    def thermal_steady_state(self):
        """Coupled steady state of the case's heat-and-mass model. When its Newton iteration
        chatters on the design-load switch min(M_P, M_des) or a kink of the exact loading factor
        (a cell at its design load or where a flight fills, e.g. small feeds), it is restarted from
        the steady state of the same model with the switch smoothed over ten times the case's
        width (at least :attr:`START_SMOOTHING` of M_des); the state returned is always that of the
        case's own model, accepted by its own convergence test."""
        from .thermal.dryer import DryerError

        d = self.thermal_dryer()
        try:
            return d.steady_state()
        except DryerError as exc:
            w = d.settings.design_load_smoothing
            if exc.reason != "no_steady_state" or w >= 0.01:
                raise
            try:   # continuation in the width: from a 10x wider switch (at least START_SMOOTHING)
                start = self.thermal_dryer(design_load_smoothing=max(self.START_SMOOTHING, 10.0 * w)).steady_state()
                return d.steady_state(z0=start.state)
            except DryerError:
                raise exc from None

    def dynamics(self, t_end=7200.0, dt=60.0, **changes):
        """Response from the steady state to new inputs ``changes`` (names of
        :data:`rotarydryer.thermal.studies.INPUTS` or ThermalSettings fields, absolute values)."""
        from .thermal.studies import perturbed

        d = self.thermal_dryer()
        ss = d.steady_state()
        d2 = perturbed(d, **changes) if changes else d
        return d2.simulate(ss.state, t_end, t_eval=np.arange(0.0, t_end + dt / 2, dt))

    def rtd(self, t_end=None, dt=None, method="auto"):
        """Tracer response at the (transport) steady state with the case's tracer pulse."""
        tr = self.case.tracer
        return self.transport_steady_state().rtd(self.transport_model().tracer_input, t_end=t_end or tr.t_end,
                                                 dt=dt or tr.dt, method=method)

    def results(self):
        """:class:`rotarydryer.results.Results` of the case (transport, RTD, heat and mass)."""
        from .results import run_case

        res = run_case(self.case)
        res.case_name = self.case_name
        return res

    def fit(self, dataset, parameters, **kwargs):
        """Fit ``parameters`` (override keys, e.g. ``["transport.backmix"]``) to a measured tracer
        curve: a :class:`rotarydryer.rtd.TracerData` or a shipped dataset name
        (``"lee2008_invicta"``); keyword arguments as
        :func:`rotarydryer.estimation.cases.fit_case_to_tracer`. Returns its ``CaseFit``."""
        from .estimation.cases import fit_case_to_tracer

        if isinstance(dataset, str):
            from .rtd import load_tracer_dataset

            dataset = load_tracer_dataset(dataset)
        return fit_case_to_tracer(self.case_name, dataset, list(parameters), **kwargs)

    def sweep(self, grid, outputs=None):
        """Steady state over a grid of overrides: list of dicts (``grid``: list of override dicts)."""
        rows = []
        for ov in grid:
            sim = Simulation(self.case_name, ov)
            row = dict(ov)
            row.update(sim.steady_state().summary())
            rows.append({k: row[k] for k in (outputs or row)})
        return rows


def build_thermal_dryer(case, settings=None, feed_moisture=None, **overrides):
    """Heat-and-mass model of a validated case: ``Simulation(case).thermal_dryer(...)``."""
    return Simulation(case).thermal_dryer(settings=settings, feed_moisture=feed_moisture, **overrides)


class SteadyResult:
    """Steady state of a :class:`Simulation`: one total holdup, one set of names.

    ``transport``: the transport-only steady state (no gas) or None; ``thermal``: the coupled
    :class:`~rotarydryer.thermal.dryer.ThermalSteadyState` or None. With heat and mass transfer
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

    def to_dataframe(self):
        """:meth:`summary` as a pandas DataFrame (value, unit)."""
        from ._display import outputs_dataframe

        return outputs_dataframe(self.summary())

    def tracer_system(self):
        """Linear tracer system at this state's flows (the coupled one with heat and mass)."""
        return (self.thermal if self.thermal is not None else self.transport).tracer_system()

    def tracer_moments(self):
        """Analytic moments of the outlet curve for the case's tracer pulse (from the injection start)."""
        return self.tracer_system().moments(self.simulation.transport_model().tracer_input)

    #: transport-only outputs with no coupled counterpart: dropped from a coupled run's outputs
    TRANSPORT_ONLY = ("kiln_bed_holdup_kg",)

    def summary(self) -> dict:
        """Outputs named with their unit: holdups, residence time, tracer moments and, with heat
        and mass transfer, :meth:`ThermalSteadyState.summary` (the transport-only total holdup is
        kept as ``transport_only_total_holdup_kg``; the fuel rate where the case has a burner)."""
        from .cases.build import has_burner

        ts = self.tracer_system()
        m = ts.moments(self.simulation.transport_model().tracer_input)
        impulse = ts.moments()
        if self.thermal is not None:
            out = self.thermal.summary(with_fuel=has_burner(self.simulation.case))
            out["transport_only_total_holdup_kg"] = self.simulation.transport_steady_state().total_holdup
        else:
            ss = self.transport
            out = dict(total_holdup_kg=ss.total_holdup, active_holdup_kg=ss.active_holdup,
                       passive_holdup_kg=ss.passive_holdup, bed_holdup_kg=ss.bed_holdup,
                       feed_rate_kg_s=float(self.simulation.transport_model().feed_rate),
                       outlet_flow_kg_s=ss.outlet_flow, mean_residence_time_s=ss.mean_residence_time)
        # analytic moments, named as RTDResult.to_dict names them (the impulse response's with rtd_)
        out.update(tracer_mean_s=m["mean"], tracer_std_s=m["std"], tracer_skewness=m["skewness"],
                   recovery=impulse["recovery"], rtd_mean_residence_time_s=impulse["mean"],
                   rtd_std_s=impulse["std"], rtd_skewness=impulse["skewness"])
        return out

    def merged(self, transport_outputs: dict) -> dict:
        """``transport_outputs`` (the transport-only model's, e.g. ``SteadyState.to_dict()`` or a
        Results' scalars) overwritten by :meth:`summary`: one value per name in every view."""
        out = {k: v for k, v in transport_outputs.items()
               if self.thermal is None or k not in self.TRANSPORT_ONLY}
        out.update(self.summary())
        return out
