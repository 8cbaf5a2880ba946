"""Residence-time distributions: analysis of curves, tracer inputs, reference
models (tanks in series, axial dispersion, Song's (2003) interactive mixers with dead zones)
and their fitting to tracer data.

Units: time in s, E(t) in 1/s. See ``docs/rtd.md`` for a walk-through.

Modules: [`.analysis`][rotarydryer.rtd.analysis] (moments, E, F, baseline, tails),
[`.pulses`][rotarydryer.rtd.pulses] (tracer inputs, convolution), [`.models`][rotarydryer.rtd.models] (TiS, ADM, cells),
[`.fitting`][rotarydryer.rtd.fitting] (least squares with confidence intervals),
[`.tracer_data`][rotarydryer.rtd.tracer_data] (measured-data CSV format).
"""

from .analysis import BASELINE_METHODS, TAIL_METHODS, RTDMoments, exit_age_curve, rtd_moments, subtract_baseline
from .fitting import CELL_MODELS, RTD_FIT_MODELS, RTD_MODELS, RTDFit, fit_rtd_model, fit_tracer_data
from .models import (
    DISPERSION_BOUNDARIES,
    AnalyticMoments,
    AxialDispersion,
    CholetteCloutier,
    TanksInSeries,
    axial_dispersion_e,
    axial_dispersion_moments,
    cholette_cloutier_e,
    cholette_cloutier_moments,
    tanks_in_series_e,
    tanks_in_series_f,
    tanks_in_series_moments,
)
from .pulses import PULSE_KINDS, TracerPulse, convolve_rtd, convolve_sampled_rtd, convolved_moments, pulse_input
from .tracer_data import (
    TracerData,
    load_tracer_csv,
    load_tracer_dataset,
    parse_tracer_text,
    tracer_datasets,
    write_tracer_csv,
)

__all__ = [
    "AnalyticMoments",
    "AxialDispersion",
    "BASELINE_METHODS",
    "CELL_MODELS",
    "CholetteCloutier",
    "DISPERSION_BOUNDARIES",
    "PULSE_KINDS",
    "RTDFit",
    "RTDMoments",
    "RTD_FIT_MODELS",
    "RTD_MODELS",
    "TAIL_METHODS",
    "TanksInSeries",
    "TracerData",
    "TracerPulse",
    "axial_dispersion_e",
    "axial_dispersion_moments",
    "cholette_cloutier_e",
    "cholette_cloutier_moments",
    "convolve_rtd",
    "convolve_sampled_rtd",
    "convolved_moments",
    "exit_age_curve",
    "fit_rtd_model",
    "fit_tracer_data",
    "load_tracer_csv",
    "load_tracer_dataset",
    "parse_tracer_text",
    "pulse_input",
    "rtd_moments",
    "subtract_baseline",
    "tanks_in_series_e",
    "tanks_in_series_f",
    "tanks_in_series_moments",
    "tracer_datasets",
    "write_tracer_csv",
]
