"""Where a flight's curtain falls: discharge per degree of rotation and across the drum, final discharge angle.

A flight discharges into the curtain from the angle at which it starts (the first unloading flight
or, under-loaded, where its holdup falls to ``f H0_des``; `rotarydryer.geometry.unloading`) to the
final discharge angle psi5, where it is empty (Lee (2008) Eq. 4.13 for a two-section flight; the
surface lies along the flight's last section for any flight). The rate is
``-dH/dpsi`` per degree (Lee (2008): ``F = omega dH/dpsi``); the solids leave the tip at the tip
angle ``chi = psi + psi_ft`` and fall vertically (Lee (2008) section 3.2.4), at the horizontal
position ``x = R_F sin(chi)`` from the drum axis (positive on the side where the flights rise).

Every flight passes every angle once a revolution, so a drum of ``N_F`` flights turning at
``n`` rev/min sheds ``N_F n / 60`` times a flight's curtain each second: the distribution of one
flight is the drum's.

An *equal angular distribution* (EAD) flight (Kelly (1992), cited by Ajayi (2011) section 2.2 and
Lee (2008) section 2.5; named after the design aim) discharges the same amount per degree of
rotation over its discharge arc: ``cv_per_degree`` (coefficient of variation of ``-dH/dpsi`` over
the arc) is 0 for it. Since ``-dH/dpsi = L^2/2`` (per radian, ``L`` the surface chord from the tip,
`rotarydryer.geometry.polygon`), that asks for a pocket whose back is an arc round the tip; with
the root on the shell it can only be approached.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_range
from .drum import _H, _S, FlightedDrum
from .unloading import discharge_start_angle

__all__ = ["CurtainDistribution", "curtain_distribution", "final_discharge_angle"]


def final_discharge_angle(drum: FlightedDrum, repose_angle) -> np.ndarray:
    """Root angle (deg from the drum bottom) at which a flight is empty, psi5: Lee (2008) Eq. 4.13
    for a two-section flight, the surface along the last section for any flight. Add
    ``drum.tip_angle`` for the tip's angle. Vectorised over ``repose_angle`` (deg, in (0, 90))."""
    return np.asarray(drum.transition_angles(repose_angle).psi5)


@dataclass(frozen=True)
class CurtainDistribution:
    """Discharge of one flight into the curtain, per degree of rotation and across the drum.

    Attributes
    ----------
    root_angle_deg : ndarray
        Root angles over the discharge arc (from ``start_angle_deg`` to ``final_discharge_angle_deg``).
    rate_per_deg_m2 : ndarray
        ``-dH/dpsi`` there, m^2 per degree per m of flight (Lee (2008): ``F = omega dH/dpsi``).
    x_edges_m : ndarray
        Edges of the bins of horizontal position across the drum, m from the axis (``-R_F`` to ``R_F``;
        positive where the flights rise).
    area_m2 : ndarray
        Solids falling in each bin, m^2 per m of flight per pass of the flight (sums to
        ``discharged_area_m2``).
    start_angle_deg, final_discharge_angle_deg : float
        Root angles where the discharge into the curtain starts and where the flight is empty.
    discharged_area_m2 : float
        Solids a flight sheds into the curtain per pass, m^2 per m (``H0``).
    cv_per_degree : float
        Coefficient of variation of the rate per degree over the discharge arc (0: equal angular
        distribution).
    cv_across_span : float
        Coefficient of variation of the solids per unit width over the bins the curtain covers
        (0: an even curtain over its span).
    """

    root_angle_deg: np.ndarray
    rate_per_deg_m2: np.ndarray
    x_edges_m: np.ndarray
    area_m2: np.ndarray
    start_angle_deg: float
    final_discharge_angle_deg: float
    discharged_area_m2: float
    cv_per_degree: float
    cv_across_span: float

    @property
    def fraction(self) -> np.ndarray:
        """Share of the discharged solids falling in each bin, -."""
        tot = self.area_m2.sum()
        return self.area_m2 / tot if tot > 0 else np.zeros_like(self.area_m2)

    @property
    def span_m(self) -> tuple[float, float]:
        """Horizontal extent of the curtain (smallest and largest x with solids), m."""
        on = np.nonzero(self.area_m2 > 0.0)[0]
        if on.size == 0:
            return (float("nan"), float("nan"))
        return (float(self.x_edges_m[on[0]]), float(self.x_edges_m[on[-1] + 1]))

    def to_dict(self) -> dict:
        """Plain-Python dictionary with units in the keys."""
        return {"start_angle_deg": self.start_angle_deg, "final_discharge_angle_deg": self.final_discharge_angle_deg,
                "discharged_area_m2": self.discharged_area_m2, "cv_per_degree": self.cv_per_degree,
                "cv_across_span": self.cv_across_span, "span_m": list(self.span_m),
                "x_edges_m": self.x_edges_m.tolist(), "fraction": self.fraction.tolist()}


def curtain_distribution(drum: FlightedDrum, repose_angle: float, loading_factor: float = 1.0, *,
                         convention: str = "root", bins: int = 40, step: float = 0.01,
                         particle_diameter=None) -> CurtainDistribution:
    """Where one flight's solids fall: rate per degree over the discharge arc and solids per bin of
    horizontal position across the drum (module docstring).

    ``repose_angle`` (deg) and ``loading_factor`` (``f``, in [0, 1]) are scalars; ``convention`` is the
    first-unloading-flight convention of `rotarydryer.geometry.unloading.cascade`; ``bins`` equal
    bins over ``[-R_F, R_F]``; the arc is resolved every ``step`` degrees (the released amounts are exact
    differences of the holdup, so they add up to ``H0`` exactly; only their split between neighbouring
    bins depends on ``step``). ``particle_diameter`` (m, optional): the finite-particle correction."""
    if not isinstance(drum, FlightedDrum):     # a name or a path read as a drum failed on an attribute
        raise ValueError(f"drum = {drum!r} is not a FlightedDrum (rotarydryer.geometry.FlightedDrum, or "
                         "preset_drum(...) from rotarydryer.geometry.presets)")
    phi = float(check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg"))
    f = float(check_range("loading_factor", loading_factor, 0.0, 1.0, low_inclusive=True, high_inclusive=True))
    if isinstance(bins, bool) or int(bins) != bins or not 1 <= int(bins) <= 100000:
        raise ValueError(f"bins = {bins!r} is outside the allowed range: an integer from 1 to 100000")
    step = float(check_range("step", step, 0.0, 10.0, high_inclusive=True, unit="deg"))
    c = drum._c
    delta = None if particle_diameter is None else drum._layer(particle_diameter)
    start, h0 = discharge_start_angle(drum, phi, f, convention=convention, particle_diameter=particle_diameter)
    start, h0 = float(start), float(h0)
    psi5 = float(final_discharge_angle(drum, phi))
    n = max(2, int(np.ceil((psi5 - start) / step)) + 1) if psi5 > start else 2
    psi = np.linspace(start, max(psi5, start), n)
    h = _H(c, psi, np.full_like(psi, phi), delta)
    h = np.minimum(h, h0)
    dm = np.maximum(-np.diff(h), 0.0)
    chi = np.radians(0.5 * (psi[1:] + psi[:-1]) + c.psi_ft)
    x = c.RF * np.sin(chi)
    edges = np.linspace(-c.RF, c.RF, int(bins) + 1)
    area, _ = np.histogram(np.clip(x, -c.RF, c.RF), bins=edges, weights=dm)
    rate = -_S(c, psi, np.full_like(psi, phi), delta)
    rate = np.where(h < h0, rate, 0.0)
    mean = float(dm.sum() / (psi[-1] - psi[0])) if psi[-1] > psi[0] else 0.0
    if mean > 0.0:
        # time-weighted over the arc: the rate on each step is its released amount over the step
        r_step = dm / np.diff(psi)
        cv_deg = float(np.sqrt(np.mean((r_step - mean) ** 2)) / mean)
    else:
        cv_deg = float("nan")
    on = area > 0.0
    dens = area[on] / np.diff(edges)[on]
    cv_x = float(np.std(dens) / np.mean(dens)) if dens.size else float("nan")
    return CurtainDistribution(root_angle_deg=psi, rate_per_deg_m2=rate, x_edges_m=edges, area_m2=area,
                               start_angle_deg=start, final_discharge_angle_deg=psi5, discharged_area_m2=float(dm.sum()),
                               cv_per_degree=cv_deg, cv_across_span=cv_x)
