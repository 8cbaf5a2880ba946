"""One results object for a simulation: inputs, model choices, version and outputs.

>>> from rotarydryer.simulation import run_case
>>> from rotarydryer.results import Results
>>> res = run_case("lee2008_invicta", {"geometry.method": "lee2008_regressions"}, thermal=False)
>>> round(res.scalars["total_holdup_kg"])      # kg, solids transport only (thermal=True: the coupled state)
16398
>>> res.cells                  # xarray.Dataset, one row per cell (flighted and unflighted)  # doctest: +SKIP
>>> res.to_frame("cells")      # pandas.DataFrame, columns "name [unit]"     # doctest: +SKIP
>>> path = res.save("invicta.nc")                                            # doctest: +SKIP
>>> Results.load(path) == res                                                # doctest: +SKIP
True

Contents
--------
``inputs``
:   The validated case as a JSON-ready dict (``case.model_dump(mode="json")``), SI units.

``model_choices``
:   Model name and the parameters the transport model was built with (JSON-ready).

``scalars``
:   Named numbers; the unit is the suffix of the name (``_kg``, ``_s``, ``_kg_s``, ``_min``,
    ``_m``; no suffix = dimensionless).

``datasets``
:   Named `xarray.Dataset` objects; every variable carries ``attrs["units"]`` and
    ``attrs["long_name"]``.  Built by [`from_transport`][rotarydryer.results.from_transport]:

    * ``nodes``: every network node (dim ``node``): phase, section, cell, position (m),
      holdup (kg), design_load (kg, NaN where not defined);
    * ``cells``: every cell (dim ``cell``; ``kind`` flighted or unflighted finite volume):
      passive/active/bed and whole holdup, design load, kilning bed (kg), dryer loading (-),
      loading state, plus the model's per-cell coefficients (repose angle deg, cycle times s, ...;
      NaN for the unflighted volumes); ``Results.flighted_cells`` selects the flighted ones;
    * ``sections``: holdups per section (dim ``section``);
    * ``rtd``: simulated tracer response (dim ``time``): E(t) 1/s, F(t) -, outlet tracer
      flow kg/s;
    * ``rtd_measured``: the case's measured tracer curve (dim ``time``), when it has one;
    * ``rtd_fits``: classical RTD models fitted to it (dims ``model``, ``parameter``), with
      ``Simulation.results(fit_rtd=True)``.

Storage format (why netCDF)
---------------------------
One netCDF-4/HDF5 file written through xarray with the ``h5netcdf`` engine: the root
group holds the metadata (inputs, model choices, scalars, version: one JSON string
attribute ``rotarydryer_results``), each dataset is a netCDF group.  Chosen over Parquet +
a JSON side file because (1) the dependency set is lighter: xarray + pandas + h5netcdf +
h5py install to about 115 MB, pandas + pyarrow to about 255 MB (pyarrow alone 170 MB);
(2) units and long names travel in variable attributes natively; (3) everything is one file, so a single
``os.replace`` makes the write atomic (two files could not be replaced together).
It is lossless for what the results hold: float64/int64/bool/str arrays bit for bit,
NaN included; metadata is JSON (Python's ``json`` round-trips floats exactly; NaN and
infinities are written as the non-standard ``NaN``/``Infinity`` tokens Python reads back).

Writes are atomic: the file is written to a temporary file in the destination directory
and moved over the target with `os.replace`; if anything fails midway the
temporary file is removed and an existing file at ``path`` is left untouched.
"""

from __future__ import annotations

import datetime as _dt
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from . import __version__
from ._display import UNIT_SUFFIXES, split_unit

__all__ = ["Results", "from_transport", "fit_measured_rtd", "load_results", "rtd_comparison", "FORMAT_VERSION",
           "UNIT_SUFFIXES"]

FORMAT_VERSION = 1
_META_ATTR = "rotarydryer_results"


def output_lines(outputs: dict) -> list[str]:
    """One text line per named output, ``  name  value unit`` (unit from the name's suffix): the
    text form of every ``summary()``."""
    lines = []
    for k, v in outputs.items():
        name, unit = split_unit(k)
        shown = f"{v:.6g}" if isinstance(v, float) else str(v)
        lines.append(f"  {name:<28s} {shown} {unit if unit != '-' else ''}".rstrip())
    return lines


def _jsonable(obj: Any) -> Any:
    """Convert to JSON-ready builtins (numpy scalars/arrays, tuples, objects -> repr)."""
    if obj is None or isinstance(obj, (bool, str, int)):
        return obj
    if isinstance(obj, float):
        return obj
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return [_jsonable(x) for x in obj.tolist()]
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(x) for x in obj]
    if hasattr(obj, "model_dump"):
        return _jsonable(obj.model_dump(mode="json"))
    return repr(obj)


def _utcnow() -> str:
    return _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()


def _xr():
    try:
        import xarray as xr
    except ImportError as exc:  # pragma: no cover - dependency documented in the report
        raise ImportError("rotarydryer.results needs xarray (pip install xarray h5netcdf)") from exc
    return xr


@dataclass(eq=False)
class Results:
    """Inputs, model choices, version and outputs of one simulation.

    Attributes
    ----------
    inputs : dict
        The case (JSON-ready, SI units, angles in deg).
    model_choices : dict
        Model name and the parameters it was built with.
    scalars : dict of str -> float
        Unit in the name suffix (``total_holdup_kg``, ``mean_residence_time_s`` ...).
    datasets : dict of str -> xarray.Dataset
        Profiles and curves with ``units`` attributes (see the module docstring).
    case_name : str
        Name or path the case was loaded from.
    version : str
        ``rotarydryer.__version__`` that produced the results.
    created : str
        ISO 8601 UTC time stamp.
    """

    inputs: dict
    model_choices: dict = field(default_factory=dict)
    scalars: dict = field(default_factory=dict)
    datasets: dict = field(default_factory=dict)
    case_name: str = ""
    version: str = __version__
    created: str = field(default_factory=_utcnow)

    # -- convenient views ---------------------------------------------------------------
    @property
    def nodes(self):
        return self.datasets.get("nodes")

    @property
    def cells(self):
        """Per cell profile (xarray.Dataset, dim ``cell``): every flighted cell and every finite volume
        of the unflighted sections (``kind``), adding up to the total holdup; or None."""
        return self.datasets.get("cells")

    @property
    def flighted_cells(self):
        """The flighted cells of [`cells`][rotarydryer.results.Results.cells] (loading state, design load, coefficients), or None."""
        c = self.cells
        if c is None or "kind" not in c:
            return c            # results saved before the cells held the unflighted volumes
        keep = np.flatnonzero(c.kind.values == "flighted")
        return c.isel(cell=keep) if keep.size else None

    @property
    def sections(self):
        return self.datasets.get("sections")

    @property
    def rtd(self):
        """Simulated tracer response (xarray.Dataset, dim ``time``), or None."""
        return self.datasets.get("rtd")

    @property
    def rtd_measured(self):
        return self.datasets.get("rtd_measured")

    @property
    def kind(self) -> str:
        return str(self.inputs.get("kind", ""))

    def to_frame(self, name: str):
        """Dataset ``name`` as a pandas DataFrame, columns named ``"variable [unit]"``."""
        if name not in self.datasets:
            raise ValueError(f"name = {name!r} is not one of {', '.join(map(repr, self.datasets))}")
        ds = self.datasets[name]
        df = ds.to_dataframe()
        df.columns = [f"{c} [{ds[c].attrs.get('units', '-')}]" for c in df.columns]
        return df

    def metadata(self) -> dict:
        """Everything except the datasets, JSON-ready."""
        return {
            "format_version": FORMAT_VERSION,
            "version": self.version,
            "created": self.created,
            "case_name": self.case_name,
            "inputs": _jsonable(self.inputs),
            "model_choices": _jsonable(self.model_choices),
            "scalars": _jsonable(self.scalars),
            "datasets": list(self.datasets),
        }

    # -- comparison ---------------------------------------------------------------------
    def identical(self, other: Results) -> bool:
        """True when metadata and every dataset (values, dims, coords, attrs) are identical
        (NaN equals NaN, floats compared exactly)."""
        if not isinstance(other, Results):
            return False
        a, b = self.metadata(), other.metadata()
        if json.dumps(a, sort_keys=True) != json.dumps(b, sort_keys=True):
            return False
        for k, ds in self.datasets.items():
            o = other.datasets[k]
            if not ds.identical(o):
                return False
            for v in ds.variables:
                if ds[v].dtype.kind != o[v].dtype.kind:
                    return False
        return True

    __eq__ = identical
    __hash__ = None  # mutable

    def __repr__(self) -> str:
        from ._display import short_repr

        keys = ("total_holdup_kg", "mean_residence_time_s", "product_moisture_kg_kg", "gas_outlet_temperature_degC")
        return short_repr("Results", self.case_name or self.kind,
                          [(k, self.scalars[k]) for k in keys if k in self.scalars]
                          + [("datasets", ", ".join(self.datasets) or "none")])

    def _repr_html_(self) -> str:
        from ._display import html_table

        return html_table(self.scalars, caption=f"rotarydryer {self.version} results: {self.case_name or self.kind}")

    def to_dataframe(self):
        """The scalar outputs as a pandas DataFrame (value, unit)."""
        from ._display import outputs_dataframe

        return outputs_dataframe(self.scalars)

    def to_xarray(self, name: str = "nodes"):
        """One of the datasets (``nodes``, ``cells``, ``sections``, ``rtd``, ...) as an xarray.Dataset."""
        if name not in self.datasets:
            raise ValueError(f"dataset = {name!r} is not one of {', '.join(self.datasets) or 'none'}")
        return self.datasets[name]

    def summary(self) -> dict:
        """The named numbers (a copy of `scalars`, units in the names), as every result's
        ``summary()`` gives them; [`summary_text`][rotarydryer.results.Results.summary_text] is the plain-text form."""
        return dict(self.scalars)

    def summary_text(self) -> str:
        """A short plain-text summary."""
        return "\n".join([f"rotarydryer {self.version} results: {self.case_name or self.kind} "
                          f"({self.model_choices.get('model', '?')}), {self.created}", *output_lines(self.scalars)])

    # -- storage ------------------------------------------------------------------------
    def save(self, path) -> Path:
        """Write to a netCDF-4 file (``.nc``) atomically; returns the path.

        The data go to a temporary file beside ``path`` that replaces ``path`` only when
        complete; on any error the temporary file is deleted and ``path`` is unchanged.
        """
        from ._io import atomic_output, check_free_space, check_output_target

        path = Path(path)
        directory = path.parent if str(path.parent) else Path(".")
        if not directory.is_dir():
            raise ValueError(f"path = {str(path)!r}: directory {str(directory)!r} does not exist")
        check_output_target(path)
        # HDF5 does not fail cleanly on a full disk (it may crash the process): refuse beforehand
        # when the folder has clearly too little room (data + 25 % + 1 MiB for the HDF5 structure)
        size = sum(int(v.nbytes) for ds in self.datasets.values() for v in ds.variables.values())
        check_free_space(directory, int(1.25 * size) + 200_000, what=f"the results file {str(path)!r}")
        with atomic_output(path) as tmp:
            _write(self, tmp)
        return path

    @classmethod
    def load(cls, path) -> Results:
        """Read a file written by [`save`][rotarydryer.results.Results.save]."""
        xr = _xr()
        path = Path(path)
        if not path.is_file():
            raise ValueError(f"path = {str(path)!r} is not a file")
        try:
            with xr.open_dataset(path, engine="h5netcdf") as root:
                meta_text = root.attrs.get(_META_ATTR)
        except (OSError, ValueError) as exc:
            raise ValueError(f"path = {str(path)!r} is not a rotarydryer results file ({exc})") from None
        if meta_text is None:
            raise ValueError(f"path = {str(path)!r} is not a rotarydryer results file (no {_META_ATTR} attribute)")
        meta = json.loads(meta_text)
        if meta.get("format_version", 0) > FORMAT_VERSION:
            raise ValueError(f"path = {str(path)!r} has format_version {meta['format_version']}; this "
                             f"rotarydryer reads up to {FORMAT_VERSION}")
        datasets = {}
        for name in meta["datasets"]:
            with xr.open_dataset(path, engine="h5netcdf", group=name) as ds:
                ds = ds.load()
            for v in ds.variables:
                ds[v].encoding = {}
            datasets[name] = ds
        return cls(inputs=meta["inputs"], model_choices=meta["model_choices"], scalars=meta["scalars"],
                   datasets=datasets, case_name=meta["case_name"], version=meta["version"],
                   created=meta["created"])

    # -- case round trip ----------------------------------------------------------------
    def case(self):
        """The validated case model (pydantic) rebuilt from `inputs`."""
        from .cases import CASE_MODELS as kinds

        if self.kind not in kinds:
            raise ValueError(f"inputs.kind = {self.kind!r} is not one of {', '.join(map(repr, kinds))}")
        return kinds[self.kind].model_validate(self.inputs)


def _write_group(path: str, name: str | None, ds) -> None:
    """Write one group (``name`` None: the root group, creating the file)."""
    if name is None:
        ds.to_netcdf(path, mode="w", engine="h5netcdf")
    else:
        ds.to_netcdf(path, mode="a", engine="h5netcdf", group=name)


def _check_nul(res: Results) -> None:
    """HDF5 strings cannot hold NUL characters: refuse them with a clear message."""
    for name, ds in res.datasets.items():
        for v in ds.variables:
            for k, a in ds[v].attrs.items():
                if isinstance(a, str) and "\x00" in a:
                    raise ValueError(f"datasets[{name!r}][{v!r}].attrs[{k!r}] = {a!r} contains a NUL character, "
                                     "which netCDF/HDF5 strings cannot store")
            if ds[v].dtype.kind in "UO" and any("\x00" in str(x) for x in np.ravel(ds[v].values)):
                raise ValueError(f"datasets[{name!r}][{v!r}] contains a NUL character, which netCDF/HDF5 "
                                 "strings cannot store")
        for k, a in ds.attrs.items():
            if isinstance(a, str) and "\x00" in a:
                raise ValueError(f"datasets[{name!r}].attrs[{k!r}] = {a!r} contains a NUL character")


def _write(res: Results, path: str) -> None:
    xr = _xr()
    _check_nul(res)
    meta = json.dumps(res.metadata())  # JSON escapes NUL and any other character
    title = res.case_name.replace("\x00", "")
    root = xr.Dataset(attrs={_META_ATTR: meta, "title": f"rotarydryer results: {title}",
                             "software": f"rotarydryer {res.version}"})
    _write_group(path, None, root)
    for name, ds in res.datasets.items():
        _write_group(path, name, ds)


def load_results(path) -> Results:
    """Same as [`Results.load`][rotarydryer.results.Results.load]."""
    return Results.load(path)


# ---- construction from the transport engine -----------------------------------------------
def _var(values, units: str, long_name: str, dims=None):
    return (dims, np.asarray(values), {"units": units, "long_name": long_name})


def from_transport(case, model, steady, rtd=None, measured=None, case_name: str = "") -> Results:
    """Collect a transport simulation into a [`Results`][rotarydryer.results.Results].

    Parameters
    ----------
    case : DryerCase (pydantic) or dict
    model : rotarydryer.transport.TransportModel
        the case's transport model (its name and parameters are recorded)
    steady : rotarydryer.transport.SteadyState
        the state reported: the transport one, or a coupled one
        ([`rotarydryer.thermal.dryer.ThermalSteadyState.transport_state`][rotarydryer.thermal.dryer.ThermalSteadyState.transport_state]), whose own network,
        sections and design loads the datasets show
    rtd : rotarydryer.transport.RTDResult, optional
    measured : (time s, signal) arrays, optional — the case's measured tracer curve
        (``rotarydryer.cases.measured_rtd``); signal in 1/s or raw concentration.
    """
    xr = _xr()
    inputs = _jsonable(case)
    datasets = {}
    n = steady.masses.size
    design = np.asarray(steady.design_load, dtype=float)
    datasets["nodes"] = xr.Dataset(
        {
            "phase": _var(steady.phase.astype(str), "-", "phase (active, passive, bed)", "node"),
            "section": _var(steady.section.astype(str), "-", "section name", "node"),
            "cell": _var(steady.cell.astype(np.int64), "-", "cell index within the section", "node"),
            "position": _var(steady.position, "m", "axial position of the cell centre from the feed end", "node"),
            "holdup": _var(np.asarray(steady.masses, dtype=float), "kg", "solids holdup", "node"),
            "design_load": _var(design, "kg", "design load (passive nodes; NaN elsewhere)", "node"),
        },
        coords={"node": ("node", np.arange(n, dtype=np.int64))},
    )
    rows = steady.cell_table()
    if rows:
        long = {"section": "section name", "cell": "cell index within the section",
                "position_m": "axial position of the cell centre", "passive_kg": "flight- and drum-borne holdup",
                "active_kg": "airborne (curtain) holdup", "design_load_kg": "design load",
                "kiln_bed_kg": "kilning bed (holdup above the design load)",
                "dryer_loading": "dryer loading M_P/M_P,des (Lee (2008) Section 4.4.2)",
                "state": "loading state (under, design, over; unflighted)",
                "kind": "flighted cell or unflighted finite volume", "bed_kg": "rolling bed (unflighted)",
                "holdup_kg": "whole holdup of the cell"}
        rename = {"passive_kg": "passive_holdup", "active_kg": "active_holdup", "bed_kg": "bed_holdup",
                  "cell": "cell_in_section"}
        vars_ = {}
        for key in rows[0]:
            vals = [r[key] for r in rows]
            if key in ("section", "state", "kind"):
                arr, unit, nm = np.array(vals, dtype=str), "-", key
            elif key == "cell":
                arr, unit, nm = np.array(vals, dtype=np.int64), "-", "cell_in_section"
            else:
                nm, unit = split_unit(key)
                nm = rename.get(key, nm)
                arr = np.array(vals, dtype=float)
            vars_[nm] = _var(arr, unit, long.get(key, key), "cell")
        datasets["cells"] = xr.Dataset(vars_, coords={"cell": ("cell", np.arange(len(rows), dtype=np.int64))})
    sec_h = steady.section_holdups()
    secs = steady.model.sections
    datasets["sections"] = xr.Dataset(
        {
            "kind": _var(np.array([s["kind"] for s in secs], dtype=str), "-", "flighted or unflighted", "section"),
            "length": _var(np.array([float(s["length"]) for s in secs]), "m", "section length", "section"),
            "n_cells": _var(np.array([int(s["n_cells"]) for s in secs], dtype=np.int64), "-", "cells", "section"),
            **{f"{p}_holdup": _var(np.array([sec_h[s["name"]][f"{p}_kg"] for s in secs]), "kg", f"{p} holdup",
                                   "section") for p in ("active", "passive", "bed", "total")},
        },
        coords={"section": ("section", np.array([s["name"] for s in secs], dtype=str))},
    )
    ss = steady.to_dict()
    scalars = _numbers(ss)
    scalars.update(steady.loading_counts())
    if rtd is not None:
        rd = rtd.to_dict()
        for k, v in rd.items():
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                # a name the steady state already uses (mean_residence_time_s) gets an rtd_ prefix
                scalars[f"rtd_{k}" if k in scalars else k] = float(v)
        r = rtd.response
        if r is not None:
            datasets["rtd"] = xr.Dataset(
                {
                    "exit_age": _var(np.asarray(r.exit_age, float), "1/s", "E(t), exit-age distribution", "time"),
                    "cumulative": _var(np.asarray(r.cumulative, float), "-", "F(t), cumulative RTD", "time"),
                    "outlet_tracer_flow": _var(np.asarray(r.outlet_tracer_flow, float), "kg/s",
                                               "tracer flow at the outlet", "time"),
                },
                coords={"time": ("time", np.asarray(r.time, float), {"units": "s", "long_name": "time since injection start"})},
                attrs={"method": str(r.method), "injected_mass_kg": float(r.injected_mass)},
            )
    if measured is not None:
        t, y = (np.asarray(a, dtype=float) for a in measured)
        datasets["rtd_measured"] = xr.Dataset(
            {"signal": _var(y, "1/s or raw concentration", "measured tracer signal (normalise by its integral)", "time")},
            coords={"time": ("time", t, {"units": "s", "long_name": "time since injection start"})},
        )
    choices = {"model": model.name, "parameters": _jsonable(model.parameters)}
    for sec in ("transport", "geometry"):
        if isinstance(inputs, dict) and sec in inputs:
            choices[sec] = inputs[sec]
    return Results(inputs=inputs if isinstance(inputs, dict) else {}, model_choices=choices, scalars=scalars,
                   datasets=datasets, case_name=case_name)


def fit_measured_rtd(time_s, signal, pulse_duration: float, models=None):
    """Fit the classical RTD models (``rotarydryer.rtd.fit_rtd_model``: tanks in series,
    closed and open axial dispersion) to a measured tracer curve; returns an
    ``xarray.Dataset`` with dims ``(model, parameter)``.

    The tracer input is a rectangular pulse of ``pulse_duration`` s starting at t = 0.
    A curve whose trapezoidal area is within 5 % of 1 is taken as a normalised E(t) in 1/s
    (Lee's files) and fitted with a fixed unit scale; any other curve (raw ppm, Ajayi) gets
    a fitted scale (its area).  Parameter units are the suffixes of their names
    (``mean_residence_time_s``, ``space_time_s``; ``n_tanks``, ``peclet`` and ``scale``
    dimensionless or in signal x s).
    """
    from .rtd import RTD_MODELS, fit_rtd_model, pulse_input

    xr = _xr()
    t = np.asarray(time_s, float)
    y = np.asarray(signal, float)
    normalised = abs(float(np.trapezoid(y, t)) - 1.0) < 0.05
    pulse = pulse_input("rectangular", pulse_duration) if pulse_duration > 0 else pulse_input("dirac")
    fits = {}
    for m in models or RTD_MODELS:
        fits[m] = fit_rtd_model(t, y, m, pulse=pulse, fit_scale=not normalised).to_dict()
    params = list(dict.fromkeys(p for d in fits.values() for p in d["parameters"]))
    models = list(fits)

    def grid(key):
        return np.array([[fits[m]["parameters"].get(p, {}).get(key, np.nan) for p in params] for m in models], float)

    dims = ("model", "parameter")
    return xr.Dataset(
        {
            "value": _var(grid("value"), "unit of the parameter name suffix", "fitted value", dims),
            "std_error": _var(grid("std_error"), "unit of the parameter name suffix", "standard error", dims),
            "ci_low": _var(grid("ci_low"), "unit of the parameter name suffix", "95 % confidence limit, low", dims),
            "ci_high": _var(grid("ci_high"), "unit of the parameter name suffix", "95 % confidence limit, high", dims),
            "r_squared": _var([fits[m]["r_squared"] for m in models], "-", "coefficient of determination", "model"),
            "outlet_mean": _var([fits[m]["outlet_moments"]["mean_s"] for m in models], "s",
                                "mean of the fitted outlet curve from the injection start", "model"),
            "outlet_std": _var([fits[m]["outlet_moments"]["std_s"] for m in models], "s",
                               "standard deviation of the fitted outlet curve", "model"),
        },
        coords={"model": ("model", np.array(models, dtype=str)), "parameter": ("parameter", np.array(params, dtype=str))},
        attrs={"pulse": f"rectangular, {pulse_duration:g} s", "scale": "fixed 1 (normalised E)" if normalised else "fitted"},
    )


def _numbers(d: dict) -> dict:
    """The numeric (not bool, not None) entries of ``d`` as floats."""
    return {k: float(v) for k, v in d.items() if isinstance(v, (int, float, np.floating)) and not isinstance(v, bool)}


def add_thermal(res: Results, steady) -> Results:
    """Add a coupled heat and mass transfer steady state
    ([`rotarydryer.thermal.dryer.ThermalSteadyState`][rotarydryer.thermal.dryer.ThermalSteadyState]) to ``res``: datasets
    ``thermal_solids`` (per node: the nodes of ``nodes``, one dimension name), ``thermal_gas`` (per gas stage, with
    the shell's loss and temperatures), ``energy_balance`` (streams, W), the energy audit's ``heat_duties`` (W;
    ``part``: the duties that add up to ``heat_release_W``) and ``shell_sections`` (per section: shell loss,
    hottest surface and wall), and the key scalars (product moisture, temperatures, fuel, shell loss,
    balance errors, heat duties)."""
    xr = _xr()
    prof = steady.profiles()
    res.datasets["thermal_solids"] = xr.Dataset(
        {
            "position": _var(np.asarray(prof["position"], float), "m", "axial position from the feed end", "node"),
            "phase": _var(np.asarray(prof["phase"]).astype(str), "-", "bed, passive or active", "node"),
            "section": _var(np.asarray(prof["section"]).astype(str), "-", "section name", "node"),
            "moisture": _var(np.asarray(prof["moisture_wet"], float), "kg/kg", "solids moisture, wet basis", "node"),
            "temperature": _var(np.asarray(prof["solids_temperature_degC"], float), "degC", "solids temperature", "node"),
            "holdup": _var(np.asarray(prof["holdup_kg"], float), "kg", "wet solids holdup", "node"),
        },
        coords={"node": ("node", np.arange(len(prof["position"]), dtype=np.int64))},
    )
    res.datasets["thermal_gas"] = xr.Dataset(
        {
            "position": _var(np.asarray(prof["gas_position"], float), "m", "axial position from the feed end", "stage"),
            "temperature": _var(np.asarray(prof["gas_temperature_degC"], float), "degC", "gas temperature", "stage"),
            "humidity": _var(np.asarray(prof["gas_humidity"], float), "kg/kg", "gas humidity, dry basis", "stage"),
        },
        coords={"stage": ("stage", np.arange(len(prof["gas_position"]), dtype=np.int64))},
    )
    terms = steady.energy_terms_w
    names = [*terms["in"], *terms["out"]]
    res.datasets["energy_balance"] = xr.Dataset(
        {
            "direction": _var(np.array(["in"] * len(terms["in"]) + ["out"] * len(terms["out"])), "-",
                              "into or out of the dryer", "stream"),
            "power": _var(np.array([*terms["in"].values(), *terms["out"].values()], float), "W",
                          "energy flow (enthalpy relative to the model reference state)", "stream"),
        },
        coords={"stream": ("stream", np.array(names))},
    )
    if steady.dryer.n_classes > 1:       # size classes: one row each (particle_size in the case)
        rows = steady.size_class_table()
        d = steady.terms

        def col(key):
            return np.array([np.nan if r[key] is None else r[key] for r in rows], float)
        res.datasets["size_classes"] = xr.Dataset(
            {
                "diameter": _var(col("diameter_m"), "m", "class diameter at the feed (mass median)", "size_class"),
                "feed_fraction": _var(col("feed_fraction"), "-", "mass fraction of the feed", "size_class"),
                "product_fraction": _var(col("product_fraction"), "-", "mass fraction of the product", "size_class"),
                "dust_fraction": _var(col("dust_fraction"), "-", "mass fraction of the dust", "size_class"),
                "lost_as_dust": _var(col("lost_as_dust"), "-", "share of the class's feed leaving as dust",
                                     "size_class"),
                "product_moisture": _var(col("product_moisture_kg_kg"), "kg/kg", "product moisture, wet basis",
                                         "size_class"),
                "mean_residence_time": _var(col("mean_residence_time_s"), "s", "dry holdup / dry feed of the class",
                                            "size_class"),
                "holdup": _var(np.asarray(d["Sc"] + d["Wc"], float), "kg", "wet solids holdup per node",
                               ("size_class", "node")),
                "moisture": _var(np.asarray(d["Wc"] / (d["Sc"] + d["Wc"]), float), "kg/kg",
                                 "solids moisture per node, wet basis", ("size_class", "node")),
                "temperature": _var(np.asarray(d["Tc"], float), "degC", "solids temperature per node",
                                    ("size_class", "node")),
            },
            coords={"size_class": ("size_class", np.arange(len(rows), dtype=np.int64)),
                    "node": ("node", np.arange(d["Sc"].shape[-1], dtype=np.int64)),
                    "edge": ("edge", np.asarray(steady.dryer.size_classes.edges, float))},
        )
    from .thermal.audit import HEAT_DUTY_LABELS, HEAT_DUTY_PARTS, shell_sections  # start-up (LAZY)

    # the energy audit (rotarydryer.thermal.audit): the heat duties (they add up to the release) and the shell
    duties = steady.heat_duties_w()
    names = ["heat_release_W", *HEAT_DUTY_PARTS, "heat_duty_exhaust_latent_W"]
    res.datasets["heat_duties"] = xr.Dataset(
        {
            "power": _var(np.array([duties[k] for k in names], float), "W", "heat duty", "duty"),
            "part": _var(np.array([k in HEAT_DUTY_PARTS for k in names]), "-",
                         "one of the duties that add up to heat_release_W", "duty"),
            "label": _var(np.array([HEAT_DUTY_LABELS[k] for k in names]), "-", "short label", "duty"),
        },
        coords={"duty": ("duty", np.array(names))},
    )
    shell = steady.shell_profile()
    gas = res.datasets["thermal_gas"]
    gas["shell_loss"] = _var(np.asarray(shell["shell_heat_loss_W"], float), "W", "shell heat loss of the stage", "stage")
    gas["shell_surface_temperature"] = _var(np.asarray(shell["surface_temperature_degC"], float), "degC",
                                            "shell outer surface temperature", "stage")
    gas["shell_wall_temperature"] = _var(np.asarray(shell["wall_temperature_degC"], float), "degC",
                                         "hottest steel temperature of the shell wall", "stage")
    rows = shell_sections(steady)
    res.datasets["shell_sections"] = xr.Dataset(
        {
            "length": _var(np.array([r["length_m"] for r in rows], float), "m", "section length", "section"),
            "shell_loss": _var(np.array([r["shell_heat_loss_W"] for r in rows], float), "W", "shell heat loss",
                               "section"),
            "max_surface_temperature": _var(np.array([r["max_surface_temperature_degC"] for r in rows], float),
                                            "degC", "hottest shell outer surface", "section"),
            "max_wall_temperature": _var(np.array([r["max_wall_temperature_degC"] for r in rows], float), "degC",
                                         "hottest steel temperature", "section"),
        },
        coords={"section": ("section", np.array([r["section"] for r in rows]))},
    )
    s = steady.summary(with_fuel=False)
    res.scalars.update(_numbers(s))
    res.model_choices["thermal_mode"] = s["thermal_mode"]
    if s.get("shell_temperature_limit_exceeded") is not None:     # a flag (the scalars hold numbers only)
        res.model_choices["shell_temperature_limit_exceeded"] = bool(s["shell_temperature_limit_exceeded"])
    return res


def __getattr__(name):
    # deprecated alias (0.1 -> 0.2): results.py is the container; the assembler is rotarydryer.simulation
    if name == "run_case":
        import warnings

        warnings.warn("rotarydryer.results.run_case is deprecated: use rotarydryer.simulation.run_case "
                      "or Simulation(case, overrides).results()", DeprecationWarning, stacklevel=2)
        from .simulation import run_case  # the one upward import, listed in tests/test_layering.py

        return run_case
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def rtd_comparison(results) -> dict | None:
    """Model against the measured tracer curve: means and standard deviations (s) as stored
    (``tracer_*`` = model with the case's tracer input, ``measured_*``) and R^2 of the model
    E(t), interpolated at the measured times, against the measured E(t) (baseline removed,
    normalised by its area).  None without a measured curve."""
    s = results.scalars
    if results.rtd is None or results.rtd_measured is None or not s.get("measured_mean_s"):
        return None
    from .cases import exit_age_r_squared  # start-up (tests/test_imports.py LAZY)
    from .rtd import rtd_moments
    m = results.rtd_measured
    t, sig = np.asarray(m.time.values, float), np.asarray(m.signal.values, float)
    mom = rtd_moments(t, sig, baseline=float(s.get("measured_baseline", 0.0)))
    e_meas = np.clip(sig - mom.baseline, 0.0, None) / mom.area
    e_mod = np.interp(t, results.rtd.time.values, results.rtd.exit_age.values, left=0.0, right=0.0)
    r2 = exit_age_r_squared(e_meas, e_mod)
    mod_mean = s.get("tracer_mean_s", s.get("simulated_mean_s"))
    mod_std = s.get("tracer_std_s", s.get("simulated_std_s"))
    return dict(model_mean_s=float(mod_mean), measured_mean_s=float(s["measured_mean_s"]),
                model_std_s=float(mod_std), measured_std_s=float(s["measured_std_s"]), r_squared=r2,
                n_points=int(t.size))
