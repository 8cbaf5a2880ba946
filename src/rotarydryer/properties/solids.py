"""Solids properties that depend on moisture: dynamic angle of repose and bulk density.

Moisture ``x`` is in kg water per kg (as each source defines it: wet basis for
Ajayi's zinc concentrate, as coded by Lee for raw sugar). Inside the range the
correlation was fitted on the functions are silent; outside it they warn
([`PropertyRangeWarning`][rotarydryer.properties.solids.PropertyRangeWarning]), and where the result would be non-physical
(repose angle outside (0, 90) deg, density <= 0) they raise ``ValueError``.

Materials
---------
``"zinc_concentrate_ajayi2011"``
:   MMG Karumba zinc concentrate. Repose angle Ajayi (2011) Eq. 3.2,
    ``phi = 419.6 x - 7.801`` deg (Table 3.3, x = 0.120-0.166 kg/kg wet, pilot drum,
    ImageJ); consolidated (tapped) bulk density Ajayi (2011) Eq. 3.4,
    ``rho_b = 2043.8 - 3095.2 x`` kg/m^3 (Table 3.4).

``"raw_sugar_lee2008"``
:   CSR raw sugar. Repose angle Lee (2008) Eq. 7.2 (after Britton et al. 2006),
    ``phi = 1222.2 w + 34.5`` deg with ``w`` in kg/kg as in Lee's gPROMS code
    (w = 0.02 -> 0.002 along the dryer; the text's "0.2 -> 0.02 wt %" differs by a
    factor of 10 and is taken as a typo, notes lee_models.md section 5.5). Bulk density
    is constant: 940 kg/m^3 as in Lee's code and tables (the consolidated value measured
    in Table 7.1 is 936.06 kg/m^3; ``bulk_density(..., variant="measured")`` returns it).
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from .._validation import check_choice, check_range

__all__ = [
    "PropertyRangeWarning",
    "SOLIDS",
    "repose_angle",
    "bulk_density",
    "lee2008_moisture_profile",
]


class PropertyRangeWarning(UserWarning):
    """A property correlation is used outside the moisture range it was fitted on."""


SOLIDS: dict[str, dict[str, Any]] = {
    "zinc_concentrate_ajayi2011": {
        "repose": (419.6, -7.801),  # Ajayi (2011) Eq. 3.2, deg = a x + b
        "repose_range": (0.120, 0.166),  # Table 3.3
        "density": (2043.8, -3095.2),  # Ajayi (2011) Eq. 3.4, kg/m^3 = a + b x
        "density_code": (2043.81, -3095.24),  # the same in Ajayi's gPROMS code (L3608-3618), used by the models
        "density_range": (0.120, 0.166),
    },
    "raw_sugar_lee2008": {
        "repose": (1222.2, 34.5),  # Lee (2008) Eq. 7.2
        "repose_range": (0.002, 0.02),  # Lee's gPROMS moisture profile
        "density": (940.0, 0.0),  # Lee (2008) gPROMS Process entity rhob := 940
        "density_measured": 936.06,  # Lee (2008) Table 7.1, consolidated
        "density_range": (0.0, 0.02),
    },
}


def _warn_range(material, quantity, x, rng):
    if np.any((x < rng[0]) | (x > rng[1])):
        warnings.warn(
            f"moisture outside the range {rng[0]:g}-{rng[1]:g} kg/kg on which the {quantity} "
            f"correlation for {material!r} was fitted",
            PropertyRangeWarning,
            stacklevel=3,
        )


def repose_angle(moisture, material: str = "zinc_concentrate_ajayi2011"):
    """Dynamic angle of repose, deg, as a function of moisture (kg/kg).

    >>> round(float(repose_angle(0.15)), 2)     # Ajayi (2011) Eq. 3.2
    55.14
    >>> round(float(repose_angle(0.02, "raw_sugar_lee2008")), 3)   # Lee (2008) Eq. 7.2
    58.944
    """
    check_choice("material", material, SOLIDS)
    x = check_range("moisture", moisture, 0.0, 1.0, low_inclusive=True, unit="kg/kg")
    a, b = SOLIDS[material]["repose"]
    _warn_range(material, "repose angle", x, SOLIDS[material]["repose_range"])
    phi = a * x + b
    if np.any((phi <= 0.0) | (phi >= 90.0)):
        raise ValueError(
            f"moisture = {x!r} kg/kg gives a repose angle outside (0, 90) deg for {material!r}; "
            f"the correlation was fitted on {SOLIDS[material]['repose_range']} kg/kg"
        )
    return phi


def bulk_density(moisture, material: str = "zinc_concentrate_ajayi2011", variant: str = "model"):
    """Bulk density, kg/m^3, as a function of moisture (kg/kg).

    ``variant="measured"`` returns Lee's measured consolidated raw-sugar density
    (936.06 kg/m^3) instead of the 940 kg/m^3 his model used.

    >>> round(float(bulk_density(0.15)), 1)     # Ajayi (2011) Eq. 3.4
    1579.5
    """
    check_choice("material", material, SOLIDS)
    check_choice("variant", variant, ("model", "measured"))
    x = check_range("moisture", moisture, 0.0, 1.0, low_inclusive=True, unit="kg/kg")
    props = SOLIDS[material]
    _warn_range(material, "bulk density", x, props["density_range"])
    if variant == "measured" and "density_measured" in props:
        return np.full_like(x, props["density_measured"])
    a, b = props["density"]
    rho = a + b * x
    if np.any(rho <= 0.0):
        raise ValueError(f"moisture = {x!r} kg/kg gives a non-positive bulk density for {material!r}")
    return rho


def lee2008_moisture_profile(n_cells: int, inlet: float = 0.02, outlet: float = 0.002):
    """Lee's assumed moisture profile along the Invicta dryer, kg/kg, one value per cell.

    Log-linear from ``inlet`` (cell 1) to ``outlet`` (cell N), Lee (2008) gPROMS Dryer
    model (Appendix I, l.12456): ``w_i = inlet * (outlet/inlet)^((i-1)/(N-1))``.
    """
    if isinstance(n_cells, bool) or int(n_cells) != n_cells or n_cells < 1:
        raise ValueError(f"n_cells = {n_cells!r} must be an integer >= 1")
    check_range("inlet", inlet, 0.0, 1.0, unit="kg/kg")
    check_range("outlet", outlet, 0.0, 1.0, unit="kg/kg")
    i = np.arange(int(n_cells))
    return inlet * np.exp(np.log(outlet / inlet) * i / max(n_cells - 1, 1))
