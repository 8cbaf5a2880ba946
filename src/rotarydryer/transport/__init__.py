"""Solids transport in flighted rotary dryers (compartment and dispersion models).

Public API::

    from rotarydryer.transport import lee2008, Network, TracerInput
    from rotarydryer.geometry.lee2008_regressions import Lee2008Regressions
    model = lee2008(geometry=Lee2008Regressions(), n_cells=35)
    ss = model.steady_state()          # holdups (kg), flows (kg/s)
    rtd = ss.rtd(t_end=3600, dt=10)     # analytic moments + simulated curve

See :mod:`rotarydryer.transport.network` for the engine and
:mod:`rotarydryer.transport.models` for the models.
"""

from .models import (
    NetworkBuilder,
    lee2008,
    lee2008_repose_profile,
    sheehan2005_model1,
    sheehan2005_model2,
)
from .network import EdgeFamily, Network, NoSteadyStateError, TracerInput, TracerResponse, TracerSystem
from .results import RTDResult, RTDWindowWarning, SteadyState, TransportModel

__all__ = [
    "EdgeFamily",
    "Network",
    "NetworkBuilder",
    "NoSteadyStateError",
    "RTDResult",
    "RTDWindowWarning",
    "SteadyState",
    "TracerInput",
    "TracerResponse",
    "TracerSystem",
    "TransportModel",
    "lee2008",
    "lee2008_repose_profile",
    "sheehan2005_model1",
    "sheehan2005_model2",
]
