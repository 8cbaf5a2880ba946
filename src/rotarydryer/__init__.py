"""rotarydryer: an open simulator of flighted rotary dryers.

Units are SI inside the package (kg, m, s, K unless a docstring says otherwise);
angles are in degrees at the public API.
"""

__version__ = "0.1.0"

__all__ = ["Simulation", "__version__"]


def __getattr__(name):   # lazy: importing rotarydryer stays cheap
    if name == "Simulation":
        from .simulation import Simulation

        return Simulation
    raise AttributeError(f"module 'rotarydryer' has no attribute {name!r}")
