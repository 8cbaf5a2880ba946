"""Parameter estimation with uncertainty (weighted least squares, maximum likelihood)."""

from .fit import (
    BootstrapResult,
    Dataset,
    FitError,
    FitResult,
    IdentifiabilityWarning,
    Parameter,
    ParameterEstimate,
    ProfileResult,
    StartResult,
    bootstrap,
    fit,
    profile_likelihood,
)

__all__ = [
    "BootstrapResult",
    "Dataset",
    "FitError",
    "FitResult",
    "IdentifiabilityWarning",
    "Parameter",
    "ParameterEstimate",
    "ProfileResult",
    "StartResult",
    "bootstrap",
    "fit",
    "profile_likelihood",
]
