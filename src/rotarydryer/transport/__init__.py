"""Solids transport in flighted rotary dryers (compartment and dispersion models).

Public API:

    from rotarydryer.transport import lee2008, lee2008_repose_profile
    from rotarydryer.geometry.lee2008_regressions import Lee2008Regressions
    model = lee2008(geometry=Lee2008Regressions(), n_cells=35, feed_rate=27.2, length=12.0, rpm=3.0,
                    slope=2.8, bulk_density=940.0, repose_angle=lee2008_repose_profile(35, 0.02, 0.002),
                    kiln_time=8.69, backmix=0.68, drag_reduction=0.48)   # Lee's Invicta (its case file)
    ss = model.steady_state()          # holdups (kg), flows (kg/s)
    rtd = ss.rtd(t_end=3600, dt=10)     # analytic moments + simulated curve

See [`rotarydryer.transport.network`][rotarydryer.transport.network] for the engine and
[`rotarydryer.transport.models`][rotarydryer.transport.models] for the models.
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
