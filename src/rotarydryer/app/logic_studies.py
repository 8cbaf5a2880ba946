"""Logic of the "Studies and sensitivity" page: a one-input what-if study and a global
(Sobol / Monte Carlo) sensitivity study of a case; plain functions, no Streamlit.

No physics here: each point is ``Simulation(case, overrides).steady_state().summary()`` and the
sensitivity study is `rotarydryer.studies.sensitivity.sobol_study` (SALib), with its
figure `plot_sensitivity`. The inputs a study may vary
are those of `rotarydryer.app.logic_dryer.study_inputs` (override keys of the case). The
page's runs are capped (`MAX_POINTS`, `MAX_RUNS`) so that one study takes well under
a minute; ``rotarydryer sweep`` and ``rotarydryer sensitivity`` have no such cap.
"""

from __future__ import annotations

import math

import numpy as np

from .._display import UNITS, quantity_of, unit_of
from .._io import csv_text
from .logic import _is_upload, _load, png
from .logic_dryer import _check_thermal, study_inputs

__all__ = ["MAX_POINTS", "MAX_RUNS", "MAX_PARAMS", "SAMPLE_CHOICES", "STUDY_OUTPUTS", "whatif_view",
           "sensitivity_view", "study_inputs"]

#: most points of one what-if study on the page (a coupled solve takes ~0.3-1 s)
MAX_POINTS = 15
#: most model runs of one sensitivity study on the page (samples x (inputs + 2))
MAX_RUNS = 96
#: most uncertain inputs of one sensitivity study on the page
MAX_PARAMS = 4
#: base sample counts offered (powers of 2, as Saltelli's design wants)
SAMPLE_CHOICES = (4, 8, 16, 32)

#: outputs of the studies: (summary name, label); the what-if rows and CSV keep the summary's names
#: and SI values, the page's table and figure show them in the display units (rotarydryer._display)
STUDY_OUTPUTS = (
    ("product_moisture_kg_kg", "product moisture (wet)"),
    ("gas_outlet_temperature_degC", "gas outlet temperature"),
    ("fuel_rate_kg_s", "fuel rate"),
    ("mean_residence_time_s", "mean residence time"),
    ("product_temperature_degC", "product temperature"),
    ("specific_energy_kJ_kg_water", "specific energy (per kg of water)"),
)


def display_column(name: str, label: str) -> tuple[str, float, float]:
    """``(column title with its display unit, scale, offset)`` of a study output: the display value
    is SI x scale + offset (`rotarydryer._display`)."""
    quantity, factor = quantity_of(name)
    unit = unit_of(quantity)
    scale, offset = UNITS[quantity][unit]
    return f"{label} ({unit})", scale * factor, offset


def _input_spec(case: str, key: str) -> dict:
    specs = {s["key"]: s for s in study_inputs(case)}
    if key not in specs:
        raise ValueError(f"input = {key!r} is not one this page studies; choose from {', '.join(specs)}")
    return specs[key]


def _check_count(name: str, n, lo: int, hi: int) -> int:
    if isinstance(n, bool) or not float(n).is_integer():
        raise ValueError(f"{name} = {n!r} is not an integer")
    n = int(n)
    if not lo <= n <= hi:
        raise ValueError(f"{name} = {n} is outside the allowed range [{lo}, {hi}] on this page "
                         "(rotarydryer sweep and rotarydryer sensitivity have no such limit)")
    return n


def _check_range(key: str, low: float, high: float):
    for name, v in (("low", low), ("high", high)):
        if not math.isfinite(float(v)):
            raise ValueError(f"{key}: {name} = {v} is not a finite number")
    if not float(low) < float(high):
        raise ValueError(f"{key}: low = {float(low):g} must be below high = {float(high):g}")


def _summary(case: str, overrides: dict) -> dict:
    from ..simulation import Simulation

    c = _load(case, overrides)
    _check_thermal(c, "this case")
    return Simulation(c).steady_state().summary()


def _outputs_for(case: str) -> list[tuple]:
    from ..cases.build import has_burner

    burner = has_burner(_load(case))
    return [o for o in STUDY_OUTPUTS if o[0] != "fuel_rate_kg_s" or burner]


def whatif_view(case: str, key: str, low: float, high: float, points: int = 5, images: bool = True,
                progress=None) -> dict:
    """Steady state of the whole dryer at ``points`` values of one input ``key`` (evenly spaced
    on [low, high]; the other inputs at the case's values).

    Both ends are checked first (the CLI's messages); a point the model cannot solve (e.g. an
    overfilled drum) is kept as a row with its ``error`` and left out of the plot. Returns
    ``{"rows": [{key, outputs by their summary names (SI)..., error}], "outputs": [(name, label)], "csv": str,
    "plot": png, "failed": n}``.  ``progress(done, total)`` is called before the first point and
    after each."""
    spec = _input_spec(case, key)
    points = _check_count("points", points, 2, MAX_POINTS)
    _check_range(key, low, high)
    for v in (low, high):
        _check_thermal(_load(case, {key: v}), "this case")   # the schema's message for a value out of range
    values = np.linspace(float(low), float(high), points)
    if spec["integer"]:
        values = np.unique(np.round(values))
    outs = _outputs_for(case)
    rows = []
    if progress:
        progress(0, len(values))
    for v in values:
        row: dict[str, float | str | None] = {key: float(v)}
        try:
            s = _summary(case, {key: float(v)})
            for name, _ in outs:
                val = s.get(name)
                row[name] = None if val is None else float(val)
            row["error"] = ""
        except (ValueError, ArithmeticError) as exc:     # one bad point never ends the study
            row.update({name: None for name, _ in outs})
            row["error"] = " ".join(str(exc).split())
        rows.append(row)
        if progress:
            progress(len(rows), len(values))
    failed = sum(1 for r in rows if r["error"])
    if failed == len(rows):
        raise ValueError(f"no point of {key} in [{float(low):g}, {float(high):g}] could be solved; first: "
                         f"{rows[0]['error']}")
    out = {"rows": rows, "outputs": outs, "failed": failed, "csv": csv_text(rows, last=("error",)), "key": key, "label": spec["label"]}
    if images:
        out["plot"] = png(_whatif_figure(rows, key, spec["label"], outs))
    return out


def _whatif_figure(rows, key, label, outs):
    from .._plotting import pyplot

    plt = pyplot()
    n = len(outs)
    ncol = 3
    nrow = int(math.ceil(n / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(10, 2.6 * nrow + 0.4), squeeze=False, constrained_layout=True)
    x = np.array([r[key] for r in rows], float)
    for ax, (name, lab) in zip(axes.flat, outs):
        title, scale, offset = display_column(name, lab)
        y = np.array([np.nan if r.get(name) is None else r[name] * scale + offset for r in rows], float)
        ok = np.isfinite(y)
        ax.plot(x[ok], y[ok], "o-", ms=4)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(label, fontsize=8)
        ax.tick_params(labelsize=8)
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[n:]:
        ax.set_axis_off()
    return fig


class _UploadedCaseModel:
    """``point -> summary`` of a staged upload (sobol_study runs a callable in-process)."""

    def __init__(self, case: str, base: dict):
        self.case, self.base, self.__name__ = case, dict(base), "uploaded case"

    def __call__(self, point: dict) -> dict:
        return _summary(self.case, {**self.base, **point})


def sensitivity_view(case: str, params: dict, samples: int = 8, seed: int = 0, progress=None,
                     images: bool = True) -> dict:
    """Sobol first- and total-order indices (95 % bootstrap intervals) and Monte Carlo output
    distributions of the case's outputs for uniform inputs ``params = {key: (low, high)}``
    (`rotarydryer.studies.sensitivity.sobol_study`, one process, warm starts for a built-in
    case). At most `MAX_PARAMS` inputs and `MAX_RUNS` runs (``samples * (inputs + 2)``).

    Returns ``{"data": SensitivityResult.to_dict(), "table": [...], "distributions": [...],
    "runs_csv": str, "plots": [png per two outputs]}``."""
    from ..studies import sensitivity as sens

    sens.require_salib()
    if not params:
        raise ValueError("no uncertain inputs: choose at least one input")
    if len(params) > MAX_PARAMS:
        raise ValueError(f"{len(params)} uncertain inputs; the limit is {MAX_PARAMS} on this page "
                         "(rotarydryer sensitivity takes up to 20)")
    for key in params:
        _input_spec(case, key)
    params = sens.check_params(params)
    samples = _check_count("samples", samples, 1, max(SAMPLE_CHOICES))
    runs = samples * (len(params) + 2)
    if runs > MAX_RUNS:
        raise ValueError(f"samples = {samples} with {len(params)} inputs gives {runs} runs; the limit is {MAX_RUNS} "
                         "runs on this page (fewer samples or inputs; rotarydryer sensitivity has no such limit)")
    _check_thermal(_load(case), "this case")
    outputs = [o[0] for o in _outputs_for(case)[:4]]
    if _is_upload(case):
        for key, (lo, hi) in params.items():        # sobol_study checks a named case itself
            for v in (lo, hi):
                _load(case, {key: v})
        model = _UploadedCaseModel(case, {})
    else:
        model = case
    res = sens.sobol_study(model, params, samples, outputs, workers=1, seed=seed, progress=progress)
    data = res.to_dict()
    if res.n_failed == res.n_runs:
        first = res.failures[0]["error"] if res.failures else ""
        raise ValueError(f"all {res.n_runs} runs failed; first: {first}")
    out = {"data": data, "table": res.table(), "distributions": res.distribution_table(),
           "runs_csv": csv_text(res.runs_table()), "n_runs": res.n_runs, "n_failed": res.n_failed,
           "seconds": res.seconds, "notes": list(res.notes)}
    if images:       # two outputs per figure: about 720 px wide, readable unscaled on a laptop
        outs = [o for o in data["outputs"] if o in data["indices"]]
        out["plots"] = [png(sens.plot_sensitivity({**data, "outputs": outs[i:i + 2]}))
                        for i in range(0, len(outs), 2)]
    return out
