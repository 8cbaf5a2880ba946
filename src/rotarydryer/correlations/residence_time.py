r"""Mean residence time (MRT) and holdup correlations for rotary dryers.

All functions take SI arguments and return the mean residence time
$\tau$ in **seconds**:

* ``length``, ``diameter`` in m; ``slope`` in m/m (rise over run, the tangent of
  the inclination); ``rpm`` in revolutions per minute;
* ``particle_size`` in m (converted internally to the µm that the printed
  constants need, Song 2003 nomenclature "D_p, µm");
* ``gas_mass_flux`` and ``solids_mass_flux`` in kg/(m² s) per dryer
  cross-section (only their ratio G/F enters the Friedman-Marshall family);
* ``gas_flow`` is ``"co-current"`` or ``"counter-current"``.

The Friedman-Marshall family (Song 2003 Eqs. 2.2-2.5 = 4.2-4.5) shares the form

$$
\tau = \frac{a\,L}{s\,n^{p}\,D} \pm \frac{b}{D_p^{0.5}}\,\frac{L\,G}{F}
$$

with + for counter-current and - for co-current gas (Song 2003 L652, L1399).
The constants are Song's rescaled values for τ in seconds, which is what Song
prints (the Perry's-handbook form in ft, min and lb/(h ft²) quoted in
notes/lee_models.md §1 from general literature is *not* used; Song's Eq. 4.4 is).

Sources: Song (2003) ch. 2 (L638-680) and ch. 4 (L1391-1421); Lee (2008)
ch. 2 Eqs. 2.2-2.4; the Saeman-Mitchell form is not in the seed documents and
is quoted from general literature (notes/ajayi_transport.md §2.3, flagged there).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np

from .._validation import check_choice, check_finite, check_positive, check_range
from ..published import read_published_csv
from . import CorrelationRangeWarning
from ._common import SECONDS_PER_HOUR, as_result, warn_outside

__all__ = [
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
    "mean_residence_time",
    "mean_residence_time_methods",
    "missing_inputs",
    "song_2003_appendix_a",
    "GAS_FLOWS",
    "NonPositiveResidenceTime",
]

GAS_FLOWS = ("co-current", "counter-current")

#: Range of Song's Ottawa pilot-dryer data (Appendix A.1, 73 runs) on which Eq. 4.5 was fitted.
SONG_2003_RANGE = {
    "rpm": (3.0, 8.0),  # rev/min
    "slope": (0.067, 0.117),  # m/m
    "gas_to_solids_ratio": (0.0, 3.19),  # G/F, max 10581.83/3317.74 = 3.189
    "particle_size": (0.9 * 444e-6, 1.1 * 444e-6),  # m; a single sand, Sauter 444 µm (±10 % tolerated)
}


class NonPositiveResidenceTime(ValueError):
    """A Friedman-Marshall-form correlation whose co-current gas term reaches its slope term: a residence
    time <= 0. ``summary``: the reason without the Python hint (what a front end shows)."""

    def __init__(self, summary: str):
        super().__init__(summary + " (allow_nonpositive=True returns the raw formula value)")
        self.summary = summary


def _gas_sign(gas_flow: str) -> float:
    check_choice("gas_flow", gas_flow, GAS_FLOWS)
    return 1.0 if gas_flow == "counter-current" else -1.0


def _check_common(length, diameter, slope, rpm):
    length = check_positive("length", length, unit="m")
    diameter = check_positive("diameter", diameter, unit="m")
    slope = check_range("slope", slope, 0.0, 1.0, unit="m/m")
    rpm = check_positive("rpm", rpm, unit="rev/min")
    return length, diameter, slope, rpm


def _friedman_marshall_form(
    name, a, p, b, length, diameter, slope, rpm, particle_size, gas_mass_flux, solids_mass_flux, gas_flow,
    allow_nonpositive=False,
):
    """Evaluate tau = a L/(s n^p D) ± (b/D_p^0.5) L G/F with D_p in µm; tau in s."""
    length, diameter, slope, rpm = _check_common(length, diameter, slope, rpm)
    particle_size = check_range("particle_size", particle_size, 0.0, 0.1, unit="m")
    gas = check_range("gas_mass_flux", gas_mass_flux, 0.0, math.inf, low_inclusive=True, unit="kg/(m2 s)")
    solids = check_positive("solids_mass_flux", solids_mass_flux, unit="kg/(m2 s)")
    sign = _gas_sign(gas_flow)
    dp_um = particle_size * 1e6
    slope_term = a * length / (slope * rpm**p * diameter)
    gas_term = (b / np.sqrt(dp_um)) * length * gas / solids
    tau = slope_term + sign * gas_term
    if np.any(tau <= 0.0):
        bad = np.broadcast_to(tau <= 0.0, np.shape(tau))

        def at(x):      # the value at the first entry with tau <= 0
            return float(np.broadcast_to(x, np.shape(tau))[bad].flat[0])

        msg = (
            f"{name}: the co-current gas term (b/D_p^0.5) L G/F = {at(gas_term):.4g} s is at least the slope "
            f"term a L/(s n^{p:g} D) = {at(slope_term):.4g} s, so the correlation predicts a non-positive "
            "residence time: these inputs (a small particle size, a high gas-to-solids flux ratio, a steep "
            "slope or a fast drum) are outside its range"
        )
        if not allow_nonpositive:
            raise NonPositiveResidenceTime(msg)
        warnings.warn(msg, CorrelationRangeWarning, stacklevel=3)
    return tau


def sullivan_1927(length, diameter, slope, rpm, repose_angle):
    r"""Mean residence time of a rotary kiln (no flights), Sullivan, Maier & Ralston (1927).

    $$
    \tau = \frac{106.2\, L\, \gamma^{0.5}}{\tan^{-1}(s)\; n\; D}
    $$

    Song (2003) Eq. 2.1 (L642), constant rescaled by Song for τ in seconds
    (106.2 = 1.77 × 60).

    Parameters
    ----------
    length : array_like
        Dryer length L, m.
    diameter : array_like
        Dryer diameter D, m.
    slope : array_like
        Dryer slope s, m/m.
    rpm : array_like
        Rotation speed n, rev/min.
    repose_angle : array_like
        Dry angle of repose γ, degrees.

    Returns
    -------
    float or ndarray
        Mean residence time τ, s.

    Notes
    -----
    Ambiguity: Song does not state the unit of $\tan^{-1}(s)$. It is read
    here in **degrees** (the original Sullivan slope is in degrees), because only
    then does Eq. 2.1 with γ = 40° agree with Friedman & Marshall's restatement
    Eq. 2.2 (106.2·√40/57.30 = 11.7 against 10.58, 11 % apart); radians would
    make it 57 times larger. Written for unflighted kilns; no fitted range is
    given in the sources, so no range warning is issued.

    Examples
    --------
    >>> round(sullivan_1927(length=3.05, diameter=0.305, slope=0.083, rpm=5.0, repose_angle=40.0), 2)
    283.12
    """
    length, diameter, slope, rpm = _check_common(length, diameter, slope, rpm)
    repose_angle = check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg")
    slope_deg = np.degrees(np.arctan(slope))
    return as_result(106.2 * length * np.sqrt(repose_angle) / (slope_deg * rpm * diameter))


def sullivan_friedman_marshall_1949(length, diameter, slope, rpm):
    r"""Sullivan's kiln equation as restated by Friedman & Marshall (1949), no gas term.

    $$
    \tau = \frac{10.58\, L}{s\, n^{0.9}\, D}
    $$

    Song (2003) Eq. 2.2 (L646): slope in m/m, exponent 0.9 on n, angle of
    repose 40° assumed.

    Parameters
    ----------
    length, diameter : array_like
        Dryer length L and diameter D, m.
    slope : array_like
        Dryer slope s, m/m.
    rpm : array_like
        Rotation speed n, rev/min.

    Returns
    -------
    float or ndarray
        Mean residence time τ, s.

    Examples
    --------
    >>> round(sullivan_friedman_marshall_1949(3.05, 0.305, 0.083, 5.0), 2)
    299.46
    """
    length, diameter, slope, rpm = _check_common(length, diameter, slope, rpm)
    return as_result(10.58 * length / (slope * rpm**0.9 * diameter))


def friedman_marshall_1949(
    length, diameter, slope, rpm, particle_size, gas_mass_flux, solids_mass_flux, gas_flow="co-current",
    allow_nonpositive=False,
):
    r"""Mean residence time, Friedman & Marshall (1949).

    $$
    \tau = \frac{10.58\, L}{s\, n^{0.9}\, D} \pm \frac{608.3}{D_p^{0.5}}\,\frac{L\, G}{F}
    $$

    Song (2003) Eq. 2.3 = Eq. 4.2 (L650, L1397); + counter-current, − co-current.
    D_p in µm (Song's nomenclature; the ch. 2 print says d_p but the constant
    needs µm, verified on Song's Appendix A data). On Song's pilot data it
    under-predicts (Song 2003 L1407).

    Parameters
    ----------
    length, diameter : array_like
        Dryer length L and diameter D, m.
    slope : array_like
        Dryer slope s, m/m.
    rpm : array_like
        Rotation speed n, rev/min.
    particle_size : array_like
        Weighted-mean (Sauter) particle size D_p, m.
    gas_mass_flux, solids_mass_flux : array_like
        Gas G and dry-solids F mass flux per dryer cross-section, kg/(m² s).
    gas_flow : {"co-current", "counter-current"}
        Direction of the gas relative to the solids.
    allow_nonpositive : bool
        If False (default) a co-current gas term that makes τ ≤ 0 raises
        ``ValueError``; if True the raw formula value is returned with a
        `CorrelationRangeWarning` (used to
        reproduce Song's evaluation of the printed formulas).

    Returns
    -------
    float or ndarray
        Mean residence time τ, s.

    Raises
    ------
    ValueError
        If the co-current gas term makes τ ≤ 0 and ``allow_nonpositive`` is False.

    Notes
    -----
    Friedman & Marshall's pilot-dryer range is not given in the seed documents,
    so no range warning is issued.

    Examples
    --------
    >>> round(friedman_marshall_1949(3.05, 0.305, 0.083, 5.0, 444e-6, 0.5, 0.7), 2)
    236.56
    """
    return as_result(
        _friedman_marshall_form(
            "friedman_marshall_1949", 10.58, 0.9, 608.3, length, diameter, slope, rpm,
            particle_size, gas_mass_flux, solids_mass_flux, gas_flow,
            allow_nonpositive,
        )
    )


def foust_1960(
    length, diameter, slope, rpm, particle_size, gas_mass_flux, solids_mass_flux, gas_flow="co-current",
    allow_nonpositive=False,
):
    r"""Mean residence time, Friedman-Marshall as reported by Foust et al. (1960).

    $$
    \tau = \frac{21\, L}{s\, n^{0.9}\, D} \pm \frac{614.2}{D_p^{0.5}}\,\frac{L\, G}{F}
    $$

    Song (2003) Eq. 2.4 = Eq. 4.3 (L654, L1401). Song (L652, after Renaud et
    al. 2000) explains that the first term is inflated by 98.5 % through a
    missing 0.6 unit factor; on Song's data it over-predicts. Arguments and
    units as [`friedman_marshall_1949`][rotarydryer.correlations.residence_time.friedman_marshall_1949]; returns τ in s.

    Examples
    --------
    >>> round(foust_1960(3.05, 0.305, 0.083, 5.0, 444e-6, 0.5, 0.7), 2)
    530.88
    """
    return as_result(
        _friedman_marshall_form(
            "foust_1960", 21.0, 0.9, 614.2, length, diameter, slope, rpm,
            particle_size, gas_mass_flux, solids_mass_flux, gas_flow,
            allow_nonpositive,
        )
    )


def perry_green_1984(
    length, diameter, slope, rpm, particle_size, gas_mass_flux, solids_mass_flux, gas_flow="co-current",
    allow_nonpositive=False,
):
    r"""Mean residence time, Friedman-Marshall as reported by Perry & Green (1984).

    $$
    \tau = \frac{13.8\, L}{s\, n^{0.9}\, D} \pm \frac{590.6}{D_p^{0.5}}\,\frac{L\, G}{F}
    $$

    Song (2003) Eq. 2.5 = Eq. 4.4 (L658, L1405): the first constant of Eq. 2.3
    raised by 30 %, the mean error Friedman & Marshall observed. This is the form
    Song prints (τ in s, SI lengths, D_p in µm); the Perry's-handbook form in
    ft/min/lb units (0.23 L/(S N^0.9 D) ± 0.6 B L G/F) quoted from general
    literature in notes/lee_models.md §1 is not used. The second constant 590.6
    differs from 608.3 without explanation in Song. Best of the three literature
    forms on Song's pilot data. Arguments and units as
    [`friedman_marshall_1949`][rotarydryer.correlations.residence_time.friedman_marshall_1949]; returns τ in s.

    Examples
    --------
    >>> round(perry_green_1984(length=3.05, diameter=0.305, slope=0.083, rpm=5.0,
    ...                        particle_size=444e-6, gas_mass_flux=0.5,
    ...                        solids_mass_flux=0.7, gas_flow="co-current"), 2)
    329.53
    """
    return as_result(
        _friedman_marshall_form(
            "perry_green_1984", 13.8, 0.9, 590.6, length, diameter, slope, rpm,
            particle_size, gas_mass_flux, solids_mass_flux, gas_flow,
            allow_nonpositive,
        )
    )


def song_2003(
    length, diameter, slope, rpm, particle_size, gas_mass_flux, solids_mass_flux, gas_flow="co-current",
    allow_nonpositive=False,
):
    r"""Mean residence time, Song & Thibault correlation (Song 2003 Eq. 4.5).

    $$
    \tau = \frac{14.3\, L}{s\, n\, D} - \frac{354}{D_p^{0.5}}\,\frac{L\, G}{F}
    $$

    Song (2003) Eq. 4.5 (L1411), fitted to all 73 Ottawa pilot-dryer runs
    (0.305 m × 3.05 m, 9 lifters, co-current, dry sand D_p = 444 µm). Unit
    exponent on n (Song L1421). Arguments and units as
    [`friedman_marshall_1949`][rotarydryer.correlations.residence_time.friedman_marshall_1949]; returns τ in s.

    Fitted range (Song 2003 Appendix A.1): n = 3-8 rpm, s = 0.067-0.117 m/m,
    G/F = 0-3.19, D_p = 444 µm (a single sand), co-current gas only. Outside it
    a `CorrelationRangeWarning` is issued. For
    counter-current gas the sign of the gas term is taken as + (the convention of
    the family it extends); Song never fitted that case and a warning says so.

    Examples
    --------
    >>> round(song_2003(3.05, 0.305, 0.083, 5.0, 444e-6, 0.5, 0.7), 2)
    307.98
    """
    tau = _friedman_marshall_form(
        "song_2003", 14.3, 1.0, 354.0, length, diameter, slope, rpm,
        particle_size, gas_mass_flux, solids_mass_flux, gas_flow,
            allow_nonpositive,
    )
    src = "Song (2003) Eq. 4.5"
    warn_outside("rpm", rpm, *SONG_2003_RANGE["rpm"], unit="rev/min", source=src)
    warn_outside("slope", slope, *SONG_2003_RANGE["slope"], unit="m/m", source=src)
    ratio = np.asarray(gas_mass_flux, dtype=float) / np.asarray(solids_mass_flux, dtype=float)
    warn_outside("gas_mass_flux/solids_mass_flux", ratio, *SONG_2003_RANGE["gas_to_solids_ratio"], source=src)
    warn_outside("particle_size", particle_size, *SONG_2003_RANGE["particle_size"], unit="m", source=src)
    if gas_flow == "counter-current":
        warnings.warn(
            f"gas_flow = 'counter-current' is outside the fitted range of {src} (co-current runs only); "
            "the gas term sign is taken as + by analogy with Eqs. 4.2-4.4",
            CorrelationRangeWarning,
            stacklevel=2,
        )
    return as_result(tau)


_THETA_GRID = np.linspace(0.0, 2.0 * np.pi, 8193)
_FILL_GRID = _THETA_GRID - np.sin(_THETA_GRID)


def _bed_angle_from_holdup(fill):
    """Solve θ - sin θ = fill for θ in (0, 2π), vectorised.

    Start from a tabulated inverse (linear interpolation on 8193 points), or the
    series inversion θ ≈ (6 fill)^(1/3) below the ninth table point, then two
    Newton steps; a step leaving [0, 2π] is replaced by the start value, so it
    cannot diverge or hang.
    """
    fill = np.asarray(fill, dtype=float)
    theta = np.interp(fill, _FILL_GRID, _THETA_GRID)
    theta = np.where(fill < _FILL_GRID[8], np.cbrt(6.0 * fill), theta)
    start = theta
    for _ in range(2):
        with np.errstate(divide="ignore", invalid="ignore"):
            new = theta - (theta - np.sin(theta) - fill) / (1.0 - np.cos(theta))
        theta = np.where(np.isfinite(new) & (new > 0.0) & (new < 2.0 * np.pi), new, start)
    return theta


def sai_1990(length, diameter, slope, rpm, solids_mass_flux, holdup, bulk_density):
    r"""Mean residence time of a rotary kiln from its holdup, Sai et al. (1990).

    $$
    H = \rho L r^2 (\theta - \sin\theta)/2, \qquad h = r\,[1 - \cos(\theta/2)]
    $$

    $$
    \tau = \frac{78912\, h^{0.24}}{[\tan^{-1}(s)]^{1.02}\; n^{0.88}\; (\pi r^2 F)^{0.072}}
    $$

    Song (2003) Eqs. 2.6-2.8 (L660-670). A flat, symmetric bed of uniform depth
    is assumed; θ (rad) is the angle the bed subtends at the axis and h (m) its
    maximum depth. No gas effect.

    Parameters
    ----------
    length, diameter : array_like
        Kiln length L and diameter D = 2r, m.
    slope : array_like
        Slope s, m/m.
    rpm : array_like
        Rotation speed n, rev/min.
    solids_mass_flux : array_like
        Solids feed F per cross-section, kg/(m² s).
    holdup : array_like
        Solids holdup H, kg (must be known a priori).
    bulk_density : array_like
        Bed bulk density ρ, kg/m³.

    Returns
    -------
    float or ndarray
        Mean residence time τ, s.

    Notes
    -----
    Ambiguity: Song gives no units for $\tan^{-1}(s)$ or π r² F. Read
    here, following Song's nomenclature: angle in **degrees** (as in Sullivan's
    Eq. 2.1, see [`sullivan_1927`][rotarydryer.correlations.residence_time.sullivan_1927]), π r² F in **kg/h** (F in kg/(h m²)), h
    in m and τ in s. This reading is unverified: Song did not evaluate Eq. 2.8
    and gives no published value; the rotary-kiln range of Sai et al. is not
    given, so no range warning is issued.

    Examples
    --------
    >>> round(sai_1990(3.05, 0.305, 0.083, 5.0, 1.2318, 30.0, 1650.0), 1)
    1201.9
    """
    length, diameter, slope, rpm = _check_common(length, diameter, slope, rpm)
    slope = check_positive("slope", slope, unit="m/m")
    solids = check_positive("solids_mass_flux", solids_mass_flux, unit="kg/(m2 s)")
    holdup = check_positive("holdup", holdup, unit="kg")
    bulk_density = check_positive("bulk_density", bulk_density, unit="kg/m3")
    radius = diameter / 2.0
    fill = 2.0 * holdup / (bulk_density * length * radius**2)
    if np.any(fill >= 2.0 * np.pi):
        raise ValueError(
            f"holdup = {np.max(holdup):g} kg exceeds the volume of the kiln at bulk_density "
            f"(fill parameter 2H/(rho L r^2) must be < 2*pi)"
        )
    theta = _bed_angle_from_holdup(np.broadcast_to(fill, np.broadcast(fill, holdup).shape).astype(float))
    bed_depth = radius * (1.0 - np.cos(theta / 2.0))
    slope_deg = np.degrees(np.arctan(slope))
    feed_kg_h = np.pi * radius**2 * solids * SECONDS_PER_HOUR
    tau = 78912.0 * bed_depth**0.24 / (slope_deg**1.02 * rpm**0.88 * feed_kg_h**0.072)
    return as_result(tau)


def alvarez_shene_1994(diameter, slope, rpm, particle_size, particle_density, solids_mass_flux, gas_mass_flux):
    r"""Mean residence time, Alvarez & Shene (1994), usable at zero slope.

    $$
    \tau = \frac{7856\, d_p^{0.032} \rho^{0.956}}{\pi r^2 F n (18.95 s + 1)}
    + \frac{1009\, d_p^{-0.065} \rho^{0.002}}{27.22 s + 1}
    - \frac{0.108\, G^{0.5}}{29.19 s + 1}
    $$

    Song (2003) Eq. 2.9 (L672-674); Lee (2008) Eq. 2.8 (body stripped there).

    Parameters
    ----------
    diameter : array_like
        Dryer diameter D = 2r, m.
    slope : array_like
        Slope s, m/m (0 allowed).
    rpm : array_like
        Rotation speed n, rev/min.
    particle_size : array_like
        Particle diameter d_p, m.
    particle_density : array_like
        Solids density ρ, kg/m³.
    solids_mass_flux, gas_mass_flux : array_like
        Solids F and gas G mass flux per cross-section, kg/(m² s).

    Returns
    -------
    float or ndarray
        Mean residence time τ, s.

    Notes
    -----
    Ambiguity: Song gives no units. Read here with Song's nomenclature: d_p in
    m, ρ in kg/m³, F and G in kg/(h m²) (so π r² F is in kg/h), τ in s. There is
    no length term: the correlation is specific to Alvarez & Shene's dryer and is
    not evaluated against data by Song; unverified, no fitted range given.

    Examples
    --------
    >>> round(alvarez_shene_1994(0.305, 0.083, 5.0, 444e-6, 1650.0, 1.2318, 2.3833), 1)
    2269.6
    """
    diameter = check_positive("diameter", diameter, unit="m")
    slope = check_range("slope", slope, 0.0, 1.0, low_inclusive=True, unit="m/m")
    rpm = check_positive("rpm", rpm, unit="rev/min")
    dp = check_range("particle_size", particle_size, 0.0, 0.1, unit="m")
    rho = check_positive("particle_density", particle_density, unit="kg/m3")
    solids_h = check_positive("solids_mass_flux", solids_mass_flux, unit="kg/(m2 s)") * SECONDS_PER_HOUR
    gas_h = check_range("gas_mass_flux", gas_mass_flux, 0.0, math.inf, low_inclusive=True,
                        unit="kg/(m2 s)") * SECONDS_PER_HOUR
    r = diameter / 2.0
    tau = (
        7856.0 * dp**0.032 * rho**0.956 / (np.pi * r**2 * solids_h * rpm * (18.95 * slope + 1.0))
        + 1009.0 * dp**-0.065 * rho**0.002 / (27.22 * slope + 1.0)
        - 0.108 * np.sqrt(gas_h) / (29.19 * slope + 1.0)
    )
    if np.any(tau <= 0.0):
        raise ValueError("alvarez_shene_1994: the gas term makes the residence time non-positive; "
                         f"gas_mass_flux = {np.max(np.asarray(gas_mass_flux)):g} kg/(m2 s) is too large")
    return as_result(tau)


def saeman_mitchell_1954(length, diameter, slope, rpm, gas_velocity, cascade_factor, gas_coefficient,
                         gas_flow="co-current"):
    r"""Mean residence time, Saeman & Mitchell (1954) cascade form.

    $$
    \tau = \frac{L}{f(H)\, D\, n\, (s \pm m' v_g)}
    $$

    **Not in the seed documents**: Song (2003) cites Saeman & Mitchell only for
    two-humped RTDs; the form is the general-literature one quoted (and flagged
    "verify before use") in notes/ajayi_transport.md §2.3 and
    notes/lee_models.md §1. Here n is converted to rev/s so that τ is in s; the
    sign is + for co-current gas (the gas speeds the solids) and − for
    counter-current.

    Parameters
    ----------
    length, diameter : array_like
        Dryer length L and diameter D, m.
    slope : array_like
        Slope s, m/m.
    rpm : array_like
        Rotation speed n, rev/min.
    gas_velocity : array_like
        Superficial gas velocity v_g, m/s (≥ 0).
    cascade_factor : array_like
        Cascade factor f(H), dimensionless (about π to 2π).
    gas_coefficient : array_like
        Empirical constant m', s/m.
    gas_flow : {"co-current", "counter-current"}

    Returns
    -------
    float or ndarray
        Mean residence time τ, s.

    Examples
    --------
    >>> round(saeman_mitchell_1954(3.05, 0.305, 0.083, 5.0, 1.0, math.pi, 0.01), 2)
    410.72
    """
    length, diameter, slope, rpm = _check_common(length, diameter, slope, rpm)
    v = check_range("gas_velocity", gas_velocity, 0.0, math.inf, low_inclusive=True, unit="m/s")
    f = check_positive("cascade_factor", cascade_factor)
    m = check_range("gas_coefficient", gas_coefficient, 0.0, math.inf, low_inclusive=True, unit="s/m")
    sign = -_gas_sign(gas_flow)
    forward = slope + sign * m * v
    if np.any(forward <= 0.0):
        raise ValueError("saeman_mitchell_1954: counter-current gas term m'*v_g exceeds the slope; "
                         "the solids would not advance (slope - gas_coefficient*gas_velocity must be > 0)")
    return as_result(length / (f * diameter * (rpm / 60.0) * forward))


def miller_1942(length, diameter, slope, rpm, flight_solids_volume, k, m):
    r"""Mean residence time, Miller, Smith & Schuette (1942), as reviewed by Lee (2008).

    $$
    \tau = \frac{k\, L}{s\, D\, \omega} + m\, \forall_{solids}
    $$

    Lee (2008) Eq. 2.4 (l.890-919). k depends on the number and shape of flights
    and m on the gas flow; both must be fitted to each dryer (Lee), so they are
    required arguments. Reading: the additive form (the "+" is visible in the
    garble; the alternative k L ∀^m/(s D ω) is not implemented). Units as Lee
    gives none: ω taken in rev/min, k in s·rev/min, m in s/m³, so τ is in s.

    Parameters
    ----------
    length, diameter : array_like
        m.
    slope : array_like
        m/m.
    rpm : array_like
        Rotation speed ω, rev/min.
    flight_solids_volume : array_like
        Volume of solids in a flight ∀, m³.
    k : array_like
        Fitted constant, s·rev/min.
    m : array_like
        Fitted constant, s/m³.

    Returns
    -------
    float or ndarray
        τ, s.

    Examples
    --------
    >>> round(miller_1942(3.05, 0.305, 0.083, 5.0, 0.001, 13.0, 1.0e4), 2)
    323.25
    """
    length, diameter, slope, rpm = _check_common(length, diameter, slope, rpm)
    vol = check_range("flight_solids_volume", flight_solids_volume, 0.0, math.inf, low_inclusive=True, unit="m3")
    k = check_positive("k", k)
    m = check_finite("m", m)
    tau = k * length / (slope * diameter * rpm) + m * vol
    if np.any(tau <= 0):
        raise ValueError("miller_1942: the fitted constants give a non-positive residence time")
    return as_result(tau)


def solids_holdup(mean_residence_time, solids_feed_rate):
    r"""Steady-state solids holdup from the mean residence time, H = τ F.

    Song (2003) Eq. 4.1; Lee (2008) Eq. 2.2.

    Parameters
    ----------
    mean_residence_time : array_like
        τ, s.
    solids_feed_rate : array_like
        Dry-solids feed rate F, kg/s.

    Returns
    -------
    float or ndarray
        Holdup H, kg.

    Examples
    --------
    >>> round(solids_holdup(6.98 * 60, 7.93 / 60), 2)   # Song (2003) Table 4.1 run 3
    55.35
    """
    tau = check_positive("mean_residence_time", mean_residence_time, unit="s")
    feed = check_range("solids_feed_rate", solids_feed_rate, 0.0, math.inf, low_inclusive=True, unit="kg/s")
    return as_result(tau * feed)


# --------------------------------------------------------------------------- dispatcher

_METHODS: dict[str, tuple[Callable[..., Any], tuple[str, ...]]] = {
    "song_2003": (song_2003, ("length", "diameter", "slope", "rpm", "particle_size", "gas_mass_flux",
                              "solids_mass_flux", "gas_flow")),
    "perry_green_1984": (perry_green_1984, ("length", "diameter", "slope", "rpm", "particle_size",
                                            "gas_mass_flux", "solids_mass_flux", "gas_flow")),
    "friedman_marshall_1949": (friedman_marshall_1949, ("length", "diameter", "slope", "rpm", "particle_size",
                                                        "gas_mass_flux", "solids_mass_flux", "gas_flow")),
    "foust_1960": (foust_1960, ("length", "diameter", "slope", "rpm", "particle_size", "gas_mass_flux",
                                "solids_mass_flux", "gas_flow")),
    "sullivan_friedman_marshall_1949": (sullivan_friedman_marshall_1949, ("length", "diameter", "slope", "rpm")),
    "sullivan_1927": (sullivan_1927, ("length", "diameter", "slope", "rpm", "repose_angle")),
    "sai_1990": (sai_1990, ("length", "diameter", "slope", "rpm", "solids_mass_flux", "holdup", "bulk_density")),
    "alvarez_shene_1994": (alvarez_shene_1994, ("diameter", "slope", "rpm", "particle_size", "particle_density",
                                                "solids_mass_flux", "gas_mass_flux")),
    "saeman_mitchell_1954": (saeman_mitchell_1954, ("length", "diameter", "slope", "rpm", "gas_velocity",
                                                    "cascade_factor", "gas_coefficient", "gas_flow")),
    "miller_1942": (miller_1942, ("length", "diameter", "slope", "rpm", "flight_solids_volume", "k", "m")),
}

_FM_FAMILY = ("song_2003", "perry_green_1984", "friedman_marshall_1949", "foust_1960")

#: Methods in order of preference (best on Song's pilot data first).
MEAN_RESIDENCE_TIME_METHODS = tuple(_METHODS)


def _in_song_range(inputs) -> bool:
    try:
        rpm = np.asarray(inputs["rpm"], float)
        slope = np.asarray(inputs["slope"], float)
        ratio = np.asarray(inputs["gas_mass_flux"], float) / np.asarray(inputs["solids_mass_flux"], float)
        dp = np.asarray(inputs["particle_size"], float)
    except (TypeError, ValueError, ZeroDivisionError):
        return False
    r = SONG_2003_RANGE
    return bool(
        np.all((rpm >= r["rpm"][0]) & (rpm <= r["rpm"][1]))
        and np.all((slope >= r["slope"][0]) & (slope <= r["slope"][1]))
        and np.all((ratio >= r["gas_to_solids_ratio"][0]) & (ratio <= r["gas_to_solids_ratio"][1]))
        and np.all((dp >= r["particle_size"][0]) & (dp <= r["particle_size"][1]))
        and inputs.get("gas_flow", "co-current") == "co-current"
    )


def missing_inputs(method: str, **inputs) -> list[str]:
    """The arguments ``method`` needs that ``inputs`` lacks (None counts as missing; ``gas_flow`` has a default).

    Examples
    --------
    >>> missing_inputs("perry_green_1984", length=10.0, diameter=2.0, slope=0.03, rpm=4.0)
    ['particle_size', 'gas_mass_flux', 'solids_mass_flux']
    """
    check_choice("method", method, _METHODS)
    return [k for k in _METHODS[method][1] if k != "gas_flow" and inputs.get(k) is None]


def mean_residence_time_methods(*, check_ranges: bool = False, **inputs) -> list[str]:
    """List the mean-residence-time methods that can be evaluated with the given inputs.

    A method is listed when every argument it needs is given (``gas_flow``
    defaults to co-current). With ``check_ranges=True`` the methods whose
    published fitted range excludes the inputs (so far only ``song_2003``
    has a known range) are dropped. Order: best on Song's pilot data first.

    Examples
    --------
    >>> mean_residence_time_methods(length=3.05, diameter=0.305, slope=0.083, rpm=5.0)
    ['sullivan_friedman_marshall_1949']
    >>> mean_residence_time_methods(length=3.05, diameter=0.305, slope=0.083, rpm=5.0,
    ...     particle_size=444e-6, gas_mass_flux=0.5, solids_mass_flux=0.7)[:2]
    ['song_2003', 'perry_green_1984']
    """
    given = {k for k, v in inputs.items() if v is not None} | {"gas_flow"}
    out = []
    for name, (_, needed) in _METHODS.items():
        if not set(needed) <= given:
            continue
        if check_ranges and name == "song_2003" and not _in_song_range(inputs):
            continue
        out.append(name)
    return out


def mean_residence_time(method: str | None = None, **inputs):
    """Mean residence time of solids in a rotary dryer, s, by the chosen correlation.

    Parameters
    ----------
    method : str, optional
        One of `MEAN_RESIDENCE_TIME_METHODS`. If omitted, the first of
        ``mean_residence_time_methods(check_ranges=True, **inputs)`` is used
        (Song's Eq. 4.5 inside its fitted range, else Perry & Green).
    **inputs
        SI keyword arguments of the chosen correlation (see the module
        docstring): ``length`` m, ``diameter`` m, ``slope`` m/m, ``rpm`` rev/min,
        ``particle_size`` m, ``gas_mass_flux`` and ``solids_mass_flux``
        kg/(m² s), ``gas_flow``; plus ``repose_angle`` (deg), ``holdup`` (kg),
        ``bulk_density``, ``particle_density`` (kg/m³), ``gas_velocity`` (m/s),
        ``cascade_factor``, ``gas_coefficient``, ``flight_solids_volume``,
        ``k``, ``m`` for the methods that need them; ``allow_nonpositive`` for
        the Friedman-Marshall family. Unused inputs are ignored.

    Returns
    -------
    float or ndarray
        τ, s.

    Examples
    --------
    >>> round(mean_residence_time(method="perry_green_1984", length=3.05, diameter=0.305,
    ...     slope=0.083, rpm=5.0, particle_size=444e-6, gas_mass_flux=0.5,
    ...     solids_mass_flux=0.7, gas_flow="co-current"), 2)
    329.53
    """
    if method is None:
        candidates = mean_residence_time_methods(check_ranges=True, **inputs)
        if not candidates:
            raise ValueError(
                "mean_residence_time: the inputs given "
                f"({', '.join(sorted(k for k, v in inputs.items() if v is not None))}) "
                "are not enough for any method; see mean_residence_time_methods()"
            )
        method = candidates[0]
    check_choice("method", method, _METHODS)
    func, needed = _METHODS[method]
    missing = missing_inputs(method, **inputs)
    if missing:
        raise ValueError(f"mean_residence_time(method={method!r}) needs the argument(s) {', '.join(missing)}")
    kwargs = {k: inputs[k] for k in needed if k in inputs and inputs[k] is not None}
    if "allow_nonpositive" in inputs and method in _FM_FAMILY:
        kwargs["allow_nonpositive"] = bool(inputs["allow_nonpositive"])
    return func(**kwargs)


# --------------------------------------------------------------------------- data


def song_2003_appendix_a() -> dict[str, np.ndarray]:
    """Song (2003) Appendix A.1: the 73 Ottawa pilot-dryer MRT runs, in SI units.

    Read from the package data file ``data/song_appendixA_mrt.csv`` (transcribed
    verbatim from the thesis, seed lines 1497-1572).

    Returns
    -------
    dict of ndarray
        ``length`` m, ``diameter`` m, ``particle_size`` m, ``particle_density``
        kg/m³, ``solids_mass_flux`` and ``gas_mass_flux`` kg/(m² s), ``rpm``
        rev/min, ``slope`` m/m, ``mean_residence_time`` s (measured),
        ``solids_feed_rate`` kg/s, ``src_line``.

    Examples
    --------
    >>> d = song_2003_appendix_a()
    >>> len(d["rpm"]), round(float(d["mean_residence_time"][0]), 1)
    (73, 354.6)
    """

    rows = read_published_csv("song_appendixA_mrt.csv")

    def col(name, scale=1.0):
        return np.array([float(r[name]) for r in rows]) * scale

    return {
        "src_line": col("src_line").astype(int),
        "length": col("L_m"),
        "diameter": col("D_m"),
        "particle_size": col("dp_um", 1e-6),
        "particle_density": col("rho_p_kg_m3"),
        "solids_mass_flux": col("F_kg_h_m2", 1.0 / SECONDS_PER_HOUR),
        "gas_mass_flux": col("G_kg_h_m2", 1.0 / SECONDS_PER_HOUR),
        "rpm": col("n_rpm"),
        "slope": col("slope_m_m"),
        "mean_residence_time": col("tau_min", 60.0),
        "solids_feed_rate": col("Ori_F_kg_min", 1.0 / 60.0),
    }
