"""rotarydryer: an open simulator of flighted rotary dryers.

Units are SI inside the package (kg, m, s, K unless a docstring says otherwise);
angles are in degrees at the public API.
"""

__version__ = "0.1.0"
