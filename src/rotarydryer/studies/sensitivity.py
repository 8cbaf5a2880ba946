"""Global sensitivity and uncertainty of a case (issue 16 part 4): Sobol indices and Monte Carlo.

>>> from rotarydryer.studies.sensitivity import sobol_study
>>> res = sobol_study("song2003_ottawa", {"operating.rpm": (3.0, 5.0), "operating.feed_rate": (0.05, 0.08)},
...                   samples=64, base_overrides={"thermal.enabled": "false"})     # doctest: +SKIP
>>> res.table()[0]                # output, parameter, S1, S1_conf, ST, ST_conf  # doctest: +SKIP

The inputs (override keys of the case) are uniform on ``[LOW, HIGH]``. The design is Saltelli's
extension of a scrambled Sobol' sequence (SALib ``sample.sobol``, first and total order only):
``samples`` base points give ``samples * (D + 2)`` model runs for D inputs. Each run is
``Simulation(case, overrides).steady_state().summary()``; the indices and their bootstrap
confidence intervals (95 %) are SALib's ``analyze.sobol``, and the output distributions (mean,
standard deviation, percentiles, histogram) are taken over every successful run (each row of the
design is uniform on the box).

Failed runs (a ``ValueError`` of an infeasible point: critical speed, overfilled drum, no coupled
steady state ...) do not end the study: they are recorded with their message, and every Saltelli
block (the D + 2 runs built on one base point) with a failed run is left out of the indices of
every output, so that the A, B and AB matrices stay aligned; the result says how many runs
failed and how many blocks were used. An output a case does not compute (the fuel rate without
a burner, the product moisture with heat and mass transfer off) is skipped with a note.

Runs go through the one executor like ``rotarydryer sweep`` (`rotarydryer.executor.Executor`):
in contiguous chunks of whole blocks (`study_chunks`, which depend on the design's size only), on
warm local worker processes (``workers``) or a Dask cluster (``scheduler``, ``cluster``), one BLAS
thread per process. Within a chunk each coupled steady state starts from the converged state of
the nearest run already done in that chunk (``warm_start``; the chunk's first run starts cold); a
start that does not converge falls back to the cold start. So every backend and worker count
gives the same runs and indices, bit for bit.

SALib is an optional dependency: ``pip install 'rotarydryer[sensitivity]'``.
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from typing import Optional

import numpy as np

from ..executor import Executor, RunFailure, split

__all__ = ["OUTPUTS", "MAX_PARAMS", "MAX_SAMPLES", "MAX_RUNS", "SensitivityResult", "sobol_study",
           "parse_param", "check_params", "check_samples", "require_salib", "saltelli_design",
           "plot_sensitivity"]

#: outputs studied by default (names of ``SteadyResult.summary()``)
OUTPUTS = ("product_moisture_kg_kg", "gas_outlet_temperature_degC", "fuel_rate_kg_s", "mean_residence_time_s")
#: most uncertain inputs of one study
MAX_PARAMS = 20
#: most base samples (the design has samples * (D + 2) runs)
MAX_SAMPLES = 65536
#: most model runs of one study
MAX_RUNS = 1_000_000
#: confidence level of the bootstrap intervals
CONF_LEVEL = 0.95
#: states remembered per chunk for warm starts
WARM_MEMORY = 64

INSTALL_HINT = "pip install 'rotarydryer[sensitivity]' (or pip install SALib)"


def require_salib():
    """Import SALib or raise ImportError naming the extra that installs it."""
    try:
        import SALib  # noqa: F401
        from SALib.analyze import sobol as _a  # noqa: F401
    except ImportError as exc:
        raise ImportError(f"the sensitivity study needs SALib, in the 'sensitivity' extra: {INSTALL_HINT}") from exc


# ---------------------------------------------------------------------------------- input checks
def parse_param(item: str) -> tuple[str, tuple[float, float]]:
    """``"operating.rpm=2,4"`` -> ``("operating.rpm", (2.0, 4.0))`` (ValueError naming --param)."""
    if "=" not in item:
        raise ValueError(f"--param {item!r}: expected KEY=LOW,HIGH, e.g. operating.rpm=2,4")
    key, rng = item.split("=", 1)
    key = key.strip()
    parts = [p.strip() for p in rng.split(",")]
    if not key:
        raise ValueError(f"--param {item!r}: no key before '='")
    if len(parts) != 2 or not all(parts):
        raise ValueError(f"--param {item!r}: expected two numbers LOW,HIGH after '=', got {rng!r}")
    vals = []
    for name, p in zip(("LOW", "HIGH"), parts):
        try:
            v = float(p)
        except ValueError:
            raise ValueError(f"--param {key}: {name} = {p!r} is not a number") from None
        vals.append(v)
    return key, (vals[0], vals[1])


def check_params(params) -> dict[str, tuple[float, float]]:
    """``{key: (low, high)}`` checked: 1 to `MAX_PARAMS` keys, finite numbers, low < high."""
    if isinstance(params, Mapping):
        items = list(params.items())
    else:
        items = list(params or [])
    if not items:
        raise ValueError("no uncertain inputs: give at least one --param KEY=LOW,HIGH")
    if len(items) > MAX_PARAMS:
        raise ValueError(f"{len(items)} uncertain inputs (--param); the limit is {MAX_PARAMS} per study")
    out: dict[str, tuple[float, float]] = {}
    for key, rng in items:
        key = str(key).strip()
        if key in out:
            raise ValueError(f"--param {key} is given twice; give each key once")
        try:
            low, high = (float(rng[0]), float(rng[1]))
            if len(rng) != 2:
                raise TypeError
        except (TypeError, ValueError, IndexError):
            raise ValueError(f"--param {key} = {rng!r}: expected two numbers (LOW, HIGH)") from None
        for name, v in (("LOW", low), ("HIGH", high)):
            if not math.isfinite(v):
                raise ValueError(f"--param {key}: {name} = {v} is not a finite number")
        if not low < high:
            raise ValueError(f"--param {key}: LOW = {low:g} must be below HIGH = {high:g}")
        out[key] = (low, high)
    return out


def check_samples(samples, n_params: int) -> int:
    """Base sample count: an integer in [2, `MAX_SAMPLES`] whose design has at most
    `MAX_RUNS` runs."""
    given = samples                 # as the user wrote it (1e30, not its 31 digits)
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)):
        try:
            f = float(samples)
        except (TypeError, ValueError):
            raise ValueError(f"--samples = {samples!r} is not an integer") from None
        if not f.is_integer():
            raise ValueError(f"--samples = {samples!r} is not an integer")
        samples = int(f)
    samples = int(samples)
    if not 2 <= samples <= MAX_SAMPLES:
        raise ValueError(f"--samples = {given} is outside the allowed range [2, {MAX_SAMPLES}] (the indices and "
                         "their intervals need at least 2 blocks of runs)")
    if samples & (samples - 1):
        lo = 1 << (samples.bit_length() - 1)
        raise ValueError(f"--samples = {samples} is not a power of 2 (the Sobol' sequence keeps its balance "
                         f"properties only then; others give biased indices, e.g. S1 > ST); allowed: 2, 4, 8, ... {MAX_SAMPLES}; use {lo} "
                         f"or {2 * lo}")
    runs = samples * (n_params + 2)
    if runs > MAX_RUNS:
        raise ValueError(f"--samples = {samples} with {n_params} inputs gives {runs} runs; the limit is "
                         f"{MAX_RUNS} per study")
    if samples < FEW_SAMPLES:
        # -n 2 gave S1 = 0.90 +- 518 for a single input, whose S1 = ST = 1 exactly (found by review)
        warnings.warn(f"--samples = {samples}: so few base samples give indices that are not estimates (their "
                      f"intervals are wider than the indices' range); {FEW_SAMPLES} or more give rough ones, 64 or more "
                      "usable ones", UserWarning, stacklevel=2)
    return samples


#: fewer base samples than this give Sobol' indices whose intervals exceed their range: warned about
FEW_SAMPLES = 16


#: largest seed of the scrambled Sobol' sequence and the bootstrap (NumPy seeds are 32-bit here)
MAX_SEED = 2**32 - 1


def check_seed(seed, option: str = "--seed") -> int:
    """The seed as an int in [0, `MAX_SEED`], or a ``ValueError`` naming ``option``."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= int(seed) <= MAX_SEED:
        raise ValueError(f"{option} = {seed!r} is outside the allowed range: an integer from 0 to {MAX_SEED}")
    return int(seed)


def _problem(params: dict) -> dict:
    return {"num_vars": len(params), "names": list(params), "bounds": [list(v) for v in params.values()]}


def saltelli_design(params: dict, samples: int, seed: int = 0) -> np.ndarray:
    """The ``samples * (D + 2)`` x D design (rows in SALib's block order: A, AB_1..AB_D, B)."""
    require_salib()
    problem = _problem(params)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # "N should be a power of 2" and similar advice
        try:
            from SALib.sample import sobol as sampler

            return sampler.sample(problem, samples, calc_second_order=False, scramble=True, seed=seed)
        except (ImportError, TypeError):     # SALib < 1.4.6
            from SALib.sample import saltelli

            return saltelli.sample(problem, samples, calc_second_order=False)


# ---------------------------------------------------------------------------------- model runs
def _check_case(case, base: dict, params: dict) -> None:
    """Fail fast (ValueError naming the key) on an unknown case or key, or a range the case
    schema refuses at either end."""
    from ..cases import discrete_kind, load_case

    loaded = load_case(case, dict(base))
    for key, (low, high) in params.items():
        what = discrete_kind(type(loaded), key)
        if what is not None:
            # every sample of drum.n_flights=12,24 failed at a fraction of a flight (found by fuzzing)
            raise ValueError(f"--param {key}: the key takes {what}; "
                             "a Sobol study samples continuous inputs (compare the values you want with "
                             f"`rotarydryer sweep --grid {key}=...`)")
        for v in (low, high):
            try:
                load_case(case, {**base, key: v})
            except ValueError as exc:       # the case loader names its overrides --set: here they are --param's
                raise ValueError(str(exc).replace(f"--set {key}:", f"--param {key}={low:g},{high:g}:")) from None


def _steady_summary(case, overrides: dict, warm=None, outputs=None):
    """``(summary dict, warm-start data or None)`` of one run, started from ``warm`` (the data of
    a nearby run, `rotarydryer.simulation.Simulation.steady_state`: the same steady state, on
    its heat-and-mass model when only parameter values differ); ``outputs``: the names wanted
    (`SteadyResult.summary`)."""
    from ..simulation import Simulation

    res = Simulation(case, overrides).steady_state(warm=warm)
    return res.summary(outputs, strict=False), res.warm_data()      # a missing output is recorded with its reason


def _run_chunk(case, base: dict, keys: Sequence[str], X: np.ndarray, outputs: Sequence[str],
               warm_start: bool = True):
    """Run the rows of ``X`` (one chunk, in order); returns ``(Y, errors)``: Y (rows x outputs,
    NaN where an output is missing or the run failed), errors (message or '' per row).
    Top-level so that it pickles for process pools and Dask; one BLAS thread."""
    from .._threads import single_threaded

    X = np.asarray(X, dtype=float)
    Y = np.full((len(X), len(outputs)), np.nan)
    errors = [""] * len(X)
    missing: list[dict] = [{} for _ in range(len(X))]     # per run: {output: why it is missing}
    memory: list[tuple] = []     # (normalised point, warm-start data of its run)
    span = np.ptp(X, axis=0) if len(X) else np.ones(len(keys))
    span = np.where(span > 0, span, 1.0)
    with single_threaded():
        for i, x in enumerate(X):
            point = {k: float(v) for k, v in zip(keys, x)}
            try:
                if callable(case):
                    out, data = case(point), None
                else:
                    warm = None
                    if warm_start and memory:
                        u = x / span
                        # the nearest remembered point, all distances in one pass (a loop over the 64 cost 0.2 ms a run)
                        j = int(np.argmin(np.sum((np.array([m[0] for m in memory]) - u) ** 2, axis=1)))
                        warm = {**memory[j][1], "models": _other_models(memory, memory[j][1])}
                    out, data = _steady_summary(case, {**base, **point}, warm, outputs)
                    if data is not None and warm_start:
                        memory.append((x / span, data))
                        if len(memory) > WARM_MEMORY:
                            memory.pop(0)
            except (ValueError, ArithmeticError, MemoryError) as exc:   # one bad point never ends the study
                errors[i] = " ".join(str(exc).split()) or type(exc).__name__
                continue
            for j, name in enumerate(outputs):
                v = out.get(name)
                if v is not None:
                    try:
                        Y[i, j] = float(v)
                    except (TypeError, ValueError):
                        pass
                if not np.isfinite(Y[i, j]):
                    missing[i][name] = _missing_reason(name, out)
    return Y, errors, missing


#: models of other networks a study's run may reuse (`_other_models`): the last few distinct ones
OTHER_MODELS = 3


def _other_models(memory, nearest) -> list:
    """Simulations of the remembered runs, the latest first, one per heat-and-mass network other than ``nearest``'s
    (at most `OTHER_MODELS`): a run whose nearest point has another network (a Sobol row that changes
    ``transport.moisture_scale``) may reuse one of them instead of building its own (the warm start still comes
    from the nearest point)."""
    def network(sim):
        return None if sim is None or sim._dryer is None else id(sim._dryer.model)

    seen, out = {network(nearest.get("simulation"))}, []
    for _, data in reversed(memory):
        sim = data.get("simulation")
        key = network(sim)
        if key is not None and key not in seen:
            seen.add(key)
            out.append(sim)
            if len(out) >= OTHER_MODELS:
                break
    return out


def _missing_reason(name: str, out: dict) -> str:
    """Why output ``name`` is missing from a successful run's ``out``: the run's own message
    (``fuel_rate_error`` for the fuel rate, ``NAME_error`` for others), else a generic one."""
    err = out.get("fuel_rate_error") if name == "fuel_rate_kg_s" else out.get(f"{name}_error")
    if err:
        return " ".join(str(err).split())
    if name not in out:
        return "not computed by this run"
    return f"not a finite number ({out.get(name)!r})"


def _reason_kind(reason: str) -> str:
    """The kind of a missing-output reason, for counting (the numbers of each run left out)."""
    if reason.startswith("burner cannot reach"):
        return "burner cannot reach the set gas inlet temperature"
    return reason.split(": ", 1)[0]


def missing_summary(missing, output: str) -> list[dict]:
    """``[{"reason": kind, "runs": n, "example": first full message}]`` of the runs missing
    ``output`` (``missing``: per-run ``{output: reason}``), most frequent first."""
    counts: dict[str, list] = {}
    for m in missing or []:
        why = (m or {}).get(output)
        if why:
            kind = _reason_kind(why)
            counts.setdefault(kind, [0, why])[0] += 1
    return [{"reason": k, "runs": n, "example": ex} for k, (n, ex) in sorted(counts.items(), key=lambda kv: -kv[1][0])]


#: most rows of a chunk of a study (16 blocks of 8 inputs: about 3 s of coupled runs)
CHUNK_ROWS = 160


def study_chunks(n_rows: int, block: int) -> list[slice]:
    """Contiguous chunks of whole Saltelli blocks (`rotarydryer.executor.split` of the blocks: 16
    as even ones, at most `CHUNK_ROWS` rows each). They depend on the design's size only, never on
    the backend or the worker count, so every backend runs the same warm-start chains."""
    return [slice(sl.start * block, sl.stop * block)
            for sl in split(n_rows // block, max_size=max(1, CHUNK_ROWS // block))]


def _study_chunk(rows, case, base: dict, keys: Sequence[str], outputs: Sequence[str], warm_start: bool = True):
    """`_run_chunk` of a chunk's rows for the executor: one ``(y, error, missing)`` per row."""
    Y, errors, missing = _run_chunk(case, base, keys, np.asarray(rows, dtype=float).reshape(len(rows), len(keys)),
                                    outputs, warm_start)
    return list(zip(Y, errors, missing))


def _warm_study(case, overrides: dict, outputs: Sequence[str]) -> None:
    """A worker's warm-up before its first chunk: imports, compiled kernels, one model built and solved."""
    if not callable(case):
        try:
            _steady_summary(case, overrides, None, outputs)
        except (ValueError, ArithmeticError):
            pass


def _evaluate(case, base, keys, X, outputs, *, block, executor: Executor, warm_start=True, progress=None):
    Y = np.full((len(X), len(outputs)), np.nan)
    errors = [""] * len(X)
    missing: list[dict] = [{} for _ in range(len(X))]
    rows = [np.asarray(x, dtype=float) for x in X]
    first = {**base, **{k: float(v) for k, v in zip(keys, X[0])}} if len(X) else dict(base)
    out = executor.map_chunks(_study_chunk, rows, chunks=study_chunks(len(X), block),
                              args=(case, base, list(keys), list(outputs), warm_start),
                              warm=((_warm_study, (case, first, list(outputs))),), progress=progress)
    for i, r in enumerate(out):
        if isinstance(r, RunFailure):
            errors[i] = r.error
        else:
            Y[i], errors[i], missing[i] = r
    return Y, errors, missing


# ---------------------------------------------------------------------------------- analysis
def _distribution(y: np.ndarray, bins: int = 30) -> dict:
    y = y[np.isfinite(y)]
    if y.size == 0:
        return {"n": 0}
    q = np.percentile(y, [5, 25, 50, 75, 95])
    lo, hi = float(y.min()), float(y.max())
    try:
        counts, edges = np.histogram(y, bins=bins, range=(lo, hi) if hi > lo else (lo - 0.5, hi + 0.5))
    except ValueError:      # a range of a few ulps: "too many bins for data range"
        counts, edges = np.histogram(y, bins=1, range=(lo - 0.5 * max(abs(lo), 1.0) * 1e-9,
                                                       hi + 0.5 * max(abs(hi), 1.0) * 1e-9))
    return {"n": int(y.size), "mean": float(y.mean()), "sd": float(y.std(ddof=1)) if y.size > 1 else 0.0,
            "min": lo, "p5": float(q[0]), "p25": float(q[1]), "p50": float(q[2]), "p75": float(q[3]),
            "p95": float(q[4]), "max": hi, "histogram": {"counts": counts.tolist(), "edges": edges.tolist()}}


#: an output whose runs spread by less than this share of its largest value is constant (the steady-state
#: solver's round-off, 1e-11 on its residual, makes a constant output vary by about 1e-15 of it: its Sobol
#: indices were printed as real, ST 1.58; found by fuzzing)
CONSTANT_SPREAD = 1e-9
#: ... and below this share of 1e-3 kg/kg for a moisture (an output in kg/kg): a product dried to 1.8e-7 kg/kg varied
#: by the solver's absolute resolution of the water (7.6e-14 kg/kg, 4e-7 of it) with two inputs it does not depend on,
#: and its Sobol indices were printed as real (S1 1.007; found by fuzzing)
MOISTURE_SCALE_KG_KG = 1e-3


def _spread_scale(output: str, Y: np.ndarray) -> float:
    """What an output's spread over the runs is compared with (times CONSTANT_SPREAD) to call it constant: its
    largest magnitude, or MOISTURE_SCALE_KG_KG for a moisture (kg/kg) nearer zero."""
    scale = float(np.max(np.abs(Y)))
    return max(scale, MOISTURE_SCALE_KG_KG) if output.endswith("_kg_kg") else scale


def _sobol_indices(params: dict, Y: np.ndarray, block: int, seed: int, num_resamples: int,
                   output: str = "") -> tuple[dict, int]:
    """Indices of one output from the complete blocks (no NaN): ``({param: {...}}, blocks used)``."""
    from SALib.analyze import sobol as analyzer

    blocks = Y.reshape(-1, block)
    ok = np.all(np.isfinite(blocks), axis=1)
    n = int(ok.sum())
    keys = list(params)
    empty = {k: {"S1": float("nan"), "S1_conf": float("nan"), "ST": float("nan"), "ST_conf": float("nan")}
             for k in keys}
    if n < 2 or np.ptp(blocks[ok]) <= CONSTANT_SPREAD * _spread_scale(output, blocks[ok]):
        return empty, n       # a constant output, or one varying by the solver's round-off only: no indices
    state = np.random.get_state()
    try:
        # SALib takes seed 0 for "no seed" and then draws the bootstrap from NumPy's global generator:
        # seeded here (and restored after), so that seed 0 gives the same intervals on every run too
        np.random.seed(seed)
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            si = analyzer.analyze(_problem(params), blocks[ok].ravel(), calc_second_order=False,
                                  num_resamples=num_resamples, conf_level=CONF_LEVEL, seed=seed,
                                  print_to_console=False)
    finally:
        np.random.set_state(state)
    return {k: {"S1": float(si["S1"][i]), "S1_conf": float(si["S1_conf"][i]),
                "ST": float(si["ST"][i]), "ST_conf": float(si["ST_conf"][i])} for i, k in enumerate(keys)}, n


@dataclasses.dataclass
class SensitivityResult:
    """A Sobol study: indices per output and input, output distributions, failed runs.

    ``indices[output][param]`` = {S1, S1_conf, ST, ST_conf} (conf: half-width of the 95 %
    bootstrap interval); ``distributions[output]`` = {n, mean, sd, min, p5 ... p95, max,
    histogram}; ``X`` (runs x inputs) and ``Y`` (runs x outputs, NaN = failed/missing) the runs.
    """

    case: str
    params: dict
    samples: int
    outputs: list
    indices: dict
    distributions: dict
    n_runs: int
    n_failed: int
    blocks_used: dict
    failures: list
    notes: list
    seconds: float
    base_overrides: dict = dataclasses.field(default_factory=dict)
    X: Optional[np.ndarray] = None
    Y: Optional[np.ndarray] = None
    errors: Optional[list] = None
    #: {output: [{"reason", "runs", "example"}]}: why an output is missing in successful runs
    missing_outputs: dict = dataclasses.field(default_factory=dict)

    @property
    def runs_per_second(self) -> float:
        return self.n_runs / self.seconds if self.seconds > 0 else float("nan")

    def table(self) -> list[dict]:
        """One row per (output, input): output, parameter, S1, S1_conf, ST, ST_conf (None where undefined:
        an output that does not vary, too few complete blocks; see ``notes``)."""
        return [{"output": o, "parameter": p, **{k: (float(x) if np.isfinite(x) else None) for k, x in v.items()}}
                for o, per in self.indices.items() for p, v in per.items()]

    def distribution_table(self) -> list[dict]:
        """One row per output: n, mean, sd, min, p5, p25, p50, p75, p95, max."""
        return [{"output": o, **{k: v for k, v in d.items() if k != "histogram"}}
                for o, d in self.distributions.items()]

    def runs_table(self) -> list[dict]:
        """One row per model run: inputs, outputs (None if missing), error."""
        rows = []
        if self.X is None:
            return rows
        for i in range(len(self.X)):
            r = {k: float(v) for k, v in zip(self.params, self.X[i])}
            r.update({o: (float(v) if np.isfinite(v) else None) for o, v in zip(self.outputs, self.Y[i])})
            r["error"] = self.errors[i] if self.errors else ""
            rows.append(r)
        return rows

    def to_dict(self) -> dict:
        """JSON-ready summary (no per-run arrays): what ``rotarydryer report --sensitivity`` reads."""
        return {"kind": "sobol_sensitivity", "case": self.case, "base_overrides": dict(self.base_overrides),
                "params": {k: list(v) for k, v in self.params.items()}, "samples": self.samples,
                "outputs": list(self.outputs), "conf_level": CONF_LEVEL, "n_runs": self.n_runs,
                "n_failed": self.n_failed, "blocks_used": dict(self.blocks_used), "seconds": self.seconds,
                "runs_per_second": self.runs_per_second, "indices": self.indices,
                "distributions": self.distributions, "failures": self.failures, "notes": self.notes,
                "missing_outputs": self.missing_outputs}


def sobol_study(case, params, samples: int, outputs: Sequence[str] = OUTPUTS, *, workers: int = 1,
                scheduler: Optional[str] = None, cluster: Optional[str] = None, executor: Optional[Executor] = None,
                base_overrides: Optional[dict] = None, seed: int = 0,
                warm_start: bool = True, num_resamples: int = 200,
                progress: Optional[Callable[[int], None]] = None) -> SensitivityResult:
    """Sobol first- and total-order indices and output distributions of ``case``.

    Parameters
    ----------
    case : str, path or callable
        Case name or ``.toml`` file; or a function ``f(point: dict) -> dict of outputs``
        (analytic test models; ``workers=1`` unless it pickles).
    params : {key: (low, high)}
        Uniform uncertain inputs (override keys).
    samples : int
        Base samples N, a power of 2 (others are refused); the design has ``N * (D + 2)`` runs.
    outputs : names of the outputs (default `OUTPUTS`).
    workers, scheduler, cluster : local processes, a Dask scheduler address, or "local:N" (a Dask
        LocalCluster); or ``executor``, a `rotarydryer.executor.Executor`. Every backend gives the
        same runs and indices, bit for bit.
    base_overrides : overrides applied to every run (``--set``).
    progress : called with the number of runs finished.
    """
    require_salib()
    t0 = time.perf_counter()
    params = check_params(params)
    samples = check_samples(samples, len(params))
    seed = check_seed(seed, "seed")
    outputs = list(outputs)
    if not outputs:
        raise ValueError("outputs: give at least one output name")
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise ValueError(f"workers = {workers!r} is outside the allowed range: an integer >= 1")
    base = dict(base_overrides or {})
    name = case.__name__ if callable(case) else str(case)
    if not callable(case):
        _check_case(case, base, params)
    keys = list(params)
    block = len(keys) + 2
    X = saltelli_design(params, samples, seed)
    ex = executor or Executor(workers=int(workers), scheduler=scheduler, cluster=cluster)
    Y, errors, missing_why = _evaluate(case, base, keys, X, outputs, block=block, executor=ex, warm_start=warm_start,
                                       progress=progress)
    failed = np.array([bool(e) for e in errors])
    n_failed = int(failed.sum())
    notes = []
    # a failed run removes its block from every output's indices (consistent exclusion)
    blocks_failed = failed.reshape(-1, block).any(axis=1)
    Yc = Y.copy()
    Yc[np.repeat(blocks_failed, block)] = np.nan
    indices, used, dists, kept = {}, {}, {}, []
    missing_outputs: dict[str, list] = {}
    for j, o in enumerate(outputs):
        ok_runs = ~failed
        why = missing_summary([m for m, ok in zip(missing_why, ok_runs) if ok], o)
        if why:
            missing_outputs[o] = why
        reasons = "; ".join(f"{w['runs']} run{'s' if w['runs'] != 1 else ''}: {w['reason']}" for w in why)
        if ok_runs.any() and not np.isfinite(Y[ok_runs, j]).any():
            generic = all(w["reason"] == "not computed by this run" for w in why)
            notes.append(f"{o}: not computed by this case (e.g. no burner, or heat and mass transfer off); skipped"
                         if generic or not why else f"{o}: missing in every successful run ({reasons}); skipped")
            continue
        if not ok_runs.any():
            notes.append(f"{o}: every run failed; skipped")
            continue
        missing = int(np.sum(ok_runs & ~np.isfinite(Y[:, j])))
        if missing:
            notes.append(f"{o}: missing in {missing} successful runs ({reasons or 'no reason given'}); their "
                         "blocks are left out of its indices")
        indices[o], used[o] = _sobol_indices(params, Yc[:, j], block, seed, num_resamples, o)
        dists[o] = _distribution(Y[ok_runs, j])
        kept.append(o)
        if used[o] < 2:
            notes.append(f"{o}: fewer than 2 complete blocks of runs; no indices")
        elif not np.isfinite(indices[o][keys[0]]["S1"]):
            of = "of it" if not o.endswith("_kg_kg") else f"of max(it, {MOISTURE_SCALE_KG_KG:g} kg/kg)"
            notes.append(f"{o}: the same value in every run ({dists[o]['p50']:.6g}, to {CONSTANT_SPREAD:g} {of}): it "
                         "does not depend on these inputs over their ranges; no indices")
    uncomputed = [o for o in outputs if any(n.startswith(f"{o}: not computed by this case") for n in notes)]
    if uncomputed and len(uncomputed) == len(outputs):     # nothing to show: it exited 0 with empty tables
        raise ValueError(f"output {', '.join(uncomputed)}: not computed by this case (e.g. no burner, or heat and mass "
                         "transfer off); choose outputs the case computes")
    if n_failed:
        notes.append(f"{n_failed} of {len(X)} runs failed ({int(blocks_failed.sum())} of {len(blocks_failed)} "
                     "blocks left out of the indices)")
    counts: dict[str, int] = {}
    for e in errors:
        if e:
            counts[e] = counts.get(e, 0) + 1
    failures = [{"error": e, "runs": c} for e, c in sorted(counts.items(), key=lambda kv: -kv[1])[:20]]
    return SensitivityResult(case=name, params=params, samples=samples, outputs=kept, indices=indices,
                             distributions=dists, n_runs=len(X), n_failed=n_failed, blocks_used=used,
                             failures=failures, notes=notes, seconds=time.perf_counter() - t0,
                             missing_outputs=missing_outputs,
                             base_overrides=base, X=X, Y=Y[:, [outputs.index(o) for o in kept]], errors=errors)


# ---------------------------------------------------------------------------------- plot
def plot_sensitivity(data: dict):
    """Figure of a study (``SensitivityResult.to_dict()``): per output, the S1/ST bars with
    their confidence intervals (top row) and the histogram of the output (bottom row)."""
    from .._plotting import pyplot

    plt = pyplot()
    outs = [o for o in data.get("outputs", []) if o in data.get("indices", {})]
    n = max(len(outs), 1)
    fig, axes = plt.subplots(2, n, figsize=(3.6 * n + 0.8, 6.4), squeeze=False)
    names = list(data.get("params", {}))
    for j, o in enumerate(outs):
        ax = axes[0, j]
        x = np.arange(len(names))
        idx = data["indices"][o]

        def col(k):
            return np.array([np.nan if idx[p][k] is None else idx[p][k] for p in names], dtype=float)

        ax.bar(x - 0.2, col("S1"), 0.4, yerr=np.nan_to_num(col("S1_conf")), label="first order S1", capsize=2)
        ax.bar(x + 0.2, col("ST"), 0.4, yerr=np.nan_to_num(col("ST_conf")), label="total order ST", capsize=2)
        ax.set_xticks(x)
        ax.set_xticklabels([p.split(".")[-1] for p in names], rotation=45, ha="right", fontsize=8)
        ax.set_title(o, fontsize=9)
        ax.axhline(0, color="k", lw=0.5)
        if j == 0:
            ax.set_ylabel("Sobol index")
            ax.legend(fontsize=7)
        d = data.get("distributions", {}).get(o, {})
        ax = axes[1, j]
        h = d.get("histogram")
        if h:
            e = np.asarray(h["edges"], dtype=float)
            ax.bar(e[:-1], h["counts"], np.diff(e), align="edge", color="#d9a441", edgecolor="#5b3a12", lw=0.3)
            for k, ls in (("p5", ":"), ("p50", "-"), ("p95", ":")):
                if d.get(k) is not None:
                    ax.axvline(d[k], color="#5b3a12", ls=ls, lw=1)
        ax.set_xlabel(o, fontsize=8)
        if j == 0:
            ax.set_ylabel("runs")
    if not outs:
        axes[0, 0].text(0.5, 0.5, "no outputs", ha="center")
    fig.suptitle(f"Sobol sensitivity: {data.get('case', '')}, {data.get('n_runs', 0)} runs "
                 f"({data.get('n_failed', 0)} failed)", fontsize=10)
    fig.tight_layout()
    return fig
