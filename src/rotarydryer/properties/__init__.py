"""Material properties: solids (repose angle, bulk density versus moisture), humid air,
water and steam, combustion gases."""

from . import combustion, humid_air, water
from .solids import (
    SOLIDS,
    bulk_density,
    lee2008_moisture_profile,
    repose_angle,
)

__all__ = ["combustion", "humid_air", "water", "SOLIDS", "bulk_density", "lee2008_moisture_profile", "repose_angle"]
