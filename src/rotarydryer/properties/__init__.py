"""Material properties: solids (repose angle, bulk density versus moisture)."""

from .solids import (
    SOLIDS,
    bulk_density,
    lee2008_moisture_profile,
    repose_angle,
)

__all__ = ["SOLIDS", "bulk_density", "lee2008_moisture_profile", "repose_angle"]
