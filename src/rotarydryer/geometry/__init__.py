"""Flight geometry and unloading (Lee (2008) ch. 4).

Public API:

    from rotarydryer.geometry import TwoSectionFlight, PolygonFlight, FlightedDrum
    flight = TwoSectionFlight(s1=0.195, s2=0.183, alpha1=90.0, alpha2=117.0)
    # or any shape: PolygonFlight([(0.195, 90.0), (0.10, 135.0), (0.09, 135.0)])
    drum = FlightedDrum(radius=2.5, n_flights=28, flight=flight)
    drum.holdup_area(psi, repose_angle)     # m^2, vectorised
    drum.holdup_area(psi, repose_angle, particle_diameter=0.01)  # with the finite-particle correction
    drum.transition_angles(repose_angle)    # (psi1, ..., psi5), deg
    drum.cascade(repose_angle, loading_factor, rpm=3.0)   # CascadeSummary
    drum.design_load_area(repose_angle, method="lee2008") # m^2 of drum cross-section
    drum.loading_factor(dryer_loading, repose_angle)      # f_load, Eq. 4.22
    drum.final_discharge_angle(repose_angle)              # psi5, deg
    curtain_distribution(drum, repose_angle)              # where the curtain falls across the drum
"""

from .curtain import CurtainDistribution, curtain_distribution, final_discharge_angle
from .design_load import (
    DESIGN_LOAD_METHODS,
    LOADING_STATES,
    design_load_area,
    design_load_mass,
    design_load_methods,
    loading_factor,
    loading_state,
)
from .drum import (
    CRITICAL_SPEED_WARN_FRACTION,
    CriticalSpeedWarning,
    FlightedDrum,
    TransitionAngles,
    check_speed,
    critical_speed,
    finite_particle_correction,
)
from .drum import (
    SURFACE_LAYER as SURFACE_LAYER_DEFAULT,
)
from .flights import PolygonFlight, TwoSectionFlight
from .unloading import (
    FALL_HEIGHT_DEFINITIONS,
    PASSIVE_TIME_BRANCHES,
    CascadeDrag,
    CascadeSummary,
    cascade,
    fall_height,
    first_unloading_angle,
)

__all__ = [
    "CRITICAL_SPEED_WARN_FRACTION",
    "CriticalSpeedWarning",
    "check_speed",
    "critical_speed",
    "CascadeDrag",
    "CascadeSummary",
    "DESIGN_LOAD_METHODS",
    "FALL_HEIGHT_DEFINITIONS",
    "FlightedDrum",
    "LOADING_STATES",
    "SURFACE_LAYER_DEFAULT",
    "finite_particle_correction",
    "PASSIVE_TIME_BRANCHES",
    "TransitionAngles",
    "TwoSectionFlight",
    "PolygonFlight",
    "cascade",
    "CurtainDistribution",
    "curtain_distribution",
    "final_discharge_angle",
    "design_load_mass",
    "design_load_area",
    "design_load_methods",
    "fall_height",
    "first_unloading_angle",
    "loading_factor",
    "loading_state",
]
