r"""Solids velocity and axial dispersion of Ajayi's (2011) MMG model from the operating point.

Ajayi (2011) fitted the solids ("kilning") velocity u_s and the axial dispersion coefficient D
of his multi-section model to each tracer test (Table 5.2, l.1763-1770), so the model predicts
nothing it was not fitted to. This module gives both from the operating point (drum speed,
slope and diameter, solids moisture, feed rate) with two coefficients, calibrated once
(``docs/mmg_cross_test.md``; the case file ``ajayi2011_mmg.toml`` holds the calibrated values):

**Velocity** (each section k, unflighted bed velocity and flighted kilning velocity alike, as
Ajayi's Eq. 5.19 uses one u_s for both):

$$
u_k = c_u\,\frac{\tan\alpha\;N^{0.9}\,D_{drum}}{K_{FM}}\sqrt{\frac{\beta_{ref}}{\beta_k}},
\qquad K_{FM} = 10.58\ \mathrm{s\,rpm^{0.9}},\ \beta_{ref} = 40^\circ
$$

the kiln equation of Sullivan et al. (1927), tau = 106.2 L beta^0.5 / (alpha_deg N D) (Song (2003)
Eq. 1, l.640-642 of the seed text), in the form Friedman & Marshall (1949) gave it (Song (2003)
Eq. 2, l.644-646): tau = 10.58 L /
(s N^0.9 D), with the slope s = tan(alpha) in m/m, the speed exponent 0.9 and the angle of repose
fixed at beta = 40 deg. Here the repose angle is kept through Sullivan's tau ~ sqrt(beta)
(Friedman & Marshall's 10.58 at beta = 40 deg), u = L / tau. N in rev/min, D_drum in m, tau in s.
beta_k is the dynamic angle of repose of the solids (zinc concentrate: Ajayi (2011) Eq. 3.2,
through the material law) at the section's mean moisture on the test's moisture profile
(`rotarydryer.transport.ajayi.mmg_test_moisture_profile`). The feed rate does not enter the
kiln velocity (Sullivan's kiln: the holdup is proportional to the feed); it enters the flighted
sections through their loading, and fouling through the flights' design load (Ajayi (2011) Eq.
5.21, in the model).

**Dispersion** (unflighted sections):

$$
D_k = c_D\,u_k\,d_{p,k}
$$

a constant particle Peclet number Pe_p = u d_p / D = 1/c_D, with Ajayi's section particle sizes
(Ajayi (2011) l.2255: A 0.020 m ... E 0.007 m).

**Alternative velocity law** (``law="kramers"``, for comparison; docs/mmg_cross_test.md): the
flat rolling bed of Kramers & Croockewit (1952) / Saeman (1951) (notes ajayi_transport.md Section
2.3: not in Ajayi's thesis),

$$
Q_v = c_u\,\tfrac43 \pi n R^3 \frac{\tan\alpha}{\sin\beta}\Big(\frac{2h}{R}-\frac{h^2}{R^2}\Big)^{3/2},
\qquad Q_v = F/\rho_b,\ u = Q_v / A(h)
$$

(n in rev/s, dh/dz = 0): the bed depth h follows from the feed, so u depends on the feed
(a deeper bed moves slower: u -> 2 pi n R tan(alpha)/sin(beta) for a shallow bed).

All functions are pure and vectorised over their array arguments; outputs carry their unit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._limits import check_key
from .._validation import check_choice, check_range

__all__ = ["LAWS", "FM_CONSTANT", "FM_SPEED_EXPONENT", "FM_REFERENCE_REPOSE", "friedman_marshall_velocity",
           "kramers_velocity", "particle_dispersion", "PredictiveTransport", "predictive_transport"]

#: velocity laws: "friedman_marshall" (default) and "kramers" (comparison)
LAWS = ("friedman_marshall", "kramers")
#: s rpm^0.9, Friedman & Marshall (1949) tau = 10.58 L / (s N^0.9 D) (Song (2003) Eq. 2; tau in s, L, D in m)
FM_CONSTANT = 10.58
#: Friedman & Marshall (1949) speed exponent (Song (2003) Eq. 2)
FM_SPEED_EXPONENT = 0.9
#: deg, the repose angle Friedman & Marshall (1949) fixed in Sullivan's equation (Song (2003) p. 2, Eq. 2)
FM_REFERENCE_REPOSE = 40.0


def friedman_marshall_velocity(rpm, diameter, slope, repose_angle):
    r"""Kiln velocity u = tan(alpha) N^0.9 D sqrt(40/beta) / 10.58 (m/s): Sullivan et al. (1927) in the
    Friedman & Marshall (1949) form, Song (2003) Eq. 1-2, with the repose angle kept (module docstring).

    rpm : rev/min; diameter : drum diameter, m; slope : deg; repose_angle : dynamic angle of repose, deg."""
    n = check_range("operating.rpm", rpm, 0.0, math.inf, unit="rev/min")
    d = check_range("drum diameter", diameter, 0.0, math.inf, unit="m")
    a = check_range("drum.slope", slope, 0.0, 45.0, low_inclusive=True, unit="deg")
    b = check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg")
    return (np.tan(np.radians(a)) * n**FM_SPEED_EXPONENT * d * np.sqrt(FM_REFERENCE_REPOSE / b) / FM_CONSTANT)


def kramers_velocity(volume_flow, rpm, radius, slope, repose_angle, coefficient=1.0):
    r"""Mean axial velocity (m/s) and depth (m) of a flat rolling bed carrying ``volume_flow`` (m^3/s):
    Kramers & Croockewit (1952) / Saeman (1951) with dh/dz = 0 and a transport coefficient c_u,
    Q_v = c_u (4/3) pi n R^3 (tan alpha / sin beta) (2h/R - h^2/R^2)^(3/2), u = Q_v / A(h), A the
    circular segment of depth h. Returns ``(velocity_m_s, depth_m)``; ``ValueError`` when the bed
    would fill more than half the drum (the equation holds for h <= R)."""
    q = check_range("volume_flow", volume_flow, 0.0, math.inf, unit="m^3/s")
    ns = check_range("operating.rpm", rpm, 0.0, math.inf, unit="rev/min") / 60.0
    R = check_range("drum.radius", radius, 0.0, math.inf, unit="m")
    a = check_range("drum.slope", slope, 0.0, 45.0, unit="deg")
    b = check_range("repose_angle", repose_angle, 0.0, 90.0, unit="deg")
    c = check_key("transport.velocity_coefficient", coefficient)
    k = c * 4.0 / 3.0 * math.pi * ns * R**3 * np.tan(np.radians(a)) / np.sin(np.radians(b))
    s = (q / k) ** (2.0 / 3.0)              # (chord half-length / R)^2 = 2h/R - h^2/R^2
    if np.any(s >= 1.0):
        raise ValueError(f"volume_flow = {float(np.max(q)):.4g} m^3/s needs a rolling bed deeper than the drum "
                         f"radius {float(np.max(R)):.4g} m (Kramers-Croockewit holds for h <= R): the feed is too "
                         "large for this drum speed, slope and transport.velocity_coefficient")
    theta = 2.0 * np.arcsin(np.sqrt(s))     # central angle of the bed
    area = 0.5 * R**2 * (theta - np.sin(theta))
    depth = R * (1.0 - np.cos(theta / 2.0))
    return q / area, depth


def particle_dispersion(velocity, particle_diameter, coefficient):
    """Axial dispersion D = c_D u d_p (m^2/s): a constant particle Peclet number u d_p / D = 1/c_D."""
    u = check_range("velocity", velocity, 0.0, math.inf, low_inclusive=True, unit="m/s")
    dp = check_range("particle_diameter", particle_diameter, 0.0, math.inf, unit="m")
    c = check_key("transport.dispersion_coefficient", coefficient)
    return c * u * dp


@dataclass
class PredictiveTransport:
    """Per-section solids velocity and dispersion of the predictive parameterisation (dicts keyed by
    section name; dispersion for unflighted sections only) and what they were computed from."""

    kiln_velocity_m_s: dict
    dispersion_m2_s: dict
    repose_angle_deg: dict
    moisture_kg_kg: dict
    law: str
    velocity_coefficient: float
    dispersion_coefficient: float
    bed_depth_m: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {k: (dict(v) if isinstance(v, dict) else v) for k, v in self.__dict__.items()}


def predictive_transport(*, sections, feed_rate, rpm, slope, radius, moisture_inlet, moisture_outlet, material,
                         velocity_coefficient, dispersion_coefficient, law="friedman_marshall",
                         moisture_scale=1.0) -> PredictiveTransport:
    r"""Solids velocity and dispersion of each section from the operating point (module docstring).

    Parameters
    ----------
    sections : list of dict
        Flow order; ``name``, ``kind`` ("flighted"/"unflighted"), ``length`` (m) and, for the
        dispersion of unflighted sections, ``particle_diameter`` (m; default the material's).
    feed_rate : float, kg/s wet; rpm : rev/min; slope : deg; radius : drum radius, m
    moisture_inlet, moisture_outlet : float
        The test's feed and product moisture, kg/kg wet: the moisture along the dryer is Ajayi's
        Eq. 3.1 mapped onto them (times ``moisture_scale``).
    material : rotarydryer.properties.materials.Material
        Repose angle and bulk density versus moisture.
    velocity_coefficient : float, c_u (-), > 0
    dispersion_coefficient : float, c_D (-), >= 0
    law : {"friedman_marshall", "kramers"}
    """
    from .ajayi import mmg_test_moisture_profile

    check_choice("transport.velocity_law", law, LAWS)
    F = float(check_range("operating.feed_rate", feed_rate, 0.0, math.inf, unit="kg/s"))
    cu = float(check_key("transport.velocity_coefficient", velocity_coefficient))
    cd = float(check_key("transport.dispersion_coefficient", dispersion_coefficient))
    scale = float(check_key("transport.moisture_scale", moisture_scale))
    R = float(check_range("drum.radius", radius, 0.0, math.inf, unit="m"))
    material.check_moisture("moisture_inlet", moisture_inlet)
    material.check_moisture("moisture_outlet", moisture_outlet)
    length = sum(float(s["length"]) for s in sections)
    u, D, beta, xs, depth = {}, {}, {}, {}, {}
    x0 = 0.0
    for s in sections:
        L = float(s["length"])
        z = np.linspace(x0, x0 + L, 41)
        x = scale * float(np.mean(mmg_test_moisture_profile(z, moisture_inlet, moisture_outlet, length)))
        material.check_moisture(f"solids moisture of section {s['name']}", x)
        phi = float(np.asarray(material.repose_angle(x)))
        if law == "friedman_marshall":
            v = float(cu * friedman_marshall_velocity(rpm, 2.0 * R, slope, phi))
        else:
            rho = float(np.asarray(material.bulk_density(x)))
            v, h = (float(a) for a in kramers_velocity(F / rho, rpm, R, slope, phi, cu))
            depth[s["name"]] = h
        u[s["name"]], beta[s["name"]], xs[s["name"]] = v, phi, x
        if s["kind"] == "unflighted":
            dp = s.get("particle_diameter") or material.particle_diameter
            D[s["name"]] = float(particle_dispersion(v, dp, cd))
        x0 += L
    return PredictiveTransport(kiln_velocity_m_s=u, dispersion_m2_s=D, repose_angle_deg=beta, moisture_kg_kg=xs,
                               law=law, velocity_coefficient=cu, dispersion_coefficient=cd, bed_depth_m=depth)
