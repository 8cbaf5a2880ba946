"""Published correlations for flighted rotary dryers.

One function per author-year correlation, in the style of Caleb Bell's
``fluids``/``ht``: SI arguments with units in every docstring, the equation and
its source, a doctest with an exact number, a ``method=`` dispatcher and a
``*_methods()`` lister that returns the correlations applicable to the inputs.

Modules
-------
residence_time
    Mean residence time (MRT) and holdup correlations reviewed by Song (2003)
    ch. 2 and 4 and Lee (2008) ch. 2; dispatcher [`mean_residence_time`][rotarydryer.correlations.mean_residence_time].
heat_transfer
    Volumetric coefficients Ua (Song 2003 Table 3.1), particle Nusselt
    correlations (Song 2003 Table 3.2, Ajayi 2011 Eq. 6.41), Song's estimation
    equation 3.9 and the Chilton-Colburn analogy (Song 2003 Eq. 3.8).
drag
    Single-particle drag coefficients (Schiller-Naumann, Haider-Levenspiel,
    Lee 2008 Eq. 6.6) and terminal velocity.
trajectory
    Fall of a particle released from a flight through a co- or
    counter-current gas stream: fall time and axial displacement.

Inputs outside the range a correlation was fitted on give a
`CorrelationRangeWarning`; non-physical inputs raise ``ValueError``.
Design-load models (Porter, Kelly, Baker, Ajayi's modified Baker) live in
``rotarydryer.geometry.design_load`` because they need the flight geometry.
"""

from __future__ import annotations


class CorrelationRangeWarning(UserWarning):
    """An input lies outside the range on which a correlation was fitted.

    The result is still returned (it is an extrapolation); the warning text
    names the argument, its value and the fitted range.
    """


# Submodules import CorrelationRangeWarning from here, so it must be defined first.
from .drag import (  # noqa: E402
    drag_coefficient,
    drag_coefficient_methods,
    haider_levenspiel_1989,
    lee_2008,
    modified_schiller_naumann,
    reynolds_number,
    schiller_naumann_1933,
    stokes_drag,
    terminal_velocity,
)
from .heat_transfer import (  # noqa: E402
    chilton_colburn_mass_transfer_coefficient,
    heat_transfer_coefficient,
    log_mean_temperature_difference,
    nusselt_number,
    nusselt_number_methods,
    ua_from_drying_data,
    volumetric_heat_transfer_coefficient,
    volumetric_heat_transfer_coefficient_methods,
)
from .residence_time import (  # noqa: E402
    alvarez_shene_1994,
    foust_1960,
    friedman_marshall_1949,
    mean_residence_time,
    mean_residence_time_methods,
    miller_1942,
    perry_green_1984,
    saeman_mitchell_1954,
    sai_1990,
    solids_holdup,
    song_2003,
    song_2003_appendix_a,
    sullivan_1927,
    sullivan_friedman_marshall_1949,
)
from .trajectory import (  # noqa: E402
    CascadeTrajectory,
    cascade_residence_time,
    cascade_trajectory,
    forward_step_without_gas,
    gas_forward_step_factor,
    sherritt_curtain_velocity_ratio,
)

__all__ = [
    "CorrelationRangeWarning",
    # residence time
    "mean_residence_time",
    "mean_residence_time_methods",
    "sullivan_1927",
    "sullivan_friedman_marshall_1949",
    "friedman_marshall_1949",
    "foust_1960",
    "perry_green_1984",
    "song_2003",
    "sai_1990",
    "alvarez_shene_1994",
    "saeman_mitchell_1954",
    "miller_1942",
    "solids_holdup",
    "song_2003_appendix_a",
    # heat transfer
    "volumetric_heat_transfer_coefficient",
    "volumetric_heat_transfer_coefficient_methods",
    "nusselt_number",
    "nusselt_number_methods",
    "heat_transfer_coefficient",
    "ua_from_drying_data",
    "log_mean_temperature_difference",
    "chilton_colburn_mass_transfer_coefficient",
    # drag
    "drag_coefficient",
    "drag_coefficient_methods",
    "schiller_naumann_1933",
    "haider_levenspiel_1989",
    "lee_2008",
    "modified_schiller_naumann",
    "stokes_drag",
    "reynolds_number",
    "terminal_velocity",
    # trajectory
    "cascade_trajectory",
    "CascadeTrajectory",
    "forward_step_without_gas",
    "cascade_residence_time",
    "gas_forward_step_factor",
    "sherritt_curtain_velocity_ratio",
]
